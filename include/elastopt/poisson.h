/// @file poisson.h
/// 2D Poisson problem with linear triangles (notes 001 §3–4), as an objective.
///
///     −Δu = f in Ω = (0,1)²,   u = 0 on ∂Ω,
/// weak form (ERRATA for 001 eqs. 36–37: v = Σ v_j N_j with arbitrary v_j, one equation
/// per free node j):  Σᵢ uᵢ ∫ ∇Nᵢ·∇N_j = ∫ f N_j.  Structured triangulation: n×n squares,
/// each split along its (0,0)–(1,1) diagonal, (n+1)² nodes, 2n² triangles; the boundary
/// nodes are eliminated (Dirichlet), leaving (n−1)² unknowns. The stiffness matrix K is
/// assembled with the shared fixed-pattern assembler (sparse.h), the load F with a
/// quadrature exact for quadratics. The problem is exposed as the objective
///     g(u) = ½ uᵀKu − Fᵀu,   ∇g = Ku − F,   ∇²g = K  (SPD)
/// so every optimizer and, through Newton, every linear solver can solve it (notes §4.2:
/// solving Ku = F is minimizing g). The manufactured solution u = sin(πx) sin(πy),
/// f = 2π² u, gives the error: the L2 norm of u_h − u (7-point quadrature per
/// triangle) decreases as O(h²), the nodal max error too.
///
/// ```c
/// eo_poisson *p; eo_poisson_create(ctx, 32, &p);
/// eo_objective *obj = eo_poisson_objective(p);
/// double *u = calloc(obj->n, sizeof *u);
/// eo_solver_minimize(solver, obj, u, NULL, NULL, &res);
/// double l2, mx; eo_poisson_error(p, u, &l2, &mx);
/// eo_poisson_destroy(&p);
/// ```
/// Ownership: the problem owns its objective, matrix and vectors (borrowed by callers).
#ifndef ELASTOPT_POISSON_H
#define ELASTOPT_POISSON_H

#include "export.h"
#include "objective.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_poisson eo_poisson;

/// Unit square with n×n cells (n >= 2). EO_ERR_INVALID for n < 2, EO_ERR_NOMEM.
EO_API int eo_poisson_create(eo_ctx *ctx, int n, eo_poisson **out);
EO_API void eo_poisson_destroy(eo_poisson **p);
/// The objective g(u) = ½uᵀKu − Fᵀu over the (n−1)² interior nodes (borrowed).
EO_API eo_objective *eo_poisson_objective(eo_poisson *p);
/// The stiffness matrix K (upper CSC, borrowed) and load vector F (borrowed).
EO_API const eo_csc *eo_poisson_matrix(const eo_poisson *p);
EO_API const double *eo_poisson_load(const eo_poisson *p);
/// Interior node i (0-based) ↔ grid position (i % (n−1) + 1, i / (n−1) + 1)·h.
/// L2 error ‖u_h − u‖ over Ω and max nodal error of interior values u (n−1)².
EO_API int eo_poisson_error(const eo_poisson *p, const double *u, double *l2, double *max_err);
/// Mesh size h = 1/n.
EO_API double eo_poisson_h(const eo_poisson *p);

#ifdef __cplusplus
}
#endif
#endif
