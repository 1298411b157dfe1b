/* Optimizers made of callbacks (include/elastopt/callback.h): no built-in registry entry;
 * each eo_callback_optimizer_register call makes one ops table at run time.
 *
 * The object embeds its eo_optimizer_type as the first member; the solver hands the
 * running table to minimize in sc->optimizer, so the one static minimize below finds
 * the object (and the user's callbacks) of whichever table was selected.
 *
 *   minimize form    cb_minimize calls def.minimize(user, sc, x, res) and fills the
 *                    bookkeeping the callback did not (time, evaluation counts).
 *   direction form   cb_minimize runs eo_descent_minimize (descent.c) with a direction op
 *                    that calls def.direction: x_{k+1} = x_k + α p_k, α from
 *                    solver.linesearch starting at α₀, stopped by solver.stop with the
 *                    decrement λ²/2 = −α₀∇gᵀp/2, solver.max_iters, solver.time_budget.
 * The workspace of the loop is sized in setup (n known), so nothing here allocates per
 * iteration; what the callbacks allocate is theirs. */
#include <string.h>

#include "elastopt/callback.h"
#include "../solver_registry.h"
#include "descent.h"

struct eo_callback_optimizer {
    eo_optimizer_type type;   /* first member: sc->optimizer points here */
    eo_ctx *ctx;
    char *name, *summary;
    eo_callback_minimize_fn minimize;
    eo_callback_direction_fn direction;
    void *user;
    int registered;
};

typedef struct cb_state {
    eo_descent_ws w;
    const eo_callback_optimizer *o;  /* set by minimize for the direction op */
} cb_state;

static int cb_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    cb_state *st = vst;
    (void)params;
    return eo_descent_ws_init(ctx, n, &st->w);
}

static void cb_destroy(void *vst, eo_ctx *ctx)
{
    cb_state *st = vst;
    eo_descent_ws_deinit(ctx, &st->w);
}

static int cb_direction(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                        double g, const double *grad, double *p, eo_direction_out *out,
                        eo_solve_result *res)
{
    cb_state *st = vst;
    (void)params, (void)res;
    double alpha0 = 1;
    int reason = 0;
    int rc = st->o->direction(st->o->user, sc, x, g, grad, p, &alpha0, &reason);
    if (rc < 0) return rc;
    if (reason > 0) reason = 0; /* only a negative reason stops here; convergence is the rule's */
    if (!reason && !(alpha0 > 0 && isfinite(alpha0)))
        return eo_error(sc->ctx, EO_ERR_RANGE, "optimizer '%s': first trial step %g must be > 0",
                        st->o->name, alpha0);
    out->alpha0 = alpha0;
    out->reason = reason;
    return EO_OK;
}

static const eo_descent_ops cb_descent_ops = {.direction = cb_direction};

static int cb_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x,
                       eo_solve_result *res)
{
    cb_state *st = vst;
    const eo_callback_optimizer *o = (const eo_callback_optimizer *)sc->optimizer;
    if (!o || o->type.minimize != cb_minimize)
        return eo_error(sc->ctx, EO_ERR_INVALID, "callback optimizer: solver context without its table");
    st->o = o;
    if (o->direction) return eo_descent_minimize(&cb_descent_ops, st, params, sc, &st->w, x, res);

    eo_objective *obj = sc->obj;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    res->g = res->grad_norm = NAN;
    int rc = o->minimize(o->user, sc, x, res);
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    if (rc >= 0 && res->reason == 0)
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "optimizer '%s' returned without a reason", o->name);
    return rc < 0 ? rc : EO_OK;
}

static char *dup_str(eo_ctx *ctx, const char *s) { return eo_strdup(ctx, s ? s : ""); }

int eo_callback_optimizer_register(eo_ctx *ctx, const eo_callback_optimizer_def *def,
                                   eo_callback_optimizer **out)
{
    *out = NULL;
    if (!def || !def->name)
        return eo_error(ctx, EO_ERR_INVALID, "register callback optimizer: no definition or no name");
    if (!def->minimize == !def->direction)
        return eo_error(ctx, EO_ERR_INVALID,
                        "register callback optimizer '%s': set exactly one of minimize and direction",
                        def->name);
    eo_callback_optimizer *o = eo_calloc(ctx, 1, sizeof *o);
    if (!o) return eo_error(ctx, EO_ERR_NOMEM, "register callback optimizer: out of memory");
    o->ctx = ctx;
    o->name = dup_str(ctx, def->name);
    o->summary = dup_str(ctx, def->summary);
    int rc = EO_OK;
    if (!o->name || !o->summary) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "register callback optimizer: out of memory");
        goto fail;
    }
    o->minimize = def->minimize;
    o->direction = def->direction;
    o->user = def->user;
    o->type = (eo_optimizer_type){
        .info = {.name = o->name, .summary = o->summary},
        .state_size = sizeof(cb_state),
        .needs_linear = def->needs_linear ? 1 : 0,
        .needs_hessian = def->needs_hessian ? 1 : 0,
        .setup = cb_setup,
        .minimize = cb_minimize,
        .destroy = cb_destroy,
        .newton_decrement = def->newton_decrement ? 1 : 0,
    };
    EO_TRY(rc = eo_registry_add(ctx, &eo_reg_optimizer, &o->type));
    o->registered = 1;
    *out = o;
    return EO_OK;
fail:
    eo_callback_optimizer_destroy(&o);
    return rc;
}

const eo_optimizer_type *eo_callback_optimizer_type(const eo_callback_optimizer *o)
{
    return o ? &o->type : NULL;
}

void eo_callback_optimizer_destroy(eo_callback_optimizer **op)
{
    if (!op || !*op) return;
    eo_callback_optimizer *o = *op;
    if (o->registered) eo_registry_remove(&eo_reg_optimizer, &o->type);
    eo_free(o->ctx, o->name);
    eo_free(o->ctx, o->summary);
    eo_free(o->ctx, o);
    *op = NULL;
}
