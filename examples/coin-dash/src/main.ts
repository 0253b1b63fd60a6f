/**
 * Coin Dash in the browser: the fixed-step loop on requestAnimationFrame, keyboard + touch +
 * gamepad through one input sampler, interpolated drawing, a replay recorded as you play and
 * verified by re-simulation when the round ends.
 */
import {
  FixedLoop,
  FrameDriver,
  FrameStepper,
  InputSampler,
  InterpolationBuffer,
  ReplayRecorder,
  animationFrameScheduler,
  attachButtons,
  attachKeyboard,
  attachStick,
  gamepadPoller,
  gameSetup,
  trackVisibility,
  verifyReplay,
  type PlayerInput,
} from 'fixedstep';
import {
  COINS,
  COIN_RADIUS,
  HEIGHT,
  PLAYER_RADIUS,
  ROUND_TICKS,
  TICK_RATE,
  WIDTH,
  coinDash,
} from './game.js';

const canvas = document.querySelector<HTMLCanvasElement>('#field')!;
const hud = document.querySelector<HTMLElement>('#hud')!;
const ctx = canvas.getContext('2d')!;

// --- input: every device feeds one sampler, each event stamped with its own time -------------
const sampler = new InputSampler(coinDash.input);
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
attachStick(document.querySelector<HTMLElement>('#stick')!, sampler, { x: 'moveX', y: 'moveY' });
attachButtons(sampler, [
  { element: document.querySelector<HTMLElement>('#dash')!, button: 'dash' },
]);
const pollGamepad = gamepadPoller(navigator, sampler, {
  buttons: { 0: 'dash', 12: 'up', 13: 'down', 14: 'left', 15: 'right' },
  axes: { 0: 'moveX', 1: 'moveY' },
});

// --- the round: a game, a recorder, a loop -------------------------------------------------
const seed =
  Number(new URLSearchParams(location.search).get('seed') ?? '') ||
  1 + Math.floor(Math.random() * 1e9);
const setup = gameSetup(coinDash, 1, seed);
const game = coinDash.create(setup);
const recorder = ReplayRecorder.forGame(coinDash, setup, ['you']);
recorder.start(game);

const loop = new FixedLoop({ step: coinDash }); // the game's tick rate, declared once
trackVisibility(document, loop);
// Interpolated drawing: the player and the coins, (x, y) each.
const view = new InterpolationBuffer({ fields: 2, capacity: 1 + COINS });
const coinWas = new Float64Array(COINS);
const storeView = () => {
  view.store(0, game.x[0]!, game.y[0]!);
  for (let c = 0; c < COINS; c++) {
    view.store(1 + c, game.coinX[c]!, game.coinY[c]!);
    // Coins never move: one that did was collected and dropped elsewhere — draw it there at once.
    if (game.coinX[c] !== coinWas[c]) view.snap(1 + c);
    coinWas[c] = game.coinX[c]!;
  }
};
storeView();

let result = '';
const stepper = new FrameStepper<PlayerInput>({
  loop,
  input: sampler,
  update: (_dt, input) => {
    if (game.over) return;
    view.beginTick();
    game.step([input]);
    recorder.record([input], game);
    storeView();
    if (game.over) finish();
  },
  render: (alpha) => {
    draw(view.interpolate(alpha));
  },
});

function finish(): void {
  const bytes = recorder.finish();
  // The whole round is the seed and the inputs: re-simulate it and check every stored hash.
  const check = verifyReplay(bytes, coinDash);
  result = `${check.ok ? 'replay verified' : 'replay did NOT verify'} · ${bytes.length} bytes`;
  const link = document.querySelector<HTMLAnchorElement>('#download')!;
  // finish() is typed Uint8Array<ArrayBufferLike>; Blob wants an ArrayBuffer-backed one, as it is.
  const blob = new Blob([bytes as Uint8Array<ArrayBuffer>], { type: 'application/octet-stream' });
  link.href = URL.createObjectURL(blob);
  link.hidden = false;
  Object.assign(window, { coinDashReplay: bytes });
}

function draw(xy: Float64Array): void {
  const scale = Math.min(canvas.width / WIDTH, canvas.height / HEIGHT);
  ctx.fillStyle = '#10141c';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  ctx.fillStyle = '#f5c542';
  for (let c = 0; c < COINS; c++) disc(xy[2 * (1 + c)]!, xy[2 * (1 + c) + 1]!, COIN_RADIUS);
  ctx.fillStyle = '#4cc2ff';
  disc(xy[0]!, xy[1]!, PLAYER_RADIUS);
  const left = Math.max(0, (ROUND_TICKS - game.tick) / TICK_RATE);
  hud.textContent = `coins ${game.score[0]} · ${left.toFixed(1)} s left${result ? ` · ${result}` : ''}`;

  function disc(x: number, y: number, r: number) {
    ctx.beginPath();
    ctx.arc(x * scale, y * scale, r * scale, 0, 2 * Math.PI);
    ctx.fill();
  }
}

new FrameDriver(animationFrameScheduler(), (now) => {
  pollGamepad(now);
  stepper.frame(now);
}).start();

// For tests and the curious: the live objects.
Object.assign(window, { coinDash: { game, loop, sampler, seed } });
