// MapLibre's worker, started as early as the page can: boot.ts loads this beside the dashboard's code, so the
// worker (a thread of its own, its 0.5 MB script fetched and compiled there) starts while React and the panels load
// and the snapshot arrives. Started from the map's first render, it waited for the main thread, busy with the first
// screen, and the map was ready 0.3-0.5 s after the panels' values.
import { prewarm, setWorkerUrl } from "maplibre-gl";
import workerUrl from "maplibre-gl/dist/maplibre-gl-worker.mjs?url";

// the worker is a file of the build, served by the console like the rest of the dashboard
setWorkerUrl(workerUrl);
prewarm();
