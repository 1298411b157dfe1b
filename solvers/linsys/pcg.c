/* pcg — preconditioned conjugate gradients for symmetric positive definite A.
 *
 *   r₀ = b − A x₀,  z₀ = M⁻¹ r₀,  p₀ = z₀
 *   α_k = r_kᵀz_k / p_kᵀA p_k,   x_{k+1} = x_k + α_k p_k,   r_{k+1} = r_k − α_k A p_k
 *   z_{k+1} = M⁻¹ r_{k+1},   β_k = r_{k+1}ᵀz_{k+1} / r_kᵀz_k,   p_{k+1} = z_{k+1} + β_k p_k
 *
 * Preconditioners M (built in `factor`):
 *   jacobi  M = diag(A). A non-positive diagonal entry proves A is not positive
 *           definite: factor returns EO_WARN_NOT_PD with that column.
 *   ichol0  zero-fill incomplete Cholesky M = L Lᵀ on the pattern of A:
 *             l_jk = (a_jk − Σ_{m<k} l_jm l_km) / l_kk   for (j,k) in the pattern,
 *             l_jj = sqrt(a_jj − Σ_{m<j} l_jm²),
 *           (Meijerink & van der Vorst 1977). IC(0) can break down (l_jj² ≤ 0) for SPD
 *           matrices that are not M-matrices; then it is recomputed for A + σ diag(A)
 *           with σ = 1e-3, 4e-3, ... (Manteuffel's shift) up to 8 times, else the
 *           Jacobi preconditioner is used (logged). The rows of L are the columns of
 *           our upper CSC, so L shares A's pattern.
 * The iteration, stopping, curvature check and warm start are cg_iter.h's (shared
 * with cg.c). No allocation in solve.
 *
 * Parameters (solver.pcg.<key>):
 *   tol             relative residual ‖b − Ax‖/‖b‖ to reach           default 1e-10
 *   max_iters       iteration cap                                     default 10000
 *   preconditioner  "jacobi" | "ichol0"                               default "jacobi"
 *   warm_start      start from the x passed to solve instead of 0     default false
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "cg_iter.h"

typedef struct pcg_params {
    double tol;              /* relative residual; default 1e-10 */
    int max_iters;           /* default 10000 */
    char preconditioner[16]; /* "jacobi" (default) or "ichol0" */
    int warm_start;          /* default false */
} pcg_params;

static const char *const preconds[] = {"jacobi", "ichol0", NULL};

static const eo_param_desc pcg_desc[] = {
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(pcg_params, tol), .def.d = 1e-10,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "relative residual |b - Ax|/|b| to reach"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(pcg_params, max_iters),
     .def.i = 10000, .min = 1, .range = EO_RANGE_MIN, .help = "iteration cap"},
    {.key = "preconditioner", .kind = EO_PARAM_CHOICE, .offset = offsetof(pcg_params, preconditioner),
     .size = sizeof(((pcg_params *)0)->preconditioner), .def.s = "jacobi", .choices = preconds,
     .help = "jacobi (diagonal) or ichol0 (zero-fill incomplete Cholesky)"},
    {.key = "warm_start", .kind = EO_PARAM_BOOL, .offset = offsetof(pcg_params, warm_start),
     .def.i = 0, .help = "start from the x passed in (else from 0)"},
    {0},
};

typedef struct pcg_state {
    eo_cg cg;        /* iteration workspace and borrowed A (cg_iter.h) */
    int ichol0;      /* preconditioner "ichol0" requested (else "jacobi") */
    int ic;          /* IC(0) factor in use (else Jacobi) */
    double *dinv;
    double *L;       /* ichol0: values of L on A's pattern (row j of L = column j of A) */
    double *w;       /* ichol0: dense row scratch, all zero between uses */
} pcg_state;

static int pcg_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    const pcg_params *p = params;
    pcg_state *s = st;
    s->cg.o = (eo_cg_opts){
        .tol = p->tol, .max_iters = p->max_iters, .warm_start = p->warm_start, .name = "pcg"};
    s->ichol0 = strcmp(p->preconditioner, "ichol0") == 0;
    return EO_OK;
}

static void pcg_destroy(void *st, eo_ctx *ctx)
{
    pcg_state *s = st;
    eo_cg_destroy(&s->cg, ctx);
    double **arr[] = {&s->dinv, &s->L, &s->w};
    for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) {
        eo_free(ctx, *arr[i]);
        *arr[i] = NULL;
    }
}

static int pcg_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    pcg_state *s = st;
    pcg_destroy(s, ctx);
    int rc = eo_cg_analyze(&s->cg, A, 1, ctx);
    if (rc < 0) return rc;
    s->dinv = eo_malloc(ctx, (size_t)(A->n ? A->n : 1) * sizeof(double));
    int ok = s->dinv != NULL;
    if (ok && s->ichol0) {
        s->L = eo_malloc(ctx, (size_t)(A->nnz ? A->nnz : 1) * sizeof(double));
        s->w = eo_calloc(ctx, (size_t)(A->n ? A->n : 1), sizeof(double));
        ok = s->L && s->w;
    }
    if (!ok) {
        pcg_destroy(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "pcg: out of memory (n=%d)", A->n);
    }
    return EO_OK;
}

/* IC(0) of A + sigma·diag(A), row by row (row j of L = column j of the upper CSC, rows
 * sorted, diagonal last). Returns -1 on success, else the failing row. */
static int ichol0(pcg_state *s, const eo_csc *A, double sigma)
{
    const int *cp = A->colptr, *ri = A->rowind;
    double *L = s->L, *w = s->w;
    for (int j = 0; j < A->n; j++) {
        int end = cp[j + 1] - 1; /* diagonal position */
        for (int p = cp[j]; p < end; p++) {
            int k = ri[p];
            double v = A->val[p];
            for (int q = cp[k]; q < cp[k + 1] - 1; q++) v -= L[q] * w[ri[q]];
            v /= L[cp[k + 1] - 1];
            L[p] = v;
            w[k] = v;
        }
        double djj = A->val[end] * (1 + sigma);
        for (int p = cp[j]; p < end; p++) {
            djj -= L[p] * L[p];
            w[ri[p]] = 0;
        }
        if (!(djj > 0) || !isfinite(djj)) return j;
        L[end] = sqrt(djj);
    }
    return -1;
}

static int pcg_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    pcg_state *s = st;
    s->cg.A = A;
    for (int j = 0; j < A->n; j++) {
        double a = A->val[A->colptr[j + 1] - 1];
        if (!(a > 0)) {
            stats->not_pd_column = j;
            return eo_error_at(ctx, EO_WARN_NOT_PD, EO_ERRLOC_ITEM(NULL, -1, "column", j),
                               "pcg: diagonal entry %.3g <= 0: matrix not positive definite", a);
        }
        s->dinv[j] = 1 / a;
    }
    s->ic = 0;
    if (s->L) {
        double sigma = 0;
        for (int t = 0; t <= 8; t++) {
            int bad = ichol0(s, A, sigma);
            if (bad < 0) {
                s->ic = 1;
                break;
            }
            for (int i = 0; i < A->n; i++) s->w[i] = 0; /* scratch may be dirty at failure */
            eo_log(ctx, EO_LOG_DEBUG, "pcg: IC(0) breakdown at row %d with shift %g", bad, sigma);
            sigma = sigma == 0 ? 1e-3 : 4 * sigma;
        }
        if (!s->ic) eo_log(ctx, EO_LOG_INFO, "pcg: IC(0) failed with every shift; using Jacobi");
    }
    return EO_OK;
}

/* z = M⁻¹ r (an eo_cg_precond_fn) */
static void precond(const void *pc, const double *r, double *z)
{
    const pcg_state *s = pc;
    const int n = s->cg.n;
    if (!s->ic) {
        for (int i = 0; i < n; i++) z[i] = r[i] * s->dinv[i];
        return;
    }
    const int *cp = s->cg.A->colptr, *ri = s->cg.A->rowind;
    const double *L = s->L;
    for (int j = 0; j < n; j++) { /* L y = r, rows of L */
        double v = r[j];
        for (int p = cp[j]; p < cp[j + 1] - 1; p++) v -= L[p] * z[ri[p]];
        z[j] = v / L[cp[j + 1] - 1];
    }
    for (int j = n - 1; j >= 0; j--) { /* Lᵀ z = y, columns of Lᵀ = rows of L */
        z[j] /= L[cp[j + 1] - 1];
        double zj = z[j];
        for (int p = cp[j]; p < cp[j + 1] - 1; p++) z[ri[p]] -= L[p] * zj;
    }
}

static int pcg_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    pcg_state *s = st;
    return eo_cg_solve(&s->cg, precond, s, b, x, stats, ctx);
}

const eo_linsolve_type eo_linsolve_pcg = {
    .info = {.name = "pcg",
             .summary = "preconditioned conjugate gradients (Jacobi or IC(0))",
             .params = pcg_desc,
             .params_size = sizeof(pcg_params)},
    .state_size = sizeof(pcg_state),
    .setup = pcg_setup,
    .analyze = pcg_analyze,
    .factor = pcg_factor,
    .solve = pcg_solve,
    .destroy = pcg_destroy,
};
