import { QueryClientProvider } from "@tanstack/react-query";
import { StrictMode } from "react";
import { createRoot } from "react-dom/client";
import { App } from "./App";
import { getToken, onTokenChange, wsProtocols } from "./data/auth";
import { Connection, defaultUrl } from "./data/connection";
import { startEarly } from "./data/early";
import { DataProvider } from "./data/provider";
import { healthQuery, makeQueryClient } from "./data/queries";
import { ReplaySource } from "./data/replay";
import type { DataSource } from "./data/source";
import { urlWithVehicle, vehicleFromUrl } from "./lib/vehicle";
import { countRender, countingRenders } from "./lib/renders";
import { TOPICS } from "./api/types";
import { selectedTopic } from "./data/slices/vehicles";
import { Inbox, createStateStore, update } from "./data/store";
import "./styles.css";

// The selection lives in the address (?vehicle=<id>): a link or a reload opens the same vehicle.
const store = createStateStore(vehicleFromUrl(window.location.search));
store.subscribe(
  (s) => s.selected,
  (selected) => window.history.replaceState(window.history.state, "", urlWithVehicle(window.location.href, selected)),
);
const inbox = new Inbox(store); // the data source's messages, applied to the store once a frame

// with ?renders (bench/browser.py): how often each topic of the selected vehicle changed, beside the renders
if (countingRenders) for (const t of TOPICS) store.subscribe(selectedTopic(t), () => countRender(`selected:${t}`));

// REST loading and caching (TanStack Query); the WebSocket is the live source (the store)
const queryClient = makeQueryClient();

const root = createRoot(document.getElementById("root")!);
root.render(
  <p className="starting" data-testid="connection-state" role="status">
    Connecting…
  </p>,
);

// Before anything else the console says whether reads need a token (with --auth-reads /ws refuses a client
// without one) and whether it replays a recording: that decides the data source. boot.ts asked as the page
// loaded, and opened the WebSocket the source takes over.
async function start(): Promise<void> {
  const h = await startEarly();
  update(store, (s) => ({ ...s, authRequired: h.authRequired, readAuthRequired: h.readAuthRequired }));
  queryClient.setQueryData(healthQuery().queryKey, h); // the panels that read it need not ask again
  const source: DataSource = h.replay
    ? new ReplaySource(defaultUrl(), inbox, () => wsProtocols())
    : new Connection(defaultUrl(), inbox, () => wsProtocols());
  inbox.clock = source.now;
  const mayConnect = () => !store.getState().readAuthRequired || getToken() !== null;
  onTokenChange(() => (mayConnect() ? source.restart() : source.stop()));
  root.render(
    <StrictMode>
      <QueryClientProvider client={queryClient}>
        <DataProvider store={store} source={source}>
          <App />
        </DataProvider>
      </QueryClientProvider>
    </StrictMode>,
  );
  if (mayConnect())
    source.start(); // with the messages boot.ts's socket held: the first render has the snapshot
  else source.stop(); // "Not signed in" until the operator signs in
}
void start();
