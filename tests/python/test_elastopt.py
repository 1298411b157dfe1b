"""Tests of the Python package (python/elastopt), run by tests/test_python.sh (suite
`python`) with PYTHONPATH=python against the build tree's libelastopt.so.

Environment: ELASTOPT_CLI (the elastopt command), EO_PY_ABI (tests/py_abi, the C
layouts), EO_BUILD_ROOT (the build tree), EO_SOURCE_ROOT, EO_TMP (a scratch folder)."""
import math
import os
import subprocess
import sys
import unittest
from pathlib import Path

import numpy as np

import elastopt as eo
from elastopt import _ffi
from elastopt.objective import symmetric_full

try:
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla
except ImportError:  # the optimizer tests need SciPy's spsolve
    sp = spla = None

CLI = os.environ.get("ELASTOPT_CLI")
TMP = Path(os.environ.get("EO_TMP", "/tmp/elastopt-python-test"))
SMALL = {"mesh.generate.cells": [8, 2, 2]}


def py_newton_direction(prob, x, g, grad):
    """Newton direction: clamped Hessian solved with scipy.sparse.linalg.spsolve"""
    return spla.spsolve(prob.hessian(x, proj="clamp"), -grad)


def py_newton_minimize(prob, x):
    """Newton with Armijo backtracking written in Python (minimize form)"""
    g, grad = prob.g0, prob.grad0
    for k in range(prob.max_iters + 1):
        p = spla.spsolve(prob.hessian(x, proj="clamp"), -grad)
        dec = -grad @ p / 2
        reason = prob.stop(g, np.linalg.norm(grad), dec, x=x, grad=grad)
        if reason or k == prob.max_iters:
            return x, k, reason
        a = 1.0
        while prob.value(x + a * p) > g - 1e-4 * a * 2 * dec:
            a /= 2
        x = x + a * p
        g, grad = prob.gradient(x)
        if prob.report(x, g, grad, decrement=dec, alpha=a):
            return x, k + 1, None


def py_gradient_descent(prob, x):
    """Mass-scaled gradient descent with the configured line search (minimize form)"""
    g, grad = prob.g0, prob.grad0
    M = prob.metric()
    for k in range(prob.max_iters + 1):
        reason = prob.stop(g, np.linalg.norm(grad), x=x, grad=grad)
        if reason or k == prob.max_iters:
            return x, k, reason
        # the configured line search (backtracking here)
        x, g, a, nev, gnew, ok = prob.line_search(x, -grad / M, g, grad)
        if not ok:
            return x, k, "diverged_linesearch"
        grad = prob.gradient(x)[1] if gnew is None else gnew
        if prob.report(x, g, grad, alpha=a, ls_evals=nev):
            return x, k + 1, None


def setUpModule():
    TMP.mkdir(parents=True, exist_ok=True)
    if spla is not None:
        eo.register_optimizer("py_newton", direction=py_newton_direction, needs_hessian=True,
                              newton_decrement=True)
        eo.register_optimizer("py_newton_min", minimize=py_newton_minimize, needs_hessian=True,
                              newton_decrement=True)
        eo.register_optimizer("py_gd", minimize=py_gradient_descent)


def tearDownModule():
    """Everything the tests made is freed: no byte left in the package's context."""
    import gc
    for name in eo.registered_optimizers():
        eo.unregister_optimizer(name)
    gc.collect()
    left = eo.live_bytes()
    if left:
        raise AssertionError(f"{left} bytes still allocated through the context")


class Layout(unittest.TestCase):
    def test_struct_layouts_match_the_c_compiler(self):
        exe = os.environ.get("EO_PY_ABI")
        if not exe:
            self.skipTest("EO_PY_ABI not set")
        lines = subprocess.run([exe], check=True, capture_output=True, text=True).stdout.split("\n")
        ffi = _ffi.ffi
        checked = 0
        for ln in filter(None, lines):
            t, f, v = ln.split()
            got = ffi.sizeof(t) if f == "-" else ffi.offsetof(t, f)
            self.assertEqual(got, int(v), f"{t} {f}: cffi {got}, C {v}")
            checked += 1
        self.assertGreater(checked, 60)


class Loading(unittest.TestCase):
    def _import(self, env):
        e = {k: v for k, v in os.environ.items() if k not in ("ELASTOPT_LIB", "EO_BUILD_ROOT")}
        e.update(env)
        return subprocess.run([sys.executable, "-c", "import elastopt; print(elastopt.lib_path)"],
                              env=e, capture_output=True, text=True)

    def test_elastopt_lib_is_used_first(self):
        r = self._import({"ELASTOPT_LIB": str(eo.lib_path)})
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout.strip(), str(eo.lib_path))
        r = self._import({"ELASTOPT_LIB": str(TMP / "no" / "libelastopt.so.0")})
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("ImportError: elastopt: libelastopt.so not found", r.stderr)
        self.assertIn("ELASTOPT_LIB", r.stderr)


class CommandLine(unittest.TestCase):
    def test_python_m_elastopt_runs_the_build_trees_cli(self):
        """`python -m elastopt` from another folder, without ELASTOPT_CLI: the CLI beside
        the loaded library (build/cli/elastopt), its output and exit status."""
        e = {k: v for k, v in os.environ.items() if k != "ELASTOPT_CLI"}
        r = subprocess.run([sys.executable, "-c", "import elastopt; print(elastopt.cli_path())"],
                           env=e, capture_output=True, text=True, cwd=TMP)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(Path(r.stdout.strip()), eo.lib_path.resolve().parent / "cli" / "elastopt")
        r = subprocess.run([sys.executable, "-m", "elastopt", "list"], env=e, capture_output=True,
                           text=True, cwd=TMP)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("newton", r.stdout)
        r = subprocess.run([sys.executable, "-m", "elastopt", "run", "--scene", "nosuch"], env=e,
                           capture_output=True, text=True, cwd=TMP)
        self.assertEqual(r.returncode, 2, r.stderr)   # the CLI's usage status, passed through
        self.assertIn("nosuch", r.stderr)


class Arrays(unittest.TestCase):
    """Every array the package hands out is a read-only copy (writing raises ValueError
    and changes nothing) or a new array owned by the caller; none is a view."""

    def test_sim_arrays_refuse_writes(self):
        with eo.Sim(scene="cantilever", overrides=SMALL) as s:
            s.step()
            x_before, v_before = s.get_state()[:2]
            for name in ("positions", "velocities", "rest_positions", "initial_positions",
                         "tets", "vertex_mass"):
                a = getattr(s, name)
                self.assertFalse(a.flags.writeable, name)
                with self.assertRaises(ValueError, msg=name):
                    a[0] = 7
                with self.assertRaises(ValueError, msg=name):
                    a += 1
            x, v = s.get_state()[:2]
            self.assertTrue(np.array_equal(x, x_before) and np.array_equal(v, v_before))
            # a copy: it keeps the values of the time it was taken
            x1 = s.positions
            s.step()
            self.assertTrue(np.array_equal(x1, x_before))
            self.assertGreater(np.abs(s.positions - x1).max(), 1e-6)
            # get_state: writable copies owned by the caller, applied by set_state only
            xs, vs, t, k = s.get_state()
            self.assertTrue(xs.flags.writeable and vs.flags.writeable)
            xs[:, 2] += 0.5
            self.assertFalse(np.array_equal(s.positions, xs))
            s.set_state(positions=xs)
            self.assertTrue(np.array_equal(s.positions, xs))
            s.velocities = np.ones((s.nv, 3))
            self.assertTrue(np.array_equal(s.velocities, np.ones((s.nv, 3))))

    def test_problem_arrays(self):
        with eo.Sim(scene="cantilever", overrides=SMALL) as s:
            P = s.problem()
            with self.assertRaises(ValueError):
                P.guess[0] = 1.0
            with self.assertRaises(ValueError):
                P.free_index[0] = 0
            g, grad = P.gradient(P.guess)
            ref = grad.copy()
            grad[:] = 0.0              # the caller's own array: allowed, no effect elsewhere
            self.assertTrue(np.array_equal(P.gradient(P.guess)[1], ref))
            self.assertGreater(np.abs(ref).max(), 0)

    def test_callback_arrays_refuse_writes(self):
        seen = {}

        def write_grad(prob, x, g, grad):
            seen["direction"] = (x.flags.writeable, grad.flags.writeable)
            grad[0] = 0.0
            return -grad

        def write_grad0(prob, x):
            seen["minimize"] = (x.flags.writeable, prob.grad0.flags.writeable)
            x[0] += 0.0                # the start copy is the optimizer's own
            prob.grad0[0] = 0.0
            return x, 0, None

        for name, kw in (("py_write_grad", {"direction": write_grad}),
                         ("py_write_grad0", {"minimize": write_grad0})):
            eo.register_optimizer(name, **kw)
            try:
                with eo.Sim(scene="cantilever", overrides={**SMALL, "solver.optimizer": name}) as s:
                    x0 = s.positions
                    with self.assertRaises(ValueError) as e:
                        s.step()
                    self.assertIn("read-only", str(e.exception))
                    self.assertTrue(np.array_equal(s.positions, x0))   # the step did not happen
                    self.assertEqual(s.index, 0)
            finally:
                eo.unregister_optimizer(name)
        self.assertEqual(seen, {"direction": (False, False), "minimize": (True, False)})
        # the iterate of an on_iteration callback
        with eo.Sim(scene="cantilever", overrides=SMALL) as s:
            def cb(info, x):
                x[0] = 0.0
            s.on_iteration = cb
            with self.assertRaises(ValueError):
                s.step()


class Stepping(unittest.TestCase):
    def test_python_steps_equal_the_cli(self):
        """5 steps from Python and from `elastopt run`: positions and velocities to 1e-12."""
        if not CLI:
            self.skipTest("ELASTOPT_CLI not set")
        out = TMP / "cli_run"
        ov = {"time.steps": 5, "mesh.generate.cells": [8, 2, 2], "solver.hessian_fix": "abs"}
        args = [CLI, "run", "--scene", "twist", "--out", str(out), "--quiet"]
        for k, v in ov.items():
            args += ["-o", eo._core.override_text(k, v)]
        subprocess.run(args, check=True)
        frame = eo.read_vtu(out / "frame_000005.vtu")
        with eo.Sim(scene="twist", overrides=ov) as sim:
            rs = sim.run()
            self.assertEqual(len(rs), 5)
            self.assertTrue(all(r.converged for r in rs))
            x, v, t, k = sim.get_state()
            self.assertEqual(k, 5)
            self.assertAlmostEqual(t, 0.05, places=14)
            self.assertEqual(frame["points"].shape, x.shape)
            self.assertLessEqual(np.abs(frame["points"] - x).max(), 1e-12)
            self.assertLessEqual(np.abs(frame["point_data"]["velocity"] - v).max(), 1e-12)
            moved = np.abs(x - sim.initial_positions).max()
            self.assertGreater(moved, 1e-3)   # the bar really twisted

    def test_explicit_steps_are_not_counted_as_converged(self):
        """An explicit integrator's steps: reason "explicit", converged False, free fall exact."""
        ov = {"time.integrator": "verlet", "time.steps": 3, "time.dt": 1e-4, "mesh.generate.cells": [4, 1, 1]}
        with eo.Sim(scene="freefall", overrides=ov) as sim:
            rs = sim.run()
            self.assertEqual([r.reason for r in rs], ["explicit"] * 3)
            self.assertFalse(any(r.converged for r in rs))
            self.assertEqual([r.iterations for r in rs], [0, 0, 0])
        self.assertEqual(eo.reason_name(6), "explicit")

    def test_state_roundtrip_and_restart(self):
        """A state copied into another sim continues the same trajectory, bit for bit."""
        with eo.Sim(scene="cantilever", overrides=SMALL) as a, eo.Sim(scene="cantilever", overrides=SMALL) as b:
            a.run(3)
            x, v, t, k = a.get_state()
            b.set_state(x, v, t, k)
            xb, vb, tb, kb = b.get_state()
            self.assertTrue(np.array_equal(xb, x) and np.array_equal(vb, v) and tb == t and kb == k)
            a.step()
            b.step()
            self.assertTrue(np.array_equal(a.positions, b.positions))
            self.assertTrue(np.array_equal(a.velocities, b.velocities))
            # setting positions through the property moves the body
            b.positions = b.positions + [0.0, 0.0, 1.0]
            self.assertTrue(np.allclose(b.positions[:, 2] - a.positions[:, 2], 1.0, atol=0))
            with self.assertRaises(ValueError):
                b.positions = np.zeros((3, 3))
            b.reset()
            self.assertEqual((b.t, b.index), (0.0, 0))
            self.assertTrue(np.array_equal(b.positions, b.initial_positions))

    def test_dict_scene_and_config(self):
        src = Path(os.environ.get("EO_SOURCE_ROOT", Path(__file__).parents[2]))
        import json
        d = json.loads((src / "examples" / "cantilever.json").read_text())
        with eo.Sim(scene="cantilever") as c:
            self.assertEqual(c.config["solver"]["optimizer"], "newton")
        with eo.Sim(d, overrides={"time.steps": 2, **SMALL}) as s:
            self.assertEqual(s.steps, 2)
            self.assertEqual(s.nv, 9 * 3 * 3)
            self.assertEqual(s.tets.shape, (s.nt, 4))
            self.assertAlmostEqual(s.vertex_mass.sum(), 1000 * 1.0 * 0.1 * 0.1, places=9)
            rs = s.run()
            self.assertEqual(len(rs), 2)
            f = s.fields()
            self.assertEqual(f["J"].shape, (s.nt,))
            self.assertAlmostEqual(f["J"].min(), rs[-1].stats["min_J"], places=14)

    def test_errors_carry_the_library_message(self):
        with self.assertRaises(eo.ElastoptError) as e:
            eo.Sim(overrides={"time.dtt": 1})
        self.assertEqual(e.exception.name, "EO_ERR_UNKNOWN_KEY")
        self.assertIn("time.dtt", e.exception.message)
        self.assertIn("valid keys here: integrator, dt, steps", e.exception.message)
        with self.assertRaises(eo.ElastoptError) as e:
            eo.Sim(overrides={"solver.optimizer": "nosuch"})
        self.assertIn("newton", e.exception.message)   # lists the valid names
        bad = TMP / "bad.json"
        bad.write_text('{"time": {"dt": 0.01,}}\n')
        with self.assertRaises(eo.ElastoptError) as e:
            eo.Sim(bad)
        self.assertEqual(e.exception.name, "EO_ERR_PARSE")
        self.assertIn(f"{bad}:1:", e.exception.message)


class Derivatives(unittest.TestCase):
    """∇g against finite differences of g; H v against finite differences of ∇g."""

    @classmethod
    def setUpClass(cls):
        cls.sim = eo.Sim(scene="twist", overrides=SMALL)
        cls.sim.run(2)
        cls.P = cls.sim.problem()
        rng = np.random.default_rng(1)
        cls.x = cls.P.guess + 1e-3 * rng.standard_normal(cls.P.n)  # off the minimizer
        cls.dirs = rng.standard_normal((4, cls.P.n))

    @classmethod
    def tearDownClass(cls):
        cls.sim.close()

    def test_gradient_matches_fd_of_g(self):
        P, x = self.P, self.x
        g, grad = P.gradient(x)
        self.assertAlmostEqual(P.value(x), g, delta=1e-14 * abs(g))
        for d in self.dirs:
            h = 1e-7   # truncation-limited here: 6e-9 relative at 1e-7, 4e-7 at 1e-6
            fd = (P.value(x + h * d) - P.value(x - h * d)) / (2 * h)
            self.assertLessEqual(abs(fd - grad @ d), 1e-6 * abs(grad @ d), (fd, grad @ d))
        # per coordinate on a few coordinates
        for i in (0, P.n // 2, P.n - 1):
            e = np.zeros(P.n)
            e[i] = 1e-6
            fd = (P.value(x + e) - P.value(x - e)) / 2e-6
            self.assertLessEqual(abs(fd - grad[i]), 1e-5 * np.abs(grad).max() + 1e-9)

    def test_hessian_times_vector_matches_fd_of_gradient(self):
        P, x = self.P, self.x
        H = P.hessian(x)   # true Hessian
        self.assertEqual(H.shape, (P.n, P.n))
        self.assertEqual(abs(H - H.T).max(), 0)
        for d in self.dirs:
            h = 1e-6
            fd = (P.gradient(x + h * d)[1] - P.gradient(x - h * d)[1]) / (2 * h)
            Hd = H @ d
            self.assertLessEqual(np.linalg.norm(fd - Hd), 1e-6 * np.linalg.norm(Hd))

    def test_projections_and_pattern(self):
        P, x = self.P, self.x
        U = P.hessian(x, upper=True)
        self.assertEqual(sp.triu(U).nnz, U.nnz)            # upper triangle only
        full = P.hessian(x)
        self.assertEqual(abs(sp.triu(full) - U).max(), 0)
        Hc = P.hessian(x, proj="clamp")
        self.assertGreater(np.linalg.eigvalsh(Hc.toarray()).min(), 0)   # mass makes it PD
        with self.assertRaises(ValueError):
            P.hessian(x, proj="square")
        # the SciPy-free path builds the same full matrix
        n = U.shape[0]
        indptr, indices, data = symmetric_full(n, U.indptr, U.indices, U.data)
        self.assertTrue(np.array_equal(sp.csc_matrix((data, indices, indptr), shape=(n, n)).toarray(),
                                       full.toarray()))

    def test_hessian_without_scipy(self):
        """Without SciPy hessian() gives the (indptr, indices, data) of the same matrix."""
        import elastopt.objective as objmod
        saved, objmod._sp = objmod._sp, None
        try:
            indptr, indices, data = self.P.hessian(self.x)
        finally:
            objmod._sp = saved
        n = self.P.n
        self.assertEqual(indptr.size, n + 1)
        ref = self.P.hessian(self.x)
        self.assertTrue(np.array_equal(sp.csc_matrix((data, indices, indptr), shape=(n, n)).toarray(),
                                       ref.toarray()))

    def test_free_map_and_counts(self):
        P = self.P
        pos = self.sim.positions
        xf = P.to_free(pos)
        self.assertEqual(xf.size, P.n)
        self.assertLess(P.n, 3 * self.sim.nv)   # the clamped ends are eliminated
        c0 = P.counts["gradient"]
        P.gradient(xf)
        self.assertEqual(P.counts["gradient"], c0 + 1)

    def test_problem_goes_stale(self):
        with eo.Sim(scene="cantilever", overrides=SMALL) as s:
            P = s.problem()
            P.value(P.guess)
            s.step()
            with self.assertRaises(ValueError):
                P.value(P.guess)


@unittest.skipIf(spla is None, "SciPy not installed")
class PythonOptimizers(unittest.TestCase):
    def _run(self, opt, steps=3, scene="twist", extra=None):
        ov = {"time.steps": steps, "time.dt": 0.03, "solver.optimizer": opt, **SMALL, **(extra or {})}
        with eo.Sim(scene=scene, overrides=ov) as s:
            recs = []
            s.on_iteration = lambda info, x: recs.append(info) and False
            rs = s.run()
            return rs, s.positions, recs

    def test_listed_with_the_builtins(self):
        names = [n for n, _ in eo.methods("optimizer")]
        for n in ("newton", "py_newton", "py_newton_min", "py_gd"):
            self.assertIn(n, names)

    def test_direction_form_equals_builtin_newton(self):
        rn, xn, _ = self._run("newton")
        rp, xp, recs = self._run("py_newton")
        self.assertTrue(all(r.converged for r in rp))
        self.assertEqual([r.iterations for r in rp], [r.iterations for r in rn])
        self.assertGreater(sum(r.iterations for r in rp), 3)   # several Newton iterations
        self.assertLessEqual(np.abs(xp - xn).max(), 1e-10)
        self.assertEqual(len(recs), sum(r.iterations + 1 for r in rp))
        self.assertEqual(recs[-1]["reason"], "converged_decrement")

    def test_minimize_form_converges_on_the_step(self):
        rn, xn, _ = self._run("newton")
        rp, xp, recs = self._run("py_newton_min")
        self.assertTrue(all(r.reason == "converged_decrement" for r in rp), [r.reason for r in rp])
        self.assertLessEqual(np.abs(xp - xn).max(), 1e-10)
        # one record per iterate: start, one per accepted step; the last carries the reason
        self.assertEqual(len(recs), sum(r.iterations + 1 for r in rp))
        self.assertEqual([r["iteration"] for r in recs[:rp[0].iterations + 1]],
                         list(range(rp[0].iterations + 1)))
        self.assertEqual(recs[rp[0].iterations]["reason"], "converged_decrement")
        self.assertTrue(all(math.isfinite(r["alpha"]) for r in recs[:rp[0].iterations]))

    def test_gradient_descent_on_the_cantilever_step(self):
        """The first cantilever step: g decreases to the Newton minimizer's value."""
        with eo.Sim(scene="cantilever", overrides=SMALL) as s:
            xref, rref = s.trial()
            x, r = s.trial(solver=eo.Solver({"solver.optimizer": "py_gd", "solver.stop": "gradient",
                                             "solver.tol": 1e-5, "solver.max_iters": 10000}))
            P = s.problem()
            self.assertEqual(r.reason, "converged_gradient")
            self.assertGreater(r.iterations, 5)
            g0 = P.value(P.guess)
            self.assertLessEqual(abs(P.value(x) - rref.g), 1e-6 * abs(g0 - rref.g))
            self.assertLessEqual(np.linalg.norm(P.gradient(x)[1]), 1e-5 * np.linalg.norm(P.gradient(P.guess)[1]))
            self.assertLessEqual(np.abs(x - xref).max(), 1e-3 * np.abs(P.guess - xref).max())

    def test_exceptions_propagate(self):
        def broken(prob, x, g, grad):
            raise ZeroDivisionError("no direction today")
        eo.register_optimizer("py_broken", direction=broken)
        try:
            with eo.Sim(scene="cantilever", overrides={**SMALL, "solver.optimizer": "py_broken"}) as s:
                with self.assertRaises(ZeroDivisionError):
                    s.step()
        finally:
            eo.unregister_optimizer("py_broken")
        self.assertNotIn("py_broken", [n for n, _ in eo.methods("optimizer")])
        with self.assertRaises(eo.ElastoptError) as e:
            eo.register_optimizer("newton", direction=broken)
        self.assertIn("already registered", e.exception.message)
        with self.assertRaises(ValueError):
            eo.register_optimizer("x", minimize=broken, direction=broken)

    def test_bench_times_python_optimizers_beside_builtins(self):
        suite = {"repeats": 1, "steps": 1, "time_budget": 5, "max_iters": 3000, "plots": False,
                 "thresholds": [1e-2, 1e-4, 1e-6], "budgets": [0.01, 0.1], "baseline": "newton",
                 "require_converged": ["newton", "py_newton", "py_newton_min"],
                 "scenes": [{"name": "cantilever", "scene": "cantilever",
                             "set": {"mesh.generate.cells": [8, 2, 2]}}],
                 "configs": [{"name": "newton", "set": {"solver.optimizer": "newton"}},
                             {"name": "py_newton", "set": {"solver.optimizer": "py_newton"}},
                             {"name": "py_newton_min", "set": {"solver.optimizer": "py_newton_min"}}]}
        seen = []
        res = eo.run_bench(suite, TMP / "bench", progress=lambda p: seen.append(p["phase"]))
        self.assertEqual(res.configs, ["newton", "py_newton", "py_newton_min"])
        self.assertEqual(res.runs, 3)
        self.assertEqual(res.required_failures, 0)
        self.assertIn("curves", seen)
        for name in res.configs:
            row = res.row("cantilever", name)
            self.assertEqual(row["status"], "converged", row)
            t = float(row["t_1e-06_median"])
            self.assertTrue(math.isfinite(t) and t > 0, row)
            self.assertLessEqual(float(row["final_rel_err"]), 1e-6)
            self.assertEqual(row["clock"], "cpu", row)   # CPU seconds of the solving thread
        self.assertEqual(float(res.row("cantilever", "newton")["ratio_1e-06"]), 1.0)
        with self.assertRaises(ValueError):
            eo.run_bench(suite, TMP / "bench-bad", clock="sundial")
        self.assertTrue((res.out_dir / "report.md").exists())
        self.assertIn("py_newton_min", (res.out_dir / "report.md").read_text())
        curves = (res.out_dir / "curves.csv").read_text()
        self.assertGreater(curves.count(",py_newton_min,"), 1)   # per-iterate records


if __name__ == "__main__":
    unittest.main()
