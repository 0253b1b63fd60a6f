import express from 'express';
import { attachRelay, gameCatalog, highscoreApi, loadGames, openStore } from '../src/index.js';

export async function start(options: { port: number; dataDir: string }) {
  const games = await loadGames();
  const store = await openStore({ dataDir: options.dataDir, databaseUrl: process.env.DATABASE_URL });
  const api = highscoreApi({ games, store });
  const app = express();
  // The API reads its own body: mount it before any body parser.
  app.use((req, res, next) => {
    api.handler(req, res).then((answered) => answered || next(), next);
  });
  app.get('/', (_req, res) => res.send('my game'));
  const server = app.listen(options.port, '127.0.0.1');
  await new Promise((resolve) => server.once('listening', resolve));
  const relay = attachRelay(server, { catalog: gameCatalog(games.games) });
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
