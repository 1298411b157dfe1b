/* gmg — Galerkin geometric multigrid for the 3-unknowns-per-node systems of a mesh
 * (Xian, Tong & Liu 2019, "A Scalable Galerkin Multigrid Method for Real-time Simulation
 * of Deformable Objects", ACM TOG 38(6), 162).
 *
 * The paper: a hierarchy of nested coarse spaces x = U_l z_l built once from the rest
 * shape, coarse matrices by the Galerkin projection A_l = U_lᵀ A U_l, recomputed at every
 * Newton iteration (the projections are fixed, so only the products are redone); its
 * coarse space is "skinning space": each coarse handle carries an affine map (12
 * unknowns) and every vertex follows ONE handle (piecewise-constant skinning weights), so
 * that the coarse matrices stay sparse while the resolution drops aggressively; V-cycles
 * with a smoother on every level and a direct solve on the coarsest; used inside Newton
 * and projective dynamics. (The abstract and opening pages were what the search tool could
 * read; the clustering, smoother and cycle settings below are this file's choices.)
 *
 * Hierarchy (built in analyze from the pattern and eo_linsolve_set_coordinates' rest
 * positions of the FREE vertices, in the free numbering of the matrix). Every level's
 * unknowns are nodes with 3 components (x, y, z) and every prolongation is P_l = W_l ⊗ I₃
 * with a sparse scalar W_l (rows: level-l nodes, columns: level-(l+1) nodes), so all
 * matrices are 3×3-block sparse. Grids: cubes of side H_l = cell·h·2^(l−1) (h = mean
 * length of the matrix graph's edges between nodes, l = 1, 2, ...), one origin (the
 * bounding-box corner) for all levels, so the levels are nested.
 *   prolongation = "affine" (the paper's skinning space): the level-1 clusters are the
 *     occupied grid cubes; a cluster with centroid c and vertex covariance Σ = Σ_k λ_k
 *     e_k e_kᵀ carries the node "translation" t and one node a_k per direction kept
 *     (λ_k > 1e-4 λ_max): x_i = t + Σ_k a_k φ_k(p_i), φ_k(p) = e_kᵀ(p − c)/√λ_k — the
 *     affine map of the paper (12 unknowns with three directions), written in the
 *     cluster's principal axes and scaled so that Σ_i φ_k φ_m = N δ_km (W_l's columns are
 *     orthogonal; flat or tiny clusters drop the degenerate directions instead of making
 *     A_1 singular). Level l+1 clusters the level-l clusters by the cubes of side H_{l+1};
 *     a coarse affine map restricted to a child cluster is the child's affine map
 *     (t_a = t_A + Σ_m a_Am φ_Am(c_a), a_ak = Σ_m a_Am (e_Amᵀ e_ak) √λ_ak/√λ_Am), so
 *     U_{l+1} = U_l W_l exactly (nested skinning spaces).
 *   prolongation = "linear" (default): trilinear interpolation from the nodes of the grid
 *     of side H_l (the coarse spaces of classical geometric multigrid, continuous
 *     piecewise (tri)linear, no tetrahedralization needed); grid nodes that interpolate to
 *     no finer node are dropped. Measured on the clamp-projected Hessians of the first
 *     cantilever step at cells 20r×2r×2r, r = 1, 2, 4 (tests/test_gmg.c, 2, 3, 4 levels):
 *     V-cycle residual factor 0.44, 0.37, 0.34 (mesh-independent, improving), against
 *     0.49, 0.57, 0.70 (growing with the levels) for the discontinuous affine clusters;
 *     both are offered, linear is the default.
 *   Coarsening stops when a level has <= coarse_size unknowns, after max_levels levels, or
 *   when a level would keep more than 70% of the unknowns of the one above.
 * Galerkin products (factor, every Newton iteration): A_{l+1} = W_lᵀ A_l W_l blockwise,
 *   (A_{l+1})_JM = Σ_I Σ_K W_IJ W_KM (A_l)_IK. The block patterns of A_l W_l and A_{l+1}
 *   are computed once (analyze); numerically each row I of A_l W_l is formed once in a
 *   dense row buffer and scattered into the rows J of W_l's row I by a merge along the
 *   sorted column lists — O(nnz(A_l)·|W row| + |W row|·nnz(A_l W_l row)) block flops, no
 *   search, no allocation.
 * V-cycle (symmetric, so it is a valid PCG preconditioner): smooth_steps forward block
 *   Gauss–Seidel sweeps (3×3 diagonal blocks inverted in factor), restriction r_{l+1} =
 *   W_lᵀ(b − A_l x), the cycle on level l+1, prolongation x += W_l x_{l+1}, smooth_steps
 *   backward sweeps. Coarsest level: CHOLMOD supernodal Cholesky (AMD), analyzed once.
 * Uses: `solver.linear = "gmg"` iterates x_{k+1} = x_k + V(b − A x_k) from x_0 = 0 (or
 *   warm) until ‖b − Ax‖ <= tol ‖b‖ (EO_WARN_NOT_CONVERGED at max_iters, on divergence
 *   ‖r‖ > 1e6 ‖r_0‖ or non-finite values; set_rtol overrides tol for inexact Newton);
 *   `solver.pcg.preconditioner = "gmg"` applies one V-cycle per PCG iteration.
 * Differences from the paper: CPU and serial (the paper's timings are on a GPU); clusters
 *   are grid cubes, not the paper's clustering; the smoother is 3×3-block Gauss–Seidel
 *   (symmetric), the affine handles are split into 3×3 blocks for it; the default coarse
 *   space is trilinear (measured above), the paper's affine one is prolongation = affine.
 * Measured (bench/results/gmg-*.txt; process CPU, shared 2-core machine): per Newton
 *   system of the twist bar to rtol 1e-8, pcg+gmg 0.55 s at 108k tets and 1.16 s at 292k
 *   (11 PCG iterations at both), pcg+BoomerAMG 1.07 / 3.64 s, CHOLMOD 1.13 / 8.58 s; a
 *   whole time step with ew2: 3.05 / 7.90 s against 6.78 / 22.9 (BoomerAMG) and 4.36 / 30.5
 *   (CHOLMOD). The affine spaces: 0.83 / 2.15 s per system, 16-17 PCG iterations.
 * Without node coordinates (or 3 nv != n, or n <= coarse_size) there is one level:
 *   CHOLMOD on A, and the iteration converges in one cycle.
 * A diagonal block (or the coarsest matrix) that is not positive definite proves A is not
 *   (a nonzero column of W_l gives a positive block; the composite prolongation to the
 *   coarsest level is made of full column rank in create: coarsest_rank): factor returns
 *   EO_WARN_NOT_PD, with the column on level 0.
 *
 * Parameters (solver.gmg.<key>):
 *   tol           relative residual ‖b − Ax‖/‖b‖ to reach              default 1e-10
 *   max_iters     V-cycle cap                                          default 500
 *   warm_start    start from the x passed to solve                     default false
 *   prolongation  linear | affine                                      default "linear"
 *   cell          level-1 cube side / mean edge length                 default 2
 *   coarse_size   unknowns at which coarsening stops (CHOLMOD below)   default 1500
 *   max_levels    levels including the finest                          default 10
 *   smooth_steps  Gauss–Seidel sweeps before and after each correction default 2
 *                 (1 sweep: factors 0.69/0.59/0.55; 3 sweeps: 0.29/0.25/0.29)
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h> /* after complex.h's I is defined by it: undone below, the code names nodes I */
#undef I

#include "cholmod_util.h"
#include "gmg.h"

/* ------------------------------------------------------------ sparse structures -------- */

/* block CSR, both triangles, 3×3 row-major blocks, columns sorted in each row */
typedef struct bsr {
    int n, nnz;
    int *ptr, *col, *diag; /* diag: position of (I,I) */
    double *val;           /* 9 nnz */
} bsr;

/* scalar CSR */
typedef struct spm {
    int n, m, nnz;
    int *ptr, *col;
    double *val;
} spm;

typedef struct level {
    bsr A;
    spm W, WT;         /* to the next coarser level (none on the coarsest) */
    int *apptr, *apcol; /* pattern of A W (rows of this level, coarse columns) */
    double *dinv;      /* 9 per node */
    double *x, *b, *r; /* 3 n */
} level;

struct eo_gmg {
    eo_gmg_opts o;
    int n, nlev;
    level lev[EO_GMG_MAX_LEVELS];
    int *dst0; /* 2 per CSC entry of A: positions in lev[0].A.val (-1 none) */
    int nnz0;
    const eo_csc *A; /* borrowed at setup */
    /* coarsest level: CHOLMOD on an upper CSC (lev[nlev-1] values; or A itself) */
    eo_chm chm;
    eo_csc *Cc;
    int *csrc;
    /* Galerkin workspace */
    int *mark;
    double *buf;
    double t_gal, t_coarse;
    int ndropped; /* coarsest nodes dropped as dependent (coarsest_rank) */
};

static void bsr_free(eo_ctx *ctx, bsr *B)
{
    eo_free(ctx, B->ptr);
    eo_free(ctx, B->col);
    eo_free(ctx, B->diag);
    eo_free(ctx, B->val);
    memset(B, 0, sizeof *B);
}

static void spm_free(eo_ctx *ctx, spm *S)
{
    eo_free(ctx, S->ptr);
    eo_free(ctx, S->col);
    eo_free(ctx, S->val);
    memset(S, 0, sizeof *S);
}

void eo_gmg_destroy(eo_ctx *ctx, eo_gmg **gp)
{
    if (!gp || !*gp) return;
    eo_gmg *g = *gp;
    for (int l = 0; l < EO_GMG_MAX_LEVELS; l++) {
        level *L = &g->lev[l];
        bsr_free(ctx, &L->A);
        spm_free(ctx, &L->W);
        spm_free(ctx, &L->WT);
        eo_free(ctx, L->apptr);
        eo_free(ctx, L->apcol);
        eo_free(ctx, L->dinv);
        eo_free(ctx, L->x);
        eo_free(ctx, L->b);
        eo_free(ctx, L->r);
    }
    eo_free(ctx, g->dst0);
    eo_free(ctx, g->csrc);
    eo_free(ctx, g->mark);
    eo_free(ctx, g->buf);
    eo_csc_destroy(&g->Cc);
    eo_chm_finish(&g->chm);
    eo_free(ctx, g);
    *gp = NULL;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* position of column c in row i of (ptr, col), -1 if absent */
static int find_col(const int *ptr, const int *col, int i, int c)
{
    int lo = ptr[i], hi = ptr[i + 1] - 1;
    while (lo <= hi) {
        int mid = (lo + hi) / 2;
        if (col[mid] == c) return mid;
        if (col[mid] < c) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

/* ------------------------------------------------------------ level 0 from the CSC ------ */

static int level0_pattern(eo_gmg *g, const eo_csc *A, eo_ctx *ctx)
{
    const int nb = A->n / 3;
    bsr *B = &g->lev[0].A;
    B->n = nb;
    B->ptr = eo_calloc(ctx, (size_t)nb + 1, sizeof(int));
    int *cnt = eo_calloc(ctx, (size_t)nb + 1, sizeof(int));
    int *last = eo_malloc(ctx, (size_t)(nb ? nb : 1) * sizeof(int));
    if (!B->ptr || !cnt || !last) goto nomem;
    /* upper bound per block row: entries of the CSC touching it (duplicates removed later) */
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) {
            int I = A->rowind[q] / 3, J = j / 3;
            cnt[I]++;
            if (I != J) cnt[J]++;
        }
    int tot = 0;
    for (int I = 0; I < nb; I++) {
        int c = cnt[I];
        cnt[I] = tot;
        tot += c;
    }
    cnt[nb] = tot;
    int *tmp = eo_malloc(ctx, (size_t)(tot ? tot : 1) * sizeof(int));
    int *fill = eo_malloc(ctx, (size_t)(nb ? nb : 1) * sizeof(int));
    if (!tmp || !fill) {
        eo_free(ctx, tmp);
        eo_free(ctx, fill);
        goto nomem;
    }
    memcpy(fill, cnt, (size_t)nb * sizeof(int));
    for (int I = 0; I < nb; I++) last[I] = -1;
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) {
            int I = A->rowind[q] / 3, J = j / 3;
            tmp[fill[I]++] = J;
            if (I != J) tmp[fill[J]++] = I;
        }
    /* sort + unique per row */
    int nnz = 0;
    for (int I = 0; I < nb; I++) {
        int s = cnt[I], e = fill[I];
        qsort(tmp + s, (size_t)(e - s), sizeof(int), cmp_int);
        int u = 0;
        for (int q = s; q < e; q++)
            if (u == 0 || tmp[s + u - 1] != tmp[q]) tmp[s + u++] = tmp[q];
        fill[I] = u;
        nnz += u;
    }
    B->nnz = nnz;
    B->col = eo_malloc(ctx, (size_t)(nnz ? nnz : 1) * sizeof(int));
    B->diag = eo_malloc(ctx, (size_t)(nb ? nb : 1) * sizeof(int));
    B->val = eo_malloc(ctx, (size_t)(nnz ? nnz : 1) * 9 * sizeof(double));
    g->dst0 = eo_malloc(ctx, (size_t)(A->nnz ? A->nnz : 1) * 2 * sizeof(int));
    if (!B->col || !B->diag || !B->val || !g->dst0) {
        eo_free(ctx, tmp);
        eo_free(ctx, fill);
        goto nomem;
    }
    B->ptr[0] = 0;
    for (int I = 0; I < nb; I++) {
        memcpy(B->col + B->ptr[I], tmp + cnt[I], (size_t)fill[I] * sizeof(int));
        B->ptr[I + 1] = B->ptr[I] + fill[I];
        B->diag[I] = find_col(B->ptr, B->col, I, I);
    }
    eo_free(ctx, tmp);
    eo_free(ctx, fill);
    g->nnz0 = A->nnz;
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) {
            int i = A->rowind[q], I = i / 3, J = j / 3, a = i % 3, b = j % 3;
            g->dst0[2 * q] = find_col(B->ptr, B->col, I, J) * 9 + a * 3 + b;
            g->dst0[2 * q + 1] = i != j ? find_col(B->ptr, B->col, J, I) * 9 + b * 3 + a : -1;
        }
    eo_free(ctx, cnt);
    eo_free(ctx, last);
    return EO_OK;
nomem:
    eo_free(ctx, cnt);
    eo_free(ctx, last);
    return eo_error(ctx, EO_ERR_NOMEM, "%s: out of memory (level 0, n=%d)", g->o.name, A->n);
}

/* ------------------------------------------------------------ coarse spaces ------------ */

/* symmetric 3×3 eigen-decomposition by cyclic Jacobi: S = V diag(w) Vᵀ, V columns e_k
 * (V[3*r + k] = (e_k)_r), w descending */
static void eig3(const double *S, double *w, double *V)
{
    double a[9];
    memcpy(a, S, sizeof a);
    for (int i = 0; i < 9; i++) V[i] = (i % 4) == 0;
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
        double dia = a[0] * a[0] + a[4] * a[4] + a[8] * a[8];
        if (off <= 1e-30 * dia || off == 0) break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                double apq = a[3 * p + q];
                if (apq == 0) continue;
                double th = (a[3 * q + q] - a[3 * p + p]) / (2 * apq);
                double t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
                double c = 1 / sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 3; k++) { /* a = Jᵀ a J */
                    double akp = a[3 * k + p], akq = a[3 * k + q];
                    a[3 * k + p] = c * akp - s * akq;
                    a[3 * k + q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = a[3 * p + k], aqk = a[3 * q + k];
                    a[3 * p + k] = c * apk - s * aqk;
                    a[3 * q + k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; k++) {
                    double vkp = V[3 * k + p], vkq = V[3 * k + q];
                    V[3 * k + p] = c * vkp - s * vkq;
                    V[3 * k + q] = s * vkp + c * vkq;
                }
            }
    }
    for (int k = 0; k < 3; k++) w[k] = a[4 * k];
    for (int i = 0; i < 2; i++) /* sort descending */
        for (int j = 0; j < 2 - i; j++)
            if (w[j] < w[j + 1]) {
                double t = w[j];
                w[j] = w[j + 1];
                w[j + 1] = t;
                for (int r = 0; r < 3; r++) {
                    t = V[3 * r + j];
                    V[3 * r + j] = V[3 * r + j + 1];
                    V[3 * r + j + 1] = t;
                }
            }
}

/* A cluster (affine) or a grid node (linear) of some level. */
typedef struct cnode {
    int cell[3];     /* grid cell (affine: the cluster's cube; linear: node index) */
    double cnt, s[3], S[6]; /* affine: vertices, Σp, Σppᵀ (xx xy xz yy yz zz) */
    double c[3];     /* centroid (affine) or position (linear) */
    double e[9];     /* affine: directions, e_k = column k */
    double sig[3];   /* affine: √λ_k */
    int k;           /* affine: directions kept */
    int first;       /* index of its first node (translation) in the level's numbering */
} cnode;

typedef struct trip {
    int row, col;
    double w;
} trip;

static int cmp_trip(const void *a, const void *b)
{
    const trip *x = a, *y = b;
    if (x->row != y->row) return (x->row > y->row) - (x->row < y->row);
    return (x->col > y->col) - (x->col < y->col);
}

/* CSR of W (nf × nc) and its transpose from triplets (sorted in place, no duplicates) */
static int spm_from_trips(eo_ctx *ctx, trip *t, int nt, int nf, int nc, spm *W, spm *WT)
{
    qsort(t, (size_t)nt, sizeof *t, cmp_trip);
    W->n = nf, W->m = nc, W->nnz = nt;
    WT->n = nc, WT->m = nf, WT->nnz = nt;
    W->ptr = eo_calloc(ctx, (size_t)nf + 1, sizeof(int));
    W->col = eo_malloc(ctx, (size_t)(nt ? nt : 1) * sizeof(int));
    W->val = eo_malloc(ctx, (size_t)(nt ? nt : 1) * sizeof(double));
    WT->ptr = eo_calloc(ctx, (size_t)nc + 1, sizeof(int));
    WT->col = eo_malloc(ctx, (size_t)(nt ? nt : 1) * sizeof(int));
    WT->val = eo_malloc(ctx, (size_t)(nt ? nt : 1) * sizeof(double));
    if (!W->ptr || !W->col || !W->val || !WT->ptr || !WT->col || !WT->val) return EO_ERR_NOMEM;
    for (int q = 0; q < nt; q++) {
        W->ptr[t[q].row + 1]++;
        W->col[q] = t[q].col;
        W->val[q] = t[q].w;
        WT->ptr[t[q].col + 1]++;
    }
    for (int i = 0; i < nf; i++) W->ptr[i + 1] += W->ptr[i];
    for (int j = 0; j < nc; j++) WT->ptr[j + 1] += WT->ptr[j];
    int *fill = eo_malloc(ctx, (size_t)(nc ? nc : 1) * sizeof(int));
    if (!fill) return EO_ERR_NOMEM;
    memcpy(fill, WT->ptr, (size_t)nc * sizeof(int));
    for (int i = 0; i < nf; i++) /* rows ascending: WT columns come out sorted */
        for (int q = W->ptr[i]; q < W->ptr[i + 1]; q++) {
            int p = fill[W->col[q]]++;
            WT->col[p] = i;
            WT->val[p] = W->val[q];
        }
    eo_free(ctx, fill);
    return EO_OK;
}

static void cell_of(const double *p, const double *o, double H, const int *ncell, int *c)
{
    for (int d = 0; d < 3; d++) {
        int k = (int)floor((p[d] - o[d]) / H);
        c[d] = k < 0 ? 0 : k >= ncell[d] ? ncell[d] - 1 : k;
    }
}

/* affine cluster statistics -> centroid, directions, scales */
static void cluster_finish(cnode *A)
{
    for (int d = 0; d < 3; d++) A->c[d] = A->s[d] / A->cnt;
    double C[9] = {A->S[0] / A->cnt - A->c[0] * A->c[0], A->S[1] / A->cnt - A->c[0] * A->c[1],
                   A->S[2] / A->cnt - A->c[0] * A->c[2], 0, A->S[3] / A->cnt - A->c[1] * A->c[1],
                   A->S[4] / A->cnt - A->c[1] * A->c[2], 0, 0, A->S[5] / A->cnt - A->c[2] * A->c[2]};
    C[3] = C[1], C[6] = C[2], C[7] = C[5];
    double w[3];
    eig3(C, w, A->e);
    A->k = 0;
    for (int k = 0; k < 3; k++)
        if (A->cnt >= 2 && w[k] > 1e-4 * w[0] && w[k] > 0) {
            A->sig[k] = sqrt(w[k]);
            A->k = k + 1;
        }
}

/* One coarsening step from the nodes `fine` (nf_nodes of them, nf unknown nodes) with
 * cube side H: the coarse nodes (allocated into *coarse, count *ncn), their number of
 * unknown nodes *nc, and W (nf × nc) with its transpose. level_from_vertices: `fine`
 * are vertices (one node each). */
static int coarsen(eo_gmg *g, eo_ctx *ctx, const cnode *fine, int nfn, int nf, int from_vertices, const double *o,
                   const int *ncell, double H, cnode **coarse, int *ncn, int *nc, spm *W, spm *WT)
{
    const int affine = g->o.prolongation == EO_GMG_AFFINE;
    *coarse = NULL;
    *ncn = *nc = 0;
    const long nx = ncell[0] + !affine, ny = ncell[1] + !affine, nz = ncell[2] + !affine;
    const long ncells = nx * ny * nz;
    if (ncells > 64L * nfn + 1024) return 1; /* a pathological box: stop coarsening */
    int *id = eo_malloc(ctx, (size_t)ncells * sizeof(int));
    cnode *cn = NULL;
    trip *t = NULL;
    int rc = EO_ERR_NOMEM;
    if (!id) goto done;
    for (long q = 0; q < ncells; q++) id[q] = -1;
    int m = 0;
    if (affine) {
        /* clusters: the occupied cubes, children by their (parent) cell */
        int *par = eo_malloc(ctx, (size_t)(nfn ? nfn : 1) * sizeof(int));
        cn = eo_calloc(ctx, (size_t)(nfn ? nfn : 1), sizeof(cnode));
        if (!par || !cn) {
            eo_free(ctx, par);
            goto done;
        }
        for (int a = 0; a < nfn; a++) {
            int c[3];
            if (from_vertices) cell_of(fine[a].c, o, H, ncell, c);
            else
                for (int d = 0; d < 3; d++) c[d] = fine[a].cell[d] / 2 < ncell[d] ? fine[a].cell[d] / 2 : ncell[d] - 1;
            long q = c[0] + nx * (c[1] + ny * (long)c[2]);
            if (id[q] < 0) {
                id[q] = m;
                memcpy(cn[m].cell, c, sizeof c);
                m++;
            }
            cnode *A = &cn[id[q]];
            par[a] = id[q];
            A->cnt += fine[a].cnt;
            for (int d = 0; d < 3; d++) A->s[d] += fine[a].s[d];
            for (int d = 0; d < 6; d++) A->S[d] += fine[a].S[d];
        }
        int nodes = 0;
        for (int A = 0; A < m; A++) {
            cluster_finish(&cn[A]);
            cn[A].first = nodes;
            nodes += 1 + cn[A].k;
        }
        /* rows: every node of every fine cluster (vertex: its one node) */
        int ntr = 0;
        t = eo_malloc(ctx, (size_t)(nf ? nf : 1) * 4 * sizeof(trip));
        if (!t) {
            eo_free(ctx, par);
            goto done;
        }
        for (int a = 0; a < nfn; a++) {
            const cnode *f = &fine[a], *A = &cn[par[a]];
            const int kf = from_vertices ? 0 : f->k;
            for (int j = 0; j <= kf; j++) {
                const int row = from_vertices ? a : f->first + j;
                if (j == 0) { /* translation: t_A + Σ_m a_m φ_Am(c_a) */
                    t[ntr++] = (trip){row, A->first, 1.0};
                    for (int mm = 0; mm < A->k; mm++) {
                        double ph = 0;
                        for (int d = 0; d < 3; d++) ph += A->e[3 * d + mm] * (f->c[d] - A->c[d]);
                        ph /= A->sig[mm];
                        if (fabs(ph) > 1e-14) t[ntr++] = (trip){row, A->first + 1 + mm, ph};
                    }
                } else { /* direction j-1 of a: Σ_m a_Am (e_Amᵀ e_ak) σ_ak/σ_Am */
                    for (int mm = 0; mm < A->k; mm++) {
                        double dot = 0;
                        for (int d = 0; d < 3; d++) dot += A->e[3 * d + mm] * f->e[3 * d + j - 1];
                        double w = dot * f->sig[j - 1] / A->sig[mm];
                        if (fabs(w) > 1e-14) t[ntr++] = (trip){row, A->first + 1 + mm, w};
                    }
                }
            }
        }
        eo_free(ctx, par);
        *nc = nodes;
        rc = spm_from_trips(ctx, t, ntr, nf, nodes, W, WT);
    } else {
        /* trilinear weights of the grid nodes around each fine node */
        t = eo_malloc(ctx, (size_t)(nf ? nf : 1) * 8 * sizeof(trip));
        if (!t) goto done;
        int ntr = 0;
        for (int a = 0; a < nfn; a++) {
            int c[3];
            double u[3];
            cell_of(fine[a].c, o, H, ncell, c);
            for (int d = 0; d < 3; d++) {
                u[d] = (fine[a].c[d] - o[d]) / H - c[d];
                u[d] = u[d] < 0 ? 0 : u[d] > 1 ? 1 : u[d];
            }
            for (int corner = 0; corner < 8; corner++) {
                int b[3] = {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
                double w = 1;
                for (int d = 0; d < 3; d++) w *= b[d] ? u[d] : 1 - u[d];
                if (w < 1e-12) continue;
                long q = (c[0] + b[0]) + nx * ((c[1] + b[1]) + ny * (long)(c[2] + b[2]));
                if (id[q] < 0) id[q] = m++;
                t[ntr++] = (trip){a, id[q], w};
            }
        }
        cn = eo_calloc(ctx, (size_t)(m ? m : 1), sizeof(cnode));
        if (!cn) goto done;
        for (long q = 0; q < ncells; q++)
            if (id[q] >= 0) {
                cnode *A = &cn[id[q]];
                A->cell[0] = (int)(q % nx);
                A->cell[1] = (int)((q / nx) % ny);
                A->cell[2] = (int)(q / (nx * ny));
                for (int d = 0; d < 3; d++) A->c[d] = o[d] + H * A->cell[d];
                A->first = id[q];
            }
        *nc = m;
        rc = spm_from_trips(ctx, t, ntr, nf, m, W, WT);
    }
    *ncn = m;
done:
    eo_free(ctx, id);
    eo_free(ctx, t);
    if (rc == EO_OK) *coarse = cn;
    else eo_free(ctx, cn);
    return rc;
}

/* ------------------------------------------------------------ Galerkin patterns -------- */

/* patterns of A W (rows of level l) and of A_{l+1} = Wᵀ A W (full, sorted) */
static int galerkin_pattern(eo_gmg *g, int l, eo_ctx *ctx)
{
    level *F = &g->lev[l], *C = &g->lev[l + 1];
    const bsr *A = &F->A;
    const spm *W = &F->W, *WT = &F->WT;
    const int nf = A->n, nc = W->m;
    int *mark = g->mark;
    for (int j = 0; j < nc; j++) mark[j] = -1;
    /* A W: count, then fill */
    F->apptr = eo_calloc(ctx, (size_t)nf + 1, sizeof(int));
    if (!F->apptr) return EO_ERR_NOMEM;
    long tot = 0;
    for (int I = 0; I < nf; I++) {
        int c = 0;
        for (int q = A->ptr[I]; q < A->ptr[I + 1]; q++) {
            int K = A->col[q];
            for (int p = W->ptr[K]; p < W->ptr[K + 1]; p++)
                if (mark[W->col[p]] != I) mark[W->col[p]] = I, c++;
        }
        tot += c;
        if (tot > 2000000000L) return eo_error(ctx, EO_ERR_NOMEM, "%s: Galerkin pattern too large", g->o.name);
        F->apptr[I + 1] = (int)tot;
    }
    F->apcol = eo_malloc(ctx, (size_t)(tot ? tot : 1) * sizeof(int));
    if (!F->apcol) return EO_ERR_NOMEM;
    for (int j = 0; j < nc; j++) mark[j] = -1;
    for (int I = 0; I < nf; I++) {
        int w = F->apptr[I];
        for (int q = A->ptr[I]; q < A->ptr[I + 1]; q++) {
            int K = A->col[q];
            for (int p = W->ptr[K]; p < W->ptr[K + 1]; p++)
                if (mark[W->col[p]] != I) mark[W->col[p]] = I, F->apcol[w++] = W->col[p];
        }
        qsort(F->apcol + F->apptr[I], (size_t)(w - F->apptr[I]), sizeof(int), cmp_int);
    }
    /* Wᵀ (A W) */
    bsr *B = &C->A;
    B->n = nc;
    B->ptr = eo_calloc(ctx, (size_t)nc + 1, sizeof(int));
    B->diag = eo_malloc(ctx, (size_t)(nc ? nc : 1) * sizeof(int));
    if (!B->ptr || !B->diag) return EO_ERR_NOMEM;
    for (int j = 0; j < nc; j++) mark[j] = -1;
    tot = 0;
    for (int J = 0; J < nc; J++) {
        int c = 0;
        for (int p = WT->ptr[J]; p < WT->ptr[J + 1]; p++) {
            int I = WT->col[p];
            for (int q = F->apptr[I]; q < F->apptr[I + 1]; q++)
                if (mark[F->apcol[q]] != J) mark[F->apcol[q]] = J, c++;
        }
        tot += c;
        if (tot > 200000000L) return eo_error(ctx, EO_ERR_NOMEM, "%s: coarse pattern too large", g->o.name);
        B->ptr[J + 1] = (int)tot;
    }
    B->nnz = (int)tot;
    B->col = eo_malloc(ctx, (size_t)(tot ? tot : 1) * sizeof(int));
    B->val = eo_malloc(ctx, (size_t)(tot ? tot : 1) * 9 * sizeof(double));
    if (!B->col || !B->val) return EO_ERR_NOMEM;
    for (int j = 0; j < nc; j++) mark[j] = -1;
    for (int J = 0; J < nc; J++) {
        int w = B->ptr[J];
        for (int p = WT->ptr[J]; p < WT->ptr[J + 1]; p++) {
            int I = WT->col[p];
            for (int q = F->apptr[I]; q < F->apptr[I + 1]; q++)
                if (mark[F->apcol[q]] != J) mark[F->apcol[q]] = J, B->col[w++] = F->apcol[q];
        }
        qsort(B->col + B->ptr[J], (size_t)(w - B->ptr[J]), sizeof(int), cmp_int);
        B->diag[J] = find_col(B->ptr, B->col, J, J);
        if (B->diag[J] < 0) return eo_error(ctx, EO_ERR_INTERNAL, "%s: coarse node %d without diagonal", g->o.name, J);
    }
    return EO_OK;
}

/* A_{l+1} = Wᵀ A_l W (values) */
static void galerkin_numeric(eo_gmg *g, int l)
{
    level *F = &g->lev[l], *C = &g->lev[l + 1];
    const bsr *A = &F->A;
    const spm *W = &F->W;
    bsr *B = &C->A;
    int *mark = g->mark;
    double *buf = g->buf;
    memset(B->val, 0, (size_t)B->nnz * 9 * sizeof(double));
    for (int I = 0; I < A->n; I++) {
        const int s = F->apptr[I], e = F->apptr[I + 1], len = e - s;
        for (int q = s; q < e; q++) mark[F->apcol[q]] = q - s;
        memset(buf, 0, (size_t)len * 9 * sizeof(double));
        for (int q = A->ptr[I]; q < A->ptr[I + 1]; q++) {
            const double *a = A->val + 9 * (size_t)q;
            const int K = A->col[q];
            for (int p = W->ptr[K]; p < W->ptr[K + 1]; p++) {
                double w = W->val[p], *d = buf + 9 * (size_t)mark[W->col[p]];
                for (int t = 0; t < 9; t++) d[t] += w * a[t];
            }
        }
        for (int p = W->ptr[I]; p < W->ptr[I + 1]; p++) {
            const int J = W->col[p];
            const double w = W->val[p];
            int r = B->ptr[J];
            for (int q = 0; q < len; q++) { /* merge: both column lists sorted */
                const int M = F->apcol[s + q];
                while (B->col[r] < M) r++;
                double *d = B->val + 9 * (size_t)r;
                const double *x = buf + 9 * (size_t)q;
                for (int t = 0; t < 9; t++) d[t] += w * x[t];
            }
        }
    }
}

/* ------------------------------------------------------------ coarsest rank ---------- */

/* The composite prolongation U_c = W_0 W_1 ... W_{L-2} to the coarsest level can lose
 * column rank: trilinear interpolation from a grid whose cubes hold a thin or flat part of
 * the mesh (a sheet, a leg, an ear one or two elements thick) gives columns that agree on
 * every fine node they reach (e.g. two grid nodes on either side of a flat layer:
 * proportional columns), and then A_c = U_cᵀ A U_c is singular however positive definite
 * A is, so the coarsest Cholesky fails on a good matrix. The rank is a property of the
 * geometry: the scalar Gram matrix G = U_cᵀ U_c is factored once (LAPACK's pivoted
 * Cholesky, dpstrf, on G scaled to unit diagonal) and the coarsest nodes whose column's
 * squared residual, relative to its own squared length, is below EO_GMG_RANK_TOL
 * (numerically in the span of the others) are dropped from
 * W_{L-2}; the coarse space loses nothing it could represent. Intermediate levels may stay
 * rank deficient: their smoother needs only the diagonal blocks (positive for any
 * nonzero column), and the coarsest level's full rank keeps "A_c not positive definite ⇒ A
 * not positive definite" true. Skipped above EO_GMG_RANK_MAX coarsest nodes (dense G). */
#define EO_GMG_RANK_MAX 3000
#define EO_GMG_RANK_TOL 1e-8

static int coarsest_rank(eo_gmg *g, eo_ctx *ctx)
{
    const int L = g->nlev - 1, m = g->lev[L].A.n;
    if (L < 1 || m > EO_GMG_RANK_MAX || m == 0) return EO_OK;
    int cap = 1;
    for (int l = 1; l <= L; l++)
        if (g->lev[l].A.n > cap) cap = g->lev[l].A.n;
    double *G = eo_calloc(ctx, (size_t)m * (size_t)m, sizeof(double));
    double *acc = eo_calloc(ctx, (size_t)cap, sizeof(double));
    int *lst[2] = {eo_malloc(ctx, (size_t)cap * sizeof(int)), eo_malloc(ctx, (size_t)cap * sizeof(int))};
    double *lv[2] = {eo_malloc(ctx, (size_t)cap * sizeof(double)), eo_malloc(ctx, (size_t)cap * sizeof(double))};
    lapack_int *piv = eo_malloc(ctx, (size_t)m * sizeof(lapack_int));
    int *seen = eo_malloc(ctx, (size_t)cap * sizeof(int));
    trip *t = NULL;
    int rc = EO_ERR_NOMEM;
    if (!G || !acc || !lst[0] || !lst[1] || !lv[0] || !lv[1] || !piv || !seen) goto done;
    for (int j = 0; j < cap; j++) seen[j] = -1;
    /* G += u_i u_iᵀ for the composite row u_i of every finest node */
    for (int i = 0; i < g->lev[0].A.n; i++) {
        const spm *W0 = &g->lev[0].W;
        int n = 0, cur = 0;
        for (int p = W0->ptr[i]; p < W0->ptr[i + 1]; p++) lst[0][n] = W0->col[p], lv[0][n++] = W0->val[p];
        for (int l = 1; l < L; l++) {
            const spm *W = &g->lev[l].W;
            int k = 0;
            const int stamp = i * EO_GMG_MAX_LEVELS + l;
            for (int a = 0; a < n; a++) {
                const int I = lst[cur][a];
                for (int p = W->ptr[I]; p < W->ptr[I + 1]; p++) {
                    const int J = W->col[p];
                    if (seen[J] != stamp) seen[J] = stamp, acc[J] = 0, lst[!cur][k++] = J;
                    acc[J] += lv[cur][a] * W->val[p];
                }
            }
            for (int a = 0; a < k; a++) lv[!cur][a] = acc[lst[!cur][a]];
            cur = !cur;
            n = k;
        }
        for (int a = 0; a < n; a++)
            for (int b = 0; b < n; b++) G[(size_t)lst[cur][a] * m + lst[cur][b]] += lv[cur][a] * lv[cur][b];
    }
    /* unit diagonal: a pivot is then a column's residual relative to its own length, so a
     * short column (a grid node reached with small weights) is kept, a dependent one not */
    for (int j = 0; j < m; j++) acc[j] = G[(size_t)j * m + j] > 0 ? 1 / sqrt(G[(size_t)j * m + j]) : 0;
    for (int j = 0; j < m; j++)
        for (int i = 0; i < m; i++) G[(size_t)j * m + i] *= acc[i] * acc[j];
    lapack_int rank = m;
    const lapack_int info = LAPACKE_dpstrf(LAPACK_COL_MAJOR, 'L', m, G, m, piv, &rank, EO_GMG_RANK_TOL);
    if (info < 0) {
        rc = eo_error(ctx, EO_ERR_INTERNAL, "%s: dpstrf failed (info %d)", g->o.name, (int)info);
        goto done;
    }
    g->ndropped = m - (int)rank;
    if (rank == m) {
        rc = EO_OK;
        goto done;
    }
    /* keep the first `rank` pivots, in their old order */
    int *newid = seen;
    for (int j = 0; j < m; j++) newid[j] = -1;
    for (int a = 0; a < rank; a++) newid[piv[a] - 1] = 0;
    int k = 0;
    for (int j = 0; j < m; j++)
        if (newid[j] == 0) newid[j] = k++;
    level *F = &g->lev[L - 1];
    t = eo_malloc(ctx, (size_t)(F->W.nnz ? F->W.nnz : 1) * sizeof(trip));
    if (!t) goto done;
    int nt = 0;
    for (int I = 0; I < F->W.n; I++)
        for (int p = F->W.ptr[I]; p < F->W.ptr[I + 1]; p++)
            if (newid[F->W.col[p]] >= 0) t[nt++] = (trip){I, newid[F->W.col[p]], F->W.val[p]};
    const int nf = F->W.n;
    spm_free(ctx, &F->W);
    spm_free(ctx, &F->WT);
    eo_free(ctx, F->apptr);
    eo_free(ctx, F->apcol);
    F->apptr = F->apcol = NULL;
    bsr_free(ctx, &g->lev[L].A);
    if ((rc = spm_from_trips(ctx, t, nt, nf, k, &F->W, &F->WT)) < 0) goto done;
    rc = galerkin_pattern(g, L - 1, ctx);
    if (rc >= 0)
        eo_log(ctx, EO_LOG_DEBUG, "%s: %d of %d coarsest nodes dropped (dependent columns of the prolongation)",
               g->o.name, m - k, m);
done:
    eo_free(ctx, G);
    eo_free(ctx, acc);
    eo_free(ctx, lst[0]);
    eo_free(ctx, lst[1]);
    eo_free(ctx, lv[0]);
    eo_free(ctx, lv[1]);
    eo_free(ctx, piv);
    eo_free(ctx, seen);
    eo_free(ctx, t);
    return rc;
}

/* ------------------------------------------------------------ coarsest (CHOLMOD) ------- */

static int coarsest_pattern(eo_gmg *g, eo_ctx *ctx)
{
    const bsr *B = &g->lev[g->nlev - 1].A;
    const int n = 3 * B->n;
    int nnz = 0;
    for (int M = 0; M < B->n; M++)
        for (int q = B->ptr[M]; q < B->ptr[M + 1] && B->col[q] <= M; q++) nnz += B->col[q] < M ? 9 : 6;
    int rc = eo_csc_create(ctx, n, nnz, &g->Cc);
    if (rc < 0) return rc;
    g->csrc = eo_malloc(ctx, (size_t)(nnz ? nnz : 1) * sizeof(int));
    if (!g->csrc) return EO_ERR_NOMEM;
    eo_csc *C = g->Cc;
    int w = 0;
    for (int M = 0; M < B->n; M++)
        for (int b = 0; b < 3; b++) {
            C->colptr[3 * M + b] = w;
            for (int q = B->ptr[M]; q < B->ptr[M + 1] && B->col[q] <= M; q++) {
                const int J = B->col[q];
                for (int a = 0; a < 3; a++) {
                    if (J == M && a > b) break;
                    C->rowind[w] = 3 * J + a;
                    g->csrc[w] = 9 * q + b * 3 + a; /* (3J+a, 3M+b) = block (M,J) entry (b,a) */
                    w++;
                }
            }
        }
    C->colptr[n] = w;
    return eo_chm_analyze(&g->chm, C, g->o.name, ctx);
}

/* ------------------------------------------------------------ create ------------------- */

static int level_vectors(eo_gmg *g, int l, eo_ctx *ctx)
{
    level *L = &g->lev[l];
    size_t m = (size_t)(L->A.n ? L->A.n : 1);
    L->x = eo_malloc(ctx, 3 * m * sizeof(double));
    L->b = eo_malloc(ctx, 3 * m * sizeof(double));
    L->r = eo_malloc(ctx, 3 * m * sizeof(double));
    L->dinv = eo_malloc(ctx, 9 * m * sizeof(double));
    return L->x && L->b && L->r && L->dinv ? EO_OK : EO_ERR_NOMEM;
}

int eo_gmg_create(eo_ctx *ctx, const eo_csc *A, const eo_gmg_opts *o, int nv, const double *xyz, eo_gmg **out)
{
    *out = NULL;
    eo_gmg *g = eo_calloc(ctx, 1, sizeof *g);
    if (!g) return eo_error(ctx, EO_ERR_NOMEM, "%s: out of memory", o->name);
    g->o = *o;
    g->n = A->n;
    g->nlev = 1;
    eo_chm_start(&g->chm);
    eo_chm_ordering(&g->chm, EO_CHM_DEFAULT_ORDERING);
    g->chm.c.supernodal = CHOLMOD_SUPERNODAL;
    g->chm.c.final_ll = 1;
    cnode *fine = NULL, *coarse = NULL;
    int rc = EO_OK;
    const int multilevel = nv > 0 && 3 * nv == A->n && A->n > o->coarse_size && o->max_levels > 1;
    if (!multilevel) { /* one level: CHOLMOD on A */
        rc = eo_chm_analyze(&g->chm, A, o->name, ctx);
        if (rc < 0) goto fail;
        *out = g;
        return EO_OK;
    }
    if ((rc = level0_pattern(g, A, ctx)) < 0) goto fail;
    /* mean edge length of the node graph, bounding box */
    const bsr *B0 = &g->lev[0].A;
    double hsum = 0, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    long ne = 0;
    for (int I = 0; I < nv; I++) {
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], xyz[3 * I + d]);
            hi[d] = fmax(hi[d], xyz[3 * I + d]);
        }
        for (int q = B0->ptr[I]; q < B0->ptr[I + 1]; q++) {
            int J = B0->col[q];
            if (J <= I) continue;
            double dx = xyz[3 * I] - xyz[3 * J], dy = xyz[3 * I + 1] - xyz[3 * J + 1], dz = xyz[3 * I + 2] - xyz[3 * J + 2];
            hsum += sqrt(dx * dx + dy * dy + dz * dz);
            ne++;
        }
    }
    fine = eo_calloc(ctx, (size_t)nv, sizeof(cnode));
    g->mark = eo_malloc(ctx, (size_t)nv * sizeof(int)); /* every level has <= nv nodes... */
    if (!fine || !g->mark) {
        rc = EO_ERR_NOMEM;
        goto fail;
    }
    for (int I = 0; I < nv; I++) {
        cnode *f = &fine[I];
        memcpy(f->c, xyz + 3 * I, 3 * sizeof(double));
        f->cnt = 1;
        memcpy(f->s, f->c, sizeof f->s);
        f->S[0] = f->c[0] * f->c[0], f->S[1] = f->c[0] * f->c[1], f->S[2] = f->c[0] * f->c[2];
        f->S[3] = f->c[1] * f->c[1], f->S[4] = f->c[1] * f->c[2], f->S[5] = f->c[2] * f->c[2];
        f->first = I;
    }
    const double h = ne ? hsum / ne : 0;
    const double cell = o->cell > 0 ? o->cell : 2;
    int nfn = nv, nf = nv, maxbuf = 0, ncell[3];
    double H = cell * h;
    for (int d = 0; d < 3 && h > 0; d++) { /* level-1 cubes; each coarser level merges 2x2x2 of them */
        double c = ceil((hi[d] - lo[d]) / H - 1e-9);
        ncell[d] = c < 1 ? 1 : c > 1e6 ? 1000000 : (int)c;
    }
    for (int l = 0; h > 0 && l + 1 < o->max_levels && l + 1 < EO_GMG_MAX_LEVELS && 3 * nf > o->coarse_size; l++) {
        int ncn = 0, nc = 0;
        level *L = &g->lev[l];
        rc = coarsen(g, ctx, fine, nfn, nf, l == 0, lo, ncell, H, &coarse, &ncn, &nc, &L->W, &L->WT);
        if (rc < 0) goto fail;
        if (rc > 0 || nc == 0 || nc > 0.7 * nf) { /* coarsening stalled: stop here */
            rc = EO_OK;
            spm_free(ctx, &L->W);
            spm_free(ctx, &L->WT);
            eo_free(ctx, coarse);
            coarse = NULL;
            break;
        }
        if ((rc = galerkin_pattern(g, l, ctx)) < 0) goto fail;
        for (int I = 0; I < L->A.n; I++) {
            int len = L->apptr[I + 1] - L->apptr[I];
            if (len > maxbuf) maxbuf = len;
        }
        g->nlev = l + 2;
        eo_free(ctx, fine);
        fine = coarse;
        coarse = NULL;
        nfn = ncn;
        nf = nc;
        H *= 2;
        for (int d = 0; d < 3; d++) ncell[d] = (ncell[d] + 1) / 2;
    }
    eo_free(ctx, fine);
    fine = NULL;
    if (g->nlev > 1 && (rc = coarsest_rank(g, ctx)) < 0) goto fail;
    for (int l = 0; l < g->nlev; l++)
        if ((rc = level_vectors(g, l, ctx)) < 0) goto fail;
    g->buf = eo_malloc(ctx, (size_t)(maxbuf ? maxbuf : 1) * 9 * sizeof(double));
    if (!g->buf) {
        rc = EO_ERR_NOMEM;
        goto fail;
    }
    if (g->nlev == 1) { /* nothing coarser: CHOLMOD on A, the block copy is not needed */
        rc = eo_chm_analyze(&g->chm, A, o->name, ctx);
    } else {
        rc = coarsest_pattern(g, ctx);
    }
    if (rc < 0) goto fail;
    *out = g;
    return EO_OK;
fail:
    eo_free(ctx, fine);
    eo_free(ctx, coarse);
    eo_gmg_destroy(ctx, &g);
    if (rc == EO_ERR_NOMEM) return eo_error(ctx, EO_ERR_NOMEM, "%s: out of memory building the hierarchy (n=%d)", o->name, A->n);
    return rc;
}

/* ------------------------------------------------------------ setup -------------------- */

/* inverse of the SPD 3×3 block a (row-major) into d; 0 if not positive definite */
static int inv3_spd(const double *a, double *d)
{
    const double m1 = a[0], m2 = a[0] * a[4] - a[1] * a[3];
    const double c0 = a[4] * a[8] - a[5] * a[7], c1 = a[5] * a[6] - a[3] * a[8], c2 = a[3] * a[7] - a[4] * a[6];
    const double det = a[0] * c0 + a[1] * c1 + a[2] * c2;
    if (!(m1 > 0) || !(m2 > 0) || !(det > 0)) return 0;
    const double id = 1 / det;
    d[0] = c0 * id;
    d[1] = (a[2] * a[7] - a[1] * a[8]) * id;
    d[2] = (a[1] * a[5] - a[2] * a[4]) * id;
    d[3] = c1 * id;
    d[4] = (a[0] * a[8] - a[2] * a[6]) * id;
    d[5] = (a[2] * a[3] - a[0] * a[5]) * id;
    d[6] = c2 * id;
    d[7] = (a[1] * a[6] - a[0] * a[7]) * id;
    d[8] = (a[0] * a[4] - a[1] * a[3]) * id;
    return 1;
}

static int coarse_factor(eo_gmg *g, const eo_csc *M, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    cholmod_sparse S = eo_chm_view(M);
    int ok = eo_chm_factorize(&g->chm, &S, 0);
    int status = g->chm.c.status;
    if (status == CHOLMOD_NOT_POSDEF || (ok && g->chm.L->minor < (size_t)M->n)) {
        int k = (int)g->chm.L->minor, col = eo_chm_orig(&g->chm, k);
        const int direct = g->nlev == 1;
        stats->not_pd_column = direct ? col : -1;
        return eo_error_at(ctx, EO_WARN_NOT_PD, EO_ERRLOC_ITEM(NULL, -1, "column", direct ? col : -1),
                           "%s: %s matrix not positive definite (CHOLMOD pivot %d of %d)", g->o.name,
                           direct ? "the" : "the coarsest Galerkin", k, M->n);
    }
    if (!ok || status < CHOLMOD_OK)
        return eo_error(ctx, status == CHOLMOD_OUT_OF_MEMORY ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                        "%s: cholmod_factorize failed (CHOLMOD status %d)", g->o.name, status);
    return EO_OK;
}

int eo_gmg_setup(eo_gmg *g, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    g->A = A;
    g->t_gal = g->t_coarse = 0;
    if (g->nlev == 1) {
        double t0 = eo_wtime();
        int rc = coarse_factor(g, A, stats, ctx);
        g->t_coarse = eo_wtime() - t0;
        return rc;
    }
    double t0 = eo_wtime();
    bsr *B0 = &g->lev[0].A;
    memset(B0->val, 0, (size_t)B0->nnz * 9 * sizeof(double));
    for (int q = 0; q < A->nnz; q++) {
        B0->val[g->dst0[2 * q]] = A->val[q];
        if (g->dst0[2 * q + 1] >= 0) B0->val[g->dst0[2 * q + 1]] = A->val[q];
    }
    for (int l = 0; l + 1 < g->nlev; l++) galerkin_numeric(g, l);
    g->t_gal = eo_wtime() - t0;
    for (int l = 0; l + 1 < g->nlev; l++) {
        level *L = &g->lev[l];
        for (int I = 0; I < L->A.n; I++)
            if (!inv3_spd(L->A.val + 9 * (size_t)L->A.diag[I], L->dinv + 9 * (size_t)I)) {
                stats->not_pd_column = l == 0 ? 3 * I : -1;
                return eo_error_at(ctx, EO_WARN_NOT_PD, EO_ERRLOC_ITEM(NULL, -1, "column", l == 0 ? 3 * I : -1),
                                   "%s: diagonal 3x3 block of node %d on level %d not positive definite: matrix "
                                   "not positive definite",
                                   g->o.name, I, l);
            }
    }
    t0 = eo_wtime();
    const int *src = g->csrc;
    const double *bv = g->lev[g->nlev - 1].A.val;
    for (int q = 0; q < g->Cc->nnz; q++) g->Cc->val[q] = bv[src[q]];
    int rc = coarse_factor(g, g->Cc, stats, ctx);
    g->t_coarse = eo_wtime() - t0;
    return rc;
}

/* ------------------------------------------------------------ V-cycle ------------------ */

static void gs_sweep(const level *L, int backward)
{
    const bsr *A = &L->A;
    const int n = A->n;
    double *x = L->x;
    const double *b = L->b;
    for (int k = 0; k < n; k++) {
        const int I = backward ? n - 1 - k : k;
        double s0 = b[3 * I], s1 = b[3 * I + 1], s2 = b[3 * I + 2];
        for (int q = A->ptr[I]; q < A->ptr[I + 1]; q++) {
            const int J = A->col[q];
            if (J == I) continue;
            const double *a = A->val + 9 * (size_t)q, *y = x + 3 * J;
            s0 -= a[0] * y[0] + a[1] * y[1] + a[2] * y[2];
            s1 -= a[3] * y[0] + a[4] * y[1] + a[5] * y[2];
            s2 -= a[6] * y[0] + a[7] * y[1] + a[8] * y[2];
        }
        const double *d = L->dinv + 9 * (size_t)I;
        x[3 * I] = d[0] * s0 + d[1] * s1 + d[2] * s2;
        x[3 * I + 1] = d[3] * s0 + d[4] * s1 + d[5] * s2;
        x[3 * I + 2] = d[6] * s0 + d[7] * s1 + d[8] * s2;
    }
}

static void coarse_solve(eo_gmg *g, const double *b, double *x, int n)
{
    cholmod_dense B;
    memset(&B, 0, sizeof B);
    B.nrow = B.nzmax = B.d = (size_t)n;
    B.ncol = 1;
    B.x = (void *)(uintptr_t)b;
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    if (cholmod_solve2(CHOLMOD_A, g->chm.L, &B, NULL, &g->chm.X, NULL, &g->chm.Y, &g->chm.E, &g->chm.c))
        memcpy(x, g->chm.X->x, (size_t)n * sizeof(double));
    else
        memset(x, 0, (size_t)n * sizeof(double)); /* cannot happen with a valid factor */
}

static void vcycle(eo_gmg *g, int l)
{
    level *L = &g->lev[l];
    const int n = 3 * L->A.n;
    if (l == g->nlev - 1) {
        coarse_solve(g, L->b, L->x, n);
        return;
    }
    memset(L->x, 0, (size_t)n * sizeof(double));
    for (int s = 0; s < g->o.smooth_steps; s++) gs_sweep(L, 0);
    /* r = b − A x, restricted: b_c = Wᵀ r */
    const bsr *A = &L->A;
    for (int I = 0; I < A->n; I++) {
        double s0 = L->b[3 * I], s1 = L->b[3 * I + 1], s2 = L->b[3 * I + 2];
        for (int q = A->ptr[I]; q < A->ptr[I + 1]; q++) {
            const double *a = A->val + 9 * (size_t)q, *y = L->x + 3 * A->col[q];
            s0 -= a[0] * y[0] + a[1] * y[1] + a[2] * y[2];
            s1 -= a[3] * y[0] + a[4] * y[1] + a[5] * y[2];
            s2 -= a[6] * y[0] + a[7] * y[1] + a[8] * y[2];
        }
        L->r[3 * I] = s0, L->r[3 * I + 1] = s1, L->r[3 * I + 2] = s2;
    }
    level *C = &g->lev[l + 1];
    const spm *WT = &L->WT, *W = &L->W;
    for (int J = 0; J < WT->n; J++) {
        double s0 = 0, s1 = 0, s2 = 0;
        for (int p = WT->ptr[J]; p < WT->ptr[J + 1]; p++) {
            const double w = WT->val[p], *r = L->r + 3 * WT->col[p];
            s0 += w * r[0], s1 += w * r[1], s2 += w * r[2];
        }
        C->b[3 * J] = s0, C->b[3 * J + 1] = s1, C->b[3 * J + 2] = s2;
    }
    vcycle(g, l + 1);
    for (int I = 0; I < W->n; I++)
        for (int p = W->ptr[I]; p < W->ptr[I + 1]; p++) {
            const double w = W->val[p], *y = C->x + 3 * W->col[p];
            L->x[3 * I] += w * y[0], L->x[3 * I + 1] += w * y[1], L->x[3 * I + 2] += w * y[2];
        }
    for (int s = 0; s < g->o.smooth_steps; s++) gs_sweep(L, 1);
}

void eo_gmg_apply(const void *pc, const double *r, double *z)
{
    eo_gmg *g = (eo_gmg *)(uintptr_t)pc;
    if (g->nlev == 1) {
        coarse_solve(g, r, z, g->n);
        return;
    }
    level *L = &g->lev[0];
    memcpy(L->b, r, (size_t)g->n * sizeof(double));
    vcycle(g, 0);
    memcpy(z, L->x, (size_t)g->n * sizeof(double));
}

/* ------------------------------------------------------------ inspection --------------- */

int eo_gmg_levels(const eo_gmg *g) { return g->nlev; }
int eo_gmg_dropped(const eo_gmg *g) { return g->ndropped; }
int eo_gmg_level_n(const eo_gmg *g, int l) { return g->nlev == 1 ? g->n : 3 * g->lev[l].A.n; }
long eo_gmg_level_nnz(const eo_gmg *g, int l)
{
    return g->nlev == 1 ? 2L * (g->A ? g->A->nnz : 0) - g->n : 9L * g->lev[l].A.nnz;
}

void eo_gmg_level_dense(const eo_gmg *g, int l, double *D)
{
    const bsr *A = &g->lev[l].A;
    const int n = 3 * A->n;
    memset(D, 0, (size_t)n * n * sizeof(double));
    for (int I = 0; I < A->n; I++)
        for (int q = A->ptr[I]; q < A->ptr[I + 1]; q++)
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) D[(size_t)(3 * I + a) * n + 3 * A->col[q] + b] = A->val[9 * (size_t)q + 3 * a + b];
}

void eo_gmg_prolongation_dense(const eo_gmg *g, int l, double *P)
{
    const spm *W = &g->lev[l].W;
    const int nf = 3 * W->n, nc = 3 * W->m;
    memset(P, 0, (size_t)nf * nc * sizeof(double));
    for (int I = 0; I < W->n; I++)
        for (int p = W->ptr[I]; p < W->ptr[I + 1]; p++)
            for (int a = 0; a < 3; a++) P[(size_t)(3 * I + a) * nc + 3 * W->col[p] + a] = W->val[p];
}

void eo_gmg_setup_times(const eo_gmg *g, double *t_galerkin, double *t_coarse)
{
    *t_galerkin = g->t_gal;
    *t_coarse = g->t_coarse;
}

/* ------------------------------------------------------------ the linear solver -------- */

typedef struct gmg_params {
    double tol;            /* relative residual; default 1e-10 */
    int max_iters;         /* V-cycles; default 500 */
    int warm_start;        /* default false */
    char prolongation[16]; /* "linear" | "affine"; default "linear" */
    double cell;           /* level-1 cube side / mean edge length; default 2 */
    int coarse_size;       /* default 1500 */
    int max_levels;        /* default 10 */
    int smooth_steps;      /* default 2 */
} gmg_params;

static const char *const prolongations[] = {"linear", "affine", NULL};

static const eo_param_desc gmg_desc[] = {
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(gmg_params, tol), .def.d = 1e-10, .min = 0,
     .range = EO_RANGE_POSITIVE, .help = "relative residual |b - Ax|/|b| to reach"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(gmg_params, max_iters), .def.i = 500, .min = 1,
     .range = EO_RANGE_MIN, .help = "V-cycle cap"},
    {.key = "warm_start", .kind = EO_PARAM_BOOL, .offset = offsetof(gmg_params, warm_start), .def.i = 0,
     .help = "start from the x passed in (else from 0)"},
    {.key = "prolongation", .kind = EO_PARAM_CHOICE, .offset = offsetof(gmg_params, prolongation),
     .size = sizeof(((gmg_params *)0)->prolongation), .def.s = "linear", .choices = prolongations,
     .help = "coarse spaces: linear (trilinear interpolation from nested grids of cubes; V-cycle factor "
             "0.44/0.37/0.34 on the cantilever refined 1x/2x/4x) or affine (Xian et al. 2019's skinning "
             "space: one affine map per cluster of vertices, piecewise-constant weights; 0.49/0.57/0.70, "
             "growing with the levels)"},
    {.key = "cell", .kind = EO_PARAM_DOUBLE, .offset = offsetof(gmg_params, cell), .def.d = 2, .min = 0,
     .range = EO_RANGE_POSITIVE,
     .help = "side of the level-1 cubes in mean edge lengths of the mesh graph (each coarser level doubles "
             "it); 2 measured best of 1.5/2/3 for the V-cycle factor on the cantilever"},
    {.key = "coarse_size", .kind = EO_PARAM_INT, .offset = offsetof(gmg_params, coarse_size), .def.i = 1500,
     .min = 3, .range = EO_RANGE_MIN,
     .help = "coarsening stops at a level with at most this many unknowns, solved by CHOLMOD"},
    {.key = "max_levels", .kind = EO_PARAM_INT, .offset = offsetof(gmg_params, max_levels), .def.i = 10, .min = 1,
     .max = EO_GMG_MAX_LEVELS, .range = EO_RANGE_CLOSED, .help = "levels including the finest (1: CHOLMOD on A)"},
    {.key = "smooth_steps", .kind = EO_PARAM_INT, .offset = offsetof(gmg_params, smooth_steps), .def.i = 2,
     .min = 1, .max = 100, .range = EO_RANGE_CLOSED,
     .help = "block Gauss-Seidel sweeps before (forward) and after (backward) each coarse correction"},
    {0},
};

typedef struct gmg_state {
    gmg_params p;
    eo_gmg *g;
    const eo_csc *A;
    int n;
    double rtol;
    double *r, *z;
    double *xyz;
    int nv;
} gmg_state;

static int gmg_setup_params(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    gmg_state *s = st;
    s->p = *(const gmg_params *)params;
    return EO_OK;
}

static void gmg_free_pattern(gmg_state *s, eo_ctx *ctx)
{
    eo_gmg_destroy(ctx, &s->g);
    eo_free(ctx, s->r);
    eo_free(ctx, s->z);
    s->r = s->z = NULL;
}

static void gmg_destroy(void *st, eo_ctx *ctx)
{
    gmg_state *s = st;
    gmg_free_pattern(s, ctx);
    eo_free(ctx, s->xyz);
    s->xyz = NULL;
}

static eo_gmg_opts opts_of(const gmg_params *p)
{
    return (eo_gmg_opts){.prolongation = strcmp(p->prolongation, "affine") ? EO_GMG_LINEAR : EO_GMG_AFFINE,
                         .cell = p->cell,
                         .coarse_size = p->coarse_size,
                         .max_levels = p->max_levels,
                         .smooth_steps = p->smooth_steps,
                         .name = "gmg"};
}

static int gmg_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    gmg_state *s = st;
    gmg_free_pattern(s, ctx);
    s->n = A->n;
    s->r = eo_malloc(ctx, (size_t)(A->n ? A->n : 1) * sizeof(double));
    s->z = eo_malloc(ctx, (size_t)(A->n ? A->n : 1) * sizeof(double));
    if (!s->r || !s->z) {
        gmg_free_pattern(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "gmg: out of memory (n=%d)", A->n);
    }
    eo_gmg_opts o = opts_of(&s->p);
    int rc = eo_gmg_create(ctx, A, &o, s->nv, s->xyz, &s->g);
    if (rc < 0) gmg_free_pattern(s, ctx);
    return rc;
}

static int gmg_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    gmg_state *s = st;
    s->A = A;
    return eo_gmg_setup(s->g, A, stats, ctx);
}

static int gmg_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    gmg_state *s = st;
    const int n = s->n;
    double bb = 0;
    for (int i = 0; i < n; i++) bb += b[i] * b[i];
    const double bnorm = sqrt(bb), tol = s->rtol > 0 ? s->rtol : s->p.tol;
    stats->iterations = 0;
    stats->residual = 0;
    if (!s->p.warm_start || bnorm == 0) memset(x, 0, (size_t)n * sizeof(double));
    if (bnorm == 0) return EO_OK;
    double rnorm = 0, r0 = 0;
    int k = 0;
    const char *why = NULL;
    for (;;) {
        eo_csc_symv(s->A, x, s->r);
        rnorm = 0;
        for (int i = 0; i < n; i++) {
            s->r[i] = b[i] - s->r[i];
            rnorm += s->r[i] * s->r[i];
        }
        rnorm = sqrt(rnorm);
        if (k == 0) r0 = rnorm;
        if (rnorm <= tol * bnorm) break;
        if (!isfinite(rnorm) || rnorm > 1e6 * r0) why = "diverged";
        else if (k >= s->p.max_iters) why = "reached max_iters";
        if (why) break;
        eo_gmg_apply(s->g, s->r, s->z);
        for (int i = 0; i < n; i++) x[i] += s->z[i];
        k++;
    }
    stats->iterations = k;
    stats->residual = rnorm / bnorm;
    if (why)
        return eo_error(ctx, EO_WARN_NOT_CONVERGED, "gmg: %s after %d V-cycles, relative residual %.3g (tol %.3g)",
                        why, k, stats->residual, tol);
    return EO_OK;
}

static void gmg_set_rtol(void *st, double rtol) { ((gmg_state *)st)->rtol = rtol > 0 ? rtol : 0; }

static int gmg_set_coordinates(void *st, int nv, const double *xyz, eo_ctx *ctx)
{
    gmg_state *s = st;
    eo_free(ctx, s->xyz);
    s->xyz = NULL;
    s->nv = 0;
    if (nv == 0) return EO_OK;
    s->xyz = eo_malloc(ctx, (size_t)3 * nv * sizeof(double));
    if (!s->xyz) return eo_error(ctx, EO_ERR_NOMEM, "gmg: out of memory for %d coordinates", nv);
    memcpy(s->xyz, xyz, (size_t)3 * nv * sizeof(double));
    s->nv = nv;
    return EO_OK;
}

const eo_linsolve_type eo_linsolve_gmg = {
    .info = {.name = "gmg",
             .summary = "Galerkin geometric multigrid V-cycles (Xian et al. 2019; trilinear or affine-skinning "
                        "coarse spaces from the node coordinates, block Gauss-Seidel, CHOLMOD coarsest)",
             .params = gmg_desc,
             .params_size = sizeof(gmg_params)},
    .state_size = sizeof(gmg_state),
    .setup = gmg_setup_params,
    .analyze = gmg_analyze,
    .factor = gmg_factor,
    .solve = gmg_solve,
    .destroy = gmg_destroy,
    .set_rtol = gmg_set_rtol,
    .set_coordinates = gmg_set_coordinates,
};
