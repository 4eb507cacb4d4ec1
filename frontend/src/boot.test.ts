import { readFileSync } from "node:fs";
import { dirname, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { describe, expect, it } from "vitest";

const SRC = dirname(fileURLToPath(import.meta.url));

/** The modules a file imports statically (not `import type`, not `import()`), as written. */
function staticImports(file: string): string[] {
  const text = readFileSync(file, "utf8");
  return [...text.matchAll(/^(?:import|export)\s+(?!type\b)(?:[^;]*?\sfrom\s+)?"([^"]+)";/gms)].map((m) => m[1]);
}

/** Every module boot.ts's chunk holds: its static imports, followed through the project's own files. */
function bootGraph(): Set<string> {
  const seen = new Set<string>();
  const todo = [resolve(SRC, "boot.ts")];
  for (let file = todo.pop(); file; file = todo.pop()) {
    if (seen.has(file)) continue;
    seen.add(file);
    if (!/\.tsx?$/.test(file)) continue;
    for (const spec of staticImports(file)) {
      if (!spec.startsWith(".")) seen.add(spec);
      else if (!spec.endsWith(".css")) todo.push(resolve(dirname(file), spec) + (/\.tsx?$/.test(spec) ? "" : ".ts"));
    }
  }
  return seen;
}

describe("the page's entry (boot.ts)", () => {
  it("holds neither React nor the panels nor MapLibre: its requests leave before the dashboard's code has loaded", () => {
    const graph = [...bootGraph()];
    expect(graph.some((m) => m.endsWith("/data/early.ts"))).toBe(true);
    expect(graph.some((m) => m.endsWith("/lib/themeApply.ts"))).toBe(true);
    // no package but the REST client (openapi-fetch: no dependencies, 2 kB gzipped), the health check's
    expect(graph.filter((m) => !m.startsWith("/")).sort()).toEqual(["openapi-fetch"]);
    expect(graph.filter((m) => m.endsWith(".tsx") || m.includes("/panels/"))).toEqual([]);
  });
});
