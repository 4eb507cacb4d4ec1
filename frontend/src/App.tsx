import { ArrangeableGroup } from "./components/Arrange";
import { ErrorBoundary } from "./components/ErrorBoundary";
import { AlarmsPanel } from "./panels/Alarms/Alarms";
import { CommandsPanel } from "./panels/Commands/Commands";
import { DatabaseBanner } from "./panels/DatabaseBanner/DatabaseBanner";
import { DdsDiagnostics } from "./panels/DdsDiagnostics/DdsDiagnostics";
import { ExportPanel } from "./panels/Export/Export";
import { FleetBar } from "./panels/FleetBar/FleetBar";
import { FixPanel } from "./panels/Fix/Fix";
import { GatewaysPanel } from "./panels/Gateways/Gateways";
import { Header } from "./panels/Header/Header";
import { InsPanel } from "./panels/Ins/Ins";
import { MapPanel } from "./panels/Map/Map";
import { ReplayBar } from "./panels/Replay/Replay";
import { SatellitesPanel } from "./panels/Satellites/Satellites";
import { VehicleSelector } from "./panels/VehicleSelector/VehicleSelector";
import { useEffect, useRef } from "react";
import "./lib/themeApply"; // the theme is set before the first paint

// The panels of each group by test id, in their default order (the operator's order is kept in the
// settings). On a wide screen the groups are columns: the side column, the selected vehicle's status
// with its commands (the INS panel, the command buttons right under it, then the GPS fix), and the
// map's. A wide panel takes the whole width of its column; the others share it two to a row.
const SIDE = { "alarms-panel": { node: <AlarmsPanel /> }, "gateways-panel": { node: <GatewaysPanel /> } };
const STATUS = {
  "ins-panel": { node: <InsPanel />, wide: true },
  "commands-panel": { node: <CommandsPanel />, wide: true },
  "fix-panel": { node: <FixPanel />, wide: true },
};
const MAIN = {
  "map-panel": { node: <MapPanel />, wide: true },
  "satellites-panel": { node: <SatellitesPanel />, wide: true },
  "export-panel": { node: <ExportPanel />, wide: true },
};

/** Keeps the height of the top bars (which grows with the fleet bar's rows) in `--top-bars`, the page's scroll
 * padding: a panel scrolled to, or an element reached with Tab, is shown below the bars rather than under them. */
function useTopBarsHeight() {
  const ref = useRef<HTMLDivElement>(null);
  useEffect(() => {
    const bars = ref.current;
    if (!bars) return;
    const observer = new ResizeObserver(() => document.documentElement.style.setProperty("--top-bars", `${bars.offsetHeight}px`));
    observer.observe(bars);
    return () => observer.disconnect();
  }, []);
  return ref;
}

export function App() {
  const topBars = useTopBarsHeight();
  return (
    <div className="app">
      {/* the header and the fleet bar stay at the top together, whatever is scrolled */}
      <div className="top-bars" ref={topBars}>
        <Header />
        <DatabaseBanner />
        <ErrorBoundary name="Fleet">
          <FleetBar />
        </ErrorBoundary>
        <ReplayBar />
      </div>
      <div className="layout">
        <main className="main">
          <ArrangeableGroup
            group="status"
            panels={STATUS}
            className="panels status-panels"
            testId="status-panels"
            label="Selected vehicle: status and commands"
          />
          <ArrangeableGroup
            group="main"
            panels={MAIN}
            className="panels main-panels"
            testId="main-panels"
            label="Map and satellites"
          />
        </main>
        <aside className="side" aria-label="Vehicles and alerts">
          <ErrorBoundary name="Vehicles">
            <VehicleSelector />
          </ErrorBoundary>
          <ErrorBoundary name="DDS diagnostics">
            <DdsDiagnostics />
          </ErrorBoundary>
          <ArrangeableGroup group="side" panels={SIDE} className="side-panels" testId="side-panels" label="Side panels" />
        </aside>
      </div>
    </div>
  );
}
