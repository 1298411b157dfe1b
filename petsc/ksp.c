/* petsc_ksp: a linear solver of the library's kind (linsolve.h) backed by PETSc KSP, for
 * the Newton systems of the library's optimizers run distributed (solver.backend=petsc).
 *
 * On a distributed space (objective.h eo_vspace, this backend's: space.c) each rank hands
 * in its part's Hessian (the upper-triangle CSC of its local free coordinates, only its
 * tets' terms); the global matrix is assembled as an MPIAIJ by COO with the duplicates of
 * shared vertices summed (MatSetPreallocationCOO once per pattern, MatSetValuesCOO per
 * factorization). b and x are complete at every copy: b's owned entries go in, x comes
 * back to every copy. Without a distributed space (one process) the matrix is the whole
 * one on PETSC_COMM_SELF, with GAMG's rigid-body modes from eo_linsolve_set_coordinates
 * (the distributed path takes them from the space), so that one rank and P ranks build
 * the same kind of hierarchy.
 *
 * Positive definiteness (the shift loop, none's fallback, project_on_demand's and
 * progressive's retries need to know, as CHOLMOD's failing LLᵀ tells the serial engine).
 * MUMPS: the matrix is *not* marked SPD, so MUMPS factors it as LDLᵀ with threshold and
 * 2×2 pivoting (SYM = 2), which succeeds on an indefinite matrix, and with ICNTL(13) = 1
 * (module.c: the root front factored without ScaLAPACK, which counts no negative pivots)
 * its negative-pivot count INFOG(12) (MatGetInertia) is the global inertia on any rank
 * count. (SYM = 1, LDLᵀ without pivoting, the former setting, fails only on a zero pivot:
 * it reported success with 53 negative pivots on the inverted scene's first Hessian.)
 * The decision does not rest on that count alone:
 *  - count > 0 must be confirmed by a negative-curvature witness: a few Lanczos steps on
 *    A⁻¹ (the factor's solves) from a fixed start vector; the first negative pivot of the
 *    Lanczos tridiagonal T gives v in the Krylov space with vᵀA⁻¹v < 0, and w = A⁻¹v must
 *    show wᵀ(Aw) < 0 with Aw by MatMult, i.e. from the matrix itself, not the factor
 *    (a certificate that A is not PD). Confirmed: EO_WARN_NOT_PD from factor. Not
 *    confirmed within WITNESS_STEPS: the matrix is used as PD and the disagreement is
 *    logged (a wrong count would otherwise reject a PD matrix at every attempt: the shift
 *    loop would grow to shift_max);
 *  - count = 0 is checked on every solve: the solved direction d must have dᵀ(Ad) > 0
 *    (MatMult again), which every PD matrix satisfies; if not, EO_WARN_NOT_PD from solve
 *    (as the serial cg's negative curvature), so an undercount cannot pass an indefinite
 *    matrix whose direction shows it.
 * A factorization MUMPS could not do for lack of workspace (INFOG(1) = -9,
 * FACTOR_OUTMEMORY: its estimate is not an upper bound in parallel) says nothing about
 * definiteness: it is redone with ICNTL(14) (the workspace relaxation, percent) doubled,
 * up to 4 times, and the larger value kept for the next factorizations. (Measured: the
 * 7,200-tet twist on 4 ranks failed every factorization that way with the default 20 %,
 * which the former code took for "not PD": 63 factorizations in a 6-iteration step.)
 * Iterative: the matrix is marked SPD; CG reports an indefinite matrix
 * (KSP_DIVERGED_INDEFINITE_MAT: EO_WARN_NOT_PD from solve); an AMG preconditioner that
 * lost definiteness (DIVERGED_INDEFINITE_PC) is retried with GMRES, whose answer the
 * optimizer's descent test judges.
 *
 * Collectives: analyze only records the pattern; factor agrees over the ranks whether any
 * rank's pattern or numbering changed (a released vertex on one rank) and rebuilds the
 * matrix and the KSP together. Parameters: config section solver.petsc_ksp (ksp, pc, rtol,
 * max_lin_iters, options; eo_petsc_params). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "petsc_backend.h"

/* Lanczos steps on A⁻¹ looking for a negative-curvature witness when MUMPS counts
 * negative pivots */
#define WITNESS_STEPS 12
/* ICNTL(14) doublings after FACTOR_OUTMEMORY */
#define OUTMEM_RETRIES 4

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
    int direct;                  /* pc = mumps */
    int check_curv;              /* the last factor was taken as PD: check dᵀAd at solve */
    int forget;                  /* eo_linsolve_forget since the last set-up */
    PetscInt icntl14;            /* > 0: the workspace relaxation grown after FACTOR_OUTMEMORY */
    Vec W, AW;                   /* work: curvature check, witness */
    Vec wv[WITNESS_STEPS + 1];   /* Lanczos basis */
    /* rest coordinates of the nodes (set_coordinates; the one-process path's GAMG) */
    int nxyz;
    double *xyz;
    /* pc = cholmod: the whole matrix on rank 0, the library's CHOLMOD LLᵀ */
    int root, rank;
    eo_linsolve *rls;            /* rank 0 */
    eo_csc *RA;                  /* rank 0: the global upper triangle */
    int nup;                     /* this rank's upper-triangle entries */
    int *rcounts, *rdispls, *rslot; /* rank 0: entries per rank, offsets, CSC slot of each */
    double *upv, *rvals, *rb, *rx;
    VecScatter toz;              /* B -> B0 (all entries on rank 0) */
    Vec B0;
} ksp_state;

static void root_free(ksp_state *s)
{
    eo_linsolve_destroy(&s->rls);
    eo_csc_destroy(&s->RA);
    eo_free(s->ctx, s->rcounts);
    eo_free(s->ctx, s->rslot);
    eo_free(s->ctx, s->upv);
    eo_free(s->ctx, s->rvals);
    eo_free(s->ctx, s->rb);
    s->rcounts = s->rdispls = s->rslot = NULL;
    s->upv = s->rvals = s->rb = s->rx = NULL;
    VecScatterDestroy(&s->toz);
    VecDestroy(&s->B0);
}

static void sys_free(ksp_state *s)
{
    root_free(s);
    KSPDestroy(&s->ksp);
    MatDestroy(&s->A);
    VecDestroy(&s->B);
    VecDestroy(&s->X);
    VecDestroy(&s->coords);
    VecDestroy(&s->W);
    VecDestroy(&s->AW);
    for (int i = 0; i <= WITNESS_STEPS; i++) VecDestroy(&s->wv[i]);
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
    s->root = strcmp(s->p.pc, "cholmod") == 0;
    if (strcmp(s->p.ksp, "preonly") == 0 && strcmp(s->p.pc, "mumps") != 0 && !s->root)
        return eo_error(ctx, EO_ERR_INVALID, "key 'solver.petsc_ksp.ksp': preonly needs pc = mumps (a direct solve); "
                        "pc = %s is a preconditioner: use ksp = cg, minres or gmres", s->p.pc);
    return EO_OK;
}

static void ks_destroy(void *st, eo_ctx *ctx)
{
    ksp_state *s = st;
    sys_free(s);
    eo_free(ctx, s->xyz);
    s->xyz = NULL;
}

static int ks_set_coordinates(void *st, int nv, const double *xyz, eo_ctx *ctx)
{
    ksp_state *s = st;
    eo_free(ctx, s->xyz);
    s->xyz = NULL, s->nxyz = 0;
    if (nv <= 0) return EO_OK;
    s->xyz = eo_malloc(ctx, 3 * (size_t)nv * sizeof(double));
    if (!s->xyz) return eo_error(ctx, EO_ERR_NOMEM, "petsc_ksp: out of memory (coordinates)");
    memcpy(s->xyz, xyz, 3 * (size_t)nv * sizeof(double));
    s->nxyz = nv;
    if (!s->vs && strcmp(s->p.pc, "gamg") == 0) s->dirty = 1; /* the near-null space comes with the matrix */
    return EO_OK;
}

/* GAMG's rigid-body modes on one process (no space): from set_coordinates' positions */
static int seq_rigid_modes(ksp_state *s)
{
    eo_ctx *ctx = s->ctx;
    int rc = EO_OK;
    PetscInt bs = 1;
    EO_PC(MatGetBlockSize(s->A, &bs));
    if (bs != 3 || !s->xyz || 3 * s->nxyz != s->nglobal) return EO_OK;
    EO_PC(MatCreateVecs(s->A, &s->coords, NULL));
    EO_PC(VecSetBlockSize(s->coords, 3));
    PetscScalar *a;
    EO_PC(VecGetArray(s->coords, &a));
    memcpy(a, s->xyz, 3 * (size_t)s->nxyz * sizeof(double));
    EO_PC(VecRestoreArray(s->coords, &a));
    EO_PC(MatNullSpaceCreateRigidBody(s->coords, &s->rbm));
    EO_PC(MatSetNearNullSpace(s->A, s->rbm));
fail:
    return rc;
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

typedef struct rc_entry {
    int col, row, src; /* global column ≥ row; index in the gathered array */
} rc_entry;

static int rc_cmp(const void *a, const void *b)
{
    const rc_entry *x = a, *y = b;
    if (x->col != y->col) return x->col < y->col ? -1 : 1;
    if (x->row != y->row) return x->row < y->row ? -1 : 1;
    return (x->src > y->src) - (x->src < y->src);
}

/* pc = cholmod: the pattern of the whole upper triangle gathered on rank 0, analyzed by
 * the library's CHOLMOD there (collective). */
static int root_build(ksp_state *s, const eo_csc *A)
{
    eo_ctx *ctx = s->ctx;
    int rc = EO_OK, size = 1;
    int *ij = NULL, *all = NULL;
    rc_entry *ent = NULL;
    MPI_Comm_rank(s->comm, &s->rank);
    MPI_Comm_size(s->comm, &size);
    s->nup = 0;
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) s->nup++;
    s->upv = eo_malloc(ctx, (size_t)(s->nup + 1) * sizeof(double));
    ij = eo_malloc(ctx, (size_t)(2 * s->nup + 1) * sizeof(int));
    if (!s->upv || !ij) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "petsc_ksp: out of memory");
        goto fail;
    }
    int k = 0;
    for (int j = 0; j < A->n; j++)
        for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) {
            const int a = (int)s->glob[A->rowind[q]], b = (int)s->glob[j];
            ij[2 * k] = a < b ? a : b, ij[2 * k + 1] = a < b ? b : a;
            k++;
        }
    if (s->rank == 0) {
        s->rcounts = eo_calloc(ctx, 2 * (size_t)size, sizeof(int));
        if (!s->rcounts) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "petsc_ksp: out of memory");
            goto fail;
        }
        s->rdispls = s->rcounts + size;
    }
    (void)MPI_Gather(&s->nup, 1, MPI_INT, s->rcounts, 1, MPI_INT, 0, s->comm);
    long total = 0;
    int *c2 = NULL, *d2 = NULL;
    if (s->rank == 0) {
        for (int r = 0; r < size; r++) s->rdispls[r] = (int)total, total += s->rcounts[r];
        all = eo_malloc(ctx, (size_t)(2 * total + 1) * sizeof(int));
        c2 = eo_malloc(ctx, 2 * (size_t)size * sizeof(int));
        s->rvals = eo_malloc(ctx, (size_t)(total + 1) * sizeof(double));
        s->rslot = eo_malloc(ctx, (size_t)(total + 1) * sizeof(int));
        s->rb = eo_malloc(ctx, 2 * (size_t)(s->nglobal + 1) * sizeof(double));
        if (!all || !c2 || !s->rvals || !s->rslot || !s->rb) {
            eo_free(ctx, c2);
            rc = eo_error(ctx, EO_ERR_NOMEM, "petsc_ksp: out of memory (%ld entries on rank 0)", total);
            goto fail_collective;
        }
        s->rx = s->rb + s->nglobal + 1;
        d2 = c2 + size;
        for (int r = 0; r < size; r++) c2[r] = 2 * s->rcounts[r], d2[r] = 2 * s->rdispls[r];
    }
fail_collective:
    (void)MPI_Gatherv(ij, 2 * s->nup, MPI_INT, all, c2, d2, MPI_INT, 0, s->comm);
    eo_free(ctx, c2);
    int ok = rc >= 0;
    if (s->rank == 0 && ok) {
        ent = eo_malloc(ctx, (size_t)(total + 1) * sizeof(rc_entry));
        if (!ent) ok = 0, rc = eo_error(ctx, EO_ERR_NOMEM, "petsc_ksp: out of memory");
        for (long e = 0; ok && e < total; e++) ent[e] = (rc_entry){all[2 * e + 1], all[2 * e], (int)e};
        if (ok) qsort(ent, (size_t)total, sizeof *ent, rc_cmp);
        long nnz = 0;
        for (long e = 0; ok && e < total; e++)
            if (e == 0 || ent[e].col != ent[e - 1].col || ent[e].row != ent[e - 1].row) nnz++;
        if (ok && (rc = eo_csc_create(ctx, s->nglobal, (int)nnz, &s->RA)) < 0) ok = 0;
        if (ok) {
            long z = -1;
            for (int j = 0; j <= s->nglobal; j++) s->RA->colptr[j] = 0;
            for (long e = 0; e < total; e++) {
                if (e == 0 || ent[e].col != ent[e - 1].col || ent[e].row != ent[e - 1].row) {
                    z++;
                    s->RA->rowind[z] = ent[e].row;
                    s->RA->colptr[ent[e].col + 1]++;
                }
                s->rslot[ent[e].src] = (int)z;
            }
            for (int j = 0; j < s->nglobal; j++) s->RA->colptr[j + 1] += s->RA->colptr[j];
            for (long q = 0; q < nnz; q++) s->RA->val[q] = 1;
            const eo_linsolve_type *t = NULL;
            if ((rc = eo_linsolve_find(ctx, "cholmod", &t)) < 0 || (rc = eo_linsolve_create(ctx, t, NULL, &s->rls)) < 0 ||
                (rc = eo_linsolve_analyze(s->rls, s->RA)) < 0)
                ok = 0;
        }
    }
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, s->comm);
    if (!ok && rc >= 0) rc = eo_error(ctx, EO_ERR_LINSOLVE, "petsc_ksp: pc = cholmod failed on rank 0");
    if (ok) {
        EO_PC(VecScatterCreateToZero(s->B, &s->toz, &s->B0));
    }
fail:
    eo_free(ctx, ij);
    eo_free(ctx, all);
    eo_free(ctx, ent);
    return rc;
}

/* The matrix, vectors and KSP for the pattern of A (collective). */
static int build(ksp_state *s, const eo_csc *A)
{
    eo_ctx *ctx = s->ctx;
    int rc = EO_OK;
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
    if (s->root) { /* no PETSc matrix: the vectors and the rank-0 system */
        EO_PC(VecCreateMPI(s->comm, s->nown, s->nglobal, &s->B));
        EO_PC(VecDuplicate(s->B, &s->X));
        if ((rc = root_build(s, A)) < 0) goto fail;
        s->gen = d ? d->gen : 0;
        s->built = 1;
        goto fail;
    }
    if ((rc = eo_petsc_coo_mat(ctx, s->comm, A, s->glob, s->nown, s->nglobal, &s->A, &s->ncoo)) < 0) goto fail;
    EO_PC(PetscMalloc1(s->ncoo + 1, &s->coo_v));
    EO_PC(MatCreateVecs(s->A, &s->X, &s->B));
    EO_PC(VecDuplicate(s->X, &s->W));
    EO_PC(VecDuplicate(s->X, &s->AW));
    if (strcmp(s->p.pc, "gamg") == 0 && d && (rc = eo_petsc_rigid_modes(d, s->A, &s->coords, &s->rbm)) < 0) goto fail;
    if (strcmp(s->p.pc, "gamg") == 0 && !d && (rc = seq_rigid_modes(s)) < 0) goto fail;
    EO_PC(KSPCreate(s->comm, &s->ksp));
    if ((rc = eo_petsc_ksp_configure(ctx, s->ksp, &s->p, NULL, NULL)) < 0) goto fail;
    {
        PC pc;
        PCType pct;
        EO_PC(KSPGetPC(s->ksp, &pc));
        EO_PC(PCGetType(pc, &pct));
        s->direct = pct && strcmp(pct, PCCHOLESKY) == 0; /* MUMPS (or an expert's -pc_type cholesky) */
    }
    if (!s->direct) { /* SPD for the iterative solvers; MUMPS: LDLᵀ with pivoting and its inertia (header) */
        EO_PC(MatSetOption(s->A, MAT_SPD, PETSC_TRUE));
        EO_PC(MatSetOption(s->A, MAT_SPD_ETERNAL, PETSC_TRUE));
    }
    if (s->direct && s->icntl14 > 0) { /* a relaxation grown on an earlier pattern */
        PC pc;
        Mat F;
        EO_PC(KSPSetOperators(s->ksp, s->A, s->A));
        EO_PC(KSPGetPC(s->ksp, &pc));
        EO_PC(PCFactorSetUpMatSolverType(pc));
        EO_PC(PCFactorGetMatrix(pc, &F));
        EO_PC(MatMumpsSetIcntl(F, 14, s->icntl14));
    }
    if (s->rtol > 0) EO_PC(KSPSetTolerances(s->ksp, s->rtol, 1e-300, 1e10, s->p.max_lin_iters));
    s->gen = d ? d->gen : 0;
    s->built = 1;
fail:
    return rc;
}

static int any(ksp_state *s, int v)
{
    MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_INT, MPI_MAX, s->comm);
    return v;
}

/* A negative-curvature witness for a factored A with negative pivots (header): Lanczos on
 * A⁻¹ (PCApply: the factor's solve) from a fixed start vector, with full
 * reorthogonalization; T_k's LDLᵀ (the tridiagonal's Sturm sequence at 0) gives, at its
 * first negative pivot d_m, y = L⁻ᵀe_m with yᵀT_k y = d_m < 0, so v = V_k y has vᵀA⁻¹v < 0;
 * w = A⁻¹v is a witness when wᵀ(Aw) < 0 by MatMult beyond rounding. found = 1 then, curv
 * = wᵀAw/wᵀw. Collective (every decision on reduced values). */
static int witness(ksp_state *s, PC pc, int *found, double *curv)
{
    eo_ctx *ctx = s->ctx;
    int rc = EO_OK;
    double alpha[WITNESS_STEPS], beta[WITNESS_STEPS], dpiv[WITNESS_STEPS], y[WITNESS_STEPS];
    *found = 0;
    *curv = 0;
    for (int i = 0; i <= WITNESS_STEPS; i++)
        if (!s->wv[i]) EO_PC(VecDuplicate(s->X, &s->wv[i]));
    PetscReal anorm = 0;
    EO_PC(MatNorm(s->A, NORM_INFINITY, &anorm));
    /* start: a fixed vector of the global row numbers (no symmetry of the mesh in it) */
    PetscScalar *a;
    PetscInt lo, hi;
    EO_PC(VecGetOwnershipRange(s->wv[0], &lo, &hi));
    EO_PC(VecGetArray(s->wv[0], &a));
    for (PetscInt i = lo; i < hi; i++) a[i - lo] = 1.0 + 0.5 * sin(0.7548776662 * (double)i + 0.3);
    EO_PC(VecRestoreArray(s->wv[0], &a));
    PetscReal nrm;
    EO_PC(VecNormalize(s->wv[0], &nrm));
    for (int k = 0; k < WITNESS_STEPS; k++) {
        EO_PC(PCApply(pc, s->wv[k], s->W)); /* W = A⁻¹ v_k */
        PetscScalar ak;
        EO_PC(VecDot(s->W, s->wv[k], &ak));
        alpha[k] = ak;
        for (int pass = 0; pass < 2; pass++) /* full reorthogonalization, twice */
            for (int j = 0; j <= k; j++) {
                PetscScalar h;
                EO_PC(VecDot(s->W, s->wv[j], &h));
                EO_PC(VecAXPY(s->W, -h, s->wv[j]));
            }
        /* the tridiagonal's LDLᵀ, pivot k */
        dpiv[k] = k == 0 ? alpha[0] : alpha[k] - beta[k - 1] * beta[k - 1] / dpiv[k - 1];
        if (dpiv[k] < 0) {
            /* y = L⁻ᵀ e_k: y_k = 1, y_i = −(β_i/d_i) y_{i+1} */
            y[k] = 1;
            for (int i = k - 1; i >= 0; i--) y[i] = -(beta[i] / dpiv[i]) * y[i + 1];
            EO_PC(VecSet(s->AW, 0));
            for (int i = 0; i <= k; i++) EO_PC(VecAXPY(s->AW, y[i], s->wv[i]));
            EO_PC(PCApply(pc, s->AW, s->W)); /* w = A⁻¹ v */
            EO_PC(MatMult(s->A, s->W, s->AW));
            PetscScalar c, ww;
            EO_PC(VecDot(s->W, s->AW, &c));
            EO_PC(VecDot(s->W, s->W, &ww));
            *curv = ww > 0 ? c / ww : 0;
            /* beyond rounding: |wᵀAw − exact| ≲ nnz-row · eps · ‖A‖∞ ‖w‖² */
            if (c < -1e-12 * anorm * ww) *found = 1;
            break;
        }
        if (k + 1 == WITNESS_STEPS) break;
        EO_PC(VecNorm(s->W, NORM_2, &nrm));
        beta[k] = nrm;
        if (!(nrm > 1e-14 * fabs(alpha[0]))) break; /* an invariant subspace without a negative direction */
        EO_PC(VecCopy(s->W, s->wv[k + 1]));
        EO_PC(VecScale(s->wv[k + 1], 1.0 / nrm));
    }
fail:
    return rc;
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
    if (s->root) {
        int k = 0;
        for (int j = 0; j < A->n; j++)
            for (int q = A->colptr[j]; q < A->colptr[j + 1]; q++) s->upv[k++] = A->val[q];
        if (k != s->nup) return eo_error(ctx, EO_ERR_LINSOLVE, "petsc_ksp: the pattern changed without analyze");
        (void)MPI_Gatherv(s->upv, s->nup, MPI_DOUBLE, s->rvals, s->rcounts, s->rdispls, MPI_DOUBLE, 0, s->comm);
        int frc = EO_OK;
        if (s->rank == 0) {
            for (int q = 0; q < s->RA->nnz; q++) s->RA->val[q] = 0;
            long all = 0;
            int size;
            MPI_Comm_size(s->comm, &size);
            for (int r = 0; r < size; r++) all += s->rcounts[r];
            for (long e = 0; e < all; e++) s->RA->val[s->rslot[e]] += s->rvals[e];
            frc = eo_linsolve_factor(s->rls, s->RA);
            if (frc > 0 && frc != EO_WARN_NOT_PD) frc = EO_OK;
        }
        (void)MPI_Bcast(&frc, 1, MPI_INT, 0, s->comm);
        if (frc == EO_WARN_NOT_PD)
            return eo_error(ctx, EO_WARN_NOT_PD, "petsc_ksp: CHOLMOD's Cholesky factorization failed: the matrix is "
                            "not positive definite");
        if (frc < 0) return eo_error(ctx, EO_ERR_LINSOLVE, "petsc_ksp: CHOLMOD failed on rank 0");
        return EO_OK;
    }
    if (eo_petsc_coo_fill(A, s->coo_v) != s->ncoo) return eo_error(ctx, EO_ERR_LINSOLVE, "petsc_ksp: the pattern changed without analyze");
    EO_PC(MatSetValuesCOO(s->A, s->coo_v, INSERT_VALUES));
    EO_PC(KSPSetOperators(s->ksp, s->A, s->A));
    s->check_curv = 0;
    stats->n_negative = stats->n_zero = -1;
    PC pc;
    EO_PC(KSPGetPC(s->ksp, &pc));
    PetscErrorCode e = 0;
    PCFailedReason why = PC_NOERROR;
    /* a new problem (eo_linsolve_forget): GAMG builds its interpolation from this matrix
     * instead of keeping the one of an earlier problem (PCGAMGSetReuseInterpolation,
     * module.c), so that a step's result does not depend on the steps before it and a
     * restarted run continues bit for bit (3 + 3 twist steps on 2 ranks against 6: the
     * kept interpolation made them 4.9e-11 apart) */
    PetscBool gamg = PETSC_FALSE;
    EO_PC(PetscObjectTypeCompare((PetscObject)pc, PCGAMG, &gamg));
    const int regrow = gamg && s->forget;
    if (regrow) EO_PC(PCGAMGSetReuseInterpolation(pc, PETSC_FALSE));
    s->forget = 0;
    for (int attempt = 0;; attempt++) {
        e = KSPSetUp(s->ksp);
        why = PC_NOERROR;
        if (!e) EO_PC(PCGetFailedReasonRank(pc, &why));
        const int outmem = any(s, !e && why == PC_FACTOR_OUTMEMORY);
        if (!outmem || !s->direct || attempt == OUTMEM_RETRIES) break;
        /* MUMPS' workspace estimate was short (INFOG(1) = -9): not a statement about the
         * matrix; grow ICNTL(14) and factor again (a fresh analysis and factorization) */
        Mat F;
        PetscInt cur = 20;
        EO_PC(PCFactorGetMatrix(pc, &F));
        EO_PC(MatMumpsGetIcntl(F, 14, &cur));
        s->icntl14 = 2 * (cur > 20 ? cur : 20);
        eo_log(ctx, EO_LOG_WARN, "petsc_ksp: MUMPS ran out of its workspace estimate (ICNTL(14) = %d %%); "
               "factoring again with ICNTL(14) = %d %%", (int)cur, (int)s->icntl14);
        /* the options database too: a -mat_mumps_icntl_14 given there (or set by an
         * earlier retry) would otherwise be read again at the analysis and win */
        char v[32];
        snprintf(v, sizeof v, "%d", (int)s->icntl14);
        EO_PC(PetscOptionsSetValue(NULL, "-mat_mumps_icntl_14", v));
        EO_PC(KSPReset(s->ksp));
        EO_PC(KSPSetOperators(s->ksp, s->A, s->A));
        EO_PC(PCFactorSetUpMatSolverType(pc));
        EO_PC(PCFactorGetMatrix(pc, &F));
        EO_PC(MatMumpsSetIcntl(F, 14, s->icntl14));
    }
    if (regrow) EO_PC(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE));
    int failed = e != 0 || why != PC_NOERROR;
    if (any(s, failed)) {
        stats->not_pd_column = -1;
        return eo_error(ctx, EO_WARN_NOT_PD, "petsc_ksp: the factorization failed (%s): the matrix is not positive "
                        "definite", e ? "PETSc error" : PCFailedReasons[why]);
    }
    if (s->direct) {
        Mat F;
        PetscInt nneg = 0;
        EO_PC(PCFactorGetMatrix(pc, &F));
        EO_PC(MatGetInertia(F, &nneg, NULL, NULL));
        int nn = (int)nneg; /* INFOG is global; the same value on every rank made sure of */
        MPI_Allreduce(MPI_IN_PLACE, &nn, 1, MPI_INT, MPI_MAX, s->comm);
        nneg = nn;
        stats->n_negative = (int)nneg;
        if (nneg > 0) {
            double curv = 0;
            int found = 0;
            if ((rc = witness(s, pc, &found, &curv)) < 0) return rc;
            if (found) {
                stats->not_pd_column = -1;
                return eo_error(ctx, EO_WARN_NOT_PD, "petsc_ksp: the matrix is not positive definite (MUMPS LDLᵀ: %d "
                                "negative pivots; a direction of curvature %.3g found)", (int)nneg, curv);
            }
            eo_log(ctx, EO_LOG_WARN, "petsc_ksp: MUMPS counted %d negative pivots, but %d Lanczos steps on the "
                   "inverse found no direction of negative curvature: the matrix is used as positive definite",
                   (int)nneg, WITNESS_STEPS);
        }
        s->check_curv = 1;
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
    PetscErrorCode e = 0;
    KSPConvergedReason kr = KSP_CONVERGED_ITS;
    if (s->root) {
        EO_PC(VecScatterBegin(s->toz, s->B, s->B0, INSERT_VALUES, SCATTER_FORWARD));
        EO_PC(VecScatterEnd(s->toz, s->B, s->B0, INSERT_VALUES, SCATTER_FORWARD));
        int src = EO_OK;
        if (s->rank == 0) {
            PetscScalar *b0;
            EO_PC(VecGetArray(s->B0, &b0));
            memcpy(s->rb, b0, (size_t)s->nglobal * sizeof(double));
            src = eo_linsolve_solve(s->rls, s->rb, s->rx);
            memcpy(b0, s->rx, (size_t)s->nglobal * sizeof(double));
            EO_PC(VecRestoreArray(s->B0, &b0));
        }
        (void)MPI_Bcast(&src, 1, MPI_INT, 0, s->comm);
        if (src < 0) return eo_error(ctx, EO_ERR_LINSOLVE, "petsc_ksp: CHOLMOD's solve failed on rank 0");
        EO_PC(VecScatterBegin(s->toz, s->B0, s->X, INSERT_VALUES, SCATTER_REVERSE));
        EO_PC(VecScatterEnd(s->toz, s->B0, s->X, INSERT_VALUES, SCATTER_REVERSE));
        stats->iterations = 0;
        goto back;
    }
    e = KSPSolve(s->ksp, s->B, s->X);
    kr = KSP_DIVERGED_PC_FAILED;
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
back:
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
    if (s->check_curv && !e && kr >= 0) {
        /* the count said PD: the solved direction's curvature, by MatMult (header) */
        PetscScalar c, bb;
        EO_PC(MatMult(s->A, s->X, s->AW));
        EO_PC(VecDot(s->X, s->AW, &c));
        EO_PC(VecDot(s->B, s->B, &bb));
        if (bb > 0 && !(c > 0)) {
            stats->curvature = c;
            return eo_error(ctx, EO_WARN_NOT_PD, "petsc_ksp: MUMPS counted no negative pivot, but the solved "
                            "direction has curvature dᵀAd = %.3g ≤ 0: the matrix is not positive definite", c);
        }
    }
    if (e || kr < 0)
        return eo_error(ctx, EO_WARN_NOT_CONVERGED, "petsc_ksp: the solve did not converge (%s)",
                        e ? "PETSc error" : KSPConvergedReasons[kr]);
fail:
    return rc;
}

static void ks_set_rtol(void *st, double rtol)
{
    ksp_state *s = st;
    if (s->root) return;
    s->rtol = rtol;
    if (s->ksp) KSPSetTolerances(s->ksp, rtol, 1e-300, 1e10, s->p.max_lin_iters);
}

/* Reported as direct, so that newton's forcing = auto leaves solver.petsc_ksp.rtol in force
 * (measured: auto's Eisenstat-Walker terms with CG + GAMG left a step of the inverted
 * scene unconverged and 0.03 m off the serial answer; rtol = 1e-10: 7e-13); an explicit
 * solver.newton.forcing (constant, ew1, ew2) still sets the tolerance through set_rtol. */
static int ks_is_iterative(const void *st)
{
    (void)st;
    return 0;
}

static void ks_forget(void *st)
{
    ksp_state *s = st;
    s->forget = 1;
}

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
    .set_coordinates = ks_set_coordinates,
    .forget = ks_forget,
};
