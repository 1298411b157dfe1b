#!/usr/bin/env bash
# Install whatever is missing (Debian 12 packages), configure and build into ./build.
# Usage: bash scripts/setup.sh [extra meson setup options]   (default --buildtype=release)
set -euo pipefail
cd "$(dirname "$0")/.."
pkgs=(meson ninja-build pkg-config gcc liblapacke-dev libopenblas-dev libsuitesparse-dev
      libnlopt-dev coinor-libipopt-dev libhypre-dev libjansson-dev gnuplot-nox valgrind python3-jsonschema
      g++ libtet1.5-dev   # g++ + libtet1.5-dev: TetGen for surface meshes (-Dtetgen)
      python3-numpy python3-cffi python3-scipy   # the Python package (python/elastopt)
      python3-mesonpy python3-venv               # pip install of it (pyproject.toml, docs/python.md)
      petsc-dev openmpi-bin libopenmpi-dev       # the PETSc / MPI backend (-Dpetsc) and its mpirun tests
      python3-sphinx python3-myst-parser doxygen python3-breathe)   # the documentation site (scripts/build-docs.sh)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
# The main build is a release build: the default run took 5-8% less CPU time
# than debugoptimized (bench/results/buildtype-amd-epyc-2cpu.txt) and the whole test
# suite passes in it (no test relies on assert). A later --buildtype=... in the
# arguments wins; a build dir for debugging: meson setup build-dbg --buildtype=debug.
if [ ! -f build/build.ninja ]; then
  meson setup build --buildtype=release "$@" >/dev/null
fi
ninja -C build >/dev/null
echo "setup: built ./build/cli/elastopt" >&2
