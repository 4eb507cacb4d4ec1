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
          <AlertsPanel />
          <GatewaysPanel />
        </aside>
        <main className="main">
          <MapPanel />
          <SatellitesPanel />
          <div className="column">
            <FixPanel />
            <InsPanel />
            <ExportPanel />
          </div>
          <CommandsPanel />
        </main>
      </div>
    </div>
  );
}
