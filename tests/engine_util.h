/* Test helper for the step engine: load a scene (built-in by name or JSON text) with
 * -o style overrides, and advance it step by step with the configured solver. */
#ifndef EO_TESTS_ENGINE_UTIL_H
#define EO_TESTS_ENGINE_UTIL_H

#include <string.h>

#include "elastopt/solver.h"
#include "elastopt/step.h"
#include "testutil.h"

typedef struct eo_sim {
    eo_ctx *ctx;
    eo_cfg *cfg;
    eo_scene *sc;
    eo_step *st;
    eo_solver *solver;
    eo_solver_opts so;
    eo_objective *obj;
    int solver_n, begun;
} eo_sim;

/* name: built-in scene (NULL: use json); overrides: NULL-terminated "key=value". */
static inline int eo_sim_open(eo_sim *s, eo_ctx *ctx, const char *name, const char *json,
                              const char *const *overrides)
{
    memset(s, 0, sizeof *s);
    s->ctx = ctx;
    int rc = json ? eo_cfg_load(ctx, NULL, json, &s->cfg) : eo_scene_cfg_load(ctx, NULL, name, &s->cfg);
    for (const char *const *o = overrides; rc >= 0 && o && *o; o++) rc = eo_cfg_override(ctx, s->cfg, *o);
    if (rc >= 0) rc = eo_scene_load(ctx, s->cfg, &s->sc);
    eo_solver_opts_default(&s->so);
    if (rc >= 0) rc = eo_solver_opts_load(ctx, s->cfg, &s->so);
    if (rc >= 0) rc = eo_step_create(ctx, s->sc, &s->st);
    if (rc >= 0) rc = eo_step_begin(s->st, &s->obj);
    if (rc >= 0) {
        s->begun = 1;
        s->solver_n = s->obj->n;
        rc = eo_solver_create(ctx, &s->so, s->cfg, s->solver_n, &s->solver);
    }
    if (rc >= 0) rc = eo_cfg_finish(ctx, s->cfg);
    if (rc < 0) fprintf(stderr, "eo_sim_open(%s): %s\n", name ? name : "json", eo_ctx_message(ctx));
    return rc;
}

/* One step; result in *r (may be NULL). Returns the minimize status. */
static inline int eo_sim_step(eo_sim *s, eo_iter_fn cb, void *user, eo_solve_result *r)
{
    eo_solve_result tmp;
    if (!r) r = &tmp;
    int rc = EO_OK;
    if (!s->begun) rc = eo_step_begin(s->st, &s->obj);
    s->begun = 0;
    if (rc < 0) return rc;
    if (s->obj->n != s->solver_n) {
        eo_solver_destroy(&s->solver);
        s->solver_n = s->obj->n;
        rc = eo_solver_create(s->ctx, &s->so, s->cfg, s->solver_n, &s->solver);
        if (rc < 0) return rc;
    }
    double *x = eo_step_guess(s->st);
    rc = eo_solver_minimize(s->solver, s->obj, x, cb, user, r);
    if (rc < 0) return rc;
    return eo_step_end(s->st, x);
}

static inline void eo_sim_close(eo_sim *s)
{
    eo_solver_destroy(&s->solver);
    eo_step_destroy(&s->st);
    eo_scene_destroy(s->ctx, &s->sc);
    eo_cfg_destroy(s->ctx, &s->cfg);
}

/* Mean z displacement of the vertices with rest x >= xmin (the tip of a bar). */
static inline double eo_sim_tip_dz(const eo_sim *s, double xmin)
{
    const eo_mesh *m = eo_step_mesh(s->st);
    const double *x = eo_step_x(s->st);
    double sum = 0;
    int n = 0;
    for (int v = 0; v < m->nv; v++)
        if (m->X[3 * v] >= xmin) {
            sum += x[3 * v + 2] - m->X[3 * v + 2];
            n++;
        }
    return n ? sum / n : 0;
}

#endif
