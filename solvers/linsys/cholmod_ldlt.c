/* cholmod_ldlt — sparse simplicial LDLᵀ factorization (CHOLMOD, square-root free).
 *
 *   P A Pᵀ = L D Lᵀ,  L unit lower triangular, D diagonal,
 *   d_k = a_kk − Σ_{j<k} l_kj² d_j,   l_ik = (a_ik − Σ_{j<k} l_ij l_kj d_j) / d_k.
 *
 * A is positive definite iff every d_k > 0. CHOLMOD only stops on d_k = 0 (or NaN),
 * so after factorizing we scan D (the first entry of each column of the simplicial
 * L) and report the first d_k <= 0 as EO_WARN_NOT_PD with its original column, so
 * that Newton can shift the Hessian. With allow_indefinite = true a non-singular
 * indefinite matrix is accepted and the LDLᵀ solve returns x = A⁻¹b anyway (useful
 * for saddle-point or comparison runs, not for Newton descent directions).
 *
 * Parameters (solver.cholmod_ldlt.<key>):
 *   ordering          "auto" | "amd" | "metis" | "nesdis" | "natural"  default "amd"
 *   allow_indefinite  accept d_k < 0 (still refuse d_k = 0)           default false
 *   openmp            let CHOLMOD's own OpenMP loops run on 4 threads    default false
 */
#include <math.h>
#include <stddef.h>

#include "cholmod_util.h"

typedef struct ldlt_params {
    char ordering[16];    /* fill-reducing ordering; default "amd" */
    int allow_indefinite; /* accept negative pivots; default false */
    int openmp;           /* CHOLMOD's internal OpenMP loops; default false */
} ldlt_params;

static const char *const orderings[] = EO_CHM_ORDERINGS;

static const eo_param_desc ldlt_desc[] = {
    {.key = "ordering", .kind = EO_PARAM_CHOICE, .offset = offsetof(ldlt_params, ordering),
     .size = sizeof(((ldlt_params *)0)->ordering), .def.s = "amd", .choices = orderings,
     .help = "fill-reducing ordering: auto (CHOLMOD's choice), amd, metis, nesdis, natural"},
    {.key = "allow_indefinite", .kind = EO_PARAM_BOOL,
     .offset = offsetof(ldlt_params, allow_indefinite), .def.i = 0,
     .help = "accept negative pivots (indefinite but non-singular matrices)"},
    {.key = "openmp", .kind = EO_PARAM_BOOL, .offset = offsetof(ldlt_params, openmp), .def.i = 0,
     .help = "run CHOLMOD's internal OpenMP loops (4 threads, compiled in) instead of serially"},
    {0},
};

typedef struct ldlt_state {
    eo_chm chm;
    ldlt_params p;
    int n;
} ldlt_state;

static int ldlt_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    ldlt_state *s = st;
    s->p = *(const ldlt_params *)params;
    eo_chm_start(&s->chm);
    eo_chm_ordering(&s->chm, s->p.ordering);
    s->chm.c.supernodal = CHOLMOD_SIMPLICIAL;
    s->chm.c.final_ll = 0;
    s->chm.c.final_asis = 1;
    return EO_OK;
}

static int ldlt_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    ldlt_state *s = st;
    s->n = A->n;
    return eo_chm_analyze(&s->chm, A, "cholmod_ldlt", ctx);
}

static int not_pd(ldlt_state *s, int k, double d, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    int col = eo_chm_orig(&s->chm, k);
    stats->not_pd_column = col;
    return eo_error_at(ctx, EO_WARN_NOT_PD, EO_ERRLOC_ITEM(NULL, -1, "column", col),
                       "cholmod_ldlt: matrix not positive definite (pivot d = %.3g at step %d of %d)",
                       d, k, s->n);
}

static int ldlt_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    ldlt_state *s = st;
    cholmod_sparse S = eo_chm_view(A);
    int ok = eo_chm_factorize(&s->chm, &S, s->p.openmp);
    int status = s->chm.c.status;
    cholmod_factor *L = s->chm.L;
    if (status == CHOLMOD_NOT_POSDEF || (ok && L->minor < (size_t)A->n)) {
        int k = (int)L->minor;
        double d = 0;
        if (!L->is_super && L->x && L->p && k < A->n) d = ((double *)L->x)[((int *)L->p)[k]];
        return not_pd(s, k, d, stats, ctx);
    }
    if (!ok || status < CHOLMOD_OK)
        return eo_error(ctx, status == CHOLMOD_OUT_OF_MEMORY ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                        "cholmod_ldlt: cholmod_factorize failed (CHOLMOD status %d)", status);
    if (L->is_super || L->is_ll)
        return eo_error(ctx, EO_ERR_INTERNAL, "cholmod_ldlt: expected a simplicial LDL' factor");
    const int *Lp = L->p;
    const double *Lx = L->x;
    for (int k = 0; k < A->n; k++) {
        double d = Lx[Lp[k]]; /* D(k,k) is stored as the diagonal of L */
        if (!(d > 0) && (!s->p.allow_indefinite || !(d < 0))) return not_pd(s, k, d, stats, ctx);
    }
    return EO_OK;
}

static int ldlt_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    ldlt_state *s = st;
    stats->iterations = 0;
    return eo_chm_solve(&s->chm, b, x, s->n, "cholmod_ldlt", ctx);
}

static void ldlt_destroy(void *st, eo_ctx *ctx)
{
    (void)ctx;
    eo_chm_finish(&((ldlt_state *)st)->chm);
}

const eo_linsolve_type eo_linsolve_cholmod_ldlt = {
    .info = {.name = "cholmod_ldlt",
             .summary = "CHOLMOD simplicial LDL' (reports negative pivots; optional indefinite)",
             .params = ldlt_desc,
             .params_size = sizeof(ldlt_params)},
    .state_size = sizeof(ldlt_state),
    .setup = ldlt_setup,
    .analyze = ldlt_analyze,
    .factor = ldlt_factor,
    .solve = ldlt_solve,
    .destroy = ldlt_destroy,
};
