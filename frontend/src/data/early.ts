// A new client's first requests, sent as the page loads, before the dashboard's code (1.5 MB, two thirds of it
// MapLibre) has arrived and run: the health check, then the WebSocket, whose snapshot is what the first screen
// draws. main.tsx's source takes the socket over (Connection.start) with the messages it held; before, both waited
// for the code, and the snapshot came 0.4-0.6 s after navigation. Nothing here may import React or the panels
// (boot.ts's chunk is its imports: this file, api/rest.ts, token.ts, settingStore.ts, themeApply.ts).
import { health, type Health } from "../api/rest";
import { getToken, wsProtocols } from "./token";

/** The console's WebSocket, asking for its reports in batches under load (a browser pays about 0.13 ms of its main
 * thread per message whatever its size, 30 % of it with 250 vehicles sent one message per report), and acknowledging
 * the frames it takes (`ack`, sent by the source): the console then holds reports beyond a window of bytes, where
 * newer ones replace them, instead of queueing megabytes in the sockets behind which a new fix waited. An early
 * socket acknowledges nothing until its source takes it over: meanwhile the console holds the reports. */
export function defaultUrl(): string {
  const { protocol, host } = window.location;
  return `${protocol === "https:" ? "wss" : "ws"}://${host}/ws?batch=1&ack=1`;
}

/** A socket opened before its source existed, and the messages it received meanwhile (in order). */
export interface EarlySocket {
  ws: WebSocket;
  url: string;
  protocols: string[];
  held: MessageEvent<string>[];
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

/** Start the health check and, once it allows, the WebSocket (a replay's source reads the same socket). */
export function startEarly(): Promise<Health> {
  healthAnswer ??= consoleHealth().then((h) => {
    if (mayRead(h)) openEarly(defaultUrl(), wsProtocols());
    return h;
  });
  return healthAnswer;
}

/** Open the socket a source will take over, holding its messages until then. */
export function openEarly(url: string, protocols: string[]): EarlySocket {
  const ws = protocols.length ? new WebSocket(url, protocols) : new WebSocket(url);
  const held: MessageEvent<string>[] = [];
  ws.onmessage = (ev: MessageEvent<string>) => held.push(ev);
  early = { ws, url, protocols, held };
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
