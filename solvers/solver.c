/* The solver object: resolves the method names of eo_solver_opts through the
 * registries, loads each method's params from config section `solver.<name>`, owns the
 * optimizer state and the linear solver, and runs minimize. Also eo_solver_report, the
 * per-iteration reporting helper shared by the optimizers. */
#include "elastopt/impl/method.h"
#include "solver_registry.h"
#include "dist_objective.h"

#include <float.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* The kinds whose methods live in config section solver.<name>, by slot of type[] and
 * params[] (the optimizer first: it decides whether a linear solver is needed). */
enum { SLOT_OPT, SLOT_HESSFIX, SLOT_LINESEARCH, SLOT_STOP, SLOT_LINEAR, N_KINDS };
static eo_registry *const solver_regs[N_KINDS] = {
    [SLOT_OPT] = &eo_reg_optimizer, [SLOT_HESSFIX] = &eo_reg_hessfix,
    [SLOT_LINESEARCH] = &eo_reg_linesearch, [SLOT_STOP] = &eo_reg_stop, [SLOT_LINEAR] = &eo_reg_linsolve};

struct eo_solver {
    eo_ctx *ctx;
    eo_solver_opts opts;
    int n;                      /* size the optimizer state is set up for (-1: not yet) */
    const void *type[N_KINDS];  /* selected ops table per kind (linear: NULL if unused) */
    void *params[N_KINDS];      /* their params (NULL if none) */
    void *opt_state;
    int opt_set_up;
    void *hf_state;             /* the Hessian fix's state (NULL: none) */
    int hf_set_up;
    eo_linsolve *linear;
    eo_profile prof;            /* accumulated over the minimizations (eo_solver_get_profile) */
    struct eo_stop_state *stop; /* the convergence measure's state (eo_solver_stop_check) */
    double ref_dec0, ref_gm0;   /* eo_solver_set_reference for the next minimization (0: none) */
};

/* The convergence measure of one minimization (solver.h, eo_solver_stop_check): the
 * inverse metric and what was measured at x₀. Sized with the optimizer's workspace. */
struct eo_stop_state {
    int n, begun;
    double *dinv;              /* n: 1/Dᵢ of the objective's metric (1 where it has none) */
    double g0, gm0, floor_dec, floor_grad, g_scale;
    double grad_char;          /* the objective's characteristic gradient norm (0: none) */
    double gm_last;            /* ‖∇g‖_{D⁻¹} of the last call with a gradient (same iterate) */
    double ref_dec0, ref_gm0;  /* references given for this minimization (0: none) */
    double dec0_used, gm0_used; /* the references measured against (eo_solver_get_reference) */
};

static const char *const linesearch_auto[] = {"auto", NULL};
static const char *const backend_names[] = {"native", "petsc", NULL};

#define OPTS_STR(field) .size = sizeof(((eo_solver_opts *)0)->field)

const eo_param_desc eo_solver_opts_desc[] = {
    {.key = "optimizer", .kind = EO_PARAM_METHOD, .offset = offsetof(eo_solver_opts, optimizer),
     OPTS_STR(optimizer), .def.s = "newton", .registry = &eo_reg_optimizer,
     .help = "optimizer minimizing each step problem"},
    {.key = "hessian_fix", .kind = EO_PARAM_METHOD, .offset = offsetof(eo_solver_opts, hessian_fix),
     OPTS_STR(hessian_fix), .def.s = "project_on_demand", .registry = &eo_reg_hessfix,
     .help = "how Newton makes its Hessian positive definite"},
    {.key = "linesearch", .kind = EO_PARAM_METHOD, .offset = offsetof(eo_solver_opts, linesearch),
     OPTS_STR(linesearch), .def.s = "auto", .registry = &eo_reg_linesearch, .choices = linesearch_auto,
     .help = "line search along each direction; auto = the optimizer's choice (wolfe for lbfgs and ncg, barrier_filter "
             "for bcqn, none for newton_tr, else backtracking)"},
    {.key = "stop", .kind = EO_PARAM_METHOD, .offset = offsetof(eo_solver_opts, stop),
     OPTS_STR(stop), .def.s = "relative_decrement", .registry = &eo_reg_stop,
     .help = "stopping rule (reads tol)"},
    {.key = "linear", .kind = EO_PARAM_METHOD, .offset = offsetof(eo_solver_opts, linear),
     OPTS_STR(linear), .def.s = "auto", .registry = &eo_reg_linsolve,
     .help = "linear solver for Newton systems and the consistent-mass solve of explicit integrators; auto = "
             "the policy by size (solver.auto: cholmod, a reused factor preconditioning CG, multigrid)"},
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_solver_opts, tol), .def.d = 1e-10,
     .min = 0, .range = EO_RANGE_POSITIVE,
     .help = "relative_decrement: lambda <= tol*lambda_0; newton_decrement: lambda^2/2 <= tol (units of g); "
             "gradient: relative reduction"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(eo_solver_opts, max_iters),
     .def.i = 100, .min = 0, .max = 100000000, .range = EO_RANGE_CLOSED,
     .help = "iteration cap per minimization (reason diverged_max_iters)"},
    {.key = "time_budget", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_solver_opts, time_budget),
     .def.d = 0, .min = 0, .range = EO_RANGE_MIN, .help = "seconds per minimization, 0 = none"},
    {.key = "backend", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_solver_opts, backend), OPTS_STR(backend),
     .def.s = "native", .choices = backend_names,
     .help = "native, or petsc: the optimizer distributed over MPI ranks by the PETSc backend (the library's "
             "optimizer on the ranks' parts, linear solver auto = petsc_ksp; snes_* and tao_* as they are); needs a "
             "build with -Dpetsc"},
    {.key = "carry_linear", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_solver_opts, carry_linear), .def.i = 0,
     .help = "keep the linear solver's reused factor / AMG interpolation from one time step to the next: fewer "
             "factorizations, but a step depends on the steps before it and --restart is no longer bit for bit "
             "(false: forgotten at every minimization)"},
    {0},
};

void eo_solver_opts_default(eo_solver_opts *o) { eo_params_default(eo_solver_opts_desc, o); }

static double metric_norm(const struct eo_stop_state *st, const eo_vspace *vs, const double *v)
{
    double s = 0;
    for (int i = 0; i < st->n; i++)
        if (!vs || vs->own[i]) s += v[i] * v[i] * st->dinv[i];
    eo_vreduce(vs, &s, 1, EO_REDUCE_SUM);
    return sqrt(s);
}

/* The measure at x₀ (first call of a minimization): the metric, g₀, ‖∇g₀‖_{D⁻¹}, the
 * rounding floors EO_STOP_FLOOR·ε²·s of the objective's rounding scales s and its
 * characteristic gradient norm (characteristic_gradient). */
static void stop_begin(const eo_solver_ctx *sc, struct eo_stop_state *st, const eo_stop_info *si, const double *x,
                       const double *grad)
{
    eo_objective *obj = sc->obj;
    int ok = obj->ops->metric_diag && obj->ops->metric_diag(obj->data, st->dinv) >= 0;
    for (int i = 0; ok && i < st->n; i++) ok = isfinite(st->dinv[i]) && st->dinv[i] > 0;
    if (obj->space) { /* every part the same choice */
        double o = ok;
        eo_vreduce(obj->space, &o, 1, EO_REDUCE_MIN);
        ok = o == 1;
    }
    for (int i = 0; i < st->n; i++) st->dinv[i] = ok ? 1 / st->dinv[i] : 1;
    st->g0 = si->g;
    st->gm0 = st->gm_last = grad ? metric_norm(st, obj->space, grad) : NAN;
    double rs[3] = {0, 0, 0};
    const double e2 = DBL_EPSILON * DBL_EPSILON;
    if (x && eo_objective_rounding_scale(obj, x, rs) >= 0 && isfinite(rs[0]) && isfinite(rs[1])) {
        st->floor_dec = EO_STOP_FLOOR * e2 * rs[0];
        st->floor_grad = EO_STOP_FLOOR * e2 * rs[1];
        st->g_scale = isfinite(rs[2]) ? rs[2] : 0;
    } else {
        st->floor_dec = st->floor_grad = st->g_scale = 0;
    }
    eo_objective_characteristic ch;
    st->grad_char = eo_objective_characteristic_get(obj, &ch) >= 0 && isfinite(ch.grad) && ch.grad > 0 ? ch.grad : 0;
    st->begun = 1;
}

int eo_solver_stop_check(const eo_solver_ctx *sc, eo_stop_info *si, const double *x, const double *grad)
{
    struct eo_stop_state *st = sc->stop_state;
    if (!st || st->n != sc->obj->n) return sc->stop->check(sc->stop_params, si);
    if (!st->begun) stop_begin(sc, st, si, x, grad);
    si->measure = sc->optimizer && sc->optimizer->newton_decrement ? EO_MEASURE_DECREMENT : EO_MEASURE_GRADIENT;
    si->g0 = st->g0;
    if (grad) st->gm_last = metric_norm(st, sc->obj->space, grad);
    si->grad_metric = st->gm_last;
    si->grad_metric0 = st->gm0;
    /* a continuation measures against the step's start (eo_solver_set_reference) */
    if (st->ref_gm0 > 0 && !(si->grad_metric0 >= st->ref_gm0)) si->grad_metric0 = st->ref_gm0;
    if (st->ref_dec0 > 0 && isfinite(si->decrement0) && si->decrement0 < st->ref_dec0) si->decrement0 = st->ref_dec0;
    st->gm0_used = si->grad_metric0;
    if (isfinite(si->decrement0) && si->decrement0 > 0) st->dec0_used = si->decrement0;
    si->floor_dec = st->floor_dec;
    si->floor_grad = st->floor_grad;
    si->g_scale = st->g_scale;
    si->grad_char = st->grad_char;
    return sc->stop->check(sc->stop_params, si);
}

/* CPU time at the start of the minimization running on this thread (eo_solver_minimize
 * sets it, saving and restoring an enclosing one): eo_iter_info.cpu_time is measured
 * from it. */
static _Thread_local double minimize_cpu0;

int eo_solver_report(const eo_solver_ctx *sc, double t0, eo_iter_info *info)
{
    info->time = eo_wtime() - t0;
    info->cpu_time = eo_cputime() - minimize_cpu0;
    return sc->on_iter ? sc->on_iter(info, sc->user) : 0;
}

/* Names of every registered method of the solver kinds that has parameters, for the
 * sub-sections accepted in `solver`. */
#define MAX_EXTRA 256
static void method_section_names(const char **names, size_t cap)
{
    size_t k = 0;
    for (size_t i = 0; i < N_KINDS; i++)
        for (const void *const *t = eo_registry_types(solver_regs[i]); t && *t; t++) {
            const eo_method_info *mi = eo_method_info_of(*t);
            if (!mi->params || !mi->params_size) continue;
            int dup = 0;
            for (size_t j = 0; j < k; j++)
                if (strcmp(names[j], mi->name) == 0) dup = 1;
            if (!dup && k + 1 < cap) names[k++] = mi->name;
        }
    names[k] = NULL;
}

int eo_solver_opts_load(eo_ctx *ctx, eo_cfg *cfg, eo_solver_opts *o)
{
    if (!cfg) return EO_OK;
    const char *names[MAX_EXTRA + 1];
    method_section_names(names, MAX_EXTRA - 1);
    size_t k = 0;
    while (names[k]) k++;
    names[k] = "fallback"; /* the fallback chain, read by the simulation driver (sim.h) */
    names[k + 1] = "fallback_start";
    names[k + 2] = NULL;
    return eo_cfg_section(ctx, cfg, "solver", eo_solver_opts_desc, o, names);
}

/* Allocate and load the params of one method (NULL if it has none). */
static int load_params(eo_ctx *ctx, eo_cfg *cfg, const void *type, void **out)
{
    const eo_method_info *mi = eo_method_info_of(type);
    *out = NULL;
    if (!mi->params || !mi->params_size) return EO_OK;
    void *p = eo_calloc(ctx, 1, mi->params_size);
    if (!p) return eo_error(ctx, EO_ERR_NOMEM, "solver: out of memory");
    eo_params_default(mi->params, p);
    if (cfg) {
        char path[96];
        snprintf(path, sizeof path, "solver.%s", mi->name);
        int rc = eo_cfg_section(ctx, cfg, path, mi->params, p, NULL);
        if (rc < 0) {
            eo_free(ctx, p);
            return rc;
        }
    }
    *out = p;
    return EO_OK;
}

static const char *opts_name(const eo_solver_opts *o, int slot)
{
    const char *names[N_KINDS] = {[SLOT_OPT] = o->optimizer, [SLOT_HESSFIX] = o->hessian_fix,
                                  [SLOT_LINESEARCH] = o->linesearch, [SLOT_STOP] = o->stop,
                                  [SLOT_LINEAR] = o->linear};
    return names[slot];
}

/* Why the optimizer cannot run on a distributed objective, from what it needs. */
static const char *dist_why(const eo_optimizer_type *o)
{
    if (o->needs_ops & EO_OBJ_NEEDS_CONSTANT)
        return "it factors the constant matrix of the whole problem in one process";
    if (o->needs_ops & EO_OBJ_NEEDS_VERTEX) return "it sweeps over vertex blocks one after the other";
    if (o->needs_ops & EO_OBJ_NEEDS_SPLIT) return "it needs the per-tet split of the whole problem";
    if (o->needs_ops & EO_OBJ_NEEDS_INERTIA) return "it needs the mass matrix of the whole problem";
    if (o->needs_ops & EO_OBJ_NEEDS_WHOLE) return "it hands the whole vector to an external code";
    return "it sums over whole vectors itself";
}

/* A distributed run (solver.backend=petsc): every selected method must declare that it runs on distributed vectors (EO_METHOD_DISTRIBUTED).
 * The backend's own optimizers (EO_OBJ_NEEDS_PARTS) take the parts as they are. */
static int check_distributed(eo_solver *s)
{
    const eo_optimizer_type *opt = s->type[SLOT_OPT];
    if (opt->needs_ops & EO_OBJ_NEEDS_PARTS) return EO_OK;
    static const char *const key[N_KINDS] = {"optimizer", "hessian_fix", "linesearch", "stop", "linear"};
    static const char *const kind[N_KINDS] = {"optimizer", "Hessian fix", "line search", "stopping rule",
                                              "linear solver"};
    for (int i = 0; i < N_KINDS; i++) {
        if (!s->type[i] || (i == SLOT_HESSFIX && !opt->needs_hessian)) continue;
        const eo_method_info *mi = eo_method_info_of(s->type[i]);
        if (mi->flags & EO_METHOD_DISTRIBUTED) continue;
        const char *why = i == SLOT_OPT      ? dist_why(opt)
                          : i == SLOT_LINEAR ? "it needs the whole matrix in one process; use petsc_ksp"
                                             : "it sums over whole vectors itself";
        return eo_error(s->ctx, EO_ERR_UNSUPPORTED,
                        "key 'solver.%s': %s '%s' has no distributed form (solver.backend=petsc): %s", key[i],
                        kind[i], mi->name, why);
    }
    return EO_OK;
}

int eo_solver_create(eo_ctx *ctx, const eo_solver_opts *opts, eo_cfg *cfg, eo_solver **out)
{
    int rc = EO_OK;
    *out = NULL;
    eo_solver *s = eo_calloc(ctx, 1, sizeof *s);
    if (!s) return eo_error(ctx, EO_ERR_NOMEM, "solver: out of memory");
    s->ctx = ctx;
    s->n = -1;
    if (opts) s->opts = *opts;
    else eo_solver_opts_default(&s->opts);
    if (!(s->opts.tol > 0 && isfinite(s->opts.tol))) {
        rc = eo_error(ctx, EO_ERR_RANGE, "key 'solver.tol': value %g must be > 0", s->opts.tol);
        goto fail;
    }
    if (s->opts.max_iters < 0) {
        rc = eo_error(ctx, EO_ERR_RANGE, "key 'solver.max_iters': value %d must be >= 0",
                      s->opts.max_iters);
        goto fail;
    }
    if (!(s->opts.time_budget >= 0 && isfinite(s->opts.time_budget))) {
        rc = eo_error(ctx, EO_ERR_RANGE, "key 'solver.time_budget': value %g must be >= 0",
                      s->opts.time_budget);
        goto fail;
    }

    /* backend petsc: the library's optimizer distributed (solvers/dist_objective.c), its
     * systems solved by the backend's linear solver (auto: petsc_ksp); the backend's own
     * snes_* and tao_* optimizers run as they are */
    if (strcmp(s->opts.backend, "petsc") == 0 && strcmp(s->opts.linear, "auto") == 0)
        snprintf(s->opts.linear, sizeof s->opts.linear, "petsc_ksp");
    /* resolve the selected methods; the linear solver only if the optimizer needs one */
    for (size_t i = 0; i < N_KINDS; i++) {
        if (i == SLOT_LINEAR && !((const eo_optimizer_type *)s->type[SLOT_OPT])->needs_linear)
            continue;
        if (i == SLOT_LINESEARCH && strcmp(s->opts.linesearch, "auto") == 0) {
            const char *pref = ((const eo_optimizer_type *)s->type[SLOT_OPT])->linesearch;
            snprintf(s->opts.linesearch, sizeof s->opts.linesearch, "%s", pref ? pref : "backtracking");
        }
        EO_TRY(rc = eo_registry_lookup(ctx, solver_regs[i], opts_name(&s->opts, (int)i), &s->type[i]));
        EO_TRY(rc = load_params(ctx, cfg, s->type[i], &s->params[i]));
    }
    /* check the sections of the registered methods that are not selected */
    if (cfg) {
        for (size_t i = 0; i < N_KINDS; i++)
            for (const void *const *t = eo_registry_types(solver_regs[i]); t && *t; t++) {
                if (*t == s->type[i]) continue;
                void *p = NULL;
                EO_TRY(rc = load_params(ctx, cfg, *t, &p));
                eo_free(ctx, p);
            }
    }

    const eo_optimizer_type *opt = s->type[SLOT_OPT];
    if (strcmp(s->opts.backend, "petsc") == 0) EO_TRY(rc = check_distributed(s));
    if (opt->needs_linear) {
        EO_TRY(rc = eo_linsolve_create(ctx, s->type[SLOT_LINEAR], s->params[SLOT_LINEAR], &s->linear));
    }
    s->opt_state = eo_calloc(ctx, 1, opt->state_size ? opt->state_size : 1);
    if (!s->opt_state) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "solver: out of memory");
        goto fail;
    }
    const eo_hessfix_type *hf = s->type[SLOT_HESSFIX];
    if (hf->state_size && opt->needs_hessian) { /* optimizers without a Hessian skip it */
        s->hf_state = eo_calloc(ctx, 1, hf->state_size);
        if (!s->hf_state) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "solver: out of memory");
            goto fail;
        }
    }
    *out = s;
    return EO_OK;
fail:
    eo_solver_destroy(&s);
    return rc;
}

void eo_solver_destroy(eo_solver **sp)
{
    if (!sp || !*sp) return;
    eo_solver *s = *sp;
    eo_ctx *ctx = s->ctx;
    const eo_optimizer_type *opt = s->type[SLOT_OPT];
    if (s->opt_state && s->opt_set_up && opt->destroy) opt->destroy(s->opt_state, ctx);
    eo_free(ctx, s->opt_state);
    const eo_hessfix_type *hf = s->type[SLOT_HESSFIX];
    if (s->hf_state && s->hf_set_up && hf->destroy) hf->destroy(s->hf_state, ctx);
    eo_free(ctx, s->hf_state);
    eo_linsolve_destroy(&s->linear);
    for (size_t i = 0; i < N_KINDS; i++) eo_free(ctx, s->params[i]);
    if (s->stop) eo_free(ctx, s->stop->dinv);
    eo_free(ctx, s->stop);
    eo_free(ctx, s);
    *sp = NULL;
}

int eo_solver_minimize(eo_solver *s, eo_objective *obj, double *x, eo_iter_fn on_iter,
                       void *user, eo_solve_result *res)
{
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (!obj || !x)
        return res->status = eo_error(s->ctx, EO_ERR_INVALID, "solver: no objective or no x");
    if (obj->n < 0)
        return res->status = eo_error(s->ctx, EO_ERR_INVALID, "solver: objective has n = %d < 0", obj->n);
    const eo_optimizer_type *opt = s->type[SLOT_OPT];
    eo_dist_view view;
    if (eo_ctx_dist(s->ctx) && strcmp(s->opts.backend, "petsc") == 0 && !(opt->needs_ops & EO_OBJ_NEEDS_PARTS)) {
        /* one part of a distributed problem: the optimizer minimizes the distributed view
         * of the part's objective, from x made equal to its owners' values */
        int rc = eo_dist_view_init(&view, s->ctx, obj);
        if (rc >= 0) rc = eo_dist_view_consistent(view.space, x);
        if (rc >= 0 && s->linear) rc = eo_linsolve_set_space(s->linear, view.space);
        if (rc < 0) return res->status = rc;
        obj = &view.obj;
    }
    int resize = obj->n != s->n;
    if (obj->space) { /* a part's size changed: every part sets up afresh, so that the
                       * optimizers' carried state (shift, decrement history) stays alike */
        double r = resize;
        eo_vreduce(obj->space, &r, 1, EO_REDUCE_MAX);
        resize = r != 0;
    }
    if (resize) {
        /* first minimize, or a new problem size (a boundary set was released): size the
         * optimizer's workspace for it (the only allocation outside create) */
        if (s->opt_set_up && opt->destroy) opt->destroy(s->opt_state, s->ctx);
        memset(s->opt_state, 0, opt->state_size ? opt->state_size : 1);
        s->opt_set_up = 1;
        s->n = -1;
        int rc = opt->setup(s->opt_state, s->params[SLOT_OPT], obj->n, s->ctx);
        if (rc < 0) return res->status = rc;
        const eo_hessfix_type *hf = s->type[SLOT_HESSFIX];
        if (s->hf_state) { /* the fix's workspace follows the size too */
            if (s->hf_set_up && hf->destroy) hf->destroy(s->hf_state, s->ctx);
            memset(s->hf_state, 0, hf->state_size);
            s->hf_set_up = 1;
            if (hf->setup && (rc = hf->setup(s->hf_state, s->params[SLOT_HESSFIX], obj->n, s->ctx)) < 0)
                return res->status = rc;
        }
        if (!s->stop && !(s->stop = eo_calloc(s->ctx, 1, sizeof *s->stop)))
            return res->status = eo_error(s->ctx, EO_ERR_NOMEM, "solver: out of memory");
        eo_free(s->ctx, s->stop->dinv);
        s->stop->n = 0;
        if (!(s->stop->dinv = eo_calloc(s->ctx, (size_t)(obj->n > 0 ? obj->n : 1), sizeof(double))))
            return res->status = eo_error(s->ctx, EO_ERR_NOMEM, "solver: out of memory (n = %d)", obj->n);
        s->stop->n = obj->n;
        s->n = obj->n;
    }
    /* every minimization starts from what it is given, not from what the linear solver
     * learnt in the ones before (a kept factor or interpolation): a time step's result is
     * then a function of its start, and a restarted run goes on bit for bit */
    if (s->linear && !s->opts.carry_linear) eo_linsolve_forget(s->linear);
    s->stop->begun = 0;
    s->stop->ref_dec0 = s->ref_dec0 > 0 && isfinite(s->ref_dec0) ? s->ref_dec0 : 0;
    s->stop->ref_gm0 = s->ref_gm0 > 0 && isfinite(s->ref_gm0) ? s->ref_gm0 : 0;
    s->ref_dec0 = s->ref_gm0 = 0; /* for this minimization only */
    s->stop->dec0_used = s->stop->gm0_used = NAN;
    eo_solver_ctx sc = {
        .obj = obj,
        .ctx = s->ctx,
        .linear = s->linear,
        .hessfix = s->type[SLOT_HESSFIX],
        .hessfix_params = s->params[SLOT_HESSFIX],
        .hessfix_state = s->hf_state,
        .linesearch = s->type[SLOT_LINESEARCH],
        .linesearch_params = s->params[SLOT_LINESEARCH],
        .stop = s->type[SLOT_STOP],
        .stop_params = s->params[SLOT_STOP],
        .tol = s->opts.tol,
        .max_iters = s->opts.max_iters,
        .time_budget = s->opts.time_budget,
        .on_iter = on_iter,
        .user = user,
        .optimizer = opt,
        .stop_state = s->stop,
    };
    eo_linsolve_stats l0 = {0};
    if (s->linear) l0 = *eo_linsolve_get_stats(s->linear);
    const double outer_cpu0 = minimize_cpu0;
    const double t0 = eo_wtime(), c0 = eo_cputime();
    minimize_cpu0 = c0;
    int rc = opt->minimize(s->opt_state, s->params[SLOT_OPT], &sc, x, res);
    const double c1 = eo_cputime();
    minimize_cpu0 = outer_cpu0;
    res->cpu_time = c1 - c0;
    eo_profile *p = &s->prof;
    p->t_total += eo_wtime() - t0;
    p->c_total += c1 - c0;
    p->c_assembly += res->c_assembly;
    p->c_linesearch += res->c_linesearch;
    p->c_gradient += res->c_gradient;
    p->minimizations++;
    p->iterations += res->iterations;
    p->t_assembly += res->t_assembly;
    p->n_assembly += res->n_assembly;
    p->t_linesearch += res->t_linesearch;
    p->n_ls_evals += res->n_ls_evals;
    p->t_gradient += res->t_gradient;
    p->n_gradient += res->n_gradient_outside;
    if (s->linear) {
        const eo_linsolve_stats *l = eo_linsolve_get_stats(s->linear);
        p->t_analyze += l->t_analyze - l0.t_analyze;
        p->n_analyze += l->n_analyze - l0.n_analyze;
        p->t_factor += l->t_factor - l0.t_factor;
        p->n_factor += l->n_factor - l0.n_factor;
        p->t_solve += l->t_solve - l0.t_solve;
        p->c_analyze += l->c_analyze - l0.c_analyze;
        p->c_factor += l->c_factor - l0.c_factor;
        p->c_solve += l->c_solve - l0.c_solve;
        p->n_solve += l->n_solve - l0.n_solve;
        res->n_not_pd = l->n_not_pd - l0.n_not_pd;
        p->n_not_pd += res->n_not_pd;
    }
    return rc;
}

void eo_solver_set_reference(eo_solver *s, double decrement0, double grad_metric0)
{
    s->ref_dec0 = decrement0;
    s->ref_gm0 = grad_metric0;
}

int eo_solver_measures_decrement(const eo_solver *s)
{
    const eo_optimizer_type *t = s->type[SLOT_OPT];
    return t && t->newton_decrement;
}

void eo_solver_get_reference(const eo_solver *s, double *decrement0, double *grad_metric0)
{
    *decrement0 = s->stop ? s->stop->dec0_used : NAN;
    *grad_metric0 = s->stop ? s->stop->gm0_used : NAN;
}

const eo_profile *eo_solver_get_profile(const eo_solver *s) { return &s->prof; }
void eo_solver_reset_profile(eo_solver *s) { memset(&s->prof, 0, sizeof s->prof); }

void eo_profile_diff(const eo_profile *a, const eo_profile *b, eo_profile *o)
{
    o->minimizations = a->minimizations - b->minimizations;
    o->iterations = a->iterations - b->iterations;
    o->t_total = a->t_total - b->t_total;
    o->t_assembly = a->t_assembly - b->t_assembly;
    o->t_analyze = a->t_analyze - b->t_analyze;
    o->t_factor = a->t_factor - b->t_factor;
    o->t_solve = a->t_solve - b->t_solve;
    o->t_linesearch = a->t_linesearch - b->t_linesearch;
    o->t_gradient = a->t_gradient - b->t_gradient;
    o->n_assembly = a->n_assembly - b->n_assembly;
    o->n_analyze = a->n_analyze - b->n_analyze;
    o->n_factor = a->n_factor - b->n_factor;
    o->n_solve = a->n_solve - b->n_solve;
    o->n_ls_evals = a->n_ls_evals - b->n_ls_evals;
    o->n_gradient = a->n_gradient - b->n_gradient;
    o->n_not_pd = a->n_not_pd - b->n_not_pd;
    o->c_total = a->c_total - b->c_total;
    o->c_assembly = a->c_assembly - b->c_assembly;
    o->c_analyze = a->c_analyze - b->c_analyze;
    o->c_factor = a->c_factor - b->c_factor;
    o->c_solve = a->c_solve - b->c_solve;
    o->c_linesearch = a->c_linesearch - b->c_linesearch;
    o->c_gradient = a->c_gradient - b->c_gradient;
}

void eo_profile_cpu_view(const eo_profile *p, eo_profile *o)
{
    *o = *p;
    o->t_total = p->c_total;
    o->t_assembly = p->c_assembly;
    o->t_analyze = p->c_analyze;
    o->t_factor = p->c_factor;
    o->t_solve = p->c_solve;
    o->t_linesearch = p->c_linesearch;
    o->t_gradient = p->c_gradient;
}

double eo_profile_other(const eo_profile *p)
{
    return p->t_total - (p->t_assembly + p->t_analyze + p->t_factor + p->t_solve + p->t_linesearch + p->t_gradient);
}

double eo_profile_iteration_ratio(const eo_profile *p)
{
    if (p->iterations <= 0 || p->n_factor <= 0 || !(p->t_factor > 0)) return NAN;
    return (p->t_total / (double)p->iterations) / (p->t_factor / (double)p->n_factor);
}

const eo_solver_opts *eo_solver_get_opts(const eo_solver *s) { return &s->opts; }
eo_linsolve *eo_solver_get_linsolve(const eo_solver *s) { return s->linear; }

json_t *eo_solver_to_json(const eo_solver *s)
{
    json_t *j = eo_params_to_json(eo_solver_opts_desc, &s->opts);
    if (!j) return NULL;
    if (!s->linear) json_object_del(j, "linear");
    if (s->linear && eo_linsolve_get_stats(s->linear)->n_analyze > 0) {
        /* what the linear solver did with the last pattern (auto: the policy's choice) */
        char d[256];
        json_object_set_new(j, "linear_choice", json_string(eo_linsolve_describe(s->linear, d, sizeof d)));
        json_object_set_new(j, "linear_refactorizations", json_integer(eo_linsolve_get_stats(s->linear)->n_refactor));
    }
    for (size_t i = 0; i < N_KINDS; i++) {
        if (!s->type[i] || !s->params[i]) continue;
        const eo_method_info *mi = eo_method_info_of(s->type[i]);
        json_object_set_new(j, mi->name, eo_params_to_json(mi->params, s->params[i]));
    }
    return j;
}
