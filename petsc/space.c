/* The vector space of a distributed step objective (petsc_backend.h, eo_petsc_space): the
 * context hook eo_dist_hooks.space with which the library's own optimizers run on the
 * ranks' parts (solvers/dist_objective.c, objective.h eo_vspace).
 *
 * The numbering is eo_dist's (dist.c): the free coordinates of the vertices a rank owns
 * are the global rows [rstart, rstart + nown); a ghost's row comes from its owner. A local
 * entry is owned when its row lies in that range. assemble sums the ranks' partial values
 * onto the owners (the reverse scatter, ADD_VALUES) and hands the totals back to every
 * copy (the forward scatter); reduce is MPI_Allreduce on PETSC_COMM_WORLD. */
#include <string.h>

#include "petsc_backend.h"

static eo_petsc_space g_space;

static int space_reduce(double *v, int n, eo_reduce_op op, void *user)
{
    eo_petsc_space *s = user;
    MPI_Op o = op == EO_REDUCE_MIN ? MPI_MIN : op == EO_REDUCE_MAX ? MPI_MAX : MPI_SUM;
    return MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, o, s->d.comm) == MPI_SUCCESS ? 0 : EO_ERR_IO;
}

static int space_assemble(double *v, void *user)
{
    eo_petsc_space *s = user;
    eo_dist *d = &s->d;
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    if ((rc = eo_dist_sum_rep(d, v, s->G)) < 0) return rc;
    EO_PC(VecScatterBegin(d->to_local, s->G, d->xl, INSERT_VALUES, SCATTER_FORWARD));
    EO_PC(VecScatterEnd(d->to_local, s->G, d->xl, INSERT_VALUES, SCATTER_FORWARD));
    const PetscScalar *r;
    EO_PC(VecGetArrayRead(d->xl, &r));
    memcpy(v, r, (size_t)d->n * sizeof(double));
    EO_PC(VecRestoreArrayRead(d->xl, &r));
fail:
    return rc;
}

int eo_petsc_space_is(const eo_vspace *vs) { return vs && vs->assemble == space_assemble; }

static const eo_petsc_params space_params = {.ksp = "preonly", .pc = "mumps", .rtol = 1e-10, .max_lin_iters = 1};

int eo_petsc_space_hook(eo_ctx *ctx, eo_objective *obj, const eo_vspace **out, void *user)
{
    (void)user;
    eo_petsc_space *s = &g_space;
    const unsigned long gen0 = s->d.gen;
    int rc = eo_dist_setup(&s->d, ctx, obj, &space_params);
    if (rc < 0) return rc;
    eo_dist *d = &s->d;
    if (d->gen != gen0 || !s->G) {
        VecDestroy(&s->G);
        eo_free(ctx, s->own);
        eo_free(ctx, s->gid);
        s->own = NULL, s->gid = NULL;
        EO_PC(VecCreateMPI(d->comm, d->nown, d->nglobal, &s->G));
        const size_t m = (size_t)(d->n > 0 ? d->n : 1);
        s->own = eo_calloc(ctx, m, 1);
        s->gid = eo_calloc(ctx, m, sizeof(long));
        if (!s->own || !s->gid) return eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (vector space)");
        for (int i = 0; i < d->n; i++) {
            s->gid[i] = (long)d->lglob[i];
            s->own[i] = d->lglob[i] >= d->rstart && d->lglob[i] < d->rstart + d->nown;
        }
    }
    s->vs = (eo_vspace){.n = d->n, .nglobal = d->nglobal, .own = s->own, .gid = s->gid, .reduce = space_reduce,
                        .assemble = space_assemble, .user = s, .nparts = d->size, .part = d->rank};
    *out = &s->vs;
    return EO_OK;
fail:
    return rc;
}
