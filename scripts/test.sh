#!/usr/bin/env bash
# Installs what is missing, builds everything (Release) and runs the whole test suite; then the
# sanitizer lane and the fuzz smoke run (issue 17) when asked for. Each lane prints its wall time.
#   ASIMOV_SANITIZER_LANE=1  adds the ASan + UBSan build (clang: with the fuzz targets) and its suite
#                            without the randomized brute-force comparisons and the long stiff
#                            programs (asan_skip below: they ran 2-25 min each under ASan). Off
#                            by default: its whole run on 2 cores is not yet measured to fit.
#   ASIMOV_FUZZ_SECONDS=N    new inputs per fuzz target in the smoke run (default 60; 0 skips it)
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

[ "${ASIMOV_SANITIZER_LANE:-0}" = 1 ] || exit 0

# ASan + UBSan, every finding fatal. With clang (libFuzzer) the same build has the fuzz targets,
# whose corpus replays are part of its suite; with gcc only the suite.
start=$SECONDS
compiler=(-DCMAKE_CXX_COMPILER=g++)
fuzz=OFF
if command -v clang++ >/dev/null 2>&1; then compiler=(-DCMAKE_CXX_COMPILER=clang++); fuzz=ON; fi
cmake -S . -B build-asan "${compiler[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -g1 -DNDEBUG" \
  -DASIMOV_SANITIZE=ON -DASIMOV_BUILD_FUZZ=$fuzz -DASIMOV_BUILD_BENCH=OFF
cmake --build build-asan -j2
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:check_initialization_order=1:detect_stack_use_after_return=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
# Measured under ASan on the shared 2 cores (issue 17): the brute-force oracles of collision/,
# the random IK round trips of robots/, gap stepping and programs/stiff (long_draw alone > 10
# min) took 1-25 min each; their code is covered by the faster tests that stay. Timing asserts
# ("set up in seconds") are release-build properties: skipped here too.
asan_skip='brute force|FK\(IK\(T\)\) round trips|IK round trips for both elbows|numeric IK converges'
asan_skip+='|spherical wrist: all solutions|gap stepping: the same first contact|step displacement bound covers'
asan_skip+='|which body is A|^programs: stiff$|set up in seconds|a chain deeper than the limit'
ctest --test-dir build-asan --output-on-failure -j2 --timeout 900 -E "$asan_skip"
lane "sanitizer build + suite" $((SECONDS - start))

seconds="${ASIMOV_FUZZ_SECONDS:-60}"
if [ "$fuzz" = ON ] && [ "$seconds" -gt 0 ]; then
  start=$SECONDS
  ./fuzz/run.sh build-asan "$seconds"
  lane "fuzz smoke (${seconds} s per target)" $((SECONDS - start))
fi
