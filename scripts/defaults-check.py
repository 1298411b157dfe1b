#!/usr/bin/python3
"""Convergence of the default solver on every step of the hard scenes.

Runs `elastopt run` with the solver defaults (each scene's own solver section, the
library's defaults for everything it does not name, the default fallback chain) on:
  - every built-in scene, run 10x longer than its example;
  - the hard suite's scenes (bench/hard.json), each for `--hard-steps` steps;
  - the stiff real-bar two-turn twist (IPC bar, E = 1e8, nu = 0.499) and the real-mesh
    hard starts (inverted and random bunny), when ../shared/meshes is present.
Prints one line per case (converged steps / steps, iterations, worst reason, CPU time of
the run: user + system of the child process; wall time in parentheses) and
writes a JSON table (--json). `--cli` selects the binary (e.g. an older build, for a
before/after table); `--extra -o KEY=VALUE` is added to every run.

Usage: scripts/defaults-check.py [--cli build/cli/elastopt] [--only NAME,...]
                                 [--json out.json] [--hard-steps 10] [--quick | --ci]
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("EO_SHARED", os.path.join(ROOT, "..", "shared"))

BUILTIN_STEPS = {"cantilever": 40, "cantilever_static": 1, "twist": 50, "stretch": 60, "freefall": 30,
                 "inverted": 40, "drop": 100, "cloth": 150}


def ov_args(d):
    out = []
    for k, v in d.items():
        out += ["-o", f"{k}={json.dumps(v)}"]
    return out


def cases(hard_steps, quick):
    cs = []
    for name, n in BUILTIN_STEPS.items():
        steps = 10 * n if not quick else 2 * n
        if name == "cantilever_static":
            steps = 10
        cs.append((f"{name} x10" if not quick else f"{name} x2", ["--scene", name], {"time.steps": steps}))
    hard = json.load(open(os.path.join(ROOT, "bench", "hard.json")))
    for sc in hard["scenes"]:
        src = sc.get("scene") or sc.get("file")
        args = ["--scene", src] if not src.endswith(".json") else [os.path.join(ROOT, "bench", src)]
        if src.endswith(".json") and not os.path.isdir(os.path.join(SHARED, "meshes")):
            continue
        s = dict(sc.get("set", {}))
        s["time.steps"] = hard_steps
        cs.append((f"hard: {sc['name']}", args, s))
    bar = os.path.join(ROOT, "bench", "real", "ipc-bar-twist.json")
    if os.path.isdir(os.path.join(SHARED, "meshes")):
        cs.append(("real bar two-turn twist E=1e8 nu=0.499", [bar],
                   {"material.E": 1e8, "material.nu": 0.499, "time.steps": 10}))
        cs.append(("real bunny twist E=1e8 nu=0.49", [os.path.join(ROOT, "bench", "real", "bunny-twist.json")],
                   {"material.E": 1e8, "material.nu": 0.49, "time.steps": 15}))
        swing = os.path.join(ROOT, "bench", "real", "bunny-swing.json")
        cs.append(("real bunny inverted start", [swing],
                   {"boundary": [], "gravity": [0, 0, 0], "initial.scale": [1, -1, 1], "time.dt": 0.05,
                    "time.steps": 15}))
        cs.append(("real bunny random start", [swing],
                   {"boundary": [], "gravity": [0, 0, 0], "initial": {"random_ball": {"radius": 1.0, "seed": 7}},
                    "time.dt": 1.0, "time.steps": 2}))
    return cs


def run(cli, name, args, sets, extra, tmp):
    out = os.path.join(tmp, "run")
    cmd = [cli, "run", *args, "--out", out, "--force", "--quiet", "-o", "output.vtu=false", *ov_args(sets), *extra]
    t0 = time.time()
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.time() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    try:
        s = json.load(open(os.path.join(out, "summary.json")))
    except (OSError, ValueError):
        return {"case": name, "error": (p.stderr.strip().splitlines() or ["?"])[-1], "exit": p.returncode}
    st = s["steps"]
    conv = sum(1 for x in st if x["converged"] or x["reason"] in ("explicit", "converged_explicit"))
    bad = [x for x in st if not (x["converged"] or x["reason"] in ("explicit", "converged_explicit"))]
    worst = bad[0]["reason"] if bad else ""
    minj = min((x["min_J"] for x in st if x["min_J"] is not None), default=float("nan"))
    return {"case": name, "converged": conv, "steps": len(st), "planned": s.get("steps_planned", len(st)),
            "iterations": sum(x["iterations"] for x in st), "worst": worst, "min_J": minj, "wall": dt, "cpu": cpu,
            "fallback_steps": sum(1 for x in st if x.get("entry", 0) > 0), "exit": p.returncode,
            "warnings": sum(1 for ln in p.stderr.splitlines() if "warning" in ln),
            "factor_warnings": sum(1 for ln in p.stderr.splitlines() if "not positive definite" in ln)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", default=os.path.join(ROOT, "build", "cli", "elastopt"))
    ap.add_argument("--only", default="")
    ap.add_argument("--json", default="")
    ap.add_argument("--hard-steps", type=int, default=10)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--ci", action="store_true",
                    help="the test suite's subset: the twist run 400 steps, the built-in hard scenes and the real "
                         "bar (when ../shared/meshes is present)")
    ap.add_argument("-o", dest="extra", action="append", default=[])
    a = ap.parse_args()
    extra = sum((["-o", e] for e in a.extra), [])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        todo = cases(a.hard_steps, a.quick)
        if a.ci:
            todo = [("twist 400 steps", ["--scene", "twist"], {"time.steps": 400})] + \
                   [c for c in todo if (c[0].startswith("hard:") and "bunny" not in c[0]) or c[0].startswith("real bar")]
        for name, args, sets in todo:
            if a.only and not any(w in name for w in a.only.split(",")):
                continue
            r = run(a.cli, name, args, sets, extra, tmp)
            rows.append(r)
            if "error" in r:
                print(f"{name:45s} ERROR exit {r['exit']}: {r['error']}", flush=True)
            else:
                print(f"{name:45s} {r['converged']:4d}/{r['planned']:<4d} iters {r['iterations']:6d}  "
                      f"fallback {r['fallback_steps']:3d}  min J {r['min_J']:10.3g}  {r['worst']:24s} "
                      f"warn {r['warnings']:3d} (factor {r['factor_warnings']})  cpu {r['cpu']:7.1f} s (wall {r['wall']:.0f})",
                      flush=True)
    if a.json:
        json.dump({"cli": a.cli, "extra": a.extra, "rows": rows}, open(a.json, "w"), indent=1)
    ok = all("error" not in r and r["converged"] == r["planned"] for r in rows)
    print(f"{sum(1 for r in rows if 'error' not in r and r['converged'] == r['planned'])}/{len(rows)} cases "
          f"converged on every step")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
