/* PETSc's own nonlinear solvers as optimizers (petsc_backend.h), on the same distributed
 * step problem as the library's optimizers on the PETSc backend:
 *
 *   snes_newtonls   SNES newtonls on F(x) = ∇g(x) = 0, Jacobian = the Hessian projected by
 *                   the Hessian fix's element projection (clamp by default), line search
 *                   bt on the objective g (SNESSetObjective)
 *   snes_newtontr   SNES newtontr (trust region on ‖F‖), same F and Jacobian
 *   tao_nls         TAO Newton line search on min g (its own Hessian modification)
 *   tao_ntr         TAO Newton trust region (Steihaug–Toint CG: KSP stcg with our pc)
 *   tao_lmvm        TAO limited-memory variable metric (no Hessian)
 *   tao_bqnls       TAO bound-constrained quasi-Newton line search (no bounds here)
 *
 * Stopping: the library's rule (solver.stop) on the common measure, as for every other
 * optimizer (solver.h, "The convergence measure"): the metric gradient norm
 * ‖∇g‖_{D⁻¹} (D = the objective's metric, a lumped mass summed onto the owners) against
 * tol times its value at x₀, with the rounding floor EO_STOP_FLOOR·ε²·s[1] of the step's
 * start (s summed over the ranks), so that a step at its minimizer is converged instead
 * of a line search failing at the rounding level (snes_newtonls reported
 * diverged_linesearch at ‖∇g‖ = 2e-12 on the cantilever). The values are global
 * (PETSc vectors and reductions), so every rank takes the same decision. SNES's and TAO's
 * own tests (iteration caps, NaN, function counts) still apply; their tolerances are
 * off. solver.max_iters caps the iterations; the KSP is
 * configured from solver.<name> as for petsc_ksp (then -snes_* / -tao_* / -ksp_*
 * options). The callback gets one record per iteration from the solver's monitor
 * (g, ‖∇g‖). Reasons: PETSc's converged reasons → converged_gradient (converged_step for
 * a SNES step-length stop), iteration cap → diverged_max_iters, line search failure →
 * diverged_linesearch, a non-finite value → diverged_nonfinite, the rest →
 * diverged_external. */
#include <float.h>
#include <math.h>
#include <petscsnes.h>
#include <petsctao.h>
#include <string.h>

#include "petsc_backend.h"

typedef enum { K_SNES_LS, K_SNES_TR, K_TAO_NLS, K_TAO_NTR, K_TAO_LMVM, K_TAO_BQNLS } kind;

typedef struct pk_state {
    eo_dist d;
    Vec X, G;
    const eo_solver_ctx *sc;
    double *x;
    double t0;
    int iters;
    int stop;              /* the callback asked to stop */
    eo_solve_result *res;
    int err;               /* an eo status from inside a PETSc callback */
    /* the common measure (stop_prepare, stop_check) */
    Vec Dinv, W;           /* D⁻¹ of the metric on the owned rows; work */
    Vec Fprev;             /* SNES: ∇g at the previous iterate, for its direction's decrement */
    Vec Xb;                /* SNES: x before a full step at the rounding level */
    double floor_grad, floor_dec, g_scale, g0, gn0, gm0, dec0, dec_last;
    int begun;
} pk_state;

static int pk_setup(void *st, const void *params, int n, eo_ctx *ctx)
{
    (void)st, (void)params, (void)n, (void)ctx;
    return EO_OK;
}

static void pk_destroy(void *st, eo_ctx *ctx)
{
    (void)ctx;
    pk_state *s = st;
    VecDestroy(&s->X);
    VecDestroy(&s->G);
    VecDestroy(&s->Dinv);
    VecDestroy(&s->W);
    VecDestroy(&s->Fprev);
    VecDestroy(&s->Xb);
    eo_dist_destroy(&s->d);
}

/* ---- the common measure */

/* D⁻¹ (the parts' metric diagonals summed onto the owners; the identity where an objective
 * has none, on every rank alike) and the rounding floor at x₀ (x: the local coordinates) */
static int stop_prepare(pk_state *s, eo_objective *obj, const double *x)
{
    eo_ctx *ctx = s->d.ctx;
    int rc = EO_OK;
    double *dm = s->d.grep; /* scratch: n doubles, free before the solve */
    int ok = obj->ops->metric_diag && obj->ops->metric_diag(obj->data, dm) >= 0;
    for (int i = 0; ok && i < s->d.n; i++) ok = isfinite(dm[i]) && dm[i] >= 0;
    int all = ok;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, s->d.comm);
    if (!all)
        for (int i = 0; i < s->d.n; i++) dm[i] = 1;
    if ((rc = eo_dist_sum_rep(&s->d, dm, s->Dinv)) < 0) return rc;
    if (!all) EO_PC(VecSet(s->Dinv, 1));
    EO_PC(VecReciprocal(s->Dinv));
    double rs[3] = {0, 0, 0};
    ok = eo_objective_rounding_scale(obj, x, rs) >= 0 && isfinite(rs[1]) && isfinite(rs[2]);
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, s->d.comm);
    const double e2 = DBL_EPSILON * DBL_EPSILON;
    s->floor_grad = all ? EO_STOP_FLOOR * e2 * eo_dist_sum(&s->d, rs[1]) : 0;
    s->floor_dec = all ? EO_STOP_FLOOR * e2 * eo_dist_sum(&s->d, rs[0]) : 0;
    s->dec0 = s->dec_last = NAN;
    s->g_scale = all ? eo_dist_sum(&s->d, rs[2]) : 0;
    s->begun = 0;
fail:
    return rc;
}

/* solver.stop at an iterate with value g and gradient G (global): 0 or a converged reason */
static int stop_check(pk_state *s, int it, double g, Vec G, double gn)
{
    double m2 = 0;
    if (VecPointwiseMult(s->W, G, G) || VecDot(s->W, s->Dinv, &m2)) return 0;
    const double gm = sqrt(m2);
    if (!s->begun) {
        s->g0 = g, s->gn0 = gn, s->gm0 = gm;
        s->begun = 1;
    }
    const eo_solver_ctx *sc = s->sc;
    eo_stop_info si = {.iteration = it, .g = g, .g_prev = NAN, .grad_norm = gn, .grad_norm0 = s->gn0,
                       .decrement = NAN, .decrement0 = NAN, .decrement_prev = NAN, .step_norm = NAN,
                       .x_norm = NAN, .tol = sc->tol, .measure = EO_MEASURE_GRADIENT, .g0 = s->g0,
                       .grad_metric = gm, .grad_metric0 = s->gm0, .floor_dec = 0, .floor_grad = s->floor_grad,
                       .g_scale = s->g_scale, .grad_char = 0};
    const int r = sc->stop->check(sc->stop_params, &si);
    return r > 0 ? r : 0;
}

/* snes_newtonls stopped by its line search: the Newton decrement λ²/2 = ½ FᵀY of the
 * direction Y = J⁻¹F it could not follow from the final x, tested by solver.stop as the
 * library's newton tests its own (relative to the first direction's, with the rounding
 * floor of the step's start): a line search that fails at the minimizer, where g no longer
 * resolves a decrease, is convergence, not failure. 0 or a converged reason. */
static int stop_check_decrement(pk_state *s, SNES snes, int it, double g, Vec G, double gn)
{
    Vec Y;
    double fy = NAN, m2 = 0;
    if (SNESGetSolutionUpdate(snes, &Y) || !Y || VecDot(G, Y, &fy) || !(fy >= 0)) return 0;
    if (VecPointwiseMult(s->W, G, G) || VecDot(s->W, s->Dinv, &m2)) return 0;
    const eo_solver_ctx *sc = s->sc;
    eo_stop_info si = {.iteration = it, .g = g, .g_prev = NAN, .grad_norm = gn, .grad_norm0 = s->gn0,
                       .decrement = fy / 2, .decrement0 = s->dec0, .decrement_prev = s->dec_last, .step_norm = NAN,
                       .x_norm = NAN, .tol = sc->tol, .measure = EO_MEASURE_DECREMENT, .g0 = s->g0,
                       .grad_metric = sqrt(m2), .grad_metric0 = s->gm0, .floor_dec = s->floor_dec,
                       .floor_grad = s->floor_grad, .g_scale = s->g_scale, .grad_char = 0};
    const int r = sc->stop->check(sc->stop_params, &si);
    return r > 0 ? r : 0;
}

/* ---- callbacks */

static PetscErrorCode cb_objective(pk_state *s, Vec X, PetscReal *f)
{
    double g;
    int rc = eo_dist_value(&s->d, s->sc->obj, X, &g);
    if (rc < 0) {
        s->err = rc;
        return PETSC_ERR_LIB;
    }
    *f = g;
    return 0;
}

static PetscErrorCode snes_obj(SNES snes, Vec X, PetscReal *f, void *u)
{
    (void)snes;
    return cb_objective(u, X, f);
}

static PetscErrorCode snes_fun(SNES snes, Vec X, Vec F, void *u)
{
    (void)snes;
    pk_state *s = u;
    double g;
    int rc = eo_dist_gradient(&s->d, s->sc->obj, X, &g, F);
    if (rc < 0) {
        s->err = rc;
        return PETSC_ERR_LIB;
    }
    if (!isfinite(g)) return VecSet(F, INFINITY); /* SNES: function domain error */
    return 0;
}

static PetscErrorCode hess(pk_state *s, Vec X)
{
    double t = eo_wtime();
    int rc = eo_dist_hessian(&s->d, s->sc->obj, X, s->sc->hessfix ? s->sc->hessfix->elem_proj : EO_PROJ_CLAMP);
    s->res->t_assembly += eo_wtime() - t;
    s->res->n_assembly++;
    if (rc < 0) {
        s->err = rc;
        return PETSC_ERR_LIB;
    }
    return 0;
}

static PetscErrorCode snes_jac(SNES snes, Vec X, Mat A, Mat B, void *u)
{
    (void)snes, (void)A, (void)B;
    return hess(u, X);
}

static PetscErrorCode tao_fg(Tao tao, Vec X, PetscReal *f, Vec G, void *u)
{
    (void)tao;
    pk_state *s = u;
    double g;
    int rc = eo_dist_gradient(&s->d, s->sc->obj, X, &g, G);
    if (rc < 0) {
        s->err = rc;
        return PETSC_ERR_LIB;
    }
    *f = g;
    return 0;
}

static PetscErrorCode tao_hess(Tao tao, Vec X, Mat A, Mat B, void *u)
{
    (void)tao, (void)A, (void)B;
    return hess(u, X);
}

/* one record per iteration: g and ‖∇g‖ at the iterate */
static int record(pk_state *s, int it, Vec X, double g, double gn)
{
    eo_iter_info info = {.iteration = it, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN, .inverted = -1,
                         .x = s->x};
    s->iters = it;
    if (!s->sc->on_iter) return 0;
    if (eo_dist_to_rep(&s->d, X, s->x) < 0) return 0;
    info.inverted = eo_dist_inverted(&s->d, s->sc->obj, X);
    int stop = eo_solver_report(s->sc, s->t0, &info) != 0, all = stop;
    MPI_Allreduce(&stop, &all, 1, MPI_INT, MPI_MAX, s->d.comm);
    return all;
}

/* SNES's own test (caps, NaN, function counts; its tolerances off), then the common one */
static PetscErrorCode snes_conv(SNES snes, PetscInt it, PetscReal xn, PetscReal sn, PetscReal fn,
                                SNESConvergedReason *reason, void *u)
{
    pk_state *s = u;
    PetscErrorCode e = SNESConvergedDefault(snes, it, xn, sn, fn, reason, NULL);
    if (e || *reason != SNES_CONVERGED_ITERATING || !isfinite(fn)) return e;
    Vec F, X;
    PetscReal g = NAN;
    SNESGetFunction(snes, &F, NULL, NULL);
    SNESGetSolution(snes, &X);
    if (cb_objective(s, X, &g)) return PETSC_ERR_LIB;
    if (it > 0) { /* Y is the direction taken from the previous iterate: its decrement */
        Vec Y;
        double fy = NAN;
        if (!SNESGetSolutionUpdate(snes, &Y) && Y && !VecDot(s->Fprev, Y, &fy) && fy >= 0) {
            s->dec_last = fy / 2;
            if (it == 1) s->dec0 = fy / 2;
        }
    }
    if (!s->Fprev && VecDuplicate(F, &s->Fprev)) return PETSC_ERR_LIB;
    VecCopy(F, s->Fprev);
    if (stop_check(s, (int)it, g, F, fn)) *reason = SNES_CONVERGED_FNORM_RELATIVE;
    return 0;
}

static PetscErrorCode snes_mon(SNES snes, PetscInt it, PetscReal fn, void *u)
{
    pk_state *s = u;
    Vec X;
    PetscReal g = NAN;
    SNESGetSolution(snes, &X);
    cb_objective(s, X, &g);
    if (record(s, (int)it, X, g, fn)) {
        s->stop = 1;
        SNESSetConvergedReason(snes, SNES_DIVERGED_FUNCTION_COUNT);
    }
    return 0;
}

static PetscErrorCode tao_mon(Tao tao, void *u)
{
    pk_state *s = u;
    PetscInt it;
    PetscReal f, gn, cnorm, xdiff;
    TaoConvergedReason r;
    Vec X;
    TaoGetSolutionStatus(tao, &it, &f, &gn, &cnorm, &xdiff, &r);
    TaoGetSolution(tao, &X);
    if (record(s, (int)it, X, f, gn)) {
        s->stop = 1;
        TaoSetConvergedReason(tao, TAO_DIVERGED_USER);
    }
    return 0;
}

/* TAO's own test (caps, NaN, function counts; its tolerances off), then the common one */
static PetscErrorCode tao_conv(Tao tao, void *u)
{
    pk_state *s = u;
    PetscErrorCode e = TaoDefaultConvergenceTest(tao, NULL);
    TaoConvergedReason r;
    if (e || TaoGetConvergedReason(tao, &r) || r != TAO_CONTINUE_ITERATING) return e;
    PetscInt it;
    PetscReal f, gn, cn, xd;
    TaoGetSolutionStatus(tao, &it, &f, &gn, &cn, &xd, &r);
    if (!isfinite(f) || !isfinite(gn)) return 0;
    Vec G;
    if (TaoGetGradient(tao, &G, NULL, NULL) || !G) return 0;
    if (stop_check(s, (int)it, f, G, gn)) TaoSetConvergedReason(tao, TAO_CONVERGED_GTTOL);
    return 0;
}

/* ---- the run */

static int run(kind kd, void *st, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    pk_state *s = st;
    const eo_petsc_params *p = params;
    eo_ctx *ctx = sc->ctx;
    eo_objective *obj = sc->obj;
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    SNES snes = NULL;
    Tao tao = NULL;
    KSP ksp = NULL;
    int rc, reason = 0;
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    s->sc = sc;
    s->x = x;
    s->t0 = eo_wtime();
    s->iters = 0;
    s->stop = 0;
    s->err = 0;
    s->res = res;
    const unsigned long gen0 = s->d.gen;
    if ((rc = eo_dist_setup(&s->d, ctx, obj, p)) < 0) goto done;
    const int rebuilt = s->d.gen != gen0; /* renumbered here or on another rank */
    if (rebuilt || !s->X) {
        VecDestroy(&s->X);
        VecDestroy(&s->G);
        VecDestroy(&s->Dinv);
        VecDestroy(&s->W);
        VecDestroy(&s->Fprev);
        VecDestroy(&s->Xb);
        if ((rc = eo_dist_vec(&s->d, &s->X)) < 0 || (rc = eo_dist_vec(&s->d, &s->G)) < 0 ||
            (rc = eo_dist_vec(&s->d, &s->Dinv)) < 0 || (rc = eo_dist_vec(&s->d, &s->W)) < 0)
            goto done;
    }
    if ((rc = eo_dist_from_rep(&s->d, x, s->X)) < 0) goto done;
    if ((rc = stop_prepare(s, obj, x)) < 0) goto done;
    const int needs_h = kd == K_SNES_LS || kd == K_SNES_TR || kd == K_TAO_NLS || kd == K_TAO_NTR;
    if (needs_h && (rc = eo_dist_hessian(&s->d, obj, s->X, sc->hessfix ? sc->hessfix->elem_proj : EO_PROJ_CLAMP)) < 0)
        goto done; /* creates the matrix */
    const int maxit = sc->max_iters > 0 ? sc->max_iters : 1;
    if (kd == K_SNES_LS || kd == K_SNES_TR) {
        EO_PC(SNESCreate(s->d.comm, &snes));
        EO_PC(SNESSetType(snes, kd == K_SNES_LS ? SNESNEWTONLS : SNESNEWTONTR));
        EO_PC(SNESSetFunction(snes, s->G, snes_fun, s));
        EO_PC(SNESSetJacobian(snes, s->d.A, s->d.A, snes_jac, s));
        EO_PC(SNESSetObjective(snes, snes_obj, s));
        EO_PC(SNESSetTolerances(snes, 0, 0, 0, maxit, -1));
        EO_PC(SNESSetConvergenceTest(snes, snes_conv, s, NULL));
        EO_PC(SNESMonitorSet(snes, snes_mon, s, NULL));
        EO_PC(SNESGetKSP(snes, &ksp));
        if ((rc = eo_petsc_ksp_configure(ctx, ksp, p, &s->d, NULL)) < 0) goto done;
        EO_PC(SNESSetFromOptions(snes));
        PetscErrorCode e = SNESSolve(snes, NULL, s->X);
        if (s->err) {
            rc = s->err;
            goto done;
        }
        if (e) EO_PC(e);
        SNESConvergedReason r;
        PetscInt it;
        EO_PC(SNESGetConvergedReason(snes, &r));
        EO_PC(SNESGetIterationNumber(snes, &it));
        PetscInt li;
        EO_PC(SNESGetLinearSolveIterations(snes, &li));
        res->lin_iters = li;
        res->iterations = (int)it;
        if (r == SNES_DIVERGED_LINE_SEARCH && !s->stop) {
            double gl = NAN, gnl = NAN;
            if ((rc = eo_dist_gradient(&s->d, obj, s->X, &gl, s->G)) < 0) goto done;
            EO_PC(VecNorm(s->G, NORM_2, &gnl));
            reason = stop_check_decrement(s, snes, (int)it, gl, s->G, gnl);
            Vec Y;
            double fy = NAN;
            EO_PC(SNESGetSolutionUpdate(snes, &Y));
            EO_PC(VecDot(s->G, Y, &fy));
            double gs = fabs(gl) > fabs(s->g0) ? fabs(gl) : fabs(s->g0);
            if (s->g_scale > gs) gs = s->g_scale;
            if (!reason && fy >= 0 && fy / 2 <= DBL_EPSILON * gs) {
                /* the direction's decrease is below what g resolves, so no line search on g
                 * can judge it: take the full Newton step, as the library's newton does at the
                 * rounding level, and keep it only if the measure then passes */
                if (!s->Xb) EO_PC(VecDuplicate(s->X, &s->Xb));
                EO_PC(VecCopy(s->X, s->Xb));
                EO_PC(VecAXPY(s->X, -1, Y));
                double g2 = NAN, gn2 = NAN;
                if ((rc = eo_dist_gradient(&s->d, obj, s->X, &g2, s->G)) < 0) goto done;
                EO_PC(VecNorm(s->G, NORM_2, &gn2));
                if (isfinite(g2) && (reason = stop_check(s, (int)it + 1, g2, s->G, gn2)))
                    res->iterations = (int)it + 1;
                else
                    EO_PC(VecCopy(s->Xb, s->X));
            }
        }
        if (!reason) /* not converged by the decrement test or the full step above */
            reason = s->stop                              ? EO_DIVERGED_EXTERNAL
                     : r == SNES_CONVERGED_SNORM_RELATIVE ? EO_CONVERGED_STEP
                     : r > 0                              ? EO_CONVERGED_GRADIENT
                     : r == SNES_DIVERGED_MAX_IT          ? EO_DIVERGED_MAX_ITERS
                     : r == SNES_DIVERGED_LINE_SEARCH     ? EO_DIVERGED_LINESEARCH
                     : r == SNES_DIVERGED_FNORM_NAN || r == SNES_DIVERGED_FUNCTION_DOMAIN ? EO_DIVERGED_NONFINITE
                     : r == SNES_DIVERGED_LINEAR_SOLVE    ? EO_DIVERGED_LINSOLVE
                                                          : EO_DIVERGED_EXTERNAL;
    } else {
        static const char *const types[] = {[K_TAO_NLS] = TAONLS, [K_TAO_NTR] = TAONTR, [K_TAO_LMVM] = TAOLMVM,
                                            [K_TAO_BQNLS] = TAOBQNLS};
        EO_PC(TaoCreate(s->d.comm, &tao));
        EO_PC(TaoSetType(tao, types[kd]));
        EO_PC(TaoSetSolution(tao, s->X));
        EO_PC(TaoSetObjectiveAndGradient(tao, s->G, tao_fg, s));
        if (needs_h) EO_PC(TaoSetHessian(tao, s->d.A, s->d.A, tao_hess, s));
        EO_PC(TaoSetTolerances(tao, 0, 0, 0));
        EO_PC(TaoSetConvergenceTest(tao, tao_conv, s));
        EO_PC(TaoSetMaximumIterations(tao, maxit));
        EO_PC(TaoSetMaximumFunctionEvaluations(tao, 100 * maxit + 1000));
        EO_PC(TaoSetMonitor(tao, tao_mon, s, NULL));
        EO_PC(TaoGetKSP(tao, &ksp));
        if (ksp) {
            eo_petsc_params q = *p;
            if (kd == K_TAO_NTR) snprintf(q.ksp, sizeof q.ksp, "cg"); /* replaced by stcg below */
            if (kd == K_TAO_NTR && strcmp(q.pc, "mumps") == 0) snprintf(q.ksp, sizeof q.ksp, "cg");
            if ((rc = eo_petsc_ksp_configure(ctx, ksp, &q, &s->d, NULL)) < 0) goto done;
            if (kd == K_TAO_NTR) EO_PC(KSPSetType(ksp, KSPSTCG));
            if (kd == K_TAO_NLS && strcmp(p->ksp, "preonly") == 0) EO_PC(KSPSetType(ksp, KSPSTCG));
        }
        if (kd == K_TAO_LMVM || kd == K_TAO_BQNLS) {
            /* the quasi-Newton matrix's initial scaling: PETSc's default (a diagonal
             * rescaling) never reached solver.tol = 1e-10 in 500 iterations on the
             * cantilever, twist or stretch (5 steps each); the scalar (Shanno–Phua) one
             * converged on every twist and stretch step and 3 of 5 cantilever steps.
             * Overridable: -tao_lmvm_mat_lmvm_scale_type (tao_bqnls_ likewise). */
            const char *key = kd == K_TAO_LMVM ? "-tao_lmvm_mat_lmvm_scale_type" : "-tao_bqnls_mat_lmvm_scale_type";
            PetscBool set = PETSC_FALSE;
            EO_PC(PetscOptionsHasName(NULL, NULL, key, &set));
            if (!set) EO_PC(PetscOptionsSetValue(NULL, key, "scalar"));
        }
        EO_PC(TaoSetFromOptions(tao));
        PetscErrorCode e = TaoSolve(tao);
        if (s->err) {
            rc = s->err;
            goto done;
        }
        if (e) EO_PC(e);
        TaoConvergedReason r;
        PetscInt it;
        EO_PC(TaoGetConvergedReason(tao, &r));
        EO_PC(TaoGetIterationNumber(tao, &it));
        PetscInt li = 0;
        EO_PC(TaoGetLinearSolveIterations(tao, &li));
        res->lin_iters = li;
        res->iterations = (int)it;
        reason = s->stop                   ? EO_DIVERGED_EXTERNAL
                 : r > 0                   ? EO_CONVERGED_GRADIENT
                 : r == TAO_DIVERGED_MAXITS ? EO_DIVERGED_MAX_ITERS
                 : r == TAO_DIVERGED_LS_FAILURE ? EO_DIVERGED_LINESEARCH
                 : r == TAO_DIVERGED_NAN   ? EO_DIVERGED_NONFINITE
                                           : EO_DIVERGED_EXTERNAL;
    }
    double g = NAN;
    if ((rc = eo_dist_gradient(&s->d, obj, s->X, &g, s->G)) < 0) goto done;
    double gn = NAN;
    EO_PC(VecNorm(s->G, NORM_2, &gn));
    res->g = g;
    res->grad_norm = gn;
    if ((rc = eo_dist_to_rep(&s->d, s->X, x)) < 0) goto done;
    if (sc->on_iter) { /* the last record, with the reason */
        eo_iter_info info = {.iteration = res->iterations, .g = g, .grad_norm = gn, .decrement = NAN,
                             .alpha = NAN, .inverted = eo_dist_inverted(&s->d, obj, s->X), .reason = reason,
                             .x = x};
        eo_solver_report(sc, s->t0, &info);
    }
fail:
done:
    SNESDestroy(&snes);
    TaoDestroy(&tao);
    res->reason = reason ? reason : EO_DIVERGED_EXTERNAL;
    res->time = eo_wtime() - s->t0;
    res->n_value = obj->n_value - nv0;
    res->n_gradient = obj->n_gradient - ng0;
    res->n_hessian = obj->n_hessian - nh0;
    res->n_factor = res->n_assembly;
    res->status = rc < 0 ? rc : EO_OK;
    return rc < 0 ? rc : EO_OK;
}

#define PK_OPT(NAME, KIND, SUMMARY, HESS)                                                                  \
    static int NAME##_min(void *st, const void *pa, const eo_solver_ctx *sc, double *x, eo_solve_result *r) \
    {                                                                                                      \
        return run(KIND, st, pa, sc, x, r);                                                                \
    }                                                                                                      \
    const eo_optimizer_type eo_optimizer_##NAME = {                                                        \
        .info = {.name = #NAME, .summary = SUMMARY, .params = eo_petsc_params_desc,                        \
                 .params_size = sizeof(eo_petsc_params)},                                                  \
        .state_size = sizeof(pk_state), .needs_linear = 0, .needs_hessian = HESS, .linesearch = "none",   \
        .needs_ops = EO_OBJ_NEEDS_PARTS,                                                                   \
        .setup = pk_setup, .minimize = NAME##_min, .destroy = pk_destroy}

PK_OPT(snes_newtonls, K_SNES_LS, "PETSc SNES newtonls on grad g = 0 (line search on g; MPI)", 1);
PK_OPT(snes_newtontr, K_SNES_TR, "PETSc SNES newtontr on grad g = 0 (trust region; MPI)", 1);
PK_OPT(tao_nls, K_TAO_NLS, "PETSc TAO Newton line search (MPI)", 1);
PK_OPT(tao_ntr, K_TAO_NTR, "PETSc TAO Newton trust region, Steihaug-Toint CG (MPI)", 1);
PK_OPT(tao_lmvm, K_TAO_LMVM, "PETSc TAO limited-memory variable metric (MPI)", 0);
PK_OPT(tao_bqnls, K_TAO_BQNLS, "PETSc TAO bound-constrained quasi-Newton line search (MPI)", 0);
