// @vitest-environment jsdom
import { afterEach, describe, expect, it, vi } from "vitest";

/** A MediaQueryList as Chromium keeps one (measured in headless Chromium): `matches` evaluates the query and keeps the
 * answer, and the frame's evaluation fires `change` only when its answer differs from the one kept, so a read between
 * the system's change and the frame takes the change in without an event. */
class ChromiumMediaQueryList extends EventTarget {
  private kept: boolean;
  constructor(private readonly system: { light: boolean }) {
    super();
    this.kept = system.light;
  }
  get matches(): boolean {
    this.kept = this.system.light;
    return this.kept;
  }
  frame(): void {
    if (this.system.light === this.kept) return;
    this.kept = this.system.light;
    this.dispatchEvent(Object.assign(new Event("change"), { matches: this.kept }));
  }
}

afterEach(() => {
  vi.unstubAllGlobals();
  vi.resetModules();
  localStorage.clear();
  delete document.documentElement.dataset.theme;
});

describe("the theme follows the system's preference", () => {
  it("even when a render reads the theme between the system's change and the next frame", async () => {
    const system = { light: false };
    const list = new ChromiumMediaQueryList(system);
    vi.stubGlobal("matchMedia", () => list);
    vi.resetModules();
    const { currentTheme } = await import("./themeApply");
    expect(document.documentElement.dataset.theme).toBe("dark");
    system.light = true; // the day comes
    currentTheme(); // a panel's theme hook renders before the frame
    list.frame();
    expect(document.documentElement.dataset.theme).toBe("light");
    expect(currentTheme()).toBe("light");
  });
});
