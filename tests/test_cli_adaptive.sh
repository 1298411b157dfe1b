#!/usr/bin/env bash
# elastopt run with adaptive time stepping (time.adaptive), on the cantilever at dt = 0.03
# with solver.max_iters = 4 (the nominal steps 2.. do not converge):
#  - without it exit 1 (steps not converged), with it exit 0; steps.csv has the appended
#    columns rejected, substeps, min_substep (then n_not_pd: 31 fields, the first 27 as before): rows
#    with rejected > 0 have substeps > 1 and min_substep < dt, t stays n*dt exactly as in
#    the run without; summary.json per step and the totals under "adaptive" agree with it
#  - restart in the middle (3 steps, then --restart to 5) == an uninterrupted 5-step run:
#    restart.dat (holding the controller's level and streak), steps.csv without the
#    timing columns, the last frame
#  - time.adaptive with an explicit integrator: exit 2 naming the key, nothing written
set -u
EXE="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
T="${EO_BUILD_ROOT:-/tmp}/testtmp/cli_adaptive"
rm -rf "$T" && mkdir -p "$T" && cd "$T" || exit 1
PY=/usr/bin/python3
[ -x $PY ] || PY=python3
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }

H=(-o time.dt=0.03 -o solver.max_iters=4 -o output.every=5 -o "solver.fallback=[]")
"$EXE" run --out off -q "${H[@]}" -o time.steps=3 -o output.vtu=false
rc=$?
[ $rc -eq 1 ] && ok || bad "adaptive off: exit $rc, expected 1 (steps not converged)"
"$EXE" run --out on -q "${H[@]}" -o time.steps=3 -o output.vtu=false -o time.adaptive=true
rc=$?
[ $rc -eq 0 ] && ok || bad "adaptive on: exit $rc, expected 0"
$PY - <<'PY' && ok || bad "steps.csv / summary.json of the adaptive run"
import csv, json
on = list(csv.DictReader(open("on/steps.csv")))
off = list(csv.DictReader(open("off/steps.csv")))
head = open("on/steps.csv").readline().strip().split(",")
assert head[-6:] == ["total_energy", "rejected", "substeps", "min_substep", "n_not_pd", "solve_cpu_time"], head
assert all(len(r) == 32 for r in on), "field count"
assert [r["t"] for r in on] == [r["t"] for r in off], "t differs from the run without substeps"
assert all(r["converged"] == "1" for r in on), [r["reason"] for r in on]
assert any(r["converged"] == "0" for r in off)
rej = [int(r["rejected"]) for r in on]
assert sum(rej) >= 1, rej
for r in on:
    if int(r["rejected"]): assert int(r["substeps"]) > 1 and float(r["min_substep"]) < 0.03, r
    else: assert int(r["substeps"]) == 1 and float(r["min_substep"]) == 0.03, r
for r in off: assert (r["rejected"], r["substeps"], float(r["min_substep"])) == ("0", "1", 0.03), r
s = json.load(open("on/summary.json"))
a = s["adaptive"]
assert a["on"] is True and a["rejected"] == sum(rej) and a["substeps"] == sum(int(r["substeps"]) for r in on), a
assert a["min_substep"] == min(float(r["min_substep"]) for r in on), a
assert [e["rejected"] for e in s["steps"]] == rej
assert json.load(open("off/summary.json"))["adaptive"] == {"on": False, "rejected": 0, "substeps": 3, "min_substep": 0.03}
PY

# restart inside the adaptive run == uninterrupted
"$EXE" run --out full -q "${H[@]}" -o time.steps=5 -o time.adaptive=true || bad "uninterrupted run"
"$EXE" run --out part -q "${H[@]}" -o time.steps=3 -o time.adaptive=true || bad "first part"
grep -qa "^array adaptive 2$" part/restart.dat && ok || bad "restart.dat has no adaptive array"
$PY - <<'PY' && ok || bad "the restart point is at a reduced substep size (else the case tests little)"
import struct
b = open("part/restart.dat", "rb").read()
i = b.index(b"array adaptive 2\n") + len(b"array adaptive 2\n")
level, streak = struct.unpack("<2d", b[i:i + 16])
assert level > 0, (level, streak)
PY
"$EXE" run --restart part -q -o time.steps=5
rc=$?
[ $rc -eq 0 ] && ok || bad "restart: exit $rc"
cmp -s part/restart.dat full/restart.dat && ok || bad "restart: restart.dat differs from the uninterrupted run"
cmp -s part/frame_000005.vtu full/frame_000005.vtu && ok || bad "restart: frame 5 differs"
cmp -s <(cut -d, -f1-5,8-31 part/steps.csv) <(cut -d, -f1-5,8-31 full/steps.csv) && ok || bad "restart: steps.csv differs"

# an explicit integrator cannot step adaptively
"$EXE" run --out expl -q -o time.integrator=rk4 -o time.adaptive=true >expl.out 2>expl.err
rc=$?
[ $rc -eq 2 ] && grep -q "time.adaptive" expl.err && [ ! -e expl ] && ok ||
    bad "explicit + adaptive: exit $rc, $(cat expl.err), $(ls expl 2>&1)"

echo "cli_adaptive: $pass passed, $fail failed"
[ $fail -eq 0 ]
