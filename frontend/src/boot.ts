// The page's entry: the first screen's requests leave at once (early.ts), then the dashboard's code is loaded
// while the console answers, in two chunks fetched together: MapLibre, whose worker starts as soon as it has run
// (mapWorker.ts), and React with the panels (main.tsx).
import { startEarly } from "./data/early";
import "./lib/themeApply"; // the theme is set before the first paint (the style sheet is in the page's head)
import "./styles.css";

void startEarly();
void import("./lib/mapWorker");
void import("./main");
