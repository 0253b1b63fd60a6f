// The JavaScript engines of the determinism suite (e2e/determinism): where they are, and — when we
// are root on a machine with apt-get — installing the missing ones from Debian's packages. Node
// built-ins only, so it runs before any dependency is installed.
//
//   node scripts/engines.mjs            what is found, what is missing and why
//   node scripts/engines.mjs --install  the same, installing what is missing (root + apt-get)
//
// Engines: V8 (Node itself, and Chromium: CHROMIUM_PATH or /usr/bin/chromium), SpiderMonkey (Firefox: FIREFOX_PATH, /usr/bin/firefox-esr, /usr/bin/firefox)
// and JavaScriptCore (WebKitGTK: WEBKIT_WEBDRIVER_PATH or WebKitWebDriver, MINIBROWSER_PATH or
// webkit2gtk's MiniBrowser, and Xvfb — WebKitGTK has no headless mode). `npm test` installs the
// missing ones; an engine that is still missing is skipped by the suite, which says why.
import { existsSync, readdirSync } from 'node:fs';
import { delimiter, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { canInstallPackages, installPackages, isExecutable } from './setup.mjs';

/** Debian packages that provide each engine (and what it needs to run headless). */
export const ENGINE_PACKAGES = Object.freeze({
  firefox: ['firefox-esr'],
  webkit: ['webkit2gtk-driver', 'xvfb', 'xauth'],
});

/** The first executable named `name` on $PATH, or undefined. */
function which(name, env) {
  for (const dir of (env.PATH ?? '/usr/local/bin:/usr/bin:/bin').split(delimiter)) {
    if (dir && isExecutable(join(dir, name))) return join(dir, name);
  }
  return undefined;
}

/** webkit2gtk's MiniBrowser: Debian keeps it under /usr/lib/<triplet>/webkit2gtk-4.x/. */
function findMiniBrowser() {
  const candidates = [];
  for (const lib of ['/usr/lib', '/usr/lib64']) {
    let entries;
    try {
      entries = readdirSync(lib).sort();
    } catch {
      continue;
    }
    for (const e of entries) {
      for (const api of ['webkit2gtk-4.1', 'webkit2gtk-4.0', 'webkitgtk-6.0']) {
        candidates.push(join(lib, e, api, 'MiniBrowser'));
      }
    }
    for (const api of ['webkit2gtk-4.1', 'webkit2gtk-4.0', 'webkitgtk-6.0']) {
      candidates.push(join(lib, api, 'MiniBrowser'));
    }
  }
  candidates.push(
    '/usr/libexec/webkit2gtk-4.1/MiniBrowser',
    '/usr/libexec/webkit2gtk-4.0/MiniBrowser',
  );
  return candidates.find(isExecutable);
}

function fromEnv(env, name) {
  const v = env[name];
  if (!v) return undefined;
  return isExecutable(v) ? { path: v } : { error: `${name}=${v} is not an executable file` };
}

/**
 * Finds every engine without installing anything. Returns
 * `{ chromium, firefox, webkit }`, each `{ ok: true, ... paths }` or `{ ok: false, reason, packages }`.
 */
export function findEngines(env = process.env) {
  const result = {};

  const chromium = fromEnv(env, 'CHROMIUM_PATH');
  if (chromium?.error)
    result.chromium = { ok: false, reason: chromium.error, packages: ['chromium'] };
  else {
    const path =
      chromium?.path ?? (isExecutable('/usr/bin/chromium') ? '/usr/bin/chromium' : undefined);
    result.chromium = path
      ? { ok: true, path }
      : {
          ok: false,
          reason: 'no Chromium: neither CHROMIUM_PATH nor /usr/bin/chromium',
          packages: ['chromium'],
        };
  }

  const firefox = fromEnv(env, 'FIREFOX_PATH');
  if (firefox?.error)
    result.firefox = { ok: false, reason: firefox.error, packages: ENGINE_PACKAGES.firefox };
  else {
    const path =
      firefox?.path ?? ['/usr/bin/firefox-esr', '/usr/bin/firefox'].find((p) => isExecutable(p));
    result.firefox = path
      ? { ok: true, path }
      : {
          ok: false,
          reason: 'no Firefox: neither FIREFOX_PATH, /usr/bin/firefox-esr nor /usr/bin/firefox',
          packages: ENGINE_PACKAGES.firefox,
        };
  }

  const driverEnv = fromEnv(env, 'WEBKIT_WEBDRIVER_PATH');
  const browserEnv = fromEnv(env, 'MINIBROWSER_PATH');
  const driver = driverEnv?.path ?? which('WebKitWebDriver', env);
  const browser = browserEnv?.path ?? findMiniBrowser();
  const xvfb = which('Xvfb', env);
  const missing = [];
  if (driverEnv?.error) missing.push(driverEnv.error);
  else if (!driver) missing.push('no WebKitWebDriver on PATH (package webkit2gtk-driver)');
  if (browserEnv?.error) missing.push(browserEnv.error);
  else if (!browser) missing.push('no webkit2gtk MiniBrowser (package libwebkit2gtk-4.1-0)');
  if (!xvfb) missing.push('no Xvfb on PATH (package xvfb): WebKitGTK has no headless mode');
  result.webkit =
    missing.length === 0
      ? { ok: true, driver, browser, xvfb }
      : { ok: false, reason: missing.join('; '), packages: ENGINE_PACKAGES.webkit };
  return result;
}

/**
 * The Debian packages of the engines {@link findEngines} does not find (Firefox ESR; WebKitGTK's
 * driver, Xvfb and xauth), each `{ name, why }`, for `installPackages`.
 */
export function missingEnginePackages(env = process.env) {
  const found = findEngines(env);
  return ['firefox', 'webkit'].flatMap((id) =>
    found[id].ok
      ? []
      : found[id].packages.map((name) => ({ name, why: `the determinism suite (${id})` })),
  );
}

function describe(found) {
  const lines = [];
  for (const [id, e] of Object.entries(found)) {
    if (e.ok) {
      const where = Object.entries(e)
        .filter(([k]) => k !== 'ok')
        .map(([k, v]) => `${k} ${v}`)
        .join(', ');
      lines.push(`  ${id.padEnd(9)} found: ${where}`);
    } else {
      lines.push(`  ${id.padEnd(9)} MISSING: ${e.reason} (Debian: ${e.packages.join(' ')})`);
    }
  }
  return lines.join('\n');
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  if (process.argv.includes('--install') && canInstallPackages()) {
    installPackages(missingEnginePackages());
  }
  const found = findEngines();
  console.log(
    `Engines of the determinism suite (plus Node ${process.version}):\n${describe(found)}`,
  );
  if (!existsSync('/usr/bin/apt-get') && Object.values(found).some((e) => !e.ok)) {
    console.log('(no apt-get here: install the missing browsers with your package manager)');
  }
}
