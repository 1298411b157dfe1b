/* Internal: the Galerkin multigrid hierarchy of gmg.c, shared by the standalone solver
 * `gmg` and pcg's `gmg` preconditioner (pcg.c). Not a public header; tests and benchmarks
 * reach it through the static library.
 *
 *   eo_gmg_create   once per pattern (analyze): levels, prolongations P_l, the block
 *                   patterns of A_{l+1} = P_lᵀ A_l P_l, the coarsest CHOLMOD analysis;
 *   eo_gmg_setup    per matrix (factor): level-0 values, the Galerkin products, the
 *                   inverted 3×3 diagonal blocks, the coarsest numeric factorization;
 *   eo_gmg_apply    z = M⁻¹ r, one symmetric V-cycle from z = 0 (eo_cg_precond_fn).
 * The mathematics and the parameters are in gmg.c's opening comment. */
#ifndef EO_LINSYS_GMG_H
#define EO_LINSYS_GMG_H

#include "elastopt/linsolve.h"

typedef struct eo_gmg eo_gmg;

enum { EO_GMG_LINEAR, EO_GMG_AFFINE };
#define EO_GMG_MAX_LEVELS 16

typedef struct eo_gmg_opts {
    int prolongation; /* EO_GMG_LINEAR or EO_GMG_AFFINE */
    double cell;      /* level-1 cube side / mean edge length; <= 0: 2 */
    int coarse_size;  /* stop coarsening at this many unknowns (CHOLMOD below) */
    int max_levels;   /* levels including the finest */
    int smooth_steps; /* block Gauss–Seidel sweeps before and after the coarse correction */
    const char *name; /* prefixes messages */
} eo_gmg_opts;

/* Build the hierarchy for the pattern of A (values ignored) and the nv node positions
 * xyz (3 nv, read during the call; the unknowns of node i are 3i, 3i+1, 3i+2). Without
 * coordinates (nv = 0), with 3 nv != A->n or when A is already small, the hierarchy has
 * one level: CHOLMOD on A. EO_OK, EO_ERR_NOMEM, EO_ERR_LINSOLVE. */
int eo_gmg_create(eo_ctx *ctx, const eo_csc *A, const eo_gmg_opts *o, int nv, const double *xyz, eo_gmg **out);
void eo_gmg_destroy(eo_ctx *ctx, eo_gmg **g);
/* Values of A (same pattern as at create): Galerkin products, smoother, coarsest factor.
 * EO_OK, EO_WARN_NOT_PD (a diagonal block or the coarsest matrix is not positive
 * definite; stats->not_pd_column = the column on level 0, else -1), EO_ERR_*. Does not
 * allocate from ctx (CHOLMOD allocates its factor itself). A is borrowed until the next
 * setup. */
int eo_gmg_setup(eo_gmg *g, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx);
/* z = M⁻¹ r: one V-cycle from z = 0 (r and z of length A->n, distinct). */
void eo_gmg_apply(const void *g, const double *r, double *z);

/* Inspection (tests, benchmarks). */
int eo_gmg_levels(const eo_gmg *g);
/* coarsest nodes dropped at create as dependent columns of the composite prolongation */
int eo_gmg_dropped(const eo_gmg *g);
/* unknowns of level l (3 per node) */
int eo_gmg_level_n(const eo_gmg *g, int l);
/* nonzeros of level l's full matrix (both triangles, scalar count) */
long eo_gmg_level_nnz(const eo_gmg *g, int l);
/* Dense copies: the full matrix of level l (n_l × n_l, row-major) and the prolongation
 * from level l+1 to level l (n_l × n_{l+1}, row-major, the node weights ⊗ I₃). */
void eo_gmg_level_dense(const eo_gmg *g, int l, double *D);
void eo_gmg_prolongation_dense(const eo_gmg *g, int l, double *P);
/* seconds of the last setup spent in the Galerkin products and the coarsest factor */
void eo_gmg_setup_times(const eo_gmg *g, double *t_galerkin, double *t_coarse);

#endif
