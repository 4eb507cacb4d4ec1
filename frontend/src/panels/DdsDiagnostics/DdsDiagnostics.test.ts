import { createElement } from "react";
import { renderToStaticMarkup } from "react-dom/server";
import { describe, expect, it } from "vitest";
import type { PeerFinding } from "../../api/rest";
import { PeerFindings } from "./DdsDiagnostics";

// What the console's /api/metrics gives, word for word (backend/tests/system/test_interop_rti.py checks these texts against real
// RTI Connext participants: test_console_tells_of_rti_writers_it_does_not_read and
// test_console_tells_an_rti7_on_defaults_to_stop_type_information).
const DOCS = "(docs/dds.md#rti-connext-7)";
const maskFix =
  "set XCDR2 on that writer and NDDS_XTYPES_COMPLIANCE_MASK=0x1a9 in its environment (Connext 7; Connext 6 cannot write it readably)";
const gps: PeerFinding = {
  participant: "01017b88-d626-3033-9d3e-ee0f000001c1",
  name: "Plain612",
  vendor: "RTI",
  kind: "representation",
  topic: "GPSReport",
  fix: maskFix,
  message: `RTI participant Plain612 offers GPSReport in XCDR1: ${maskFix} ${DOCS}`,
};
const typedFix =
  "set <resource_limits><type_object_max_serialized_length> to 0 in its participant QoS (the drop-in profile " +
  "docs/rti/sem-console-interop.xml does)";
const typed: PeerFinding = {
  participant: "0101924f-4008-8163-c064-2e0c000001c1",
  name: "Rti",
  vendor: "RTI",
  kind: "typeInformation",
  topic: null,
  fix: typedFix,
  message: `RTI participant Rti sends type information this console cannot use (none of its SEM topics match): ${typedFix} ${DOCS}`,
};
const partitionFix = "publish it in the default partition, as the console reads (it is in partition fleetA)";
const unmatched: PeerFinding = {
  participant: "0101c0a8-0001-0000-0000-0a7d000001c1",
  name: "FleetA612",
  vendor: "RTI",
  kind: "unmatched",
  topic: "InertialSensorReport",
  fix: partitionFix,
  message: `RTI participant FleetA612 has a writer of InertialSensorReport that the console does not match: ${partitionFix} ${DOCS}`,
};
const readerFix = "subscribe to it in the default partition, where the console publishes (it is in partition fleetA)";
const unreached: PeerFinding = {
  participant: "0101c0a8-0001-0000-0000-0a7d000001c1",
  name: "FleetA612",
  vendor: "RTI",
  kind: "unmatchedReader",
  topic: "GPSFixCommand",
  fix: readerFix,
  message: `RTI participant FleetA612 has a reader of GPSFixCommand that the console's commands do not reach: ${readerFix} ${DOCS}`,
};

/** Each finding's text as the operator reads it (the markup's tags and React's text separators taken out). */
function items(findings: PeerFinding[]): string[] {
  const html = renderToStaticMarkup(createElement(PeerFindings, { findings }));
  return html
    .split("<li ")
    .slice(1)
    .map((li) =>
      li
        .replace(/^[^>]*>/, "")
        .replace(/<!-- -->/g, "")
        .replace(/<\/?p[^>]*>/g, " ")
        .replace(/<[^>]*>/g, "")
        .replace(/\s+/g, " ")
        .trim(),
    );
}

describe("the DDS diagnostics view", () => {
  it("names each participant, what it does and the exact fix, in the operator's words", () => {
    expect(items([gps, typed, unmatched, unreached])).toEqual([
      "RTI participant Plain612 · GPSReport: offers it in XCDR1, which the console does not read Fix: " +
        maskFix +
        " docs/dds.md, “Connext 7.x, and the recipe for RTI vehicles”",
      "RTI participant Rti: sends type information this console cannot use: none of its SEM topics match Fix: " +
        typedFix.replace(/</g, "&lt;").replace(/>/g, "&gt;") +
        " docs/dds.md, “Connext 7.x, and the recipe for RTI vehicles”",
      "RTI participant FleetA612 · InertialSensorReport: has a writer of it that the console does not match Fix: " +
        partitionFix +
        " docs/dds.md, “Connext 7.x, and the recipe for RTI vehicles”",
      "RTI participant FleetA612 · GPSFixCommand: has a reader of it that the console&#x27;s commands do not reach Fix: " +
        readerFix +
        " docs/dds.md, “Connext 7.x, and the recipe for RTI vehicles”",
    ]);
  });

  it("shows nothing of a participant it has no finding on", () => {
    expect(items([])).toEqual([]);
  });
});
