import { StrictMode } from "react";
import { createRoot } from "react-dom/client";
import { App } from "./App";
import { Connection, Store, defaultUrl } from "./data/connection";
import { DataContext } from "./data/hooks";
import "./styles.css";

const store = new Store();
const connection = new Connection(defaultUrl(), store);
connection.start();

createRoot(document.getElementById("root")!).render(
  <StrictMode>
    <DataContext.Provider value={{ store, connection }}>
      <App />
    </DataContext.Provider>
  </StrictMode>,
);
