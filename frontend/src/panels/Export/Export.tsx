import { useState, type MouseEvent } from "react";
import { download, problemText } from "../../api/rest";
import { Panel } from "../../components/Panel";
import { VehicleTag } from "../../components/VehicleTag";
import { useToken } from "../../data/auth";
import { useConsoleNow, useData, useSelector } from "../../data/hooks";
import { exportFileName, exportUrl, rangeQuery, type ExportKind, type ExportRange } from "../../lib/exports";

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
  const token = useToken();
  const { source } = useData();
  const now = useConsoleNow(30_000);
  const [choice, setChoice] = useState("1");
  const [since, setSince] = useState("");
  const [until, setUntil] = useState("");
  const [error, setError] = useState<string | null>(null);

  const range: ExportRange = CHOICES.find((c) => c.value === choice)?.range ?? { kind: "between", since, until };
  const checked = rangeQuery(range, now * 1000);
  const rangeError = "error" in checked ? checked.error : null;

  const vehicle = selected ? { id: selected, name } : null;

  // The URL is built when clicked, so "last hour" ends now: on the console's clock, which stamped the history (a
  // replay's is the recording's instant shown, as the link's own address says), not the browser's. The file is fetched
  // here (with the token under --auth-reads) and saved under a name that says whose and when (the console's own names
  // carry the GUID).
  const fetchOnClick =
    (kind: ExportKind, who: { id: string; name: string | null } | null) => (e: MouseEvent<HTMLAnchorElement>) => {
      e.preventDefault();
      const clicked = source.consoleNow() * 1000;
      const q = rangeQuery(range, clicked);
      if ("error" in q) return;
      const url = exportUrl(kind, who?.id ?? null, q);
      const filename = exportFileName(kind, who, clicked);
      setError(null);
      download(url, token)
        .then((blob) => {
          const a = document.createElement("a");
          a.href = URL.createObjectURL(blob);
          a.download = filename;
          a.click();
          setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
        })
        .catch((err: unknown) => setError(`Export of ${filename} failed: ${problemText(err)}`));
    };
  const link = (kind: ExportKind, who: { id: string; name: string | null } | null, label: string, testId: string) => {
    const q = "error" in checked ? {} : checked;
    return (
      <a
        className={`button small${rangeError ? " disabled" : ""}`}
        href={exportUrl(kind, who?.id ?? null, q)}
        download={exportFileName(kind, who, now * 1000)}
        onClick={fetchOnClick(kind, who)}
        aria-disabled={!!rangeError}
        data-testid={testId}
      >
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
              From{" "}
              <input
                type="text"
                placeholder="YYYY-MM-DD HH:MM"
                title="a 24-hour UTC date and time"
                maxLength={19}
                size={16}
                value={since}
                onChange={(e) => setSince(e.target.value)}
                aria-label="From (UTC)"
              />
            </label>
            <label>
              To{" "}
              <input
                type="text"
                placeholder="YYYY-MM-DD HH:MM"
                title="a 24-hour UTC date and time"
                maxLength={19}
                size={16}
                value={until}
                onChange={(e) => setUntil(e.target.value)}
                aria-label="To (UTC)"
              />
            </label>
          </>
        )}
      </div>
      {rangeError && (
        <p className="error" role="alert">
          {rangeError}
        </p>
      )}
      {vehicle ? (
        <div className="export-links" role="group" aria-label="Exports of the selected vehicle">
          <VehicleTag v={vehicle} />
          {link("gpx", vehicle, "Track GPX", "export-gpx")}
          {link("csv", vehicle, "Track CSV", "export-csv")}
          {link("commands", vehicle, "Commands CSV", "export-commands")}
        </div>
      ) : (
        <p className="muted">Select a vehicle to export its track.</p>
      )}
      <div className="export-links">
        <span className="muted">Every vehicle:</span>
        {link("commands", null, "Commands CSV", "export-commands-all")}
      </div>
      {error && (
        <p className="error" role="alert">
          {error}
        </p>
      )}
      <p className="muted small-note">
        Times are UTC. The console keeps each vehicle's track and chart data for its track retention.
      </p>
    </Panel>
  );
}
