#!/usr/bin/env bash
# The real-mesh scene of the PETSc tests (test_petsc.sh, test_petsc_parity.sh): the IPC bar
# (886 vertices, 2523 tets, Gmsh) of ../shared/meshes, one end fixed, the other rotating,
# under gravity, newmark. usage: petsc_bar_scene.sh MESH STEPS FIX > scene.json
cat <<JSON
{"mesh": {"file": "$1"},
 "material": {"model": "stable_neo_hookean", "E": 1e6, "nu": 0.4, "density": 1000},
 "gravity": [0, 0, -9.81],
 "boundary": [
  {"box": [[-1, -1, -1], [0, 2, 2]], "fixed": true},
  {"box": [[10, -1, -1], [11, 2, 2]], "rotate": {"axis": [1, 0, 0], "center": [0, 0.25, 0.5], "rate": 3}}],
 "time": {"integrator": "newmark", "dt": 0.02, "steps": $2},
 "solver": {"optimizer": "newton", "hessian_fix": "$3"}}
JSON
