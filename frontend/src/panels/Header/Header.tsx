import { useState } from "react";
import { ApiError, checkToken } from "../../api/rest";
import { setToken, useToken } from "../../data/auth";
import { resetLayout, useThemeSetting, isThemeChoice } from "../../data/settings";
import { useCapabilities, useConnectionState, useConsoleNow, usePlayback, useSelector } from "../../data/hooks";
import { utc } from "../../lib/units";
import { useConsoleHealth, useOperatorName } from "../../data/loaders";
import { RecordControl } from "../Recording/Recording";

const LABEL = {
  connecting: "Connecting…",
  live: "Live",
  reconnecting: "Reconnecting…",
  offline: "Offline (retrying)",
  "signed-out": "Not signed in",
};

export function Header() {
  const conn = useConnectionState();
  const playback = usePlayback();
  const { command } = useCapabilities();
  const consoleId = useSelector((s) => s.consoleId);
  const station = useConsoleHealth()?.consoleName ?? null; // this station's name, as the shelves and silences say it
  const authRequired = useSelector((s) => s.authRequired);
  const readAuthRequired = useSelector((s) => s.readAuthRequired);
  const token = useToken();
  const operator = useOperatorName();
  const now = useConsoleNow(1000);
  const [draft, setDraft] = useState("");
  const [refused, setRefused] = useState<string | null>(null);
  const signIn = async (t: string) => {
    setRefused(null);
    try {
      await checkToken(t); // the console says whether the token is good before it is kept
      setToken(t);
      setDraft("");
    } catch (e) {
      setRefused(e instanceof ApiError ? e.message : String(e));
    }
  };
  return (
    <header className="app-header">
      <h1>SEM Console</h1>
      <span className={`conn conn-${conn}`} data-testid="connection-state" role="status" aria-label="connection">
        {playback && conn === "live" ? "Connected" : LABEL[conn]}
      </span>
      {playback && (
        <span className="replay-badge" data-testid="replay-badge" title={`Replaying ${playback.status.file}: read-only`}>
          Replay <span className="replay-file">{playback.status.file}</span>
        </span>
      )}
      <span
        className="muted"
        data-testid="console-station"
        title={consoleId ? `console source GUID ${consoleId}` : "console source GUID"}
      >
        {station ? `station ${station}` : consoleId ? `console ${consoleId.slice(0, 8)}` : ""}
      </span>
      <BusSecurity />
      <span className="spacer" />
      <RecordControl />
      {readAuthRequired && !token && (
        <span className="readonly" data-testid="sign-in-to-read">
          Sign in to see the vehicles
        </span>
      )}
      {((authRequired && command) || readAuthRequired) && // a replay commands nothing: a token matters only to read
        (token ? (
          <span className="signin" data-testid="signed-in">
            {operator ? (
              <>
                Signed in as <b data-testid="operator-name">{operator}</b>
              </>
            ) : (
              "Signed in"
            )}{" "}
            <button onClick={() => setToken(null)}>Sign out</button>
          </span>
        ) : (
          <form
            className="signin"
            onSubmit={(e) => {
              e.preventDefault();
              void signIn(draft.trim());
            }}
          >
            <span className="readonly" data-testid="read-only">
              Read-only
            </span>
            <input
              type="password"
              aria-label="Operator token"
              placeholder="Operator token"
              value={draft}
              onChange={(e) => setDraft(e.target.value)}
            />
            <button type="submit">Sign in</button>
            {refused && (
              <span className="error" role="alert" data-testid="sign-in-error">
                {refused}
              </span>
            )}
          </form>
        ))}
      <ThemeToggle />
      <button
        className="small"
        onClick={resetLayout}
        title="the default panel order, nothing collapsed"
        data-testid="reset-layout"
      >
        Reset layout
      </button>
      <span className="clock" title={playback ? "UTC, the recording's time" : "UTC, the console's clock"}>
        {utc(now, true, "s")}
      </span>
    </header>
  );
}

/** Whether the console's DDS bus is secured (DDS Security) and under which identity; an open bus said plainly. */
function BusSecurity() {
  const security = useConsoleHealth()?.ddsSecurity;
  if (!security) return null; // a replay, or the console not answering yet
  if (!security.secured)
    return (
      <span
        className="bus-open"
        data-testid="bus-security"
        title="no DDS Security: any process on the vehicles' network can read every report and command a vehicle"
      >
        DDS bus open (no security)
      </span>
    );
  return (
    <span
      className="bus-secured"
      data-testid="bus-security"
      title={`DDS Security: ${security.subject ?? security.identity ?? ""}, from ${security.source ?? ""}`}
    >
      DDS secured as {security.identity}
    </span>
  );
}

/** Light for daylight, dark for the night, or whatever the system is set to (the default). */
function ThemeToggle() {
  const [theme, setTheme] = useThemeSetting();
  return (
    <label
      className="theme-toggle"
      title="colours for daylight (light) or the night (dark); System follows the computer's setting"
    >
      Theme
      <select value={theme} onChange={(e) => isThemeChoice(e.target.value) && setTheme(e.target.value)} data-testid="theme">
        <option value="system">System</option>
        <option value="light">Light</option>
        <option value="dark">Dark</option>
      </select>
    </label>
  );
}
