#!/usr/bin/env bash
# elastopt mesh / convert: --json values (generator and the shared IPC bar, credit:
# ipc-sim/IPC input/tetMeshes, MIT), convert round trips through every format, exit 2
# with file:line for bad inputs, exit 2 and nothing left behind for unwritable output.
set -u
EXE="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
SHARED="${EO_SHARED:-$(dirname "$0")/../../shared}"
if [ ! -f "$SHARED/meshes/ipc_bar-2523.msh" ]; then
    echo "cli_mesh: shared meshes not found at $SHARED/meshes (set EO_SHARED): skipped"; exit 77
fi
T="${EO_BUILD_ROOT:-/tmp}/testtmp/cli_mesh"
rm -rf "$T" && mkdir -p "$T" && cd "$T" || exit 1
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }

# check_json JSON_TEXT PYTHON_ASSERTIONS (o is the parsed object)
check_json() {
    printf '%s' "$1" | python3 -c "
import json, sys
o = json.load(sys.stdin)
close = lambda a, b, t=1e-12: abs(a - b) <= t * max(1.0, abs(b))
$2
" && ok || bad "json check failed: $2 on $1"
}

# --- mesh --json on the generator and the IPC bar
out=$("$EXE" mesh --json gen:2,0.5,1.5:3,4,5:5)
[ $? -eq 0 ] && ok || bad "mesh gen exit"
check_json "$out" 'assert o["vertices"] == 120 and o["tets"] == 300, o
assert close(o["volume"], 1.5)
assert o["bbox"] == [0, 0, 0, 2, 0.5, 1.5], o["bbox"]
assert o["min_volume"] > 0 and o["reoriented"] == 0 and o["dropped_tets"] == 0'

BAR="$SHARED/meshes/ipc_bar-2523.msh"
out=$("$EXE" mesh --json "$BAR")
[ $? -eq 0 ] && ok || bad "mesh bar exit"
check_json "$out" 'assert o["vertices"] == 886 and o["tets"] == 2523
assert close(o["volume"], 5.0)
assert o["bbox"] == [0, 0, 0, 10, 0.5, 1], o["bbox"]
assert o["boundary_faces"] == 1618 and o["min_volume"] > 0 and 0 < o["worst_quality"] <= 1'
"$EXE" mesh "$BAR" | grep -q "^tets *2523$" && ok || bad "text output"

# --- convert round trips: msh -> node -> mesh -> msh, plus vtu and obj
"$EXE" convert "$BAR" a.node >/dev/null && ok || bad "convert to tetgen"
[ -f a.node ] && [ -f a.ele ] && ok || bad "tetgen pair written"
"$EXE" convert a.ele b.mesh >/dev/null && ok || bad "convert tetgen (.ele name) to medit"
"$EXE" convert b.mesh c.msh >/dev/null && ok || bad "convert medit to gmsh"
"$EXE" convert a d.msh >/dev/null && ok || bad "convert tetgen base name to gmsh"
"$EXE" convert c.msh e.vtu >/dev/null && ok || bad "convert to vtu"
"$EXE" convert c.msh f.obj >/dev/null && ok || bad "convert to obj"
"$EXE" convert gen:1,1,1:2,2,2:5 g.mesh >/dev/null && ok || bad "convert generator"
for f in a.node b.mesh c.msh d.msh; do
    check_json "$("$EXE" mesh --json $f)" 'assert o["vertices"] == 886 and o["tets"] == 2523 and close(o["volume"], 5.0), o'
done
check_json "$("$EXE" mesh --json g.mesh)" 'assert o["tets"] == 40 and close(o["volume"], 1.0)'
head -c 200 e.vtu | grep -q 'NumberOfPoints="886" NumberOfCells="2523"' && ok || bad "vtu header"
[ "$(grep -c '^f ' f.obj)" -eq 1618 ] && ok || bad "obj has 1618 triangles"
ls | grep -q '\.tmp\.' && bad "temporary files left" || ok

# --- bad inputs: exit 2, one message "elastopt: error: FILE:LINE: ..."
expect_fail() { # NAME PATTERN ARGS...
    local name=$1 pat=$2
    shift 2
    err=$("$EXE" "$@" 2>&1 >/dev/null)
    rc=$?
    [ $rc -eq 2 ] && ok || bad "$name: exit $rc, expected 2"
    printf '%s' "$err" | grep -q -- "$pat" && ok || bad "$name: message '$err' lacks '$pat'"
}
printf '$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 one 0\n4 0 0 1\n$EndNodes\n' >tok.msh
expect_fail "non-numeric" "^elastopt: error: tok.msh:8: vertex 3: expected y coordinate, got 'one'" mesh tok.msh
head -c 30000 "$BAR" >trunc.msh
expect_fail "truncated" "^elastopt: error: trunc.msh:[0-9]*: .*got end of file" mesh trunc.msh
printf '4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n' >r.node
printf '1 4 0\n1 1 2 3 7\n' >r.ele
expect_fail "index out of range" "^elastopt: error: r.ele:2: tet 1: expected point index in \[1, 4\], got 7" convert r.node out.msh
printf '5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 9 9 9\n' >u.node
printf '1 4 0\n1 1 2 3 4\n' >u.ele
expect_fail "unreferenced" "^elastopt: error: u.node:6: vertex 5: not used by any tet" mesh u
"$EXE" mesh --json --drop-unreferenced u 2>/dev/null | python3 -c 'import json,sys; o=json.load(sys.stdin); assert o["vertices"]==4 and o["dropped_vertices"]==1' && ok || bad "drop unreferenced"
printf '4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 inf\n' >n.node
printf '1 4 0\n1 1 2 3 4\n' >n.ele
expect_fail "inf coordinate" "^elastopt: error: n.node:5: vertex 4: expected finite coordinates" mesh n.ele
printf '4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n' >d.node
printf '2 4 0\n1 1 2 3 4\n2 2 1 3 4\n' >d.ele
expect_fail "duplicate tet" "^elastopt: error: d.ele:3: tet 2: duplicate of tet 1" mesh d.node
printf '4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 2 2 0\n' >z.node
printf '1 4 0\n1 1 2 3 4\n' >z.ele
expect_fail "zero volume" "^elastopt: error: z.ele:2: tet 1: zero volume" mesh z.node
expect_fail "missing file" "^elastopt: error: missing.msh: cannot open" mesh missing.msh
: >empty.mesh
expect_fail "empty file" "^elastopt: error: empty.mesh: the file is empty (0 bytes)" mesh empty.mesh
expect_fail "bad gen spec" "^elastopt: error: gen:1,1:2,2,2: expected gen:" mesh gen:1,1:2,2,2
expect_fail "read-only output format" "^elastopt: error: out.stl: stl files can be read, not written" convert c.msh out.stl
expect_fail "unknown output format" "expected an output name ending in" convert c.msh out.xyz
expect_fail "usage" "expected a mesh file" mesh

# --- unwritable output folder: exit 2, nothing written
: >plainfile
for ext in node mesh msh vtu obj; do
    expect_fail "missing folder .$ext" "^elastopt: error: .*no/such/dir/out.$ext: cannot write" convert c.msh "no/such/dir/out.$ext"
    expect_fail "parent is a file .$ext" "^elastopt: error: plainfile/out.$ext: cannot write" convert c.msh "plainfile/out.$ext"
done
[ -e no ] && bad "folder created for unwritable output" || ok
ls | grep -q '^out\.\|\.tmp\.' && bad "output or temporary file left: $(ls)" || ok
# a failed conversion does not replace an existing output
cp c.msh keep.msh
expect_fail "bad input keeps old output" "tok.msh:8" convert tok.msh keep.msh
cmp -s c.msh keep.msh && ok || bad "keep.msh was modified by a failed convert"

echo "cli_mesh: $pass passed, $fail failed"
[ $fail -eq 0 ]
