// Planned silences ("out of comms until"), in the alarm panel: the ones in force on this database's stations, each
// cancellable, and the form that declares one for the selected vehicle. During one the vehicle's loss raises no
// alarm; still not heard at its end (and the console's grace after it), the console raises one.
import { useState } from "react";
import { ApiError, cancelSilence, planSilence } from "../../api/rest";
import { useData, useSelectedVehicle, useSilences, useVehicleNames } from "../../data/hooks";
import { vehicleLabel } from "../../lib/vehicle";
import { plannedEntry } from "../../lib/labels";
import { clockTime, nextUtc } from "../../lib/units";

/** What the time field says of a time it cannot take. */
export const BAD_UNTIL = "Until: write a UTC time of day as HH:MM, 24-hour (14:20)";

function said(e: unknown): string {
  return e instanceof ApiError && e.status ? e.message : "console unreachable";
}

export function PlannedSilences({ mayAct, token }: { mayAct: boolean; token: string | null }) {
  const silences = useSilences();
  const { source } = useData();
  const vehicle = useSelectedVehicle();
  const names = useVehicleNames();
  const labelOf = (id: string) => vehicleLabel({ id, name: names.get(id) || null }); // named as everywhere on the page
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
  const name = vehicle ? vehicleLabel(vehicle) : null;
  const current = vehicle ? (silences.find((x) => x.providerId === vehicle.id) ?? null) : null; // one in force: change or end it

  return (
    <section className="alarm-silences" aria-label="Planned silences" data-testid="planned-silences">
      <h3 className="alarm-subtitle">Planned silences</h3>
      {silences.length > 0 && (
        <ul className="alarm-list" aria-label="Planned silences">
          {silences.map((x) => (
            <li key={x.id} className="alarm-entry" data-testid="planned-silence">
              <span className="alarm-text">{plannedEntry(labelOf(x.providerId), x.until, x.reason, x.by, x.station)}</span>
              {mayAct && (
                <button
                  className="small"
                  aria-disabled={busy || undefined}
                  onClick={() => void run(() => cancelSilence(x.providerId, token), "Not cancelled")}
                  aria-label={`Cancel silence: ${labelOf(x.providerId)}`}
                >
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
            noValidate
            onSubmit={(e) => {
              e.preventDefault();
              if (busy) return;
              const t = nextUtc(until, source.consoleNow()); // the next such time on the console's clock, which ends it
              if (t === null) return setError(BAD_UNTIL);
              if (!reason.trim()) return setError("Why: say why it will be out of comms");
              void run(() => planSilence(vehicle.id, t, reason.trim(), token), current ? "End not changed" : "Not declared");
            }}
          >
            <span className="alarm-text" data-testid="silence-form-title">
              {current ? `${name}: planned silence until ${clockTime(current.until)}` : `Out of comms until: ${name}`}
            </span>
            <label>
              {current ? "New end (UTC)" : "Until (UTC)"}
              <input
                type="text"
                inputMode="numeric"
                placeholder="HH:MM"
                pattern="([01][0-9]|2[0-3]):[0-5][0-9]"
                maxLength={5}
                size={5}
                value={until}
                onChange={(e) => setUntil(e.target.value)}
                required
              />
            </label>
            <label>
              Why (diving, over the horizon, a relay down)
              <input value={reason} onChange={(e) => setReason(e.target.value)} maxLength={200} required />
            </label>
            <button className="small" type="submit" aria-disabled={busy || undefined}>
              {current ? "Change end" : "Declare planned silence"}
            </button>
            {current && (
              <button
                className="small"
                type="button"
                aria-disabled={busy || undefined}
                onClick={() => void run(() => cancelSilence(vehicle.id, token), "Not ended")}
              >
                End silence now
              </button>
            )}
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
