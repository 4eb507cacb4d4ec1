// CoMap C2 under the map: edit the world model (draw, move vertices, delete, import, export, send), assign
// survey and move tasks to the selected vehicle, follow their state and HOLD, RESUME or INTERRUPT them, and
// show the selected vehicle's capabilities.
// Shown only when the console has CoMap (GET /api/worldmodel answers).
import { useState } from "react";
import type { FeatureCollection } from "geojson";
import { createTask, putWorldModel, synchTask, type Capability, type SynchAction, type Task } from "../api/rest";
import { useToken } from "../data/auth";
import { useCapabilities, useSelectedVehicle, useTasks, useVehicleCapabilities } from "../data/hooks";
import { coverageColor, drawnGeometry, nextFeatureId, parseWorldModel, type Coverage, type LonLat } from "../lib/geo";
import { countRender } from "../lib/renders";
import { vehicleLabel } from "../lib/vehicle";

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

/** One VehicleCapabilities entry as the operator reads it. */
function capabilityText(c: Capability): string {
  const parts: string[] = [c.kind === "AREA_SURVEY" ? "area survey" : c.kind === "POINT_SURVEY" ? "point survey" : "move"];
  if (c.sensor) parts.push(c.sensor);
  if (typeof c.resolution === "number") parts.push(`${c.resolution} px/m²`);
  if (typeof c.coverageRate === "number") parts.push(`${c.coverageRate} m²/s`);
  if (typeof c.duration === "number") parts.push(`${c.duration} s`);
  if (typeof c.speed === "number") parts.push(`${c.speed} m/s`);
  return parts.join(" ");
}

export function CoMapControls({ model, consoleModel, dirty, setDraft, tool, setTool, drawn, clearDrawn, moveTarget, picked, unpick }: Props) {
  countRender("comap");
  const token = useToken();
  const mayWrite = useCapabilities().command; // a replay is read-only: nothing is sent
  const vehicle = useSelectedVehicle();
  const [deleted, setDeleted] = useState<unknown[]>([]); // ids deleted this session: never given again
  const [error, setError] = useState<string | null>(null);
  const [featureId, setFeatureId] = useState<number | "">("");
  const [sensor, setSensor] = useState<Sensor>("SIDESCAN");
  const [resolution, setResolution] = useState(1);
  const [deadline, setDeadline] = useState("");
  const taskList = useTasks();
  const caps = useVehicleCapabilities(vehicle?.id ?? null);

  const run = (p: Promise<unknown>) => {
    setError(null);
    p.catch((e: Error) => setError(e.message));
  };
  // a new feature's id is above every id used so far (a survey's CoverageState for a deleted #n must not colour it)
  const freshId = () => nextFeatureId([model, consoleModel], [...deleted, ...taskList.map((t) => t.featureId)]);
  const finishDrawing = () => {
    const geometry = drawnGeometry(drawn);
    if (geometry) {
      const id = freshId();
      setDraft({ ...model, features: [...model.features, { type: "Feature", geometry, properties: { featureId: id, coverage: null } }] });
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
  const survey = () =>
    vehicle &&
    featureId !== "" &&
    !dirty &&
    run(createTask({ kind: "survey", vehicle: vehicle.id, featureId, sensor, resolution, ...(deadline ? { deadline: new Date(`${deadline}Z`).toISOString() } : {}) }, token));
  const move = () => vehicle && moveTarget && run(createTask({ kind: "move", vehicle: vehicle.id, point: moveTarget, sensor: "ANY", resolution: 1 }, token).then(() => setTool("select")));
  const synch = (id: Task["taskId"], action: SynchAction) => run(synchTask(id, action, token));

  return (
    <div className="comap" data-testid="comap">
      <div className="comap-row">
        <strong>World model</strong>
        <button className="small" aria-pressed={tool === "draw"} onClick={() => (tool === "draw" ? finishDrawing() : (clearDrawn(), setTool("draw")))}>
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
          <input type="file" accept=".json,.geojson,application/geo+json" hidden onChange={(e) => importFile(e.target.files?.[0])} />
        </label>
        <a className="button" href={exportHref} download="worldmodel.geojson">
          Export GeoJSON
        </a>
        <button className="small" disabled={!dirty || !mayWrite} onClick={() => run(putWorldModel(model, token).then(() => setDraft(null)))} data-testid="send-worldmodel">
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
          <li key={String(f.properties?.featureId)} data-testid="feature" aria-current={picked !== null && f.properties?.featureId === picked ? "true" : undefined} data-feature-id={String(f.properties?.featureId)} data-coverage={String(f.properties?.coverage ?? "")}>
            <span className="swatch" data-testid="coverage-swatch" style={{ background: coverageColor((f.properties?.coverage ?? null) as Coverage) }} />
            #{String(f.properties?.featureId)} {f.geometry?.type} · <span data-testid="coverage">{String(f.properties?.coverage ?? "coverage unknown")}</span>{" "}
            <button className="small" onClick={() => remove(f.properties?.featureId)} aria-label={`Delete feature ${String(f.properties?.featureId)}`}>
              ✕
            </button>
          </li>
        ))}
      </ul>
      <div className="comap-row">
        <strong>Task {vehicle ? vehicleLabel(vehicle) : "(select a vehicle)"}</strong>
        <select aria-label="Feature" value={featureId} onChange={(e) => setFeatureId(e.target.value ? Number(e.target.value) : "")}>
          <option value="">feature…</option>
          {consoleModel.features.map((f) => (
            <option key={String(f.properties?.featureId)} value={String(f.properties?.featureId)}>
              #{String(f.properties?.featureId)}
            </option>
          ))}
        </select>
        <select aria-label="Sensor" value={sensor} onChange={(e) => setSensor(e.target.value as Sensor)}>
          {SENSORS.map((s) => (
            <option key={s}>{s}</option>
          ))}
        </select>
        <input aria-label="Resolution (m)" type="number" min={0.01} step={0.1} value={resolution} onChange={(e) => setResolution(Number(e.target.value))} style={{ width: 70 }} />
        <input aria-label="Deadline (UTC)" type="datetime-local" value={deadline} onChange={(e) => setDeadline(e.target.value)} />
        <button
          className="small"
          disabled={!mayWrite || !vehicle || featureId === "" || dirty}
          onClick={survey}
          data-testid="survey"
          title={dirty ? "send or discard the world model edits first: the vehicle surveys the console's features" : undefined}
        >
          Survey
        </button>
        <button className="small" aria-pressed={tool === "move-target"} disabled={!mayWrite || !vehicle} onClick={() => (tool === "move-target" && moveTarget ? move() : setTool("move-target"))}>
          {tool === "move-target" ? (moveTarget ? "Send move" : "click a destination") : "Move to…"}
        </button>
      </div>
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
      {error && <p className="error" role="alert">{error}</p>}
      <table className="tasks">
        <tbody>
          {taskList.map((t) => (
            <tr key={t.taskId} data-testid="task" data-task-id={t.taskId}>
              <td>{t.taskId}</td>
              <td>{t.kind}</td>
              <td>{t.vehicle.slice(0, 8)}</td>
              <td data-testid="task-state">{t.state ?? "—"}</td>
              <td data-testid="task-progress">{typeof t.progress === "number" ? `${t.progress}%` : "—"}</td>
              <td>{typeof t.quality === "number" ? `q ${t.quality}` : ""}</td>
              <td>
                {(["HOLD", "RESUME", "INTERRUPT"] as const).map((a) => (
                  <button key={a} className="small" disabled={!mayWrite} onClick={() => synch(t.taskId, a)}>
                    {a}
                  </button>
                ))}
              </td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
