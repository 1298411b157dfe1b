/* Hessian fix "progressive": project only the element Hessians the residual points at,
 * growing the set when indefiniteness is detected (after Fernández-Fernández, Löschner
 * & Bender, "Progressively Projected Newton's Method", Computer Graphics Forum 45(2),
 * Eurographics 2026, arXiv:2505.21013, "PPN").
 *
 * What the paper says and what is reproduced here: PPN keeps a split Hessian
 * H = H_p + H_u, H_p the (clamp-)projected Hessians of a subset P of the elements and
 * H_u the unprojected rest; P is chosen from the residual ∇g of the current iterate
 * through a residual threshold δ updated by two factors (α, β), grows when the solve
 * detects indefiniteness, and PPN projects < 10% of the elements PN does. The full
 * text of the paper (the exact formula of the selection rule and the values of α, β)
 * could not be retrieved here (only its abstract and summary), so the rule below is
 * the closest one those statements document, NOT a verbatim reproduction:
 *   r_e      = max over the nodes of element e of ‖∇g_node‖₂  (objective op
 *              element_residual), r_max = max_e r_e.
 *   P, δ     empty and δ = +∞ at the start of each minimization (time step); P only
 *            grows during a minimization ("progressive").
 *   per direction:
 *     P ← P ∪ {e : r_e > δ}
 *     assemble with element e ∈ P clamped (EO_PROJ_CLAMP), the others unprojected
 *     (objective op hessian_masked), factor, p = −H⁻¹∇g;
 *     while H is not PD or p is not a descent direction (∇gᵀp ≥ −eps‖∇g‖‖p‖):
 *       δ ← δ = +∞ ? delta_init·r_max : delta_shrink·δ      (β = delta_init,
 *                                                              α = delta_shrink)
 *       P ← P ∪ {e : r_e > δ}; assemble again, factor, solve (a round);
 *     after max_rounds rounds, or once P holds every element (or the objective has no
 *     per-element ops), every Hessian contribution is clamped (as `clamp`, which also
 *     projects springs and other terms without elements) with the c·I shift loop of
 *     shift_loop.c as the safeguard (solver.progressive.shift_*, as solver.shift.*).
 * So a problem whose Hessian stays positive definite is solved by pure Newton
 * (quadratic convergence, nothing projected), and where it is not, the elements with
 * the largest residual, those far from equilibrium, are projected first.
 * iter_info.projected reports |P|/E (1 after the full clamp).
 * Memory: the mask P and the residuals r (E each) are sized in `begin` when the
 * objective's element count grows; nothing is allocated in `factor`. */
#include <math.h>
#include <stddef.h>

#include "shift_loop.h"

/// project_on_demand (config `solver.project_on_demand.*`): the shift safeguard of the
/// projected retry (same keys as solver.shift.*).
/// progressive (config `solver.progressive.*`).
typedef struct eo_hessfix_progressive_params {
    eo_hessfix_shift_params shift; ///< safeguard once every element is projected
    double delta_init;   ///< first residual threshold, relative to max_e r_e (default 0.5)
    double delta_shrink; ///< threshold factor on each detected indefiniteness (0.5)
    int max_rounds;      ///< growth rounds per direction before projecting all (20)
} eo_hessfix_progressive_params;

typedef struct prog_state {
    eo_shift_ws w;          /* first: the generic setup/destroy of the shift loop */
    unsigned char *mask;    /* E: EO_PROJ_CLAMP for elements in P, else EO_PROJ_NONE */
    double *r;              /* E: element residuals */
    int cap, ne;            /* allocated, current element count (-1: no per-element ops) */
    int nproj;              /* |P| */
    double delta;           /* residual threshold (+∞: none yet) */
} prog_state;

#define PP(field) offsetof(eo_hessfix_progressive_params, field)
static const eo_param_desc prog_desc[] = {
    {.key = "shift_init", .kind = EO_PARAM_DOUBLE, .offset = PP(shift.shift_init), .def.d = 1e-8,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "first non-zero shift, relative to mean |H_ii|"},
    {.key = "shift_grow", .kind = EO_PARAM_DOUBLE, .offset = PP(shift.shift_grow), .def.d = 10,
     .min = 1, .range = EO_RANGE_MIN_OPEN, .help = "shift growth factor per retry"},
    {.key = "shift_shrink", .kind = EO_PARAM_DOUBLE, .offset = PP(shift.shift_shrink), .def.d = 10,
     .min = 1, .range = EO_RANGE_MIN, .help = "next iteration starts at c/shift_shrink (0 below the minimum)"},
    {.key = "shift_max", .kind = EO_PARAM_DOUBLE, .offset = PP(shift.shift_max), .def.d = 1e12,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "largest shift, relative to mean |H_ii|; beyond: not PD"},
    {.key = "delta_init", .kind = EO_PARAM_DOUBLE, .offset = PP(delta_init), .def.d = 0.5,
     .min = 0, .max = 1, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX,
     .help = "first residual threshold, relative to the largest element residual"},
    {.key = "delta_shrink", .kind = EO_PARAM_DOUBLE, .offset = PP(delta_shrink), .def.d = 0.5,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN,
     .help = "threshold factor each time indefiniteness is detected"},
    {.key = "max_rounds", .kind = EO_PARAM_INT, .offset = PP(max_rounds), .def.i = 20, .min = 0,
     .max = 1000, .range = EO_RANGE_CLOSED,
     .help = "growth rounds per direction before every element is projected"},
    {0},
};
#undef PP

static void prog_destroy(void *vst, eo_ctx *ctx)
{
    prog_state *st = vst;
    eo_shift_ws_destroy(&st->w, ctx);
    eo_free(ctx, st->mask);
    eo_free(ctx, st->r);
    st->mask = NULL;
    st->r = NULL;
    st->cap = 0;
}

static int prog_begin(void *vst, const void *params, const eo_hessfix_env *env)
{
    prog_state *st = vst;
    (void)params;
    eo_shift_ws_begin(&st->w);
    st->delta = INFINITY;
    st->nproj = 0;
    st->ne = eo_objective_n_elements(env->obj);
    if (st->ne < 0) {
        st->ne = -1;
        return EO_OK;
    }
    if (st->ne > st->cap) {
        eo_free(env->ctx, st->mask);
        eo_free(env->ctx, st->r);
        st->cap = 0;
        st->mask = eo_calloc(env->ctx, (size_t)st->ne, 1);
        st->r = eo_calloc(env->ctx, (size_t)st->ne, sizeof(double));
        if (!st->mask || !st->r)
            return eo_error(env->ctx, EO_ERR_NOMEM, "progressive: out of memory (%d elements)", st->ne);
        st->cap = st->ne;
    }
    for (int e = 0; e < st->ne; e++) st->mask[e] = EO_PROJ_NONE;
    return EO_OK;
}

/* P ← P ∪ {e : r_e > δ}; returns the number added. */
static int grow(prog_state *st)
{
    int added = 0;
    for (int e = 0; e < st->ne; e++)
        if (st->mask[e] == EO_PROJ_NONE && st->r[e] > st->delta) {
            st->mask[e] = EO_PROJ_CLAMP;
            added++;
        }
    st->nproj += added;
    return added;
}

static int prog_factor(void *vst, const void *params, const eo_hessfix_env *env, double *p,
                       eo_hessfix_out *out)
{
    prog_state *st = vst;
    eo_hessfix_progressive_params def;
    const eo_hessfix_progressive_params *pp = params;
    if (!pp) {
        eo_params_default(prog_desc, &def);
        pp = &def;
    }
    int ok;
    if (st->ne > 0) {
        if (eo_objective_n_elements(env->obj) != st->ne)
            return eo_error(env->ctx, EO_ERR_INVALID,
                            "progressive: the objective's element count changed within a minimization");
        int rc = eo_objective_element_residual(env->obj, env->grad, st->r);
        if (rc < 0) return rc;
        /* on a distributed space the counts and the largest residual are the whole
         * problem's (every part's elements), so that every part decides alike */
        const eo_vspace *vs = env->obj->space;
        double rmax = 0;
        for (int e = 0; e < st->ne; e++) rmax = st->r[e] > rmax ? st->r[e] : rmax;
        eo_vreduce(vs, &rmax, 1, EO_REDUCE_MAX);
        double cnt[2] = {st->ne, 0};
        eo_vreduce(vs, cnt, 1, EO_REDUCE_SUM);
        const double ne_all = cnt[0];
        cnt[1] = grow(st);
        double nproj_all = st->nproj;
        eo_vreduce(vs, &nproj_all, 1, EO_REDUCE_SUM);
        for (int round = 0;; round++) {
            out->projected = nproj_all / ne_all;
            ok = eo_shift_assemble_factor(&st->w, &pp->shift, 0, env, EO_PROJ_NONE, st->mask, p, out);
            if (ok < 0) return ok;
            if (ok || out->reason) return EO_OK;
            /* indefinite: lower the threshold until it selects more elements */
            if (round >= pp->max_rounds || nproj_all >= ne_all || !(rmax > 0)) break;
            double added = 0;
            while (!added && nproj_all < ne_all) {
                st->delta = isfinite(st->delta) ? pp->delta_shrink * st->delta : pp->delta_init * rmax;
                added = grow(st);
                eo_vreduce(vs, &added, 1, EO_REDUCE_SUM);
                nproj_all += added;
                if (!(st->delta > 1e-300 * rmax)) break;
            }
            if (!added) break;
            eo_log(env->ctx, EO_LOG_DEBUG, "progressive: indefinite, %.0f of %.0f elements projected",
                   nproj_all, ne_all);
        }
    }
    out->projected = 1;
    ok = eo_shift_assemble_factor(&st->w, &pp->shift, 1, env, EO_PROJ_CLAMP, NULL, p, out);
    return ok < 0 ? ok : EO_OK;
}

const eo_hessfix_type eo_hessfix_progressive = {
    .info = {.name = "progressive",
             .summary = "clamp only the elements selected by the residual, growing the set on "
                        "indefiniteness (after Fernandez-Fernandez 2026)",
             .params = prog_desc,
             .params_size = sizeof(eo_hessfix_progressive_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(prog_state),
    .elem_proj = EO_PROJ_NONE,
    .setup = eo_shift_op_setup,
    .begin = prog_begin,
    .factor = prog_factor,
    .destroy = prog_destroy,
};
