/* Internal helpers shared by the CHOLMOD-based solvers (cholmod.c, cholmod_ldlt.c):
 * a cholmod_sparse header borrowing our upper-triangular CSC (stype = +1, int
 * indices, nothing copied) and a solve through cholmod_solve2 that reuses its dense
 * workspaces (allocated by CHOLMOD on the first solve only). Not a public header. */
#ifndef EO_LINSYS_CHOLMOD_UTIL_H
#define EO_LINSYS_CHOLMOD_UTIL_H

#include <stdint.h>
#include <string.h>
#include <suitesparse/cholmod.h>

#include "eo_build_config.h"
#include "elastopt/linsolve.h"
#if EO_HAVE_OPENMP
#include <omp.h>
#endif

typedef struct eo_chm {
    cholmod_common c;
    int started;
    cholmod_factor *L;
    cholmod_dense *X, *Y, *E; /* solve2 workspaces, reused */
} eo_chm;

/* Header pointing at A's arrays (CHOLMOD only reads them). */
static inline cholmod_sparse eo_chm_view(const eo_csc *A)
{
    cholmod_sparse S;
    memset(&S, 0, sizeof S);
    S.nrow = S.ncol = (size_t)A->n;
    S.nzmax = (size_t)A->nnz;
    S.p = A->colptr;
    S.i = A->rowind;
    S.x = A->val;
    S.stype = 1; /* upper triangle stored */
    S.itype = CHOLMOD_INT;
    S.xtype = CHOLMOD_REAL;
    S.dtype = CHOLMOD_DOUBLE;
    S.sorted = 1;
    S.packed = 1;
    return S;
}

static inline void eo_chm_start(eo_chm *s)
{
    cholmod_start(&s->c);
    s->c.print = 0;
    s->c.error_handler = NULL;
    s->started = 1;
}

static inline void eo_chm_free_factor(eo_chm *s)
{
    if (!s->started) return;
    cholmod_free_factor(&s->L, &s->c);
    cholmod_free_dense(&s->X, &s->c);
    cholmod_free_dense(&s->Y, &s->c);
    cholmod_free_dense(&s->E, &s->c);
}

static inline void eo_chm_finish(eo_chm *s)
{
    if (!s->started) return;
    eo_chm_free_factor(s);
    cholmod_finish(&s->c);
    s->started = 0;
}

/* The orderings the CHOLMOD-based solvers offer, and the default of solver.cholmod
 * (chosen by measurement, see cholmod.c) that pcg's cholmod_reuse uses too. */
#define EO_CHM_ORDERINGS {"auto", "amd", "metis", "nesdis", "natural", NULL}
#define EO_CHM_DEFAULT_ORDERING "amd"

/* Ordering choice -> CHOLMOD method list. "auto": CHOLMOD's default strategy (AMD, and
 * METIS when built in and AMD's fill is high: flops/lnz >= 500 and lnz/nnz(A) >= 5);
 * "amd"; "metis" (METIS_NodeND on A + Aᵀ); "nesdis" (CHOLMOD's nested dissection:
 * METIS node separators + constrained minimum degree, CAMD/CCOLAMD); "natural" (no
 * permutation). */
static inline void eo_chm_ordering(eo_chm *s, const char *ordering)
{
    if (strcmp(ordering, "amd") == 0 || strcmp(ordering, "metis") == 0 || strcmp(ordering, "nesdis") == 0) {
        s->c.nmethods = 1;
        s->c.method[0].ordering = ordering[0] == 'a' ? CHOLMOD_AMD : ordering[0] == 'm' ? CHOLMOD_METIS : CHOLMOD_NESDIS;
        s->c.postorder = 1;
    } else if (strcmp(ordering, "natural") == 0) {
        s->c.nmethods = 1;
        s->c.method[0].ordering = CHOLMOD_NATURAL;
        s->c.postorder = 0;
    } else {
        s->c.nmethods = 0;
        s->c.postorder = 1;
    }
}

static inline int eo_chm_analyze(eo_chm *s, const eo_csc *A, const char *who, eo_ctx *ctx)
{
    eo_chm_free_factor(s);
    cholmod_sparse S = eo_chm_view(A);
    s->L = cholmod_analyze(&S, &s->c);
    if (!s->L) {
        int st = s->c.status;
        return eo_error(ctx, st == CHOLMOD_OUT_OF_MEMORY ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                        "%s: cholmod_analyze failed (CHOLMOD status %d, n=%d, nnz=%d)", who, st,
                        A->n, A->nnz);
    }
    return EO_OK;
}

/* Numeric factorization, reusing the symbolic factor. Debian's CHOLMOD is built with
 * OpenMP and asks for CHOLMOD_OMP_NUM_THREADS = 4 threads (a compile-time constant)
 * inside every large supernode, on top of the BLAS's own threads: on a 2-core machine
 * that oversubscribes the cores and the threads spend their time in futex waits
 * (50k-tet twist Hessian, 36k dofs: 3 steps of Newton 2.2 s with the loops serial vs
 * 3.1-4.1 s with them; see the README's threads note). Unless `openmp` is set, the
 * OpenMP regions inside the call run on one thread (max-active-levels 0, restored
 * after); the BLAS keeps its own threads (OPENBLAS_NUM_THREADS). */
static inline int eo_chm_factorize(eo_chm *s, cholmod_sparse *S, int openmp)
{
#if EO_HAVE_OPENMP
    int levels = omp_get_max_active_levels();
    if (!openmp) omp_set_max_active_levels(0);
#else
    (void)openmp;
#endif
    int ok = cholmod_factorize(S, s->L, &s->c);
#if EO_HAVE_OPENMP
    if (!openmp) omp_set_max_active_levels(levels);
#endif
    return ok;
}

/* Original (unpermuted) index of permuted column k. */
static inline int eo_chm_orig(const eo_chm *s, int k)
{
    const int *P = s->L->Perm;
    return P ? P[k] : k;
}

static inline int eo_chm_solve(eo_chm *s, const double *b, double *x, int n, const char *who,
                               eo_ctx *ctx)
{
    cholmod_dense B;
    memset(&B, 0, sizeof B);
    B.nrow = (size_t)n;
    B.ncol = 1;
    B.nzmax = (size_t)n;
    B.d = (size_t)n;
    B.x = (void *)(uintptr_t)b; /* read only */
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A, s->L, &B, NULL, &s->X, NULL, &s->Y, &s->E, &s->c))
        return eo_error(ctx, s->c.status == CHOLMOD_OUT_OF_MEMORY ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                        "%s: cholmod_solve2 failed (CHOLMOD status %d)", who, s->c.status);
    memcpy(x, s->X->x, (size_t)n * sizeof(double));
    return EO_OK;
}

#endif
