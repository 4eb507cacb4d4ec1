// The operator's token for command routes, kept for the browser tab's session.
import { useSyncExternalStore } from "react";

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

export function useToken(): string | null {
  return useSyncExternalStore(
    (l) => {
      listeners.add(l);
      return () => listeners.delete(l);
    },
    () => token,
  );
}
