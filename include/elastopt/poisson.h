/// @file poisson.h
/// 2D Poisson problem with linear triangles (notes 001 §3–4), as an objective.
///
///     −Δu = f in Ω,   u = u_D on ∂Ω,
/// weak form (ERRATA for 001 eqs. 36–37: v = Σ v_j N_j with arbitrary v_j, one equation
/// per free node j):  Σᵢ uᵢ ∫ ∇Nᵢ·∇N_j = ∫ f N_j.  Ω is either the unit square with a
/// structured triangulation (n×n squares, each split along its (0,0)–(1,1) diagonal,
/// (n+1)² nodes, 2n² triangles, (n−1)² unknowns) or any triangulation (eo_trimesh, e.g.
/// read from a Gmsh 2D mesh with eo_trimesh_read_gmsh): the boundary nodes are the nodes
/// of edges used by one triangle. Boundary nodes are eliminated (Dirichlet) with values
/// u_D = the problem's exact solution there (0 for the default problem), moved to the
/// right-hand side: K_ff u_f = F_f − K_fb u_D. The stiffness matrix K is assembled with
/// the shared fixed-pattern assembler (sparse.h). The load F_j = Σ_e ∫_e f N_j uses the
/// quadrature `quadrature`:
///   midpoint  (default) the three edge midpoints, (A/3) Σ f(m) N_j(m): exact for
///             quadratic f·N_j, keeps the O(h²) L2 rate clean of quadrature error;
///   centroid  the notes' one-point rule (001 eq. 50): A f(x_c, y_c) N_j(x_c, y_c) =
///             A f(x_c, y_c)/3, exact for constant f (still O(h²) in L2 for smooth f).
/// The problem is exposed as the objective
///     g(u) = ½ uᵀKu − Fᵀu,   ∇g = Ku − F,   ∇²g = K  (SPD)
/// so every optimizer and, through Newton, every linear solver can solve it (notes §4.2:
/// solving Ku = F is minimizing g). Default problem: the manufactured solution
/// u = sin(πx) sin(πy), f = 2π² u (zero on the unit square's boundary and on every line
/// x, y ∈ ℤ, so also on an L-shape (−1,1)² \ [0,1)×(−1,0]). The L2 norm of u_h − u
/// (7-point quadrature per triangle) decreases as O(h²), the nodal max error too.
///
/// ```c
/// eo_poisson *p; eo_poisson_create(ctx, 32, &p);
/// eo_objective *obj = eo_poisson_objective(p);
/// double *u = calloc(obj->n, sizeof *u);
/// eo_solver_minimize(solver, obj, u, NULL, NULL, &res);
/// double l2, mx; eo_poisson_error(p, u, &l2, &mx);
/// eo_poisson_write_vtu(p, u, "u.vtu");                  // triangles + field u
/// eo_poisson_destroy(&p);
/// ```
/// Ownership: the problem owns its objective, matrix, vectors and a copy of the mesh
/// (borrowed by callers); the problem description (eo_poisson_problem) is borrowed and
/// must outlive the eo_poisson.
#ifndef ELASTOPT_POISSON_H
#define ELASTOPT_POISSON_H

#include "export.h"
#include "objective.h"
#include "trimesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_poisson eo_poisson;

/// Right-hand-side quadrature (config key poisson.quadrature).
typedef enum eo_poisson_quadrature {
    EO_POISSON_QUAD_MIDPOINT = 0,  ///< "midpoint": three edge midpoints (degree 2), default
    EO_POISSON_QUAD_CENTROID,      ///< "centroid": one point at the barycentre (001 eq. 50)
} eo_poisson_quadrature;

/// A Poisson problem: source f and exact solution u (also the Dirichlet data; NULL:
/// u_D = 0 and eo_poisson_error is unavailable). `data` is passed to both.
typedef struct eo_poisson_problem {
    double (*f)(void *data, double x, double y);
    double (*u)(void *data, double x, double y);
    void *data;
} eo_poisson_problem;

typedef struct eo_poisson_opts {
    eo_poisson_quadrature quadrature;   ///< default EO_POISSON_QUAD_MIDPOINT
    int dirichlet;                      ///< 1 (default): boundary nodes eliminated; 0: every
                                        ///< node free (K singular: for assembly tests only)
    const eo_poisson_problem *problem;  ///< NULL (default): u = sin(πx) sin(πy)
} eo_poisson_opts;

EO_API void eo_poisson_opts_default(eo_poisson_opts *o);
/// "midpoint" / "centroid" → *q; EO_ERR_UNKNOWN_NAME (message lists both) otherwise.
EO_API int eo_poisson_quadrature_parse(eo_ctx *ctx, const char *name, eo_poisson_quadrature *q);
EO_API const char *eo_poisson_quadrature_name(eo_poisson_quadrature q);

/// Unit square with n×n cells (n >= 2), default options. EO_ERR_INVALID for n < 2, EO_ERR_NOMEM.
EO_API int eo_poisson_create(eo_ctx *ctx, int n, eo_poisson **out);
/// Unit square with options (NULL: defaults).
EO_API int eo_poisson_create_opts(eo_ctx *ctx, int n, const eo_poisson_opts *o, eo_poisson **out);
/// Any triangulation (copied). EO_ERR_MESH for a degenerate triangle (with its index),
/// a node index out of range, an edge shared by more than two triangles, or no free node.
EO_API int eo_poisson_create_mesh(eo_ctx *ctx, const eo_trimesh *m, const eo_poisson_opts *o, eo_poisson **out);
EO_API void eo_poisson_destroy(eo_poisson **p);
/// The objective g(u) = ½uᵀKu − Fᵀu over the free nodes (borrowed).
EO_API eo_objective *eo_poisson_objective(eo_poisson *p);
/// The stiffness matrix K (upper CSC over the free nodes, borrowed) and load vector F
/// (including the Dirichlet lift −K_fb u_D; borrowed).
EO_API const eo_csc *eo_poisson_matrix(const eo_poisson *p);
EO_API const double *eo_poisson_load(const eo_poisson *p);
/// Free ids: node of free id i, free id of node v (−1 on the boundary). On the unit
/// square, free node i (0-based) is grid position (i % (n−1) + 1, i / (n−1) + 1)·h.
EO_API int eo_poisson_free_node(const eo_poisson *p, int i);
EO_API int eo_poisson_node_free(const eo_poisson *p, int v);
/// The mesh (borrowed).
EO_API const eo_trimesh *eo_poisson_mesh(const eo_poisson *p);
/// Nodal solution (mesh->nv values, caller storage): free values u, boundary u_D.
EO_API void eo_poisson_nodal(const eo_poisson *p, const double *u, double *nodal);
/// L2 error ‖u_h − u‖ over Ω and max nodal error of free values u. EO_ERR_UNSUPPORTED
/// if the problem has no exact solution, EO_ERR_NONFINITE.
EO_API int eo_poisson_error(const eo_poisson *p, const double *u, double *l2, double *max_err);
/// Mesh size: 1/n on the unit square, the longest edge otherwise.
EO_API double eo_poisson_h(const eo_poisson *p);
/// Write the solution (free values u) as a VTU of triangles with point field "u"
/// (and "u_exact" is not written; boundary nodes carry u_D). Errors of eo_vtu_write_tri.
EO_API int eo_poisson_write_vtu(const eo_poisson *p, const double *u, const char *path);

#ifdef __cplusplus
}
#endif
#endif
