/* umfpack — sparse LU with UMFPACK (Davis 2004, unsymmetric multifrontal method).
 *
 *   P R A Q = L U,   x = Q U⁻¹ L⁻¹ P R b   (R: row scaling, P, Q: permutations)
 *
 * Any non-singular A, definite or not: an indefinite Hessian is solved, not reported
 * (pivoting by threshold partial pivoting). Our matrices are symmetric and stored by
 * their upper triangle (sparse.h); UMFPACK needs the full matrix, so `analyze` builds
 * the full pattern once with a gather map (eo_csc_full) and runs the symbolic analysis
 * (umfpack_di_symbolic, symmetric strategy: AMD on A + Aᵀ, diagonal pivots preferred).
 * `factor` gathers the new values through the map (no allocation on our side) and
 * runs the numeric factorization (umfpack_di_numeric; UMFPACK allocates the LU factors
 * with its own malloc). A singular matrix (a zero pivot) is EO_ERR_LINSOLVE. `solve`
 * uses umfpack_di_wsolve with workspace sized at analyze (no allocation), with up to
 * `refine` steps of iterative refinement.
 *
 * Parameters (solver.umfpack.<key>):
 *   ordering   "amd" | "metis" | "cholmod" | "best"                     default "amd"
 *   refine     iterative refinement steps in solve                      default 2
 */
#include <stddef.h>
#include <string.h>
#include <suitesparse/umfpack.h>

#include "elastopt/linsolve.h"

typedef struct umf_params {
    char ordering[16]; /* default "amd" */
    int refine;        /* default 2 */
} umf_params;

static const char *const orderings[] = {"amd", "metis", "cholmod", "best", NULL};

static const eo_param_desc umf_desc[] = {
    {.key = "ordering", .kind = EO_PARAM_CHOICE, .offset = offsetof(umf_params, ordering),
     .size = sizeof(((umf_params *)0)->ordering), .def.s = "amd", .choices = orderings,
     .help = "UMFPACK's column ordering: amd, metis, cholmod (AMD then METIS), best (try several)"},
    {.key = "refine", .kind = EO_PARAM_INT, .offset = offsetof(umf_params, refine), .def.i = 2, .min = 0,
     .max = 10, .range = EO_RANGE_CLOSED, .help = "steps of iterative refinement in solve"},
    {0},
};

typedef struct umf_state {
    umf_params p;
    double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
    eo_csc_full *F; /* full matrix: pattern once per analyze, values per factor */
    void *symbolic, *numeric;
    int *Wi;        /* n */
    double *W;      /* 5n (with iterative refinement) */
} umf_state;

static int umf_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    umf_state *s = st;
    s->p = *(const umf_params *)params;
    umfpack_di_defaults(s->control);
    s->control[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_SYMMETRIC;
    s->control[UMFPACK_IRSTEP] = s->p.refine;
    const char *o = s->p.ordering;
    s->control[UMFPACK_ORDERING] = !strcmp(o, "metis")     ? UMFPACK_ORDERING_METIS
                                   : !strcmp(o, "cholmod") ? UMFPACK_ORDERING_CHOLMOD
                                   : !strcmp(o, "best")    ? UMFPACK_ORDERING_BEST
                                                           : UMFPACK_ORDERING_AMD;
    return EO_OK;
}

static void umf_destroy(void *st, eo_ctx *ctx)
{
    umf_state *s = st;
    if (s->numeric) umfpack_di_free_numeric(&s->numeric);
    if (s->symbolic) umfpack_di_free_symbolic(&s->symbolic);
    eo_csc_full_destroy(&s->F);
    eo_free(ctx, s->Wi);
    eo_free(ctx, s->W);
    s->Wi = NULL;
    s->W = NULL;
}

static int umf_status(eo_ctx *ctx, int status, const char *what)
{
    return eo_error(ctx, status == UMFPACK_ERROR_out_of_memory ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                    "umfpack: %s failed (UMFPACK status %d)", what, status);
}

static int umf_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    umf_state *s = st;
    umf_destroy(s, ctx);
    int rc = eo_csc_full_create(ctx, A, &s->F);
    if (rc < 0) return rc;
    size_t m = (size_t)(A->n ? A->n : 1);
    s->Wi = eo_malloc(ctx, m * sizeof(int));
    s->W = eo_malloc(ctx, 5 * m * sizeof(double));
    if (!s->Wi || !s->W) {
        umf_destroy(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "umfpack: out of memory (n=%d)", A->n);
    }
    if (A->n == 0) return EO_OK;
    int status = umfpack_di_symbolic(A->n, A->n, s->F->colptr, s->F->rowind, NULL, &s->symbolic, s->control,
                                     s->info);
    if (status != UMFPACK_OK) {
        umf_destroy(s, ctx);
        return umf_status(ctx, status, "umfpack_di_symbolic");
    }
    return EO_OK;
}

static int umf_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    (void)stats;
    umf_state *s = st;
    if (A->n == 0) return EO_OK;
    eo_csc_full_fill(s->F, A);
    if (s->numeric) umfpack_di_free_numeric(&s->numeric);
    int status = umfpack_di_numeric(s->F->colptr, s->F->rowind, s->F->val, s->symbolic, &s->numeric, s->control,
                                    s->info);
    if (status == UMFPACK_WARNING_singular_matrix)
        return eo_error(ctx, EO_ERR_LINSOLVE, "umfpack: matrix singular (a zero pivot in the LU factorization)");
    if (status != UMFPACK_OK) return umf_status(ctx, status, "umfpack_di_numeric");
    return EO_OK;
}

static int umf_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    umf_state *s = st;
    stats->iterations = 0;
    if (s->F->n == 0) return EO_OK;
    /* A is symmetric: A x = b, the transpose would do as well */
    int status = umfpack_di_wsolve(UMFPACK_A, s->F->colptr, s->F->rowind, s->F->val, x, b, s->numeric, s->control,
                                   s->info, s->Wi, s->W);
    if (status != UMFPACK_OK) return umf_status(ctx, status, "umfpack_di_wsolve");
    return EO_OK;
}

const eo_linsolve_type eo_linsolve_umfpack = {
    .info = {.name = "umfpack",
             .summary = "UMFPACK sparse LU of the full matrix (indefinite or any non-singular A)",
             .params = umf_desc,
             .params_size = sizeof(umf_params)},
    .state_size = sizeof(umf_state),
    .setup = umf_setup,
    .analyze = umf_analyze,
    .factor = umf_factor,
    .solve = umf_solve,
    .destroy = umf_destroy,
};
