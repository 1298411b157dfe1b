#!/usr/bin/env bash
# elastopt run / check: FD check passes on every examples/*.json; the default scene runs,
# converges every step and writes summary.json + pvd/vtu + iterations.csv; the exit
# status is 1 when a step does not converge; bad scenes (unknown key, unknown optimizer,
# malformed JSON, boundary selecting nothing, bad -o) exit 2 with file:line (or the -o
# key) in the message and write nothing.
set -u
EXE="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
SRC="${EO_SOURCE_ROOT:-$(dirname "$0")/..}"
T="${EO_BUILD_ROOT:-/tmp}/testtmp/cli_engine"
rm -rf "$T" && mkdir -p "$T" && cd "$T" || exit 1
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }

# --- FD check of every example scene
for f in "$SRC"/examples/*.json; do
    out=$("$EXE" check "$f" 2>&1)
    rc=$?
    [ $rc -eq 0 ] && ok || bad "check $f exit $rc: $out"
done
"$EXE" check --scene twist -o solver.hessian_fix=abs >/dev/null && ok || bad "check with -o"

# --- default scene
"$EXE" run --out default --quiet
rc=$?
[ $rc -eq 0 ] && ok || bad "run default exit $rc"
[ -s default/summary.json ] && [ -s default/iterations.csv ] && [ -s default/steps.csv ] && [ -s default/restart.dat ] && [ ! -e default/run.lock ] && [ -s default/cantilever.pvd ] &&
    [ -s default/frame_000000.vtu ] && [ -s default/frame_000040.vtu ] && ok || bad "default outputs missing: $(ls default)"
python3 - default/summary.json <<'PY' && ok || bad "summary.json contents"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["all_converged"] is True, s["not_converged"]
assert len(s["steps"]) == 40 and all(st["converged"] for st in s["steps"])
for k in ("iterations", "reason", "time", "g", "grad_norm", "com", "max_disp", "min_J", "inverted", "kinetic", "elastic"):
    assert k in s["steps"][0], k
assert s["build"]["version"] and s["build"]["compiler"]
assert s["resolved"]["solver"]["optimizer"] == "newton"
assert s["resolved"]["scene"]["time"]["integrator"] == "newmark"
assert s["config"]["time"]["steps"] == 40
assert s["steps"][-1]["inverted"] == 0
PY
head -1 default/iterations.csv | grep -q '^step,iteration,time,g,grad_norm,decrement,alpha,ls_evals,inverted,reason,entry$' && ok || bad "csv header"
[ "$(grep -c 'converged_decrement' default/iterations.csv)" -eq 40 ] && ok || bad "csv: one final row per step"

# --- a step that cannot converge: exit 1, files still written
"$EXE" run --scene cantilever --out capped --quiet -o solver.max_iters=1 -o solver.tol=1e-40 -o time.steps=2 -o "solver.fallback=[]"
rc=$?
[ $rc -eq 1 ] && ok || bad "not converged should exit 1, got $rc"
python3 -c "import json; s = json.load(open('capped/summary.json')); assert not s['all_converged'] and s['not_converged'] == [1, 2]" && ok || bad "capped summary"

# --- a tolerance below the rounding level (relative gradient 1e-20): the step ends as
# diverged_stagnated after a few steps without progress instead of spending max_iters
# at the floor
"$EXE" run --scene twist --out stall --quiet -o 'mesh.generate.cells=[10,2,2]' -o time.steps=4 \
    -o solver.stop=gradient -o solver.tol=1e-20 -o solver.max_iters=500 -o output.vtu=false -o "solver.fallback=[]"
rc=$?
[ $rc -eq 1 ] && ok || bad "stagnating run should exit 1, got $rc"
python3 - stall/summary.json <<'PY' && ok || bad "stagnation summary"
import json, sys
s = json.load(open(sys.argv[1]))
reasons = [st["reason"] for st in s["steps"]]
assert "diverged_stagnated" in reasons, reasons
assert all(st["iterations"] <= 100 for st in s["steps"]), [st["iterations"] for st in s["steps"]]
PY

# --- bad input: exit 2, message with file:line, nothing written
printf '{\n  "time": {"dt": 0.01},\n  "solvr": {}\n}\n' > unknown_key.json
printf '{\n  "solver": {\n    "optimizer": "newtn"\n  }\n}\n' > bad_optimizer.json
printf '{\n  "time": {"dt": 0.01,}\n}\n' > malformed.json
printf '{\n  "boundary": [\n    {"box": [[5,5,5],[6,6,6]], "fixed": true}\n  ]\n}\n' > empty_bc.json
printf '{\n  "time": {\n    "dt": -1\n  }\n}\n' > bad_dt.json
expect_bad() { # file expected-substring [extra args...]
    local f=$1 want=$2
    shift 2
    local msg
    msg=$("$EXE" run "$f" --out "out_$f" --quiet "$@" 2>&1)
    local rc=$?
    [ $rc -eq 2 ] && ok || bad "$f: exit $rc (want 2): $msg"
    case "$msg" in *"$want"*) ok ;; *) bad "$f: message '$msg' lacks '$want'" ;; esac
    [ ! -e "out_$f" ] && ok || bad "$f: wrote output"
}
expect_bad unknown_key.json "unknown_key.json:3"
expect_bad bad_optimizer.json "bad_optimizer.json:3"
expect_bad malformed.json "malformed.json:2"
expect_bad empty_bc.json "empty_bc.json:3"
expect_bad bad_dt.json "bad_dt.json:3"
printf '{"time": {"steps": 1}}\n' > good.json
expect_bad good.json "-o solver.optimizr" -o solver.optimizr=newton
expect_bad good.json "-o solver.optimizer" -o solver.optimizer=newtn
msg=$("$EXE" run --scene nosuch --out out_nosuch 2>&1); rc=$?
[ $rc -eq 2 ] && [ ! -e out_nosuch ] && ok || bad "unknown scene: exit $rc"
case "$msg" in *cantilever*) ok ;; *) bad "unknown scene message lists scenes: $msg" ;; esac
"$EXE" run --bogus >/dev/null 2>&1; [ $? -eq 2 ] && ok || bad "unknown option exit"

# --- every example runs with every optimizer configuration chosen by -o: Newton with a
# Hessian fix that makes the system positive definite (shift, clamp, abs) converges every
# step (exit 0); the true Hessian (none: steepest descent where it is indefinite, e.g. the
# inverted start) and first-order methods either converge or stop at the iteration cap
# (exit 1) -- never a crash, a bad-input exit or a non-finite value.
for f in "$SRC"/examples/*.json; do
    b=$(basename "$f" .json)
    for cfg in "newton none" "newton shift" "newton clamp" "newton abs" "gradient_descent clamp" "lbfgs clamp" "projective_dynamics clamp"; do
        set -- $cfg
        d="matrix_${b}_$1_$2"
        "$EXE" run "$f" --out "$d" --quiet -o time.steps=2 -o output.vtu=false \
            -o solver.optimizer=$1 -o solver.hessian_fix=$2 >/dev/null 2>"$d.err"
        rc=$?
        if [ "$1" = newton ] && [ "$2" != none ]; then
            [ $rc -eq 0 ] && ok || bad "$b with $cfg: exit $rc $(cat "$d.err")"
        else
            { [ $rc -eq 0 ] || [ $rc -eq 1 ]; } && ok || bad "$b with $cfg: exit $rc $(cat "$d.err")"
        fi
        python3 - "$d/summary.json" <<'PY' && ok || bad "$b with $cfg: summary has a non-finite value"
import json, math, sys
s = json.load(open(sys.argv[1]))
for st in s["steps"]:
    for k in ("g", "grad_norm", "min_J", "kinetic", "elastic"):
        assert st[k] is not None and math.isfinite(st[k]), (k, st[k])
PY
    done
done

# --- projective dynamics on the twisting bar: every step converges (exit 0), plain PD
# (more iterations: raised cap) and L-BFGS-PD with the default cap; PD converges linearly,
# so it gets the relative tolerance 1e-5 of the step's motion (the default 1e-10 is for
# Newton): 408 and 66 iterations per step measured
for h in 0 5; do
    cap=100; [ $h = 0 ] && cap=1000
    "$EXE" run "$SRC/examples/twist.json" --out "pd_twist_$h" --quiet -o output.vtu=false \
        -o solver.optimizer=projective_dynamics -o solver.projective_dynamics.lbfgs_history=$h \
        -o solver.max_iters=$cap -o solver.tol=1e-5 >/dev/null 2>"pd_twist_$h.err"
    rc=$?
    [ $rc -eq 0 ] && ok || bad "twist with projective_dynamics lbfgs_history=$h: exit $rc $(cat "pd_twist_$h.err")"
done

# --- explicit integrators beyond their stability limit: the cantilever with rk4 at
# dt = 3e-4 and forward_euler at dt = 1e-4 blow up within 300 steps. The first non-finite
# energy or force (any term, any stage) ends the run: exit 1, stop_reason
# diverged_nonfinite, fewer than 300 steps run, the last step's reason
# diverged_nonfinite, every recorded state finite, one frame per completed step.
for cfg in "rk4 3e-4" "forward_euler 1e-4"; do
    set -- $cfg
    d="blowup_$1"
    "$EXE" run --scene cantilever -o time.integrator=$1 -o time.dt=$2 -o time.steps=300 -o output.every=1 \
        --out "$d" --quiet >/dev/null 2>"$d.err"
    rc=$?
    [ $rc -eq 1 ] && ok || bad "$1 dt=$2 blow-up: exit $rc (expected 1) $(cat "$d.err")"
    grep -q "diverged_nonfinite" "$d.err" && ok || bad "$1 blow-up: no error message: $(cat "$d.err")"
    python3 - "$d/summary.json" "$d" <<'PY' && ok || bad "$1 dt=$2 blow-up: summary"
import json, math, sys, glob
s = json.load(open(sys.argv[1]))
assert s["stop_reason"] == "diverged_nonfinite", s["stop_reason"]
assert 1 < s["steps_run"] < 300, s["steps_run"]
assert s["all_converged"] is False
assert s["steps"][-1]["reason"] == "diverged_nonfinite"
assert all(st["reason"] == "explicit" and st["converged"] is False for st in s["steps"][:-1])
for st in s["steps"]:
    assert all(math.isfinite(c) for c in st["com"]), st["com"]
    assert st["max_disp"] is not None and math.isfinite(st["max_disp"]), st["max_disp"]
# frames: the initial one + one per completed step (the diverged step writes none)
frames = glob.glob(sys.argv[2] + "/frame_*.vtu")
assert len(frames) == s["steps_run"] == s["frames"], (len(frames), s["steps_run"], s["frames"])
PY
done

echo "cli_engine: $pass passed, $fail failed"
[ $fail -eq 0 ]
