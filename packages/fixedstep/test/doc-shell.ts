/**
 * The checks of a ```sh block marked `<!-- sh: DIR -->` (doc-blocks.ts): every command is one this
 * repository can answer for, and what it names is real —
 * - `npm run X`, `npm test`, `npm start`: DIR's package.json has the script;
 * - `npm install|ci [pkg…|tarball]`: a package is one of the workspace's, a tarball is named after
 *   packages/fixedstep's name and version; `npm pack -w DIR2`: DIR2 is a workspace;
 * - `npm create fixedstep@… [-- --template T]` / `npx create-fixedstep`: T is one of its templates;
 * - `fixedstep …` / `npx fixedstep …`: the CLI's own parser (`parseArgs` of @fixedstep/cli) takes
 *   it — a synopsis's `[…]` is read as given, `<file>` as a file name;
 * - `npx vitest run [--config F] [filter…]`: F exists, each filter names a test file;
 * - `node FILE [--flag…]`: FILE exists and reads each flag;
 * - `docker build -f F`, `docker run -p H:C`: F exists, C is a port F exposes;
 * - `kubectl … -n NS`, `create namespace NS`, `create secret generic S --from-literal=K=…`,
 *   `apply -k D`: D/kustomization.yaml exists, NS is the namespace it sets, a manifest reads the
 *   key K of the secret S;
 * - `haproxy -f F`: F exists;
 * - `VAR=value command`: one of the files the command names reads VAR;
 * - `cd`, `echo`: anything.
 * Anything else is a problem: a block of commands nobody checks is `<!-- text -->`.
 */
import { execFileSync } from 'node:child_process';
import { existsSync, readdirSync, readFileSync, statSync } from 'node:fs';
import { join } from 'node:path';
import { parse as parseYaml, parseAllDocuments } from 'yaml';
import { parseArgs as parseCli } from '@fixedstep/cli';
import { root, type Block } from './doc-blocks.js';

const readJson = (file: string) =>
  JSON.parse(readFileSync(file, 'utf8')) as Record<string, unknown>;

/** The repository's files (git's list), relative to the root. */
let tracked: string[] | undefined;
function repoFiles(): string[] {
  tracked ??= execFileSync('git', ['ls-files'], { cwd: root, encoding: 'utf8' }).split('\n');
  return tracked;
}

/** A file's text, or every file's under a directory, joined. */
function textOf(path: string): string {
  if (!existsSync(path)) return '';
  if (!statSync(path).isDirectory()) return readFileSync(path, 'utf8');
  return readdirSync(path, { recursive: true, withFileTypes: true })
    .filter((e) => e.isFile())
    .map((e) => readFileSync(join(e.parentPath, e.name), 'utf8'))
    .join('\n');
}

/** The commands of a block: continuation lines joined, comments dropped, split at `&&`, `;`, `|`. */
export function commandsOf(code: string): string[][] {
  const out: string[][] = [];
  for (const line of code.replace(/\\\n/g, ' ').split('\n')) {
    let words: string[] = [];
    let word = '';
    let quote = '';
    const flush = () => {
      if (word !== '') words.push(word);
      word = '';
    };
    for (let i = 0; i < line.length; i++) {
      const c = line[i]!;
      if (quote !== '') {
        if (c === quote) quote = '';
        else word += c;
      } else if (c === '"' || c === "'") quote = c;
      else if (c === '#' && word === '') break;
      else if (/\s/.test(c)) flush();
      else if ((c === '&' && line[i + 1] === '&') || c === ';' || c === '|') {
        flush();
        if (words.length > 0) out.push(words);
        words = [];
        if (c === '&' || line[i + 1] === '|') i++;
      } else word += c;
    }
    flush();
    if (words.length > 0) out.push(words);
  }
  return out;
}

interface Context {
  /** The directory whose package.json the block's `npm run` uses. */
  dir: string;
}

/** Workspace packages: directory → package.json. */
function workspaces(): Map<string, Record<string, unknown>> {
  const out = new Map<string, Record<string, unknown>>();
  for (const name of readdirSync(join(root, 'packages'))) {
    const file = join(root, 'packages', name, 'package.json');
    if (existsSync(file)) out.set(`packages/${name}`, readJson(file));
  }
  return out;
}

function npmProblems(args: string[], ctx: Context): string[] {
  const [sub, ...rest] = args;
  const scripts = Object.keys(readJson(join(root, ctx.dir, 'package.json')).scripts ?? {});
  const needScript = (name: string) =>
    scripts.includes(name) ? [] : [`${ctx.dir}/package.json has no script "${name}"`];
  if (sub === 'run') return needScript(rest[0] ?? '');
  if (sub === 'test' || sub === 'start') return needScript(sub);
  if (sub === 'install' || sub === 'i' || sub === 'ci') {
    const names = [...workspaces().values()].map((p) => p.name as string);
    const lib = readJson(join(root, 'packages/fixedstep/package.json'));
    const tarball = `${lib.name as string}-${lib.version as string}.tgz`;
    return rest
      .filter((a) => !a.startsWith('-'))
      .flatMap((a) => {
        if (a.endsWith('.tgz')) return a.endsWith(`/${tarball}`) ? [] : [`not ${tarball}: ${a}`];
        return names.includes(a) ? [] : [`"${a}" is not a package of this repository`];
      });
  }
  if (sub === 'pack') {
    const w = rest[rest.indexOf('-w') + 1];
    return rest.includes('-w') && workspaces().has(w!) ? [] : [`npm pack: no workspace ${w}`];
  }
  if (sub === 'create') {
    return rest[0]?.startsWith('fixedstep@') === true
      ? createProblems(rest.slice(1))
      : [`npm create ${rest[0]}: not create-fixedstep`];
  }
  return [`npm ${sub}: not a command this page may use`];
}

function createProblems(args: string[]): string[] {
  const at = args.indexOf('--template');
  if (at < 0) return [];
  const templates = readdirSync(join(root, 'packages/create-fixedstep/templates'));
  return templates.includes(args[at + 1]!)
    ? []
    : [`create-fixedstep has no template ${args[at + 1]}`];
}

function cliProblems(args: string[]): string[] {
  // A synopsis (`[--port 8080]`, `<file>`) is checked as if every option were given.
  const argv = args.map((a) => a.replace(/[[\]]/g, '').replace(/^<(\w+)>$/, '$1'));
  const command = parseCli(argv, {});
  if (command.kind === 'usage-error') return [`fixedstep ${args.join(' ')}: ${command.message}`];
  if (command.kind === 'help' && !argv.some((a) => a === '--help' || a === '-h')) {
    return [`fixedstep ${args.join(' ')}: not a command (the CLI answers with its help)`];
  }
  return [];
}

function vitestProblems(args: string[], ctx: Context, named: string[]): string[] {
  const problems: string[] = [];
  for (let i = 1; i < args.length; i++) {
    const a = args[i]!;
    if (a === '--config') {
      named.push(join(ctx.dir, args[i + 1]!));
      if (!existsSync(join(root, ctx.dir, args[++i]!))) problems.push(`no file ${args[i]}`);
    } else if (!a.startsWith('-')) {
      const tests = repoFiles().filter((f) => f.includes(a) && f.endsWith('.test.ts'));
      if (tests.length === 0) problems.push(`vitest: no test file matches ${a}`);
      named.push(...tests);
    }
  }
  return args[0] === 'run' ? problems : ['npx vitest: only `vitest run`'];
}

function kubectlProblems(args: string[]): string[] {
  const kustomization = parseYaml(
    readFileSync(join(root, 'deploy/kustomization.yaml'), 'utf8'),
  ) as { namespace: string; resources: string[] };
  // Every `secretKeyRef` of the manifests, as `name/key`.
  const refs: string[] = [];
  const walk = (node: unknown): void => {
    if (typeof node !== 'object' || node === null) return;
    const ref = (node as { secretKeyRef?: { name: string; key: string } }).secretKeyRef;
    if (ref) refs.push(`${ref.name}/${ref.key}`);
    Object.values(node).forEach(walk);
  };
  for (const r of kustomization.resources) {
    for (const d of parseAllDocuments(readFileSync(join(root, 'deploy', r), 'utf8')))
      walk(d.toJS());
  }
  const problems: string[] = [];
  const namespace = (ns: string | undefined) => {
    if (ns !== kustomization.namespace) problems.push(`namespace ${ns} is not deploy/'s`);
  };
  if (args.includes('-n')) namespace(args[args.indexOf('-n') + 1]);
  const verbs = args.filter((_, i) => args[i - 1] !== '-n' && !args[i]!.startsWith('-'));
  if (verbs[0] === 'create' && verbs[1] === 'namespace') namespace(verbs[2]);
  else if (verbs[0] === 'create' && verbs[1] === 'secret' && verbs[2] === 'generic') {
    for (const literal of args.filter((a) => a.startsWith('--from-literal='))) {
      const key = literal.slice('--from-literal='.length).split('=')[0]!;
      if (!refs.includes(`${verbs[3]}/${key}`)) {
        problems.push(`no manifest of deploy/ reads the key ${key} of the secret ${verbs[3]}`);
      }
    }
  } else if (verbs[0] === 'apply') {
    const dir = args[args.indexOf('-k') + 1] ?? '';
    const file = join(dir, 'kustomization.yaml');
    if (!existsSync(join(root, file))) problems.push(`no ${file}`);
  } else problems.push(`kubectl ${verbs.join(' ')}: not checked`);
  return problems;
}

function dockerProblems(args: string[], ctx: Context, named: string[]): string[] {
  // The image `docker run` starts is the one deploy/Dockerfile builds: the repository has no other.
  const dockerfile = join(ctx.dir, 'deploy/Dockerfile');
  if (args[0] === 'build') {
    const f = args[args.indexOf('-f') + 1] ?? '';
    named.push(join(ctx.dir, f));
    return existsSync(join(root, ctx.dir, f)) ? [] : [`no Dockerfile ${f}`];
  }
  if (args[0] === 'run') {
    const port = args[args.indexOf('-p') + 1]?.split(':')[1];
    return new RegExp(`^EXPOSE ${port}$`, 'm').test(textOf(join(root, dockerfile)))
      ? []
      : [`${dockerfile} exposes no port ${port}`];
  }
  return [`docker ${args[0]}: not checked`];
}

/** Problems of one command; `named` collects the files it names (for its variables). */
function commandProblems(words: string[], ctx: Context, named: string[]): string[] {
  const [program, ...args] = words;
  const file = (f: string | undefined) => {
    named.push(join(ctx.dir, f ?? ''));
    return f !== undefined && existsSync(join(root, ctx.dir, f)) ? [] : [`no file ${f}`];
  };
  switch (program) {
    case 'npm':
      return npmProblems(args, ctx);
    case 'fixedstep':
      return cliProblems(args);
    case 'npx':
      if (args[0] === 'fixedstep') return cliProblems(args.slice(1));
      if (args[0] === 'create-fixedstep') return createProblems(args.slice(2));
      if (args[0] === 'vitest') return vitestProblems(args.slice(1), ctx, named);
      return [`npx ${args[0]}: not checked`];
    case 'node': {
      const problems = file(args[0]);
      const text = textOf(join(root, ctx.dir, args[0] ?? ''));
      const flags = args.filter((a) => a.startsWith('--'));
      return [
        ...problems,
        ...flags.filter((f) => !text.includes(`'${f}'`)).map((f) => `${args[0]} reads no ${f}`),
      ];
    }
    case 'docker':
      return dockerProblems(args, ctx, named);
    case 'kubectl':
      return kubectlProblems(args);
    case 'haproxy':
      return file(args[args.indexOf('-f') + 1]);
    case 'cd':
    case 'echo':
      return [];
    default:
      return [`${program}: not a command this page may use`];
  }
}

/** What is wrong with a ```sh block: commands that are not what the repository has. */
export function shellProblems(b: Block): string[] {
  const m = /^sh: (\S+)$/.exec(b.marker ?? '');
  if (!m) return ['a sh block needs <!-- sh: DIR --> (or <!-- text -->)'];
  const ctx: Context = { dir: m[1]! };
  if (!existsSync(join(root, ctx.dir, 'package.json'))) return [`no ${ctx.dir}/package.json`];
  const problems: string[] = [];
  for (const words of commandsOf(b.code)) {
    const vars: string[] = [];
    while (/^[A-Z_][A-Z0-9_]*=/.test(words[0] ?? '')) vars.push(words.shift()!.split('=')[0]!);
    const named: string[] = [];
    problems.push(...commandProblems(words, ctx, named));
    const text = named.map((f) => textOf(join(root, f))).join('\n');
    for (const v of vars) {
      if (!text.includes(v)) problems.push(`${words.join(' ')}: nothing it names reads ${v}`);
    }
  }
  return problems;
}
