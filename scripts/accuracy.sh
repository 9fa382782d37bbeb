#!/usr/bin/env bash
# Regenerates the work-precision reports: docs/accuracy.md, docs/accuracy/*.png and the JSON
# behind them. Builds only bench_accuracy (Release, no tests) in build-accuracy/, runs it and
# draws the plots with Debian's python3-matplotlib.
#
# usage: scripts/accuracy.sh [--clean]   --clean: remove build-accuracy/ first (a clean build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-accuracy
clean=no
for arg in "$@"; do
  case "$arg" in
    --clean) clean=yes ;;
    *) echo "usage: scripts/accuracy.sh [--clean]" >&2; exit 1 ;;
  esac
done

ASIMOV_WITH_PEERS=0 ./scripts/install-deps.sh
# /usr/bin/python3 is Debian's, with python3-matplotlib; another python3 on PATH may lack it.
python=/usr/bin/python3
if ! "$python" -c 'import matplotlib' 2>/dev/null; then
  echo "accuracy: $python cannot import matplotlib (install python3-matplotlib)" >&2
  exit 1
fi

t0=$(date +%s.%N)
[ "$clean" = yes ] && rm -rf "$build"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DASIMOV_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" --target bench_accuracy -j2
t1=$(date +%s.%N)
"$build/bench/bench_accuracy" docs/accuracy
t2=$(date +%s.%N)
ccache_state=off
[ -n "$(command -v ccache)" ] && [ "${CCACHE_DISABLE:-0}" != 1 ] && ccache_state=on
timing=$(awk -v a="$t0" -v b="$t1" -v c="$t2" -v clean="$clean" -v cc="$ccache_state" -v n="$(nproc)" 'BEGIN {
  printf "build %.0f s (%s build directory, ccache %s), measurements %.0f s, on %d cores", b - a,
         clean == "yes" ? "clean" : "existing", cc, c - b, n }')
"$python" scripts/accuracy_plots.py docs --timing "$timing"
t3=$(date +%s.%N)
total=$(awk -v a="$t0" -v b="$t3" 'BEGIN { printf "%.0f s", b - a }')
sed -i "s/@TOTAL@/$total/" docs/accuracy.md  # the page cannot time its own writing
echo "accuracy: $timing; total with plots $total"
