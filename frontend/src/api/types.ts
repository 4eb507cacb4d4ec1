// The console's message and report types, all generated from the backend's schema (see scripts/gen-types.mjs).
import type {
  Command,
  GPSConstellationEnumType,
  ReportEnvelope,
  ReportTypes,
  Server,
  Client,
  Transition,
  ProviderSummary,
  ProviderDetail,
  GatewayState,
  LinkConfig,
  RecordingStatus,
  ReplayStatus,
} from "./generated/ws";

export type {
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
export type ServerMessage = Server;
export type ClientMessage = Client;
export type Topic = keyof ReportTypes;
export const TOPICS: readonly Topic[] = ["GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"];
export type LinkState = ProviderSummary["link"];
