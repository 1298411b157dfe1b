/* The constant projective-dynamics matrix of the step objective (private to problems/;
 * see pd_matrix.c for its definition). */
#ifndef EO_PROBLEMS_PD_MATRIX_H
#define EO_PROBLEMS_PD_MATRIX_H

#include "term.h"

/* Cache of L for one step objective: built on first request after a pattern change
 * (or a change of the integrator weight), then returned as is. */
typedef struct eo_pd_matrix {
    eo_csc *L;                 /* own matrix (pattern copied from the assembler) */
    unsigned long version;     /* bumped at every rebuild; 0 = never built */
    unsigned long pattern_id;  /* pattern L was built for */
    double w;                  /* integrator weight L was built with */
} eo_pd_matrix;

/* Per-tet weight kₜ of a tet material: the mean of ∂²ψ/∂F_ii² (i = 1, 2, 3) at F = I,
 * after the clamp projection; λ + 2μ for every model that linearizes to linear
 * elasticity (the P-wave modulus). */
double eo_pd_tet_weight(const eo_material_type *mt, const eo_material_coef *c);

/* L of the current pattern (id `pattern_id`, changed by the caller whenever it rebuilds
 * s->as) and weight w: rebuilt if either changed, else the cached one. The values of
 * the assembler's matrix (a Hessian a caller may still hold) are preserved. Allocates
 * only when rebuilding for a new pattern. *L borrowed. */
int eo_pd_matrix_get(eo_pd_matrix *pd, eo_sys *s, eo_term *const *terms, int nterms,
                     unsigned long pattern_id, double w, eo_csc **L, unsigned long *version);
void eo_pd_matrix_deinit(eo_ctx *ctx, eo_pd_matrix *pd);

#endif
