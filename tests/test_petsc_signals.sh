#!/usr/bin/env bash
# Signals to the ranks of a distributed run (suite 'petsc'; cli/cmd_run.c, docs/petsc.md):
#  1. SIGTERM to both ranks mid-run: every rank exits 143 (as the serial CLI), mpirun too;
#     summary.json "interrupted" with the completed steps, every rank's restart file at
#     that step, no scratch folder in $TMPDIR; `--restart` to 2 steps more gives the same
#     bits as an uninterrupted run of that many steps (CG + Jacobi: a linear solver that
#     gives the same bits in every run);
#  2. SIGINT to rank 1 alone: both ranks stop at the same step and exit 130 (the signal
#     number is shared, rank 0 does not make it a SIGTERM), the run is marked interrupted,
#     no scratch folder left.
# Each rank runs under a wrapper that records its exit status. Skipped (77) without the
# backend or mpirun.
. "$(dirname "$0")/petsc_common.sh"
export WD=$tmp
J=(-o solver.backend=petsc -o solver.petsc_ksp.ksp=cg -o solver.petsc_ksp.pc=jacobi)

# 1. SIGTERM to both ranks
d=$tmp/term
"${mpi[@]}" -x WD "$rank_wrap" "$ELASTOPT" run --scene twist -o time.steps=400 "${J[@]}" --out "$d" -q \
    > "$tmp/term.log" 2>&1 &
mp=$!
check wait_steps "$d" 2
kill -TERM $(cat "$tmp/pid.0" "$tmp/pid.1")
wait $mp
check [ $? -eq 143 ]
check [ "$(cat "$tmp/rc.0")" = 143 ]
check [ "$(cat "$tmp/rc.1")" = 143 ]
check [ "$(sfield "$d" status)" = interrupted ]
check [ "$(sfield "$d" stop_reason)" = interrupted ]
k=$(sfield "$d" steps_run)
check [ "$k" -ge 2 ]
check [ "$(($(wc -l < "$d/steps.csv") - 1))" -eq "$k" ]
for r in 0 1; do check [ "$(head -c 200 "$d/restart.dat.$r-of-2" | sed -n 2p)" = "step $k" ]; done
check no_scratch
n=$((k + 2))
timeout 120 "${mpi[@]}" "$ELASTOPT" run --restart "$d" -o time.steps=$n -q
check [ $? -eq 0 ]
timeout 120 "${mpi[@]}" "$ELASTOPT" run --scene twist -o time.steps=$n "${J[@]}" --out "$tmp/straight" -q
check [ $? -eq 0 ]
for f in restart.dat restart.dat.0-of-2 restart.dat.1-of-2; do check cmp "$d/$f" "$tmp/straight/$f"; done
check same_steps "$d" "$tmp/straight"
check [ "$(sfield "$d" status)" = finished ]
check no_scratch

# 2. SIGINT to rank 1 alone
rm -f "$tmp"/pid.* "$tmp"/rc.*
d=$tmp/int
"${mpi[@]}" -x WD "$rank_wrap" "$ELASTOPT" run --scene twist -o time.steps=400 "${J[@]}" --out "$d" -q \
    > "$tmp/int.log" 2>&1 &
mp=$!
check wait_steps "$d" 2
kill -INT "$(cat "$tmp/pid.1")"
wait $mp
check [ $? -eq 130 ]
check [ "$(cat "$tmp/rc.0")" = 130 ]
check [ "$(cat "$tmp/rc.1")" = 130 ]
check [ "$(sfield "$d" status)" = interrupted ]
k=$(sfield "$d" steps_run)
for r in 0 1; do check [ "$(head -c 200 "$d/restart.dat.$r-of-2" | sed -n 2p)" = "step $k" ]; done
check no_scratch

[ $fail -eq 0 ] && echo "petsc_signals: all checks passed"
exit $fail
