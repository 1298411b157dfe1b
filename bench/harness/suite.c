/* The optimizer benchmark harness (bench.h): the suite document (its descriptor tables)
 * loaded, expanded (vary, matrix) and checked (every scene loaded, every configuration
 * resolved) before anything runs. */
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
    {.key = "stratum_axis", .kind = EO_PARAM_INT, .offset = offsetof(eo_bench_scene_opts, stratum_axis), .def.i = -1,
     .min = -1, .max = 7, .range = EO_RANGE_MIN | EO_RANGE_MAX,
     .help = "with vary: the axis whose label is each expanded scene's stratum (prefixed by stratum and '-' when "
             "set); -1 none"},
    {0},
};

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
int bench_wrap_err(eo_ctx *ctx, int rc, const char *file, const char *what, const char *name)
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
int bench_scene_cfg(eo_ctx *ctx, const bench_scene *b, eo_cfg **cfg)
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
    int rc = bench_scene_cfg(ctx, b, cfg);
    if (rc >= 0) rc = eo_scene_load(ctx, *cfg, sc);
    if (rc >= 0) {
        eo_cfg_consume(*cfg, "solver");
        rc = eo_cfg_finish(ctx, *cfg);
    }
    return rc;
}

/* Solver options and config document of a configuration, with the harness' settings. */
int bench_config_cfg(eo_ctx *ctx, const bench_config *c, eo_cfg **cfg, eo_solver_opts *so)
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
    if (b.o.stratum_axis >= nvary) {
        snprintf(sub, sizeof sub, "%s.stratum_axis", path);
        rc = suite_err(ctx, cfg, sub, EO_ERR_RANGE, "axis %d, but vary has %d axes", b.o.stratum_axis, nvary);
        goto done;
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
                if (a == b.o.stratum_axis) {
                    char st[2 * sizeof e.o.stratum + 200];
                    snprintf(st, sizeof st, "%s%s%s", b.o.stratum, b.o.stratum[0] ? "-" : "", key);
                    snprintf(e.o.stratum, sizeof e.o.stratum, "%.*s", (int)sizeof e.o.stratum - 1, st);
                }
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
    EO_TRY(rc = bench_config_cfg(ctx, c, &cfg, &so));
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
    if (rc < 0) rc = bench_wrap_err(ctx, rc, s->path, "configuration", c->name);
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
        if (eo_ctx_dist(ctx)) { /* a part of the mesh: each tet is in one part (vertices: run.c) */
            double t = b->nt;
            eo_ctx_reduce(ctx, &t, 1, EO_REDUCE_SUM);
            b->nt = (int)t;
        }
        snprintf(b->model, sizeof b->model, "%s", sc->mat[0].opts.model);
        b->E = sc->mat[0].opts.E;
        b->nu = sc->mat[0].opts.nu;
    } else {
        rc = bench_wrap_err(ctx, rc, s->path, "scene", b->name);
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
const char *eo_bench_suite_scene_stratum(const eo_bench_suite *s, int i)
{
    return i >= 0 && i < s->nsc ? s->sc[i].o.stratum : NULL;
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
                           .profile = NULL, .profile_user = NULL, .clock = NULL, .owned_sum = NULL};
    return o;
}
