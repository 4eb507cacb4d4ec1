// The operator's token (token.ts) and the hook that re-renders on its change.
import { useSyncExternalStore } from "react";
import { getToken, onTokenChange } from "./token";

export { getToken, onTokenChange, setToken, wsProtocols } from "./token";

export function useToken(): string | null {
  return useSyncExternalStore(onTokenChange, getToken);
}
