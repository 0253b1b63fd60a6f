/**
 * A relay client that speaks the protocol by hand, for the tests that misbehave on purpose
 * (net-hostile) or idle, squat and lie (net-strangers): it keeps every message it got and the
 * reason its transport closed, and says hello to a room of capture the flag.
 */
import {
  decodeFrame,
  encodeMessage,
  type ErrorMessage,
  type NetMessage,
  type Transport,
  type WelcomeMessage,
} from 'fixedstep';
import { ctfGame } from '@fixedstep/games';

export interface RawClientOptions {
  /** The name its hellos give. */
  name: string;
  /** The number of players its hellos ask for. */
  players: number;
  /** A room's invite token, which a spectator's hello carries unless told otherwise. */
  inviteOf?: (room: string) => Uint8Array | undefined;
  /** Answer the relay's liveness pings (an idle but live squatter); default: stay silent. */
  answerPings?: boolean;
}

/** A client that speaks the relay protocol by hand. */
export class RawClient {
  readonly got: NetMessage[] = [];
  closed: string | undefined;
  constructor(
    readonly t: Transport,
    private readonly options: RawClientOptions,
  ) {
    // A frame may carry several messages (protocol 5's batch frame).
    t.onMessage((frame) => {
      for (const m of decodeFrame(frame)) {
        this.got.push(m);
        if (options.answerPings && m.type === 'ping') {
          this.send({ type: 'pong', id: m.id, time: m.time, serverTime: 0 });
        }
      }
    });
    t.onClose((r) => (this.closed = r));
  }
  send(m: NetMessage): void {
    this.t.send(encodeMessage(m));
  }
  bytes(b: Uint8Array): void {
    this.t.send(b);
  }
  hello(
    room: string,
    role: 'player' | 'spectator' = 'spectator',
    extra: Partial<NetMessage> = {},
  ): void {
    const invite = role === 'spectator' ? this.options.inviteOf?.(room) : undefined;
    this.send({
      type: 'hello',
      room,
      role,
      ...(invite ? { token: invite } : {}),
      game: 'ctf',
      gameVersion: ctfGame.info.version,
      input: ctfGame.input.id,
      players: this.options.players,
      name: this.options.name,
      ...extra,
    } as NetMessage);
  }
  get welcome(): WelcomeMessage | undefined {
    return this.got.find((m): m is WelcomeMessage => m.type === 'welcome');
  }
  get error(): ErrorMessage | undefined {
    return this.got.find((m): m is ErrorMessage => m.type === 'error' && m.fatal);
  }
}
