// A new client's first requests, sent as the page loads, before the dashboard's code (1.5 MB, two thirds of it
// MapLibre) has arrived and run: the health check and the WebSocket, whose snapshot is what the first screen
// draws. main.tsx's source takes the socket over (Connection.start) with the messages it held; before, both waited
// for the code, and the snapshot came 0.4-0.6 s after navigation. Nothing here may import React or the panels
// (boot.ts's chunk is its imports: this file, api/rest.ts, token.ts, settingStore.ts, themeApply.ts).
import { health, type Health } from "../api/rest";
import type { ClientMessage } from "../api/types";
import { readSetting, writeSetting } from "./settingStore";
import { getToken, wsProtocols } from "./token";
import { isVehicleId, vehicleFromUrl } from "../lib/vehicle";

/** The console's WebSocket, asking for its reports in batches under load (a browser pays about 0.13 ms of its main
 * thread per message whatever its size, 30 % of it with 250 vehicles sent one message per report), and acknowledging
 * the frames it takes (`ack`, sent by the source): the console then holds reports beyond a window of bytes, where
 * newer ones replace them, instead of queueing megabytes in the sockets behind which a new fix waited. An early
 * socket acknowledges nothing until its source takes it over: meanwhile the console holds the reports. */
export function defaultUrl(): string {
  const { protocol, host } = window.location;
  return `${protocol === "https:" ? "wss" : "ws"}://${host}/ws?batch=1&ack=1`;
}

/** The socket's URL naming the vehicle the page draws (`vehicle=`, none for no vehicle id): the console builds its
 * snapshot for it, that vehicle whole and every other as the brief the overviews draw (1,000 vehicles: 2.5 MB whole,
 * under 0.5 MB so). */
export function socketUrl(url: string, vehicle: string | null): string {
  if (!vehicle || !isVehicleId(vehicle)) return url;
  const u = new URL(url);
  u.searchParams.set("vehicle", vehicle);
  return u.toString();
}

/** A socket opened before its source existed, and the messages it received meanwhile (in order); `told`: the vehicle
 * it named to the console (`select`) once open, undefined before; `url`: the URL it was asked for, before its vehicle
 * (`socketUrl`). */
export interface EarlySocket {
  ws: WebSocket;
  url: string;
  protocols: string[];
  held: MessageEvent<string>[];
  told?: string | null;
  opened: number; // when it was asked for (ms on the page's clock): the console's snapshot on it was stamped after
}

/** The console's health; until it answers, asked again every 2 s (the console is not up yet). */
async function consoleHealth(): Promise<Health> {
  for (;;) {
    try {
      return await health();
    } catch {
      await new Promise((r) => setTimeout(r, 2000));
    }
  }
}

/** Reads need a token only with --auth-reads; without one the console refuses the socket. */
export function mayRead(h: Health): boolean {
  return !h.readAuthRequired || getToken() !== null;
}

let early: EarlySocket | null = null;
let healthAnswer: Promise<Health> | null = null;

const READ_AUTH_KEY = "sem-console.readAuthRequired"; // what the console's last health answer said of reads

/** Start the health check and the WebSocket (a replay's source reads the same socket) together: at once when this
 * browser last saw the console's reads open (or holds a token), else once the health answer allows. One after the
 * other, the socket waited for the health answer, 0.1-0.3 s of a new page when the console is busy. */
export function startEarly(): Promise<Health> {
  if (!healthAnswer) {
    const known = readSetting(READ_AUTH_KEY, false, (v): v is boolean => typeof v === "boolean");
    const vehicle = vehicleFromUrl(window.location.search); // the page's ?vehicle= link (none: null)
    const opened = !known || getToken() !== null ? openEarly(defaultUrl(), wsProtocols(), vehicle) : null;
    healthAnswer = consoleHealth().then((h) => {
      if (h.readAuthRequired !== known) writeSetting(READ_AUTH_KEY, h.readAuthRequired);
      if (!mayRead(h))
        opened?.ws.close(); // reads need a token it has not: the console refuses it anyway
      else if (!opened) openEarly(defaultUrl(), wsProtocols(), vehicle);
      return h;
    });
  }
  return healthAnswer;
}

/** Open the socket a source will take over, holding its messages until then; `vehicle`: the one the page opens on. */
export function openEarly(url: string, protocols: string[], vehicle: string | null = null): EarlySocket {
  const named = socketUrl(url, vehicle);
  const ws = protocols.length ? new WebSocket(named, protocols) : new WebSocket(named);
  const held: MessageEvent<string>[] = [];
  ws.onmessage = (ev: MessageEvent<string>) => held.push(ev);
  const e: EarlySocket = { ws, url, protocols, held, opened: Date.now() };
  // the vehicle the page opens on (its ?vehicle= link; none: null), named at once: the console then sends the other
  // vehicles' GPSReports without their satellites while the code loads, not whole (40 satellites each, at 10 Hz with
  // 50 vehicles, and the page's first frames applied them all)
  ws.onopen = () => {
    e.told = vehicle;
    const msg: ClientMessage = { type: "select", providerId: e.told };
    ws.send(JSON.stringify(msg));
  };
  early = e;
  return early;
}

/** The early socket, once: null if there is none, it closed, or it was opened to another URL or with other
 * protocols (another token). */
export function takeEarly(url: string, protocols: string[]): EarlySocket | null {
  const e = early;
  early = null;
  if (!e) return null;
  if (e.ws.readyState <= WebSocket.OPEN && e.url === url && e.protocols.join() === protocols.join()) return e;
  e.ws.close();
  return null;
}
