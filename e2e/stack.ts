// The real stack for the end-to-end tests: `sem-console` and `sem-sim` processes on a fresh DDS
// domain and a free port, started by global-setup.ts and controlled by the tests (stop, restart).
import { execFileSync, spawn } from "node:child_process";
import { createSocket } from "node:dgram";
import {
  appendFileSync,
  chownSync,
  existsSync,
  mkdtempSync,
  mkdirSync,
  readFileSync,
  readdirSync,
  renameSync,
  rmSync,
  writeFileSync,
} from "node:fs";
import { connect, createServer } from "node:net";
import { tmpdir } from "node:os";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const ROOT = join(dirname(fileURLToPath(import.meta.url)), "..");
const BIN = join(ROOT, ".venv", "bin");
// E2E_STACK_STATE: another file, for a second Playwright run beside the first
const STATE = process.env.E2E_STACK_STATE ?? join(ROOT, "e2e", ".stack.json");
export const VEHICLE_3_NAME = "Charlie"; // configured with --vehicle-names; vehicles 1 and 2 have none
/** The tag of a test that uses none of the stack's processes, only a console and simulators of its own on a domain of
 * its own (`freeDomain`) and files of its own in the stack's folder: playwright.config.ts runs these on a second worker,
 * beside the tests of the stack, which stop and restart its processes one test at a time. */
export const OWN_STACK = "@own-stack";

export interface Stack {
  domain: number;
  port: number;
  url: string;
  dir: string;
  simArgs: string[];
  consoleArgs: string[];
  simPid: number;
  consolePid: number;
  vehicles: string[]; // source GUIDs of vehicles 1, 2, 3
  imcVehicles: number[]; // their CoMap IMC system ids (the console's --imc-vehicles table)
}

export const SIM_IMC_ID = 0x2001; // sem-sim's first vehicle; the next ones count up

async function freePort(): Promise<number> {
  return new Promise((resolve, reject) => {
    const srv = createServer();
    srv.listen(0, "127.0.0.1", () => {
      const port = (srv.address() as { port: number }).port;
      srv.close(() => resolve(port));
    });
    srv.on("error", reject);
  });
}

async function udpFree(port: number): Promise<boolean> {
  return new Promise((resolve) => {
    const s = createSocket("udp4");
    s.once("error", () => resolve(false));
    s.bind(port, "127.0.0.1", () => s.close(() => resolve(true)));
  });
}

/** A UDP port for IMC that no DDS participant or ephemeral socket takes meanwhile: below the kernel's
 * ephemeral range (32768 up) and in the gap of a 250-port DDS domain block (offsets 0..149 are DDS's),
 * as backend/tests/conftest.py free_udp_port. `avoid`: ports already chosen. */
async function freeImcPort(avoid: number[] = []): Promise<number> {
  for (let i = 0; i < 200; i++) {
    // blocks 80..100: pytest, running beside, takes its UDP ports from blocks below 80
    const port = 7400 + 250 * (80 + Math.floor(Math.random() * 21)) + 150 + Math.floor(Math.random() * 95);
    if (!avoid.includes(port) && (await udpFree(port))) return port;
  }
  throw new Error("no free UDP port for IMC");
}

/** Whether no Cyclone participant on this host is in DDS domain `d`: with multicast its discovery port (7400 + 250 d)
 * is bound; on loopback's unicast peers (our configuration) a participant binds only its own unicast discovery port,
 * 7410 + 250 d + 2 i for participant index i (0 for the first, then up), so the first indexes are looked at too. */
async function domainFree(d: number): Promise<boolean> {
  const ports = [7400 + 250 * d, ...Array.from({ length: 10 }, (_, i) => 7410 + 250 * d + 2 * i)];
  for (const port of ports) if (!(await udpFree(port))) return false;
  return true;
}

/** A DDS domain nobody on this host uses (`domainFree`), and none of `avoid` (the stack's, for a console of a test's
 * own beside it). */
export async function freeDomain(avoid: number[] = []): Promise<number> {
  const start = Math.floor(Math.random() * 31);
  for (let i = 0; i < 31; i++) {
    // 200..230: pytest, running beside, takes 1..199 (backend/tests/conftest.py); above 230 loopback's unicast
    // discovery ports pass 65535
    const d = 200 + ((start + i) % 31);
    if (!avoid.includes(d) && (await domainFree(d))) return d;
  }
  throw new Error("no free DDS domain");
}

/** A process of the stack's: forked by the warm launcher, or started by its command. */
interface Launched {
  pid: number;
  exited: () => boolean;
}

/** The warm launcher (backend/tests/support/launcher.py): a Python process that forks consoles and simulators from an
 * interpreter that has imported them once (a console started by its command spends about 1.5 CPU-seconds importing,
 * and the suite starts about 25 beside pytest on two cores, and about 35 simulators, 0.5 each). Started by
 * global-setup.ts, its socket's path in
 * SEM_E2E_LAUNCHER for the workers. */
export async function startLauncher(): Promise<void> {
  delete process.env.SEM_E2E_LAUNCHER; // not an outer run's
  delete process.env.SEM_E2E_LAUNCHER_PID;
  if (process.env.SEM_E2E_NO_LAUNCHER === "1") return; // every process started by its command (to compare, to debug)
  const path = join(mkdtempSync(join(tmpdir(), "sem-e2e-launcher-")), "socket");
  const launcher = spawn(join(BIN, "python"), ["-m", "support.launcher", path], {
    cwd: join(ROOT, "backend", "tests"),
    stdio: ["ignore", "inherit", "inherit"],
  });
  launcher.unref();
  let failed = false;
  launcher.on("error", () => (failed = true)); // not started at all (told by "error", not by an exception)
  const deadline = Date.now() + 60_000; // its imports, on a loaded machine
  while (!existsSync(path)) {
    if (failed || launcher.exitCode !== null || launcher.signalCode !== null || Date.now() > deadline) {
      launcher.kill();
      rmSync(dirname(path), { recursive: true, force: true });
      return; // no launcher: each process is started by its command
    }
    await new Promise((r) => setTimeout(r, 100));
  }
  process.env.SEM_E2E_LAUNCHER = path;
  process.env.SEM_E2E_LAUNCHER_PID = String(launcher.pid);
}

/** Ends the launcher and whatever it forked that still runs (global-teardown.ts, after stopStack): the launcher ends
 * them within 10 s (its STOP_S), and stopPid kills it after 15. */
export async function stopLauncher(): Promise<void> {
  const pid = Number(process.env.SEM_E2E_LAUNCHER_PID);
  if (pid) await stopPid(pid, "SIGTERM");
  const path = process.env.SEM_E2E_LAUNCHER;
  if (path) rmSync(dirname(path), { recursive: true, force: true });
}

function alive(pid: number): boolean {
  try {
    process.kill(pid, 0);
    return true;
  } catch {
    return false;
  }
}

/** `command` forked by the launcher: its pid, or null when there is no launcher or it cannot fork this one (then the
 * command is started instead). Once the request is sent, no answer fails the start, never starts the command: a
 * command started beside a fork that comes late would run the process twice. */
async function forked(command: string, argv: string[], env: NodeJS.ProcessEnv): Promise<number | null> {
  const path = process.env.SEM_E2E_LAUNCHER;
  if (!path) return null;
  return new Promise((resolve, reject) => {
    const socket = connect(path);
    let sent = false;
    let answer = "";
    socket.setTimeout(120_000, () => socket.destroy()); // a fork server's imports on a loaded machine take seconds
    socket.on("connect", () => {
      socket.write(JSON.stringify({ command, argv, env, cwd: process.cwd() }) + "\n");
      sent = true;
    });
    socket.on("data", (chunk) => {
      answer += chunk.toString();
    });
    socket.on("close", () => {
      try {
        const { pid } = JSON.parse(answer) as { pid: number | null };
        resolve(pid);
      } catch {
        if (sent) reject(new Error(`the launcher did not answer for ${command} ${argv.join(" ")}`));
        else resolve(null);
      }
    });
    socket.on("error", () => {
      /* told by "close" */
    });
  });
}

async function launch(cmd: string, args: string[], env: Record<string, string> = {}): Promise<Launched> {
  const all = { ...process.env, ...env };
  const pid = await forked(cmd, args, all);
  if (pid !== null) return { pid, exited: () => !alive(pid) };
  const child = spawn(join(BIN, cmd), args, {
    stdio: ["ignore", "inherit", "inherit"],
    env: all,
    detached: false,
  });
  child.unref();
  return { pid: child.pid!, exited: () => child.exitCode !== null || child.signalCode !== null };
}

/** A start-up wait, not a timed check: 60 s, as pytest's for a console's health (backend/tests/conftest.py), which a
 * loaded machine's start can take. */
/** Until the console at `url` answers its health check. With `child` and `domain`: that it is this child's console,
 * not another process's that took the port between `freePort` and the child's bind (pytest and the other Playwright
 * worker start consoles too): `PortTaken` when the child exits first or another console answers. */
export async function waitHealthy(url: string, timeoutMs = 60_000, child?: Launched, domain?: number): Promise<void> {
  const deadline = Date.now() + timeoutMs;
  while (Date.now() < deadline) {
    if (child?.exited()) throw new PortTaken(`console for ${url} exited before it answered`);
    try {
      const r = await fetch(`${url}/api/health`);
      if (r.ok) {
        const health = (await r.json()) as { domain?: number };
        if (domain !== undefined && health.domain !== domain)
          throw new PortTaken(`${url} is another console's (domain ${health.domain})`);
        return;
      }
    } catch (e) {
      if (e instanceof PortTaken) throw e;
      /* not up yet */
    }
    await new Promise((r) => setTimeout(r, 200));
  }
  throw new Error(`console at ${url} did not start`);
}

class PortTaken extends Error {}

export async function startStack(): Promise<Stack> {
  const domain = await freeDomain();
  const port = await freePort();
  const dir = mkdtempSync(join(tmpdir(), "sem-e2e-"));
  const consoleImc = await freeImcPort();
  const simImc = await freeImcPort([consoleImc]);
  // CoMap over IMC on 127.0.0.1: the simulator's vehicles survey at 8 m/s (before --time-scale), lanes 40 m apart
  const simArgs = [
    "--domain",
    String(domain),
    "--vehicles",
    "3",
    "--imc-port",
    String(simImc),
    "--imc-host",
    "127.0.0.1",
    "--imc-id",
    String(SIM_IMC_ID),
    "--imc-peers",
    `127.0.0.1:${consoleImc}`,
    "--survey-speed",
    "8",
    "--survey-spacing",
    "40",
    "--fault",
    "reject:2",
    "--fault",
    "skip-commanded:3",
    "--time-scale",
    "0.2",
    "--surface-seconds",
    "30",
    "--align-seconds",
    "30",
    // INS reports at 4 Hz and fixes at 2: the page streaming them drew for 0.14 of a core against 0.20 at 10 and 5 Hz
    // (0.125 at 2 and 2; measured), and a page streams through most of the suite's minutes. Each vehicle is still heard
    // every 0.25 s, so a stall of over 1.25 s (not 1 s, as at 2 Hz) makes it lost at the console's 1.5 s timeout.
    "--ins-rate",
    "4",
    "--fix-rate",
    "2",
    "--state-file",
    join(dir, "sim.json"),
    "--log-level",
    "warning",
  ];
  const vehicles = execFileSync(join(BIN, "sem-sim"), ["--list", "--vehicles", "3"], { encoding: "utf8" })
    .trim()
    .split("\n")
    .map((l) => l.split(": ")[1]);
  const imcVehicles = vehicles.map((_, i) => SIM_IMC_ID + i);
  const consoleArgs = [
    "--port",
    String(port),
    "--domain",
    String(domain),
    "--db",
    join(dir, "console.sqlite3"),
    "--recordings-dir",
    join(dir, "recordings"),
    "--comms-lost-timeout",
    "1.5",
    "--regained-time",
    "1.5",
    "--log-level",
    "warning",
    "--vehicle-names",
    `${vehicles[2]}=${VEHICLE_3_NAME}`,
    "--aspn-lcm",
    `file://${join(dir, "aspn.lcm")}`,
    "--jaus-port",
    "0",
    "--jaus-subsystem",
    "7",
    "--imc-port",
    String(consoleImc),
    "--imc-host",
    "127.0.0.1",
    "--imc-peers",
    `127.0.0.1:${simImc}`,
    "--imc-vehicles",
    vehicles.map((v, i) => `${v}=${imcVehicles[i]}`).join(","),
  ];
  const sim = await launch("sem-sim", simArgs);
  const con = await launch("sem-console", consoleArgs);
  const stack: Stack = {
    domain,
    port,
    url: `http://127.0.0.1:${port}`,
    dir,
    simArgs,
    consoleArgs,
    simPid: sim.pid,
    consolePid: con.pid,
    vehicles,
    imcVehicles,
  };
  save(stack);
  await waitHealthy(stack.url);
  return stack;
}

export function load(): Stack {
  return JSON.parse(readFileSync(STATE, "utf8")) as Stack;
}

/** Written whole, then renamed: the other worker's load() never reads half a file. */
function save(stack: Stack): void {
  writeFileSync(`${STATE}.tmp`, JSON.stringify(stack, null, 2));
  renameSync(`${STATE}.tmp`, STATE);
}

async function stopPid(pid: number, signal: NodeJS.Signals): Promise<void> {
  try {
    process.kill(pid, signal);
  } catch {
    return; // already gone
  }
  const deadline = Date.now() + 15_000;
  while (Date.now() < deadline) {
    try {
      process.kill(pid, 0);
    } catch {
      return;
    }
    await new Promise((r) => setTimeout(r, 100));
  }
  try {
    process.kill(pid, "SIGKILL");
  } catch {
    /* gone */
  }
}

export async function stopSim(signal: NodeJS.Signals = "SIGKILL"): Promise<void> {
  await stopPid(load().simPid, signal);
}

export async function restartSim(): Promise<void> {
  const stack = load();
  stack.simPid = (await launch("sem-sim", stack.simArgs)).pid;
  save(stack);
}

/** A simulator a spec starts beside the stack, stopped by `stop` (SIGINT, its shutdown sequence, unless told another
 * signal), which returns once it has exited; a second `stop` does nothing (its pid may be another process's by then). */
export interface SpecSim {
  stop(signal?: NodeJS.Signals): Promise<void>;
}

/** `sem-sim *args`, forked by the launcher as the stack's processes are (a simulator started by its command spends
 * about 0.5 CPU-s importing), else started by its command. */
export async function startSpecSim(args: string[]): Promise<SpecSim> {
  const { pid } = await launch("sem-sim", args);
  let stopped = false;
  return {
    stop: async (signal: NodeJS.Signals = "SIGINT") => {
      if (stopped) return;
      stopped = true;
      await stopPid(pid, signal);
    },
  };
}

export async function restartConsole(): Promise<void> {
  const stack = load();
  await stopPid(stack.consolePid, "SIGINT");
  stack.consolePid = (await launch("sem-console", stack.consoleArgs)).pid;
  save(stack);
  await waitHealthy(stack.url);
}

/** Another console beside the stack's; returns its URL and a stop function. */
export async function startExtraConsole(
  args: string[],
  env: Record<string, string> = {},
): Promise<{ url: string; stop: () => Promise<void> }> {
  const at = args.lastIndexOf("--domain"); // the last one given is the one the console takes
  const domain = at >= 0 ? Number(args[at + 1]) : undefined;
  for (let attempt = 1; ; attempt++) {
    const port = await freePort();
    const url = `http://127.0.0.1:${port}`;
    const child = await launch("sem-console", ["--port", String(port), "--log-level", "warning", ...args], env);
    const stop = () => stopPid(child.pid, "SIGINT");
    try {
      await waitHealthy(url, 60_000, child, domain);
      return { url, stop };
    } catch (e) {
      await stop(); // a console that did not start is not left running
      if (!(e instanceof PortTaken) || attempt >= 3) throw e;
    }
  }
}

/** A second console on the same domain with an operator token configured; returns its URL and a stop function. */
export async function startGuardedConsole(
  token: string,
  args: string[] = [],
): Promise<{ url: string; stop: () => Promise<void> }> {
  const stack = load();
  return startExtraConsole(
    [
      "--domain",
      String(stack.domain),
      "--db",
      join(stack.dir, "guarded.sqlite3"),
      "--recordings-dir",
      join(stack.dir, "recordings"),
      ...args,
    ],
    { SEM_OPERATOR_TOKENS: `e2e-operator:${token}` },
  );
}

/** A console replaying a recording of the stack's (`sem-console --replay`): no DDS. */
export async function startReplayConsole(
  recording: string,
  args: string[] = [],
): Promise<{ url: string; stop: () => Promise<void> }> {
  return startExtraConsole(["--replay", join(load().dir, "recordings", recording), ...args]);
}

export async function stopStack(): Promise<void> {
  const stack = load();
  await Promise.all([stopPid(stack.consolePid, "SIGINT"), stopPid(stack.simPid, "SIGINT")]);
  closePostgresLeft();
}

/** A mixed fleet of its own, apart from the stack's domain: a console and two simulators on a fresh domain, vehicle 1
 * on UMAA 3.0.1 and vehicle 2 on UMAA 6.0 (`sem-sim --umaa 6.0`). Returns the console's URL, the vehicles' GUIDs and a
 * stop function. */
export async function startMixedFleet(): Promise<{
  url: string;
  vehicles: string[];
  stop: () => Promise<void>;
}> {
  const stack = load();
  const domain = await freeDomain([stack.domain]); // the stack's sim runs vehicles 1..3 (3.0.1): vehicle 2 there too
  const run = `mixed-${domain}`; // each fleet its own state files and database: a spec starts from nothing
  const vehicles = execFileSync(join(BIN, "sem-sim"), ["--list", "--vehicles", "2"], { encoding: "utf8" })
    .trim()
    .split("\n")
    .map((l) => l.split(": ")[1]);
  const sims = await Promise.all([
    launch("sem-sim", [
      "--domain",
      String(domain),
      "--state-file",
      join(stack.dir, `${run}-3.0.1.json`),
      "--log-level",
      "warning",
    ]),
    launch("sem-sim", [
      "--domain",
      String(domain),
      "--umaa",
      "6.0",
      "--first-vehicle",
      "2",
      "--state-file",
      join(stack.dir, `${run}-6.0.json`),
      "--log-level",
      "warning",
    ]),
  ]);
  const stopSims = () => Promise.all(sims.map((s) => stopPid(s.pid, "SIGINT")));
  const con = await startExtraConsole([
    "--domain",
    String(domain),
    "--db",
    join(stack.dir, `${run}.sqlite3`),
    "--recordings-dir",
    join(stack.dir, "recordings"),
  ]).catch(async (e: unknown) => {
    await stopSims();
    throw e;
  });
  return {
    url: con.url,
    vehicles,
    stop: async () => {
      await Promise.all([con.stop(), stopSims()]);
    },
  };
}

const asPostgres = process.getuid?.() === 0; // initdb refuses to run as root

function pgBin(name: string): string {
  const versions = existsSync("/usr/lib/postgresql")
    ? readdirSync("/usr/lib/postgresql").sort((a, b) => Number(a) - Number(b))
    : [];
  const found = versions
    .map((v) => `/usr/lib/postgresql/${v}/bin/${name}`)
    .filter((p) => existsSync(p))
    .at(-1);
  if (!found) throw new Error(`PostgreSQL's ${name} is not installed: apt-get install -y postgresql (scripts/setup.sh does)`);
  return found;
}

function pgRun(cmd: string, ...args: string[]): void {
  execFileSync(asPostgres ? "runuser" : cmd, asPostgres ? ["-u", "postgres", "--", cmd, ...args] : args, {
    stdio: "pipe",
    timeout: 120_000,
  });
}

/** The clusters this run's specs started (one directory a line), for the stack's teardown. */
const pgClusters = () => join(load().dir, "postgres-clusters");

/** Stops every PostgreSQL a spec of this run started and did not close (a spec that failed in its beforeAll, a worker
 * killed or interrupted), and removes its directory: none is left running after the run. */
export function closePostgresLeft(): void {
  const list = pgClusters();
  if (!existsSync(list)) return;
  for (const root of readFileSync(list, "utf8").split("\n").filter(Boolean)) {
    if (existsSync(join(root, "data", "postmaster.pid"))) {
      try {
        pgRun(pgBin("pg_ctl"), "-D", join(root, "data"), "-m", "immediate", "-w", "stop");
      } catch {
        /* stopped meanwhile */
      }
    }
    rmSync(root, { recursive: true, force: true });
  }
  rmSync(list, { force: true });
}

/** A real PostgreSQL for a spec's operations centre (Debian's postgresql, which scripts/setup.sh installs), started as
 * backend/tests/support/pg.py starts the pytest one: a cluster in a temporary directory, by initdb and pg_ctl run as the
 * `postgres` user when the tests run as root, on a free port of 127.0.0.1. `url`: its database for the consoles;
 * `stop` and `start` for an outage; `close` stops it and removes its directory. */
export async function startPostgres(): Promise<{
  url: string;
  stop: () => void;
  start: () => void;
  close: () => void;
}> {
  const root = mkdtempSync(join(tmpdir(), "sem-e2e-pg-"));
  appendFileSync(pgClusters(), `${root}\n`); // stopped by the stack's teardown if the spec's own close never runs
  const data = join(root, "data");
  const sockets = join(root, "sockets");
  mkdirSync(sockets);
  const pgUid = asPostgres ? Number(execFileSync("id", ["-u", "postgres"], { encoding: "utf8" })) : 0;
  const pgGid = asPostgres ? Number(execFileSync("id", ["-g", "postgres"], { encoding: "utf8" })) : 0;
  const password = "e2e-pg-s3cret";
  const pwfile = join(root, "pw");
  writeFileSync(pwfile, `${password}\n`);
  if (asPostgres) for (const p of [root, sockets, pwfile]) chownSync(p, pgUid, pgGid);
  pgRun(
    pgBin("initdb"),
    "-D",
    data,
    "-U",
    "postgres",
    "--auth-local=trust",
    "--auth-host=scram-sha-256",
    `--pwfile=${pwfile}`,
    "-E",
    "UTF8",
    "--no-sync",
  );
  rmSync(pwfile);
  const port = await freePort();
  const start = () =>
    pgRun(
      pgBin("pg_ctl"),
      "-D",
      data,
      "-o",
      `-p ${port} -k ${sockets} -c listen_addresses=127.0.0.1 -c fsync=off`,
      "-l",
      join(root, "server.log"),
      "-w",
      "start",
    );
  const stop = () => pgRun(pgBin("pg_ctl"), "-D", data, "-m", "fast", "-w", "stop");
  start();
  return {
    url: `postgresql://postgres:${password}@127.0.0.1:${port}/postgres`,
    stop: () => void stop(),
    start: () => void start(),
    close: () => {
      try {
        stop();
      } catch {
        /* stopped already */
      }
      rmSync(root, { recursive: true, force: true });
    },
  };
}
