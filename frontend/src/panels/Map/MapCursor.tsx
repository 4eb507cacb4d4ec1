import { useSyncExternalStore } from "react";
import { positionText, type LonLat } from "../../lib/geo";

/** The pointer's position over the map, outside React state: a mouse move re-renders only the readout
 * (MapCursor), not the panel with its marks and sources. */
export class CursorStore {
  private at: LonLat | null = null;
  private listeners = new Set<() => void>();
  get = (): LonLat | null => this.at;
  set(at: LonLat | null): void {
    this.at = at;
    for (const l of this.listeners) l();
  }
  subscribe = (l: () => void): (() => void) => {
    this.listeners.add(l);
    return () => this.listeners.delete(l);
  };
}

/** The pointer's position while it is over the map; nothing while it is not (a dash there read as a position not
 * known). */
export function MapCursor({ cursor, useDms }: { cursor: CursorStore; useDms: boolean }) {
  const at = useSyncExternalStore(cursor.subscribe, cursor.get);
  return at ? <span data-testid="map-cursor">{positionText(at.lat, at.lon, useDms)}</span> : null;
}
