import { useEffect, useRef, useState } from "react";
import { problemText } from "../../api/rest";
import { useNow, usePlayback } from "../../data/hooks";
import { SPEEDS } from "../../data/source";
import { clockDuration, utc } from "../../lib/units";

/** Play, pause, speed and a seek bar with time labels: shown only when the data source is a replay. */
export function ReplayBar() {
  const playback = usePlayback();
  const now = useNow(200);
  const [draft, setDraft] = useState<number | null>(null); // the seek bar while it is dragged
  const [error, setError] = useState<string | null>(null);
  const seekBar = useRef<HTMLInputElement>(null);
  const controls = playback?.controls;

  const run = async (fn: () => Promise<void>) => {
    setError(null);
    try {
      await fn();
    } catch (e) {
      setError(problemText(e));
    }
  };

  // Seek when the bar is let go (or stepped with the keyboard): its native change event, not every input event
  // of a drag, which would rebuild the state at each pixel.
  useEffect(() => {
    const el = seekBar.current;
    if (!el || !controls) return;
    const commit = () => {
      const to = Number(el.value);
      void run(() => controls.seek(to)).finally(() => setDraft(null));
    };
    el.addEventListener("change", commit);
    return () => el.removeEventListener("change", commit);
  }, [controls]);

  if (!playback) return null;
  const { status } = playback;
  const position = draft ?? Math.min(status.end, Math.max(status.start, now));
  const playing = status.state === "playing";
  const speeds = SPEEDS.includes(status.speed) ? SPEEDS : [...SPEEDS, status.speed].sort((a, b) => a - b);
  return (
    <section className="replay-bar" data-testid="replay-bar" aria-label="Replay controls" data-state={status.state}>
      <button
        className="replay-play"
        data-testid="replay-play"
        aria-label={playing ? "Pause" : "Play"}
        onClick={() => void run(playing ? playback.controls.pause : playback.controls.play)}
      >
        {playing ? "❚❚ Pause" : "▶ Play"}
      </button>
      <label className="replay-speed">
        Speed{" "}
        <select
          aria-label="Playback speed"
          data-testid="replay-speed"
          value={status.speed}
          onChange={(e) => void run(() => playback.controls.setSpeed(Number(e.target.value)))}
        >
          {speeds.map((s) => (
            <option key={s} value={s}>
              {s}×
            </option>
          ))}
        </select>
      </label>
      <span className="replay-elapsed" data-testid="replay-elapsed">
        {clockDuration(position - status.start)}
      </span>
      <input
        ref={seekBar}
        type="range"
        className="replay-seek"
        aria-label="Seek"
        data-testid="replay-seek"
        min={status.start}
        max={status.end}
        step="any"
        value={position}
        onChange={(e) => setDraft(Number(e.target.value))}
      />
      <span className="replay-total muted" data-testid="replay-total">
        {clockDuration(status.end - status.start)}
      </span>
      <span className="replay-time" data-testid="replay-time" title="the instant shown (UTC)">
        {utc(position, true, "ds")}
      </span>
      {error && (
        <span className="error" role="alert" data-testid="replay-error">
          {error}
        </span>
      )}
    </section>
  );
}
