/**
 * The highscore panel of chapters 9 and 5: the table of a game (from `GET api/highscores`) and a
 * form that submits a replay with the score it claims (`POST api/highscores?score=N`). The server
 * re-simulates the replay; a claim the replay does not reach is refused, and the panel says why.
 * What that proves is that these inputs reach this score with this seed on this version of the
 * game — not that a person pressed them (a bot's replay verifies just as well).
 */
import type { RegisteredGame } from '@fixedstep/games';
import { button } from '../ui/controls.js';
import { h, setAttr, setText, setHidden } from '../ui/dom.js';
import * as fmt from '../ui/format.js';
import { isRanked, scoreKeyOf } from './games.js';
import { withPlayerName } from './replays.js';
import {
  fetchHighscores,
  submitScore,
  type HighscoreRow,
  type SubmitResult,
} from './highscores.js';

export interface Submission {
  bytes: Uint8Array;
  /** The score the replay ends on (what an honest claim is). */
  score: number;
}

export interface HighscorePanelOptions {
  /**
   * The name to submit under, read when Submit is pressed (a name typed after the game counts):
   * the replay is recorded again with it as its player. Default: the name in the replay.
   */
  name?: () => string;
}

export class HighscorePanel {
  readonly el: HTMLElement;
  private def: RegisteredGame | undefined;
  private submission: Submission | undefined;
  private readonly title: HTMLElement;
  private readonly table: HTMLTableSectionElement;
  private readonly tableEl: HTMLTableElement;
  private readonly tableNote: HTMLElement;
  private readonly form: HTMLElement;
  private readonly claim: HTMLInputElement;
  private readonly submitBtn: HTMLButtonElement;
  private readonly result: HTMLElement;
  private readonly formNote: HTMLElement;
  private loading = 0;
  private ranked = new Map<string, boolean>();

  constructor(private readonly options: HighscorePanelOptions = {}) {
    this.title = h('h3', { id: 'highscores-title' }, 'Highscores');
    this.table = h('tbody', {});
    this.tableNote = h('p', { class: 'hs-note', 'data-testid': 'highscores-note' });
    this.claim = h('input', {
      type: 'number',
      min: 0,
      step: 1,
      id: 'claimed-score',
      class: 'text-field hs-claim',
      inputmode: 'numeric',
      'data-testid': 'control-claimed-score',
    });
    this.submitBtn = button('Submit score', 'control-submit-score', () => {
      void this.submit();
    });
    this.result = h('p', {
      class: 'hs-result',
      role: 'status',
      'aria-live': 'polite',
      'data-testid': 'submit-result',
      hidden: true,
    });
    this.formNote = h('p', { class: 'hs-note' });
    this.form = h(
      'div',
      { class: 'hs-form', role: 'group', 'aria-label': 'Submit this game’s score' },
      h('label', { for: 'claimed-score', class: 'control-label' }, 'Score'),
      this.claim,
      this.submitBtn,
      this.formNote,
      this.result,
    );
    this.tableEl = h(
      'table',
      { class: 'data-table hs-table' },
      h(
        'thead',
        {},
        h(
          'tr',
          {},
          h('th', { scope: 'col' }, '#'),
          h('th', { scope: 'col' }, 'Name'),
          h('th', { scope: 'col', class: 'num' }, 'Score'),
          h('th', { scope: 'col', class: 'num' }, 'Length'),
        ),
      ),
      this.table,
    );
    this.el = h(
      'section',
      { class: 'hs-panel', 'aria-labelledby': 'highscores-title', 'data-testid': 'highscores' },
      this.title,
      this.form,
      this.tableEl,
      this.tableNote,
    );
  }

  /** Show the table of `def`'s game. */
  setGame(def: RegisteredGame): void {
    const changed = this.def?.info.id !== def.info.id;
    this.def = def;
    setText(this.title, `Highscores — ${def.info.title}`);
    if (changed) {
      this.submission = undefined;
      this.refreshForm();
      void this.load();
    }
  }

  /** Offer this replay (or nothing) for submission. */
  setSubmission(sub: Submission | undefined): void {
    this.submission = sub;
    setHidden(this.result, true);
    this.claim.value = sub ? String(sub.score) : '';
    this.refreshForm();
  }

  private isRanked(def: RegisteredGame): boolean {
    let r = this.ranked.get(def.info.id);
    if (r === undefined) {
      r = isRanked(def);
      this.ranked.set(def.info.id, r);
    }
    return r;
  }

  private refreshForm(): void {
    const def = this.def;
    const ranked = def !== undefined && this.isRanked(def);
    const can = ranked && this.submission !== undefined;
    this.claim.disabled = !can;
    this.submitBtn.disabled = !can;
    if (!def) setText(this.formNote, '');
    else if (!ranked) {
      setText(
        this.formNote,
        `${def.info.title} has no score for the server to rank (its HUD has no “${scoreKeyOf(def)}”), so it has no table yet.`,
      );
    } else if (!this.submission) {
      setText(
        this.formNote,
        'Finish a run under the fixed step (a crash, a game over, or End game) to submit its replay.',
      );
    } else {
      setText(
        this.formNote,
        'The server re-simulates the replay and accepts the score only if these inputs reach it with this seed on this version of the game — it cannot tell who pressed them. Change the number to try cheating.',
      );
    }
  }

  /** Load the table of the current game. */
  async load(): Promise<void> {
    const def = this.def;
    if (!def) return;
    const n = ++this.loading;
    const ranked = this.isRanked(def);
    setHidden(this.tableEl, !ranked);
    if (!ranked) {
      this.table.replaceChildren();
      setText(this.tableNote, '');
      return;
    }
    setText(this.tableNote, 'Loading…');
    const res = await fetchHighscores(def.info.id, 10);
    if (n !== this.loading) return;
    this.table.replaceChildren();
    setAttr(this.el, 'data-state', res.kind);
    if (res.kind === 'unavailable') {
      setText(this.tableNote, res.reason);
      this.submitBtn.disabled = true;
      this.claim.disabled = true;
      return;
    }
    if (res.kind === 'refused') {
      setText(this.tableNote, `The server refused: ${res.error}`);
      return;
    }
    if (res.entries.length === 0) {
      setText(this.tableNote, 'No scores yet: be the first.');
      return;
    }
    setText(this.tableNote, '');
    this.table.append(...res.entries.map((e, i) => row(e, i + 1, def.info.tickRate)));
  }

  private async submit(): Promise<void> {
    const sub = this.submission;
    if (!sub) return;
    const claimed = Number(this.claim.value);
    this.submitBtn.disabled = true;
    setHidden(this.result, false);
    this.result.className = 'hs-result';
    setText(this.result, 'Sending the replay; the server is re-simulating it…');
    const name = this.options.name?.();
    const bytes = name === undefined ? sub.bytes : withPlayerName(sub.bytes, name);
    const res = await submitScore(
      bytes,
      Number.isFinite(claimed) ? Math.round(claimed) : 0,
      undefined,
      {
        onRetry: ({ delayMs, status }) => {
          setAttr(this.result, 'data-value', 'queued');
          setText(
            this.result,
            `${status === 0 ? 'The server cannot be reached' : 'The server is busy'}: your score is queued and is sent again in ${Math.ceil(delayMs / 1000)} s…`,
          );
        },
      },
    );
    this.showResult(res);
    this.submitBtn.disabled = false;
    if (res.kind === 'accepted') await this.load();
  }

  private showResult(res: SubmitResult): void {
    setAttr(this.result, 'data-value', res.kind);
    if (res.kind === 'accepted') {
      setAttr(this.result, 'data-rank', String(res.rank));
      this.result.className = 'hs-result verdict good';
      setText(
        this.result,
        res.rank > 0
          ? `Accepted: ${fmt.plural(res.entry.score, 'point')} for ${res.entry.name}, verified by re-simulation — rank ${res.rank}.`
          : `Accepted and verified (${fmt.plural(res.entry.score, 'point')} for ${res.entry.name}), but not in the top of the table.`,
      );
    } else if (res.kind === 'refused') {
      setAttr(this.result, 'data-code', res.code);
      this.result.className = 'hs-result verdict bad';
      setText(this.result, `Refused (${res.code}): ${res.error}`);
    } else {
      setAttr(this.result, 'data-code', 'UNAVAILABLE');
      this.result.className = 'hs-result verdict';
      setText(this.result, res.reason);
    }
  }
}

function row(e: HighscoreRow, rank: number, tickRate: number): HTMLTableRowElement {
  const s = Math.round(e.ticks / tickRate);
  return h(
    'tr',
    {},
    h('td', {}, String(rank)),
    h('td', { class: 'hs-name' }, e.name),
    h('td', { class: 'num' }, fmt.count(e.score)),
    h('td', { class: 'num' }, `${Math.floor(s / 60)}:${String(s % 60).padStart(2, '0')}`),
  );
}
