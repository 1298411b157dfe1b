/* Test helpers around the library's simulation driver (eo_sim, sim.h): open a scene
 * (built-in by name or JSON text) with -o style overrides, step it with a callback, and
 * a few measurements (tip displacement). The protocol itself is eo_sim_step. */
#ifndef EO_TESTS_ENGINE_UTIL_H
#define EO_TESTS_ENGINE_UTIL_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/sim.h"
#include "testutil.h"

/* name: built-in scene (NULL: use json); overrides: NULL-terminated "key=value". The
 * first step's objective is prepared (eo_test_sim_obj, the step's guess). */
static inline int eo_test_sim_open(eo_sim **s, eo_ctx *ctx, const char *name, const char *json,
                                   const char *const *overrides)
{
    *s = NULL;
    eo_cfg *cfg = NULL;
    int rc = json ? eo_cfg_load(ctx, NULL, json, &cfg) : eo_scene_cfg_load(ctx, NULL, name, &cfg);
    for (const char *const *o = overrides; rc >= 0 && o && *o; o++) rc = eo_cfg_override(ctx, cfg, *o);
    if (rc >= 0) {
        rc = eo_sim_create(ctx, cfg, s); /* takes cfg over */
        cfg = NULL;
    }
    if (rc >= 0) rc = eo_sim_prepare(*s, NULL, NULL);
    eo_cfg_destroy(&cfg);
    if (rc < 0) fprintf(stderr, "eo_test_sim_open(%s): %s\n", name ? name : "json", eo_ctx_message(ctx));
    return rc;
}

/* The step engine's objective (one object for the whole run: its n is that of the step
 * last prepared); prepares the next step if none is. */
static inline eo_objective *eo_test_sim_obj(eo_sim *s)
{
    eo_objective *o = NULL;
    eo_sim_prepare(s, &o, NULL);
    return o;
}

/* The next step's starting guess (prepared if needed; writable). */
static inline double *eo_test_sim_guess(eo_sim *s)
{
    double *g = NULL;
    eo_sim_prepare(s, NULL, &g);
    return g;
}

/* One step with callback cb (may be NULL); result in *r (may be NULL). */
static inline int eo_test_sim_step(eo_sim *s, eo_iter_fn cb, void *user, eo_sim_step_result *r)
{
    eo_sim_set_iter_callback(s, cb, user);
    int rc = eo_sim_step(s, r);
    eo_sim_set_iter_callback(s, NULL, NULL);
    return rc;
}

/* Per-iteration counts of a run (eo_test_count_iter as the iteration callback): Newton
 * iterations, linear-solver iterations, the forcing terms used (eta_min starts at
 * +INFINITY: eo_test_counts_reset), directions of negative curvature and those of them
 * not met by a projection. */
typedef struct eo_test_counts {
    long iters, lin_iters, negcurv, negcurv_unprojected;
    double eta_min, eta_max;
} eo_test_counts;

static inline void eo_test_counts_reset(eo_test_counts *c)
{
    memset(c, 0, sizeof *c);
    c->eta_min = INFINITY;
}

static inline int eo_test_count_iter(const eo_iter_info *info, void *user)
{
    eo_test_counts *c = user;
    c->negcurv += info->neg_curvature;
    if (info->neg_curvature && info->projected != 1) c->negcurv_unprojected++;
    c->lin_iters += info->lin_iters;
    if (info->reason == 0) c->iters++;
    if (info->eta > 0) {
        if (info->eta < c->eta_min) c->eta_min = info->eta;
        if (info->eta > c->eta_max) c->eta_max = info->eta;
    }
    return 0;
}

/* Mean z displacement of the vertices with rest x >= xmin (the tip of a bar). */
static inline double eo_test_tip_dz(const eo_sim *s, double xmin)
{
    const eo_step *st = eo_sim_step_problem(s);
    const eo_mesh *m = eo_step_mesh(st);
    const double *x = eo_step_x(st);
    double sum = 0;
    int n = 0;
    for (int v = 0; v < m->nv; v++)
        if (m->X[3 * v] >= xmin) {
            sum += x[3 * v + 2] - m->X[3 * v + 2];
            n++;
        }
    return n ? sum / n : 0;
}

/* Solve the first step of `scene` (overrides ov, then extra) with the sim's solver from
 * the step's guess x0: x and x0 out (malloc'd, n values), the result in *res and its
 * factorizations in *n_factor (may be NULL). Returns the status of eo_sim_trial. */
static inline int eo_test_solve_first(eo_ctx *ctx, const char *scene, const char *const *ov,
                                      const char *const *extra, double **x_out, double **x0_out, int *n_out,
                                      eo_solve_result *res, long *n_factor)
{
    const char *all[32];
    int j = 0;
    for (const char *const *o = ov; o && *o && j < 31; o++) all[j++] = *o;
    for (const char *const *o = extra; o && *o && j < 31; o++) all[j++] = *o;
    all[j] = NULL;
    eo_sim *s = NULL;
    *x_out = *x0_out = NULL;
    if (eo_test_sim_open(&s, ctx, scene, NULL, all) < 0) return -1;
    eo_objective *obj = NULL;
    eo_sim_prepare(s, &obj, NULL);
    const int n = obj->n;
    double *x = (double *)malloc((size_t)n * sizeof(double)), *x0 = (double *)malloc((size_t)n * sizeof(double));
    memcpy(x0, eo_test_sim_guess(s), (size_t)n * sizeof(double));
    int rc = eo_sim_trial(s, NULL, x0, x, NULL, NULL, &obj, res);
    if (n_factor) *n_factor = res->n_factor;
    eo_sim_destroy(&s);
    *x_out = x;
    *x0_out = x0;
    *n_out = n;
    return rc;
}

/* The overrides of a tightly converged Newton reference (no line search, to the rounding
 * floor, fallback chain off). */
static const char *const eo_test_newton_ref[] = {"solver.optimizer=newton", "solver.linesearch=none",
                                                 "solver.tol=1e-15", "solver.relative_decrement.plateau=1e-30",
                                                 "solver.max_iters=60", "solver.fallback=[]", NULL};

/* Minimize obj from x0 with the solver section `solver_json` (a JSON object, e.g.
 * {"optimizer": "newton"}); x out (obj->n values), callback fn/user (may be NULL). */
static inline int eo_test_solve_json(eo_ctx *ctx, eo_objective *obj, const double *x0, double *x,
                                     const char *solver_json, eo_iter_fn fn, void *user, eo_solve_result *r)
{
    char json[1024];
    snprintf(json, sizeof json, "{\"solver\": %s}", solver_json);
    eo_cfg *cfg = NULL;
    eo_solver *sv = NULL;
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    int rc = eo_cfg_load(ctx, NULL, json, &cfg);
    if (rc >= 0) rc = eo_solver_opts_load(ctx, cfg, &o);
    if (rc >= 0) rc = eo_solver_create(ctx, &o, cfg, &sv);
    if (rc >= 0) {
        memcpy(x, x0, (size_t)obj->n * sizeof(double));
        rc = eo_solver_minimize(sv, obj, x, fn, user, r);
    }
    eo_solver_destroy(&sv);
    eo_cfg_destroy(&cfg);
    return rc;
}

/* ‖x − x*‖₂ / ‖x* − x₀‖₂: the error of x as a fraction of the step's motion. */
static inline double eo_test_motion_error(int n, const double *x, const double *xs, const double *x0)
{
    double e = 0, m = 0;
    for (int i = 0; i < n; i++) {
        e += (x[i] - xs[i]) * (x[i] - xs[i]);
        m += (xs[i] - x0[i]) * (xs[i] - x0[i]);
    }
    return sqrt(e / m);
}

#endif
