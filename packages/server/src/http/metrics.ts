import { Counter, Gauge, Histogram, Registry, collectDefaultMetrics } from 'prom-client';
import type { Relay } from 'fixedstep';
import type { StateSyncWorkerStats } from '../state-sync/messages.js';

/**
 * The server's Prometheus metrics (`GET /metrics`), in a registry of its own (never prom-client's
 * global one, so two servers in one process do not mix): HTTP requests, the verification queue,
 * its latency and outcomes, store errors, and the relay's rooms, players, messages and desyncs.
 */
export class ServerMetrics {
  readonly registry = new Registry();
  readonly httpRequests = new Counter({
    name: 'fixedstep_http_requests_total',
    help: 'HTTP requests answered, by method, route and status',
    labelNames: ['method', 'route', 'status'] as const,
    registers: [this.registry],
  });
  readonly verificationQueue = new Gauge({
    name: 'fixedstep_verification_queue_length',
    help: 'Submissions waiting for a verification worker',
    registers: [this.registry],
  });
  readonly verificationRunning = new Gauge({
    name: 'fixedstep_verifications_running',
    help: 'Submissions being re-simulated right now',
    registers: [this.registry],
  });
  readonly verificationSeconds = new Histogram({
    name: 'fixedstep_verification_seconds',
    help: 'Time from queueing a submission to its verdict, in seconds',
    buckets: [0.005, 0.02, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10],
    registers: [this.registry],
  });
  readonly verificationOutcomes = new Counter({
    name: 'fixedstep_verification_outcomes_total',
    help: 'Verdicts on submissions: ok, or the refusal code (DOES_NOT_REPRODUCE, SCORE_MISMATCH, …)',
    labelNames: ['outcome'] as const,
    registers: [this.registry],
  });
  readonly submissions = new Counter({
    name: 'fixedstep_submissions_total',
    help: 'Highscore submissions answered, by result (added, repeated, or the refusal code)',
    labelNames: ['result'] as const,
    registers: [this.registry],
  });
  readonly storeErrors = new Counter({
    name: 'fixedstep_store_errors_total',
    help: 'Store operations that failed (the database was down or refused)',
    registers: [this.registry],
  });

  constructor(options: { defaultMetrics?: boolean } = {}) {
    if (options.defaultMetrics !== false)
      collectDefaultMetrics({ register: this.registry, prefix: 'fixedstep_' });
  }

  /**
   * Adds state sync's rooms and players (gauges) and its ticks, snapshot bytes, late and filled
   * inputs (counters), read from what its workers last reported (each does every second).
   */
  watchStateSync(stateSync: { readonly stats: StateSyncWorkerStats }): void {
    const registers = [this.registry];
    new Gauge({
      name: 'fixedstep_state_sync_rooms',
      help: 'State-sync rooms open',
      registers,
      collect() {
        this.set(stateSync.stats.rooms);
      },
    });
    new Gauge({
      name: 'fixedstep_state_sync_players',
      help: 'Player seats with a connected member in state-sync rooms',
      registers,
      collect() {
        this.set(stateSync.stats.players);
      },
    });
    const counter = (name: string, help: string, key: keyof StateSyncWorkerStats) =>
      new Counter({
        name,
        help,
        registers,
        collect() {
          // The workers keep the running totals; a counter here only mirrors them.
          this.reset();
          this.inc(stateSync.stats[key]);
        },
      });
    counter('fixedstep_state_sync_ticks_total', 'Ticks stepped by state-sync rooms', 'ticks');
    counter(
      'fixedstep_state_sync_snapshot_bytes_total',
      'Bytes of snapshot messages sent by state-sync rooms (headers included)',
      'snapshotBytes',
    );
    counter(
      'fixedstep_state_sync_late_inputs_total',
      "Inputs that arrived after their tick was stepped (dropped: the server's stand-in stood)",
      'lateInputs',
    );
    counter(
      'fixedstep_state_sync_filled_inputs_total',
      "Player-ticks stepped without that player's input (the server's stand-in)",
      'filledInputs',
    );
  }

  /** Adds the relay's gauges, read from `relay.stats` and `relay.roomList()` at each scrape. */
  watchRelay(relay: Relay): void {
    const gauge = (name: string, help: string, read: () => number) =>
      new Gauge({
        name,
        help,
        registers: [this.registry],
        collect() {
          this.set(read());
        },
      });
    gauge(
      'fixedstep_relay_connections',
      'WebSocket connections to the relay',
      () => relay.stats.connections,
    );
    gauge('fixedstep_relay_rooms', 'Rooms open on the relay', () => relay.stats.rooms);
    gauge('fixedstep_relay_players', "Players in the relay's rooms", () =>
      relay.roomList().reduce((sum, room) => sum + room.players, 0),
    );
    gauge(
      'fixedstep_relay_rooms_running',
      'Rooms whose match is running',
      () => relay.roomList().filter((room) => room.state === 'running').length,
    );
    gauge(
      'fixedstep_relay_messages_in_total',
      'Messages received by the relay',
      () => relay.stats.messagesIn,
    );
    gauge(
      'fixedstep_relay_messages_out_total',
      'Messages sent by the relay',
      () => relay.stats.messagesOut,
    );
    gauge('fixedstep_relay_bytes_out_total', 'Bytes sent by the relay', () => relay.stats.bytesOut);
    gauge('fixedstep_relay_desyncs_total', 'Desyncs the relay detected', () => relay.stats.desyncs);
  }
}
