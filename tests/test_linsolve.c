/* Suite 'linsolve': the fixed-pattern assembler and the contract every registered
 * linear solver must meet.
 *
 * Assembler: hand-checked pattern of a tiny mesh, eliminated (-1) and repeated ids,
 * random groups vs a dense reference, symv/find/diag/full expansion, zero-and-reassemble,
 * failure injection over create/add/finalize, and the 50k-tet build time.
 * Solvers (loop over eo_registry_list(EO_KIND_LINSOLVE), plus parameter variants):
 *   M0 = 3D Laplacian + I (strictly diagonally dominant): everyone solves it;
 *   M1 = M0 + random SPD element blocks (SPD, not diagonally dominant): everyone but
 *        Jacobi must solve it; Jacobi must solve it or say clearly it did not;
 *   M2 = blocks (1-a)I + a 11ᵀ (SPD, ρ(I − D⁻¹A) > 1): Jacobi must report
 *        EO_WARN_NOT_CONVERGED, quickly;
 *   refactor with new values (pattern reused) gives the new solution;
 *   indefinite L − 2.05 I: cholmod, cholmod_ldlt, lapack report EO_WARN_NOT_PD with
 *        the column, cg/pcg report it from solve; spqr and cholmod_ldlt
 *        (allow_indefinite) solve it;
 *   no context allocation in factor/solve; failure injection over create/analyze.
 * References are dense LAPACKE dposv / dgesv.
 * `test_linsolve quick` (the quick suite): the same contract on a 6x6x5 grid instead of
 * 10x10x9, every solver with its defaults only (no parameter variants), no 50k-tet
 * assembly timing; the full suite runs both. */
#include <jansson.h>
#include <lapacke.h>
#include <stdlib.h>
#include <string.h>
#if defined(_OPENMP)
#include <omp.h>
#endif

#include "eo_build_config.h"
#include "elastopt/linsolve.h"
#include "elastopt/sparse.h"
#include "testutil.h"

/* ---------------------------------------------------------------- helpers ---------- */

static double *dense_of(const eo_csc *A)
{
    double *D = malloc((size_t)A->n * A->n * sizeof(double));
    eo_csc_to_dense(A, D);
    return D;
}

/* x = A⁻¹ b with dense LAPACK; spd: dposv, else dgesv. Returns info. */
static int dense_solve(const eo_csc *A, const double *b, double *x, int spd)
{
    int n = A->n;
    double *D = dense_of(A);
    memcpy(x, b, (size_t)n * sizeof(double));
    int info;
    if (spd) {
        info = LAPACKE_dposv(LAPACK_ROW_MAJOR, 'U', n, 1, D, n, x, 1);
    } else {
        lapack_int *ipiv = malloc((size_t)n * sizeof(lapack_int));
        info = LAPACKE_dgesv(LAPACK_ROW_MAJOR, n, 1, D, n, ipiv, x, 1);
        free(ipiv);
    }
    free(D);
    return info;
}

static double rel_err(int n, const double *x, const double *ref)
{
    double e = 0, r = 0;
    for (int i = 0; i < n; i++) {
        e += (x[i] - ref[i]) * (x[i] - ref[i]);
        r += ref[i] * ref[i];
    }
    return sqrt(e / (r > 0 ? r : 1));
}

static double rel_res(const eo_csc *A, const double *b, const double *x)
{
    double *y = malloc((size_t)A->n * sizeof(double)), rr = 0, bb = 0;
    eo_csc_symv(A, x, y);
    for (int i = 0; i < A->n; i++) {
        rr += (b[i] - y[i]) * (b[i] - y[i]);
        bb += b[i] * b[i];
    }
    free(y);
    return sqrt(rr / (bb > 0 ? bb : 1));
}

/* Test matrices on an nx×ny×nz grid (n = nx ny nz), assembled with the assembler:
 * edges (k = 2, Ke = [1 −1; −1 1]) give the graph Laplacian, `shift` goes on the
 * diagonal, and `nblocks` random groups of 4 variables get Ke = GᵀG (SPD blocks, also
 * coupling far-apart variables). Values can be re-assembled with another seed. */
typedef struct testmat {
    eo_assembler *as;
    int n, h_edge, h_blk, nedge, nblocks;
} testmat;

static void testmat_fill(testmat *T, double shift, double blkscale, unsigned long long seed)
{
    eo_assembler_zero(T->as);
    const double Ke[4] = {1, -1, -1, 1};
    for (int e = 0; e < T->nedge; e++) eo_assembler_add(T->as, T->h_edge, e, Ke);
    eo_test_seed(seed);
    for (int e = 0; e < T->nblocks; e++) {
        double G[16], K[16];
        for (int t = 0; t < 16; t++) G[t] = eo_test_rand(-1, 1);
        for (int a = 0; a < 4; a++)
            for (int b = 0; b < 4; b++) {
                double s = 0;
                for (int c = 0; c < 4; c++) s += G[c * 4 + a] * G[c * 4 + b];
                K[a * 4 + b] = blkscale * s;
            }
        eo_assembler_add(T->as, T->h_blk, e, K);
    }
    for (int i = 0; i < T->n; i++) eo_assembler_add_diag(T->as, i, shift);
}

static int testmat_create(eo_ctx *ctx, int nx, int ny, int nz, int nblocks, testmat *T)
{
    memset(T, 0, sizeof *T);
    int n = nx * ny * nz;
    T->n = n;
    int *edges = malloc((size_t)6 * n * sizeof(int)), ne = 0;
#define ID(i, j, k) (((k) * ny + (j)) * nx + (i))
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                if (i + 1 < nx) edges[2 * ne] = ID(i, j, k), edges[2 * ne + 1] = ID(i + 1, j, k), ne++;
                if (j + 1 < ny) edges[2 * ne] = ID(i, j, k), edges[2 * ne + 1] = ID(i, j + 1, k), ne++;
                if (k + 1 < nz) edges[2 * ne] = ID(i, j, k), edges[2 * ne + 1] = ID(i, j, k + 1), ne++;
            }
#undef ID
    int *blk = malloc((size_t)(4 * nblocks + 1) * sizeof(int));
    eo_test_seed(12345);
    for (int t = 0; t < 4 * nblocks; t++) blk[t] = (int)eo_test_rand(0, n);
    int rc = eo_assembler_create(ctx, n, &T->as);
    if (rc >= 0) rc = T->h_edge = eo_assembler_add_elements(ctx, T->as, ne, 2, edges);
    if (rc >= 0) rc = T->h_blk = eo_assembler_add_elements(ctx, T->as, nblocks, 4, blk);
    if (rc >= 0) rc = eo_assembler_finalize(ctx, T->as);
    T->nedge = ne;
    T->nblocks = nblocks;
    free(edges);
    free(blk);
    return rc;
}

/* M2: n/m blocks of size m, A_block = (1−a) I + a 11ᵀ. */
static int jacobi_trap_create(eo_ctx *ctx, int nb, int m, double a, eo_assembler **as)
{
    int *d = malloc((size_t)nb * m * sizeof(int));
    double *K = malloc((size_t)m * m * sizeof(double));
    for (int t = 0; t < nb * m; t++) d[t] = t;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < m; j++) K[i * m + j] = (i == j ? 1 : a);
    int rc = eo_assembler_create(ctx, nb * m, as);
    int h = rc >= 0 ? eo_assembler_add_elements(ctx, *as, nb, m, d) : rc;
    if (h >= 0) rc = eo_assembler_finalize(ctx, *as);
    if (rc >= 0 && h >= 0)
        for (int e = 0; e < nb; e++) eo_assembler_add(*as, h, e, K);
    free(d);
    free(K);
    return h < 0 ? h : rc;
}

/* ------------------------------------------------------------- assembler ---------- */

static void test_assembler_tiny(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_assembler *as = NULL;
    /* 5 variables; e0 = {0, 2, −1}, e1 = {2, 3, 2} (variable 2 twice); 1 and 4 untouched */
    const int dofs[6] = {0, 2, -1, 2, 3, 2};
    CHECK(eo_assembler_create(ctx, 5, &as) == EO_OK, "create");
    int h = eo_assembler_add_elements(ctx, as, 2, 3, dofs);
    CHECK(h == 0, "handle %d", h);
    CHECK(eo_assembler_matrix(as) == NULL, "no matrix before finalize");
    CHECK(eo_assembler_finalize(ctx, as) == EO_OK, "finalize: %s", eo_ctx_message(ctx));
    CHECK(eo_assembler_add_elements(ctx, as, 1, 3, dofs) == EO_ERR_INVALID, "no add after finalize");
    CHECK(eo_assembler_finalize(ctx, as) == EO_ERR_INVALID, "finalize twice");
    eo_csc *A = eo_assembler_matrix(as);
    /* columns: 0:{0} 1:{1} 2:{0,2} 3:{2,3} 4:{4} */
    const int cp[6] = {0, 1, 2, 4, 6, 7}, ri[7] = {0, 1, 0, 2, 2, 3, 4};
    CHECK(A->n == 5 && A->nnz == 7, "n %d nnz %d", A->n, A->nnz);
    int same = A->nnz == 7;
    for (int j = 0; j <= 5 && same; j++) same = A->colptr[j] == cp[j];
    for (int p = 0; p < 7 && same; p++) same = A->rowind[p] == ri[p];
    CHECK(same, "pattern differs from the hand-computed one");
    CHECK(eo_csc_check(ctx, A) == EO_OK, "invariants: %s", eo_ctx_message(ctx));
    CHECK(eo_csc_find(A, 2, 0) == 2 && eo_csc_find(A, 0, 2) == 2, "find (0,2)");
    CHECK(eo_csc_find(A, 3, 2) == 4 && eo_csc_find(A, 1, 1) == 1, "find (2,3), (1,1)");
    CHECK(eo_csc_find(A, 0, 3) == -1 && eo_csc_find(A, 1, 4) == -1 && eo_csc_find(A, 0, 9) == -1, "absent");
    /* maps: e0 local (0,1) -> (0,2) stored; (1,0) not; (2,*) eliminated */
    const int *m0 = eo_assembler_map(as, h, 0);
    CHECK(m0[0 * 3 + 1] == 2 && m0[1 * 3 + 0] == -1 && m0[2 * 3 + 2] == -1 && m0[0] == 0, "map e0");
    const int *m1 = eo_assembler_map(as, h, 1);
    CHECK(m1[0 * 3 + 2] == 3 && m1[2 * 3 + 0] == 3, "repeated id: both orientations to the diagonal");
    /* values: element matrices by definition vs assembled */
    double K0[9] = {4, 1, 7, 1, 5, 8, 7, 8, 9}, K1[9] = {2, 3, 1, 3, 6, 2, 1, 2, 3};
    double Dref[25] = {0};
    const double *Ks[2] = {K0, K1};
    for (int e = 0; e < 2; e++)
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                int ga = dofs[3 * e + a], gb = dofs[3 * e + b];
                if (ga >= 0 && gb >= 0) Dref[ga * 5 + gb] += Ks[e][a * 3 + b];
            }
    Dref[4 * 5 + 4] += 0.5;
    double D[25], D2[25];
    for (int rep = 0; rep < 2; rep++) {
        eo_assembler_zero(as);
        eo_assembler_add(as, h, 0, K0);
        eo_assembler_add(as, h, 1, K1);
        eo_assembler_add_diag(as, 4, 0.5);
        eo_csc_to_dense(A, rep ? D2 : D);
    }
    int eq = 1, rep_eq = 1;
    for (int t = 0; t < 25; t++) {
        eq &= fabs(D[t] - Dref[t]) < 1e-14;
        rep_eq &= D[t] == D2[t];
    }
    CHECK(eq, "assembled values differ from the definition");
    CHECK(rep_eq, "zero + reassemble must give identical values");
    CHECK(D[2 * 5 + 2] == 5 + 2 + 2 * 1 + 3, "diag (2,2) = K0[1][1] + K1[0][0] + K1[0][2] + K1[2][0] + K1[2][2]: %g",
          D[2 * 5 + 2]);
    double dg[5];
    eo_csc_diag(A, dg);
    CHECK(dg[1] == 0 && dg[4] == 0.5 && dg[0] == 4, "diag");
    /* bad ids */
    eo_assembler *as2 = NULL;
    eo_assembler_create(ctx, 3, &as2);
    const int bad[3] = {0, 3, 1};
    CHECK(eo_assembler_add_elements(ctx, as2, 1, 3, bad) == EO_ERR_INVALID, "id out of range");
    CHECK(strstr(eo_ctx_message(ctx), "element 0") != NULL, "message names the element: %s", eo_ctx_message(ctx));
    eo_assembler_destroy(&as2);
    eo_assembler_destroy(&as);
    eo_assembler_destroy(&as);
    CHECK(as == NULL, "destroy sets NULL");
    eo_test_ctx_done(&ctx);
}

/* random groups with eliminated and repeated ids vs dense; symv, full expansion */
static void test_assembler_random(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const int n = 150, ng = 3, ks[3] = {2, 5, 12}, nes[3] = {300, 80, 40};
    int *dofs[3];
    double *Ke[3];
    eo_assembler *as = NULL;
    eo_test_seed(7);
    CHECK(eo_assembler_create(ctx, n, &as) == EO_OK, "create");
    for (int g = 0; g < ng; g++) {
        dofs[g] = malloc((size_t)nes[g] * ks[g] * sizeof(int));
        Ke[g] = malloc((size_t)nes[g] * ks[g] * ks[g] * sizeof(double));
        for (int t = 0; t < nes[g] * ks[g]; t++) {
            double u = eo_test_rand(0, 1);
            dofs[g][t] = u < 0.1 ? -1 : (int)eo_test_rand(0, n - 20); /* last 20: untouched */
            if (u > 0.95 && t % ks[g]) dofs[g][t] = dofs[g][t - 1];  /* repeats */
        }
        for (int e = 0; e < nes[g]; e++) {
            int k = ks[g];
            double *K = Ke[g] + (size_t)e * k * k;
            for (int a = 0; a < k; a++)
                for (int b = a; b < k; b++) K[a * k + b] = K[b * k + a] = eo_test_rand(-1, 1);
        }
        CHECK(eo_assembler_add_elements(ctx, as, nes[g], ks[g], dofs[g]) == g, "group %d", g);
    }
    CHECK(eo_assembler_finalize(ctx, as) == EO_OK, "finalize");
    eo_csc *A = eo_assembler_matrix(as);
    CHECK(eo_csc_check(ctx, A) == EO_OK, "invariants: %s", eo_ctx_message(ctx));
    double *Dref = calloc((size_t)n * n, sizeof(double)), *D = malloc((size_t)n * n * sizeof(double));
    eo_assembler_zero(as);
    for (int g = 0; g < ng; g++) {
        int k = ks[g];
        for (int e = 0; e < nes[g]; e++) {
            const double *K = Ke[g] + (size_t)e * k * k;
            const int *d = dofs[g] + (size_t)e * k;
            eo_assembler_add(as, g, e, K);
            for (int a = 0; a < k; a++)
                for (int b = 0; b < k; b++)
                    if (d[a] >= 0 && d[b] >= 0) Dref[d[a] * n + d[b]] += K[a * k + b];
        }
    }
    eo_csc_to_dense(A, D);
    double err = 0;
    int pattern_ok = 1;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            err = fmax(err, fabs(D[i * n + j] - Dref[i * n + j]));
            if (Dref[i * n + j] != 0 && eo_csc_find(A, i, j) < 0) pattern_ok = 0;
        }
    CHECK(err < 1e-12, "assembled vs dense: max diff %g", err);
    CHECK(pattern_ok, "a nonzero of the reference is missing from the pattern");
    for (int i = n - 20; i < n; i++)
        CHECK(A->colptr[i + 1] - A->colptr[i] >= 1 && eo_csc_find(A, i, i) == A->colptr[i + 1] - 1,
              "untouched variable %d keeps its diagonal", i);
    double x[150], y[150], yref[150];
    for (int i = 0; i < n; i++) x[i] = eo_test_rand(-1, 1);
    eo_csc_symv(A, x, y);
    double e2 = 0;
    for (int i = 0; i < n; i++) {
        yref[i] = 0;
        for (int j = 0; j < n; j++) yref[i] += Dref[i * n + j] * x[j];
        e2 = fmax(e2, fabs(y[i] - yref[i]));
    }
    CHECK(e2 < 1e-12, "symv vs dense: %g", e2);
    eo_csc_full *F = NULL;
    CHECK(eo_csc_full_create(ctx, A, &F) == EO_OK, "full");
    double e3 = 0;
    int sorted = 1;
    for (int j = 0; j < n; j++)
        for (int q = F->colptr[j]; q < F->colptr[j + 1]; q++) {
            e3 = fmax(e3, fabs(F->val[q] - Dref[F->rowind[q] * n + j]));
            if (q > F->colptr[j] && F->rowind[q] <= F->rowind[q - 1]) sorted = 0;
            if (F->rowind[q] == j && F->diag[j] != q) sorted = 0;
        }
    CHECK(e3 < 1e-12 && sorted && F->nnz == 2 * A->nnz - n, "full expansion (err %g)", e3);
    eo_csc *B = NULL;
    CHECK(eo_csc_clone(ctx, A, &B) == EO_OK && B->nnz == A->nnz && B->val[B->nnz - 1] == A->val[A->nnz - 1], "clone");
    eo_csc_shift(B, 2.0);
    CHECK(B->val[B->colptr[1] - 1] == A->val[A->colptr[1] - 1] + 2.0, "shift");
    eo_csc_destroy(&B);
    eo_csc_full_destroy(&F);
    for (int g = 0; g < ng; g++) {
        free(dofs[g]);
        free(Ke[g]);
    }
    free(Dref);
    free(D);
    eo_assembler_destroy(&as);
    eo_test_ctx_done(&ctx);
}

/* Block scatter (3×3 blocks, lib/sparse.c block_maps): groups of vertex triples (tets
 * k = 12, springs k = 6 with a repeated vertex now and then, contacts k = 3, a quarter
 * of the vertices eliminated) are block groups and assemble to the dense definition;
 * eo_assembler_add_scaled adds w·Ke. With an extra group that splits a triple (one
 * coordinate eliminated), that group keeps its k×k map, and every group (block or
 * not: block offsets are verified against the pattern) still assembles exactly. */
static void assemble_blocks(int split)
{
    eo_ctx *ctx = eo_test_ctx();
    enum { NV = 40, NG = 4 };
    int fmap[NV], nfree = 0;
    eo_test_seed(11 + split);
    for (int v = 0; v < NV; v++) {
        fmap[v] = eo_test_rand(0, 1) < 0.25 ? -1 : nfree;
        if (fmap[v] >= 0) nfree += 3;
    }
    const int n = nfree, ks[NG] = {12, 6, 3, 3}, nes[NG] = {120, 60, 20, split ? 10 : 0};
    int *dofs[NG];
    double *Ke[NG];
    eo_assembler *as = NULL;
    CHECK(eo_assembler_create(ctx, n, &as) == EO_OK, "create");
    int ngroups = split ? NG : NG - 1;
    for (int g = 0; g < ngroups; g++) {
        const int k = ks[g], m = k / 3;
        dofs[g] = malloc((size_t)nes[g] * k * sizeof(int));
        Ke[g] = malloc((size_t)nes[g] * k * k * sizeof(double));
        for (int e = 0; e < nes[g]; e++) {
            int vs[4] = {0, 0, 0, 0};
            for (int a = 0; a < m; a++) {
                int v, dup;
                do { /* distinct vertices, except a repeated spring end now and then */
                    v = (int)eo_test_rand(0, NV - 0.001);
                    dup = 0;
                    for (int b = 0; b < a; b++) dup |= vs[b] == v;
                } while (dup && !(g == 1 && e % 7 == 0));
                vs[a] = v;
                for (int c = 0; c < 3; c++) dofs[g][e * k + 3 * a + c] = fmap[v] < 0 ? -1 : fmap[v] + c;
            }
            if (g == 3 && fmap[vs[0]] >= 0) dofs[g][e * k + 1] = -1; /* split triple */
            double *K = Ke[g] + (size_t)e * k * k;
            for (int a = 0; a < k; a++)
                for (int b = a; b < k; b++) K[a * k + b] = K[b * k + a] = eo_test_rand(-1, 1);
        }
        CHECK(eo_assembler_add_elements(ctx, as, nes[g], k, dofs[g]) == g, "group %d", g);
    }
    CHECK(eo_assembler_finalize(ctx, as) == EO_OK, "finalize: %s", eo_ctx_message(ctx));
    eo_csc *A = eo_assembler_matrix(as);
    CHECK(eo_csc_check(ctx, A) == EO_OK, "invariants: %s", eo_ctx_message(ctx));
    int nblock = 0;
    for (int g = 0; g < ngroups; g++) nblock += eo_assembler_is_block(as, g);
    if (!split) {
        CHECK(nblock == 3, "vertex-triple groups must be block groups: %d of 3", nblock);
        CHECK(eo_assembler_map(as, 0, 0) == NULL, "a block group has no k*k map");
    } else {
        CHECK(!eo_assembler_is_block(as, 3) && eo_assembler_map(as, 3, 0) != NULL, "split group keeps its map");
    }
    double *Dref = calloc((size_t)n * n, sizeof(double)), *D = malloc((size_t)n * n * sizeof(double));
    const double w = 0.37;
    eo_assembler_zero(as);
    for (int g = 0; g < ngroups; g++) {
        const int k = ks[g];
        for (int e = 0; e < nes[g]; e++) {
            const double *K = Ke[g] + (size_t)e * k * k;
            const int *d = dofs[g] + (size_t)e * k;
            const double we = e % 2 ? w : 1.0;
            if (e % 2) eo_assembler_add_scaled(as, g, e, K, w);
            else eo_assembler_add(as, g, e, K);
            for (int a = 0; a < k; a++)
                for (int b = 0; b < k; b++)
                    if (d[a] >= 0 && d[b] >= 0) Dref[d[a] * n + d[b]] += we * K[a * k + b];
        }
    }
    eo_csc_to_dense(A, D);
    double err = 0;
    for (int q = 0; q < n * n; q++) err = fmax(err, fabs(D[q] - Dref[q]));
    printf("assembler blocks (%s): n = %d, %d of %d groups by blocks, max |A - definition| = %.2e\n",
           split ? "with a split triple" : "vertex triples", n, nblock, ngroups, err);
    CHECK(err < 1e-13, "block assembly vs definition: %g", err);
    for (int g = 0; g < ngroups; g++) {
        free(dofs[g]);
        free(Ke[g]);
    }
    free(Dref);
    free(D);
    eo_assembler_destroy(&as);
    eo_test_ctx_done(&ctx);
}

static void test_assembler_blocks(void)
{
    assemble_blocks(0);
    assemble_blocks(1);
}

static void test_assembler_fail(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const int d1[8] = {0, 1, 2, 3, 3, 4, -1, 5}, d2[6] = {5, 6, 0, 6, 2, 2};
    int ok = 0, fails = 0;
    for (long f = 1; f < 200 && !ok; f++) {
        eo_assembler *as = NULL;
        eo_ctx_fail_after(ctx, f);
        int rc = eo_assembler_create(ctx, 8, &as);
        if (rc >= 0) rc = eo_assembler_add_elements(ctx, as, 2, 4, d1);
        if (rc >= 0) rc = eo_assembler_add_elements(ctx, as, 3, 2, d2);
        if (rc >= 0) rc = eo_assembler_finalize(ctx, as);
        if (rc >= 0) {
            ok = 1;
            CHECK(eo_csc_check(ctx, eo_assembler_matrix(as)) == EO_OK, "valid after %ld", f);
        } else {
            fails++;
            CHECK(rc == EO_ERR_NOMEM, "injected failure %ld gives NOMEM, got %d", f, rc);
        }
        eo_assembler_destroy(&as);
        eo_ctx_fail_after(ctx, 0);
        CHECK(eo_ctx_live_bytes(ctx) == 0, "leak after failure at allocation %ld: %zu bytes", f,
              eo_ctx_live_bytes(ctx));
    }
    CHECK(ok && fails >= 5, "failure injection covered %d failing runs", fails);
    eo_test_ctx_done(&ctx);
}

/* 50k tets of a structured grid (Kuhn split, 6 tets per cube), 3 dofs per vertex, the
 * bottom layer eliminated: finalize must take well under a second. */
static void test_assembler_timing(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const int cx = 20, cy = 20, cz = 21, vx = cx + 1, vy = cy + 1, vz = cz + 1;
    int nv = vx * vy * vz, nt = 6 * cx * cy * cz;
    int *dofs = malloc((size_t)nt * 12 * sizeof(int)), t = 0;
    static const int kuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                   {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
    for (int k = 0; k < cz; k++)
        for (int j = 0; j < cy; j++)
            for (int i = 0; i < cx; i++)
                for (int s = 0; s < 6; s++, t++)
                    for (int a = 0; a < 4; a++) {
                        int c = kuhn[s][a];
                        int ii = i + (c & 1), jj = j + ((c >> 1) & 1), kk = k + ((c >> 2) & 1);
                        int v = (kk * vy + jj) * vx + ii;
                        for (int d = 0; d < 3; d++) dofs[t * 12 + 3 * a + d] = kk == 0 ? -1 : 3 * v + d;
                    }
    eo_assembler *as = NULL;
    double t0 = eo_wtime();
    eo_assembler_create(ctx, 3 * nv, &as);
    int h = eo_assembler_add_elements(ctx, as, nt, 12, dofs);
    int rc = eo_assembler_finalize(ctx, as);
    double tf = eo_wtime() - t0;
    CHECK(h == 0 && rc == EO_OK, "finalize 50k tets: %s", eo_ctx_message(ctx));
    eo_csc *A = eo_assembler_matrix(as);
    CHECK(eo_csc_check(ctx, A) == EO_OK, "invariants: %s", eo_ctx_message(ctx));
    double Ke[144];
    for (int q = 0; q < 144; q++) Ke[q] = (q / 12 == q % 12) ? 2.0 : 0.01;
    t0 = eo_wtime();
    eo_assembler_zero(as);
    for (int e = 0; e < nt; e++) eo_assembler_add(as, h, e, Ke);
    double ta = eo_wtime() - t0;
    printf("assembler: %d tets, %d variables, nnz(upper) %d: finalize %.3f s, one assembly %.4f s\n", nt,
           3 * nv, A->nnz, tf, ta);
    /* speed is measured in bench/, not asserted here (sanitizers, valgrind, loaded CI) */
    /* a bottom (eliminated) vertex's dofs have only their diagonal */
    CHECK(A->colptr[1] - A->colptr[0] == 1 && A->val[0] == 0, "eliminated variable: diagonal only, zero");
    free(dofs);
    eo_assembler_destroy(&as);
    eo_test_ctx_done(&ctx);
}

/* --------------------------------------------------------------- solvers ---------- */

typedef struct variant {
    const char *name, *key, *value;
} variant;

/* the registered solvers with their defaults, plus parameter variants */
static const variant variants[] = {
    {"cholmod", "supernodal", "false"},   {"cholmod", "ordering", "\"natural\""},
    {"cholmod", "ordering", "\"auto\""},  {"cholmod_ldlt", "ordering", "\"auto\""},
    {"pcg", "preconditioner", "\"ichol0\""}, {"sor", "omega", "1.2"},
    {"cholmod", "openmp", "true"},        {"cholmod_ldlt", "openmp", "true"},
    {"cholmod", "ordering", "\"metis\""},  {"cholmod", "ordering", "\"nesdis\""},
    {"cholmod", "ordering", "\"amd\""},    {"cholmod_ldlt", "ordering", "\"metis\""},
    {"pcg", "preconditioner", "\"ic0\""},  {"pcg", "preconditioner", "\"cholmod_reuse\""},
    {"pcg", "preconditioner", "\"gmg\""}, /* no coordinates here: one level (CHOLMOD); test_gmg has the rest */
#if EO_HAVE_HYPRE
    {"pcg", "preconditioner", "\"amg\""},
#endif
    {"gmres", "preconditioner", "\"ic0\""}, {"gmres", "preconditioner", "\"none\""},
    {"gmres", "restart", "5"},             {"umfpack", "ordering", "\"metis\""},
    {"lapack_ldlt", "allow_indefinite", "true"},
    {"pcg", "ordering", "\"nesdis\""},
    /* the policy's three choices on the small contract matrices */
    {"auto", "reuse_min", "0"},           {"auto", "iterative_min", "0"},
    {"auto", "nd_min", "0"},
};

typedef struct solver_cfg {
    const eo_linsolve_type *type;
    double params[64]; /* aligned storage for any params struct */
    char label[96];
} solver_cfg;

static int set_param(eo_ctx *ctx, solver_cfg *c, const char *key, const char *value)
{
    const eo_param_desc *d = eo_params_find(c->type->info.params, key);
    if (!d) return 1;
    json_t *v = eo_json_from_override(value);
    int rc = eo_params_set_json(ctx, d, c->params, v, NULL);
    json_decref(v);
    return rc;
}

static int is_iterative(const eo_linsolve_type *t)
{
    return eo_params_find(t->info.params, "max_iters") != NULL;
}

static void cfg_init(eo_ctx *ctx, solver_cfg *c, const eo_linsolve_type *t)
{
    memset(c, 0, sizeof *c);
    c->type = t;
    CHECK(t->info.params_size <= sizeof c->params, "%s params too large", t->info.name);
    eo_params_default(t->info.params, c->params);
    snprintf(c->label, sizeof c->label, "%s", t->info.name);
    /* iterative: tight tolerance, enough iterations */
    set_param(ctx, c, "tol", "1e-12");
    set_param(ctx, c, "max_iters", "20000");
}

/* analyze + factor + solve; checks no context allocation in factor/solve */
static int run(eo_ctx *ctx, eo_linsolve *ls, const eo_csc *A, const double *b, double *x, int analyze,
               int *factor_rc)
{
    int rc = EO_OK;
    if (analyze) rc = eo_linsolve_analyze(ls, A);
    if (rc < 0) return rc;
    size_t live = eo_ctx_live_bytes(ctx);
#if defined(_OPENMP)
    const int levels = omp_get_max_active_levels();
#endif
    *factor_rc = rc = eo_linsolve_factor(ls, A);
#if defined(_OPENMP)
    CHECK(omp_get_max_active_levels() == levels, "%s: factor left OpenMP max-active-levels at %d (was %d)",
          eo_linsolve_get_type(ls)->info.name, omp_get_max_active_levels(), levels);
#endif
    if (rc != EO_OK) return rc;
    rc = eo_linsolve_solve(ls, b, x);
    CHECK(eo_ctx_live_bytes(ctx) == live, "%s: factor/solve allocated %zu bytes",
          eo_linsolve_get_type(ls)->info.name, eo_ctx_live_bytes(ctx) - live);
    return rc;
}

static int g_quick; /* `quick` argument: smaller contract grid, no variants, no timing */

static void contract_one(solver_cfg *c)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *name = c->type->info.name, *L = c->label;
    const int jac = strcmp(name, "jacobi") == 0;
    eo_linsolve *ls = NULL;
    testmat T;
    CHECK(testmat_create(ctx, g_quick ? 6 : 10, g_quick ? 6 : 10, g_quick ? 5 : 9, 150, &T) == EO_OK, "test matrix");
    eo_csc *A = eo_assembler_matrix(T.as);
    const int n = A->n;
    double *b = malloc((size_t)n * sizeof(double)), *x = malloc((size_t)n * sizeof(double));
    double *ref = malloc((size_t)n * sizeof(double));
    eo_test_seed(99);
    for (int i = 0; i < n; i++) b[i] = eo_test_rand(-1, 1);

    int rc = eo_linsolve_create(ctx, c->type, c->params, &ls), frc = 0;
    CHECK(rc == EO_OK, "%s: create: %s", L, eo_ctx_message(ctx));
    if (rc < 0) goto done;
    CHECK(eo_linsolve_solve(ls, b, x) == EO_ERR_INVALID, "%s: solve before factor refused", L);
    const double tol = 1e-8; /* iterative ones run to a 1e-12 residual */

    /* M0: diagonally dominant */
    testmat_fill(&T, 1.0, 0.0, 1);
    dense_solve(A, b, ref, 1);
    rc = run(ctx, ls, A, b, x, 1, &frc);
    CHECK(rc == EO_OK, "%s: M0 solve rc %d: %s", L, rc, eo_ctx_message(ctx));
    CHECK(rel_err(n, x, ref) < tol, "%s: M0 error %g", L, rel_err(n, x, ref));
    const eo_linsolve_stats *st = eo_linsolve_get_stats(ls);
    /* iterative, except a reused factor's first solve: the factor is of this matrix, so
     * the solve is direct (pcg cholmod_reuse, auto's reuse) */
    int iter = eo_linsolve_is_iterative(ls);
    if (strcmp(name, "auto")) {
        CHECK(iter == (c->type->set_rtol != NULL), "%s: eo_linsolve_is_iterative %d", L, iter);
        iter = is_iterative(c->type); /* the stationary methods iterate without a forcing term */
    } else {
        char d[160];
        eo_linsolve_describe(ls, d, sizeof d);
        CHECK(iter == (strncmp(d, "pcg", 3) == 0), "%s: eo_linsolve_is_iterative %d for '%s'", L, iter, d);
    }
    if (iter && st->n_refactor == 0)
        CHECK(st->iterations > 0 && st->residual >= 0 && st->residual <= 1e-12 * 1.0001, "%s: stats it %d res %g",
              L, st->iterations, st->residual);
    else
        CHECK(st->iterations == 0, "%s: direct iterations", L);
    CHECK(st->n_factor == 1 && st->n_solve == 1 && st->not_pd_column == -1, "%s: counters", L);

    /* M1: SPD, not diagonally dominant; refactor only (same pattern) */
    testmat_fill(&T, 0.5, 1.0, 2);
    dense_solve(A, b, ref, 1);
    rc = run(ctx, ls, A, b, x, 0, &frc);
    if (jac) {
        CHECK(rc == EO_OK ? rel_err(n, x, ref) < tol
                          : rc == EO_WARN_NOT_CONVERGED && eo_linsolve_get_stats(ls)->residual > 1e-12,
              "%s: M1 must solve or report not converged (rc %d)", L, rc);
    } else {
        CHECK(rc == EO_OK, "%s: M1 rc %d: %s", L, rc, eo_ctx_message(ctx));
        CHECK(rel_err(n, x, ref) < tol, "%s: M1 error %g", L, rel_err(n, x, ref));
    }
    /* new values, same pattern: new solution */
    testmat_fill(&T, 0.7, 0.5, 3);
    dense_solve(A, b, ref, 1);
    rc = run(ctx, ls, A, b, x, 0, &frc);
    if (!jac) {
        CHECK(rc == EO_OK && rel_err(n, x, ref) < tol, "%s: refactor rc %d error %g", L, rc, rel_err(n, x, ref));
        /* a second right-hand side with the same factorization */
        for (int i = 0; i < n; i++) b[i] = cos(i);
        dense_solve(A, b, ref, 1);
        rc = eo_linsolve_solve(ls, b, x);
        CHECK(rc == EO_OK && rel_err(n, x, ref) < tol, "%s: second rhs rc %d error %g", L, rc, rel_err(n, x, ref));
        /* zero rhs */
        for (int i = 0; i < n; i++) b[i] = 0, x[i] = 1;
        rc = eo_linsolve_solve(ls, b, x);
        double mx = 0;
        for (int i = 0; i < n; i++) mx = fmax(mx, fabs(x[i]));
        CHECK(rc == EO_OK && mx == 0, "%s: zero rhs gives 0 (rc %d, max %g)", L, rc, mx);
        for (int i = 0; i < n; i++) b[i] = eo_test_rand(-1, 1);
    }

    /* indefinite: Laplacian − 2.05 I (diagonal stays positive) */
    testmat_fill(&T, -2.05, 0.0, 4);
    int info = dense_solve(A, b, ref, 0);
    CHECK(info == 0, "dgesv reference");
    rc = run(ctx, ls, A, b, x, 0, &frc);
    const int ldlt_indef = !strcmp(name, "lapack_ldlt") && strstr(L, "allow_indefinite");
    /* amg, gmg: preconditioners that factor (gmg here: CHOLMOD), so not-PD may come from factor */
    const int reuse = strstr(L, "cholmod_reuse") != NULL, amg = strstr(L, "amg") != NULL || strstr(L, "gmg") != NULL;
    const int want_col = !strcmp(name, "cholmod") || !strcmp(name, "lapack") || !strcmp(name, "cholmod_ldlt") ||
                         (!strcmp(name, "lapack_ldlt") && !ldlt_indef) || (reuse && frc == EO_WARN_NOT_PD);
    if (!strcmp(name, "lapack_ldlt")) { /* inertia vs the dense eigenvalues (dsyev) */
        double *D = dense_of(A), *ev = malloc((size_t)n * sizeof(double));
        LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'N', 'U', n, D, n, ev);
        int neg = 0;
        for (int i = 0; i < n; i++) neg += ev[i] < 0;
        st = eo_linsolve_get_stats(ls);
        CHECK(neg > 0 && st->n_negative == neg && st->n_zero == 0, "%s: inertia %d negative (dsyev: %d), %d zero", L,
              st->n_negative, neg, st->n_zero);
        free(D);
        free(ev);
    }
    if (want_col) {
        st = eo_linsolve_get_stats(ls);
        CHECK(frc == EO_WARN_NOT_PD, "%s: indefinite factor rc %d", L, frc);
        CHECK(st->not_pd_column >= 0 && st->not_pd_column < n, "%s: column %d", L, st->not_pd_column);
        CHECK(strstr(eo_ctx_message(ctx), "column") != NULL, "%s: message '%s'", L, eo_ctx_message(ctx));
        CHECK(eo_linsolve_solve(ls, b, x) == EO_ERR_INVALID, "%s: no solve after a failed factor", L);
    } else if (!strcmp(name, "cg") || (!strcmp(name, "pcg") && !amg)) {
        CHECK(frc == EO_OK && rc == EO_WARN_NOT_PD, "%s: indefinite: factor %d solve %d", L, frc, rc);
        st = eo_linsolve_get_stats(ls);
        CHECK(st->curvature < 0, "%s: negative curvature reported in stats: %g", L, st->curvature);
        CHECK(strstr(eo_ctx_message(ctx), "curvature") != NULL, "%s: message '%s'", L, eo_ctx_message(ctx));
    } else if (!strcmp(name, "gmres")) {
        /* restarted GMRES(m) may stagnate on indefinite systems (it always does for small
         * m): converge, or say so with the true residual (full-length GMRES: test_gmres_indefinite) */
        st = eo_linsolve_get_stats(ls);
        if (rc == EO_OK)
            CHECK(rel_err(n, x, ref) < 1e-8, "%s: indefinite err %g", L, rel_err(n, x, ref));
        else
            CHECK(rc == EO_WARN_NOT_CONVERGED && st->residual > 1e-12 &&
                      fabs(rel_res(A, b, x) - st->residual) <= 1e-6 * st->residual + 1e-15,
                  "%s: indefinite: rc %d, reported residual %g, true %g", L, rc, st->residual, rel_res(A, b, x));
    } else if (!strcmp(name, "spqr") || !strcmp(name, "umfpack") || !strcmp(name, "lapack_lu") || ldlt_indef) {
        CHECK(rc == EO_OK && rel_err(n, x, ref) < 1e-8, "%s: indefinite solve rc %d err %g", L, rc,
              rel_err(n, x, ref));
    } else {
        CHECK(rc != EO_OK || rel_res(A, b, x) < 1e-6, "%s: indefinite: ok status must mean solved", L);
    }
    /* Hessian-fix flow: after a not-PD factor, shifted values factor fine again */
    testmat_fill(&T, 1.0, 0.0, 5);
    dense_solve(A, b, ref, 1);
    rc = run(ctx, ls, A, b, x, 0, &frc);
    CHECK(rc == EO_OK && rel_err(n, x, ref) < tol && eo_linsolve_get_stats(ls)->not_pd_column == -1,
          "%s: refactor after indefinite: rc %d err %g", L, rc, rel_err(n, x, ref));
    testmat_fill(&T, -2.05, 0.0, 4);
    dense_solve(A, b, ref, 0);
    if (!strcmp(name, "cholmod_ldlt")) {
        solver_cfg c2 = *c;
        set_param(ctx, &c2, "allow_indefinite", "true");
        eo_linsolve *l2 = NULL;
        CHECK(eo_linsolve_create(ctx, c2.type, c2.params, &l2) == EO_OK, "ldlt indefinite create");
        rc = run(ctx, l2, A, b, x, 1, &frc);
        CHECK(rc == EO_OK && rel_err(n, x, ref) < 1e-8, "%s allow_indefinite: rc %d err %g", L, rc,
              rel_err(n, x, ref));
        eo_linsolve_destroy(&l2);
    }
    eo_linsolve_destroy(&ls);

    /* M2: SPD where Jacobi diverges (ρ = a (m−1) = 2.7) */
    {
        eo_assembler *as2 = NULL;
        CHECK(jacobi_trap_create(ctx, 40, 10, 0.3, &as2) == EO_OK, "M2");
        eo_csc *A2 = eo_assembler_matrix(as2);
        double *b2 = malloc(400 * sizeof(double)), *x2 = malloc(400 * sizeof(double)), *r2 = malloc(400 * sizeof(double));
        for (int i = 0; i < 400; i++) b2[i] = eo_test_rand(-1, 1);
        dense_solve(A2, b2, r2, 1);
        CHECK(eo_linsolve_create(ctx, c->type, c->params, &ls) == EO_OK, "create");
        double t0 = eo_wtime();
        rc = run(ctx, ls, A2, b2, x2, 1, &frc);
        double dt = eo_wtime() - t0;
        if (jac) {
            CHECK(rc == EO_WARN_NOT_CONVERGED, "%s: M2 must not converge (rc %d)", L, rc);
            CHECK(strstr(eo_ctx_message(ctx), "diverged") != NULL, "%s: message '%s'", L, eo_ctx_message(ctx));
            CHECK(eo_linsolve_get_stats(ls)->iterations < 100 && dt < 1, "%s: stops early (%d its)", L,
                  eo_linsolve_get_stats(ls)->iterations);
        } else {
            CHECK(rc == EO_OK && rel_err(400, x2, r2) < 1e-8, "%s: M2 rc %d err %g", L, rc, rel_err(400, x2, r2));
        }
        eo_linsolve_destroy(&ls);
        eo_assembler_destroy(&as2);
        free(b2);
        free(x2);
        free(r2);
    }
done:
    eo_linsolve_destroy(&ls);
    eo_assembler_destroy(&T.as);
    free(b);
    free(x);
    free(ref);
    eo_test_ctx_done(&ctx);
}

static void test_contract(void)
{
    eo_ctx *ctx = eo_test_ctx();
    int count = 0;
    for (const void *const *t = eo_registry_list(EO_KIND_LINSOLVE); *t; t++, count++) {
        solver_cfg c;
        cfg_init(ctx, &c, *t);
        double t0 = eo_wtime();
        contract_one(&c);
        printf("contract %-28s %.3f s\n", c.label, eo_wtime() - t0);
        for (size_t v = 0; v < (g_quick ? 0 : sizeof variants / sizeof variants[0]); v++) {
            if (strcmp(variants[v].name, (*(const eo_linsolve_type *const *)t)->info.name)) continue;
            cfg_init(ctx, &c, *t);
            CHECK(set_param(ctx, &c, variants[v].key, variants[v].value) == EO_OK, "variant %s.%s: %s",
                  variants[v].name, variants[v].key, eo_ctx_message(ctx));
            snprintf(c.label, sizeof c.label, "%s[%s=%s]", variants[v].name, variants[v].key, variants[v].value);
            t0 = eo_wtime();
            contract_one(&c);
            printf("contract %-28s %.3f s\n", c.label, eo_wtime() - t0);
        }
    }
    CHECK(count == 15, "registered linear solvers: %d", count);
    eo_test_ctx_done(&ctx);
}

static void test_api(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const eo_linsolve_type *t = NULL;
    CHECK(eo_linsolve_find(ctx, "nope", &t) == EO_ERR_UNKNOWN_NAME && !t, "unknown");
    CHECK(strstr(eo_ctx_message(ctx), "cholmod") && strstr(eo_ctx_message(ctx), "sor"), "lists names: %s",
          eo_ctx_message(ctx));
    CHECK(eo_linsolve_find(ctx, "lapack", &t) == EO_OK && t, "find lapack");
    /* lapack refuses n > max_n */
    solver_cfg c;
    cfg_init(ctx, &c, t);
    set_param(ctx, &c, "max_n", "100");
    testmat T;
    testmat_create(ctx, 6, 6, 6, 0, &T);
    testmat_fill(&T, 1, 0, 1);
    eo_linsolve *ls = NULL;
    CHECK(eo_linsolve_create(ctx, t, c.params, &ls) == EO_OK, "create");
    CHECK(eo_linsolve_analyze(ls, eo_assembler_matrix(T.as)) == EO_ERR_UNSUPPORTED, "max_n refused");
    CHECK(strstr(eo_ctx_message(ctx), "max_n") != NULL, "message: %s", eo_ctx_message(ctx));
    CHECK(eo_linsolve_factor(ls, eo_assembler_matrix(T.as)) == EO_ERR_INVALID, "factor before analyze");
    eo_linsolve_destroy(&ls);
    /* params are range-checked at create */
    CHECK(eo_linsolve_find(ctx, "sor", &t) == EO_OK, "sor");
    cfg_init(ctx, &c, t);
    *(double *)((char *)c.params + eo_params_find(t->info.params, "omega")->offset) = 2.5;
    CHECK(eo_linsolve_create(ctx, t, c.params, &ls) == EO_ERR_RANGE && !ls, "omega 2.5 rejected: %s",
          eo_ctx_message(ctx));
    CHECK(strstr(eo_ctx_message(ctx), "solver.sor.omega") != NULL, "message: %s", eo_ctx_message(ctx));
    /* pattern change detected */
    CHECK(eo_linsolve_create(ctx, t, NULL, &ls) == EO_OK, "defaults");
    CHECK(eo_linsolve_analyze(ls, eo_assembler_matrix(T.as)) == EO_OK, "analyze");
    testmat T2;
    testmat_create(ctx, 5, 5, 5, 0, &T2);
    testmat_fill(&T2, 1, 0, 1);
    CHECK(eo_linsolve_factor(ls, eo_assembler_matrix(T2.as)) == EO_ERR_INVALID, "pattern change refused");
    eo_linsolve_destroy(&ls);
    eo_assembler_destroy(&T.as);
    eo_assembler_destroy(&T2.as);
    eo_test_ctx_done(&ctx);
}

/* GMRES with a Krylov space as large as needed (restart 300 on n = 900) solves the
 * indefinite L − 2.05 I to 1e-10 (Jacobi |diag| and IC(0)-falling-back-to-Jacobi) */
static void test_gmres_indefinite(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const eo_linsolve_type *t = NULL;
    CHECK(eo_linsolve_find(ctx, "gmres", &t) == EO_OK, "gmres registered");
    testmat T;
    testmat_create(ctx, 10, 10, 9, 150, &T);
    testmat_fill(&T, -2.05, 0.0, 4);
    eo_csc *A = eo_assembler_matrix(T.as);
    const int n = A->n;
    double *b = malloc((size_t)n * sizeof(double)), *x = malloc((size_t)n * sizeof(double));
    double *ref = malloc((size_t)n * sizeof(double));
    eo_test_seed(99);
    for (int i = 0; i < n; i++) b[i] = eo_test_rand(-1, 1);
    dense_solve(A, b, ref, 0);
    const char *pcs[] = {"\"jacobi\"", "\"ic0\""};
    for (int k = 0; k < 2; k++) {
        solver_cfg c;
        cfg_init(ctx, &c, t);
        set_param(ctx, &c, "restart", "300");
        set_param(ctx, &c, "tol", "1e-10");
        set_param(ctx, &c, "preconditioner", pcs[k]);
        eo_linsolve *ls = NULL;
        int frc = 0;
        CHECK(eo_linsolve_create(ctx, t, c.params, &ls) == EO_OK, "create");
        int rc = run(ctx, ls, A, b, x, 1, &frc);
        const eo_linsolve_stats *st = eo_linsolve_get_stats(ls);
        CHECK(rc == EO_OK && rel_res(A, b, x) <= 1e-10 && rel_err(n, x, ref) < 1e-7,
              "gmres(300) %s indefinite: rc %d its %d res %g err %g", pcs[k], rc, st->iterations, rel_res(A, b, x),
              rel_err(n, x, ref));
        eo_linsolve_destroy(&ls);
    }
    free(b);
    free(x);
    free(ref);
    eo_assembler_destroy(&T.as);
    eo_test_ctx_done(&ctx);
}

/* eo_linsolve_set_rtol: an inexact solve stops at the requested residual, 0 restores
 * tol, >= 1 is refused; direct solvers accept and ignore it */
static void test_rtol(void)
{
    eo_ctx *ctx = eo_test_ctx();
    testmat T;
    testmat_create(ctx, 10, 10, 9, 150, &T);
    testmat_fill(&T, 0.5, 1.0, 2);
    eo_csc *A = eo_assembler_matrix(T.as);
    const int n = A->n;
    double *b = malloc((size_t)n * sizeof(double)), *x = malloc((size_t)n * sizeof(double));
    for (int i = 0; i < n; i++) b[i] = cos(i);
    const char *names[] = {"cg", "pcg", "gmres", "cholmod"};
    for (int k = 0; k < 4; k++) {
        const eo_linsolve_type *t = NULL;
        eo_linsolve_find(ctx, names[k], &t);
        eo_linsolve *ls = NULL;
        int frc = 0;
        CHECK(eo_linsolve_create(ctx, t, NULL, &ls) == EO_OK, "create %s", names[k]);
        CHECK(eo_linsolve_set_rtol(ls, 1.5) == EO_ERR_RANGE && eo_linsolve_set_rtol(ls, NAN) == EO_ERR_RANGE,
              "%s: rtol >= 1 refused", names[k]);
        CHECK(eo_linsolve_set_rtol(ls, 1e-3) == EO_OK, "%s: set_rtol", names[k]);
        int rc = run(ctx, ls, A, b, x, 1, &frc);
        double r1 = rel_res(A, b, x);
        int it1 = eo_linsolve_get_stats(ls)->iterations;
        CHECK(eo_linsolve_set_rtol(ls, 0) == EO_OK, "%s: restore", names[k]);
        rc |= eo_linsolve_solve(ls, b, x);
        double r2 = rel_res(A, b, x);
        int it2 = eo_linsolve_get_stats(ls)->iterations;
        if (k < 3)
            CHECK(rc == EO_OK && r1 <= 1e-3 && r1 > 1e-8 && r2 <= 1e-10 * 1.001 && it1 < it2,
                  "%s: rtol 1e-3 -> res %g in %d its; tol 1e-10 -> res %g in %d its", names[k], r1, it1, r2, it2);
        else
            CHECK(rc == EO_OK && r1 < 1e-12 && r2 < 1e-12, "cholmod ignores rtol: %g %g", r1, r2);
        eo_linsolve_destroy(&ls);
    }
    free(b);
    free(x);
    eo_assembler_destroy(&T.as);
    eo_test_ctx_done(&ctx);
}

/* cholmod_reuse with the parameters c: a solver factoring the near matrix (shift 1.0),
 * then solving the far one (other random blocks) with that old factor; rc of the far
 * solve, its reference solution in ref */
static eo_linsolve *stale_solve(eo_ctx *ctx, const eo_linsolve_type *t, const solver_cfg *c, testmat *T,
                                const eo_csc *A, const double *b, double *x, double *ref, int *rc)
{
    eo_linsolve *ls = NULL;
    int frc = 0;
    CHECK(eo_linsolve_create(ctx, t, c->params, &ls) == EO_OK, "create");
    testmat_fill(T, 1.0, 1.0, 2);
    run(ctx, ls, A, b, x, 1, &frc);
    testmat_fill(T, 0.3, 1.0, 7);
    dense_solve(A, b, ref, 1);
    *rc = run(ctx, ls, A, b, x, 0, &frc);
    return ls;
}

/* pcg cholmod_reuse: when it refactors (pcg.c: rules 1-3) */
static void test_cholmod_reuse(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const eo_linsolve_type *t = NULL;
    eo_linsolve_find(ctx, "pcg", &t);
    solver_cfg c;
    cfg_init(ctx, &c, t);
    set_param(ctx, &c, "preconditioner", "\"cholmod_reuse\"");
    set_param(ctx, &c, "tol", "1e-10");
    set_param(ctx, &c, "refactor_iters", "10");
    testmat T;
    testmat_create(ctx, 10, 10, 9, 150, &T);
    eo_csc *A = eo_assembler_matrix(T.as);
    const int n = A->n;
    double *b = malloc((size_t)n * sizeof(double)), *x = malloc((size_t)n * sizeof(double));
    double *ref = malloc((size_t)n * sizeof(double));
    for (int i = 0; i < n; i++) b[i] = sin(0.3 * i);
    eo_linsolve *ls = NULL;
    int frc = 0, rc;
    CHECK(eo_linsolve_create(ctx, t, c.params, &ls) == EO_OK, "create");
    const eo_linsolve_stats *st = eo_linsolve_get_stats(ls);
    /* 1: first factor after analyze refactors; the exact factor converges at once */
    testmat_fill(&T, 1.0, 1.0, 2);
    dense_solve(A, b, ref, 1);
    rc = run(ctx, ls, A, b, x, 1, &frc);
    CHECK(rc == EO_OK && st->n_refactor == 1 && st->iterations <= 2 && rel_err(n, x, ref) < 1e-8,
          "fresh factor: rc %d refactors %ld its %d", rc, st->n_refactor, st->iterations);
    /* a nearby matrix (shift 1.0 -> 1.02): the old factor preconditions, no refactor */
    testmat_fill(&T, 1.02, 1.0, 2);
    dense_solve(A, b, ref, 1);
    rc = run(ctx, ls, A, b, x, 0, &frc);
    int its_near = st->iterations;
    CHECK(rc == EO_OK && st->n_refactor == 1 && its_near > 2 && its_near <= 10 && rel_err(n, x, ref) < 1e-8,
          "reused factor: rc %d refactors %ld its %d err %g", rc, st->n_refactor, its_near, rel_err(n, x, ref));
    /* an analyze of the same pattern keeps the factor */
    rc = run(ctx, ls, A, b, x, 1, &frc);
    CHECK(rc == EO_OK && st->n_refactor == 1 && st->iterations == its_near, "same-pattern analyze keeps the factor");
    /* 2: a far matrix (other random blocks) needs > 10 iterations: solved, and the next
     * factor refactors */
    testmat_fill(&T, 0.3, 1.0, 7);
    dense_solve(A, b, ref, 1);
    rc = run(ctx, ls, A, b, x, 0, &frc);
    int its_far = st->iterations;
    CHECK(rc == EO_OK && st->n_refactor == 1 && its_far > 10 && rel_err(n, x, ref) < 1e-8,
          "far matrix with the old factor: rc %d its %d refactors %ld", rc, its_far, st->n_refactor);
    rc = run(ctx, ls, A, b, x, 0, &frc);
    CHECK(rc == EO_OK && st->n_refactor == 2 && st->iterations <= 2, "refactored after %d > 10 its: %ld, its %d",
          its_far, st->n_refactor, st->iterations);
    eo_linsolve_destroy(&ls);
    /* 3': the far matrix with refactor_iters 2: a solve with the old factor stops at
     * reuse_max_iters = 4 x 2 = 8 (< its_far) and refactors at once: direct, exact */
    set_param(ctx, &c, "refactor_iters", "2");
    ls = stale_solve(ctx, t, &c, &T, A, b, x, ref, &rc);
    st = eo_linsolve_get_stats(ls);
    CHECK(its_far > 8 && rc == EO_OK && st->n_refactor == 2 && st->iterations == 0 && rel_err(n, x, ref) < 1e-8,
          "reuse_max_iters 4 x 2 < %d: refactor inside the solve (rc %d, refactors %ld, its %d, err %g)", its_far, rc,
          st->n_refactor, st->iterations, rel_err(n, x, ref));
    /* ... and it stopped before the cap: from the second iteration on, the contraction so
     * far projected more than 8 iterations (its_far of them were needed) */
    int gave_up_at = -1;
    const char *msg = strstr(eo_ctx_message(ctx), "given up (contraction too slow) after ");
    if (msg) gave_up_at = atoi(msg + strlen("given up (contraction too slow) after "));
    printf("far matrix, cap 8: the old factor's CG gave up after %d iterations (%d to converge)\n", gave_up_at,
           its_far);
    CHECK(gave_up_at >= 2 && gave_up_at < 8, "projected past the cap: gave up after %d iterations (%s)", gave_up_at,
          eo_ctx_message(ctx));
    rc = run(ctx, ls, A, b, x, 0, &frc); /* the same matrix again: the new factor is kept */
    CHECK(rc == EO_OK && st->n_refactor == 2 && st->iterations <= 2 && rel_err(n, x, ref) < 1e-8,
          "after the cap: factor kept (refactors %ld, its %d)", st->n_refactor, st->iterations);
    eo_linsolve_destroy(&ls);
    /* the cap given explicitly, above its_far: the old factor's CG runs to the end */
    set_param(ctx, &c, "reuse_max_iters", "1000");
    ls = stale_solve(ctx, t, &c, &T, A, b, x, ref, &rc);
    st = eo_linsolve_get_stats(ls);
    CHECK(rc == EO_OK && st->n_refactor == 1 && st->iterations == its_far && rel_err(n, x, ref) < 1e-8,
          "reuse_max_iters 1000: %d its with the old factor (%d before), refactors %ld", st->iterations, its_far,
          st->n_refactor);
    eo_linsolve_destroy(&ls);
    set_param(ctx, &c, "reuse_max_iters", "0");
    set_param(ctx, &c, "refactor_iters", "10");
    /* 3: a solve that hits max_iters with a reused factor refactors at once */
    set_param(ctx, &c, "max_iters", "3");
    ls = stale_solve(ctx, t, &c, &T, A, b, x, ref, &rc);
    st = eo_linsolve_get_stats(ls);
    CHECK(rc == EO_OK && st->n_refactor == 2 && rel_err(n, x, ref) < 1e-8,
          "max_iters with the old factor: refactor inside solve (rc %d, refactors %ld, err %g)", rc, st->n_refactor,
          rel_err(n, x, ref));
    eo_linsolve_destroy(&ls);
    free(b);
    free(x);
    free(ref);
    eo_assembler_destroy(&T.as);
    eo_test_ctx_done(&ctx);
}

/* auto: the choice by size (thresholds set low), its description, is_iterative, the
 * reuse of the factor, a tolerance handed to a delegate created later, a new pattern of
 * another size switching the delegate */
static void test_auto(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const eo_linsolve_type *t = NULL;
    CHECK(eo_linsolve_find(ctx, "auto", &t) == EO_OK, "auto registered");
    solver_cfg c;
    cfg_init(ctx, &c, t);
    set_param(ctx, &c, "reuse_min", "200");
    set_param(ctx, &c, "iterative_min", "900");
    set_param(ctx, &c, "nd_min", "400");
    static const struct {
        int nx, ny, nz;
        const char *choice;
        int iterative;
    } cases[] = {{4, 4, 4, "cholmod (amd), n = 64 < reuse_min 200", 0},
                 {6, 6, 6, "pcg + cholmod_reuse (amd), n = 216 >= reuse_min 200", 1},
                 {8, 8, 8, "pcg + cholmod_reuse (nesdis), n = 512 >= reuse_min 200", 1},
                 {10, 10, 10, "pcg + gmg, n = 1000 >= iterative_min 900", 1}};
    eo_linsolve *keep = NULL; /* one object through every size: the delegate follows */
    CHECK(eo_linsolve_create(ctx, t, c.params, &keep) == EO_OK, "create");
    char d[160];
    CHECK(!strcmp(eo_linsolve_describe(keep, d, sizeof d), "no matrix analyzed yet") &&
              eo_linsolve_is_iterative(keep) == 0 && eo_linsolve_allows_own_factor(keep),
          "before analyze: '%s'", d);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        testmat T;
        testmat_create(ctx, cases[k].nx, cases[k].ny, cases[k].nz, cases[k].nx * 15, &T);
        eo_csc *A = eo_assembler_matrix(T.as);
        const int n = A->n;
        double *b = malloc((size_t)n * sizeof(double)), *x = malloc((size_t)n * sizeof(double));
        double *ref = malloc((size_t)n * sizeof(double));
        for (int i = 0; i < n; i++) b[i] = cos(0.7 * i);
        eo_linsolve *ls = NULL;
        CHECK(eo_linsolve_create(ctx, t, c.params, &ls) == EO_OK, "create");
        const eo_linsolve_stats *st = eo_linsolve_get_stats(ls);
        /* a forcing term given before the first analyze reaches the delegate */
        CHECK(eo_linsolve_set_rtol(ls, 1e-3) == EO_OK, "set_rtol before analyze");
        int frc = 0;
        testmat_fill(&T, 1.0, 1.0, 2);
        dense_solve(A, b, ref, 1);
        int rc = run(ctx, ls, A, b, x, 1, &frc);
        eo_linsolve_describe(ls, d, sizeof d);
        CHECK(rc == EO_OK && !strcmp(d, cases[k].choice), "n = %d: rc %d, choice '%s' (expected '%s')", n, rc, d,
              cases[k].choice);
        CHECK(eo_linsolve_is_iterative(ls) == cases[k].iterative, "n = %d: is_iterative %d", n,
              eo_linsolve_is_iterative(ls));
        /* direct, a fresh reused factor (exact) or the multigrid to 1e-3 */
        const double tol1 = cases[k].iterative && strstr(d, "gmg") ? 1e-2 : 1e-10;
        CHECK(rel_err(n, x, ref) < tol1, "n = %d (%s): first solve error %g", n, d, rel_err(n, x, ref));
        /* a nearby matrix: the reuse keeps its factor and iterates, to the forcing term */
        testmat_fill(&T, 1.05, 1.0, 2);
        dense_solve(A, b, ref, 1);
        eo_linsolve_set_rtol(ls, 1e-9);
        rc = run(ctx, ls, A, b, x, 0, &frc);
        CHECK(rc == EO_OK && rel_err(n, x, ref) < 1e-7, "n = %d (%s): second solve rc %d error %g", n, d, rc,
              rel_err(n, x, ref));
        if (strstr(d, "cholmod_reuse"))
            CHECK(st->n_refactor == 1 && st->iterations > 0 && st->residual <= 1e-9 * 1.0001,
                  "n = %d: reused factor: refactors %ld, PCG iterations %d, residual %g", n, st->n_refactor,
                  st->iterations, st->residual);
        else if (!cases[k].iterative)
            CHECK(st->iterations == 0 && st->n_factor == 2, "n = %d: direct: its %d factors %ld", n, st->iterations,
                  st->n_factor);
        eo_linsolve_destroy(&ls);
        /* the kept object: a new pattern of another size switches the delegate */
        rc = run(ctx, keep, A, b, x, 1, &frc);
        eo_linsolve_describe(keep, d, sizeof d);
        CHECK(rc == EO_OK && !strcmp(d, cases[k].choice) && rel_err(n, x, ref) < 1e-7,
              "kept solver at n = %d: '%s', error %g", n, d, rel_err(n, x, ref));
        free(b);
        free(x);
        free(ref);
        eo_assembler_destroy(&T.as);
    }
    eo_linsolve_destroy(&keep);
    eo_test_ctx_done(&ctx);
}

/* set_coordinates: argument checks; amg (if built) with rigid-body modes still solves */
static void test_coordinates(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const eo_linsolve_type *t = NULL;
    eo_linsolve_find(ctx, "pcg", &t);
    testmat T;
    testmat_create(ctx, 10, 10, 9, 150, &T);
    testmat_fill(&T, 0.5, 1.0, 2);
    eo_csc *A = eo_assembler_matrix(T.as);
    const int n = A->n, nv = n / 3;
    double *b = malloc((size_t)n * sizeof(double)), *x = malloc((size_t)n * sizeof(double));
    double *ref = malloc((size_t)n * sizeof(double)), *xyz = malloc((size_t)n * sizeof(double));
    for (int i = 0; i < n; i++) b[i] = cos(i), xyz[i] = eo_test_rand(0, 1);
    dense_solve(A, b, ref, 1);
    eo_linsolve *ls = NULL;
    CHECK(eo_linsolve_create(ctx, t, NULL, &ls) == EO_OK, "create");
    CHECK(eo_linsolve_set_coordinates(ls, -1, xyz) == EO_ERR_INVALID, "nv < 0");
    CHECK(eo_linsolve_set_coordinates(ls, 3, NULL) == EO_ERR_INVALID, "NULL xyz");
    CHECK(eo_linsolve_set_coordinates(ls, nv, xyz) == EO_OK, "jacobi ignores coordinates");
    eo_linsolve_destroy(&ls);
#if EO_HAVE_HYPRE
    solver_cfg c;
    for (int rbm = 0; rbm < 2; rbm++) {
        cfg_init(ctx, &c, t);
        set_param(ctx, &c, "preconditioner", "\"amg\"");
        set_param(ctx, &c, "amg_rbm", rbm ? "true" : "false");
        set_param(ctx, &c, "tol", "1e-10");
        int frc = 0;
        CHECK(eo_linsolve_create(ctx, t, c.params, &ls) == EO_OK, "create amg");
        CHECK(eo_linsolve_set_coordinates(ls, nv, xyz) == EO_OK, "amg coordinates");
        int rc = run(ctx, ls, A, b, x, 1, &frc);
        CHECK(rc == EO_OK && rel_err(n, x, ref) < 1e-8, "amg rbm=%d: rc %d its %d err %g", rbm, rc,
              eo_linsolve_get_stats(ls)->iterations, rel_err(n, x, ref));
        /* coordinates after analyze are used by the next factor */
        CHECK(eo_linsolve_set_coordinates(ls, nv, xyz) == EO_OK, "again");
        rc = run(ctx, ls, A, b, x, 0, &frc);
        CHECK(rc == EO_OK && rel_err(n, x, ref) < 1e-8, "amg refactor: rc %d", rc);
        eo_linsolve_destroy(&ls);
    }
#else
    /* without hypre the name is valid but creating the solver says it is not built */
    solver_cfg c;
    cfg_init(ctx, &c, t);
    CHECK(set_param(ctx, &c, "preconditioner", "\"amg\"") == EO_OK, "amg is a known name");
    CHECK(eo_linsolve_create(ctx, t, c.params, &ls) == EO_ERR_UNSUPPORTED && !ls, "amg refused without hypre");
    CHECK(strstr(eo_ctx_message(ctx), "hypre") != NULL, "message says why: %s", eo_ctx_message(ctx));
#endif
    free(b);
    free(x);
    free(ref);
    free(xyz);
    eo_assembler_destroy(&T.as);
    eo_test_ctx_done(&ctx);
}

/* failure injection over create + analyze of every solver: no leak on any path */
static void test_linsolve_fail(void)
{
    eo_ctx *ctx = eo_test_ctx();
    testmat T;
    testmat_create(ctx, 5, 5, 4, 10, &T);
    testmat_fill(&T, 1, 1, 1);
    eo_csc *A = eo_assembler_matrix(T.as);
    for (const void *const *t = eo_registry_list(EO_KIND_LINSOLVE); *t; t++) {
        const eo_linsolve_type *type = *t;
        size_t base = eo_ctx_live_bytes(ctx);
        int ok = 0;
        for (long f = 1; f < 100 && !ok; f++) {
            eo_linsolve *ls = NULL;
            eo_ctx_fail_after(ctx, f);
            int rc = eo_linsolve_create(ctx, type, NULL, &ls);
            if (rc >= 0) rc = eo_linsolve_analyze(ls, A);
            eo_ctx_fail_after(ctx, 0);
            if (rc >= 0) {
                ok = 1;
                rc = eo_linsolve_factor(ls, A);
                CHECK(rc == EO_OK, "%s: factor after injection run %ld", type->info.name, f);
            } else {
                CHECK(rc == EO_ERR_NOMEM, "%s: injected failure %ld gives %d", type->info.name, f, rc);
            }
            eo_linsolve_destroy(&ls);
            CHECK(eo_ctx_live_bytes(ctx) == base, "%s: leak at injected failure %ld", type->info.name, f);
        }
        CHECK(ok, "%s: eventually succeeds", type->info.name);
    }
    eo_assembler_destroy(&T.as);
    eo_test_ctx_done(&ctx);
}

int main(int argc, char **argv)
{
    g_quick = argc > 1 && strcmp(argv[1], "quick") == 0;
    test_assembler_tiny();
    test_assembler_random();
    test_assembler_blocks();
    test_assembler_fail();
    if (!g_quick) test_assembler_timing();
    test_api();
    test_linsolve_fail();
    test_contract();
    test_gmres_indefinite();
    test_rtol();
    test_cholmod_reuse();
    test_auto();
    test_coordinates();
    return eo_test_finish("test_linsolve");
}
