// Test fixtures: server messages built from the parts of a report a test needs.
import type { ReportTypes, ServerMessage, Topic } from "../api/types";

/** Every member optional, at every depth: the part of a report a test sets. */
export type DeepPartial<T> = T extends (infer U)[] ? DeepPartial<U>[] : T extends object ? { [K in keyof T]?: DeepPartial<T[K]> } : T;

/** A `report` message of `topic` carrying `report` (members the test leaves out are absent, as a reducer must bear). */
export function reportMessage<T extends Topic>(providerId: string, topic: T, report: DeepPartial<ReportTypes[T]>, invalid: string[] = [], receivedAt = 1): ServerMessage {
  const sample = report as ReportTypes[T];
  return { type: "report", providerId, topic, report: { report: sample, invalid, receivedAt } } as ServerMessage;
}
