/**
 * Your game in the browser, whatever draws it (made by `npm create fixedstep`): the keyboard
 * through the input sampler, the fixed-step loop (`FrameStepper`), a replay recorded as you play
 * (verify it, download it, send it with your score to the highscore table) — and online play:
 * open the page with `?room=<name>` in two tabs and both play one round through the relay of
 * `fixedstep serve` (`npm run serve`).
 *
 * It draws nothing itself. `play(draw)` returns the function to call once per displayed frame;
 * that function runs the ticks that are due and then hands `draw` (in src/main.ts) where every
 * player and coin is, between the last two ticks. This file is the same in every template (plain
 * canvas, Phaser, PixiJS, three.js): only src/main.ts, the drawing, differs.
 */
import {
  FixedLoop,
  FrameStepper,
  InputSampler,
  InterpolationBuffer,
  ReplayRecorder,
  RollbackSession,
  attachKeyboard,
  connectWebSocket,
  fetchWithRetry,
  gameSetup,
  performanceClock,
  trackVisibility,
  verifyReplay,
  type ButtonInput,
} from 'fixedstep';
import { COINS, ROUND_TICKS, TICK_RATE, WIDTH, myGame, type MyGame } from './game.js';

/** The canvas the game is drawn on (index.html: 960 × 540 pixels for the 16 × 9 m field). */
export const field = document.querySelector<HTMLCanvasElement>('#field')!;
/** Pixels per metre on {@link field}. */
export const SCALE = field.width / WIDTH;
/** Colours as 0xRRGGBB, the form Phaser, PixiJS and three.js take (the canvas writes `#rrggbb`). */
export const COLORS = {
  background: 0x10141c,
  coin: 0xf5c542,
  /** Player 0 (you, alone; the first to join, online), then player 1. */
  players: [0x4cc2ff, 0xff7a59],
} as const;
/** The most players a page draws: one alone, two online. */
export const MAX_PLAYERS = 2;

/**
 * Where to draw, in metres (x right, y down, as in src/game.ts): `xy[2 * i]`, `xy[2 * i + 1]` for
 * each of the `players` players, then for each of the COINS coins — blended between the last two
 * ticks by how far the loop is into the next one, so motion is smooth at any display rate.
 */
export type Draw = (xy: Float64Array, players: number) => void;

/**
 * The function to call once per displayed frame, with that frame's requestAnimationFrame
 * timestamp (milliseconds, on the time line of `performance.now()` and of the key events).
 */
export type Frame = (now: number) => void;

const hud = document.querySelector<HTMLElement>('#hud')!;
const params = new URLSearchParams(location.search);

// --- input: every key event stamped with its own time, sampled once per tick ----------------
const sampler = new InputSampler(myGame.input);
attachKeyboard(window, sampler, {
  ArrowLeft: 'left',
  ArrowRight: 'right',
  ArrowUp: 'up',
  ArrowDown: 'down',
  KeyA: 'left',
  KeyD: 'right',
  KeyW: 'up',
  KeyS: 'down',
  Space: 'dash',
});

/**
 * Starts a round — alone, or online when the page's address has `?room=<name>` — and returns
 * the {@link Frame} to call from the renderer's own frame callback. The timestamp is the only
 * clock the game's loop reads: pass the frame's timestamp, never an engine's delta (engines
 * smooth, clamp or scale their deltas; time taken from them is lost or invented).
 */
export function play(draw: Draw): Frame {
  const room = params.get('room');
  return room === null ? playAlone(draw) : playOnline(room, draw);
}

/** One round on this machine: a loop, a recorder, the highscore table at the end. */
function playAlone(draw: Draw): Frame {
  const seed = Number(params.get('seed') ?? '') || 1 + Math.floor(Math.random() * 1e9);
  const setup = gameSetup(myGame, 1, seed);
  const game = myGame.create(setup);
  const recorder = ReplayRecorder.forGame(myGame, setup, ['you']);
  recorder.start(game);

  const loop = new FixedLoop({ step: myGame }); // the game's tick rate, declared once
  trackVisibility(document, loop);
  const view = new InterpolationBuffer({ fields: 2, capacity: 1 + COINS });
  const store = () => {
    storeView(view, game, 1);
  };
  store();

  let result = '';
  let ended = false;
  const stepper = new FrameStepper<ButtonInput>({
    loop,
    input: sampler,
    update: (_dt, input) => {
      if (ended) return;
      view.beginTick();
      game.step([input]);
      recorder.record([input], game);
      store();
      if (game.over) finish();
    },
    render: (alpha) => {
      const left = Math.max(0, (ROUND_TICKS - game.tick) / TICK_RATE);
      draw(view.interpolate(alpha), 1);
      hud.textContent = `coins ${game.score[0]} · ${left.toFixed(1)} s left${result ? ` · ${result}` : ''}`;
    },
  });

  // Ending early (the button, or Escape) makes a shorter replay, as valid as a whole round.
  const endButton = document.querySelector<HTMLButtonElement>('#end')!;
  endButton.hidden = false;
  endButton.addEventListener('click', finish);
  window.addEventListener('keydown', (e) => {
    if (e.code === 'Escape') finish();
  });

  function finish(): void {
    if (ended) return;
    ended = true;
    endButton.hidden = true;
    const bytes = recorder.finish();
    // The whole round is the seed and the inputs: re-simulate it and check every stored hash.
    const check = verifyReplay(bytes, myGame);
    result = `${check.ok ? 'replay verified' : 'replay did NOT verify'} · ${bytes.length} bytes`;
    const link = document.querySelector<HTMLAnchorElement>('#download')!;
    // finish() is typed Uint8Array<ArrayBufferLike>; Blob wants an ArrayBuffer-backed one, as it is.
    const body = bytes as Uint8Array<ArrayBuffer>;
    link.href = URL.createObjectURL(new Blob([body], { type: 'application/octet-stream' }));
    link.hidden = false;
    void submitScore(game.score[0]!, body).then((said) => (result += ` · ${said}`));
  }

  Object.assign(window, { myGame: { game, loop, seed, recorder } });
  return (now) => {
    stepper.frame(now);
  };
}

/**
 * The score with its replay to the highscore table of `fixedstep serve` (`npm run serve`): the
 * server re-simulates the replay and keeps the score only if the replay reaches it. A busy or
 * starting server (503, 429) is asked again after a wait (`fetchWithRetry`).
 */
async function submitScore(score: number, replay: Uint8Array<ArrayBuffer>): Promise<string> {
  try {
    const res = await fetchWithRetry(`/api/highscores?score=${score}`, {
      method: 'POST',
      body: replay,
    });
    const answer = (await res.json()) as { rank?: number; error?: string; code?: string };
    document.body.dataset.highscore = res.ok ? 'accepted' : `refused: ${answer.code}`;
    return res.ok ? `highscore rank ${answer.rank}` : `highscore refused (${answer.error})`;
  } catch {
    document.body.dataset.highscore = 'no server';
    return 'no highscore server here (npm run serve)';
  }
}

/** Two players, one per tab, through the relay at /ws/<room>: rollback, so no one waits. */
function playOnline(name: string, draw: Draw): Frame {
  hud.textContent = `joining room ${name}…`;
  const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws/${name}`;
  const now = { isBeforeUpdateEnd: (t: number) => t <= performance.now() };
  let session: RollbackSession<ButtonInput> | undefined;
  connectWebSocket(url).then(
    (transport) => {
      session = new RollbackSession<ButtonInput>({
        transport,
        clock: performanceClock(),
        room: name,
        game: myGame,
        players: 2,
        stopAt: ROUND_TICKS,
        localInput: () => sampler.sample(now, 0),
      });
      Object.assign(window, { myGame: { session } });
    },
    (error: unknown) => {
      hud.textContent = `room ${name}: no relay here (npm run serve): ${String(error)}`;
    },
  );
  const view = new InterpolationBuffer({ fields: 2, capacity: 2 + COINS });
  let drawnTick = -1;
  // The session keeps its own time (performanceClock): the frame's timestamp only says "draw now".
  return () => {
    if (session === undefined) return;
    session.frame();
    const game = session.simulation as MyGame | undefined;
    if (game === undefined) {
      hud.textContent = `room ${name}: waiting for the other player…`;
      return;
    }
    if (game.tick !== drawnTick) {
      view.beginTick();
      storeView(view, game, 2);
      drawnTick = game.tick;
    }
    draw(view.interpolate(session.alpha), 2);
    const you = session.welcome?.slot ?? 0;
    hud.textContent =
      `room ${name} · you ${game.score[you]} · them ${game.score[1 - you]} · tick ${game.tick}` +
      (session.isFinished ? ' · round over' : '');
  };
}

/** Players, then coins, (x, y) each, into the interpolation buffer. */
function storeView(view: InterpolationBuffer, game: MyGame, players: number): void {
  for (let p = 0; p < players; p++) view.store(p, game.x[p]!, game.y[p]!);
  for (let c = 0; c < COINS; c++) {
    view.store(players + c, game.coinX[c]!, game.coinY[c]!);
    // A collected coin drops elsewhere at once: draw it there, not sliding across the field.
    view.snap(players + c);
  }
}
