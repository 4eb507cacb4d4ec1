import { StrictMode } from "react";
import { createRoot } from "react-dom/client";
import { App } from "./App";
import { health } from "./api/rest";
import { getToken, onTokenChange, wsProtocols } from "./data/auth";
import { Connection, Store, defaultUrl } from "./data/connection";
import { DataContext } from "./data/hooks";
import { urlWithVehicle, vehicleFromUrl } from "./lib/vehicle";
import "./styles.css";

// The selection lives in the address (?vehicle=<id>): a link or a reload opens the same vehicle.
const store = new Store(vehicleFromUrl(window.location.search));
let shown = store.getState().selected;
store.subscribe(() => {
  const selected = store.getState().selected;
  if (selected === shown) return;
  shown = selected;
  window.history.replaceState(window.history.state, "", urlWithVehicle(window.location.href, selected));
});

const connection = new Connection(defaultUrl(), store, () => wsProtocols());
const mayConnect = () => !store.getState().readAuthRequired || getToken() !== null;
onTokenChange(() => (mayConnect() ? connection.restart() : connection.stop()));

// Whether reads need a token is known before the first connect (with --auth-reads /ws refuses a client without one).
async function start(): Promise<void> {
  for (;;) {
    try {
      const h = await health();
      store.update((s) => ({ ...s, authRequired: h.authRequired, readAuthRequired: h.readAuthRequired }));
      break;
    } catch {
      await new Promise((r) => setTimeout(r, 2000)); // the console is not up yet
    }
  }
  if (mayConnect()) connection.start();
  else connection.stop(); // "Not signed in" until the operator signs in
}
void start();

createRoot(document.getElementById("root")!).render(
  <StrictMode>
    <DataContext.Provider value={{ store, connection }}>
      <App />
    </DataContext.Provider>
  </StrictMode>,
);
