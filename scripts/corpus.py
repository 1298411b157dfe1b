#!/usr/bin/python3
"""The benchmark's mesh corpus: prepare the meshes, check them, write the suites.

    corpus.py prepare [--data DIR] [--only NAME,...] [--suite SUITE.json]
                                                      decompress / tetrahedralize every manifest
                                                      mesh into build/corpus/, normalized, and
                                                      check its counts against the manifest
    corpus.py check   [--data DIR]                    manifest against the stored files (sha256,
                                                      licences, every suite mesh listed); fast
    corpus.py suites                                  write bench/corpus-quick.json, corpus-full.json,
                                                      corpus-full-smoke.json and corpus-methods.json
    corpus.py table                                   the manifest as a Markdown table
    corpus.py manifest [--data DIR]                   recompute the measured manifest fields
                                                      (counts, quality, bounding box, sha256)

The stored files (xz-compressed Gmsh tet meshes and OBJ surfaces, the source's licence
text beside them) live in the data folder, default bench/corpus/data in the repository
(ELASTOPT_CORPUS_DATA or --data override it); the four meshes marked "shared" are the
project's shared meshes, read from ../shared/meshes (EO_SHARED overrides); the manifest is
bench/corpus/manifest.json. Preparing a mesh: a tet mesh is converted by `elastopt
convert` to TetGen .node/.ele; a surface is normalized first, then tetrahedralized by
`elastopt convert --quality Q --max-volume V` (TetGen "pzQ" + q/a switches: no randomness,
the same tets on every run, the count recorded in the manifest). Every prepared mesh is
normalized by a similarity: bounding box centred at the origin, longest side 1 m, the axes
permuted cyclically (a rotation: no tet flips) so that the longest side is x. The suites'
scenes are then written once for all meshes (docs/corpus.md).
"""
import argparse
import hashlib
import json
import lzma
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MANIFEST = os.path.join(ROOT, "bench", "corpus", "manifest.json")
BUILD = os.path.join(ROOT, "build", "corpus")
DEFAULT_DATA = os.path.join(ROOT, "bench", "corpus", "data")
SHARED_MESHES = os.path.join(os.environ.get("EO_SHARED") or os.path.join(ROOT, "..", "shared"), "meshes")
SUITE_MESH_DIR = "../../build/corpus"  # relative to bench/corpus/base.json, the scenes' file

IPC = {"repo": "ipc-sim/IPC", "commit": "573d2c7e04104d3f9baf526bdaee7745891a571a",
       "licence": "MIT", "licence_file": "ipc-sim-IPC.LICENSE"}
OS = {"repo": "odedstein/meshes", "commit": "835213277571d625722d25880c9c3010c6f45a5a"}


def ipc(name, stored, attribution="IPC authors", shared=False):
    return dict(name=name, kind="tet", stored=stored, path="input/tetMeshes/" + os.path.basename(stored).replace(
        ".xz", "").replace("ipc_", ""), attribution=attribution, shared=shared, **IPC)


def surf(name, obj, folder, licence, attribution, max_volume=0.0, quality=2.0):
    base = "os_" + obj
    return dict(name=name, kind="surface", stored=base + ".obj.xz", repo=OS["repo"], commit=OS["commit"],
                path="objects/%s/%s.obj" % (folder, obj), licence=licence, licence_file=base + ".README.md",
                attribution=attribution, tetgen={"quality": quality, "max_volume": max_volume}, shared=False)


STANFORD = "geometry from the Stanford 3D Scanning Repository (research use, credit Stanford)"
# The corpus. "shared": the file is one of the project's shared meshes (../shared/meshes),
# read uncompressed from there.
SOURCES = [
    ipc("ipc-bar-186", "ipc_bar-186.msh.xz"),
    ipc("ipc-bar-651", "ipc_bar-651.msh.xz"),
    ipc("ipc-bar-2523", "../ipc_bar-2523.msh", shared=True),
    ipc("ipc-bar-14114", "../ipc_bar-14114.msh", shared=True),
    ipc("ipc-torus", "ipc_torus.msh.xz"),
    ipc("ipc-corner", "ipc_ANSYS1e-3Corner_coarse.msh.xz"),
    ipc("ipc-rod", "ipc_rod.msh.xz"),
    ipc("ipc-mat20", "ipc_mat20x20.msh.xz"),
    ipc("ipc-cow-head", "ipc_cow_head.msh.xz"),
    ipc("ipc-sphere1k", "ipc_sphere1K.msh.xz"),
    ipc("ipc-hammer", "ipc_hammer.msh.xz"),
    ipc("ipc-mat40", "ipc_mat40x40.msh.xz"),
    ipc("ipc-plate", "ipc_plate1.msh.xz"),
    ipc("ipc-bunny", "../ipc_bunny.msh", "IPC authors; " + STANFORD, shared=True),
    ipc("ipc-sphere5k", "ipc_sphere5K.msh.xz"),
    ipc("ipc-dolphin", "ipc_dolphin5K.msh.xz"),
    ipc("ipc-alien", "ipc_alien.msh.xz"),
    ipc("ipc-monkey", "ipc_monkey8K.msh.xz"),
    ipc("ipc-armadillo", "../ipc_Armadillo13K.msh", "IPC authors; " + STANFORD, shared=True),
    ipc("ipc-hollow-cat", "ipc_hollowCat7.5K.msh.xz"),
    surf("spot", "spot_low_resolution", "spot", "public domain",
         "Spot by Keenan Crane (public domain); remeshed by Oded Stein"),
    surf("spot-v1e-4", "spot_low_resolution", "spot", "public domain",
         "Spot by Keenan Crane (public domain); remeshed by Oded Stein", max_volume=1e-4),
    surf("spot-v3e-5", "spot_low_resolution", "spot", "public domain",
         "Spot by Keenan Crane (public domain); remeshed by Oded Stein", max_volume=3e-5),
    surf("spot-v1e-5", "spot_low_resolution", "spot", "public domain",
         "Spot by Keenan Crane (public domain); remeshed by Oded Stein", max_volume=1e-5),
    surf("fish", "fish_low_resolution", "fish", "public domain",
         "Blub by Keenan Crane (public domain); remeshed by Oded Stein"),
    surf("sphere", "sphere", "sphere", "CC BY 4.0", "Oded Stein"),
    surf("torus", "torus", "torus", "CC BY 4.0", "Oded Stein"),
    surf("goathead", "goathead", "goathead", "CC BY 3.0", "hugoelec (Thingiverse 42256); remeshed by Oded Stein"),
    surf("koala", "koala_low_resolution", "koala", "CC BY 3.0",
         "YahooJAPAN (Thingiverse 182225); remeshed by Oded Stein"),
    surf("skull", "skull_low_resolution", "skull", "CC BY 3.0",
         "YahooJAPAN (Thingiverse 182365); remeshed by Oded Stein"),
    surf("scorpion", "scorpion_low_resolution", "scorpion", "CC BY 3.0",
         "YahooJAPAN (Thingiverse 182363); remeshed and reposed by Oded Stein"),
    surf("penguin", "penguin", "penguin", "CC BY 4.0", "Oded Stein"),
    surf("cat", "cat-low-resolution", "cat", "CC BY 4.0", "billyd (Thingiverse 1565405); remeshed by Oded Stein"),
]


def die(msg):
    print("corpus: " + msg, file=sys.stderr)
    sys.exit(2)


def elastopt():
    exe = os.environ.get("ELASTOPT", os.path.join(ROOT, "build", "cli", "elastopt"))
    if not os.access(exe, os.X_OK):
        die("no elastopt at %s (build first: bash scripts/setup.sh; or set ELASTOPT)" % exe)
    return exe


def data_dir(args):
    return os.path.abspath(args.data or os.environ.get("ELASTOPT_CORPUS_DATA") or DEFAULT_DATA)


def stored_path(data, m):
    """where a manifest entry's stored file is: the data folder, or for the project's shared
    meshes ("shared": true) ../shared/meshes (EO_SHARED=DIR points at another shared folder)"""
    if m.get("shared"):
        return os.path.join(SHARED_MESHES, os.path.basename(m["stored"]))
    return os.path.join(data, m["stored"])


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def read_stored(path):
    with open(path, "rb") as f:
        raw = f.read()
    return lzma.decompress(raw) if path.endswith(".xz") else raw


# ---- normalization ------------------------------------------------------------------

def bbox(points):
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    return lo, hi


def similarity(lo, hi):
    """centre, scale and the cyclic axis shift putting the longest side along x"""
    ext = [hi[k] - lo[k] for k in range(3)]
    a = max(range(3), key=lambda k: ext[k])
    c = [(lo[k] + hi[k]) / 2 for k in range(3)]
    return c, 1.0 / ext[a], a


def apply(p, c, s, a):
    q = [(p[k] - c[k]) * s for k in range(3)]
    return [q[a], q[(a + 1) % 3], q[(a + 2) % 3]]  # cyclic: a rotation


def normalize_obj(text):
    lines = text.splitlines()
    pts = [[float(t) for t in ln.split()[1:4]] for ln in lines if ln.startswith("v ")]
    lo, hi = bbox(pts)
    c, s, a = similarity(lo, hi)
    out = []
    for ln in lines:
        if ln.startswith("v "):
            q = apply([float(t) for t in ln.split()[1:4]], c, s, a)
            ln = "v %.17g %.17g %.17g" % tuple(q)
        out.append(ln)
    return "\n".join(out) + "\n", lo, hi, s, a


def normalize_node(path):
    with open(path) as f:
        lines = f.read().splitlines()
    body = [i for i, ln in enumerate(lines) if ln.strip() and not ln.lstrip().startswith("#")]
    n = int(lines[body[0]].split()[0])
    rows = body[1:1 + n]
    pts = [[float(t) for t in lines[i].split()[1:4]] for i in rows]
    lo, hi = bbox(pts)
    c, s, a = similarity(lo, hi)
    for i, p in zip(rows, pts):
        f = lines[i].split()
        f[1:4] = ["%.17g" % v for v in apply(p, c, s, a)]
        lines[i] = " ".join(f)
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(path + ".tmp", path)
    return lo, hi, s, a


# ---- quality ------------------------------------------------------------------------

def dihedral_range(node, ele):
    """min and max dihedral angle (degrees) of a TetGen pair"""
    import numpy as np

    def table(path):
        with open(path) as f:
            rows = [ln.split() for ln in f if ln.strip() and not ln.lstrip().startswith("#")]
        return rows[1:1 + int(rows[0][0])]
    X = np.array([[float(t) for t in r[1:4]] for r in table(node)])
    T = np.array([[int(t) for t in r[1:5]] for r in table(ele)])
    T -= T.min()
    P = X[T]  # nt x 4 x 3
    opp = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]
    normals = []
    for k, (i, j, l) in enumerate(opp):
        n = np.cross(P[:, j] - P[:, i], P[:, l] - P[:, i])
        # outward: away from the opposite vertex k
        sgn = np.sign(np.einsum("ij,ij->i", n, P[:, i] - P[:, k]))
        n = n * sgn[:, None]
        normals.append(n / np.linalg.norm(n, axis=1)[:, None])
    angles = []
    for k in range(4):
        for l in range(k + 1, 4):
            cosang = np.clip(np.einsum("ij,ij->i", normals[k], normals[l]), -1, 1)
            angles.append(np.pi - np.arccos(cosang))
    A = np.degrees(np.stack(angles))
    return float(A.min()), float(A.max())


# ---- prepare ------------------------------------------------------------------------

def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        die("%s failed (exit %d): %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-500:]))
    return p.stdout


def prepare_one(exe, src, data, quality=False):
    """build/corpus/NAME.node/.ele, normalized; returns the measured fields"""
    stored = stored_path(data, src)
    if not os.path.isfile(stored):
        raise FileNotFoundError(stored)
    os.makedirs(BUILD, exist_ok=True)
    out = os.path.join(BUILD, src["name"] + ".node")
    with tempfile.TemporaryDirectory() as tmp:
        if src["kind"] == "surface":
            text, lo, hi, s, a = normalize_obj(read_stored(stored).decode())
            obj = os.path.join(tmp, src["name"] + ".obj")
            with open(obj, "w") as f:
                f.write(text)
            tg = src["tetgen"]
            run([exe, "convert", obj, out, "--quality", repr(tg["quality"]), "--max-volume", repr(tg["max_volume"])])
        else:
            msh = os.path.join(tmp, src["name"] + ".msh")
            with open(msh, "wb") as f:
                f.write(read_stored(stored))
            run([exe, "convert", msh, out])
            lo, hi, s, a = normalize_node(out)
    info = json.loads(run([exe, "mesh", "--json", out]))
    if info["reoriented"] or info["dropped_tets"]:
        die("%s: the prepared mesh has %d reoriented and %d dropped tets (the normalization must be a rotation)"
            % (src["name"], info["reoriented"], info["dropped_tets"]))
    m = {"vertices": info["vertices"], "tets": info["tets"], "worst_radius_ratio": float("%.4g" % info["worst_quality"]),
         "bbox_source": [float("%.6g" % v) for v in lo + hi], "scale": float("%.6g" % s),
         "axis_to_x": "xyz"[a], "sha256": sha256(stored), "stored_bytes": os.path.getsize(stored)}
    if src["kind"] == "surface":
        m["tetgen"] = dict(src["tetgen"], switches=tetgen_switches(src["tetgen"]))
    if quality:
        dmin, dmax = dihedral_range(out, os.path.join(BUILD, src["name"] + ".ele"))
        m["min_dihedral_deg"] = round(dmin, 3)
        m["max_dihedral_deg"] = round(dmax, 3)
    return m


def tetgen_switches(tg):
    s = "pzQ"
    if tg["quality"] > 0:
        s += "q%g" % tg["quality"]
    if tg["max_volume"] > 0:
        s += "a%g" % tg["max_volume"]
    return s


def load_manifest():
    with open(MANIFEST) as f:
        return json.load(f)


def cmd_manifest(args):
    exe, data = elastopt(), data_dir(args)
    meshes = []
    for src in SOURCES:
        m = prepare_one(exe, src, data, quality=True)
        entry = {k: v for k, v in src.items() if k != "tetgen"}
        entry.update(m)
        meshes.append(entry)
        print("%-16s %6d vertices %7d tets  worst radius ratio %.3g  dihedral [%.2f, %.2f] deg" % (
            src["name"], m["vertices"], m["tets"], m["worst_radius_ratio"], m["min_dihedral_deg"],
            m["max_dihedral_deg"]))
    doc = {"description": "The benchmark's mesh corpus (docs/corpus.md): source, licence and measured counts of "
                          "every mesh. 'stored' is relative to the data folder (default bench/corpus/data; 'shared' files: ../shared/meshes); "
                          "counts are those of the prepared mesh (scripts/corpus.py prepare); bbox_source is the "
                          "stored file's bounding box [xmin, ymin, zmin, xmax, ymax, zmax] before normalization "
                          "(scale: the factor to a longest side of 1 m; axis_to_x: the source axis that becomes x).",
           "normalization": "centre of the bounding box at the origin, longest side 1 m, cyclic axis shift making "
                            "it x",
           "meshes": meshes}
    os.makedirs(os.path.dirname(MANIFEST), exist_ok=True)
    with open(MANIFEST, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print("wrote %s (%d meshes)" % (os.path.relpath(MANIFEST, ROOT), len(meshes)))


def cmd_prepare(args):
    exe, data = elastopt(), data_dir(args)
    man = {m["name"]: m for m in load_manifest()["meshes"]}
    only = set(args.only.split(",")) if args.only else None
    if args.suite:
        with open(args.suite) as f:
            only = (only or set()) | set(suite_meshes(json.load(f)))
    if only and only - set(man):
        die("not in the manifest: " + ", ".join(sorted(only - set(man))))
    bad = missing = done = 0
    src_by_name = {s["name"]: s for s in SOURCES}
    for name, ref in man.items():
        if only and name not in only:
            continue
        src = dict(src_by_name.get(name) or ref)
        try:
            m = prepare_one(exe, src, data)
        except FileNotFoundError as e:
            print("corpus: %s: stored file %s absent (skipped)" % (name, e), file=sys.stderr)
            missing += 1
            continue
        errs = [k for k in ("vertices", "tets", "sha256") if m[k] != ref[k]]
        if errs:
            bad += 1
            print("corpus: %s: %s differ from the manifest (%s)" % (
                name, ", ".join(errs), "; ".join("%s %s != %s" % (k, m[k], ref[k]) for k in errs)), file=sys.stderr)
        done += 1
    print("corpus: prepared %d meshes in %s (%d absent, %d differing from the manifest)" % (
        done, os.path.relpath(BUILD, ROOT), missing, bad))
    if bad:
        sys.exit(1)


def cmd_check(args):
    """the manifest against the stored files and the suites; no TetGen, no elastopt"""
    data = data_dir(args)
    doc = load_manifest()
    errors, checked = [], 0
    names = [m["name"] for m in doc["meshes"]]
    if len(set(names)) != len(names):
        errors.append("duplicate mesh names")
    src_names = [s["name"] for s in SOURCES]
    if sorted(src_names) != sorted(names):
        errors.append("manifest and scripts/corpus.py SOURCES list different meshes")
    real = [m for m in doc["meshes"]]
    if len({m["stored"] for m in real}) < 20:
        errors.append("fewer than 20 distinct stored meshes")
    for m in doc["meshes"]:
        for k in ("repo", "commit", "path", "licence", "vertices", "tets", "worst_radius_ratio", "min_dihedral_deg",
                  "bbox_source", "sha256"):
            if k not in m or m[k] in ("", None):
                errors.append("%s: no %s" % (m["name"], k))
        if len(m.get("commit", "")) != 40:
            errors.append("%s: commit is not a 40-digit hash" % m["name"])
        if m["kind"] == "surface" and "switches" not in m.get("tetgen", {}):
            errors.append("%s: a surface without its TetGen switches" % m["name"])
        if not (0 < m["min_dihedral_deg"] <= 70.53 <= m["max_dihedral_deg"] < 180):
            errors.append("%s: dihedral range [%s, %s] impossible" % (m["name"], m["min_dihedral_deg"],
                                                                   m["max_dihedral_deg"]))
        if not m["tets"] >= m["vertices"] / 2 or m["vertices"] < 4:
            errors.append("%s: implausible counts %d vertices, %d tets" % (m["name"], m["vertices"], m["tets"]))
        path = stored_path(data, m)
        if os.path.isfile(path):
            checked += 1
            if sha256(path) != m["sha256"]:
                errors.append("%s: %s does not match its sha256" % (m["name"], m["stored"]))
            if m["kind"] == "tet" and m["stored"].endswith(".msh.xz"):
                counts = msh_counts(read_stored(path).decode())
                if counts != (m["vertices"], m["tets"]):
                    errors.append("%s: the stored file has %d nodes, %d tets; the manifest says %d, %d" % (
                        (m["name"],) + counts + (m["vertices"], m["tets"])))
            lic = os.path.join(data, m.get("licence_file", ""))
            if m.get("shared") and not os.path.isfile(lic):
                pass  # a shared mesh: its licence is in ../shared/meshes/README.md
            elif not m.get("licence_file") or not os.path.isfile(lic):
                errors.append("%s: licence text %s absent" % (m["name"], m.get("licence_file")))
            elif m["licence"].split()[0].lower() not in open(lic).read().lower():
                errors.append("%s: licence text %s does not name %s" % (m["name"], m["licence_file"], m["licence"]))
    # every mesh a suite names is in the manifest; the suites are those this script writes
    for suite, want in all_suites(doc):
        try:
            with open(os.path.join(ROOT, "bench", suite)) as f:
                have = json.load(f)
        except (OSError, ValueError) as e:
            errors.append("bench/%s: %s (run: scripts/corpus.py suites)" % (suite, e))
            continue
        for used in suite_meshes(have):
            if used not in names:
                errors.append("%s names mesh %s, not in the manifest" % (suite, used))
        if have != want:
            errors.append("bench/%s is not current (run: scripts/corpus.py suites)" % suite)
    for e in errors:
        print("corpus check: " + e, file=sys.stderr)
    print("corpus check: %d meshes in the manifest, %d stored files checked in %s, %d errors" % (
        len(names), checked, data, len(errors)))
    if errors:
        sys.exit(1)


def msh_counts(text):
    """nodes and 4-node tets of a Gmsh 4.1 ASCII file (counted, not trusted from headers)"""
    lines = text.splitlines()
    i = lines.index("$Nodes")
    nodes = int(lines[i + 1].split()[1])
    i = lines.index("$Elements")
    nblocks = int(lines[i + 1].split()[0])
    j, tets = i + 2, 0
    for _ in range(nblocks):
        _, _, etype, n = (int(t) for t in lines[j].split())
        if etype == 4:
            tets += n
        j += n + 1
    return nodes, tets


def suite_meshes(suite):
    out = []
    for sc in suite["scenes"]:
        for part in [sc.get("set", {})] + [s for ax in sc.get("vary", []) for s in ax.values()]:
            f = part.get("mesh.file")
            if f:
                out.append(os.path.basename(f)[:-len(".node")])
    return out


# ---- suites -------------------------------------------------------------------------

H24 = 1 / 24
FAR = 10.0


def slab_lo(frac=0.1):
    return [[-FAR, -FAR, -FAR], [-0.5 + frac, FAR, FAR]]


def slab_hi(frac=0.1):
    return [[0.5 - frac, -FAR, -FAR], [FAR, FAR, FAR]]


# Loads on a normalized mesh (longest side x in [-0.5, 0.5]); each sets every key it needs.
LOADS = {
    "gravity": {"boundary": [{"box": slab_lo(), "fixed": True}], "gravity": [0, -9.81, 0],
                "time.integrator": "newmark", "time.dt": H24},
    "twist": {"boundary": [{"box": slab_lo(), "fixed": True},
                           {"box": slab_hi(), "rotate": {"axis": [1, 0, 0], "center": [0, 0, 0],
                                                         "rate": math.pi}}],
              "gravity": [0, 0, 0], "time.integrator": "newmark", "time.dt": H24},
    "drop": {"boundary": [], "gravity": [-9.81, 0, 0], "initial": {"velocity": [-3, 0, 0]},
             "collisions": [{"plane": {"point": [-0.55, 0, 0], "normal": [1, 0, 0]}, "stiffness": 1e5}],
             "time.integrator": "backward_euler", "time.dt": 0.01},
    "inverted": {"boundary": [], "gravity": [0, 0, 0],
                 "initial": {"reflect": {"point": [0, 0, 0], "normal": [1, 0, 0]}},
                 "time.integrator": "backward_euler", "time.dt": 0.05},
    "random": {"boundary": [], "gravity": [0, 0, 0], "initial": {"random_ball": {"radius": 0.3, "seed": 7}},
               "time.integrator": "backward_euler", "time.dt": 1.0},
}
# where each load's measured step is: (select, skip, horizon)
LOAD_STEPS = {"gravity": ("largest_motion", 0, 6), "twist": ("first", 5, 0), "drop": ("largest_correction", 0, 8),
              "inverted": ("first", 0, 0), "random": ("first", 0, 0)}


def mesh_set(name):
    return {"mesh.file": "%s/%s.node" % (SUITE_MESH_DIR, name)}


def scene(name, mesh, load, extra=None, stratum="", **kw):
    sel, skip, horizon = LOAD_STEPS[load]
    s = {"name": name, "file": "corpus/base.json", "optional": True, "select": sel, "skip": skip}
    if horizon:
        s["horizon"] = horizon
    st = dict(mesh_set(mesh), **LOADS[load])
    st.update(extra or {})
    s["set"] = st
    if stratum:
        s["stratum"] = stratum
    s.update(kw)
    return s


def load_axis(mesh, loads):
    return {ld: dict(mesh_set(mesh), **LOADS[ld]) for ld in loads}


NEWTON = {"solver.optimizer": "newton", "solver.linesearch": "backtracking", "solver.max_iters": 1000}
FIRST = {"solver.stop": "gradient", "solver.tol": 1e-6, "solver.max_iters": 20000}
QUICK_CONFIGS = [
    {"name": "newton-project_on_demand", "set": dict(NEWTON, **{"solver.hessian_fix": "project_on_demand"})},
    {"name": "newton-clamp", "set": dict(NEWTON, **{"solver.hessian_fix": "clamp"})},
    {"name": "lbfgs-wolfe", "set": dict(FIRST, **{"solver.optimizer": "lbfgs", "solver.linesearch": "wolfe"})},
    {"name": "pd_local_global-anderson", "set": dict(FIRST, **{"solver.optimizer": "pd_local_global",
                                                               "solver.pd_local_global.anderson": True})},
    {"name": "vbd", "set": dict(FIRST, **{"solver.optimizer": "vbd"})},
]
FULL_CONFIGS = QUICK_CONFIGS + [
    {"name": "newton-progressive", "set": dict(NEWTON, **{"solver.hessian_fix": "progressive"})},
    {"name": "newton-abs", "set": dict(NEWTON, **{"solver.hessian_fix": "abs"})},
    {"name": "newton_tr", "set": {"solver.optimizer": "newton_tr", "solver.max_iters": 1000}},
    {"name": "ncg", "set": dict(FIRST, **{"solver.optimizer": "ncg", "solver.linesearch": "wolfe"})},
    {"name": "pd-lbfgs5", "set": dict(FIRST, **{"solver.optimizer": "projective_dynamics",
                                                "solver.projective_dynamics.lbfgs_history": 5})},
    {"name": "pd_local_global", "set": dict(FIRST, **{"solver.optimizer": "pd_local_global"})},
    {"name": "vbd-accelerated", "set": dict(FIRST, **{"solver.optimizer": "vbd", "solver.vbd.accelerated": True})},
    {"name": "admm_pd", "set": dict(FIRST, **{"solver.optimizer": "admm_pd"})},
    {"name": "bcqn", "set": dict(FIRST, **{"solver.optimizer": "bcqn"})},
    {"name": "pd_local_global-chebyshev", "set": dict(FIRST, **{"solver.optimizer": "pd_local_global",
                                                                "solver.pd_local_global.chebyshev": True})},
    {"name": "jacobi_chebyshev", "set": dict(FIRST, **{"solver.optimizer": "jacobi_chebyshev"})},
    {"name": "aqp", "set": dict(FIRST, **{"solver.optimizer": "aqp"})},
    {"name": "newton-pcg-gmg", "set": {"solver.optimizer": "newton", "solver.linear": "pcg",
                                       "solver.pcg.preconditioner": "gmg"}},
]
# The methods suite: Newton as the library runs it by default (project_on_demand, backtracking,
# linear = auto), the best and the Anderson-accelerated methods of the quick results, and the
# newer methods (each as the full suite runs it).
METHODS_CONFIGS = [{"name": "newton", "set": {"solver.optimizer": "newton"}}] + [
    c for n in ("lbfgs-wolfe", "pd_local_global-anderson", "vbd", "vbd-accelerated", "admm_pd",
                "pd_local_global-chebyshev", "jacobi_chebyshev", "bcqn", "aqp", "newton-pcg-gmg")
    for c in FULL_CONFIGS if c["name"] == n]

QUICK_MESHES = [("ipc-bar-651", "twist"), ("spot", "gravity"), ("fish", "drop"), ("ipc-torus", "inverted"),
                ("ipc-torus", "random"), ("ipc-cow-head", "twist"), ("sphere", "gravity"), ("torus", "drop"),
                ("ipc-hammer", "gravity"), ("goathead", "twist"), ("ipc-sphere1k", "drop"), ("ipc-mat20", "inverted")]
METHODS_BUDGET = 4.0  # s per solve of the methods suite (3 repeats: about 30 min of processor time)
SMALL = 8000  # tets: random starts and the nu x element sweep run on meshes up to this size


def suite_common(desc, repeats, budget):
    return {"description": desc, "repeats": repeats, "baseline": "newton-clamp", "steps": 1,
            "time_budget": budget, "max_iters": 20000, "thresholds": [1e-2, 1e-4, 1e-6],
            "budgets": [0.01, 0.1, 1], "trajectory": False, "ipopt_check": False,
            "require_converged": ["newton-clamp"]}


def quick_suite():
    s = suite_common(
        "corpus-quick (docs/corpus.md): 12 scenes on 10 corpus meshes (IPC tet meshes as they come, odedstein surfaces "
        "tetrahedralized by TetGen; normalized to a longest side of 1 m along x) under the five loads (gravity, "
        "twist, drop, inverted and random starts), one measured step each, one stratum per load; five "
        "configurations, 3 repeats. Run: bash scripts/corpus.sh quick (prepares the meshes first).", 3, 2.0)
    s["scenes"] = [scene("%s-%s" % (m, ld), m, ld, stratum=ld) for m, ld in QUICK_MESHES]
    s["configs"] = QUICK_CONFIGS
    return s


def full_suite(man):
    tets = {m["name"]: m["tets"] for m in man["meshes"]}
    s = suite_common(
        "corpus-full (docs/corpus.md): every corpus mesh under every load (random starts on meshes up to %d "
        "tets), and the sweeps: resolution (the IPC bar at 186 to 14k tets, Spot by TetGen at four volume "
        "bounds, a generated box), stiffness (E = 1e4 to 1e8), nu (0.3 to 0.4999) x element (p1, p1anp, p2, "
        "p2p0), time step (h = 1/24 to 1/240 and static); %d configurations, 3 repeats." % (SMALL, len(FULL_CONFIGS)),
        3, 10.0)
    s["time_budget"] = 10.0
    sc = []
    order = sorted(tets, key=lambda n: tets[n])
    for m in order:
        if m.startswith("spot-v"):
            continue  # the resolution sweep
        loads = [ld for ld in LOADS if ld != "random" or tets[m] <= SMALL]
        for ld in loads:
            sc.append(scene("%s-%s" % (m, ld), m, ld, stratum="load-" + ld))
    res = ["ipc-bar-186", "ipc-bar-651", "ipc-bar-2523", "ipc-bar-14114"]
    for m in res:
        sc.append(scene("res-%s-twist" % m, m, "twist", stratum="resolution-bar"))
    for m in ["spot", "spot-v1e-4", "spot-v3e-5", "spot-v1e-5"]:
        sc.append(scene("res-%s-gravity" % m, m, "gravity", stratum="resolution-spot"))
    for n in (8, 16, 32, 48):
        gen = {"mesh.generate.size": [1, 0.25, 0.25], "mesh.generate.cells": [n, n // 4, n // 4],
               "mesh.generate.origin": [-0.5, 0, -0.125]}  # g(x0) != 0 at step 1 (see docs/corpus.md)
        sc.append({"name": "res-box%d-gravity" % n, "file": "corpus/base.json", "select": "largest_motion",
                   "horizon": 6, "stratum": "resolution-box", "set": dict(LOADS["gravity"], **gen)})
    E = {"E1e4": {"material.E": 1e4}, "E1e5": {"material.E": 1e5}, "E1e6": {"material.E": 1e6},
         "E1e7": {"material.E": 1e7}, "E1e8": {"material.E": 1e8}}
    for m in ("ipc-bunny", "koala", "ipc-hammer"):
        sc.append(dict(scene("E-%s" % m, m, "gravity"), stratum="stiffness", stratum_axis=0, vary=[E]))
    nu = {"nu0.3": {"material.nu": 0.3}, "nu0.45": {"material.nu": 0.45}, "nu0.49": {"material.nu": 0.49},
          "nu0.499": {"material.nu": 0.499}, "nu0.4999": {"material.nu": 0.4999}}
    el = {e: {"element": e} for e in ("p1", "p1anp", "p2", "p2p0")}
    for m, ld in (("spot", "twist"), ("ipc-rod", "gravity")):
        sc.append(dict(scene("nu-%s-%s" % (m, ld), m, ld), stratum="poisson", stratum_axis=0, vary=[nu, el]))
    h = {"h1_24": {"time.dt": 1 / 24}, "h1_48": {"time.dt": 1 / 48}, "h1_96": {"time.dt": 1 / 96},
         "h1_240": {"time.dt": 1 / 240}, "static": {"time.integrator": "static", "time.load_steps": 0}}
    for m in ("fish", "ipc-plate", "goathead"):
        sc.append(dict(scene("h-%s" % m, m, "gravity"), stratum="timestep", stratum_axis=0, vary=[h]))
    s["scenes"] = sc
    s["configs"] = FULL_CONFIGS
    return s


# real-mesh stratum: shapes unlike each other (bars and rods, animals, a hammer, a torus), each
# under one of the three loads of a simulation (gravity, twist, drop)
METHODS_REAL = [("ipc-bar-651", "twist"), ("ipc-rod", "gravity"), ("sphere", "drop"), ("spot", "gravity"),
                ("ipc-cow-head", "twist"), ("fish", "drop"), ("torus", "twist"), ("ipc-hammer", "gravity"),
                ("ipc-mat40", "drop"), ("koala", "twist"), ("ipc-bunny", "gravity")]
# stiff stratum: E over three decades up to 1e8 Pa, nu from 0.45 to 0.4999
METHODS_STIFF = ["spot", "ipc-hammer"]
METHODS_E = (1e5, 1e6, 1e7, 1e8)
METHODS_NU = (0.45, 0.4999)


def methods_suite():
    s = suite_common(
        "corpus-methods (docs/corpus.md): the newer methods (vbd plain and accelerated, ADMM-PD, Chebyshev on PD "
        "local/global and on damped block Jacobi, BCQN, AQP, Newton with Galerkin-multigrid PCG) against Newton as "
        "the library runs it by default, L-BFGS (Wolfe) and PD local/global + Anderson on two strata: real meshes "
        "(%d corpus meshes of different shapes under gravity, twist or drop) and stiff materials (E = %g to %g Pa "
        "x nu = %s on %s, gravity); %d configurations, 3 repeats, %g s per solve, curve runs stop at 5e-7. "
        "Run: bash scripts/corpus.sh methods." % (
            len(METHODS_REAL), METHODS_E[0], METHODS_E[-1], " and ".join("%g" % v for v in METHODS_NU),
            " and ".join(METHODS_STIFF), len(METHODS_CONFIGS), METHODS_BUDGET), 3, METHODS_BUDGET)
    s["baseline"] = "newton"
    s["require_converged"] = ["newton"]
    s["target"] = 5e-7  # just past the last threshold: nothing beyond it is reported
    sc = [scene("%s-%s" % (m, ld), m, ld, stratum="real") for m, ld in METHODS_REAL]
    E = {"E1e%d" % round(math.log10(e)): {"material.E": e} for e in METHODS_E}
    nu = {"nu%g" % v: {"material.nu": v} for v in METHODS_NU}
    for m in METHODS_STIFF:
        sc.append(dict(scene("stiff-%s" % m, m, "gravity"), stratum="stiff", vary=[E, nu]))
    s["scenes"] = sc
    s["configs"] = METHODS_CONFIGS
    return s


def smoke_suite(man):
    """the full suite's scene kinds on its smallest mesh: every load, each sweep's keys, 2 configurations"""
    full = full_suite(man)
    small = "ipc-bar-186"
    keep = []
    for sc in full["scenes"]:
        n = sc["name"]
        if n.startswith(small + "-") or n in ("res-box8-gravity", "res-%s-twist" % small) or \
                n.startswith(("E-ipc-bunny", "nu-spot", "h-fish")):
            sc = json.loads(json.dumps(sc))
            if "mesh.file" in sc["set"]:
                sc["set"].update(mesh_set(small))
            sc["name"] = sc["name"].replace("ipc-bunny", small).replace("spot", small).replace("fish", small)
            keep.append(sc)
    s = dict(full, description="corpus-full-smoke: the full suite's scene kinds (every load, the resolution, "
                               "stiffness, nu x element and time-step entries) on its smallest mesh (%s), with "
                               "two configurations and one repeat: a check that every kind loads and runs "
                               "(scripts/corpus.py writes it from the full suite)." % small,
             repeats=1, time_budget=2.0, scenes=keep,
             configs=[c for c in full["configs"] if c["name"] in ("newton-clamp", "lbfgs-wolfe")])
    return s


def all_suites(man):
    return (("corpus-quick.json", quick_suite()), ("corpus-full.json", full_suite(man)),
            ("corpus-full-smoke.json", smoke_suite(man)), ("corpus-methods.json", methods_suite()))


def cmd_suites(args):
    man = load_manifest()
    for name, suite in all_suites(man):
        path = os.path.join(ROOT, "bench", name)
        with open(path, "w") as f:
            json.dump(suite, f, indent=1)
            f.write("\n")
        print("wrote bench/%s (%d scene entries)" % (name, len(suite["scenes"])))


def cmd_table(args):
    """the manifest as a Markdown table (docs/corpus.md)"""
    print("| mesh | kind | vertices | tets | worst radius ratio | dihedral (deg) | source bbox extent | source | licence |")
    print("|---|---|---|---|---|---|---|---|---|")
    for m in load_manifest()["meshes"]:
        b = m["bbox_source"]
        ext = " × ".join("%.3g" % (b[k + 3] - b[k]) for k in range(3))
        kind = "tet" if m["kind"] == "tet" else "surface, TetGen `%s`" % m["tetgen"]["switches"]
        src = "%s `%s` @ %s" % (m["repo"], m["path"], m["commit"][:7])
        print("| %s | %s | %d | %d | %.3g | %.2f – %.2f | %s | %s | %s (%s) |" % (
            m["name"], kind, m["vertices"], m["tets"], m["worst_radius_ratio"], m["min_dihedral_deg"],
            m["max_dihedral_deg"], ext, src, m["licence"], m["attribution"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("command", choices=["prepare", "check", "suites", "manifest", "table"])
    ap.add_argument("--data", help="folder of the stored files (default bench/corpus/data)")
    ap.add_argument("--only", help="prepare: these meshes only (comma-separated names)")
    ap.add_argument("--suite", help="prepare: the meshes this suite names only")
    args = ap.parse_args()
    {"prepare": cmd_prepare, "check": cmd_check, "suites": cmd_suites, "manifest": cmd_manifest,
     "table": cmd_table}[args.command](args)


if __name__ == "__main__":
    main()
