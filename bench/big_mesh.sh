#!/bin/sh
# Big meshes through `asimov run` (docs/collision.md §13): peak RSS, wall and CPU time of
# programs/demo/crash.v2 in the default cell's arm with one more object, a closed bumpy torus STL
# of N faces (bench/make_big_stl.cpp) whose tube lies where the crash program's box is, so the
# arm reaches it and the torus's grid is built (halvings: auto). Also the same run without the
# torus (the process's own baseline). The STL files go to a scratch folder (default /tmp/asimov-big),
# never into the repository.
#   bench/big_mesh.sh [BUILD_DIR] [FACES ...]     (default: build 1000000 10000000)
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
[ $# -gt 0 ] && shift
[ $# -gt 0 ] || set -- 1000000 10000000
scratch=${ASIMOV_BIG_DIR:-/tmp/asimov-big}
mkdir -p "$scratch"
cell() {  # cell() NAME [MESH]: the default cell's arm and tool, the torus instead of the table and box
  {
    echo "robot: puma560"
    echo "tool: [0, 0, 200, 0, 0, 0]"
    echo "tool_shape: {box: [50, 80, 140], at: [0, 0, 130, 0, 0, 0]}"
    [ $# -gt 1 ] && echo "objects: [{name: torus, mesh: $2, at: [1600, 250, -300, 0, 0, 0]}]"
    echo "collision: {halvings: auto, step_mm: 1.0, clearance_mm: 0}"
  } > "$scratch/$1.yaml"
}
measure() {  # measure() LABEL CELL FACES
  /usr/bin/time -v -o "$scratch/time.txt" "$build/app/asimov" run "$here/programs/demo/crash.v2" --cell "$2" > "$scratch/run.out" 2>&1 || true
  rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$scratch/time.txt")
  wall=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$scratch/time.txt")
  user=$(sed -n 's/.*User time (seconds): //p' "$scratch/time.txt")
  sys=$(sed -n 's/.*System time (seconds): //p' "$scratch/time.txt")
  # The first VAL-style message: the collision, or an error (then the figures are not the mesh's).
  halt=$(grep -o '^\*[A-Za-z ]*\*.*' "$scratch/run.out" | head -1 || true)
  if [ "$3" -gt 0 ]; then per=$(awk -v r="$rss" -v f="$3" 'BEGIN { printf "%.1f", r * 1024 / f }'); else per=-; fi
  echo "$1: peak RSS $((rss / 1024)) MiB ($per B/face), wall $wall, user $user s, sys $sys s; ${halt:-no collision}"
}
uptime
cell none
measure "no torus" "$scratch/none.yaml" 0
for n in "$@"; do
  stl="$scratch/torus_$n.stl"
  [ -f "$stl" ] || "$build/bench/make_big_stl" "$n" "$stl" > /dev/null
  faces=$(od -An -tu4 -j80 -N4 "$stl" | tr -d ' ')
  cell "torus_$n" "$stl"
  measure "$faces faces" "$scratch/torus_$n.yaml" "$faces"
done
