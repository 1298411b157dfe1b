#!/usr/bin/env bash
# The mesh corpus benchmark in one command (docs/corpus.md).
#
#   bash scripts/corpus.sh quick [--out DIR]   # bench/corpus-quick.json: ~3 min of processor time
#   bash scripts/corpus.sh full  [--out DIR]   # bench/corpus-full.json: hours (see docs/corpus.md)
#   bash scripts/corpus.sh methods [--out DIR] # bench/corpus-methods.json: the newer methods, ~1 h
#   bash scripts/corpus.sh check               # manifest against the stored files (fast)
#
# Builds ./build if needed (scripts/setup.sh), prepares the suite's meshes into build/corpus
# (decompressed, tetrahedralized by TetGen, normalized; counts checked against
# bench/corpus/manifest.json), then runs `elastopt bench`. The stored files are read from
# bench/corpus/data (ELASTOPT_CORPUS_DATA=DIR overrides; the four shared IPC meshes from
# ../shared/meshes); scenes whose mesh is absent
# are dropped with a note. Default output: bench/results/corpus-<suite>.
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-}
shift || true
out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=${2:?--out needs a folder}; shift 2 ;;
    *) echo "corpus.sh: unknown argument '$1' (usage: corpus.sh quick|full|methods|check [--out DIR])" >&2; exit 2 ;;
  esac
done
py=/usr/bin/python3
case "$what" in
  check) exec "$py" scripts/corpus.py check ;;
  quick|full|methods) ;;
  *) echo "usage: bash scripts/corpus.sh quick|full|methods|check [--out DIR]" >&2; exit 2 ;;
esac
[ -x build/cli/elastopt ] || bash scripts/setup.sh
suite=bench/corpus-$what.json
"$py" scripts/corpus.py prepare --suite "$suite"
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
exec ./build/cli/elastopt bench "$suite" --out "${out:-bench/results/corpus-$what}"
