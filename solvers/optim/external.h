/* Helpers shared by the wrappers of external optimizers (nlopt.c, ipopt.c), which see
 * the objective only through callbacks and expose no search direction.
 *
 * Stopping rule: the elastopt rule (sc->stop) is applied at every iterate the external
 * code accepts, through the common measure (eo_solver_stop_check). eo_external_stop is
 * for a code that exposes no direction (NLopt): relative_decrement measures it by the
 * metric gradient norm like every optimizer without a Newton decrement; other rules that
 * need a direction (newton_decrement: λ²/2 = −∇gᵀp/2) fall back to the `gradient` rule
 * (‖∇g‖₂ ≤ tol·‖∇g(x₀)‖₂, default floor) with the same solver.tol. (Ipopt reports its
 * step length, so ipopt.c recovers its direction and evaluates the rule itself.)
 * Internal to solvers/optim. */
#ifndef EO_OPTIM_EXTERNAL_H
#define EO_OPTIM_EXTERNAL_H

#include "descent.h"

/* Positive eo_reason if the rule says converged at the iterate x described by si (grad
 * = ∇g(x)), through the common measure (eo_solver_stop_check: the rounding floor, and
 * relative_decrement's metric gradient norm for an optimizer without a Newton
 * decrement). Another rule that needs a direction is replaced by `gradient`. */
static inline int eo_external_stop(const eo_solver_ctx *sc, eo_stop_info *si, const double *x, const double *grad)
{
    int r = eo_solver_stop_check(sc, si, x, grad);
    if (!r && sc->stop->needs_direction && sc->stop != &eo_stop_relative_decrement)
        r = eo_stop_gradient.check(NULL, si);
    return r;
}

/* Inverted elements at x (-1 if the objective does not count them). */
static inline int eo_external_inverted(const eo_solver_ctx *sc, const double *x)
{
    const eo_objective *o = sc->obj;
    return o->ops->inverted_count ? o->ops->inverted_count(o->data, x) : -1;
}

/* Log once per minimization which rule is really applied. */
static inline void eo_external_note_rule(const eo_solver_ctx *sc, const char *who)
{
    if (sc->stop->needs_direction)
        eo_log(sc->ctx, EO_LOG_DEBUG,
               "%s: stopping rule '%s' needs a direction; using 'gradient' with tol %g", who,
               sc->stop->info.name, sc->tol);
}

#endif
