/* Mixed variational FEM (registry key "mixed_fem").
 *
 * Paper       Trusty, Chen, Levin & Kaufman, "Mixed Variational Finite Elements for
 *             Implicit Simulation of Deformables", SIGGRAPH Asia 2022 (ACM TOG 41(6));
 *             the variant of the authors' reference code (github tytrusty/mfem,
 *             src/variables/mixed_stretch.cpp and src/optimizers/newton_optimizer.cpp:
 *             the "mixed-stretch" variable with the Newton optimizer), read to
 *             understand the algorithm, written again here.
 * Problem     each linear tet e gets a symmetric stretch variable sₑ (3×3, stored as 9
 *             symmetric entries; the paper's 6 with weights diag(1,1,1,2,2,2) give the
 *             same inner product) and a multiplier Λₑ, and the step objective
 *             g(x) = Φ(x) + w Σₑ Vₑ ψₑ(Fₑ(x)) (Φ: inertia, gravity, springs, contact, …;
 *             objective split ops, objective.h) becomes the saddle point of
 *                 L(x, s, Λ) = Φ(x) + w Σₑ Vₑ [ ψₑ(sₑ) + Λₑ : (S(Fₑ(x)) − sₑ) ],
 *             S(F) = V Σ Vᵀ the polar stretch of the signed SVD F = U Σ Vᵀ (F = R S,
 *             R = U Vᵀ ∈ SO(3)), ψ(s) the material at F = s (rotation invariance:
 *             ψ(F) = ψ(S(F)); for isotropic models ψ(s) is ψ of the signed singular
 *             values of s, its gradient ψ'(s) = P(s) and its Hessian the restriction of
 *             ∂P/∂F at F = s to symmetric directions, which that operator preserves;
 *             the Hessian's projection is the material kernel's clamp of its nine
 *             analytic modes, materials/kernel.c).
 * Iteration   an SQP (Newton on the KKT system with the constraint curvature
 *             Λ : ∂²S/∂F² dropped, as the paper and its code do) in which s and Λ are
 *             eliminated per element, leaving ONE displacement-sized SPD system:
 *               Js = ∂vec S/∂vec F at Fₑ(x) (dŜ = Vᵀ dS V: dŜᵢᵢ = dF̂ᵢᵢ,
 *                    dŜᵢⱼ = (σᵢ dF̂ᵢⱼ + σⱼ dF̂ⱼᵢ)/(σᵢ + σⱼ), dF̂ = Uᵀ dF V),
 *               H = ψ''(sₑ) projected (solver.mixed_fem.proj), Kₑ = Vₑ JsᵀH Js,
 *               (∇²Φ + w Σₑ GₑᵀKₑGₑ) dx = −∇Φ − w Σₑ Vₑ GₑᵀJsᵀ[ψ'(sₑ) + H(S(Fₑ) − sₑ)]
 *             (objective op split_assemble for the matrix; the right side is −∇g(x)
 *             plus w Σ GᵀVₑ[P(Fₑ) − Jsᵀ(…)] by split_adjoint, since JsᵀP(S) = P(F)),
 *             factored with solver.linear; then per element
 *               dsₑ = S(Fₑ) − sₑ + Js Gₑdx,     Λₑ = ψ'(sₑ) + H dsₑ.
 *             At sₑ = S(Fₑ) the direction is a Gauss–Newton step on g; the system
 *             needs no indefinite Hessian and no eigenvalue projection beyond ψ''(s)'s.
 * Line search backtracking on the paper's merit function (the Lagrangian with the new Λ
 *             held fixed) along (dx, ds):
 *               m(α) = g(x + α dx) + w Σₑ Vₑ [ψ(sₑ + α dsₑ) − ψ(Fₑ) + Λₑ:(S(Fₑ) − sₑ − α dsₑ)]
 *             (Fₑ at x + α dx; g carries w Σ Vψ(F), which the bracket removes), first
 *             trial α = 1, α halved (the code's factor 0.5) while m(α) ≥ m(0) (the code's
 *             sufficient-decrease constant c = 0), at most ls_max = 20 trials (the code's
 *             max_linesearch_iterations). A failed search ends the run with
 *             EO_DIVERGED_LINESEARCH (the code keeps iterating from the same point).
 * Start       x₀ as given, sₑ = S(Fₑ(x₀)), Λ = 0 (the code's reset: s from the initial
 *             positions, λ = 0 after every step).
 * Stopping    the shared convergence test eo_solver_stop_check on ∇g(x) of the primal
 *             objective at every iterate (the metric gradient ratio of the default rule;
 *             one gradient call per iteration), instead of the code's ‖(dx, ds)‖∞ ≤ 1e-10
 *             or a relative change of m below 1e-12: the primal gradient is what its
 *             convergence app plots and what every optimizer here is judged by. The
 *             direction is not a Newton direction of g (newton_decrement = 0).
 * Differs     (1) s starts from S(F(x₀)) every minimization (the code keeps s from the
 *             previous time step, which equals S(F(xₙ)) at a converged step; x₀ is the
 *             integrator's guess here); (2) the polar decomposition is the signed SVD
 *             (eo_svd3), not Newton's method on SO(3) warm-started from the last R;
 *             (3) ψ(s) and its derivatives are the library's isotropic materials through
 *             eo_material_evaluate (the code writes SNH, ARAP, … as polynomials in the 6
 *             entries of s and projects the 6×6 Hessian with an eigensolver); (4) a
 *             trial whose merit change is within rounding (|m(α) − m(0)| ≤ 64ε·Σ|terms|)
 *             is accepted, so that the search does not fail at the rounding floor;
 *             (5) where rounding breaks the system's positive definiteness (the
 *             derivative of the polar stretch grows like 1/(σᵢ + σⱼ), unbounded at a
 *             flat or inverted tet with σ₂ + σ₃ = 0) the factorization is retried with
 *             H + cI, c = 1e-8·max Hᵢᵢ growing 10x (at most 12 times; res.n_shifted);
 *             (6) contact and friction stay penalty terms inside Φ (the paper also mixes
 *             collisions; not here). F-space models (no ψ(σ): `linear`) are refused at
 *             the first minimize. Linear tets only (needs the split ops).
 * Cost        per iteration and element two SVDs (F and s), P(F), ψ''(s) and
 *             JsᵀHJs (2·729 flops); per line-search trial one SVD of F plus ψ(F), ψ(s);
 *             one assembly, factorization and solve. The constraint residual
 *             max‖sₑ − S(Fₑ)‖_F at the end is logged at debug level.
 * Memory      4 vectors of n; per element 3·81 + 8·9 doubles, sized at the first minimize
 *             of a larger element count; nothing inside the iterations. */
#include <float.h>
#include <stddef.h>
#include <string.h>

#include "descent.h"
#include "external.h" /* eo_external_inverted */
#include "elastopt/material.h"

/// Parameters (config `solver.mixed_fem.*`).
typedef struct eo_mixed_fem_params {
    char proj[16];   ///< projection of ψ''(s) and of the other terms' Hessians: "clamp"
                     ///< (default) or "abs"
    int ls_max;      ///< line-search trials (halvings) at most (default 20)
} eo_mixed_fem_params;

static const char *const proj_names[] = {"clamp", "abs", NULL};

static const eo_param_desc mixed_desc[] = {
    {.key = "proj", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_mixed_fem_params, proj),
     .size = sizeof(((eo_mixed_fem_params *)0)->proj), .def.s = "clamp", .choices = proj_names,
     .help = "projection of the stretch Hessian psi''(s) (its nine analytic modes) and of the other terms' "
             "Hessians: clamp (negative eigenvalues to 0) or abs"},
    {.key = "ls_max", .kind = EO_PARAM_INT, .offset = offsetof(eo_mixed_fem_params, ls_max), .def.i = 20,
     .min = 1, .max = 200, .range = EO_RANGE_CLOSED,
     .help = "backtracking trials (alpha halved) on the merit function at most; then the run ends "
             "(line search failed)"},
    {0},
};

typedef struct mixed_state {
    int n;
    double *buf;
    double *grad, *rhs, *dx, *xt;   /* n each */
    double *ebuf;
    double *s, *ds, *F, *Ft, *SF, *Ps, *Lam, *str; /* 9E each */
    double *Js, *Hs, *K;            /* 81E each */
    int ne_cap;
    const eo_csc *H;                /* pattern last analyzed */
    const int *colptr, *rowind;
    int pn, pnnz;
} mixed_state;

static void mixed_free(mixed_state *st, eo_ctx *ctx)
{
    eo_free(ctx, st->buf);
    eo_free(ctx, st->ebuf);
    st->buf = st->ebuf = NULL;
    st->ne_cap = 0;
}

static int mixed_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    mixed_state *st = vst;
    (void)params;
    mixed_free(st, ctx);
    memset(st, 0, sizeof *st);
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "mixed_fem: n = %d < 0", n);
    const size_t nn = (size_t)(n > 0 ? n : 1);
    st->buf = eo_calloc(ctx, 4 * nn, sizeof(double));
    if (!st->buf) return eo_error(ctx, EO_ERR_NOMEM, "mixed_fem: out of memory (n = %d)", n);
    st->grad = st->buf, st->rhs = st->buf + nn, st->dx = st->buf + 2 * nn, st->xt = st->buf + 3 * nn;
    st->n = n;
    return EO_OK;
}

static void mixed_destroy(void *vst, eo_ctx *ctx) { mixed_free(vst, ctx); }

static int ensure_elements(mixed_state *st, int ne, eo_ctx *ctx)
{
    if (ne <= st->ne_cap) return EO_OK;
    eo_free(ctx, st->ebuf);
    const size_t m = 9 * (size_t)(ne > 0 ? ne : 1);
    st->ebuf = eo_calloc(ctx, 8 * m + 3 * 9 * m, sizeof(double));
    if (!st->ebuf) {
        st->ne_cap = 0;
        return eo_error(ctx, EO_ERR_NOMEM, "mixed_fem: out of memory (%d elements)", ne);
    }
    double *p = st->ebuf;
    st->s = p, p += m;
    st->ds = p, p += m;
    st->F = p, p += m;
    st->Ft = p, p += m;
    st->SF = p, p += m;
    st->Ps = p, p += m;
    st->Lam = p, p += m;
    st->str = p, p += m;
    st->Js = p, p += 9 * m;
    st->Hs = p, p += 9 * m;
    st->K = p;
    st->ne_cap = ne;
    return EO_OK;
}

static int is_element(const eo_objective_split *sp, int e) { return !(sp->type[e]->flags & EO_MATERIAL_EDGE); }

static void sym3(double A[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++) A[3 * i + j] = A[3 * j + i] = 0.5 * (A[3 * i + j] + A[3 * j + i]);
}

/* The polar stretch S = V Σ Vᵀ of F (signed SVD) and, unless Js is NULL, its derivative
 * Js[(3p+q)·9 + (3a+b)] = ∂S_pq/∂F_ab (file comment). */
static void polar_stretch(const double F[9], double S[9], double Js[81])
{
    double U[9], sg[3], V[9];
    eo_svd3(F, U, sg, V);
    for (int p = 0; p < 3; p++)
        for (int q = 0; q < 3; q++)
            S[3 * p + q] = V[3 * p] * sg[0] * V[3 * q] + V[3 * p + 1] * sg[1] * V[3 * q + 1] +
                           V[3 * p + 2] * sg[2] * V[3 * q + 2];
    sym3(S);
    if (!Js) return;
    const double floor = 1e-12 * fmax(fabs(sg[0]), DBL_MIN);
    double inv[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = sg[i] + sg[j];
            if (fabs(d) < floor) d = d < 0 ? -floor : floor;
            inv[i][j] = 1 / d;
        }
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double dS[3][3]; /* in the V frame */
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) {
                    const double fij = U[3 * a + i] * V[3 * b + j], fji = U[3 * a + j] * V[3 * b + i];
                    dS[i][j] = i == j ? fij : (sg[i] * fij + sg[j] * fji) * inv[i][j];
                }
            double T[3][3]; /* dS Vᵀ */
            for (int i = 0; i < 3; i++)
                for (int q = 0; q < 3; q++) T[i][q] = dS[i][0] * V[3 * q] + dS[i][1] * V[3 * q + 1] + dS[i][2] * V[3 * q + 2];
            for (int p = 0; p < 3; p++)
                for (int q = p; q < 3; q++) {
                    const double v = V[3 * p] * T[0][q] + V[3 * p + 1] * T[1][q] + V[3 * p + 2] * T[2][q];
                    Js[(3 * p + q) * 9 + 3 * a + b] = v;
                    Js[(3 * q + p) * 9 + 3 * a + b] = v;
                }
        }
}

static inline double dot9(const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < 9; i++) s += a[i] * b[i];
    return s;
}
static inline void matvec9(const double *A, const double *x, double *y)
{
    for (int i = 0; i < 9; i++) y[i] = dot9(A + 9 * i, x);
}

/* Per-element linearization at F = F(x) and s: SF, Js, Ps, Hs, K and the right-side
 * stresses str = V(P(F) − Jsᵀ(Ps + Hs(SF − s))). *bad = 1 where ψ(s) or ψ(F) is +∞. */
static int linearize(mixed_state *st, const eo_objective_split *sp, eo_proj proj, eo_ctx *ctx, int *bad)
{
    *bad = 0;
    for (int e = 0; e < sp->ne; e++) {
        const size_t o9 = 9 * (size_t)e, o81 = 81 * (size_t)e;
        double *K = st->K + o81, *str = st->str + o9;
        if (!is_element(sp, e)) {
            memset(K, 0, 81 * sizeof(double));
            memset(str, 0, 9 * sizeof(double));
            continue;
        }
        const eo_material_type *mt = sp->type[e];
        const eo_material_coef *c = sp->coef[e];
        const double V = sp->vol[e];
        double *Js = st->Js + o81, *Hs = st->Hs + o81, *SF = st->SF + o9, *Ps = st->Ps + o9;
        const double *s = st->s + o9, *F = st->F + o9;
        polar_stretch(F, SF, Js);
        eo_material_eval ev;
        int rc = eo_material_evaluate(mt, c, s, EO_EVAL_HESS, proj, &ev);
        if (rc < 0) return eo_error(ctx, rc, "mixed_fem: material of element %d at its stretch s", e);
        if (!isfinite(ev.psi)) {
            *bad = 1;
            return EO_OK;
        }
        memcpy(Ps, ev.P, sizeof ev.P);
        sym3(Ps);
        memcpy(Hs, ev.dPdF, sizeof ev.dPdF);
        double HJ[81], r[9], lam[9];
        for (int i = 0; i < 9; i++)
            for (int j = 0; j < 9; j++) {
                double sum = 0;
                for (int k = 0; k < 9; k++) sum += Hs[9 * i + k] * Js[9 * k + j];
                HJ[9 * i + j] = sum;
            }
        for (int i = 0; i < 9; i++)
            for (int j = i; j < 9; j++) {
                double sum = 0;
                for (int k = 0; k < 9; k++) sum += Js[9 * k + i] * HJ[9 * k + j];
                K[9 * i + j] = K[9 * j + i] = V * sum;
            }
        for (int i = 0; i < 9; i++) r[i] = SF[i] - s[i];
        matvec9(Hs, r, lam);
        for (int i = 0; i < 9; i++) lam[i] += Ps[i];
        sym3(lam);
        rc = eo_material_evaluate(mt, c, F, EO_EVAL_GRAD, EO_PROJ_NONE, &ev);
        if (rc < 0) return eo_error(ctx, rc, "mixed_fem: material of element %d", e);
        if (!isfinite(ev.psi)) {
            *bad = 1;
            return EO_OK;
        }
        for (int j = 0; j < 9; j++) {
            double sum = 0;
            for (int k = 0; k < 9; k++) sum += Js[9 * k + j] * lam[k];
            str[j] = V * (ev.P[j] - sum);
        }
    }
    return EO_OK;
}

/* The merit's element part at F (st->Ft or st->F) and s + α ds:
 * w Σ V[ψ(s + α ds) − ψ(F) + Λ:(S(F) − s − α ds)], and *mag the sum of the magnitudes of
 * its terms (for the rounding test). +∞ where ψ is. */
static double merit_elements(mixed_state *st, const eo_objective_split *sp, const double *F, double alpha,
                             const double *Lam, double *mag)
{
    double m = 0, a = 0;
    for (int e = 0; e < sp->ne; e++) {
        if (!is_element(sp, e)) continue;
        const size_t o9 = 9 * (size_t)e;
        const eo_material_type *mt = sp->type[e];
        const eo_material_coef *c = sp->coef[e];
        double sa[9], S[9];
        for (int i = 0; i < 9; i++) sa[i] = st->s[o9 + i] + alpha * st->ds[o9 + i];
        eo_material_eval ev;
        if (eo_material_evaluate(mt, c, sa, EO_EVAL_ENERGY, EO_PROJ_NONE, &ev) < 0 || !isfinite(ev.psi))
            return INFINITY;
        const double psi_s = ev.psi;
        if (eo_material_evaluate(mt, c, F + o9, EO_EVAL_ENERGY, EO_PROJ_NONE, &ev) < 0 || !isfinite(ev.psi))
            return INFINITY;
        const double psi_F = ev.psi;
        polar_stretch(F + o9, S, NULL);
        double cst = 0;
        if (Lam)
            for (int i = 0; i < 9; i++) cst += Lam[o9 + i] * (S[i] - sa[i]);
        const double V = sp->vol[e];
        m += V * (psi_s - psi_F + cst);
        a += V * (fabs(psi_s) + fabs(psi_F) + fabs(cst));
    }
    *mag = sp->w * a;
    return isfinite(m) ? sp->w * m : INFINITY;
}

static double max_constraint_residual(mixed_state *st, const eo_objective_split *sp)
{
    double r = 0;
    for (int e = 0; e < sp->ne; e++) {
        if (!is_element(sp, e)) continue;
        double S[9];
        polar_stretch(st->F + 9 * (size_t)e, S, NULL);
        double d2 = 0;
        for (int i = 0; i < 9; i++) d2 += (S[i] - st->s[9 * (size_t)e + i]) * (S[i] - st->s[9 * (size_t)e + i]);
        r = fmax(r, sqrt(d2));
    }
    return r;
}

static int mixed_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    mixed_state *st = vst;
    eo_mixed_fem_params def;
    const eo_mixed_fem_params *pp = params;
    if (!pp) {
        eo_params_default(mixed_desc, &def);
        pp = &def;
    }
    const eo_proj proj = strcmp(pp->proj, "abs") == 0 ? EO_PROJ_ABS : EO_PROJ_CLAMP;
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    double g = NAN, gn = NAN, gn0 = NAN, g_prev = NAN, step_norm = NAN;
    int rc = EO_OK, reason = 0, k = 0, bad = 0;
    eo_objective_split sp;
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (n != st->n) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "mixed_fem set up for n = %d; called with %d", st->n, n);
        goto done;
    }
    if (!sc->linear) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "mixed_fem needs a linear solver");
        goto done;
    }
    rc = eo_objective_split_get(obj, &sp);
    if (rc == EO_OK && !obj->ops->split_assemble) rc = EO_ERR_UNSUPPORTED;
    if (rc == EO_ERR_UNSUPPORTED) {
        rc = eo_error(sc->ctx, EO_ERR_UNSUPPORTED,
                      "mixed_fem needs an objective with elastic elements (the split ops of a step problem "
                      "with linear tets, split_assemble included)");
        goto done;
    }
    if (rc < 0) goto done;
    for (int e = 0; e < sp.ne; e++)
        if (is_element(&sp, e) && !sp.type[e]->sigma_eval) {
            rc = eo_error(sc->ctx, EO_ERR_UNSUPPORTED,
                          "mixed_fem: material '%s' of element %d is not isotropic (no psi(sigma)): the stretch "
                          "variable s = S(F) needs psi(F) = psi(S(F)); use an isotropic model",
                          sp.type[e]->info.name, e);
            goto done;
        }
    rc = ensure_elements(st, sp.ne, sc->ctx);
    if (rc < 0) goto done;
    rc = eo_objective_gradient(obj, x, &g, st->grad);
    if (rc < 0) goto done;
    gn = gn0 = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
    rc = obj->ops->split_apply(obj->data, x, st->F);
    if (rc < 0) goto done;
    for (int e = 0; e < sp.ne; e++) polar_stretch(st->F + 9 * (size_t)e, st->s + 9 * (size_t)e, NULL);
    for (k = 0;; k++) {
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .ls_evals = 0, .shift = 0, .inverted = eo_external_inverted(sc, x),
                             .reason = 0, .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .decrement0 = 0, .decrement_prev = 0,
                           .step_norm = step_norm, .x_norm = eo_norm2(n, x), .tol = sc->tol};
        if (!reason && (!isfinite(g) || !isfinite(gn))) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, st->grad);
        if (!reason && sc->time_budget > 0 && eo_wtime() - t0 > sc->time_budget) reason = EO_DIVERGED_TIME_BUDGET;
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        double alpha = NAN;
        int nls = 0;
        if (!reason) { /* the condensed system and the direction */
            const double ta = eo_wtime(), ca = eo_cputime();
            rc = linearize(st, &sp, proj, sc->ctx, &bad);
            if (rc < 0) goto done;
            if (bad) reason = EO_DIVERGED_NONFINITE;
            eo_csc *H = NULL;
            if (!reason) {
                rc = obj->ops->split_adjoint(obj->data, st->str, st->rhs);
                if (rc < 0) goto done;
                for (int i = 0; i < n; i++) st->rhs[i] = sp.w * st->rhs[i] - st->grad[i];
                rc = eo_objective_split_assemble(obj, x, st->K, sp.w, proj, &H);
                if (rc < 0) goto done;
            }
            res->t_assembly += eo_wtime() - ta;
            res->c_assembly += eo_cputime() - ca;
            res->n_assembly++;
            if (!reason && (H != st->H || H->colptr != st->colptr || H->rowind != st->rowind || H->n != st->pn ||
                            H->nnz != st->pnnz)) {
                st->H = NULL;
                int lr = eo_linsolve_analyze(sc->linear, H);
                if (lr < 0) {
                    res->status = lr;
                    reason = EO_DIVERGED_LINSOLVE;
                } else {
                    st->H = H, st->colptr = H->colptr, st->rowind = H->rowind, st->pn = H->n, st->pnnz = H->nnz;
                }
            }
            if (!reason) { /* safeguard: H + cI, c = 1e-8·max Hᵢᵢ growing 10x, where rounding
                              * (a polar stretch derivative near σᵢ + σⱼ = 0) breaks PD */
                int lr = eo_linsolve_factor(sc->linear, H);
                res->n_factor++;
                double dmax = 0, shift = 0, c = 0;
                if (lr == EO_WARN_NOT_PD)
                    for (int j = 0; j < n; j++) dmax = fmax(dmax, fabs(H->val[H->colptr[j + 1] - 1]));
                for (int t = 0; lr == EO_WARN_NOT_PD && t < 12 && dmax > 0; t++) {
                    c = c > 0 ? 10 * c : 1e-8 * dmax;
                    for (int j = 0; j < n; j++) H->val[H->colptr[j + 1] - 1] += c - shift;
                    shift = c;
                    lr = eo_linsolve_factor(sc->linear, H);
                    res->n_factor++;
                }
                if (shift > 0) res->n_shifted++;
                info.shift = shift;
                if (lr < 0) {
                    res->status = lr;
                    reason = EO_DIVERGED_LINSOLVE;
                } else if (lr == EO_WARN_NOT_PD) {
                    reason = EO_DIVERGED_NOT_PD;
                }
            }
            if (!reason) {
                int lr = eo_linsolve_solve(sc->linear, st->rhs, st->dx);
                if (lr < 0) {
                    res->status = lr;
                    reason = EO_DIVERGED_LINSOLVE;
                }
            }
        }
        if (!reason) { /* ds, Λ from the linearized constraint and the s-stationarity */
            for (int i = 0; i < n; i++) st->xt[i] = x[i] + st->dx[i];
            rc = obj->ops->split_apply(obj->data, st->xt, st->Ft);
            if (rc < 0) goto done;
            for (int e = 0; e < sp.ne; e++) {
                const size_t o9 = 9 * (size_t)e, o81 = 81 * (size_t)e;
                double *ds = st->ds + o9, *Lam = st->Lam + o9;
                if (!is_element(&sp, e)) {
                    memset(ds, 0, 9 * sizeof(double));
                    memset(Lam, 0, 9 * sizeof(double));
                    continue;
                }
                double dF[9], dS[9];
                for (int i = 0; i < 9; i++) dF[i] = st->Ft[o9 + i] - st->F[o9 + i];
                matvec9(st->Js + o81, dF, dS);
                for (int i = 0; i < 9; i++) ds[i] = st->SF[o9 + i] - st->s[o9 + i] + dS[i];
                sym3(ds);
                matvec9(st->Hs + o81, ds, Lam);
                for (int i = 0; i < 9; i++) Lam[i] += st->Ps[o9 + i];
                sym3(Lam);
            }
            /* the merit's backtracking */
            const double tl = eo_wtime(), cl = eo_cputime();
            double mag0 = 0;
            const double m0 = g + merit_elements(st, &sp, st->F, 0, st->Lam, &mag0);
            const double tol_round = 64 * DBL_EPSILON * (fabs(g) + mag0);
            alpha = 1;
            int ok = 0;
            double gt = NAN;
            for (nls = 1; nls <= pp->ls_max; nls++) {
                for (int i = 0; i < n; i++) st->xt[i] = x[i] + alpha * st->dx[i];
                rc = eo_objective_value(obj, st->xt, &gt);
                if (rc < 0) goto done;
                if (isfinite(gt)) {
                    rc = obj->ops->split_apply(obj->data, st->xt, st->Ft);
                    if (rc < 0) goto done;
                    double mag = 0;
                    const double m = gt + merit_elements(st, &sp, st->Ft, alpha, st->Lam, &mag);
                    if (m < m0 || (isfinite(m) && fabs(m - m0) <= tol_round)) {
                        ok = 1;
                        break;
                    }
                }
                alpha *= 0.5;
            }
            if (nls > pp->ls_max) nls = pp->ls_max;
            res->t_linesearch += eo_wtime() - tl;
            res->c_linesearch += eo_cputime() - cl;
            res->n_ls_evals += nls;
            if (!ok) reason = EO_DIVERGED_LINESEARCH;
        }
        if (reason) {
            info.reason = reason;
            info.ls_evals = nls;
            eo_solver_report(sc, t0, &info);
            break;
        }
        info.alpha = alpha;
        info.ls_evals = nls;
        if (eo_solver_report(sc, t0, &info)) {
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        double s2 = 0;
        for (int i = 0; i < n; i++) {
            x[i] = st->xt[i];
            s2 += alpha * alpha * st->dx[i] * st->dx[i];
        }
        for (size_t i = 0; i < 9 * (size_t)sp.ne; i++) st->s[i] += alpha * st->ds[i];
        memcpy(st->F, st->Ft, 9 * (size_t)sp.ne * sizeof(double));
        step_norm = sqrt(s2);
        g_prev = g;
        const double tg = eo_wtime(), cg = eo_cputime();
        rc = eo_objective_gradient(obj, x, &g, st->grad);
        res->t_gradient += eo_wtime() - tg;
        res->c_gradient += eo_cputime() - cg;
        res->n_gradient_outside++;
        if (rc < 0) goto done;
        gn = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
    }
    eo_log(sc->ctx, EO_LOG_DEBUG, "mixed_fem: %d iterations, constraint residual max_e |s_e - S(F_e)|_F = %.3e", k,
           max_constraint_residual(st, &sp));
done:
    res->reason = reason;
    res->iterations = k;
    res->g = g;
    res->grad_norm = gn;
    res->decrement = NAN;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_mixed_fem = {
    .info = {.name = "mixed_fem",
             .summary = "mixed variational FEM (Trusty 2022): per-tet stretch s = S(F) with multipliers, SQP "
                        "with s and lambda condensed per element, one displacement-sized SPD solve per iteration",
             .params = mixed_desc,
             .params_size = sizeof(eo_mixed_fem_params)},
    .state_size = sizeof(mixed_state),
    .needs_linear = 1,
    .needs_hessian = 0,
    .needs_ops = EO_OBJ_NEEDS_SPLIT,
    .setup = mixed_setup,
    .minimize = mixed_minimize,
    .destroy = mixed_destroy,
};
