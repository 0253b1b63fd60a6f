/**
 * three.js draws, fixedstep steps: the ball of ball.ts at its 60 ticks a second on any display,
 * the arrow keys sampled by timestamp, the ball drawn between its last two ticks.
 */
import * as THREE from 'three';
import {
  FixedLoop,
  FrameStepper,
  InputSampler,
  InterpolationBuffer,
  attachKeyboard,
  trackVisibility,
} from 'fixedstep';
import { HEIGHT, RADIUS, WIDTH, ballGame } from './ball.js';

const ball = ballGame.create({ seed: 1, players: 1, options: new Uint8Array(0) });
// A camera in metres: x right, y down, like the simulation (top 0, bottom HEIGHT).
const camera = new THREE.OrthographicCamera(0, WIDTH, 0, HEIGHT, -1, 1);
const scene = new THREE.Scene();
scene.background = new THREE.Color('#10141c');
const mesh = new THREE.Mesh(
  new THREE.CircleGeometry(RADIUS, 48),
  new THREE.MeshBasicMaterial({ color: 0x4cc2ff, side: THREE.DoubleSide }),
);
scene.add(mesh);
const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setSize(960, 540);
document.querySelector('#game')!.appendChild(renderer.domElement);

// #region glue
const input = new InputSampler(ballGame.input);
const keys = { ArrowLeft: 'left', ArrowRight: 'right', ArrowUp: 'up', ArrowDown: 'down' };
attachKeyboard(window, input, { ...keys, Space: 'kick' });
const loop = new FixedLoop({ step: ballGame }); // the game's tick rate
trackVisibility(document, loop);
const view = new InterpolationBuffer({ fields: 2, capacity: 1 });
view.store(0, ball.x, ball.y);
const stepper = new FrameStepper({
  loop,
  input,
  update: (_dt, tickInput) => {
    view.beginTick();
    ball.step([tickInput]);
    view.store(0, ball.x, ball.y);
  },
  render: (alpha) => {
    const xy = view.interpolate(alpha);
    mesh.position.set(xy[0]!, xy[1]!, 0);
    renderer.render(scene, camera);
  },
});
renderer.setAnimationLoop((time) => stepper.frame(time)); // time: the rAF timestamp
// #endregion glue

// For tests and the curious: the live objects, and where the ball was drawn (in metres).
Object.assign(window, {
  recipe: { game: ball, loop, drawn: () => [mesh.position.x, mesh.position.y] },
});
