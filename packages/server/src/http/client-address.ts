import { isIP } from 'node:net';
import type http from 'node:http';

/**
 * The client's address for rate limits and caps. Behind a reverse proxy every request comes from
 * the proxy, so the address is taken from the header the proxy sets — only when one is configured
 * (`trustProxy`, e.g. `x-forwarded-for` or `x-real-ip`), since anyone can send that header to a
 * server that is not behind one. Of a list (`a, b, c`) the last entry is taken: the one the trusted
 * proxy appended. IPv6 addresses are keyed by their /64, which one subscriber usually holds whole.
 */
export function clientAddress(req: http.IncomingMessage, trustProxy?: string): string {
  let address = req.socket.remoteAddress ?? 'unknown';
  if (trustProxy !== undefined && trustProxy !== '') {
    const raw = req.headers[trustProxy.toLowerCase()];
    const value = Array.isArray(raw) ? raw.at(-1) : raw;
    const last = value?.split(',').at(-1)?.trim();
    if (last !== undefined && isIP(last) !== 0) address = last;
  }
  return addressKey(address);
}

/** An address as a rate-limit key: IPv4 (also IPv4-mapped IPv6) as is, IPv6 by its first 64 bits. */
export function addressKey(address: string): string {
  const mapped = /^::ffff:(\d+\.\d+\.\d+\.\d+)$/i.exec(address);
  if (mapped) return mapped[1]!;
  if (isIP(address) !== 6) return address;
  const [head = '', tail = ''] = address.toLowerCase().split('::');
  const left = head === '' ? [] : head.split(':');
  const right = tail === '' ? [] : tail.split(':');
  const groups = address.includes('::')
    ? [...left, ...Array<string>(8 - left.length - right.length).fill('0'), ...right]
    : left;
  return `${groups
    .slice(0, 4)
    .map((g) => g.replace(/^0+(?=.)/, ''))
    .join(':')}::/64`;
}
