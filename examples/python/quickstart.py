# %% [markdown]
# # elastopt from Python: a quick start
#
# Notebook-style cells (`# %%`: run them one by one in an editor that understands them,
# or the whole file). From the source tree, after `bash scripts/setup.sh`:
#
#     PYTHONPATH=python /usr/bin/python3 examples/python/quickstart.py
#
# Nothing is installed: the package finds build/libelastopt.so (or $ELASTOPT_LIB).

# %% A scene: the built-in cantilever with overrides (the CLI's -o key=value)
import numpy as np
import scipy.sparse.linalg as spla

import elastopt as eo

sim = eo.Sim(scene="cantilever", overrides={"time.steps": 10, "mesh.generate.cells": [10, 2, 2]})
print(f"{sim.nv} vertices, {sim.nt} tets, {sim.steps} steps of {sim.config['time']['dt']} s")

# %% Step, and read the state as numpy arrays (nv x 3)
r = sim.step()
print(f"step 1: {r.iterations} iterations, {r.reason}, tip z = {sim.positions[:, 2].min():.6f} m")
x, v, t, k = sim.get_state()

# %% The next step's optimization problem: g, ∇g and the Hessian at any x
P = sim.problem()                      # over the free coordinates (clamped end eliminated)
x0 = P.guess                           # the solver's starting point
g, grad = P.gradient(x0)
H = P.hessian(x0)                      # scipy.sparse.csc_matrix, both triangles
d = np.random.default_rng(0).standard_normal(P.n)
h = 1e-6
print("directional derivative: FD", (P.value(x0 + h * d) - P.value(x0 - h * d)) / (2 * h),
      " grad.d", grad @ d)
print("H d vs FD of grad:", np.linalg.norm(H @ d - (P.gradient(x0 + h * d)[1] - P.gradient(x0 - h * d)[1]) / (2 * h))
      / np.linalg.norm(H @ d))

# %% A Newton step by hand with SciPy: the minimizer of this step's quadratic model
xn = x0 + spla.spsolve(P.hessian(x0, proj="clamp"), -grad)
print(f"g(x0) = {g:.12g}, g(x0 + p) = {P.value(xn):.12g}")


# %% An optimizer written in Python, direction form: the library's line search,
# stopping rule, iteration cap and records do the rest
def py_newton(prob, x, g, grad):
    """Newton direction from the clamped Hessian and SciPy's spsolve"""
    return spla.spsolve(prob.hessian(x, proj="clamp"), -grad)


eo.register_optimizer("py_newton", direction=py_newton, needs_hessian=True)


# %% ... and the minimize form: the whole loop in Python; report() records each iterate
# (and says when the caller wants to stop, e.g. the benchmark's target error)
def py_gd(prob, x):
    """Mass-scaled gradient descent with Armijo backtracking"""
    g, grad = prob.g0, prob.grad0
    M = prob.metric()                   # lumped mass of the free coordinates
    for k in range(prob.max_iters + 1):
        reason = prob.stop(g, np.linalg.norm(grad))    # the configured solver.stop
        if reason or k == prob.max_iters:
            return x, k, reason
        p = -grad / M
        a = 1.0
        while prob.value(x + a * p) > g + 1e-4 * a * (grad @ p):
            a /= 2
        x = x + a * p
        g, grad = prob.gradient(x)
        if prob.report(x, g, grad, alpha=a):
            return x, k + 1, None


eo.register_optimizer("py_gd", minimize=py_gd)

# %% Use them like built-in methods: in a sim, in a trial solve, in a bench suite
sim.set_solver({"solver.optimizer": "py_newton"})
print("py_newton:", sim.step())
xg, res = sim.trial(solver=eo.Solver({"solver.optimizer": "py_gd", "solver.stop": "gradient",
                                      "solver.tol": 1e-4, "solver.max_iters": 5000}))
print(f"py_gd on the next step: {res.iterations} iterations, {res.reason}")

# %% Benchmark them beside Newton (in this process; no plots)
suite = {
    "repeats": 1, "steps": 1, "time_budget": 2, "plots": False, "baseline": "newton",
    "thresholds": [1e-2, 1e-4, 1e-6], "budgets": [0.01, 0.1],
    "scenes": [{"name": "cantilever", "scene": "cantilever", "set": {"mesh.generate.cells": [10, 2, 2]}}],
    "configs": [{"name": "newton", "set": {"solver.optimizer": "newton"}},
                {"name": "py_newton", "set": {"solver.optimizer": "py_newton"}},
                {"name": "py_gd", "set": {"solver.optimizer": "py_gd", "solver.stop": "gradient",
                                          "solver.tol": 1e-6, "solver.max_iters": 3000}}],
}
res = eo.run_bench(suite, "out/python-bench")
for row in res.rows:
    print(f"{row['config']:10s} {row['status']:10s} time to 1e-6: {row['t_1e-06_median']} s "
          f"(x{row['ratio_1e-06']} of newton)")
print("report:", res.files["report.md"])

# %% Errors from the library are exceptions with its message
try:
    eo.Sim(overrides={"time.dtt": 0.5})
except eo.ElastoptError as e:
    print("ElastoptError:", e.message)
sim.close()
