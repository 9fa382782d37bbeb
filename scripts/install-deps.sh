#!/usr/bin/env bash
# Installs the Debian packages asimov needs, and only those that are missing.
# Idempotent: a second run calls no apt-get at all. Run as root (or with sudo available).
set -euo pipefail

packages=(
  build-essential cmake ccache pkg-config
  libeigen3-dev libboost-dev libfmt-dev catch2
  libyaml-cpp-dev libcli11-dev libedit-dev libtinyxml2-dev nlohmann-json3-dev
  libbenchmark-dev
)
# Peers for bench/ only (FCL, KDL, Lua 5.4); the peer benchmarks are skipped without them.
if [ "${ASIMOV_WITH_PEERS:-1}" = 1 ]; then
  packages+=(libfcl-dev liborocos-kdl-dev lua5.4)
fi
# Plots of the work-precision reports (scripts/accuracy.sh); nothing else needs them.
if [ "${ASIMOV_WITH_PLOTS:-1}" = 1 ]; then
  packages+=(python3-matplotlib)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
