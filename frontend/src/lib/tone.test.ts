// @vitest-environment jsdom
import { beforeEach, expect, it, vi } from "vitest";

/** A stand-in for the Web Audio API that keeps its state as a browser does: suspended until resumed, and a log. */
class FakeContext {
  static made: FakeContext[] = [];
  state: "suspended" | "running" = "suspended";
  currentTime = 0;
  destination = {};
  log: string[] = [];
  constructor() {
    FakeContext.made.push(this);
  }
  resume() {
    this.state = "running";
    this.log.push("resume");
    return Promise.resolve();
  }
  suspend() {
    this.state = "suspended";
    this.log.push("suspend");
    return Promise.resolve();
  }
  createGain() {
    return { connect: (n: unknown) => n, gain: { setValueAtTime() {}, exponentialRampToValueAtTime() {} } };
  }
  createOscillator() {
    const log = this.log;
    log.push(`oscillator while ${this.state}`);
    return {
      connect: (n: unknown) => n,
      type: "sine",
      frequency: { value: 0 },
      start: (at: number) => log.push(`start at ${at}`),
      stop() {},
    };
  }
}

beforeEach(() => {
  vi.useFakeTimers();
  vi.resetModules(); // the module keeps its context: each test its own
  FakeContext.made = [];
  vi.stubGlobal("AudioContext", FakeContext); // unstubbed, and the real clock back, after each test (panels/setup.ts)
});

it("plays no tone before a gesture, then rests the audio between tones and wakes it for the next", async () => {
  const tone = await import("./tone");
  tone.unlockAudioOnGesture();
  tone.beep();
  expect(FakeContext.made).toHaveLength(0); // no gesture yet: no context, no tone

  window.dispatchEvent(new Event("pointerdown"));
  await vi.advanceTimersByTimeAsync(0);
  const [c] = FakeContext.made;
  expect(c.log).toEqual(["resume"]);
  await vi.advanceTimersByTimeAsync(2000); // no tone for a while: the context rests
  expect(c.state).toBe("suspended");

  tone.beep(); // woken from its rest: the tones start a little later, as a device woken may drop their start
  await vi.advanceTimersByTimeAsync(0);
  expect(c.log.slice(1)).toEqual([
    "suspend",
    "resume",
    "oscillator while running",
    "start at 0.1",
    "oscillator while running",
    "start at 0.35",
  ]);
  await vi.advanceTimersByTimeAsync(1000);
  tone.beep(); // within the rest time: played at once, and the rest starts again from it
  await vi.advanceTimersByTimeAsync(0);
  expect(c.log.slice(-5)).toEqual([
    "resume",
    "oscillator while running",
    "start at 0",
    "oscillator while running",
    "start at 0.25",
  ]);
  await vi.advanceTimersByTimeAsync(1999);
  expect(c.state).toBe("running");
  await vi.advanceTimersByTimeAsync(1);
  expect(c.state).toBe("suspended");
  expect(c.log.filter((l) => l.startsWith("oscillator"))).toHaveLength(4);
});
