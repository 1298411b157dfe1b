#!/usr/bin/env bash
# pip install of the Python package (pyproject.toml, meson-python) into a temporary venv
# made with --system-site-packages (Debian's numpy / cffi), offline and without build
# isolation; then, from a folder outside the source tree and with no variable pointing
# at the build tree, tests/python/install_check.py runs a scene (python -m elastopt run,
# the Sim API), a Python optimizer converging on steps, and a small benchmark (python -m
# elastopt bench, elastopt.run_bench). The pip build is kept small: optional backends
# off (a native file's [project options]: pip 23.0 keeps only the last of repeated
# --config-settings keys), its build folder in the temporary folder.
# Skipped (77) without Debian's python3, python3-mesonpy, venv (python3-venv), numpy or cffi.
set -u
PY=/usr/bin/python3
SRC="${EO_SOURCE_ROOT:?}"
[ -x "$PY" ] || { echo "SKIP: $PY not installed"; exit 77; }
"$PY" -c 'import mesonpy' 2>/dev/null || { echo "SKIP: python3-mesonpy not installed (apt-get install python3-mesonpy)"; exit 77; }
"$PY" -c 'import numpy, cffi' 2>/dev/null || { echo "SKIP: python3-numpy / python3-cffi not installed"; exit 77; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$PY" -m venv --system-site-packages "$tmp/venv" > "$tmp/venv.log" 2>&1 ||
  { cat "$tmp/venv.log"; echo "SKIP: python3 -m venv failed (apt-get install python3-venv)"; exit 77; }
cat > "$tmp/small.ini" <<'EOF'
[project options]
petsc = 'disabled'
hypre = 'disabled'
tetgen = 'disabled'
nlopt = 'disabled'
ipopt = 'disabled'
EOF
unset ELASTOPT_LIB ELASTOPT_CLI ELASTOPT_BENCH_LIB EO_BUILD_ROOT EO_PY_ABI EO_SOURCE_ROOT EO_SHARED \
      PYTHONPATH LD_LIBRARY_PATH
export PIP_NO_INPUT=1 PIP_DISABLE_PIP_VERSION_CHECK=1 PYTHONDONTWRITEBYTECODE=1
echo "pip install --no-build-isolation --no-index --config-settings=builddir=$tmp/build" \
     "--config-settings=setup-args=--native-file=$tmp/small.ini $SRC"
if ! "$tmp/venv/bin/python" -m pip install --no-build-isolation --no-index \
     --config-settings=builddir="$tmp/build" \
     --config-settings=setup-args=--native-file="$tmp/small.ini" "$SRC" > "$tmp/pip.log" 2>&1; then
  tail -60 "$tmp/pip.log"
  echo "FAIL: pip install"
  exit 1
fi
tail -1 "$tmp/pip.log"
mkdir "$tmp/work" && cp "$SRC/tests/python/install_check.py" "$tmp/work/" && cd "$tmp/work" &&
  "$tmp/venv/bin/python" install_check.py "$SRC"
