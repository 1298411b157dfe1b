"""Sim: a scene, its step engine and a solver, stepped from Python (sim.h, eo_sim).

Arrays: every array a Sim hands out is a read-only copy (positions, velocities,
rest_positions, initial_positions, tets, vertex_mass, StepProblem.guess, the x of an
on_iteration callback): the library's own memory is never exposed, so an array stays
valid (and unchanged) after the sim steps or is closed, and writing into one raises
ValueError instead of silently changing nothing. To change the state assign
(`sim.positions = x`, `sim.velocities = v`) or call set_state(); get_state() returns
writable copies owned by the caller (a snapshot to edit and pass back).
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from typing import Any, Callable, List, Optional, Tuple, Union

import numpy as np

from ._core import Overrides, check, ctx, overrides_list, reason_name, take_json, set_pending
from ._ffi import REASONS, ffi, lib
from .objective import ArrayLike, Objective, as_c, from_c, readonly

PathLike = Union[str, "os.PathLike[str]"]
IterCallback = Callable[[dict, Optional[np.ndarray]], Any]


@dataclass
class StepResult:
    """What one step did (eo_sim_step_result)."""
    iterations: int
    reason: str           # "converged_decrement", "diverged_max_iters", "explicit", ...
    converged: bool       # an optimization converged (reason > 0, not "explicit")
    t: float              # time after the step
    time: float           # seconds spent minimizing / advancing
    g: float
    grad_norm: float
    evaluations: dict     # value, gradient, hessian, factor
    stats: dict           # com, max_disp, min_J, max_J, inverted, kinetic, elastic, gravity,
                          # contact, potential, work_prescribed, total_energy
    rejected: int = 0     # adaptive stepping (time.adaptive): attempts rejected,
    substeps: int = 1     # substeps accepted,
    min_substep: float = 0.0  # smallest step size tried (s)


@dataclass
class SolveResult:
    """Result of one minimization (eo_solve_result)."""
    reason: str
    converged: bool
    iterations: int
    g: float
    grad_norm: float
    decrement: float
    time: float
    evaluations: dict = field(default_factory=dict)


def _stats(s: Any) -> dict:
    return {"com": [s.com[0], s.com[1], s.com[2]], "max_disp": s.max_disp, "min_J": s.min_J,
            "max_J": s.max_J, "inverted": s.inverted, "kinetic": s.kinetic,
            "elastic": s.elastic, "gravity": s.gravity, "contact": s.contact,
            "potential": s.potential, "work_prescribed": s.work_prescribed,
            "total_energy": s.total_energy}


def _solve_result(r: Any) -> SolveResult:
    return SolveResult(reason_name(r.reason), r.reason > 0, r.iterations, r.g, r.grad_norm,
                       r.decrement, r.time,
                       {"value": r.n_value, "gradient": r.n_gradient, "hessian": r.n_hessian,
                        "factor": r.n_factor})


def iter_info_dict(info: Any) -> dict:
    """An eo_iter_info as a dict (x copied only on request: see Sim.on_iteration)."""
    return {"iteration": info.iteration, "time": info.time, "g": info.g,
            "grad_norm": info.grad_norm, "decrement": info.decrement, "alpha": info.alpha,
            "ls_evals": info.ls_evals, "shift": info.shift, "projected": info.projected,
            "inverted": info.inverted, "reason": reason_name(info.reason) if info.reason else None}


def _solver_cfg(overrides: Overrides) -> Tuple[Any, Any]:
    """(opts, cfg) from solver.* overrides; the cfg must be destroyed by the caller."""
    ov = overrides_list(overrides)
    for o in ov:
        if not o.startswith("solver."):
            raise ValueError(f"solver override {o!r}: only solver.* keys change a solver")
    cfgp = ffi.new("eo_cfg **")
    check(lib.eo_cfg_create_empty(ctx, cfgp))
    try:
        for o in ov:
            check(lib.eo_cfg_override(ctx, cfgp[0], o.encode()))
        opts = ffi.new("eo_solver_opts *")
        lib.eo_solver_opts_default(opts)
        check(lib.eo_solver_opts_load(ctx, cfgp[0], opts))
    except BaseException:
        lib.eo_cfg_destroy(cfgp)
        raise
    return opts, cfgp


class Solver:
    """A stand-alone solver configuration (for Sim.trial), from solver.* overrides:
    Solver({"solver.optimizer": "lbfgs", "solver.linesearch": "wolfe"}). ElastoptError
    for an unknown key or method (the library's message)."""

    def __init__(self, overrides: Overrides = None) -> None:
        opts, cfgp = _solver_cfg(overrides)
        try:
            sp = ffi.new("eo_solver **")
            check(lib.eo_solver_create(ctx, opts, cfgp[0], sp))
        finally:
            lib.eo_cfg_destroy(cfgp)
        self._p = sp

    @property
    def config(self) -> dict:
        """The effective solver section (every default filled in)."""
        return take_json(lib.eo_solver_to_json(self._p[0]))

    def close(self) -> None:
        """Destroy the solver (also done when the object is collected)."""
        p = getattr(self, "_p", None)
        if p is not None and p[0] != ffi.NULL:
            lib.eo_solver_destroy(p)

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: the library may be gone already
            pass


class StepProblem(Objective):
    """The next step's objective of a Sim (Sim.problem()): g, ∇g, Hessian at any x of
    the free coordinates, the starting guess, the free -> full coordinate map."""

    def __init__(self, sim: Sim, obj: Any, guess: Any) -> None:
        super().__init__(obj, owner=sim)
        self._sim = sim
        self._gen = sim._gen
        #: the solver's starting point (n free coordinates; a read-only copy)
        self.guess: np.ndarray = readonly(from_c(guess, obj.n))
        st = lib.eo_sim_step_problem(sim._s)
        #: index in the flattened positions (3 nv) of each free coordinate (read-only)
        self.free_index: np.ndarray = readonly(np.array(
            [lib.eo_step_free_to_full(st, i) for i in range(obj.n)], dtype=np.int64))

    def to_free(self, positions: ArrayLike) -> np.ndarray:
        """The free coordinates of full positions (nv x 3 or 3 nv)."""
        return np.asarray(positions, dtype=np.float64).reshape(-1)[self.free_index].copy()


class Sim:
    """A simulation (sim.h): Sim(file) | Sim(scene="twist") | Sim(dict) | Sim() (the
    built-in cantilever), each with `overrides`, a dict {"time.steps": 20, ...} or a list
    of "key=value" strings (the CLI's -o). Everything is validated on creation;
    errors raise ElastoptError with the library's message (file, line, key)."""

    def __init__(self, file: Union[PathLike, dict, None] = None, *, scene: Optional[str] = None,
                 overrides: Overrides = None) -> None:
        ov = overrides_list(overrides)
        sp = ffi.new("eo_sim **")
        if isinstance(file, dict):
            cfgp = ffi.new("eo_cfg **")
            check(lib.eo_cfg_load(ctx, ffi.NULL, json.dumps(file).encode(), cfgp))
            try:
                for o in ov:
                    check(lib.eo_cfg_override(ctx, cfgp[0], o.encode()))
            except BaseException:
                lib.eo_cfg_destroy(cfgp)
                raise
            check(lib.eo_sim_create(ctx, cfgp[0], sp))   # takes the cfg over
        else:
            keep = [ffi.new("char[]", o.encode()) for o in ov]
            arr = ffi.new("const char *[]", keep + [ffi.NULL])
            path = ffi.NULL if file is None else os.fsencode(os.fspath(file))
            name = ffi.NULL if scene is None else scene.encode()
            check(lib.eo_sim_create_from(ctx, path, name, arr, sp))
        self._sp = sp
        self._s = sp[0]
        self._gen = 0
        self._iter_cb = None
        self._iter_fn = None
        self._cur_n = 0
        st = lib.eo_sim_step_problem(self._s)
        mesh = ffi.cast("const eo_mesh_head *", lib.eo_step_mesh(st))
        self.nv = mesh.nv
        self.nt = mesh.nt
        self._mesh = mesh

    # ---- lifetime
    def close(self) -> None:
        """Destroy the simulation (also done when the object is collected)."""
        if getattr(self, "_sp", None) is not None and self._sp[0] != ffi.NULL:
            lib.eo_sim_destroy(self._sp)
            self._s = ffi.NULL
            self._gen += 1

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: the library may be gone already
            pass

    def __enter__(self) -> Sim:
        return self

    def __exit__(self, *a: Any) -> None:
        self.close()

    def _live(self):
        if self._s == ffi.NULL:
            raise ValueError("elastopt: the simulation was closed")
        return self._s

    def _check_alive(self, problem):
        self._live()
        if problem._gen != self._gen:
            raise ValueError("elastopt: this step problem is stale (the simulation stepped, "
                             "trialled or changed state since Sim.problem())")

    def _changed(self):
        self._gen += 1

    # ---- description
    @property
    def config(self) -> dict:
        """The resolved scene configuration (every default filled in) with the solver's
        effective section, as in summary.json."""
        s = self._live()
        d = take_json(lib.eo_scene_to_json(lib.eo_sim_scene(s)))
        d["solver"] = take_json(lib.eo_solver_to_json(lib.eo_sim_solver(s)))
        return d

    @property
    def steps(self) -> int:
        """The scene's time.steps."""
        return self.config["time"]["steps"]

    @property
    def explicit(self) -> bool:
        """The time integrator is explicit (steps solve no optimization problem)."""
        return bool(lib.eo_sim_is_explicit(self._live()))

    @property
    def t(self) -> float:
        """Simulated time (s)."""
        return lib.eo_sim_time(self._live())

    @property
    def index(self) -> int:
        """Steps done."""
        return lib.eo_sim_index(self._live())

    @property
    def rest_positions(self) -> np.ndarray:
        """Rest positions (nv x 3, a read-only copy)."""
        self._live()
        return readonly(from_c(self._mesh.X, 3 * self.nv).reshape(self.nv, 3))

    @property
    def initial_positions(self) -> np.ndarray:
        """Positions at t = 0 (nv x 3, a read-only copy)."""
        st = lib.eo_sim_step_problem(self._live())
        return readonly(from_c(lib.eo_step_x0(st), 3 * self.nv).reshape(self.nv, 3))

    @property
    def tets(self) -> np.ndarray:
        """Tet vertex indices (nt x 4, a read-only copy)."""
        self._live()
        return readonly(from_c(self._mesh.tets, 4 * self.nt, np.int32).reshape(self.nt, 4))

    @property
    def vertex_mass(self) -> np.ndarray:
        """Lumped mass of each vertex (nv, a read-only copy)."""
        st = lib.eo_sim_step_problem(self._live())
        return readonly(from_c(lib.eo_step_vertex_mass(st), self.nv))

    # ---- state
    def get_state(self) -> Tuple[np.ndarray, np.ndarray, float, int]:
        """(positions, velocities, t, index): positions and velocities nv x 3, writable
        copies owned by the caller (a snapshot: writing into them changes nothing in
        the sim until they are passed to set_state)."""
        s = self._live()
        x = np.empty(3 * self.nv)
        v = np.empty(3 * self.nv)
        t = ffi.new("double *")
        k = ffi.new("int *")
        lib.eo_sim_get_state(s, ffi.from_buffer("double[]", x), ffi.from_buffer("double[]", v), t, k)
        return x.reshape(self.nv, 3), v.reshape(self.nv, 3), t[0], k[0]

    def set_state(self, positions: Optional[ArrayLike] = None, velocities: Optional[ArrayLike] = None,
                  t: Optional[float] = None, index: Optional[int] = None) -> None:
        """Set any part of the state (the rest is kept); the arrays are copied.
        ValueError for arrays of the wrong size, ElastoptError from the library."""
        x0, v0, t0, k0 = self.get_state()
        x, px = as_c(x0 if positions is None else positions, 3 * self.nv, "positions")
        v, pv = as_c(v0 if velocities is None else velocities, 3 * self.nv, "velocities")
        self._changed()
        check(lib.eo_sim_set_state(self._live(), px, pv, t0 if t is None else float(t),
                                   k0 if index is None else int(index)))

    @property
    def positions(self) -> np.ndarray:
        """Current positions, nv x 3: a read-only copy (writing into it raises
        ValueError; it does not change when the sim steps). Assign to set them:
        `sim.positions = x` (nv x 3 or 3 nv values)."""
        return readonly(self.get_state()[0])

    @positions.setter
    def positions(self, x: ArrayLike) -> None:
        self.set_state(positions=x)

    @property
    def velocities(self) -> np.ndarray:
        """Current velocities, nv x 3: a read-only copy (writing into it raises
        ValueError). Assign to set them: `sim.velocities = v`."""
        return readonly(self.get_state()[1])

    @velocities.setter
    def velocities(self, v: ArrayLike) -> None:
        self.set_state(velocities=v)

    def reset(self) -> None:
        """Back to the scene's initial state (t = 0)."""
        self._changed()
        check(lib.eo_sim_reset(self._live()))

    def fields(self) -> dict:
        """Per-tet fields of the current state: {"psi", "J", "inverted"} (nt each; new
        arrays owned by the caller)."""
        st = lib.eo_sim_step_problem(self._live())
        psi, J = np.empty(self.nt), np.empty(self.nt)
        inv = np.empty(self.nt, dtype=np.uint8)
        check(lib.eo_step_fields(st, ffi.from_buffer("double[]", psi), ffi.from_buffer("double[]", J),
                                 ffi.from_buffer("unsigned char[]", inv)))
        return {"psi": psi, "J": J, "inverted": inv.astype(bool)}

    # ---- solver
    def set_solver(self, overrides: Overrides) -> None:
        """Replace the solver: solver.* overrides on top of the defaults, e.g.
        {"solver.optimizer": "lbfgs", "solver.linesearch": "wolfe"}."""
        opts, cfgp = _solver_cfg(overrides)
        try:
            check(lib.eo_sim_set_solver(self._live(), opts, cfgp[0]))
        finally:
            lib.eo_cfg_destroy(cfgp)

    @property
    def on_iteration(self) -> Optional[IterCallback]:
        """fn(info: dict, x: ndarray) called after every solver iteration of step()
        (x: the iterate, a read-only copy); return True to stop that minimization
        (reason diverged_external). None: none. An exception raised by fn stops the
        step and is re-raised by step()."""
        return self._iter_fn

    @on_iteration.setter
    def on_iteration(self, fn: Optional[IterCallback]) -> None:
        s = self._live()
        if fn is None:
            lib.eo_sim_set_iter_callback(s, ffi.NULL, ffi.NULL)
            self._iter_cb = self._iter_fn = None
            return
        holder = self

        @ffi.callback("int(const eo_iter_info *, void *)")
        def cb(info, user):
            try:
                x = readonly(from_c(info.x, holder._cur_n)) if info.x != ffi.NULL else None
                return 1 if fn(iter_info_dict(info), x) else 0
            except BaseException as e:  # re-raised after the step returns
                set_pending(e)
                return 1

        lib.eo_sim_set_iter_callback(s, cb, ffi.NULL)
        self._iter_cb, self._iter_fn = cb, fn

    # ---- stepping
    def problem(self) -> StepProblem:
        """The next step's problem (StepProblem), valid until the sim steps, trials,
        resets or changes state."""
        o = ffi.new("eo_objective **")
        g = ffi.new("double **")
        check(lib.eo_sim_prepare(self._live(), o, g))
        return StepProblem(self, o[0], g[0])

    def step(self) -> StepResult:
        """One time step (StepResult). Not converging is a reason, not an exception;
        a library error raises ElastoptError with its message."""
        r = ffi.new("eo_sim_step_result *")
        if self._iter_cb is not None and not self.explicit:  # size of x in the callback
            o = ffi.new("eo_objective **")
            check(lib.eo_sim_prepare(self._live(), o, ffi.NULL))
            self._cur_n = o[0].n
        self._changed()
        check(lib.eo_sim_step(self._live(), r))
        return StepResult(r.iterations, reason_name(r.reason), r.reason > 0 and r.reason != REASONS["explicit"],
                          r.t, r.time, r.g,
                          r.grad_norm, {"value": r.n_value, "gradient": r.n_gradient,
                                        "hessian": r.n_hessian, "factor": r.n_factor},
                          _stats(r.stats), r.rejected, r.substeps, r.min_substep)

    def run(self, steps: Optional[int] = None) -> List[StepResult]:
        """`steps` steps (default: the scene's time.steps minus the steps done); stops
        after a step that became non-finite. Returns the list of StepResult."""
        if steps is None:
            steps = self.steps - self.index
        out = []
        for _ in range(int(steps)):
            r = self.step()
            out.append(r)
            if r.reason == "diverged_nonfinite":
                break
        return out

    def trial(self, x0: Optional[ArrayLike] = None,
              solver: Optional[Solver] = None) -> Tuple[np.ndarray, SolveResult]:
        """Solve the next step's problem from x0 (free coordinates; None = the guess)
        with `solver` (a Solver; None = the sim's) without advancing. Returns
        (x, SolveResult)."""
        s = self._live()
        o = ffi.new("eo_objective **")
        check(lib.eo_sim_prepare(s, o, ffi.NULL))
        n = o[0].n
        px = ffi.NULL
        if x0 is not None:
            a, px = as_c(x0, n, "x0")
        x = np.empty(n)
        res = ffi.new("eo_solve_result *")
        sv = ffi.NULL if solver is None else solver._p[0]
        self._changed()
        check(lib.eo_sim_trial(s, sv, px, ffi.from_buffer("double[]", x), ffi.NULL, ffi.NULL,
                               ffi.NULL, res))
        return x, _solve_result(res)
