/// @file callback.h
/// Optimizers made of callbacks: register a method from function pointers and a user
/// pointer, without writing a const eo_optimizer_type table (other languages, closures).
///
/// A pluggable optimizer is normally one const ops table (solver.h, eo_optimizer_type)
/// registered with eo_register. A program in another language (the Python package in
/// python/elastopt) has functions and a per-method user pointer instead; this file turns
/// them into a registered optimizer, named like any other (`solver.optimizer=<name>` in
/// scenes, `-o`, bench suites, `elastopt list`), in one of two forms:
///
///  - `minimize`: the whole minimization, with the contract of eo_optimizer_type.minimize
///    (x in: start, out: last iterate; every iterate reported through eo_solver_report,
///    whose non-zero return asks to stop; res->reason and res->iterations set). The
///    objective, stopping rule (sc->stop->check), tolerance, iteration cap, time budget
///    and the Hessian fix's choice are all in sc.
///  - `direction`: only the search direction p at x_k; the shared line-search loop of
///    newton, gradient_descent and lbfgs does the rest (evaluation, the configured stopping
///    rule with λ²/2 = −α₀∇gᵀp/2, solver.linesearch, time budget, iteration cap, the
///    records), so such a method is timed and stopped exactly like a built-in one.
///
/// ```c
/// static int steepest(void *user, const eo_solver_ctx *sc, const double *x, double g,
///                     const double *grad, double *p, double *alpha0, int *reason)
/// {
///     for (int i = 0; i < sc->obj->n; i++) p[i] = -grad[i];   // *alpha0 = 1 on entry
///     return EO_OK;
/// }
/// eo_callback_optimizer_def d = {.name = "steepest", .summary = "p = -grad g",
///                                .direction = steepest};
/// eo_callback_optimizer *o;
/// rc = eo_callback_optimizer_register(ctx, &d, &o);   // now solver.optimizer=steepest works
/// ...
/// eo_callback_optimizer_destroy(&o);                  // unregisters; solvers made with it
///                                                     // must be destroyed before
/// ```
/// Ownership: name and summary are copied; `user` is borrowed and passed back to every
/// call. The object (and its ctx) must outlive every solver created with its name.
/// Registries are process-wide and not thread-safe (registry.h).
#ifndef ELASTOPT_CALLBACK_H
#define ELASTOPT_CALLBACK_H

#include "export.h"
#include "impl/method.h"

#ifdef __cplusplus
extern "C" {
#endif

/// The whole minimization (see the file comment). Returns EO_OK (also when res->reason
/// is negative) or a negative status (the message set with eo_error on sc->ctx).
typedef int (*eo_callback_minimize_fn)(void *user, const eo_solver_ctx *sc, double *x,
                                       eo_solve_result *res);
/// The direction p (sc->obj->n values) at x with g = g(x) and grad = ∇g(x) (finite).
/// *alpha0 is the line search's first trial (1 on entry); *reason (0 on entry) may be set
/// to a negative eo_reason when there is no direction (the run stops with it). Returns
/// EO_OK or a negative status.
typedef int (*eo_callback_direction_fn)(void *user, const eo_solver_ctx *sc, const double *x,
                                        double g, const double *grad, double *p,
                                        double *alpha0, int *reason);

/// What to register. Exactly one of minimize and direction is set.
typedef struct eo_callback_optimizer_def {
    const char *name;        ///< registry key: letters, digits, '_', '-' (copied)
    const char *summary;     ///< one line for `elastopt list` (copied; NULL = "")
    int needs_hessian;       ///< 1 if it evaluates Hessians: the solver then sets up the
                             ///< Hessian fix and a bench `matrix` makes one configuration
                             ///< per fix (0 default)
    int needs_linear;        ///< 1 if it uses sc->linear (solver.linear is created) (0)
    eo_callback_minimize_fn minimize;
    eo_callback_direction_fn direction;
    void *user;              ///< passed back to minimize / direction (borrowed)
    /// 1 if the direction is a Newton direction p = −H⁻¹∇g with a Hessian H of g, so
    /// that the stopping rules measure progress by its decrement λ_k/λ_0 (as `newton`);
    /// 0 (default): by the metric gradient norm (solver.h, eo_optimizer_type)
    int newton_decrement;
} eo_callback_optimizer_def;

typedef struct eo_callback_optimizer eo_callback_optimizer;

/// Register an optimizer made of callbacks under def->name (kind EO_KIND_OPTIMIZER).
/// Returns EO_OK, EO_ERR_INVALID (no or both callbacks; bad or duplicate name: the
/// message names it), EO_ERR_NOMEM.
EO_API int eo_callback_optimizer_register(eo_ctx *ctx, const eo_callback_optimizer_def *def,
                                          eo_callback_optimizer **out);
/// The registered ops table (borrowed), e.g. for eo_registry_find comparisons.
EO_API const eo_optimizer_type *eo_callback_optimizer_type(const eo_callback_optimizer *o);
/// Unregister and free; sets *o = NULL; accepts NULL.
EO_API void eo_callback_optimizer_destroy(eo_callback_optimizer **o);

#ifdef __cplusplus
}
#endif
#endif
