// Planned silences ("out of comms until"), in the alarm panel: the ones in force on this database's stations, each
// cancellable, and the form that declares one for the selected vehicle. During one the vehicle's loss raises no
// alarm; still not heard at its end (and the console's grace after it), the console raises one.
import { useState } from "react";
import { ApiError, cancelSilence, planSilence } from "../api/rest";
import { useSelectedVehicle, useSilences } from "../data/hooks";
import { shortId } from "../lib/vehicle";
import { plannedEntry } from "../lib/labels";

/** The next UTC time of day `hhmm` ("14:20") after `now` (UTC seconds): today's, else tomorrow's. */
export function nextUtc(hhmm: string, now: number): number | null {
  const m = /^(\d{2}):(\d{2})$/.exec(hhmm);
  if (!m) return null;
  const day = Math.floor(now / 86400) * 86400;
  const t = day + Number(m[1]) * 3600 + Number(m[2]) * 60;
  return t > now ? t : t + 86400;
}

function said(e: unknown): string {
  return e instanceof ApiError && e.status ? e.message : "console unreachable";
}

export function PlannedSilences({ mayAct, token }: { mayAct: boolean; token: string | null }) {
  const silences = useSilences();
  const vehicle = useSelectedVehicle();
  const [until, setUntil] = useState("");
  const [reason, setReason] = useState("");
  const [error, setError] = useState("");
  const [busy, setBusy] = useState(false);

  const run = async (call: () => Promise<unknown>, what: string) => {
    if (busy) return;
    setBusy(true);
    try {
      await call();
      setError("");
      setReason("");
    } catch (e) {
      setError(`${what}: ${said(e)}`);
    }
    setBusy(false);
  };
  const name = vehicle ? (vehicle.name ?? shortId(vehicle.id)) : null;

  return (
    <section className="alarm-silences" aria-label="Planned silences" data-testid="planned-silences">
      <h3 className="alarm-subtitle">Planned silences</h3>
      {silences.length > 0 && (
        <ul className="alarm-list" aria-label="Planned silences">
          {silences.map((x) => (
            <li key={x.id} className="alarm-entry" data-testid="planned-silence">
              <span className="alarm-text">{plannedEntry(x.vehicle, x.until, x.reason, x.by, x.station)}</span>
              {mayAct && (
                <button className="small" aria-disabled={busy || undefined} onClick={() => void run(() => cancelSilence(x.providerId, token), "Not cancelled")} aria-label={`Cancel silence: ${x.vehicle}`}>
                  Cancel silence
                </button>
              )}
            </li>
          ))}
        </ul>
      )}
      {mayAct &&
        (vehicle && name ? (
          <form
            className="alarm-form"
            aria-label={`Out of comms until: ${name}`}
            onSubmit={(e) => {
              e.preventDefault();
              const t = nextUtc(until, Date.now() / 1000);
              if (t === null || !reason.trim() || busy) return;
              void run(() => planSilence(vehicle.id, t, reason.trim(), token), "Not declared");
            }}
          >
            <span className="alarm-text">
              Out of comms until: {name}
            </span>
            <label>
              Until (UTC)
              <input type="time" value={until} onChange={(e) => setUntil(e.target.value)} required />
            </label>
            <label>
              Why (diving, over the horizon, a relay down)
              <input value={reason} onChange={(e) => setReason(e.target.value)} maxLength={200} required />
            </label>
            <button className="small" type="submit" aria-disabled={busy || undefined}>
              Declare planned silence
            </button>
          </form>
        ) : (
          <p className="muted">Select a vehicle to declare its planned silence.</p>
        ))}
      {error && (
        <p className="error" role="alert">
          {error}
        </p>
      )}
    </section>
  );
}
