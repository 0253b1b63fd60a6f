/**
 * A program in a process of its own, driven over a line protocol: a command on its stdin, one line
 * on its stdout in answer, one command at a time. The contestants that run apart from the bench
 * (springs.c and springs-js.ts, each peer engine) are driven through one.
 */
import type { ChildProcessWithoutNullStreams } from 'node:child_process';
import { createInterface } from 'node:readline';

export class LineProcess<R> {
  /** Settles once the program has exited. */
  readonly exited: Promise<void>;
  private readonly waiting: { resolve: (reply: R) => void; reject: (error: Error) => void }[] = [];
  /** Why every later command fails: the program failed to start, or exited. */
  private failure: Error | undefined;

  /**
   * Drives `child`, named `name` in errors. `parse` turns an answer line into a reply, or throws
   * (on a line that is no reply, or one that reports an error): the command it answers then fails
   * with that error.
   */
  constructor(
    readonly child: ChildProcessWithoutNullStreams,
    name: string,
    parse: (line: string) => R,
  ) {
    const fail = (error: Error) => {
      this.failure ??= error;
      for (const w of this.waiting.splice(0)) w.reject(this.failure);
    };
    createInterface({ input: child.stdout }).on('line', (line) => {
      const w = this.waiting.shift();
      if (w === undefined) return;
      let reply: R;
      try {
        reply = parse(line);
      } catch (e) {
        w.reject(e as Error);
        return;
      }
      w.resolve(reply);
    });
    let stderr = '';
    child.stderr.setEncoding('utf8').on('data', (chunk: string) => (stderr += chunk));
    child.on('error', fail);
    this.exited = new Promise((resolve) => {
      child.on('exit', (code, signal) => {
        fail(new Error(`${name} exited (${signal ?? code}) ${stderr}`.trim()));
        resolve();
      });
    });
  }

  /** The next line's reply (the first one: the program's "ready"). */
  next(): Promise<R> {
    if (this.failure !== undefined) return Promise.reject(this.failure);
    return new Promise((resolve, reject) => this.waiting.push({ resolve, reject }));
  }

  /** Sends `text` and resolves to the reply it gets. */
  command(text: string): Promise<R> {
    const reply = this.next();
    this.child.stdin.write(`${text}\n`);
    return reply;
  }

  /** Whether the program is still running. */
  get running(): boolean {
    return this.child.exitCode === null && this.child.signalCode === null;
  }
}
