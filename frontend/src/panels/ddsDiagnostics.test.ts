import { createElement } from "react";
import { renderToStaticMarkup } from "react-dom/server";
import { describe, expect, it } from "vitest";
import type { PeerFinding } from "../api/rest";
import { PeerFindings } from "./DdsDiagnostics";

// What the console's /api/metrics gives for an RTI vehicle on its defaults (backend/tests/test_interop_rti.py checks
// these texts against real RTI Connext participants).
const gps: PeerFinding = {
  participant: "01017b88-d626-3033-9d3e-ee0f000001c1", name: "Rti", vendor: "RTI", kind: "representation", topic: "GPSReport",
  fix: "set XCDR2 on that writer and NDDS_XTYPES_COMPLIANCE_MASK=0x1a9 in its environment (Connext 7; Connext 6 cannot write it readably)",
  message: "RTI participant Rti offers GPSReport in XCDR1: …",
};
const typed: PeerFinding = {
  participant: "0101924f-4008-8163-c064-2e0c000001c1", name: "Vehicle7", vendor: "RTI", kind: "typeInformation", topic: null,
  fix: "set <resource_limits><type_object_max_serialized_length> to 0 in its participant QoS", message: "RTI participant Vehicle7 sends …",
};

/** Each finding's text as the operator reads it (the markup's tags and React's text separators taken out). */
function items(findings: PeerFinding[]): string[] {
  const html = renderToStaticMarkup(createElement(PeerFindings, { findings }));
  return html.split("<li ").slice(1).map((li) =>
    li.replace(/^[^>]*>/, "").replace(/<!-- -->/g, "").replace(/<\/?p[^>]*>/g, " ").replace(/<[^>]*>/g, "").replace(/\s+/g, " ").trim());
}

describe("the DDS diagnostics view", () => {
  it("names each participant, what it does and the exact fix, in the operator's words", () => {
    expect(items([gps, typed])).toEqual([
      "RTI participant Rti · GPSReport: offers it in XCDR1, which the console does not read Fix: set XCDR2 on that writer and " +
        "NDDS_XTYPES_COMPLIANCE_MASK=0x1a9 in its environment (Connext 7; Connext 6 cannot write it readably) " +
        "docs/dds.md, “Connext 7.x, and the recipe for RTI vehicles”",
      "RTI participant Vehicle7: sends type information this console cannot use: none of its SEM topics match Fix: set " +
        "&lt;resource_limits&gt;&lt;type_object_max_serialized_length&gt; to 0 in its participant QoS " +
        "docs/dds.md, “Connext 7.x, and the recipe for RTI vehicles”",
    ]);
  });

  it("shows nothing of a participant it has no finding on", () => {
    expect(items([])).toEqual([]);
  });
});
