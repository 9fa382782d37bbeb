#!/usr/bin/env bash
# The README's test command and the CI's (.ci/run): installs what is missing, then three lanes,
# each printing its wall time (docs/testing.md: the budget, the split, the long versions).
#  1. release: build everything (Release) and run the whole suite.
#  2. sanitizer: the suite built with ASan + UBSan (clang when present: with the fuzz targets,
#     whose committed corpora CTest replays), every finding fatal, each test at most 300 s,
#     without the tests listed in scripts/asan-skip.txt (measured there: minutes each under ASan;
#     their code paths are covered by faster tests that stay) and without the labels install
#     and python (packaging, not memory safety: lane 1 runs them) and browser (chromium's own
#     time; the studio's session code runs under the sanitizers in test_app's serve tests).
#       ASIMOV_SANITIZER_LANE=0     skips it;  =full  runs every test, the skipped ones too
#  3. fuzz smoke (clang only): every fuzz target over its committed corpus, then
#     ASIMOV_FUZZ_SECONDS (default 60; 0 skips) of new inputs, two targets at a time.
# The suite includes (CTest labels install, python) an install into build/install-test, an external
# project built and run against it (tests/consumer), and the Python module's pytest tests.
set -euo pipefail
cd "$(dirname "$0")/.."
lane() { echo "lane: $1: $2 s"; }

start=$SECONDS
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
ctest --test-dir build --output-on-failure -j2
lane "release build + suite" $((SECONDS - start))

mode="${ASIMOV_SANITIZER_LANE:-1}"
[ "$mode" != 0 ] || exit 0

# ASan + UBSan, every finding fatal. With clang (libFuzzer) the same build has the fuzz targets;
# with gcc only the suite. -O1 -g1: the level ASan's documentation suggests (exact reports with
# line numbers); the Python module is not built (it would need the ASan runtime preloaded).
start=$SECONDS
# With clang every warning is an error in this lane (issue 17 found clang-only warnings the
# release build with gcc never printed); gcc's own are the release lane's.
compiler=(-DCMAKE_CXX_COMPILER=g++)
fuzz=OFF
if command -v clang++ >/dev/null 2>&1; then compiler=(-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS=-Werror); fuzz=ON; fi
cmake -S . -B build-asan "${compiler[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -g1 -DNDEBUG" \
  -DASIMOV_SANITIZE=ON -DASIMOV_BUILD_FUZZ=$fuzz -DASIMOV_BUILD_BENCH=OFF -DASIMOV_BUILD_PYTHON=OFF
cmake --build build-asan -j2
lane "sanitizer build" $((SECONDS - start))
start=$SECONDS
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:check_initialization_order=1:detect_stack_use_after_return=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
# One regular expression per line of asan-skip.txt (after '#': the measured time, why).
skip="$(sed -e 's/[[:space:]]*#.*//' -e '/^[[:space:]]*$/d' scripts/asan-skip.txt | paste -sd'|')"
exclude=(-E "$skip")
[ "$mode" != full ] || exclude=()
ctest --test-dir build-asan --output-on-failure -j2 --timeout 300 -LE 'install|python|browser' "${exclude[@]}"
lane "sanitizer suite" $((SECONDS - start))

seconds="${ASIMOV_FUZZ_SECONDS:-60}"
if [ "$fuzz" = ON ] && [ "$seconds" -gt 0 ]; then
  start=$SECONDS
  status=0
  ./fuzz/run.sh build-asan "$seconds" load run monitor & first=$!
  ./fuzz/run.sh build-asan "$seconds" cell mesh urdf paths || status=1
  wait "$first" || status=1
  lane "fuzz smoke (${seconds} s per target)" $((SECONDS - start))
  exit $status
fi
