import http from 'node:http';
import { gameCatalog } from 'fixedstep';
import {
  Admission,
  attachMatchmaking,
  attachRelay,
  highscoreApi,
  loadGames,
  openStore,
} from '../src/index.js';

export async function start(options: { port: number; dataDir: string }) {
  const games = await loadGames(); // or loadGames(['./my-game.js'])
  const store = await openStore({ dataDir: options.dataDir, databaseUrl: process.env.DATABASE_URL });
  const api = highscoreApi({ games, store });
  const server = http.createServer((req, res) => {
    api.handler(req, res).then((answered) => {
      if (!answered) res.writeHead(404).end('not found');
    }, () => res.writeHead(500).end());
  });
  // One admission for every WebSocket surface: origins, client addresses, sockets per address.
  const admission = new Admission(); // same origin; { trustProxy } behind a proxy
  // Quick match at /match; the relay at /ws/<room> seats matched players with its tickets.
  const match = attachMatchmaking(server, { games: games.games, admission });
  const relay = attachRelay(server, {
    catalog: gameCatalog(games.games),
    admission,
    tickets: match.tickets.verify,
  });
  await new Promise<void>((resolve) => server.listen(options.port, '127.0.0.1', resolve));
  return {
    server,
    close: async () => {
      await relay.close();
      await match.close();
      await api.close();
      await new Promise((resolve) => server.close(resolve));
      await store.close();
    },
  };
}
