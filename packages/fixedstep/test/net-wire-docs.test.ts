/**
 * The docs' message tables are made from the protocols' declarations (`protocolTable`): each
 * table between `<!-- wire: <protocol> -->` and `<!-- /wire -->` must be exactly what the
 * declaration gives. `npm run docs:wire` rewrites them after a protocol change.
 */
import { readFile, writeFile } from 'node:fs/promises';
import { fileURLToPath } from 'node:url';
import { describe, expect, it } from 'vitest';
import {
  MATCH_PROTOCOL,
  RELAY_PROTOCOL,
  SIGNAL_PROTOCOL,
  STATE_SYNC_PROTOCOL,
  protocolTable,
  type WireProtocol,
} from '../src/index.js';

const repo = new URL('../../../', import.meta.url);
const write = process.env.FIXEDSTEP_WRITE_DOCS === '1';

const TABLES: [doc: string, protocol: WireProtocol<{ type: string }, object>][] = [
  ['docs/network.md', RELAY_PROTOCOL],
  ['docs/network.md', STATE_SYNC_PROTOCOL],
  ['docs/network.md', MATCH_PROTOCOL],
  ['docs/webrtc.md', SIGNAL_PROTOCOL],
];

/** `text` with the table of `name` replaced by `table`; throws when the markers are missing. */
function withTable(text: string, name: string, table: string): string {
  const open = `<!-- wire: ${name} -->\n`;
  const start = text.indexOf(open);
  const end = text.indexOf('<!-- /wire -->', start);
  if (start < 0 || end < 0) throw new Error(`no "<!-- wire: ${name} -->" … "<!-- /wire -->"`);
  return text.slice(0, start + open.length) + table + '\n' + text.slice(end);
}

describe('protocol tables in the docs', () => {
  it.each(TABLES.map(([doc, p]) => [doc, p.name, p] as const))(
    '%s holds the table of %s made from its declaration',
    async (doc, _name, protocol) => {
      const file = fileURLToPath(new URL(doc, repo));
      const text = await readFile(file, 'utf8');
      const expected = withTable(text, protocol.name, protocolTable(protocol));
      if (write && expected !== text) await writeFile(file, expected);
      const now = await readFile(file, 'utf8');
      expect(now, 'run `npm run docs:wire` after changing a protocol').toBe(expected);
    },
  );

  it('a table is the declaration: one row per message, in type-byte order, with its sizes', () => {
    const table = protocolTable(MATCH_PROTOCOL).split('\n');
    expect(table[0]).toBe('Byte 0 of every quick match message: 0x61 (version 1).');
    const rows = table.filter((l) => l.startsWith('| 0x'));
    expect(rows.map((r) => r.split(' | ')[1])).toEqual(MATCH_PROTOCOL.types);
    expect(rows[1]).toBe('| 0x02 | accept | C→S | — | 2 |');
    expect(rows.find((r) => r.includes('| queue |'))).toBe(
      '| 0x01 | queue | C→S | game: name; gameVersion: varint 0–2147483647; input: u64 as 16 hex digits; minPlayers: varint 1–16; maxPlayers: varint 1–16; timeoutMs: varint 1–600000 | 16–53 |',
    );
  });

  it('network.md’s layer diagram gives each protocol’s byte 0 and version', async () => {
    const text = await readFile(fileURLToPath(new URL('docs/network.md', repo)), 'utf8');
    const lines = text.split('\n');
    const at = lines.findIndex((l) => /^wire\s+RELAY_PROTOCOL\b/.test(l));
    expect(at).toBeGreaterThan(0);
    const names = lines[at]!.split(/\s+/).slice(1);
    const shown = [...lines[at + 1]!.matchAll(/0x[0-9a-f]{2}: v\d+/g)].map((m) => m[0]);
    const byName: Record<string, WireProtocol<{ type: string }, object>> = {
      RELAY_PROTOCOL,
      STATE_SYNC_PROTOCOL,
      SIGNAL_PROTOCOL,
      MATCH_PROTOCOL,
    };
    expect(names).toEqual(Object.keys(byName));
    expect(shown).toEqual(
      names.map((n) => {
        const p = byName[n]!;
        return `0x${p.header.toString(16).padStart(2, '0')}: v${p.version}`;
      }),
    );
  });
});
