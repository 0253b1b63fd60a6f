import http from 'node:http';
import { attachRelay, gameCatalog, highscoreApi, loadGames, openStore } from '../src/index.js';

export async function start(options: { port: number; dataDir: string }) {
  const games = await loadGames(); // or loadGames(['./my-game.js'])
  const store = await openStore({ dataDir: options.dataDir, databaseUrl: process.env.DATABASE_URL });
  const api = highscoreApi({ games, store });
  const server = http.createServer((req, res) => {
    api.handler(req, res).then((answered) => {
      if (!answered) res.writeHead(404).end('not found');
    }, () => res.writeHead(500).end());
  });
  const relay = attachRelay(server, { catalog: gameCatalog(games.games) });
  await new Promise<void>((resolve) => server.listen(options.port, '127.0.0.1', resolve));
  return {
    server,
    close: async () => {
      await relay.close();
      await api.close();
      await new Promise((resolve) => server.close(resolve));
      await store.close();
    },
  };
}
