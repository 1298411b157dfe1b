/* The simulation driver (sim.h): the one place where the per-step protocol is written.
 *
 *   implicit   begin (objective + guess of step n+1, unless eo_sim_prepare already built
 *              it), minimize with the sim's solver (it re-sizes its workspace itself when
 *              a release changes obj->n), end; if the new state is not finite (‖x‖² or
 *              Σ m‖v‖² overflowing counts) the step is undone: reason
 *              diverged_nonfinite, state back to tₙ.
 *   explicit   eo_step_advance (which rejects a step that meets a non-finite energy or
 *              force at any stage, or ends non-finite, keeping tₙ).
 *   then       per-step statistics (eo_step_stats) of the resulting state.
 *
 * Creation validates the whole configuration (scene, solver section, every method's
 * section, unknown keys) before the step engine is built. For an explicit integrator
 * with consistent mass the mass solve uses the linear solver named by `solver.linear`
 * with its `solver.<name>` parameters (default cholmod). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "elastopt/sim.h"

struct eo_sim {
    eo_ctx *ctx;
    eo_cfg *cfg;
    eo_scene *sc;
    eo_step *st;
    eo_solver *solver;
    eo_iter_fn fn;
    void *user;
    eo_objective *obj;   /* objective of the prepared next step */
    int prepared;        /* obj and the step's guess belong to the current state */
    double *xb, *vb;     /* state before an implicit step (restored if it diverges) */
    double *xyz;         /* rest positions of the free vertices (3 nv), for set_coordinates */
    const eo_solver *coord_solver; /* s->solver was given the coordinates of ... */
    int coord_n;                   /* ... an objective with coord_n free coordinates */
};

/* The mass solver of an explicit integrator: solver.linear with its section's params. */
static int mass_solver(eo_ctx *ctx, eo_cfg *cfg, const char *name, eo_linsolve **out)
{
    *out = NULL;
    const eo_linsolve_type *lt;
    int rc = eo_linsolve_find(ctx, name, &lt);
    if (rc < 0) return rc;
    const eo_method_info *mi = eo_method_info_of(lt);
    void *p = NULL;
    if (mi->params && mi->params_size) {
        p = eo_calloc(ctx, 1, mi->params_size);
        if (!p) return eo_error(ctx, EO_ERR_NOMEM, "sim: out of memory");
        eo_params_default(mi->params, p);
        char path[96];
        snprintf(path, sizeof path, "solver.%s", mi->name);
        rc = eo_cfg_section(ctx, cfg, path, mi->params, p, NULL);
    }
    if (rc >= 0) rc = eo_linsolve_create(ctx, lt, p, out);
    eo_free(ctx, p);
    return rc;
}

int eo_sim_create(eo_ctx *ctx, eo_cfg *cfg, eo_sim **out)
{
    *out = NULL;
    if (!cfg) return eo_error(ctx, EO_ERR_INVALID, "sim: no config document");
    eo_sim *s = eo_calloc(ctx, 1, sizeof *s);
    if (!s) {
        eo_cfg_destroy(&cfg);
        return eo_error(ctx, EO_ERR_NOMEM, "sim: out of memory");
    }
    s->ctx = ctx;
    s->cfg = cfg;
    eo_linsolve *mls = NULL;
    eo_solver_opts so;
    int rc;
    EO_TRY(rc = eo_scene_load(ctx, cfg, &s->sc));
    eo_solver_opts_default(&so);
    EO_TRY(rc = eo_solver_opts_load(ctx, cfg, &so));
    EO_TRY(rc = eo_solver_create(ctx, &so, cfg, &s->solver));
    if (s->sc->integrator->explicit_step && !s->sc->lumped && s->sc->mesh->nt > 0)
        EO_TRY(rc = mass_solver(ctx, cfg, so.linear, &mls));
    EO_TRY(rc = eo_cfg_finish(ctx, cfg));
    /* configuration valid: build the step engine */
    EO_TRY(rc = eo_step_create(ctx, s->sc, &s->st));
    if (mls) {
        eo_step_set_mass_solver(s->st, mls);
        mls = NULL;
    }
    size_t nf = (size_t)(3 * s->sc->mesh->nv > 0 ? 3 * s->sc->mesh->nv : 1);
    s->xb = eo_malloc(ctx, nf * sizeof(double));
    s->vb = eo_malloc(ctx, nf * sizeof(double));
    s->xyz = eo_malloc(ctx, nf * sizeof(double));
    if (!s->xb || !s->vb || !s->xyz) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "sim: out of memory");
        goto fail;
    }
    *out = s;
    return EO_OK;
fail:
    eo_linsolve_destroy(&mls);
    eo_sim_destroy(&s);
    return rc;
}

int eo_sim_create_from(eo_ctx *ctx, const char *path, const char *builtin, const char *const *overrides,
                       eo_sim **out)
{
    *out = NULL;
    eo_cfg *cfg = NULL;
    int rc = eo_scene_cfg_load(ctx, path, builtin, &cfg);
    for (const char *const *o = overrides; rc >= 0 && o && *o; o++) rc = eo_cfg_override(ctx, cfg, *o);
    if (rc < 0) {
        eo_cfg_destroy(&cfg);
        return rc;
    }
    return eo_sim_create(ctx, cfg, out);
}

void eo_sim_destroy(eo_sim **ps)
{
    if (!ps || !*ps) return;
    eo_sim *s = *ps;
    eo_ctx *ctx = s->ctx;
    eo_free(ctx, s->xb);
    eo_free(ctx, s->vb);
    eo_free(ctx, s->xyz);
    eo_solver_destroy(&s->solver);
    eo_step_destroy(&s->st);
    eo_scene_destroy(&s->sc);
    eo_cfg_destroy(&s->cfg);
    eo_free(ctx, s);
    *ps = NULL;
}

void eo_sim_set_iter_callback(eo_sim *s, eo_iter_fn fn, void *user)
{
    s->fn = fn;
    s->user = user;
}

int eo_sim_set_solver(eo_sim *s, const eo_solver_opts *opts, eo_cfg *solver_cfg)
{
    eo_solver *sv = NULL;
    int rc = eo_solver_create(s->ctx, opts, solver_cfg, &sv);
    if (rc < 0) return rc;
    eo_solver_destroy(&s->solver);
    s->solver = sv;
    s->coord_solver = NULL;
    return EO_OK;
}

int eo_sim_prepare(eo_sim *s, eo_objective **obj, double **guess)
{
    if (!s->prepared) {
        int rc = eo_step_begin(s->st, &s->obj);
        if (rc < 0) return rc;
        s->prepared = 1;
    }
    if (obj) *obj = s->obj;
    if (guess) *guess = eo_step_guess(s->st);
    return EO_OK;
}

/* Node coordinates for the linear solver of `solver` (AMG's rigid-body modes,
 * linsolve.h): the rest positions of the free vertices in free order, given again when the
 * free set changes (a release) or the solver is another one. Free coordinates come in
 * vertex triples (constraints act on whole vertices); anything else is left alone. */
static int sim_coordinates(eo_sim *s, eo_solver *solver)
{
    eo_linsolve *ls = eo_solver_get_linsolve(solver);
    const int n = s->obj->n;
    if (!ls || n % 3 != 0) return EO_OK;
    if (solver == s->solver && s->coord_solver == solver && s->coord_n == n) return EO_OK;
    const double *x0 = eo_step_x0(s->st);
    for (int i = 0; i < n; i++) s->xyz[i] = x0[eo_step_free_to_full(s->st, i)];
    int rc = eo_linsolve_set_coordinates(ls, n / 3, s->xyz);
    if (rc < 0) return rc;
    if (solver == s->solver) {
        s->coord_solver = solver;
        s->coord_n = n;
    }
    return EO_OK;
}

int eo_sim_step(eo_sim *s, eo_sim_step_result *r)
{
    eo_sim_step_result tmp;
    if (!r) r = &tmp;
    memset(r, 0, sizeof *r);
    r->g = r->grad_norm = NAN;
    int rc;
    if (eo_step_is_explicit(s->st)) {
        s->prepared = 0;
        double t0 = eo_wtime();
        if ((rc = eo_step_advance(s->st, &r->reason)) < 0) return rc;
        r->time = eo_wtime() - t0;
    } else {
        if ((rc = eo_sim_prepare(s, NULL, NULL)) < 0) return rc;
        s->prepared = 0;
        double *x = eo_step_guess(s->st);
        eo_solve_result sr;
        if ((rc = sim_coordinates(s, s->solver)) < 0) return rc;
        if ((rc = eo_solver_minimize(s->solver, s->obj, x, s->fn, s->user, &sr)) < 0) return rc;
        r->iterations = sr.iterations;
        r->reason = sr.reason;
        r->time = sr.time;
        r->g = sr.g;
        r->grad_norm = sr.grad_norm;
        r->n_value = sr.n_value;
        r->n_gradient = sr.n_gradient;
        r->n_hessian = sr.n_hessian;
        r->n_factor = sr.n_factor;
        const size_t nf = (size_t)(3 * s->sc->mesh->nv) * sizeof(double);
        const double t = eo_step_time(s->st);
        const int index = eo_step_index(s->st);
        memcpy(s->xb, eo_step_x(s->st), nf);
        memcpy(s->vb, eo_step_v(s->st), nf);
        if ((rc = eo_step_end(s->st, x)) < 0) return rc;
        if (!eo_step_state_finite(s->st)) { /* keep the last finite state */
            r->reason = EO_DIVERGED_NONFINITE;
            eo_step_set_state(s->st, s->xb, s->vb, t);
            eo_step_set_index(s->st, index);
        }
    }
    r->t = eo_step_time(s->st);
    return eo_step_stats_compute(s->st, &r->stats);
}

int eo_sim_trial(eo_sim *s, eo_solver *solver, const double *x0, double *x, eo_iter_fn fn, void *user,
                 eo_objective **obj, eo_solve_result *res)
{
    if (eo_step_is_explicit(s->st))
        return eo_error(s->ctx, EO_ERR_UNSUPPORTED, "sim: integrator %s is explicit: no problem to solve",
                        s->sc->integrator->info.name);
    int rc = eo_sim_prepare(s, obj, NULL);
    if (rc < 0) return rc;
    const double *src = x0 ? x0 : eo_step_guess(s->st);
    if (src != x) memmove(x, src, (size_t)s->obj->n * sizeof(double));
    if ((rc = sim_coordinates(s, solver ? solver : s->solver)) < 0) return rc;
    return eo_solver_minimize(solver ? solver : s->solver, s->obj, x, fn, user, res);
}

int eo_sim_reset(eo_sim *s)
{
    s->prepared = 0;
    return eo_step_reset(s->st);
}

void eo_sim_get_state(const eo_sim *s, double *x, double *v, double *t, int *index)
{
    const size_t nf = (size_t)(3 * s->sc->mesh->nv) * sizeof(double);
    if (x) memcpy(x, eo_step_x(s->st), nf);
    if (v) memcpy(v, eo_step_v(s->st), nf);
    if (t) *t = eo_step_time(s->st);
    if (index) *index = eo_step_index(s->st);
}

int eo_sim_set_state(eo_sim *s, const double *x, const double *v, double t, int index)
{
    s->prepared = 0;
    int rc = eo_step_set_state(s->st, x, v, t);
    if (rc >= 0) rc = eo_step_set_index(s->st, index);
    return rc;
}

const eo_scene *eo_sim_scene(const eo_sim *s) { return s->sc; }
eo_step *eo_sim_step_problem(const eo_sim *s) { return s->st; }
eo_solver *eo_sim_solver(const eo_sim *s) { return s->solver; }
eo_cfg *eo_sim_cfg(const eo_sim *s) { return s->cfg; }
double eo_sim_time(const eo_sim *s) { return eo_step_time(s->st); }
int eo_sim_index(const eo_sim *s) { return eo_step_index(s->st); }
int eo_sim_is_explicit(const eo_sim *s) { return eo_step_is_explicit(s->st); }
