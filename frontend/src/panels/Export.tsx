import { useState, type MouseEvent } from "react";
import { download } from "../api/rest";
import { Panel } from "../components/Panel";
import { VehicleTag } from "../components/VehicleTag";
import { useToken } from "../data/auth";
import { useNow, useSelector } from "../data/hooks";
import { exportName, exportUrl, rangeQuery, type ExportKind, type ExportRange } from "../lib/exports";

const CHOICES: { value: string; label: string; range: ExportRange | null }[] = [
  { value: "1", label: "Last hour", range: { kind: "last", hours: 1 } },
  { value: "6", label: "Last 6 hours", range: { kind: "last", hours: 6 } },
  { value: "24", label: "Last 24 hours", range: { kind: "last", hours: 24 } },
  { value: "all", label: "Everything kept", range: { kind: "all" } },
  { value: "between", label: "Between… (UTC)", range: null },
];

/** Downloads of a vehicle's track (GPX, CSV) and the command history (CSV) over a chosen time range. */
export function ExportPanel() {
  const selected = useSelector((s) => s.selected);
  const name = useSelector((s) => (s.selected ? (s.providers[s.selected]?.name ?? null) : null));
  const readAuthRequired = useSelector((s) => s.readAuthRequired);
  const token = useToken();
  const now = useNow(30_000);
  const [choice, setChoice] = useState("1");
  const [since, setSince] = useState("");
  const [until, setUntil] = useState("");
  const [error, setError] = useState<string | null>(null);

  const range: ExportRange = CHOICES.find((c) => c.value === choice)?.range ?? { kind: "between", since, until };
  const checked = rangeQuery(range, now * 1000);
  const rangeError = "error" in checked ? checked.error : null;

  // The URL is built when clicked, so "last hour" ends now; with --auth-reads the file is fetched with the token.
  const fetchOnClick = (kind: ExportKind, providerId: string | null) => (e: MouseEvent<HTMLAnchorElement>) => {
    const q = rangeQuery(range, Date.now());
    if ("error" in q) {
      e.preventDefault();
      return;
    }
    const url = exportUrl(kind, providerId, q);
    setError(null);
    if (!readAuthRequired) {
      e.currentTarget.href = url;
      return;
    }
    e.preventDefault();
    download(url, token)
      .then((blob) => {
        const a = document.createElement("a");
        a.href = URL.createObjectURL(blob);
        a.download = exportName(kind, providerId);
        a.click();
        setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
      })
      .catch((err: unknown) => setError(`Export failed: ${String(err)}`));
  };
  const link = (kind: ExportKind, providerId: string | null, label: string, testId: string) => {
    const q = "error" in checked ? {} : checked;
    return (
      <a className={`button small${rangeError ? " disabled" : ""}`} href={exportUrl(kind, providerId, q)} download={exportName(kind, providerId)}
        onClick={fetchOnClick(kind, providerId)} aria-disabled={!!rangeError} data-testid={testId}>
        {label}
      </a>
    );
  };

  return (
    <Panel title="History and export" testId="export-panel">
      <div className="export-range">
        <label>
          Range{" "}
          <select value={choice} onChange={(e) => setChoice(e.target.value)} aria-label="Export range">
            {CHOICES.map((c) => (
              <option key={c.value} value={c.value}>
                {c.label}
              </option>
            ))}
          </select>
        </label>
        {choice === "between" && (
          <>
            <label>
              From <input type="datetime-local" value={since} onChange={(e) => setSince(e.target.value)} aria-label="From (UTC)" />
            </label>
            <label>
              To <input type="datetime-local" value={until} onChange={(e) => setUntil(e.target.value)} aria-label="To (UTC)" />
            </label>
          </>
        )}
      </div>
      {rangeError && <p className="error" role="alert">{rangeError}</p>}
      {selected ? (
        <div className="export-links" role="group" aria-label="Exports of the selected vehicle">
          <VehicleTag v={{ id: selected, name }} />
          {link("gpx", selected, "Track GPX", "export-gpx")}
          {link("csv", selected, "Track CSV", "export-csv")}
          {link("commands", selected, "Commands CSV", "export-commands")}
        </div>
      ) : (
        <p className="muted">Select a vehicle to export its track.</p>
      )}
      <div className="export-links">
        <span className="muted">Every vehicle:</span>
        {link("commands", null, "Commands CSV", "export-commands-all")}
      </div>
      {error && <p className="error" role="alert">{error}</p>}
      <p className="muted small-note">Times are UTC. The console keeps each vehicle's track and chart data for its track retention.</p>
    </Panel>
  );
}
