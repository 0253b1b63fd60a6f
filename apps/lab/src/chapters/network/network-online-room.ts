/**
 * Chapter 6 — what the two "Play online" panels share (lockstep through the relay in
 * network-online.ts, state sync in network-state-online.ts): a room field with Join / Leave, a
 * link that opens the room in another tab, the machine's canvas and readouts, and the flow of a
 * session — connect, play on the page's animation frames, leave — with what the canvas says while
 * there is nothing to draw.
 */
import type { NetEvent, SessionError, SessionPhase, StateSyncEvent } from 'fixedstep';
import { SceneCanvas } from '../../ui/canvas.js';
import { button } from '../../ui/controls.js';
import { h, setText, setHidden } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import { Readout } from '../../ui/readout.js';
import { ASPECT } from '../../games-view/render.js';

/** A room name the server accepts. */
export const ROOM_NAME = /^[A-Za-z0-9_.-]{1,32}$/;

/** The WebSocket address of `path` on the server that served the page. */
export function serverSocketUrl(loc: Pick<Location, 'protocol' | 'host'>, path: string): string {
  return `${loc.protocol === 'https:' ? 'wss' : 'ws'}://${loc.host}${path}`;
}

/** What a panel reads of its session. */
interface PanelSession {
  readonly phase: SessionPhase;
  readonly failure: SessionError | undefined;
  leave(): void;
}

/** How a panel names its parts, and what its canvas says. */
export interface OnlineRoomLook {
  /**
   * `''` or e.g. `'state-'`: the room field is `net-${kind}room`, the test ids
   * `control-${kind}room`, `control-${kind}join`, `link-${kind}room-tab`, `canvas-${kind}online`
   * and, for the readouts, `${kind}online-<id>`.
   */
  kind: string;
  /** The room field's first value. */
  room: string;
  /** The canvas's label. */
  canvasLabel: string;
  /** What the canvas says once in the room, before there is a game to draw. */
  waiting: string[];
  /** What the canvas says before joining. */
  idle: string[];
}

/**
 * An online panel: its room controls, canvas and readouts, and its session's life. A subclass
 * builds its element ({@link el}) with them, opens its session ({@link open}), steps it each
 * frame ({@link frame}) and shows it ({@link render}).
 */
export abstract class OnlineRoomPanel<S extends PanelSession> {
  abstract readonly el: HTMLElement;
  protected readonly roomInput: HTMLInputElement;
  protected readonly joinBtn: HTMLButtonElement;
  protected readonly tabLink: HTMLAnchorElement;
  protected readonly canvas: SceneCanvas;
  protected readonly out: Record<string, Readout> = {};
  protected session: S | undefined;
  /** What the connection is when there is no live session to ask (offline, connecting, why it ended). */
  protected state = 'offline';
  private raf = 0;

  constructor(private readonly look: OnlineRoomLook) {
    const kind = look.kind;
    this.roomInput = h('input', {
      type: 'text',
      id: `net-${kind}room`,
      'data-testid': `control-${kind}room`,
      value: look.room,
      maxlength: 32,
      pattern: '[A-Za-z0-9_.\\-]{1,32}',
      spellcheck: 'false',
    });
    this.joinBtn = button('Join room', `control-${kind}join`, () => {
      if (this.session) this.leave();
      else this.join();
    });
    this.tabLink = h(
      'a',
      {
        class: 'net-tab-link',
        target: '_blank',
        rel: 'noopener',
        'data-testid': `link-${kind}room-tab`,
        title: 'The second player: this page in a new tab, joining the same room',
      },
      'Open this room in a new tab ↗',
    );
    this.roomInput.addEventListener('input', () => {
      this.updateLink();
    });
    this.canvas = new SceneCanvas({
      class: 'scene net-online-scene',
      label: look.canvasLabel,
      testId: `canvas-${kind}online`,
      // Joined, the panel draws on every animation frame; before that, when it changes or resizes.
      onResize: () => {
        if (!this.session) this.render();
      },
    });
    this.canvas.canvas.style.setProperty('--aspect', String(ASPECT.ctf ?? 1.5));
  }

  /** The address that opens `room` in another tab and joins it there. */
  protected abstract link(room: string): string;

  /** Connects to `room` and starts the session (rejects when it cannot). */
  protected abstract open(room: string): Promise<S>;

  /** One animation frame of the session, before the panel is drawn. */
  protected abstract frame(session: S): void;

  /** Show the numbers and draw the machine (or what it waits for: {@link message}). */
  protected abstract render(): void;

  /** A readout row of the panel's list: its term and its value, kept in {@link out} as `id`. */
  protected row(label: string, id: string, hash = false): HTMLElement[] {
    const r = new Readout('dd', `${this.look.kind}online-${id}`, { hash });
    this.out[id] = r;
    return [h('dt', {}, label), r.el];
  }

  /** The room field's label, with the field and the controls beside it. */
  protected roomGroup(...controls: HTMLElement[]): HTMLElement {
    return h(
      'div',
      { class: 'control-group' },
      h('label', { class: 'control-label', for: this.roomInput.id }, 'Room'),
      this.roomInput,
      this.joinBtn,
      ...controls,
    );
  }

  /**
   * The panel's element: a section titled `title` (heading id `${id}-title`), its `intro`, its
   * controls (a group named `controlsLabel`), then `body`.
   */
  protected section(o: {
    id: string;
    title: string;
    intro: string;
    controlsLabel: string;
    controls: HTMLElement[];
    body: HTMLElement[];
  }): HTMLElement {
    return introSection(
      'bench net-online',
      `${o.id}-title`,
      o.title,
      o.intro,
      h('div', { class: 'controls', role: 'group', 'aria-label': o.controlsLabel }, ...o.controls),
      ...o.body,
    );
  }

  /** The machine: the canvas (with `beside` under it) and the readouts' list of `rows`. */
  protected machine(beside: HTMLElement[], rows: HTMLElement[][]): HTMLElement {
    return h(
      'div',
      { class: 'net-online-body' },
      h('figure', { class: 'net-machine' }, this.canvas.canvas, ...beside),
      h('dl', { class: 'readouts' }, ...rows.flat()),
    );
  }

  /** The other-tab link follows the room field (hidden while the name is not one). */
  protected updateLink(): void {
    const room = this.roomInput.value.trim();
    const ok = ROOM_NAME.test(room);
    setHidden(this.tabLink, !ok);
    if (ok) this.tabLink.href = this.link(room);
  }

  /** Join the room the field names: connect, then play on the page's animation frames. */
  protected join(): void {
    const room = this.roomInput.value.trim();
    if (!ROOM_NAME.test(room)) {
      this.state = 'bad room name';
      this.render();
      return;
    }
    this.state = 'connecting';
    setText(this.joinBtn, 'Leave');
    this.roomInput.disabled = true;
    this.joining?.();
    this.render();
    this.open(room)
      .then((session) => {
        this.session = session;
        this.started?.();
        const frame = () => {
          this.raf = requestAnimationFrame(frame);
          this.frame(session);
          this.render();
        };
        this.raf = requestAnimationFrame(frame);
      })
      .catch((e: unknown) => {
        this.state = `could not connect (${e instanceof Error ? e.message : String(e)})`;
        setText(this.joinBtn, 'Join room');
        this.roomInput.disabled = false;
        this.render();
      });
  }

  /** A join begins (before the first render that shows it connecting). */
  protected joining?(): void;

  /** The session started: it is {@link session} and plays from the next frame. */
  protected started?(): void;

  /**
   * What the connection says of a session event: a fatal error (a refusal, a welcome it cannot
   * build, the connection lost: what `finished` rejects with) says more than the close that
   * follows it.
   */
  protected noteEvent(e: NetEvent | StateSyncEvent): void {
    if (e.type === 'error') this.state = `error: ${e.error.message}`;
    if (e.type === 'closed' && this.session?.failure === undefined) {
      this.state = `closed (${e.reason})`;
    }
  }

  /** Stop the frames. */
  protected stopFrames(): void {
    cancelAnimationFrame(this.raf);
  }

  /** Leave the room (and the session), back to offline. */
  protected leave(): void {
    this.stopFrames();
    this.session?.leave();
    this.session = undefined;
    this.left?.();
    this.state = 'offline';
    setText(this.joinBtn, 'Join room');
    this.roomInput.disabled = false;
    this.render();
  }

  /** The session is left: forget what belonged to it. */
  protected left?(): void;

  /** What the canvas says while there is no game to draw. */
  protected message(): string[] {
    const s = this.session;
    if (s?.phase === 'closed') return ['The connection closed.', 'Join the room again to play.'];
    if (s) return this.look.waiting;
    if (this.state === 'connecting') return ['Connecting to the server…'];
    if (this.state !== 'offline') {
      return [`Could not join: ${this.state}.`, 'Check the room name and the server.'];
    }
    return this.look.idle;
  }

  destroy(): void {
    this.leave();
    this.canvas.destroy();
  }
}
