/* pcg — preconditioned conjugate gradients for symmetric positive definite A.
 *
 *   r₀ = b − A x₀,  z₀ = M⁻¹ r₀,  p₀ = z₀
 *   α_k = r_kᵀz_k / p_kᵀA p_k,   x_{k+1} = x_k + α_k p_k,   r_{k+1} = r_k − α_k A p_k
 *   z_{k+1} = M⁻¹ r_{k+1},   β_k = r_{k+1}ᵀz_{k+1} / r_kᵀz_k,   p_{k+1} = z_{k+1} + β_k p_k
 *
 * Preconditioners M (solver.pcg.preconditioner; built in `factor`):
 *   jacobi         M = diag(A). A non-positive diagonal entry proves A is not positive
 *                  definite: factor returns EO_WARN_NOT_PD with that column (all
 *                  preconditioners run this check).
 *   ic0 (ichol0)   zero-fill incomplete Cholesky M = L Lᵀ on the pattern of A
 *                  (Meijerink & van der Vorst 1977) with Manteuffel's shift on
 *                  breakdown, Jacobi if every shift fails (ic0.h).
 *   cholmod_reuse  M = L Lᵀ, a CHOLMOD supernodal Cholesky factor of an EARLIER matrix
 *                  of the same pattern, kept across the Newton iterations of a problem.
 *                  Exactly when it refactors (numeric cholmod_factorize of the matrix
 *                  passed to that factor call):
 *                    1. at the first factor after an analyze of a new pattern (an
 *                       analyze of an identical pattern keeps the factor);
 *                    2. at the factor call following a solve that took more than
 *                       `refactor_iters` iterations;
 *                    3. inside a solve that hits its cap (or a non-finite residual)
 *                       with a reused factor: the current matrix is factored at once and
 *                       solved directly. The cap of a solve with an earlier matrix's
 *                       factor is `reuse_max_iters` (default 4 × refactor_iters), not
 *                       max_iters: the refactorization is due at the next factor call
 *                       anyway (rule 2), so CG iterations past a factorization's worth
 *                       only cost. From the second iteration on, a solve whose average
 *                       contraction so far, (‖r_k‖/‖r₀‖)^(1/k), projects more iterations
 *                       than the cap stops there too (measured on the IPC bar twist with
 *                       10-node p2p0 tets at ν = 0.499, n = 14 631: stale factors
 *                       contracting 0.75–0.95 per iteration ran to the cap at the
 *                       solver's own tolerance, 4 ms per iteration against 29 ms per
 *                       factorization; stopping at the projection took the 4 steps from
 *                       3.5 to 2.8 s of CPU). Measured on the IPC bunny (19k tets, n = 14 010) from
 *                       a tangled random start, where consecutive Hessians differ by
 *                       orders of magnitude: stale-factor solves took up to 3 973
 *                       iterations (20 s of CPU for one direction, ~5 ms per iteration
 *                       against ~30 ms for a factorization);
 *                    4. after the previous refactorization failed (not PD);
 *                    5. at the first factor call of a new problem (eo_linsolve_forget:
 *                       eo_solver_minimize at the start of every minimization, so the
 *                       factor is kept across the Newton iterations of a time step, not
 *                       across steps, and a restarted run takes the same path).
 *                  A refactorization of a matrix that is not positive definite returns
 *                  EO_WARN_NOT_PD with the column, as cholmod does. stats.n_refactor
 *                  counts the refactorizations; with a fresh factor PCG converges in one
 *                  or two iterations (the factor is exact up to rounding), so a solve
 *                  with a fresh factor is done directly (x = L⁻ᵀL⁻¹b, 0 iterations),
 *                  like cholmod's. The factor's ordering is `ordering`.
 *   amg            hypre BoomerAMG, one V-cycle (amg.h): systems AMG with 3 unknowns
 *                  per node and nodal coarsening, plus the rigid-body rotations when
 *                  eo_linsolve_set_coordinates gave the node positions. Set up at every
 *                  factor. Only when built with hypre (-Dhypre); otherwise creating a
 *                  pcg with it fails with EO_ERR_UNSUPPORTED and a message saying so.
 *   gmg            one symmetric V-cycle of the Galerkin multigrid of gmg.c (Xian, Tong &
 *                  Liu 2019; its hierarchy from the node coordinates of
 *                  eo_linsolve_set_coordinates, built at analyze; Galerkin products,
 *                  block Gauss–Seidel set-up and coarsest CHOLMOD factor at every
 *                  factor). Hierarchy options gmg_prolongation and gmg_coarse_size; the
 *                  others are solver.gmg's defaults. Without coordinates: CHOLMOD on A.
 * The iteration, stopping, curvature check and warm start are cg_iter.h's (shared
 * with cg.c): non-positive curvature pᵀAp <= 0 is reported (EO_WARN_NOT_PD, value in
 * stats.curvature) and the direction is never used. eo_linsolve_set_rtol overrides
 * `tol` (inexact Newton). No allocation by pcg in solve (CHOLMOD's and hypre's set-up
 * use their own allocators in factor).
 *
 * Parameters (solver.pcg.<key>):
 *   tol                   relative residual ‖b − Ax‖/‖b‖ to reach      default 1e-10
 *   max_iters             iteration cap                                default 10000
 *   preconditioner        jacobi | ic0 | ichol0 | cholmod_reuse | amg | gmg   default "jacobi"
 *   warm_start            start from the x passed to solve             default false
 *   refactor_iters        cholmod_reuse: refactor after a solve needing more
 *                         iterations than this                         default 20
 *   reuse_max_iters       cholmod_reuse: iteration cap of a solve with an earlier
 *                         matrix's factor (then refactor and solve directly);
 *                         0 = 4 × refactor_iters                       default 0
 *   ordering              cholmod_reuse: fill-reducing ordering of the factor
 *                         (as solver.cholmod.ordering)                 default "amd"
 *   amg_strong_threshold  BoomerAMG strength threshold                 default 0.5
 *   amg_rbm               amg: rigid-body modes from the coordinates   default false
 *                         (measured: 10 instead of 20 iterations, but 3.7x the setup time
 *                         on the 108k-tet bar; off is 2.4x faster per Newton system)
 *   gmg_prolongation      gmg: linear | affine                         default "linear"
 *   gmg_coarse_size       gmg: unknowns of the coarsest level at most  default 1500
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "cg_iter.h"
#include "cholmod_util.h"
#include "ic0.h"
#if EO_HAVE_HYPRE
#include "amg.h"
#endif
#include "gmg.h"

typedef struct pcg_params {
    double tol;              /* relative residual; default 1e-10 */
    int max_iters;           /* default 10000 */
    char preconditioner[16]; /* default "jacobi" */
    int warm_start;          /* default false */
    int refactor_iters;      /* cholmod_reuse; default 20 */
    int reuse_max_iters;     /* cholmod_reuse: cap of a stale-factor solve; 0 = 4 refactor_iters */
    double amg_strong_threshold; /* default 0.5 */
    int amg_rbm;             /* default false (measured) */
    char gmg_prolongation[16]; /* default "linear" */
    int gmg_coarse_size;     /* default 1500 */
    char ordering[16];       /* cholmod_reuse: default "amd" */
} pcg_params;

/* "amg" is always a valid name (so configs and docs do not depend on the build); a build
 * without hypre refuses it at create with EO_ERR_UNSUPPORTED and says how to get it. */
static const char *const preconds[] = {"jacobi", "ic0", "ichol0", "cholmod_reuse", "amg", "gmg", NULL};
static const char *const gmg_prolongations[] = {"linear", "affine", NULL};
static const char *const orderings[] = EO_CHM_ORDERINGS;

static const eo_param_desc pcg_desc[] = {
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(pcg_params, tol), .def.d = 1e-10,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "relative residual |b - Ax|/|b| to reach"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(pcg_params, max_iters),
     .def.i = 10000, .min = 1, .range = EO_RANGE_MIN, .help = "iteration cap"},
    {.key = "preconditioner", .kind = EO_PARAM_CHOICE, .offset = offsetof(pcg_params, preconditioner),
     .size = sizeof(((pcg_params *)0)->preconditioner), .def.s = "jacobi", .choices = preconds,
     .help = "jacobi (diagonal), ic0 = ichol0 (zero-fill incomplete Cholesky), cholmod_reuse (an "
             "earlier CHOLMOD factor, refactored per refactor_iters), amg (hypre BoomerAMG; builds "
             "without hypre refuse it at create), gmg (one V-cycle of the Galerkin multigrid, see solver.gmg)"},
    {.key = "warm_start", .kind = EO_PARAM_BOOL, .offset = offsetof(pcg_params, warm_start),
     .def.i = 0, .help = "start from the x passed in (else from 0)"},
    {.key = "refactor_iters", .kind = EO_PARAM_INT, .offset = offsetof(pcg_params, refactor_iters), .def.i = 20,
     .min = 1, .range = EO_RANGE_MIN,
     .help = "cholmod_reuse: a solve that needs more PCG iterations than this makes the next factor "
             "refactor the current matrix (a solve that hits reuse_max_iters refactors at once)"},
    {.key = "reuse_max_iters", .kind = EO_PARAM_INT, .offset = offsetof(pcg_params, reuse_max_iters), .def.i = 0,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "cholmod_reuse: iteration cap of a solve with an earlier matrix's factor, after which the current "
             "matrix is factored and solved directly; 0 = 4*refactor_iters (bounded by max_iters)"},
    {.key = "amg_strong_threshold", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(pcg_params, amg_strong_threshold), .def.d = 0.5, .min = 0, .max = 1,
     .range = EO_RANGE_OPEN, .help = "amg: BoomerAMG strength threshold (0.5 for 3D elasticity)"},
    {.key = "amg_rbm", .kind = EO_PARAM_BOOL, .offset = offsetof(pcg_params, amg_rbm), .def.i = 0,
     .help = "amg: add the rigid-body rotations to the interpolation when node coordinates are set "
             "(halves the PCG iterations on the twist bars but triples the setup: 2.4x slower in total "
             "at 108k tets, bench_linsolve; default off)"},
    {.key = "gmg_prolongation", .kind = EO_PARAM_CHOICE, .offset = offsetof(pcg_params, gmg_prolongation),
     .size = sizeof(((pcg_params *)0)->gmg_prolongation), .def.s = "linear", .choices = gmg_prolongations,
     .help = "gmg: coarse spaces, linear (trilinear on nested grids) or affine (Xian et al.'s skinning space); "
             "see solver.gmg.prolongation"},
    {.key = "gmg_coarse_size", .kind = EO_PARAM_INT, .offset = offsetof(pcg_params, gmg_coarse_size),
     .def.i = 1500, .min = 3, .range = EO_RANGE_MIN,
     .help = "gmg: coarsening stops at a level with at most this many unknowns (CHOLMOD there)"},
    {.key = "ordering", .kind = EO_PARAM_CHOICE, .offset = offsetof(pcg_params, ordering),
     .size = sizeof(((pcg_params *)0)->ordering), .def.s = EO_CHM_DEFAULT_ORDERING, .choices = orderings,
     .help = "cholmod_reuse: fill-reducing ordering of the factor (as solver.cholmod.ordering)"},
    {0},
};

enum { PC_JACOBI, PC_IC0, PC_REUSE, PC_AMG, PC_GMG };

typedef struct pcg_state {
    eo_cg cg;        /* iteration workspace and borrowed A (cg_iter.h) */
    pcg_params p;
    int pc;          /* requested preconditioner */
    int ic;          /* IC(0) factor in use (else Jacobi) */
    double *dinv;
    double *L;       /* ic0: values of L on A's pattern (row j of L = column j of A) */
    double *w;       /* ic0: dense row scratch, all zero between uses */
    /* cholmod_reuse */
    eo_chm chm;
    int have_factor, need_refactor, fresh; /* fresh: factor is of the current A */
    int *pat;        /* copy of colptr and rowind of the analyzed pattern */
    int pat_n, pat_nnz;
#if EO_HAVE_HYPRE
    eo_amg *amg;
#endif
    eo_gmg *gmg;
    double *xyz;     /* set_coordinates copy (3 nv), for amg and gmg */
    int nv;
} pcg_state;

static int pcg_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    pcg_state *s = st;
    s->p = *(const pcg_params *)params;
    s->cg.o = (eo_cg_opts){
        .tol = s->p.tol, .max_iters = s->p.max_iters, .warm_start = s->p.warm_start, .name = "pcg"};
    const char *pc = s->p.preconditioner;
    s->pc = !strcmp(pc, "ic0") || !strcmp(pc, "ichol0") ? PC_IC0
            : !strcmp(pc, "cholmod_reuse")              ? PC_REUSE
            : !strcmp(pc, "amg")                        ? PC_AMG
            : !strcmp(pc, "gmg")                        ? PC_GMG
                                                        : PC_JACOBI;
#if !EO_HAVE_HYPRE
    if (s->pc == PC_AMG)
        return eo_error(ctx, EO_ERR_UNSUPPORTED,
                        "pcg: preconditioner \"amg\" (hypre BoomerAMG) is not in this build: install "
                        "libhypre-dev and configure with -Dhypre=enabled (or auto)");
#endif
    if (s->pc == PC_REUSE) {
        eo_chm_start(&s->chm);
        eo_chm_ordering(&s->chm, s->p.ordering);
        s->chm.c.supernodal = CHOLMOD_SUPERNODAL;
        s->chm.c.final_ll = 1;
    }
    return EO_OK;
}

/* everything sized by analyze (the CHOLMOD factor only if `all`) */
static void free_pattern_data(pcg_state *s, eo_ctx *ctx, int all)
{
    eo_cg_destroy(&s->cg, ctx);
    double **arr[] = {&s->dinv, &s->L, &s->w};
    for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) {
        eo_free(ctx, *arr[i]);
        *arr[i] = NULL;
    }
#if EO_HAVE_HYPRE
    eo_amg_destroy(ctx, &s->amg);
#endif
    eo_gmg_destroy(ctx, &s->gmg);
    if (all) {
        eo_chm_free_factor(&s->chm);
        s->have_factor = s->fresh = 0;
        eo_free(ctx, s->pat);
        s->pat = NULL;
    }
}

static void pcg_destroy(void *st, eo_ctx *ctx)
{
    pcg_state *s = st;
    free_pattern_data(s, ctx, 1);
    eo_chm_finish(&s->chm);
    eo_free(ctx, s->xyz);
    s->xyz = NULL;
}

static int same_pattern(const pcg_state *s, const eo_csc *A)
{
    return s->pat && s->pat_n == A->n && s->pat_nnz == A->nnz &&
           !memcmp(s->pat, A->colptr, (size_t)(A->n + 1) * sizeof(int)) &&
           !memcmp(s->pat + A->n + 1, A->rowind, (size_t)A->nnz * sizeof(int));
}

static int pcg_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    pcg_state *s = st;
    const int keep = s->pc == PC_REUSE && same_pattern(s, A);
    free_pattern_data(s, ctx, !keep);
    int rc = eo_cg_analyze(&s->cg, A, 1, ctx);
    if (rc < 0) return rc;
    s->dinv = eo_malloc(ctx, (size_t)(A->n ? A->n : 1) * sizeof(double));
    int ok = s->dinv != NULL;
    if (ok && s->pc == PC_IC0) {
        s->L = eo_malloc(ctx, (size_t)(A->nnz ? A->nnz : 1) * sizeof(double));
        s->w = eo_calloc(ctx, (size_t)(A->n ? A->n : 1), sizeof(double));
        ok = s->L && s->w;
    }
    if (ok && s->pc == PC_REUSE && !keep) {
        s->pat = eo_malloc(ctx, (size_t)(A->n + 1 + A->nnz) * sizeof(int));
        ok = s->pat != NULL;
        if (ok) {
            memcpy(s->pat, A->colptr, (size_t)(A->n + 1) * sizeof(int));
            memcpy(s->pat + A->n + 1, A->rowind, (size_t)A->nnz * sizeof(int));
            s->pat_n = A->n;
            s->pat_nnz = A->nnz;
        }
    }
    if (!ok) {
        free_pattern_data(s, ctx, 1);
        return eo_error(ctx, EO_ERR_NOMEM, "pcg: out of memory (n=%d)", A->n);
    }
    if (s->pc == PC_REUSE && !keep) {
        rc = eo_chm_analyze(&s->chm, A, "pcg cholmod_reuse", ctx);
        if (rc < 0) {
            free_pattern_data(s, ctx, 1);
            return rc;
        }
    }
#if EO_HAVE_HYPRE
    if (s->pc == PC_AMG) {
        eo_amg_opts o = {.strong_threshold = s->p.amg_strong_threshold, .rbm = s->p.amg_rbm};
        rc = eo_amg_create(ctx, A, &o, &s->amg);
        if (rc < 0) {
            free_pattern_data(s, ctx, 1);
            return rc;
        }
        if (s->nv > 0) eo_amg_set_coordinates(s->amg, s->nv, s->xyz);
    }
#endif
    if (s->pc == PC_GMG) {
        eo_gmg_opts o = {.prolongation = strcmp(s->p.gmg_prolongation, "affine") ? EO_GMG_LINEAR : EO_GMG_AFFINE,
                         .cell = 2, .coarse_size = s->p.gmg_coarse_size, .max_levels = 10, .smooth_steps = 2,
                         .name = "pcg gmg"};
        rc = eo_gmg_create(ctx, A, &o, s->nv, s->xyz, &s->gmg);
        if (rc < 0) {
            free_pattern_data(s, ctx, 1);
            return rc;
        }
    }
    return EO_OK;
}

static int refactor(pcg_state *s, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    cholmod_sparse S = eo_chm_view(A);
    int ok = eo_chm_factorize(&s->chm, &S, 0);
    int status = s->chm.c.status;
    s->have_factor = s->fresh = 0;
    stats->n_refactor++;
    if (status == CHOLMOD_NOT_POSDEF || (ok && s->chm.L->minor < (size_t)A->n)) {
        int k = (int)s->chm.L->minor, col = eo_chm_orig(&s->chm, k);
        stats->not_pd_column = col;
        return eo_error_at(ctx, EO_WARN_NOT_PD, EO_ERRLOC_ITEM(NULL, -1, "column", col),
                           "pcg cholmod_reuse: matrix not positive definite (pivot %d of %d)", k, A->n);
    }
    if (!ok || status < CHOLMOD_OK)
        return eo_error(ctx, status == CHOLMOD_OUT_OF_MEMORY ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                        "pcg cholmod_reuse: cholmod_factorize failed (CHOLMOD status %d)", status);
    s->have_factor = s->fresh = 1;
    s->need_refactor = 0;
    return EO_OK;
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
    switch (s->pc) {
    case PC_IC0: s->ic = eo_ic0_factor(A, s->L, s->w, "pcg", ctx); break;
    case PC_REUSE:
        s->fresh = 0;
        if (!s->have_factor || s->need_refactor) return refactor(s, A, stats, ctx);
        break;
    case PC_AMG:
#if EO_HAVE_HYPRE
        return eo_amg_setup(s->amg, A, ctx);
#endif
        break;
    case PC_GMG: return eo_gmg_setup(s->gmg, A, stats, ctx);
    default: break;
    }
    return EO_OK;
}

/* z = M⁻¹ r (eo_cg_precond_fn) */
static void precond(const void *pc, const double *r, double *z)
{
    const pcg_state *s = pc;
    const int n = s->cg.n;
    if (s->ic) eo_ic0_apply(s->cg.A, s->L, r, z);
    else
        for (int i = 0; i < n; i++) z[i] = r[i] * s->dinv[i];
}

/* z = (L Lᵀ)⁻¹ r with the kept CHOLMOD factor (solve2 workspaces reused, no allocation
 * after the first call); Jacobi if CHOLMOD fails (it cannot with a valid factor). */
static void precond_chol(const void *pc, const double *r, double *z)
{
    pcg_state *s = (pcg_state *)(uintptr_t)pc;
    const int n = s->cg.n;
    cholmod_dense B;
    memset(&B, 0, sizeof B);
    B.nrow = B.nzmax = B.d = (size_t)n;
    B.ncol = 1;
    B.x = (void *)(uintptr_t)r;
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    if (cholmod_solve2(CHOLMOD_A, s->chm.L, &B, NULL, &s->chm.X, NULL, &s->chm.Y, &s->chm.E, &s->chm.c))
        memcpy(z, s->chm.X->x, (size_t)n * sizeof(double));
    else
        for (int i = 0; i < n; i++) z[i] = r[i] * s->dinv[i];
}

static int pcg_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    pcg_state *s = st;
    switch (s->pc) {
    case PC_REUSE: {
        if (s->fresh) { /* the factor is of this matrix: solve directly */
            stats->iterations = 0;
            return eo_chm_solve(&s->chm, b, x, s->cg.n, "pcg cholmod_reuse", ctx);
        }
        /* a stale factor: CG up to reuse_max_iters (rule 3 of the file comment) */
        const int cap = s->p.reuse_max_iters > 0 ? s->p.reuse_max_iters : 4 * s->p.refactor_iters;
        const int max_iters = s->cg.o.max_iters;
        if (cap < max_iters) s->cg.o.max_iters = cap;
        s->cg.project_max = cap;
        int rc = eo_cg_solve(&s->cg, precond_chol, s, b, x, stats, ctx);
        s->cg.project_max = 0;
        s->cg.o.max_iters = max_iters;
        if (stats->iterations > s->p.refactor_iters || rc == EO_WARN_NOT_CONVERGED) s->need_refactor = 1;
        if (rc != EO_WARN_NOT_CONVERGED) return rc;
        int frc = refactor(s, s->cg.A, stats, ctx);
        if (frc != EO_OK) return frc;
        stats->iterations = 0;
        return eo_chm_solve(&s->chm, b, x, s->cg.n, "pcg cholmod_reuse", ctx);
    }
#if EO_HAVE_HYPRE
    case PC_AMG: return eo_cg_solve(&s->cg, eo_amg_apply, s->amg, b, x, stats, ctx);
#endif
    case PC_GMG: return eo_cg_solve(&s->cg, eo_gmg_apply, s->gmg, b, x, stats, ctx);
    default: return eo_cg_solve(&s->cg, precond, s, b, x, stats, ctx);
    }
}

static void pcg_set_rtol(void *st, double rtol) { eo_cg_set_rtol(&((pcg_state *)st)->cg, rtol); }

static int pcg_set_coordinates(void *st, int nv, const double *xyz, eo_ctx *ctx)
{
    pcg_state *s = st;
    if (s->pc != PC_AMG && s->pc != PC_GMG) return EO_OK;
    eo_free(ctx, s->xyz);
    s->xyz = NULL;
    s->nv = 0;
    if (nv == 0) return EO_OK;
    s->xyz = eo_malloc(ctx, (size_t)3 * nv * sizeof(double));
    if (!s->xyz) return eo_error(ctx, EO_ERR_NOMEM, "pcg: out of memory for %d coordinates", nv);
    memcpy(s->xyz, xyz, (size_t)3 * nv * sizeof(double));
    s->nv = nv;
#if EO_HAVE_HYPRE
    if (s->amg) eo_amg_set_coordinates(s->amg, nv, xyz);
#endif
    return EO_OK;
}

/* a new problem: cholmod_reuse refactors at the next factor call (rule 5 of the file
 * comment); the other preconditioners are built from every matrix anyway */
static void pcg_forget(void *st)
{
    pcg_state *s = st;
    if (s->pc == PC_REUSE && s->have_factor) s->need_refactor = 1;
}

const eo_linsolve_type eo_linsolve_pcg = {
    .info = {.name = "pcg",
             .summary = "preconditioned conjugate gradients (Jacobi, IC(0), reused CHOLMOD factor, "
                        "BoomerAMG, Galerkin multigrid)",
             .params = pcg_desc,
             .params_size = sizeof(pcg_params)},
    .state_size = sizeof(pcg_state),
    .setup = pcg_setup,
    .analyze = pcg_analyze,
    .factor = pcg_factor,
    .solve = pcg_solve,
    .destroy = pcg_destroy,
    .set_rtol = pcg_set_rtol,
    .set_coordinates = pcg_set_coordinates,
    .forget = pcg_forget,
};
