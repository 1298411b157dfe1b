/* The distributed step problem (petsc_backend.h, eo_dist): each rank's step engine is
 * built on its local mesh (dmplex.c), so its objective is the rank's share of g: the sum
 * of the local objectives is the global g (every term is an element sum, masses
 * included). This file numbers the free coordinates globally and moves data between the
 * local free vector the step objective reads and the distributed PETSc vectors:
 *
 *   numbering   the free coordinates of the vertices a rank owns are the rows
 *               [rstart, rstart + nown) (vertex triples together); a ghost vertex's rows
 *               come from its owner over the layout's vertex SF
 *   x           X (distributed) -> the local free vector (VecScatter, ghosts included)
 *   g           local value, summed with MPI_Allreduce
 *   ∇g          local gradient, summed onto the owners (the reverse scatter, ADD_VALUES)
 *   ∇²g         the local Hessian (the step's upper-triangle CSC) as COO entries of both
 *               triangles in global rows and columns (MatSetPreallocationCOO once per
 *               pattern; MatSetValuesCOO sums the duplicates of shared vertices)
 *
 * On one rank (an MPI singleton, elastopt bench) the whole step engine is the rank's part. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "petsc_backend.h"

/* ---------------------------------------------------------------- numbering */

static void numbering_free(eo_dist *d)
{
    eo_ctx *ctx = d->ctx;
    PetscFree(d->lglob);
    eo_free(ctx, d->grep);
    d->grep = NULL;
    PetscFree(d->coo_v);
    d->ncoo = 0;
    VecDestroy(&d->xl);
    VecScatterDestroy(&d->to_local);
    MatDestroy(&d->A);
    VecDestroy(&d->coords);
    MatNullSpaceDestroy(&d->rbm);
    d->have_pattern = 0;
}

static int numbering(eo_dist *d, int n)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    numbering_free(d);
    const eo_mesh *m = eo_step_mesh(d->st);
    const eo_petsc_layout *L = eo_petsc_layout_get();
    if (d->size > 1 && (!L || L->nv != m->nv || L->nt != m->nt))
        return eo_error(ctx, EO_ERR_UNSUPPORTED, "petsc backend: under mpirun the step problem must be the "
                        "distributed scene's (its mesh is this rank's part)");
    d->n = n;
    const int nv = m->nv;
    PetscInt *vrow = NULL, *grow = NULL;
    Vec X = NULL;
    IS is = NULL;
    d->grep = eo_calloc(ctx, (size_t)(n > 0 ? n : 1), sizeof(double));
    if (!d->grep) return eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (numbering)");
    EO_PC(PetscMalloc1(3 * (size_t)nv + 1, &vrow));
    EO_PC(PetscMalloc1(3 * (size_t)nv + 1, &grow));
    int nown = 0;
    for (int v = 0; v < nv; v++)
        for (int c = 0; c < 3; c++)
            if ((!L || L->owned[v]) && eo_step_full_to_free(d->st, 3 * v + c) >= 0) nown++;
    int rstart = 0;
    MPI_Exscan(&nown, &rstart, 1, MPI_INT, MPI_SUM, d->comm);
    if (d->rank == 0) rstart = 0;
    d->nown = nown, d->rstart = rstart;
    MPI_Allreduce(&nown, &d->nglobal, 1, MPI_INT, MPI_SUM, d->comm);
    int r = rstart;
    for (int v = 0; v < nv; v++)
        for (int c = 0; c < 3; c++)
            vrow[3 * v + c] = (!L || L->owned[v]) && eo_step_full_to_free(d->st, 3 * v + c) >= 0 ? r++ : -1;
    memcpy(grow, vrow, 3 * (size_t)nv * sizeof *vrow);
    if (L) { /* the ghosts' rows from their owners */
        MPI_Datatype unit;
        MPI_Type_contiguous(3, MPIU_INT, &unit);
        MPI_Type_commit(&unit);
        PetscErrorCode e1 = PetscSFBcastBegin(L->vsf, unit, vrow, grow, MPI_REPLACE);
        PetscErrorCode e2 = e1 ? e1 : PetscSFBcastEnd(L->vsf, unit, vrow, grow, MPI_REPLACE);
        MPI_Type_free(&unit);
        EO_PC(e2);
    }
    EO_PC(PetscMalloc1(n + 1, &d->lglob));
    int bad = -1;
    for (int i = 0; i < n; i++) {
        const int j = eo_step_free_to_full(d->st, i);
        d->lglob[i] = grow[j];
        if (grow[j] < 0 && bad < 0) bad = j / 3;
    }
    int anybad = bad >= 0;
    MPI_Allreduce(MPI_IN_PLACE, &anybad, 1, MPI_INT, MPI_MAX, d->comm);
    if (anybad) {
        rc = bad >= 0 ? eo_error(ctx, EO_ERR_INVALID, "petsc backend: rank %d: vertex %d (input vertex %d) is free "
                                 "here and constrained on its owner", d->rank, bad, L ? (int)L->gid[bad] : bad)
                      : eo_error(ctx, EO_ERR_INVALID, "petsc backend: another rank's constraints differ from its "
                                 "vertices' owners'");
        goto fail;
    }
    EO_PC(VecCreateMPI(d->comm, d->nown, d->nglobal, &X));
    EO_PC(VecCreateSeq(PETSC_COMM_SELF, n, &d->xl));
    EO_PC(ISCreateGeneral(PETSC_COMM_SELF, n, d->lglob, PETSC_COPY_VALUES, &is));
    EO_PC(VecScatterCreate(X, is, d->xl, NULL, &d->to_local));
    d->have_pattern = 1;
fail:
    PetscFree(vrow);
    PetscFree(grow);
    ISDestroy(&is);
    VecDestroy(&X);
    return rc;
}

/* ---------------------------------------------------------------- matrix */

int eo_petsc_coo_mat(eo_ctx *ctx, MPI_Comm comm, const eo_csc *H, const PetscInt *glob, int nown, int nglobal,
                     Mat *A, PetscCount *ncoo)
{
    int rc = EO_OK;
    PetscInt *ci = NULL, *cj = NULL;
    PetscCount nc = 0;
    for (int j = 0; j < H->n; j++)
        for (int q = H->colptr[j]; q < H->colptr[j + 1]; q++) nc += H->rowind[q] == j ? 1 : 2;
    EO_PC(PetscMalloc1(nc + 1, &ci));
    EO_PC(PetscMalloc1(nc + 1, &cj));
    PetscCount k = 0;
    for (int j = 0; j < H->n; j++)
        for (int q = H->colptr[j]; q < H->colptr[j + 1]; q++) {
            const int i = H->rowind[q];
            ci[k] = glob[i], cj[k++] = glob[j];
            if (i != j) ci[k] = glob[j], cj[k++] = glob[i];
        }
    *ncoo = nc;
    int bs3 = nown % 3 == 0;
    MPI_Allreduce(MPI_IN_PLACE, &bs3, 1, MPI_INT, MPI_MIN, comm);
    EO_PC(MatCreate(comm, A));
    EO_PC(MatSetSizes(*A, nown, nown, nglobal, nglobal));
    EO_PC(MatSetType(*A, MATAIJ));
    if (bs3) EO_PC(MatSetBlockSize(*A, 3));
    EO_PC(MatSetPreallocationCOO(*A, nc, ci, cj));
    EO_PC(MatSetOption(*A, MAT_SYMMETRIC, PETSC_TRUE));
    EO_PC(MatSetOption(*A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
fail:
    PetscFree(ci);
    PetscFree(cj);
    return rc;
}

PetscCount eo_petsc_coo_fill(const eo_csc *H, PetscScalar *v)
{
    PetscCount k = 0;
    for (int j = 0; j < H->n; j++)
        for (int q = H->colptr[j]; q < H->colptr[j + 1]; q++) {
            v[k++] = H->val[q];
            if (H->rowind[q] != j) v[k++] = H->val[q];
        }
    return k;
}

int eo_petsc_rigid_modes(const eo_dist *d, Mat A, Vec *coords, MatNullSpace *ns)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    PetscInt bs = 1;
    EO_PC(MatGetBlockSize(A, &bs));
    if (bs != 3) return EO_OK;
    EO_PC(MatCreateVecs(A, coords, NULL));
    EO_PC(VecSetBlockSize(*coords, 3));
    const double *x0 = eo_step_x0(d->st);
    PetscScalar *a;
    EO_PC(VecGetArray(*coords, &a));
    for (int i = 0; i < d->n; i++) {
        const PetscInt g = d->lglob[i] - d->rstart;
        if (g >= 0 && g < d->nown) a[g] = x0[eo_step_free_to_full(d->st, i)];
    }
    EO_PC(VecRestoreArray(*coords, &a));
    EO_PC(MatNullSpaceCreateRigidBody(*coords, ns));
    EO_PC(MatSetNearNullSpace(A, *ns));
fail:
    return rc;
}

/* The MPIAIJ of the local Hessians (COO of both triangles in global rows and columns), with
 * GAMG's rigid-body modes. */
static int matrix_build(eo_dist *d, const eo_csc *H, const eo_petsc_params *p)
{
    eo_ctx *ctx = d->ctx;
    int rc = eo_petsc_coo_mat(ctx, d->comm, H, d->lglob, d->nown, d->nglobal, &d->A, &d->ncoo);
    if (rc < 0) return rc;
    EO_PC(PetscMalloc1(d->ncoo + 1, &d->coo_v));
    if (strcmp(p->pc, "gamg") == 0) rc = eo_petsc_rigid_modes(d, d->A, &d->coords, &d->rbm);
fail:
    return rc;
}

/* ---------------------------------------------------------------- public */

int eo_dist_setup(eo_dist *d, eo_ctx *ctx, eo_objective *obj, const eo_petsc_params *p)
{
    int rc = eo_petsc_ensure(ctx);
    if (rc < 0) return rc;
    eo_step *st = eo_step_of_objective(obj);
    if (!st)
        return eo_error(ctx, EO_ERR_UNSUPPORTED, "petsc backend: the objective is not a step problem of a scene "
                        "(distributed optimizers need eo_sim's step objective)");
    d->params = p;
    if (!d->ctx) {
        d->ctx = ctx;
        d->comm = PETSC_COMM_WORLD;
        MPI_Comm_rank(d->comm, &d->rank);
        MPI_Comm_size(d->comm, &d->size);
    }
    int renumber = !d->have_pattern || st != d->st || d->pattern != eo_step_pattern_id(st) || d->n != obj->n;
    MPI_Allreduce(MPI_IN_PLACE, &renumber, 1, MPI_INT, MPI_MAX, d->comm); /* a free set changed somewhere */
    if (renumber) {
        d->st = st;
        if ((rc = numbering(d, obj->n)) < 0) {
            d->st = NULL;
            return rc;
        }
        d->pattern = eo_step_pattern_id(st);
        d->gen++;
    }
    return EO_OK;
}

void eo_dist_destroy(eo_dist *d)
{
    if (!d->ctx) return;
    numbering_free(d);
    const unsigned long gen = d->gen;
    memset(d, 0, sizeof *d);
    d->gen = gen + 1;
}

int eo_dist_vec(eo_dist *d, Vec *v)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    EO_PC(VecCreateMPI(d->comm, d->nown, d->nglobal, v));
    if (d->A) {
        PetscInt bs = 1;
        EO_PC(MatGetBlockSize(d->A, &bs));
        if (bs == 3) EO_PC(VecSetBlockSize(*v, 3));
    }
fail:
    return rc;
}

int eo_dist_from_rep(eo_dist *d, const double *x, Vec X)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    PetscScalar *a;
    EO_PC(VecGetArray(X, &a));
    for (int i = 0; i < d->n; i++) {
        const PetscInt g = d->lglob[i] - d->rstart;
        if (g >= 0 && g < d->nown) a[g] = x[i];
    }
    EO_PC(VecRestoreArray(X, &a));
fail:
    return rc;
}

/* X -> the local free vector d->xl */
static int to_local(eo_dist *d, Vec X)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    EO_PC(VecScatterBegin(d->to_local, X, d->xl, INSERT_VALUES, SCATTER_FORWARD));
    EO_PC(VecScatterEnd(d->to_local, X, d->xl, INSERT_VALUES, SCATTER_FORWARD));
fail:
    return rc;
}

int eo_dist_to_rep(eo_dist *d, Vec X, double *x)
{
    eo_ctx *ctx = d->ctx;
    int rc = to_local(d, X);
    if (rc < 0) return rc;
    const PetscScalar *a;
    EO_PC(VecGetArrayRead(d->xl, &a));
    memcpy(x, a, (size_t)d->n * sizeof(double));
    EO_PC(VecRestoreArrayRead(d->xl, &a));
fail:
    return rc;
}

int eo_dist_sum_rep(eo_dist *d, const double *v, Vec V)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    PetscScalar *a;
    EO_PC(VecGetArray(d->xl, &a));
    memcpy(a, v, (size_t)d->n * sizeof(double));
    EO_PC(VecRestoreArray(d->xl, &a));
    EO_PC(VecSet(V, 0));
    EO_PC(VecScatterBegin(d->to_local, d->xl, V, ADD_VALUES, SCATTER_REVERSE));
    EO_PC(VecScatterEnd(d->to_local, d->xl, V, ADD_VALUES, SCATTER_REVERSE));
fail:
    return rc;
}

double eo_dist_sum(eo_dist *d, double v)
{
    double s = 0;
    MPI_Allreduce(&v, &s, 1, MPI_DOUBLE, MPI_SUM, d->comm);
    return s;
}

static double sum_all(eo_dist *d, double v)
{
    double s = eo_dist_sum(d, v);
    return isnan(s) ? INFINITY : s;
}

int eo_dist_value(eo_dist *d, eo_objective *obj, Vec X, double *g)
{
    eo_ctx *ctx = d->ctx;
    int rc = to_local(d, X);
    if (rc < 0) return rc;
    const PetscScalar *a;
    double gl = 0;
    EO_PC(VecGetArrayRead(d->xl, &a));
    rc = eo_objective_value(obj, a, &gl);
    EO_PC(VecRestoreArrayRead(d->xl, &a));
    if (rc < 0) return rc;
    *g = sum_all(d, gl);
    d->n_value++;
fail:
    return rc;
}

int eo_dist_gradient(eo_dist *d, eo_objective *obj, Vec X, double *g, Vec G)
{
    eo_ctx *ctx = d->ctx;
    int rc = to_local(d, X);
    if (rc < 0) return rc;
    double gl = 0;
    PetscScalar *a;
    EO_PC(VecGetArray(d->xl, &a));
    rc = eo_objective_gradient(obj, a, &gl, d->grep);
    if (rc >= 0)
        for (int i = 0; i < d->n; i++) a[i] = isfinite(gl) ? d->grep[i] : 0;
    EO_PC(VecRestoreArray(d->xl, &a));
    if (rc < 0) return rc;
    *g = sum_all(d, gl);
    d->n_gradient++;
    EO_PC(VecSet(G, 0));
    EO_PC(VecScatterBegin(d->to_local, d->xl, G, ADD_VALUES, SCATTER_REVERSE));
    EO_PC(VecScatterEnd(d->to_local, d->xl, G, ADD_VALUES, SCATTER_REVERSE));
fail:
    return rc;
}

int eo_dist_hessian(eo_dist *d, eo_objective *obj, Vec X, eo_proj proj)
{
    eo_ctx *ctx = d->ctx;
    int rc = to_local(d, X);
    if (rc < 0) return rc;
    eo_csc *H = NULL;
    const PetscScalar *a;
    EO_PC(VecGetArrayRead(d->xl, &a));
    rc = eo_objective_hessian(obj, a, proj, &H);
    EO_PC(VecRestoreArrayRead(d->xl, &a));
    if (rc < 0) return rc;
    d->n_hessian++;
    if (!d->A && (rc = matrix_build(d, H, d->params)) < 0) return rc;
    if (eo_petsc_coo_fill(H, d->coo_v) != d->ncoo) return eo_error(ctx, EO_ERR_LINSOLVE, "petsc: the Hessian's pattern changed without a release");
    EO_PC(MatSetValuesCOO(d->A, d->coo_v, INSERT_VALUES));
fail:
    return rc;
}

int eo_dist_inverted(eo_dist *d, eo_objective *obj, Vec X)
{
    if (!obj->ops->inverted_count || to_local(d, X) < 0) return -1;
    const PetscScalar *a;
    if (VecGetArrayRead(d->xl, &a)) return -1;
    int n = obj->ops->inverted_count(obj->data, a), s = 0;
    VecRestoreArrayRead(d->xl, &a);
    MPI_Allreduce(&n, &s, 1, MPI_INT, MPI_SUM, d->comm);
    return s;
}
