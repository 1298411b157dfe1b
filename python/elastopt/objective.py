"""g, ∇g and the Hessian of an eo_objective (objective.h) at any x, as numpy / SciPy.

An Objective wraps a borrowed `eo_objective *`: the step problem of a Sim (Sim.problem(),
valid until the sim steps, trials, resets or changes state) or the problem handed to a
Python optimizer (valid during its call). Every call counts in the objective's
evaluation counters exactly like the C inline wrappers do.

Arrays: a method's result (gradient(), hessian(), metric()) is a new array owned by the
caller; arrays that describe the problem (StepProblem.guess, SolveProblem.grad0, the x and
grad handed to a direction function) are read-only copies (writing raises ValueError).
"""
from __future__ import annotations

from typing import Any, Tuple, Union

import numpy as np

from ._core import check
from ._ffi import PROJ, ffi

try:  # SciPy is optional: without it hessian() returns (indptr, indices, data)
    import scipy.sparse as _sp
except ImportError:  # pragma: no cover - exercised only without SciPy
    _sp = None


ArrayLike = Any   # anything np.asarray takes: ndarray, list, ...


def readonly(a: np.ndarray) -> np.ndarray:
    """a, made read-only (a copy the library will not see: writing raises ValueError)."""
    a.flags.writeable = False
    return a


def as_c(x: ArrayLike, n: int, what: str = "x") -> Tuple[np.ndarray, Any]:
    """A contiguous float64 copy-or-view of x with n entries and its C pointer."""
    a = np.ascontiguousarray(x, dtype=np.float64).reshape(-1)
    if a.size != n:
        raise ValueError(f"{what} has {a.size} entries, the problem has {n}")
    return a, ffi.from_buffer("double[]", a)


def from_c(ptr: Any, n: int, dtype: Any = np.float64) -> np.ndarray:
    """A numpy copy of n values at a C pointer."""
    if n == 0:
        return np.zeros(0, dtype=dtype)
    size = np.dtype(dtype).itemsize
    return np.frombuffer(ffi.buffer(ptr, n * size), dtype=dtype).copy()


def csc_arrays(H: Any) -> Tuple[int, np.ndarray, np.ndarray, np.ndarray]:
    """(n, colptr, rowind, val) copies of an eo_csc (upper triangle)."""
    n, nnz = H.n, H.nnz
    return (n, from_c(H.colptr, n + 1, np.int32), from_c(H.rowind, nnz, np.int32),
            from_c(H.val, nnz))


def symmetric_full(n: int, colptr: np.ndarray, rowind: np.ndarray,
                   val: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Both triangles of a symmetric matrix stored by its upper triangle (CSC):
    (indptr, indices, data) of the full matrix in CSC, rows sorted in each column."""
    cols = np.repeat(np.arange(n, dtype=np.int64), np.diff(colptr))
    rows = rowind.astype(np.int64)
    off = rows != cols
    r = np.concatenate([rows, cols[off]])
    c = np.concatenate([cols, rows[off]])
    v = np.concatenate([val, val[off]])
    order = np.lexsort((r, c))
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(c, minlength=n), out=indptr[1:])
    return indptr, r[order], v[order]


class Objective:
    """g(x) over `n` free coordinates (objective.h)."""

    def __init__(self, obj: Any, owner: Any = None) -> None:
        self._obj = obj
        self._owner = owner   # object whose lifetime bounds the borrowed pointer

    def _o(self) -> Any:
        if self._owner is not None:
            self._owner._check_alive(self)
        return self._obj

    @property
    def n(self) -> int:
        """Number of free coordinates."""
        return self._o().n

    def value(self, x: ArrayLike) -> float:
        """g(x) (+inf where undefined, e.g. an inverted element of a barrier material)."""
        o = self._o()
        a, p = as_c(x, o.n)
        g = ffi.new("double *")
        o.n_value += 1
        check(o.ops.value(o.data, p, g))
        return g[0]

    def gradient(self, x: ArrayLike) -> Tuple[float, np.ndarray]:
        """(g(x), ∇g(x)) as (float, ndarray of n); the gradient is a new array owned by
        the caller (writable; the library keeps no reference to it)."""
        o = self._o()
        a, p = as_c(x, o.n)
        g = ffi.new("double *")
        grad = np.empty(o.n)
        o.n_gradient += 1
        check(o.ops.gradient(o.data, p, g, ffi.from_buffer("double[]", grad)))
        return g[0], grad

    def hessian(self, x: ArrayLike, proj: str = "none",
                upper: bool = False) -> Union[Any, Tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """∇²g(x) assembled with the per-element projection `proj` ("none": the true
        Hessian, "clamp", "abs"). Returns a scipy.sparse.csc_matrix of the whole
        symmetric matrix (upper=True: its stored upper triangle only, diagonal included);
        without SciPy the tuple (indptr, indices, data) of the same CSC matrix."""
        o = self._o()
        if proj not in PROJ:
            raise ValueError(f"proj {proj!r}; valid: {', '.join(PROJ)}")
        a, p = as_c(x, o.n)
        H = ffi.new("eo_csc **")
        o.n_hessian += 1
        check(o.ops.hessian(o.data, p, PROJ[proj], H))
        n, colptr, rowind, val = csc_arrays(H[0])
        if upper:
            arrs = (colptr.astype(np.int64), rowind.astype(np.int64), val)
        else:
            arrs = symmetric_full(n, colptr, rowind, val)
        if _sp is None:
            return arrs
        indptr, indices, data = arrs
        return _sp.csc_matrix((data, indices, indptr), shape=(n, n))

    def metric(self) -> np.ndarray | None:
        """The objective's diagonal metric (lumped mass over the free coordinates for a
        step problem), or None if it has none."""
        o = self._o()
        if o.ops.metric_diag == ffi.NULL:
            return None
        d = np.empty(o.n)
        if o.ops.metric_diag(o.data, ffi.from_buffer("double[]", d)) < 0:
            return None
        return d

    def inverted_count(self, x: ArrayLike) -> int:
        """Inverted elements at x (-1 if the objective does not count them)."""
        o = self._o()
        if o.ops.inverted_count == ffi.NULL:
            return -1
        a, p = as_c(x, o.n)
        return o.ops.inverted_count(o.data, p)

    @property
    def counts(self) -> dict:
        """Evaluations so far: {"value", "gradient", "hessian"}."""
        o = self._o()
        return {"value": o.n_value, "gradient": o.n_gradient, "hessian": o.n_hessian}

