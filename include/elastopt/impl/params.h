/// @file impl/params.h
/// The parameter structs of the built-in methods (config `solver.<name>.*`), for code
/// that fills them directly (a method's own file, tests); a configuration sets them
/// through the JSON config and each method's descriptor (elastopt help <name>).
#ifndef ELASTOPT_IMPL_PARAMS_H
#define ELASTOPT_IMPL_PARAMS_H

#include "../export.h"
#include "../params.h"

#ifdef __cplusplus
extern "C" {
#endif


/// Parameters of the c·I shift (config `solver.shift.*`, also `solver.clamp.*` and
/// `solver.abs.*` for their safeguard). Scale s = mean |H_ii| (1 if that is 0).
typedef struct eo_hessfix_shift_params {
    double shift_init;   ///< first non-zero shift, relative to s (default 1e-8)
    double shift_grow;   ///< factor on each retry: c = max(c_min, grow·c) (default 10)
    double shift_shrink; ///< after a success the next iteration starts at c/shrink,
                         ///< or at 0 when that is below c_min (default 10)
    double shift_max;    ///< give up (EO_DIVERGED_NOT_PD) above this, relative to s (1e12)
} eo_hessfix_shift_params;
/// Descriptor of eo_hessfix_shift_params (shared by shift, clamp, abs).
EO_API extern const eo_param_desc eo_hessfix_shift_params_desc[];

/// project_on_demand (config `solver.project_on_demand.*`): the shift safeguard of the
/// projected retry (same keys as solver.shift.*).
/// progressive (config `solver.progressive.*`).
typedef struct eo_hessfix_progressive_params {
    eo_hessfix_shift_params shift; ///< safeguard once every element is projected
    double delta_init;   ///< first residual threshold, relative to max_e r_e (default 0.5)
    double delta_shrink; ///< threshold factor on each detected indefiniteness (0.5)
    int max_rounds;      ///< growth rounds per direction before projecting all (20)
} eo_hessfix_progressive_params;

/// trust_region_filter (config `solver.trust_region_filter.*`).
typedef struct eo_hessfix_trust_region_filter_params {
    eo_hessfix_shift_params shift; ///< safeguard (as clamp/abs)
    double threshold;    ///< clamp when |ρ − 1| < threshold, else abs (default 0.01)
    int exact_model;     ///< ρ with the true Hessian (the paper; one extra assembly per
                         ///< iteration) or with the factored one (default true)
} eo_hessfix_trust_region_filter_params;

/// Newton (config `solver.newton.*`).
///
/// Inexact Newton: with an iterative solver.linear (cg, pcg, gmres) the direction solve
/// H̃p = −∇g stops at ‖H̃p + ∇g‖ ≤ η_k‖∇g‖, η_k set by `forcing` through
/// eo_linsolve_set_rtol before each direction (direct solvers ignore it):
///   none      the linear solver's own `tol` (default)
///   constant  η_k = eta
///   ew1       Eisenstat–Walker choice 1: η_k = |‖∇g_k‖ − ‖∇g_{k−1} + αH̃_{k−1}p_{k−1}‖| / ‖∇g_{k−1}‖,
///             safeguard η_k ≥ η_{k−1}^φ (φ = (1+√5)/2) when that is > 0.1
///   ew2       Eisenstat–Walker choice 2: η_k = ew_gamma (‖∇g_k‖/‖∇g_{k−1}‖)^ew_alpha,
///             safeguard η_k ≥ ew_gamma η_{k−1}^ew_alpha when that is > 0.1
/// η_0 = eta, then η_k ∈ [eta_min, eta_max] (Eisenstat & Walker 1996; solvers/optim/forcing.c).
typedef struct eo_newton_params {
    double descent_eps;  ///< p is a descent direction iff ∇gᵀp < −eps‖∇g‖‖p‖ (1e-12)
    char forcing[16];    ///< "none", "constant", "ew1", "ew2" (default "none")
    double eta;          ///< constant: η_k; ew1/ew2: η_0 (default 0.5)
    double ew_gamma;     ///< ew2: γ ∈ (0, 1] (default 0.9)
    double ew_alpha;     ///< ew2: α ∈ (1, 2] (default 2)
    double eta_max;      ///< upper bound of η_k (default 0.9)
    double eta_min;      ///< lower bound of η_k (default 1e-12)
    double estimate_gate; ///< decrement-estimate gate (solvers/optim/newton.c): at x_k (k ≥ 2)
                          ///< the estimate solve is skipped unless the stopping rule passes
                          ///< with a decrement between d_{k−1}³/d_{k−2}² / estimate_gate
                          ///< (quadratic progress, with this safety factor) and d_{k−1} (no
                          ///< progress: a plateau rule); d = exact λ²/2 of the last
                          ///< directions. 0 = always try (default 10)
} eo_newton_params;

/// Trust-region Newton with Steihaug–Toint CG (config `solver.newton_tr.*`;
/// solvers/optim/newton_tr.c has the algorithm).
typedef struct eo_newton_tr_params {
    char hessian[16];    ///< model Hessian: "true" (unprojected) or "fix" (per-element
                         ///< projection of solver.hessian_fix) (default "true")
    char precond[16];    ///< "none" (M = I) or "jacobi" (M = diag|H_ii|): CG preconditioner
                         ///< and trust-region norm √(pᵀMp) (default "none")
    double delta0;       ///< first radius in that norm (m for none); 0 = the first inner
                         ///< solve is unconstrained (default 0)
    double delta_max;    ///< largest radius, 0 = none (0)
    double eta;          ///< accept when ρ = actual/predicted reduction > eta (1e-4)
    double rho_low;      ///< Δ ← shrink·‖p‖ when ρ < rho_low (0.25)
    double rho_high;     ///< Δ ← grow·Δ when ρ > rho_high on the boundary (0.75)
    double shrink;       ///< (0.25)
    double grow;         ///< (2)
    char forcing[16];    ///< CG tolerance η_k = min(cg_rtol_max, ‖∇g‖/‖∇g₀‖) "quadratic"
                         ///< or its square root "superlinear" (default "quadratic")
    double cg_rtol_max;  ///< largest η_k (0.5)
    int cg_max_iters;    ///< CG iterations per inner solve, 0 = n (0)
    int max_rejects;     ///< rejected trial steps in a row before diverged_linesearch (50)
    double noise;        ///< where |g(x+p) − g(x)| ≤ noise·|g(x)| the actual reduction is
                         ///< −½(∇g(x) + ∇g(x+p))ᵀp (1e-10)
} eo_newton_tr_params;

/// Gradient descent (config `solver.gradient_descent.*`).
typedef struct eo_gradient_descent_params {
    int scaled;          ///< p = −D⁻¹∇g with D = objective metric (lumped mass) (true)
    char alpha0[16];     ///< first trial step after the first iteration: "bb" (Barzilai–
                         ///< Borwein, α₀ = sᵀDs/sᵀy) or "double" (2·α_prev) (default "bb")
} eo_gradient_descent_params;

/// L-BFGS (config `solver.lbfgs.*`).
typedef struct eo_lbfgs_params {
    int history;         ///< stored pairs m (default 8)
    char h0[16];         ///< initial inverse Hessian: "scaled_identity" (γI), "lumped_mass"
                         ///< (γD⁻¹, D = objective metric), "pd" (L⁻¹, L the objective's
                         ///< constant_hessian factored once, pd_factor.h) or "auto" (pd where
                         ///< the objective has constant_hessian, else lumped_mass) (default auto)
} eo_lbfgs_params;

/// Blended cured quasi-Newton, BCQN (config `solver.bcqn.*`; Zhu, Bridson & Kaufman 2018;
/// solvers/optim/bcqn.c has the algorithm): L-BFGS with H⁰ = L⁻¹ (the objective's
/// constant matrix, the Sobolev proxy) and each stored y blended toward L s.
typedef struct eo_bcqn_params {
    int history;         ///< stored (s, y) pairs m (default 5, the paper's)
    char blend[16];      ///< "adaptive" (the paper's β, eq. 13), "sobolev" (β = 1: the
                         ///< preconditioned gradient p = −L⁻¹∇g), "lbfgs" (β = 0: L-BFGS with
                         ///< H⁰ = L⁻¹) or "fixed" (β = beta) (default adaptive)
    double beta;         ///< fixed: the blend weight β ∈ [0, 1] (default 0.5)
    double blend_scale;  ///< adaptive: factor on the paper's β before the clamp (default 1)
} eo_bcqn_params;

/// Nonlinear conjugate gradients (config `solver.ncg.*`).
typedef struct eo_ncg_params {
    char beta[16];       ///< "pr_plus" (Polak–Ribière+), "fr" (Fletcher–Reeves), "hz"
                         ///< (Hager–Zhang) (default pr_plus)
    char precond[16];    ///< "none", "lumped_mass" (D⁻¹), "pd" (L⁻¹) or "auto" (pd where the
                         ///< objective has constant_hessian, else lumped_mass) (default auto)
    int restart;         ///< restart with p = −P⁻¹∇g every `restart` iterations, 0 = every
                         ///< n (number of variables) (default 0)
    double powell;       ///< restart when |∇gₖᵀP⁻¹∇gₖ₋₁| ≥ powell·∇gₖᵀP⁻¹∇gₖ, 0 = never (0.2)
} eo_ncg_params;

/// Fixed-point iteration of the implicit step (config `solver.fixed_point.*`).
typedef struct eo_fixed_point_params {
    char init[16];       ///< first iterate: "previous" (xₙ), "predictor" (x̃ = xₙ + h vₙ, the
                         ///< explicit Euler position) or "guess" (the x passed in) (previous)
    int window;          ///< contraction ratio ρ = (‖Δₖ‖/‖Δₖ₋ₘ‖)^(1/m) over m = window
                         ///< updates; ρ ≥ 1 → EO_DIVERGED_NOT_CONTRACTING (default 3)
} eo_fixed_point_params;

/// Wolfe line search (config `solver.wolfe.*`).
typedef struct eo_wolfe_params {
    double c1;           ///< sufficient decrease constant (1e-4)
    double c2;           ///< curvature constant |φ'(α)| ≤ c2|φ'(0)|, c1 < c2 < 1; 0 = the
                         ///< optimizer's preference (lbfgs 0.9, ncg 0.1), else 0.9 (0)
    int max_evals;       ///< trials (value+gradient each) before giving up (40)
    double noise;        ///< relative resolution of g: values within noise·|g(x)| of each
                         ///< other are equal and the approximate Wolfe test (Hager–Zhang)
                         ///< on φ' decides (1e-10)
} eo_wolfe_params;

/// Projective dynamics / its quasi-Newton form (config `solver.projective_dynamics.*`).
typedef struct eo_projective_dynamics_params {
    int lbfgs_history;   ///< 0: p = −L⁻¹∇g (PD local/global iteration as a descent method);
                         ///< m > 0: L-BFGS with m pairs and L as initial Hessian (Liu et al.
                         ///< 2017) (default 0)
} eo_projective_dynamics_params;

/// Projective dynamics, local/global solver (config `solver.pd_local_global.*`; Bouaziz
/// et al. 2014). Minimizes the step objective of PD constraint energies (materials
/// pd_arap, pd_strain_limit, pd_volume; springs) with the objective's constant matrix.
typedef struct eo_pd_local_global_params {
    int anderson;        ///< Anderson acceleration of the local/global map, with the energy
                         ///< safeguard of Peng et al. 2018 (default false)
    int window;          ///< Anderson window m, differences kept (default 5, range [1, 100])
    /// Chebyshev semi-iterative acceleration of the local/global map (Wang 2015; not with
    /// anderson): x⁺ = ω(γ(G(x) − x) + x − x₋₁) + x₋₁ after `delay` plain iterations,
    /// restarted when g rises (default false)
    int chebyshev;
    double rho;          ///< its spectral radius estimate, [0, 1); 0 = measured from the
                         ///< plain iterations of the delay (default 0)
    int delay;           ///< S, plain iterations before the acceleration (default 10)
    double gamma;        ///< under-relaxation γ, (0, 1] (default 1)
} eo_pd_local_global_params;

/// Backtracking (config `solver.backtracking.*`).
typedef struct eo_backtracking_params {
    double c1;           ///< Armijo constant (1e-4)
    double shrink;       ///< α ← shrink·α after a rejected trial (0.5)
    int max_evals;       ///< trials before giving up (60)
} eo_backtracking_params;

/// Barrier-aware line-search filter (config `solver.barrier_filter.*`; BCQN §5): the first
/// trial is min(α₀, safety·α_max), α_max the step at which the first un-inverted element
/// inverts (objective op max_step), then Armijo backtracking. The first three fields are
/// laid out as eo_backtracking_params.
typedef struct eo_barrier_filter_params {
    double c1;           ///< Armijo constant (0.2, the authors' code)
    double shrink;       ///< α ← shrink·α after a rejected trial (0.5)
    int max_evals;       ///< trials before giving up (60)
    double safety;       ///< first trial at most safety·α_max, in (0, 1) (0.5, the authors' code)
} eo_barrier_filter_params;

/// Non-monotone backtracking (config `solver.nonmonotone.*`): Armijo against a reference
/// R ≥ g(x_k) from the earlier iterates' values (eo_ls_extra.g_hist).
typedef struct eo_nonmonotone_params {
    double c1;           ///< sufficient decrease constant (1e-4)
    double shrink;       ///< α ← shrink·α after a rejected trial (0.5)
    int max_evals;       ///< trials before giving up (60)
    char reference[16];  ///< "max" (Grippo–Lampariello–Lucidi: max of the last memory+1
                         ///< values) or "average" (Zhang–Hager C_k) (default "max")
    int memory;          ///< max: M earlier values (10)
    double eta;          ///< average: Zhang–Hager weight η (0.85)
} eo_nonmonotone_params;

/// Exact line search (config `solver.exact.*`).
typedef struct eo_exact_params {
    double tol;          ///< stop when |φ'(α)| ≤ tol·|φ'(0)| or the bracket is narrower
                         ///< than tol·α (1e-8)
    int max_evals;       ///< evaluations before giving up (100)
} eo_exact_params;

/// Relative decrement stopping rule, the default (config `solver.relative_decrement.*`):
/// converged when λ_k ≤ tol·λ_0 (λ² = −∇gᵀp, λ_0 of the first direction), or at the
/// rounding floor: λ_k²/2 ≤ plateau·|g| and λ_k² > λ_{k−1}²/4.
typedef struct eo_stop_relative_decrement_params {
    double plateau;      ///< level of λ²/2, relative to |g|, below which a decrement that
                         ///< stopped falling counts as converged (1e-16)
} eo_stop_relative_decrement_params;

/// Characteristic gradient stopping rule (config `solver.characteristic_gradient.*`):
/// ‖∇g‖₂ ≤ tol·g_c (BCQN §7).
typedef struct eo_stop_characteristic_gradient_params {
    double scale;        ///< factor on g_c (default 1)
} eo_stop_characteristic_gradient_params;

/// Gradient stopping rule (config `solver.gradient.*`).
typedef struct eo_stop_gradient_params {
    double floor;        ///< lower bound of the scale ‖∇g(x₀)‖, units of ∇g (1e-300)
} eo_stop_gradient_params;

#ifdef __cplusplus
}
#endif
#endif
