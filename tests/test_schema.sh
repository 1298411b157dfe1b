#!/usr/bin/env bash
# Docs that match the code (issue 14 item 4): docs/scene.schema.json and
# docs/suite.schema.json equal what `elastopt help --schema` generates from the descriptor
# tables; every shipped scene (examples/*.json, the built-in scenes) and suite
# (bench/*.json, tests/data/*suite*.json) validates against them; documents with an
# unknown key, a wrong type or an out-of-range value do not; every key the schema names is
# in `elastopt help` (and so in docs/config-reference.md); `help bench` documents suites.
set -u
EXE="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
SRC="${EO_SOURCE_ROOT:?}"
PY=/usr/bin/python3
[ -x "$PY" ] && "$PY" -c "import jsonschema" 2>/dev/null || { echo "SKIP: python3-jsonschema not installed"; exit 77; }
# the committed schemas list the methods of every optional backend (PETSc's too)
for b in nlopt ipopt petsc_ksp; do
  if grep -q "^  $b " "$SRC/docs/methods.md" && ! "$EXE" list | grep -q "^  $b "; then
    echo "SKIP: backend $b not built"; exit 77
  fi
done
T="${EO_BUILD_ROOT:-/tmp}/testtmp/schema"
rm -rf "$T" && mkdir -p "$T" || exit 1
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }
"$EXE" help --schema scene > "$T/scene.schema.json" && ok || bad "help --schema scene"
"$EXE" help --schema suite > "$T/suite.schema.json" && ok || bad "help --schema suite"
"$EXE" help --schema nonsense > /dev/null 2>&1; [ $? -eq 2 ] && ok || bad "--schema nonsense not exit 2"
for s in scene suite; do
  if cmp -s "$T/$s.schema.json" "$SRC/docs/$s.schema.json"; then ok; else
    bad "docs/$s.schema.json is stale (run scripts/gen-docs.sh)"
  fi
done
"$EXE" help bench > "$T/help_bench.txt" && grep -q "scenes.N.set" "$T/help_bench.txt" && grep -q "ref_tol" "$T/help_bench.txt" &&
  ok || bad "help bench"
"$EXE" help > "$T/help.txt"
"$PY" - "$T" "$SRC" "$T/help.txt" <<'PY'
import glob, json, os, re, subprocess, sys
import jsonschema
t, src, helpf = sys.argv[1], sys.argv[2], sys.argv[3]
scene = json.load(open(os.path.join(t, "scene.schema.json")))
suite = json.load(open(os.path.join(t, "suite.schema.json")))
V = jsonschema.Draft202012Validator
V.check_schema(scene); V.check_schema(suite)
fails = 0; n = 0
def check(schema, path, want_ok=True, doc=None):
    global fails, n
    n += 1
    d = doc if doc is not None else json.load(open(path))
    errs = sorted(V(schema).iter_errors(d), key=lambda e: list(e.path))
    if bool(errs) == want_ok:
        fails += 1
        print("FAIL:", path, "expected", "valid" if want_ok else "invalid", [e.message for e in errs[:3]])
for p in sorted(glob.glob(os.path.join(src, "examples", "*.json"))):
    check(scene, p)
for p in sorted(glob.glob(os.path.join(src, "bench", "*.json")) + glob.glob(os.path.join(src, "tests", "data", "*suite*.json"))):
    check(suite, p)
base = json.load(open(os.path.join(src, "examples", "cantilever.json")))
import copy
bads = []
d = copy.deepcopy(base); d["tme"] = {"dt": 0.1}; bads.append(("unknown top key", d))
d = copy.deepcopy(base); d.setdefault("time", {})["dt"] = "fast"; bads.append(("wrong type", d))
d = copy.deepcopy(base); d.setdefault("time", {})["dt"] = -1; bads.append(("out of range", d))
d = copy.deepcopy(base); d.setdefault("solver", {})["optimizer"] = "no_such"; bads.append(("unknown method", d))
d = copy.deepcopy(base); d.setdefault("solver", {})["newton"] = {"bogus": 1}; bads.append(("unknown method key", d))
d = copy.deepcopy(base); d["boundary"] = [{"box": [[0, 0], [1, 1, 1]], "fixed": True}]; bads.append(("bad box", d))
for what, doc in bads:
    check(scene, what, want_ok=False, doc=doc)
# every property path of the scene schema is documented by `elastopt help`
helptext = open(helpf).read()
def walk(node, prefix):
    out = []
    for k, v in (node.get("properties") or {}).items():
        p = prefix + "." + k if prefix else k
        out.append(p)
        out += walk(v, p)
    if node.get("type") == "array" and isinstance(node.get("items"), dict):
        out += walk(node["items"], prefix + ".N")
    return out
def alias(p):  # each materials entry takes the keys of `material` (documented there)
    if p.startswith("materials.N.") and p not in ("materials.N.attribute", "materials.N.box"):
        return p.replace("materials.N.", "material.")
    return p
missing = [p for p in map(alias, walk(scene, "")) if not re.search(r"(^|\s)" + re.escape(p) + r"(\s|$)", helptext)
           and not re.search(r"(^|\n)" + re.escape(p) + r" — ", helptext)]
n += 1
if missing:
    fails += 1
    print("FAIL: keys in the schema but not in `elastopt help`:", missing[:20])
print(f"schema: {n - fails} passed, {fails} failed")
sys.exit(1 if fails else 0)
PY
[ $? -eq 0 ] && ok || bad "schema validation (see above)"
echo "schema: $pass passed, $fail failed"
[ $fail -eq 0 ]
