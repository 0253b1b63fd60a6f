/**
 * Past one process: three `fixedstep serve` processes behind HAProxy with deploy/haproxy's own
 * configuration, on 127.0.0.1, every client from a loopback address of its own (as across the
 * internet; the processes read it from HAProxy's X-Forwarded-For). All four WebSocket surfaces:
 *
 * - relay rooms (`/ws/<room>`), state-sync rooms (`/state/<room>`) and signalling rooms
 *   (`/signal/<room>`): every room on exactly one process, its members together there — lockstep
 *   and state-sync players on equal hashes, a signalling joiner tunnelling to its host;
 * - quick match (`/match`): one queue, on the first process, whose tickets seat the matched players
 *   in their `qm-` relay room on whichever process that room hashes to (the processes share
 *   `FIXEDSTEP_MATCH_SECRET`);
 * - `kill -9` of the queue's process mid-match: its rooms' clients get a clean close (no hang) and
 *   start again under the same names on a live process, the other processes' rooms play on, and
 *   `/match` moves to the next process.
 *
 * Needs Debian's haproxy (npm test installs it as root); skipped without.
 */
import { spawn, spawnSync, type ChildProcess } from 'node:child_process';
import { mkdtemp, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import WebSocket from 'ws';
import {
  LockstepSession,
  PeerHost,
  SignalClient,
  StateSyncSession,
  decodeFrame,
  decodeSignal,
  decodeStateSyncMessage,
  encodeMessage,
  encodeSignal,
  encodeStateSyncMessage,
  fnv1a64,
  hex64,
  joinPeer,
  nodeWebSocketTransport,
  performanceClock,
  quickMatch,
  type ButtonInput,
  type MatchmakingError,
  type PeerLink,
  type QuickMatchResult,
  type Transport,
} from 'fixedstep';
import { ctfGame, type Game } from '@fixedstep/games';
import {
  HAPROXY_CFG,
  haproxy,
  root,
  startHaproxy,
  stopProcess,
  until,
  type RunningHaproxy,
} from './haproxy-harness.js';
import { UnreachablePeerConnection } from './unreachable-peer.js';

interface Relay {
  port: number;
  child: ChildProcess;
  out: string;
}

const procs: ChildProcess[] = [];
let dir: string;
let relays: Relay[] = [];
let lb: RunningHaproxy;
let started = 0;

/** Every process signs and checks quick-match tickets with this (deploy/ sets it from a Secret). */
const MATCH_SECRET = 'balancer-test-match-secret-0123456789';

async function startRelay(): Promise<Relay> {
  // Each process its own data folder: a data folder belongs to one process (it locks it); several
  // processes share scores through one PostgreSQL (DATABASE_URL), as deploy/ does.
  const data = path.join(dir, `data-${started++}`);
  const child = spawn(
    process.execPath,
    [
      '--conditions=source',
      '--import',
      'tsx',
      'packages/cli/src/cli.ts',
      'serve',
      '--port',
      '0',
      '--root',
      dir,
      '--data',
      data,
    ],
    {
      cwd: root,
      env: {
        ...process.env,
        // The processes believe HAProxy's X-Forwarded-For (HAProxy is on loopback, trusted by default).
        FIXEDSTEP_PROXY_HEADER: 'x-forwarded-for',
        FIXEDSTEP_MATCH_SECRET: MATCH_SECRET,
      },
      stdio: ['ignore', 'pipe', 'pipe'],
    },
  );
  procs.push(child);
  const r: Relay = { port: 0, child, out: '' };
  child.stdout.on('data', (b: Buffer) => (r.out += b.toString()));
  child.stderr.on('data', (b: Buffer) => (r.out += b.toString()));
  r.port = Number(
    await until(
      'a relay to listen',
      () => /localhost:(\d+)\//.exec(r.out)?.[1],
      60_000,
      () => r.out,
    ),
  );
  return r;
}

beforeAll(async () => {
  if (!haproxy) return;
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-balancer-'));
  await writeFile(path.join(dir, 'index.html'), '<!doctype html><title>lab</title>');
  relays = await Promise.all([startRelay(), startRelay(), startRelay()]);
  // Ready (store open) before HAProxy starts: it counts a server as up until its checks fail, so
  // "three up" is only true once each /readyz answers 200.
  for (const r of relays) {
    await until(
      `relay ${r.port} to be ready`,
      async () => (await fetch(`http://127.0.0.1:${r.port}/readyz`).catch(() => undefined))?.ok,
      60_000,
      () => r.out,
    );
  }
  lb = await startHaproxy(
    dir,
    relays.map((r) => r.port),
  );
  procs.push(lb.child);
  await until('HAProxy to see three relays up', async () => {
    const [rooms, match] = await Promise.all([
      lb.usable('relays_by_room'),
      lb.usable('relays_match'),
    ]);
    return rooms === 3 && match === 3;
  });
}, 120_000);

afterAll(async () => {
  await Promise.all(procs.map(stopProcess));
  if (dir) await rm(dir, { recursive: true, force: true });
});

// ------------------------------------------------------------------------------------ clients

let addresses = 0;
/** A loopback address of its own (127.0.0.0/8 is all this machine's) for each client. */
const address = () => {
  const n = addresses++;
  return `127.1.${Math.floor(n / 250)}.${(n % 250) + 1}`;
};

/** A WebSocket through HAProxy from a fresh client address; a refused upgrade says why. */
function open(pathname: string): Promise<Transport> {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(`ws://127.0.0.1:${lb.port}${pathname}`, {
      localAddress: address(),
    });
    ws.on('error', reject);
    ws.on('unexpected-response', (_req, res) => {
      let body = '';
      res.on('data', (b: Buffer) => (body += b.toString()));
      res.on('end', () => {
        reject(
          new Error(`${pathname}: the upgrade got ${res.statusCode} ${body.trim()}\n${lb.log()}`),
        );
      });
    });
    ws.on('open', () => {
      resolve(nodeWebSocketTransport(ws));
    });
  });
}

/** Frames for every session: members that do not answer pings are dropped as silent. */
const framed = new Set<{ frame(): unknown }>();

const clock = performanceClock();

interface Player {
  session: LockstepSession;
  closedAt: number | undefined;
}

/** A lockstep match of capture the flag in relay room `room`: two players through HAProxy. */
async function playRelay(room: string, ticks: number, tickets?: Uint8Array[]): Promise<Player[]> {
  return Promise.all(
    [0, 1].map(async (i) => {
      const transport = await open(`/ws/${room}`);
      let slot = 0;
      const p: Player = { session: undefined!, closedAt: undefined };
      p.session = new LockstepSession({
        transport,
        clock,
        room,
        game: ctfGame,
        stopAt: ticks,
        ...(tickets ? { ticket: tickets[i] } : { players: 2, seed: 9 }),
        createSimulation: (w) => {
          slot = w.slot;
          return ctfGame.create(ctfGame.decodeConfig(w.config));
        },
        localInput: (_t, sim) => ctfGame.bot(sim as Game, slot),
        onEvent: (e) => {
          if (e.type === 'closed') p.closedAt = performance.now();
        },
      });
      framed.add(p.session);
      return p;
    }),
  );
}

/** Both players of a relay room on one hash at `ticks`, no desync. */
function expectRelayAgrees(room: string, players: Player[], ticks: number): void {
  const hashes = players.map((p) => p.session.hashAt(ticks));
  expect(hashes[0], `${room}: a hash at ${ticks}`).toBeDefined();
  expect(new Set(hashes.map((h) => hex64(h!))).size, `${room}: final hashes`).toBe(1);
  for (const p of players) expect(p.session.desyncs, `${room}: desyncs`).toEqual([]);
}

interface Watcher {
  session: StateSyncSession<ButtonInput, Game>;
  /** The server world's hash at each snapshot tick this client saw. */
  hashes: Map<number, string>;
  closedAt: number | undefined;
}

/** A state-sync room of capture the flag: two players through HAProxy. */
async function playState(room: string): Promise<Watcher[]> {
  return Promise.all(
    [0, 1].map(async () => {
      const transport = await open(`/state/${room}`);
      const w: Watcher = { session: undefined!, hashes: new Map(), closedAt: undefined };
      w.session = new StateSyncSession<ButtonInput, Game>({
        transport,
        clock,
        room,
        game: ctfGame,
        players: 2,
        seed: 5,
        localInput: (_t, sim) => ctfGame.bot(sim, w.session.welcome?.slot ?? 0),
        onEvent: (e) => {
          if (e.type === 'closed') w.closedAt = performance.now();
        },
      });
      framed.add({
        frame: () => {
          w.session.frame();
          const t = w.session.snapshotTick;
          const s = w.session.snapshotState;
          if (s && !w.hashes.has(t)) w.hashes.set(t, hex64(fnv1a64(s)));
        },
      });
      return w;
    }),
  );
}

/** Snapshot ticks both clients of a state room saw, and on how many their worlds differed. */
function stateAgreement(watchers: Watcher[]): { common: number; newest: number; differ: number } {
  const [a, b] = watchers as [Watcher, Watcher];
  let common = 0;
  let newest = -1;
  let differ = 0;
  for (const [t, h] of a.hashes) {
    const other = b.hashes.get(t);
    if (other === undefined) continue;
    common++;
    newest = Math.max(newest, t);
    if (other !== h) differ++;
  }
  return { common, newest, differ };
}

interface SignalRoom {
  host: SignalClient;
  joiner: SignalClient;
  link: PeerLink;
  /** What the joiner got back through the tunnel (the host echoes). */
  echoes: string[];
  closedAt: number | undefined;
}

/**
 * A host at `/signal/<room>` and a joiner with its invite: the joiner finds the host through the
 * hub and, with no direct route, tunnels through it; the host echoes what the joiner sends.
 */
async function hostSignal(room: string): Promise<SignalRoom> {
  const host = new SignalClient(await open(`/signal/${room}`));
  const rtc = { PeerConnection: UnreachablePeerConnection, room, connectTimeoutMs: 100 };
  const hosting = new PeerHost({
    ...rtc,
    signal: host,
    onPeer: (link) => {
      link.transport.onMessage((bytes) => {
        link.transport.send(bytes);
      });
    },
  });
  const { invite } = await hosting.ready;
  const joiner = new SignalClient(await open(`/signal/${room}`));
  const link = await joinPeer({ ...rtc, invite, signal: joiner });
  const r: SignalRoom = { host, joiner, link, echoes: [], closedAt: undefined };
  link.transport.onMessage((bytes) => r.echoes.push(new TextDecoder().decode(bytes)));
  host.onClose(() => (r.closedAt ??= performance.now()));
  return r;
}

/** The joiner sends `text` through the tunnel and waits for its host's echo. */
async function echo(room: string, r: SignalRoom, text: string): Promise<void> {
  r.link.transport.send(new TextEncoder().encode(text));
  await until(`${room}: the echo of ${text}`, () => r.echoes.includes(text), 30_000);
}

/** A player from `from` queues at `/match` through HAProxy for a match of two. */
function queueFrom(from: string, onQueued?: () => void): Promise<QuickMatchResult> {
  return quickMatch({
    url: `ws://127.0.0.1:${lb.port}/match`,
    game: ctfGame.id,
    gameVersion: ctfGame.version,
    input: ctfGame.input,
    minPlayers: 2,
    WebSocketClass: class extends WebSocket {
      constructor(url: string) {
        super(url, { localAddress: from });
      }
    },
    ...(onQueued ? { onQueued } : {}),
  });
}

/** Players from `from` (an even number of addresses) queue together; they are matched in pairs. */
async function quickPairs(from: string[]): Promise<QuickMatchResult[][]> {
  const results = await Promise.all(from.map((a) => queueFrom(a)));
  const rooms = new Map<string, QuickMatchResult[]>();
  for (const r of results) rooms.set(r.room, [...(rooms.get(r.room) ?? []), r]);
  const pairs = [...rooms.values()].map((p) => p.sort((a, b) => a.order - b.order));
  expect(pairs.map((p) => p.map((r) => r.order))).toEqual(pairs.map(() => [0, 1]));
  expect(pairs).toHaveLength(from.length / 2);
  return pairs;
}

// ----------------------------------------------------------------------- where a room lives

/**
 * Whether room `room` of `surface` exists on the process at `port`, asked directly: a spectator
 * (relay, state sync) or a joiner (signalling) without the room's invite is refused with BAD_TOKEN
 * where the room is, and told there is no such room where it is not.
 */
function roomOn(port: number, surface: 'ws' | 'state' | 'signal', room: string): Promise<boolean> {
  const join = {
    room,
    role: 'spectator',
    game: ctfGame.id,
    gameVersion: ctfGame.version,
    input: ctfGame.input.id,
    players: 2,
    name: 'probe',
  } as const;
  const [frame, decode] =
    surface === 'ws'
      ? [encodeMessage({ type: 'hello', ...join }), (b: Uint8Array) => decodeFrame(b)[0]!]
      : surface === 'state'
        ? [encodeStateSyncMessage({ type: 'join', ...join }), decodeStateSyncMessage]
        : [encodeSignal({ type: 'join', room, invite: new Uint8Array(16) }), decodeSignal];
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(`ws://127.0.0.1:${port}/${surface}/${room}`);
    ws.on('open', () => {
      ws.send(frame);
    });
    ws.on('message', (data: Buffer) => {
      const m = decode(new Uint8Array(data)) as { type: string; code?: string };
      if (m.type !== 'error') return;
      ws.terminate();
      resolve(m.code === 'BAD_TOKEN');
    });
    ws.on('error', reject);
  });
}

/** The process (index into `relays`) holding each room; exactly one each, among `live`. */
async function homes(
  surface: 'ws' | 'state' | 'signal',
  rooms: Iterable<string>,
  live: number[] = [0, 1, 2],
): Promise<Map<string, number>> {
  const home = new Map<string, number>();
  for (const room of rooms) {
    const on = await Promise.all(live.map((i) => roomOn(relays[i]!.port, surface, room)));
    expect(on.filter(Boolean), `${surface} ${room} on ${on.join(',')}`).toHaveLength(1);
    home.set(room, live[on.indexOf(true)]!);
  }
  return home;
}

/** Connections HAProxy's quick-match backend gave each process so far. */
async function matchSessions(): Promise<number[]> {
  const stats = await lb.stats();
  return ['relay1', 'relay2', 'relay3'].map(
    (s) => stats.find((x) => x.backend === 'relays_match' && x.server === s)!.sessions,
  );
}

// -------------------------------------------------------------------------------------- tests

describe.skipIf(haproxy === undefined)('three processes behind HAProxy', () => {
  it('relay, state-sync, signalling and quick-match rooms each on one process; kill -9 of the queue’s process', async () => {
    const ticks = 600;
    const qmTicks = 180;
    // The queue's process: `balance first` sends /match to relay1 while it lives.
    const queue = 0;
    const frames = setInterval(() => {
      for (const s of framed) s.frame();
    }, 8);
    const leaveAll: (() => void)[] = [];
    try {
      // ---- Quick match: the queue on relay1, the matched rooms wherever their names hash.
      const qmRooms = new Map<string, Player[]>();
      const qmHome = new Map<string, number>();
      // Batches of three pairs until a room has landed away from the queue's process (a room's
      // name is random: about two in three do).
      for (let batch = 0; batch < 5 && ![...qmHome.values()].some((h) => h !== queue); batch++) {
        const pairs = await quickPairs(Array.from({ length: 6 }, address));
        const played = await Promise.all(
          pairs.map(async (pair) => {
            const room = pair[0]!.room;
            expect(room).toMatch(/^qm-/);
            const players = await playRelay(
              room,
              qmTicks,
              pair.map((r) => r.ticket),
            );
            leaveAll.push(() => {
              for (const p of players) p.session.leave();
            });
            return [room, players] as const;
          }),
        );
        for (const [room, players] of played) qmRooms.set(room, players);
        await until(
          'the quick-match rooms to finish',
          () => played.every(([, ps]) => ps.every((p) => p.session.isFinished)),
          60_000,
        );
        for (const [room, h] of await homes(
          'ws',
          played.map(([r]) => r),
        ))
          qmHome.set(room, h);
      }
      for (const [room, players] of qmRooms) {
        expectRelayAgrees(room, players, qmTicks);
        // The matchmaker's setup: the seat its ticket names.
        expect(players.map((p) => p.session.welcome!.slot)).toEqual([0, 1]);
      }
      const qmAway = [...qmHome.values()].filter((h) => h !== queue).length;
      expect(
        qmAway,
        'quick-match rooms played on another process than the queue’s',
      ).toBeGreaterThan(0);
      // Every queue connection went to relay1.
      const queued = await matchSessions();
      expect(queued[0]).toBe(2 * qmRooms.size);
      expect(queued.slice(1)).toEqual([0, 0]);
      for (const leave of leaveAll.splice(0)) leave();

      // ---- Relay, state-sync and signalling rooms, all at once.
      const relayNames = Array.from({ length: 12 }, (_, i) => `room-${i}`);
      const stateNames = Array.from({ length: 6 }, (_, i) => `state-${i}`);
      const signalNames = Array.from({ length: 6 }, (_, i) => `signal-${i}`);
      const relayRooms = new Map<string, Player[]>();
      const stateRooms = new Map<string, Watcher[]>();
      const signalRooms = new Map<string, SignalRoom>();
      leaveAll.push(() => {
        for (const ps of relayRooms.values()) for (const p of ps) p.session.leave();
        for (const ws of stateRooms.values()) for (const w of ws) w.session.leave();
        for (const r of signalRooms.values()) {
          r.joiner.close();
          r.host.close();
        }
      });
      for (const name of relayNames) relayRooms.set(name, await playRelay(name, ticks));
      for (const name of stateNames) stateRooms.set(name, await playState(name));
      for (const name of signalNames) signalRooms.set(name, await hostSignal(name));
      await until('every relay and state-sync room to start', () =>
        [
          ...[...relayRooms.values()].flat().map((p) => p.session.phase),
          ...[...stateRooms.values()].flat().map((w) => w.session.phase),
        ].every((phase) => phase === 'running'),
      );
      // Where each room is: on exactly one process; the rooms of each surface on several.
      const relayHome = await homes('ws', relayNames);
      const stateHome = await homes('state', stateNames);
      const signalHome = await homes('signal', signalNames);
      for (const home of [relayHome, stateHome, signalHome]) {
        expect(new Set(home.values()).size).toBeGreaterThanOrEqual(2);
      }
      // Every state-sync pair in one world; every joiner with its host.
      for (const [name, watchers] of stateRooms) {
        await until(`${name}: ten snapshots both saw`, () => stateAgreement(watchers).common >= 10);
        expect(stateAgreement(watchers).differ, `${name}: snapshots that differ`).toBe(0);
        expect(new Set(watchers.map((w) => w.session.welcome!.slot))).toEqual(new Set([0, 1]));
      }
      for (const [name, r] of signalRooms) {
        expect(r.link.via).toBe('server');
        await echo(name, r, 'before');
      }

      // ---- kill -9 of the queue's process, mid-match.
      const orphansOf = (home: Map<string, number>) =>
        [...home].filter(([, h]) => h === queue).map(([n]) => n);
      const survivorsOf = (home: Map<string, number>) =>
        [...home].filter(([, h]) => h !== queue).map(([n]) => n);
      const orphans = {
        relay: orphansOf(relayHome),
        state: orphansOf(stateHome),
        signal: orphansOf(signalHome),
      };
      const survivors = {
        relay: survivorsOf(relayHome),
        state: survivorsOf(stateHome),
        signal: survivorsOf(signalHome),
      };
      // The room names are fixed and HAProxy's ring is fixed by the servers' ids: each surface has
      // rooms on the victim and elsewhere, every run.
      for (const kind of ['relay', 'state', 'signal'] as const) {
        expect(orphans[kind].length, `${kind} rooms on the victim`).toBeGreaterThan(0);
        expect(survivors[kind].length, `${kind} rooms elsewhere`).toBeGreaterThan(0);
      }
      const stateAtKill = new Map(
        survivors.state.map((n) => [n, stateAgreement(stateRooms.get(n)!).newest]),
      );
      // A player waiting in the queue when its process dies.
      const lone = address();
      let loneQueued = false;
      const lonely = queueFrom(lone, () => (loneQueued = true)).then(
        () => 'matched',
        (error: unknown) => (error as MatchmakingError).code,
      );
      await until('a player to wait in the queue', () => loneQueued);

      const killedAt = performance.now();
      relays[queue]!.child.kill('SIGKILL');

      // Its clients are closed at once: no hang.
      const closedAt = () => [
        ...orphans.relay.flatMap((n) => relayRooms.get(n)!.map((p) => p.closedAt)),
        ...orphans.state.flatMap((n) => stateRooms.get(n)!.map((w) => w.closedAt)),
        ...orphans.signal.map((n) => signalRooms.get(n)!.closedAt),
      ];
      await until('the orphaned clients to be closed', () =>
        closedAt().every((at) => at !== undefined),
      );
      for (const at of closedAt()) expect(at! - killedAt).toBeLessThan(5000);
      for (const n of orphans.relay) for (const p of relayRooms.get(n)!) framed.delete(p.session);

      // They start again under the same names: HAProxy sends each to a live process.
      for (const n of orphans.relay) relayRooms.set(n, await playRelay(n, ticks));
      for (const n of orphans.state) stateRooms.set(n, await playState(n));
      for (const n of orphans.signal) signalRooms.set(n, await hostSignal(n));
      // And /match moves on: the waiting player was told the connection closed; it queues again
      // with three newcomers, relay2 matches them, and they play.
      expect(await lonely).toBe('CONNECTION');
      const after = await quickPairs([lone, address(), address(), address()]);
      const afterRooms = await Promise.all(
        after.map(async (pair) => {
          const room = pair[0]!.room;
          const players = await playRelay(
            room,
            qmTicks,
            pair.map((r) => r.ticket),
          );
          return [room, players] as const;
        }),
      );
      leaveAll.push(() => {
        for (const [, ps] of afterRooms) for (const p of ps) p.session.leave();
      });

      // Every relay room finishes, old and new, quick-match ones too; both players on one hash.
      await until(
        'every relay room to finish',
        () =>
          [...relayRooms.values(), ...afterRooms.map(([, ps]) => ps)]
            .flat()
            .every((p) => p.session.isFinished),
        120_000,
      );
      for (const [name, players] of relayRooms) expectRelayAgrees(name, players, ticks);
      for (const [room, players] of afterRooms) expectRelayAgrees(room, players, qmTicks);
      const matchedAfter = await matchSessions();
      expect(matchedAfter[1], 'queue connections to relay2 after the kill').toBe(4);
      expect(matchedAfter[2]).toBe(0);

      // The survivors' state-sync worlds go on (two seconds of snapshots past the kill), in step;
      // the new rooms too.
      for (const [name, watchers] of stateRooms) {
        const from = stateAtKill.get(name) ?? -1;
        await until(`${name}: snapshots past the kill`, () => {
          const a = stateAgreement(watchers);
          return a.common >= 10 && a.newest >= from + 120;
        });
        expect(stateAgreement(watchers).differ, `${name}: snapshots that differ`).toBe(0);
      }
      // The survivors' joiners still reach their hosts; the new rooms' too.
      for (const [name, r] of signalRooms) await echo(name, r, 'after');

      // Nothing is left on the dead process; each room once, on a live one.
      const live = [0, 1, 2].filter((i) => i !== queue);
      const relayAfter = await homes('ws', relayNames, live);
      await homes(
        'ws',
        afterRooms.map(([r]) => r),
        live,
      );
      const stateAfter = await homes('state', stateNames, live);
      const signalAfter = await homes('signal', signalNames, live);
      // The survivors stayed where they were (consistent hashing moves only the victim's rooms).
      for (const n of survivors.relay) expect(relayAfter.get(n)).toBe(relayHome.get(n));
      for (const n of survivors.state) expect(stateAfter.get(n)).toBe(stateHome.get(n));
      for (const n of survivors.signal) expect(signalAfter.get(n)).toBe(signalHome.get(n));
      expect(await lb.usable('relays_by_room')).toBe(2);
      expect(await lb.usable('relays_match')).toBe(2);
    } finally {
      clearInterval(frames);
      for (const leave of leaveAll) leave();
      framed.clear();
    }
  }, 300_000);
});

// The checked configuration is the one deployed: no test-only edits but the statistics frontend.
describe.skipIf(haproxy === undefined)('the deployed HAProxy configuration', () => {
  it('is what this test runs (haproxy -c on both files)', () => {
    const r = spawnSync(haproxy!, ['-c', '-f', HAPROXY_CFG, '-f', path.join(dir, 'stats.cfg')], {
      env: {
        PATH: process.env.PATH ?? '',
        FIXEDSTEP_RELAY1: '127.0.0.1:1',
        FIXEDSTEP_RELAY2: '127.0.0.1:2',
        FIXEDSTEP_RELAY3: '127.0.0.1:3',
      },
      encoding: 'utf8',
    });
    expect(r.status).toBe(0);
  });
});
