#!/usr/bin/env bash
# Installs what is missing, builds everything (Release) and runs the whole test suite. The suite
# includes (CTest labels install, python) an install into build/install-test, an external
# project built and run against it (tests/consumer), and the Python module's pytest tests.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
ctest --test-dir build --output-on-failure -j2
