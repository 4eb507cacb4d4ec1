import react from "@vitejs/plugin-react";
import type { Plugin } from "vite";
import { defineConfig } from "vitest/config";

/** The chunks the entry (boot.ts) imports at once, named in the page's head so that they are fetched with the entry,
 * not a round trip after it has run (`modulepreload`, and a non-blocking `preload` of their style sheets): a console
 * busy with 50 vehicles took 25-100 ms an answer, and the first screen waited for the two in a row. */
function preloadEntryChunks(names: string[]): Plugin {
  let base = "/";
  return {
    name: "sem-preload-entry-chunks",
    apply: "build",
    configResolved(config) {
      base = config.base;
    },
    transformIndexHtml: {
      order: "post",
      handler(_html, ctx) {
        const tags = [];
        for (const chunk of Object.values(ctx.bundle ?? {})) {
          if (chunk.type !== "chunk" || chunk.isEntry || !names.includes(chunk.name)) continue;
          tags.push({
            tag: "link",
            attrs: { rel: "modulepreload", crossorigin: true, href: base + chunk.fileName },
            injectTo: "head" as const,
          });
          for (const css of chunk.viteMetadata?.importedCss ?? [])
            // crossorigin as Vite's loader asks the sheet (crossOrigin ""): a preload of another mode is not used
            tags.push({
              tag: "link",
              attrs: { rel: "preload", as: "style", crossorigin: true, href: base + css },
              injectTo: "head" as const,
            });
        }
        return tags;
      },
    },
  };
}

// `npm run dev` serves on :5173 and proxies the API and WebSocket to a console on :8000.
const backend = process.env.SEM_BACKEND ?? "http://127.0.0.1:8000";

export default defineConfig({
  plugins: [react(), preloadEntryChunks(["main", "mapWorker"])],
  server: {
    proxy: {
      "/api": backend,
      "/openapi.json": backend,
      "/ws": { target: backend.replace(/^http/, "ws"), ws: true },
    },
  },
  build: { outDir: "dist", sourcemap: true },
  // testTimeout: a bound for a loaded machine (the units run beside pytest and Playwright), not a timed check; a jsdom
  // test file's first test, its imports included, took 5.8 s against Vitest's default 5 s in a clean-clone run.
  // isolate: false: the test files share their workers' module graph and jsdom (each file's own environment comment still
  // holds), and every test cleans up after itself (setup.ts); measured, 8 CPU-s for the units against 42 with a fresh
  // worker per file, and they pass in any order (`--sequence.shuffle`)
  test: {
    environment: "node",
    isolate: false,
    include: ["src/**/*.test.ts", "src/**/*.test.tsx"],
    setupFiles: ["src/panels/setup.ts"],
    testTimeout: 30_000,
  },
});
