#!/usr/bin/env bash
# Clean layers (issue 9): lib/ < materials/ < solvers/ < problems/. The objects of each
# layer of libelastopt reference no symbol defined in a higher layer (checked with nm on
# the static library's objects), and the library calls no system()/popen()/fork()/exec*()
# (it never spawns a process).
set -u
BUILD="${EO_BUILD_ROOT:?}"
objdir=""
for d in "$BUILD"/libelastopt.a.p "$BUILD"/libelastopt.so*.p; do
  ls "$d"/*.o > /dev/null 2>&1 && { objdir=$d; break; }
done
[ -n "$objdir" ] || { echo "no object folder of libelastopt in $BUILD"; exit 1; }
command -v nm >/dev/null || { echo "SKIP: nm not installed"; exit 77; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
layer_of() {
  case "$(basename "$1")" in
    lib_*) echo 0 ;; materials_*) echo 1 ;; solvers_*) echo 2 ;; problems_*) echo 3 ;; *) echo 9 ;;
  esac
}
# all objects in one nm call each: "file: ... type symbol" lines; layer from the object name
lay='function lay(f) { sub(/.*\//, "", f); if (f ~ /^lib_/) return 0; if (f ~ /^materials_/) return 1;
  if (f ~ /^solvers_/) return 2; if (f ~ /^problems_/) return 3; return 9 }'
nm -A --defined-only "$objdir"/*.o | awk "$lay"' { split($1, a, ":"); l = lay(a[1]); if (l < 9 && $(NF-1) ~ /[TDRBC]/) print $NF, l }' |
  sort -u > "$tmp/defs.s"
nm -A -u "$objdir"/*.o | awk "$lay"' { split($1, a, ":"); l = lay(a[1]); f = a[1]; sub(/.*\//, "", f); if (l < 9) print $NF, f, l }' > "$tmp/uses"
fail=0
pass=$(cut -d' ' -f2 "$tmp/uses" | sort -u | wc -l)
# one pass: a use of a symbol defined in a higher layer, or a process-spawning call
out=$(awk -v names="lib materials solvers problems" '
  BEGIN { split(names, nm, " ") }
  NR == FNR { def[$1] = $2; next }
  ($1 in def) && def[$1] > $3 { printf "FAIL: %s (%s/) uses %s defined in %s/\n", $2, nm[$3 + 1], $1, nm[def[$1] + 1] }
  $1 ~ /^(system|popen|fork|execv|execvp|execl|execlp|posix_spawn)$/ { printf "FAIL: %s calls %s (the library never spawns a process)\n", $2, $1 }
' "$tmp/defs.s" "$tmp/uses")
if [ -n "$out" ]; then echo "$out"; fail=$(printf '%s\n' "$out" | wc -l); fi
lower=$(awk 'NR == FNR { def[$1] = $2; next } ($1 in def) && def[$1] < $3' "$tmp/defs.s" "$tmp/uses" | wc -l)
[ "$lower" -gt 100 ] || { echo "FAIL: only $lower downward references found: the check matches nothing"; fail=$((fail + 1)); }
echo "layers: $pass passed, $fail failed"
[ $fail -eq 0 ]
