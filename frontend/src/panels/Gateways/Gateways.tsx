import { useState, type ChangeEvent } from "react";
import { aspnLog, problemText, setLinkConfig } from "../../api/rest";
import type { GatewayState, LinkConfig } from "../../api/types";
import { Field, Panel } from "../../components/Panel";
import { VehicleTag } from "../../components/VehicleTag";
import { useToken } from "../../data/auth";
import { useCapabilities, useGateways, useNow, useSelectedVehicle, useSelector } from "../../data/hooks";
import { utc } from "../../lib/units";
import { vehicleLabel, type VehicleIdentity } from "../../lib/vehicle";

const TITLES: Record<GatewayState["name"], string> = {
  aspn: "ASPN-23 over LCM",
  jaus: "JAUS over JUDP",
  foxglove: "Foxglove WebSocket",
};

function GatewayRow({ g }: { g: GatewayState }) {
  return (
    <div className="gateway" data-testid={`gateway-${g.name}`} data-enabled={g.enabled ? "true" : "false"}>
      <p>
        <strong>{TITLES[g.name]}</strong>{" "}
        <span className={g.enabled ? "ok" : "muted"} data-testid="gateway-state">
          {g.enabled ? "on" : "off"}
        </span>
      </p>
      {g.enabled && (
        <>
          <Field label="Endpoint" value={g.endpoint ?? "—"} />
          <Field
            label="Messages out"
            value={`${g.messagesPerSecond.toFixed(1)}/s · ${g.messagesOut} total`}
            testId="gateway-rate"
          />
          <Field
            label="Last error"
            value={g.lastError ? `${g.lastError} (${utc(g.lastErrorAt, false)})` : "none"}
            invalid={g.lastError}
            testId="gateway-error"
          />
          {Object.keys(g.counters).length > 0 && (
            <details>
              <summary className="muted">counters</summary>
              {Object.entries(g.counters).map(([k, v]) => (
                <Field key={k} label={k} value={String(v)} />
              ))}
            </details>
          )}
        </>
      )}
    </div>
  );
}

/** Record the selected vehicle's ASPN messages from now; Stop downloads them as a .lcm file. */
function RecordAspn({ target, enabled, token }: { target: VehicleIdentity; enabled: boolean; token: string | null }) {
  const [recording, setRecording] = useState<{ vehicle: VehicleIdentity; start: number } | null>(null);
  const [error, setError] = useState<string | null>(null);
  const now = useNow(1000);
  const stop = async () => {
    if (!recording) return;
    const { vehicle, start } = recording;
    setRecording(null);
    try {
      const { blob, filename } = await aspnLog(vehicle.id, Math.max(1, Math.ceil(Date.now() / 1000 - start) + 1), token);
      const a = document.createElement("a");
      a.href = URL.createObjectURL(blob);
      a.download = filename;
      a.click();
      setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
    } catch (e) {
      setError(`ASPN log of ${vehicleLabel(vehicle)}: ${problemText(e)}`);
    }
  };
  return (
    <div className="actions" role="group" aria-label="ASPN log">
      {recording ? (
        <button
          onClick={() => void stop()}
          data-testid="aspn-stop"
          title={`Stop and download the ASPN log of ${vehicleLabel(recording.vehicle)}`}
        >
          Stop and download ({Math.round(now - recording.start)} s of {vehicleLabel(recording.vehicle)})
        </button>
      ) : (
        <button
          disabled={!enabled}
          data-testid="aspn-record"
          title={
            enabled
              ? `Record the ASPN-23 messages of ${vehicleLabel(target)}`
              : "the ASPN gateway is off (start the console with --aspn-lcm URL)"
          }
          onClick={() => (setError(null), setRecording({ vehicle: target, start: Date.now() / 1000 }))}
        >
          Record ASPN log
        </button>
      )}
      {error && (
        <span className="error" role="alert">
          {error}
        </span>
      )}
    </div>
  );
}

type Outcome = { vehicle: string; note: string | null; error: string | null };

/** The vehicle's link thresholds and recorded comms-lost configuration (reported over JAUS as 0x4C03). Keyed by
 * vehicle and configuration, so a new configuration from the console starts a fresh draft. */
function LinkConfigForm({
  target,
  config,
  canEdit,
  token,
  outcome,
  setOutcome,
}: {
  target: VehicleIdentity;
  config: LinkConfig;
  canEdit: boolean;
  token: string | null;
  outcome: Outcome | null;
  setOutcome: (o: Outcome) => void;
}) {
  const [draft, setDraft] = useState<LinkConfig>(config);
  const shown = outcome?.vehicle === target.id ? outcome : null;
  const note = shown?.note ?? null;
  const error = shown?.error ?? null;
  const num = (k: "commsLostTimeout" | "regainedTime" | "regainedBehavior") => (e: ChangeEvent<HTMLInputElement>) =>
    setDraft({ ...draft, [k]: e.target.value === "" ? Number.NaN : Number(e.target.value) });
  const save = async () => {
    try {
      await setLinkConfig(target.id, draft, token);
      setOutcome({ vehicle: target.id, note: `Saved for ${vehicleLabel(target)}.`, error: null });
    } catch (e) {
      const why = problemText(e);
      setOutcome({ vehicle: target.id, note: null, error: `Link configuration of ${vehicleLabel(target)}: ${why}` });
    }
  };
  return (
    <form
      className="link-config"
      aria-label={`Link configuration of ${vehicleLabel(target)}`}
      onSubmit={(e) => (e.preventDefault(), void save())}
    >
      <label>
        Comms-lost timeout (s){" "}
        <input
          type="number"
          min={0.1}
          step={0.1}
          value={Number.isNaN(draft.commsLostTimeout) ? "" : draft.commsLostTimeout}
          onChange={num("commsLostTimeout")}
          disabled={!canEdit}
        />
      </label>
      <label>
        Regained time (s){" "}
        <input
          type="number"
          min={0}
          step={0.1}
          value={Number.isNaN(draft.regainedTime) ? "" : draft.regainedTime}
          onChange={num("regainedTime")}
          disabled={!canEdit}
        />
      </label>
      <label>
        On comms lost{" "}
        <select
          value={draft.policy}
          onChange={(e) => setDraft({ ...draft, policy: e.target.value as LinkConfig["policy"] })}
          disabled={!canEdit}
        >
          <option value="STOP_MISSION">stop mission</option>
          <option value="CONTINUE_MISSION">continue mission</option>
        </select>
      </label>
      <label title="JAUS CommsRegainedBehavior (0 to 255): what the vehicle does when its link comes back, as its own code; recorded and reported, the console enforces nothing">
        Behaviour code when the link comes back{" "}
        <input
          type="number"
          min={0}
          max={255}
          step={1}
          value={Number.isNaN(draft.regainedBehavior) ? "" : draft.regainedBehavior}
          onChange={num("regainedBehavior")}
          disabled={!canEdit}
        />
      </label>
      <button type="submit" disabled={!canEdit} title={`Save the link configuration of ${vehicleLabel(target)}`}>
        Save
      </button>
      {note && (
        <span className="muted" role="status">
          {note}
        </span>
      )}
      {error && (
        <span className="error" role="alert" data-testid="link-config-error">
          {error}
        </span>
      )}
    </form>
  );
}

export function GatewaysPanel() {
  const gateways = useGateways();
  const selected = useSelector((s) => s.selected);
  const known = useSelectedVehicle();
  const authRequired = useSelector((s) => s.authRequired);
  const token = useToken();
  const mayWrite = useCapabilities().command; // a replay is read-only
  const [outcome, setOutcome] = useState<Outcome | null>(null);
  const target: VehicleIdentity | null = selected ? { id: selected, name: known?.name ?? null } : null;
  const aspnOn = gateways.some((g) => g.name === "aspn" && g.enabled);
  return (
    <Panel title="Gateways" testId="gateways-panel">
      {gateways.map((g) => (
        <GatewayRow key={g.name} g={g} />
      ))}
      {target && known ? (
        <div className="gateway-vehicle">
          <p>
            <VehicleTag v={target} /> JAUS id <strong data-testid="jaus-id">{known.jausId ?? "— (JAUS off)"}</strong>
          </p>
          <RecordAspn target={target} enabled={aspnOn} token={token} />
          {known.linkConfig && (
            <LinkConfigForm
              key={`${target.id} ${JSON.stringify(known.linkConfig)}`}
              target={target}
              config={known.linkConfig}
              canEdit={mayWrite && (!authRequired || !!token)}
              token={token}
              outcome={outcome}
              setOutcome={setOutcome}
            />
          )}
        </div>
      ) : (
        <p className="muted">Select a vehicle to record its ASPN log or set its link thresholds.</p>
      )}
    </Panel>
  );
}
