"""cffi (ABI mode) declarations of the public C API and the loading of the libraries.

The declarations below copy the struct layouts of include/elastopt/*.h that Python reads
or writes (and only those; every other type is opaque). tests/py_abi.c prints the C
compiler's sizes and offsets of the same structs and tests/python/test_elastopt.py
compares them with cffi's, so a header change that is not made here fails a test.

Library search (first hit wins):
  1. $ELASTOPT_LIB (a path to libelastopt.so[.0])
  2. installed with the package (pip install, the wheel layout -Dpython_wheel=true):
     libelastopt.so beside this file, or in meson-python's site-packages/.elastopt.mesonpy.libs
  3. the build tree: $EO_BUILD_ROOT, then <source root>/build (meson puts the library at
     the top of the build folder; only when the package is run from python/ of a source tree)
  4. the system's library: ctypes.util.find_library("elastopt") (meson install)
The benchmark harness (not part of the C library) is $ELASTOPT_BENCH_LIB, else
libelastopt_bench.so beside the library found (installed package), else
bench/harness/libelastopt_bench.so of the build tree. The CLI (cli_path()) likewise:
$ELASTOPT_CLI, else the `elastopt` program beside the library, else cli/elastopt of the
build tree.
"""
from __future__ import annotations

import ctypes.util
import os
import shutil
from pathlib import Path
from typing import Any, Iterator

import cffi

ffi = cffi.FFI()

ffi.cdef(r"""
typedef struct eo_ctx eo_ctx;
typedef struct eo_cfg eo_cfg;
typedef struct eo_sim eo_sim;
typedef struct eo_scene eo_scene;
typedef struct eo_step eo_step;
typedef struct eo_solver eo_solver;
typedef struct eo_linsolve eo_linsolve;
typedef struct json_t json_t;
typedef struct eo_param_desc eo_param_desc;
typedef struct eo_hessfix_type eo_hessfix_type;
typedef struct eo_mesh eo_mesh;
typedef struct eo_bench_suite eo_bench_suite;
typedef struct eo_callback_optimizer eo_callback_optimizer;

/* ---- ctx.h, status.h */
typedef struct eo_errloc {
    const char *file; long line; long column; const char *kind; long index;
} eo_errloc;
typedef void (*eo_log_fn)(int level, const char *msg, void *user);
int eo_ctx_create(const void *alloc, eo_ctx **out);
void eo_ctx_destroy(eo_ctx **ctx);
void eo_ctx_set_logger(eo_ctx *ctx, eo_log_fn fn, void *user, int level);
const char *eo_ctx_message(const eo_ctx *ctx);
int eo_ctx_status(const eo_ctx *ctx);
void eo_ctx_clear_error(eo_ctx *ctx);
size_t eo_ctx_live_bytes(const eo_ctx *ctx);
int eo_error_at(eo_ctx *ctx, int status, eo_errloc loc, const char *fmt, ...);
const char *eo_status_string(int status);
const char *eo_status_name(int status);
const char *eo_reason_string(int reason);
const char *eo_reason_name(int reason);
double eo_wtime(void);

/* ---- sparse.h */
typedef struct eo_csc {
    int n; int nnz; int *colptr; int *rowind; double *val; eo_ctx *ctx;
} eo_csc;

/* ---- objective.h */
typedef struct eo_objective_ops {
    int (*value)(void *data, const double *x, double *g);
    int (*gradient)(void *data, const double *x, double *g, double *grad);
    int (*hessian)(void *data, const double *x, int proj, eo_csc **H);
    int (*metric_diag)(void *data, double *d);
    int (*inverted_count)(void *data, const double *x);
    int (*constant_hessian)(void *data, eo_csc **L, unsigned long *version);
    int (*n_elements)(void *data);
    int (*hessian_masked)(void *data, const double *x, const unsigned char *proj_of, eo_csc **H);
    int (*element_residual)(void *data, const double *v, double *r);
    int (*inertia)(void *data, void *out);
    int (*constant_factor)(void *data);
    int (*constant_solve)(void *data, const double *b, double *x);
    int (*rounding_scale)(void *data, const double *x, double *s);  /* s[3] */
    int (*max_step)(void *data, const double *x, const double *p, double *alpha_max);
    int (*characteristic)(void *data, void *out);
    int (*split_info)(void *data, void *out);
    int (*split_apply)(void *data, const double *x, double *F);
    int (*split_adjoint)(void *data, const double *S, double *out);
    int (*vertex_blocks)(void *data, void *out);
    int (*vertex_block)(void *data, const double *x, int b, int proj, double *e, double *g3, double *H3);
    int (*split_assemble)(void *data, const double *x, const double *K, double alpha, int proj, eo_csc **H);
} eo_objective_ops;
typedef struct eo_objective {
    int n; const eo_objective_ops *ops; void *data; long n_value, n_gradient, n_hessian;
    const void *space;
} eo_objective;

/* ---- registry.h */
typedef struct eo_method_info {
    const char *name; const char *summary; const eo_param_desc *params; size_t params_size;
    unsigned flags;
} eo_method_info;
const void *const *eo_registry_list(int kind);
const char *eo_kind_key(int kind);
int eo_registry_find(eo_ctx *ctx, int kind, const char *name, const void **out);

/* ---- solver.h */
typedef struct eo_iter_info {
    int iteration; double time; double g; double grad_norm; double decrement; double alpha;
    int ls_evals; double shift; double projected; int inverted; int reason; const double *x;
    double eta; int lin_iters; int neg_curvature; double cpu_time;
} eo_iter_info;
typedef int (*eo_iter_fn)(const eo_iter_info *info, void *user);
typedef struct eo_stop_info {
    int iteration; double g, g_prev; double grad_norm; double grad_norm0; double decrement;
    double decrement0; double decrement_prev; double step_norm; double x_norm; double tol;
    int measure; double g0; double grad_metric; double grad_metric0; double floor_dec; double floor_grad;
    double g_scale;
    double grad_char;
} eo_stop_info;
typedef struct eo_stop_type {
    eo_method_info info;
    int (*check)(const void *params, const eo_stop_info *si);
    int needs_direction;
} eo_stop_type;
typedef struct eo_ls_extra {
    double *grad_new; int have_grad; double c2; const double *g_hist; int n_hist; int grad_first;
} eo_ls_extra;
typedef struct eo_linesearch_type {
    eo_method_info info;
    int (*search)(const void *params, eo_objective *obj, const double *x, const double *p,
                  double g0, double dg0, double alpha0, double *xnew, double *gnew,
                  double *alpha, int *nevals, double *work, eo_ctx *ctx, eo_ls_extra *extra);
} eo_linesearch_type;
struct eo_optimizer_type;
struct eo_stop_state;
typedef struct eo_solver_ctx {
    eo_objective *obj; eo_ctx *ctx; eo_linsolve *linear;
    const eo_hessfix_type *hessfix; const void *hessfix_params; void *hessfix_state;
    const eo_linesearch_type *linesearch; const void *linesearch_params;
    const eo_stop_type *stop; const void *stop_params;
    double tol; int max_iters; double time_budget;
    eo_iter_fn on_iter; void *user;
    const struct eo_optimizer_type *optimizer;
    struct eo_stop_state *stop_state;
} eo_solver_ctx;
int eo_solver_stop_check(const eo_solver_ctx *sc, eo_stop_info *si, const double *x, const double *grad);
typedef struct eo_solve_result {
    int reason; int iterations; double g, grad_norm, decrement; double time;
    long n_value, n_gradient, n_hessian, n_factor; int status; long n_fallback;
    long n_shifted; double projected; long n_inner; long n_negcurv; long lin_iters;
    long n_neg_curvature; double t_assembly; double t_linesearch; double t_gradient;
    long n_assembly, n_ls_evals, n_gradient_outside; int decrement_estimated;
    long n_not_pd;
    double cpu_time; double c_assembly, c_linesearch, c_gradient;
} eo_solve_result;
typedef struct eo_solver_opts {
    char optimizer[32]; char hessian_fix[32]; char linesearch[32]; char stop[32];
    char linear[32]; double tol; int max_iters; double time_budget; char backend[16]; int carry_linear;
} eo_solver_opts;
int eo_solver_report(const eo_solver_ctx *sc, double t0, eo_iter_info *info);
void eo_solver_opts_default(eo_solver_opts *o);
int eo_solver_opts_load(eo_ctx *ctx, eo_cfg *cfg, eo_solver_opts *o);
int eo_solver_create(eo_ctx *ctx, const eo_solver_opts *opts, eo_cfg *cfg, eo_solver **out);
void eo_solver_destroy(eo_solver **s);
json_t *eo_solver_to_json(const eo_solver *s);

/* ---- callback.h */
typedef int (*eo_callback_minimize_fn)(void *user, const eo_solver_ctx *sc, double *x,
                                       eo_solve_result *res);
typedef int (*eo_callback_direction_fn)(void *user, const eo_solver_ctx *sc, const double *x,
                                        double g, const double *grad, double *p,
                                        double *alpha0, int *reason);
typedef struct eo_callback_optimizer_def {
    const char *name; const char *summary; int needs_hessian; int needs_linear;
    eo_callback_minimize_fn minimize; eo_callback_direction_fn direction; void *user;
    int newton_decrement;
} eo_callback_optimizer_def;
int eo_callback_optimizer_register(eo_ctx *ctx, const eo_callback_optimizer_def *def,
                                   eo_callback_optimizer **out);
void eo_callback_optimizer_destroy(eo_callback_optimizer **o);

/* ---- config.h, scene.h */
int eo_cfg_load(eo_ctx *ctx, const char *path, const char *builtin_text, eo_cfg **out);
int eo_cfg_create_empty(eo_ctx *ctx, eo_cfg **out);
void eo_cfg_destroy(eo_cfg **cfg);
int eo_cfg_override(eo_ctx *ctx, eo_cfg *cfg, const char *assignment);
int eo_scene_cfg_load(eo_ctx *ctx, const char *path, const char *name, eo_cfg **out);
json_t *eo_scene_to_json(const eo_scene *sc);

/* ---- step.h */
typedef struct eo_step_stats {
    double com[3]; double max_disp; double min_J; double max_J; int inverted;
    double kinetic; double elastic; double gravity;
    double contact; double potential; double work_prescribed; double total_energy;
} eo_step_stats;
const double *eo_step_x0(const eo_step *st);
const eo_mesh *eo_step_mesh(const eo_step *st);
int eo_step_free_to_full(const eo_step *st, int i);
const double *eo_step_vertex_mass(const eo_step *st);
int eo_step_stats_compute(eo_step *st, eo_step_stats *s);
int eo_step_fields(eo_step *st, double *psi, double *J, unsigned char *inverted);

/* ---- mesh.h: the leading members of eo_mesh only (read through a cast) */
typedef struct eo_mesh_head { int nv; int nt; double *X; int *tets; } eo_mesh_head;

/* ---- sim.h */
typedef struct eo_sim_step_result {
    int iterations; int reason; double t; double time; double g, grad_norm;
    long n_value, n_gradient, n_hessian, n_factor; eo_step_stats stats;
    int entry; int n_entries; int entry_reason[8]; int entry_iterations[8];
    int rejected; int substeps; double min_substep;
    long n_not_pd; double cpu_time;
} eo_sim_step_result;
int eo_sim_create(eo_ctx *ctx, eo_cfg *cfg, eo_sim **out);
int eo_sim_create_from(eo_ctx *ctx, const char *path, const char *builtin,
                       const char *const *overrides, eo_sim **out);
void eo_sim_destroy(eo_sim **s);
void eo_sim_set_iter_callback(eo_sim *s, eo_iter_fn fn, void *user);
int eo_sim_set_solver(eo_sim *s, const eo_solver_opts *opts, eo_cfg *solver_cfg);
int eo_sim_step(eo_sim *s, eo_sim_step_result *r);
int eo_sim_prepare(eo_sim *s, eo_objective **obj, double **guess);
int eo_sim_trial(eo_sim *s, eo_solver *solver, const double *x0, double *x, eo_iter_fn fn,
                 void *user, eo_objective **obj, eo_solve_result *res);
int eo_sim_reset(eo_sim *s);
void eo_sim_get_state(const eo_sim *s, double *x, double *v, double *t, int *index);
int eo_sim_set_state(eo_sim *s, const double *x, const double *v, double t, int index);
const eo_scene *eo_sim_scene(const eo_sim *s);
eo_step *eo_sim_step_problem(const eo_sim *s);
eo_solver *eo_sim_solver(const eo_sim *s);
double eo_sim_time(const eo_sim *s);
int eo_sim_index(const eo_sim *s);
int eo_sim_is_explicit(const eo_sim *s);

/* ---- plugin.h */
int eo_abi_version(void);
int eo_plugin_load(eo_ctx *ctx, const char *path);

/* ---- jansson and libc (resolved through libelastopt's dependencies) */
char *json_dumps(const json_t *json, size_t flags);
void json_delete(json_t *json);
void free(void *p);
""")

# ---- the benchmark harness (bench.h), a separate library
BENCH_CDEF = r"""
typedef struct eo_bench_progress {
    int scene, nscenes, config, nconfigs;
    const char *scene_name, *config_name, *phase;
    double elapsed, fraction, eta;
} eo_bench_progress;
typedef void (*eo_bench_progress_fn)(const eo_bench_progress *p, void *user);
typedef struct eo_bench_run_opts {
    const char *out_dir; int repeats; int plots; eo_bench_progress_fn progress; void *user;
    void (*profile)(const char *scene, const char *config, const void *p, void *user);
    void *profile_user; const char *clock; int (*owned_sum)(const double *local, double *out);
} eo_bench_run_opts;
typedef struct eo_bench_summary {
    int runs; int ref_failures; int nonfinite; int nan; int required_failures;
    int plots_made; double seconds;
} eo_bench_summary;
int eo_bench_suite_load(eo_ctx *ctx, const char *path, eo_bench_suite **out);
void eo_bench_suite_destroy(eo_bench_suite **s);
int eo_bench_suite_nscenes(const eo_bench_suite *s);
int eo_bench_suite_nconfigs(const eo_bench_suite *s);
const char *eo_bench_suite_scene_name(const eo_bench_suite *s, int i);
const char *eo_bench_suite_config_name(const eo_bench_suite *s, int i);
eo_bench_run_opts eo_bench_run_opts_default(void);
int eo_bench_run(eo_ctx *ctx, const eo_bench_suite *s, const eo_bench_run_opts *opts,
                 eo_bench_summary *sum);
"""
ffi.cdef(BENCH_CDEF)

# status codes and kinds used by the package (status.h, registry.h, proj.h)
EO_OK = 0
EO_ERR_INVALID = -4
EO_ERR_UNSUPPORTED = -12
EO_ERR_INTERNAL = -13
KINDS = ["material", "optimizer", "hessian_fix", "linesearch", "stop", "linear",
         "integrator", "scene", "element", "term"]
PROJ = {"none": 0, "clamp": 1, "abs": 2}
REASONS = {  # name -> value (status.h EO_REASON_LIST)
    "iterating": 0, "converged_decrement": 1, "converged_gradient": 2, "converged_step": 3,
    "converged_energy": 4, "converged_external": 5, "explicit": 6,
    "diverged_max_iters": -1, "diverged_linesearch": -2, "diverged_nonfinite": -3,
    "diverged_not_descent": -4, "diverged_linsolve": -5, "diverged_not_pd": -6,
    "diverged_time_budget": -7, "diverged_external": -8, "diverged_stagnated": -9,
    "diverged_not_contracting": -10,
}

PACKAGE_DIR = Path(__file__).resolve().parent
_SOURCE_ROOT = PACKAGE_DIR.parents[1]


def _candidates() -> Iterator[Path]:
    env = os.environ.get("ELASTOPT_LIB")
    if env:
        yield Path(env)
        return
    yield PACKAGE_DIR / "libelastopt.so"
    for name in ("libelastopt.so", "libelastopt.so.0"):
        yield PACKAGE_DIR.parent / ".elastopt.mesonpy.libs" / name
    roots = []
    if os.environ.get("EO_BUILD_ROOT"):
        roots.append(Path(os.environ["EO_BUILD_ROOT"]))
    if (_SOURCE_ROOT / "python" / "elastopt").resolve() == PACKAGE_DIR:
        roots.append(_SOURCE_ROOT / "build")
    for r in roots:
        for name in ("libelastopt.so.0", "libelastopt.so"):
            yield r / name
    found = ctypes.util.find_library("elastopt")
    if found:
        yield Path(found)


def _load() -> tuple[Any, Path]:
    tried = []
    for c in _candidates():
        tried.append(str(c))
        if c.is_absolute() and not c.exists():
            continue
        try:
            # RTLD_GLOBAL: the harness library (and plug-ins) bind to this very copy, so
            # they share its registries (an optimizer registered from Python is seen by
            # eo_bench_run).
            return ffi.dlopen(str(c), ffi.RTLD_NOW | ffi.RTLD_GLOBAL), Path(c)
        except OSError as e:
            tried[-1] += f" ({e})"
    raise ImportError("elastopt: libelastopt.so not found; install the package (pip install "
                      "--no-build-isolation <source root>, docs/python.md), build it (meson "
                      "setup build && ninja -C build) or set ELASTOPT_LIB. Tried: "
                      + "; ".join(tried))


lib, lib_path = _load()

_bench = None


def bench_lib() -> Any:
    """The harness library (loaded on first use)."""
    global _bench
    if _bench is not None:
        return _bench
    env = os.environ.get("ELASTOPT_BENCH_LIB")
    here = lib_path.resolve().parent
    cands = [Path(env)] if env else [here / "libelastopt_bench.so",
                                     here / "bench" / "harness" / "libelastopt_bench.so"]
    for c in cands:
        if c.exists():
            _bench = ffi.dlopen(str(c), ffi.RTLD_NOW | ffi.RTLD_GLOBAL)
            return _bench
    raise ImportError("elastopt: the benchmark harness libelastopt_bench.so was not found "
                      "(pip installs it with the package; meson install does not); set "
                      "ELASTOPT_BENCH_LIB. Tried: " + ", ".join(map(str, cands)))


def cli_path() -> Path:
    """The `elastopt` command matching the loaded library: $ELASTOPT_CLI, else the program
    installed beside the library (pip), else cli/elastopt of the build tree, else the
    `elastopt` on PATH when the library is a system one (meson install).
    FileNotFoundError if there is none."""
    env = os.environ.get("ELASTOPT_CLI")
    here = lib_path.resolve().parent
    cands = [Path(env)] if env else [here / "elastopt", here / "cli" / "elastopt"]
    if not env:
        on_path = shutil.which("elastopt")
        if on_path:   # a program, not the Python wrapper pip writes (which would loop)
            cands.append(Path(on_path))
    for c in cands:
        if c.is_file() and os.access(c, os.X_OK):
            if env:
                return c
            with open(c, "rb") as f:
                if f.read(4) == b"\x7fELF":
                    return c
    raise FileNotFoundError("elastopt: the elastopt program was not found beside "
                            f"{lib_path}; set ELASTOPT_CLI. Tried: " + ", ".join(map(str, cands)))


def string(p: Any) -> str:
    """C string to str ('' for NULL)."""
    return ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else ""
