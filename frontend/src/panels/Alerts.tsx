import { Panel } from "../components/Panel";
import { useAlerts, useStore } from "../data/hooks";
import { dismiss } from "../data/store";
import { utc } from "../lib/units";

export function AlertsPanel() {
  const alerts = useAlerts();
  const store = useStore();
  const active = alerts.filter((a) => !a.dismissed);
  return (
    <Panel
      title={`Alerts${active.length ? ` (${active.length})` : ""}`}
      testId="alerts-panel"
      actions={
        active.length > 0 && (
          <button className="small" onClick={() => store.update((s) => dismiss(s, "all"))}>
            Dismiss all
          </button>
        )
      }
    >
      {active.length === 0 ? (
        <p className="muted">No active alerts.</p>
      ) : (
        <ul className="alerts" aria-label="Active alerts">
          {active.map((a) => (
            <li key={a.id} className={`alert ${a.severity}`} data-testid="alert" data-kind={a.kind}>
              <span className="a-time">{utc(a.at, false).slice(0, 8)} UTC</span>
              <span className="a-text">{a.text}</span>
              <button className="small" aria-label={`Dismiss: ${a.text}`} onClick={() => store.update((s) => dismiss(s, a.id))}>
                ✕
              </button>
            </li>
          ))}
        </ul>
      )}
    </Panel>
  );
}
