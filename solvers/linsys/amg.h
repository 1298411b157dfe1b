/* Internal: hypre BoomerAMG as a preconditioner (one V-cycle per application) for
 * pcg.c's `amg` choice; compiled only with hypre (EO_HAVE_HYPRE). Not a public header.
 *
 * Systems AMG for 3 unknowns per node (rows 3i, 3i+1, 3i+2 belong to node i):
 * HYPRE_BoomerAMGSetNumFunctions(3) with nodal coarsening (Frobenius norm of the
 * 3×3 blocks, SetNodal(1)); when node coordinates are known
 * (eo_linsolve_set_coordinates) the three rotational rigid-body modes
 * (0, −z, y), (z, 0, −x), (−y, x, 0) (about the centroid) are added to the
 * interpolation (SetInterpVectors, GM variant 2; Baker, Kolev & Yang 2010); the
 * translations are reproduced by nodal interpolation itself. Symmetric smoother
 * (hybrid symmetric Gauss–Seidel, relax type 6) so that M⁻¹ is symmetric for CG.
 * n not a multiple of 3: scalar AMG. The matrix is expanded to full CSR once per
 * pattern (eo_csc_full); hypre's setup allocates with its own allocator. */
#ifndef EO_LINSYS_AMG_H
#define EO_LINSYS_AMG_H

#include "elastopt/linsolve.h"

typedef struct eo_amg eo_amg;

typedef struct eo_amg_opts {
    double strong_threshold; /* BoomerAMG strength threshold (0.5 suits 3D elasticity) */
    int rbm;                 /* use the rigid-body modes when coordinates are set */
} eo_amg_opts;

/* Once per pattern (ctx allocations: the full pattern and index arrays). */
int eo_amg_create(eo_ctx *ctx, const eo_csc *A, const eo_amg_opts *o, eo_amg **out);
void eo_amg_destroy(eo_ctx *ctx, eo_amg **amg);
/* Rigid-body modes from the coordinates of the n/3 nodes (3 nv doubles, read during
 * the call; 3 nv != n: no modes). Used by the next eo_amg_setup. */
void eo_amg_set_coordinates(eo_amg *amg, int nv, const double *xyz);
/* AMG setup for the values of A (same pattern). EO_OK or EO_ERR_LINSOLVE. */
int eo_amg_setup(eo_amg *amg, const eo_csc *A, eo_ctx *ctx);
/* z = M⁻¹ r: one V-cycle from z = 0. */
void eo_amg_apply(const void *amg, const double *r, double *z);

#endif
