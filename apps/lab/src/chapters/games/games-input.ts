/**
 * Chapter 9's input, in one place: the keyboard of the focused game canvas and the on-screen touch
 * controls feed the session's sampler — the library's one input pipeline — each event stamped with
 * its own time on the session's time line, so a tap lands on a tick exactly like a key. Every key
 * is let go when the canvas loses focus.
 */
import { ShooterButtons, RunnerButtons } from '@fixedstep/games';
import { attachButtons, attachKeyboard, attachStick } from 'fixedstep';
import { keyMap } from '../../games-view/games.js';
import { h } from '../../ui/dom.js';
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
    return r === undefined ? session.timeMs : session.sessionTimeOfReal(r - ago);
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
 * On-screen controls for `session`'s game in `host`, sized for thumbs: the runner gets Jump and Duck;
 * the shooters a stick (eight directions) with Fire and Strafe. Every press goes through the same
 * sampler as the keyboard, stamped by {@link eventTime}. `onPress` is told of every press (so a tap
 * can start the game). Returns how to take them away.
 */
export function attachTouchControls(
  host: HTMLElement,
  session: GameSession,
  driver: LabDriver,
  onPress: () => void,
): () => void {
  const timeOf = (e: { timeStamp: number }) => eventTime(session, driver, e.timeStamp);
  const pad = (label: string, testId: string) =>
    h(
      'button',
      { type: 'button', class: 'touch-button', 'data-testid': testId, 'aria-label': label },
      label,
    );
  const sampler = session.sampler;
  const detach: (() => void)[] = [];
  if (session.def.info.id === 'runner') {
    const jump = pad('Jump', 'touch-jump');
    const duck = pad('Duck', 'touch-duck');
    host.replaceChildren(
      h('div', { class: 'touch-side' }, duck),
      h('div', { class: 'touch-side' }, jump),
    );
    detach.push(
      attachButtons(
        sampler,
        [
          { element: jump, button: RunnerButtons.jump },
          { element: duck, button: RunnerButtons.duck },
        ],
        timeOf,
      ),
    );
  } else {
    const stick = h(
      'div',
      {
        class: 'touch-stick',
        'data-testid': 'touch-stick',
        role: 'application',
        'aria-label': 'Move',
      },
      h('span', { class: 'touch-knob' }),
    );
    // The knob follows the thumb (drawing only; the sampler has the input).
    const knob = stick.firstElementChild as HTMLElement;
    let held: number | undefined;
    const follow = (e: PointerEvent) => {
      if (e.type === 'pointerdown') held ??= e.pointerId;
      if (e.pointerId !== held) return;
      if (e.type !== 'pointerdown' && e.type !== 'pointermove') {
        held = undefined;
        knob.style.transform = '';
        return;
      }
      const r = stick.getBoundingClientRect();
      const max = r.width / 2;
      let dx = e.clientX - (r.left + max);
      let dy = e.clientY - (r.top + r.height / 2);
      const len = Math.sqrt(dx * dx + dy * dy);
      if (len > max) {
        dx = (dx / len) * max;
        dy = (dy / len) * max;
      }
      knob.style.transform = `translate(${dx.toFixed(0)}px, ${dy.toFixed(0)}px)`;
    };
    const types = [
      'pointerdown',
      'pointermove',
      'pointerup',
      'pointercancel',
      'lostpointercapture',
    ] as const;
    for (const type of types) {
      stick.addEventListener(type, follow);
    }
    const fire = pad('Fire', 'touch-fire');
    const strafe = pad('Strafe', 'touch-strafe');
    host.replaceChildren(
      h('div', { class: 'touch-side' }, stick),
      h('div', { class: 'touch-side touch-buttons' }, strafe, fire),
    );
    detach.push(
      attachStick(
        stick,
        sampler,
        {
          left: ShooterButtons.left,
          right: ShooterButtons.right,
          up: ShooterButtons.up,
          down: ShooterButtons.down,
        },
        {},
        timeOf,
      ),
      attachButtons(
        sampler,
        [
          { element: fire, button: ShooterButtons.fire },
          { element: strafe, button: ShooterButtons.strafe },
        ],
        timeOf,
      ),
    );
  }
  const press = () => {
    onPress();
  };
  host.addEventListener('pointerdown', press);
  return () => {
    for (const d of detach) d();
    host.removeEventListener('pointerdown', press);
    host.replaceChildren();
  };
}
