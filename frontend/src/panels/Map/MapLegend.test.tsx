// @vitest-environment jsdom
import { act, cleanup, render, screen } from "@testing-library/react";
import type { FeatureCollection } from "geojson";
import { afterEach, describe, expect, it } from "vitest";
import { CursorStore, MapCursor } from "./MapCursor";
import { MapLegend } from "./MapLegend";

const AREAS = "areas: Covered (green), Partly covered (amber), Not covered (red)"; // the CoMap panel's words
const square: FeatureCollection = {
  type: "FeatureCollection",
  features: [
    {
      type: "Feature",
      geometry: {
        type: "Polygon",
        coordinates: [
          [
            [10, 59],
            [10.1, 59],
            [10.1, 59.1],
            [10, 59],
          ],
        ],
      },
      properties: { featureId: 1, coverage: "PARTIAL" },
    },
  ],
};

describe("MapLegend", () => {
  afterEach(cleanup);

  it("explains the areas' colours only when the map draws an area", () => {
    render(<MapLegend model={{ type: "FeatureCollection", features: [] }} />); // CoMap off: an empty world model
    expect(screen.getByTestId("map-legend").textContent).not.toContain(AREAS);
    cleanup();
    render(<MapLegend model={null} />);
    expect(screen.getByTestId("map-legend").textContent).not.toContain(AREAS);
    cleanup();
    render(<MapLegend model={square} />);
    expect(screen.getByTestId("map-legend").textContent).toContain(AREAS);
  });
});

describe("MapCursor", () => {
  afterEach(cleanup);

  it("shows the pointer's position while it is over the map, and nothing (no bare dash) while it is not", () => {
    const cursor = new CursorStore();
    const { container } = render(
      <div>
        <MapCursor cursor={cursor} useDms={false} />
      </div>,
    );
    expect(container.textContent).toBe("");
    act(() => cursor.set({ lon: 10.5, lat: 59.25 }));
    expect(screen.getByTestId("map-cursor").textContent).toBe("59.250000° N, 10.500000° E");
    act(() => cursor.set(null));
    expect(screen.queryByTestId("map-cursor")).toBeNull();
    expect(container.textContent).toBe("");
  });
});
