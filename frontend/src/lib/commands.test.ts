import { describe, expect, it } from "vitest";
import wsSchema from "../../schema/ws-schema.json";
import { commandChoices, commandTitle, noGpsFix } from "./commands";
import { INS_COMMAND, commandStatusText, reasonText } from "./labels";

/** The Command's state literals the console's WebSocket schema has. */
const stateLiterals = (
  wsSchema as { $defs: { Command: { properties: { state: { anyOf: { enum?: string[] }[] } } } } }
).$defs.Command.properties.state.anyOf.flatMap((a) => a.enum ?? []);

describe("the commands a vehicle is offered, by its UMAA version", () => {
  it("offers a UMAA 6.0 vehicle its six alignments in words, and no GPS fix, saying why", () => {
    const six = commandChoices("6.0");
    expect(six.map((c) => c.state).sort()).toEqual([
      "BEST_ALIGN",
      "GPS_ALIGN",
      "INIT",
      "SNAP_ALIGN",
      "STATIONARY_ALIGN",
      "TRANSFER_ALIGN",
    ]);
    expect(six.every((c) => c.service === "InertialSensor")).toBe(true);
    expect(six.find((c) => c.state === "GPS_ALIGN")?.label).toBe("INS GPS-aided alignment");
    expect(six.find((c) => c.state === "STATIONARY_ALIGN")?.label).toBe("INS stationary alignment");
    expect(six.find((c) => c.state === "INIT")?.confirm).toMatch(/align again/);
    expect(noGpsFix("6.0")).toBe("UMAA 6.0 has no GPS fix service");
  });

  it("offers a UMAA 3.0.1 vehicle (or one not heard yet) its GPS fix and INS ON, OFF, RESTART, as before", () => {
    for (const version of ["3.0.1", null] as const) {
      expect(commandChoices(version).map((c) => c.label)).toEqual(["Request GPS fix", "INS ON", "INS OFF", "INS RESTART"]);
      expect(noGpsFix(version)).toBeNull();
    }
  });

  it("has every state the schema has among one version's choices, and words for every 6.0 one", () => {
    const offered = [...commandChoices("3.0.1"), ...commandChoices("6.0")].map((c) => c.state).filter((s) => s !== null);
    expect(offered.sort()).toEqual([...stateLiterals].sort());
    for (const [literal, words] of Object.entries(INS_COMMAND)) expect(words.trim(), literal).toBeTruthy();
  });

  it("titles a command card in words, and says an update", () => {
    expect(commandTitle({ service: "InertialSensor", state: "GPS_ALIGN" })).toBe("INS GPS-aided alignment");
    expect(commandTitle({ service: "InertialSensor", state: "INIT" })).toBe("INS initialise");
    expect(commandTitle({ service: "InertialSensor", state: "RESTARTING" })).toBe("INS RESTART");
    expect(commandTitle({ service: "InertialSensor", state: "ON" })).toBe("INS ON");
    expect(commandTitle({ service: "GPSFix", state: null })).toBe("GPS fix");
    expect(`${commandStatusText("ISSUED")} ${reasonText("UPDATED")}`).toBe("Received again, updated: it starts over");
  });
});
