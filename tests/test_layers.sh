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
names=(lib materials solvers problems)
for o in "$objdir"/*.o; do
  l=$(layer_of "$o")
  [ "$l" = 9 ] && continue
  nm --defined-only "$o" | awk '$2 ~ /[TDRBC]/ {print $3}' | sed "s|\$| $l|" >> "$tmp/defs"
done
sort -u "$tmp/defs" > "$tmp/defs.s"
fail=0
pass=0
for o in "$objdir"/*.o; do
  l=$(layer_of "$o")
  [ "$l" = 9 ] && continue
  while read -r sym; do
    dl=$(awk -v s="$sym" '$1 == s {print $2; exit}' "$tmp/defs.s")
    if [ -n "$dl" ] && [ "$dl" -gt "$l" ]; then
      echo "FAIL: $(basename "$o") (${names[$l]}/) uses $sym defined in ${names[$dl]}/"; fail=$((fail + 1))
    fi
  done < <(nm -u "$o" | awk '{print $2}')
  pass=$((pass + 1))
  for f in system popen fork execv execvp execl execlp posix_spawn; do
    if nm -u "$o" | awk '{print $2}' | grep -qx "$f"; then
      echo "FAIL: $(basename "$o") calls $f (the library never spawns a process)"; fail=$((fail + 1))
    fi
  done
done
echo "layers: $pass passed, $fail failed"
[ $fail -eq 0 ]
