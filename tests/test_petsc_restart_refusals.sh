#!/usr/bin/env bash
# `elastopt run --restart` refused, under mpirun or not, before anything is written (suite
# 'petsc'; cli/cmd_run.c): exit 2, one message naming the cause, every file of the run
# byte-identical afterwards (summary.json stays "finished"), no new file, no scratch folder
# left in $TMPDIR:
#   a 2-rank run continued on 3 ranks, and on one process (the message names mpirun -n 2);
#   a serial run continued under mpirun;
#   a per-rank file missing, the two swapped (rank 0 would read rank 1's part), and one
#   from an earlier step (the ranks' files at different steps); the folder locked by
#   another live run.
# Then the run still continues on 2 ranks (exit 0, 5 steps). Skipped (77) without the
# backend or mpirun.
. "$(dirname "$0")/petsc_common.sh"
d=$tmp/run
timeout 120 "${mpi[@]}" "$ELASTOPT" run --scene twist -o time.steps=2 -o solver.backend=petsc --out "$d" -q
check [ $? -eq 0 ]
check [ "$(sfield "$d" status)" = finished ]
cp "$d/restart.dat.1-of-2" "$tmp/r1-step2"
timeout 120 "${mpi[@]}" "$ELASTOPT" run --restart "$d" -o time.steps=3 -q
check [ $? -eq 0 ]
cp -a "$d" "$tmp/before"
unchanged() { # the run's folder exactly as it was (names and bytes)
    diff -r "$tmp/before" "$d" > /dev/null && no_scratch
}
refused() { # refused LABEL PATTERN CMD...: exit 2, PATTERN in stderr (once), nothing changed
    local label=$1 pat=$2
    shift 2
    timeout 120 "$@" > "$tmp/out" 2> "$tmp/err"
    local rc=$?
    [ $rc -eq 2 ] || echo "FAIL: $label: exit $rc"
    [ "$(grep -c "elastopt: error: .*$pat" "$tmp/err")" -eq 1 ] || { echo "FAIL: $label: message"; cat "$tmp/err"; }
    unchanged || echo "FAIL: $label: the run's folder changed or a scratch folder is left"
    [ $rc -eq 2 ] && [ "$(grep -c "elastopt: error: .*$pat" "$tmp/err")" -eq 1 ] && unchanged
}
mpi_n 3
check refused "3 ranks" "ran distributed over 2 MPI ranks .*this is mpirun with 3 ranks.*mpirun -n 2" \
    "${mpi[@]}" "$ELASTOPT" run --restart "$d" -o time.steps=5 -q
mpi_n 2
check refused "one process" "ran distributed over 2 MPI ranks .*this is one process" \
    "$ELASTOPT" run --restart "$d" -o time.steps=5 -q
"$ELASTOPT" run --scene twist -o time.steps=2 --out "$tmp/serial" -q || { echo "FAIL: serial run"; fail=1; }
cp -a "$tmp/serial/summary.json" "$tmp/serial-summary"
timeout 120 "${mpi[@]}" "$ELASTOPT" run --restart "$tmp/serial" -o time.steps=3 -o solver.backend=petsc -q \
    > /dev/null 2> "$tmp/err"
check [ $? -eq 2 ]
check grep -q "ran on one process.*continue it without mpirun" "$tmp/err"
check cmp "$tmp/serial-summary" "$tmp/serial/summary.json"
check no_scratch

mv "$d/restart.dat.1-of-2" "$tmp/r1"
rm -rf "$tmp/before/restart.dat.1-of-2"
check refused "a file missing" "holds 1 of the 2 per-rank restart files" \
    "${mpi[@]}" "$ELASTOPT" run --restart "$d" -o time.steps=5 -q
mv "$d/restart.dat.0-of-2" "$d/restart.dat.1-of-2"
mv "$tmp/r1" "$d/restart.dat.0-of-2"
rm -rf "$tmp/before" && cp -a "$d" "$tmp/before"
check refused "swapped" "written by rank 1 of 2; this is rank 0 of 2" \
    "${mpi[@]}" "$ELASTOPT" run --restart "$d" -o time.steps=5 -q
mv "$d/restart.dat.1-of-2" "$tmp/r0"
mv "$d/restart.dat.0-of-2" "$d/restart.dat.1-of-2"
mv "$tmp/r0" "$d/restart.dat.0-of-2"
cp "$d/restart.dat.1-of-2" "$tmp/r1-step3"
cp "$tmp/r1-step2" "$d/restart.dat.1-of-2"
rm -rf "$tmp/before" && cp -a "$d" "$tmp/before"
check refused "different steps" "per-rank restart files are at different steps (2 to 3)" \
    "${mpi[@]}" "$ELASTOPT" run --restart "$d" -o time.steps=5 -q
cp "$tmp/r1-step3" "$d/restart.dat.1-of-2"
# the folder locked by another live run: rank 0 refuses, rank 1 (which reads its file
# first) ends too
sleep 60 &
holder=$!
echo $holder > "$d/run.lock"
rm -rf "$tmp/before" && cp -a "$d" "$tmp/before"
check refused "locked" "in use by another elastopt run (pid $holder" \
    "${mpi[@]}" "$ELASTOPT" run --restart "$d" -o time.steps=5 -q
kill $holder
wait $holder 2> /dev/null
rm -f "$d/run.lock"
check [ "$(sfield "$d" status)" = finished ]
check [ "$(sfield "$d" steps_run)" = 3 ]
# and it continues
timeout 120 "${mpi[@]}" "$ELASTOPT" run --restart "$d" -o time.steps=5 -q
check [ $? -eq 0 ]
check [ "$(sfield "$d" steps_run)" = 5 ]
check [ "$(sfield "$d" restarted_at_step)" = 3 ]
check no_scratch

[ $fail -eq 0 ] && echo "petsc_restart_refusals: all checks passed"
exit $fail
