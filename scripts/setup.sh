# Sourced by scripts/run, scripts/test and scripts/screenshot: makes .venv with the backend installed,
# installs the dashboard's npm packages and builds it into frontend/dist (which the console serves).
# With --secure (or SEM_SECURE=1) it also builds the DDS Security build of Cyclone DDS and its Python binding into a
# cache, once per machine (scripts/secure-build.sh, about 45 s on 2 idle cores; scripts/secure runs a command on it).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY="${PYTHON:-python3}"

apt_install() {  # Debian packages, when we can install them (without their recommended packages: chromium's and
  # docker-compose's pulled in systemd, GTK, CUPS and the Docker engine, half a minute more on a fresh machine); one apt
  # at a time, as scripts/test's may run beside another (flock: apt's own lock would fail the second at once)
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    flock /tmp/sem-console-apt.lock bash -c 'apt-get update -qq &&
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" >/dev/null' _ "$@"
  else
    echo "missing: $* (install with: sudo apt-get install $*)" >&2
    exit 1
  fi
}

command -v npm >/dev/null || apt_install nodejs npm
# The dashboard's build tool (Vite 8) needs Node 20.19+ or 22.12+ (its package's "engines"); Debian 12's own nodejs is
# 18, on which the build fails deep in a log: one line instead.
node -e 'const [a, b] = process.versions.node.split(".").map(Number);
  process.exit((a === 20 && b >= 19) || (a === 22 && b >= 12) || a > 22 ? 0 : 1)' || {
  echo "Node $(node --version) cannot build the dashboard (Vite needs Node 20.19+ or 22.12+): install a newer Node, e.g. from NodeSource or nvm" >&2
  exit 1
}
# The dashboard's packages and build beside the backend's install (each mostly uses one core); their output is
# printed only when they fail (tsc writes its type errors to stdout).
# In a session of its own (setsid), so that a failure below (the venv, pip; `exit` or set -e) or Ctrl-C ends the
# whole npm tree with this script rather than leaving it writing node_modules and dist beside the next run's.
dashboard_log="$(mktemp)"
setsid bash -c 'cd "$1/frontend" && npm ci --no-audit --no-fund --loglevel=error && npm run --silent build' _ "$ROOT" \
  >"$dashboard_log" 2>&1 &
dashboard=$!
# The caller's jobs (beside_setup and after_python_setup, below), each in a session of its own too: ended with the
# dashboard's.
setup_jobs=()
end_setup_jobs() {
  local job
  for job in "${setup_jobs[@]}"; do kill -TERM -- "-$job" 2>/dev/null || true; done
}
end_setup() {  # ends the dashboard's build and the caller's jobs (on a failure, or when the caller stops first)
  kill -TERM -- "-$dashboard" 2>/dev/null || true
  end_setup_jobs
  rm -f "$dashboard_log"
}
trap end_setup EXIT
# A caller's work that needs nothing of the set-up (scripts/test: Debian's packages) starts here, when it defines
# `beside_setup`, as `after_python_setup` below.
if declare -F beside_setup >/dev/null; then beside_setup; fi

if [ ! -x "$ROOT/.venv/bin/python" ]; then
  if ! "$PY" -m venv "$ROOT/.venv" >/dev/null 2>&1; then
    rm -rf "$ROOT/.venv"
    apt_install python3-venv  # Debian ships venv separately
    "$PY" -m venv "$ROOT/.venv"
  fi
fi
# The backend's packages are installed by uv (from PyPI into the venv): on a clean clone set-up took 83 s with pip, 72 s
# of it pip's, and takes 40 s with uv (measured on 2 cores, the dashboard's build beside it); every test run starts
# after it. pip installs uv itself; should uv not run here, pip installs the packages instead.
"$ROOT/.venv/bin/python" -m pip install -q --disable-pip-version-check uv || true
py_install() {  # [--reinstall-package NAME] PACKAGES... into the venv
  local uv_only=()
  if [ "$1" = --reinstall-package ]; then  # (pip reinstalls an editable install each time by itself)
    uv_only=(--reinstall-package "$2")
    shift 2
  fi
  # --compile-bytecode: as pip does (uv does not by default), and PYTHONDONTWRITEBYTECODE, set on these machines, keeps a
  # process from writing them: without it each console and simulator start compiles its libraries again
  if [ -x "$ROOT/.venv/bin/uv" ] &&
    "$ROOT/.venv/bin/uv" pip install -q --compile-bytecode --python "$ROOT/.venv/bin/python" "${uv_only[@]}" "$@"; then
    return
  fi
  "$ROOT/.venv/bin/python" -m pip install -q --disable-pip-version-check "$@"
}
# The UMAA types are generated from idl/ (never committed) before the backend is installed, so that its install finds
# their packages: idlgen needs only cyclonedds (the backend's pinned version), and regenerates only when idl/ changed.
py_install "$(grep -o 'cyclonedds==[0-9.]*' "$ROOT/backend/pyproject.toml")"
PYTHONPATH="$ROOT/backend" "$ROOT/.venv/bin/python" -m sem_console.idlgen --if-stale
# --reinstall-package: the editable install lists the generated packages as it finds them (uv would keep an older one)
py_install --reinstall-package sem-console -e "$ROOT/backend[test]"
# The backend's own modules compiled once here: the tests start a few hundred consoles and simulators, and with
# PYTHONDONTWRITEBYTECODE set (as on these machines) each would compile them again (about 0.15 s of CPU each).
PYTHONDONTWRITEBYTECODE= "$ROOT/.venv/bin/python" -m compileall -q "$ROOT/backend/sem_console" "$ROOT/backend/UMAA" \
  "$ROOT/backend/UMAA_appendable" "$ROOT/backend/UMAA_6_0" "$ROOT/backend/UMAA_6_0_appendable" >&2  # (-q: only a module that does not compile, named with its error)
# A caller's own work that needs the Python environment (scripts/test: the tests' caches, e2e's install) starts
# here, beside the dashboard's build, when it defines `after_python_setup`: each job in a session of its own, its pid
# added to setup_jobs, so that a failure of the set-up ends it.
if declare -F after_python_setup >/dev/null; then after_python_setup; fi

finish_setup() {  # waits for the dashboard's build (and with --secure, builds the secure build)
  local dashboard_rc=0
  wait "$dashboard" || dashboard_rc=$?
  if [ "$dashboard_rc" != 0 ]; then  # (the EXIT trap, still set, ends the jobs: the caller's may have added its own)
    cat "$dashboard_log" >&2
    echo "the dashboard's install or build failed (above)" >&2
    exit 1
  fi
  trap - EXIT  # the job is over: the sourcing script's own exit is its business
  rm -f "$dashboard_log"
  if [ "${SEM_SECURE:-0}" = 1 ]; then
    bash "$ROOT/scripts/secure-build.sh" >/dev/null
  fi
}
case " $* " in *" --secure "*) SEM_SECURE=1 ;; esac
# SEM_SETUP_LATER=1 (scripts/test): the caller goes on with the dashboard's build under way (its EXIT trap still set)
# and calls finish_setup itself.
[ "${SEM_SETUP_LATER:-0}" = 1 ] || finish_setup
