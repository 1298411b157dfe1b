/// @file impl/method.h
/// The method-author interface of the solvers (installed, for plug-ins and in-tree
/// methods; users of the library need only solver.h): the ops tables of optimizers,
/// Hessian fixes, line searches and stopping rules, the context an optimizer's minimize
/// receives (eo_solver_ctx), the common stopping test (eo_solver_stop_check) and the
/// built-in tables. A new method is one file defining a table and one registry line
/// (or one registration call from a plug-in: plugin.h, callback.h).
#ifndef ELASTOPT_IMPL_METHOD_H
#define ELASTOPT_IMPL_METHOD_H

#include "../config.h"
#include "../export.h"
#include "../linsolve.h"
#include "../objective.h"
#include "../solver.h"

#ifdef __cplusplus
extern "C" {
#endif


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
    double g_scale;       ///< the objective's value scale s[2] at x₀ (units of g; 0: none):
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
/// 1 if the solver's optimizer measures convergence by the Newton decrement
/// (eo_optimizer_type.newton_decrement), 0 if by the metric gradient norm.
struct eo_solver;
EO_API int eo_solver_measures_decrement(const struct eo_solver *s);

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
    /// Objective operations beyond value, gradient and Hessian the optimizer cannot run
    /// without (EO_OBJ_NEEDS_*, objective.h; 0 for most): the simulation driver refuses
    /// at load, naming the element, a step objective that lacks them (eo_sim_create).
    unsigned needs_ops;
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

#ifdef __cplusplus
}
#endif
#endif
