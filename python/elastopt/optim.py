"""Optimizers written in Python, registered under a name (callback.h).

Two forms, both valid afterwards as `solver.optimizer=<name>` in scenes, overrides and
bench suites (timed beside the built-in methods: the harness runs them in this process):

* minimize form, `register_optimizer(name, minimize=f)`: the whole minimization,
  ``f(problem, x0) -> (x, iterations, converged)`` (or ``(x, iterations, reason)`` with an
  eo_reason name). `problem` is a SolveProblem: value / gradient / hessian at any x, the
  configured stopping rule (`problem.stop(...)`) and line search
  (`problem.line_search(x, p)`), tolerance, iteration cap and time budget, and
  `problem.report(x, g, grad, ...)`, to be called after every accepted step:
  it records the iterate for logs and the benchmark's curves and returns True when the
  caller wants the run stopped (the benchmark stops at its target error, or the time
  budget ran out). The start x0 is reported by the package before f is called.
* direction form, `register_optimizer(name, direction=f)`: one iteration's search
  direction, ``f(problem, x, g, grad) -> p`` or ``(p, alpha0)``; the library's line-search
  loop (the one newton, gradient_descent and lbfgs share) does the rest: the configured
  line search from the first trial alpha0 (default 1), stopping rule with the decrement
  -alpha0·∇gᵀp/2, iteration cap, time budget, and the iteration records.

An exception raised by f stops the minimization with an error; the call that ran it
(Sim.step, bench, ...) re-raises that exception.
Arrays: the x and grad handed to a direction function and SolveProblem.grad0 are
read-only copies (writing raises ValueError); the x0 handed to a minimize function is a
writable copy owned by it.
"""
from __future__ import annotations

import math
from typing import Any, Callable, List, Optional, Tuple, Union

import numpy as np

from ._core import c_error, check, ctx, reason_name, set_pending
from ._ffi import EO_ERR_INVALID, REASONS, ffi, lib
from .objective import ArrayLike, Objective, as_c, from_c, readonly

#: minimize(problem, x0) -> (x, iterations, converged or reason name)
MinimizeFn = Callable[["SolveProblem", np.ndarray], Tuple[ArrayLike, int, Union[bool, str, None]]]
#: direction(problem, x, g, grad) -> p or (p, alpha0); None: no descent direction
DirectionFn = Callable[["SolveProblem", np.ndarray, float, np.ndarray], Any]

_registered = {}   # name -> _Registration (keeps the callbacks alive)


class SolveProblem(Objective):
    """The problem handed to a Python optimizer during one minimization (eo_solver_ctx):
    the objective (value, gradient, hessian, metric, inverted_count) plus the solver
    settings. Valid only during the call."""

    g0: float               #: g at the start point (minimize form)
    grad0: np.ndarray       #: ∇g at the start point (minimize form; read-only)

    def __init__(self, sc: Any, name: str) -> None:
        super().__init__(sc.obj, owner=self)
        self._sc = sc
        self._alive = True
        self.name = name
        self.tol = sc.tol                      # solver.tol
        self.max_iters = sc.max_iters          # solver.max_iters
        self.time_budget = sc.time_budget      # solver.time_budget (0 = none)
        self.stop_rule = string_or(sc.stop.info.name) if sc.stop != ffi.NULL else ""
        self._t0 = lib.eo_wtime()
        self._pending = None    # the iterate whose record is not yet emitted
        self._k = 0
        self._stopped = None    # (reason, record, emitted) when the run was stopped
        self._gn0 = math.nan
        self._dec0 = math.nan   # decrement of the first direction (relative_decrement)
        self._dec_prev = math.nan

    def _check_alive(self, _obj):
        if not self._alive:
            raise ValueError("elastopt: a SolveProblem is valid only during its minimize call")

    @property
    def elapsed(self) -> float:
        """Seconds since the start of this minimization."""
        return lib.eo_wtime() - self._t0

    def stop(self, g: float, grad_norm: float, decrement: float = math.nan, *,
             g_prev: float = math.nan, step_norm: float = math.nan, x_norm: float = math.nan,
             iteration: Optional[int] = None, x: Optional[ArrayLike] = None,
             grad: Optional[ArrayLike] = None) -> Optional[str]:
        """The configured stopping rule (solver.stop with solver.tol) at an iterate:
        the reason name if converged ("converged_decrement", ...), else None. A rule that
        needs the decrement (newton_decrement) says None while decrement is NaN. With the
        iterate x and its gradient grad the library's convergence measure applies (the
        rounding floor of the step's start, progress by the metric gradient norm unless
        the optimizer was registered with newton_decrement=True; eo_solver_stop_check);
        without them the rule sees the decrement only."""
        sc = self._sc
        it = self._k if iteration is None else iteration
        if math.isfinite(decrement) and (it == 0 or not math.isfinite(self._dec0)):
            self._dec0 = decrement
        si = ffi.new("eo_stop_info *", {
            "iteration": it, "g": g, "g_prev": g_prev,
            "grad_norm": grad_norm, "grad_norm0": self._gn0, "decrement": decrement,
            "decrement0": self._dec0, "decrement_prev": self._dec_prev,
            "step_norm": step_norm, "x_norm": x_norm, "tol": sc.tol})
        if x is not None and grad is not None:
            n = sc.obj.n
            _, px = as_c(x, n)
            _, pg = as_c(grad, n, "grad")
            r = lib.eo_solver_stop_check(sc, si, px, pg)
        else:
            r = sc.stop.check(sc.stop_params, si)
        self._dec_prev = decrement
        return reason_name(r) if r > 0 else None

    def line_search(self, x: ArrayLike, p: ArrayLike, g: Optional[float] = None,
                    grad: Optional[ArrayLike] = None, alpha0: float = 1.0, c2: float = 0.0
                    ) -> Tuple[np.ndarray, float, float, int, Optional[np.ndarray], bool]:
        """The configured line search (solver.linesearch) from x along the descent
        direction p, first trial alpha0: (x_new, g_new, alpha, evaluations, grad_new or
        None, ok). ok is False when no acceptable step was found (x_new is then the best
        point found, possibly x with alpha 0). g, grad: g(x) and ∇g(x) if known. c2: the
        curvature constant preferred from a Wolfe search (0 = its own)."""
        sc = self._sc
        n = sc.obj.n
        xa, px = as_c(x, n)
        pa, pp = as_c(p, n, "p")
        if g is None or grad is None:
            g, grad = self.gradient(xa)
        dg = float(np.dot(grad, pa))
        if not dg < 0:
            raise ValueError(f"line_search: p is not a descent direction (grad.p = {dg:g})")
        xnew, gnew_buf, work = np.empty(n), np.empty(n), np.empty(n)
        gnew, alpha, nev = ffi.new("double *"), ffi.new("double *"), ffi.new("int *")
        ex = ffi.new("eo_ls_extra *", {"grad_new": ffi.from_buffer("double[]", gnew_buf),
                                       "have_grad": 0, "c2": c2})
        rc = sc.linesearch.search(sc.linesearch_params, sc.obj, px, pp, g, dg, alpha0,
                                  ffi.from_buffer("double[]", xnew), gnew, alpha, nev,
                                  ffi.from_buffer("double[]", work), sc.ctx, ex)
        check(rc)
        ok = rc == 0 or gnew[0] < g
        return xnew, gnew[0], alpha[0], nev[0], (gnew_buf if ex.have_grad else None), ok

    def _record(self, rec, alpha, ls_evals, reason=0):
        x, g, gn, dec, inv = rec
        xa, px = as_c(x, self._sc.obj.n)
        info = ffi.new("eo_iter_info *", {
            "iteration": self._k, "g": g, "grad_norm": gn, "decrement": dec, "alpha": alpha,
            "ls_evals": ls_evals, "shift": 0.0, "projected": 0.0, "inverted": inv,
            "reason": reason, "x": px})
        return lib.eo_solver_report(self._sc, self._t0, info)

    def _begin(self, x0):
        g, grad = self.gradient(x0)
        gn = float(np.linalg.norm(grad)) if math.isfinite(g) else math.nan
        self._gn0 = gn
        self._dec0 = self._dec_prev = math.nan
        self.g0, self.grad0 = g, readonly(grad)
        self._pending = (np.array(x0, dtype=float), g, gn, math.nan, self.inverted_count(x0))

    def report(self, x: ArrayLike, g: Optional[float] = None, grad: Optional[ArrayLike] = None, *,
               decrement: float = math.nan, alpha: float = math.nan, ls_evals: int = 0) -> bool:
        """Record the step just accepted: x = the new iterate x_{k+1} with g(x) and ∇g(x)
        (evaluated here if not given), `decrement`, `alpha` and `ls_evals` describing the
        step from x_k (the benchmark's time of x_{k+1} is now). Returns True if the run
        must stop now (the caller's callback asked to, e.g. the benchmark's target error
        was reached, or solver.time_budget ran out); then return from minimize: the
        package returns the iterate at which it was stopped."""
        if self._stopped is not None:
            return True
        if g is None or grad is None:
            g, grad = self.gradient(x)
        gn = float(np.linalg.norm(grad)) if math.isfinite(g) else math.nan
        prev = self._pending
        prev = (prev[0], prev[1], prev[2], decrement, prev[4])
        if self._record(prev, alpha, ls_evals):
            self._stopped = ("diverged_external", prev, True)
            return True
        self._k += 1
        self._pending = (np.array(x, dtype=float).reshape(-1), g, gn, math.nan,
                         self.inverted_count(x))
        if self.time_budget > 0 and self.elapsed > self.time_budget:
            self._stopped = ("diverged_time_budget", self._pending, False)
            return True
        return False

    @property
    def iteration(self) -> int:
        """Index k of the last reported iterate (0 = the start point)."""
        return self._k


def string_or(p: Any) -> str:
    """C string to str ('' for NULL)."""
    return ffi.string(p).decode() if p != ffi.NULL else ""


def _reason_value(r):
    """A returned converged flag or reason -> eo_reason value (None: not converged)."""
    if r is None:
        return None
    if isinstance(r, bool):
        return REASONS["converged_external"] if r else None
    if isinstance(r, int):
        return r
    if r not in REASONS:
        raise ValueError(f"unknown reason {r!r}; valid: {', '.join(REASONS)}")
    return REASONS[r]


class _Registration:
    def __init__(self, name, minimize, direction, summary, needs_hessian, needs_linear, newton_decrement=False):
        self.name = name
        self.minimize = minimize
        self.direction = direction
        self._cb_min = ffi.callback("int(void *, const eo_solver_ctx *, double *, eo_solve_result *)",
                                    self._c_minimize) if minimize else ffi.NULL
        self._cb_dir = ffi.callback("int(void *, const eo_solver_ctx *, const double *, double, "
                                    "const double *, double *, double *, int *)",
                                    self._c_direction) if direction else ffi.NULL
        self._name_c = ffi.new("char[]", name.encode())
        self._summary_c = ffi.new("char[]", summary.encode())
        d = ffi.new("eo_callback_optimizer_def *", {
            "name": self._name_c, "summary": self._summary_c,
            "needs_hessian": int(bool(needs_hessian)), "needs_linear": int(bool(needs_linear)),
            "minimize": self._cb_min, "direction": self._cb_dir, "user": ffi.NULL,
            "newton_decrement": int(bool(newton_decrement))})
        self._p = ffi.new("eo_callback_optimizer **")
        check(lib.eo_callback_optimizer_register(ctx, d, self._p))

    def _fail(self, e, sc):
        set_pending(e)
        return c_error(EO_ERR_INVALID, f"python optimizer '{self.name}' raised "
                                       f"{type(e).__name__}: {e}", sc.ctx)

    def _c_minimize(self, user, sc, x, res):
        prob = SolveProblem(sc, self.name)
        n = sc.obj.n
        try:
            x0 = from_c(x, n)
            prob._begin(x0)
            out = self.minimize(prob, x0.copy())
            if not isinstance(out, tuple) or len(out) != 3:
                raise TypeError("minimize must return (x, iterations, converged_or_reason)")
            xr, iters, conv = out
            xr = np.ascontiguousarray(xr, dtype=np.float64).reshape(-1)
            if xr.size != n:
                raise ValueError(f"minimize returned {xr.size} values, the problem has {n}")
            reason = _reason_value(conv)
            if prob._stopped is None and not np.array_equal(prob._pending[0], xr):
                prob.report(xr)   # returned another point than the last reported one
            if prob._stopped is not None:   # the caller stopped it (or the time budget)
                rname, rec, emitted = prob._stopped
                reason = REASONS[rname]
            else:
                rec, emitted = prob._pending, False
                if reason is None:
                    reason = REASONS["diverged_max_iters"] if int(iters) >= prob.max_iters \
                        else REASONS["diverged_external"]
            if not emitted:
                prob._record(rec, math.nan, 0, reason)
            xr, g, gn = rec[0], rec[1], rec[2]
            xr = np.ascontiguousarray(xr, dtype=np.float64)
            ffi.memmove(x, ffi.from_buffer("double[]", xr), 8 * n)
            res.reason = reason
            res.iterations = int(iters)
            res.g = g
            res.grad_norm = gn
            return 0
        except BaseException as e:
            return self._fail(e, sc)
        finally:
            prob._alive = False

    def _c_direction(self, user, sc, x, g, grad, p, alpha0, reason):
        prob = SolveProblem(sc, self.name)
        n = sc.obj.n
        try:
            out = self.direction(prob, readonly(from_c(x, n)), g, readonly(from_c(grad, n)))
            a0 = 1.0
            if isinstance(out, tuple):
                out, a0 = out
            if out is None:
                reason[0] = REASONS["diverged_not_descent"]
                return 0
            pa = np.ascontiguousarray(out, dtype=np.float64).reshape(-1)
            if pa.size != n:
                raise ValueError(f"direction returned {pa.size} values, the problem has {n}")
            ffi.memmove(p, ffi.from_buffer("double[]", pa), 8 * n)
            alpha0[0] = float(a0)
            return 0
        except BaseException as e:
            return self._fail(e, sc)
        finally:
            prob._alive = False

    def close(self):
        if self._p[0] != ffi.NULL:
            lib.eo_callback_optimizer_destroy(self._p)


def register_optimizer(name: str, minimize: Optional[MinimizeFn] = None,
                       direction: Optional[DirectionFn] = None, *, summary: Optional[str] = None,
                       needs_hessian: bool = False, newton_decrement: bool = False) -> str:
    """Register a Python optimizer under `name` (see the module text). Exactly one of
    `minimize` and `direction`. `needs_hessian`: it evaluates Hessians (a bench matrix
    then makes one configuration per Hessian fix). `newton_decrement`: its directions are
    Newton directions, so the stopping rules measure progress by their decrement (else by
    the metric gradient norm, the same for every optimizer). Returns the name. ElastoptError if
    the name is taken or not a word of letters, digits, '_' and '-'."""
    if (minimize is None) == (direction is None):
        raise ValueError("register_optimizer: give exactly one of minimize and direction")
    fn = minimize or direction
    if summary is None:
        doc = (fn.__doc__ or "").strip().splitlines()
        summary = (doc[0] if doc else f"Python optimizer {getattr(fn, '__name__', name)}")
    summary = summary + " (Python)" if "python" not in summary.lower() else summary
    _registered[name] = _Registration(name, minimize, direction, summary, needs_hessian, False,
                                      newton_decrement)
    return name


def optimizer(name: str, *, form: str = "minimize", **kw: Any) -> Callable[[Callable], Callable]:
    """Decorator: @elastopt.optimizer("my_gd", form="direction") registers the function
    (form "minimize" or "direction"; keywords as register_optimizer's)."""
    if form not in ("minimize", "direction"):
        raise ValueError(f"form {form!r}; valid: minimize, direction")

    def deco(fn: Callable) -> Callable:
        register_optimizer(name, **{form: fn}, **kw)
        return fn
    return deco


def unregister_optimizer(name: str) -> None:
    """Remove a Python optimizer (no solver using it may be alive); KeyError if there is
    no Python optimizer of that name."""
    r = _registered.pop(name, None)
    if r is None:
        raise KeyError(f"no Python optimizer {name!r}")
    r.close()


def registered_optimizers() -> List[str]:
    """Names of the optimizers registered from Python (sorted)."""
    return sorted(_registered)
