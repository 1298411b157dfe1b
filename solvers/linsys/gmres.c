/* gmres — restarted GMRES(m) (Saad & Schultz 1986) with right preconditioning, for
 * symmetric indefinite (or, through the same code, any non-singular) systems.
 *
 * Each cycle minimizes ‖b − A x‖ over x₀ + M⁻¹ K_m(A M⁻¹, r₀):
 *   r₀ = b − A x₀,  β = ‖r₀‖,  v₁ = r₀/β
 *   for j = 1..m:  w = A M⁻¹ v_j;  modified Gram–Schmidt: h_ij = wᵀv_i, w −= h_ij v_i
 *                  (i = 1..j);  h_{j+1,j} = ‖w‖,  v_{j+1} = w / h_{j+1,j}
 *                  Givens rotations G_1..G_j reduce H̄_j (j+1 × j) to upper triangular
 *                  R_j and g = β e₁ to G g; |g_{j+1}| = ‖b − A x_j‖ (exact arithmetic)
 *   y = R⁻¹ g_{1..j},  x = x₀ + M⁻¹ V_j y,  restart from x.
 * Right preconditioning keeps the minimized residual the true one, so the test
 * ‖b − Ax‖ <= tol ‖b‖ is on the unpreconditioned residual; it is re-checked with an
 * explicit b − Ax at each restart (the recursive |g_{j+1}| can drift). A zero h_{j+1,j}
 * is the lucky breakdown (x exact in the space). There is no positive-definiteness
 * test: GMRES solves indefinite systems; it stops with EO_WARN_NOT_CONVERGED (stats
 * residual set) at max_iters (total inner iterations) or on non-finite values, e.g.
 * for a singular A. Workspace ((m+1) n + O(m²) doubles) is allocated in analyze.
 *
 * Preconditioners M (built in factor): jacobi M = |diag(A)| (a zero entry counts as
 * 1; |·| keeps M positive for indefinite A), ic0 (IC(0), see ic0.h; falls back to
 * Jacobi when it breaks down, as on an indefinite A), none.
 *
 * Parameters (solver.gmres.<key>):
 *   restart         Krylov dimension m per cycle                        default 30
 *   tol             relative residual ‖b − Ax‖/‖b‖ to reach             default 1e-10
 *   max_iters       total iteration cap (matrix-vector products)       default 10000
 *   preconditioner  "jacobi" | "ic0" | "none"                          default "jacobi"
 *   warm_start      start from the x passed to solve instead of 0      default false
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "ic0.h"

typedef struct gmres_params {
    int restart;             /* default 30 */
    double tol;              /* default 1e-10 */
    int max_iters;           /* default 10000 */
    char preconditioner[16]; /* default "jacobi" */
    int warm_start;          /* default false */
} gmres_params;

static const char *const preconds[] = {"jacobi", "ic0", "none", NULL};

static const eo_param_desc gmres_desc[] = {
    {.key = "restart", .kind = EO_PARAM_INT, .offset = offsetof(gmres_params, restart), .def.i = 30, .min = 1,
     .max = 1000, .range = EO_RANGE_CLOSED, .help = "Krylov dimension m of each GMRES(m) cycle"},
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(gmres_params, tol), .def.d = 1e-10, .min = 0,
     .range = EO_RANGE_POSITIVE, .help = "relative residual |b - Ax|/|b| to reach"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(gmres_params, max_iters), .def.i = 10000,
     .min = 1, .range = EO_RANGE_MIN, .help = "total iteration cap (inner iterations over all cycles)"},
    {.key = "preconditioner", .kind = EO_PARAM_CHOICE, .offset = offsetof(gmres_params, preconditioner),
     .size = sizeof(((gmres_params *)0)->preconditioner), .def.s = "jacobi", .choices = preconds,
     .help = "right preconditioner: jacobi (|diag A|), ic0 (incomplete Cholesky, Jacobi if it breaks "
             "down), none"},
    {.key = "warm_start", .kind = EO_PARAM_BOOL, .offset = offsetof(gmres_params, warm_start), .def.i = 0,
     .help = "start from the x passed in (else from 0)"},
    {0},
};

enum { PC_JACOBI, PC_IC0, PC_NONE };

typedef struct gmres_state {
    gmres_params p;
    int pc, ic; /* requested preconditioner; IC(0) factor in use */
    double rtol;
    int n, m;
    const eo_csc *A;
    double *V;             /* (m+1) n Krylov basis */
    double *H;             /* (m+1) m, column-major */
    double *cs, *sn, *g, *y;
    double *w, *z;         /* n each */
    double *dinv, *L, *ws; /* Jacobi; IC(0) values (nnz) and its zero scratch (n) */
} gmres_state;

static int gmres_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    gmres_state *s = st;
    s->p = *(const gmres_params *)params;
    s->pc = !strcmp(s->p.preconditioner, "ic0") ? PC_IC0 : !strcmp(s->p.preconditioner, "none") ? PC_NONE : PC_JACOBI;
    return EO_OK;
}

static void gmres_destroy(void *st, eo_ctx *ctx)
{
    gmres_state *s = st;
    double **arr[] = {&s->V, &s->H, &s->cs, &s->sn, &s->g, &s->y, &s->w, &s->z, &s->dinv, &s->L, &s->ws};
    for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) {
        eo_free(ctx, *arr[i]);
        *arr[i] = NULL;
    }
}

static int gmres_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    gmres_state *s = st;
    gmres_destroy(s, ctx);
    s->n = A->n;
    s->m = s->p.restart;
    size_t n = (size_t)(A->n ? A->n : 1), m = (size_t)s->m;
    s->V = eo_malloc(ctx, (m + 1) * n * sizeof(double));
    s->H = eo_malloc(ctx, (m + 1) * m * sizeof(double));
    s->cs = eo_malloc(ctx, m * sizeof(double));
    s->sn = eo_malloc(ctx, m * sizeof(double));
    s->g = eo_malloc(ctx, (m + 1) * sizeof(double));
    s->y = eo_malloc(ctx, m * sizeof(double));
    s->w = eo_malloc(ctx, n * sizeof(double));
    s->z = eo_malloc(ctx, n * sizeof(double));
    s->dinv = eo_malloc(ctx, n * sizeof(double));
    int ok = s->V && s->H && s->cs && s->sn && s->g && s->y && s->w && s->z && s->dinv;
    if (ok && s->pc == PC_IC0) {
        s->L = eo_malloc(ctx, (size_t)(A->nnz ? A->nnz : 1) * sizeof(double));
        s->ws = eo_calloc(ctx, n, sizeof(double));
        ok = s->L && s->ws;
    }
    if (!ok) {
        gmres_destroy(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "gmres: out of memory (n=%d, restart %d)", A->n, s->m);
    }
    return EO_OK;
}

static int gmres_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    (void)stats;
    gmres_state *s = st;
    s->A = A;
    for (int j = 0; j < A->n; j++) {
        double a = fabs(A->val[A->colptr[j + 1] - 1]);
        s->dinv[j] = a > 0 && isfinite(a) ? 1 / a : 1;
    }
    s->ic = s->pc == PC_IC0 ? eo_ic0_factor(A, s->L, s->ws, "gmres", ctx) : 0;
    return EO_OK;
}

/* z = M⁻¹ r */
static void precond(const gmres_state *s, const double *r, double *z)
{
    if (s->ic) eo_ic0_apply(s->A, s->L, r, z);
    else if (s->pc == PC_NONE) memcpy(z, r, (size_t)s->n * sizeof(double));
    else
        for (int i = 0; i < s->n; i++) z[i] = r[i] * s->dinv[i];
}

static double dot(int n, const double *a, const double *b)
{
    double t = 0;
    for (int i = 0; i < n; i++) t += a[i] * b[i];
    return t;
}

static int gmres_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    gmres_state *s = st;
    const int n = s->n, m = s->m;
    double *V = s->V, *H = s->H, *g = s->g, *w = s->w, *z = s->z;
    const double tol = s->rtol > 0 ? s->rtol : s->p.tol;
    const double bnorm = sqrt(dot(n, b, b));
    stats->iterations = 0;
    stats->residual = 0;
    if (!s->p.warm_start || bnorm == 0) memset(x, 0, (size_t)n * sizeof(double));
    if (bnorm == 0) return EO_OK;
    const double stop = tol * bnorm;
    int its = 0;
    double rnorm;
    for (;;) {
        eo_csc_symv(s->A, x, w); /* true residual at each (re)start */
        for (int i = 0; i < n; i++) V[i] = b[i] - w[i];
        rnorm = sqrt(dot(n, V, V));
        if (rnorm <= stop || its >= s->p.max_iters || !isfinite(rnorm)) break;
        for (int i = 0; i < n; i++) V[i] /= rnorm;
        memset(g, 0, (size_t)(m + 1) * sizeof(double));
        g[0] = rnorm;
        int k = 0; /* columns built in this cycle */
        while (k < m && its < s->p.max_iters) {
            double *vk = V + (size_t)k * n, *vn = V + (size_t)(k + 1) * n, *h = H + (size_t)k * (m + 1);
            precond(s, vk, z);
            eo_csc_symv(s->A, z, vn);
            for (int i = 0; i <= k; i++) { /* modified Gram–Schmidt */
                const double *vi = V + (size_t)i * n;
                double hik = dot(n, vn, vi);
                h[i] = hik;
                for (int t = 0; t < n; t++) vn[t] -= hik * vi[t];
            }
            double hn = sqrt(dot(n, vn, vn));
            h[k + 1] = hn;
            if (hn > 0)
                for (int t = 0; t < n; t++) vn[t] /= hn;
            for (int i = 0; i < k; i++) { /* previous rotations on the new column */
                double a = h[i], c = h[i + 1];
                h[i] = s->cs[i] * a + s->sn[i] * c;
                h[i + 1] = -s->sn[i] * a + s->cs[i] * c;
            }
            double a = h[k], c = h[k + 1], r = hypot(a, c);
            s->cs[k] = r > 0 ? a / r : 1;
            s->sn[k] = r > 0 ? c / r : 0;
            h[k] = r;
            h[k + 1] = 0;
            g[k + 1] = -s->sn[k] * g[k];
            g[k] = s->cs[k] * g[k];
            k++;
            its++;
            if (fabs(g[k]) <= stop || hn == 0 || !isfinite(g[k])) break;
        }
        /* y = R⁻¹ g, x += M⁻¹ V y */
        for (int i = k - 1; i >= 0; i--) {
            double v = g[i];
            for (int j = i + 1; j < k; j++) v -= H[(size_t)j * (m + 1) + i] * s->y[j];
            double rii = H[(size_t)i * (m + 1) + i];
            s->y[i] = rii != 0 ? v / rii : 0;
        }
        memset(w, 0, (size_t)n * sizeof(double));
        for (int j = 0; j < k; j++) {
            const double *vj = V + (size_t)j * n, yj = s->y[j];
            for (int t = 0; t < n; t++) w[t] += yj * vj[t];
        }
        precond(s, w, z);
        for (int t = 0; t < n; t++) x[t] += z[t];
    }
    stats->iterations = its;
    stats->residual = rnorm / bnorm;
    if (rnorm <= stop) return EO_OK;
    return eo_error(ctx, EO_WARN_NOT_CONVERGED,
                    "gmres: %s after %d iterations (restart %d), relative residual %.3g (tol %.3g)",
                    isfinite(rnorm) ? "not converged" : "non-finite residual", its, m, stats->residual, tol);
}

static void gmres_set_rtol(void *st, double rtol) { ((gmres_state *)st)->rtol = rtol > 0 ? rtol : 0; }

const eo_linsolve_type eo_linsolve_gmres = {
    .info = {.name = "gmres",
             .summary = "restarted GMRES(m), right-preconditioned (Jacobi, IC(0), none); indefinite A",
             .params = gmres_desc,
             .params_size = sizeof(gmres_params)},
    .state_size = sizeof(gmres_state),
    .setup = gmres_setup,
    .analyze = gmres_analyze,
    .factor = gmres_factor,
    .solve = gmres_solve,
    .destroy = gmres_destroy,
    .set_rtol = gmres_set_rtol,
};
