/* Substeps of the step engine (step.h, eo_step_set_substep): the steps of an implicit
 * integrator may be h/2^k long (h = time.dt, the nominal step) for eo_sim's adaptive
 * stepping (sim.h). The engine counts the progress through the current nominal step
 * tₙ → tₙ + h as an exact binary fraction p (a sum of powers of two no smaller than
 * 2^-EO_STEP_MAX_SUBSTEP, so every partial sum is exact):
 *
 *   a substep of level k poses the step problem with step size h/2^k (weight, predictor,
 *   velocity update, friction lag and damping all take it) ending at
 *       tₙ₊₁ = tₙ + (p + 2^-k)·h,  exactly tₙ + h for the last one (p + 2^-k = 1),
 *   and only that last one advances the step index;
 *   level 0 with p = 0 is the nominal step, computed exactly as without substeps
 *   (tₙ₊₁ = t + h).
 *
 * Prescribed motions, releases and load stepping see the time (and the load fraction
 * index + p + 2^-k of time.load_steps), so a substep applies its share of them.
 * A multistep integrator's history (bdf2) holds the previous step of the same size only:
 * a change of level invalidates it, so the first step after a change is the integrator's
 * one-step start (backward Euler for bdf2), the next ones the fixed-step formula again. */
#include <math.h>

#include "step_impl.h"

double eo_stepi_t1(const eo_step *st)
{
    if (st->sub_level == 0 && st->sub_done == 0) return st->t + st->h;
    const double f = st->sub_done + ldexp(1.0, -st->sub_level);
    const double t0 = st->sub_done > 0 ? st->sub_t0 : st->t;
    return f >= 1 ? t0 + st->h_nom : t0 + f * st->h_nom;
}

double eo_stepi_load_steps_done(const eo_step *st)
{
    return (double)st->index + st->sub_done + ldexp(1.0, -st->sub_level);
}

void eo_step_get_substep(const eo_step *st, eo_step_substep *s)
{
    s->level = st->sub_level;
    s->done = st->sub_done;
    s->t_start = st->sub_done > 0 ? st->sub_t0 : st->t;
}

int eo_step_set_substep(eo_step *st, const eo_step_substep *s)
{
    if (st->integ->explicit_step)
        return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "integrator %s is explicit: no substeps", st->integ->info.name);
    if (s->level < 0 || s->level > EO_STEP_MAX_SUBSTEP)
        return eo_error(st->ctx, EO_ERR_RANGE, "substep level %d outside 0..%d", s->level, EO_STEP_MAX_SUBSTEP);
    /* done: a multiple of 2^-level in [0, 1), so that the substeps end on tₙ + h */
    const double q = ldexp(s->done, s->level);
    if (!(s->done >= 0 && s->done < 1) || q != floor(q))
        return eo_error(st->ctx, EO_ERR_RANGE, "substep progress %.17g is not a multiple of 2^-%d in [0, 1)", s->done,
                        s->level);
    if (s->level != st->sub_level) st->hist_valid = 0; /* the history is of a step of the old size */
    st->sub_level = s->level;
    st->h = ldexp(st->h_nom, -s->level);
    st->sub_done = s->done;
    st->sub_t0 = s->done > 0 ? s->t_start : st->t;
    return EO_OK;
}

/* eo_step_end: the progress after a step (index and time are set by the caller) */
int eo_stepi_substep_advance(eo_step *st)
{
    if (st->sub_level == 0 && st->sub_done == 0) return 1;
    if (st->sub_done == 0) st->sub_t0 = st->t;
    st->sub_done += ldexp(1.0, -st->sub_level);
    if (st->sub_done < 1) return 0;
    st->sub_done = 0;
    return 1;
}
