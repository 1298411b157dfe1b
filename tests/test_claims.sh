#!/usr/bin/env bash
# The claims register (bench/claims/*.json -> docs/claims.md, scripts/claims.py): every
# file of the repository is valid (fields, status vocabulary, results that exist) and
# docs/claims.md is current; and the validator refuses what it must, on a scratch copy:
# an unknown status, a missing field, an unknown key, a result path that does not exist,
# a stale page.
set -u
src=${EO_SOURCE_ROOT:?}
py=/usr/bin/python3
[ -x "$py" ] || py=$(command -v python3) || { echo "no python3: skip"; exit 77; }
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

"$py" "$src/scripts/claims.py" --check > /tmp/claims.$$ 2>&1 && ok || bad "the repository's claims: $(cat /tmp/claims.$$)"
rm -f /tmp/claims.$$

t=$(mktemp -d)
trap 'rm -rf "$t"' EXIT
mkdir -p "$t/scripts" "$t/bench/claims" "$t/docs" "$t/bench/results"
cp "$src/scripts/claims.py" "$t/scripts/"
echo "numbers" > "$t/bench/results/x.txt"
good='{"id": "a", "paper": "P 2020", "claim": "c", "method": "m", "scenes": ["s"], "metric": "t", "measured": "2x",
 "status": "reproduced", "results": ["bench/results/x.txt"], "notes": ""}'
echo "$good" > "$t/bench/claims/a.json"
"$py" "$t/scripts/claims.py" > /dev/null && ok || bad "a valid claim is refused"
"$py" "$t/scripts/claims.py" --check > /dev/null && ok || bad "a fresh page is called stale"
grep -q '^## a$' "$t/docs/claims.md" && grep -q 'reproduced' "$t/docs/claims.md" && ok || bad "page lacks the claim"
echo "more" >> "$t/docs/claims.md"
"$py" "$t/scripts/claims.py" --check > /dev/null 2>&1 && bad "a stale page passes" || ok
"$py" "$t/scripts/claims.py" > /dev/null   # fresh again

refused() { # name, json text, expected message part
  echo "$2" > "$t/bench/claims/$1.json"
  out=$("$py" "$t/scripts/claims.py" --check 2>&1) && bad "$1 accepted" || {
    case "$out" in *"$3"*) ok ;; *) bad "$1: message '$out' lacks '$3'" ;; esac; }
  rm -f "$t/bench/claims/$1.json"
}
refused b "${good/\"a\"/\"b\"}" "docs/claims.md: not current"   # valid but the page lacks it
refused c "$(echo "${good/\"a\"/\"c\"}" | sed 's/"reproduced"/"confirmed"/')" "status 'confirmed'"
refused d "$(echo "${good/\"a\"/\"d\"}" | sed 's/"metric": "t", //')" "missing key 'metric'"
refused e "$(echo "${good/\"a\"/\"e\"}" | sed 's/"notes": ""/"notes": "", "verdict": 1/')" "unknown key 'verdict'"
refused f "$(echo "${good/\"a\"/\"f\"}" | sed 's#bench/results/x.txt#bench/results/missing.csv#')" "does not exist"
refused g "${good/\"a\"/\"other\"}" "differs from the file name"
refused h "$(echo "${good/\"a\"/\"h\"}" | sed 's#"bench/results/x.txt"##')" "only not_tested has no results"
refused i "{ not json" "not readable JSON"
"$py" "$t/scripts/claims.py" --check > /dev/null && ok || bad "the register is not back to valid"

echo "claims: $pass passed, $fail failed"
[ $fail -eq 0 ]
