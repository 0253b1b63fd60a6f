/**
 * A room host whose rooms each play one game of a catalog — the relay and the state-sync server:
 * their joins (a relay `hello`, a state-sync `join`) are taken alike.
 * @module
 */
import type { JoinFields } from '../wire/common.js';
import { gameJoinPlan, type GameJoinContext, type HostedGame } from './game-join.js';
import { RoomHost } from './host.js';
import type { Member, Room } from './room.js';

/** A room that plays one game: what `gameJoinPlan` checks a join against. */
type GameRoom<M extends Member, G extends HostedGame> = Room<M> & {
  game: G;
  seed: number;
};

/** A {@link RoomHost} whose rooms play the games of a catalog. */
export abstract class GameRoomHost<
  M extends Member,
  R extends GameRoom<M, G>,
  Msg extends { type: string },
  E extends { type: string } = never,
  G extends HostedGame = HostedGame,
> extends RoomHost<M, R, Msg, E> {
  /**
   * Takes a game join of a connection with no room yet (a repeated one is ignored): the plan from
   * `gameJoinPlan` (a refusal drops the connection), a `room-created` event for a room it
   * makes, then {@link RoomHost.join}. Returns true (the join is handled).
   */
  protected joinGame(
    m: M,
    join: JoinFields,
    context: Omit<GameJoinContext<G, R>, 'randomU32'>,
    now: number,
  ): true {
    if (m.state !== 'new') return true;
    m.name = join.name;
    const plan = gameJoinPlan(join, { ...context, randomU32: this.context.randomU32 });
    if (Array.isArray(plan)) {
      this.drop(m, plan[0], plan[1]);
      return true;
    }
    plan.created = (room) => {
      this.emit({
        type: 'room-created',
        room: room.name,
        game: room.game.id,
        players: room.players,
      });
    };
    this.join(m, plan, now);
    return true;
  }
}
