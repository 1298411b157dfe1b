/// @file material.h
/// Hyperelastic materials: ψ(F), P = ∂ψ/∂F, ∂P/∂F and its PSD projection.
///
/// Conventions: F is 3×3 stored row-major, F[3*i+j] = F_ij. P likewise.
/// dPdF[(3*i+j)*9 + (3*k+l)] = ∂P_ij/∂F_kl (symmetric 9×9).
///
/// Isotropic models are written in signed singular values (F = U Σ Vᵀ, U, V ∈ SO(3),
/// σ1 ≥ σ2 ≥ |σ3|, σ3 < 0 when det F < 0): the model gives ψ(σ), ψ_i = ∂ψ/∂σ_i,
/// ∂²ψ/∂σ² and, for each pair (i,j), the two divided differences
///     twist_ij = (ψ_i − ψ_j)/(σ_i − σ_j),   flip_ij = (ψ_i + ψ_j)/(σ_i + σ_j)
/// in closed form (exact at repeated σ). From these the shared kernel (materials/
/// kernel.c) builds P = U diag(ψ_i) Vᵀ and the analytic eigensystem of ∂P/∂F
/// (Smith, de Goes & Kim 2019; Teran et al. 2005):
///   - 3 scaling modes U diag(w_m) Vᵀ, (ν_m, w_m) the eigenpairs of the 3×3 ∂²ψ/∂σ²;
///   - per pair the SYMMETRIC mode U (e_i e_jᵀ + e_j e_iᵀ) Vᵀ/√2 with eigenvalue twist_ij
///     and the ANTISYMMETRIC mode U (e_i e_jᵀ − e_j e_iᵀ) Vᵀ/√2 with eigenvalue flip_ij.
/// (The field names follow the formulas above. Smith et al. call the antisymmetric mode
/// "twist" and the symmetric one "flip"; the pairing used here is the one that passes the
/// finite-difference tests: perturbing F along U K Vᵀ with K antisymmetric rotates U and
/// V in opposite senses, which gives (ψ_i + ψ_j)/(σ_i + σ_j).)
/// Clamping or taking absolute values of these nine eigenvalues gives the PSD
/// projection with no numeric eigensolver. A model that is not rotation invariant
/// (`linear`) supplies F-space ops instead; its Hessian is constant and PSD, so every
/// projection is the identity for it.
///
/// ```c
/// const eo_material_type *mt; eo_registry_find(ctx, EO_KIND_MATERIAL, "stvk", (const void **)&mt);
/// eo_material_coef c = eo_material_coef_from(1e5, 0.45, 1000, 0);
/// eo_material_eval out;
/// eo_material_evaluate(mt, &c, F, EO_EVAL_HESS, EO_PROJ_CLAMP, &out);
/// ```
#ifndef ELASTOPT_MATERIAL_H
#define ELASTOPT_MATERIAL_H

#include "export.h"
#include "registry.h"
#include "proj.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Coefficients shared by all models (from material.E, material.nu, material.density,
/// material.k). μ = E/(2(1+ν)), λ = Eν/((1+ν)(1−2ν)).
typedef struct eo_material_coef {
    double E, nu, mu, lambda;
    double density;  ///< kg/m³
    double k;        ///< spring stiffness (N/m), springs only
    double pd_min, pd_max; ///< bounds of a PD constraint (pd_strain_limit: singular values,
                           ///< pd_volume: det F); 1, 1 from eo_material_coef_from
} eo_material_coef;

EO_API eo_material_coef eo_material_coef_from(double E, double nu, double density, double k);

/// The `material` config section (and each entry of a per-region material list).
typedef struct eo_material_opts {
    char model[32];   ///< registry name. Default "stable_neo_hookean".
    double E;         ///< Young's modulus, Pa. Default 1e5; range (0, inf).
    double nu;        ///< Poisson ratio. Default 0.45; range (-1, 0.5).
    double density;   ///< kg/m³. Default 1000; range (0, inf).
    double k;         ///< spring stiffness, N/m (spring model). Default 1000; range (0, inf).
    double pd_min;    ///< lower bound of the PD constraint: singular values (pd_strain_limit)
                      ///< or det F (pd_volume). Default 1; range (0, inf).
    double pd_max;    ///< upper bound, >= pd_min. Default 1; range (0, inf).
} eo_material_opts;
/// Descriptor table of eo_material_opts (keys model, E, nu, density, k, pd_min, pd_max).
EO_API extern const eo_param_desc eo_material_opts_desc[];
/// Coefficients from options.
EO_API eo_material_coef eo_material_coef_from_opts(const eo_material_opts *o);

/// Values of ψ(σ) and its derivatives in singular-value space.
typedef struct eo_sigma_eval {
    double psi;        ///< ψ(σ); +INFINITY where undefined (e.g. neo_hookean at J <= 0)
    double g[3];       ///< ∂ψ/∂σ_i
    double H[9];       ///< ∂²ψ/∂σ_i∂σ_j (row-major 3×3)
    double twist[3];   ///< pairs (0,1),(0,2),(1,2): (ψ_i − ψ_j)/(σ_i − σ_j), exact at σ_i = σ_j
    double flip[3];    ///< same pairs: (ψ_i + ψ_j)/(σ_i + σ_j); models singular at
                       ///< σ_i + σ_j = 0 (corotated kinds) guard the denominator
} eo_sigma_eval;

typedef enum eo_eval_what {
    EO_EVAL_ENERGY = 0,  ///< ψ only
    EO_EVAL_GRAD = 1,    ///< ψ and P
    EO_EVAL_HESS = 2     ///< ψ, P and ∂P/∂F
} eo_eval_what;


enum {
    EO_MATERIAL_INVERSION_SAFE = 1,  ///< finite and smooth through J <= 0
    EO_MATERIAL_EDGE = 2,            ///< a 2-node (spring) model, not a tet model
    EO_MATERIAL_BARRIER = 4,         ///< ψ = +∞ at J <= 0 (optimizers must backtrack)
    EO_MATERIAL_NO_VOLUME = 8        ///< linearizes to linear elasticity with λ = 0 (no
                                     ///< volume term: pd_arap, pd_strain_limit at bounds 1, 1)
};

typedef struct eo_material_type {
    eo_method_info info;  ///< name, summary; params NULL (coefficients are shared)
    unsigned flags;       ///< EO_MATERIAL_*
    /// Isotropic models: fill `out` up to `what` at signed singular values s (σ1 ≥ σ2 ≥ |σ3|,
    /// σ3 < 0 for inverted). NULL for F-space models.
    void (*sigma_eval)(const eo_material_coef *c, const double s[3], eo_eval_what what,
                       eo_sigma_eval *out);
    /// F-space models (not rotation invariant): ψ, P (9) and dPdF (81) at F. Outputs
    /// beyond `what` may be NULL. NULL for isotropic models.
    double (*F_eval)(const eo_material_coef *c, const double F[9], eo_eval_what what,
                     double P[9], double dPdF[81]);
    /// Optional fast path (isotropic and F-space models): ψ and, when P is not NULL,
    /// P = ∂ψ/∂F directly from F (invariants I_C = tr FᵀF, J, cofactor ∂J/∂F = J F⁻ᵀ;
    /// the corotated kinds a polar decomposition eo_polar3), with no SVD. J is det F as
    /// the kernel computed it (eo_det3); barrier models are never called where
    /// eo_tet_is_inverted(J). eo_tet_evaluate and eo_material_evaluate use it for
    /// EO_EVAL_ENERGY and EO_EVAL_GRAD; the SVD path (sigma_eval) serves EO_EVAL_HESS
    /// and eo_material_evaluate_svd. Both agree to ~1e-12 relative (tests/test_materials.c).
    double (*F_psi_grad)(const eo_material_coef *c, const double F[9], double J, double P[9]);
    /// Edge models: energy of a spring of rest length L between points a and b;
    /// gradient (6: d/da, d/db) and Hessian (36) as asked, projected as told.
    double (*edge_eval)(const eo_material_coef *c, double L, const double a[3],
                        const double b[3], eo_eval_what what, eo_proj proj, double grad[6],
                        double hess[36]);
    /// Optional, isotropic tet models that are projective-dynamics constraint energies
    /// (ψ = Σ_c (w_c/2)‖F − proj_c(F)‖², Bouaziz et al. 2014): the total weight Σ_c w_c
    /// per unit rest volume (Pa), i.e. the element block V·(Σ w_c)·GᵀG of the PD global
    /// matrix (problems/pd_matrix.c). NULL: the matrix takes the mean rest stiffness
    /// ∂²ψ/∂F_ii² at F = I (λ + 2μ for the classical models).
    double (*pd_weight)(const eo_material_coef *c);
} eo_material_type;

/// det F, the one way J is computed everywhere (kernel, barrier, inverted counts):
/// cofactor expansion along the first row, F row-major.
static inline double eo_det3(const double F[9])
{
    return F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
           F[2] * (F[3] * F[7] - F[4] * F[6]);
}
/// The inversion rule, used by every caller: an element is inverted iff J <= 0 (or J is
/// NaN), J = eo_det3(F) with F = Ds Dm⁻¹ from eo_tet_F. Barrier models (neo_hookean) have
/// ψ = +∞ exactly where this holds, in every evaluation path.
static inline int eo_tet_is_inverted(double J) { return !(J > 0); }

/// Result of a full evaluation at F.
typedef struct eo_material_eval {
    double psi;
    double P[9];
    double dPdF[81];    ///< projected as asked
    double sigma[3];    ///< signed singular values (σ3 < 0 when inverted)
    double U[9], V[9];  ///< rotations, F = U diag(σ) Vᵀ (row-major)
    double J;           ///< det F
    double eig[9];      ///< the nine eigenvalues of the unprojected ∂P/∂F for isotropic
                        ///< models: 3 scaling, 3 twist (pairs 01,02,12), 3 flip; for
                        ///< `linear` its constant eigenvalues; 0 for barrier at J <= 0
} eo_material_eval;

/// Evaluate ψ, P and ∂P/∂F at F with projection `proj`. Outputs beyond `what` are left
/// zero; sigma, U, V and J (= eo_det3(F)) are always filled. ψ and P come from the
/// model's F_psi_grad when it has one and what < EO_EVAL_HESS, else from the SVD path.
/// Returns EO_OK, or EO_ERR_UNSUPPORTED for an edge (spring) model. ψ is +INFINITY for
/// barrier models where eo_tet_is_inverted(J) (then P, dPdF are zero). Never allocates.
EO_API int eo_material_evaluate(const eo_material_type *mt, const eo_material_coef *c,
                         const double F[9], eo_eval_what what, eo_proj proj,
                         eo_material_eval *out);

/// The same evaluation with ψ and P always taken from the SVD path (signed singular
/// values, sigma_eval), never from F_psi_grad: the reference the fast path is tested
/// against. Same outputs and return values as eo_material_evaluate.
EO_API int eo_material_evaluate_svd(const eo_material_type *mt, const eo_material_coef *c,
                                    const double F[9], eo_eval_what what, eo_proj proj,
                                    eo_material_eval *out);

/// Rotation R ∈ SO(3) (row-major) of the polar decomposition F = R S consistent with the
/// signed SVD: R = U Vᵀ for F = U diag(σ) Vᵀ, U, V ∈ SO(3), σ3 < 0 when det F < 0, i.e.
/// the maximizer of tr(RᵀF) over SO(3). Newton's method on SO(3) with an exact line
/// search along each direction (materials/polar3.c). Unique where σ2 + σ3 > 0.
/// Returns the number of iterations (for benchmarks); never allocates.
EO_API int eo_polar3(const double F[9], double R[9]);

/// Proximal operator of a tet model: z = argmin_z ψ(z) + (k/2)‖z − v‖²_F (k > 0, Pa),
/// the local step of ADMM splittings (solvers/optim/admm_pd.c). Isotropic models: Newton
/// on the three signed singular values (z shares v's singular vectors); F-space models:
/// Newton on the 9 entries of z with the clamped ∂P/∂F + kI, from the better of the given
/// z and v; Armijo backtracking (materials/prox.c). z out: the minimizer. Converged when
/// ‖P(z) + k(z − v)‖ ≤ tol·k·max(1, ‖v‖) within max_iters Newton iterations (*iters, may
/// be NULL). Returns EO_OK, EO_WARN_NOT_CONVERGED (z is the best iterate),
/// EO_ERR_UNSUPPORTED for an edge model, EO_ERR_INVALID for k ≤ 0, EO_ERR_NONFINITE
/// when ψ is +∞ at both z and v. Never allocates.
EO_API int eo_material_prox(const eo_material_type *mt, const eo_material_coef *c, const double v[9],
                            double k, int max_iters, double tol, double z[9], int *iters);

/// SVD of a 3×3 F (row-major): the hot-path version (one-sided Jacobi on the columns
/// of F, relative accuracy for small σ; U completed by cross products when F is rank
/// deficient) and the LAPACKE dgesvd reference. Both return U, V ∈ SO(3) (row-major)
/// and signed σ sorted σ1 ≥ σ2 ≥ |σ3| with the sign of det F on σ3.
/// eo_svd3_lapack returns EO_OK or EO_ERR_INTERNAL if dgesvd fails.
EO_API void eo_svd3(const double F[9], double U[9], double s[3], double V[9]);
EO_API int eo_svd3_lapack(const double F[9], double U[9], double s[3], double V[9]);

/// Per-tet element kernel. Precomputed from rest positions: Dm⁻¹ (row-major) and rest
/// volume w. Given the 12 current coordinates x (vertex-major), computes F = Ds Dm⁻¹,
/// energy w·ψ, and as asked the 12-gradient and 12×12 Hessian (row-major), projected.
/// Convention (notes §4.2–4.3): Ds columns x_i − x_4 (local vertices 0,1,2 minus 3), and
/// vec(F) = (Dm⁻ᵀ S ⊗ I3) x. Energy w·ψ, gradient w·(∂F/∂x)ᵀ P, Hessian
/// w·(∂F/∂x)ᵀ ∂P/∂F (∂F/∂x), built from the nine analytic modes (no 12×12 eigensolve).
/// Energy and gradient (what < EO_EVAL_HESS) come from the model's F_psi_grad when it has
/// one (no SVD); EO_EVAL_HESS uses the SVD path for all three outputs.
/// Outputs beyond `what` are not written. Returns EO_OK, EO_ERR_UNSUPPORTED for an
/// edge model; energy +INFINITY (grad, hess zero) for barrier models where
/// eo_tet_is_inverted(J), J = eo_tet_J(Dminv, x).
typedef struct eo_tet_out {
    double energy;
    double grad[12];
    double hess[144];
    double J;
    double psi;
} eo_tet_out;
EO_API int eo_tet_evaluate(const eo_material_type *mt, const eo_material_coef *c,
                    const double Dminv[9], double w, const double x[12], eo_eval_what what,
                    eo_proj proj, eo_tet_out *out);
/// The Hessian alone: out->hess (and out->J, out->psi, out->energy) exactly as
/// eo_tet_evaluate(…, EO_EVAL_HESS, …) writes them, bit for bit, without the gradient
/// (out->grad is not written): the assembly loops need no P, and skipping it saves 5–9%
/// of the kernel for the isotropic models.
EO_API int eo_tet_hessian(const eo_material_type *mt, const eo_material_coef *c, const double Dminv[9],
                          double w, const double x[12], eo_proj proj, eo_tet_out *out);
/// One quadrature point's share of an element Hessian over n ≤ 10 nodes with shape
/// gradients G (n×3, row a = ∇N_a): H[(a i)][(b k)] += w Σ_jl G_aj ∂P_ij/∂F_kl G_bl on the
/// blocks b ≥ a of H ((3n)², row-major; the caller mirrors the rest), ∂P/∂F projected
/// with proj, built from the analytic modes in the U frame without forming ∂P/∂F (the
/// linear tet's eo_tet_hessian for n nodes). *psi = ψ(F), *J = det F; barrier models:
/// ψ = +∞ where eo_tet_is_inverted(J), H untouched. EO_ERR_UNSUPPORTED for models
/// without sigma_eval (F-space and edge models: use eo_material_evaluate). No allocation.
EO_API int eo_material_hessian_nodes(const eo_material_type *mt, const eo_material_coef *c, const double F[9], int n,
                                     const double *G, double w, eo_proj proj, double *H, double *psi, double *J);
/// F = Ds Dm⁻¹ of a tet from its 12 coordinates (vertex-major), exactly as the kernel
/// forms it, and its J = eo_det3(F): the inputs of eo_tet_is_inverted.
EO_API void eo_tet_F(const double Dminv[9], const double x[12], double F[9]);
EO_API double eo_tet_J(const double Dminv[9], const double x[12]);
/// Dm⁻¹ and rest volume w = |det Dm|/6 from 12 rest coordinates (vertex-major).
/// EO_ERR_MESH if |det Dm| <= 1e-12·(longest Dm column)³ (degenerate rest tet); Dminv
/// and w untouched then. Both orientations are accepted: F = Ds Dm⁻¹ is independent of
/// it, and the mesh layer orients tets so that det[x1−x0, x2−x0, x3−x0] > 0, which is
/// det Dm < 0 in the notes' Dm = [x1−x4, x2−x4, x3−x4] convention.
EO_API int eo_tet_rest(const double X[12], double Dminv[9], double *w);

#ifdef __cplusplus
}
#endif
#endif
