// Satellite identity: the simulator's (documented) satelliteId convention, and constellation styling.
import type { GPSConstellationEnumType, GPSSatelliteType } from "../api/types";

// bytes 0..13 of uuid5(NAMESPACE_URL, "urn:sem-console:gnss-satellite"); byte 14 = constellation ordinal, 15 = PRN
export const SAT_PREFIX = "ca5d35fbbcc25b9ab20cdf56b7b9";
export const CONSTELLATIONS: readonly GPSConstellationEnumType[] = [
  "UNKNOWN",
  "BEIDOU",
  "GALILEO",
  "GLONASS",
  "GPS",
  "IRNSS",
  "QZSS",
  "SBAS",
];
export const LETTER: Record<GPSConstellationEnumType, string> = {
  GPS: "G",
  GALILEO: "E",
  GLONASS: "R",
  BEIDOU: "C",
  SBAS: "S",
  QZSS: "J",
  IRNSS: "I",
  UNKNOWN: "U",
};
export const COLOR: Record<GPSConstellationEnumType, string> = {
  GPS: "#4fc3f7",
  GALILEO: "#ffb74d",
  GLONASS: "#e57373",
  BEIDOU: "#ba68c8",
  SBAS: "#aed581",
  QZSS: "#f06292",
  IRNSS: "#fff176",
  UNKNOWN: "#90a4ae",
};
export type Shape = "circle" | "square" | "diamond" | "triangle";
export const SHAPE: Record<GPSConstellationEnumType, Shape> = {
  GPS: "circle",
  GALILEO: "square",
  GLONASS: "diamond",
  BEIDOU: "triangle",
  SBAS: "square",
  QZSS: "circle",
  IRNSS: "diamond",
  UNKNOWN: "circle",
};

const labels = new Map<string, string>(); // a few hundred satellites at most: each id's label made once

/** A short label: G12, E07, ... for the known convention, else the first 8 hex digits, or "?". Called for every
 * satellite of every vehicle's GPSReport (20,000 a second with 50 vehicles at 10 Hz): looked up, not made. */
export function satelliteLabel(id: string | null | undefined): string {
  if (!id) return "?";
  let label = labels.get(id);
  if (label === undefined) {
    if (labels.size >= 4096) labels.clear(); // ids that keep changing cannot grow it without bound
    label = makeLabel(id);
    labels.set(id, label);
  }
  return label;
}

function makeLabel(id: string): string {
  const hex = id.replace(/-/g, "").toLowerCase();
  if (hex.length === 32 && hex.startsWith(SAT_PREFIX)) {
    const constellation = CONSTELLATIONS[parseInt(hex.slice(28, 30), 16)];
    const prn = parseInt(hex.slice(30, 32), 16);
    if (constellation) return `${LETTER[constellation]}${String(prn).padStart(2, "0")}`;
  }
  return hex.slice(0, 8);
}

export function constellationOf(s: GPSSatelliteType): GPSConstellationEnumType {
  return s.constellationType ?? "UNKNOWN";
}
