// The page's first requests (early.ts) with --auth-reads: the socket opens at once unless this browser last saw reads
// need a token and holds none (then the console would refuse it), and what the health answer said is remembered.
import { afterEach, describe, expect, it, vi } from "vitest";

class FakeSocket {
  static all: FakeSocket[] = [];
  static readonly OPEN = 1;
  readyState = 0;
  onmessage: unknown = null;
  onopen: unknown = null;
  closed = false;
  constructor(
    readonly url: string,
    readonly protocols?: string[],
  ) {
    FakeSocket.all.push(this);
  }
  close(): void {
    this.closed = true;
    this.readyState = 3;
  }
}

/** A storage of the browser's kind, kept across the page loads below (localStorage) or one page's (sessionStorage). */
function storage(items: Map<string, string>): Pick<Storage, "getItem" | "setItem" | "removeItem"> {
  return {
    getItem: (k) => items.get(k) ?? null,
    setItem: (k, v) => void items.set(k, v),
    removeItem: (k) => void items.delete(k),
  };
}

/** One page load: early.ts afresh, the console's health answer saying whether reads need a token. */
async function load(local: Map<string, string>, readAuthRequired: boolean, token: string | null) {
  vi.resetModules();
  FakeSocket.all = [];
  vi.stubGlobal("WebSocket", FakeSocket);
  vi.stubGlobal("window", { location: { protocol: "http:", host: "console", search: "" }, addEventListener: () => undefined });
  vi.stubGlobal("location", { origin: "http://console" });
  vi.stubGlobal("localStorage", storage(local));
  vi.stubGlobal("sessionStorage", storage(new Map(token ? [["sem-console-token", token]] : [])));
  let answer: (r: Response) => void = () => undefined;
  vi.stubGlobal("fetch", () => new Promise<Response>((r) => (answer = r)));
  const { startEarly } = await import("./early");
  const health = startEarly();
  const before = FakeSocket.all.length; // opened before the health answer
  answer(new Response(JSON.stringify({ readAuthRequired, authRequired: readAuthRequired, replay: null })));
  await health;
  return { before, sockets: FakeSocket.all };
}

describe("the early socket with --auth-reads", () => {
  afterEach(() => vi.unstubAllGlobals());

  it("opens at once until reads were seen to need a token; then only with one", async () => {
    const local = new Map<string, string>();
    const first = await load(local, true, null); // a first visit: not known yet, refused by the console
    expect(first.before).toBe(1);
    expect(first.sockets[0].closed).toBe(true);
    expect(local.get("sem-console.readAuthRequired")).toBe("true");

    const again = await load(local, true, null); // remembered: no socket the console would refuse
    expect(again.before).toBe(0);
    expect(again.sockets).toHaveLength(0);

    const signedIn = await load(local, true, "tok"); // a token of this tab's session: at once, with it
    expect(signedIn.before).toBe(1);
    expect(signedIn.sockets[0].protocols).toEqual(["sem-console", "bearer.dG9r"]);
    expect(signedIn.sockets[0].closed).toBe(false);

    const opened = await load(local, false, null); // the console's reads opened: the socket after the answer
    expect(opened.before).toBe(0);
    expect(opened.sockets).toHaveLength(1);
    expect(local.get("sem-console.readAuthRequired")).toBe("false");
    expect((await load(local, false, null)).before).toBe(1); // and at once on the next load
  });
});
