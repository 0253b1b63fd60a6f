/**
 * Chapter 9's input, in one place: the keyboard of the focused game canvas and the on-screen touch
 * controls feed the session's sampler — the library's one input pipeline — each event stamped with
 * its own time on the session's time line, so a tap lands on a tick exactly like a key. Every key
 * is let go when the canvas loses focus.
 */
import { attachKeyboard } from 'fixedstep';
import { keyMap } from '../../games-view/games.js';
import { attachTouchPad } from '../../games-view/touch-pad.js';
import type { LabDriver } from '../../shell/driver.js';
import type { GameSession } from './games-lab.js';

/**
 * The session time of an input event stamped `timeStamp` on the page's clock: on the real clock
 * its place on the real time line; on the simulated display the clock's time plus the real time
 * since the last frame (0 while paused, so a key pressed during a pause lands on the next tick).
 */
export function eventTime(session: GameSession, driver: LabDriver, timeStamp: number): number {
  const ago = Math.max(0, performance.now() - timeStamp);
  if (driver.isReal) {
    const r = driver.realNow();
    return r === undefined ? session.timeMs : session.timeOfReal(r - ago);
  }
  return session.timeMs + Math.max(0, driver.sinceLastFrame() - ago);
}

/**
 * Wire `canvas`'s keyboard to `session`: game keys go to its sampler at their own times;
 * `onGameKey` is told of each (first) press of a game key, so a key can start the game. Returns
 * how to unwire.
 */
export function attachGameInput(
  canvas: HTMLCanvasElement,
  session: GameSession,
  driver: LabDriver,
  onGameKey: () => void,
): () => void {
  const keys = keyMap(session.def.info);
  const detach = attachKeyboard(canvas, session.sampler, keys, (e) =>
    eventTime(session, driver, e.timeStamp),
  );
  const onKey = (e: KeyboardEvent) => {
    if (e.repeat || keys[e.code] === undefined) return;
    session.keyEvents++;
    onGameKey();
  };
  const onBlur = () => {
    session.releaseAll(session.timeMs + driver.sinceLastFrame());
  };
  canvas.addEventListener('keydown', onKey);
  canvas.addEventListener('blur', onBlur);
  return () => {
    detach();
    canvas.removeEventListener('keydown', onKey);
    canvas.removeEventListener('blur', onBlur);
  };
}

/**
 * On-screen controls for `session`'s game in `host` (see {@link attachTouchPad}): every press goes
 * through the same sampler as the keyboard, stamped by {@link eventTime}. `onPress` is told of
 * every press (so a tap can start the game). Returns how to take them away.
 */
export function attachTouchControls(
  host: HTMLElement,
  session: GameSession,
  driver: LabDriver,
  onPress: () => void,
): () => void {
  const detach = attachTouchPad(host, session.def.info.id, session.sampler, (e) =>
    eventTime(session, driver, e.timeStamp),
  );
  const press = () => {
    onPress();
  };
  host.addEventListener('pointerdown', press);
  return () => {
    detach();
    host.removeEventListener('pointerdown', press);
  };
}
