/* Generic linear-solver object: one allocation holding the header, the copied params
 * and the method's private state; forwards analyze/factor/solve with timing and
 * checks the phase order and that the pattern is the analyzed one. */
#include "elastopt/linsolve.h"
#include "elastopt/objective.h"
#include "../solver_registry.h"

#include <math.h>
#include <stdalign.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

extern const eo_linsolve_type eo_linsolve_auto; /* auto.c: the policy (eo_linsolve_allows_own_factor) */

struct eo_linsolve {
    const eo_linsolve_type *type;
    eo_ctx *ctx;
    void *params;  /* copy, inside this block */
    void *state;   /* inside this block */
    int analyzed, factored, set_up;
    int expect_not_pd, warned_not_pd; /* eo_linsolve_set_expect_not_pd; the one warning given */
    int n, nnz;
    eo_linsolve_stats stats;
};

static size_t round_up(size_t s)
{
    size_t a = alignof(max_align_t);
    return (s + a - 1) / a * a;
}

int eo_linsolve_find(eo_ctx *ctx, const char *name, const eo_linsolve_type **out)
{
    const void *t = NULL;
    int rc = eo_registry_lookup(ctx, &eo_reg_linsolve, name, &t);
    *out = t;
    return rc;
}

int eo_linsolve_create(eo_ctx *ctx, const eo_linsolve_type *type, const void *params,
                       eo_linsolve **out)
{
    *out = NULL;
    if (!type) return eo_error(ctx, EO_ERR_INVALID, "linear solver: no type");
    size_t hs = round_up(sizeof(eo_linsolve)), ps = round_up(type->info.params_size);
    eo_linsolve *ls = eo_calloc(ctx, 1, hs + ps + (type->state_size ? type->state_size : 1));
    if (!ls) return eo_error(ctx, EO_ERR_NOMEM, "linear solver %s: out of memory", type->info.name);
    ls->type = type;
    ls->ctx = ctx;
    ls->params = (char *)ls + hs;
    ls->state = (char *)ls + hs + ps;
    ls->stats.not_pd_column = -1;
    ls->stats.n_negative = ls->stats.n_zero = -1;
    if (type->info.params_size) {
        if (params) memcpy(ls->params, params, type->info.params_size);
        else eo_params_default(type->info.params, ls->params);
        if (type->info.params) {
            eo_param_src src = {NULL, NULL, NULL, NULL};
            char path[96];
            snprintf(path, sizeof path, "solver.%s", type->info.name);
            src.path = path;
            int rc = eo_params_check(ctx, type->info.params, ls->params, &src);
            if (rc < 0) {
                eo_free(ctx, ls);
                return rc;
            }
        }
    }
    if (type->setup) {
        ls->set_up = 1;
        int rc = type->setup(ls->state, ls->params, ctx);
        if (rc < 0) {
            eo_linsolve_destroy(&ls);
            return rc;
        }
    }
    *out = ls;
    return EO_OK;
}

void eo_linsolve_destroy(eo_linsolve **ls)
{
    if (!ls || !*ls) return;
    eo_linsolve *s = *ls;
    if (s->type->destroy && (s->set_up || !s->type->setup)) s->type->destroy(s->state, s->ctx);
    eo_free(s->ctx, s);
    *ls = NULL;
}

int eo_linsolve_analyze(eo_linsolve *ls, const eo_csc *A)
{
    if (!A || A->n < 0)
        return eo_error(ls->ctx, EO_ERR_INVALID, "linear solver %s: no matrix", ls->type->info.name);
    ls->analyzed = ls->factored = 0;
    double t = eo_wtime(), c = eo_cputime();
    int rc = ls->type->analyze(ls->state, A, ls->ctx);
    ls->stats.t_analyze += eo_wtime() - t;
    ls->stats.c_analyze += eo_cputime() - c;
    ls->stats.n_analyze++;
    if (rc < 0) return rc;
    ls->analyzed = 1;
    ls->n = A->n;
    ls->nnz = A->nnz;
    return rc;
}

int eo_linsolve_factor(eo_linsolve *ls, const eo_csc *A)
{
    const char *name = ls->type->info.name;
    if (!ls->analyzed)
        return eo_error(ls->ctx, EO_ERR_INVALID, "linear solver %s: factor before analyze", name);
    if (!A || A->n != ls->n || A->nnz != ls->nnz)
        return eo_error(ls->ctx, EO_ERR_INVALID,
                        "linear solver %s: matrix pattern differs from the analyzed one "
                        "(n=%d nnz=%d, analyzed n=%d nnz=%d); call analyze again",
                        name, A ? A->n : -1, A ? A->nnz : -1, ls->n, ls->nnz);
    ls->factored = 0;
    ls->stats.not_pd_column = -1;
    ls->stats.n_negative = ls->stats.n_zero = -1;
    double t = eo_wtime(), c = eo_cputime();
    int quiet = eo_ctx_set_quiet_warnings(ls->ctx, 1); /* a not-PD message is reported below */
    int rc = ls->type->factor(ls->state, A, &ls->stats, ls->ctx);
    eo_ctx_set_quiet_warnings(ls->ctx, quiet);
    ls->stats.t_factor += eo_wtime() - t;
    ls->stats.c_factor += eo_cputime() - c;
    ls->stats.n_factor++;
    if (rc == EO_OK) ls->factored = 1;
    if (rc == EO_WARN_NOT_PD) {
        ls->stats.n_not_pd++;
        if (!ls->expect_not_pd && !ls->warned_not_pd && !quiet) {
            ls->warned_not_pd = 1;
            eo_log(ls->ctx, EO_LOG_WARN, "%s (a matrix expected to be positive definite; later failures of this "
                   "solver are counted as n_not_pd, not printed)", eo_ctx_message(ls->ctx));
        } else {
            eo_log(ls->ctx, EO_LOG_DEBUG, "%s", eo_ctx_message(ls->ctx));
        }
    } else if (rc > 0 && !quiet) {
        eo_log(ls->ctx, EO_LOG_WARN, "%s", eo_ctx_message(ls->ctx));
    }
    return rc;
}

int eo_linsolve_set_expect_not_pd(eo_linsolve *ls, int on)
{
    int old = ls->expect_not_pd;
    ls->expect_not_pd = on != 0;
    return old;
}

int eo_linsolve_get_expect_not_pd(const eo_linsolve *ls) { return ls->expect_not_pd; }

int eo_linsolve_solve(eo_linsolve *ls, const double *b, double *x)
{
    if (!ls->factored)
        return eo_error(ls->ctx, EO_ERR_INVALID,
                        "linear solver %s: solve without a successful factor", ls->type->info.name);
    ls->stats.iterations = 0;
    ls->stats.residual = -1;
    ls->stats.curvature = 0;
    double t = eo_wtime(), c = eo_cputime();
    int quiet = eo_ctx_set_quiet_warnings(ls->ctx, 1);
    int rc = ls->type->solve(ls->state, b, x, &ls->stats, ls->ctx);
    eo_ctx_set_quiet_warnings(ls->ctx, quiet);
    ls->stats.t_solve += eo_wtime() - t;
    ls->stats.c_solve += eo_cputime() - c;
    ls->stats.n_solve++;
    /* cg/pcg/gmres meeting pᵀAp <= 0: expected on an unprojected Hessian like a failed
     * factorization (the caller counts it, eo_solve_result.n_neg_curvature) */
    if (rc == EO_WARN_NOT_PD && (ls->expect_not_pd || ls->warned_not_pd || quiet)) {
        eo_log(ls->ctx, EO_LOG_DEBUG, "%s", eo_ctx_message(ls->ctx));
    } else if (rc == EO_WARN_NOT_PD) {
        ls->warned_not_pd = 1;
        eo_log(ls->ctx, EO_LOG_WARN, "%s (a matrix expected to be positive definite; later failures of this "
               "solver are counted, not printed)", eo_ctx_message(ls->ctx));
    } else if (rc > 0 && !quiet) {
        eo_log(ls->ctx, EO_LOG_WARN, "%s", eo_ctx_message(ls->ctx));
    }
    return rc;
}

int eo_linsolve_set_rtol(eo_linsolve *ls, double rtol)
{
    if (!(rtol < 1) || !isfinite(rtol))
        return eo_error(ls->ctx, EO_ERR_RANGE, "linear solver %s: rtol %g must be < 1", ls->type->info.name,
                        rtol);
    if (ls->type->set_rtol) ls->type->set_rtol(ls->state, rtol);
    return EO_OK;
}

int eo_linsolve_set_coordinates(eo_linsolve *ls, int nv, const double *xyz)
{
    if (nv < 0 || (nv > 0 && !xyz))
        return eo_error(ls->ctx, EO_ERR_INVALID, "linear solver %s: set_coordinates: nv %d, xyz %p",
                        ls->type->info.name, nv, (const void *)xyz);
    return ls->type->set_coordinates ? ls->type->set_coordinates(ls->state, nv, xyz, ls->ctx) : EO_OK;
}

int eo_linsolve_set_space(eo_linsolve *ls, const struct eo_vspace *space)
{
    if (ls->type->set_space) return ls->type->set_space(ls->state, space, ls->ctx);
    if (eo_vspace_distributed(space))
        return eo_error(ls->ctx, EO_ERR_UNSUPPORTED, "linear solver %s cannot solve distributed equations: it needs "
                        "the whole matrix in one process; use petsc_ksp", ls->type->info.name);
    return EO_OK;
}

const eo_linsolve_stats *eo_linsolve_get_stats(const eo_linsolve *ls) { return &ls->stats; }

void eo_linsolve_forget(eo_linsolve *ls)
{
    if (ls && ls->type->forget) ls->type->forget(ls->state);
}

int eo_linsolve_is_iterative(const eo_linsolve *ls)
{
    return ls->type->is_iterative ? ls->type->is_iterative(ls->state) != 0 : ls->type->set_rtol != NULL;
}

const char *eo_linsolve_describe(const eo_linsolve *ls, char *buf, size_t size)
{
    if (!size) return buf;
    buf[0] = 0;
    if (ls->type->describe) ls->type->describe(ls->state, buf, size);
    if (!buf[0]) snprintf(buf, size, "%s", ls->type->info.name);
    return buf;
}

int eo_linsolve_allows_own_factor(const eo_linsolve *ls)
{
    return strncmp(ls->type->info.name, "cholmod", 7) == 0 || ls->type == &eo_linsolve_auto;
}
const eo_linsolve_type *eo_linsolve_get_type(const eo_linsolve *ls) { return ls->type; }
const void *eo_linsolve_get_params(const eo_linsolve *ls) { return ls->params; }
