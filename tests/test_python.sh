#!/usr/bin/env bash
# The Python package (python/elastopt) from the source tree: PYTHONPATH=python, the build
# tree's libelastopt.so. Skipped (77) without Debian's python3, numpy or cffi.
# Usage: test_python.sh ELASTOPT_CLI PY_ABI
set -u
PY=/usr/bin/python3
[ -x "$PY" ] || { echo "SKIP: $PY not installed"; exit 77; }
"$PY" -c 'import numpy, cffi' 2>/dev/null || { echo "SKIP: python3-numpy / python3-cffi not installed"; exit 77; }
SRC="${EO_SOURCE_ROOT:?}"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
export PYTHONPATH="$SRC/python" ELASTOPT_CLI="$(realpath "$1")" EO_PY_ABI="$(realpath "$2")" EO_TMP="$tmp" PYTHONDONTWRITEBYTECODE=1
unset ELASTOPT_LIB
# a sanitizer build: the interpreter must load the ASan runtime first (LD_PRELOAD); the
# interpreter's own allocations are not ours to check for leaks
asan=$(ldd "$ELASTOPT_CLI" 2>/dev/null | awk '/libasan/ {print $3; exit}')
if [ -n "$asan" ]; then
    export LD_PRELOAD="$asan" ASAN_OPTIONS="detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
fi
cd "$SRC/tests/python" && "$PY" -m unittest -v test_elastopt
