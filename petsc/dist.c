/* The distributed step problem (petsc_backend.h): partition of the tets, numbering of the
 * free coordinates by owner rank, distributed evaluation of g, ∇g and the projected
 * Hessian through the step objective's partitioned evaluation (eo_step_set_part).
 *
 * Partition (once per step engine): tet owner from PETSc's MatPartitioning (PT-Scotch) on
 * the face dual graph, each rank giving the rows of a contiguous block of tets; or
 * `slab`: equal-count slabs along the longest axis of the tet centroids. A vertex belongs
 * to the lowest rank among the owners of its tets, so an owned vertex always lies in a
 * tet of its rank.
 * Numbering (once per free set): the free coordinates of the vertices of rank r are rows
 * [rstart_r, rstart_r + nown_r), in increasing free index (vertex triples stay together:
 * block size 3).
 * Evaluation: X (distributed) is scattered to the coordinates of the rank's vertices
 * (owned and shared), written into the replicated free vector the step objective reads,
 * the objective adds the rank's part; values are summed with MPI_Allreduce, gradients
 * added back with the reverse scatter, the Hessian's entries of the rank's tets are read
 * from the step's CSC (positions found once per free set) into MPIAIJ rows (ADD_VALUES,
 * preallocated from the whole pattern). */
#include <math.h>
#if EO_PETSC_SCOTCH
#include <stdint.h>
#include <stdio.h>
#include <scotch.h>
#endif
#include <stdlib.h>
#include <string.h>

#include "petsc_backend.h"

/* ---------------------------------------------------------------- partition */

typedef struct face_key {
    int v[3];
    int tet;
} face_key;

static int face_cmp(const void *a, const void *b)
{
    const face_key *x = a, *y = b;
    for (int i = 0; i < 3; i++)
        if (x->v[i] != y->v[i]) return x->v[i] < y->v[i] ? -1 : 1;
    return x->tet < y->tet ? -1 : x->tet > y->tet;
}

static void sort3(int *v)
{
    int t;
    if (v[0] > v[1]) t = v[0], v[0] = v[1], v[1] = t;
    if (v[1] > v[2]) t = v[1], v[1] = v[2], v[2] = t;
    if (v[0] > v[1]) t = v[0], v[0] = v[1], v[1] = t;
}

/* nb[4k..4k+3]: face neighbours of tet k (-1 none) */
static int dual_graph(eo_ctx *ctx, const eo_mesh *m, int *nb)
{
    face_key *f = eo_malloc(ctx, (size_t)(4 * (m->nt > 0 ? m->nt : 1)) * sizeof *f);
    if (!f) return eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (dual graph)");
    static const int fv[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    for (int k = 0; k < m->nt; k++)
        for (int a = 0; a < 4; a++) {
            face_key *q = f + 4 * k + a;
            for (int i = 0; i < 3; i++) q->v[i] = m->tets[4 * k + fv[a][i]];
            sort3(q->v);
            q->tet = k;
        }
    qsort(f, (size_t)(4 * m->nt), sizeof *f, face_cmp);
    for (int i = 0; i < 4 * m->nt; i++) nb[i] = -1;
    int *cnt = eo_calloc(ctx, (size_t)(m->nt > 0 ? m->nt : 1), sizeof(int));
    if (!cnt) {
        eo_free(ctx, f);
        return eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (dual graph)");
    }
    for (int i = 0; i + 1 < 4 * m->nt; i++) {
        if (f[i].v[0] != f[i + 1].v[0] || f[i].v[1] != f[i + 1].v[1] || f[i].v[2] != f[i + 1].v[2]) continue;
        int a = f[i].tet, b = f[i + 1].tet;
        if (a == b || cnt[a] >= 4 || cnt[b] >= 4) continue;
        nb[4 * a + cnt[a]++] = b;
        nb[4 * b + cnt[b]++] = a;
    }
    eo_free(ctx, cnt);
    eo_free(ctx, f);
    return EO_OK;
}

static const eo_mesh *g_sort_mesh;
static int g_sort_axis;
static double centroid(const eo_mesh *m, int k, int axis)
{
    double c = 0;
    for (int a = 0; a < 4; a++) c += m->X[3 * m->tets[4 * k + a] + axis];
    return c;
}
static int slab_cmp(const void *a, const void *b)
{
    int i = *(const int *)a, j = *(const int *)b;
    double ci = centroid(g_sort_mesh, i, g_sort_axis), cj = centroid(g_sort_mesh, j, g_sort_axis);
    if (ci != cj) return ci < cj ? -1 : 1;
    return i < j ? -1 : i > j;
}

static int partition_slab(eo_dist *d, const eo_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < m->nv; v++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], m->X[3 * v + c]);
            hi[c] = fmax(hi[c], m->X[3 * v + c]);
        }
    int axis = 0;
    for (int c = 1; c < 3; c++)
        if (hi[c] - lo[c] > hi[axis] - lo[axis]) axis = c;
    int *order = eo_malloc(d->ctx, (size_t)(m->nt > 0 ? m->nt : 1) * sizeof(int));
    if (!order) return eo_error(d->ctx, EO_ERR_NOMEM, "petsc: out of memory (partition)");
    for (int k = 0; k < m->nt; k++) order[k] = k;
    g_sort_mesh = m;
    g_sort_axis = axis;
    qsort(order, (size_t)m->nt, sizeof(int), slab_cmp);
    for (int q = 0; q < m->nt; q++) d->tet_owner[order[q]] = (int)((long)q * d->size / m->nt);
    eo_free(d->ctx, order);
    return EO_OK;
}

#if EO_PETSC_SCOTCH
/* Scotch's graph partitioning in a context with a fixed random seed and deterministic
 * threads: the same partition in every run. */
static int scotch_part(eo_ctx *ctx, int n, const PetscInt *ia, const PetscInt *ja, int nparts, int *owner)
{
    int rc = EO_OK;
    SCOTCH_Num *vt = eo_malloc(ctx, (size_t)(n + 1) * sizeof *vt);
    SCOTCH_Num *et = eo_malloc(ctx, (size_t)(ia[n] > 0 ? ia[n] : 1) * sizeof *et);
    SCOTCH_Num *pt = eo_malloc(ctx, (size_t)(n > 0 ? n : 1) * sizeof *pt);
    SCOTCH_Context *cx = SCOTCH_contextAlloc();
    SCOTCH_Graph g, gc;
    SCOTCH_Strat strat;
    int have_g = 0, have_gc = 0, have_s = 0, have_cx = 0;
    if (!vt || !et || !pt || !cx) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (partition)");
        goto done;
    }
    for (int i = 0; i <= n; i++) vt[i] = (SCOTCH_Num)ia[i];
    for (PetscInt k = 0; k < ia[n]; k++) et[k] = (SCOTCH_Num)ja[k];
    if (SCOTCH_contextInit(cx) != 0) goto bad;
    have_cx = 1;
    SCOTCH_contextRandomSeed(cx, 1);
    if (SCOTCH_contextOptionSetNum(cx, SCOTCH_OPTIONNUMDETERMINISTIC, 1) != 0 ||
        SCOTCH_contextOptionSetNum(cx, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1) != 0)
        goto bad;
    if (SCOTCH_graphInit(&g) != 0) goto bad;
    have_g = 1;
    if (SCOTCH_graphBuild(&g, 0, n, vt, NULL, NULL, NULL, vt[n], et, NULL) != 0) goto bad;
    if (SCOTCH_graphInit(&gc) != 0) goto bad;
    have_gc = 1;
    if (SCOTCH_contextBindGraph(cx, &g, &gc) != 0) goto bad;
    if (SCOTCH_stratInit(&strat) != 0) goto bad;
    have_s = 1;
    if (SCOTCH_stratGraphMapBuild(&strat, SCOTCH_STRATQUALITY, nparts, 0.01) != 0) goto bad;
    if (SCOTCH_graphPart(&gc, nparts, &strat, pt) != 0) goto bad;
    for (int i = 0; i < n; i++) owner[i] = (int)pt[i];
    goto done;
bad:
    rc = eo_error(ctx, EO_ERR_LINSOLVE, "petsc: Scotch could not partition the %d tets into %d parts", n, nparts);
done:
    if (have_s) SCOTCH_stratExit(&strat);
    if (have_gc) SCOTCH_graphExit(&gc);
    if (have_g) SCOTCH_graphExit(&g);
    if (have_cx) SCOTCH_contextExit(cx);
    if (cx) SCOTCH_memFree(cx);
    eo_free(ctx, vt);
    eo_free(ctx, et);
    eo_free(ctx, pt);
    return rc;
}
#endif

/* Scotch on the face dual graph, run on rank 0 alone, the owners broadcast. Through PETSc's
 * MatPartitioning (PT-Scotch on all ranks, or on rank 0 alone, with or without
 * SCOTCH_randomSeed) every run got another partition of the 20k-tet twist (4 runs, 4
 * partitions, all with the minimal 128-face cut), and with it another GAMG hierarchy and
 * CG iteration count; Scotch's own graph partitioning in a context with a fixed seed and
 * deterministic threads gives the same partition every run. The whole dual graph is built
 * on rank 0 only (the other ranks wait for the owners). */
static int partition_ptscotch(eo_dist *d, const eo_mesh *m)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    int *nb = NULL;
    Mat adj = NULL;
    MatPartitioning part = NULL;
    IS is = NULL;
    char msg[512] = "";
    if (d->rank == 0) {
        nb = eo_malloc(ctx, (size_t)(4 * (m->nt > 0 ? m->nt : 1)) * sizeof(int));
        if (!nb) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (partition)");
            goto fail;
        }
        if ((rc = dual_graph(ctx, m, nb)) < 0) goto fail;
        const int nk = m->nt;
        PetscInt *ia, *ja;
        EO_PC(PetscMalloc1(nk + 1, &ia));
        EO_PC(PetscMalloc1(4 * nk + 1, &ja));
        ia[0] = 0;
        for (int q = 0; q < nk; q++) {
            ia[q + 1] = ia[q];
            for (int a = 0; a < 4; a++)
                if (nb[4 * q + a] >= 0) ja[ia[q + 1]++] = nb[4 * q + a];
        }
        eo_free(ctx, nb);
        nb = NULL;
#if EO_PETSC_SCOTCH
        rc = scotch_part(ctx, nk, ia, ja, d->size, d->tet_owner);
        PetscFree(ia);
        PetscFree(ja);
        if (rc < 0) goto fail;
#else /* Scotch's header missing: PETSc's PT-Scotch interface (a new partition every run) */
        EO_PC(MatCreateMPIAdj(PETSC_COMM_SELF, nk, nk, ia, ja, NULL, &adj)); /* takes ia, ja */
        EO_PC(MatPartitioningCreate(PETSC_COMM_SELF, &part));
        EO_PC(MatPartitioningSetAdjacency(part, adj));
        EO_PC(MatPartitioningSetType(part, MATPARTITIONINGPTSCOTCH));
        EO_PC(MatPartitioningSetNParts(part, d->size));
        EO_PC(MatPartitioningApply(part, &is));
        const PetscInt *idx;
        EO_PC(ISGetIndices(is, &idx));
        for (int q = 0; q < nk; q++) d->tet_owner[q] = (int)idx[q];
        EO_PC(ISRestoreIndices(is, &idx));
#endif
    }
fail:
    if (rc < 0) snprintf(msg, sizeof msg, "%s", eo_ctx_message(ctx));
    eo_free(ctx, nb);
    ISDestroy(&is);
    MatPartitioningDestroy(&part);
    MatDestroy(&adj);
    int st = rc; /* rank 0's outcome, then the owners */
    if (MPI_Bcast(&st, 1, MPI_INT, 0, d->comm) != MPI_SUCCESS ||
        MPI_Bcast(msg, (int)sizeof msg, MPI_CHAR, 0, d->comm) != MPI_SUCCESS)
        return eo_error(ctx, EO_ERR_LINSOLVE, "petsc: the broadcast of the partition failed");
    if (st < 0) return d->rank == 0 ? rc : eo_error(ctx, st, "%s", msg);
    if (MPI_Bcast(d->tet_owner, m->nt, MPI_INT, 0, d->comm) != MPI_SUCCESS)
        return eo_error(ctx, EO_ERR_LINSOLVE, "petsc: the broadcast of the partition failed");
    return EO_OK;
}

static void partition_free(eo_dist *d)
{
    eo_ctx *ctx = d->ctx;
    eo_free(ctx, d->tet_owner);
    eo_free(ctx, d->vert_owner);
    eo_free(ctx, d->my_tets);
    eo_free(ctx, d->my_verts);
    eo_free(ctx, d->vown);
    d->tet_owner = d->vert_owner = d->my_tets = d->my_verts = NULL;
    d->vown = NULL;
}

static int partition(eo_dist *d, const eo_mesh *m, const char *how)
{
    eo_ctx *ctx = d->ctx;
    partition_free(d);
    size_t nt = (size_t)(m->nt > 0 ? m->nt : 1), nv = (size_t)(m->nv > 0 ? m->nv : 1);
    d->tet_owner = eo_calloc(ctx, nt, sizeof(int));
    d->vert_owner = eo_malloc(ctx, nv * sizeof(int));
    d->my_tets = eo_malloc(ctx, nt * sizeof(int));
    d->my_verts = eo_malloc(ctx, nv * sizeof(int));
    d->vown = eo_calloc(ctx, nv, 1);
    if (!d->tet_owner || !d->vert_owner || !d->my_tets || !d->my_verts || !d->vown)
        return eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (partition)");
    int rc = EO_OK;
    if (d->size > 1) {
        if (strcmp(how, "slab") == 0) rc = partition_slab(d, m);
        else rc = partition_ptscotch(d, m);
        if (rc < 0) return rc;
    }
    for (int v = 0; v < m->nv; v++) d->vert_owner[v] = d->size; /* no tet: see below */
    for (int k = 0; k < m->nt; k++)
        for (int a = 0; a < 4; a++) {
            int v = m->tets[4 * k + a];
            if (d->tet_owner[k] < d->vert_owner[v]) d->vert_owner[v] = d->tet_owner[k];
        }
    for (int v = 0; v < m->nv; v++)
        if (d->vert_owner[v] == d->size)
            return eo_error(ctx, EO_ERR_UNSUPPORTED, "petsc backend: vertex %d belongs to no tet (mesh.points and "
                            "lattices have no distributed form)", v);
    d->n_my_tets = d->n_my_verts = 0;
    unsigned char *seen = d->vown; /* reused below */
    for (int k = 0; k < m->nt; k++) {
        if (d->tet_owner[k] != d->rank) continue;
        d->my_tets[d->n_my_tets++] = k;
        for (int a = 0; a < 4; a++) {
            int v = m->tets[4 * k + a];
            if (!seen[v]) {
                seen[v] = 1;
                d->my_verts[d->n_my_verts++] = v;
            }
        }
    }
    for (int v = 0; v < m->nv; v++) d->vown[v] = d->vert_owner[v] == d->rank;
    d->part = (eo_step_part){.nt = d->n_my_tets, .tets = d->my_tets, .nv = d->n_my_verts, .verts = d->my_verts,
                             .vown = d->vown};
    return EO_OK;
}

/* ---------------------------------------------------------------- numbering */

static void numbering_free(eo_dist *d)
{
    eo_ctx *ctx = d->ctx;
    eo_free(ctx, d->perm);
    eo_free(ctx, d->lfree);
    eo_free(ctx, d->xrep);
    eo_free(ctx, d->grep);
    PetscFree(d->lglob);
    PetscFree(d->rows);
    PetscFree(d->cols);
    PetscFree(d->vals);
    eo_free(ctx, d->rowptr);
    eo_free(ctx, d->pos);
    d->perm = d->lfree = d->rowptr = d->pos = NULL;
    d->xrep = d->grep = NULL;
    d->lglob = d->rows = d->cols = NULL;
    d->vals = NULL;
    d->nrows = 0;
    VecDestroy(&d->xl);
    VecScatterDestroy(&d->to_local);
    VecDestroy(&d->xall);
    VecScatterDestroy(&d->to_all);
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
    d->n = n;
    size_t ns = (size_t)(n > 0 ? n : 1);
    int *count = eo_calloc(ctx, (size_t)d->size + 1, sizeof(int));
    d->perm = eo_malloc(ctx, ns * sizeof(int));
    d->xrep = eo_calloc(ctx, ns, sizeof(double));
    d->grep = eo_calloc(ctx, ns, sizeof(double));
    d->lfree = eo_malloc(ctx, (size_t)(3 * d->n_my_verts + 1) * sizeof(int));
    if (!count || !d->perm || !d->xrep || !d->grep || !d->lfree) {
        eo_free(ctx, count);
        return eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (numbering)");
    }
    for (int i = 0; i < n; i++) count[d->vert_owner[eo_step_free_to_full(d->st, i) / 3] + 1]++;
    for (int r = 0; r < d->size; r++) count[r + 1] += count[r];
    d->rstart = count[d->rank];
    d->nown = count[d->rank + 1] - count[d->rank];
    for (int i = 0; i < n; i++) d->perm[i] = count[d->vert_owner[eo_step_free_to_full(d->st, i) / 3]]++;
    eo_free(ctx, count);
    d->nl = 0;
    for (int q = 0; q < d->n_my_verts; q++)
        for (int c = 0; c < 3; c++) {
            int i = eo_step_full_to_free(d->st, 3 * d->my_verts[q] + c);
            if (i >= 0) d->lfree[d->nl++] = i;
        }
    EO_PC(PetscMalloc1(d->nl + 1, &d->lglob));
    for (int q = 0; q < d->nl; q++) d->lglob[q] = d->perm[d->lfree[q]];
    Vec X = NULL;
    IS is = NULL;
    EO_PC(VecCreateMPI(d->comm, d->nown, d->n, &X));
    EO_PC(VecCreateSeq(PETSC_COMM_SELF, d->nl, &d->xl));
    EO_PC(ISCreateGeneral(PETSC_COMM_SELF, d->nl, d->lglob, PETSC_COPY_VALUES, &is));
    EO_PC(VecScatterCreate(X, is, d->xl, NULL, &d->to_local));
    EO_PC(VecScatterCreateToAll(X, &d->to_all, &d->xall));
    d->have_pattern = 1;
fail:
    ISDestroy(&is);
    VecDestroy(&X);
    return rc;
}

/* ---------------------------------------------------------------- matrix */

typedef struct trip {
    PetscInt r, c;
    int pos;
} trip;

static int trip_cmp(const void *a, const void *b)
{
    const trip *x = a, *y = b;
    if (x->r != y->r) return x->r < y->r ? -1 : 1;
    return x->c < y->c ? -1 : x->c > y->c;
}

/* Entries of my tets in the CSC H, as rows; preallocation from the whole pattern. */
static int matrix_build(eo_dist *d, const eo_csc *H, const eo_petsc_params *p)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    const eo_mesh *m = eo_step_mesh(d->st);
    unsigned char *mark = eo_calloc(ctx, (size_t)(H->nnz > 0 ? H->nnz : 1), 1);
    size_t cap = 1024, nt = 0;
    trip *t = eo_malloc(ctx, cap * sizeof *t);
    PetscInt *dnz = NULL, *onz = NULL;
    if (!mark || !t) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (matrix)");
        goto fail;
    }
    for (int q = 0; q < d->n_my_tets; q++) {
        const int *tet = m->tets + 4 * d->my_tets[q];
        int f[12];
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) f[3 * a + c] = eo_step_full_to_free(d->st, 3 * tet[a] + c);
        for (int a = 0; a < 12; a++)
            for (int b = 0; b < 12; b++) {
                int i = f[a], j = f[b];
                if (i < 0 || j < 0 || i > j) continue;
                int pos = eo_csc_find(H, i, j);
                if (pos < 0 || mark[pos]) continue;
                mark[pos] = 1;
                if (nt + 2 > cap) {
                    trip *nt2 = eo_realloc(ctx, t, 2 * cap * sizeof *t);
                    if (!nt2) {
                        rc = eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (matrix)");
                        goto fail;
                    }
                    t = nt2;
                    cap *= 2;
                }
                t[nt++] = (trip){d->perm[i], d->perm[j], pos};
                if (i != j) t[nt++] = (trip){d->perm[j], d->perm[i], pos};
            }
    }
    qsort(t, nt, sizeof *t, trip_cmp);
    int nrows = 0;
    for (size_t q = 0; q < nt; q++) nrows += q == 0 || t[q].r != t[q - 1].r;
    d->nrows = nrows;
    EO_PC(PetscMalloc1(nrows + 1, &d->rows));
    EO_PC(PetscMalloc1(nt + 1, &d->cols));
    EO_PC(PetscMalloc1(nt + 1, &d->vals));
    d->rowptr = eo_malloc(ctx, (size_t)(nrows + 1) * sizeof(int));
    d->pos = eo_malloc(ctx, (nt + 1) * sizeof(int));
    if (!d->rowptr || !d->pos) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (matrix)");
        goto fail;
    }
    int r = -1;
    for (size_t q = 0; q < nt; q++) {
        if (q == 0 || t[q].r != t[q - 1].r) {
            d->rows[++r] = t[q].r;
            d->rowptr[r] = (int)q;
        }
        d->cols[q] = t[q].c;
        d->pos[q] = t[q].pos;
    }
    d->rowptr[nrows] = (int)nt;
    /* preallocation of my rows from the whole (replicated) pattern */
    EO_PC(PetscCalloc1(d->nown + 1, &dnz));
    EO_PC(PetscCalloc1(d->nown + 1, &onz));
    const int r0 = d->rstart, r1 = d->rstart + d->nown;
    for (int j = 0; j < H->n; j++)
        for (int q = H->colptr[j]; q < H->colptr[j + 1]; q++) {
            const int gi = d->perm[H->rowind[q]], gj = d->perm[j];
            if (gi >= r0 && gi < r1) {
                if (gj >= r0 && gj < r1) dnz[gi - r0]++;
                else onz[gi - r0]++;
            }
            if (gi != gj && gj >= r0 && gj < r1) {
                if (gi >= r0 && gi < r1) dnz[gj - r0]++;
                else onz[gj - r0]++;
            }
        }
    EO_PC(MatCreate(d->comm, &d->A));
    EO_PC(MatSetSizes(d->A, d->nown, d->nown, d->n, d->n));
    EO_PC(MatSetType(d->A, MATAIJ));
    EO_PC(MatSetBlockSize(d->A, 3));
    EO_PC(MatSeqAIJSetPreallocation(d->A, 0, dnz));
    EO_PC(MatMPIAIJSetPreallocation(d->A, 0, dnz, 0, onz));
    EO_PC(MatSetOption(d->A, MAT_SYMMETRIC, PETSC_TRUE));
    EO_PC(MatSetOption(d->A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
    EO_PC(MatSetOption(d->A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
    if (strcmp(p->pc, "gamg") == 0) { /* rigid-body modes from the rest coordinates */
        EO_PC(VecCreateMPI(d->comm, d->nown, d->n, &d->coords));
        EO_PC(VecSetBlockSize(d->coords, 3));
        const double *x0 = eo_step_x0(d->st);
        for (int i = 0; i < d->n; i++)
            if (d->perm[i] >= r0 && d->perm[i] < r1)
                EO_PC(VecSetValue(d->coords, d->perm[i], x0[eo_step_free_to_full(d->st, i)], INSERT_VALUES));
        EO_PC(VecAssemblyBegin(d->coords));
        EO_PC(VecAssemblyEnd(d->coords));
        EO_PC(MatNullSpaceCreateRigidBody(d->coords, &d->rbm));
        EO_PC(MatSetNearNullSpace(d->A, d->rbm));
    }
fail:
    PetscFree(dnz);
    PetscFree(onz);
    eo_free(ctx, mark);
    eo_free(ctx, t);
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
    const eo_mesh *m = eo_step_mesh(st);
    if (st != d->st || m->nt != d->nt_mesh || m->nv != d->nv_mesh || strcmp(p->partitioner, d->partitioner) != 0) {
        numbering_free(d);
        d->st = st;
        d->nt_mesh = m->nt;
        d->nv_mesh = m->nv;
        snprintf(d->partitioner, sizeof d->partitioner, "%s", p->partitioner);
        if ((rc = partition(d, m, p->partitioner)) < 0) {
            d->st = NULL;
            return rc;
        }
    }
    if (!d->have_pattern || d->pattern != eo_step_pattern_id(st) || d->n != obj->n) {
        if ((rc = numbering(d, obj->n)) < 0) return rc;
        d->pattern = eo_step_pattern_id(st);
    }
    return EO_OK;
}

void eo_dist_destroy(eo_dist *d)
{
    if (!d->ctx) return;
    eo_dist_end(d);
    numbering_free(d);
    partition_free(d);
    memset(d, 0, sizeof *d);
}

int eo_dist_begin(eo_dist *d) { return eo_step_set_part(d->st, &d->part); }
void eo_dist_end(eo_dist *d)
{
    if (d->st) eo_step_set_part(d->st, NULL);
}

int eo_dist_vec(eo_dist *d, Vec *v)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    EO_PC(VecCreateMPI(d->comm, d->nown, d->n, v));
    EO_PC(VecSetBlockSize(*v, 3));
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
        int g = d->perm[i] - d->rstart;
        if (g >= 0 && g < d->nown) a[g] = x[i];
    }
    EO_PC(VecRestoreArray(X, &a));
fail:
    return rc;
}

int eo_dist_to_rep(eo_dist *d, Vec X, double *x)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    const PetscScalar *a;
    EO_PC(VecScatterBegin(d->to_all, X, d->xall, INSERT_VALUES, SCATTER_FORWARD));
    EO_PC(VecScatterEnd(d->to_all, X, d->xall, INSERT_VALUES, SCATTER_FORWARD));
    EO_PC(VecGetArrayRead(d->xall, &a));
    for (int i = 0; i < d->n; i++) x[i] = a[d->perm[i]];
    EO_PC(VecRestoreArrayRead(d->xall, &a));
fail:
    return rc;
}

/* X -> the replicated x at my vertices' coordinates */
static int to_local(eo_dist *d, Vec X)
{
    eo_ctx *ctx = d->ctx;
    int rc = EO_OK;
    const PetscScalar *a;
    EO_PC(VecScatterBegin(d->to_local, X, d->xl, INSERT_VALUES, SCATTER_FORWARD));
    EO_PC(VecScatterEnd(d->to_local, X, d->xl, INSERT_VALUES, SCATTER_FORWARD));
    EO_PC(VecGetArrayRead(d->xl, &a));
    for (int q = 0; q < d->nl; q++) d->xrep[d->lfree[q]] = a[q];
    EO_PC(VecRestoreArrayRead(d->xl, &a));
fail:
    return rc;
}

static double sum_all(eo_dist *d, double v)
{
    double s = 0;
    MPI_Allreduce(&v, &s, 1, MPI_DOUBLE, MPI_SUM, d->comm);
    return isnan(s) ? INFINITY : s;
}

int eo_dist_value(eo_dist *d, eo_objective *obj, Vec X, double *g)
{
    int rc = to_local(d, X);
    if (rc < 0) return rc;
    double gl = 0;
    if ((rc = eo_objective_value(obj, d->xrep, &gl)) < 0) return rc;
    *g = sum_all(d, gl);
    d->n_value++;
    return EO_OK;
}

int eo_dist_gradient(eo_dist *d, eo_objective *obj, Vec X, double *g, Vec G)
{
    eo_ctx *ctx = d->ctx;
    int rc = to_local(d, X);
    if (rc < 0) return rc;
    double gl = 0;
    if ((rc = eo_objective_gradient(obj, d->xrep, &gl, d->grep)) < 0) return rc;
    *g = sum_all(d, gl);
    d->n_gradient++;
    PetscScalar *a;
    EO_PC(VecGetArray(d->xl, &a));
    for (int q = 0; q < d->nl; q++) a[q] = isfinite(gl) ? d->grep[d->lfree[q]] : 0;
    EO_PC(VecRestoreArray(d->xl, &a));
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
    if ((rc = eo_objective_hessian(obj, d->xrep, proj, &H)) < 0) return rc;
    d->n_hessian++;
    if (!d->A && (rc = matrix_build(d, H, d->params)) < 0) return rc;
    EO_PC(MatZeroEntries(d->A));
    for (int r = 0; r < d->nrows; r++) {
        const int q0 = d->rowptr[r], q1 = d->rowptr[r + 1];
        for (int q = q0; q < q1; q++) d->vals[q] = H->val[d->pos[q]];
        EO_PC(MatSetValues(d->A, 1, d->rows + r, q1 - q0, d->cols + q0, d->vals + q0, ADD_VALUES));
    }
    EO_PC(MatAssemblyBegin(d->A, MAT_FINAL_ASSEMBLY));
    EO_PC(MatAssemblyEnd(d->A, MAT_FINAL_ASSEMBLY));
fail:
    return rc;
}

int eo_dist_inverted(eo_dist *d, eo_objective *obj, Vec X)
{
    if (!obj->ops->inverted_count || to_local(d, X) < 0) return -1;
    int n = obj->ops->inverted_count(obj->data, d->xrep), s = 0;
    MPI_Allreduce(&n, &s, 1, MPI_INT, MPI_SUM, d->comm);
    return s;
}
