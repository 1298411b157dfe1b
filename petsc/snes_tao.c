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
 * Stopping: SNES: ‖F‖ ≤ tol·‖F(x₀)‖ (snes rtol = solver.tol, step tolerance off); TAO:
 * ‖∇g‖ ≤ tol·‖∇g(x₀)‖ (gttol). solver.max_iters caps the iterations; the KSP is
 * configured from solver.<name> as for petsc_ksp (then -snes_* / -tao_* / -ksp_*
 * options). The callback gets one record per iteration from the solver's monitor
 * (g, ‖∇g‖). Reasons: PETSc's converged reasons → converged_gradient (converged_step for
 * a SNES step-length stop), iteration cap → diverged_max_iters, line search failure →
 * diverged_linesearch, a non-finite value → diverged_nonfinite, the rest →
 * diverged_external. */
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
    eo_dist_destroy(&s->d);
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
        if ((rc = eo_dist_vec(&s->d, &s->X)) < 0 || (rc = eo_dist_vec(&s->d, &s->G)) < 0) goto done;
    }
    if ((rc = eo_dist_from_rep(&s->d, x, s->X)) < 0) goto done;
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
        EO_PC(SNESSetTolerances(snes, 1e-300, sc->tol, 0, maxit, -1));
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
        EO_PC(TaoSetTolerances(tao, 0, 0, sc->tol));
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
