/**
 * The security headers every response carries. A fixed set of five headers needs no library: the
 * CSP is the lab's own (scripts and styles from this origin, WebAssembly for the physics kernel,
 * WebSockets to this host for the relay, no framing).
 */
export const CONTENT_SECURITY_POLICY = [
  "default-src 'self'",
  "script-src 'self' 'wasm-unsafe-eval'",
  // The lab sets style attributes from code (charts, sliders).
  "style-src 'self' 'unsafe-inline'",
  "img-src 'self' data: blob:",
  "font-src 'self' data:",
  "connect-src 'self' ws: wss:",
  "worker-src 'self' blob:",
  "object-src 'none'",
  "base-uri 'self'",
  "form-action 'self'",
  "frame-ancestors 'none'",
].join('; ');

/**
 * The CSP of the API reference at `/docs/`: TypeDoc's pages run a small inline script (the theme,
 * before the page paints) that the lab's policy would block. The reference is our own static
 * build, never user content, so inline scripts are allowed there and only there.
 */
export const DOCS_CONTENT_SECURITY_POLICY = CONTENT_SECURITY_POLICY.replace(
  "script-src 'self' 'wasm-unsafe-eval'",
  "script-src 'self' 'unsafe-inline'",
);

/** Header name → value, added to every answer of the server. */
export const SECURITY_HEADERS: Readonly<Record<string, string>> = Object.freeze({
  'Content-Security-Policy': CONTENT_SECURITY_POLICY,
  'X-Frame-Options': 'DENY',
  'X-Content-Type-Options': 'nosniff',
  'Referrer-Policy': 'no-referrer',
  'Cross-Origin-Opener-Policy': 'same-origin',
});
