// Replay in the console: a stretch of the live stack with a GPS fix command is recorded (POST /api/recordings),
// then `sem-console --replay` serves that file. The dashboard must show the same vehicle, satellites and
// command timeline, seek and change speed, keep command controls disabled, and show the replay badge.
import { McapIndexedReader, McapStreamReader, type McapTypes } from "@mcap/core";
import { parseIDL, type IDLMessageDefinition } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";
import { expect, test, type APIRequestContext, type Page } from "@playwright/test";
import { decompress } from "fzstd";
import { vehicle } from "../helpers";
import { VEHICLE_3_NAME, load, startReplayConsole } from "../stack";

const HAPPY = ["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"];
const SATELLITE = /^[GERCSJIU]\d+$/;

interface Recorded {
  file: string;
  session: string;
  insSession: string; // an INS ON command to another vehicle in the same stretch
  insVehicleId: string;
  vehicleId: string;
  gps: {
    receivedAt: number;
    report: { satellites: { satelliteId: string }[] };
  };
}

let recorded: Recorded;
let replay: { url: string; stop: () => Promise<void> };

async function json<T>(r: Promise<{ json(): Promise<unknown>; ok(): boolean; status(): number }>): Promise<T> {
  const res = await r;
  expect(res.ok(), `HTTP ${res.status()}`).toBe(true);
  return (await res.json()) as T;
}

async function recordACommand(request: APIRequestContext): Promise<Recorded> {
  const { url, vehicles } = load();
  const vehicleId = vehicles[0];
  await json(request.post(`${url}/api/recordings`, { data: { action: "start" } }));
  await new Promise((r) => setTimeout(r, 1500));
  const { sessionId } = await json<{ sessionId: string }>(
    request.post(`${url}/api/providers/${vehicleId}/gps-fix`, { data: {} }),
  );
  await expect
    .poll(
      async () => (await json<{ status: string; cleanedUp: boolean }>(request.get(`${url}/api/commands/${sessionId}`))).cleanedUp,
      { timeout: 40_000 },
    )
    .toBe(true);
  const insVehicleId = vehicles[2]; // another vehicle (the first one's timeline holds the GPS fix only; the second rejects)
  const ins = await json<{ sessionId: string }>(
    request.post(`${url}/api/providers/${insVehicleId}/inertial-sensor`, {
      data: { state: "ON" },
    }),
  );
  await expect
    .poll(
      async () =>
        (await json<{ status: string; cleanedUp: boolean }>(request.get(`${url}/api/commands/${ins.sessionId}`))).cleanedUp,
      { timeout: 40_000 },
    )
    .toBe(true);
  await new Promise((r) => setTimeout(r, 1500));
  const detail = await json<{ reports: { GPSReport: Recorded["gps"] } }>(request.get(`${url}/api/providers/${vehicleId}`));
  const { file } = await json<{ file: string }>(request.post(`${url}/api/recordings`, { data: { action: "stop" } }));
  return {
    file,
    session: sessionId,
    insSession: ins.sessionId,
    insVehicleId,
    vehicleId,
    gps: detail.reports.GPSReport,
  };
}

async function seek(page: Page, position: number): Promise<void> {
  await page.getByTestId("replay-seek").fill(String(position)); // the bar's change event seeks
  await expect
    .poll(async () => (await json<{ position: number }>(page.request.get(`${replay.url}/api/replay`))).position)
    .toBeCloseTo(position, 3);
}

/** Paused on the server whatever its state, through the API: the bar's one button reads Play or Pause by the state,
 * and a click aimed at Pause just as the recording ends lands on Play, which starts it again from the start. The
 * button itself is pressed in the last test, while it plays. */
async function pause(page: Page): Promise<{ start: number; end: number }> {
  const status = await json<{ start: number; end: number; state: string }>(
    page.request.post(`${replay.url}/api/replay`, { data: { action: "pause" } }),
  );
  expect(status.state).toBe("paused");
  await expect(page.getByTestId("replay-bar")).toHaveAttribute("data-state", "paused");
  return status;
}

/** The satellite table's labels, read in one go once it has `n` rows: the page applies the seek's snapshot after the
 * console has seeked, and the table may be empty in between. */
async function shownSatellites(page: Page, n: number): Promise<string[]> {
  const cells = page.getByTestId("satellite-table").locator("tbody tr td:first-child");
  let labels: string[] = [];
  await expect.poll(async () => (labels = await cells.allTextContents()).length).toBe(n);
  return labels.map((l) => l.trim()).sort();
}

test.describe.serial("replay of a recording", () => {
  test.beforeAll(async ({ request }) => {
    test.setTimeout(120_000);
    recorded = await recordACommand(request);
    replay = await startReplayConsole(recorded.file);
  });

  test.afterAll(async () => {
    await replay?.stop();
  });

  test("the recording reads with @mcap/core, the TypeScript MCAP library Foxglove's apps use", async ({ request }) => {
    // an MCAP reader we did not write, on the file as the console serves it: streamed and through its indexes, CRCs checked
    const res = await request.get(`${load().url}/api/recordings/${recorded.file}`);
    expect(res.ok(), `HTTP ${res.status()}`).toBe(true);
    const data = new Uint8Array(await res.body());
    const decompressHandlers = {
      zstd: (buffer: Uint8Array, size: bigint) => {
        const out = decompress(buffer);
        expect(BigInt(out.length)).toBe(size);
        return out;
      },
    };
    const stream = new McapStreamReader({
      decompressHandlers,
      validateCrcs: true,
    });
    stream.append(data);
    const channels = new Map<number, McapTypes.Channel>();
    const schemas = new Map<number, McapTypes.Schema>();
    const streamed = new Map<string, number>();
    const transitions: string[] = [];
    const cdr = new Map<string, { data: Uint8Array; logTime: bigint }[]>(); // SEM topic -> its messages' CDR
    for (let record = stream.nextRecord(); record; record = stream.nextRecord()) {
      if (record.type === "Schema") schemas.set(record.id, record);
      if (record.type === "Channel") channels.set(record.id, record);
      if (record.type !== "Message") continue;
      const channel = channels.get(record.channelId)!;
      streamed.set(channel.topic, (streamed.get(channel.topic) ?? 0) + 1);
      if (channel.messageEncoding === "cdr")
        cdr.set(channel.topic, [...(cdr.get(channel.topic) ?? []), { data: record.data, logTime: record.logTime }]);
      if (channel.topic === "sem-console/transitions") {
        const t = JSON.parse(new TextDecoder().decode(record.data)) as {
          sessionId: string;
          transition: { status: string };
        };
        if (t.sessionId === recorded.session) transitions.push(t.transition.status);
      }
    }
    expect(stream.done()).toBe(true);
    // every SEM topic a channel of CDR with its UMAA type's OMG IDL schema; the command's transitions in order. The
    // UMAA 6.0 topics have theirs beside (none carried samples in this run): their schema texts parse too
    const sem = [...channels.values()].filter((c) => c.metadata.get("umaaVersion") === "3.0.1");
    expect(sem).toHaveLength(10);
    const sem60 = [...channels.values()].filter((c) => c.metadata.get("umaaVersion") === "6.0");
    expect(sem60.map((c) => c.topic).sort()).toEqual([
      "UMAA::SA::GlobalPoseStatus::GlobalPoseReportType",
      "UMAA::SEM::GPSStatus::GPSReportType",
      "UMAA::SEM::InertialSensorControl::InertialSensorCommandAckReportType",
      "UMAA::SEM::InertialSensorControl::InertialSensorCommandStatusType",
      "UMAA::SEM::InertialSensorControl::InertialSensorCommandType",
      "UMAA::SEM::InertialSensorStatus::InertialSensorReportType",
    ]);
    for (const c of sem60) {
      expect(c.messageEncoding).toBe("cdr");
      expect(schemas.get(c.schemaId)!.name).toBe(c.topic); // 6.0 names each topic after its type
      expect(() => parseIDL(new TextDecoder().decode(schemas.get(c.schemaId)!.data)), c.topic).not.toThrow();
    }
    for (const c of sem) {
      expect(c.messageEncoding).toBe("cdr");
      expect(schemas.get(c.schemaId)).toMatchObject({ encoding: "omgidl" });
      expect(schemas.get(c.schemaId)!.name).toMatch(/^UMAA::SEM::\w+::\w+Type$/);
    }
    expect(streamed.get("UMAA::SEM::GPSFixControl::GPSFixCommand")).toBeGreaterThanOrEqual(1);
    expect(streamed.get("UMAA::SEM::GPSStatus::GPSReport")).toBeGreaterThanOrEqual(1);
    expect(transitions).toEqual(HAPPY);

    const reader = await McapIndexedReader.Initialize({
      readable: {
        size: async () => BigInt(data.length),
        read: async (offset, length) => data.slice(Number(offset), Number(offset + length)),
      },
      decompressHandlers,
    });
    const total = [...streamed.values()].reduce((a, b) => a + b, 0);
    expect(Number(reader.statistics!.messageCount)).toBe(total);
    expect(reader.chunkIndexes.length).toBe(reader.statistics!.chunkCount);
    for (const [id, count] of reader.statistics!.channelMessageCounts) {
      expect(Number(count)).toBe(streamed.get(reader.channelsById.get(id)!.topic));
    }
    let indexed = 0;
    let last = 0n;
    for await (const message of reader.readMessages({ validateCrcs: true })) {
      expect(message.logTime >= last).toBe(true); // in log time order, by the message indexes
      last = message.logTime;
      indexed += 1;
    }
    expect(indexed).toBe(total);

    // Foxglove's own OMG IDL parser and CDR decoder (what its apps use), on the schema text and bytes as recorded.
    // It implements neither @optional nor the DHEADER XCDR2 puts before a sequence of structs, so
    // GPSFixReport and GPSReport are out of its reach (README, "Opening in Foxglove"); the other eight decode.
    const decode = (topic: string): (Record<string, unknown> & { logTime: bigint })[] => {
      const channel = sem.find((c) => c.topic === topic)!;
      const schema = schemas.get(channel.schemaId)!;
      const definitions: IDLMessageDefinition[] = parseIDL(new TextDecoder().decode(schema.data));
      const reader = new MessageReader(schema.name, definitions);
      const enums = (name: string): Map<number, string> => {
        const module = definitions.find((d) => d.aggregatedKind === "module" && (d.name ?? "").endsWith(`::${name}`));
        return new Map(module && "definitions" in module ? module.definitions.map((c) => [Number(c.value), c.name]) : []);
      };
      const statusNames = topic.endsWith("CommandStatus") ? enums("CommandStatusEnumType") : undefined;
      const stateNames = topic.includes("InertialSensor") ? enums("InertialSensorStateEnumType") : undefined;
      const messages = cdr.get(topic) ?? [];
      expect(messages.length, topic).toBeGreaterThan(0);
      return messages.map(({ data, logTime }) => {
        const message = reader.readMessage<Record<string, unknown>>(data);
        if (statusNames) message.commandStatus = statusNames.get(message.commandStatus as number);
        if (stateNames && "state" in message) message.state = stateNames.get(message.state as number);
        return { ...message, logTime };
      });
    };
    for (const c of sem) {
      // all ten schema texts parse as recorded, the same-named module and enum included
      expect(() => parseIDL(new TextDecoder().decode(schemas.get(c.schemaId)!.data)), c.topic).not.toThrow();
    }
    const guid = (g: unknown): string => {
      const hex = Buffer.from(Uint8Array.from(Object.values(g as Record<string, number>))).toString("hex");
      return `${hex.slice(0, 8)}-${hex.slice(8, 12)}-${hex.slice(12, 16)}-${hex.slice(16, 20)}-${hex.slice(20)}`;
    };
    const vehicles = new Set(load().vehicles);
    const command = decode("UMAA::SEM::GPSFixControl::GPSFixCommand").filter((m) => guid(m.sessionID) === recorded.session);
    expect(command.map((m) => guid(m.destination))).toEqual([recorded.vehicleId]);
    const statuses = decode("UMAA::SEM::GPSFixControl::GPSFixCommandStatus").filter(
      (m) => guid(m.sessionID) === recorded.session,
    );
    expect(statuses.map((m) => m.commandStatus)).toEqual(HAPPY); // as the vehicle reported them, ISSUED first
    expect(statuses.every((m) => guid(m.source) === recorded.vehicleId)).toBe(true);
    const acks = decode("UMAA::SEM::GPSFixControl::GPSFixCommandAckReport").filter((m) => guid(m.sessionID) === recorded.session);
    expect(acks.map((m) => guid(m.source))).toEqual([recorded.vehicleId]);
    for (const topic of [
      "UMAA::SEM::GPSFixStatus::GPSFixStatusReport",
      "UMAA::SEM::InertialSensorStatus::InertialSensorReport",
    ]) {
      const reports = decode(topic); // every vehicle's; the key and the time stamp are the last members: read in step
      expect(reports.length, topic).toBeGreaterThan(10);
      expect(new Set(reports.map((m) => guid(m.source))), topic).toEqual(vehicles);
      for (const m of reports) {
        const stamped = Number((m.timeStamp as { seconds: number | bigint }).seconds);
        expect(Math.abs(stamped - Number(m.logTime / 1_000_000_000n)), topic).toBeLessThanOrEqual(5); // stamped when sent
      }
    }
    const ins = decode("UMAA::SEM::InertialSensorControl::InertialSensorCommand").filter(
      (m) => guid(m.sessionID) === recorded.insSession,
    );
    expect(ins.map((m) => [guid(m.destination), m.state])).toEqual([[recorded.insVehicleId, "ON"]]);
    const insStatuses = decode("UMAA::SEM::InertialSensorControl::InertialSensorCommandStatus").filter(
      (m) => guid(m.sessionID) === recorded.insSession,
    );
    const insLive = await json<{ transitions: { status: string }[] }>(
      request.get(`${load().url}/api/commands/${recorded.insSession}`),
    );
    expect(insLive.transitions.length).toBeGreaterThanOrEqual(2); // as the live console took them, ISSUED first
    expect(insStatuses.map((m) => m.commandStatus)).toEqual(insLive.transitions.map((t) => t.status));
    const insAcks = decode("UMAA::SEM::InertialSensorControl::InertialSensorCommandAckReport").filter(
      (m) => guid(m.sessionID) === recorded.insSession,
    );
    expect(insAcks.map((m) => [guid(m.source), m.state])).toEqual([[recorded.insVehicleId, "ON"]]);
  });

  test("shows the recorded vehicle, satellites and command timeline, with the badge and commands disabled", async ({ page }) => {
    const live = load();
    await page.goto(`${replay.url}/?vehicle=${recorded.vehicleId}`);
    await expect(page.getByTestId("replay-badge")).toContainText(recorded.file);
    await expect(page.getByTestId("bus-security")).toHaveCount(0); // a recording has no bus
    await expect(page.getByTestId("connection-state")).toHaveText("Connected");
    await expect(page).toHaveTitle(/Replay · SEM Console$/); // beside a live console's tab, never taken for one
    await expect(page.getByTestId("replay-bar")).toBeVisible();
    await expect(page.getByTestId("vehicle")).toHaveCount(3); // the three vehicles on the bus when it was recorded
    await expect(vehicle(page, recorded.vehicleId)).toHaveAttribute("aria-pressed", "true");
    // named as the recording console named them (sem-console/names): the third vehicle by that console's
    // --vehicle-names, which this one (started without it) does not have; the first has no name there
    await expect(vehicle(page, recorded.insVehicleId).getByTestId("vehicle-tag")).toContainText(VEHICLE_3_NAME);
    await expect(vehicle(page, recorded.vehicleId).getByTestId("vehicle-tag")).toHaveText(
      `Vehicle ${recorded.vehicleId.slice(0, 8)}`,
    );

    // the instant the live console took its last GPSReport: the same satellites
    const { end } = await pause(page); // paused on the server before the seek, so no step of play lands after it
    // just after the report, but within the recording: it may end less than 50 ms after the report (the seek bar
    // cannot go past the end, and the seek would not land where asked)
    await seek(page, Math.min(end, recorded.gps.receivedAt + 0.05));
    const expected = (
      await json<{
        reports: {
          GPSReport: { report: { satellites: { satelliteId: string }[] } };
        };
      }>(page.request.get(`${replay.url}/api/providers/${recorded.vehicleId}`))
    ).reports.GPSReport.report;
    expect(expected).toEqual(recorded.gps.report);
    await expect(page.getByTestId("sats-listed")).toHaveText(String(recorded.gps.report.satellites.length));
    const labels = await shownSatellites(page, recorded.gps.report.satellites.length);
    expect(labels).toHaveLength(recorded.gps.report.satellites.length);
    expect(labels.every((l) => SATELLITE.test(l))).toBe(true);
    await expect(page.getByTestId("sky-satellite")).toHaveCount(recorded.gps.report.satellites.length);

    // no badge says "Live": each vehicle's link and each panel's freshness is the recording's, in words
    const RECORDED = /^Recorded: (live|regained|stale|lost)$/;
    await expect(page.getByTestId("fleet-link")).toHaveText([RECORDED, RECORDED, RECORDED]);
    await expect(page.getByTestId("vehicle-link")).toHaveText([RECORDED, RECORDED, RECORDED]);
    await expect(page.getByTestId("fleet-live")).toHaveText(/^Recorded: \d live$/);
    await expect(page.getByTestId("satellites-panel-freshness")).toHaveText(/^Recorded: (live|stale|lost) · /);
    await expect(page.getByText(/^live\b/i)).toHaveCount(0);

    // the command timeline, as the live console recorded it
    const cmd = page.getByTestId("commands-panel").getByTestId("command").first();
    await expect(cmd).toHaveAttribute("data-session", recorded.session);
    await expect(cmd).toHaveAttribute("data-status", "COMPLETED");
    expect(await cmd.getByTestId("transition").evaluateAll((els) => els.map((e) => (e as HTMLElement).dataset.status))).toEqual(
      HAPPY,
    );
    const liveCmd = await json<{
      transitions: { status: string; reason: string }[];
    }>(page.request.get(`${live.url}/api/commands/${recorded.session}`));
    expect(liveCmd.transitions.map((t) => t.status)).toEqual(HAPPY);
    await expect(cmd.getByTestId("ack")).toBeVisible();

    // read-only: every command control disabled, no record control, the console refuses commands
    await expect(page.getByTestId("commands-replay")).toBeVisible();
    for (const name of ["Request GPS fix", "INS ON", "INS OFF", "INS RESTART"]) {
      await expect(page.getByTestId("commands-panel").getByRole("button", { name, exact: true })).toBeDisabled();
    }
    await expect(page.getByTestId("recording")).toHaveCount(0);
    const refused = await page.request.post(`${replay.url}/api/providers/${recorded.vehicleId}/gps-fix`, { data: {} });
    expect(refused.status()).toBe(409);
  });

  test("seek rebuilds the state at that instant; speed and play move it on", async ({ page }) => {
    await page.goto(`${replay.url}/?vehicle=${recorded.vehicleId}`);
    await expect(page.getByTestId("replay-bar")).toBeVisible();
    const status = await pause(page);
    expect(status.end - status.start, "the recording's length (s): 5x play must not reach its end below").toBeGreaterThan(6);
    const command = await json<{
      createdAt: number;
      transitions: { receivedAt: number }[];
    }>(page.request.get(`${replay.url}/api/commands/${recorded.session}`));
    const commands = page.getByTestId("commands-panel").getByTestId("command");

    await seek(page, command.createdAt - 0.5); // before the command: not there
    await expect(commands).toHaveCount(0);
    await expect(page.getByTestId("command-list")).toContainText("No commands sent to this vehicle.");
    const midway = (command.transitions[2].receivedAt + command.transitions[3].receivedAt) / 2;
    await seek(page, midway); // between EXECUTING and COMPLETED
    await expect(commands.first()).toHaveAttribute("data-status", "EXECUTING");
    await seek(page, status.end); // the end: done
    await expect(commands.first()).toHaveAttribute("data-status", "COMPLETED");
    await expect(page.getByTestId("replay-elapsed")).toHaveText(await page.getByTestId("replay-total").innerText());

    // speed: 5x plays five seconds of recording per second
    await seek(page, status.start);
    await page.getByTestId("replay-speed").selectOption("5");
    await expect.poll(async () => (await json<{ speed: number }>(page.request.get(`${replay.url}/api/replay`))).speed).toBe(5);
    const played = async () =>
      (await json<{ position: number }>(page.request.get(`${replay.url}/api/replay`))).position - status.start;
    const t0 = Date.now();
    await page.getByRole("button", { name: "Play" }).click();
    // 2.5 s of recording: 0.5 s at 5x (2.5 s at 1x)
    await expect.poll(played, { timeout: 2000, intervals: [100] }).toBeGreaterThan(2.5);
    expect((Date.now() - t0) / 1000).toBeLessThan(2);
    await pause(page); // never faster than 5x
    expect(await played()).toBeLessThanOrEqual((5 * (Date.now() - t0)) / 1000 + 0.5);

    // Pause, pressed while it plays, pauses where it was: at 1x from the start, the recording's whole length of play
    // left for the click (at 5x, a loaded run's click came after the last 1.5 s of play and found it ended)
    await page.getByTestId("replay-speed").selectOption("1");
    await expect.poll(async () => (await json<{ speed: number }>(page.request.get(`${replay.url}/api/replay`))).speed).toBe(1);
    await seek(page, status.start);
    await page.getByRole("button", { name: "Play" }).click();
    await expect(page.getByTestId("replay-bar")).toHaveAttribute("data-state", "playing");
    await expect.poll(played, { intervals: [100] }).toBeGreaterThan(0.3);
    await page.getByRole("button", { name: "Pause" }).click();
    await expect(page.getByTestId("replay-bar")).toHaveAttribute("data-state", "paused");
    // paused where it was (a click that landed on Play as the recording ended would have played it again to the end)
    const at = await played();
    expect(at).toBeLessThan(status.end - status.start);
    await page.waitForTimeout(500);
    expect(await played()).toBe(at);
  });
});
