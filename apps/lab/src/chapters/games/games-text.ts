/**
 * What chapter 9 says: the lede, each game's blurb, the readout rows, the after-game summary and
 * "How this page works". The after-game words are computed from the session and the replay file's
 * own sections (a pure function, tested), so they say what is true of this game.
 */
import { CTF, CTF_WALLS, SURVIVAL, SURVIVAL_WALLS } from '@fixedstep/games';
import { code } from '../../ui/dom.js';
import { inputWords, type InputKind } from '../../ui/input-kind.js';
import { textSection } from '../../ui/prose.js';
import * as fmt from '../../ui/format.js';
import { hudLabel, type GameId } from '../../games-view/games.js';
import { describeContents, type ReplayContents } from '../../games-view/replays.js';
import { runnerApex, type RankedRun } from './games-lab.js';

/** The apex every fixed-step runner jump reaches, m. */
export const REFERENCE_APEX = runnerApex(1 / 60);

/** The chapter's lede, naming what this device plays with (the keyboard, touch or both). */
export function lede(kind: InputKind): string {
  return `The talk’s three games — the runner (“SCORE 0 / HIGHSCORE 35730”), capture the flag (“Kills: 1, Flags captured: 0”) and survival (“Kills: 0, Lives: 15”). Play them with ${inputWords(kind)} on any display, then flip the loop to a variable Δt and watch them break.`;
}

/** The line under Play: how else to start, with this device's input (`control` is the game's first on-screen control). */
export function startHint(kind: InputKind, key: string, control: string): string {
  const press = `press ${key} with the game focused`;
  const tap = `tap ${control} under the game`;
  const how = kind === 'keyboard' ? press : kind === 'touch' ? tap : `${tap} or ${press}`;
  return `or ${how} · or let the bot play`;
}

/** The runner's line under GAME OVER: how to run again, with this device's input. */
export function runAgainHint(kind: InputKind, key: string): string {
  return kind === 'touch' ? 'tap Jump to run again' : `${key} to run again`;
}

/** Units per fixed step (1/60 s) of a speed in units per second, as the page writes it. */
function perStep(unitsPerSecond: number): string {
  return String(Number((unitsPerSecond / 60).toFixed(2)));
}

/**
 * What each game says about itself on the page; its numbers are the games' own constants (speeds,
 * the thinnest wall, lives), so the text follows the games.
 */
export const ABOUT: Readonly<Record<GameId, { lede: string; breaks: string; fixed: string }>> = {
  runner: {
    lede: 'Run, jump over the red blocks, duck under the birds. The speed grows; the highscore stays.',
    breaks:
      'Under a variable Δt each jump is integrated with the frame’s own Δt: at 30 Hz it is lower and shorter than at 144 Hz, so the same timing clears a block on one screen and not on another.',
    fixed: `Under the fixed step every jump is the same: apex ${REFERENCE_APEX.toFixed(3)} m, whatever the display.`,
  },
  ctf: {
    lede: 'You are the red player with the white ring. Take the blue flag from the right and bring it home while yours is on its stand. Bots fill both teams.',
    breaks: `Under a variable Δt a bullet moves ${CTF.bulletSpeed} units/s × Δt at once and is only checked where it lands: at 30 Hz that is ${CTF.bulletSpeed / 30} units, and the ${CTF_WALLS.thinnest}-unit walls stop almost nothing. Red rings mark each pass.`,
    fixed: `Under the fixed step bullets are swept (continuous collision detection) and players move ${perStep(CTF.playerSpeed)} units a step against ${CTF_WALLS.thinnest}-unit walls: nothing goes through.`,
  },
  survival: {
    lede: `Waves of enemies run at you. Keep moving, shoot them down, use the walls. ${SURVIVAL.lives} lives.`,
    breaks:
      'Under a variable Δt an enemy pressing on a wall during a long frame jumps past its middle and is pushed out on your side. Red rings mark each pass.',
    fixed: `Under the fixed step an enemy moves at most ${perStep(SURVIVAL.maxEnemySpeed + 60 * SURVIVAL.maxShove)} units a step (running, and shoved by the others) against walls ${SURVIVAL_WALLS.thinnest} thick (minWallSize = maxSpeed × step): it slides along the wall and comes round its end.`,
  },
};

export interface Row {
  key: string;
  label: string;
  title?: string;
  hash?: boolean;
}

/** The readouts beside the game (test ids `readout-${key}`). */
export function rowsFor(id: GameId): Row[] {
  const hud: Record<GameId, Row[]> = {
    runner: [
      { key: 'score', label: 'Score' },
      { key: 'highscore', label: 'Highscore' },
      { key: 'jumps', label: 'Jumps' },
      {
        key: 'jump-apex',
        label: 'Last jump apex',
        title: `The highest point of the last jump. Under the fixed step: always ${REFERENCE_APEX.toFixed(3)} m.`,
      },
    ],
    ctf: [
      { key: 'kills', label: 'Kills' },
      { key: 'flags', label: 'Flags captured' },
      { key: 'deaths', label: 'Deaths' },
      { key: 'team-score', label: 'Red : blue' },
    ],
    survival: [
      { key: 'kills', label: 'Kills' },
      { key: 'lives', label: 'Lives' },
      { key: 'wave', label: 'Wave' },
      { key: 'enemies', label: 'Enemies' },
    ],
  };
  const walls: Row[] =
    id === 'runner'
      ? []
      : [
          {
            key: 'through-walls',
            label: 'Through walls',
            title:
              'Bullets, players or enemies whose path went through a wall (the game’s own count)',
          },
        ];
  return [
    ...hud[id],
    ...walls,
    { key: 'tick', label: 'Tick', title: 'Updates run so far' },
    { key: 'sim-time', label: 'Sim time', title: 'Simulated time' },
    { key: 'max-dt', label: 'Longest Δt', title: 'The longest Δt one update was given' },
    { key: 'hash', label: 'State hash', title: 'FNV-1a 64 of the game’s state now', hash: true },
    {
      key: 'replay-bytes',
      label: 'Replay so far',
      title: 'The recorded inputs so far, run-length coded (the file adds hashes and keyframes)',
    },
  ];
}

/** What the after-game panel is told about the game that just ended (or crashed). */
export interface AfterGame {
  title: string;
  gameId: string;
  /** Whether it ran under the fixed step (and so was recorded). */
  fixed: boolean;
  /** The runner crashed and can run again (the game goes on). */
  runnerCrash: boolean;
  /** How this device plays (what "run again" tells it to press). */
  input: InputKind;
  /** Whether the game is over by its own rules (else the player ended it). */
  over: boolean;
  ticks: number;
  /** The score the server ranks now, if the game has one. */
  score: number | undefined;
  /** The HUD now, for a game without a score. */
  hud: Readonly<Record<string, number>>;
  /** The best run of the session (what the highscore form offers). */
  best: RankedRun | undefined;
  /** What the recording so far holds, from its own sections. */
  contents: ReplayContents | undefined;
}

/** The heading, the paragraph and the short line for screen readers of the after-game panel. */
export function afterGameText(a: AfterGame): { heading: string; text: string; summary: string } {
  const heading = a.runnerCrash ? 'Crashed' : a.over ? 'Game over' : 'Game ended';
  const result =
    a.score !== undefined
      ? fmt.plural(a.score, 'point')
      : Object.entries(a.hud)
          .filter(([k]) => k !== 'timeLeft')
          .map(([k, v]) => `${hudLabel(k).toLowerCase()} ${fmt.count(v)}`)
          .join(', ');
  const summary = `${a.title}: ${result}`;
  if (!a.fixed) {
    return {
      heading,
      summary,
      text: `${summary}. This game ran under a variable Δt: it was not recorded — its updates depend on the frame times, so no replay could reproduce it. Switch the loop to the fixed step to record.`,
    };
  }
  const parts = [`${summary} in ${fmt.count(a.ticks)} ticks.`];
  if (a.contents) {
    parts.push(
      `The replay is ${describeContents(a.contents, fmt.count)}. It plays back bit for bit: the game is computed again from the inputs and the seed.`,
    );
  }
  const best = a.best;
  if (best && a.score !== undefined) {
    parts.push(
      best.ticks === a.ticks && best.score === a.score
        ? 'Submit this run below to rank its score.'
        : `The best run of this game scored ${fmt.plural(best.score, 'point')}: the form below submits the replay up to its end (tick ${fmt.count(best.ticks)}).`,
    );
  }
  if (a.runnerCrash) {
    const how =
      a.input === 'touch'
        ? 'Tap Jump'
        : a.input === 'keyboard'
          ? 'Press Space'
          : 'Press Space or tap Jump';
    parts.push(`${how} to run again — the recording goes on.`);
  }
  return { heading, summary, text: parts.join(' ') };
}

export function howItWorks(): HTMLElement {
  return textSection(
    'how',
    'how-title',
    'How this page works',
    'Keys (and taps) go into a ButtonSampler with the time the browser stamped on the event. Every display frame a FrameStepper asks the FixedLoop how many 1/60 s steps are due and runs them, each with exactly the presses that happened before its end — so a tap is never lost or doubled, whatever the frame rate. The canvas then draws every moving thing between its last two states, at α = accumulator / step.',
    code(
      'const sampler = new ButtonSampler();\nattachKeyboard(canvas, sampler, keys, (e) => timeOf(e.timeStamp));\n\nconst stepper = new FrameStepper({\n  loop: new FixedLoop({ step: 60 }),\n  input: sampler,\n  update: (_dt, input) => {\n    game.step([input]);\n    recorder.record([input], game);\n  },\n  render: (alpha) => draw(game, alpha),\n});\n// every display frame:\nstepper.frame(now);',
    ),
    `The recording is the replay: the inputs of every tick (run-length coded), the seed and a state hash every 10 s — nothing else; a player re-simulates to seek, at millions of ticks a second. The panel after a game says how many bytes each part takes. “Variable Δt” swaps the FixedLoop for the talk’s naive loop, which calls update(dt) once per frame with that frame’s Δt; it is not recorded, because nothing could replay it.`,
  );
}
