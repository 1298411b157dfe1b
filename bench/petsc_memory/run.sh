#!/usr/bin/env bash
# Peak resident memory per MPI rank (getrusage ru_maxrss through /usr/bin/time -f %M) of the
# generated twist on 1, 2, 4 ranks with the PETSc backend (CG + GAMG), one whole step (not
# capped: a step stopped at solver.max_iters goes on with the scene's solver.fallback
# entry, which builds a second linear solver beside the first — the former cap of two
# iterations measured two GAMG hierarchies). Also the CPU seconds (user + system) per rank.
# usage: [PC=gamg|jacobi|mumps] [EXTRA="-o key=value ..."] bench/petsc_memory/run.sh ELASTOPT OUTDIR "NX,NY,NZ" [RANKS...]
# PC=jacobi (CG capped at 20 iterations): the preconditioner holds almost nothing, so the
# peak is the problem itself (mesh, step engine, Hessian); gamg (default): as used in
# practice; mumps: the direct solve (ksp = preonly). EXTRA: more options for every run
# (e.g. PETSc options such as -pc_gamg_threshold 0.01).
# Writes OUTDIR/rss-<cells>-<pc>-<ranks>.<rank> ("KB user sys") and prints one line per run.
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
    "${mpi[@]}" -n "$p" bash -c '/usr/bin/time -f "%M %U %S" -o "$0.${OMPI_COMM_WORLD_RANK:-0}" "$@"; exit 0' \
        "$out/rss-$tag" "$E" run --scene twist -o "mesh.generate.cells=[$cells]" -o time.steps=1 \
        -o output.vtu=false -o solver.backend=petsc -o solver.petsc_ksp.ksp=$ksp \
        -o solver.petsc_ksp.pc=$pc -o solver.petsc_ksp.max_lin_iters=$([ "$pc" = jacobi ] && echo 20 || echo 10000) ${extra[@]+"${extra[@]}"} --out "$out/run-$tag" --force -q -v > "$out/log-$tag" 2>&1
    printf "cells [%s] %s ranks %d: peak RSS per rank (MB):" "$cells" "$pc" "$p"
    for r in $(seq 0 $((p - 1))); do printf " %.0f" "$(tail -1 "$out/rss-$tag.$r" 2>/dev/null | awk '{print $1 / 1024}')"; done
    printf "; CPU s per rank:"
    for r in $(seq 0 $((p - 1))); do printf " %.1f" "$(tail -1 "$out/rss-$tag.$r" 2>/dev/null | awk '{print $2 + $3}')"; done
    printf "; %s\n" "$(grep -o '[0-9]* iterations,' "$out/log-$tag" | tail -1)"
done
