/* The optimizer benchmark harness (bench.h): suite loading and the per-step protocol.
 *
 * For a scene with measured steps k = 0..S−1 (after `skip` reference-only steps):
 *
 *   reference   xₖ₊₁ = argmin gₖ by Newton + clamp + backtracking, stopped when the
 *               Newton decrement λ²/2 ≤ ref_tol·|gₖ(x₀)| (checked in the iteration
 *               callback, the solver's own tol set to 1e-300); the states (xₖ, vₖ, tₖ),
 *               x*ₖ, gₖ(x₀) and gₖ(x*ₖ) are stored.
 *   curves      for each configuration and step: the step object is set back to state
 *               k (eo_step_set_state), its objective and starting guess rebuilt, one
 *               warm-up run of at most `warmup_iters` iterations (it pays the first-call
 *               costs: symbolic analysis, workspaces), then `repeats` timed runs record
 *               time and g; the first also records the position error
 *               eₚ = ‖x − x*‖_M/‖x₀ − x*‖_M of every iterate (its own time excluded).
 *               Each run stops when eₑ = (g − g*)/|g₀ − g*| ≤ target.
 *   trajectory  each configuration with its own stopping rule from the scene's initial
 *               state over all skip + S steps (the whole benchmark scene), stopping at
 *               the first step its rule does not meet; distance per frame to the
 *               reference positions. A suite scene with time.adaptive = true (a scene
 *               key like any other, `set` in the suite) steps these runs adaptively
 *               (sim.h: a step that fails is retried in substeps, frames stay at n·dt);
 *               the reference and the fixed-budget runs always take nominal steps.
 *
 * Every step runs through eo_sim (sim.h), the library's one copy of the step protocol:
 * the reference and the trajectories with eo_sim_step (the sim's solver swapped with
 * eo_sim_set_solver), the measured steps with eo_sim_set_state + eo_sim_trial (the
 * next step's problem solved from one state, without advancing). A scene with an
 * explicit integrator has no step problem to minimize and is rejected at load.
 *
 * All recording buffers are sized before the runs; the callbacks do not allocate. One
 * curve solver per configuration exists at a time (created per scene; it re-sizes
 * itself when a release changes the number of free coordinates). */
#define _DEFAULT_SOURCE /* getloadavg */
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_impl.h"
#include "elastopt/io.h"
#include "elastopt/registry.h"
#include "elastopt/scene.h"
#include "elastopt/sim.h"
#include "elastopt/suggest.h"

#define SZ(T, f) sizeof(((T *)0)->f)

static const char *const select_choices[] = {"first", "largest_motion", "largest_correction", NULL};
static const char *const select_choices_scene[] = {"suite", "first", "largest_motion", "largest_correction", NULL};
static const char *const traj_choices[] = {"scene", "window", NULL};
static const char *const traj_choices_scene[] = {"suite", "scene", "window", NULL};
static const char *const clock_choices[] = {"cpu", "wall", NULL};

const eo_param_desc eo_bench_opts_desc[] = {
    {.key = "description", .kind = EO_PARAM_STRING, .offset = offsetof(eo_bench_opts, description),
     .size = SZ(eo_bench_opts, description), .def.s = "", .help = "free text describing the suite"},
    {.key = "repeats", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_opts, repeats), .def.i = 3, .min = 1,
     .max = BENCH_MAX_REPEATS, .range = EO_RANGE_CLOSED,
     .help = "timed repeats of every run (median reported; a warm-up run is excluded)"},
    {.key = "baseline", .kind = EO_PARAM_STRING, .offset = offsetof(eo_bench_opts, baseline),
     .size = SZ(eo_bench_opts, baseline), .def.s = "",
     .help = "configuration the ratios refer to (default: the first configuration)"},
    {.key = "target", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_bench_opts, target), .def.d = 1e-10,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "curve runs stop at relative energy error <= target"},
    {.key = "ref_tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_bench_opts, ref_tol), .def.d = 1e-14,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "reference Newton stops at lambda^2/2 <= ref_tol*|g(x0)|"},
    {.key = "ref_max_iters", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_opts, ref_max_iters), .def.i = 500,
     .min = 1, .range = EO_RANGE_MIN, .help = "iteration cap of the reference solves"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_opts, max_iters), .def.i = 10000,
     .min = 1, .max = 10000000, .range = EO_RANGE_CLOSED, .help = "iteration cap of the curve runs"},
    {.key = "time_budget", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_bench_opts, time_budget), .def.d = 10,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "seconds per minimization (curve and trajectory runs)"},
    {.key = "steps", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_opts, steps), .def.i = 2, .min = 1,
     .range = EO_RANGE_MIN, .help = "measured time steps per scene"},
    {.key = "skip", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_opts, skip), .def.i = 0, .min = 0,
     .range = EO_RANGE_MIN, .help = "reference-only time steps before the measured ones"},
    {.key = "select", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_bench_opts, select),
     .size = SZ(eo_bench_opts, select), .def.s = "first", .choices = select_choices,
     .help = "measured steps: first (the `steps` after `skip`), largest_motion (the `steps` consecutive reference "
             "steps among the `horizon` after `skip` with the largest total mass-weighted RMS motion), "
             "largest_correction (largest total distance from each step's starting guess to its minimizer: impacts)"},
    {.key = "horizon", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_opts, horizon), .def.i = 0, .min = 0,
     .range = EO_RANGE_MIN,
     .help = "reference steps after `skip` that select chooses from (0 = steps; select = first ignores it)"},
    {.key = "trajectory", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_bench_opts, trajectory), .def.i = 1,
     .help = "run every configuration over the scene (see trajectory_start) with its own "
             "stopping rule, up to the first step the rule does not meet"},
    {.key = "trajectory_start", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_bench_opts, trajectory_start),
     .size = SZ(eo_bench_opts, trajectory_start), .def.s = "scene", .choices = traj_choices,
     .help = "where trajectory runs start: scene (its initial state) or window (the reference state before the "
             "first measured step); they end after the last measured step"},
    {.key = "warmup_iters", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_opts, warmup_iters), .def.i = 3,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "iterations of the untimed warm-up run before the timed repeats (0 = no warm-up)"},
    {.key = "ipopt_check", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_bench_opts, ipopt_check), .def.i = 1,
     .help = "solve every measured step once more with Ipopt (exact clamped Hessian) as a second reference and "
             "report its differences to x* (skipped without Ipopt)"},
    {.key = "curve_rows", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_opts, curve_rows), .def.i = 200,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "curves.csv keeps every iteration up to this one, then 50 per decade (0 = all)"},
    {.key = "plots", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_bench_opts, plots), .def.i = 1,
     .help = "make PNG plots with gnuplot (skipped with a note if gnuplot is missing)"},
    {.key = "clock", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_bench_opts, clock),
     .size = SZ(eo_bench_opts, clock), .def.s = "cpu", .choices = clock_choices,
     .help = "what times, ratios and time budgets measure: cpu (CPU seconds of the solving thread, "
             "CLOCK_THREAD_CPUTIME_ID: stable on a shared machine) or wall (elapsed seconds); both are recorded"},
    {0},
};

const eo_param_desc eo_bench_scene_desc[] = {
    {.key = "name", .kind = EO_PARAM_STRING, .offset = offsetof(eo_bench_scene_opts, name),
     .size = SZ(eo_bench_scene_opts, name), .def.s = "", .help = "scene name in the outputs (required)"},
    {.key = "scene", .kind = EO_PARAM_STRING, .offset = offsetof(eo_bench_scene_opts, scene),
     .size = SZ(eo_bench_scene_opts, scene), .def.s = "", .help = "built-in scene (elastopt list)"},
    {.key = "file", .kind = EO_PARAM_STRING, .offset = offsetof(eo_bench_scene_opts, file),
     .size = SZ(eo_bench_scene_opts, file), .def.s = "", .help = "scene config file, relative to the suite"},
    {.key = "steps", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_scene_opts, steps), .def.i = -1,
     .help = "measured steps (-1 = the suite's)"},
    {.key = "skip", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_scene_opts, skip), .def.i = -1,
     .help = "reference-only steps first (-1 = the suite's)"},
    {.key = "time_budget", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_bench_scene_opts, time_budget),
     .def.d = -1, .help = "seconds per minimization (-1 = the suite's)"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_scene_opts, max_iters), .def.i = -1,
     .help = "iteration cap of the curve runs (-1 = the suite's)"},
    {.key = "repeats", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_scene_opts, repeats), .def.i = -1,
     .max = BENCH_MAX_REPEATS, .range = EO_RANGE_MAX, .help = "timed repeats of every run on this scene (-1 = the suite's)"},
    {.key = "select", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_bench_scene_opts, select),
     .size = SZ(eo_bench_scene_opts, select), .def.s = "suite", .choices = select_choices_scene,
     .help = "measured steps (suite = the suite's select)"},
    {.key = "horizon", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_scene_opts, horizon), .def.i = -1,
     .help = "reference steps after skip to select from (-1 = the suite's)"},
    {.key = "trajectory_start", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_bench_scene_opts, trajectory_start),
     .size = SZ(eo_bench_scene_opts, trajectory_start), .def.s = "suite", .choices = traj_choices_scene,
     .help = "where trajectory runs start (suite = the suite's trajectory_start)"},
    {.key = "optional", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_bench_scene_opts, optional), .def.i = 0,
     .help = "drop the scene at load, with a note, if a file it names cannot be read (e.g. the shared meshes are "
             "absent)"},
    {.key = "stratum", .kind = EO_PARAM_STRING, .offset = offsetof(eo_bench_scene_opts, stratum),
     .size = SZ(eo_bench_scene_opts, stratum), .def.s = "",
     .help = "group of the scene in the performance and data profiles (one profile per stratum besides the one over "
             "every scene; default none)"},
    {0},
};

/* ================================================================ pieces */

/* A step function: the time of the first iterate that meets the threshold. No time
 * between two iterates is ever reported: an iterate exists only once the iteration that
 * produced it has ended (its line search included), so a threshold met by the first
 * iterate after x0 costs the whole first iteration. */
double eo_bench_time_to(int n, const double *t, const double *err, double thr)
{
    for (int k = 0; k < n; k++)
        if (err[k] <= thr) return t[k];
    return INFINITY;
}

double eo_bench_error_at(int n, const double *t, const double *err, double budget)
{
    if (n <= 0) return NAN;
    double e = err[0];
    for (int k = 0; k < n && t[k] <= budget; k++) e = err[k];
    return e;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double eo_bench_median(int n, const double *v, double *vmin, double *vmax)
{
    double w[64];
    int m = 0;
    for (int i = 0; i < n && m < 64; i++)
        if (!isnan(v[i])) w[m++] = v[i];
    if (vmin) *vmin = NAN;
    if (vmax) *vmax = NAN;
    if (!m) return NAN;
    qsort(w, (size_t)m, sizeof w[0], cmp_double);
    if (vmin) *vmin = w[0];
    if (vmax) *vmax = w[m - 1];
    if (m % 2) return w[m / 2];
    double a = w[m / 2 - 1], b = w[m / 2];
    if (isinf(a) || isinf(b)) return b;
    return 0.5 * (a + b);
}

/* ================================================================ suite loading */

static int suite_err(eo_ctx *ctx, eo_cfg *cfg, const char *path, int status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;
static int suite_err(eo_ctx *ctx, eo_cfg *cfg, const char *path, int status, const char *fmt, ...)
{
    char text[900];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    eo_param_src src = eo_cfg_src(cfg, path);
    eo_errloc loc = EO_ERRLOC_NONE;
    loc.file = src.file;
    if (src.text) eo_json_locate(src.text, path, &loc.line, &loc.column);
    return eo_error_at(ctx, status, loc, "key '%s': %s", path, text);
}

/* Re-issue the context's error with a prefix naming the suite item. */
static int wrap_err(eo_ctx *ctx, int rc, const char *file, const char *what, const char *name)
{
    char msg[1200];
    snprintf(msg, sizeof msg, "%s", eo_ctx_message(ctx));
    return eo_error(ctx, rc, "%s: %s '%s': %s", file, what, name, msg);
}

static void free_set(eo_ctx *ctx, char **set, int n)
{
    for (int i = 0; i < n; i++) eo_free(ctx, set[i]);
    eo_free(ctx, set);
}

/* Append the members of a "set" object as "key=<json>" strings. */
static int set_append(eo_ctx *ctx, eo_cfg *cfg, const char *path, const json_t *obj, char ***set, int *n)
{
    if (!obj) return EO_OK;
    if (!json_is_object(obj))
        return suite_err(ctx, cfg, path, EO_ERR_TYPE, "expected an object {\"key\": value, ...}, got %s",
                         eo_json_type_name(obj));
    size_t add = json_object_size(obj);
    char **s = eo_realloc(ctx, *set, (size_t)(*n + (int)add + 1) * sizeof(char *));
    if (!s) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    *set = s;
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)obj, key, v) {
        char *text = json_dumps(v, JSON_ENCODE_ANY | JSON_COMPACT | JSON_REAL_PRECISION(17));
        if (!text) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        size_t len = strlen(key) + strlen(text) + 2;
        char *a = eo_malloc(ctx, len);
        if (!a) {
            free(text);
            return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        }
        snprintf(a, len, "%s=%s", key, text);
        free(text);
        s[(*n)++] = a;
    }
    return EO_OK;
}

static int copy_set(eo_ctx *ctx, char **src, int n, char ***dst, int *nd)
{
    *dst = NULL;
    *nd = 0;
    if (!n) return EO_OK;
    *dst = eo_calloc(ctx, (size_t)n + 1, sizeof(char *));
    if (!*dst) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    for (int i = 0; i < n; i++) {
        (*dst)[i] = eo_strdup(ctx, src[i]);
        if (!(*dst)[i]) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        (*nd)++;
    }
    return EO_OK;
}

static int apply_set(eo_ctx *ctx, eo_cfg *cfg, char **set, int n)
{
    for (int i = 0; i < n; i++) {
        int rc = eo_cfg_override(ctx, cfg, set[i]);
        if (rc < 0) return rc;
    }
    return EO_OK;
}

/* Scene config of a suite scene: file or built-in, plus its overrides. */
static int scene_cfg(eo_ctx *ctx, const bench_scene *b, eo_cfg **cfg)
{
    int rc = eo_scene_cfg_load(ctx, b->file[0] ? b->file : NULL, b->o.scene[0] ? b->o.scene : NULL, cfg);
    if (rc < 0) return rc;
    return apply_set(ctx, *cfg, b->set, b->nset);
}

/* Load a suite scene (configuration solver section ignored: the suite's configurations
 * define the solver). */
static int scene_open(eo_ctx *ctx, const bench_scene *b, eo_cfg **cfg, eo_scene **sc)
{
    *sc = NULL;
    int rc = scene_cfg(ctx, b, cfg);
    if (rc >= 0) rc = eo_scene_load(ctx, *cfg, sc);
    if (rc >= 0) {
        eo_cfg_consume(*cfg, "solver");
        rc = eo_cfg_finish(ctx, *cfg);
    }
    return rc;
}

/* Solver options and config document of a configuration, with the harness' settings. */
static int config_cfg(eo_ctx *ctx, const bench_config *c, eo_cfg **cfg, eo_solver_opts *so)
{
    int rc = eo_cfg_create_empty(ctx, cfg);
    if (rc < 0) return rc;
    rc = apply_set(ctx, *cfg, c->set, c->nset);
    if (rc < 0) return rc;
    eo_solver_opts_default(so);
    return eo_solver_opts_load(ctx, *cfg, so);
}

static int add_scene(eo_ctx *ctx, eo_bench_suite *s, const bench_scene *b)
{
    if (s->nsc == s->capsc) {
        int cap = s->capsc ? 2 * s->capsc : 16;
        bench_scene *p = eo_realloc(ctx, s->sc, (size_t)cap * sizeof *p);
        if (!p) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        s->sc = p;
        s->capsc = cap;
    }
    s->sc[s->nsc++] = *b;
    return EO_OK;
}

static int add_config(eo_ctx *ctx, eo_bench_suite *s, const char *name, char **set, int nset)
{
    if (s->ncf == s->capcf) {
        int cap = s->capcf ? 2 * s->capcf : 32;
        bench_config *p = eo_realloc(ctx, s->cf, (size_t)cap * sizeof *p);
        if (!p) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        s->cf = p;
        s->capcf = cap;
    }
    bench_config *c = s->cf + s->ncf;
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "%s", name);
    s->ncf++;
    return copy_set(ctx, set, nset, &c->set, &c->nset);
}

/* A list of positive numbers at `key`. */
static int number_list(eo_ctx *ctx, eo_cfg *cfg, const char *key, double *out, int *n)
{
    json_t *v = eo_cfg_get(cfg, key);
    if (!v) return EO_OK;
    if (!json_is_array(v) || json_array_size(v) < 1 || json_array_size(v) > BENCH_MAX_LIST)
        return suite_err(ctx, cfg, key, EO_ERR_TYPE, "expected a list of 1 to %d positive numbers, got %s", BENCH_MAX_LIST,
                         eo_json_describe(v, (char[32]){0}, 32));
    *n = 0;
    size_t i;
    json_t *e;
    json_array_foreach(v, i, e) {
        double d = json_number_value(e);
        if (!json_is_number(e) || !(d > 0) || !isfinite(d))
            return suite_err(ctx, cfg, key, EO_ERR_RANGE, "item %zu is not a positive number", i);
        out[(*n)++] = d;
    }
    return EO_OK;
}

/* A list of positive integers at `key` (iteration budgets). */
static int int_list(eo_ctx *ctx, eo_cfg *cfg, const char *key, int *out, int *n)
{
    json_t *v = eo_cfg_get(cfg, key);
    if (!v) return EO_OK;
    if (!json_is_array(v) || json_array_size(v) > BENCH_MAX_LIST)
        return suite_err(ctx, cfg, key, EO_ERR_TYPE, "expected a list of at most %d positive integers, got %s",
                         BENCH_MAX_LIST, eo_json_describe(v, (char[32]){0}, 32));
    *n = 0;
    size_t i;
    json_t *e;
    json_array_foreach(v, i, e) {
        if (!json_is_integer(e) || json_integer_value(e) < 1 || json_integer_value(e) > 1000000)
            return suite_err(ctx, cfg, key, EO_ERR_RANGE, "item %zu is not an integer in [1, 1000000]", i);
        out[(*n)++] = (int)json_integer_value(e);
    }
    return EO_OK;
}

/* Expand one `scenes` entry (with its `vary` product). */
static int load_scene_entry(eo_ctx *ctx, eo_bench_suite *s, eo_cfg *cfg, int idx)
{
    static const char *const extra[] = {"set", "vary", "iter_budgets", NULL};
    char path[64], sub[96];
    snprintf(path, sizeof path, "scenes.%d", idx);
    bench_scene b;
    memset(&b, 0, sizeof b);
    eo_params_default(eo_bench_scene_desc, &b.o);
    int rc = eo_cfg_section(ctx, cfg, path, eo_bench_scene_desc, &b.o, extra);
    if (rc < 0) return rc;
    if (!json_is_object(eo_cfg_get(cfg, path)))
        return suite_err(ctx, cfg, path, EO_ERR_TYPE, "expected an object");
    if (!b.o.name[0]) return suite_err(ctx, cfg, path, EO_ERR_INVALID, "a scene needs a \"name\"");
    if (!b.o.scene[0] == !b.o.file[0])
        return suite_err(ctx, cfg, path, EO_ERR_INVALID, "give exactly one of \"scene\" (built-in) or \"file\"");
    if (b.o.file[0]) {
        if (b.o.file[0] != '/' && s->dir[0]) snprintf(b.file, sizeof b.file, "%s/%s", s->dir, b.o.file);
        else snprintf(b.file, sizeof b.file, "%s", b.o.file);
    }
    b.steps = b.o.steps >= 1 ? b.o.steps : s->o.steps;
    b.skip = b.o.skip >= 0 ? b.o.skip : s->o.skip;
    b.max_iters = b.o.max_iters >= 1 ? b.o.max_iters : s->o.max_iters;
    b.time_budget = b.o.time_budget > 0 ? b.o.time_budget : s->o.time_budget;
    b.repeats = b.o.repeats >= 1 ? b.o.repeats : s->o.repeats;
    const char *sel = strcmp(b.o.select, "suite") ? b.o.select : s->o.select;
    b.select = !strcmp(sel, "largest_motion") ? BENCH_SELECT_MOTION
               : !strcmp(sel, "largest_correction") ? BENCH_SELECT_CORRECTION
                                                     : BENCH_SELECT_FIRST;
    b.horizon = b.o.horizon >= 0 ? b.o.horizon : s->o.horizon;
    if (b.select == BENCH_SELECT_FIRST || b.horizon < b.steps) {
        if (b.select != BENCH_SELECT_FIRST && b.horizon > 0) {
            snprintf(sub, sizeof sub, "%s.horizon", path);
            return suite_err(ctx, cfg, b.o.horizon >= 0 ? sub : "horizon", EO_ERR_RANGE,
                             "horizon %d is below the %d measured steps it must hold", b.horizon, b.steps);
        }
        b.horizon = b.steps;
    }
    b.traj_window = !strcmp(strcmp(b.o.trajectory_start, "suite") ? b.o.trajectory_start : s->o.trajectory_start,
                            "window");
    /* the scene's iter_budgets: a subset of the suite's (default: all of them) */
    for (int j = 0; j < s->nibud; j++) b.ibud_on[j] = 1;
    b.nibud_on = s->nibud;
    snprintf(sub, sizeof sub, "%s.iter_budgets", path);
    if (eo_cfg_get(cfg, sub)) {
        int own[BENCH_MAX_LIST], nown = 0;
        if ((rc = int_list(ctx, cfg, sub, own, &nown)) < 0) return rc;
        b.nibud_on = 0;
        for (int j = 0; j < s->nibud; j++) {
            b.ibud_on[j] = 0;
            for (int q = 0; q < nown; q++) b.ibud_on[j] |= own[q] == s->ibud[j];
            b.nibud_on += b.ibud_on[j];
        }
        for (int q = 0; q < nown; q++) {
            int in = 0;
            for (int j = 0; j < s->nibud; j++) in |= own[q] == s->ibud[j];
            if (!in) return suite_err(ctx, cfg, sub, EO_ERR_RANGE, "%d is not in the suite's iter_budgets", own[q]);
        }
    }
    snprintf(sub, sizeof sub, "%s.set", path);
    char **base = NULL;
    int nbase = 0;
    rc = set_append(ctx, cfg, sub, eo_cfg_get(cfg, sub), &base, &nbase);
    if (rc < 0) goto done;
    snprintf(sub, sizeof sub, "%s.vary", path);
    json_t *vary = eo_cfg_get(cfg, sub);
    int nvary = 0, count[8], pick[8];
    json_t *axes[8];
    if (vary) {
        if (!json_is_array(vary) || json_array_size(vary) > 8) {
            rc = suite_err(ctx, cfg, sub, EO_ERR_TYPE, "expected a list of at most 8 objects {\"label\": {set}, ...}");
            goto done;
        }
        nvary = (int)json_array_size(vary);
        for (int a = 0; a < nvary; a++) {
            axes[a] = json_array_get(vary, (size_t)a);
            if (!json_is_object(axes[a]) || !json_object_size(axes[a])) {
                rc = suite_err(ctx, cfg, sub, EO_ERR_TYPE, "item %d: expected a non-empty object {\"label\": {set}}", a);
                goto done;
            }
            count[a] = (int)json_object_size(axes[a]);
            pick[a] = 0;
        }
    }
    for (;;) {
        bench_scene e = b;
        e.set = NULL;
        e.nset = 0;
        rc = copy_set(ctx, base, nbase, &e.set, &e.nset);
        snprintf(e.name, sizeof e.name, "%s", b.o.name);
        size_t ln = strlen(e.name);
        for (int a = 0; a < nvary && rc >= 0; a++) {
            /* the pick[a]-th member of axis a (insertion order) */
            const char *key;
            json_t *v;
            int j = 0;
            json_object_foreach(axes[a], key, v) {
                if (j++ != pick[a]) continue;
                snprintf(e.name + ln, sizeof e.name - ln, "-%s", key);
                ln = strlen(e.name);
                char vp[200];
                snprintf(vp, sizeof vp, "%s.%d.%s", sub, a, key);
                rc = set_append(ctx, cfg, vp, v, &e.set, &e.nset);
                break;
            }
        }
        if (rc >= 0) rc = add_scene(ctx, s, &e);
        if (rc < 0) {
            free_set(ctx, e.set, e.nset);
            goto done;
        }
        /* next combination */
        int a = nvary - 1;
        while (a >= 0 && ++pick[a] == count[a]) pick[a--] = 0;
        if (a < 0) break;
    }
done:
    free_set(ctx, base, nbase);
    return rc;
}

static int load_config_entry(eo_ctx *ctx, eo_bench_suite *s, eo_cfg *cfg, int idx)
{
    char path[64], sub[96];
    snprintf(path, sizeof path, "configs.%d", idx);
    json_t *item = eo_cfg_get(cfg, path);
    if (!json_is_object(item)) return suite_err(ctx, cfg, path, EO_ERR_TYPE, "expected an object {\"name\", \"set\"}");
    const char *key;
    json_t *v;
    json_object_foreach(item, key, v) {
        if (strcmp(key, "name") && strcmp(key, "set")) {
            snprintf(sub, sizeof sub, "%s.%s", path, key);
            char prefix[72], hint[200];
            snprintf(prefix, sizeof prefix, "%s.", path);
            eo_suggest_hint(key, "name, set", prefix, hint, sizeof hint);
            return suite_err(ctx, cfg, sub, EO_ERR_UNKNOWN_KEY, "unknown key%s; valid keys here: name, set", hint);
        }
    }
    json_t *name = json_object_get(item, "name");
    if (!json_is_string(name) || !json_string_length(name))
        return suite_err(ctx, cfg, path, EO_ERR_INVALID, "a configuration needs a \"name\" string");
    char **set = NULL;
    int nset = 0;
    snprintf(sub, sizeof sub, "%s.set", path);
    int rc = set_append(ctx, cfg, sub, json_object_get(item, "set"), &set, &nset);
    if (rc >= 0) rc = add_config(ctx, s, json_string_value(name), set, nset);
    free_set(ctx, set, nset);
    return rc;
}

/* Names of a `matrix` axis: a list of strings (or absent: one empty entry). */
static int axis_names(eo_ctx *ctx, eo_cfg *cfg, const char *path, const json_t *v, const char **out, int *n)
{
    *n = 0;
    if (!v) {
        out[(*n)++] = "";
        return EO_OK;
    }
    if (!json_is_array(v) || !json_array_size(v) || json_array_size(v) > 16)
        return suite_err(ctx, cfg, path, EO_ERR_TYPE, "expected a list of 1 to 16 names");
    size_t i;
    json_t *e;
    json_array_foreach(v, i, e) {
        if (!json_is_string(e)) return suite_err(ctx, cfg, path, EO_ERR_TYPE, "item %zu is not a name", i);
        out[(*n)++] = json_string_value(e);
    }
    return EO_OK;
}

static int load_matrix_entry(eo_ctx *ctx, eo_bench_suite *s, eo_cfg *cfg, int idx)
{
    static const char *const keys[] = {"optimizer", "hessian_fix", "linesearch", "set", NULL};
    char path[64], sub[96];
    snprintf(path, sizeof path, "matrix.%d", idx);
    json_t *item = eo_cfg_get(cfg, path);
    if (!json_is_object(item))
        return suite_err(ctx, cfg, path, EO_ERR_TYPE, "expected an object {optimizer, hessian_fix, linesearch, set}");
    const char *key;
    json_t *v;
    json_object_foreach(item, key, v) {
        int ok = 0;
        for (const char *const *k = keys; *k; k++) ok |= strcmp(*k, key) == 0;
        if (!ok) {
            snprintf(sub, sizeof sub, "%s.%s", path, key);
            char prefix[72], hint[200];
            snprintf(prefix, sizeof prefix, "%s.", path);
            eo_suggest_hint(key, "optimizer, hessian_fix, linesearch, set", prefix, hint, sizeof hint);
            return suite_err(ctx, cfg, sub, EO_ERR_UNKNOWN_KEY,
                             "unknown key%s; valid keys here: optimizer, hessian_fix, linesearch, set", hint);
        }
    }
    const char *opt[16], *fix[16], *ls[16];
    int nopt, nfix, nls, rc;
    snprintf(sub, sizeof sub, "%s.optimizer", path);
    if ((rc = axis_names(ctx, cfg, sub, json_object_get(item, "optimizer"), opt, &nopt)) < 0) return rc;
    snprintf(sub, sizeof sub, "%s.hessian_fix", path);
    if ((rc = axis_names(ctx, cfg, sub, json_object_get(item, "hessian_fix"), fix, &nfix)) < 0) return rc;
    snprintf(sub, sizeof sub, "%s.linesearch", path);
    if ((rc = axis_names(ctx, cfg, sub, json_object_get(item, "linesearch"), ls, &nls)) < 0) return rc;
    char **common = NULL;
    int ncommon = 0;
    snprintf(sub, sizeof sub, "%s.set", path);
    rc = set_append(ctx, cfg, sub, json_object_get(item, "set"), &common, &ncommon);
    for (int a = 0; a < nopt && rc >= 0; a++) {
        const eo_optimizer_type *ot = NULL;
        if (opt[a][0]) {
            rc = eo_registry_find(ctx, EO_KIND_OPTIMIZER, opt[a], (const void **)&ot);
            if (rc < 0) {
                snprintf(sub, sizeof sub, "%s.optimizer", path);
                char msg[600];
                snprintf(msg, sizeof msg, "%s", eo_ctx_message(ctx));
                rc = suite_err(ctx, cfg, sub, rc, "%s", msg);
                break;
            }
        }
        /* the Hessian fix only matters for optimizers that use the Hessian */
        int use_fix = ot ? ot->needs_hessian : 1;
        for (int b = 0; b < (use_fix ? nfix : 1) && rc >= 0; b++)
            for (int c = 0; c < nls && rc >= 0; c++) {
                char name[128] = "";
                size_t k = 0;
                const char *parts[3] = {opt[a], use_fix ? fix[b] : "", ls[c]};
                for (int q = 0; q < 3; q++)
                    if (parts[q][0]) k += (size_t)snprintf(name + k, sizeof name - k, "%s%s", k ? "-" : "", parts[q]);
                char **set = NULL;
                int nset = 0;
                rc = copy_set(ctx, common, ncommon, &set, &nset);
                char *extra[3] = {NULL, NULL, NULL};
                const char *keys3[3] = {"solver.optimizer", "solver.hessian_fix", "solver.linesearch"};
                int nextra = 0;
                for (int q = 0; q < 3 && rc >= 0; q++) {
                    if (!parts[q][0]) continue;
                    size_t len = strlen(keys3[q]) + strlen(parts[q]) + 4;
                    extra[nextra] = eo_malloc(ctx, len);
                    if (!extra[nextra]) {
                        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
                        break;
                    }
                    snprintf(extra[nextra], len, "%s=\"%s\"", keys3[q], parts[q]);
                    nextra++;
                }
                if (rc >= 0) {
                    char **all = eo_realloc(ctx, set, (size_t)(nset + nextra + 1) * sizeof(char *));
                    if (!all) rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
                    else {
                        set = all;
                        for (int q = 0; q < nextra; q++) {
                            set[nset++] = extra[q];
                            extra[q] = NULL;
                        }
                    }
                }
                for (int q = 0; q < 3; q++) eo_free(ctx, extra[q]);
                if (rc >= 0) rc = add_config(ctx, s, name, set, nset);
                free_set(ctx, set, nset);
            }
    }
    free_set(ctx, common, ncommon);
    return rc;
}

static int find_config(const eo_bench_suite *s, const char *name)
{
    for (int i = 0; i < s->ncf; i++)
        if (strcmp(s->cf[i].name, name) == 0) return i;
    return -1;
}

/* Resolve a configuration: solver created (every key and name checked). */
static int check_config(eo_ctx *ctx, eo_bench_suite *s, bench_config *c)
{
    eo_cfg *cfg = NULL;
    eo_solver *sv = NULL;
    eo_solver_opts so;
    int rc = EO_OK;
    for (int i = 0; i < c->nset; i++)
        if (strncmp(c->set[i], "solver.", 7) != 0) {
            const char *eq = strchr(c->set[i], '=');
            rc = eo_error(ctx, EO_ERR_INVALID,
                          "key '%.*s': a configuration sets only solver.* keys (scene keys go in the scene's \"set\")",
                          (int)(eq ? eq - c->set[i] : 0), c->set[i]);
            goto fail;
        }
    EO_TRY(rc = config_cfg(ctx, c, &cfg, &so));
    EO_TRY(rc = eo_solver_create(ctx, &so, cfg, &sv));
    EO_TRY(rc = eo_cfg_finish(ctx, cfg));
    const eo_optimizer_type *ot = NULL;
    EO_TRY(rc = eo_registry_find(ctx, EO_KIND_OPTIMIZER, so.optimizer, (const void **)&ot));
    c->needs_hessian = ot->needs_hessian;
    for (int i = 0; i < c->nset; i++) c->own_max_iters |= strncmp(c->set[i], "solver.max_iters=", 17) == 0;
    json_t *j = eo_solver_to_json(sv);
    char *text = j ? json_dumps(j, JSON_COMPACT | JSON_REAL_PRECISION(10)) : NULL;
    json_decref(j);
    if (!text) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        goto fail;
    }
    c->resolved = eo_strdup(ctx, text);
    free(text);
    if (!c->resolved) rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
fail:
    if (rc < 0) rc = wrap_err(ctx, rc, s->path, "configuration", c->name);
    eo_solver_destroy(&sv);
    eo_cfg_destroy(&cfg);
    return rc;
}

static int check_scene(eo_ctx *ctx, eo_bench_suite *s, bench_scene *b)
{
    eo_cfg *cfg = NULL;
    eo_scene *sc = NULL;
    int rc = scene_open(ctx, b, &cfg, &sc);
    if (rc >= 0 && sc->integrator->explicit_step)
        rc = eo_error(ctx, EO_ERR_INVALID,
                      "key 'time.integrator': %s is explicit: its steps are no optimization problem, so there "
                      "is nothing to benchmark (use an implicit integrator: newmark, backward_euler, static)",
                      sc->integrator->info.name);
    if (rc >= 0) {
        b->nt = sc->mesh->nt;
        b->nv = sc->mesh->nv;
        snprintf(b->model, sizeof b->model, "%s", sc->mat[0].opts.model);
        b->E = sc->mat[0].opts.E;
        b->nu = sc->mat[0].opts.nu;
    } else {
        rc = wrap_err(ctx, rc, s->path, "scene", b->name);
    }
    eo_scene_destroy(&sc);
    eo_cfg_destroy(&cfg);
    return rc;
}

/* Drop optional scene i (its check failed with EO_ERR_IO), keeping the message. */
static int skip_scene(eo_ctx *ctx, eo_bench_suite *s, int i)
{
    char **p = eo_realloc(ctx, s->skipped, (size_t)(s->nskipped + 1) * sizeof(char *));
    if (!p) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    s->skipped = p;
    size_t len = strlen(s->sc[i].name) + strlen(eo_ctx_message(ctx)) + 3;
    char *msg = eo_malloc(ctx, len);
    if (!msg) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    snprintf(msg, len, "%s: %s", s->sc[i].name, eo_ctx_message(ctx));
    s->skipped[s->nskipped++] = msg;
    free_set(ctx, s->sc[i].set, s->sc[i].nset);
    memmove(s->sc + i, s->sc + i + 1, (size_t)(s->nsc - i - 1) * sizeof *s->sc);
    s->nsc--;
    return EO_OK;
}

void eo_bench_suite_destroy(eo_bench_suite **ps)
{
    eo_ctx *ctx = ps && *ps ? (*ps)->ctx : NULL;
    if (!ps || !*ps) return;
    eo_bench_suite *s = *ps;
    for (int i = 0; i < s->nsc; i++) free_set(ctx, s->sc[i].set, s->sc[i].nset);
    for (int i = 0; i < s->ncf; i++) {
        free_set(ctx, s->cf[i].set, s->cf[i].nset);
        eo_free(ctx, s->cf[i].resolved);
    }
    eo_free(ctx, s->sc);
    eo_free(ctx, s->cf);
    eo_free(ctx, s->req);
    for (int i = 0; i < s->nskipped; i++) eo_free(ctx, s->skipped[i]);
    eo_free(ctx, s->skipped);
    eo_free(ctx, s);
    *ps = NULL;
}

int eo_bench_suite_load(eo_ctx *ctx, const char *path, eo_bench_suite **out)
{
    static const char *const top[] = {"thresholds", "budgets", "iter_budgets", "require_converged", "scenes",
                                      "configs", "matrix", NULL};
    *out = NULL;
    eo_cfg *cfg = NULL;
    int rc;
    eo_bench_suite *s = eo_calloc(ctx, 1, sizeof *s);
    if (s) s->ctx = ctx;
    if (!s) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    snprintf(s->path, sizeof s->path, "%s", path);
    const char *slash = strrchr(path, '/');
    if (slash) snprintf(s->dir, sizeof s->dir, "%.*s", (int)(slash - path), path);
    eo_params_default(eo_bench_opts_desc, &s->o);
    double thr[] = {1e-2, 1e-3, 1e-4, 1e-6, 1e-8}, bud[] = {0.01, 0.1, 1};
    s->nthr = 5;
    memcpy(s->thr, thr, sizeof thr);
    s->nbud = 3;
    memcpy(s->bud, bud, sizeof bud);
    EO_TRY(rc = eo_cfg_load(ctx, path, NULL, &cfg));
    EO_TRY(rc = eo_cfg_section(ctx, cfg, "", eo_bench_opts_desc, &s->o, top));
    EO_TRY(rc = number_list(ctx, cfg, "thresholds", s->thr, &s->nthr));
    EO_TRY(rc = number_list(ctx, cfg, "budgets", s->bud, &s->nbud));
    EO_TRY(rc = int_list(ctx, cfg, "iter_budgets", s->ibud, &s->nibud));
    for (int i = 0; i < s->nthr; i++)
        if (s->thr[i] <= s->o.target) {
            rc = suite_err(ctx, cfg, "thresholds", EO_ERR_RANGE,
                           "threshold %g is not above target %g: runs stop before reaching it", s->thr[i],
                           s->o.target);
            goto fail;
        }
    json_t *list = eo_cfg_get(cfg, "scenes");
    if (!json_is_array(list) || !json_array_size(list)) {
        rc = suite_err(ctx, cfg, "scenes", EO_ERR_INVALID, "a suite needs a non-empty list \"scenes\"");
        goto fail;
    }
    for (size_t i = 0; i < json_array_size(list); i++) EO_TRY(rc = load_scene_entry(ctx, s, cfg, (int)i));
    /* configurations in document order of the "configs" and "matrix" lists */
    const char *key;
    json_t *val;
    json_object_foreach(eo_cfg_root(cfg), key, val) {
        int is_cf = strcmp(key, "configs") == 0, is_mx = strcmp(key, "matrix") == 0;
        if (!is_cf && !is_mx) continue;
        list = eo_cfg_get(cfg, key);
        if (!json_is_array(list)) {
            rc = suite_err(ctx, cfg, key, EO_ERR_TYPE, "expected a list of %s", is_cf ? "configurations" : "matrix objects");
            goto fail;
        }
        for (size_t i = 0; i < json_array_size(list); i++)
            EO_TRY(rc = is_cf ? load_config_entry(ctx, s, cfg, (int)i) : load_matrix_entry(ctx, s, cfg, (int)i));
    }
    if (!s->ncf) {
        rc = suite_err(ctx, cfg, "configs", EO_ERR_INVALID, "a suite needs at least one configuration (configs or matrix)");
        goto fail;
    }
    for (int i = 0; i < s->nsc; i++)
        for (int j = 0; j < i; j++)
            if (strcmp(s->sc[i].name, s->sc[j].name) == 0) {
                rc = suite_err(ctx, cfg, "scenes", EO_ERR_INVALID, "two scenes are named '%s'", s->sc[i].name);
                goto fail;
            }
    for (int i = 0; i < s->ncf; i++)
        if (find_config(s, s->cf[i].name) != i) {
            rc = suite_err(ctx, cfg, "configs", EO_ERR_INVALID, "two configurations are named '%s'", s->cf[i].name);
            goto fail;
        }
    s->baseline = 0;
    if (s->o.baseline[0] && (s->baseline = find_config(s, s->o.baseline)) < 0) {
        char names[2048];
        size_t k = 0;
        names[0] = 0;
        for (int i = 0; i < s->ncf && k < sizeof names; i++)
            k += (size_t)snprintf(names + k, sizeof names - k, "%s%s", i ? ", " : "", s->cf[i].name);
        rc = suite_err(ctx, cfg, "baseline", EO_ERR_INVALID, "'%s' is not a configuration; configurations: %s",
                       s->o.baseline, names);
        goto fail;
    }
    snprintf(s->o.baseline, sizeof s->o.baseline, "%.63s", s->cf[s->baseline].name);
    list = eo_cfg_get(cfg, "require_converged");
    if (list) {
        if (!json_is_array(list)) {
            rc = suite_err(ctx, cfg, "require_converged", EO_ERR_TYPE, "expected a list of configuration names");
            goto fail;
        }
        s->req = eo_calloc(ctx, json_array_size(list) + 1, sizeof(int));
        if (!s->req) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
            goto fail;
        }
        size_t i;
        json_t *e;
        json_array_foreach(list, i, e) {
            int k = json_is_string(e) ? find_config(s, json_string_value(e)) : -1;
            if (k < 0) {
                rc = suite_err(ctx, cfg, "require_converged", EO_ERR_INVALID, "item %zu is not a configuration name", i);
                goto fail;
            }
            s->req[s->nreq++] = k;
        }
    }
    EO_TRY(rc = eo_cfg_finish(ctx, cfg));
    for (int i = 0; i < s->ncf; i++) EO_TRY(rc = check_config(ctx, s, s->cf + i));
    for (int i = 0; i < s->nsc; i++) {
        rc = check_scene(ctx, s, s->sc + i);
        if (rc == EO_ERR_IO && s->sc[i].o.optional) { /* e.g. the shared meshes are absent: drop it */
            EO_TRY(rc = skip_scene(ctx, s, i));
            i--;
            continue;
        }
        EO_TRY(rc);
    }
    if (!s->nsc) {
        rc = eo_error(ctx, EO_ERR_INVALID, "%s: every scene is optional and was dropped (first: %s)", s->path,
                      s->skipped[0]);
        goto fail;
    }
    eo_cfg_destroy(&cfg);
    *out = s;
    return EO_OK;
fail:
    eo_cfg_destroy(&cfg);
    eo_bench_suite_destroy(&s);
    return rc;
}

const eo_bench_opts *eo_bench_suite_opts(const eo_bench_suite *s) { return &s->o; }
int eo_bench_suite_nscenes(const eo_bench_suite *s) { return s->nsc; }
int eo_bench_suite_nconfigs(const eo_bench_suite *s) { return s->ncf; }
const char *eo_bench_suite_scene_name(const eo_bench_suite *s, int i)
{
    return i >= 0 && i < s->nsc ? s->sc[i].name : NULL;
}
const char *eo_bench_suite_config_name(const eo_bench_suite *s, int i)
{
    return i >= 0 && i < s->ncf ? s->cf[i].name : NULL;
}
int eo_bench_suite_nskipped(const eo_bench_suite *s) { return s->nskipped; }
const char *eo_bench_suite_skipped(const eo_bench_suite *s, int i)
{
    return i >= 0 && i < s->nskipped ? s->skipped[i] : NULL;
}

eo_bench_run_opts eo_bench_run_opts_default(void)
{
    eo_bench_run_opts o = {.out_dir = NULL, .repeats = 0, .plots = -1, .progress = NULL, .user = NULL,
                           .profile = NULL, .profile_user = NULL, .clock = NULL};
    return o;
}

/* ================================================================ running */

/* Recording buffer of one minimization (sized before the run). */
typedef struct rec_buf {
    int cap, n;
    double *t, *g, *gn, *pe;  /* per record; pe NULL: no position error */
    double *t2;               /* per record: the other clock's time (t is the suite's clock) */
    int wall;                 /* t is wall time (else CPU time of the solving thread) */
    double *e;                /* relative energy error, filled after the run */
    const double *xstar, *wM;
    double pe0;               /* ‖x₀ − x*‖_M */
    int nfree;
    double gstar, de, target, budget;
    double cb_wall, cb_cpu;   /* the callback's own time (position errors), excluded */
    int max_records;          /* > 0: stop after this many records (warm-up run) */
    double gbest;             /* lowest g so far */
    int since_best;           /* records since gbest last decreased */
    int reached, out_of_time, stagnated;
} rec_buf;

/* A curve run that has not lowered its best g for this many iterations is stopped as
 * stagnated (the step length has reached the rounding level of g: e.g. Armijo accepts
 * α‖p‖ too small to change g, and the run would otherwise go on to its cap). */
enum { STAGNATION_ITERS = 20 };

static double mnorm_diff(int n, const double *w, const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < n; i++) {
        double d = a[i] - b[i];
        s += w[i] * d * d;
    }
    return sqrt(s);
}

static int curve_iter(const eo_iter_info *it, void *user)
{
    rec_buf *b = user;
    const double w_in = b->pe ? eo_wtime() : 0, c_in = b->pe ? eo_cputime() : 0;
    const double tw = it->time - b->cb_wall, tc = it->cpu_time - b->cb_cpu;
    const double t = b->wall ? tw : tc;
    if (b->n < b->cap) {
        int k = b->n++;
        b->t[k] = t;
        b->t2[k] = b->wall ? tc : tw;
        b->g[k] = it->g;
        b->gn[k] = it->grad_norm;
        if (b->pe) {
            double d = mnorm_diff(b->nfree, b->wM, it->x, b->xstar);
            b->pe[k] = b->pe0 > 0 ? d / b->pe0 : (d == 0 ? 0 : INFINITY);
        }
    }
    int stop = 0;
    if (it->g < b->gbest) {
        b->gbest = it->g;
        b->since_best = 0;
    } else {
        b->since_best++;
    }
    if (b->max_records > 0 && b->n >= b->max_records) stop = 1;
    if ((it->g - b->gstar) / b->de <= b->target) stop = b->reached = 1;
    else if (b->budget > 0 && t > b->budget) stop = b->out_of_time = 1;
    else if (b->since_best >= STAGNATION_ITERS) stop = b->stagnated = 1;
    if (b->pe) {
        b->cb_wall += eo_wtime() - w_in;
        b->cb_cpu += eo_cputime() - c_in;
    }
    return stop;
}

/* A trajectory that satisfies its own stopping rule on every step but ends farther than
 * this fraction of the reference motion (RMS displacement over the measured steps) from
 * the reference has found another stationary point: status "elsewhere". */
#define ELSEWHERE 1e-2

/* Reference stop: the Newton decrement below tol = ref_tol·|g(x₀)|, or the rounding
 * floor: the last step did not lower g although its decrement was already below
 * 1e-9·|g(x₀)| (then no tighter solution exists in floating point: the line search
 * only accepts steps that leave g unchanged). */
typedef struct ref_state {
    double tol, gscale, dec, prev_g, prev_dec;
    int stopped, rounding;
} ref_state;

static int ref_iter(const eo_iter_info *it, void *user)
{
    ref_state *r = user;
    if (!isnan(it->decrement)) r->dec = it->decrement;
    if (it->iteration > 0 && !(it->g < r->prev_g) && r->prev_dec <= 1e-9 * r->gscale) {
        r->dec = r->prev_dec;
        return r->stopped = r->rounding = 1;
    }
    r->prev_g = it->g;
    r->prev_dec = isnan(it->decrement) ? INFINITY : it->decrement;
    if (!isnan(it->decrement) && it->decrement <= r->tol && !it->reason) return r->stopped = 1;
    return 0;
}

static int all_finite(int n, const double *x)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

/* Mass-weighted RMS distance of two full position vectors. */
static double rms_dist(int nv, const double *m, const double *a, const double *b)
{
    double s = 0, mt = 0;
    for (int v = 0; v < nv; v++) {
        double d2 = 0;
        for (int k = 0; k < 3; k++) {
            double d = a[3 * v + k] - b[3 * v + k];
            d2 += d * d;
        }
        s += m[v] * d2;
        mt += m[v];
    }
    return mt > 0 ? sqrt(s / mt) : NAN;
}

typedef struct run_ctx {
    eo_ctx *ctx;
    const eo_bench_suite *s;
    const eo_bench_run_opts *ro;
    bench_out *out;
    int repeats, si;
    int wall;             /* the run's clock is wall time (else thread CPU time) */
    double t0, units_total, units_done;
    FILE *curves, *traj, *fixed;
} run_ctx;

static void progress(run_ctx *r, int si, int ci, const char *phase)
{
    if (!r->ro->progress) return;
    eo_bench_progress p = {.scene = si, .nscenes = r->s->nsc, .config = ci, .nconfigs = r->s->ncf,
                           .scene_name = r->s->sc[si].name,
                           .config_name = ci >= 0 ? r->s->cf[ci].name : "",
                           .phase = phase};
    p.elapsed = eo_wtime() - r->t0;
    p.fraction = r->units_total > 0 ? r->units_done / r->units_total : 0;
    p.eta = p.fraction > 0.002 ? p.elapsed * (1 - p.fraction) / p.fraction : -1;
    r->ro->progress(&p, r->ro->user);
}

/* timed repeats: the run option (--repeats) if given, else `own` (the scene's or the
 * suite's), capped at BENCH_MAX_REPEATS */
static int run_repeats(const eo_bench_run_opts *ro, int own)
{
    int n = ro->repeats > 0 ? ro->repeats : own;
    return n < 1 ? 1 : n > BENCH_MAX_REPEATS ? BENCH_MAX_REPEATS : n;
}

/* Steps of a scene's trajectory runs before the measured steps are known: the window's
 * length if it is contiguous (select = first, or a window start), else up to the horizon. */
static int traj_steps_estimate(const bench_scene *b)
{
    if (b->traj_window) return b->select == BENCH_SELECT_FIRST ? b->steps : b->steps + 1;
    return b->skip + (b->select == BENCH_SELECT_FIRST ? b->steps : b->horizon);
}

/* Work units of a scene (tets x step solves) for the progress fraction: reference,
 * curves (warm-up + repeats), trajectories, fixed budgets (a fraction of a solve each). */
static double scene_units(const eo_bench_suite *s, const bench_scene *b, int repeats, int traj_steps)
{
    double u = (double)b->nt * (b->skip + b->horizon) +
               (double)b->nt * b->steps * s->ncf * (repeats + 1) +
               (double)b->nt * b->steps * s->ncf * 0.3 * b->nibud_on;
    if (s->o.trajectory) u += (double)b->nt * traj_steps * s->ncf;
    return u;
}

/* One CSV number with its leading comma; a non-finite value (not reached, not
 * available, infinite) is an empty field: no output file holds a non-finite number. */
void eo_bench_csv_num(FILE *f, double v)
{
    if (!isfinite(v)) fputs(",", f);
    else fprintf(f, ",%.6e", v);
}

static const char *curve_reason_name(const bench_step_res *r)
{
    return r->reached ? "reached_target" : r->stagnated ? "stagnated" : eo_reason_name(r->reason);
}

/* Write the curve rows of one (scene, config, step) and the plot data block. */
static void write_curve(run_ctx *r, FILE *dat, const bench_scene *b, const bench_config *c, int step,
                        const rec_buf *rep, int nrep, const bench_step_res *res, double *tmp)
{
    int nmax = 0;
    for (int q = 0; q < nrep; q++)
        if (rep[q].n > nmax) nmax = rep[q].n;
    fprintf(dat, "# %s step %d\n", c->name, step + 1);
    for (int k = 0; k < nmax; k++) {
        int m = 0, src = -1;
        for (int q = 0; q < nrep; q++)
            if (rep[q].n > k) {
                tmp[m++] = rep[q].t[k];
                if (src < 0) src = q;
            }
        double tmin, tmax, tmed = eo_bench_median(m, tmp, &tmin, &tmax);
        m = 0;
        for (int q = 0; q < nrep; q++)
            if (rep[q].n > k) tmp[m++] = rep[q].t2[k];
        const double t2med = eo_bench_median(m, tmp, NULL, NULL);
        double e = rep[src].e[k];
        double pe = rep[0].pe && k < rep[0].n ? rep[0].pe[k] : NAN;
        if (!eo_bench_keep_row(k, nmax, r->s->o.curve_rows)) continue;
        fprintf(r->curves, "%s,%d,%s,%d", b->name, step + 1, c->name, k);
        eo_bench_csv_num(r->curves, tmed);
        eo_bench_csv_num(r->curves, tmin);
        eo_bench_csv_num(r->curves, tmax);
        eo_bench_csv_num(r->curves, k > 0 ? (r->wall ? tmed : t2med) : 0.0);
        eo_bench_csv_num(r->curves, k > 0 ? (r->wall ? t2med : tmed) : 0.0);
        eo_bench_csv_num(r->curves, rep[src].g[k]);
        eo_bench_csv_num(r->curves, e);
        eo_bench_csv_num(r->curves, pe);
        eo_bench_csv_num(r->curves, rep[src].gn[k]);
        fprintf(r->curves, ",%s\n", k == nmax - 1 ? curve_reason_name(res) : "");
        if (k > 0 && tmed > 0 && tmed < r->out->res[r->si].tmin) r->out->res[r->si].tmin = tmed;
        fprintf(dat, "%.6e %.6e\n", k > 0 ? tmed : 0.0, e > 1e-17 ? e : 1e-17);
    }
    fprintf(dat, "\n\n");
}

/* Run the curves of one configuration on one step from the current guess. */
static int run_curves(run_ctx *r, eo_sim *sim, eo_solver *sv, int n, const double *x0, double *x,
                      const bench_ref *ref, const double *xstar, const double *wM, rec_buf *w, rec_buf *rep,
                      bench_step_res *res, double budget)
{
    eo_ctx *ctx = r->ctx;
    double de = fabs(ref->g0 - ref->gstar);
    if (!(de > 0)) de = fmax(fabs(ref->gstar), 1e-300);
    double pe0 = mnorm_diff(n, wM, x0, xstar);
    eo_solve_result sr;
    int rc;
    const int q0 = r->s->o.warmup_iters > 0 ? -1 : 0;
    for (int q = q0; q < r->repeats; q++) {
        rec_buf *b = q < 0 ? w : rep + q;
        b->max_records = q < 0 ? r->s->o.warmup_iters + 1 : 0;
        b->n = 0;
        b->nfree = n;
        b->xstar = xstar;
        b->wM = wM;
        b->pe0 = pe0;
        b->gstar = ref->gstar;
        b->de = de;
        b->target = r->s->o.target;
        b->budget = budget;
        b->wall = r->wall;
        b->cb_wall = b->cb_cpu = 0;
        b->gbest = INFINITY;
        b->since_best = 0;
        b->reached = b->out_of_time = b->stagnated = 0;
        rc = eo_sim_trial(sim, sv, x0, x, curve_iter, b, NULL, &sr);
        if (rc < 0) return rc;
        if (q == 0) {
            res->reason = b->out_of_time ? EO_DIVERGED_TIME_BUDGET : sr.reason;
            res->reached = b->reached;
            res->stagnated = b->stagnated;
        }
        if (!all_finite(n, x)) res->nonfinite = res->nan = 1;
        if (sr.reason == EO_DIVERGED_NONFINITE) res->nonfinite = 1;
    }
    /* iterate times: τ₀ = 0, τₖ = time of record k−1; relative errors */
    res->nrep = r->repeats;
    double tots[BENCH_MAX_REPEATS];
    for (int q = 0; q < r->repeats; q++) {
        rec_buf *b = rep + q;
        for (int k = b->n - 1; k >= 1; k--) {
            b->t[k] = b->t[k - 1];
            b->t2[k] = b->t2[k - 1];
        }
        if (b->n) b->t[0] = b->t2[0] = 0;
        for (int k = 0; k < b->n; k++) {
            if (isnan(b->g[k]) || isnan(b->gn[k])) res->nonfinite = res->nan = 1;
            b->e[k] = (b->g[k] - ref->gstar) / de;
        }
        tots[q] = b->n ? b->t[b->n - 1] : 0;
        for (int j = 0; j < r->s->nthr; j++) res->ttt[j][q] = eo_bench_time_to(b->n, b->t, b->e, r->s->thr[j]);
        for (int j = 0; j < r->s->nbud; j++) res->eab[j][q] = eo_bench_error_at(b->n, b->t, b->e, r->s->bud[j]);
    }
    /* iterations and final error of the median-time repeat */
    double med = eo_bench_median(r->repeats, tots, NULL, NULL);
    int pick = 0;
    for (int q = 0; q < r->repeats; q++)
        if (fabs(tots[q] - med) < fabs(tots[pick] - med)) pick = q;
    res->iters = rep[pick].n ? rep[pick].n - 1 : 0;
    res->final_err = rep[pick].n ? rep[pick].e[rep[pick].n - 1] : NAN;
    (void)ctx;
    return EO_OK;
}

static void aggregate(const eo_bench_suite *s, int repeats, bench_pair *p, int is_traj, double ref_disp,
                      const int *meas)
{
    for (int j = 0; j < s->nthr; j++) {
        double tot[BENCH_MAX_REPEATS];
        for (int q = 0; q < repeats; q++) {
            tot[q] = 0;
            for (int k = 0; k < p->nsteps; k++) tot[q] += p->st[k].ttt[j][q];
        }
        p->ttt_med[j] = eo_bench_median(repeats, tot, &p->ttt_min[j], &p->ttt_max[j]);
    }
    for (int j = 0; j < s->nbud; j++) {
        double worst[BENCH_MAX_REPEATS];
        for (int q = 0; q < repeats; q++) {
            worst[q] = -INFINITY;
            for (int k = 0; k < p->nsteps; k++) worst[q] = fmax(worst[q], p->st[k].eab[j][q]);
        }
        p->eab_med[j] = eo_bench_median(repeats, worst, NULL, NULL);
    }
    p->steps_reached = 0;
    for (int k = 0; k < p->nsteps; k++) {
        p->steps_reached += p->st[k].reached;
        p->nonfinite |= p->st[k].nonfinite;
        p->nan |= p->st[k].nan;
    }
    p->first_bad_step = -1;
    p->traj_converged = 0;
    p->traj_time = 0;
    p->traj_max_dist = 0;
    p->traj_final_dist = NAN;
    if (is_traj) {
        for (int k = 0; k < p->traj_done; k++) {
            const bench_traj_res *t = p->tr + k;
            p->nonfinite |= t->nonfinite;
            p->nan |= t->nan;
            if (t->reason > 0) p->traj_converged++;
            else if (p->first_bad_step < 0) {
                p->first_bad_step = k;
                p->first_bad_reason = t->reason;
            }
            p->traj_time += t->time;
            p->traj_max_dist = fmax(p->traj_max_dist, t->dist);
            p->traj_final_dist = t->dist;
        }
        if (p->traj_done < p->ntraj && p->first_bad_step < 0) {
            p->first_bad_step = p->traj_done;
            p->first_bad_reason = EO_DIVERGED_NONFINITE;
        }
    } else {
        for (int k = 0; k < p->nsteps; k++)
            if (!p->st[k].reached && p->first_bad_step < 0) {
                p->first_bad_step = k;
                p->first_bad_reason = p->st[k].reason;
            }
    }
    /* the failing step counted from the scene's start */
    const int bad = p->first_bad_step >= 0 ? p->first_bad_step : 0;
    const int scene_step = is_traj ? p->traj_first + bad : meas[bad < p->nsteps ? bad : 0];
    if (p->nonfinite) {
        snprintf(p->status, sizeof p->status, "non-finite");
        snprintf(p->reason, sizeof p->reason, "%s (step %d: %s)",
                 p->nan ? "NaN or non-finite positions returned"
                        : "non-finite g or gradient met, run stopped; returned positions finite",
                 scene_step + 1,
                 p->first_bad_step >= 0 ? eo_reason_name(p->first_bad_reason) : "curve run");
    } else if (p->first_bad_step < 0 && is_traj && p->traj_max_dist > ELSEWHERE * fmax(ref_disp, 1e-12)) {
        snprintf(p->status, sizeof p->status, "elsewhere");
        snprintf(p->reason, sizeof p->reason,
                 "own rule satisfied on every step, but up to %.2g m (%.0f%% of the reference motion) away from the "
                 "reference trajectory: another stationary point",
                 p->traj_max_dist, 100 * p->traj_max_dist / fmax(ref_disp, 1e-12));
    } else if (p->first_bad_step < 0) {
        snprintf(p->status, sizeof p->status, "converged");
        snprintf(p->reason, sizeof p->reason, "%s", is_traj ? "converged on every step" : "reached target on every step");
    } else {
        snprintf(p->status, sizeof p->status, "stopped");
        snprintf(p->reason, sizeof p->reason, "step %d: %s", scene_step + 1, eo_reason_name(p->first_bad_reason));
    }
}

/* Stops the solver at iterate `*limit` (warm-up runs). */
static int fixed_iter(const eo_iter_info *it, void *user)
{
    return it->iteration >= *(const int *)user;
}

/* The time budget of the trajectory and fixed-budget runs in the suite's clock (the
 * solver's own solver.time_budget counts wall seconds, so the harness sets it to 0 and
 * stops the run here), and the fixed iteration budget (limit > 0). */
typedef struct budget_cb {
    int limit;            /* stop at this iterate (0: none) */
    double budget;        /* seconds in the suite's clock (0: none) */
    int wall;
    int hit;              /* the budget stopped the run */
} budget_cb;

static int budget_iter(const eo_iter_info *it, void *user)
{
    budget_cb *c = user;
    if (c->limit > 0 && it->iteration >= c->limit) return 1;
    const double t = c->wall ? it->time : it->cpu_time;
    if (c->budget > 0 && t > c->budget) return c->hit = 1;
    return 0;
}

/* A run the budget callback stopped ends with reason diverged_time_budget. */
static int budget_reason(const budget_cb *c, int reason)
{
    return c->hit && reason == EO_DIVERGED_EXTERNAL ? EO_DIVERGED_TIME_BUDGET : reason;
}

/* Measured steps of a scene from the reference's per-step scores (motion or
 * correction): the block of `S` consecutive steps among skip .. nref−1 with the largest
 * total score (ties: the earlier block; a failed reference step, NaN, disqualifies its
 * blocks), so the trajectory and fixed-budget runs over the window cost S steps;
 * select = first: skip .. skip + S − 1. */
static void select_steps(const bench_scene *b, int nref, const double *motion, const double *correction, int *meas)
{
    const int S = b->steps;
    int start = b->skip;
    if (b->select != BENCH_SELECT_FIRST) {
        const double *score = b->select == BENCH_SELECT_MOTION ? motion : correction;
        double best = -INFINITY;
        for (int k = b->skip; k + S <= nref; k++) {
            double sum = 0;
            for (int m = 0; m < S; m++) sum += isnan(score[k + m]) ? -INFINITY : score[k + m];
            if (sum > best) best = sum, start = k;
        }
    }
    for (int m = 0; m < S; m++) meas[m] = start + m;
}

/* x* of scene step k in the free coordinates of the prepared step (the reference frame
 * after step k). */
static void ref_xstar(eo_step *st, int n, const double *frame_next, double *xstar)
{
    for (int i = 0; i < n; i++) xstar[i] = frame_next[eo_step_free_to_full(st, i)];
}

/* One scene: reference, curves of every configuration, trajectories, fixed budgets. */
static int run_scene(run_ctx *r, int si)
{
    eo_ctx *ctx = r->ctx;
    const eo_bench_suite *s = r->s;
    const bench_scene *b = s->sc + si;
    bench_scene_res *sr = r->out->res + si;
    eo_cfg *scfg = NULL, *ccfg = NULL;
    eo_sim *sim = NULL;
    eo_solver *sv = NULL;
    eo_afile *datf = NULL;
    double *mem = NULL;
    bench_ref *allref = NULL;
    int rc;
    /* measured steps; reference steps (skip + horizon: the steps to select from) */
    const int S = b->steps, NR = b->skip + b->horizon;
    r->si = si;
    sr->tmin = INFINITY;
    progress(r, si, -1, "reference");
    EO_TRY(rc = scene_cfg(ctx, b, &scfg));
    json_object_del(eo_cfg_root(scfg), "solver"); /* the suite's configurations define the solver */
    rc = eo_sim_create(ctx, scfg, &sim);           /* takes scfg over */
    scfg = NULL;
    EO_TRY(rc);
    const eo_scene *sc = eo_sim_scene(sim);
    eo_step *st = eo_sim_step_problem(sim);
    r->repeats = run_repeats(r->ro, b->repeats);
    sr->repeats = r->repeats;
    const int nv = sc->mesh->nv, nf = 3 * nv, cap = b->max_iters + 2, R = r->repeats;
    /* frames (x, v) 0..NR of the reference, x* of the current step, guess, x, wM, tmp,
     * times, motion and correction per reference step, recording buffers; the reference
     * step k starts from frame k and ends in frame k + 1 */
    size_t need = (size_t)(NR + 1) * 2 * nf + 4 * (size_t)nf + 64 + (size_t)(NR + 1) + (size_t)NR +
                  (size_t)(R + 1) * 6 * (size_t)cap;
    mem = eo_malloc(ctx, need * sizeof(double));
    sr->ref = eo_calloc(ctx, (size_t)S, sizeof *sr->ref);
    sr->meas = eo_calloc(ctx, (size_t)S, sizeof *sr->meas);
    sr->motion = eo_calloc(ctx, 2 * (size_t)NR, sizeof *sr->motion);
    sr->pair = eo_calloc(ctx, (size_t)s->ncf, sizeof *sr->pair);
    allref = eo_calloc(ctx, (size_t)NR, sizeof *allref);
    if (!mem || !sr->ref || !sr->meas || !sr->motion || !sr->pair || !allref) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (bench scene %s)", b->name);
        goto fail;
    }
    sr->correction = sr->motion + NR;
    sr->nref = NR;
    double *fx = mem, *fv = fx + (size_t)(NR + 1) * nf, *xsm = fv + (size_t)(NR + 1) * nf;
    double *x0 = xsm + nf, *x = x0 + nf, *wM = x + nf, *tmp = wM + nf;
    double *ft = tmp + 64, *ftime = ft + NR + 1, *recmem = ftime + NR; /* ftime: solve time per window frame */
    rec_buf w, rep[BENCH_MAX_REPEATS];
    for (int q = -1; q < R; q++) {
        rec_buf *b2 = q < 0 ? &w : rep + q;
        double *p = recmem + (size_t)(q + 1) * 6 * (size_t)cap;
        memset(b2, 0, sizeof *b2);
        b2->cap = cap;
        b2->t = p, b2->g = p + cap, b2->gn = p + 2 * (size_t)cap, b2->e = p + 3 * (size_t)cap;
        b2->pe = q == 0 ? p + 4 * (size_t)cap : NULL; /* position error: first timed repeat */
        b2->t2 = p + 5 * (size_t)cap;
    }
    const double *vmass = eo_step_vertex_mass(st);
    double mtot = 0;
    for (int v = 0; v < nv; v++) mtot += vmass[v];

    /* ---- reference */
    eo_solver_opts rso;
    eo_solver_opts_default(&rso);
    snprintf(rso.optimizer, sizeof rso.optimizer, "newton");
    snprintf(rso.hessian_fix, sizeof rso.hessian_fix, "clamp");
    snprintf(rso.linesearch, sizeof rso.linesearch, "backtracking");
    snprintf(rso.stop, sizeof rso.stop, "newton_decrement");
    rso.tol = 1e-300;
    rso.max_iters = s->o.ref_max_iters;
    rso.time_budget = 0;
    EO_TRY(rc = eo_sim_set_solver(sim, &rso, NULL));
    /* the reference solves the nominal steps' problems (a scene's time.adaptive acts in
     * the trajectory runs only) */
    const int adaptive = eo_sim_adaptive(sim);
    EO_TRY(rc = eo_sim_set_adaptive(sim, 0));
    ref_state rs;
    eo_sim_set_iter_callback(sim, ref_iter, &rs);
    eo_objective *obj;
    double *guess;
    eo_step_stats stats;
    EO_TRY(rc = eo_step_stats_compute(st, &stats));
    sr->start_minJ = stats.min_J;
    sr->start_inverted = stats.inverted;
    sr->start_elastic = stats.elastic;
    for (int k = 0; k < NR; k++) {
        eo_sim_get_state(sim, fx + (size_t)k * nf, fv + (size_t)k * nf, &ft[k], NULL);
        EO_TRY(rc = eo_sim_prepare(sim, &obj, &guess));
        const int n = obj->n;
        double g0;
        EO_TRY(rc = eo_objective_value(obj, guess, &g0));
        memcpy(x0, guess, (size_t)n * sizeof(double));
        rs = (ref_state){.tol = s->o.ref_tol * fmax(fabs(g0), 1e-300), .gscale = fmax(fabs(g0), 1e-300),
                         .dec = NAN, .prev_g = INFINITY, .prev_dec = INFINITY};
        eo_sim_step_result res;
        EO_TRY(rc = eo_sim_step(sim, &res));
        bench_ref *q = allref + k;
        q->t = ft[k] + sc->time.dt;
        q->g0 = g0;
        q->gstar = res.g;
        q->dec = rs.dec;
        q->time = r->wall ? res.time : res.cpu_time;
        q->iters = res.iterations;
        q->reason = rs.stopped ? EO_CONVERGED_DECREMENT : res.reason;
        q->converged = rs.stopped || res.reason > 0;
        q->rounding = rs.rounding;
        q->n = n;
        q->floor = 2.2e-16 * fmax(fabs(g0), fabs(res.g)) / fmax(fabs(g0 - res.g), 1e-300);
        q->ip_reason = -1000; /* the Ipopt check: not run */
        if (!q->converged) r->out->sum->ref_failures++;
        /* per-step scores: the motion of the step and the distance from its start guess
         * to x* (free coordinates; constrained vertices contribute 0), both m RMS */
        const double *xa = eo_step_x(st);
        sr->motion[k] = rms_dist(nv, vmass, xa, fx + (size_t)k * nf);
        double c2 = 0;
        for (int i = 0; i < n; i++) {
            int fi = eo_step_free_to_full(st, i);
            double d = xa[fi] - x0[i];
            c2 += vmass[fi / 3] * d * d;
        }
        sr->correction[k] = mtot > 0 ? sqrt(c2 / mtot) : NAN;
        if (!q->converged || eo_sim_index(sim) == k) sr->motion[k] = sr->correction[k] = NAN;
    }
    eo_sim_set_iter_callback(sim, NULL, NULL);
    eo_sim_get_state(sim, fx + (size_t)NR * nf, fv + (size_t)NR * nf, &ft[NR], NULL);
    select_steps(b, NR, sr->motion, sr->correction, sr->meas);
    for (int m = 0; m < S; m++) sr->ref[m] = allref[sr->meas[m]];
    /* the data profiles' cost unit: one gradient evaluation of each measured step's
     * objective at its starting guess, in the suite's clock (median of 5 after one
     * untimed call) */
    for (int m = 0; m < S; m++) {
        const int k = sr->meas[m];
        const size_t fr = (size_t)k * nf;
        EO_TRY(rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[k], k));
        EO_TRY(rc = eo_sim_prepare(sim, &obj, &guess));
        double gv, tg[5];
        EO_TRY(rc = eo_objective_gradient(obj, guess, &gv, x));
        for (int q = 0; q < 5; q++) {
            const double a = r->wall ? eo_wtime() : eo_cputime();
            EO_TRY(rc = eo_objective_gradient(obj, guess, &gv, x));
            tg[q] = (r->wall ? eo_wtime() : eo_cputime()) - a;
        }
        sr->ref[m].tgrad = eo_bench_median(5, tg, NULL, NULL);
    }
    sr->win0 = sr->meas[0];
    sr->win1 = sr->meas[S - 1];
    /* the trajectory runs: scene steps t0 .. win1 */
    const int t0 = b->traj_window ? sr->win0 : 0, NT = sr->win1 + 1 - t0, NW = sr->win1 + 1 - sr->win0;
    r->units_total += scene_units(s, b, R, NT) - scene_units(s, b, R, traj_steps_estimate(b)); /* now known */
    const void *ipopt_type = NULL;
    if (s->o.ipopt_check && eo_registry_find(ctx, EO_KIND_OPTIMIZER, "ipopt", &ipopt_type) == EO_OK) {
        eo_solver_opts io;
        eo_solver_opts_default(&io);
        snprintf(io.optimizer, sizeof io.optimizer, "ipopt");
        snprintf(io.hessian_fix, sizeof io.hessian_fix, "clamp");
        io.max_iters = s->o.ref_max_iters;
        io.time_budget = 0;
        EO_TRY(rc = eo_solver_create(ctx, &io, NULL, &sv));
        for (int m = 0; m < S; m++) {
            const int k = sr->meas[m];
            const size_t fr = (size_t)k * nf;
            EO_TRY(rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[k], k));
            EO_TRY(rc = eo_sim_prepare(sim, &obj, &guess));
            const int n = obj->n;
            for (int i = 0; i < n; i++) wM[i] = vmass[eo_step_free_to_full(st, i) / 3];
            memcpy(x0, guess, (size_t)n * sizeof(double));
            ref_xstar(st, n, fx + fr + nf, xsm);
            eo_solve_result ir;
            EO_TRY(rc = eo_sim_trial(sim, sv, x0, x, NULL, NULL, NULL, &ir));
            bench_ref *q = sr->ref + m;
            double de = fabs(q->g0 - q->gstar), pe0 = mnorm_diff(n, wM, x0, xsm);
            q->ip_reason = ir.reason;
            q->ip_iters = ir.iterations;
            q->ip_time = r->wall ? ir.time : ir.cpu_time;
            q->ip_de = (ir.g - q->gstar) / (de > 0 ? de : fmax(fabs(q->gstar), 1e-300));
            q->ip_pe = all_finite(n, x) ? mnorm_diff(n, wM, x, xsm) / (pe0 > 0 ? pe0 : 1) : NAN;
        }
        eo_solver_destroy(&sv);
    }
    sr->ref_disp = rms_dist(nv, vmass, fx + (size_t)(sr->win1 + 1) * nf, fx + (size_t)t0 * nf);
    sr->win_disp = rms_dist(nv, vmass, fx + (size_t)(sr->win1 + 1) * nf, fx + (size_t)sr->win0 * nf);
    EO_TRY(rc = eo_sim_set_state(sim, fx + (size_t)(sr->win1 + 1) * nf, fv + (size_t)(sr->win1 + 1) * nf,
                                 ft[sr->win1 + 1], sr->win1 + 1));
    EO_TRY(rc = eo_step_stats_compute(st, &stats));
    sr->end_minJ = stats.min_J;
    sr->end_inverted = stats.inverted;
    sr->end_elastic = stats.elastic;
    r->units_done += (double)b->nt * NR;
    sr->allref = allref; /* kept for reference.csv */
    allref = NULL;

    /* ---- plot data */
    char name[200], path[1400];
    eo_bench_file_name(b->name, name, sizeof name);
    snprintf(path, sizeof path, "%s/plots/%s.dat", r->out->dir, name);
    EO_TRY(rc = eo_afile_open(ctx, path, &datf));
    fprintf(eo_afile_fp(datf), "# %s: blocks (configuration c, step k) at index c*%d + k: time (s), relative energy error\n",
            b->name, S);

    /* ---- configurations */
    for (int ci = 0; ci < s->ncf; ci++) {
        const bench_config *c = s->cf + ci;
        bench_pair *p = sr->pair + ci;
        p->nsteps = S;
        p->ntraj = NT;
        p->traj_first = t0;
        p->st = eo_calloc(ctx, (size_t)S, sizeof *p->st);
        p->tr = eo_calloc(ctx, (size_t)NT, sizeof *p->tr);
        if (!p->st || !p->tr) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
            goto fail;
        }
        eo_solver_opts so, cso;
        EO_TRY(rc = config_cfg(ctx, c, &ccfg, &so));
        /* one iteration cap and one time budget for the speed (curve) and the status
         * (trajectory) runs: the configuration's own solver.max_iters if it sets one (at most
         * the scene's: the recording buffers hold that many), else the scene's; its own
         * solver.time_budget if set, else the scene's, in the suite's clock */
        const int cap_iters = c->own_max_iters && so.max_iters < b->max_iters ? so.max_iters : b->max_iters;
        const double budget = so.time_budget > 0 ? so.time_budget : b->time_budget;
        p->max_iters = cap_iters;
        p->budget = budget;
        cso = so;
        cso.tol = 1e-300;
        cso.max_iters = cap_iters;
        cso.time_budget = 0; /* the harness enforces the budget, excluding its own time */
        progress(r, si, ci, "curves");
        EO_TRY(rc = eo_solver_create(ctx, &cso, ccfg, &sv));
        for (int k = 0; k < S; k++) {
            const int ks = sr->meas[k];
            const size_t fr = (size_t)ks * nf;
            EO_TRY(rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[ks], ks));
            EO_TRY(rc = eo_sim_prepare(sim, &obj, &guess));
            int n = obj->n;
            memcpy(x0, guess, (size_t)n * sizeof(double));
            for (int i = 0; i < n; i++) wM[i] = vmass[eo_step_free_to_full(st, i) / 3];
            ref_xstar(st, n, fx + fr + nf, xsm);
            EO_TRY(rc = run_curves(r, sim, sv, n, x0, x, sr->ref + k, xsm, wM, &w, rep, p->st + k, budget));
            write_curve(r, eo_afile_fp(datf), b, c, k, rep, R, p->st + k, tmp);
            r->units_done += (double)b->nt * (R + 1);
            progress(r, si, ci, "curves");
        }
        if (r->ro->profile) {
            eo_profile pv = *eo_solver_get_profile(sv);
            if (!r->wall) eo_profile_cpu_view(eo_solver_get_profile(sv), &pv);
            r->ro->profile(b->name, c->name, &pv, r->ro->profile_user);
        }
        eo_solver_destroy(&sv);
        /* trajectory with the configuration's own stopping rule, from scene step t0 to
         * the last measured step, up to the first step the rule does not meet; an untimed
         * warm-up of at most warmup_iters iterations on the first step first */
        if (s->o.trajectory) {
            progress(r, si, ci, "trajectory");
            eo_solver_opts tso = so;
            tso.max_iters = cap_iters; /* the curve runs' cap */
            tso.time_budget = 0; /* the budget in the suite's clock: budget_iter */
            EO_TRY(rc = eo_sim_set_solver(sim, &tso, ccfg));
            EO_TRY(rc = eo_sim_set_adaptive(sim, adaptive)); /* the scene's time.adaptive */
            EO_TRY(rc = eo_sim_set_state(sim, fx + (size_t)t0 * nf, fv + (size_t)t0 * nf, ft[t0], t0));
            if (s->o.warmup_iters > 0) {
                int left = s->o.warmup_iters;
                eo_solve_result wr;
                EO_TRY(rc = eo_sim_trial(sim, NULL, NULL, x, fixed_iter, &left, NULL, &wr));
            }
            budget_cb tb = {.limit = 0, .budget = budget, .wall = r->wall};
            eo_sim_set_iter_callback(sim, budget_iter, &tb);
            for (int k = t0; k <= sr->win1; k++) {
                eo_sim_step_result res;
                tb.hit = 0;
                if ((rc = eo_sim_step(sim, &res)) < 0) break;
                /* a step whose new state was not finite is undone by the sim */
                const int rejected = eo_sim_index(sim) == k;
                bench_traj_res *t = p->tr + (k - t0);
                t->iters = res.iterations;
                t->reason = budget_reason(&tb, res.reason);
                t->time = r->wall ? res.time : res.cpu_time;
                t->time2 = r->wall ? res.cpu_time : res.time;
                t->g = res.g;
                t->nan = rejected || isnan(res.g);
                t->nonfinite = t->nan || res.reason == EO_DIVERGED_NONFINITE;
                p->traj_done = k - t0 + 1;
                if (rejected) {
                    t->dist = NAN;
                    break;
                }
                t->dist = rms_dist(nv, vmass, eo_step_x(st), fx + (size_t)(k + 1) * nf);
                fprintf(r->traj, "%s,%s,%d,%.6g,%d,%s", b->name, c->name, k + 1, ft[k + 1], t->iters,
                        eo_reason_name(t->reason));
                eo_bench_csv_num(r->traj, t->time);
                eo_bench_csv_num(r->traj, res.time);
                eo_bench_csv_num(r->traj, res.cpu_time);
                eo_bench_csv_num(r->traj, t->g);
                eo_bench_csv_num(r->traj, t->dist);
                eo_bench_csv_num(r->traj, rms_dist(nv, vmass, fx + (size_t)(k + 1) * nf, fx + (size_t)t0 * nf));
                fputc('\n', r->traj);
                if (!(t->reason > 0)) break;
            }
            eo_sim_set_iter_callback(sim, NULL, NULL);
            EO_TRY(rc);
            r->units_done += (double)b->nt * NT;
        }
        /* fixed iteration budgets over the measured window: exactly k iterations per
         * frame (stopping rule disabled; the solver's iteration cap max_iters = k, which
         * stops it before a (k+1)-th direction, solvers/optim/descent.c), the solver's
         * time per frame and the distance to the reference. One solver per budget, each
         * warmed up (untimed) on the window's first step before its timed frames. */
        if (b->nibud_on) {
            progress(r, si, ci, "fixed");
            /* exactly k iterations per nominal step: no substeps */
            EO_TRY(rc = eo_sim_set_adaptive(sim, 0));
            const size_t fr = (size_t)sr->win0 * nf;
            /* the iteration limit (backstop for optimizers with their own loops: nlopt counts
             * evaluations) and the time budget in the suite's clock */
            budget_cb fb = {.limit = 0, .budget = budget, .wall = r->wall};
            for (int j = 0; j < s->nibud; j++) {
                if (!b->ibud_on[j]) continue;
                bench_fixed_res *fz = p->fixed + j;
                const int limit = s->ibud[j];
                eo_solver_opts fso = so;
                fso.tol = 1e-300;
                fso.max_iters = limit;
                fso.time_budget = 0; /* the budget in the suite's clock: budget_iter */
                EO_TRY(rc = eo_sim_set_solver(sim, &fso, ccfg));
                EO_TRY(rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[sr->win0], sr->win0));
                if (s->o.warmup_iters > 0) {
                    int left = s->o.warmup_iters < limit ? s->o.warmup_iters : limit;
                    eo_solve_result wr;
                    EO_TRY(rc = eo_sim_trial(sim, NULL, NULL, x, fixed_iter, &left, NULL, &wr));
                }
                fb.limit = limit;
                eo_sim_set_iter_callback(sim, budget_iter, &fb);
                rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[sr->win0], sr->win0);
                for (int k = sr->win0; rc >= 0 && k <= sr->win1; k++) {
                    eo_sim_step_result res;
                    fb.hit = 0;
                    if ((rc = eo_sim_step(sim, &res)) < 0) break;
                    res.reason = budget_reason(&fb, res.reason);
                    const int rejected = eo_sim_index(sim) == k, f = k - sr->win0;
                    ftime[f] = r->wall ? res.time : res.cpu_time;
                    fz->frames = f + 1;
                    fz->iters += res.iterations;
                    if (res.iterations < limit && !fz->short_frames++) fz->first_short_reason = res.reason;
                    if (rejected || isnan(res.g)) fz->nan = 1;
                    if (fz->nan || res.reason == EO_DIVERGED_NONFINITE) fz->nonfinite = 1;
                    double d = rejected ? NAN : rms_dist(nv, vmass, eo_step_x(st), fx + (size_t)(k + 1) * nf);
                    if (!rejected) {
                        fz->max_dist = fmax(fz->max_dist, d);
                        fz->final_dist = d;
                    }
                    fprintf(r->fixed, "%s,%s,%d,%d,%.6g,%d,%s", b->name, c->name, limit, k + 1, ft[k + 1],
                            res.iterations, eo_reason_name(res.reason));
                    eo_bench_csv_num(r->fixed, ftime[f]);
                    eo_bench_csv_num(r->fixed, res.time);
                    eo_bench_csv_num(r->fixed, res.cpu_time);
                    eo_bench_csv_num(r->fixed, d);
                    eo_bench_csv_num(r->fixed, rms_dist(nv, vmass, fx + (size_t)(k + 1) * nf, fx + fr));
                    fputc('\n', r->fixed);
                    if (rejected) break;
                }
                if (rc < 0) break;
                fz->ms_med = eo_bench_median(fz->frames, ftime, &fz->ms_min, &fz->ms_max); /* first 64 frames */
                if (fz->frames < NW) fz->final_dist = NAN;
                r->units_done += (double)b->nt * S * 0.3;
            }
            eo_sim_set_iter_callback(sim, NULL, NULL);
            EO_TRY(rc);
        }
        eo_cfg_destroy(&ccfg);
        aggregate(s, R, p, s->o.trajectory, sr->ref_disp, sr->meas);
        r->out->sum->runs++;
        if (p->nonfinite) r->out->sum->nonfinite++;
        if (p->nan) r->out->sum->nan++;
        for (int q = 0; q < s->nreq; q++)
            if (s->req[q] == ci && strcmp(p->status, "converged") != 0) r->out->sum->required_failures++;
        fflush(r->curves);
        fflush(r->traj);
        fflush(r->fixed);
    }
    EO_TRY(rc = eo_afile_commit(ctx, &datf));
    progress(r, si, -1, "done");
    rc = EO_OK;
fail:
    eo_afile_abort(ctx, &datf);
    if (rc < 0 && !strstr(eo_ctx_message(ctx), b->name)) rc = wrap_err(ctx, rc, s->path, "scene", b->name);
    eo_solver_destroy(&sv);
    eo_cfg_destroy(&ccfg);
    eo_sim_destroy(&sim);
    eo_cfg_destroy(&scfg);
    eo_free(ctx, mem);
    eo_free(ctx, allref);
    return rc;
}

static void read_loadavg(char *buf, size_t n)
{
    double l[3];
    if (getloadavg(l, 3) == 3) snprintf(buf, n, "%.2f %.2f %.2f", l[0], l[1], l[2]);
    else snprintf(buf, n, "unknown");
}

int eo_bench_run(eo_ctx *ctx, const eo_bench_suite *s, const eo_bench_run_opts *opts, eo_bench_summary *sum)
{
    memset(sum, 0, sizeof *sum);
    if (!opts || !opts->out_dir) return eo_error(ctx, EO_ERR_INVALID, "bench: no output folder");
    run_ctx r = {.ctx = ctx, .s = s, .ro = opts};
    bench_out out = {.s = s, .dir = opts->out_dir, .sum = sum};
    r.out = &out;
    out.repeats = run_repeats(opts, s->o.repeats); /* the suite's; scenes may set their own */
    const char *clk = opts->clock ? opts->clock : s->o.clock;
    if (strcmp(clk, "cpu") && strcmp(clk, "wall"))
        return eo_error(ctx, EO_ERR_INVALID, "bench: clock '%s': expected cpu or wall", clk);
    r.wall = out.wall = strcmp(clk, "wall") == 0;
    out.plots = opts->plots >= 0 ? opts->plots : s->o.plots;
    eo_afile *cf = NULL, *tf = NULL, *xf = NULL;
    int rc;
    char path[1200];
    out.res = eo_calloc(ctx, (size_t)s->nsc, sizeof *out.res);
    if (!out.res) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    snprintf(path, sizeof path, "%s/plots", opts->out_dir);
    EO_TRY(rc = eo_mkdir_p(ctx, path));
    snprintf(path, sizeof path, "%s/curves.csv", opts->out_dir);
    EO_TRY(rc = eo_afile_open(ctx, path, &cf));
    snprintf(path, sizeof path, "%s/trajectory.csv", opts->out_dir);
    EO_TRY(rc = eo_afile_open(ctx, path, &tf));
    snprintf(path, sizeof path, "%s/fixed.csv", opts->out_dir);
    EO_TRY(rc = eo_afile_open(ctx, path, &xf));
    r.curves = eo_afile_fp(cf);
    r.traj = eo_afile_fp(tf);
    r.fixed = eo_afile_fp(xf);
    /* time columns: solve_time / time = the suite's clock (the one in the report), then
     * wall and CPU seconds both */
    fprintf(r.fixed, "scene,config,iter_budget,step,t,iterations,reason,solve_time,solve_wall,solve_cpu,dist_rms,"
                     "ref_disp_rms\n");
    fprintf(r.curves, "scene,step,config,iteration,time,time_min,time_max,wall_time,cpu_time,g,rel_energy_err,"
                      "rel_pos_err,grad_norm,reason\n");
    fprintf(r.traj, "scene,config,step,t,iterations,reason,solve_time,solve_wall,solve_cpu,g,dist_rms,ref_disp_rms\n");
    for (int i = 0; i < s->nsc; i++)
        r.units_total += scene_units(s, s->sc + i, run_repeats(opts, s->sc[i].repeats), traj_steps_estimate(s->sc + i));
    read_loadavg(out.load_start, sizeof out.load_start);
    r.t0 = out.t_start = eo_wtime();
    const double c0 = eo_cputime();
    for (int i = 0; i < s->nsc; i++) EO_TRY(rc = run_scene(&r, i));
    out.t_end = eo_wtime();
    out.cpu_seconds = eo_cputime() - c0;
    read_loadavg(out.load_end, sizeof out.load_end);
    sum->seconds = out.t_end - out.t_start;
    EO_TRY(rc = eo_afile_commit(ctx, &cf));
    EO_TRY(rc = eo_afile_commit(ctx, &tf));
    EO_TRY(rc = eo_afile_commit(ctx, &xf));
    if (out.plots) {
        out.gnuplot = system("command -v gnuplot >/dev/null 2>&1") == 0;
        if (out.gnuplot) {
            for (int i = 0; i < s->nsc; i++)
                if (eo_bench_plot_scene(ctx, &out, i) >= 0) sum->plots_made++;
            if (eo_bench_plot_pareto(ctx, &out) >= 0) sum->plots_made++;
        }
    }
    EO_TRY(rc = eo_bench_profiles(ctx, &out));
    EO_TRY(rc = eo_bench_write_summary(ctx, &out));
    EO_TRY(rc = eo_bench_write_report(ctx, &out));
    rc = EO_OK;
fail:
    eo_afile_abort(ctx, &cf);
    eo_afile_abort(ctx, &tf);
    eo_afile_abort(ctx, &xf);
    for (int i = 0; i < s->nsc; i++) {
        bench_scene_res *sr = out.res + i;
        eo_free(ctx, sr->meas);
        eo_free(ctx, sr->motion);
        eo_free(ctx, sr->allref);
        for (int c = 0; sr->pair && c < s->ncf; c++) {
            eo_free(ctx, sr->pair[c].st);
            eo_free(ctx, sr->pair[c].tr);
        }
        eo_free(ctx, sr->pair);
        eo_free(ctx, sr->ref);
    }
    eo_free(ctx, out.res);
    return rc;
}
