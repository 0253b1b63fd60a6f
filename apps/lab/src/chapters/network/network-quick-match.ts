/**
 * Chapter 6's "Quick match" button: waits in the server's quick-match queue (`/match`) for one
 * other player of capture the flag and hands the room both were given to the online panel, which
 * joins it. Two tabs that press it within the wait find each other; pressing it again cancels.
 */
import { MatchmakingError, quickMatch, type QuickMatchResult } from 'fixedstep';
import { button } from '../../ui/controls.js';
import { h, setText } from '../../ui/dom.js';
import { gameDef } from '../../games-view/games.js';
import { serverSocketUrl } from './network-online-room.js';

/** How long one press waits for another player, in ms. */
export const QUICK_MATCH_WAIT_MS = 60_000;

/** The matchmaking endpoint of the server that served the page. */
export function matchUrl(loc: Pick<Location, 'protocol' | 'host'>): string {
  return serverSocketUrl(loc, '/match');
}

/** What the status line says when a wait ends without a match. */
export function quickMatchFailure(error: unknown): string {
  if (error instanceof MatchmakingError && error.code === 'NO_MATCH') {
    return `No one else pressed “Quick match” within ${QUICK_MATCH_WAIT_MS / 1000} s.`;
  }
  return `Quick match failed: ${error instanceof Error ? error.message : String(error)}`;
}

/** The button and its status line; `onMatch` gets the room to join. */
export class QuickMatchControl {
  /** The control's element: the button and a status line. */
  readonly el: HTMLElement;
  private readonly btn: HTMLButtonElement;
  private readonly status: HTMLElement;
  private abort: AbortController | undefined;

  /** A control that calls `onMatch` with each match it finds. */
  constructor(private readonly onMatch: (match: QuickMatchResult) => void) {
    this.btn = button('Quick match', 'control-quick-match', () => {
      if (this.abort) this.cancel('Cancelled.');
      else this.start();
    });
    this.btn.title = 'Wait for another player (another tab) who presses Quick match too';
    this.status = h('span', {
      class: 'net-quick-status',
      'data-testid': 'quick-match-status',
      role: 'status',
    });
    this.el = h('span', { class: 'net-quick-match' }, this.btn, this.status);
  }

  private start(): void {
    const def = gameDef('ctf');
    const abort = new AbortController();
    this.abort = abort;
    setText(this.btn, 'Cancel quick match');
    setText(this.status, 'Looking for another player…');
    quickMatch({
      url: matchUrl(location),
      game: def.info.id,
      gameVersion: def.info.version,
      input: def.input,
      minPlayers: 2,
      maxPlayers: 2,
      timeoutMs: QUICK_MATCH_WAIT_MS,
      signal: abort.signal,
    })
      .then((match) => {
        if (this.abort !== abort) return;
        // The ticket seats this tab in the slot the matchmaker gave it: the panel shows which.
        this.done(`Matched with ${match.players - 1} other player(s): joining the room.`);
        this.onMatch(match);
      })
      .catch((error: unknown) => {
        if (this.abort === abort) this.done(quickMatchFailure(error));
      });
  }

  private done(text: string): void {
    this.abort = undefined;
    setText(this.btn, 'Quick match');
    setText(this.status, text);
  }

  /** Stops waiting (the server is told), showing `text`. */
  cancel(text = ''): void {
    const abort = this.abort;
    this.done(text);
    abort?.abort(new Error('cancelled'));
  }
}
