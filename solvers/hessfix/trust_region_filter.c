/* Hessian fix "trust_region_filter": clamp or abs per iteration from the trust-region
 * ratio of the previous step (Chen, Liu, Jacobson, Levin & Zheng, "Trust-Region
 * Eigenvalue Filtering for Projected Newton", SIGGRAPH Asia 2024, arXiv:2410.10102; the
 * rule and the threshold as in the authors' implementation, github.com/honglin-c/
 * trust-region-newton, main.cpp).
 *
 * After the step x_{k+1} = x_k + αp_k the ratio of actual to predicted reduction is
 *     ρ_k = (g(x_k) − g(x_{k+1})) / −(α∇g_kᵀp_k + ½α² p_kᵀ ∇²g(x_k) p_k),
 * the quadratic model taken with the TRUE Hessian ∇²g(x_k) (not the projected one).
 * The next direction assembles the element Hessians with
 *     EO_PROJ_CLAMP  if |ρ_k − 1| < threshold  (the model is trusted: clamping, closest
 *                                              to Newton, converges fastest),
 *     EO_PROJ_ABS    otherwise, and at the first iteration of every minimization
 *                    (ρ = 0 before any step), where |λ| keeps steps short in strongly
 *                    compressed elements,
 * threshold = 0.01 (the paper's setting). The paper unifies Newton, clamp and abs as
 * generalized trust-region models but switches only between clamp and abs; so does
 * this fix (no iteration uses the unprojected Hessian). The shift loop of shift_loop.c
 * stays as the safeguard (solver.trust_region_filter.shift_*, as solver.shift.*).
 * Cost: pᵀ∇²g p needs the unprojected Hessian at x_k, assembled once more after the
 * factorization (exact_model = true, the paper's ratio); exact_model = false uses the
 * factored model H̃ instead (pᵀH̃p = −∇gᵀp, no extra assembly). The fraction projected
 * is 1 (every element is filtered one way or the other). With want_direction = 0
 * (projective_dynamics: one factorization per minimization) the first-iteration choice,
 * abs, is used. */
#include <math.h>
#include <stddef.h>

#include "shift_loop.h"

/// trust_region_filter (config `solver.trust_region_filter.*`).
typedef struct eo_hessfix_trust_region_filter_params {
    eo_hessfix_shift_params shift; ///< safeguard (as clamp/abs)
    double threshold;    ///< clamp when |ρ − 1| < threshold, else abs (default 0.01)
    int exact_model;     ///< ρ with the true Hessian (the paper; one extra assembly per
                         ///< iteration) or with the factored one (default true)
} eo_hessfix_trust_region_filter_params;

typedef struct trf_state {
    eo_shift_ws w;      /* first: the generic setup/destroy ops use it */
    double rho;         /* ratio of the last accepted step (0 before any) */
    double pHp;         /* pᵀ∇²g p of the last direction (NAN: use the factored model) */
} trf_state;

static const eo_param_desc trf_desc[] = {
    {.key = "shift_init", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(eo_hessfix_trust_region_filter_params, shift.shift_init), .def.d = 1e-8,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "first non-zero shift, relative to mean |H_ii|"},
    {.key = "shift_grow", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(eo_hessfix_trust_region_filter_params, shift.shift_grow), .def.d = 10,
     .min = 1, .range = EO_RANGE_MIN_OPEN, .help = "shift growth factor per retry"},
    {.key = "shift_shrink", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(eo_hessfix_trust_region_filter_params, shift.shift_shrink), .def.d = 10,
     .min = 1, .range = EO_RANGE_MIN, .help = "next iteration starts at c/shift_shrink (0 below the minimum)"},
    {.key = "shift_max", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(eo_hessfix_trust_region_filter_params, shift.shift_max), .def.d = 1e12,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "largest shift, relative to mean |H_ii|; beyond: not PD"},
    {.key = "threshold", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(eo_hessfix_trust_region_filter_params, threshold), .def.d = 0.01,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "clamp when |rho - 1| < threshold, else abs"},
    {.key = "exact_model", .kind = EO_PARAM_BOOL,
     .offset = offsetof(eo_hessfix_trust_region_filter_params, exact_model), .def.i = 1,
     .help = "rho from the true Hessian (one extra assembly per iteration) or the factored one"},
    {0},
};

static int trf_begin(void *vst, const void *params, const eo_hessfix_env *env)
{
    trf_state *st = vst;
    (void)params, (void)env;
    eo_shift_ws_begin(&st->w);
    st->rho = 0;
    st->pHp = NAN;
    return EO_OK;
}

static int trf_factor(void *vst, const void *params, const eo_hessfix_env *env, double *p,
                      eo_hessfix_out *out)
{
    trf_state *st = vst;
    eo_hessfix_trust_region_filter_params def;
    const eo_hessfix_trust_region_filter_params *tp = params;
    if (!tp) {
        eo_params_default(trf_desc, &def);
        tp = &def;
    }
    const eo_proj proj = fabs(st->rho - 1) < tp->threshold ? EO_PROJ_CLAMP : EO_PROJ_ABS;
    eo_log(env->ctx, EO_LOG_DEBUG, "trust_region_filter: rho = %g, %s", st->rho,
           proj == EO_PROJ_CLAMP ? "clamp" : "abs");
    out->projected = 1;
    st->pHp = NAN;
    int ok = eo_shift_assemble_factor(&st->w, &tp->shift, 1, env, proj, NULL, p, out);
    if (ok <= 0) return ok < 0 ? ok : EO_OK;
    if (env->want_direction && tp->exact_model) {
        eo_csc *H0 = NULL;
        int reason = 0;
        int rc = env->assemble(env->user, EO_PROJ_NONE, NULL, &H0, &reason);
        if (rc < 0) return rc;
        if (!reason && H0) st->pHp = eo_csc_quad_space(H0, p, env->obj->space);
    }
    return EO_OK;
}

static void trf_accepted(void *vst, const void *params, const eo_hessfix_step_info *si)
{
    trf_state *st = vst;
    (void)params;
    double pred = si->predicted;
    if (isfinite(st->pHp)) pred = -(si->alpha * si->dg + 0.5 * si->alpha * si->alpha * st->pHp);
    st->rho = si->actual / pred;
    if (!isfinite(st->rho)) st->rho = 0;
}

const eo_hessfix_type eo_hessfix_trust_region_filter = {
    .info = {.name = "trust_region_filter",
             .summary = "clamp or abs per iteration from the trust-region ratio of the last step (Chen 2024)",
             .params = trf_desc,
             .params_size = sizeof(eo_hessfix_trust_region_filter_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(trf_state),
    .elem_proj = EO_PROJ_CLAMP,
    .setup = eo_shift_op_setup,
    .begin = trf_begin,
    .factor = trf_factor,
    .accepted = trf_accepted,
    .destroy = eo_shift_op_destroy,
};
