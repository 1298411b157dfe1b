/* auto — the default linear solver: a policy that picks, for each sparsity pattern, the
 * method measured fastest for systems of that size, and delegates every call to it.
 *
 * The choice is made at `analyze` from n (the unknowns of the pattern):
 *
 *   n <  reuse_min                 cholmod: a fresh supernodal LLᵀ factor per factor call
 *   reuse_min <= n < iterative_min pcg with cholmod_reuse: a CHOLMOD factor of an earlier
 *                                  matrix of the same step (eo_linsolve_forget) preconditions CG, refactored when
 *                                  a solve needs more than refactor_iters iterations (or a
 *                                  fresh factor's own solve: exact, no iteration)
 *   n >= iterative_min             pcg with `preconditioner` (gmg: one Galerkin multigrid
 *                                  V-cycle from the node coordinates; amg: BoomerAMG)
 *
 * and the fill-reducing ordering of every CHOLMOD factor: `ordering` = "auto" takes AMD
 * below nd_min unknowns and CHOLMOD's nested dissection (NESDIS: METIS separators +
 * constrained minimum degree) from there; any other value is used as given.
 *
 * Why these thresholds (bench/results/linear-auto-amd-epyc-2cpu.txt; CPU time, one BLAS thread, real
 * unstructured meshes): see docs/defaults.md, "The linear solver policy". In short:
 * nested dissection factors 1.6× faster than AMD on the TetGen bunny at 115k tets; at
 * 20k AMD and NESDIS are within a few percent; factorization reuse with the
 * Eisenstat–Walker forcing of Newton (`solver.newton.forcing = auto`) replaces most
 * numeric factorizations by a few preconditioned CG iterations; the multigrid takes over
 * where a factor no longer fits in memory or costs more than its V-cycles.
 *
 * The delegate is an ordinary registered solver created with these settings; its
 * statistics are copied into this solver's after each call (its warnings are reported
 * once, by the generic layer of this solver). eo_linsolve_describe gives the choice in
 * words ("pcg + cholmod_reuse (nesdis), n = 70623 >= reuse_min 20000"), which the run
 * summary records; eo_linsolve_is_iterative is the delegate's.
 *
 * Parameters (solver.auto.<key>):
 *   reuse_min        unknowns from which the factor is reused    default 10000
 *   iterative_min    unknowns from which PCG + multigrid runs     default 1500000
 *   preconditioner   gmg | amg: the multigrid above iterative_min default "gmg"
 *   ordering         auto | amd | metis | nesdis                  default "auto"
 *   nd_min           ordering auto: nested dissection from here   default 20000
 *   refactor_iters   reuse: refactor after a solve needing more   default 5
 *                    PCG iterations than this
 */
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "elastopt/linsolve.h"
#include "elastopt/params.h"

typedef struct auto_params {
    int reuse_min;             /* default 10000 */
    int iterative_min;         /* default 1500000 */
    char preconditioner[16];   /* default "gmg" */
    char ordering[16];         /* default "auto" */
    int nd_min;                /* default 20000 */
    int refactor_iters;        /* default 5 */
} auto_params;

static const char *const auto_preconds[] = {"gmg", "amg", NULL};
static const char *const auto_orderings[] = {"auto", "amd", "metis", "nesdis", NULL};

static const eo_param_desc auto_desc[] = {
    {.key = "reuse_min", .kind = EO_PARAM_INT, .offset = offsetof(auto_params, reuse_min), .def.i = 10000,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "unknowns from which a CHOLMOD factor is reused across the Newton iterations of a step as the preconditioner "
             "of CG (pcg cholmod_reuse); below, cholmod factors every matrix"},
    {.key = "iterative_min", .kind = EO_PARAM_INT, .offset = offsetof(auto_params, iterative_min),
     .def.i = 1500000, .min = 0, .range = EO_RANGE_MIN,
     .help = "unknowns from which PCG with a multigrid preconditioner replaces the factorization"},
    {.key = "preconditioner", .kind = EO_PARAM_CHOICE, .offset = offsetof(auto_params, preconditioner),
     .size = sizeof(((auto_params *)0)->preconditioner), .def.s = "gmg", .choices = auto_preconds,
     .help = "multigrid above iterative_min: gmg (Galerkin multigrid from the node coordinates) or amg "
             "(hypre BoomerAMG; builds without hypre refuse it)"},
    {.key = "ordering", .kind = EO_PARAM_CHOICE, .offset = offsetof(auto_params, ordering),
     .size = sizeof(((auto_params *)0)->ordering), .def.s = "auto", .choices = auto_orderings,
     .help = "fill-reducing ordering of the CHOLMOD factors: auto = amd below nd_min unknowns, nesdis (nested "
             "dissection) from there; or amd, metis, nesdis"},
    {.key = "nd_min", .kind = EO_PARAM_INT, .offset = offsetof(auto_params, nd_min), .def.i = 20000, .min = 0,
     .range = EO_RANGE_MIN, .help = "ordering auto: unknowns from which nested dissection replaces AMD"},
    {.key = "refactor_iters", .kind = EO_PARAM_INT, .offset = offsetof(auto_params, refactor_iters),
     .def.i = 5, .min = 1, .range = EO_RANGE_MIN,
     .help = "factor reuse: a solve needing more PCG iterations than this refactors at the next factor call "
             "(measured: 2-10 equally fast, 20 2x slower on 100k-tet meshes)"},
    {0},
};

enum { MODE_NONE, MODE_DIRECT, MODE_REUSE, MODE_MG };

typedef struct auto_state {
    auto_params p;
    int mode;
    int n;
    char ordering[16];   /* the ordering in use */
    eo_linsolve *inner;  /* the delegate */
    double *xyz;         /* set_coordinates copy, handed to every delegate */
    int nv;
    double rtol;         /* last set_rtol (<= 0: none), handed to a new delegate */
    long refactor_base;  /* numeric refactorizations of the delegates destroyed so far */
} auto_state;

static int auto_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    auto_state *s = st;
    s->p = *(const auto_params *)params;
    return EO_OK;
}

/* params[key] = value in a params struct described by d (strings and ints only) */
static void set_str(const eo_param_desc *d, void *obj, const char *key, const char *value)
{
    const eo_param_desc *p = eo_params_find(d, key);
    if (p) snprintf((char *)obj + p->offset, p->size, "%s", value);
}

static void set_int(const eo_param_desc *d, void *obj, const char *key, int value)
{
    const eo_param_desc *p = eo_params_find(d, key);
    if (p) *(int *)((char *)obj + p->offset) = value;
}

/* the delegate for mode m (created, coordinates and tolerance handed on) */
static int make_inner(auto_state *s, int m, eo_ctx *ctx)
{
    const eo_linsolve_type *t = NULL;
    int rc = eo_linsolve_find(ctx, m == MODE_DIRECT ? "cholmod" : "pcg", &t);
    if (rc < 0) return rc;
    double buf[64]; /* aligned storage for the delegate's params struct */
    if (t->info.params_size > sizeof buf)
        return eo_error(ctx, EO_ERR_INTERNAL, "linear solver auto: %s's parameters do not fit", t->info.name);
    eo_params_default(t->info.params, buf);
    set_str(t->info.params, buf, "ordering", s->ordering);
    if (m == MODE_REUSE) {
        set_str(t->info.params, buf, "preconditioner", "cholmod_reuse");
        set_int(t->info.params, buf, "refactor_iters", s->p.refactor_iters);
    } else if (m == MODE_MG) {
        set_str(t->info.params, buf, "preconditioner", s->p.preconditioner);
    }
    rc = eo_linsolve_create(ctx, t, buf, &s->inner);
    if (rc < 0) return rc;
    eo_linsolve_set_expect_not_pd(s->inner, 1); /* this solver's layer reports */
    if (s->nv > 0) rc = eo_linsolve_set_coordinates(s->inner, s->nv, s->xyz);
    if (rc >= 0 && s->rtol > 0) rc = eo_linsolve_set_rtol(s->inner, s->rtol);
    if (rc < 0) eo_linsolve_destroy(&s->inner);
    return rc;
}

/* the delegate's per-call statistics into ours (the generic layer keeps the times and
 * counts of this solver itself) */
static void copy_stats(const auto_state *s, eo_linsolve_stats *out)
{
    const eo_linsolve_stats *in = eo_linsolve_get_stats(s->inner);
    out->iterations = in->iterations;
    out->residual = in->residual;
    out->not_pd_column = in->not_pd_column;
    out->curvature = in->curvature;
    out->n_negative = in->n_negative;
    out->n_zero = in->n_zero;
    out->n_refactor = s->refactor_base + in->n_refactor;
}

static int auto_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    auto_state *s = st;
    const int n = A->n;
    const int m = n >= s->p.iterative_min ? MODE_MG : n >= s->p.reuse_min ? MODE_REUSE : MODE_DIRECT;
    const char *ord = strcmp(s->p.ordering, "auto") ? s->p.ordering : n >= s->p.nd_min ? "nesdis" : "amd";
    if (!s->inner || m != s->mode || strcmp(ord, s->ordering)) {
        if (s->inner) s->refactor_base += eo_linsolve_get_stats(s->inner)->n_refactor;
        eo_linsolve_destroy(&s->inner);
        snprintf(s->ordering, sizeof s->ordering, "%s", ord);
        s->mode = MODE_NONE;
        int rc = make_inner(s, m, ctx);
        if (rc < 0) return rc;
        s->mode = m;
    }
    s->n = n;
    return eo_linsolve_analyze(s->inner, A);
}

static int auto_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    auto_state *s = st;
    (void)ctx;
    int rc = eo_linsolve_factor(s->inner, A);
    copy_stats(s, stats);
    return rc;
}

static int auto_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    auto_state *s = st;
    (void)ctx;
    int rc = eo_linsolve_solve(s->inner, b, x);
    copy_stats(s, stats);
    return rc;
}

static void auto_destroy(void *st, eo_ctx *ctx)
{
    auto_state *s = st;
    eo_linsolve_destroy(&s->inner);
    eo_free(ctx, s->xyz);
    s->xyz = NULL;
}

static void auto_forget(void *st)
{
    auto_state *s = st;
    eo_linsolve_forget(s->inner);
}

static void auto_set_rtol(void *st, double rtol)
{
    auto_state *s = st;
    s->rtol = rtol;
    if (s->inner) eo_linsolve_set_rtol(s->inner, rtol);
}

static int auto_set_coordinates(void *st, int nv, const double *xyz, eo_ctx *ctx)
{
    auto_state *s = st;
    eo_free(ctx, s->xyz);
    s->xyz = NULL;
    s->nv = 0;
    if (nv > 0) {
        s->xyz = eo_malloc(ctx, (size_t)3 * nv * sizeof(double));
        if (!s->xyz) return eo_error(ctx, EO_ERR_NOMEM, "linear solver auto: out of memory for %d coordinates", nv);
        memcpy(s->xyz, xyz, (size_t)3 * nv * sizeof(double));
        s->nv = nv;
    }
    return s->inner ? eo_linsolve_set_coordinates(s->inner, nv, xyz) : EO_OK;
}

static int auto_is_iterative(const void *st)
{
    const auto_state *s = st;
    return s->inner ? eo_linsolve_is_iterative(s->inner) : 0;
}

static int auto_describe(const void *st, char *buf, size_t size)
{
    const auto_state *s = st;
    switch (s->mode) {
    case MODE_DIRECT:
        return snprintf(buf, size, "cholmod (%s), n = %d < reuse_min %d", s->ordering, s->n, s->p.reuse_min);
    case MODE_REUSE:
        return snprintf(buf, size, "pcg + cholmod_reuse (%s), n = %d >= reuse_min %d", s->ordering, s->n,
                        s->p.reuse_min);
    case MODE_MG:
        return snprintf(buf, size, "pcg + %s, n = %d >= iterative_min %d", s->p.preconditioner, s->n,
                        s->p.iterative_min);
    default: return snprintf(buf, size, "no matrix analyzed yet");
    }
}

const eo_linsolve_type eo_linsolve_auto = {
    .info = {.name = "auto",
             .summary = "policy by size: cholmod below reuse_min unknowns, a reused CHOLMOD factor preconditioning "
                        "CG up to iterative_min, multigrid-preconditioned CG above; AMD or nested-dissection ordering",
             .params = auto_desc,
             .params_size = sizeof(auto_params)},
    .state_size = sizeof(auto_state),
    .setup = auto_setup,
    .analyze = auto_analyze,
    .factor = auto_factor,
    .solve = auto_solve,
    .destroy = auto_destroy,
    .set_rtol = auto_set_rtol,
    .set_coordinates = auto_set_coordinates,
    .is_iterative = auto_is_iterative,
    .describe = auto_describe,
    .forget = auto_forget,
};
