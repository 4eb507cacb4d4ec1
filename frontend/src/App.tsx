import { ArrangeableGroup } from "./components/Arrange";
import { ErrorBoundary } from "./components/ErrorBoundary";
import { AlertsPanel } from "./panels/Alerts";
import { CommandsPanel } from "./panels/Commands";
import { ExportPanel } from "./panels/Export";
import { FixPanel } from "./panels/Fix";
import { GatewaysPanel } from "./panels/Gateways";
import { Header } from "./panels/Header";
import { InsPanel } from "./panels/Ins";
import { MapPanel } from "./panels/Map";
import { ReplayBar } from "./panels/Replay";
import { SatellitesPanel } from "./panels/Satellites";
import { VehicleSelector } from "./panels/VehicleSelector";

// The panels of each group by test id, in their default order (the operator's order is kept in the
// settings). A wide panel takes the whole width of the main area; the others share it two to a row.
const SIDE = { "alerts-panel": { node: <AlertsPanel /> }, "gateways-panel": { node: <GatewaysPanel /> } };
const MAIN = {
  "map-panel": { node: <MapPanel />, wide: true },
  "fix-panel": { node: <FixPanel /> },
  "ins-panel": { node: <InsPanel /> },
  "satellites-panel": { node: <SatellitesPanel />, wide: true },
  "export-panel": { node: <ExportPanel /> },
  "commands-panel": { node: <CommandsPanel /> },
};

export function App() {
  return (
    <div className="app">
      <Header />
      <ReplayBar />
      <div className="layout">
        <aside className="side">
          <ErrorBoundary name="Vehicles">
            <VehicleSelector />
          </ErrorBoundary>
          <ArrangeableGroup group="side" panels={SIDE} className="side-panels" testId="side-panels" label="Side panels" />
        </aside>
        <main className="main">
          <ArrangeableGroup group="main" panels={MAIN} className="main-panels" testId="main-panels" label="Main panels" />
        </main>
      </div>
    </div>
  );
}
