#!/usr/bin/env bash
# elastopt poisson and explicit runs (notes 001): `poisson` prints JSON with an O(h^2)
# L2 error and converges with newton/cholmod, lbfgs and newton/pcg, exits 2 on bad input;
# `run` with an explicit integrator records iterations 0 / reason explicit per step and
# exits 0; rk4 beyond its stability limit stops with exit 1, reason diverged_nonfinite
# (summary stop_reason, the step's reason), finite values in the summary; `check` passes
# on an explicit scene (the potential E(x) whose -grad is the force).
set -u
EXE="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
SRC="${EO_SOURCE_ROOT:-$(dirname "$0")/..}"
T="${EO_BUILD_ROOT:-/tmp}/testtmp/cli_features"
rm -rf "$T" && mkdir -p "$T" && cd "$T" || exit 1
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }

for cfg in "newton cholmod" "lbfgs cholmod" "newton pcg"; do
    set -- $cfg
    "$EXE" poisson --n 16 -o solver.optimizer=$1 -o solver.linear=$2 -o solver.stop=gradient -o solver.tol=1e-12 \
        -o solver.max_iters=10000 > "p_$1_$2.json"
    rc=$?
    [ $rc -eq 0 ] && ok || bad "poisson $cfg exit $rc"
    python3 - "p_$1_$2.json" <<'PY' && ok || bad "poisson $cfg output"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["converged"] and d["unknowns"] == 225 and d["n"] == 16, d
assert 4e-3 < d["l2_error"] < 7e-3 and d["max_error"] < 5e-3, d
assert d["solver"]["optimizer"] in ("newton", "lbfgs")
PY
done
"$EXE" poisson --n 1 >/dev/null 2>&1; [ $? -eq 2 ] && ok || bad "poisson --n 1 should exit 2"
"$EXE" poisson -o solver.optimizr=newton >/dev/null 2>&1; [ $? -eq 2 ] && ok || bad "poisson unknown key exit 2"
"$EXE" poisson --n 8 -o solver.optimizer=gradient_descent -o solver.max_iters=2 -o solver.tol=1e-30 >/dev/null
[ $? -eq 1 ] && ok || bad "poisson capped should exit 1"

# explicit run of the chain example
"$EXE" run "$SRC/examples/spring_chain.json" --out chain -o time.integrator=verlet -o time.dt=0.002 \
    -o time.steps=50 -o output.vtu=false > chain.out 2> chain.err
rc=$?
[ $rc -eq 0 ] && ok || bad "verlet chain exit $rc"
python3 - chain/summary.json <<'PY' && ok || bad "verlet chain summary"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["all_converged"] and s["stop_reason"] is None and len(s["steps"]) == 50 and s["not_converged"] == []
# explicit steps are counted as such, not as converged
assert s["step_counts"] == {"converged": 0, "explicit": 50, "not_converged": 0}, s["step_counts"]
for st in s["steps"]:
    assert st["iterations"] == 0 and st["reason"] == "explicit" and st["converged"] is False and st["g"] is None, st
assert s["steps"][-1]["com"][2] < -1e-3
PY
[ "$(grep -c ',explicit,0$' chain/iterations.csv)" -eq 50 ] && ok || bad "csv: one row per explicit step"
# steps.csv: reason explicit, converged 0 on every row
[ "$(awk -F, 'NR > 1 && $4 == "explicit" && $5 == 0' chain/steps.csv | wc -l)" -eq 50 ] && ok || bad "steps.csv explicit rows"
grep -q "50/50 explicit" chain.out chain.err && ! grep -q "converged" chain.out && ok ||
    bad "closing line: $(cat chain.out chain.err)"

# rk4 beyond its stability limit: a clear diagnosis, not NaN
"$EXE" run --scene cantilever --out rk4 --quiet -o time.integrator=rk4 -o time.steps=100 -o output.vtu=false \
    2> rk4.err
rc=$?
[ $rc -eq 1 ] && ok || bad "rk4 divergence should exit 1, got $rc"
grep -q "diverged_nonfinite" rk4.err && grep -q "reduce time.dt" rk4.err && ok || bad "rk4 message: $(cat rk4.err)"
python3 - rk4/summary.json <<'PY' && ok || bad "rk4 summary"
import json, math, sys
s = json.load(open(sys.argv[1]))
assert s["stop_reason"] == "diverged_nonfinite" and not s["all_converged"], s["stop_reason"]
assert s["steps"][-1]["reason"] == "diverged_nonfinite" and s["steps_run"] < 100
assert all(st["reason"] == "explicit" for st in s["steps"][:-1])
assert s["step_counts"]["explicit"] == s["steps_run"] - 1 and s["step_counts"]["not_converged"] == 1
PY
"$EXE" check --scene cantilever -o time.integrator=heun >/dev/null && ok || bad "check on an explicit scene"

# run --profile: one line per step and the totals table; the numbers add up (the
# factorization count equals the Hessians of the summary, the ratio is >= 1)
"$EXE" run --scene twist -o time.steps=3 -o output.vtu=false --out prof --quiet --profile > prof.txt
rc=$?
[ $rc -eq 0 ] && ok || bad "run --profile exit $rc"
python3 - prof.txt prof/summary.json <<'PY' && ok || bad "run --profile output: $(cat prof.txt)"
import json, re, sys
t = open(sys.argv[1]).read()
s = json.load(open(sys.argv[2]))
steps = re.findall(r"^profile step (\d+): (\d+) it ([0-9.]+) s .*numeric ([0-9.]+) \((\d+)\)", t, re.M)
assert [int(x[0]) for x in steps] == [1, 2, 3], steps
for (k, it, tot, tf, nf), st in zip(steps, s["steps"]):
    assert int(it) == st["iterations"], (it, st)
    assert float(tf) <= float(tot) + 1e-4
tab = dict(re.findall(r"^  (assembly \(Hessian\)|factor: numeric|factor: symbolic|solve|line search|gradient)\s+[0-9.]+\s+[0-9.]+%\s+(\d+)", t, re.M))
assert int(tab["factor: symbolic"]) == 1, tab
assert int(tab["factor: numeric"]) == sum(int(x[4]) for x in steps), tab
m = re.search(r"iteration / numeric factorization: ([0-9.]+)", t)
assert m and float(m.group(1)) >= 1, t
PY
"$EXE" run --scene cantilever -o time.steps=2 -o output.vtu=false --out noprof --quiet > noprof.txt
[ ! -s noprof.txt ] && ok || bad "run without --profile printed: $(cat noprof.txt)"

echo "cli_features: $pass passed, $fail failed"
[ $fail -eq 0 ]
