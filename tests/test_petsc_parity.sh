#!/usr/bin/env bash
# One solver core, serial and distributed (suite 'petsc'; docs/petsc.md): the library's
# newton with every Hessian fix (none, shift, clamp, abs, project_on_demand, progressive,
# trust_region_filter) and lbfgs, run with solver.backend=petsc on 1, 2 and 4 ranks
# (`mpirun -n K`), end within 1e-8 (relative to the largest position) of the serial
# engine's positions after 10 steps, on the built-in cantilever and twist with their own
# settings (only the method changed) and on a real mesh (the IPC bar of ../shared/meshes,
# one end fixed, the other rotating; skipped with a note when absent), and on the inverted
# scene (indefinite Hessians) with project_on_demand, shift and clamp. Every step of
# every run converges. Prints the table scene × method × ranks → max |Δx|.
# Skipped (77) when the module was not built or mpirun is missing.
. "$(dirname "$0")/petsc_common.sh"

# cell LABEL K RUN-ARGS...: the run on K ranks against the serial one in $tmp/s (positions
# within 1e-8, every step converged, iterations within the parity rule); appends the
# max |dx| (or FAIL) to $row
cell() {
    local label=$1 k=$2 rc out crc prc=0 dx
    shift 2
    timeout 300 mpirun -n "$k" "${mpi_opts[@]}" "$ELASTOPT" run "$@" -o solver.backend=petsc --out "$tmp/p" -q \
        --force > "$tmp/p.log" 2>&1
    rc=$?
    out=$(python3 "$here/petsc_compare.py" "$tmp/s" "$tmp/p" 1e-8 x)
    crc=$?
    python3 "$here/petsc_parity.py" "$tmp/s" "$tmp/p" 100 x > "$tmp/par.log" || prc=1
    dx=$(echo "$out" | sed -n 's/.*max |dx| = \([^ ]*\) m.*/\1/p')
    if [ $rc -ne 0 ] || [ $crc -ne 0 ] || [ $prc -ne 0 ]; then
        echo "FAIL: $label $k ranks: exit $rc, $out"; cat "$tmp/par.log"; tail -5 "$tmp/p.log"; fail=1
        dx="FAIL"
    fi
    row="$row $(printf "%12s" "${dx:-?}")"
}

scenes=(cantilever twist)
bar=${EO_SHARED:-$here/../../shared}/meshes/ipc_bar-2523.msh
if [ -f "$bar" ]; then
    bash "$here/petsc_bar_scene.sh" "$bar" 10 project_on_demand > "$tmp/bar.json"
    scenes+=(bar)
else
    echo "note: $bar missing: the real-mesh rows are skipped"
fi
methods=(none shift clamp abs project_on_demand progressive trust_region_filter lbfgs)
src() { if [ "$1" = bar ]; then echo "$tmp/bar.json"; else echo "--scene $1"; fi; }
mopt() { if [ "$1" = lbfgs ]; then echo "-o solver.optimizer=lbfgs"; else echo "-o solver.hessian_fix=$1"; fi; }
printf "%-11s %-20s %12s %12s %12s\n" scene method "1 rank" "2 ranks" "4 ranks"
for scene in "${scenes[@]}"; do
    for m in "${methods[@]}"; do
        # shellcheck disable=SC2046
        "$ELASTOPT" run $(src "$scene") -o time.steps=10 $(mopt "$m") --out "$tmp/s" -q --force ||
            { echo "FAIL: serial $scene $m"; fail=1; continue; }
        row=""
        for k in 1 2 4; do
            # shellcheck disable=SC2046
            cell "$scene $m" "$k" $(src "$scene") -o time.steps=10 $(mopt "$m")
        done
        printf "%-11s %-20s%s\n" "$scene" "$m" "$row"
    done
done
# the inverted scene, whose true Hessians are indefinite: the MUMPS path must learn it as
# the serial engine's CHOLMOD does (petsc/ksp.c: LDLᵀ inertia confirmed by a
# negative-curvature witness), or project_on_demand, shift and none take other directions
for m in project_on_demand shift clamp; do
    "$ELASTOPT" run --scene inverted -o time.steps=10 -o solver.hessian_fix=$m --out "$tmp/s" -q --force ||
        { echo "FAIL: serial inverted $m"; fail=1; continue; }
    row=""
    for k in 1 2 4; do
        cell "inverted $m" "$k" --scene inverted -o time.steps=10 -o solver.hessian_fix=$m -o solver.petsc_ksp.pc=mumps
    done
    printf "%-11s %-20s%s\n" inverted "$m" "$row"
done
# the other methods that run distributed, twist, 2 ranks: newton_tr, ncg, newton with the
# line searches that evaluate gradients (wolfe, exact) or the step bound (barrier_filter),
# the other stopping rules
for m in "solver.optimizer=newton_tr" "solver.optimizer=ncg" "solver.linesearch=wolfe" "solver.linesearch=exact" \
    "solver.linesearch=barrier_filter" "solver.stop=newton_decrement" "solver.stop=characteristic_gradient"; do
    "$ELASTOPT" run --scene twist -o time.steps=10 -o "$m" --out "$tmp/s" -q --force || { echo "FAIL: serial $m"; fail=1; continue; }
    timeout 300 mpirun -n 2 "${mpi_opts[@]}" "$ELASTOPT" run --scene twist -o time.steps=10 -o "$m" -o solver.backend=petsc \
        --out "$tmp/p" -q --force > "$tmp/p.log" 2>&1
    rc=$?
    out=$(python3 "$here/petsc_compare.py" "$tmp/s" "$tmp/p" 1e-8 "twist $m, 2 ranks")
    crc=$?
    echo "$out"
    python3 "$here/petsc_parity.py" "$tmp/s" "$tmp/p" 100 x > "$tmp/par.log" || crc=1
    if [ $rc -ne 0 ] || [ $crc -ne 0 ]; then echo "FAIL: twist $m 2 ranks: exit $rc"; cat "$tmp/par.log"; fail=1; fi
done
[ $fail -eq 0 ] && echo "petsc parity: all checks passed"
exit $fail
