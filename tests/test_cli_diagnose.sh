#!/usr/bin/env bash
# Diagnoses instead of blind retries, on the command line:
#  1. a static scene whose bodies keep free rigid-body modes is refused at load (exit 2,
#     nothing written, the modes named), not run into hundreds of failed factorizations;
#  2. project_on_demand's expected not-positive-definite factorizations are counted
#     (summary.json total_not_pd, steps.csv n_not_pd), not printed;
#  3. inputs are checked before they are trusted: a non-finite restart.dat, an oversized
#     config, suite or restart file are refused at once (exit 2, nothing written) in
#     little memory.
set -u
EXE="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
T="${EO_BUILD_ROOT:-/tmp}/testtmp/cli_diagnose"
rm -rf "$T" && mkdir -p "$T" && cd "$T" || exit 1
PY=/usr/bin/python3
[ -x $PY ] || PY=python3
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }

# ---- 1. static scenes without enough supports: a unit cube of 2x2x2 cells
cube() { # name, boundary entries
    cat >"$1.json" <<J
{"mesh": {"generate": {"size": [1, 1, 1], "cells": [2, 2, 2]}},
 "time": {"integrator": "static", "dt": 1, "steps": 2}, "output": {"vtu": false},
 "boundary": [$2]}
J
}
refused() { # name, expected text, key:line of the error (the boundary list; the integrator if it is empty)
    "$EXE" run "$1.json" --out "$1" >"$1.out" 2>"$1.err"
    local rc=$?
    [ $rc -eq 2 ] && ok || bad "$1: exit $rc, expected 2: $(cat "$1.err")"
    grep -qF "$2" "$1.err" && ok || bad "$1: message '$(cat "$1.err")' lacks '$2'"
    grep -q "$1.json:${3#*:}:.*key '${3%:*}': static scene" "$1.err" && ok || bad "$1: no file:line of $3"
    grep -q "not positive definite" "$1.err" && bad "$1: factorization warnings" || ok
    [ ! -e "$1" ] && ok || bad "$1: the refused run wrote $1/"
}
cube free ""
refused free "the free set has 6 unconstrained rigid-body modes (translations x, y, z; rotations about x, y, z)" time.integrator:2
cube pin '{"nearest": [0, 0, 0], "fixed": true}'
refused pin "3 unconstrained rigid-body modes (rotations about x, y, z through the only constrained vertex, 0 at (0, 0, 0)); gravity holds the rotations about horizontal axes (the body hangs below the point), not the rotation about the vertical through it" boundary:3
cube edge '{"box": [[-1, -1, -1], [0.1, 0.1, 2]], "fixed": true}'
refused edge "1 unconstrained rigid-body mode (rotation about the line through (0, 0, 0) along z, the line of all constrained vertices); gravity cannot hold it (the line is vertical)" boundary:3
# a horizontal hinge (the edge y = z = 0): gravity holds the cube below it, the run goes on
cube hinge '{"box": [[-1, -1, -1], [2, 0.1, 0.1]], "fixed": true}'
"$EXE" run hinge.json --out hinge >hinge.out 2>hinge.err
rc=$?
[ $rc -ne 2 ] && [ -e hinge/summary.json ] && ok || bad "horizontal hinge refused: exit $rc $(cat hinge.err)"
"$EXE" run hinge.json -o 'gravity=[0,0,0]' --out hinge0 >hinge0.out 2>hinge0.err
[ $? -eq 2 ] && grep -q "1 unconstrained rigid-body mode (rotation about the line through (0, 0, 0) along x, the line of all constrained vertices); gravity cannot hold it (no gravity)" hinge0.err &&
    [ ! -e hinge0 ] && ok || bad "hinge without gravity: $(cat hinge0.err)"
# the built-in static cantilever without its support: no file, the key of the integrator
"$EXE" run --scene cantilever_static -o 'boundary=[]' --out nobc >nobc.out 2>nobc.err
[ $? -eq 2 ] && grep -q "key 'time.integrator': static scene: the free set has 6 unconstrained" nobc.err &&
    [ ! -e nobc ] && ok || bad "cantilever_static without support: $(cat nobc.err)"
# a fixed face: supported, runs and converges without a factorization warning
cube face '{"box": [[-1, -1, -1], [0.1, 2, 2]], "fixed": true}'
"$EXE" run face.json --out face >face.out 2>face.err
rc=$?
[ $rc -eq 0 ] && ok || bad "fixed face: exit $rc $(cat face.err)"
grep -q "not positive definite" face.err && bad "fixed face: factorization warnings" || ok
# the same unsupported cube is fine with a dynamic integrator (the mass term holds it)
"$EXE" run free.json --out freedyn -o time.integrator=backward_euler -o time.dt=0.01 >freedyn.out 2>freedyn.err
[ $? -eq 0 ] && ok || bad "free cube, backward_euler: $(cat freedyn.err)"

# ---- 2. project_on_demand's fallbacks are counted, not printed
"$EXE" run --scene inverted -o solver.hessian_fix=project_on_demand --out pod --profile >pod.out 2>pod.err
rc=$?
[ $rc -eq 0 ] && ok || bad "inverted + project_on_demand: exit $rc $(cat pod.err)"
grep -q "not positive definite" pod.err && bad "project_on_demand printed $(grep -c 'not positive definite' pod.err) not-PD lines" || ok
$PY - <<'P' && ok || bad "inverted + project_on_demand: counts"
import csv, json, sys
s = json.load(open("pod/summary.json"))
rows = list(csv.DictReader(open("pod/steps.csv")))
per_step = sum(int(r["n_not_pd"]) for r in rows)
steps = sum(e["evaluations"]["not_pd"] for e in s["steps"])
print("total_not_pd", s["total_not_pd"], "steps.csv", per_step, "summary steps", steps)
sys.exit(0 if s["total_not_pd"] > 0 and per_step == s["total_not_pd"] == steps else 1)
P
n=$(grep "not pos. definite" pod.out | awk '{print $NF}')
[ -n "$n" ] && [ "$n" -gt 0 ] && ok || bad "--profile: no not-PD count: $(grep -i 'pos' pod.out)"

# ---- 3a. a restart.dat holding a NaN / Inf: refused at once, the run folder unchanged
"$EXE" run --scene cantilever -o time.steps=2 -o output.vtu=false --out rs --quiet || bad "restart base run"
poke() { # file, array name, value index, value
    $PY - "$@" <<'P'
import struct, sys
path, name, idx, val = sys.argv[1], sys.argv[2].encode(), int(sys.argv[3]), float(sys.argv[4])
b = bytearray(open(path, "rb").read())
i = b.index(b"array " + name + b" ")
j = b.index(b"\n", i) + 1 + 8 * idx
b[j:j + 8] = struct.pack("=d", val)
open(path, "wb").write(b)
P
}
snap() { (cd "$1" && find . -type f -exec md5sum {} + | sort); }
cp -r rs rs_nan && poke rs_nan/restart.dat x 7 nan
before=$(snap rs_nan)
"$EXE" run --restart rs_nan -o time.steps=4 >rs_nan.out 2>rs_nan.err
rc=$?
[ $rc -eq 2 ] && ok || bad "NaN restart: exit $rc, expected 2: $(cat rs_nan.err)"
grep -q "restart.dat:[0-9]*: array x: value 7 (vertex 2, y) is nan; a restart state must be finite" rs_nan.err && ok ||
    bad "NaN restart message: $(cat rs_nan.err)"
[ "$(snap rs_nan)" = "$before" ] && ok || bad "NaN restart changed the run folder"
cp -r rs rs_inf && poke rs_inf/restart.dat v 5 inf
"$EXE" run --restart rs_inf -o time.steps=4 >rs_inf.out 2>rs_inf.err
[ $? -eq 2 ] && grep -q "array v: value 5 (vertex 1, z) is inf" rs_inf.err && ok || bad "Inf restart: $(cat rs_inf.err)"
# a restart.dat far larger than this scene's state: refused from its size
cp -r rs rs_big && truncate -s 1G rs_big/restart.dat
before=$(snap rs_big)
(ulimit -v 400000; "$EXE" run --restart rs_big -o time.steps=4 >rs_big.out 2>rs_big.err)
rc=$?
[ $rc -eq 2 ] && grep -q "restart.dat: 1073741824 bytes.*the limit for the restart file of this scene" rs_big.err &&
    ok || bad "oversized restart: exit $rc $(cat rs_big.err)"
[ "$(snap rs_big)" = "$before" ] && ok || bad "oversized restart changed the run folder"
# the unpoked copy still continues
"$EXE" run --restart rs -o time.steps=4 --quiet && ok || bad "a good restart"

# ---- 3b. oversized configuration files: refused from their size, in little memory
truncate -s 1G huge.json
(ulimit -v 400000; "$EXE" run huge.json --out huge >huge.out 2>huge.err)
rc=$?
[ $rc -eq 2 ] && ok || bad "1 GB config: exit $rc, expected 2"
grep -q "huge.json: 1073741824 bytes (1.07e+03 MB); the limit for a configuration file (EO_CFG_MAX_BYTES) is 8388608 bytes" huge.err &&
    ok || bad "1 GB config message: $(cat huge.err)"
[ ! -e huge ] && ok || bad "1 GB config wrote huge/"
# a real 10 MB JSON document (a point cloud): refused the same way
$PY -c "
import json
json.dump({'mesh': {'points': [[i * 1e-3, 0.5, 0.25] for i in range(400000)]}}, open('ten.json', 'w'))"
"$EXE" run ten.json --out ten >ten.out 2>ten.err
[ $? -eq 2 ] && grep -q "ten.json: [0-9]* bytes.*the limit for a configuration file" ten.err && [ ! -e ten ] && ok ||
    bad "10 MB config: $(cat ten.err)"
# a suite file goes through the same loader
(ulimit -v 400000; "$EXE" bench huge.json >hb.out 2>hb.err)
[ $? -eq 2 ] && grep -q "limit for a configuration file" hb.err && ok || bad "1 GB suite: $(cat hb.err)"
rm -f huge.json

# ---- 3c. a number that overflows a double is malformed JSON: never an infinite value
printf '{\n  "time": {"dt": 1e999}\n}\n' >inf.json
"$EXE" run inf.json --out inf >inf.out 2>inf.err
[ $? -eq 2 ] && grep -q "inf.json:2:.*real number overflow" inf.err && [ ! -e inf ] && ok || bad "1e999: $(cat inf.err)"
"$EXE" run -o time.dt=1e999 --out inf >inf2.out 2>inf2.err
[ $? -eq 2 ] && grep -q "command line -o time.dt: expected a number" inf2.err && ok || bad "-o 1e999: $(cat inf2.err)"

echo "cli_diagnose: $pass passed, $fail failed"
[ $fail -eq 0 ]
