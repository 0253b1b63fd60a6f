/**
 * Your game in the browser: the fixed-step loop (`FrameStepper`) on requestAnimationFrame, the
 * keyboard through the input sampler, interpolated drawing, a replay recorded as you play (verify
 * it, download it, send it with your score to the highscore table) — and online play: open the
 * page with `?room=<name>` in two tabs and both play one round through the relay of
 * `fixedstep serve` (`npm run serve`).
 */
import {
  FixedLoop,
  FrameDriver,
  FrameStepper,
  InputSampler,
  InterpolationBuffer,
  ReplayRecorder,
  RollbackSession,
  animationFrameScheduler,
  attachKeyboard,
  connectWebSocket,
  fetchWithRetry,
  gameSetup,
  performanceClock,
  trackVisibility,
  verifyReplay,
  type ButtonInput,
} from 'fixedstep';
import {
  COINS,
  COIN_RADIUS,
  HEIGHT,
  PLAYER_RADIUS,
  ROUND_TICKS,
  TICK_RATE,
  WIDTH,
  myGame,
  type MyGame,
} from './game.js';

const canvas = document.querySelector<HTMLCanvasElement>('#field')!;
const hud = document.querySelector<HTMLElement>('#hud')!;
const ctx = canvas.getContext('2d')!;
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

const room = params.get('room');
if (room === null) playAlone();
else void playOnline(room);

/** One round on this machine: a loop, a recorder, the highscore table at the end. */
function playAlone(): void {
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

  new FrameDriver(animationFrameScheduler(), (now) => {
    stepper.frame(now);
  }).start();
  Object.assign(window, { myGame: { game, loop, seed, recorder } });
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
async function playOnline(name: string): Promise<void> {
  hud.textContent = `joining room ${name}…`;
  const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws/${name}`;
  const now = { isBeforeUpdateEnd: (t: number) => t <= performance.now() };
  const session = new RollbackSession<ButtonInput>({
    transport: await connectWebSocket(url),
    clock: performanceClock(),
    room: name,
    game: myGame,
    players: 2,
    stopAt: ROUND_TICKS,
    localInput: () => sampler.sample(now, 0),
  });
  const view = new InterpolationBuffer({ fields: 2, capacity: 2 + COINS });
  let drawnTick = -1;
  new FrameDriver(animationFrameScheduler(), () => {
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
  }).start();
  Object.assign(window, { myGame: { session } });
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

function draw(xy: Float64Array, players: number): void {
  const scale = Math.min(canvas.width / WIDTH, canvas.height / HEIGHT);
  ctx.fillStyle = '#10141c';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  ctx.fillStyle = '#f5c542';
  for (let c = 0; c < COINS; c++) {
    disc(xy[2 * (players + c)]!, xy[2 * (players + c) + 1]!, COIN_RADIUS);
  }
  for (let p = 0; p < players; p++) {
    ctx.fillStyle = p === 0 ? '#4cc2ff' : '#ff7a59';
    disc(xy[2 * p]!, xy[2 * p + 1]!, PLAYER_RADIUS);
  }

  function disc(x: number, y: number, r: number) {
    ctx.beginPath();
    ctx.arc(x * scale, y * scale, r * scale, 0, 2 * Math.PI);
    ctx.fill();
  }
}
