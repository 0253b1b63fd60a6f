/**
 * On-screen controls for the games, sized for thumbs, shared by chapter 9 (live play) and chapter
 * 6 (play online): every press goes to an `InputSampler` — the library's one input pipeline, the
 * same one the keyboard feeds — stamped with its own time, so a tap lands on a tick exactly like a
 * key.
 */
import { ShooterButtons, RunnerButtons } from '@fixedstep/games';
import { attachButtons, attachStick, type InputSampler } from 'fixedstep';
import { h } from '../ui/dom.js';
import './touch-pad.css';

/** The on-screen control that starts game `gameId` (and the runner's run again): Jump or Fire. */
export function touchStartLabel(gameId: string): string {
  return gameId === 'runner' ? 'Jump' : 'Fire';
}

/**
 * Put the on-screen controls of game `gameId` into `host` and wire them to `sampler`: the runner
 * gets Jump and Duck; the shooters a stick (eight directions) with Fire and Strafe. `timeOf` puts
 * a pointer event on the sampler's time line. Returns how to take them away.
 */
export function attachTouchPad(
  host: HTMLElement,
  gameId: string,
  sampler: InputSampler<unknown>,
  timeOf: (e: { timeStamp: number }) => number,
): () => void {
  const pad = (label: string, testId: string) =>
    h(
      'button',
      { type: 'button', class: 'touch-button', 'data-testid': testId, 'aria-label': label },
      label,
    );
  const detach: (() => void)[] = [];
  if (gameId === 'runner') {
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
  return () => {
    for (const d of detach) d();
    host.replaceChildren();
  };
}
