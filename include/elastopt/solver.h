/// @file solver.h
/// Optimizers, Hessian fixes, line searches and stopping rules, each chosen by name.
///
/// The solver of one step problem is assembled from four pluggable pieces:
///   solver.optimizer   newton, gradient_descent, lbfgs, ...   (eo_optimizer_type)
///   solver.hessian_fix none, shift, clamp, abs                 (eo_hessfix_type)
///   solver.linesearch  backtracking, exact, none               (eo_linesearch_type)
///   solver.stop        newton_decrement, gradient              (eo_stop_type)
///   solver.linear      cholmod, cholmod_ldlt, ...               (eo_linsolve_type)
/// and each method's parameters live in config section `solver.<method name>`.
///
/// ```c
/// eo_solver *s; eo_solver_create(ctx, &opts, obj->n, &s);  // opts: names + params
/// eo_solve_result r;
/// eo_solver_minimize(s, obj, x, on_iter, user, &r);        // x: start in, minimizer out
/// printf("%s after %d iterations\n", eo_reason_string(r.reason), r.iterations);
/// eo_solver_destroy(&s);
/// ```
/// No allocation happens inside the iterations: workspace is sized in create.
#ifndef ELASTOPT_SOLVER_H
#define ELASTOPT_SOLVER_H

#include "linsolve.h"
#include "objective.h"

#ifdef __cplusplus
extern "C" {
#endif

/// What one iteration reports (to the CSV log and the benchmark recorder).
typedef struct eo_iter_info {
    int iteration;        ///< 0 = the start point, then 1, 2, ...
    double time;          ///< seconds since the start of this minimization
    double g;             ///< objective
    double grad_norm;     ///< ‖∇g‖₂
    double decrement;     ///< λ²/2 = −∇gᵀp/2 of the direction taken (NAN if none)
    double alpha;         ///< accepted step length (NAN at iteration 0)
    int ls_evals;         ///< objective evaluations in the line search
    double shift;         ///< Hessian shift c used (0 if none)
    int inverted;         ///< inverted elements at the iterate (-1 if unknown)
    int reason;           ///< reason if this is the last iteration, else 0
    const double *x;      ///< the iterate (borrowed, valid during the callback)
} eo_iter_info;

/// Callback after every iteration; return non-zero to stop (reason EXTERNAL).
typedef int (*eo_iter_fn)(const eo_iter_info *info, void *user);

/// Context given to a stopping rule.
typedef struct eo_stop_info {
    int iteration;
    double g, g_prev;     ///< current and previous objective (g_prev = NAN at first)
    double grad_norm;     ///< ‖∇g(x)‖₂
    double grad_norm0;    ///< ‖∇g(x₀)‖₂ at the start of this minimization
    double decrement;     ///< λ²/2 for the direction just computed at x (NAN if none)
    double step_norm;     ///< ‖α p‖₂ of the last step (NAN at first)
    double x_norm;        ///< ‖x‖₂
    double tol;           ///< solver.tol
} eo_stop_info;

typedef struct eo_stop_type {
    eo_method_info info;
    /// Positive eo_reason if converged, 0 to go on. Called twice per iteration: once
    /// after the gradient (decrement = NAN) and, for direction-based rules, once after
    /// the direction is known.
    int (*check)(const void *params, const eo_stop_info *si);
    int needs_direction;  ///< 1 if the rule needs the decrement (newton_decrement)
} eo_stop_type;

typedef struct eo_linesearch_type {
    eo_method_info info;
    /// Find α along p from x (g0 = g(x), dg0 = ∇g(x)ᵀp < 0). Writes the accepted point
    /// to xnew and g(xnew) to *gnew, the step to *alpha, evaluations to *nevals.
    /// A trial with non-finite g is rejected and the step shrunk. `alpha0` is the first
    /// trial. Returns EO_OK, or a positive warning EO_WARN_NOT_CONVERGED when no
    /// acceptable step was found (then xnew/gnew hold the best point found, possibly x).
    int (*search)(const void *params, eo_objective *obj, const double *x, const double *p,
                  double g0, double dg0, double alpha0, double *xnew, double *gnew,
                  double *alpha, int *nevals, eo_ctx *ctx);
} eo_linesearch_type;

/// Hessian fix: how Newton makes its system positive definite.
typedef struct eo_hessfix_type {
    eo_method_info info;
    eo_proj elem_proj;   ///< per-element projection used when assembling (clamp, abs)
    int shifts;          ///< 1: adds c·I and retries on EO_WARN_NOT_PD / non-descent
} eo_hessfix_type;

typedef struct eo_solver eo_solver;

/// Everything the solver needs to know about one minimization.
typedef struct eo_solver_ctx {
    eo_objective *obj;
    eo_ctx *ctx;
    eo_linsolve *linear;                ///< NULL for methods that do not solve systems
    const eo_hessfix_type *hessfix;
    const void *hessfix_params;
    const eo_linesearch_type *linesearch;
    const void *linesearch_params;
    const eo_stop_type *stop;
    const void *stop_params;
    double tol;                         ///< solver.tol
    int max_iters;                      ///< solver.max_iters
    double time_budget;                 ///< seconds, 0 = none
    eo_iter_fn on_iter;
    void *user;
} eo_solver_ctx;

/// Result of one minimization.
typedef struct eo_solve_result {
    int reason;           ///< eo_reason
    int iterations;
    double g, grad_norm, decrement;
    double time;          ///< seconds
    long n_value, n_gradient, n_hessian, n_factor;
    int status;           ///< eo_status of the last library call (0 unless an error)
} eo_solve_result;

typedef struct eo_optimizer_type {
    eo_method_info info;
    size_t state_size;
    int needs_linear;     ///< 1 if it factors/solves systems (solver.linear used)
    int needs_hessian;    ///< 1 if it calls objective hessian
    /// Size workspace for n variables. Called once before minimize (and again if n changes).
    int (*setup)(void *st, const void *params, int n, eo_ctx *ctx);
    /// Minimize from x (in: start, out: last iterate). Must record every iteration
    /// through sc->on_iter (if set) and end with a reason in res.
    int (*minimize)(void *st, const void *params, const eo_solver_ctx *sc, double *x,
                    eo_solve_result *res);
    void (*destroy)(void *st, eo_ctx *ctx);
} eo_optimizer_type;

/// Shared helper for optimizers: report an iteration (fills time, calls on_iter);
/// returns non-zero if the callback asked to stop.
int eo_solver_report(const eo_solver_ctx *sc, double t0, eo_iter_info *info);

#ifdef __cplusplus
}
#endif
#endif
