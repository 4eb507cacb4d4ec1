// The console's message and report types, all generated from the backend's schema (see scripts/gen-types.mjs).
import type {
  Command,
  DatabaseState,
  GPSConstellationEnumType,
  ReportEnvelope,
  ReportMessage,
  ReportTypes,
  Server,
  SnapshotMessage,
  Client,
  Transition,
  ProviderSummary,
  ProviderDetail,
  GatewayState,
  LinkConfig,
  RecordingStatus,
  ReplayStatus,
  VehicleBrief,
} from "./generated/ws";

export type {
  VehicleBrief,
  DatabaseState,
  GatewayState,
  LinkConfig,
  Command,
  GPSConstellationEnumType,
  ReportEnvelope,
  ReportTypes,
  Transition,
  ProviderSummary,
  ProviderDetail,
  RecordingStatus,
  ReplayStatus,
};
export type {
  GPSReportType,
  GPSSatelliteType,
  GPSFixReportType,
  GPSFixStatusReportType,
  InertialSensorReportType,
  InertialSensorOpStatusEnumType,
  InertialSensorStateEnumType,
} from "./generated/ws";
export type ClientMessage = Client;
export type Topic = keyof ReportTypes;

// Report payloads typed per topic. The schema gives one untyped `ReportEnvelope.report` (its type per topic is
// `ReportTypes`): these types pair each topic with its report, so a message's `topic` narrows its `report`.

/** The envelope of a report of topic T: the sample typed as ReportTypes[T]. */
export type ReportEnvelopeOf<T extends Topic> = Omit<ReportEnvelope, "report"> & { report: ReportTypes[T] };

/** A `report` message, discriminated by `topic`. */
export type TypedReportMessage = {
  [T in Topic]: Omit<ReportMessage, "topic" | "report"> & { topic: T; report: ReportEnvelopeOf<T> };
}[Topic];

/** A vehicle's latest report per topic (the snapshot's `reports`). */
export type TopicReports = { [T in Topic]?: ReportEnvelopeOf<T> | null };

/** A vehicle in the snapshot, its reports typed per topic. */
export type TypedProviderDetail = Omit<ProviderDetail, "reports"> & { reports: TopicReports };

/** The snapshot, its vehicles' reports typed per topic. */
export type TypedSnapshotMessage = Omit<SnapshotMessage, "providers"> & { providers: TypedProviderDetail[] };

/** A message from the console (/ws), with report payloads typed per topic. */
export type ServerMessage = Exclude<Server, ReportMessage | SnapshotMessage> | TypedReportMessage | TypedSnapshotMessage;
export const TOPICS: readonly Topic[] = ["GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"];
export type LinkState = ProviderSummary["link"];
