export * from './dynamics/index.js';
export * from './world/index.js';
