/**
 * Assembles the library's WebAssembly kernels from their text source and writes their bytes as a
 * TypeScript module (so the library ships no separate binary and needs no assembler to build):
 *
 *   packages/fixedstep/src/physics/dynamics/kernels.wat -> kernels-wasm.ts
 *   packages/fixedstep/src/physics/world/contact-solver.wat -> contact-solver-wasm.ts
 *   packages/fixedstep/src/physics/world/broad-phase.wat -> broad-phase-wasm.ts
 *
 * The world's two sources take their memory layout from `world/kernel-layout.ts`: each
 * `{{NAME}}`, or a small sum or product of names and integers
 * (`{{VISIT_LANE_BYTES + VISIT_NORMAL_X}}`, `{{2 * VISIT_PAIR_BYTES}}`), becomes the integer. A
 * placeholder naming nothing there, and a name there that no source uses, stop the script with the
 * file and line.
 *
 * Run with `npm run build:wasm` after editing a .wat file or the layout. `--check` only compares
 * and exits 1 when the committed bytes are stale (a unit test does the same).
 */
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import wabtInit from 'wabt';

const src = fileURLToPath(new URL('../packages/fixedstep/src/physics/', import.meta.url));

/** Every kernel: its folder, its text source, the module written, the constant it exports. */
export const KERNELS = [
  {
    dir: `${src}dynamics/`,
    wat: 'kernels.wat',
    ts: 'kernels-wasm.ts',
    name: 'SPRING_KERNELS_WASM',
  },
  {
    dir: `${src}world/`,
    wat: 'contact-solver.wat',
    ts: 'contact-solver-wasm.ts',
    name: 'CONTACT_SOLVER_WASM',
    layout: 'kernel-layout.ts',
  },
  {
    dir: `${src}world/`,
    wat: 'broad-phase.wat',
    ts: 'broad-phase-wasm.ts',
    name: 'BROAD_PHASE_WASM',
    layout: 'kernel-layout.ts',
  },
];

/** A layout file's constants (`export const NAME = 123;`, nothing else exported), by name. */
export function readLayout(path) {
  const names = new Map();
  readFileSync(path, 'utf8')
    .split('\n')
    .forEach((line, at) => {
      if (!/^\s*export\b/.test(line)) return;
      const m = /^export const ([A-Z][A-Z0-9_]*) = (\d+);$/.exec(line.trim());
      if (!m) throw new Error(`${path}:${at + 1}: not \`export const NAME = <integer>;\`: ${line}`);
      if (names.has(m[1])) throw new Error(`${path}:${at + 1}: ${m[1]} declared twice`);
      names.set(m[1], Number(m[2]));
    });
  return names;
}

/** The value of a placeholder's expression: integers and names, `*` before `+` and `-`. */
function evaluate(expression, layout, used, where) {
  const tokens = expression.match(/\s*([A-Za-z_][A-Za-z0-9_]*|\d+|[-+*]|\S)/g) ?? [];
  let total = 0;
  let sign = 1;
  let product = 1;
  let expectOperand = true;
  for (const raw of tokens) {
    const token = raw.trim();
    if (expectOperand) {
      let value;
      if (/^\d+$/.test(token)) value = Number(token);
      else if (layout.has(token)) {
        value = layout.get(token);
        used.add(token);
      } else if (/^[A-Za-z_]/.test(token))
        throw new Error(
          `${where}: {{${expression}}} names ${token}, which the layout does not declare`,
        );
      else
        throw new Error(`${where}: {{${expression}}}: a name or an integer expected at '${token}'`);
      product *= value;
      expectOperand = false;
    } else if (token === '*') expectOperand = true;
    else if (token === '+' || token === '-') {
      total += sign * product;
      sign = token === '+' ? 1 : -1;
      product = 1;
      expectOperand = true;
    } else throw new Error(`${where}: {{${expression}}}: an operator expected at '${token}'`);
  }
  if (expectOperand) throw new Error(`${where}: {{${expression}}} is incomplete`);
  return total + sign * product;
}

/**
 * A kernel's .wat text with its layout's placeholders substituted, and the layout names it used.
 * Throws, naming the file and line, on a placeholder that names nothing, or on any placeholder in
 * a kernel without a layout.
 */
export function expandKernel(kernel = KERNELS[0]) {
  const file = `${kernel.dir}${kernel.wat}`;
  const layout = kernel.layout ? readLayout(`${kernel.dir}${kernel.layout}`) : new Map();
  const used = new Set();
  const text = readFileSync(file, 'utf8')
    .split('\n')
    .map((line, at) =>
      line.replace(/\{\{([^{}]*)\}\}/g, (_, expression) => {
        const where = `${kernel.wat}:${at + 1}`;
        if (!kernel.layout)
          throw new Error(`${where}: a placeholder, but ${kernel.wat} has no layout`);
        return String(evaluate(expression, layout, used, where));
      }),
    )
    .join('\n');
  const stray = /\{\{|\}\}/.exec(text);
  if (stray) throw new Error(`${kernel.wat}: a '${stray[0]}' that is not a placeholder`);
  return { text, used };
}

/** Names each layout file declares that none of its kernels use (by layout path; [] when all are). */
export function unusedLayoutNames(kernels = KERNELS) {
  const unused = [];
  const byLayout = new Map();
  for (const kernel of kernels) {
    if (!kernel.layout) continue;
    const path = `${kernel.dir}${kernel.layout}`;
    const used = byLayout.get(path) ?? new Set();
    for (const name of expandKernel(kernel).used) used.add(name);
    byLayout.set(path, used);
  }
  for (const [path, used] of byLayout)
    for (const name of readLayout(path).keys())
      if (!used.has(name)) unused.push(`${path}: ${name}`);
  return unused;
}

/** The bytes of a kernel's .wat (the spring kernels' by default), its layout substituted, assembled. */
export async function assembleKernels(kernel = KERNELS[0]) {
  const wabt = await wabtInit();
  const module = wabt.parseWat(kernel.wat, expandKernel(kernel).text, { bulk_memory: true });
  try {
    module.validate();
    return new Uint8Array(module.toBinary({}).buffer);
  } finally {
    module.destroy();
  }
}

/** The generated module of a kernel (the spring kernels' by default) for `bytes`. */
export function kernelsModule(bytes, kernel = KERNELS[0]) {
  const rows = [];
  for (let i = 0; i < bytes.length; i += 24)
    rows.push(`  ${Array.from(bytes.subarray(i, i + 24)).join(', ')},`);
  return `// Generated by scripts/wasm.mjs from ${kernel.wat}: do not edit (run \`npm run build:wasm\`).\n/** The assembled bytes of ${kernel.wat} (${bytes.length} bytes). */\nexport const ${kernel.name} = new Uint8Array([\n${rows.join('\n')}\n]);\n`;
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  let unused;
  try {
    unused = unusedLayoutNames();
  } catch (error) {
    console.error(error instanceof Error ? error.message : error);
    process.exit(1);
  }
  if (unused.length > 0) {
    console.error(`declared in the layout but used by no .wat source:\n  ${unused.join('\n  ')}`);
    process.exit(1);
  }
  for (const kernel of KERNELS) {
    const text = kernelsModule(await assembleKernels(kernel), kernel);
    const target = `${kernel.dir}${kernel.ts}`;
    if (process.argv.includes('--check')) {
      if (readFileSync(target, 'utf8') !== text) {
        console.error(`${target} is stale: run npm run build:wasm`);
        process.exit(1);
      }
    } else {
      writeFileSync(target, text);
      console.log(`wrote ${target}`);
    }
  }
}
