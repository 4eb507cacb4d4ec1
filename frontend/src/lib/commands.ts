// The commands panel's list: live commands (WebSocket) merged with older pages (REST).
import type { Command } from "../api/types";

/** Both lists without repeats, newest first; a live command wins over its REST copy (it is newer). */
export function mergeCommands(live: Command[], older: Command[]): Command[] {
  const seen = new Map<string, Command>();
  for (const c of [...live, ...older]) if (!seen.has(c.sessionId)) seen.set(c.sessionId, c);
  return [...seen.values()].sort((a, b) => b.createdAt - a.createdAt);
}
