import { codecScenes, measureScene } from './suites/state-sync.js';
for (const s of codecScenes(false).slice(3)) {
  const r = measureScene(s, 'schema', 5);
  console.log(
    s.name,
    (r.downWs / 1024).toFixed(2),
    'KB/s',
    r.inSync,
    r.badSnapshots,
    JSON.stringify(r.positionError),
  );
}
