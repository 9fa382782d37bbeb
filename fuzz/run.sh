#!/usr/bin/env bash
# fuzz/run.sh BUILD_DIR SECONDS [TARGET ...]
# Runs each libFuzzer target (default: all of fuzz/CMakeLists.txt) over its committed corpus
# fuzz/corpus/TARGET, then for SECONDS more on new inputs, one target at a time (at nice 19),
# with the limits of issue 17: 10 s per input, 2 GB of memory. New corpus entries go to a
# scratch folder (kept only with FUZZ_KEEP=1); a crash, timeout or out-of-memory input is saved
# as fuzz/findings/TARGET-* and the script exits 1. Prints one line per target: executions,
# coverage (cov: edges, ft: features), corpus size, seconds.
#   CI smoke: fuzz/run.sh build-asan 60      long run: fuzz/run.sh build-asan 3600 cell
# FUZZ_TIMEOUT=S (default 10) is libFuzzer's per-input limit in wall-clock seconds: at nice 19 on
# a busy machine an input gets a small share of a core, so long runs there take a larger limit
# and replay each slow input at normal priority (fuzz/README.md).
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "${1:?build dir}" && pwd)"
seconds="${2:?seconds}"
shift 2
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(load run monitor cell mesh urdf paths studio_message)
findings="$here/findings"
status=0
for t in "${targets[@]}"; do
  bin="$build/fuzz/fuzz_$t"
  if [ ! -x "$bin" ]; then echo "fuzz: $t: no $bin (configure with -DASIMOV_BUILD_FUZZ=ON, clang)"; status=1; continue; fi
  scratch="$(mktemp -d "${TMPDIR:-/tmp}/asimov-fuzz-$t.XXXXXX")"
  mkdir -p "$scratch/corpus" "$scratch/work"
  dict=()
  case "$t" in load|run) dict=(-dict="$here/dict/v2.dict") ;; monitor) dict=(-dict="$here/dict/monitor.dict") ;;
    cell) dict=(-dict="$here/dict/cell.dict") ;; mesh) dict=(-dict="$here/dict/mesh.dict") ;; urdf) dict=(-dict="$here/dict/urdf.dict") ;;
    paths) dict=(-dict="$here/dict/paths.dict") ;; esac
  start=$SECONDS
  # The monitor's STORE writes into the current folder: a scratch one.
  (cd "$scratch/work" && nice -n 19 "$bin" -max_total_time="$seconds" -timeout="${FUZZ_TIMEOUT:-10}" -rss_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 "${dict[@]}" -artifact_prefix="$scratch/" \
      "$scratch/corpus" "$here/corpus/$t") >"$scratch/log" 2>&1
  rc=$?
  took=$((SECONDS - start))
  done_line="$(grep -E '^#[0-9]+[[:space:]]+DONE' "$scratch/log" | tail -1)"
  [ -n "$done_line" ] || done_line="$(grep -E '^#[0-9]+' "$scratch/log" | tail -1)"
  execs="$(grep -E '^stat::number_of_executed_units' "$scratch/log" | awk '{print $2}')"
  cov="$(echo "$done_line" | grep -oE 'cov: [0-9]+' | awk '{print $2}')"
  ft="$(echo "$done_line" | grep -oE 'ft: [0-9]+' | awk '{print $2}')"
  corp="$(echo "$done_line" | grep -oE 'corp: [0-9]+' | awk '{print $2}')"
  echo "fuzz: $t: ${execs:-?} executions, cov ${cov:-?}, ft ${ft:-?}, corpus ${corp:-?}, ${took} s, exit $rc"
  artifacts=("$scratch"/crash-* "$scratch"/timeout-* "$scratch"/oom-* "$scratch"/leak-* "$scratch"/slow-unit-*)
  for a in "${artifacts[@]}"; do
    [ -e "$a" ] || continue
    mkdir -p "$findings"
    cp "$a" "$findings/$t-$(basename "$a")"
    echo "fuzz: $t: saved $findings/$t-$(basename "$a")"
  done
  if [ $rc -ne 0 ]; then
    echo "fuzz: $t: FAILED; the end of its log:"
    tail -60 "$scratch/log"
    status=1
  fi
  if [ "${FUZZ_KEEP:-0}" = 1 ]; then echo "fuzz: $t: corpus and log kept in $scratch"; else rm -rf "$scratch"; fi
done
exit $status
