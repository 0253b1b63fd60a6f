/**
 * deploy/ is checked, not built (no Docker engine or cluster here): the Kubernetes manifests are
 * parsed with a YAML library and validated against the Kubernetes API schemas
 * (kubernetes-models), cross-checked against each other and against the server (ports, probe
 * paths, environment variables the relay reads); the HAProxy configuration is checked by HAProxy
 * itself (`haproxy -c`) and run in front of three stub servers to see where each path goes
 * (both skipped with the reason when Debian's haproxy is not installed); the Dockerfile's
 * instructions, paths and command are checked against the repository.
 */
import { spawnSync, type ChildProcess } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { mkdtemp, rm } from 'node:fs/promises';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { parseAllDocuments, parse as parseYaml } from 'yaml';
import { Namespace } from 'kubernetes-models/v1/Namespace';
import { Service } from 'kubernetes-models/v1/Service';
import { Deployment } from 'kubernetes-models/apps/v1/Deployment';
import { StatefulSet } from 'kubernetes-models/apps/v1/StatefulSet';
import { PodDisruptionBudget } from 'kubernetes-models/policy/v1/PodDisruptionBudget';
import { admissionOptionsFromEnv } from '../src/http/admission.js';
import { request } from './helpers.js';
import {
  haproxy,
  root,
  startHaproxy,
  stopProcess,
  until,
  type RunningHaproxy,
} from './haproxy-harness.js';

const deploy = path.join(root, 'deploy');
const read = (p: string) => readFileSync(path.join(deploy, p), 'utf8');

interface K8sObject {
  apiVersion: string;
  kind: string;
  metadata: { name: string; labels?: Record<string, string> };
  spec?: Record<string, unknown>;
}

const MODELS: Record<string, new (data: never) => { validate(): void }> = {
  'v1/Namespace': Namespace,
  'v1/Service': Service,
  'apps/v1/Deployment': Deployment,
  'apps/v1/StatefulSet': StatefulSet,
  'policy/v1/PodDisruptionBudget': PodDisruptionBudget,
};

const kustomization = parseYaml(read('kustomization.yaml')) as {
  resources: string[];
  namespace: string;
  configMapGenerator: { name: string; files: string[] }[];
  images: { name: string }[];
};

/** Every YAML document of the manifests the kustomization lists. */
const documents = kustomization.resources.flatMap((file) =>
  parseAllDocuments(read(file)).map((doc) => ({ file, doc })),
);
const objects = documents.map(({ doc }) => doc.toJS() as K8sObject);

const find = (kind: string, name: string): K8sObject => {
  const o = objects.find((x) => x.kind === kind && x.metadata.name === name);
  if (!o) throw new Error(`no ${kind} ${name} in deploy/`);
  return o;
};

interface SecretKeyRef {
  name: string;
  key: string;
  optional?: boolean;
}
interface Container {
  name: string;
  image: string;
  ports: { name: string; containerPort: number }[];
  env?: { name: string; value?: string; valueFrom?: { secretKeyRef?: SecretKeyRef } }[];
  readinessProbe?: { httpGet?: { path: string; port: string } };
  livenessProbe?: { httpGet?: { path: string; port: string } };
}
const podSpec = (o: K8sObject) =>
  (
    o.spec as {
      template: { spec: { containers: Container[]; terminationGracePeriodSeconds?: number } };
    }
  ).template.spec;

describe('deploy/: Kubernetes manifests', () => {
  it('every object parses and is valid against its API schema', () => {
    for (const { file, doc } of documents) {
      expect(doc.errors, `${file}: YAML errors`).toEqual([]);
      expect(doc.warnings, `${file}: YAML warnings`).toEqual([]);
    }
    expect(objects.length).toBeGreaterThanOrEqual(6);
    for (const o of objects) {
      const Model = MODELS[`${o.apiVersion}/${o.kind}`];
      expect(Model, `a schema for ${o.apiVersion} ${o.kind}`).toBeDefined();
      expect(() => {
        new Model!(o as never).validate();
      }, `${o.kind} ${o.metadata.name}`).not.toThrow();
    }
  });

  it('a wrong manifest is caught (the validation is real)', () => {
    const bad = structuredClone(find('StatefulSet', 'fixedstep-relay')) as unknown as {
      spec: { template: { spec: { containers: { ports: { containerPort: unknown }[] }[] } } };
    };
    bad.spec.template.spec.containers[0]!.ports[0]!.containerPort = '8080';
    expect(() => {
      new StatefulSet(bad as never).validate();
    }).toThrow(/containerPort must be integer/);
  });

  it('the kustomization names files that exist, and the HAProxy config as its ConfigMap', () => {
    for (const f of kustomization.resources) expect(existsSync(path.join(deploy, f))).toBe(true);
    const gen = kustomization.configMapGenerator.find((g) => g.name === 'fixedstep-haproxy')!;
    expect(gen.files).toEqual(['haproxy.cfg=haproxy/haproxy.cfg']);
    expect(existsSync(path.join(deploy, 'haproxy/haproxy.cfg'))).toBe(true);
    expect(kustomization.images.map((i) => i.name)).toEqual(['fixedstep']);
    const haproxy = podSpec(find('Deployment', 'fixedstep-haproxy'));
    const volumes = (
      find('Deployment', 'fixedstep-haproxy').spec as {
        template: { spec: { volumes: { configMap?: { name: string } }[] } };
      }
    ).template.spec.volumes;
    expect(volumes.some((v) => v.configMap?.name === 'fixedstep-haproxy')).toBe(true);
    expect(haproxy.containers[0]!.image).toMatch(/^haproxy:2\.6/);
  });

  it('the relays: stable names for HAProxy, the server’s port and probes, drain time, env the relay reads', () => {
    const set = find('StatefulSet', 'fixedstep-relay');
    const svc = find('Service', 'fixedstep-relay');
    const spec = set.spec as { serviceName: string; replicas: number };
    expect(spec.serviceName).toBe('fixedstep-relay');
    expect((svc.spec as { clusterIP: string }).clusterIP).toBe('None');
    // HAProxy's default servers are the pods fixedstep-relay-0..N-1 of that service.
    const cfg = read('haproxy/haproxy.cfg');
    for (let i = 0; i < spec.replicas; i++) {
      expect(cfg).toContain(`fixedstep-relay-${i}.fixedstep-relay:8080`);
    }
    const pod = podSpec(set);
    const c = pod.containers[0]!;
    expect(c.image).toBe('fixedstep');
    expect(c.ports).toEqual([{ name: 'http', containerPort: 8080 }]);
    expect(c.readinessProbe?.httpGet).toEqual({ path: '/readyz', port: 'http' });
    expect(c.livenessProbe?.httpGet).toEqual({ path: '/healthz', port: 'http' });
    expect(cfg).toContain('${FIXEDSTEP_CHECK_PATH-/readyz}');
    // SIGTERM drains for up to 25 s (the default): the grace period must be longer.
    expect(pod.terminationGracePeriodSeconds).toBeGreaterThan(25);
    // The relay reads these variables; the values must parse.
    const env = Object.fromEntries(
      (c.env ?? []).filter((e) => e.value).map((e) => [e.name, e.value]),
    );
    expect(Object.keys(env).filter((k) => k.startsWith('FIXEDSTEP_'))).toEqual([
      'FIXEDSTEP_PROXY_HEADER',
      'FIXEDSTEP_TRUSTED_PROXIES',
      'FIXEDSTEP_ALLOWED_ORIGINS',
      'FIXEDSTEP_STORE_LIVENESS_MS',
    ]);
    // Liveness fails only after the store has not opened for this long: minutes, not seconds.
    expect(Number(env.FIXEDSTEP_STORE_LIVENESS_MS)).toBeGreaterThanOrEqual(60_000);
    expect(admissionOptionsFromEnv(env)).toEqual({
      allowedOrigins: 'same-origin',
      trustProxy: { header: 'x-forwarded-for', proxies: ['10.0.0.0/8'] },
    });
  });

  it('every relay signs and checks quick-match tickets with one secret, from one Secret', () => {
    // The queue's process signs, the process a qm- room hashes to checks: one secret for all pods,
    // and no pod without it (a random secret of its own would refuse the others' tickets).
    const c = podSpec(find('StatefulSet', 'fixedstep-relay')).containers[0]!;
    const secret = c.env?.find((e) => e.name === 'FIXEDSTEP_MATCH_SECRET');
    expect(secret?.value).toBeUndefined();
    expect(secret?.valueFrom?.secretKeyRef).toEqual({ name: 'fixedstep-match', key: 'secret' });
    // How to make it is said where it is used, and in docs/deploy.md.
    const howTo = 'kubectl -n fixedstep create secret generic fixedstep-match';
    expect(read('kubernetes/relay.yaml')).toContain(howTo);
    expect(readFileSync(path.join(root, 'docs/deploy.md'), 'utf8')).toContain(howTo);
  });

  it('the public service keeps client addresses and reaches HAProxy’s port', () => {
    const svc = find('Service', 'fixedstep').spec as {
      type: string;
      externalTrafficPolicy: string;
      ports: { port: number; targetPort: string }[];
      selector: Record<string, string>;
    };
    expect(svc.type).toBe('LoadBalancer');
    expect(svc.externalTrafficPolicy).toBe('Local');
    const haproxy = find('Deployment', 'fixedstep-haproxy');
    const c = podSpec(haproxy).containers[0]!;
    expect(c.ports.map((p) => p.name)).toContain(svc.ports[0]!.targetPort);
    expect(c.env).toContainEqual({ name: 'FIXEDSTEP_BIND', value: ':8080' });
    expect(haproxy.metadata.labels).toMatchObject(svc.selector);
  });
});

describe('deploy/: HAProxy', () => {
  it.skipIf(haproxy === undefined)(
    'haproxy -c accepts the configuration (needs Debian’s haproxy, which npm test installs as root; skipped without it)',
    () => {
      const check = (env: Record<string, string>) =>
        spawnSync(haproxy!, ['-c', '-f', path.join(deploy, 'haproxy/haproxy.cfg')], {
          env: { PATH: process.env.PATH ?? '', ...env },
          encoding: 'utf8',
        });
      const ok = check({
        FIXEDSTEP_RELAY1: '127.0.0.1:18081',
        FIXEDSTEP_RELAY2: '127.0.0.1:18082',
        FIXEDSTEP_RELAY3: '127.0.0.1:18083',
      });
      expect(ok.stdout + ok.stderr).toMatch(/Configuration file is valid/);
      expect(ok.status).toBe(0);
      // With the defaults (the pods' names, unresolvable here) it is still valid.
      expect(check({}).status).toBe(0);
    },
  );

  it('routes every room-scoped path by its room with a consistent hash, /match to one process', () => {
    const cfg = read('haproxy/haproxy.cfg');
    // The relay, state sync and signalling: the room is the third path field (or the relay's query).
    expect(cfg).toMatch(
      /set-var\(txn\.room\) path,field\(3,\/\),url_dec if \{ path_beg \/ws\/ \/state\/ \/signal\/ \}/,
    );
    expect(cfg).toMatch(/set-var\(txn\.room\) url_param\(room\),url_dec if \{ path \/ws \}/);
    expect(cfg).toMatch(/use_backend relays_by_room if \{ var\(txn\.room\) -m found \}/);
    expect(cfg).toMatch(
      /backend relays_by_room\n\s+balance hash var\(txn\.room\)\n\s+hash-type consistent/,
    );
    // Quick match: the first live server by id.
    expect(cfg).toMatch(/use_backend relays_match if \{ path \/match \}/);
    expect(cfg).toMatch(/backend relays_match\n\s+balance first\n/);
    expect(cfg).not.toMatch(/^\s*(server|default-server)\b.*\bmaxconn\b/m);
    expect(cfg).toMatch(/option forwardfor/);
    expect(cfg).toMatch(/timeout tunnel 1h/);
    // Three backends, three servers each, with the same fixed ids and checks.
    const servers = cfg.match(/^\s+server relay\d .* id \d check$/gm)!;
    expect(servers).toHaveLength(9);
    expect(new Set(servers.map((l) => l.trim())).size).toBe(3);
    expect(
      cfg.match(/http-check send meth GET uri "\$\{FIXEDSTEP_CHECK_PATH-\/readyz\}"/g),
    ).toHaveLength(3);
  });
});

/**
 * The configuration run for real in front of three stub servers that answer every request with
 * their own number (and 200 at /readyz): where each path goes, and what a dead server moves.
 */
describe.skipIf(haproxy === undefined)('deploy/: where HAProxy sends each path', () => {
  let dir: string;
  let lb: RunningHaproxy;
  /** HAProxy, once started (stopped after, whatever failed). */
  let started: ChildProcess | undefined;
  const stubs: http.Server[] = [];

  beforeAll(async () => {
    dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-routes-'));
    for (let n = 1; n <= 3; n++) {
      const stub = http.createServer((req, res) => {
        res.end(req.url === '/readyz' ? 'ready' : String(n));
      });
      await new Promise<void>((resolve) => stub.listen(0, '127.0.0.1', resolve));
      stubs.push(stub);
    }
    lb = await startHaproxy(
      dir,
      stubs.map((s) => (s.address() as { port: number }).port),
    );
    started = lb.child;
    await until(
      'HAProxy to see three servers up',
      async () => (await lb.usable('relays_by_room')) === 3,
    );
  }, 60_000);

  afterAll(async () => {
    if (started) await stopProcess(started);
    for (const s of stubs) {
      s.closeAllConnections();
      s.close();
    }
    if (dir) await rm(dir, { recursive: true, force: true });
  });

  /** The stub a request for `p` reached (1 to 3). */
  const via = async (p: string) => Number((await request(lb.port, p)).body.toString());
  const names = Array.from({ length: 40 }, (_, i) => `room-${i}`);
  /** Where each room's four URLs go; they must agree. */
  const homes = async () => {
    const home = new Map<string, number>();
    for (const name of names) {
      const at = await Promise.all(
        [`/ws/${name}`, `/ws?room=${name}`, `/state/${name}`, `/signal/${name}`].map(via),
      );
      expect(new Set(at), `${name}: ${at.join(',')}`).toEqual(new Set([at[0]]));
      home.set(name, at[0]!);
    }
    return home;
  };

  it('a room’s relay, state-sync and signalling URLs reach one process; /match the first; a dead one moves only its own rooms and the queue', async () => {
    const before = await homes();
    // The rooms spread over all three.
    const counts = [1, 2, 3].map((n) => [...before.values()].filter((h) => h === n).length);
    expect(
      counts.every((c) => c > 0),
      `rooms per server ${counts.join(',')}`,
    ).toBe(true);
    // A room's name percent-encoded is the same room (the server decodes it too).
    expect(await via('/ws/%72oom-0')).toBe(before.get('room-0'));
    // The queue: always the first server. Anything else: round robin over all three.
    for (let i = 0; i < 6; i++) expect(await via('/match')).toBe(1);
    const others = new Set<number>();
    for (let i = 0; i < 6; i++) others.add(await via('/'));
    expect(others).toEqual(new Set([1, 2, 3]));

    // Server 1 dies: its rooms move, the others' stay; the queue moves to server 2.
    stubs[0]!.closeAllConnections();
    stubs[0]!.close();
    await until(
      'HAProxy to take server 1 off',
      async () => (await lb.usable('relays_by_room')) === 2,
      30_000,
      () => lb.log(),
    );
    expect(await via('/match')).toBe(2);
    const after = await homes();
    const moved = names.filter((n) => before.get(n) === 1);
    const stayed = names.filter((n) => before.get(n) !== 1);
    expect(moved.filter((n) => after.get(n) === 1)).toEqual([]);
    expect(stayed.map((n) => after.get(n))).toEqual(stayed.map((n) => before.get(n)));
  }, 60_000);
});

describe('deploy/: Dockerfile', () => {
  const lines = read('Dockerfile')
    .replace(/\\\n/g, ' ')
    .split('\n')
    .map((l) => l.trim())
    .filter((l) => l !== '' && !l.startsWith('#'));
  const instructions = lines.map((l) => l.split(/\s+/, 1)[0]!);

  it('uses only known instructions, on Node 20 as the repository does', () => {
    const known = [
      'FROM',
      'WORKDIR',
      'COPY',
      'RUN',
      'ENV',
      'USER',
      'VOLUME',
      'EXPOSE',
      'STOPSIGNAL',
      'HEALTHCHECK',
      'CMD',
    ];
    for (const i of instructions) expect(known).toContain(i);
    const froms = lines.filter((l) => l.startsWith('FROM '));
    expect(froms.map((l) => l.split(/\s+/)[1])).toEqual([
      'node:20-bookworm-slim',
      'node:20-bookworm-slim',
    ]);
    const engines = (
      JSON.parse(readFileSync(path.join(root, 'package.json'), 'utf8')) as {
        engines: { node: string };
      }
    ).engines.node;
    expect(engines).toMatch(/^>=20\./);
    expect(instructions.at(-1)).toBe('CMD');
  });

  it('copies paths the build makes, runs as node, and starts the server on the exposed port', () => {
    const copies = lines.filter((l) => l.startsWith('COPY --from=build'));
    for (const l of copies) {
      const [, , ...rest] = l.split(/\s+/);
      const sources = rest.slice(0, -1);
      for (const s of sources) {
        const rel = s.replace(/^\/app\/?/, '');
        // Built in the image: dist/ and node_modules/ come from `npm ci` and `npm run build`.
        const made = rel === 'node_modules' || rel.endsWith('/dist');
        expect(made || existsSync(path.join(root, rel)), `COPY ${s}`).toBe(true);
      }
    }
    expect(lines).toContain('USER node');
    expect(lines).toContain('EXPOSE 8080');
    const cmd = JSON.parse(lines.at(-1)!.slice(4)) as string[];
    expect(cmd.slice(0, 3)).toEqual(['node', 'packages/cli/bin/fixedstep.js', 'serve']);
    expect(existsSync(path.join(root, cmd[1]!))).toBe(true);
    expect(cmd.join(' ')).toContain('--host 0.0.0.0 --port 8080');
    expect(existsSync(path.join(deploy, 'Dockerfile.dockerignore'))).toBe(true);
  });
});
