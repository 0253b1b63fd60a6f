/**
 * Several WebSocket endpoints on one `http.Server` (the relay at `/ws`, state sync at `/state`, the
 * signalling hub at `/signal`, a user's own): each listens to `'upgrade'` and takes the paths it
 * owns. An upgrade to a path that nobody owns must still be answered (404) — by exactly one of
 * them, and only when no listener of the server's is a stranger that may own it — or the client
 * waits until its own timeout. Endpoints claim their paths here so they can tell.
 */
import type http from 'node:http';

type Owns = (pathname: string) => boolean;

const claims = new WeakMap<http.Server, Owns[]>();

/**
 * Claims the paths `owns` accepts on `server`; call the returned function on detach. `sample` is a
 * path the endpoint owns: if another endpoint already owns it, two would answer one upgrade, so
 * this throws instead.
 */
export function claimUpgradePaths(server: http.Server, owns: Owns, sample: string): () => void {
  const list = claims.get(server) ?? [];
  if (list.some((o) => o(sample))) {
    throw new Error(`another WebSocket endpoint on this server already owns ${sample}`);
  }
  list.push(owns);
  claims.set(server, list);
  return () => {
    const i = list.indexOf(owns);
    if (i >= 0) list.splice(i, 1);
  };
}

/**
 * Whether the endpoint that claimed `owns` should refuse an upgrade to `pathname` that it does not
 * own itself: true when no claimed endpoint owns the path, every `'upgrade'` listener of the server
 * is a claimed endpoint (a stranger's listener may own it), and this endpoint is the first claimant
 * (so one answer is written).
 */
export function shouldRefuseUpgrade(server: http.Server, owns: Owns, pathname: string): boolean {
  const list = claims.get(server) ?? [];
  if (list[0] !== owns) return false;
  if (list.some((o) => o(pathname))) return false;
  return server.listenerCount('upgrade') <= list.length;
}
