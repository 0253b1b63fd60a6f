/**
 * A PostgreSQL server for a test: Debian's binaries (`FIXEDSTEP_PG_BIN`, else the newest under
 * /usr/lib/postgresql), a cluster made in a scratch folder on a free port, started and stopped
 * when the test says — as the `postgres` user when we are root (PostgreSQL refuses to run as root).
 */
import { spawnSync } from 'node:child_process';
import { chownSync, existsSync, mkdtempSync, readdirSync, rmSync } from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';

/** The PostgreSQL binaries, or undefined when there are none (then the tests that need them skip). */
export const pgBin: string | undefined =
  process.env.FIXEDSTEP_PG_BIN ??
  (existsSync('/usr/lib/postgresql')
    ? readdirSync('/usr/lib/postgresql')
        .sort((a, b) => Number(b) - Number(a))
        .map((v) => `/usr/lib/postgresql/${v}/bin`)
        .find((b) => existsSync(path.join(b, 'initdb')))
    : undefined);

const isRoot = process.getuid?.() === 0;

function asPostgres(cmd: string, args: string[]): { status: number | null; output: string } {
  const r = isRoot
    ? spawnSync('runuser', ['-u', 'postgres', '--', cmd, ...args], { encoding: 'utf8' })
    : spawnSync(cmd, args, { encoding: 'utf8' });
  return { status: r.status, output: `${r.stdout}${r.stderr}` };
}

/** A free TCP port on 127.0.0.1 (free when asked). */
export function freePort(): Promise<number> {
  return new Promise((resolve) => {
    const s = net.createServer().listen(0, '127.0.0.1', () => {
      const port = (s.address() as net.AddressInfo).port;
      s.close(() => {
        resolve(port);
      });
    });
  });
}

/** A cluster made (`initdb`) but not started: {@link PgCluster.start} and {@link PgCluster.stop}. */
export class PgCluster {
  private readonly dir: string;
  private running = false;

  private constructor(
    private readonly bin: string,
    /** Its port on 127.0.0.1. */
    readonly port: number,
  ) {
    this.dir = mkdtempSync(path.join(os.tmpdir(), 'fixedstep-pg-'));
    if (isRoot) {
      const uid = spawnSync('id', ['-u', 'postgres'], { encoding: 'utf8' });
      const gid = spawnSync('id', ['-g', 'postgres'], { encoding: 'utf8' });
      chownSync(this.dir, Number(uid.stdout), Number(gid.stdout));
    }
    const init = asPostgres(path.join(bin, 'initdb'), [
      '-D',
      this.data,
      '-A',
      'trust',
      '-U',
      'postgres',
      '--no-sync',
    ]);
    if (init.status !== 0) throw new Error(`initdb failed: ${init.output}`);
  }

  /** Makes a cluster on a free port (not started). */
  static async create(bin: string): Promise<PgCluster> {
    return new PgCluster(bin, await freePort());
  }

  private get data(): string {
    return path.join(this.dir, 'data');
  }

  /** Its connection string. */
  get url(): string {
    return `postgres://postgres@127.0.0.1:${this.port}/postgres`;
  }

  /** Starts it and waits until it accepts connections. */
  start(): void {
    const r = asPostgres(path.join(this.bin, 'pg_ctl'), [
      '-D',
      this.data,
      '-l',
      path.join(this.dir, 'log'),
      '-w',
      '-t',
      '60',
      '-o',
      `-p ${this.port} -k ${this.dir} -c listen_addresses=127.0.0.1`,
      'start',
    ]);
    if (r.status !== 0) throw new Error(`pg_ctl start failed: ${r.output}`);
    this.running = true;
  }

  /** Stops it at once (`-m immediate`: a crash, as far as clients can tell). */
  stop(): void {
    if (!this.running) return;
    asPostgres(path.join(this.bin, 'pg_ctl'), ['-D', this.data, '-m', 'immediate', 'stop']);
    this.running = false;
  }

  /** Stops it and removes its folder. */
  remove(): void {
    this.stop();
    rmSync(this.dir, { recursive: true, force: true });
  }
}
