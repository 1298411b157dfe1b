/* A CHOLMOD factor that follows a changing set of free variables by rank updates and
 * downdates (cholmod_updown) instead of refactoring (eo_updown, linsolve.h).
 *
 * Matrix      A (n×n SPD, all variables, e.g. the PD global matrix of a scene without
 *             boundary conditions) and a free set S. The factored matrix is
 *                 Ã(S) = [ A_SS  0 ;  0  diag(A_CC) ]      (C = the constrained rest),
 *             whose free block is exactly the matrix of the eliminated problem and whose
 *             constrained rows are decoupled. Ã(S) is stored in A's pattern (explicit
 *             zeros), so one symbolic analysis serves every S.
 * Release     R (S' = S ∪ R): Δ = Ã(S') − Ã(S) has zero diagonal and is
 *                 Δ = Σ_{i∈R} (eᵢbᵢᵀ + bᵢeᵢᵀ),  bᵢ = A_{·i} on the rows of S and of the
 *             members of R before i (each off-diagonal pair counted once). With
 *             cᵢ = √‖bᵢ‖,  eᵢbᵢᵀ + bᵢeᵢᵀ = uᵢuᵢᵀ − vᵢvᵢᵀ,
 *                 uᵢ = (cᵢeᵢ + bᵢ/cᵢ)/√2,   vᵢ = (cᵢeᵢ − bᵢ/cᵢ)/√2,
 *             so L D Lᵀ is updated with U = [uᵢ] (cholmod_updown, update) and then
 *             downdated with V = [vᵢ]: the intermediate Ã(S) + UUᵀ is SPD, and so is the
 *             result. Rank 2|R| in all.
 * Pin         P (S' = S \ P): the same with the roles of U and V exchanged (update with
 *             V, downdate with U), the bᵢ taken over S' and the earlier members of P.
 * Factor      simplicial LDLᵀ (the form cholmod_updown works on), fill-reducing AMD
 *             ordering of A's pattern; C is given to CHOLMOD in the permuted row order.
 * The factor after any sequence of changes equals (to rounding) the fresh factorization
 * of Ã(S) with the same ordering: tests/test_pd_local_global.c checks 1e-10. */
#include <math.h>
#include <string.h>
#include <suitesparse/cholmod.h>

#include "elastopt/linsolve.h"

struct eo_updown {
    eo_ctx *ctx;
    int n;
    cholmod_common c;
    int started;
    eo_csc *A;              /* own copy of A */
    cholmod_sparse At;      /* header over Ã's values */
    double *val;            /* Ã(S) values, A's pattern */
    cholmod_factor *L;
    unsigned char *free_;   /* current S */
    int *pinv;              /* inverse permutation of L */
    unsigned char *mark;    /* scratch: rows allowed in bᵢ */
    double *bcol;           /* scratch column */
    int *full_colptr, *full_rowind; /* full (both triangles) pattern of A */
    double *full_val;
    long n_updown_cols;     /* columns passed to cholmod_updown in total */
    cholmod_dense *X, *Y, *E; /* cholmod_solve2's solution and workspace, kept between solves */
    double fl, lnz;         /* the analysis' factorization flops and nnz(L) */
};

static int chm_fail(eo_updown *u, const char *what)
{
    return eo_error(u->ctx, EO_ERR_INTERNAL, "updown: %s failed (CHOLMOD status %d)", what, u->c.status);
}

/* Ã(S) values from A's. */
static void fill_tilde(eo_updown *u)
{
    const eo_csc *A = u->A;
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) {
            int i = A->rowind[q];
            u->val[q] = (i == j || (u->free_[i] && u->free_[j])) ? A->val[q] : 0;
        }
}

static int factor_fresh(eo_updown *u)
{
    cholmod_free_factor(&u->L, &u->c);
    u->L = cholmod_analyze(&u->At, &u->c);
    if (!u->L) return chm_fail(u, "analyze");
    u->fl = u->c.fl;
    u->lnz = u->c.lnz;
    if (!cholmod_factorize(&u->At, u->L, &u->c)) return chm_fail(u, "factorize");
    if (u->c.status == CHOLMOD_NOT_POSDEF)
        return eo_error(u->ctx, EO_ERR_INVALID, "updown: matrix not positive definite (column %d)", (int)u->L->minor);
    const int *perm = u->L->Perm;
    for (int k = 0; k < u->n; k++) u->pinv[perm[k]] = k;
    return EO_OK;
}

int eo_updown_create(eo_ctx *ctx, const eo_csc *A, const unsigned char *is_free, eo_updown **out)
{
    *out = NULL;
    if (!A || A->n <= 0) return eo_error(ctx, EO_ERR_INVALID, "updown: empty matrix");
    eo_updown *u = eo_calloc(ctx, 1, sizeof *u);
    if (!u) return eo_error(ctx, EO_ERR_NOMEM, "updown: out of memory");
    u->ctx = ctx;
    u->n = A->n;
    int rc = eo_csc_clone(ctx, A, &u->A);
    if (rc < 0) goto fail;
    const size_t n = (size_t)A->n, nnz = (size_t)A->nnz;
    u->val = eo_malloc(ctx, nnz * sizeof(double));
    u->free_ = eo_malloc(ctx, n);
    u->mark = eo_calloc(ctx, n, 1);
    u->pinv = eo_malloc(ctx, n * sizeof(int));
    u->bcol = eo_calloc(ctx, n, sizeof(double));
    u->full_colptr = eo_calloc(ctx, n + 1, sizeof(int));
    u->full_rowind = eo_malloc(ctx, 2 * nnz * sizeof(int));
    u->full_val = eo_malloc(ctx, 2 * nnz * sizeof(double));
    if (!u->val || !u->free_ || !u->mark || !u->pinv || !u->bcol || !u->full_colptr || !u->full_rowind ||
        !u->full_val) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "updown: out of memory (n = %d)", A->n);
        goto fail;
    }
    /* full pattern (column i lists every row j with A_ij ≠ 0 stored, j ≠ i) */
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) {
            int i = A->rowind[q];
            if (i == j) continue;
            u->full_colptr[i + 1]++;
            u->full_colptr[j + 1]++;
        }
    for (int j = 0; j < A->n; j++) u->full_colptr[j + 1] += u->full_colptr[j];
    int *pos = eo_malloc(ctx, n * sizeof(int));
    if (!pos) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "updown: out of memory");
        goto fail;
    }
    memcpy(pos, u->full_colptr, n * sizeof(int));
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) {
            int i = A->rowind[q];
            if (i == j) continue;
            u->full_rowind[pos[j]] = i, u->full_val[pos[j]++] = A->val[q];
            u->full_rowind[pos[i]] = j, u->full_val[pos[i]++] = A->val[q];
        }
    eo_free(ctx, pos);
    for (size_t i = 0; i < n; i++) u->free_[i] = is_free ? (is_free[i] != 0) : 1;
    cholmod_start(&u->c);
    u->started = 1;
    u->c.print = 0;
    u->c.error_handler = NULL;
    u->c.supernodal = CHOLMOD_SIMPLICIAL;
    u->c.final_ll = 0;
    u->c.nmethods = 1;
    u->c.method[0].ordering = CHOLMOD_AMD;
    u->c.postorder = 1;
    memset(&u->At, 0, sizeof u->At);
    u->At.nrow = u->At.ncol = n;
    u->At.nzmax = nnz;
    u->At.p = u->A->colptr;
    u->At.i = u->A->rowind;
    u->At.x = u->val;
    u->At.stype = 1;
    u->At.itype = CHOLMOD_INT;
    u->At.xtype = CHOLMOD_REAL;
    u->At.dtype = CHOLMOD_DOUBLE;
    u->At.sorted = 1;
    u->At.packed = 1;
    fill_tilde(u);
    rc = factor_fresh(u);
    if (rc < 0) goto fail;
    *out = u;
    return EO_OK;
fail:
    eo_updown_destroy(&u);
    return rc;
}

void eo_updown_destroy(eo_updown **pu)
{
    if (!pu || !*pu) return;
    eo_updown *u = *pu;
    eo_ctx *ctx = u->ctx;
    if (u->started) {
        cholmod_free_factor(&u->L, &u->c);
        cholmod_free_dense(&u->X, &u->c);
        cholmod_free_dense(&u->Y, &u->c);
        cholmod_free_dense(&u->E, &u->c);
        cholmod_finish(&u->c);
    }
    eo_csc_destroy(&u->A);
    eo_free(ctx, u->val);
    eo_free(ctx, u->free_);
    eo_free(ctx, u->mark);
    eo_free(ctx, u->pinv);
    eo_free(ctx, u->bcol);
    eo_free(ctx, u->full_colptr);
    eo_free(ctx, u->full_rowind);
    eo_free(ctx, u->full_val);
    eo_free(ctx, u);
    *pu = NULL;
}

/* Build U (sign +1) and V (sign −1) for the variables `set` (k of them), the rows of
 * bᵢ being those with mark[] set (mark grows by each i as it is processed), then
 * apply: first `first` (+1 = U, −1 = V) as an update, then the other as a downdate. */
static int apply(eo_updown *u, const int *set, int k, int first)
{
    const int n = u->n;
    cholmod_sparse *C[2] = {NULL, NULL};
    int rc = EO_OK;
    /* count entries: column i has |{j marked, j ≠ i, A_ij ≠ 0}| + 1 */
    size_t nz = 0;
    for (int s = 0, pass = 0; pass < 2; pass++) {
        /* pass 0 counts; pass 1 fills (mark restored in between) */
        if (pass == 1) {
            for (int t = 0; t < k; t++) u->mark[set[t]] = 0;
            for (int c = 0; c < 2; c++) {
                C[c] = cholmod_allocate_sparse((size_t)n, (size_t)k, nz, 1, 1, 0, CHOLMOD_REAL, &u->c);
                if (!C[c]) {
                    rc = chm_fail(u, "allocate C");
                    goto done;
                }
            }
            nz = 0;
        }
        for (s = 0; s < k; s++) {
            const int i = set[s];
            double bn = 0;
            int cnt = 0;
            for (int q = u->full_colptr[i]; q < u->full_colptr[i + 1]; q++) {
                int j = u->full_rowind[q];
                if (!u->mark[j]) continue;
                cnt++;
                bn += u->full_val[q] * u->full_val[q];
            }
            if (pass == 0) {
                nz += (size_t)cnt + 1;
            } else {
                bn = sqrt(bn);
                const double ci = bn > 0 ? sqrt(bn) : 1, r2 = sqrt(0.5);
                int *Cp[2] = {C[0]->p, C[1]->p}, *Ci[2] = {C[0]->i, C[1]->i};
                double *Cx[2] = {C[0]->x, C[1]->x};
                /* entries in permuted row order, sorted: collect then insertion sort */
                size_t p0 = nz;
                for (int c = 0; c < 2; c++) Cp[c][s] = (int)p0;
                size_t p = p0;
                Ci[0][p] = Ci[1][p] = u->pinv[i];
                Cx[0][p] = Cx[1][p] = r2 * ci;
                p++;
                for (int q = u->full_colptr[i]; q < u->full_colptr[i + 1]; q++) {
                    int j = u->full_rowind[q];
                    if (!u->mark[j]) continue;
                    double b = u->full_val[q] / ci;
                    Ci[0][p] = Ci[1][p] = u->pinv[j];
                    Cx[0][p] = r2 * b;
                    Cx[1][p] = -r2 * b;
                    p++;
                }
                for (size_t a = p0 + 1; a < p; a++) /* sort rows (same order in U and V) */
                    for (size_t b = a; b > p0 && Ci[0][b - 1] > Ci[0][b]; b--)
                        for (int c = 0; c < 2; c++) {
                            int ti = Ci[c][b];
                            Ci[c][b] = Ci[c][b - 1];
                            Ci[c][b - 1] = ti;
                            double tx = Cx[c][b];
                            Cx[c][b] = Cx[c][b - 1];
                            Cx[c][b - 1] = tx;
                        }
                nz = p;
                for (int c = 0; c < 2; c++) Cp[c][s + 1] = (int)nz;
            }
            u->mark[i] = 1;
        }
    }
    const int up = first > 0 ? 0 : 1; /* index of the update matrix */
    if (!cholmod_updown(1, C[up], u->L, &u->c)) {
        rc = chm_fail(u, "update");
        goto done;
    }
    if (!cholmod_updown(0, C[1 - up], u->L, &u->c)) {
        rc = chm_fail(u, "downdate");
        goto done;
    }
    if (u->c.status == CHOLMOD_NOT_POSDEF) {
        rc = eo_error(u->ctx, EO_ERR_INVALID, "updown: downdate lost positive definiteness");
        goto done;
    }
    u->n_updown_cols += 2L * k;
done:
    cholmod_free_sparse(&C[0], &u->c);
    cholmod_free_sparse(&C[1], &u->c);
    return rc;
}

int eo_updown_set_free(eo_updown *u, const unsigned char *is_free, int *rank)
{
    const int n = u->n;
    int np = 0, nr = 0, rc = EO_OK;
    if (rank) *rank = 0;
    int *set = eo_malloc(u->ctx, (size_t)n * sizeof(int));
    if (!set) return eo_error(u->ctx, EO_ERR_NOMEM, "updown: out of memory");
    /* pins first: S' = S \ P, rows of bᵢ = S' (then the earlier members of P) */
    for (int i = 0; i < n; i++) {
        int f = is_free[i] != 0;
        if (u->free_[i] && !f) set[np++] = i;
    }
    if (np > 0) {
        for (int i = 0; i < n; i++) u->mark[i] = u->free_[i] && is_free[i];
        rc = apply(u, set, np, -1);
        if (rc < 0) goto done;
        for (int t = 0; t < np; t++) u->free_[set[t]] = 0;
    }
    /* releases: S' = S ∪ R, rows of bᵢ = S (then the earlier members of R) */
    for (int i = 0; i < n; i++)
        if (!u->free_[i] && is_free[i]) set[nr++] = i;
    if (nr > 0) {
        for (int i = 0; i < n; i++) u->mark[i] = u->free_[i];
        rc = apply(u, set, nr, +1);
        if (rc < 0) goto done;
        for (int t = 0; t < nr; t++) u->free_[set[t]] = 1;
    }
    fill_tilde(u);
    if (rank) *rank = 2 * (np + nr);
done:
    eo_free(u->ctx, set);
    return rc;
}

int eo_updown_refactor(eo_updown *u)
{
    fill_tilde(u);
    if (!cholmod_factorize(&u->At, u->L, &u->c)) return chm_fail(u, "factorize");
    if (u->c.status == CHOLMOD_NOT_POSDEF) return eo_error(u->ctx, EO_ERR_INVALID, "updown: not positive definite");
    return EO_OK;
}

int eo_updown_solve_multi(eo_updown *u, int nrhs, const double *b, double *x)
{
    if (nrhs < 1) return eo_error(u->ctx, EO_ERR_INVALID, "updown: %d right-hand sides", nrhs);
    cholmod_dense B;
    memset(&B, 0, sizeof B);
    B.nrow = B.d = (size_t)u->n;
    B.ncol = (size_t)nrhs;
    B.nzmax = (size_t)u->n * (size_t)nrhs;
    B.x = (void *)b;
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    /* the solution and workspace are reused from the previous solve of the same width */
    if (!cholmod_solve2(CHOLMOD_A, u->L, &B, NULL, &u->X, NULL, &u->Y, &u->E, &u->c)) return chm_fail(u, "solve");
    memcpy(x, u->X->x, (size_t)u->n * (size_t)nrhs * sizeof(double));
    return EO_OK;
}

int eo_updown_solve(eo_updown *u, const double *b, double *x) { return eo_updown_solve_multi(u, 1, b, x); }

const eo_csc *eo_updown_matrix(const eo_updown *u) { return u->A; }
const unsigned char *eo_updown_free_set(const eo_updown *u) { return u->free_; }

int eo_updown_factor_dense(eo_updown *u, double *LD)
{
    const int n = u->n;
    cholmod_factor *F = cholmod_copy_factor(u->L, &u->c);
    if (!F) return chm_fail(u, "copy factor");
    cholmod_sparse *S = cholmod_factor_to_sparse(F, &u->c);
    cholmod_free_factor(&F, &u->c);
    if (!S) return chm_fail(u, "factor to sparse");
    memset(LD, 0, (size_t)n * n * sizeof(double));
    const int *p = S->p, *ii = S->i;
    const double *xv = S->x;
    for (int j = 0; j < n; j++)
        for (int q = p[j]; q < p[j + 1]; q++) LD[(size_t)ii[q] * n + j] = xv[q];
    cholmod_free_sparse(&S, &u->c);
    return EO_OK;
}

long eo_updown_columns(const eo_updown *u) { return u->n_updown_cols; }

void eo_updown_costs(const eo_updown *u, double *flops, double *lnz)
{
    if (flops) *flops = u->fl;
    if (lnz) *lnz = u->lnz;
}
