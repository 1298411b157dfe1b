"""elastopt from Python: cffi (ABI mode) over the shared library libelastopt.so.

    import elastopt as eo
    sim = eo.Sim(scene="cantilever", overrides={"time.steps": 10})
    r = sim.step()                       # StepResult: iterations, reason, stats, ...
    x = sim.positions                    # nv x 3 read-only copy (assign to set)
    P = sim.problem()                    # the next step's objective
    g, grad = P.gradient(P.guess)        # g, ∇g at any x of the free coordinates
    H = P.hessian(P.guess)               # scipy.sparse.csc_matrix (both triangles)
    eo.register_optimizer("py_gd", direction=lambda prob, x, g, grad: -grad)
    sim.set_solver({"solver.optimizer": "py_gd"})
    res = eo.run_bench("bench/smoke.json", "out/bench")   # in-process: py_gd is timed too

Install: `pip install --no-build-isolation .` from the source root builds the library, the
benchmark harness and the CLI into the package (docs/python.md); `python -m elastopt
run|bench|list ...` then runs that CLI from anywhere. From the source tree instead,
PYTHONPATH=python finds the build tree's library (see _ffi.py for the search order:
$ELASTOPT_LIB, the package's own folder, $EO_BUILD_ROOT, ./build, the system's library).

Arrays handed out by the package are read-only copies (Sim.positions, velocities, ...;
writing raises ValueError) or new arrays owned by the caller (results such as
Objective.gradient); no array is a view of the library's memory. Errors from C raise
ElastoptError carrying the library's message (file, line, key). Not thread-safe (the
registries are process-wide).
"""
from ._core import (ElastoptError, abi_version, live_bytes, load_plugin, methods,
                    reason_name)
from ._ffi import cli_path, lib_path
from .bench import BenchResult, run_bench
from .objective import Objective
from .optim import (SolveProblem, optimizer, register_optimizer, registered_optimizers,
                    unregister_optimizer)
from .sim import Sim, Solver, SolveResult, StepProblem, StepResult
from .vtu import read_vtu

__all__ = ["ElastoptError", "Sim", "Solver", "StepProblem", "StepResult", "SolveResult",
           "Objective", "SolveProblem", "register_optimizer", "optimizer",
           "unregister_optimizer", "registered_optimizers", "run_bench", "BenchResult",
           "read_vtu", "methods", "load_plugin", "live_bytes", "abi_version", "reason_name",
           "lib_path", "cli_path"]
