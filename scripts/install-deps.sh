#!/usr/bin/env bash
# Installs the Debian packages asimov needs, and only those that are missing.
# Idempotent: a second run calls no apt-get at all. Run as root (or with sudo available).
set -euo pipefail

packages=(
  build-essential cmake ccache pkg-config
  libeigen3-dev libboost-dev libfmt-dev catch2
  libyaml-cpp-dev libcli11-dev libedit-dev libtinyxml2-dev nlohmann-json3-dev libassimp-dev
  libbenchmark-dev
  # The Python module (python/, docs/python.md) and its tests; jsonschema validates every JSON
  # document asimov writes against docs/schema/.
  pybind11-dev python3-dev python3-numpy python3-pytest python3-jsonschema
)
# Peers for bench/ only (FCL, Bullet, KDL, Lua 5.4); the peer benchmarks are skipped without them.
if [ "${ASIMOV_WITH_PEERS:-1}" = 1 ]; then
  packages+=(libfcl-dev libbullet-dev liborocos-kdl-dev lua5.4)
fi
# The sanitizer lane and the fuzz targets of scripts/test.sh (issue 17): clang 14 with its
# sanitizer and libFuzzer runtimes.
if [ "${ASIMOV_WITH_SANITIZERS:-1}" = 1 ]; then
  packages+=(clang libclang-rt-14-dev)
fi
# Plots of the work-precision reports (scripts/accuracy.sh); nothing else needs them.
if [ "${ASIMOV_WITH_PLOTS:-1}" = 1 ]; then
  packages+=(python3-matplotlib)
fi

# The 3D replay page (`asimov run --replay`): node/npm fetch three.js from the npm registry into
# app/replay/node_modules (npm ci, the versions of app/replay/package-lock.json). Debian's
# nodejs and npm only when no npm is on the PATH (some nodejs packages bundle npm and conflict
# with Debian's).
if [ "${ASIMOV_WITH_REPLAY:-1}" = 1 ] && ! command -v npm >/dev/null 2>&1; then
  packages+=(nodejs npm)
fi
# The browser tests (tests/browser, label browser): Debian's chromium, driven by playwright-core
# from npm (never a browser download).
if [ "${ASIMOV_WITH_BROWSER:-1}" = 1 ]; then
  packages+=(chromium)
fi

# npm ci in app/replay, only when node_modules does not hold the locked three.js yet.
replay_npm() {
  [ "${ASIMOV_WITH_REPLAY:-1}" = 1 ] || return 0
  local dir
  dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/app/replay"
  if ! command -v npm >/dev/null 2>&1; then
    echo "install-deps: npm not found; asimov run --replay will say its viewer files are missing"
    return 0
  fi
  local want have
  want="$(node -e 'console.log(require(process.argv[1]).packages["node_modules/three"].version)' "$dir/package-lock.json")"
  have="$(node -e 'try{console.log(require(process.argv[1]).version)}catch(e){}' "$dir/node_modules/three/package.json")"
  if [ "$want" = "$have" ]; then
    echo "install-deps: three.js $have present in app/replay"
    return 0
  fi
  echo "install-deps: npm ci in app/replay (three.js $want)"
  (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
}

# npm ci in another folder of the repository (the studio's page, the browser tests), only when
# its node_modules does not match its lock file yet (npm writes node_modules/.package-lock.json).
npm_folder() {
  local dir
  dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/$1"
  [ -f "$dir/package-lock.json" ] || return 0
  if ! command -v npm >/dev/null 2>&1; then
    echo "install-deps: npm not found; $1 not installed"
    return 0
  fi
  if [ -f "$dir/node_modules/.package-lock.json" ] &&
     node -e 'const a=require(process.argv[1]).packages,b=require(process.argv[2]).packages;for(const k in a)if(k&&!a[k].optional&&(!b[k]||b[k].version!==a[k].version))process.exit(1)' \
       "$dir/package-lock.json" "$dir/node_modules/.package-lock.json" 2>/dev/null; then
    echo "install-deps: $1 node_modules present"
    return 0
  fi
  echo "install-deps: npm ci in $1"
  (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
}
npm_all() {
  replay_npm
  npm_folder app/serve/web
  [ "${ASIMOV_WITH_BROWSER:-1}" = 1 ] && npm_folder tests/browser
  return 0
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  npm_all
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
npm_all
