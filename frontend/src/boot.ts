// The page's entry: the first screen's requests leave at once (early.ts), then the dashboard's code (main.tsx,
// with React, MapLibre and the panels) is loaded while the console answers.
import { startEarly } from "./data/early";
import "./lib/theme"; // the theme is set before the first paint (the style sheet is in the page's head)
import "./styles.css";

void startEarly();
void import("./main");
