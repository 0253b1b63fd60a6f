/**
 * Your game drawn by three.js: the field seen from above through an orthographic camera in
 * metres, a mesh per player and coin, each positioned every frame where src/play.ts says it is,
 * between the last two ticks.
 *
 * three.js draws; it does not run the game. The renderer's animation loop passes the frame's
 * timestamp to fixedstep's loop, which decides how many fixed steps the game takes; no
 * three.js clock (`Clock`, `Timer`) plays any part in the simulation.
 */
import * as THREE from 'three';
import { COINS, COIN_RADIUS, HEIGHT, PLAYER_RADIUS, WIDTH } from './game.js';
import { COLORS, MAX_PLAYERS, field, play } from './play.js';

// A camera in metres, x right and y down like the simulation (top 0, bottom HEIGHT), looking
// down the z axis at the field.
const camera = new THREE.OrthographicCamera(0, WIDTH, 0, HEIGHT, -10, 10);
const scene = new THREE.Scene();
scene.background = new THREE.Color(COLORS.background);
const renderer = new THREE.WebGLRenderer({ canvas: field, antialias: true });
renderer.setSize(field.width, field.height, false); // the canvas's size; its CSS stays as it is

// y down flips the winding the camera sees: the discs are drawn from both sides.
const disc = (radius: number, color: number) => {
  const mesh = new THREE.Mesh(
    new THREE.CircleGeometry(radius, 48),
    new THREE.MeshBasicMaterial({ color, side: THREE.DoubleSide }),
  );
  mesh.visible = false;
  scene.add(mesh);
  return mesh;
};
const coins = Array.from({ length: COINS }, () => disc(COIN_RADIUS, COLORS.coin));
const players = COLORS.players.slice(0, MAX_PLAYERS).map((c) => disc(PLAYER_RADIUS, c));

const frame = play((xy, playing) => {
  players.forEach((mesh, p) => {
    mesh.visible = p < playing;
    // z = 1: nearer the camera than the coins (z = 0), so a player is drawn over a coin.
    if (mesh.visible) mesh.position.set(xy[2 * p]!, xy[2 * p + 1]!, 1);
  });
  coins.forEach((mesh, c) => {
    const i = playing + c;
    mesh.visible = true;
    mesh.position.set(xy[2 * i]!, xy[2 * i + 1]!, 0);
  });
});
// `time` is the requestAnimationFrame timestamp: the steps that are due, then one render.
renderer.setAnimationLoop((time) => {
  frame(time);
  renderer.render(scene, camera);
});
