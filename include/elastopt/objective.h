/// @file objective.h
/// The objective interface every optimizer sees: g(x) over n free variables.
///
/// A step problem (problems/step.c) implements it as a sum of terms (inertia,
/// elasticity, gravity, springs, ...); tests implement it for small analytic problems;
/// the Poisson problem implements it too. Optimizers use only this interface, so
/// every optimizer works on every problem.
///
/// ```c
/// double g; eo_objective_gradient(obj, x, &g, grad);   // g may be +INFINITY (inverted)
/// eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);     // H borrowed, fixed pattern
/// ```
/// Ownership: the objective owns its Hessian matrix; callers borrow it until the next
/// hessian call.
#ifndef ELASTOPT_OBJECTIVE_H
#define ELASTOPT_OBJECTIVE_H

#include "material.h"
#include "sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_objective_ops {
    /// g(x). Return EO_OK; set *g = +INFINITY where undefined (never NaN).
    int (*value)(void *data, const double *x, double *g);
    /// g(x) and ∇g(x) (n). *g may be +INFINITY (then grad is unspecified).
    int (*gradient)(void *data, const double *x, double *g, double *grad);
    /// ∇²g(x) with per-element projection `proj`, into the fixed pattern; *H borrowed.
    int (*hessian)(void *data, const double *x, eo_proj proj, eo_csc **H);
    /// Optional: a diagonal metric (e.g. lumped mass) for scaled methods; NULL if none.
    int (*metric_diag)(void *data, double *d);
    /// Optional: number of inverted elements at x (for logs); NULL if not applicable.
    int (*inverted_count)(void *data, const double *x);
} eo_objective_ops;

typedef struct eo_objective {
    int n;                          ///< number of free variables
    const eo_objective_ops *ops;
    void *data;
    long n_value, n_gradient, n_hessian;  ///< evaluation counters
} eo_objective;

static inline int eo_objective_value(eo_objective *o, const double *x, double *g)
{
    o->n_value++;
    return o->ops->value(o->data, x, g);
}
static inline int eo_objective_gradient(eo_objective *o, const double *x, double *g, double *grad)
{
    o->n_gradient++;
    return o->ops->gradient(o->data, x, g, grad);
}
static inline int eo_objective_hessian(eo_objective *o, const double *x, eo_proj proj, eo_csc **H)
{
    o->n_hessian++;
    return o->ops->hessian(o->data, x, proj, H);
}

#ifdef __cplusplus
}
#endif
#endif
