/* Shared loop of the line-search descent optimizers (newton, gradient_descent, lbfgs).
 *
 * Each optimizer supplies only its direction (and what it learns from an accepted
 * step); the loop does evaluation, stopping tests, line search, acceptance, reporting
 * and the result. Internal to solvers/optim. */
#ifndef EO_OPTIM_DESCENT_H
#define EO_OPTIM_DESCENT_H

#include <math.h>

#include "elastopt/impl/method.h"

/* Workspace of the loop, sized once in setup. */
typedef struct eo_descent_ws {
    int n;
    double *p, *grad, *grad_new, *x_new, *work;
} eo_descent_ws;

int eo_descent_ws_init(eo_ctx *ctx, int n, eo_descent_ws *w);
void eo_descent_ws_deinit(eo_ctx *ctx, eo_descent_ws *w);

/* What the direction routine returns besides p. */
typedef struct eo_direction_out {
    double alpha0;  /* first line-search trial; the decrement is −alpha0·∇gᵀp/2 */
    double shift;   /* Hessian shift used (0 if none) */
    double projected; /* fraction of elements projected by the Hessian fix (0 if none) */
    int reason;     /* negative eo_reason when no direction could be computed */
    double eta;     /* inexact Newton: inner relative tolerance (0 if none) */
    int lin_iters;  /* iterations of the inner linear solve (0 if none) */
    int neg_curvature; /* the inner CG met non-positive curvature (handled by the fix) */
} eo_direction_out;

typedef struct eo_descent_ops {
    /* Called once at the start (x₀, g, ∇g known). May be NULL. */
    int (*begin)(void *st, const void *params, const eo_solver_ctx *sc, const double *x,
                 double g, const double *grad, eo_solve_result *res);
    /* Direction p (n) at x. Negative return = error status; reasons go in out->reason. */
    int (*direction)(void *st, const void *params, const eo_solver_ctx *sc, const double *x,
                     double g, const double *grad, double *p, eo_direction_out *out,
                     eo_solve_result *res);
    /* The step x → x_new (length alpha along p) was accepted. May be NULL. */
    void (*accepted)(void *st, const void *params, const double *x, const double *x_new,
                     const double *grad, const double *grad_new, const double *p, double alpha);
    /* Optional (used with a stopping rule that needs_direction): at an iterate k > 0,
     * before a new direction is computed, *est = an estimate of λ²/2 at x from what the
     * optimizer already has (newton: −½∇gᵀH̃⁻¹∇g with the factor of the previous
     * direction's matrix, one solve), or NAN if it has none. The rule is tested with it;
     * a converged reason stops the run without a new Hessian or factorization. si is the
     * rule's input at x (decrement NAN), for an optimizer that first asks whether the
     * estimate could pass at all (newton's estimate_gate). Negative return = error
     * status. May be NULL. */
    int (*decrement_estimate)(void *st, const void *params, const eo_solver_ctx *sc,
                              const double *x, double g, const double *grad,
                              const eo_stop_info *si, double *est, eo_solve_result *res);
    /* Curvature constant this optimizer prefers from a Wolfe line search (eo_ls_extra.c2;
     * 0 = no preference): 0.9 quasi-Newton, 0.1 nonlinear CG. */
    double ls_c2;
} eo_descent_ops;

int eo_descent_minimize(const eo_descent_ops *ops, void *st, const void *params,
                        const eo_solver_ctx *sc, eo_descent_ws *w, double *x,
                        eo_solve_result *res);

static inline double eo_dot(int n, const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}
static inline double eo_norm2(int n, const double *a) { return sqrt(eo_dot(n, a, a)); }
static inline double eo_norm_inf(int n, const double *a)
{
    double m = 0;
    for (int i = 0; i < n; i++) m = fabs(a[i]) > m ? fabs(a[i]) : m;
    return m;
}

/* A local yes/no made the same on every part of a distributed objective (1 if any part
 * says 1; the flag itself on an ordinary one): clocks and callbacks. */
static inline int eo_solver_agree(const eo_solver_ctx *sc, int yes)
{
    if (!sc->obj->space) return yes;
    double v = yes != 0;
    eo_vreduce(sc->obj->space, &v, 1, EO_REDUCE_MAX);
    return v != 0;
}

/* Load the objective's diagonal metric into d (n) if available and usable (every entry
 * finite and > 0); else fill d with ones. Returns 1 if the metric is used. */
int eo_descent_metric(const eo_solver_ctx *sc, double *d);

/* Fill the bookkeeping of a result at the end of a minimization: wall time since t0,
 * objective evaluations since the counts nv0/ng0/nh0 taken at the start, status of rc.
 * Shared by the descent loop and the external-optimizer wrappers. */
static inline void eo_solve_result_finish(eo_solve_result *res, const eo_objective *obj, long nv0,
                                          long ng0, long nh0, double t0, int rc)
{
    res->time = eo_wtime() - t0;
    res->n_value = obj->n_value - nv0;
    res->n_gradient = obj->n_gradient - ng0;
    res->n_hessian = obj->n_hessian - nh0;
    res->status = rc < 0 ? rc : EO_OK;
}

#endif
