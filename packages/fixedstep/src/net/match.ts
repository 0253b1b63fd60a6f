import { hex64 } from '../det/hash.js';
import { Random } from '../det/random.js';
import type { AnyGameDefinition } from '../sim/game.js';
import type { Simulation } from '../sim/simulation.js';
import type { WelcomeMessage } from './relay/messages.js';
import { gameCatalog, type GameCatalog, type HostedGame } from './room/game-join.js';
import type { ConnectionInfo } from './room/host-types.js';
import { Relay, type RelayOptions, type RelayStats, type RoomInfo } from './relay/relay.js';
import { EventScheduler } from './scheduler.js';
import type { NetSession } from './sessions/base.js';
import { LockstepSession } from './sessions/lockstep.js';
import type { NetSessionOptions, NetSessionStats } from './sessions/relay-options.js';
import { RollbackSession } from './sessions/rollback.js';
import { SpectatorSession } from './sessions/spectator.js';
import { SimulatedLink, type LinkConditions, type LinkStats, type Transport } from './transport.js';

/**
 * What a {@link SimulatedMatch} plays: a game definition. Its `bot`, if any, is every player's
 * default input.
 */
export type MatchGame = AnyGameDefinition;

/** The relay's view of a game definition (a definition already is one). */
export function relayGameOf(game: MatchGame): HostedGame {
  return game as HostedGame;
}

/** One client of a {@link SimulatedMatch}. */
export interface MatchClientSpec {
  /** Session kind. */
  kind: 'lockstep' | 'rollback' | 'spectator';
  /** Room to join. Default: the match's room. */
  room?: string;
  /** Player slots if this client creates its room. Default: the match's. */
  players?: number;
  /** Its link to the server (both directions). Default: the match's link. */
  link?: Partial<LinkConditions>;
  /** Where it connects from, as the relay sees it (address, URL room). Default: nothing said. */
  connection?: ConnectionInfo;
  /** When it connects, in ms of simulated time (a late joiner). Default 0. */
  joinAtMs?: number;
  /** When it leaves (closes its transport), in ms. Default: never. */
  leaveAtMs?: number;
  /** Periods with its tab hidden: display frames come once a second (throttled timers). */
  hidden?: readonly { atMs: number; durationMs: number }[];
  /** Display refresh rate. Default 60. */
  displayHz?: number;
  /** Its local input (players). Default: the game's bot, decided every `botEvery` ticks and held. */
  input?: (tick: number, sim: Simulation<unknown>, slot: number) => unknown;
  /** Builds its simulation (default: the game from the welcome's setup). */
  createSimulation?: (welcome: WelcomeMessage) => Simulation<unknown>;
  /**
   * Extra session options (input delay, prediction window, forensics window …). A spectator's
   * `invite` defaults to the room's, asked of the relay once a player has created the room.
   */
  session?: Partial<
    Omit<NetSessionOptions<unknown>, 'transport' | 'clock' | 'room' | 'game' | 'gameVersion'>
  > &
    Record<string, unknown>;
}

/** Options of a {@link SimulatedMatch}. */
export interface SimulatedMatchOptions {
  /** The game (its bot plays by default). */
  game: MatchGame;
  /** The game's seed. */
  seed: number;
  /** Player slots of the room. Default: the number of non-spectator clients. */
  players?: number;
  clients: readonly MatchClientSpec[];
  /** Every session stops at this tick; the match is over when all have a confirmed state there. */
  ticks: number;
  /** The default link of every client. */
  link?: Partial<LinkConditions>;
  /** Seed of the links' delays and losses. Default 1. */
  linkSeed?: number;
  /** Relay options (deadline, hash interval, limits …). */
  relay?: Partial<Omit<RelayOptions, 'clock' | 'catalog'>>;
  /** The relay's catalog. Default: this game only. */
  catalog?: GameCatalog;
  /** Wall clock for {@link MatchResult.wallMs}. Default `performance.now()`. */
  wallClock?: () => number;
  /** Human-like bots: re-decide every this many ticks, hold in between. Default 6 (100 ms). */
  botEvery?: number;
  room?: string;
}

/** One client's outcome. */
export interface MatchClientResult {
  kind: MatchClientSpec['kind'];
  room: string;
  slot: number;
  tick: number;
  /** Hash (16 hex digits) of the confirmed state at the match's last tick, or '' if not reached. */
  finalHash: string;
  stats: NetSessionStats;
  /** Client → server, server → client. */
  link: [LinkStats, LinkStats] | undefined;
  closed: boolean;
}

export interface MatchResult {
  /** Whether every remaining client reached the last tick. */
  finished: boolean;
  /** Whether, in every room, every client that reached it has the same final hash. */
  hashesAgree: boolean;
  simulatedMs: number;
  wallMs: number;
  clients: MatchClientResult[];
  relay: RelayStats;
  room: RoomInfo | undefined;
}

interface Client {
  spec: MatchClientSpec;
  session: NetSession | undefined;
  link: SimulatedLink | undefined;
  closed: boolean;
}

/**
 * A whole match on simulated time: the real relay core and real client sessions, connected by
 * {@link SimulatedLink}s on one {@link EventScheduler}, with bots at the controls. A 10-minute
 * match runs in seconds and the same options always give the same result. Used by the tests and
 * the relay benchmark; the lab can drive one frame by frame.
 */
export class SimulatedMatch {
  readonly scheduler = new EventScheduler(0);
  readonly relay: Relay;
  readonly def: MatchGame;
  readonly roomName: string;
  private readonly clients: Client[] = [];
  private readonly options: SimulatedMatchOptions;
  private linkCount = 0;

  constructor(options: SimulatedMatchOptions) {
    this.options = options;
    const def = options.game;
    this.def = def;
    this.roomName = options.room ?? 'match';
    const clock = this.scheduler.clock;
    const random = new Random(options.seed ^ 0x9e3779b9);
    this.relay = new Relay({
      clock,
      randomU32: () => random.nextU32(),
      ...options.relay,
      catalog: options.catalog ?? gameCatalog([def]),
    });
    const tickMs = 1000 / def.tickRate;
    this.scheduler.every(
      tickMs / 2,
      () => {
        this.relay.update(clock.now());
      },
      tickMs / 2,
    );
    for (const spec of options.clients) this.addClient(spec);
  }

  /**
   * A link to the relay, accepted with `info` (the client's address, the room its URL names);
   * returns the client's end (for raw or hostile traffic).
   */
  connect(
    link: Partial<LinkConditions> = {},
    info: ConnectionInfo = {},
  ): { transport: Transport; link: SimulatedLink } {
    const l = new SimulatedLink({
      scheduler: this.scheduler,
      seed: (this.options.linkSeed ?? 1) * 7919 + this.linkCount++,
      ...this.options.link,
      ...link,
    });
    this.relay.accept(l.b, info);
    return { transport: l.a, link: l };
  }

  /** Add a client (at `spec.joinAtMs`, or now). */
  addClient(spec: MatchClientSpec): void {
    const client: Client = { spec, session: undefined, link: undefined, closed: false };
    this.clients.push(client);
    const index = this.clients.length - 1;
    const join = () => {
      this.startClient(client, index);
    };
    const at = spec.joinAtMs ?? 0;
    if (at <= this.scheduler.now) join();
    else this.scheduler.at(at, join);
  }

  /** The sessions (undefined until a client joins). */
  get sessions(): (NetSession | undefined)[] {
    return this.clients.map((c) => c.session);
  }

  /** Run until every client is done (or closed), or `limitMs` of simulated time passes. */
  run(limitMs = Infinity): MatchResult {
    const wall = this.options.wallClock ?? (() => performance.now());
    const t0 = wall();
    const started = this.scheduler.now;
    this.scheduler.runUntilDone(() => this.done(), limitMs);
    return this.result(wall() - t0, this.scheduler.now - started);
  }

  private done(): boolean {
    return this.clients.every(
      (c) =>
        c.closed ||
        (c.session !== undefined && (c.session.isFinished || c.session.phase === 'closed')),
    );
  }

  private startClient(client: Client, index: number): void {
    const spec = client.spec;
    const def = this.def;
    const roomName = spec.room ?? this.roomName;
    // A spectator brings the room's invite token (a player would hand it over; here the match
    // asks the relay): wait until a player has created the room.
    let invite: Uint8Array | undefined;
    if (spec.kind === 'spectator' && spec.session?.invite === undefined) {
      invite = this.relay.invite(roomName);
      if (invite === undefined) {
        this.scheduler.at(this.scheduler.now + 50, () => {
          this.startClient(client, index);
        });
        return;
      }
    }
    const { transport, link } = this.connect(spec.link, spec.connection);
    client.link = link;
    const botEvery = this.options.botEvery ?? 6;
    let held: unknown = def.input.neutral();
    const input =
      spec.input ??
      ((tick: number, sim: Simulation<unknown>, slot: number) => {
        if (def.bot && tick % botEvery === 0) held = def.bot(sim, slot);
        return held;
      });
    const base: NetSessionOptions<unknown> = {
      transport,
      clock: this.scheduler.clock,
      room: roomName,
      game: def,
      players:
        spec.players ??
        this.options.players ??
        this.options.clients.filter((c) => c.kind !== 'spectator').length,
      seed: this.options.seed,
      ...(invite ? { invite } : {}),
      name: `client${index}`,
      stopAt: this.options.ticks,
      ...(spec.createSimulation ? { createSimulation: spec.createSimulation } : {}),
      localInput: (tick, sim) => input(tick, sim, client.session?.welcome?.slot ?? 0),
      ...spec.session,
    };
    client.session = (
      spec.kind === 'rollback'
        ? new RollbackSession(base)
        : spec.kind === 'lockstep'
          ? new LockstepSession(base)
          : new SpectatorSession(base)
    ) as NetSession;
    const session = client.session;
    const hz = spec.displayHz ?? 60;
    const period = 1000 / hz;
    const hidden = spec.hidden ?? [];
    const isHidden = (t: number) => hidden.some((h) => t >= h.atMs && t < h.atMs + h.durationMs);
    // Frames at the display rate, phase-shifted per client; once a second while hidden.
    const first = this.scheduler.now + ((index * 3.7) % period);
    const frames = this.scheduler.every(
      () => (isHidden(this.scheduler.now) ? 1000 : period),
      () => {
        if (session.phase === 'closed') {
          frames.cancel();
          return;
        }
        session.frame(this.scheduler.now);
      },
      first,
    );
    if (spec.leaveAtMs !== undefined) {
      this.scheduler.at(spec.leaveAtMs, () => {
        client.closed = true;
        frames.cancel();
        transport.close('left');
      });
    }
  }

  /** The outcome so far. */
  result(wallMs = 0, simulatedMs = this.scheduler.now): MatchResult {
    const stopAt = this.options.ticks;
    const clients = this.clients.map((c): MatchClientResult => {
      const s = c.session;
      const h = s?.hashAt(stopAt);
      return {
        kind: c.spec.kind,
        room: c.spec.room ?? this.roomName,
        slot: s?.welcome?.slot ?? -1,
        tick: s?.tick ?? 0,
        finalHash: h === undefined ? '' : hex64(h),
        stats: s ? { ...s.stats } : ({} as NetSessionStats),
        link: c.link ? [{ ...c.link.stats[0] }, { ...c.link.stats[1] }] : undefined,
        closed: c.closed || s?.phase === 'closed',
      };
    });
    const live = clients.filter((c) => !c.closed);
    const rooms = new Set(live.map((c) => c.room));
    const agree = [...rooms].every((room) => {
      const hashes = new Set(live.filter((c) => c.room === room).map((c) => c.finalHash));
      return hashes.size === 1 && !hashes.has('');
    });
    return {
      finished: live.every((c) => c.finalHash !== ''),
      hashesAgree: agree && live.length > 0,
      simulatedMs,
      wallMs,
      clients,
      relay: { ...this.relay.stats, dropped: { ...this.relay.stats.dropped } },
      room: this.relay.room(this.roomName),
    };
  }
}
