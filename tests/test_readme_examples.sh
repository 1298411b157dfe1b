#!/usr/bin/env bash
# readme_examples (suite docs, full suite only): what README.md shows runs against this build.
#  - every ```sh block is run with bash -e in a scratch folder that links the repository's
#    examples/, bench/, python/, include/ and build/ (= this build); a block that calls
#    scripts/setup.sh (the two commands at the top) is checked with bash -n, then the part
#    after `bash scripts/setup.sh && ` of each line runs, except `meson test`, which is
#    checked by listing the tests it names (the full suite, and the quick suite the text
#    describes as "about 40" tests: 30-60 accepted);
#  - the ```c block is compiled with the command the README gives (`cc -std=c11 twist.c …`)
#    and run with the LD_LIBRARY_PATH it gives; it must print one line per step;
#  - the ```python block runs with the README's `PYTHONPATH=python /usr/bin/python3`.
# Usage: test_readme_examples.sh   (EO_SOURCE_ROOT, EO_BUILD_ROOT from meson)
set -u
src=${EO_SOURCE_ROOT:?}
build=${EO_BUILD_ROOT:?}
readme=$src/README.md
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for d in examples bench python include; do ln -s "$src/$d" "$tmp/$d"; done
ln -s "$build" "$tmp/build"
fail=0 pass=0 skip=0
ok() { echo "ok: $*"; pass=$((pass + 1)); }
bad() { echo "FAILED: $*"; fail=$((fail + 1)); }

# blocks: lang<TAB>index into $tmp/block.N
/usr/bin/python3 - "$readme" "$tmp" > "$tmp/blocks" <<'EOF' || { echo "cannot read $1"; exit 1; }
import re, sys
text = open(sys.argv[1], encoding="utf-8").read().split("\n")
n, lang, body = 0, None, []
for line in text:
    m = re.match(r"^```(\w*)\s*$", line)
    if lang is None and m and m.group(1):
        lang, body = m.group(1), []
    elif lang is not None and line.strip() == "```":
        open("%s/block.%d" % (sys.argv[2], n), "w").write("\n".join(body) + "\n")
        print("%s\t%d" % (lang, n))
        n, lang = n + 1, None
    elif lang is not None:
        body.append(line)
EOF
asan=0
ldd "$build/libelastopt.so" 2>/dev/null | grep -q 'libasan\|libubsan' && asan=1
n_c=0 n_py=0 n_sh=0
while IFS=$'\t' read -r lang i; do
  f=$tmp/block.$i
  case $lang in
    sh)
      n_sh=$((n_sh + 1))
      if grep -q 'scripts/setup.sh' "$f"; then
        bash -n "$f" && ok "setup block $i parses" || bad "setup block $i does not parse"
        while IFS= read -r line; do
          cmd=${line#bash scripts/setup.sh && }
          cmd=${cmd%%#*}
          [ -z "${cmd// /}" ] && continue
          if [[ $cmd == meson\ test* ]]; then
            n=$(cd "$tmp" && meson test -C build --list 2>/dev/null | grep -c .)
            [ "$n" -gt 50 ] && ok "full suite lists $n tests" || bad "full suite lists $n tests"
            q=$(cd "$tmp" && meson test -C build --suite quick --list 2>/dev/null | grep -c .)
            { [ "$q" -ge 30 ] && [ "$q" -le 60 ]; } && ok "quick suite lists $q tests (README: about 40)" \
              || bad "quick suite lists $q tests, the README says about 40"
          else
            (cd "$tmp" && bash -ec "$cmd" > "$tmp/out.$i" 2>&1) && ok "runs: $cmd" \
              || { bad "exit $? from: $cmd"; tail -5 "$tmp/out.$i"; }
          fi
        done < "$f"
      else
        (cd "$tmp" && bash -e "$f" > "$tmp/out.$i" 2>&1) && ok "sh block $i ($(grep -c . "$f") lines)" \
          || { bad "sh block $i"; cat "$f"; tail -20 "$tmp/out.$i"; }
      fi
      ;;
    c)
      n_c=$((n_c + 1))
      if [ $asan = 1 ]; then echo "skip: C block (sanitizer build of the library)"; skip=$((skip + 1)); continue; fi
      cc_cmd=$(grep -o 'cc -std=c11 twist\.c[^`]*' "$readme" | head -1)
      run_cmd=$(grep -o 'LD_LIBRARY_PATH=build \./twist' "$readme" | head -1)
      [ -n "$cc_cmd" ] && [ -n "$run_cmd" ] || { bad "README gives no build/run command for the C example"; continue; }
      cp "$f" "$tmp/twist.c"
      if ! (cd "$tmp" && ${CC:-cc} ${cc_cmd#cc } > "$tmp/cc.log" 2>&1); then
        bad "C block does not compile: $cc_cmd"; cat "$tmp/cc.log"; continue
      fi
      if (cd "$tmp" && env $run_cmd > "$tmp/c.out" 2>&1); then
        steps=$(grep -c '^step [0-9]*: [0-9]* iterations, converged' "$tmp/c.out")
        [ "$steps" = 10 ] && ok "C block: 10 converged steps" || { bad "C block printed $steps converged steps"; cat "$tmp/c.out"; }
      else
        bad "C block exit $?"; cat "$tmp/c.out"
      fi
      ;;
    python)
      n_py=$((n_py + 1))
      if ! /usr/bin/python3 -c 'import numpy, cffi, scipy' 2>/dev/null; then
        echo "skip: Python block (Debian's python3-numpy, python3-cffi, python3-scipy missing)"; skip=$((skip + 1)); continue
      fi
      if [ $asan = 1 ]; then echo "skip: Python block (sanitizer build of the library)"; skip=$((skip + 1)); continue; fi
      grep -q 'PYTHONPATH=python /usr/bin/python3' "$readme" || bad "README gives no way to run the Python example"
      if (cd "$tmp" && PYTHONPATH=python /usr/bin/python3 "$f" > "$tmp/py.out" 2>&1); then
        rows=$(grep -c '^[0-9]* [0-9]* converged' "$tmp/py.out")
        { [ "$rows" = 10 ] && grep -q '^g = .*unknowns$' "$tmp/py.out"; } && ok "Python block: 10 converged steps and the step problem" \
          || { bad "Python block output"; cat "$tmp/py.out"; }
      else
        bad "Python block exit"; tail -20 "$tmp/py.out"
      fi
      ;;
    *) ;;
  esac
done < "$tmp/blocks"
[ $n_sh -ge 2 ] || bad "expected the setup block and a CLI block in README.md, found $n_sh sh blocks"
[ $n_c -ge 1 ] || bad "no C example in README.md"
[ $n_py -ge 1 ] || bad "no Python example in README.md"
echo "readme_examples: $pass passed, $fail failed, $skip skipped"
[ $fail = 0 ]
