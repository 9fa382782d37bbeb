#!/bin/sh
# The install tests of tests/CMakeLists.txt (label install), against a throw-away prefix.
#   install_test.sh install  BUILD PREFIX          cmake --install BUILD --prefix PREFIX (fresh)
#   install_test.sh consumer PREFIX SOURCE_DIR     builds tests/consumer against PREFIX and runs it
#   install_test.sh python   PREFIX PYTHON SRC     the installed module runs crash.v2
#   install_test.sh exe      PREFIX                the installed asimov: --version, a run with
#                                                  --replay (assets found beside the executable)
set -eu
mode=$1
case "$mode" in
  install)
    rm -rf "$3"
    cmake --install "$2" --prefix "$3" >/dev/null
    echo "installed into $3: $(find "$3" -type f | wc -l) files"
    ;;
  consumer)
    prefix=$2 src=$3/tests/consumer bin=$2/consumer-build
    rm -rf "$bin"
    launcher=
    command -v ccache >/dev/null && launcher=-DCMAKE_CXX_COMPILER_LAUNCHER=ccache
    cmake -S "$src" -B "$bin" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" $launcher >/dev/null
    cmake --build "$bin" -j2 >/dev/null
    "$bin/consumer" "$prefix/share/asimov/programs"
    ;;
  exe)
    prefix=$2 out=$2/exe-test
    rm -rf "$out" && mkdir -p "$out"
    "$prefix/bin/asimov" --version
    unset ASIMOV_REPLAY_DIR
    if [ ! -f "$prefix/share/asimov/replay/three.module.min.js" ]; then
      echo "three.js not installed (npm ci in app/replay): replay not tried"
      exit 77
    fi
    rc=0
    "$prefix/bin/asimov" run "$prefix/share/asimov/programs/demo/crash.v2" --replay "$out/crash.html" >/dev/null 2>&1 || rc=$?
    [ "$rc" -eq 3 ] || { echo "installed asimov run crash.v2: exit $rc, expected 3"; exit 1; }
    grep -q 'id="asimov-replay-viewer"' "$out/crash.html"
    echo "replay page written by the installed asimov: $(wc -c <"$out/crash.html") bytes"
    ;;
  python)
    PYTHONPATH="$2/lib/python3/dist-packages" "$3" -c '
import sys, asimov
assert asimov.__file__.startswith(sys.argv[1]), asimov.__file__
bodies = asimov.run(sys.argv[2] + "/programs/demo/crash.v2")["collision"]["bodies"]
print("installed", asimov.__file__, bodies)
assert bodies == ["link4", "box"]
' "$2" "$4"
    ;;
  *) echo "install_test.sh: unknown mode $mode" >&2; exit 1 ;;
esac
