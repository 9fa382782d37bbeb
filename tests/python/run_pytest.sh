#!/bin/sh
# CTest's `python: pytest` (tests/CMakeLists.txt): pytest over tests/python with the build tree's
# module. Exit 77 (skipped) when the interpreter lacks pytest or numpy; pytest's exit 5 (no test
# collected, e.g. a filter that matches nothing) is a failure with a message, not a silent pass.
#   run_pytest.sh PYTHON TESTS_DIR [pytest args...]
python=$1 dir=$2
shift 2
if ! "$python" -c 'import pytest, numpy' 2>/dev/null; then
  echo "$python cannot import pytest and numpy (Debian: python3-pytest, python3-numpy)"
  exit 77
fi
"$python" -m pytest -q -p no:cacheprovider "$dir" "$@"
rc=$?
[ "$rc" -eq 5 ] && echo "pytest collected no test in $dir" && exit 1
exit "$rc"
