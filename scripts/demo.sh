#!/usr/bin/env bash
# Installs what is missing, builds asimov (Release) and runs the demo in the built-in cell.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
echo "== pick_place.v2: completes =="
./build/app/asimov run programs/demo/pick_place.v2 --report build/pick_place.report.json
echo "== crash.v2: drives the arm into the box (exit 3 expected) =="
rc=0
./build/app/asimov run programs/demo/crash.v2 --report build/crash.report.json || rc=$?
echo "exit code $rc; report in build/crash.report.json"
[ "$rc" -eq 3 ]
