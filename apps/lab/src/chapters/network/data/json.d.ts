// The lab imports recorded JSON through Vite; typed as unknown so every reader must check it.
declare module '*.json' {
  const value: unknown;
  export default value;
}
