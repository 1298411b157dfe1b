/* Newton's method with a line search (registry key "newton").
 *
 * Quadratic model at x (002 eq. 9, remainder O(‖p‖³)):
 *     g(x + p) ≈ g(x) + ∇gᵀp + ½ pᵀ H p,     H = ∇²g(x) (assembled with the Hessian fix's
 *                                                     per-element projection)
 * Direction     p = −(H + cI)⁻¹ ∇g           (002 eq. 10 with Note 4's shift c ≥ 0)
 * Decrement     λ² = ∇gᵀ(H + cI)⁻¹∇g = −∇gᵀp  (ERRATA for 002 Def. 4); the stopping rule
 *               newton_decrement stops when λ²/2 ≤ tol, λ²/2 estimating g(x) − g*.
 * Line search   x ← x + αp, first trial α = 1 (the configured solver.linesearch); a
 *               trial where g = +∞ (inverted element of a barrier material) is rejected
 *               and the step shrunk by the line search.
 *
 * Linear algebra: the Hessian pattern is fixed for an objective, so
 * eo_linsolve_analyze runs once per pattern (the H pointer and its colptr/rowind arrays
 * are remembered; a new pattern is analyzed again) and eo_linsolve_factor at every
 * factorization. The shift c is added in place to the stored diagonal (the last entry
 * of each CSC column, see sparse.h) and the original diagonal restored after the
 * solve; nothing is allocated.
 *
 * Hessian fixes (sc->hessfix; shift parameters from sc->hessfix_params, see
 * eo_hessfix_shift_params; s = mean |H_ii|, c_min = shift_init·s, c_max = shift_max·s):
 *   shift        c starts at the value carried over from the previous iteration (0 at
 *                the first). If the factorization reports EO_WARN_NOT_PD or p is not a
 *                descent direction (∇gᵀp ≥ −descent_eps·‖∇g‖‖p‖), c ← max(c_min,
 *                shift_grow·c) and H + cI is factored again; c > c_max ends the run with
 *                EO_DIVERGED_NOT_PD. After success the next iteration starts at
 *                c/shift_shrink, or at 0 when that is below c_min (Nocedal & Wright,
 *                Numerical Optimization, Alg. 3.3, with the shift carried over).
 *   clamp, abs   H is assembled from per-element projected Hessians (PSD), c = 0; if the
 *                factorization still fails (e.g. rigid modes of a static problem make
 *                the projected H only semi-definite) the same shift logic runs as a
 *                safeguard. Iterations that needed c > 0 are counted in res.n_shifted.
 *   none         one factorization of the true H; if it is not PD or p is not a descent
 *                direction, this iteration uses the steepest-descent direction p = −∇g
 *                (counted in res.n_fallback), so the run always ends with a reason. The
 *                "decrement" of such an iteration is ‖∇g‖²/2, not a Newton decrement.
 * A factorization or solve error (negative status) ends the run with
 * EO_DIVERGED_LINSOLVE (status in res.status); a non-finite Hessian diagonal with
 * EO_DIVERGED_NONFINITE. */
#include <stddef.h>
#include <string.h>

#include "descent.h"

typedef struct newton_state {
    eo_descent_ws w;
    double *diag;           /* n: saved diagonal of H */
    const eo_csc *H;        /* pattern last analyzed */
    const int *colptr, *rowind;
    int pn, pnnz;
    double c_next;          /* shift to start the next iteration with */
    eo_ctx *ctx;
} newton_state;

static const eo_param_desc newton_desc[] = {
    {.key = "descent_eps", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, descent_eps),
     .def.d = 1e-12, .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "p is a descent direction iff grad'p < -eps*|grad|*|p|"},
    {0},
};

static int newton_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    newton_state *st = vst;
    (void)params;
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->diag);
    memset(st, 0, sizeof *st);
    st->ctx = ctx;
    int rc = eo_descent_ws_init(ctx, n, &st->w);
    if (rc < 0) return rc;
    st->diag = eo_calloc(ctx, (size_t)(n > 0 ? n : 1), sizeof(double));
    if (!st->diag) return eo_error(ctx, EO_ERR_NOMEM, "newton: out of memory");
    return EO_OK;
}

static void newton_destroy(void *vst, eo_ctx *ctx)
{
    newton_state *st = vst;
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->diag);
    st->diag = NULL;
}

static int newton_begin(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                        double g, const double *grad, eo_solve_result *res)
{
    newton_state *st = vst;
    (void)params, (void)x, (void)g, (void)grad, (void)res;
    st->c_next = 0;
    if (!sc->linear) return eo_error(sc->ctx, EO_ERR_INVALID, "newton needs a linear solver");
    return EO_OK;
}

static void set_diag(eo_csc *H, const double *d, double c)
{
    for (int j = 0; j < H->n; j++) H->val[H->colptr[j + 1] - 1] = d[j] + c;
}

static int newton_direction(void *vst, const void *params, const eo_solver_ctx *sc,
                            const double *x, double g, const double *grad, double *p,
                            eo_direction_out *out, eo_solve_result *res)
{
    newton_state *st = vst;
    const eo_newton_params *np = params;
    const eo_hessfix_type *hf = sc->hessfix;
    eo_hessfix_shift_params hp;
    const int n = sc->obj->n;
    eo_csc *H = NULL;
    (void)g;

    if (sc->hessfix_params) hp = *(const eo_hessfix_shift_params *)sc->hessfix_params;
    else eo_params_default(eo_hessfix_shift_params_desc, &hp);

    int rc = eo_objective_hessian(sc->obj, x, hf->elem_proj, &H);
    if (rc < 0) return rc;
    if (!H || H->n != n)
        return eo_error(sc->ctx, EO_ERR_INVALID, "newton: Hessian has n = %d, objective has n = %d",
                        H ? H->n : -1, n);
    if (H != st->H || H->colptr != st->colptr || H->rowind != st->rowind || H->n != st->pn ||
        H->nnz != st->pnnz) {
        for (int j = 0; j < n; j++) {
            int e = H->colptr[j + 1] - 1;
            if (e < H->colptr[j] || H->rowind[e] != j)
                return eo_error(sc->ctx, EO_ERR_INVALID,
                                "newton: Hessian column %d has no stored diagonal entry", j);
        }
        st->H = NULL;
        rc = eo_linsolve_analyze(sc->linear, H);
        if (rc < 0) {
            res->status = rc;
            out->reason = EO_DIVERGED_LINSOLVE;
            return EO_OK;
        }
        st->H = H;
        st->colptr = H->colptr;
        st->rowind = H->rowind;
        st->pn = H->n;
        st->pnnz = H->nnz;
    }

    double s = 0;
    for (int j = 0; j < n; j++) {
        st->diag[j] = H->val[H->colptr[j + 1] - 1];
        s += fabs(st->diag[j]);
    }
    if (!isfinite(s)) {
        out->reason = EO_DIVERGED_NONFINITE;
        return EO_OK;
    }
    s = n > 0 && s > 0 ? s / n : 1;
    const int shifting = hf->shifts || hf->safeguard;
    const double c_min = hp.shift_init * s, c_max = hp.shift_max * s;
    const double gnorm = eo_norm2(n, grad);
    double c = shifting ? st->c_next : 0;

    for (;;) {
        int good = 0;
        if (c > 0) set_diag(H, st->diag, c);
        int frc = eo_linsolve_factor(sc->linear, H);
        res->n_factor++;
        if (frc >= 0 && frc != EO_WARN_NOT_PD) {
            frc = eo_linsolve_solve(sc->linear, grad, p);
            if (frc >= 0 && frc != EO_WARN_NOT_PD) {
                for (int i = 0; i < n; i++) p[i] = -p[i];
                double dg = eo_dot(n, grad, p), pn = eo_norm2(n, p);
                good = isfinite(dg) && isfinite(pn) && dg < -np->descent_eps * gnorm * pn;
            }
        }
        if (c > 0) set_diag(H, st->diag, 0);
        if (frc < 0) {
            res->status = frc;
            out->reason = EO_DIVERGED_LINSOLVE;
            return EO_OK;
        }
        if (good) break;
        if (!shifting) {
            for (int i = 0; i < n; i++) p[i] = -grad[i];
            res->n_fallback++;
            eo_log(sc->ctx, EO_LOG_DEBUG, "newton: Hessian not positive definite, steepest descent");
            c = 0;
            break;
        }
        c = c * hp.shift_grow > c_min ? c * hp.shift_grow : c_min;
        if (!(c <= c_max)) {
            out->reason = EO_DIVERGED_NOT_PD;
            out->shift = c;
            return EO_OK;
        }
    }
    if (c > 0) {
        res->n_shifted++;
        st->c_next = c / hp.shift_shrink >= c_min ? c / hp.shift_shrink : 0;
    } else {
        st->c_next = 0;
    }
    out->shift = c;
    out->alpha0 = 1;
    return EO_OK;
}

static const eo_descent_ops newton_ops = {
    .begin = newton_begin,
    .direction = newton_direction,
    .accepted = NULL,
};

static int newton_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x,
                           eo_solve_result *res)
{
    newton_state *st = vst;
    eo_newton_params def;
    if (!params) {
        eo_params_default(newton_desc, &def);
        params = &def;
    }
    return eo_descent_minimize(&newton_ops, st, params, sc, &st->w, x, res);
}

const eo_optimizer_type eo_optimizer_newton = {
    .info = {.name = "newton",
             .summary = "Newton's method: p = -(H + cI)^-1 grad, line search, Hessian fix",
             .params = newton_desc,
             .params_size = sizeof(eo_newton_params)},
    .state_size = sizeof(newton_state),
    .needs_linear = 1,
    .needs_hessian = 1,
    .setup = newton_setup,
    .minimize = newton_minimize,
    .destroy = newton_destroy,
};
