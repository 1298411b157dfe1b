#!/usr/bin/env bash
# The mesh corpus (bench/corpus/manifest.json, scripts/corpus.py, docs/corpus.md): the
# manifest is complete (source, 40-digit commit, licence, counts, quality, TetGen switches
# of every surface; at least 20 distinct stored meshes), every mesh a corpus suite names
# is in it, and the suites are the ones the script writes. Where the stored files are
# present (bench/corpus/data, or ELASTOPT_CORPUS_DATA) their sha256, node and tet
# counts and licence texts are checked too, and two meshes are prepared (a Gmsh tet mesh
# and a TetGen'd surface) to the manifest's counts. The checker refuses what it must, on a
# scratch copy: a missing licence, a wrong count, a suite naming an unknown mesh, a stale
# suite.
set -u
src=${EO_SOURCE_ROOT:?}
exe=${1:-}
py=/usr/bin/python3
[ -x "$py" ] || py=$(command -v python3) || { echo "no python3: skip"; exit 77; }
data=${ELASTOPT_CORPUS_DATA:-$src/bench/corpus/data}
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

out=$("$py" "$src/scripts/corpus.py" check --data "$data" 2>&1) && ok || bad "the repository's corpus: $out"
echo "$out" | tail -1

t=$(mktemp -d)
trap 'rm -rf "$t"' EXIT
mkdir -p "$t/scripts" "$t/bench/corpus" "$t/data"
cp "$src/scripts/corpus.py" "$t/scripts/"
cp "$src/bench/corpus/manifest.json" "$src/bench/corpus/base.json" "$t/bench/corpus/"
cp "$src"/bench/corpus-*.json "$t/bench/"
"$py" "$t/scripts/corpus.py" check --data "$t/data" > /dev/null && ok || bad "the scratch copy is refused"

edit() { # python expression on the manifest dict m
  "$py" - "$t/bench/corpus/manifest.json" "$1" <<'PY'
import json, sys
path, expr = sys.argv[1], sys.argv[2]
m = json.load(open(path))
exec(expr)
json.dump(m, open(path, "w"), indent=1)
PY
}
refused() { # what, expected message part
  out=$("$py" "$t/scripts/corpus.py" check --data "${data_dir:-$t/data}" 2>&1) && bad "$1 accepted" || {
    case "$out" in *"$2"*) ok ;; *) bad "$1: message '$out' lacks '$2'" ;; esac; }
  cp "$src/bench/corpus/manifest.json" "$t/bench/corpus/"
  cp "$src"/bench/corpus-*.json "$t/bench/"
}
edit 'm["meshes"][0]["licence"] = ""'
refused "a mesh without a licence" "no licence"
edit 'm["meshes"][3]["commit"] = "master"'
refused "a branch name for a commit" "not a 40-digit hash"
edit 'm["meshes"] = [e for e in m["meshes"] if e["name"] != "spot"]'
refused "a suite mesh missing from the manifest" "names mesh spot, not in the manifest"
edit '[e.pop("switches") for e in [x["tetgen"] for x in m["meshes"] if x["kind"] == "surface"][:1]]'
refused "a surface without its TetGen switches" "without its TetGen switches"
sed -i 's/"repeats": 3/"repeats": 2/' "$t/bench/corpus-quick.json"
refused "a hand-edited suite" "corpus-quick.json is not current"

if [ -f "$data/ipc_bar-186.msh.xz" ] && [ -f "$data/os_sphere.obj.xz" ]; then
  data_dir=$data
  edit 'e = [x for x in m["meshes"] if x["name"] == "ipc-bar-186"][0]; e["tets"] += 1'
  refused "a wrong tet count" "the manifest says 86, 187"
  edit 'e = [x for x in m["meshes"] if x["name"] == "sphere"][0]; e["sha256"] = "0" * 64'
  refused "a wrong checksum" "does not match its sha256"
  unset data_dir
  if [ -x "$exe" ]; then
    out=$(ELASTOPT="$exe" "$py" "$src/scripts/corpus.py" prepare --data "$data" --only ipc-bar-186,sphere 2>&1) \
      && case "$out" in *"prepared 2 meshes"*"0 differing"*) ok ;; *) bad "prepare: $out" ;; esac \
      || bad "prepare failed: $out"
    # the normalization: longest side 1 along x, centred
    bb=$("$exe" mesh --json "$src/build/corpus/ipc-bar-186.node" | "$py" -c 'import json,sys; b=json.load(sys.stdin)["bbox"]; print(" ".join("%.12g" % v for v in b))')
    [ "$bb" = "-0.5 -0.025 -0.05 0.5 0.025 0.05" ] && ok || bad "normalized bar bbox $bb"
  fi
else
  echo "stored corpus files absent in $data: the file checks are skipped"
fi
echo "corpus: $pass passed, $fail failed"
[ $fail -eq 0 ]
