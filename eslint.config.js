// @ts-check
import js from '@eslint/js';
import tseslint from 'typescript-eslint';
import vitest from '@vitest/eslint-plugin';
import globals from 'globals';

/** Calls that make a simulation non-deterministic: clocks, Math.random, engine-dependent math. */
const nonDeterministic = [
  ...[
    'random',
    'sin',
    'cos',
    'tan',
    'asin',
    'acos',
    'atan',
    'atan2',
    'exp',
    'expm1',
    'log',
    'log1p',
    'log2',
    'log10',
    'pow',
    'hypot',
    'sinh',
    'cosh',
    'tanh',
    'cbrt',
    'asinh',
    'acosh',
    'atanh',
  ].map((property) => ({
    object: 'Math',
    property,
    message:
      'Simulation code must be deterministic: use the helpers in fixedstep det/ (dsin, dcos, datan2, …).',
  })),
  {
    object: 'Date',
    property: 'now',
    message: 'Simulation code never reads a clock: time is tick × step.',
  },
  {
    object: 'performance',
    property: 'now',
    message: 'Simulation code never reads a clock: time is tick × step.',
  },
  {
    object: 'crypto',
    property: 'getRandomValues',
    message: 'Simulation code must be deterministic: use a seeded Random.',
  },
  {
    object: 'crypto',
    property: 'randomUUID',
    message: 'Simulation code must be deterministic: use a seeded Random.',
  },
];

export default tseslint.config(
  {
    ignores: ['**/node_modules/**', '**/dist/**', 'artifacts/**', 'coverage/**', '.bench-build/**'],
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
