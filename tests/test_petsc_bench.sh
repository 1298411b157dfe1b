#!/usr/bin/env bash
# `elastopt bench` under mpirun (suite 'petsc'; cli/cmd_bench.c, bench/harness/run.c,
# docs/petsc.md): every rank runs its part of each scene with distributed configurations
# (tests/data/petsc_mpi_suite.json: newton on the PETSc backend (petsc_ksp) with MUMPS and with CG + Jacobi,
# snes_newtonls (its line search failing at the rounding level of g is not a failure),
# snes_newtontr, tao_nls, tao_lmvm (with the scalar initial scaling); two scenes):
#  1. on 2 ranks: exit 0, every configuration converged on both scenes, rank 0's report
#     counts the whole mesh (900 tets, 336 vertices), no scratch folder left;
#  2. the same suite on one process: the reference's g(x0) and g(x*) agree to 1e-9 and
#     its per-step motion and correction (mass-weighted over the vertices, shared ones
#     counted once with their whole mass) to 1e-6, relative;
#  3. a suite with configurations that are not distributed (newton, ipopt) under mpirun:
#     exit 2, one message naming them, no output folder.
# Skipped (77) without the backend or mpirun.
. "$(dirname "$0")/petsc_common.sh"
suite=$here/data/petsc_mpi_suite.json
timeout 120 "${mpi[@]}" "$ELASTOPT" bench "$suite" --out "$tmp/b2" --repeats 1 -q
check [ $? -eq 0 ]
check python3 - "$tmp/b2/summary.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
ok = len(rows) == 12 and all(r["status"] == "converged" and r["tets"] == "900" for r in rows)
print([(r["scene"], r["config"], r["status"]) for r in rows if r["status"] != "converged"] or "all 12 converged")
sys.exit(0 if ok else 1)
PY
check [ "$(grep -c "900 tets, 336 vertices" "$tmp/b2/report.md")" -eq 2 ]
check no_scratch
timeout 120 "$ELASTOPT" bench "$suite" --out "$tmp/b1" --repeats 1 -q
check [ $? -eq 0 ]
check python3 - "$tmp/b1/reference.csv" "$tmp/b2/reference.csv" <<'PY'
import csv, sys
a, b = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
worst = {"g": 0.0, "motion": 0.0}
for x, y in zip(a, b):
    for k, kind in (("g0", "g"), ("gstar", "g"), ("motion", "motion"), ("correction", "motion")):
        u, v = float(x[k]), float(y[k])
        worst[kind] = max(worst[kind], abs(u - v) / abs(u))
print("reference, 1 process against 2 ranks: largest relative difference of g %.1e, of motion/correction %.1e"
      % (worst["g"], worst["motion"]))
sys.exit(0 if len(a) == len(b) == 4 and worst["g"] <= 1e-9 and worst["motion"] <= 1e-6 else 1)
PY
timeout 120 "${mpi[@]}" "$ELASTOPT" bench "$here/data/petsc_suite.json" --out "$tmp/bad" -q > /dev/null 2> "$tmp/bad.err"
check [ $? -eq 2 ]
check [ "$(grep -c "elastopt: error: .*every configuration must run distributed.*newton-clamp (newton), ipopt-clamp (ipopt)" "$tmp/bad.err")" -eq 1 ]
check [ ! -e "$tmp/bad" ]
check no_scratch

[ $fail -eq 0 ] && echo "petsc_bench: all checks passed"
exit $fail
