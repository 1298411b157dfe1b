#!/usr/bin/env bash
# Suite 'engine': the default fallback chain continues from the best iterate
# (solver.fallback_start = best) on a real mesh started inverted: the IPC bar-2523
# reflected through y (free, no gravity, stable neo-Hookean E = 1e6, nu = 0.4,
# dt = 0.05), the cheap relative of the inverted real bunny (docs/defaults.md).
#  - Step 1: the scene's solver (newton + project_on_demand) stops at its 100 iterations,
#    `abs` (100) continues from there and stops too, and the scene's solver again, from
#    abs's end point, converges in a few Newton iterations (measured 7: its quadratic
#    phase). With fallback_start = guess the same entries restart from the starting guess:
#    the third entry repeats the first one exactly (same reason, same iterations) and the
#    step does not converge.
#  - Steps 1-3 converge with the default chain without its newton_tr entry (before:
#    newton_tr, 434 and 373 iterations in steps 1 and 3).
# Skipped (exit 77) when ../shared/meshes is absent.
EXE="$1"
SRC="${EO_SOURCE_ROOT:-$(dirname "$0")/..}"
SHARED="${EO_SHARED:-$SRC/../shared}"
T=$(mktemp -d) && trap 'rm -rf "$T"' EXIT
PY=/usr/bin/python3
[ -x $PY ] || PY=python3
if [ ! -f "$SHARED/meshes/ipc_bar-2523.msh" ]; then
    echo "note: $SHARED/meshes/ipc_bar-2523.msh absent: skipped"
    exit 77
fi
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }

cat >"$T/bar.json" <<EOF
{"mesh": {"file": "$SHARED/meshes/ipc_bar-2523.msh"},
 "material": {"model": "stable_neo_hookean", "E": 1e6, "nu": 0.4, "density": 1000},
 "gravity": [0, 0, 0], "initial": {"scale": [1, -1, 1]},
 "time": {"integrator": "newmark", "dt": 0.05, "steps": 3}}
EOF

run() { # run NAME -o ... : exit status in $T/NAME.rc
    local name=$1
    shift
    "$EXE" run "$T/bar.json" --out "$T/$name" --quiet -o output.vtu=false "$@" 2>"$T/$name.err"
    echo $? >"$T/$name.rc"
}

run best
run guess -o time.steps=1 -o solver.fallback_start=guess \
    -o 'solver.fallback=[{"hessian_fix": "abs", "max_iters": 100}, {}]'

$PY - "$T" <<'EOF'
import json, sys
T = sys.argv[1]
best = json.load(open(f"{T}/best/summary.json"))["steps"]
guess = json.load(open(f"{T}/guess/summary.json"))["steps"]
fails = 0
def check(cond, msg):
    global fails
    print(("ok: " if cond else "FAIL: ") + msg)
    fails += 0 if cond else 1
s1 = best[0]
fb = s1["fallback_from"]
print("best:", [(x["entry"], x["reason"], x["iterations"]) for x in best], "step 1 from", fb)
print("guess:", guess[0]["entry"], guess[0]["reason"], guess[0]["iterations"], guess[0]["fallback_from"])
check(all(x["converged"] for x in best) and len(best) == 3, "best: steps 1-3 converged")
check(all(x["entry"] <= 2 for x in best), "best: no step needed the newton_tr entry (entries %s)" % [x["entry"] for x in best])
check(s1["entry"] == 2 and [f["reason"] for f in fb] == ["diverged_max_iters"] * 2,
      "best: step 1 kept entry 2 after entries 0 and 1 stopped at their caps (%s)" % fb)
check(s1["iterations"] <= 15, "best: entry 2 continued from abs's end point and converged in %d <= 15 iterations" % s1["iterations"])
g0 = guess[0]
gf = g0["fallback_from"]
check(not g0["converged"] and g0["entry"] == 2 and g0["reason"] == gf[0]["reason"] == "diverged_max_iters"
      and g0["iterations"] == gf[0]["iterations"] == 100,
      "guess: the scene's solver again from the starting guess repeats entry 0 (%s, %d iterations) and fails"
      % (g0["reason"], g0["iterations"]))
sys.exit(1 if fails else 0)
EOF
[ $? -eq 0 ] && ok || bad "fallback from the best iterate (see above)"
[ "$(cat "$T/best.rc")" = 0 ] && ok || bad "best: exit $(cat "$T/best.rc") (expected 0): $(tail -1 "$T/best.err")"
[ "$(cat "$T/guess.rc")" = 1 ] && ok || bad "guess: exit $(cat "$T/guess.rc") (expected 1)"
echo "fallback_best: $pass passed, $fail failed"
[ $fail -eq 0 ]
