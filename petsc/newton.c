/* petsc_newton: our Newton iteration on PETSc vectors (petsc_backend.h).
 *
 *   x_{k+1} = x_k + α_k p_k,   (H̃_k + c_k I) p_k = −∇g(x_k)   (KSP: MUMPS, or CG/MINRES/
 *                                                            GMRES with GAMG, BoomerAMG, ...)
 *
 * with the same pieces as `newton` (solvers/optim/newton.c, descent.c):
 *  - Hessian fix (solver.hessian_fix): none (H, −∇g when H is not PD / p not descent),
 *    shift (H + cI), clamp / abs (per-element projected H, the shift loop as safeguard),
 *    project_on_demand (H first; clamp + the shift loop when that fails, per direction);
 *    the shift loop of solvers/hessfix/shift_loop.c: c from the carried c_next, on
 *    failure c ← max(shift_init·s, shift_grow·c), s = mean |H_ii|, give up above
 *    shift_max·s (diverged_not_pd); after success c_next = c/shift_shrink (0 below
 *    shift_init·s). Failure = KSP diverged (indefinite matrix, factorization error) or
 *    ∇gᵀp ≥ −descent_eps‖∇g‖‖p‖. Parameters: solver.<fix>.shift_* as for `newton`.
 *  - line search (solver.linesearch): the registered backtracking, nonmonotone or none
 *    themselves, run on each rank's owned entries (their only global quantities are g,
 *    summed over the ranks, and ∇gᵀp, given); wolfe and exact need global gradient
 *    products inside the search and are refused.
 *  - stopping rule (solver.stop): the registered rule, called with the same eo_stop_info.
 * Every decision is taken on values reduced over the ranks, so all ranks take the same
 * path. The callback sees the iterate gathered on every rank (only when one is set). */
#include "elastopt/impl/params.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "petsc_backend.h"
#include "petsc_options.h"

typedef struct pn_state {
    eo_dist d;
    int n;
    Vec X, G, P, Xn, Gn, Xt, D;
    KSP ksp;
    double c_next;
    double *work;
    int ready;
    /* the line search's objective: n = owned entries, evaluations through d */
    eo_objective lsobj;
    eo_objective *obj;
    /* the objective the stopping rule sees: the local one with rank-summed scales */
    eo_objective gobj;
} pn_state;

static int pn_setup(void *st, const void *params, int n, eo_ctx *ctx)
{
    (void)st, (void)params, (void)ctx;
    ((pn_state *)st)->n = n;
    return EO_OK;
}

static void vecs_free(pn_state *s)
{
    Vec *v[] = {&s->X, &s->G, &s->P, &s->Xn, &s->Gn, &s->Xt, &s->D};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) VecDestroy(v[i]);
    KSPDestroy(&s->ksp);
    s->ready = 0;
}

/* KSPs of destroyed states, destroyed at the next agreed rebuild: the solver destroys an
 * optimizer's state when its objective's n changes, which under MPI may happen on one rank
 * only (a released vertex), while destroying a KSP with a MUMPS factor is collective */
static KSP g_deferred[8];
static int g_ndeferred;

static void deferred_flush(void)
{
    for (int i = 0; i < g_ndeferred; i++) KSPDestroy(&g_deferred[i]);
    g_ndeferred = 0;
}

static void pn_destroy(void *st, eo_ctx *ctx)
{
    pn_state *s = st;
    if (s->ksp && g_ndeferred < (int)(sizeof g_deferred / sizeof g_deferred[0])) {
        g_deferred[g_ndeferred++] = s->ksp;
        s->ksp = NULL;
    }
    vecs_free(s);
    eo_free(ctx, s->work);
    s->work = NULL;
    eo_dist_destroy(&s->d);
}

/* ---- the line search's view: owned entries of a distributed vector */

static int ls_value(void *data, const double *x, double *g)
{
    pn_state *s = data;
    eo_ctx *ctx = s->d.ctx;
    int rc = EO_OK;
    PetscScalar *a;
    EO_PC(VecGetArray(s->Xt, &a));
    memcpy(a, x, (size_t)s->d.nown * sizeof(double));
    EO_PC(VecRestoreArray(s->Xt, &a));
    return eo_dist_value(&s->d, s->obj, s->Xt, g);
fail:
    return rc;
}

static int ls_gradient(void *data, const double *x, double *g, double *grad)
{
    pn_state *s = data;
    eo_ctx *ctx = s->d.ctx;
    int rc = ls_value(data, x, g); /* sets Xt */
    if (rc < 0) return rc;
    if ((rc = eo_dist_gradient(&s->d, s->obj, s->Xt, g, s->Gn)) < 0) return rc;
    const PetscScalar *a;
    EO_PC(VecGetArrayRead(s->Gn, &a));
    memcpy(grad, a, (size_t)s->d.nown * sizeof(double));
    EO_PC(VecRestoreArrayRead(s->Gn, &a));
fail:
    return rc;
}

static int ls_hessian(void *data, const double *x, eo_proj proj, eo_csc **H)
{
    (void)x, (void)proj, (void)H;
    return eo_error(((pn_state *)data)->d.ctx, EO_ERR_UNSUPPORTED, "petsc_newton: a line search asked for a Hessian");
}

static const eo_objective_ops ls_ops = {.value = ls_value, .gradient = ls_gradient, .hessian = ls_hessian};

/* ---- the stopping rule's view: the rounding scales and characteristic scales of g summed
 * (largest) over the ranks, so that every rank measures the same floors */

static int g_value(void *data, const double *x, double *g)
{
    pn_state *s = data;
    return eo_objective_value(s->obj, x, g);
}

static int g_gradient(void *data, const double *x, double *g, double *grad)
{
    pn_state *s = data;
    return eo_objective_gradient(s->obj, x, g, grad);
}

static int g_hessian(void *data, const double *x, eo_proj proj, eo_csc **H)
{
    pn_state *s = data;
    return eo_objective_hessian(s->obj, x, proj, H);
}

static int g_rounding_scale(void *data, const double *x, double out[3])
{
    pn_state *s = data;
    int rc = eo_objective_rounding_scale(s->obj, x, out);
    int ok = rc >= 0;
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, s->d.comm);
    if (!ok) return rc < 0 ? rc : EO_ERR_UNSUPPORTED;
    MPI_Allreduce(MPI_IN_PLACE, out, 3, MPI_DOUBLE, MPI_SUM, s->d.comm);
    return EO_OK;
}

static int g_characteristic(void *data, eo_objective_characteristic *out)
{
    pn_state *s = data;
    int rc = eo_objective_characteristic_get(s->obj, out);
    int ok = rc >= 0;
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, s->d.comm);
    if (!ok) return rc < 0 ? rc : EO_ERR_UNSUPPORTED;
    double gr = out->grad * out->grad; /* a norm: the ranks' squares summed (shared vertices twice) */
    MPI_Allreduce(MPI_IN_PLACE, &gr, 1, MPI_DOUBLE, MPI_SUM, s->d.comm);
    out->grad = sqrt(gr);
    double sv[2] = {out->stiffness * out->volume, out->volume}; /* volume-weighted mean */
    MPI_Allreduce(MPI_IN_PLACE, sv, 2, MPI_DOUBLE, MPI_SUM, s->d.comm);
    out->volume = sv[1];
    out->stiffness = sv[1] > 0 ? sv[0] / sv[1] : out->stiffness;
    return EO_OK;
}

static const eo_objective_ops g_ops = {.value = g_value, .gradient = g_gradient, .hessian = g_hessian,
                                       .rounding_scale = g_rounding_scale, .characteristic = g_characteristic};

/* ---- setup per minimization */

static int prepare(pn_state *s, const eo_solver_ctx *sc, const eo_petsc_params *p)
{
    eo_ctx *ctx = sc->ctx;
    int rc;
    const char *ls = eo_method_info_of(sc->linesearch)->name, *hf = eo_method_info_of(sc->hessfix)->name;
    const char *why = eo_petsc_newton_refuses(hf, ls);
    if (why) return eo_error(ctx, EO_ERR_UNSUPPORTED, "petsc_newton: %s / %s: %s", hf, ls, why);
    const unsigned long gen0 = s->d.gen;
    if ((rc = eo_dist_setup(&s->d, ctx, sc->obj, p)) < 0) return rc;
    const int rebuilt = s->d.gen != gen0; /* renumbered here or on another rank */
    if (rebuilt || !s->ready) {
        deferred_flush(); /* at the same point as the other ranks' vecs_free */
        vecs_free(s);
        Vec *v[] = {&s->X, &s->G, &s->P, &s->Xn, &s->Gn, &s->Xt, &s->D};
        for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
            if ((rc = eo_dist_vec(&s->d, v[i])) < 0) return rc;
        EO_PC(KSPCreate(s->d.comm, &s->ksp));
        if ((rc = eo_petsc_ksp_configure(ctx, s->ksp, p, &s->d, NULL)) < 0) return rc;
        eo_free(ctx, s->work);
        s->work = eo_malloc(ctx, (size_t)(s->d.nown + 1) * sizeof(double));
        if (!s->work) return eo_error(ctx, EO_ERR_NOMEM, "petsc_newton: out of memory");
        s->ready = 1;
    }
    s->obj = sc->obj;
    s->lsobj = (eo_objective){.n = s->d.nown, .ops = &ls_ops, .data = s};
    return EO_OK;
fail:
    return rc;
}

/* ---- one direction: the fix's projection, the shift loop */

typedef struct dir_out {
    double shift;
    int factored, reason, lin_iters, fallback, projected;
} dir_out;

static int solve_once(pn_state *s, eo_ctx *ctx, double c, const double eps, double gnorm, int *ok, int *its)
{
    int rc = EO_OK;
    KSPConvergedReason kr;
    PetscInt it = 0;
    Mat A = s->d.A;
    if (c > 0) EO_PC(MatShift(A, c));
    EO_PC(KSPSetOperators(s->ksp, A, A));
    EO_PC(VecScale(s->G, -1));
    PetscErrorCode e = KSPSolve(s->ksp, s->G, s->P);
    VecScale(s->G, -1);
    if (c > 0) EO_PC(MatDiagonalSet(A, s->D, INSERT_VALUES)); /* the exact diagonal back */
    *ok = 0;
    if (e) return EO_OK; /* a failed factorization is a failed attempt, not an error */
    EO_PC(KSPGetConvergedReason(s->ksp, &kr));
    EO_PC(KSPGetIterationNumber(s->ksp, &it));
    *its += (int)it;
    if (kr == KSP_DIVERGED_INDEFINITE_PC) {
        /* the AMG preconditioner (not the matrix) lost definiteness: CG cannot use it,
         * GMRES can; the descent test below still judges the matrix */
        KSPType type;
        EO_PC(KSPGetType(s->ksp, &type));
        char saved[32];
        snprintf(saved, sizeof saved, "%s", type);
        if (c > 0) EO_PC(MatShift(A, c));
        EO_PC(KSPSetType(s->ksp, KSPGMRES));
        EO_PC(VecScale(s->G, -1));
        e = KSPSolve(s->ksp, s->G, s->P);
        VecScale(s->G, -1);
        EO_PC(KSPSetType(s->ksp, saved));
        if (c > 0) EO_PC(MatDiagonalSet(A, s->D, INSERT_VALUES));
        if (e) return EO_OK;
        EO_PC(KSPGetConvergedReason(s->ksp, &kr));
        EO_PC(KSPGetIterationNumber(s->ksp, &it));
        *its += (int)it;
    }
    if (kr < 0) return EO_OK;
    {
        /* a direct solve (MUMPS Cholesky, which PETSc runs as LDL^T on a matrix not marked
         * SPD) succeeds on an indefinite matrix where the serial engine's CHOLMOD LL^T
         * fails: a negative pivot counts as a failed attempt here too, so every fix makes
         * the serial engine's choices (the count covers the root node with ICNTL(13) = 1,
         * module.c) */
        PC pc;
        PCType pct;
        EO_PC(KSPGetPC(s->ksp, &pc));
        EO_PC(PCGetType(pc, &pct));
        if (pct && strcmp(pct, PCCHOLESKY) == 0) {
            Mat F;
            PetscInt nneg = 0; /* INFOG(12): negative pivots of the LDL^T factorization */
            EO_PC(PCFactorGetMatrix(pc, &F));
            EO_PC(MatMumpsGetInfog(F, 12, &nneg));
            if (nneg > 0) return EO_OK;
        }
    }
    double dg, pn;
    EO_PC(VecDot(s->G, s->P, &dg));
    EO_PC(VecNorm(s->P, NORM_2, &pn));
    *ok = isfinite(dg) && dg < -eps * gnorm * pn;
fail:
    return rc;
}

static int direction(pn_state *s, const eo_solver_ctx *sc, double gnorm, eo_solve_result *res, dir_out *o)
{
    eo_ctx *ctx = sc->ctx;
    int rc = EO_OK;
    const char *hf = eo_method_info_of(sc->hessfix)->name;
    const int none = strcmp(hf, "none") == 0, shifting = !none;
    eo_hessfix_shift_params hp = {.shift_init = 1e-8, .shift_grow = 10, .shift_shrink = 10, .shift_max = 1e12};
    if (shifting && sc->hessfix_params) hp = *(const eo_hessfix_shift_params *)sc->hessfix_params;
    /* project_on_demand (Longva et al. 2023, solvers/hessfix/project_on_demand.c): the
     * true Hessian first, unshifted; when its solve fails or p is not a descent
     * direction, the clamp-projected Hessian with the shift loop, as `clamp` */
    const int pod = strcmp(hf, "project_on_demand") == 0;
    eo_proj proj = pod ? EO_PROJ_NONE : sc->hessfix->elem_proj;
    const double eps = 1e-12;
    memset(o, 0, sizeof *o);
    o->projected = proj != EO_PROJ_NONE;
    double t = eo_wtime();
    if ((rc = eo_dist_hessian(&s->d, sc->obj, s->X, proj)) < 0) return rc;
    res->t_assembly += eo_wtime() - t;
    res->n_assembly++;
    if (pod) {
        int ok = 0;
        res->n_factor++;
        if ((rc = solve_once(s, ctx, 0, eps, gnorm, &ok, &o->lin_iters)) < 0) return rc;
        if (ok) {
            o->factored = 1;
            return EO_OK;
        }
        proj = EO_PROJ_CLAMP;
        o->projected = 1;
        t = eo_wtime();
        if ((rc = eo_dist_hessian(&s->d, sc->obj, s->X, proj)) < 0) return rc;
        res->t_assembly += eo_wtime() - t;
        res->n_assembly++;
    }
    EO_PC(MatGetDiagonal(s->d.A, s->D));
    double sabs;
    EO_PC(VecNorm(s->D, NORM_1, &sabs));
    sabs = s->d.nglobal > 0 ? sabs / s->d.nglobal : 1;
    if (!isfinite(sabs)) {
        o->reason = EO_DIVERGED_NONFINITE;
        return EO_OK;
    }
    if (!(sabs > 0)) sabs = 1;
    const double cmin = hp.shift_init * sabs;
    double c = shifting ? s->c_next : 0;
    for (;;) {
        int ok = 0;
        res->n_factor++;
        if ((rc = solve_once(s, ctx, c, eps, gnorm, &ok, &o->lin_iters)) < 0) return rc;
        if (ok) {
            o->factored = 1;
            o->shift = c;
            if (c > 0) res->n_shifted++;
            s->c_next = c / hp.shift_shrink < cmin ? 0 : c / hp.shift_shrink;
            return EO_OK;
        }
        if (!shifting) { /* none: the steepest-descent fallback */
            EO_PC(VecAXPBY(s->P, -1, 0, s->G));
            res->n_fallback++;
            o->fallback = 1;
            return EO_OK;
        }
        c = fmax(cmin, hp.shift_grow * c);
        if (c > hp.shift_max * sabs) {
            o->reason = EO_DIVERGED_NOT_PD;
            o->shift = c;
            return EO_OK;
        }
    }
fail:
    return rc;
}

/* ---- the iteration */

static int agree_max(eo_dist *d, int v)
{
    int m = v;
    MPI_Allreduce(&v, &m, 1, MPI_INT, MPI_MAX, d->comm);
    return m;
}

static int pn_minimize(void *st, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    pn_state *s = st;
    const eo_petsc_params *p = params;
    eo_ctx *ctx = sc->ctx;
    eo_objective *obj = sc->obj;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    double g = NAN, gn = NAN, gn0 = NAN, g_prev = NAN, step_norm = NAN, last_dec = NAN, dec0 = NAN, dec_prev = NAN;
    int rc, reason = 0, k = 0;
    double ghist[EO_LS_HISTORY];
    int nhist = 0;
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if ((rc = prepare(s, sc, p)) < 0) goto done;
    /* the stopping rule's measure through the rank-summed objective (its rounding scales) */
    eo_solver_ctx scg = *sc;
    s->gobj = (eo_objective){.n = obj->n, .ops = &g_ops, .data = s};
    scg.obj = &s->gobj;
    sc = &scg;
    if ((rc = eo_dist_from_rep(&s->d, x, s->X)) < 0) goto done;
    double tg = eo_wtime();
    if ((rc = eo_dist_gradient(&s->d, obj, s->X, &g, s->G)) < 0) goto done;
    res->t_gradient += eo_wtime() - tg;
    res->n_gradient_outside++;
    if (VecNorm(s->G, NORM_2, &gn)) goto petsc_fail;
    if (!isfinite(g)) gn = NAN;
    gn0 = gn;
    ghist[nhist++] = g;
    s->c_next = 0;
    for (k = 0;; k++) {
        double xn = 0;
        if (VecNorm(s->X, NORM_2, &xn)) goto petsc_fail;
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .inverted = eo_dist_inverted(&s->d, obj, s->X), .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .decrement0 = dec0, .decrement_prev = dec_prev,
                           .step_norm = step_norm, .x_norm = xn, .tol = sc->tol};
        if (sc->on_iter && (rc = eo_dist_to_rep(&s->d, s->X, x)) < 0) goto done;
        double dg = NAN;
        if (!isfinite(g) || !isfinite(gn)) reason = EO_DIVERGED_NONFINITE;
        /* the common measure (solver.h): x is the replicated start at k = 0, where the
         * rounding floor is measured; a Newton decrement needs no gradient */
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, NULL);
        if (!reason && sc->time_budget > 0 && agree_max(&s->d, eo_wtime() - t0 > sc->time_budget))
            reason = EO_DIVERGED_TIME_BUDGET;
        if (!reason) {
            dir_out d;
            if ((rc = direction(s, sc, gn, res, &d)) < 0) goto done;
            info.shift = d.shift;
            info.projected = d.projected;
            info.lin_iters = d.lin_iters;
            res->lin_iters += d.lin_iters;
            reason = d.reason;
            if (!reason) {
                if (VecDot(s->G, s->P, &dg)) goto petsc_fail;
                if (!(dg < 0) || !isfinite(dg)) {
                    reason = EO_DIVERGED_NOT_DESCENT;
                } else {
                    info.decrement = last_dec = -dg / 2;
                    if (k == 0) si.decrement0 = dec0 = last_dec;
                    if (sc->stop->needs_direction) {
                        si.decrement = info.decrement;
                        reason = eo_solver_stop_check(sc, &si, x, NULL);
                    }
                }
            }
        }
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (reason) {
            info.reason = reason;
            eo_solver_report(sc, t0, &info);
            break;
        }
        /* the line search on the owned entries */
        const PetscScalar *xa, *pa;
        PetscScalar *xna;
        double gnew = NAN, alpha = 0;
        int nev = 0;
        eo_ls_extra ex = {.grad_new = NULL, .g_hist = ghist, .n_hist = nhist};
        const double tls = eo_wtime();
        if (VecGetArrayRead(s->X, &xa) || VecGetArrayRead(s->P, &pa) || VecGetArray(s->Xn, &xna)) goto petsc_fail;
        int lrc = sc->linesearch->search(sc->linesearch_params, &s->lsobj, xa, pa, g, dg, 1.0, xna, &gnew, &alpha,
                                         &nev, s->work, ctx, &ex);
        VecRestoreArrayRead(s->X, &xa);
        VecRestoreArrayRead(s->P, &pa);
        VecRestoreArray(s->Xn, &xna);
        res->t_linesearch += eo_wtime() - tls;
        res->n_ls_evals += nev;
        info.ls_evals = nev;
        if ((rc = lrc) < 0) goto done;
        if (!isfinite(gnew) || !(lrc == EO_OK || gnew < g) || !(alpha > 0)) {
            reason = EO_DIVERGED_LINESEARCH;
            info.reason = reason;
            rc = EO_OK;
            eo_solver_report(sc, t0, &info);
            break;
        }
        rc = EO_OK;
        info.alpha = alpha;
        if (agree_max(&s->d, eo_solver_report(sc, t0, &info) != 0)) {
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        /* accept: x ← xnew, the gradient there */
        double gchk;
        tg = eo_wtime();
        if ((rc = eo_dist_gradient(&s->d, obj, s->Xn, &gchk, s->Gn)) < 0) goto done;
        res->t_gradient += eo_wtime() - tg;
        res->n_gradient_outside++;
        if (VecAXPY(s->X, -1, s->Xn) || VecNorm(s->X, NORM_2, &step_norm) || VecCopy(s->Xn, s->X) ||
            VecCopy(s->Gn, s->G))
            goto petsc_fail;
        g_prev = g;
        g = gchk;
        if (nhist == EO_LS_HISTORY) memmove(ghist, ghist + 1, (EO_LS_HISTORY - 1) * sizeof ghist[0]), nhist--;
        ghist[nhist++] = g;
        if (VecNorm(s->G, NORM_2, &gn)) goto petsc_fail;
        if (!isfinite(g)) gn = NAN;
        dec_prev = last_dec;
        last_dec = NAN;
    }
    rc = eo_dist_to_rep(&s->d, s->X, x);
    goto done;
petsc_fail:
    rc = eo_error(ctx, EO_ERR_LINSOLVE, "petsc_newton: a PETSc vector operation failed");
done:
    res->reason = reason;
    res->iterations = k;
    res->g = g;
    res->grad_norm = gn;
    res->decrement = last_dec;
    res->time = eo_wtime() - t0;
    res->n_value = obj->n_value - nv0;
    res->n_gradient = obj->n_gradient - ng0;
    res->n_hessian = obj->n_hessian - nh0;
    res->status = rc < 0 ? rc : EO_OK;
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_petsc_newton = {
    .info = {.name = "petsc_newton",
             .summary = "Newton on PETSc/MPI: our Hessian fixes, line search and stop rule; KSP solve (MUMPS, "
                        "CG+GAMG, ...); solver.backend=petsc runs newton as this",
             .params = eo_petsc_params_desc,
             .params_size = sizeof(eo_petsc_params)},
    .state_size = sizeof(pn_state),
    .needs_linear = 0,
    .needs_hessian = 1,
    .needs_ops = EO_OBJ_NEEDS_PARTS,
    .linesearch = "backtracking",
    .setup = pn_setup,
    .minimize = pn_minimize,
    .destroy = pn_destroy,
    .newton_decrement = 1,
};
