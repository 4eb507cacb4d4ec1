// Component tests' rendering: a panel inside the providers the page gives it (main.tsx), on a TestSource's store.
import { QueryClientProvider } from "@tanstack/react-query";
import { render, type RenderResult } from "@testing-library/react";
import type { ReactNode } from "react";
import { DataProvider } from "../data/provider";
import { healthQuery, makeQueryClient } from "../data/queries";
import type { TestSource } from "../data/testing";
import type { Health } from "../api/rest";

const HEALTH: Partial<Health> = { authRequired: false, readAuthRequired: false, replay: false, basemap: false };

/** `ui` rendered on `source`'s store, GET /api/health answered as a console without auth or chart. */
export function renderWith(source: TestSource, ui: ReactNode): RenderResult {
  const queries = makeQueryClient();
  queries.setQueryData(healthQuery().queryKey, HEALTH as Health);
  return render(
    <QueryClientProvider client={queries}>
      <DataProvider store={source.store} source={source}>
        {ui}
      </DataProvider>
    </QueryClientProvider>,
  );
}
