#!/usr/bin/env bash
# Hostile scene inputs on the command line (issue 14, item 6): each is refused before
# anything is written (exit 2, a message naming the key and file:line or the -o
# override) or, for overlapping boundary sets with different motions, warned about
# naming both entries.
set -u
EXE="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
T="${EO_BUILD_ROOT:-/tmp}/testtmp/cli_hostile"
rm -rf "$T" && mkdir -p "$T" && cd "$T" || exit 1
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }

# a barrier material from an inverted start: refused at once, nothing written
"$EXE" run -o material.model=neo_hookean -o initial.reflect.normal=[1,0,0] --out inv 2> inv.err
rc=$?
[ $rc -eq 2 ] && ok || bad "barrier from an inverted start: exit $rc"
grep -q "barrier material" inv.err && grep -q "initial.reflect" inv.err && grep -q "first: tet 0" inv.err && ok ||
    bad "barrier message: $(cat inv.err)"
[ ! -e inv ] && ok || bad "barrier refusal wrote inv/"

# a generated box that cannot fit this machine: the key and its file:line
cat > big.json <<'J'
{
  "mesh": {"generate": {"cells": [4000, 400, 400]}}
}
J
"$EXE" run big.json --out big 2> big.err
rc=$?
[ $rc -eq 2 ] && ok || bad "huge box: exit $rc"
grep -q "big.json:2:.*mesh.generate.cells.*GB" big.err && ok || bad "huge box message: $(cat big.err)"
[ ! -e big ] && ok || bad "huge box wrote big/"
"$EXE" run -o mesh.generate.cells=[100000,100000,100] --out big 2> big2.err
[ $? -eq 2 ] && grep -q "command line -o mesh.generate.cells" big2.err && ok || bad "huge box -o: $(cat big2.err)"

# a step count whose per-step records cannot be held: the key and its file:line
cat > steps.json <<'J'
{
  "time": {"steps": 2000000000}
}
J
"$EXE" run steps.json --out steps 2> steps.err
rc=$?
[ $rc -eq 2 ] && grep -q "steps.json:2:.*time.steps.*GB" steps.err && [ ! -e steps ] && ok ||
    bad "huge time.steps: exit $rc, $(cat steps.err)"

# overlapping boundary sets: different motions warn naming both; equal motions do not
cat > ov.json <<'J'
{"boundary": [{"box": [[-1,-1,-1],[0.05,1,1]], "fixed": true},
              {"box": [[-1,-1,-1],[0.2,1,1]], "translate": [0,0,0.1]},
              {"box": [[-1,-1,-1],[0.01,1,1]], "fixed": true}],
 "time": {"steps": 1}, "output": {"vtu": false}}
J
"$EXE" run ov.json --out ov > ov.out 2> ov.err
rc=$?
[ $rc -eq 0 ] && ok || bad "overlap run: exit $rc $(cat ov.err)"
grep -q "warning: boundary.0 and boundary.1 share 18 vertices but prescribe different motions" ov.err && ok ||
    bad "overlap 0/1 warning: $(cat ov.err)"
grep -q "warning: boundary.1 and boundary.2 share 9 vertices" ov.err && ok || bad "overlap 1/2 warning"
[ "$(grep -c 'warning: boundary' ov.err)" = 2 ] && ok || bad "exactly two overlap warnings: $(cat ov.err)"
cat > ov2.json <<'J'
{"boundary": [{"box": [[-1,-1,-1],[0.05,1,1]], "fixed": true},
              {"box": [[-1,-1,-1],[0.2,1,1]], "fixed": true}],
 "time": {"steps": 1}, "output": {"vtu": false}}
J
"$EXE" run ov2.json --out ov2 > ov2.out 2> ov2.err
[ $? -eq 0 ] && ! grep -q "warning: boundary" ov2.err && ok || bad "same-motion overlap must not warn: $(cat ov2.err)"

# "did you mean": a subcommand, an option, a -o key, a mesh extension (exit 2 each)
"$EXE" runn 2> dym1.err
[ $? -eq 2 ] && grep -q "unknown command 'runn' (did you mean 'run'?); valid: list help run" dym1.err && ok ||
    bad "subcommand hint: $(cat dym1.err)"
"$EXE" run --qiet 2> dym2.err
[ $? -eq 2 ] && grep -q "unknown option '--qiet' (did you mean '--quiet'?)" dym2.err && ok || bad "option hint: $(cat dym2.err)"
"$EXE" run -o solver.hessianfix=abs --out dym 2> dym3.err
[ $? -eq 2 ] && grep -q "solver.hessianfix: unknown key (did you mean 'solver.hessian_fix'?); valid keys here:" dym3.err &&
    [ ! -e dym ] && ok || bad "key hint: $(cat dym3.err)"
"$EXE" help lbgfs 2> dym5.err
[ $? -eq 2 ] && grep -q "named 'lbgfs' (did you mean 'lbfgs'?)" dym5.err && ok || bad "help hint: $(cat dym5.err)"
"$EXE" mesh nothing.msh4 2> dym4.err
[ $? -eq 2 ] && grep -q "unknown mesh format (did you mean '.msh'?)" dym4.err && ok || bad "extension hint: $(cat dym4.err)"

echo "cli_hostile: $pass passed, $fail failed"
[ $fail -eq 0 ]
