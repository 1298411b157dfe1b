#!/usr/bin/env bash
# A 4-rank run's partitioned output (one .vtu piece per rank and frame, a .pvtu per frame,
# the .pvd series) opened in ParaView (pvbatch, Debian's paraview + python3-paraview 5.11)
# and compared with the serial run's output: same frames, cells and points (the pieces'
# shared points merged), displacement ranges equal to 1e-8 (tests/petsc_paraview.py).
# Skipped (77) without the PETSc module, mpirun or pvbatch.
. "$(dirname "$0")/petsc_common.sh"
pvb=$(command -v pvbatch || command -v pvbatch3.11 || true)
[ -n "$pvb" ] || { echo "skip: no pvbatch (apt-get install paraview python3-paraview)"; exit 77; }
"$ELASTOPT" run --scene twist -o time.steps=3 --out "$tmp/s" -q || { echo "FAIL: serial run"; exit 1; }
timeout 120 mpirun -n 4 "${mpi_opts[@]}" "$ELASTOPT" run --scene twist -o time.steps=3 -o solver.backend=petsc \
    --out "$tmp/p" -q > "$tmp/p.log" 2>&1 || { echo "FAIL: 4-rank run"; cat "$tmp/p.log"; exit 1; }
(cd "$tmp" && timeout 300 "$pvb" "$here/petsc_paraview.py" "$tmp/s" "$tmp/p" 2>&1) | grep -v "^$" | tail -5 > "$tmp/pv.log"
cat "$tmp/pv.log"
grep -q "^paraview: OK" "$tmp/pv.log"
