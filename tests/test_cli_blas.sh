#!/usr/bin/env bash
# The BLAS line and the re-execution with OPENBLAS_CORETYPE (cli/blas_fix.c):
#  - `run --profile` prints "profile: BLAS ..." naming the core, summary.json has "blas"
#    with the same core and the thread count;
#  - OPENBLAS_CORETYPE=Prescott set by the user is kept (core Prescott; on an AVX2 /
#    AVX-512 CPU reported as a fallback with a recommended coretype);
#  - with ELASTOPT_BLAS_FIX=force it is overridden: exactly one re-execution (strace when
#    present), the recommended core runs, "(fixed from Prescott)" in the profile and
#    fixed_from in summary.json; --no-blas-fix and ELASTOPT_NO_BLAS_FIX=1 opt out;
#  - threads: 1 by default, the user's OPENBLAS_NUM_THREADS kept (threads_policy).
# The fallback cases need an AVX CPU and OpenBLAS; elsewhere only the first checks run.
set -u
EXE="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
T="${EO_BUILD_ROOT:-/tmp}/testtmp/cli_blas"
rm -rf "$T" && mkdir -p "$T" && cd "$T" || exit 1
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }
unset OPENBLAS_CORETYPE ELASTOPT_BLAS_FIXED_FROM ELASTOPT_NO_BLAS_FIX ELASTOPT_BLAS_FIX
RUN=(run --force --profile --quiet -o time.steps=1 -o output.vtu=false)

# field of summary.json (python expression on s["blas"])
blas() { python3 -c "import json,sys; b=json.load(open(sys.argv[1]+'/summary.json'))['blas']; print($2)" "$1"; }

"$EXE" "${RUN[@]}" --out plain > plain.txt 2>&1
[ $? -eq 0 ] && ok || bad "plain run"
line=$(grep '^profile: BLAS ' plain.txt)
[ -n "$line" ] && ok || bad "no BLAS line in --profile output"
core=$(blas plain "b['core']")
name=$(blas plain "b['name']")
[ "$name" != unknown ] && ok || bad "BLAS not identified: $(blas plain b)"
[ "$(blas plain "b['threads'] >= 1")" = True ] && ok || bad "threads: $(blas plain b)"
[ "$(blas plain "b['fixed_from'] is None")" = True ] && ok || bad "fixed_from without a re-execution"
pol=$(blas plain "b['threads_policy']")
case "$pol" in
    "1 (elastopt's default"*) [ "$(blas plain "b['threads']")" = 1 ] && ok || bad "default, threads $(blas plain b)" ;;
    *) [ "$name" != OpenBLAS ] && ok || bad "threads_policy '$pol'" ;;
esac
OPENBLAS_NUM_THREADS=2 "$EXE" "${RUN[@]}" --out two > two.txt 2>&1
if [ "$name" = OpenBLAS ]; then
    [ "$(blas two "b['threads']")" = 2 ] && ok || bad "OPENBLAS_NUM_THREADS=2 not kept: $(blas two b)"
fi
[ "$(blas two "b['threads_policy']")" = "OPENBLAS_NUM_THREADS=2 (user)" ] && ok || bad "policy: $(blas two b)"
case "$line" in *"core $core"*) ok ;; *) [ -z "$core" ] && ok || bad "profile line '$line' lacks core $core" ;; esac

if [ "$name" = OpenBLAS ] && grep -q -w avx /proc/cpuinfo 2>/dev/null; then
    # the user's choice is kept, and reported as a fallback
    OPENBLAS_CORETYPE=Prescott "$EXE" "${RUN[@]}" --out user > user.txt 2>&1
    [ "$(blas user "b['core']")" = Prescott ] && ok || bad "user's OPENBLAS_CORETYPE overridden: $(blas user b)"
    rec=$(blas user "b['recommended_coretype']")
    [ "$(blas user "b['fallback']")" = True ] && [ "$rec" != None ] && ok || bad "Prescott not a fallback: $(blas user b)"
    grep -q "core Prescott (a generic fallback on this CPU: OPENBLAS_CORETYPE=$rec" user.txt && ok ||
        bad "fallback not in the profile line: $(grep 'profile: BLAS' user.txt)"

    # forced: one re-execution onto the recommended core
    OPENBLAS_CORETYPE=Prescott ELASTOPT_BLAS_FIX=force "$EXE" "${RUN[@]}" --out fixed > fixed.txt 2>&1
    [ $? -eq 0 ] && ok || bad "fixed run exit"
    [ "$(blas fixed "b['core']")" = "$rec" ] && ok || bad "core after the fix: $(blas fixed b)"
    [ "$(blas fixed "b['fixed_from']")" = Prescott ] && ok || bad "fixed_from: $(blas fixed b)"
    [ "$(blas fixed "b['fallback']")" = False ] && ok || bad "still a fallback: $(blas fixed b)"
    grep -q "^profile: BLAS OpenBLAS .*core $rec (fixed from Prescott)" fixed.txt && ok ||
        bad "profile line: $(grep 'profile: BLAS' fixed.txt)"
    if command -v strace >/dev/null; then
        n=$(OPENBLAS_CORETYPE=Prescott ELASTOPT_BLAS_FIX=force strace -f -e trace=execve "$EXE" --version 2>&1 |
            grep -c 'execve("/proc/self/exe"')
        [ "$n" -eq 1 ] && ok || bad "$n re-executions, expected 1"
    fi

    # opting out
    OPENBLAS_CORETYPE=Prescott ELASTOPT_BLAS_FIX=force "$EXE" "${RUN[@]}" --no-blas-fix --out off1 > off1.txt 2>&1
    [ $? -eq 0 ] && [ "$(blas off1 "b['core']")" = Prescott ] && ok || bad "--no-blas-fix: $(blas off1 b)"
    OPENBLAS_CORETYPE=Prescott ELASTOPT_BLAS_FIX=force ELASTOPT_NO_BLAS_FIX=1 "$EXE" "${RUN[@]}" --out off2 > off2.txt 2>&1
    [ "$(blas off2 "b['core']")" = Prescott ] && ok || bad "ELASTOPT_NO_BLAS_FIX=1: $(blas off2 b)"
fi

echo "cli_blas: $pass passed, $fail failed"
[ $fail -eq 0 ]
