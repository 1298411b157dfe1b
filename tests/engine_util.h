/* Test helpers around the library's simulation driver (eo_sim, sim.h): open a scene
 * (built-in by name or JSON text) with -o style overrides, step it with a callback, and
 * a few measurements (tip displacement). The protocol itself is eo_sim_step. */
#ifndef EO_TESTS_ENGINE_UTIL_H
#define EO_TESTS_ENGINE_UTIL_H

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

#endif
