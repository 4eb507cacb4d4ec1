import { useState } from "react";
import { ApiError, controlRecording } from "../api/rest";
import { useToken } from "../data/auth";
import { useNow, useRecording, useSelector } from "../data/hooks";

function elapsed(seconds: number): string {
  const s = Math.max(0, Math.floor(seconds));
  const hh = Math.floor(s / 3600);
  const mm = String(Math.floor((s % 3600) / 60)).padStart(2, "0");
  const ss = String(s % 60).padStart(2, "0");
  return hh ? `${hh}:${mm}:${ss}` : `${mm}:${ss}`;
}

/** The header's record/stop control: records every SEM sample the console receives to MCAP. */
export function RecordControl() {
  const rec = useRecording();
  const authRequired = useSelector((s) => s.authRequired);
  const token = useToken();
  const now = useNow(1000);
  const [busy, setBusy] = useState(false);
  const [error, setError] = useState<string | null>(null);
  if (!rec) return null;
  const recording = rec.state === "recording";
  const allowed = !authRequired || !!token;
  const run = async (action: "start" | "stop") => {
    setBusy(true);
    setError(null);
    try {
      await controlRecording(action, token); // the new state arrives on the WebSocket too
    } catch (e) {
      setError(e instanceof ApiError ? e.message : String(e));
    } finally {
      setBusy(false);
    }
  };
  return (
    <span className="recording" data-testid="recording" data-state={rec.state}>
      {recording ? (
        <>
          <span className="rec-dot" aria-hidden="true">●</span>
          <span title={`${rec.directory}/${rec.file ?? ""}`} data-testid="recording-status">
            REC {rec.startedAt !== null ? elapsed(now - rec.startedAt) : ""}
            {rec.dropped > 0 ? ` (${rec.dropped} dropped)` : ""}
          </span>
          <button className="small" disabled={busy || !allowed} onClick={() => void run("stop")} title="Stop recording">
            Stop
          </button>
        </>
      ) : (
        <button className="small" disabled={busy || !allowed} onClick={() => void run("start")}
          title={allowed ? `Record every SEM sample to ${rec.directory}` : "Sign in to record"}>
          ● Record
        </button>
      )}
      {rec.state === "failed" && (
        <span className="error" role="alert" data-testid="recording-error">{rec.error}</span>
      )}
      {error && <span className="error" role="alert">{error}</span>}
    </span>
  );
}
