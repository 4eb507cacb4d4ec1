// CoMap C2 under the map: edit the world model (draw, move vertices, delete, import, export, send), assign
// survey and move tasks to the selected vehicle, follow their state and HOLD, RESUME or INTERRUPT them, and
// show the selected vehicle's capabilities.
// Shown only when the console has CoMap (GET /api/worldmodel answers, GET /api/comap says enabled); otherwise
// CoMapOff says why. Every order is bound to the vehicle selected when it was prepared (a Move-to armed,
// a confirmation open) and void once another vehicle is selected, as the UMAA command confirmations.
import { useEffect, useState } from "react";
import type { FeatureCollection } from "geojson";
import { createTask, problemText, putWorldModel, synchTask, type Capability, type SynchAction, type Task } from "../../api/rest";
import { Confirm } from "../../components/Confirm";
import { VehicleTag } from "../../components/VehicleTag";
import { useToken } from "../../data/auth";
import {
  useCapabilities,
  useData,
  useLostVehicles,
  useSelectedVehicle,
  useSelector,
  useSilences,
  useVehicleNames,
} from "../../data/hooks";
import { LastHeard, LostFor } from "../../components/LastHeard";
import { useComapStatus, useTasks, useVehicleCapabilities } from "../../data/loaders";
import { FINISHED } from "../../data/slices/comap";
import { plannedUntil } from "../../data/slices/alarms";
import { coverageColor, drawnGeometry, nextFeatureId, parseWorldModel, type Coverage, type LonLat } from "../../lib/geo";
import { RESOLUTION_UNIT, clockTime, resolution as resolutionText, utcWhen } from "../../lib/units";
import {
  coverageText,
  lostButtonNote,
  lostClause,
  lostMeanwhileText,
  positionText,
  sensorText,
  taskKindText,
  taskStateText,
} from "../../lib/labels";
import { countRender } from "../../lib/renders";
import { vehicleLabel, type VehicleIdentity } from "../../lib/vehicle";

export type MapTool = "select" | "measure" | "draw" | "edit" | "move-target";

interface Props {
  model: FeatureCollection; // what the map shows: the draft (with the console's coverage) while editing, else the console's
  consoleModel: FeatureCollection; // the console's world model: what a survey can be assigned on
  dirty: boolean;
  setDraft: (fc: FeatureCollection | null) => void; // null: back to the console's model
  tool: MapTool;
  setTool: (t: MapTool) => void;
  drawn: LonLat[]; // vertices clicked in draw mode
  clearDrawn: () => void;
  moveTarget: LonLat | null;
  picked: unknown; // the featureId clicked on the map with the edit tool, null for none
  unpick: () => void;
}

type Sensor = Task["sensor"] & string;
const SENSORS: Sensor[] = ["ANY", "SIDESCAN", "MULTIBEAM", "CAMERA", "MAGNETOMETER"];
const SYNCH_WORDS: Record<SynchAction, string> = { HOLD: "Hold", RESUME: "Resume", INTERRUPT: "Interrupt" };
const GEOMETRY_WORDS: Record<string, string> = { Polygon: "Polygon", LineString: "Line", Point: "Point" };

/** The tooltip that keeps CoMap's (IMC's) word for a value shown in plain words. */
function imc(field: string, literal: string | null | undefined): string | undefined {
  return literal ? `IMC ${field}: ${literal}` : undefined;
}

/** One VehicleCapabilities entry as the operator reads it. */
export function capabilityText(c: Capability): string {
  const parts: string[] = [c.kind === "AREA_SURVEY" ? "area survey" : c.kind === "POINT_SURVEY" ? "point survey" : "move"];
  if (c.sensor) parts.push(sensorText(c.sensor).toLowerCase());
  if (typeof c.resolution === "number") parts.push(resolutionText(c.resolution));
  if (typeof c.coverageRate === "number") parts.push(`${c.coverageRate} m²/s`);
  if (typeof c.duration === "number") parts.push(`${c.duration} s`);
  if (typeof c.speed === "number") parts.push(`${c.speed} m/s`);
  return parts.join(" ");
}

/** What waits for the operator's Confirm, bound to the vehicle it was prepared for, and to whether that
 * vehicle was lost then (the confirmation then says so, as the UMAA commands' do). */
export type Pending = { target: VehicleIdentity; lost: boolean } & (
  | { kind: "move"; point: LonLat }
  | { kind: "survey"; featureId: number; sensor: Sensor; resolution: number; deadline: number | null }
  | { kind: "synch"; task: Task; action: SynchAction }
);

/** What the deadline field says of a time it cannot take. */
export const BAD_DEADLINE = "Deadline: write a UTC time, 24-hour, as HH:MM or YYYY-MM-DD HH:MM (or nothing for none)";

/** The survey's deadline as written (empty: none), in UTC seconds, the next such time after `now` (the console's
 * clock); "bad" for what is no 24-hour UTC time. */
function deadlineOf(text: string, now: number): number | null | "bad" {
  return text.trim() ? (utcWhen(text, now) ?? "bad") : null;
}

export function pendingText(p: Pending): string {
  if (p.kind === "move") return `Move ${vehicleLabel(p.target)} to ${positionText(p.point.lat, p.point.lon)}?`;
  if (p.kind === "survey")
    return `Survey feature #${p.featureId} with ${vehicleLabel(p.target)}: ${sensorText(p.sensor).toLowerCase()}, resolution ${resolutionText(p.resolution)}${p.deadline !== null ? `, by ${clockTime(p.deadline)}` : ""}?`;
  return `${SYNCH_WORDS[p.action]} task ${p.task.taskId} (${taskKindText(p.task.kind).toLowerCase()}) of ${vehicleLabel(p.target)}?`;
}

function pendingName(p: Pending): string {
  return p.kind === "move" ? "Move-to" : p.kind === "survey" ? "Survey" : SYNCH_WORDS[p.action];
}

const COMAP_OFF = "CoMap is off: this console was started without --imc-port, so no vehicle can be tasked from here.";
const COMAP_ABSENT = "CoMap is off: this console has no CoMap (it answers 404).";

/** In place of the CoMap controls when the console has no world model: why, once the console says. */
export function CoMapOff() {
  const status = useComapStatus();
  if (status === null || (status !== "absent" && status.enabled)) return null;
  return (
    <p className="muted" data-testid="comap-off">
      {status === "absent" ? COMAP_ABSENT : COMAP_OFF}
    </p>
  );
}

export function CoMapControls({
  model,
  consoleModel,
  dirty,
  setDraft,
  tool,
  setTool,
  drawn,
  clearDrawn,
  moveTarget,
  picked,
  unpick,
}: Props) {
  countRender("comap");
  const token = useToken();
  const { source } = useData();
  const mayWrite = useCapabilities().command; // a replay is read-only: nothing is sent
  const selected = useSelector((s) => s.selected);
  const vehicle = useSelectedVehicle();
  const nameOf = useVehicleNames();
  const lost = useLostVehicles(); // by id, when each was last heard
  const silences = useSilences();
  const status = useComapStatus();
  const [deleted, setDeleted] = useState<unknown[]>([]); // ids deleted this session: never given again
  const [error, setError] = useState<string | null>(null);
  const [note, setNote] = useState<string | null>(null);
  const [featureId, setFeatureId] = useState<number | "">("");
  const [sensor, setSensor] = useState<Sensor>("SIDESCAN");
  const [resolution, setResolution] = useState(1);
  const [deadline, setDeadline] = useState("");
  const [armed, setArmed] = useState<VehicleIdentity | null>(null); // Move-to armed for this vehicle: the map's next click is its destination
  const [pending, setPending] = useState<Pending | null>(null);
  const taskList = useTasks();
  const caps = useVehicleCapabilities(vehicle?.id ?? null);
  const identity = (id: string): VehicleIdentity => ({ id, name: nameOf.get(id) || null });
  const isLost = (id: string): boolean => lost.has(id);
  const untilOf = (id: string): number | null => plannedUntil(silences, id, "lost"); // lost in its planned silence: its end

  // Adjusted while rendering, so no frame shows an order armed for a vehicle no longer selected:
  if ((armed && armed.id !== selected) || (pending && pending.target.id !== selected)) {
    const what = pending ?? { kind: "move" as const, target: armed! };
    setNote(
      `${what.kind === "move" ? "Move-to" : pendingName(what as Pending)} for ${vehicleLabel(what.target)} not sent: the selected vehicle changed.`,
    );
    setArmed(null);
    setPending(null);
  } else if (pending && !pending.lost && isLost(pending.target.id)) {
    // its vehicle lost meanwhile: what the operator is confirming no longer says what would happen
    setNote(lostMeanwhileText(pendingName(pending), vehicleLabel(pending.target), untilOf(pending.target.id)));
    setPending(null);
  } else if (armed && tool !== "move-target" && pending?.kind !== "move") {
    setArmed(null); // another map tool taken meanwhile (measure, draw): Move-to is put down
  }
  // the map's tool follows: a Move-to no longer armed leaves its click-a-destination tool
  useEffect(() => {
    if (tool === "move-target" && armed === null) setTool("select");
  }, [tool, armed, setTool]);

  // a refusal names the order and its vehicle: the confirmation that named them is gone by the time it comes
  const run = (what: string, p: Promise<unknown>) => {
    setError(null);
    setNote(null);
    p.catch((e: unknown) => setError(`${what} not sent: ${problemText(e)}`));
  };
  // a new feature's id is above every id used so far (a survey's CoverageState for a deleted #n must not colour it)
  const freshId = () => nextFeatureId([model, consoleModel], [...deleted, ...taskList.map((t) => t.featureId)]);
  const finishDrawing = () => {
    const geometry = drawnGeometry(drawn);
    if (geometry) {
      const id = freshId();
      setDraft({
        ...model,
        features: [...model.features, { type: "Feature", geometry, properties: { featureId: id, coverage: null } }],
      });
    }
    clearDrawn();
    setTool("select");
  };
  const remove = (id: unknown) => {
    setDeleted((d) => [...d, id]);
    unpick(); // the picked feature may be the one deleted
    setDraft({ ...model, features: model.features.filter((f) => f.properties?.featureId !== id) });
  };
  const importFile = (file: File | undefined) => {
    if (!file) return;
    file
      .text()
      .then((text) => setDraft(parseWorldModel(text, freshId())))
      .catch((e: Error) => setError(`import: ${e.message}`));
  };
  const exportHref = `data:application/geo+json;charset=utf-8,${encodeURIComponent(JSON.stringify(model))}`;
  // Why the selected vehicle cannot be tasked (null: it can): CoMap off, or no IMC id for it.
  const offReason = status === "absent" ? COMAP_ABSENT : status !== null && !status.enabled ? COMAP_OFF : null;
  const noImc =
    vehicle && caps !== null && caps.imcId === null
      ? `${vehicleLabel(vehicle)} has no IMC system id (the console's --imc-vehicles): it cannot be tasked.`
      : null;
  const cannotTask = !mayWrite ? "Replay: read-only." : (offReason ?? noImc ?? (vehicle ? null : "Select a vehicle to task it."));
  const target: VehicleIdentity | null = vehicle ? { id: vehicle.id, name: vehicle.name } : null;
  const targetLost = target !== null && isLost(target.id) ? lostButtonNote(untilOf(target.id)) : "";

  const send = (p: Pending) => {
    setPending(null);
    const to = p.target.id; // the vehicle it was prepared for, whatever is selected now
    if (p.kind === "move") {
      setArmed(null);
      run(
        `Move-to for ${vehicleLabel(p.target)}`,
        createTask({ kind: "move", vehicle: to, point: p.point, sensor: "ANY", resolution: 1 }, token),
      );
    } else if (p.kind === "survey") {
      run(
        `Survey for ${vehicleLabel(p.target)}`,
        createTask(
          {
            kind: "survey",
            vehicle: to,
            featureId: p.featureId,
            sensor: p.sensor,
            resolution: p.resolution,
            ...(p.deadline !== null ? { deadline: new Date(p.deadline * 1000).toISOString() } : {}),
          },
          token,
        ),
      );
    } else {
      run(
        `${SYNCH_WORDS[p.action]} of task ${p.task.taskId} for ${vehicleLabel(p.target)}`,
        synchTask(p.task.taskId, p.action, token),
      );
    }
  };
  const survey = () => {
    if (!target || featureId === "" || dirty) return;
    const by = deadlineOf(deadline, source.consoleNow());
    if (by === "bad") return setNote(BAD_DEADLINE);
    setNote(null);
    setPending({ kind: "survey", target, lost: isLost(target.id), featureId, sensor, resolution, deadline: by });
  };
  const moveButton = () => {
    setNote(null);
    if (armed && moveTarget) setPending({ kind: "move", target: armed, lost: isLost(armed.id), point: moveTarget });
    else if (armed) {
      setArmed(null); // pressed again before a destination: put down
      setTool("select");
    } else if (target) {
      setArmed(target);
      setTool("move-target");
    }
  };
  const synch = (t: Task, action: SynchAction) => {
    setNote(null);
    // INTERRUPT, and any order to a lost vehicle, waits for the operator's confirmation
    if (action === "INTERRUPT" || isLost(t.vehicle))
      setPending({ kind: "synch", target: identity(t.vehicle), lost: isLost(t.vehicle), task: t, action });
    else
      run(
        `${SYNCH_WORDS[action]} of task ${t.taskId} for ${vehicleLabel(identity(t.vehicle))}`,
        synchTask(t.taskId, action, token),
      );
  };

  if (offReason) {
    return (
      <div className="comap" data-testid="comap">
        <p className="muted" data-testid="comap-off">
          {offReason}
        </p>
      </div>
    );
  }

  return (
    <div className="comap" data-testid="comap">
      <div className="comap-row">
        <strong>World model</strong>
        <button
          className="small"
          aria-pressed={tool === "draw"}
          onClick={() => (tool === "draw" ? finishDrawing() : (clearDrawn(), setTool("draw")))}
        >
          {tool === "draw" ? `Finish (${drawn.length} points)` : "Draw feature"}
        </button>
        <button
          className="small"
          aria-pressed={tool === "edit"}
          data-testid="edit-features"
          onClick={() => {
            if (tool !== "edit") setDraft(model); // edits go to a draft, sent with "Send world model"
            setTool(tool === "edit" ? "select" : "edit");
          }}
          title="drag a vertex handle on the map to move it; click a feature to delete it"
        >
          {tool === "edit" ? "Done editing" : "Edit features"}
        </button>
        {tool === "edit" && picked !== null && model.features.some((f) => f.properties?.featureId === picked) && (
          <button className="small" data-testid="delete-picked" onClick={() => remove(picked)}>
            Delete #{String(picked)}
          </button>
        )}
        <label className="button small">
          Import GeoJSON
          <input
            type="file"
            accept=".json,.geojson,application/geo+json"
            hidden
            onChange={(e) => importFile(e.target.files?.[0])}
          />
        </label>
        <a className="button" href={exportHref} download="worldmodel.geojson">
          Export GeoJSON
        </a>
        <button
          className="small"
          disabled={!dirty || !mayWrite}
          onClick={() =>
            run(
              "World model",
              putWorldModel(model, token).then(() => setDraft(null)),
            )
          }
          data-testid="send-worldmodel"
        >
          Send world model
        </button>
        {dirty && (
          <button className="small" onClick={() => setDraft(null)}>
            Discard changes
          </button>
        )}
      </div>
      <ul className="features">
        {model.features.map((f) => (
          <li
            key={String(f.properties?.featureId)}
            data-testid="feature"
            aria-current={picked !== null && f.properties?.featureId === picked ? "true" : undefined}
            data-feature-id={String(f.properties?.featureId)}
            data-coverage={String(f.properties?.coverage ?? "")}
          >
            <span
              className="swatch"
              data-testid="coverage-swatch"
              style={{ background: coverageColor((f.properties?.coverage ?? null) as Coverage) }}
            />
            #{String(f.properties?.featureId)} {GEOMETRY_WORDS[f.geometry?.type ?? ""] ?? f.geometry?.type} ·{" "}
            <span data-testid="coverage" title={imc("coverage", (f.properties?.coverage ?? null) as string | null)}>
              {coverageText((f.properties?.coverage ?? null) as string | null)}
            </span>{" "}
            <button
              className="small"
              onClick={() => remove(f.properties?.featureId)}
              aria-label={`Delete feature ${String(f.properties?.featureId)}`}
            >
              ✕
            </button>
          </li>
        ))}
      </ul>
      <div className="comap-row" role="group" aria-label={target ? `Task ${vehicleLabel(target)}` : "Task a vehicle"}>
        <strong>Task {target ? <VehicleTag v={target} /> : "(select a vehicle)"}</strong>
        <select
          aria-label="Feature"
          value={featureId}
          onChange={(e) => setFeatureId(e.target.value ? Number(e.target.value) : "")}
        >
          <option value="">feature…</option>
          {consoleModel.features.map((f) => (
            <option key={String(f.properties?.featureId)} value={String(f.properties?.featureId)}>
              #{String(f.properties?.featureId)}
            </option>
          ))}
        </select>
        <select aria-label="Sensor" value={sensor} onChange={(e) => setSensor(e.target.value as Sensor)}>
          {SENSORS.map((s) => (
            <option key={s} value={s}>
              {sensorText(s)}
            </option>
          ))}
        </select>
        <input
          aria-label={`Resolution (${RESOLUTION_UNIT})`}
          title="survey resolution, in the unit of the vehicles' capabilities"
          type="number"
          min={0.01}
          step={0.1}
          value={resolution}
          onChange={(e) => setResolution(Number(e.target.value))}
          style={{ width: 70 }}
        />
        <span className="muted">{RESOLUTION_UNIT}</span>
        <input
          aria-label="Deadline (UTC)"
          title="none, or a 24-hour UTC time: HH:MM (the next one) or YYYY-MM-DD HH:MM"
          type="text"
          placeholder="deadline HH:MM UTC"
          maxLength={16}
          size={16}
          value={deadline}
          onChange={(e) => setDeadline(e.target.value)}
        />
        <button
          className="small"
          disabled={cannotTask !== null || featureId === "" || dirty}
          onClick={survey}
          data-testid="survey"
          title={
            cannotTask ??
            (dirty
              ? "send or discard the world model edits first: the vehicle surveys the console's features"
              : target
                ? `Survey the chosen feature with ${vehicleLabel(target)} (asks you to confirm)`
                : undefined)
          }
        >
          Survey{targetLost}
        </button>
        <button
          className="small"
          aria-pressed={armed !== null}
          disabled={cannotTask !== null}
          onClick={moveButton}
          data-testid="move-to"
          data-vehicle={armed?.id}
          title={
            cannotTask ??
            (armed
              ? `Move-to armed for ${vehicleLabel(armed)}: click its destination on the map`
              : target
                ? `Move ${vehicleLabel(target)}: then click its destination on the map`
                : undefined)
          }
        >
          {armed
            ? moveTarget
              ? `Send move of ${vehicleLabel(armed)}…`
              : `Move ${vehicleLabel(armed)}: click its destination`
            : `Move to…${targetLost}`}
        </button>
      </div>
      {cannotTask && target && mayWrite && (
        <p className="muted" data-testid="comap-cannot-task">
          {cannotTask}
        </p>
      )}
      {pending && (
        <Confirm
          key={`${pending.kind} ${pending.target.id}`}
          label={`Confirm ${pendingName(pending).toLowerCase()}`}
          vehicle={pending.target.id}
          confirmText={
            pending.lost
              ? "Send anyway"
              : pending.kind === "synch"
                ? SYNCH_WORDS[pending.action]
                : pending.kind === "move"
                  ? "Send move"
                  : "Send survey"
          }
          onConfirm={() => send(pending)}
          onCancel={() => setPending(null)}
          testId="comap-confirm"
        >
          <p>{pendingText(pending)}</p>
          {pending.lost && (
            <p className="confirm-lost" data-testid="comap-confirm-lost">
              <strong>
                {isLost(pending.target.id) ? (
                  <LostFor
                    target={pending.target}
                    since={lost.get(pending.target.id) ?? null}
                    until={untilOf(pending.target.id)}
                  />
                ) : (
                  `${vehicleLabel(pending.target)} was lost`
                )}
                . Send anyway?
              </strong>{" "}
              It may reach the vehicle late, or not at all.
            </p>
          )}
          {pending.kind === "synch" && pending.action === "INTERRUPT" && (
            <p>It stops the task for good: a new task is needed to go on.</p>
          )}
        </Confirm>
      )}
      {note && (
        <p className="muted" role="status" data-testid="comap-note">
          {note}
        </p>
      )}
      {vehicle && (
        <p className="capabilities muted" data-testid="capabilities">
          Capabilities:{" "}
          {caps === null
            ? "none heard"
            : caps.imcId === null
              ? "no IMC system id (--imc-vehicles)"
              : caps.capabilities === null
                ? `IMC ${caps.imcId}: none heard yet`
                : `IMC ${caps.imcId}: ${caps.capabilities.map(capabilityText).join(" · ") || "none"}`}
        </p>
      )}
      {dirty && (
        <p className="muted" data-testid="draft-note">
          Unsent edits: surveys are assigned on the console's features; send or discard the edits first.
        </p>
      )}
      {!mayWrite && <p className="readonly-note">Replay: read-only. The world model and tasks are not sent.</p>}
      {error && (
        <p className="error" role="alert" data-testid="comap-error">
          {error}
        </p>
      )}
      <table className="tasks">
        <tbody>
          {taskList.map((t) => {
            const owner = identity(t.vehicle);
            const finished = t.state !== null && FINISHED.has(t.state);
            // a task's HOLD, RESUME, INTERRUPT go to its own vehicle, and only while that vehicle is the one selected
            const why = !mayWrite
              ? "Replay: read-only."
              : finished
                ? "the task has finished"
                : t.vehicle !== selected
                  ? `select ${vehicleLabel(owner)} to act on its task`
                  : null;
            return (
              <tr key={t.taskId} data-testid="task" data-task-id={t.taskId} data-vehicle={t.vehicle}>
                <td>{t.taskId}</td>
                <td>
                  {taskKindText(t.kind)}
                  {t.featureId !== null && t.kind === "survey" ? ` #${t.featureId}` : ""}
                </td>
                <td data-testid="task-vehicle">
                  <VehicleTag v={owner} />
                  {isLost(t.vehicle) && (
                    <span className={untilOf(t.vehicle) !== null ? "fleet-planned" : "tone-bad"} data-testid="task-lost">
                      {" "}
                      {lostClause(untilOf(t.vehicle))} · <LastHeard since={lost.get(t.vehicle) ?? null} />
                    </span>
                  )}
                </td>
                <td
                  data-testid="task-state"
                  data-state={t.state ?? ""}
                  title={
                    t.state === "HELD" || t.state === "INTERRUPTED"
                      ? `${imc("task state", t.state)}: sent to the vehicle; CoMap has no acknowledgement of a hold or interrupt, so its TaskStatus reports (progress) show what it does`
                      : imc("task state", t.state)
                  }
                >
                  {t.state ? taskStateText(t.state) : "—"}
                </td>
                <td data-testid="task-progress">{typeof t.progress === "number" ? `${t.progress}%` : "—"}</td>
                <td>{typeof t.quality === "number" ? `quality ${t.quality}%` : ""}</td>
                <td className="muted" data-testid="task-by">
                  {t.operator ? `by ${t.operator}` : ""}
                  {t.station ? (
                    <span data-testid="task-station" title="the console station that assigned it">
                      {" "}
                      on {t.station}
                    </span>
                  ) : null}
                </td>
                <td>
                  {(["HOLD", "RESUME", "INTERRUPT"] as const).map((a) => (
                    <button
                      key={a}
                      className="small"
                      disabled={why !== null}
                      title={
                        why ??
                        `${SYNCH_WORDS[a]} this task of ${vehicleLabel(owner)}${isLost(t.vehicle) ? `, which is ${lostClause(untilOf(t.vehicle))} (asks you to confirm)` : a === "INTERRUPT" ? " (asks you to confirm)" : ""}`
                      }
                      onClick={() => synch(t, a)}
                    >
                      {SYNCH_WORDS[a]}
                    </button>
                  ))}
                </td>
              </tr>
            );
          })}
        </tbody>
      </table>
    </div>
  );
}
