#!/usr/bin/env bash
# Peak resident memory per MPI rank (getrusage ru_maxrss through /usr/bin/time -f %M) of the
# generated twist on 1, 2, 4 ranks with the PETSc backend (CG + GAMG), one step capped at
# two Newton iterations (the peak is reached at the first Hessian and GAMG setup or
# factorization).
# usage: [PC=gamg|jacobi|mumps] [EXTRA="-o key=value ..."] bench/petsc_memory/run.sh ELASTOPT OUTDIR "NX,NY,NZ" [RANKS...]
# PC=jacobi (CG capped at 20 iterations): the preconditioner holds almost nothing, so the
# peak is the problem itself (mesh, step engine, Hessian); gamg (default): as used in
# practice; mumps: the direct solve (ksp = preonly). EXTRA: more options for every run
# (e.g. PETSc options such as -pc_gamg_threshold 0.01).
# Writes OUTDIR/rss-<cells>-<ranks>.<rank> (KB) and prints one line per run.
set -u
E=$1; out=$2; cells=$3; shift 3
ranks=("${@:-1 2 4}")
pc=${PC:-gamg}
ksp=cg
[ "$pc" = mumps ] && ksp=preonly
read -r -a extra <<< "${EXTRA:-}"
mkdir -p "$out"
mpi=(mpirun --oversubscribe --mca mpi_yield_when_idle 1)
[ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)
for p in ${ranks[@]}; do
    tag=$(echo "$cells" | tr ',' 'x')-$pc-$p
    rm -f "$out"/rss-"$tag".*
    "${mpi[@]}" -n "$p" bash -c '/usr/bin/time -f %M -o "$0.${OMPI_COMM_WORLD_RANK:-0}" "$@"; exit 0' \
        "$out/rss-$tag" "$E" run --scene twist -o "mesh.generate.cells=[$cells]" -o time.steps=1 \
        -o solver.max_iters=2 -o output.vtu=false -o solver.backend=petsc -o solver.petsc_ksp.ksp=$ksp \
        -o solver.petsc_ksp.pc=$pc -o solver.petsc_ksp.max_lin_iters=$([ "$pc" = jacobi ] && echo 20 || echo 10000) ${extra[@]+"${extra[@]}"} --out "$out/run-$tag" --force -q -v > "$out/log-$tag" 2>&1
    printf "cells [%s] %s ranks %d: peak RSS per rank (MB):" "$cells" "$pc" "$p"
    for r in $(seq 0 $((p - 1))); do printf " %.0f" "$(echo "$(tail -1 "$out/rss-$tag.$r" 2>/dev/null || echo 0) / 1024" | bc -l)"; done
    echo
done
