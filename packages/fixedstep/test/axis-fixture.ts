/**
 * A replay recorded with a linear (even-level) stick axis, as every `{ min, max, bits }` axis was
 * encoded before centred axes: fixtures/stick-linear-v2.fsr was written by {@link recordStick}
 * with that encoding (commit 1a043ba), and must keep reading and verifying as it did.
 */
import { PlayerInput, ReplayRecorder, fnv1a64, type InputSchema, type Simulation } from 'fixedstep';

/** The tiny game: a dot moved by one stick axis, x += axis / 8 a tick. */
export class StickDot implements Simulation<PlayerInput> {
  tick = 0;
  x = 0;
  step(inputs: readonly PlayerInput[]): void {
    this.x += inputs[0]!.axis(0) / 8;
    this.tick++;
  }
  save(): Uint8Array {
    const b = new Uint8Array(12);
    const v = new DataView(b.buffer);
    v.setUint32(0, this.tick, true);
    v.setFloat64(4, this.x, true);
    return b;
  }
  load(bytes: Uint8Array): void {
    const v = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.tick = v.getUint32(0, true);
    this.x = v.getFloat64(4, true);
  }
  hash(): bigint {
    return fnv1a64(this.save());
  }
}

/** 90 ticks: 30 never set, 30 at 0.3, 30 at −1. */
export function recordStick(input: InputSchema<PlayerInput>): Uint8Array {
  const sim = new StickDot();
  const rec = new ReplayRecorder({
    gameId: 'stick',
    gameVersion: '1',
    tickRate: 60,
    players: ['a'],
    input,
    checkpointEvery: 30,
  });
  rec.start(sim);
  for (let t = 0; t < 90; t++) {
    const i = new PlayerInput(input);
    if (t >= 30) i.setAxis(0, t < 60 ? 0.3 : -1);
    sim.step([i]);
    rec.record([i], sim);
  }
  return rec.finish();
}
