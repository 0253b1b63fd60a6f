/**
 * The sh-block checker of the docs (doc-shell.ts) refuses what is not there: each case is a
 * command a page could get wrong, and the problem it must be reported with.
 */
import { describe, expect, it } from 'vitest';
import { commandsOf, shellProblems } from './doc-shell.js';

const sh = (code: string, dir = '.'): string[] =>
  shellProblems({ doc: 'test.md', line: 1, lang: 'sh', code, marker: `sh: ${dir}` });

describe('commandsOf', () => {
  it('splits lines, continuations and && into commands, keeps quotes, drops comments', () => {
    expect(
      commandsOf(
        'kubectl -n fixedstep create secret generic s \\\n  --from-literal=secret="$(openssl rand -base64 32)"\n' +
          'npm run build && echo ok   # a comment\n# only a comment\nA=1 B=x haproxy -f "a b.cfg"\n',
      ),
    ).toEqual([
      [
        'kubectl',
        '-n',
        'fixedstep',
        'create',
        'secret',
        'generic',
        's',
        '--from-literal=secret=$(openssl rand -base64 32)',
      ],
      ['npm', 'run', 'build'],
      ['echo', 'ok'],
      ['A=1', 'B=x', 'haproxy', '-f', 'a b.cfg'],
    ]);
  });
});

describe('shellProblems', () => {
  it('takes what the repository has', () => {
    expect(
      sh(
        [
          'npm ci && npm run build && npm test',
          'npm install fixedstep @fixedstep/games',
          'npm pack -w packages/fixedstep --pack-destination /tmp',
          'npm install /tmp/fixedstep-0.1.0.tgz',
          'fixedstep serve --port 8080 --data ./fixedstep-data --games ./my-game.js',
          'fixedstep replay verify <file> [--games ./my-game.js]',
          'npx fixedstep check ./dist/game.js --ticks 1200 --engines node,chromium',
          'FIXEDSTEP_ENGINES=node npx vitest run --config e2e/vitest.config.ts e2e/determinism',
          'node scripts/engines.mjs --install',
          'docker build -f deploy/Dockerfile -t fixedstep . && docker run -p 8080:8080 fixedstep',
          'kubectl -n fixedstep create secret generic fixedstep-match --from-literal=secret=x',
          'kubectl apply -k deploy/',
          'FIXEDSTEP_BIND=:8080 FIXEDSTEP_RELAY1=a:1 haproxy -f deploy/haproxy/haproxy.cfg',
        ].join('\n'),
      ),
    ).toEqual([]);
  });

  it.each([
    ['npm run nope', './package.json has no script "nope"'],
    ['npm install left-pad', '"left-pad" is not a package of this repository'],
    ['npm install /tmp/fixedstep-0.0.9.tgz', 'not fixedstep-0.1.0.tgz: /tmp/fixedstep-0.0.9.tgz'],
    ['npm pack -w packages/nope', 'npm pack: no workspace packages/nope'],
    ['npm create fixedstep@latest g -- --template vue', 'create-fixedstep has no template vue'],
    [
      'fixedstep serve --prot 8080',
      'fixedstep serve --prot 8080: unknown option for serve: --prot',
    ],
    [
      'fixedstep replay check run.fsr',
      'fixedstep replay check run.fsr: replay needs a subcommand: info or verify',
    ],
    ['npx vitest run e2e/nowhere', 'vitest: no test file matches e2e/nowhere'],
    ['node scripts/engines.mjs --all', 'scripts/engines.mjs reads no --all'],
    ['docker run -p 80:9090 fixedstep', 'deploy/Dockerfile exposes no port 9090'],
    ['kubectl -n games apply -k deploy/', "namespace games is not deploy/'s"],
    ['kubectl apply -k packages/', 'no packages/kustomization.yaml'],
    [
      'kubectl -n fixedstep create secret generic fixedstep-db --from-literal=secret=x',
      'no manifest of deploy/ reads the key secret of the secret fixedstep-db',
    ],
    [
      'kubectl -n fixedstep create secret generic fixedstep-match --from-literal=key=x',
      'no manifest of deploy/ reads the key key of the secret fixedstep-match',
    ],
    [
      'FIXEDSTEP_RELAY9=a:1 haproxy -f deploy/haproxy/haproxy.cfg',
      'haproxy -f deploy/haproxy/haproxy.cfg: nothing it names reads FIXEDSTEP_RELAY9',
    ],
    ['curl http://localhost:8080/', 'curl: not a command this page may use'],
  ])('refuses %s', (command, problem) => {
    expect(sh(command)).toEqual([problem]);
  });

  it('needs a directory', () => {
    expect(
      shellProblems({ doc: 't.md', line: 1, lang: 'sh', code: 'npm test\n', marker: undefined }),
    ).toEqual(['a sh block needs <!-- sh: DIR --> (or <!-- text -->)']);
  });
});
