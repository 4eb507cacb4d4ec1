// The data layer's provider: the store and source to every component, and the loading that follows the selection
// whatever panels are shown or folded.
import type { ReactNode } from "react";
import { DataContext, type DataContextValue } from "./hooks";
import { useSelectedDetailLoaded } from "./loaders";

/** `children` on `store` and `source`, the selected vehicle's detail loaded when the WebSocket gave it in part. */
export function DataProvider({ store, source, children }: DataContextValue & { children: ReactNode }) {
  return (
    <DataContext.Provider value={{ store, source }}>
      <SelectedDetailLoaded />
      {children}
    </DataContext.Provider>
  );
}

function SelectedDetailLoaded(): null {
  useSelectedDetailLoaded();
  return null;
}
