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

#include <jansson.h>

#include "elastopt/sim.h"
#include "elastopt/element.h"
#include "elastopt/impl/method.h"
#include "elastopt/registry.h"

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
    double *x0b;         /* where the next fallback entry starts: the step's starting guess,
                            or (fb_best) the best iterate of the entries run so far */
    eo_solver *fb[EO_SIM_MAX_ENTRIES - 1]; /* solver.fallback entries */
    int nfb;
    int fb_best;         /* solver.fallback_start = best (default) */
    int entry;           /* configuration running (or last run) */
    /* adaptive stepping (time.adaptive; see adaptive_step) */
    int adapt;           /* on */
    int adapt_max_level; /* smallest substep dt/2^adapt_max_level (time.adaptive_min_fraction) */
    int adapt_grow_after;
    int adapt_streak;    /* converged substeps in a row */
    double *hb;          /* a multistep integrator's history before a substep (NULL if none) */
    double *xyz;         /* rest positions of the free vertices (3 nv), for set_coordinates */
    const eo_solver *coord_solver; /* s->solver was given the coordinates of ... */
    int coord_n;                   /* ... an objective with coord_n free coordinates */
    /* energy watch (eo_sim_energy_warning) */
    int conservative;    /* scene and integrator keep the total energy */
    double e0;           /* total energy of the initial state */
    double eref0;        /* max(kinetic + elastic + contact at t = 0, m_total |g| L) */
    double wmax;         /* max |work of the prescribed motions| so far */
    double egrowth;      /* largest growth factor warned about (0: none) */
    char ewarn[400];
};

/* Conservative: a dynamic integrator that is not dissipative, and no damping, spring
 * damping or friction in the scene (collisions' penalty contact is a potential). */
static int scene_conservative(const eo_scene *sc)
{
    const eo_integrator_type *it = sc->integrator;
    int diss = it->is_dissipative ? it->is_dissipative(sc->integrator_params) : it->dissipative;
    if (!it->inertia || diss) return 0;
    if (sc->damping.viscous > 0 || sc->damping.rayleigh_alpha > 0 || sc->damping.rayleigh_beta > 0) return 0;
    if (sc->springs.damping > 0) return 0;
    for (int o = 0; o < sc->ncollision; o++)
        if (sc->collision[o].opts.friction > 0) return 0;
    return 1;
}

/* The reference energies of the watch from the current (initial) state. */
static int energy_watch_init(eo_sim *s)
{
    eo_step_stats st;
    int rc = eo_step_stats_compute(s->st, &st);
    if (rc < 0) return rc;
    s->conservative = scene_conservative(s->sc);
    s->e0 = st.total_energy;
    const eo_mesh *m = s->sc->mesh;
    const double *mass = eo_step_vertex_mass(s->st), *g = s->sc->opts.gravity;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, mt = 0;
    for (int v = 0; v < m->nv; v++) {
        mt += mass[v];
        for (int c = 0; c < 3; c++) lo[c] = fmin(lo[c], m->X[3 * v + c]), hi[c] = fmax(hi[c], m->X[3 * v + c]);
    }
    double L2 = 0;
    for (int c = 0; c < 3 && m->nv > 0; c++) L2 += (hi[c] - lo[c]) * (hi[c] - lo[c]);
    const double gscale = mt * sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) * sqrt(L2);
    s->eref0 = fmax(st.kinetic + st.elastic + st.contact, gscale);
    s->wmax = fabs(st.work_prescribed);
    s->egrowth = 0;
    s->ewarn[0] = 0;
    return EO_OK;
}

/* After a step: warn (eo_log, once per new maximum) when the total energy of a
 * conservative scene exceeds its initial value by more than (EO_SIM_ENERGY_GROWTH − 1)
 * times the reference energy. */
static void energy_watch(eo_sim *s, const eo_step_stats *st, int index)
{
    if (!s->conservative || !isfinite(st->total_energy)) return;
    s->wmax = fmax(s->wmax, fabs(st->work_prescribed));
    const double ref = fmax(s->eref0, s->wmax);
    if (!(ref > 0)) return;
    const double growth = 1.0 + (st->total_energy - s->e0) / ref;
    if (!(growth > EO_SIM_ENERGY_GROWTH) || growth <= s->egrowth) return;
    const char *name = s->sc->integrator->info.name;
    const char *advice = s->sc->integrator->explicit_step
                             ? "reduce time.dt or use an implicit integrator (implicit_midpoint, generalized_alpha)"
                         : strcmp(name, "newmark") == 0
                             ? "try implicit_midpoint or generalized_alpha"
                             : "try generalized_alpha with time.generalized_alpha.rho_inf < 1, or a smaller time.dt";
    const int first = s->egrowth == 0;
    s->egrowth = growth;
    snprintf(s->ewarn, sizeof s->ewarn,
             "total energy grew x%.3g in %d steps with integrator %s (from %.6g J to %.6g J, reference %.6g J; not "
             "energy-stable on this scene: %s)",
             growth, index, name, s->e0, st->total_energy, ref, advice);
    if (first) eo_log(s->ctx, EO_LOG_WARN, "%s", s->ewarn);
}

const char *eo_sim_energy_warning(const eo_sim *s) { return s->ewarn[0] ? s->ewarn : NULL; }
int eo_sim_energy_conservative(const eo_sim *s) { return s->conservative; }

static void fallback_clear(eo_solver **fb, int *nfb)
{
    for (int i = 0; i < *nfb; i++) eo_solver_destroy(&fb[i]);
    *nfb = 0;
}

/* The default fallback chain of a scene's solver (EO_SIM_DEFAULT_FALLBACK, sim.h): used
 * when the scene names no `solver.fallback` (an explicit [] turns it off), also with
 * solver.backend = petsc (its entries run distributed like the first). Measured choice: docs/defaults.md, "Defaults that converge". */
static const char default_fallback[] = EO_SIM_DEFAULT_FALLBACK;

/* The solvers of cfg's `solver.fallback` (each entry merged over the `solver` section),
 * validated like the main one; the list is consumed in cfg. cfg NULL or no list: none,
 * or with use_default the default chain. *best: `solver.fallback_start` is "best" (the
 * default) rather than "guess". */
static int fallback_load(eo_ctx *ctx, eo_cfg *cfg, eo_solver **fb, int *nfb, int use_default, int *best)
{
    *nfb = 0;
    *best = 1;
    if (!cfg) return EO_OK;
    /* read without marking `solver` consumed whole (its keys are checked by its loads) */
    json_t *main_sec = json_object_get(eo_cfg_root(cfg), "solver");
    json_t *from = json_is_object(main_sec) ? json_object_get(main_sec, "fallback_start") : NULL;
    if (from) {
        eo_cfg_consume(cfg, "solver.fallback_start");
        const char *v = json_is_string(from) ? json_string_value(from) : NULL;
        if (!v || (strcmp(v, "best") && strcmp(v, "guess")))
            return eo_error(ctx, EO_ERR_TYPE,
                            "%s: key 'solver.fallback_start': expected \"best\" or \"guess\" (where a fallback "
                            "entry starts: the best iterate so far, or the step's starting guess)",
                            eo_cfg_file(cfg));
        *best = strcmp(v, "best") == 0;
    }
    json_t *list = json_is_object(main_sec) ? json_object_get(main_sec, "fallback") : NULL;
    json_t *deflist = NULL;
    if (!list) {
        if (!use_default) return EO_OK;
        if (!(list = deflist = json_loads(default_fallback, 0, NULL)))
            return eo_error(ctx, EO_ERR_NOMEM, "sim: out of memory");
    }
    if (!deflist) eo_cfg_consume(cfg, "solver.fallback");
    if (!json_is_array(list) || json_array_size(list) > EO_SIM_MAX_ENTRIES - 1)
        return eo_error(ctx, EO_ERR_TYPE, "%s: key 'solver.fallback': expected a list of at most %d solver sections",
                        eo_cfg_file(cfg), EO_SIM_MAX_ENTRIES - 1);
    int rc = EO_OK;
    size_t i;
    json_t *item;
    json_array_foreach(list, i, item) {
        if (!json_is_object(item)) {
            rc = eo_error(ctx, EO_ERR_TYPE, "%s: key 'solver.fallback.%zu': expected an object (a solver section)",
                          eo_cfg_file(cfg), i);
            break;
        }
        eo_cfg *ec = NULL;
        if ((rc = eo_cfg_create_empty(ctx, &ec)) < 0) break;
        json_t *merged = json_deep_copy(main_sec);
        if (!merged) merged = json_object();
        json_object_del(merged, "fallback");
        json_object_del(merged, "fallback_start");
        if (!merged || json_object_update_recursive(merged, item) < 0 ||
            json_object_set_new(eo_cfg_root(ec), "solver", merged) < 0) {
            eo_cfg_destroy(&ec);
            rc = eo_error(ctx, EO_ERR_NOMEM, "sim: out of memory");
            break;
        }
        eo_solver_opts o;
        eo_solver_opts_default(&o);
        rc = eo_solver_opts_load(ctx, ec, &o);
        if (rc >= 0) rc = eo_solver_create(ctx, &o, ec, &fb[*nfb]);
        if (rc >= 0) {
            ++*nfb;
            rc = eo_cfg_finish(ctx, ec);
        }
        eo_cfg_destroy(&ec);
        if (rc < 0) {
            char msg[600];
            snprintf(msg, sizeof msg, "%s", eo_ctx_message(ctx));
            rc = eo_error(ctx, rc, "%s: solver.fallback.%zu: %s", eo_cfg_file(cfg), i, msg);
            break;
        }
    }
    json_decref(deflist);
    if (rc < 0) fallback_clear(fb, nfb);
    return rc;
}

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

/* An optimizer that needs per-tet operations of the linear tet (needs_ops: the split
 * F = D x, the vertex blocks) on a scene whose element has none, or a scene without
 * contact (EO_OBJ_NEEDS_NO_CONTACT) on one with collisions: refused before anything is
 * built or written. `what` names the entry (solver, solver.fallback.N). */
static int check_element(eo_ctx *ctx, const eo_scene *sc, const eo_solver *sv, const char *what)
{
    const eo_optimizer_type *t = NULL;
    if (eo_registry_find(ctx, EO_KIND_OPTIMIZER, eo_solver_get_opts(sv)->optimizer, (const void **)&t) < 0)
        return EO_OK;
    if ((t->needs_ops & EO_OBJ_NEEDS_NO_CONTACT) && sc->ncollision > 0)
        return eo_error(ctx, EO_ERR_INVALID,
                        "%s: optimizer %s refuses the scene's collisions: contact is outside its split "
                        "(pd_local_global, lbfgs or newton take it)",
                        what, t->info.name);
    if (!sc->element || (sc->element->flags & EO_ELEMENT_LINEAR) ||
        !(t->needs_ops & (EO_OBJ_NEEDS_SPLIT | EO_OBJ_NEEDS_VERTEX | EO_OBJ_NEEDS_PARTS)))
        return EO_OK;
    return eo_error(ctx, EO_ERR_INVALID,
                    "%s: optimizer %s needs %s, which element %s does not have (they assume one deformation "
                    "gradient per 4-node tet): use element p1 or another optimizer",
                    what, t->info.name,
                    t->needs_ops & EO_OBJ_NEEDS_SPLIT    ? "the per-tet split F = D x"
                    : t->needs_ops & EO_OBJ_NEEDS_VERTEX ? "per-vertex blocks"
                                                         : "the distributed evaluation of linear tets (PETSc backend)",
                    sc->element->info.name);
}

static int check_elements(eo_ctx *ctx, const eo_scene *sc, const eo_solver *sv, eo_solver *const *fb, int nfb)
{
    int rc = check_element(ctx, sc, sv, "solver");
    for (int i = 0; rc >= 0 && i < nfb; i++) {
        char what[48];
        snprintf(what, sizeof what, "solver.fallback.%d", i);
        rc = check_element(ctx, sc, fb[i], what);
    }
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
    EO_TRY(rc = fallback_load(ctx, cfg, s->fb, &s->nfb, !s->sc->integrator->explicit_step, &s->fb_best));
    if (s->sc->integrator->explicit_step && !s->sc->lumped && s->sc->mesh->nt > 0)
        EO_TRY(rc = mass_solver(ctx, cfg, so.linear, &mls));
    EO_TRY(rc = eo_cfg_finish(ctx, cfg));
    EO_TRY(rc = check_elements(ctx, s->sc, s->solver, s->fb, s->nfb));
    /* configuration valid: build the step engine */
    EO_TRY(rc = eo_step_create(ctx, s->sc, &s->st));
    if (mls) {
        eo_step_set_mass_solver(s->st, mls);
        mls = NULL;
    }
    size_t nf = (size_t)(3 * s->sc->mesh->nv > 0 ? 3 * s->sc->mesh->nv : 1);
    s->xb = eo_malloc(ctx, nf * sizeof(double));
    s->vb = eo_malloc(ctx, nf * sizeof(double));
    s->x0b = s->nfb ? eo_malloc(ctx, nf * sizeof(double)) : NULL;
    s->xyz = eo_malloc(ctx, nf * sizeof(double));
    const size_t hlen = eo_step_history_len(s->st);
    s->hb = hlen ? eo_malloc(ctx, hlen * sizeof(double)) : NULL;
    if (!s->xb || !s->vb || (s->nfb && !s->x0b) || !s->xyz || (hlen && !s->hb)) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "sim: out of memory");
        goto fail;
    }
    EO_TRY(rc = energy_watch_init(s));
    s->adapt = s->sc->time.adaptive;
    s->adapt_grow_after = s->sc->time.adaptive_grow_after;
    while (s->adapt_max_level < EO_STEP_MAX_SUBSTEP &&
           ldexp(1.0, -(s->adapt_max_level + 1)) >= s->sc->time.adaptive_min_fraction)
        s->adapt_max_level++;
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
    eo_free(ctx, s->x0b);
    eo_free(ctx, s->hb);
    fallback_clear(s->fb, &s->nfb);
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

int eo_sim_check_solver(eo_sim *s, const eo_solver *sv) { return check_element(s->ctx, s->sc, sv, "solver"); }

int eo_sim_set_solver(eo_sim *s, const eo_solver_opts *opts, eo_cfg *solver_cfg)
{
    eo_solver *sv = NULL, *fb[EO_SIM_MAX_ENTRIES - 1];
    int nfb = 0, best = 1;
    int rc = eo_solver_create(s->ctx, opts, solver_cfg, &sv);
    if (rc < 0) return rc;
    if ((rc = fallback_load(s->ctx, solver_cfg, fb, &nfb, 0, &best)) < 0) {
        eo_solver_destroy(&sv);
        return rc;
    }
    if ((rc = check_elements(s->ctx, s->sc, sv, fb, nfb)) < 0) {
        fallback_clear(fb, &nfb);
        eo_solver_destroy(&sv);
        return rc;
    }
    double *x0b = NULL;
    if (nfb && !s->x0b) {
        x0b = eo_malloc(s->ctx, (size_t)(3 * s->sc->mesh->nv > 0 ? 3 * s->sc->mesh->nv : 1) * sizeof(double));
        if (!x0b) {
            fallback_clear(fb, &nfb);
            eo_solver_destroy(&sv);
            return eo_error(s->ctx, EO_ERR_NOMEM, "sim: out of memory");
        }
        s->x0b = x0b;
    }
    eo_solver_destroy(&s->solver);
    s->solver = sv;
    fallback_clear(s->fb, &s->nfb);
    for (int i = 0; i < nfb; i++) s->fb[i] = fb[i];
    s->nfb = nfb;
    s->fb_best = best;
    s->coord_solver = NULL;
    return EO_OK;
}

int eo_sim_entry(const eo_sim *s) { return s->entry; }
int eo_sim_n_fallback(const eo_sim *s) { return s->nfb; }

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

/* One run of a solver within a step: its reason, g and ‖∇g‖ become the step's, its time
 * and evaluations add up (the caller sets the iterations). */
static void add_run(eo_sim_step_result *r, const eo_solve_result *sr)
{
    r->reason = sr->reason;
    r->time += sr->time;
    r->cpu_time += sr->cpu_time;
    r->g = sr->g;
    r->grad_norm = sr->grad_norm;
    r->n_value += sr->n_value;
    r->n_gradient += sr->n_gradient;
    r->n_hessian += sr->n_hessian;
    r->n_factor += sr->n_factor;
    r->n_not_pd += sr->n_not_pd;
}

/* A fallback entry that converged by the metric gradient measure (its optimizer has no
 * Newton decrement: newton_tr, lbfgs, ...) while the scene's solver measures by the
 * decrement: the two ratios are relative to different references, and at a tangled start
 * a gradient ratio of 1e-10 was accepted with λ/λ₀ = 2.8e-7. The scene's solver then
 * continues from x against the step's references (its own first decrement included) and
 * decides: usually 1–3 Newton iterations; if it does not converge, neither does the step
 * (the chain's reason is then the scene's solver's). r gets its cost; its iterations add to
 * the kept run's (entry_iterations keep the entry's own). */
static int confirm(eo_sim *s, eo_solver *entry, double *x, double ref_dec0, double ref_gm0, eo_sim_step_result *r)
{
    double d0, gm0, de, ge;
    eo_solver_get_reference(s->solver, &d0, &gm0);
    eo_solver_get_reference(entry, &de, &ge);
    if (!eo_solver_measures_decrement(s->solver) || eo_solver_measures_decrement(entry) || !(isfinite(d0) && d0 > 0))
        return EO_OK; /* the same measure, or no first decrement to compare with */
    if (d0 > ref_dec0) ref_dec0 = d0;
    if (isfinite(ge) && ge > ref_gm0) ref_gm0 = ge;
    eo_solver_set_reference(s->solver, ref_dec0, ref_gm0);
    int rc;
    if ((rc = sim_coordinates(s, s->solver)) < 0) return rc;
    eo_solve_result sr;
    if ((rc = eo_solver_minimize(s->solver, s->obj, x, s->fn, s->user, &sr)) < 0) return rc;
    r->iterations += sr.iterations;
    add_run(r, &sr);
    return EO_OK;
}

/* Solve the prepared step from x (in place, obj->n values) with `solver`, then while it
 * has not converged with the fallback entries. With solver.fallback_start = guess each
 * entry starts from the step's starting guess; with best (the default) from the best
 * iterate so far: the point of lowest g among the starting guess and the end points of
 * the entries that ran (every optimizer of the chain ends a failed run at its last
 * accepted iterate, which for the descent methods and newton_tr is also its lowest;
 * a non-finite or higher end point is not kept), and measures convergence against the
 * step's references (eo_solver_set_reference: the largest first decrement and initial
 * metric gradient norm of the entries so far), not against its own start's. The
 * starting guess's g is evaluated only when the first entry fails. r gets the chain, the
 * kept run's iterations, reason, g and ‖∇g‖, and adds the time and evaluations of every
 * run. */
static int solve_chain(eo_sim *s, double *x, eo_sim_step_result *r)
{
    int rc;
    const size_t nx = (size_t)s->obj->n * sizeof(double);
    double g_best = NAN;
    if (s->nfb) memcpy(s->x0b, x, nx);
    double ref_dec0 = 0, ref_gm0 = 0; /* the step's references, for entries that continue */
    for (int e = 0; e <= s->nfb; e++) {
        eo_solve_result sr;
        if (e > 0) memcpy(x, s->x0b, nx); /* the step's starting guess or the best iterate */
        s->entry = e;
        eo_solver *sv = e ? s->fb[e - 1] : s->solver;
        if (e > 0 && s->fb_best) eo_solver_set_reference(sv, ref_dec0, ref_gm0);
        if ((rc = sim_coordinates(s, sv)) < 0) return rc;
        if ((rc = eo_solver_minimize(sv, s->obj, x, s->fn, s->user, &sr)) < 0) return rc;
        r->entry = e;
        r->n_entries = e + 1;
        r->entry_reason[e] = sr.reason;
        r->entry_iterations[e] = sr.iterations;
        r->iterations = sr.iterations;
        add_run(r, &sr);
        if (sr.reason == EO_DIVERGED_EXTERNAL) break;
        if (sr.reason >= 0) {
            if (e > 0 && s->fb_best && (rc = confirm(s, sv, x, ref_dec0, ref_gm0, r)) < 0) return rc;
            break;
        }
        if (s->fb_best && e < s->nfb) {
            double d0, gm0;
            eo_solver_get_reference(sv, &d0, &gm0);
            if (d0 > ref_dec0) ref_dec0 = d0;
            if (gm0 > ref_gm0) ref_gm0 = gm0;
            if (e == 0) {
                double t0 = eo_wtime(), c0 = eo_cputime();
                if ((rc = eo_objective_value(s->obj, s->x0b, &g_best)) < 0) return rc;
                eo_ctx_reduce(s->ctx, &g_best, 1, EO_REDUCE_SUM); /* a distributed run: the parts' g */
                r->time += eo_wtime() - t0;
                r->cpu_time += eo_cputime() - c0;
                r->n_value++;
            }
            if (isfinite(sr.g) && !(sr.g >= g_best)) {
                memcpy(s->x0b, x, nx);
                g_best = sr.g;
            }
        }
    }
    return EO_OK;
}

/* Accept x as the new state (eo_step_end) and check it: a non-finite state is undone
 * (positions, velocities, time, index; with `whole`, also the substep progress and a
 * multistep integrator's history) and *finite = 0. */
static int accept(eo_sim *s, const double *x, int whole, int *finite)
{
    const size_t nf = (size_t)(3 * s->sc->mesh->nv) * sizeof(double);
    const double t = eo_step_time(s->st);
    const int index = eo_step_index(s->st);
    const double work = eo_step_work_prescribed(s->st);
    eo_step_substep ss;
    int rc;
    memcpy(s->xb, eo_step_x(s->st), nf);
    memcpy(s->vb, eo_step_v(s->st), nf);
    if (whole) {
        eo_step_get_substep(s->st, &ss);
        if (s->hb && (rc = eo_step_get_history(s->st, s->hb)) < 0) return rc;
    }
    if ((rc = eo_step_end(s->st, x)) < 0) return rc;
    *finite = eo_step_state_finite(s->st);
    if (!*finite) { /* keep the last finite state */
        eo_step_set_state(s->st, s->xb, s->vb, t);
        eo_step_set_index(s->st, index);
        eo_step_set_work_prescribed(s->st, work);
        if (whole && (rc = eo_step_set_substep(s->st, &ss)) < 0) return rc;
        if (whole && s->hb && (rc = eo_step_set_history(s->st, s->hb)) < 0) return rc;
    }
    return EO_OK;
}

static void add_cost(eo_sim_step_result *r, const eo_sim_step_result *a)
{
    r->time += a->time;
    r->cpu_time += a->cpu_time;
    r->n_value += a->n_value;
    r->n_gradient += a->n_gradient;
    r->n_hessian += a->n_hessian;
    r->n_factor += a->n_factor;
    r->n_not_pd += a->n_not_pd;
}

static void copy_chain(eo_sim_step_result *r, const eo_sim_step_result *a)
{
    r->entry = a->entry;
    r->n_entries = a->n_entries;
    memcpy(r->entry_reason, a->entry_reason, sizeof r->entry_reason);
    memcpy(r->entry_iterations, a->entry_iterations, sizeof r->entry_iterations);
}

/* The next substeps at half the size (an attempt was rejected). */
static int halve(eo_sim *s, eo_step_substep *ss)
{
    ss->level++;
    s->adapt_streak = 0;
    return eo_step_set_substep(s->st, ss);
}

/* Adaptive stepping (time.adaptive): the nominal step tₙ → tₙ + dt in substeps of
 * dt/2^k (eo_step_set_substep; k persists between steps). Each substep is solved with the
 * solver and its fallback chain; one that does not converge (or whose new state is not
 * finite) is rejected and tried again from the same state with k + 1, down to k =
 * adapt_max_level, where it is accepted as it is (not converged, like a step without
 * adaptive stepping; a non-finite one is undone and ends the step with
 * diverged_nonfinite). After adapt_grow_after converged substeps in a row k drops by one
 * (the size doubles) where the progress allows it (a multiple of the doubled size, so
 * that the substeps still end on tₙ + dt). A callback stop (diverged_external) is
 * accepted at once and ends the call, possibly inside the nominal step (the next call
 * completes it). With adaptive stepping off (eo_sim_set_adaptive) but a level left, the
 * nominal step is completed at that level and the next ones are nominal. */
static int adaptive_step(eo_sim *s, eo_sim_step_result *r)
{
    eo_step *st = s->st;
    eo_step_substep ss;
    int rc, failed = 0;
    r->min_substep = INFINITY;
    r->reason = EO_CONVERGED_EXPLICIT; /* replaced by the first substep's */
    for (;;) {
        eo_step_get_substep(st, &ss);
        r->min_substep = fmin(r->min_substep, ldexp(s->sc->time.dt, -ss.level));
        if ((rc = eo_sim_prepare(s, NULL, NULL)) < 0) return rc;
        s->prepared = 0;
        double *x = eo_step_guess(st);
        eo_sim_step_result a;
        memset(&a, 0, sizeof a);
        if ((rc = solve_chain(s, x, &a)) < 0) return rc;
        add_cost(r, &a);
        copy_chain(r, &a);
        const int conv = a.reason >= 0, ext = a.reason == EO_DIVERGED_EXTERNAL;
        const int can_halve = s->adapt && ss.level < s->adapt_max_level && !ext;
        if (!conv && can_halve) {
            r->rejected++;
            if ((rc = halve(s, &ss)) < 0) return rc;
            continue;
        }
        int finite;
        if ((rc = accept(s, x, 1, &finite)) < 0) return rc;
        if (!finite) {
            if (can_halve) {
                r->rejected++;
                if ((rc = halve(s, &ss)) < 0) return rc;
                continue;
            }
            r->reason = EO_DIVERGED_NONFINITE;
            r->g = a.g;
            r->grad_norm = a.grad_norm;
            return EO_OK;
        }
        r->substeps++;
        r->iterations += a.iterations;
        r->g = a.g;
        r->grad_norm = a.grad_norm;
        if (!failed) r->reason = a.reason; /* the first that failed, else the last */
        failed |= !conv;
        s->adapt_streak = conv ? s->adapt_streak + 1 : 0;
        if (ext) return EO_OK;
        eo_step_get_substep(st, &ss);
        if (s->adapt && ss.level > 0 && s->adapt_streak >= s->adapt_grow_after) {
            const double q = ldexp(ss.done, ss.level - 1); /* the doubled size fits */
            if (q == floor(q)) {
                ss.level--;
                s->adapt_streak = 0;
                if ((rc = eo_step_set_substep(st, &ss)) < 0) return rc;
            }
        }
        if (ss.done == 0) break; /* the nominal step is complete */
    }
    if (!s->adapt && ss.level > 0) {
        ss.level = 0;
        if ((rc = eo_step_set_substep(st, &ss)) < 0) return rc;
    }
    return EO_OK;
}

int eo_sim_step(eo_sim *s, eo_sim_step_result *r)
{
    eo_sim_step_result tmp;
    if (!r) r = &tmp;
    memset(r, 0, sizeof *r);
    r->g = r->grad_norm = NAN;
    r->min_substep = s->sc->time.dt;
    int rc;
    if (eo_step_is_explicit(s->st)) {
        s->prepared = 0;
        double t0 = eo_wtime(), c0 = eo_cputime();
        if ((rc = eo_step_advance(s->st, &r->reason)) < 0) return rc;
        r->time = eo_wtime() - t0;
        r->cpu_time = eo_cputime() - c0;
        s->entry = 0;
        r->n_entries = 1;
        r->entry_reason[0] = r->reason;
        r->substeps = r->reason != EO_DIVERGED_NONFINITE;
    } else {
        eo_step_substep ss;
        eo_step_get_substep(s->st, &ss);
        if (s->adapt || ss.level || ss.done > 0) {
            if ((rc = adaptive_step(s, r)) < 0) return rc;
        } else {
            if ((rc = eo_sim_prepare(s, NULL, NULL)) < 0) return rc;
            s->prepared = 0;
            double *x = eo_step_guess(s->st);
            if ((rc = solve_chain(s, x, r)) < 0) return rc;
            int finite;
            if ((rc = accept(s, x, 0, &finite)) < 0) return rc;
            if (!finite) r->reason = EO_DIVERGED_NONFINITE;
            r->substeps = finite;
        }
    }
    r->t = eo_step_time(s->st);
    if ((rc = eo_step_stats_compute(s->st, &r->stats)) < 0) return rc;
    if (r->reason != EO_DIVERGED_NONFINITE) energy_watch(s, &r->stats, eo_step_index(s->st));
    return EO_OK;
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
    s->adapt_streak = 0;
    int rc = eo_step_reset(s->st);
    return rc < 0 ? rc : energy_watch_init(s);
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
    s->adapt_streak = 0;
    int rc = eo_step_set_state(s->st, x, v, t);
    if (rc >= 0) rc = eo_step_set_index(s->st, index);
    return rc;
}

size_t eo_sim_history_len(const eo_sim *s) { return eo_step_history_len(s->st); }
int eo_sim_get_history(const eo_sim *s, double *h) { return eo_step_get_history(s->st, h); }
int eo_sim_set_history(eo_sim *s, const double *h)
{
    s->prepared = 0;
    return eo_step_set_history(s->st, h);
}

int eo_sim_adaptive(const eo_sim *s) { return s->adapt; }

int eo_sim_set_adaptive(eo_sim *s, int on)
{
    if (on && eo_step_is_explicit(s->st))
        return eo_error(s->ctx, EO_ERR_UNSUPPORTED, "sim: integrator %s is explicit: no adaptive stepping",
                        s->sc->integrator->info.name);
    s->adapt = on != 0;
    eo_step_substep ss;
    eo_step_get_substep(s->st, &ss);
    if (!on && ss.level && ss.done == 0) { /* at a nominal boundary: nominal steps from now on */
        ss.level = 0;
        s->prepared = 0;
        return eo_step_set_substep(s->st, &ss);
    }
    return EO_OK;
}

void eo_sim_get_adaptive_state(const eo_sim *s, int *level, int *streak)
{
    eo_step_substep ss = {0};
    if (!eo_step_is_explicit(s->st)) eo_step_get_substep(s->st, &ss);
    if (level) *level = ss.level;
    if (streak) *streak = s->adapt_streak;
}

int eo_sim_set_adaptive_state(eo_sim *s, int level, int streak)
{
    if (streak < 0) return eo_error(s->ctx, EO_ERR_RANGE, "sim: adaptive streak %d < 0", streak);
    if (eo_step_is_explicit(s->st)) {
        if (level == 0) {
            s->adapt_streak = streak;
            return EO_OK;
        }
        return eo_error(s->ctx, EO_ERR_UNSUPPORTED, "sim: integrator %s is explicit: no substeps",
                        s->sc->integrator->info.name);
    }
    eo_step_substep ss;
    eo_step_get_substep(s->st, &ss);
    ss.level = level;
    int rc = eo_step_set_substep(s->st, &ss);
    if (rc < 0) return rc;
    s->prepared = 0;
    s->adapt_streak = streak;
    return EO_OK;
}

const eo_scene *eo_sim_scene(const eo_sim *s) { return s->sc; }
eo_step *eo_sim_step_problem(const eo_sim *s) { return s->st; }
eo_solver *eo_sim_solver(const eo_sim *s) { return s->solver; }
eo_cfg *eo_sim_cfg(const eo_sim *s) { return s->cfg; }
double eo_sim_time(const eo_sim *s) { return eo_step_time(s->st); }
int eo_sim_index(const eo_sim *s) { return eo_step_index(s->st); }
int eo_sim_is_explicit(const eo_sim *s) { return eo_step_is_explicit(s->st); }
