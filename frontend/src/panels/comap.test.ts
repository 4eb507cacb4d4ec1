import { describe, expect, it } from "vitest";
import { RESOLUTION_UNIT, resolution } from "../lib/units";
import { capabilityText, pendingText } from "./CoMap";

describe("CoMap's survey resolution", () => {
  it("is said in one unit, the vehicle's (IMC's px/m²), in the capabilities and in the survey's confirmation", () => {
    expect(RESOLUTION_UNIT).toBe("px/m²");
    expect(resolution(4)).toBe("4 px/m²");
    expect(capabilityText({ kind: "AREA_SURVEY", sensor: "SIDESCAN", resolution: 4, coverageRate: 20 } as Parameters<typeof capabilityText>[0])).toBe(
      "area survey side-scan sonar 4 px/m² 20 m²/s",
    );
    const survey = pendingText({
      kind: "survey", target: { id: "77b2ceb8-5afe-554e-8450-93db17c48923", name: "Alpha" }, lost: false, featureId: 3, sensor: "SIDESCAN", resolution: 1, deadline: "",
    });
    expect(survey).toBe("Survey feature #3 with Alpha (77b2ceb8): side-scan sonar, resolution 1 px/m²?");
  });
});
