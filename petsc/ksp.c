/* petsc_ksp: a linear solver of the library's kind (linsolve.h) backed by PETSc KSP, for
 * the Newton systems of the library's optimizers run distributed (solver.backend=petsc).
 *
 * On a distributed space (objective.h eo_vspace, this backend's: space.c) each rank hands
 * in its part's Hessian (the upper-triangle CSC of its local free coordinates, only its
 * tets' terms); the global matrix is assembled as an MPIAIJ by COO with the duplicates of
 * shared vertices summed (MatSetPreallocationCOO once per pattern, MatSetValuesCOO per
 * factorization). b and x are complete at every copy: b's owned entries go in, x comes
 * back to every copy. Without a distributed space (one process) the matrix is the whole
 * one on PETSC_COMM_SELF.
 *
 * Positive definiteness (the shift loop and project_on_demand need to know, like CHOLMOD's
 * LLᵀ tells the serial engine): the matrix is marked SPD, so that MUMPS factors it as LLᵀ
 * (SYM = 1) and a non-positive pivot fails the factorization (PC failed: EO_WARN_NOT_PD
 * from factor); CG reports an indefinite matrix (KSP_DIVERGED_INDEFINITE_MAT: EO_WARN_NOT_PD
 * from solve); an AMG preconditioner that lost definiteness (DIVERGED_INDEFINITE_PC) is
 * retried with GMRES, whose answer the optimizer's descent test judges.
 *
 * Collectives: analyze only records the pattern; factor agrees over the ranks whether any
 * rank's pattern or numbering changed (a released vertex on one rank) and rebuilds the
 * matrix and the KSP together. Parameters: config section solver.petsc_ksp (ksp, pc, rtol,
 * max_lin_iters, options; eo_petsc_params). */
#include <math.h>
#include <string.h>

#include "petsc_backend.h"

typedef struct ksp_state {
    eo_petsc_params p;
    eo_ctx *ctx;
    const eo_vspace *vs;         /* this backend's space, or NULL: one process */
    unsigned long gen;           /* the space's numbering the matrix was built for */
    /* the pattern last analyzed (local CSC) */
    const int *colptr, *rowind;
    int n, nnz, dirty;
    /* the global system */
    MPI_Comm comm;
    int nown, rstart, nglobal;
    PetscInt *glob;              /* n: local entry -> global row (own numbering without a space) */
    PetscCount ncoo;
    PetscScalar *coo_v;
    Mat A;
    Vec B, X, coords;
    MatNullSpace rbm;
    KSP ksp;
    double rtol;                 /* set_rtol (0: p.rtol) */
    int built;
} ksp_state;

static void sys_free(ksp_state *s)
{
    KSPDestroy(&s->ksp);
    MatDestroy(&s->A);
    VecDestroy(&s->B);
    VecDestroy(&s->X);
    VecDestroy(&s->coords);
    MatNullSpaceDestroy(&s->rbm);
    PetscFree(s->coo_v);
    PetscFree(s->glob);
    s->ncoo = 0;
    s->built = 0;
}

static int ks_setup(void *st, const void *params, eo_ctx *ctx)
{
    ksp_state *s = st;
    s->p = *(const eo_petsc_params *)params;
    s->ctx = ctx;
    int rc = eo_petsc_ensure(ctx);
    if (rc < 0) return rc;
    if (strcmp(s->p.ksp, "preonly") == 0 && strcmp(s->p.pc, "mumps") != 0)
        return eo_error(ctx, EO_ERR_INVALID, "key 'solver.petsc_ksp.ksp': preonly needs pc = mumps (a direct solve); "
                        "pc = %s is a preconditioner: use ksp = cg, minres or gmres", s->p.pc);
    return EO_OK;
}

static void ks_destroy(void *st, eo_ctx *ctx)
{
    (void)ctx;
    sys_free(st);
}

static int ks_set_space(void *st, const eo_vspace *vs, eo_ctx *ctx)
{
    ksp_state *s = st;
    if (vs && !eo_petsc_space_is(vs))
        return eo_error(ctx, EO_ERR_UNSUPPORTED, "petsc_ksp: the vector space is not the PETSc backend's");
    s->vs = vs;
    return EO_OK;
}

static int ks_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    ksp_state *s = st;
    (void)ctx;
    s->colptr = A->colptr, s->rowind = A->rowind, s->n = A->n, s->nnz = A->nnz;
    s->dirty = 1; /* rebuilt at the next factor, together with the other ranks */
    return EO_OK;
}

/* The matrix, vectors and KSP for the pattern of A (collective). */
static int build(ksp_state *s, const eo_csc *A)
{
    eo_ctx *ctx = s->ctx;
    int rc = EO_OK;
    PetscInt *ci = NULL, *cj = NULL;
    const eo_dist *d = s->vs ? &((const eo_petsc_space *)s->vs->user)->d : NULL;
    sys_free(s);
    s->comm = d ? d->comm : PETSC_COMM_SELF;
    s->nown = d ? d->nown : A->n;
    s->rstart = d ? d->rstart : 0;
    s->nglobal = d ? d->nglobal : A->n;
    if (d && d->n != A->n)
        return eo_error(ctx, EO_ERR_INVALID, "petsc_ksp: the matrix has n = %d, the vector space %d", A->n, d->n);
    EO_PC(PetscMalloc1(A->n + 1, &s->glob));
    for (int i = 0; i < A->n; i++) s->glob[i] = d ? d->lglob[i] : i;
    PetscCount nc = 0;
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) nc += A->rowind[q] == j ? 1 : 2;
    EO_PC(PetscMalloc1(nc + 1, &ci));
    EO_PC(PetscMalloc1(nc + 1, &cj));
    EO_PC(PetscMalloc1(nc + 1, &s->coo_v));
    PetscCount k = 0;
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) {
            const int i = A->rowind[q];
            ci[k] = s->glob[i], cj[k++] = s->glob[j];
            if (i != j) ci[k] = s->glob[j], cj[k++] = s->glob[i];
        }
    s->ncoo = nc;
    int bs3 = s->nown % 3 == 0;
    MPI_Allreduce(MPI_IN_PLACE, &bs3, 1, MPI_INT, MPI_MIN, s->comm);
    EO_PC(MatCreate(s->comm, &s->A));
    EO_PC(MatSetSizes(s->A, s->nown, s->nown, s->nglobal, s->nglobal));
    EO_PC(MatSetType(s->A, MATAIJ));
    if (bs3) EO_PC(MatSetBlockSize(s->A, 3));
    EO_PC(MatSetPreallocationCOO(s->A, nc, ci, cj));
    EO_PC(MatSetOption(s->A, MAT_SYMMETRIC, PETSC_TRUE));
    EO_PC(MatSetOption(s->A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
    /* SPD: MUMPS factors LLᵀ and fails on a matrix that is not (the definiteness test) */
    EO_PC(MatSetOption(s->A, MAT_SPD, PETSC_TRUE));
    EO_PC(MatSetOption(s->A, MAT_SPD_ETERNAL, PETSC_TRUE));
    EO_PC(MatCreateVecs(s->A, &s->X, &s->B));
    if (strcmp(s->p.pc, "gamg") == 0 && bs3 && d) { /* rigid-body modes from the rest coordinates */
        EO_PC(VecDuplicate(s->X, &s->coords));
        EO_PC(VecSetBlockSize(s->coords, 3));
        const double *x0 = eo_step_x0(d->st);
        PetscScalar *a;
        EO_PC(VecGetArray(s->coords, &a));
        for (int i = 0; i < d->n; i++) {
            const PetscInt g = d->lglob[i] - d->rstart;
            if (g >= 0 && g < d->nown) a[g] = x0[eo_step_free_to_full(d->st, i)];
        }
        EO_PC(VecRestoreArray(s->coords, &a));
        EO_PC(MatNullSpaceCreateRigidBody(s->coords, &s->rbm));
        EO_PC(MatSetNearNullSpace(s->A, s->rbm));
    }
    EO_PC(KSPCreate(s->comm, &s->ksp));
    if ((rc = eo_petsc_ksp_configure(ctx, s->ksp, &s->p, NULL, NULL)) < 0) goto fail;
    if (s->rtol > 0) EO_PC(KSPSetTolerances(s->ksp, s->rtol, 1e-300, 1e10, s->p.max_lin_iters));
    s->gen = d ? d->gen : 0;
    s->built = 1;
fail:
    PetscFree(ci);
    PetscFree(cj);
    return rc;
}

static int any(ksp_state *s, int v)
{
    MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_INT, MPI_MAX, s->comm);
    return v;
}

static int ks_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    ksp_state *s = st;
    int rc = EO_OK;
    const eo_dist *d = s->vs ? &((const eo_petsc_space *)s->vs->user)->d : NULL;
    s->comm = d ? d->comm : PETSC_COMM_SELF;
    int rebuild = !s->built || s->dirty || (d && d->gen != s->gen) || (!d && s->nglobal != A->n);
    if (any(s, rebuild)) {
        if ((rc = build(s, A)) < 0) return rc;
    }
    s->dirty = 0;
    PetscCount k = 0;
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) {
            s->coo_v[k++] = A->val[q];
            if (A->rowind[q] != j) s->coo_v[k++] = A->val[q];
        }
    if (k != s->ncoo) return eo_error(ctx, EO_ERR_LINSOLVE, "petsc_ksp: the pattern changed without analyze");
    EO_PC(MatSetValuesCOO(s->A, s->coo_v, INSERT_VALUES));
    EO_PC(KSPSetOperators(s->ksp, s->A, s->A));
    PetscErrorCode e = KSPSetUp(s->ksp);
    PC pc;
    PCFailedReason why = PC_NOERROR;
    EO_PC(KSPGetPC(s->ksp, &pc));
    if (!e) EO_PC(PCGetFailedReasonRank(pc, &why));
    int failed = e != 0 || why != PC_NOERROR;
    if (any(s, failed)) {
        stats->not_pd_column = -1;
        return eo_error(ctx, EO_WARN_NOT_PD, "petsc_ksp: the factorization failed (%s): the matrix is not positive "
                        "definite", e ? "PETSc error" : PCFailedReasons[why]);
    }
fail:
    return rc;
}

static int ks_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    ksp_state *s = st;
    int rc = EO_OK;
    const eo_dist *d = s->vs ? &((const eo_petsc_space *)s->vs->user)->d : NULL;
    PetscScalar *a;
    EO_PC(VecGetArray(s->B, &a));
    for (int i = 0; i < s->n; i++) {
        const PetscInt g = s->glob[i] - s->rstart;
        if (g >= 0 && g < s->nown) a[g] = b[i];
    }
    EO_PC(VecRestoreArray(s->B, &a));
    PetscErrorCode e = KSPSolve(s->ksp, s->B, s->X);
    KSPConvergedReason kr = KSP_DIVERGED_PC_FAILED;
    PetscInt it = 0;
    if (!e) EO_PC(KSPGetConvergedReason(s->ksp, &kr));
    EO_PC(KSPGetIterationNumber(s->ksp, &it));
    stats->iterations = (int)it;
    if (kr == KSP_DIVERGED_INDEFINITE_PC) {
        /* the preconditioner (an AMG), not necessarily the matrix, lost definiteness: CG
         * cannot use it, GMRES can; the optimizer's descent test judges the answer */
        KSPType type;
        char saved[32];
        EO_PC(KSPGetType(s->ksp, &type));
        snprintf(saved, sizeof saved, "%s", type);
        EO_PC(KSPSetType(s->ksp, KSPGMRES));
        e = KSPSolve(s->ksp, s->B, s->X);
        EO_PC(KSPSetType(s->ksp, saved));
        kr = KSP_DIVERGED_PC_FAILED;
        if (!e) EO_PC(KSPGetConvergedReason(s->ksp, &kr));
        EO_PC(KSPGetIterationNumber(s->ksp, &it));
        stats->iterations += (int)it;
    }
    if (d) {
        eo_dist *dd = (eo_dist *)d;
        EO_PC(VecScatterBegin(dd->to_local, s->X, dd->xl, INSERT_VALUES, SCATTER_FORWARD));
        EO_PC(VecScatterEnd(dd->to_local, s->X, dd->xl, INSERT_VALUES, SCATTER_FORWARD));
        const PetscScalar *r;
        EO_PC(VecGetArrayRead(dd->xl, &r));
        memcpy(x, r, (size_t)s->n * sizeof(double));
        EO_PC(VecRestoreArrayRead(dd->xl, &r));
    } else {
        const PetscScalar *r;
        EO_PC(VecGetArrayRead(s->X, &r));
        memcpy(x, r, (size_t)s->n * sizeof(double));
        EO_PC(VecRestoreArrayRead(s->X, &r));
    }
    if (kr == KSP_DIVERGED_INDEFINITE_MAT)
        return eo_error(ctx, EO_WARN_NOT_PD, "petsc_ksp: CG met an indefinite matrix (pᵀAp ≤ 0)");
    if (e || kr < 0)
        return eo_error(ctx, EO_WARN_NOT_CONVERGED, "petsc_ksp: the solve did not converge (%s)",
                        e ? "PETSc error" : KSPConvergedReasons[kr]);
fail:
    return rc;
}

static void ks_set_rtol(void *st, double rtol)
{
    ksp_state *s = st;
    s->rtol = rtol;
    if (s->ksp) KSPSetTolerances(s->ksp, rtol, 1e-300, 1e10, s->p.max_lin_iters);
}

static int ks_is_iterative(const void *st) { return strcmp(((const ksp_state *)st)->p.ksp, "preonly") != 0; }

static int ks_describe(const void *st, char *buf, size_t size)
{
    const ksp_state *s = st;
    return snprintf(buf, size, "petsc_ksp (%s + %s)", s->p.ksp, s->p.pc);
}

const eo_linsolve_type eo_linsolve_petsc_ksp = {
    .info = {.name = "petsc_ksp",
             .summary = "PETSc KSP (MUMPS Cholesky, CG + GAMG, BoomerAMG, ...) on the ranks' parts of the Hessian "
                        "(solver.backend=petsc)",
             .params = eo_petsc_params_desc,
             .params_size = sizeof(eo_petsc_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(ksp_state),
    .setup = ks_setup,
    .analyze = ks_analyze,
    .factor = ks_factor,
    .solve = ks_solve,
    .destroy = ks_destroy,
    .set_rtol = ks_set_rtol,
    .is_iterative = ks_is_iterative,
    .describe = ks_describe,
    .set_space = ks_set_space,
};
