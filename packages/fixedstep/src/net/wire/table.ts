/**
 * A protocol's messages as a Markdown table, made from its declaration: the docs' tables are
 * generated, so they cannot drift from the code (a test compares them).
 * @module
 */
import type { WireProtocol } from './protocol.js';

const SIDES = { client: 'C→S', server: 'S→C', both: 'both' } as const;

/**
 * The messages of `protocol` as a Markdown table: type byte, name, who sends it, its fields in
 * wire order with their kinds, and its fewest–most bytes under the protocol's default limits.
 */
export function protocolTable(protocol: WireProtocol<{ type: string }, object>): string {
  const rows = protocol.describe().map((m) => {
    const fields = m.fields.map((f) => `${f.name}: ${f.kind}`).join('; ') || '—';
    const size = m.minBytes === m.maxBytes ? `${m.minBytes}` : `${m.minBytes}–${m.maxBytes}`;
    const code = `0x${m.code.toString(16).padStart(2, '0')}`;
    return `| ${code} | ${m.type} | ${SIDES[m.from]} | ${fields.replaceAll('|', '\\|')} | ${size} |`;
  });
  return [
    `Byte 0 of every ${protocol.name} message: 0x${protocol.header.toString(16).padStart(2, '0')} (version ${protocol.version}).`,
    '',
    '| type | message | sent | fields, in wire order | bytes |',
    '|---|---|---|---|---|',
    ...rows,
  ].join('\n');
}
