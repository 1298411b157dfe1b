"""Checks of the pip-installed package, run by tests/test_python_install.sh with the
venv's python from a folder outside the source tree, with no variable pointing at the
build tree. Usage: install_check.py SOURCE_ROOT (only to assert nothing is loaded from it)."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

import elastopt as eo

SRC = Path(sys.argv[1]).resolve()
SMALL = {"mesh.generate.cells": [8, 2, 2]}
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def inside(p, root):
    try:
        Path(p).resolve().relative_to(Path(root).resolve())
        return True
    except ValueError:
        return False


# ---- where everything comes from: the venv, never the source or build tree
site = Path(eo.__file__).resolve().parent
check(inside(site, sys.prefix), f"package imported from the venv: {site}")
check(eo.lib_path.resolve().parent == site, f"library inside the package: {eo.lib_path}")
check(eo.cli_path().parent == site, f"CLI inside the package: {eo.cli_path()}")


def mapped_from_source():
    with open("/proc/self/maps") as f:
        return sorted({ln.split()[-1] for ln in f if len(ln.split()) >= 6
                       and inside(ln.split()[-1], SRC)})


# ---- (a) a scene from the CLI (python -m elastopt, the console script) and from the API
ov = {"time.steps": 3, **SMALL}
args = [sys.executable, "-m", "elastopt", "run", "--scene", "cantilever", "--out", "run_cli", "--quiet"]
for k, v in ov.items():
    args += ["-o", f"{k}={json.dumps(v)}"]
r = subprocess.run(args, capture_output=True, text=True)
check(r.returncode == 0, f"python -m elastopt run --scene cantilever (status {r.returncode}) {r.stderr[-400:]}")
frame = Path("run_cli/frame_000003.vtu")
check(frame.exists(), "the run wrote frame_000003.vtu")
r = subprocess.run([str(Path(sys.executable).parent / "elastopt"), "list"], capture_output=True, text=True)
check(r.returncode == 0 and "newton" in r.stdout, "the `elastopt` console script lists the optimizers")
r = subprocess.run([sys.executable, "-m", "elastopt", "run", "--scene", "nosuch"], capture_output=True, text=True)
check(r.returncode == 2 and "nosuch" in r.stderr, f"a bad scene name: exit status 2 with the message ({r.returncode})")

with eo.Sim(scene="cantilever", overrides=ov) as sim:
    rs = sim.run()
    check(len(rs) == 3 and all(s.converged for s in rs), f"Sim: 3 converged steps {[s.reason for s in rs]}")
    x, v, t, k = sim.get_state()
    if frame.exists():
        f = eo.read_vtu(frame)
        dx = np.abs(f["points"] - x).max()
        dv = np.abs(f["point_data"]["velocity"] - v).max()
        check(dx <= 1e-12 and dv <= 1e-12, f"Sim equals the CLI run: |dx| {dx:.2e}, |dv| {dv:.2e}")
    sag = sim.initial_positions[:, 2].mean() - sim.positions[:, 2].mean()
    check(sag > 1e-5, f"the cantilever sags under gravity: {sag:.3e} m")
    try:
        sim.positions[0, 0] = 1.0
        check(False, "positions refuse writes")
    except ValueError:
        check(True, "positions refuse writes (ValueError)")
try:
    eo.Sim(overrides={"time.dtt": 1})
    check(False, "a bad key raises ElastoptError")
except eo.ElastoptError as e:
    check(e.name == "EO_ERR_UNKNOWN_KEY" and "time.dtt" in e.message,
          f"a bad key raises ElastoptError with the library's message: {e}")


# ---- (b) a Python optimizer (Newton with a dense numpy solve) through the API
def dense(H, n):
    if isinstance(H, tuple):   # no SciPy: (indptr, indices, data) of a CSC matrix
        indptr, indices, data = H
        A = np.zeros((n, n))
        cols = np.repeat(np.arange(n), np.diff(indptr))
        np.add.at(A, (indices, cols), data)
        return A
    return H.toarray()


def dense_newton(prob, x, g, grad):
    """Newton direction: clamped Hessian, dense numpy solve"""
    return np.linalg.solve(dense(prob.hessian(x, proj="clamp"), prob.n), -grad)


eo.register_optimizer("py_dense_newton", direction=dense_newton, needs_hessian=True,
                      newton_decrement=True)
check("py_dense_newton" in [n for n, _ in eo.methods("optimizer")], "py_dense_newton is listed")
ov2 = {"time.steps": 3, "time.dt": 0.03, **SMALL}
res = {}
for opt in ("newton", "py_dense_newton"):
    with eo.Sim(scene="twist", overrides={**ov2, "solver.optimizer": opt}) as sim:
        rs = sim.run()
        res[opt] = ([s.reason for s in rs], [s.iterations for s in rs], np.array(sim.positions))
reasons, iters, xp = res["py_dense_newton"]
check(reasons == ["converged_decrement"] * 3, f"py_dense_newton converges on each step: {reasons}")
check(iters == res["newton"][1] and sum(iters) > 3,
      f"same iterations as the built-in newton: {iters} vs {res['newton'][1]}")
d = np.abs(xp - res["newton"][2]).max()
check(d <= 1e-10, f"same positions as the built-in newton: {d:.2e}")

# ---- (c) a small benchmark: the CLI's and the in-process one (times the Python optimizer)
suite = {"repeats": 1, "steps": 1, "time_budget": 5, "max_iters": 3000, "plots": False,
         "thresholds": [1e-2, 1e-4, 1e-6], "budgets": [0.01, 0.1], "baseline": "newton",
         "require_converged": ["newton"],
         "scenes": [{"name": "cantilever", "scene": "cantilever", "set": SMALL}],
         "configs": [{"name": "newton", "set": {"solver.optimizer": "newton"}}]}
Path("suite.json").write_text(json.dumps(suite))
r = subprocess.run([sys.executable, "-m", "elastopt", "bench", "suite.json", "--out", "bench_cli",
                    "--no-plots", "--quiet"], capture_output=True, text=True)
check(r.returncode == 0, f"python -m elastopt bench (status {r.returncode}) {r.stderr[-400:]}")
summary = Path("bench_cli/summary.csv")
check(summary.exists() and ",converged," in summary.read_text(), "the CLI bench wrote a converged summary row")

suite["configs"].append({"name": "py_dense_newton", "set": {"solver.optimizer": "py_dense_newton"}})
suite["require_converged"].append("py_dense_newton")
b = eo.run_bench(suite, "bench_py")
check(b.runs == 2 and b.required_failures == 0, f"run_bench: {b.runs} runs, {b.required_failures} required failures")
for name in ("newton", "py_dense_newton"):
    row = b.row("cantilever", name)
    check(row["status"] == "converged" and float(row["final_rel_err"]) <= 1e-6,
          f"run_bench {name}: {row['status']}, final_rel_err {row['final_rel_err']}")

left = mapped_from_source()
check(not left, f"nothing loaded from the source or build tree {left}")
eo.unregister_optimizer("py_dense_newton")
print(f"{len(failures)} failed", flush=True)
sys.exit(1 if failures else 0)
