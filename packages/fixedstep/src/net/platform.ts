/**
 * The platform objects the network helpers accept — a WebSocket, an AbortSignal, `fetch`'s
 * arguments and answer — typed structurally, by the few members the library uses. The published
 * declarations name no global of the DOM or of Node, so a project compiled with
 * `lib: ["ES2022"], types: []` (a game's simulation, built for Node and the browser alike)
 * type-checks them; the browser's and Node's objects fit these types as they are.
 * @module
 */

/** The part of an `AbortSignal` (browser or Node) the library uses. */
export interface AbortSignalLike {
  readonly aborted: boolean;
  readonly reason?: unknown;
  addEventListener(type: 'abort', listener: () => void, options?: { once?: boolean }): void;
  removeEventListener(type: 'abort', listener: () => void): void;
}

/** A WebSocket `message` event, as far as the library reads it. */
export interface WebSocketMessageEventLike {
  readonly data: unknown;
}

/** A WebSocket `close` event, as far as the library reads it. */
export interface WebSocketCloseEventLike {
  readonly code: number;
  readonly reason: string;
}

/**
 * The part of a browser-style `WebSocket` the library uses: the browser's, Node 22's global one,
 * and the `ws` package's fit it.
 */
export interface WebSocketLike {
  /** Set to `'arraybuffer'` by the library: binary frames arrive as `ArrayBuffer`s. */
  binaryType: string;
  readonly readyState: number;
  readonly bufferedAmount: number;
  send(data: Uint8Array): void;
  close(code?: number, reason?: string): void;
  addEventListener(type: 'open' | 'error', listener: () => void): void;
  addEventListener(type: 'message', listener: (event: WebSocketMessageEventLike) => void): void;
  addEventListener(type: 'close', listener: (event: WebSocketCloseEventLike) => void): void;
}

/** A WebSocket class: `new WebSocketClass(url)` opens a connection. */
export type WebSocketClassLike = new (url: string) => WebSocketLike;

/** The part of `fetch`'s second argument the library reads. */
export interface FetchInitLike {
  readonly signal?: AbortSignalLike | null;
}

/** The part of a `fetch` answer the library reads. */
export interface FetchResponseLike {
  readonly status: number;
  readonly headers: { get(name: string): string | null };
  readonly body?: { cancel(): Promise<void> } | null;
}

/** The platform's `fetch`, where the compilation declares one (DOM, `@types/node`). */
type PlatformFetch = typeof globalThis extends { fetch: infer F } ? F : never;

/**
 * `fetch`'s second argument: the platform's `RequestInit` where the compilation declares `fetch`
 * (the DOM lib, `@types/node`), else {@link FetchInitLike}.
 */
export type FetchInit = PlatformFetch extends (input: never, init?: infer I) => unknown
  ? NonNullable<I> & FetchInitLike
  : FetchInitLike;

/**
 * A `fetch` answer: the platform's `Response` where the compilation declares `fetch`, else
 * {@link FetchResponseLike}.
 */
export type FetchResponse = PlatformFetch extends (...args: never[]) => Promise<infer R>
  ? R & FetchResponseLike
  : FetchResponseLike;

/**
 * Why `signal` aborted, to reject with: `abort()`'s reason as given (an `AbortError`
 * `DOMException` when none was given).
 */
export function abortReason(signal: AbortSignalLike): Error {
  return signal.reason as Error;
}
