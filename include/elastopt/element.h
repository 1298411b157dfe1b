/// @file element.h
/// Finite elements: the kind (`element` scene key, EO_KIND_ELEMENT) that knows the nodes
/// of a tet, its shape functions, its quadrature and its mass.
///
/// An element is a const table, registered like every other kind. The step engine and its
/// terms ask it for what they need and nothing else knows shape functions:
///  - `nodes`: nodes per tet, 4 (the mesh's tets) or 10 (a quadratic mesh's tet10, mesh.h;
///    a linear mesh is made quadratic once, at scene load, by eo_mesh_to_quadratic);
///  - the shape functions N_a and their derivatives ∂N_a/∂λ_j in the barycentric
///    coordinates λ of the straight-sided (affine) tet of the corners. The geometry is the
///    corners' (subparametric): ∇N_a = Σ_j ∂N_a/∂λ_j ∇λ_j with ∇λ_j constant per tet, so the
///    rest data of every element is the linear tet's Dₘ⁻¹ and volume V;
///  - the energy quadrature (points in barycentric coordinates, weights summing to 1), on
///    which ψ, P and the projected ∂P/∂F come from the same material kernel as the linear
///    tet (eo_material_evaluate), so every Hessian fix works unchanged (per-point PSD
///    projections sum to a PSD element matrix);
///  - the consistent mass per unit ρV (nodes × nodes), the lumped mass per unit ρV
///    (positive, summing to 1) and the load vector ∫N_a dV / V (gravity with the consistent
///    mass; with the lumped mass gravity is the lumped masses times g).
///
/// ```c
/// const eo_element_type *el;
/// eo_registry_find(ctx, EO_KIND_ELEMENT, "p2", (const void **)&el);
/// double e, g[30], H[900], minJ;
/// eo_element_evaluate(el, mt, &coef, Dminv, V, x30, EO_EVAL_HESS, EO_PROJ_CLAMP, &e, g, H, &minJ);
/// ```
#ifndef ELASTOPT_ELEMENT_H
#define ELASTOPT_ELEMENT_H

#include "export.h"
#include "material.h"
#include "registry.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    EO_ELEMENT_MAX_NODES = 10,   ///< largest `nodes` an element may have
    EO_ELEMENT_MAX_QP = 64       ///< largest `nq`
};

enum {
    /// The linear tet: the engine's own paths (eo_tet_evaluate, the Morton-ordered loops,
    /// the per-tet operations of projective dynamics, ADMM, vertex block descent) apply.
    EO_ELEMENT_LINEAR = 1,
    /// Mean-dilatation mixed element (displacement of the element's order, pressure and
    /// dilatation constant per tet, condensed: Simo, Taylor & Pister 1985; Hughes 1980 for
    /// the linear case): the energy per tet is
    ///     V [Σ_q w_q ψ_d(F_q) + κ/2 (θ − 1)²],   θ = Σ_q w_q det F_q,
    /// with ψ_d the material at the reduced λ_d = min(λ, μ) (same μ) and κ = λ − λ_d:
    /// the same linearization as the material (λ_d + κ = λ), the volume constraint enforced
    /// once per tet instead of at every point. With a projection asked, the curvature
    /// term κ(θ − 1)∇²θ is dropped (Gauss–Newton: the element matrix stays PSD).
    EO_ELEMENT_MEAN_DILATATION = 2,
    /// Average nodal pressure (Bonet & Burton 1998): the tets carry the material at λ_d
    /// (as above) and the volumetric rest, κ = λ − λ_d, acts on the patch volume ratio of
    /// each vertex: Σ_a V_a κ_a/2 (J_a − 1)², J_a = Σ_{t∋a} V_t J_t / Σ_{t∋a} V_t, V_a and κ_a
    /// the patch's quarter-volume sums (problems/term_elastic_nodal.c). The elastic term
    /// adds it; eo_element_evaluate gives the tets' part only.
    EO_ELEMENT_NODAL_DILATATION = 4
};

typedef struct eo_element_type {
    eo_method_info info;   ///< name, summary; params NULL
    int nodes;             ///< nodes per tet: 4 or 10
    unsigned flags;        ///< EO_ELEMENT_*
    /// Energy quadrature: nq points (barycentric λ₀..λ₃, 4 each), weights summing to 1
    /// (fractions of the rest volume), and the polynomial degree the rule integrates exactly.
    int nq;
    const double *qp;
    const double *qw;
    int degree;
    /// N_a(λ) (nodes) and ∂N_a/∂λ_j (nodes × 4, row a) at barycentric λ; either may be NULL.
    void (*shape)(const double lambda[4], double *N, double *dN);
    /// Consistent mass / (ρV) (nodes × nodes, row-major, exact), lumped mass / (ρV) (nodes,
    /// positive, summing to 1) and ∫N_a dV / V (nodes, summing to 1).
    const double *mass;
    const double *lumped;
    const double *load;
} eo_element_type;

/// The built-in elements: the linear tet, the 10-node quadratic tet, its mean-dilatation
/// mixed form (P2–P0) and the average-nodal-pressure linear tet.
EO_API extern const eo_element_type eo_element_p1, eo_element_p2, eo_element_p2p0, eo_element_p1anp;

/// The coefficients of the deviatoric-leaning part ψ_d of a mean-dilatation element: μ
/// kept, λ_d = min(λ, μ) (E and ν recomputed to match); *kappa = λ − λ_d.
EO_API eo_material_coef eo_element_split_coef(const eo_material_coef *c, double *kappa);

/// Energy Σ_q w_q V (ψ(F_q)), and as asked its gradient (3·nodes) and Hessian
/// ((3·nodes)², row-major; each point's ∂P/∂F projected with `proj`), at the element's
/// node coordinates x (3·nodes, node-major, in the element's node order), F_q = Σ_a x_a ⊗ ∇N_a(λ_q).
/// Dminv, V: the corner tet's rest data (eo_tet_rest). *minJ (may be NULL): the smallest
/// det F over the points. Barrier models: energy +INFINITY (grad, hess zero) when a point
/// has eo_tet_is_inverted(J). Outputs beyond `what` are not written; with what =
/// EO_EVAL_HESS, grad may be NULL (the Hessian alone: isotropic models then take the
/// analytic-mode path, eo_material_hessian_nodes, without forming ∂P/∂F). Never allocates.
/// Returns EO_OK or EO_ERR_UNSUPPORTED (an edge model).
EO_API int eo_element_evaluate(const eo_element_type *el, const eo_material_type *mt, const eo_material_coef *c,
                               const double Dminv[9], double V, const double *x, eo_eval_what what, eo_proj proj,
                               double *energy, double *grad, double *hess, double *minJ);

/// Physical shape gradients ∇N_a (nodes × 3, row a) at barycentric λ of the tet with rest
/// data Dminv.
EO_API void eo_element_grad(const eo_element_type *el, const double Dminv[9], const double lambda[4], double *G);

#ifdef __cplusplus
}
#endif
#endif
