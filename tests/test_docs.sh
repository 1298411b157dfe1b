#!/usr/bin/env bash
# The generated references in docs/ match what the binary documents (run
# scripts/gen-docs.sh after changing a key, a default or a method). Skipped (77) when the
# build lacks an optional backend that the committed docs list.
set -u
exe=$1
src=${EO_SOURCE_ROOT:?}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$exe" list > "$tmp/list" || { echo "elastopt list failed"; exit 1; }
for b in nlopt ipopt petsc_ksp; do
  if grep -q "^  $b " "$src/docs/methods.md" && ! grep -q "^  $b " "$tmp/list"; then
    echo "backend $b not built: skipping the docs comparison"; exit 77
  fi
done
fail=0
"$exe" help > "$tmp/help"
sed -n '/^```$/,/^```$/p' "$src/docs/config-reference.md" | sed '1d;$d' > "$tmp/help.doc"
sed -n '/^```$/,/^```$/p' "$src/docs/methods.md" | sed '1d;$d' > "$tmp/list.doc"
if ! diff -u "$tmp/help.doc" "$tmp/help" > "$tmp/d1"; then
  echo "docs/config-reference.md is stale (run scripts/gen-docs.sh):"; head -40 "$tmp/d1"; fail=1
fi
if ! diff -u "$tmp/list.doc" "$tmp/list" > "$tmp/d2"; then
  echo "docs/methods.md is stale (run scripts/gen-docs.sh):"; head -40 "$tmp/d2"; fail=1
fi
if [ $fail = 0 ]; then echo "docs: 2 passed, 0 failed"; else echo "docs: 0 passed, 1 failed"; fi
exit $fail
