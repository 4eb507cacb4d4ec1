import { useState } from "react";
import { problemText, setVehicleName } from "../../api/rest";
import { useToken } from "../../data/auth";
import { useCapabilities, useSelector } from "../../data/hooks";
import { vehicleLabel, type VehicleIdentity } from "../../lib/vehicle";

export const MAX_NAME = 40; // the console's limit (PUT /api/providers/{id}/name)

/** Rename the selected vehicle: the name is stored on the console and shared with the other consoles of its
 * database; an empty name goes back to the console's --vehicle-names one. Esc cancels. Keyed by the vehicle by
 * its parent, so another selection starts closed. */
export function RenameVehicle({ v }: { v: VehicleIdentity }) {
  const token = useToken();
  const authRequired = useSelector((s) => s.authRequired);
  const mayWrite = useCapabilities().command && (!authRequired || !!token); // a replay is read-only
  const [draft, setDraft] = useState<string | null>(null); // null: closed
  const [error, setError] = useState<string | null>(null);
  const [busy, setBusy] = useState(false);
  const close = () => (setDraft(null), setError(null));
  const save = async () => {
    if (draft === null) return;
    setBusy(true);
    try {
      await setVehicleName(v.id, draft, token);
      close(); // the WebSocket's `provider` message brings the new name to every page
    } catch (e) {
      setError(`Renaming ${vehicleLabel(v)}: ${problemText(e)}`);
    } finally {
      setBusy(false);
    }
  };
  if (draft === null) {
    return (
      <button
        type="button"
        className="rename"
        onClick={() => setDraft(v.name ?? "")}
        disabled={!mayWrite}
        title={mayWrite ? `Rename ${vehicleLabel(v)} on every console` : "Renaming needs an operator token (and a live console)"}
      >
        Rename
      </button>
    );
  }
  return (
    <form
      className="rename-form"
      aria-label={`Rename ${vehicleLabel(v)}`}
      onSubmit={(e) => (e.preventDefault(), void save())}
      onKeyDown={(e) => e.key === "Escape" && (e.preventDefault(), close())}
    >
      <label>
        Name{" "}
        <input
          value={draft}
          maxLength={MAX_NAME}
          autoFocus
          onChange={(e) => setDraft(e.target.value)}
          placeholder="empty: the configured name"
        />
      </label>
      <button type="submit" disabled={busy}>
        Save
      </button>
      <button type="button" onClick={close}>
        Cancel
      </button>
      {error && (
        <span className="error" role="alert" data-testid="rename-error">
          {error}
        </span>
      )}
    </form>
  );
}
