/// @file solver.h
/// Optimizers, Hessian fixes, line searches and stopping rules, each chosen by name.
///
/// The solver of one step problem is assembled from four pluggable pieces:
///   solver.optimizer   newton, newton_tr, gradient_descent, lbfgs, bcqn, ncg,
///                      projective_dynamics, pd_local_global, fixed_point, vbd,
///                      jacobi_chebyshev, admm_pd, aqp
///                                                               (eo_optimizer_type)
///   solver.hessian_fix none, shift, clamp, abs, project_on_demand,
///                      progressive, trust_region_filter         (eo_hessfix_type)
///   solver.linesearch  backtracking, nonmonotone, wolfe, exact, barrier_filter, none
///                                                               (eo_linesearch_type)
///   solver.stop        relative_decrement, newton_decrement, gradient,
///                      characteristic_gradient                  (eo_stop_type)
///   solver.linear      cholmod, cholmod_ldlt, ...               (eo_linsolve_type)
/// solver.linesearch defaults to `auto`: the optimizer's own choice
/// (eo_optimizer_type.linesearch): `wolfe` for lbfgs and ncg, `barrier_filter` for bcqn,
/// `backtracking` for newton,
/// gradient_descent and projective_dynamics (and for a plug-in that names none); the
/// solver echoes the resolved name. wolfe's curvature constant c2 then defaults to the
/// optimizer's preference (0.9 lbfgs, 0.1 ncg; eo_ls_extra.c2) and it hands back ∇g of
/// the accepted point (one value+gradient call per trial). Any registered line search
/// can still be named explicitly.
/// plus solver.tol, solver.max_iters, solver.time_budget (eo_solver_opts), and each
/// method's parameters live in config section `solver.<method name>` (e.g.
/// `solver.backtracking.c1`, `solver.shift.shift_init`, `solver.lbfgs.history`). Sections
/// of methods that are registered but not selected are read and checked too, so one
/// config may carry settings for several methods and switch with `-o solver.optimizer=...`.
///
/// ```c
/// eo_solver_opts o; eo_solver_opts_default(&o);
/// rc = eo_solver_opts_load(ctx, cfg, &o);                  // section "solver" (cfg may be NULL)
/// eo_solver *s; rc = eo_solver_create(ctx, &o, cfg, &s);     // + sections solver.<name>
/// eo_solve_result r;
/// rc = eo_solver_minimize(s, obj, x, on_iter, user, &r);   // x: start in, minimizer out
/// printf("%s after %d iterations\n", eo_reason_string(r.reason), r.iterations);
/// eo_solver_destroy(&s);
/// ```
/// Ownership: the solver copies opts and all params; the objective and x are borrowed
/// for the duration of minimize. A solver is created without knowing the problem size:
/// the optimizer's workspace is sized at the first minimize and again whenever obj->n
/// differs from the previous call (a released boundary set), so one solver serves every
/// step of a simulation. No allocation happens inside the iterations; the only exception
/// is Newton's first iteration on a Hessian whose pattern it has not seen
/// (eo_linsolve_analyze, once per pattern).
///
/// The convergence measure. Every optimizer tests its iterates through
/// eo_solver_stop_check, so `solver.tol` means the same accuracy whichever runs:
///  - progress is relative to the start x₀ of the minimization (each time step starts
///    one) and measured the same way for all: by the Newton decrement λ_k/λ_0
///    (λ² = −∇gᵀp = ‖p‖²_H) for optimizers whose direction is a Newton direction
///    (eo_optimizer_type.newton_decrement: newton), by the metric gradient norm
///    ‖∇g_k‖_{D⁻¹}/‖∇g_0‖_{D⁻¹} (D the objective's metric, the lumped mass) for every
///    other one. Both estimate ‖x_k − x*‖ relative to the step's motion ‖x_0 − x*‖; the
///    gradient ratio bounds it from above where H ≥ D (stiff modes weigh more), so a
///    first-order method is never declared converged further from x* than Newton.
///  - an absolute floor tied to the rounding level at x₀: λ²/2 (or ‖∇g‖²_{D⁻¹}/2) below
///    EO_STOP_FLOOR·ε²·s, s the objective's rounding scales (objective.h), is converged:
///    a step that starts at (or reaches) its minimizer, a body at rest, converges.
///  - no optimizer is declared converged without measuring its own progress: where no
///    first decrement exists the ratio is of gradients, never an absolute test.
/// The rules (solver.stop; tol = solver.tol, default 1e-10):
///  - relative_decrement (the default): the measure above ≤ tol; for Newton also
///    converged at the plateau, λ²/2 ≤ plateau·max(|g(x₀)|, |g|) (1e-16) with λ² no longer
///    falling (λ_k² > λ_{k−1}²/4), where g cannot resolve further progress. With
///    tol = 1e-10 the static StVK cantilever's tip is within 3.7e-11 and the dynamic
///    cantilever's after 50 steps within 2.3e-10 of the converged answer; at tol = 1e-8
///    newton, newton_tr, lbfgs, ncg, gradient_descent and projective_dynamics all end
///    within 4e-9 of the motion on the first cantilever step (tests/test_converge.c).
///    Linearly converging methods need many iterations for 1e-10: give them a looser tol.
///  - newton_decrement: λ²/2 = −∇gᵀp/2 ≤ tol, in the units of g (for the step objective
///    ½‖x − x̃‖²_M + w E, kg·m²). λ²/2 estimates g(x) − g*, so tol = 1e-10 means
///    ‖x − x*‖_H ≲ √(2·tol) ≈ 1.4e-5 m·√kg.
///  - gradient: ‖∇g‖₂ ≤ tol·max(‖∇g(x₀)‖₂, floor) (relative to the start of this
///    minimization).
///  - characteristic_gradient: ‖∇g‖₂ ≤ tol·g_c, g_c the objective's characteristic
///    gradient norm (objective.h, characteristic; Zhu, Bridson & Kaufman 2018): an
///    absolute test in the units of ∇g, independent of the start; the paper's tol is 1e-3.
///    Objectives without g_c: relative to ‖∇g(x₀)‖₂ as `gradient`.
#ifndef ELASTOPT_SOLVER_H
#define ELASTOPT_SOLVER_H

#include "config.h"
#include "export.h"
#include "linsolve.h"
#include "objective.h"

#ifdef __cplusplus
extern "C" {
#endif

/// What one iteration reports (to the CSV log and the benchmark recorder).
///
/// Record k describes the iterate x_k and what was done from it: g and ‖∇g‖ at x_k, the
/// direction computed at x_k (its decrement and the Hessian shift used for it) and the
/// line search from x_k along it (α, evaluations). The last record (reason ≠ 0) has
/// α = NAN and, if the run stopped before a direction was computed, decrement = NAN.
/// A callback that returns non-zero stops the run before the step of its record is
/// accepted (reason EO_DIVERGED_EXTERNAL; x out = that record's x_k).
typedef struct eo_iter_info {
    int iteration;        ///< 0 = the start point, then 1, 2, ...
    double time;          ///< seconds since the start of this minimization
    double g;             ///< objective at x_k
    double grad_norm;     ///< ‖∇g(x_k)‖₂
    double decrement;     ///< λ²/2 = −α₀∇gᵀp/2 of the direction computed at x_k (NAN if none)
    double alpha;         ///< step length accepted from x_k (NAN on the last record)
    int ls_evals;         ///< objective evaluations in the line search from x_k
    double shift;         ///< Hessian shift c used for the direction (0 if none)
    double projected;     ///< fraction of elements whose Hessian the Hessian fix projected
                          ///< for the direction (0 for optimizers without a fix)
    int inverted;         ///< inverted elements at x_k (-1 if unknown)
    int reason;           ///< reason if this is the last iteration, else 0
    const double *x;      ///< the iterate x_k (borrowed, valid during the callback)
    /// Inexact Newton (solver.newton.forcing ≠ none): forcing term η_k = relative inner
    /// tolerance given to the iterative linear solver for the direction (0 if none).
    double eta;
    int lin_iters;        ///< iterations of the last inner linear solve (0 direct/none)
    /// 1 if the inner CG met non-positive curvature pᵀHp ≤ 0 for this direction (the
    /// Hessian fix then used another system: `none` the clamp-projected one, `shift` a
    /// larger shift, ...); the offending CG direction is never used.
    int neg_curvature;
    /// CPU seconds of the calling thread since the start of this minimization
    /// (eo_cputime; filled by eo_solver_report like `time`).
    double cpu_time;
} eo_iter_info;

/// Callback after every iteration; return non-zero to stop (reason EO_DIVERGED_EXTERNAL).
typedef int (*eo_iter_fn)(const eo_iter_info *info, void *user);

/// Context given to a stopping rule.
typedef struct eo_stop_info {
    int iteration;
    double g, g_prev;     ///< current and previous objective (g_prev = NAN at first)
    double grad_norm;     ///< ‖∇g(x)‖₂
    double grad_norm0;    ///< ‖∇g(x₀)‖₂ at the start of this minimization
    double decrement;     ///< λ²/2 for the direction just computed at x (NAN if none)
    double decrement0;    ///< λ²/2 of the first direction of this minimization (NAN before
                          ///< it; 0 from optimizers that do not track it)
    double decrement_prev; ///< λ²/2 of the previous iteration's direction (NAN at first; 0
                          ///< from optimizers that do not track it)
    double step_norm;     ///< ‖α p‖₂ of the last step (NAN at first)
    double x_norm;        ///< ‖x‖₂
    double tol;           ///< solver.tol
    /// Filled by eo_solver_stop_check (0 / NAN from optimizers that call the rule
    /// directly, which then get the rules' legacy behaviour): see "The convergence
    /// measure" above.
    int measure;          ///< EO_MEASURE_DECREMENT, EO_MEASURE_GRADIENT or 0 (unknown)
    double g0;            ///< g(x₀) of this minimization
    double grad_metric;   ///< ‖∇g(x)‖_{D⁻¹}, D the objective's metric (identity if none)
    double grad_metric0;  ///< the same at x₀
    double floor_dec;     ///< rounding floor of λ²/2 at x₀, units of g (0: none)
    double floor_grad;    ///< rounding floor of ‖∇g‖²_{D⁻¹}/2 at x₀, units of g (0: none)
    double g_scale;       ///< the objective's rounding scale s[0] at x₀ (units of g; 0: none):
                          ///< ε·g_scale is the rounding level of g itself
    /// The objective's characteristic gradient norm g_c (objective.h, characteristic),
    /// read by eo_solver_stop_check at x₀; 0 if the objective has none (or the rule is
    /// called directly). Appended last: earlier fields keep their offsets.
    double grad_char;
} eo_stop_info;

/// Which measure of progress eo_stop_info carries (eo_stop_info.measure).
enum {
    EO_MEASURE_DECREMENT = 1, ///< λ² = −∇gᵀp with p from a Hessian of g (newton)
    EO_MEASURE_GRADIENT = 2   ///< ‖∇g‖_{D⁻¹} (every other optimizer)
};

/// Rounding floor of the stopping rules, in units of ε² (ε = DBL_EPSILON) times the
/// objective's rounding scale s (objective.h, rounding_scale): an iterate whose λ²/2 (or
/// ‖∇g‖²_{D⁻¹}/2) lies below EO_STOP_FLOOR·ε²·s is at what rounding alone produces at
/// the step's start, and converged. Measured at rest on the cantilever (E = 1e5…1e10,
/// ν = 0.3…0.4999): λ²/2 = 1e-3…2.4 ε²·s[0], ‖∇g‖²_{D⁻¹}/2 ≤ 0.2 ε²·s[1]; on that bar
/// the floor is a motion of ~1e-14 m.
#define EO_STOP_FLOOR 1e4

typedef struct eo_stop_type {
    eo_method_info info;
    /// Positive eo_reason if converged, 0 to go on. Called once after the gradient at
    /// each iterate (decrement = NAN) and, for rules with needs_direction, once more
    /// after the direction is known.
    int (*check)(const void *params, const eo_stop_info *si);
    int needs_direction;  ///< 1 if the rule needs the decrement (newton_decrement)
} eo_stop_type;

/// Optional inputs and outputs of one line search call (the `extra` argument of
/// eo_linesearch_type.search; NULL = none of them).
typedef struct eo_ls_extra {
    double *grad_new;    ///< in: n doubles for ∇g(xnew), or NULL if the caller does not want it
    int have_grad;       ///< out: 1 if grad_new holds ∇g at the returned xnew (exactly the
                         ///< gradient call that produced *gnew), 0 if the caller must evaluate it
    double c2;           ///< in: curvature constant the optimizer prefers (0 = no preference);
                         ///< used by wolfe when its own c2 is 0 (auto): 0.9 quasi-Newton, 0.1 CG
    /// in: g at the accepted iterates of this minimization, oldest first, the last one =
    /// g0 (at most EO_LS_HISTORY of them; NULL/0 = none), for non-monotone searches
    const double *g_hist;
    int n_hist;
    /// in: 1 if the caller expects the first trial to be accepted (the descent loop: the
    /// last search accepted its first trial). Value-only searches (backtracking,
    /// nonmonotone, none) then evaluate that trial with its gradient into grad_new: one
    /// gradient call instead of a value call plus, once accepted, a gradient call.
    int grad_first;
} eo_ls_extra;

/// Length of the history of g values the descent loop hands to the line search.
#define EO_LS_HISTORY 64

typedef struct eo_linesearch_type {
    eo_method_info info;
    /// Find α along p from x (g0 = g(x), dg0 = ∇g(x)ᵀp < 0). Writes the accepted point
    /// to xnew and g(xnew) to *gnew, the step to *alpha, objective evaluations (value
    /// or gradient calls) to *nevals. `work` is caller scratch of n doubles.
    /// A trial with non-finite g is never accepted. `alpha0` is the first trial.
    /// `extra` (may be NULL): searches that evaluate gradients (wolfe, exact) fill
    /// extra->grad_new with ∇g(xnew) and set extra->have_grad = 1, so the caller needs no
    /// further evaluation at the accepted point; the others set have_grad = 0.
    /// Returns EO_OK, a positive warning EO_WARN_NOT_CONVERGED when no acceptable step
    /// was found (then xnew/gnew hold the best point found, possibly x with *alpha = 0),
    /// or a negative status from the objective.
    int (*search)(const void *params, eo_objective *obj, const double *x, const double *p,
                  double g0, double dg0, double alpha0, double *xnew, double *gnew,
                  double *alpha, int *nevals, double *work, eo_ctx *ctx, eo_ls_extra *extra);
} eo_linesearch_type;

/// Hessian fix: how an optimizer that factors a Hessian (newton, projective_dynamics)
/// gets a positive-definite system. A fix is one file and one registry line; it owns
/// the whole algorithm (which projection to assemble with, whether to shift, retry or
/// fall back), the optimizer only supplies the matrix and uses the result.
///
/// Per minimization the optimizer calls `begin`, then per direction `factor` with an
/// eo_hessfix_env, and after each accepted step `accepted` (optional) with the line
/// search outcome. `factor` asks env->assemble for the system matrix at x with the
/// per-element projection it wants (uniform, or one eo_proj per element), modifies it
/// only in place (a c·I shift on the stored diagonal, restored before returning),
/// factors it with env->linear and, if env->want_direction, solves p = −H̃⁻¹∇g and
/// checks that p is a descent direction (∇gᵀp < −descent_eps·‖∇g‖‖p‖). The c·I shift
/// loop shared by shift, clamp, abs and the newer fixes is in solvers/hessfix/shift_loop.c.
///
/// ```c
/// // inside an optimizer's direction routine
/// eo_hessfix_env env = {.obj = obj, .linear = ls, .ctx = ctx, .x = x, .g = g, .grad = grad,
///                       .want_direction = 1, .descent_eps = 1e-12,
///                       .assemble = my_assemble, .user = me, .res = res};
/// eo_hessfix_out out;
/// rc = hf->factor(sc->hessfix_state, sc->hessfix_params, &env, p, &out);
/// if (rc < 0) return rc;             // error status
/// if (out.reason) ...                // no direction: EO_DIVERGED_NOT_PD, _LINSOLVE, ...
/// ```
/// Ownership: env and everything it points to are borrowed for the call; the state is
/// allocated by the solver (state_size bytes, zeroed), sized by `setup` once for n
/// variables; nothing is allocated inside `factor` (progressive sizes its element mask
/// in `begin`, when the objective's element count grows).

typedef struct eo_solve_result eo_solve_result;

/// Assemble the system matrix at env->x for a Hessian fix. proj_of NULL: every element
/// projected with `proj` (objective op hessian); else element e with proj_of[e] (op
/// hessian_masked, E = eo_objective_n_elements entries). The matrix returned in *A is
/// borrowed until the next call, has the upper-triangle CSC layout of sparse.h with the
/// diagonal stored last in each column, and has been analyzed by env->linear (the
/// callback analyzes a new pattern). An optimizer with a constant matrix
/// (projective_dynamics with the objective's constant_hessian) returns it whatever the
/// projection. Returns EO_OK or a negative status (an error ending the run); sets
/// *reason to a negative eo_reason (EO_DIVERGED_LINSOLVE, status in res) when no matrix
/// can be given (then *A is unspecified).
typedef int (*eo_hessfix_assemble_fn)(void *user, eo_proj proj, const unsigned char *proj_of,
                                      eo_csc **A, int *reason);

/// What a Hessian fix works on during one `factor` call (all borrowed).
typedef struct eo_hessfix_env {
    eo_objective *obj;        ///< the objective (per-element ops of objective.h)
    eo_linsolve *linear;      ///< holds the factors on return (out.factored)
    eo_ctx *ctx;
    int n;                    ///< variables
    const double *x;          ///< iterate (n)
    double g;                 ///< g(x)
    const double *grad;       ///< ∇g(x) (n)
    int want_direction;       ///< 1: solve for p and test descent; 0: factors only, for an
                              ///< optimizer that reuses them for many solves
                              ///< (projective_dynamics): p untouched, no descent test, and
                              ///< a fix must not fall back to −∇g (it shifts instead)
    double descent_eps;       ///< p is a descent direction iff ∇gᵀp < −eps‖∇g‖‖p‖
    eo_hessfix_assemble_fn assemble;
    void *user;               ///< passed to assemble
    eo_solve_result *res;     ///< counters n_factor, n_shifted, n_fallback; status on a
                              ///< linear-solver failure
} eo_hessfix_env;

/// What `factor` returns besides p.
typedef struct eo_hessfix_out {
    double shift;             ///< c of the factored H̃ = H_proj + cI (0 if none)
    double projected;         ///< fraction of the elements assembled with a projection
                              ///< (0 none, 1 all; clamp/abs report 1 also on objectives
                              ///< without per-element terms)
    int factored;             ///< 1: env->linear holds the factors of a PD H̃ and (with
                              ///< want_direction) p = −H̃⁻¹∇g; 0: p = −∇g fallback or none
    int reason;               ///< negative eo_reason if there is no direction / system:
                              ///< EO_DIVERGED_NOT_PD (shift above shift_max),
                              ///< EO_DIVERGED_LINSOLVE, EO_DIVERGED_NONFINITE; else 0
    int neg_curvature;        ///< 1 if an iterative inner solve (cg/pcg) met pᵀAp ≤ 0
                              ///< during this call (EO_WARN_NOT_PD from solve)
} eo_hessfix_out;

/// Line-search outcome of the step along the fix's last direction (hook `accepted`).
typedef struct eo_hessfix_step_info {
    double alpha;             ///< accepted step length along p
    double g_old, g_new;      ///< g(x_k), g(x_k + αp)
    double dg;                ///< ∇g(x_k)ᵀp (< 0)
    double actual;            ///< actual reduction g_old − g_new
    double predicted;         ///< reduction predicted by the factored model,
                              ///< −(α∇gᵀp + ½α²pᵀH̃p) = −α∇gᵀp(1 − α/2) since pᵀH̃p = −∇gᵀp
                              ///< (for the −∇g fallback the model is H̃ = I)
} eo_hessfix_step_info;

typedef struct eo_hessfix_type {
    eo_method_info info;
    size_t state_size;        ///< private state (zeroed by the solver), 0 if none
    /// Per-element projection for optimizers that correct the Hessian's inertia on their
    /// own and only ask for a projected Hessian (ipopt). newton and projective_dynamics
    /// never read it.
    eo_proj elem_proj;
    /// Optional: size workspace for n variables (once, before any begin).
    int (*setup)(void *st, const void *params, int n, eo_ctx *ctx);
    /// Optional: start of a minimization (env->x = x₀, env->g, env->grad given; no
    /// matrix assembled yet). Returns EO_OK or a negative status.
    int (*begin)(void *st, const void *params, const eo_hessfix_env *env);
    /// The factored positive-definite system at env->x and (want_direction) p (n).
    /// Returns EO_OK (see out->reason) or a negative status.
    int (*factor)(void *st, const void *params, const eo_hessfix_env *env, double *p,
                  eo_hessfix_out *out);
    /// Optional: the step along the last direction was accepted (newton calls it before
    /// the next `factor`, when g at the new point is known).
    void (*accepted)(void *st, const void *params, const eo_hessfix_step_info *info);
    /// Optional: free what setup/begin allocated (also after a failed setup).
    void (*destroy)(void *st, eo_ctx *ctx);
} eo_hessfix_type;

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

typedef struct eo_solver eo_solver;

/// Everything the solver needs to know about one minimization.
typedef struct eo_solver_ctx {
    eo_objective *obj;
    eo_ctx *ctx;
    eo_linsolve *linear;                ///< NULL for methods that do not solve systems
    const eo_hessfix_type *hessfix;
    const void *hessfix_params;         ///< the fix's params struct or NULL (= defaults)
    void *hessfix_state;                ///< the fix's state (set up for n); NULL if the fix has
                                        ///< none or the optimizer has needs_hessian = 0
    const eo_linesearch_type *linesearch;
    const void *linesearch_params;
    const eo_stop_type *stop;
    const void *stop_params;
    double tol;                         ///< solver.tol
    int max_iters;                      ///< solver.max_iters
    double time_budget;                 ///< seconds, 0 = none
    eo_iter_fn on_iter;
    void *user;
    /// The running optimizer's own ops table (the one eo_solver_create resolved), so one
    /// minimize function can serve several tables (callback.h: each table embedded in
    /// an object with its callbacks). Appended last: earlier fields keep their offsets.
    const struct eo_optimizer_type *optimizer;
    /// State of the convergence measure of this minimization (eo_solver_stop_check);
    /// owned by the solver, NULL in a context built by hand.
    struct eo_stop_state *stop_state;
} eo_solver_ctx;

/// The stopping test every optimizer calls at each iterate (instead of sc->stop->check):
/// fills the measure fields of *si (g₀, the metric gradient norms, the rounding floors
/// from the objective at the first call of the minimization, which must be at x₀ with
/// k = 0) from x and grad = ∇g(x) (grad NULL: the metric norm of the last call, at the
/// same iterate), then applies
/// the rounding floor and sc->stop. Returns the rule's positive eo_reason or 0.
EO_API int eo_solver_stop_check(const eo_solver_ctx *sc, eo_stop_info *si, const double *x, const double *grad);

/// Result of one minimization.
typedef struct eo_solve_result {
    int reason;           ///< eo_reason
    int iterations;       ///< accepted steps
    double g, grad_norm, decrement;  ///< at the returned x (decrement NAN if not computed)
    double time;          ///< seconds
    long n_value, n_gradient, n_hessian, n_factor;  ///< calls during this minimization
    int status;           ///< eo_status of the last library call (0 unless an error)
    long n_fallback;      ///< directions replaced by the (scaled) steepest descent one
                          ///< (newton + hessian_fix none; lbfgs memory resets; ncg
                          ///< restarts because p was not a descent direction)
    long n_shifted;       ///< newton iterations whose direction needed a shift c > 0
                          ///< (the fix for `shift`, the safeguard for clamp/abs)
    double projected;     ///< mean over the directions of this minimization of the
                          ///< fraction of elements projected (0 if none computed)
    long n_inner;         ///< inner iterations (newton_tr: CG iterations; else 0)
    long n_negcurv;       ///< newton_tr: inner solves that met negative curvature dᵀHd ≤ 0
                          ///< and stepped to the trust-region boundary along d (else 0)
    long lin_iters;       ///< newton: inner linear-solver iterations, summed (0 direct)
    long n_neg_curvature; ///< newton: directions whose inner CG met pᵀHp ≤ 0 (handled by
                          ///< the Hessian fix, see eo_iter_info.neg_curvature)
    /// Timers of this minimization (wall seconds) kept by the optimizers that know the
    /// phase (the descent loop, newton); 0 where not measured. Linear-solver times come
    /// from eo_linsolve_stats; eo_solver_get_profile adds both up.
    double t_assembly;    ///< Hessian assembly (objective hessian calls for directions)
    double t_linesearch;  ///< inside the line search, its objective evaluations included
    double t_gradient;    ///< gradient evaluations outside the line search
    long n_assembly, n_ls_evals, n_gradient_outside;  ///< the calls timed above
    int decrement_estimated;  ///< 1: stopped on the decrement estimated from the previous
                              ///< factor (newton + newton_decrement), `decrement` is that
                              ///< estimate; 0: from the direction at the returned x
    long n_not_pd;        ///< factorizations of the solver's linear solver that found the matrix
                          ///< not positive definite (EO_WARN_NOT_PD; for project_on_demand the
                          ///< directions that fell back to the projected Hessian), counted
                          ///< by eo_solver_minimize from eo_linsolve_stats.n_not_pd
    /// CPU seconds of the calling thread (eo_cputime) for the same spans: the whole
    /// minimization (set by eo_solver_minimize) and the timed phases above.
    double cpu_time;
    double c_assembly, c_linesearch, c_gradient;
} eo_solve_result;

/// Where a solver's time went: wall seconds (t_*), CPU seconds of the calling thread
/// (c_*, eo_cputime: the same spans) and counts accumulated over every
/// eo_solver_minimize since eo_solver_create or eo_solver_reset_profile (read with
/// eo_solver_get_profile). The parts do not overlap; eo_profile_other is the rest
/// (stopping tests, Hessian-fix bookkeeping, vector updates, callbacks).
typedef struct eo_profile {
    long minimizations;   ///< eo_solver_minimize calls
    long iterations;      ///< accepted steps
    double t_total;       ///< inside eo_solver_minimize
    double t_assembly;    ///< Hessian assembly (element kernels + scatter)
    double t_analyze;     ///< symbolic factorization (eo_linsolve_analyze)
    double t_factor;      ///< numeric factorization (eo_linsolve_factor)
    double t_solve;       ///< solves (eo_linsolve_solve)
    double t_linesearch;  ///< line searches, their value/gradient calls included
    double t_gradient;    ///< gradients outside the line search (start point, accepted point)
    long n_assembly, n_analyze, n_factor, n_solve, n_ls_evals, n_gradient;
    long n_not_pd;        ///< numeric factorizations that found the matrix not positive definite
    /// the t_* spans in CPU seconds of the calling thread (eo_cputime)
    double c_total, c_assembly, c_analyze, c_factor, c_solve, c_linesearch, c_gradient;
} eo_profile;

/// The solver's accumulated profile (borrowed, updated by every minimize).
EO_API const eo_profile *eo_solver_get_profile(const eo_solver *s);
/// Zero the accumulated profile.
EO_API void eo_solver_reset_profile(eo_solver *s);
/// out = a − b field by field (the profile of what happened between two snapshots).
EO_API void eo_profile_diff(const eo_profile *a, const eo_profile *b, eo_profile *out);
/// t_total minus the timed parts.
EO_API double eo_profile_other(const eo_profile *p);
/// The CPU view of a profile: *out = *p with every t_* replaced by its c_* (so that
/// eo_profile_other and eo_profile_iteration_ratio give CPU figures).
EO_API void eo_profile_cpu_view(const eo_profile *p, eo_profile *out);
/// Seconds per iteration over seconds per numeric factorization:
/// (t_total / iterations) / (t_factor / n_factor); NAN without iterations or factors.
EO_API double eo_profile_iteration_ratio(const eo_profile *p);

typedef struct eo_optimizer_type {
    eo_method_info info;
    size_t state_size;
    int needs_linear;     ///< 1 if it factors/solves systems (solver.linear used)
    int needs_hessian;    ///< 1 if it calls objective hessian
    /// Line search used when solver.linesearch is "auto" (the default): a registered
    /// line-search name, NULL = "backtracking". lbfgs and ncg: "wolfe"; newton,
    /// gradient_descent, projective_dynamics: backtracking; bcqn: barrier_filter;
    /// newton_tr uses none.
    const char *linesearch;
    /// Size workspace for n variables, on a zeroed state. The solver calls it at the
    /// first minimize and, after destroy and zeroing, whenever obj->n changes.
    int (*setup)(void *st, const void *params, int n, eo_ctx *ctx);
    /// Minimize from x (in: start, out: last iterate). Must record every iteration
    /// through sc->on_iter (if set) and end with a reason in res. Returns EO_OK (also
    /// when the reason is negative) or a negative status (objective error, bad input).
    int (*minimize)(void *st, const void *params, const eo_solver_ctx *sc, double *x,
                    eo_solve_result *res);
    void (*destroy)(void *st, eo_ctx *ctx);
    /// 1 if the decrement it reports is λ² = −∇gᵀp with p = −H⁻¹∇g for a Hessian H of g
    /// (newton): the stopping rules then measure progress by λ_k/λ_0. 0 (the default, also
    /// for plug-ins): by the metric gradient norm ‖∇g_k‖_{D⁻¹}/‖∇g_0‖_{D⁻¹}.
    int newton_decrement;
} eo_optimizer_type;

EO_API extern const eo_optimizer_type eo_optimizer_newton, eo_optimizer_newton_tr,
    eo_optimizer_gradient_descent, eo_optimizer_lbfgs, eo_optimizer_ncg,
    eo_optimizer_projective_dynamics, eo_optimizer_pd_local_global, eo_optimizer_bcqn;
EO_API extern const eo_hessfix_type eo_hessfix_none, eo_hessfix_shift, eo_hessfix_clamp,
    eo_hessfix_abs, eo_hessfix_project_on_demand, eo_hessfix_progressive,
    eo_hessfix_trust_region_filter;
EO_API extern const eo_linesearch_type eo_linesearch_backtracking, eo_linesearch_wolfe,
    eo_linesearch_exact, eo_linesearch_none, eo_linesearch_nonmonotone, eo_linesearch_barrier_filter;
EO_API extern const eo_stop_type eo_stop_newton_decrement, eo_stop_gradient,
    eo_stop_relative_decrement, eo_stop_characteristic_gradient;

/// Shared helper for optimizers: report an iteration (fills time = now − t0, calls
/// sc->on_iter); returns non-zero if the callback asked to stop.
EO_API int eo_solver_report(const eo_solver_ctx *sc, double t0, eo_iter_info *info);

/// Solver choice: config section `solver` (descriptor eo_solver_opts_desc).
typedef struct eo_solver_opts {
    char optimizer[32];    ///< registered optimizer (default "newton")
    char hessian_fix[32];  ///< registered Hessian fix (default "project_on_demand")
    char linesearch[32];   ///< registered line search, or "auto" (default): the
                           ///< optimizer's choice (eo_optimizer_type.linesearch),
                           ///< replaced by the resolved name in eo_solver_get_opts
    char stop[32];         ///< registered stopping rule (default "relative_decrement")
    char linear[32];       ///< registered linear solver (default "cholmod"), used only by
                           ///< optimizers that solve systems (newton, projective_dynamics)
    double tol;            ///< stopping tolerance, see the file comment (default 1e-10)
    int max_iters;         ///< iteration cap → EO_DIVERGED_MAX_ITERS (default 100)
    double time_budget;    ///< seconds per minimization, 0 = none (default 0)
    /// "native" (default) or "petsc": run `optimizer` distributed with the PETSc / MPI
    /// backend (its version petsc_<optimizer>, e.g. petsc_newton; the backend's own
    /// snes_* and tao_* optimizers run as they are). The backend is a module the CLI
    /// loads when built with -Dpetsc (README "PETSc / MPI backend"); without it
    /// eo_solver_create fails with EO_ERR_UNKNOWN_NAME naming the option.
    char backend[16];
} eo_solver_opts;
EO_API extern const eo_param_desc eo_solver_opts_desc[];

/// Defaults of every field.
EO_API void eo_solver_opts_default(eo_solver_opts *o);
/// Load config section `solver` into o (keys of eo_solver_opts_desc; the names of all
/// registered solver methods are accepted as sub-sections, read by eo_solver_create;
/// anything else is EO_ERR_UNKNOWN_KEY). cfg NULL: no-op.
EO_API int eo_solver_opts_load(eo_ctx *ctx, eo_cfg *cfg, eo_solver_opts *o);
/// Resolve every name (EO_ERR_UNKNOWN_NAME listing the valid ones), load each method's
/// params from `solver.<name>` (cfg may be NULL: defaults), check the sections of the
/// registered but unselected methods too and create the linear solver if the optimizer
/// needs one. The problem size is not needed: the workspace is sized lazily by
/// eo_solver_minimize. opts NULL = defaults; copied.
/// Returns EO_OK, EO_ERR_UNKNOWN_NAME, EO_ERR_UNKNOWN_KEY, EO_ERR_TYPE, EO_ERR_RANGE,
/// EO_ERR_INVALID, EO_ERR_NOMEM.
EO_API int eo_solver_create(eo_ctx *ctx, const eo_solver_opts *opts, eo_cfg *cfg, eo_solver **out);
/// Minimize obj from x (obj->n values, in/out); (re)sizes the optimizer's workspace
/// when obj->n differs from the previous call. on_iter may be NULL. Returns EO_OK with
/// the reason in res (negative reasons are not errors), or a negative status
/// (EO_ERR_INVALID for no objective, an objective error, EO_ERR_NOMEM).
EO_API int eo_solver_minimize(eo_solver *s, eo_objective *obj, double *x, eo_iter_fn on_iter,
                       void *user, eo_solve_result *res);
/// Free; sets *s = NULL; accepts NULL.
EO_API void eo_solver_destroy(eo_solver **s);
/// The options in use (borrowed).
EO_API const eo_solver_opts *eo_solver_get_opts(const eo_solver *s);
/// The linear solver (borrowed; NULL if the optimizer needs none), e.g. for its stats.
EO_API eo_linsolve *eo_solver_get_linsolve(const eo_solver *s);
/// Echo of the effective configuration: the `solver` section with the selected
/// methods' parameter sections. New reference (NULL on out of memory).
EO_API json_t *eo_solver_to_json(const eo_solver *s);

#ifdef __cplusplus
}
#endif
#endif
