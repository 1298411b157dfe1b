/* Internal: the trial-step bookkeeping shared by backtracking.c, exact.c and none.c (not
 * a public header): the first trial α₀, the point x + αp, one counted evaluation of g
 * there, and the common way to give up (x itself, α = 0, EO_WARN_NOT_CONVERGED). */
#ifndef EO_LINESEARCH_TRIAL_H
#define EO_LINESEARCH_TRIAL_H

#include <math.h>

#include "elastopt/impl/method.h"

/* α₀ as given when it is a positive finite number, else 1. */
static inline double eo_ls_first_step(double alpha0) { return alpha0 > 0 && isfinite(alpha0) ? alpha0 : 1; }

/* xt = x + a·p (n entries). */
static inline void eo_ls_point(int n, const double *x, const double *p, double a, double *xt)
{
    for (int i = 0; i < n; i++) xt[i] = x[i] + a * p[i];
}

/* xt = x + a·p and *f = g(xt); counts the evaluation in *nevals. Returns the
 * objective's status (negative: an error to pass on). */
static inline int eo_ls_value(eo_objective *obj, const double *x, const double *p, double a, double *xt,
                              double *f, int *nevals)
{
    eo_ls_point(obj->n, x, p, a, xt);
    ++*nevals;
    return eo_objective_value(obj, xt, f);
}

/* As eo_ls_value, with ∇g(xt) into grad when grad is not NULL (one gradient call, which
 * also gives the value). */
static inline int eo_ls_eval(eo_objective *obj, const double *x, const double *p, double a, double *xt, double *f,
                             int *nevals, double *grad)
{
    if (!grad) return eo_ls_value(obj, x, p, a, xt, f, nevals);
    eo_ls_point(obj->n, x, p, a, xt);
    ++*nevals;
    return eo_objective_gradient(obj, xt, f, grad);
}

/* The buffer for the first trial's gradient: extra->grad_new when the caller asks for it
 * (extra->grad_first), else NULL (value only). */
static inline double *eo_ls_first_grad(const eo_ls_extra *extra)
{
    return extra && extra->grad_first ? extra->grad_new : NULL;
}

/* No acceptable step: xnew = x, gnew = g0, α = 0; returns EO_WARN_NOT_CONVERGED. */
static inline int eo_ls_give_up(int n, const double *x, double g0, double *xnew, double *gnew, double *alpha)
{
    for (int i = 0; i < n; i++) xnew[i] = x[i];
    *gnew = g0;
    *alpha = 0;
    return EO_WARN_NOT_CONVERGED;
}

#endif
