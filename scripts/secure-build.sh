#!/usr/bin/env bash
# Builds the DDS Security build of Cyclone DDS and its Python binding into a cache, once per version:
#   $SEM_SECURE_CACHE (default ~/.cache/sem-console/cyclonedds-secure-11.0.1, -tests for scripts/test)/prefix: Cyclone DDS C built with
#     -DENABLE_SECURITY=ON -DENABLE_SSL=ON (libdds_security_auth, _ac and _crypto beside libddsc);
#   .../python: the cyclonedds Python binding built against it (pip --target), which scripts/secure puts before the
#     project's .venv, whose own cyclonedds stays PyPI's wheel (that has no security plugins).
# The C source is the one the crates registry's cyclors 0.4.0 vendors (Cyclone DDS 11.0.1), checked against the
# registry index's checksum, and the binding's source (PyPI's cyclonedds 11.0.1 archive) against PyPI's. Run by
# `scripts/setup.sh --secure` (or SEM_SECURE=1) and by scripts/test; about 45 s
# on 2 idle cores. Prints the cache's folder on its last line; a failure leaves its one-line reason in .../failed
# (the security tests' skip reason). Needs cmake, a C compiler and OpenSSL's headers (Debian: cmake, build-essential,
# libssl-dev), installed here when run as root.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VERSION="11.0.1"
CRATE="cyclors-0.4.0"
CRATE_SHA256="6beb8dc0574f6e2184a2a67c6833ff7ab5b64a95d2459db9b009797b0bb7374e"
SDIST_SHA256="487cdd9e3dbe3bc6f66c3318c45979f4015bb9d32d5dfcb9bb4a67376176a526"  # PyPI's cyclonedds-11.0.1.tar.gz
# SEM_SECURE_FOR_TESTS=1 (scripts/test): the same build unoptimised (-O0), in a cache of its own: the tests need what it
# does, not its speed (the DDS Security tests took as long on either), and it builds on 36 CPU-s rather than 75
# (measured on 2 idle cores, 2026-12-01; beside the tests, niced, the optimised build took 409 s).
build_type=(-DCMAKE_BUILD_TYPE=Release)
flavour=""
if [ "${SEM_SECURE_FOR_TESTS:-0}" = 1 ]; then
  build_type=(-DCMAKE_BUILD_TYPE=None -DCMAKE_C_FLAGS=-O0)
  flavour="-tests"
fi
CACHE="${SEM_SECURE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/sem-console/cyclonedds-secure-$VERSION$flavour}"
PY="$ROOT/.venv/bin/python"

if [ -f "$CACHE/ready" ]; then
  echo "$CACHE"
  exit 0
fi
fail() {
  echo "$1" >&2
  echo "$1" >"$CACHE/failed"
  exit 1
}
mkdir -p "$CACHE"
rm -rf "$CACHE/prefix" "$CACHE/python" "$CACHE/failed"
[ -x "$PY" ] || fail "the secure build needs the project's $PY: run scripts/setup.sh first"

missing=()
command -v cmake >/dev/null || missing+=(cmake)
command -v cc >/dev/null || missing+=(build-essential)
[ -f /usr/include/openssl/ssl.h ] || missing+=(libssl-dev)
if [ "${#missing[@]}" -gt 0 ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    flock /tmp/sem-console-apt.lock bash -c 'apt-get update -qq &&
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" >/dev/null' _ "${missing[@]}" \
      || fail "the secure build needs ${missing[*]}, and apt-get could not install them"
  else
    fail "the secure build needs: ${missing[*]} (install with: sudo apt-get install ${missing[*]})"
  fi
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
log="$CACHE/build.log"
echo "building Cyclone DDS $VERSION with DDS Security into $CACHE (about a minute; log: $log)" >&2
curl -fsSL --retry 3 -o "$work/$CRATE.crate" "https://static.crates.io/crates/cyclors/$CRATE.crate" \
  || fail "could not download $CRATE from the crates registry (Cyclone DDS $VERSION's source)"
echo "$CRATE_SHA256  $work/$CRATE.crate" | sha256sum --check --quiet \
  || fail "$CRATE from the crates registry does not have the registry index's checksum"
tar -xzf "$work/$CRATE.crate" -C "$work"
start=$SECONDS
{
  cmake -S "$work/$CRATE/cyclonedds" -B "$work/build" "${build_type[@]}" \
    -DCMAKE_INSTALL_PREFIX="$CACHE/prefix" -DENABLE_SECURITY=ON -DENABLE_SSL=ON -DENABLE_LTO=OFF \
    -DBUILD_DDSPERF=OFF -DBUILD_EXAMPLES=OFF -DBUILD_TESTING=OFF -DENABLE_SHM=OFF -DENABLE_ICEORYX=OFF
  cmake --build "$work/build" --parallel "$(nproc)"
  cmake --install "$work/build"
} >"$log" 2>&1 || { tail -n 30 "$log" >&2; fail "the Cyclone DDS build failed (log: $log)"; }
for plugin in auth ac crypto; do
  [ -f "$CACHE/prefix/lib/libdds_security_$plugin.so" ] || fail "the build made no libdds_security_$plugin.so (log: $log)"
done
# the binding alone (--no-deps: the project's .venv has its dependencies), built against this prefix (--no-cache-dir: pip
# would take a wheel it built against another prefix before, whose library path is written into it), from PyPI's source
# archive checked against its checksum (--require-hashes)
echo "cyclonedds==$VERSION --hash=sha256:$SDIST_SHA256" >"$work/binding.txt"
CYCLONEDDS_HOME="$CACHE/prefix" "$PY" -m pip install -q --disable-pip-version-check --no-cache-dir --no-deps --target "$CACHE/python" \
  --no-binary cyclonedds --require-hashes -r "$work/binding.txt" >>"$log" 2>&1 \
  || { tail -n 30 "$log" >&2; fail "the cyclonedds binding's build failed, or PyPI's source archive has not the checksum written here (log: $log)"; }
echo "built in $((SECONDS - start)) s" >>"$log"
touch "$CACHE/ready"
echo "$CACHE"
