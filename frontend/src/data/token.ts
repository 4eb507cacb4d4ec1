// The operator's token for command routes (and reads, with --auth-reads), kept for the browser tab's session.
// Without React: the first screen's early requests (early.ts) read it before the dashboard's code has loaded.

const KEY = "sem-console-token";
const listeners = new Set<() => void>();
let token: string | null = typeof sessionStorage !== "undefined" ? sessionStorage.getItem(KEY) : null;

export function setToken(t: string | null): void {
  token = t && t.trim() ? t.trim() : null;
  if (typeof sessionStorage !== "undefined") {
    if (token) sessionStorage.setItem(KEY, token);
    else sessionStorage.removeItem(KEY);
  }
  for (const l of listeners) l();
}

export function getToken(): string | null {
  return token;
}

export function onTokenChange(l: () => void): () => void {
  listeners.add(l);
  return () => listeners.delete(l);
}

/** The subprotocols that carry the token on /ws (a browser's WebSocket cannot send an Authorization header). */
export function wsProtocols(t: string | null = token): string[] {
  if (!t) return [];
  const bytes = new TextEncoder().encode(t);
  const b64 = btoa(String.fromCharCode(...bytes))
    .replace(/\+/g, "-")
    .replace(/\//g, "_")
    .replace(/=+$/, "");
  return ["sem-console", `bearer.${b64}`];
}
