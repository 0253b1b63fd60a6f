/**
 * A gallery match over simulated links: bots shoot at what their screens show, and the server's
 * judgement is compared with theirs — the lag-compensation measurement of the tests, the bench
 * and the lab (one scene builder for all three).
 * @module
 */
import {
  EventScheduler,
  PlayerInput,
  Random,
  SimulatedLink,
  StateSyncRoom,
  StateSyncSession,
  downBit,
  pressedBit,
} from 'fixedstep';
import {
  GALLERY_HIT_RADIUS,
  GALLERY_INPUT,
  GALLERY_LANES,
  galleryGame,
  type Gallery,
} from './gallery.js';

/** Options of {@link runGalleryMatch}. */
export interface GalleryMatchOptions {
  /** Judge shots at the time the shooter saw. */
  compensate: boolean;
  /** Round trip, ms (half each way). */
  rttMs: number;
  /** Jitter each way, ms. Default 10. */
  jitterMs?: number;
  /** Shooters. Default 2. */
  players?: number;
  /** Simulated seconds. Default 30. */
  seconds?: number;
  seed?: number;
}

/** What a gallery match measured. */
export interface GalleryMatchResult {
  /** Shots fired (judged by the server). */
  shots: number;
  /** Shots that hit on their shooter's screen, and of those, the ones the server judged hits. */
  screenHits: number;
  confirmed: number;
  /** Shots that missed on screen but hit on the server. */
  phantom: number;
  /** Mean rewind the shots asked for, ticks. */
  meanRewind: number;
}

/**
 * Bots aim at a random lane's target where their screen draws it (plus up to ±1.5 hit radii, so
 * some miss on screen), fire every 20 ticks, and say how far back their screen was; the server
 * judges each shot. Returns how often a hit on screen was a hit on the server.
 */
export function runGalleryMatch(o: GalleryMatchOptions): GalleryMatchResult {
  const scheduler = new EventScheduler(0);
  const clock = scheduler.clock;
  const players = o.players ?? 2;
  const game = galleryGame(o.compensate);
  const tokens = new Random(o.seed ?? 1);
  const room = new StateSyncRoom<Gallery>({
    game,
    name: 'gallery',
    clock,
    players,
    seed: 1,
    randomU32: () => tokens.nextU32(),
  });
  scheduler.every(4, () => room.update(clock.now()));
  const screen = new Map<string, boolean>();
  let rewinds = 0;
  for (let i = 0; i < players; i++) {
    const link = new SimulatedLink({
      scheduler,
      seed: 70 + i,
      latencyMs: o.rttMs / 2,
      jitterMs: o.jitterMs ?? 10,
    });
    room.accept(link.b);
    const rng = new Random(900 + i);
    const input = new PlayerInput(GALLERY_INPUT);
    let aim: { lane: number; x: number; seen: number; onScreen: boolean } | undefined;
    let nextShot = 60 + i * 7;
    const session = new StateSyncSession<PlayerInput, Gallery>({
      transport: link.a,
      clock,
      room: 'gallery',
      game,
      render: {
        fields: 1,
        entities: GALLERY_LANES,
        read: (sim, out) => {
          out.set(sim.x);
        },
        owned: () => [],
      },
      localInput: (tick) => {
        input.buttons = 0;
        if (aim !== undefined) {
          const rewind = Math.max(0, Math.min(31.9375, tick - aim.seen));
          input.buttons = downBit(0) | pressedBit(0); // fire: down, and pressed this tick
          input.setAxis(GALLERY_INPUT.axis.lane, aim.lane);
          input.setAxis(GALLERY_INPUT.axis.aim, aim.x);
          input.setAxis(GALLERY_INPUT.axis.rewind, rewind);
          screen.set(`${session.welcome!.slot}:${tick}`, aim.onScreen);
          rewinds += input.axis(GALLERY_INPUT.axis.rewind);
          aim = undefined;
        }
        return input;
      },
    });
    scheduler.every(
      1000 / 60,
      () => {
        session.frame(clock.now());
        const drawn = session.render(clock.now());
        if (session.simulation === undefined || session.tick < nextShot) return;
        nextShot = session.tick + 20;
        const lane = rng.int(GALLERY_LANES);
        const x = drawn[lane]! + rng.range(-1.5, 1.5) * GALLERY_HIT_RADIUS;
        aim = {
          lane,
          x,
          seen: session.renderTick,
          onScreen: Math.abs(drawn[lane]! - x) <= GALLERY_HIT_RADIUS,
        };
      },
      1 + i * 3.7,
    );
  }
  scheduler.runUntil((o.seconds ?? 30) * 1000);
  let screenHits = 0;
  let confirmed = 0;
  let phantom = 0;
  let shots = 0;
  for (const shot of room.simulation.log) {
    const onScreen = screen.get(`${shot.player}:${shot.tick}`);
    if (onScreen === undefined) continue;
    shots++;
    if (onScreen) {
      screenHits++;
      if (shot.hit) confirmed++;
    } else if (shot.hit) {
      phantom++;
    }
  }
  return { shots, screenHits, confirmed, phantom, meanRewind: rewinds / Math.max(1, screen.size) };
}
