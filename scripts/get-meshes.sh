#!/usr/bin/env bash
# The real meshes that some examples, benchmark scenes and tests read from ../shared/meshes
# (the project's shared folder beside the repository; a clone does not have it).
#
#   bash scripts/get-meshes.sh                    # say where each file comes from, which are present
#   bash scripts/get-meshes.sh --download DIR     # fetch the IPC tet meshes into DIR (curl or wget)
#   bash scripts/get-meshes.sh --substitute DIR   # write a generated stand-in bar (no network)
#
# Use DIR = ../shared/meshes (relative to the repository) for the scenes and tests to find
# them. Tests and benchmark scenes that need a missing file are skipped with a message.
set -euo pipefail
cd "$(dirname "$0")/.."
base=https://raw.githubusercontent.com/ipc-sim/IPC/master/input/tetMeshes
# local name : file in ipc-sim/IPC input/tetMeshes : what
files=(
  "ipc_bar-2523.msh:bar-2523.msh:bar 10 x 0.5 x 1, 886 vertices, 2523 tets"
  "ipc_bar-14114.msh:bar-14114.msh:the same bar, 3842 vertices, 14114 tets"
  "ipc_bunny.msh:bunny.msh:Stanford bunny (y-up), 4670 vertices, 19379 tets"
  "ipc_Armadillo13K.msh:Armadillo13K.msh:Stanford armadillo (y-up), 13230 vertices, 54985 tets"
)
credit="Source: the IPC project (ipc-sim/IPC, input/tetMeshes, MIT licence, IPC authors); the
bunny and armadillo geometry is from the Stanford 3D Scanning Repository (research use,
credit Stanford)."

case "${1:-}" in
  "")
    echo "Real meshes read from ../shared/meshes (Gmsh MSH 4.1 ASCII):"
    for f in "${files[@]}"; do
      IFS=: read -r name src what <<< "$f"
      if [ -f "../shared/meshes/$name" ]; then state=present; else state=absent; fi
      printf '  %-22s %-8s %s (IPC %s)\n' "$name" "$state" "$what" "$src"
    done
    echo "$credit"
    echo "Fetch them: bash scripts/get-meshes.sh --download ../shared/meshes"
    echo "No network: bash scripts/get-meshes.sh --substitute DIR writes a generated bar."
    ;;
  --download)
    dir=${2:?usage: get-meshes.sh --download DIR}
    mkdir -p "$dir"
    for f in "${files[@]}"; do
      IFS=: read -r name src _ <<< "$f"
      [ -f "$dir/$name" ] && { echo "have $dir/$name"; continue; }
      echo "fetch $base/$src -> $dir/$name"
      if command -v curl >/dev/null; then curl -fsSL -o "$dir/$name.part" "$base/$src"
      else wget -q -O "$dir/$name.part" "$base/$src"; fi
      mv "$dir/$name.part" "$dir/$name"
    done
    echo "$credit"
    ;;
  --substitute)
    dir=${2:?usage: get-meshes.sh --substitute DIR}
    exe=${ELASTOPT:-build/cli/elastopt}
    mkdir -p "$dir"
    # a bar of the IPC bar's size (10 x 0.5 x 1) with about as many tets (40x2x4 cells x 6)
    "$exe" convert gen:10,0.5,1:40,2,4:6 "$dir/bar-generated.msh"
    echo "wrote $dir/bar-generated.msh: a generated stand-in for ipc_bar-2523.msh (not the same"
    echo "mesh: results differ). The bunny and armadillo have no generated substitute."
    ;;
  *) echo "usage: get-meshes.sh [--download DIR | --substitute DIR]" >&2; exit 2 ;;
esac
