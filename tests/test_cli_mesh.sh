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

# --- hostile paths: exit 2 at once with a message (never a hang on a FIFO)
mkfifo fifo.msh && ok || bad "mkfifo"
mkdir -p folder.msh
expect_fail "FIFO input" "^elastopt: error: fifo.msh: is a FIFO (named pipe); expected a mesh file" mesh fifo.msh
expect_fail "folder input" "^elastopt: error: folder.msh: is a folder; expected a mesh file" mesh folder.msh
ln -sf /dev/null null.mesh
expect_fail "device input" "^elastopt: error: null.mesh: is a character device" mesh null.mesh
ln -sf /dev/zero zero.msh
expect_fail "endless device input" "^elastopt: error: zero.msh: is a character device" mesh zero.msh
: >empty.msh
expect_fail "empty input" "^elastopt: error: empty.msh: the file is empty (0 bytes)" convert empty.msh x.mesh
long=$(printf 'a%.0s' $(seq 1 5000)).msh
expect_fail "long input name" "longer than the system allows" mesh "$long"
expect_fail "FIFO output" "^elastopt: error: fifo.msh: cannot write: it is a FIFO" convert gen:1,1,1:1,1,1 fifo.msh
expect_fail "folder output" "^elastopt: error: folder.msh: cannot write: it is a folder" convert gen:1,1,1:1,1,1 folder.msh
expect_fail "long output name" "longer than the system allows" convert gen:1,1,1:1,1,1 "$long"
expect_fail "device as output" "^elastopt: error: .*cannot write" convert gen:1,1,1:1,1,1 zero.msh
[ -p fifo.msh ] && [ -d folder.msh ] && [ -L zero.msh ] && ok || bad "hostile outputs were replaced"
# a TetGen pair whose .ele cannot be written leaves the existing .node untouched
printf 'old node\n' >pair.node
mkdir -p pair.ele
expect_fail "pair with a folder .ele" "^elastopt: error: pair.ele: cannot write: it is a folder" convert c.msh pair.node
[ "$(cat pair.node)" = "old node" ] && ok || bad "pair.node was changed by a failed convert"
ls | grep -q '\.tmp\.\|\.bak\.' && bad "temporary or backup files left: $(ls)" || ok

# --- tags: a Gmsh 4.1 file with physical groups (x = 0 face: 11, x = 1 face: 12, volume: 5)
python3 - <<'PY'
# unit cube, 5 tets; node k+1 at (k&1, k>>1&1, k>>2&1)
tets = [(0, 1, 2, 4), (3, 2, 1, 7), (5, 4, 7, 1), (6, 7, 4, 2), (1, 2, 4, 7)]
x0, x1 = [(0, 2, 4), (6, 4, 2)], [(3, 1, 7), (5, 7, 1)]
L = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$Entities", "0 0 2 1", "1 0 0 0 0 1 1 1 11 0",
     "2 1 0 0 1 1 1 1 12 0", "1 0 0 0 1 1 1 1 5 0", "$EndEntities", "$Nodes", "1 8 1 8", "3 1 0 8"]
L += [str(k + 1) for k in range(8)] + ["%d %d %d" % (k & 1, k >> 1 & 1, k >> 2 & 1) for k in range(8)]
L += ["$EndNodes", "$Elements", "3 9 1 9", "2 1 2 2"]
e = 1
for blk, tris in ((1, x0), (2, x1)):
    if blk == 2: L.append("2 2 2 2")
    for t in tris:
        L.append("%d %d %d %d" % ((e,) + tuple(v + 1 for v in t))); e += 1
L.append("3 1 4 5")
for t in tets:
    L.append("%d %d %d %d %d" % ((e,) + tuple(v + 1 for v in t))); e += 1
L.append("$EndElements")
open("tagged.msh", "w").write("\n".join(L) + "\n")
PY
"$EXE" mesh --json tagged.msh | python3 -c 'import json,sys; o=json.load(sys.stdin); assert o["tets"]==5 and o["tagged_triangles"]==4 and abs(o["volume"]-1)<1e-15, o' && ok || bad "tagged.msh loads"
cat >tags.json <<'JSON'
{"mesh": {"file": "tagged.msh"},
 "boundary": [{"tag": 11, "fixed": true},
              {"tag": 12, "translate": [0.01, 0, 0]}],
 "gravity": [0, 0, 0],
 "time": {"steps": 2, "dt": 0.01}, "output": {"vtu": false}}
JSON
out=$("$EXE" run tags.json --out tags_out 2>&1)
rc=$?
[ $rc -eq 0 ] && ok || bad "run tags.json: exit $rc: $out"
printf '%s' "$out" | grep -q "^boundary.0 (tag 11 of the tagged triangles; fixed): 4 vertices$" && ok || bad "tag 11 count: $out"
printf '%s' "$out" | grep -q "^boundary.1 (tag 12 of the tagged triangles; translate): 4 vertices$" && ok || bad "tag 12 count: $out"
printf '%s' "$out" | grep -q "^region 0 (material, .*): 5 tets$" && ok || bad "region count: $out"
out=$("$EXE" run tags.json --out tags_out --force --quiet 2>&1)
printf '%s' "$out" | grep -q "boundary.0" && bad "--quiet prints the scene report: $out" || ok
cat >tag7.json <<'JSON'
{"mesh": {"file": "tagged.msh"},
 "boundary": [
   {"tag": 7, "fixed": true}]}
JSON
expect_fail "absent tag" "^elastopt: error: .*tag7.json:3:.*key 'boundary.0.tag': no tagged triangle, tet or vertex carries tag 7; the mesh has triangle tags: 11, 12; tet attributes: 5; vertex markers: none" run tag7.json --out tag7_out
[ -e tag7_out ] && bad "a bad scene wrote output" || ok

# --- the IPC bunny (credit: ipc-sim/IPC input/tetMeshes/bunny.msh, MIT; geometry: Stanford
# 3D Scanning Repository) with surface / nearest selectors for 2 steps; it is y-up while
# the default gravity is -z: the run warns
BUNNY="$SHARED/meshes/ipc_bunny.msh"
cat >bunny.json <<JSON
{"mesh": {"file": "$BUNNY"},
 "material": {"model": "neo_hookean", "E": 1e5, "nu": 0.3},
 "boundary": [{"nearest": [0, -0.34, 0], "fixed": true},
              {"surface": true, "fixed": true, "release": 0.005}],
 "time": {"steps": 2, "dt": 0.01}, "output": {"vtu": false}}
JSON
out=$("$EXE" run bunny.json --out bunny_out 2>&1)
rc=$?
[ $rc -eq 0 ] && ok || bad "run bunny: exit $rc: $out"
printf '%s' "$out" | grep -q "^mesh: .*ipc_bunny.msh: 4670 vertices, 19379 tets" && ok || bad "bunny mesh line: $out"
printf '%s' "$out" | grep -q "^boundary.0 (nearest \[0, -0.34, 0\]: vertex [0-9]* at .*; fixed): 1 vertex$" && ok || bad "nearest: $out"
printf '%s' "$out" | grep -q "^boundary.1 (boundary surface; fixed): 3135 vertices$" && ok || bad "surface count: $out"
printf '%s' "$out" | grep -q "^elastopt: warning: gravity \[0, 0, -9.81\] does not point down this mesh: .*facing -y.*looks y-up; set gravity \[0, -9.81, 0\]" && ok || bad "y-up warning: $out"
python3 -c "import json; o=json.load(open('bunny_out/summary.json')); assert o['steps_run']==2 and o['resolved']['scene']['boundary'][1]['vertices']==3135, o['steps_run']" && ok || bad "bunny summary"
out=$("$EXE" run bunny.json --out bunny_out --force -o gravity=0,-9.81,0 -o time.steps=1 2>&1)
printf '%s' "$out" | grep -q "warning" && bad "warning with gravity -y: $out" || ok

# --- surface input (TetGen) and VTU input through the CLI
if "$EXE" list 2>/dev/null | grep -q . && "$EXE" mesh --json tagged.msh >/dev/null; then
    printf 'v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nv 0 0 1\nv 2 0 1\nv 2 1 1\nv 0 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n' >box.obj
    out=$("$EXE" mesh --json --max-volume 0.01 box.obj 2>&1)
    if printf '%s' "$out" | grep -q "TetGen library, which this build lacks"; then
        echo "cli_mesh: no TetGen in this build: surface input checked for its error only"; ok
    else
        check_json "$out" 'assert close(o["volume"], 2.0, 1e-9) and o["tets"] > 200 and o["max_volume"] <= 0.01 * (1 + 1e-9), o'
        "$EXE" convert box.obj box.vtu >/dev/null && ok || bad "convert obj -> vtu"
        check_json "$("$EXE" mesh --json box.vtu)" 'assert close(o["volume"], 2.0, 1e-9), o'
    fi
fi
"$EXE" convert "$BAR" bar.vtu >/dev/null && ok || bad "convert bar -> vtu"
check_json "$("$EXE" mesh --json bar.vtu)" 'assert o["vertices"] == 886 and o["tets"] == 2523 and close(o["volume"], 5.0), o'

# Vega FEM .veg: read by extension, converted, refused as an output
"$EXE" convert "${EO_SOURCE_ROOT:?}/tests/data/cube6.veg" cube6.msh > /dev/null && ok || bad "convert .veg"
check_json "$("$EXE" mesh --json cube6.msh)" 'assert o["vertices"] == 8 and o["tets"] == 6 and close(o["volume"], 1.0), o'
"$EXE" convert cube6.msh back.veg > /dev/null 2> veg.err
[ $? -eq 2 ] && grep -q "veg files can be read, not written" veg.err && [ ! -e back.veg ] && ok || bad "write .veg: $(cat veg.err)"

# --- quadratic: convert --order 2 (27 vertices + 98 edges of a 2x2x2 box), mesh shows order 2,
# the 10-node mesh survives msh -> vtu -> node; MEDIT refuses it with exit 2
"$EXE" convert gen:1,1,1:2,2,2 q.msh --order 2 > /dev/null 2> q0.err && ok || bad "convert --order 2: $(cat q0.err)"
check_json "$("$EXE" mesh --json q.msh)" 'assert o["order"] == 2 and o["vertices"] == 125 and o["tets"] == 48, o
assert close(o["volume"], 1.0)'
"$EXE" convert q.msh q.vtu > /dev/null && "$EXE" convert q.vtu q2.node > /dev/null && ok || bad "quadratic msh -> vtu -> node"
"$EXE" mesh q2.node | grep -q "^order *2 " && "$EXE" mesh q2.node | grep -q "^vertices *125$" && ok || bad "quadratic tetgen info"
"$EXE" convert q.msh q.mesh > /dev/null 2> q.err
[ $? -eq 2 ] && grep -q "MEDIT output of a quadratic" q.err && [ ! -e q.mesh ] && ok || bad "medit quadratic: $(cat q.err)"
"$EXE" convert gen:1,1,1:2,2,2 q3.msh --order 3 > /dev/null 2>&1
[ $? -eq 2 ] && [ ! -e q3.msh ] && ok || bad "--order 3 refused"

echo "cli_mesh: $pass passed, $fail failed"
[ $fail -eq 0 ]
