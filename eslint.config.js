// @ts-check
import js from '@eslint/js';
import tseslint from 'typescript-eslint';
import vitest from '@vitest/eslint-plugin';
import globals from 'globals';
import { tsImport } from 'tsx/esm/api';

// The one list of forbidden functions, shared with the runtime determinism guard
// (packages/fixedstep/src/det/forbidden.ts), loaded through tsx because it is TypeScript.
const { FORBIDDEN_FUNCTIONS } =
  /** @type {typeof import('./packages/fixedstep/src/det/forbidden.ts')} */ (
    await tsImport('./packages/fixedstep/src/det/forbidden.ts', import.meta.url)
  );

/** Calls that make a simulation non-deterministic: clocks, Math.random, engine-dependent math. */
const nonDeterministic = FORBIDDEN_FUNCTIONS.map((f) => ({
  object: f.object,
  property: f.property,
  message: `Simulation code must be deterministic: ${f.advice}.`,
}));

/**
 * The library's layers, lowest first: a module may import from its own layer and the ones before
 * it, never after (`det ← time ← sim ← input/physics/replay ← net`). `testing` sits on top.
 */
const LAYERS = ['det', 'time', 'sim', 'input', 'physics', 'replay', 'net', 'testing'];
/** input (device adapters), physics and replay are one level: none imports another. */
const LEVEL = { det: 0, time: 1, sim: 2, input: 3, physics: 3, replay: 3, net: 4, testing: 5 };
const layerRules = LAYERS.map((layer) => ({
  files: [`packages/fixedstep/src/${layer}/**/*.ts`],
  rules: {
    'no-restricted-imports': [
      'error',
      {
        patterns: LAYERS.filter((other) => other !== layer && LEVEL[other] >= LEVEL[layer]).map(
          (other) => ({
            group: [`../${other}/*`, `../../${other}/*`, `../${other}`, `../../${other}`],
            message: `Layers: ${layer}/ may import only from ${LAYERS.filter((o) => LEVEL[o] < LEVEL[layer]).join(', ') || 'itself'} (det ← time ← sim ← physics/replay ← net).`,
          }),
        ),
      },
    ],
  },
}));

export default tseslint.config(
  {
    // examples/ are standalone projects on the published package: their own tests type-check them.
    ignores: [
      '**/node_modules/**',
      '**/dist/**',
      'artifacts/**',
      'coverage/**',
      '.bench-build/**',
      'examples/**',
      'packages/cli/lab/**',
      'packages/create-fixedstep/templates/**',
    ],
  },
  js.configs.recommended,
  ...tseslint.configs.strictTypeChecked,
  ...tseslint.configs.stylisticTypeChecked,
  {
    languageOptions: {
      parserOptions: { projectService: true, tsconfigRootDir: import.meta.dirname },
      globals: { ...globals.node, ...globals.browser },
    },
    rules: {
      '@typescript-eslint/require-array-sort-compare': 'error',
      '@typescript-eslint/restrict-template-expressions': [
        'error',
        { allowNumber: true, allowBoolean: true },
      ],
      '@typescript-eslint/no-non-null-assertion': 'off',
      '@typescript-eslint/prefer-literal-enum-member': 'off',
      '@typescript-eslint/no-unnecessary-condition': [
        'error',
        { allowConstantLoopConditions: true },
      ],
      'no-console': 'off',
      // Hot loops over typed arrays index on purpose.
      '@typescript-eslint/prefer-for-of': 'off',
    },
  },
  {
    // Simulation paths: no clocks, no Math.random, no engine trig. time/ (the loop and its drivers) may read clocks.
    files: [
      'packages/fixedstep/src/{det,sim,physics,replay}/**/*.ts',
      'packages/games/src/**/*.ts',
      'packages/rapier/src/**/*.ts',
    ],
    rules: {
      'no-restricted-properties': ['error', ...nonDeterministic],
      'no-restricted-syntax': [
        'error',
        {
          selector: "BinaryExpression[operator='**']",
          message:
            'x ** y is Math.pow: engines differ in the last bit. Multiply, or use dexp and dlog.',
        },
        {
          selector: "AssignmentExpression[operator='**=']",
          message: 'x **= y is Math.pow: engines differ in the last bit.',
        },
        {
          selector: "NewExpression[callee.name='Date']",
          message: 'Simulation code never reads a clock: time is tick × step.',
        },
        {
          selector: "CallExpression[callee.name='Date']",
          message: 'Simulation code never reads a clock: time is tick × step.',
        },
      ],
    },
  },
  ...layerRules,
  {
    files: ['**/*.test.ts', 'e2e/**/*.ts'],
    plugins: { vitest },
    rules: {
      ...vitest.configs.recommended.rules,
      'vitest/valid-expect': 'error',
      'vitest/no-focused-tests': 'error',
      'vitest/no-disabled-tests': 'error',
      'vitest/expect-expect': [
        'error',
        { assertFunctionNames: ['expect', 'expect*', 'assert*', 'fc.assert'] },
      ],
      '@typescript-eslint/no-unused-expressions': 'error',
    },
  },
  {
    files: ['**/*.js', '**/*.mjs'],
    ...tseslint.configs.disableTypeChecked,
  },
);
