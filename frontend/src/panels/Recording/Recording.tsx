import { useMutation } from "@tanstack/react-query";
import { ApiError, controlRecording } from "../../api/rest";
import { useToken } from "../../data/auth";
import { useCapabilities, useConsoleNow, useRecording, useSelector } from "../../data/hooks";
import { clockDuration } from "../../lib/units";

/** The header's record/stop control: records every SEM sample the console receives, UMAA 3.0.1 and 6.0, to MCAP. */
export function RecordControl() {
  const rec = useRecording();
  const { record } = useCapabilities();
  const authRequired = useSelector((s) => s.authRequired);
  const token = useToken();
  const now = useConsoleNow(1000);
  // the new state arrives on the WebSocket too: the answer is not kept
  const control = useMutation({ mutationFn: (action: "start" | "stop") => controlRecording(action, token) });
  if (!rec || !record) return null; // a replay records nothing
  const recording = rec.state === "recording";
  const allowed = !authRequired || !!token;
  const busy = control.isPending;
  const error = control.error ? (control.error instanceof ApiError ? control.error.message : String(control.error)) : null;
  const run = (action: "start" | "stop") => control.mutate(action);
  return (
    <span className="recording" data-testid="recording" data-state={rec.state}>
      {recording ? (
        <>
          <span className="rec-dot" aria-hidden="true">
            ●
          </span>
          <span title={`${rec.directory}/${rec.file ?? ""}`} data-testid="recording-status">
            REC {rec.startedAt !== null ? clockDuration(now - rec.startedAt) : ""}
            {rec.dropped > 0 ? ` (${rec.dropped} dropped)` : ""}
          </span>
          <button className="small" disabled={busy || !allowed} onClick={() => run("stop")} title="Stop recording">
            Stop
          </button>
        </>
      ) : (
        <button
          className="small"
          disabled={busy || !allowed}
          onClick={() => run("start")}
          title={allowed ? `Record every SEM sample (UMAA 3.0.1 and 6.0) to ${rec.directory}` : "Sign in to record"}
        >
          ● Record
        </button>
      )}
      {rec.state === "failed" && (
        <span className="error" role="alert" data-testid="recording-error">
          {rec.error}
        </span>
      )}
      {error && (
        <span className="error" role="alert">
          {error}
        </span>
      )}
    </span>
  );
}
