/* The distributed mesh (petsc_backend.h, eo_petsc_layout): under mpirun with several ranks
 * the scene's mesh is read (eo_mesh_read_file, through the context's mesh source) or
 * generated on rank 0 alone, handed to DMPlex (DMPlexCreateFromCellListPetsc: only rank 0
 * gives cells) and split by DMPlexDistribute with PETSc's partitioner (PT-Scotch, overlap
 * 0). Each rank then builds its LOCAL eo_mesh: its cells and the vertices of their
 * closure, with the tets' region attributes and the vertices' markers carried along by the
 * migration SF, and runs the whole step engine (eo_sim) on it. Because every term that
 * remains (elastic energy, inertia with lumped or consistent element masses, gravity
 * f = M g) is a sum over elements, the local g, ∇g and Hessian of the ranks add up to the
 * global ones; the scene features that are not element sums are refused at load
 * (problems/scene_config.c, check_distributed).
 *
 * The layout kept for the optimizers (dist.c) and the CLI's output: the global (input)
 * number of each local vertex, which local vertices this rank owns (the others are leaves
 * of the DM's point SF) and a vertex SF (roots: this rank's local vertices; leaves: its
 * ghost vertices, pointing at the owner's local vertex), over which global row numbers
 * are broadcast and gradients summed.
 *
 * The mesh source of a distributed run reads the file on rank 0 only; the other ranks get
 * rank 0's status and message (a bad file ends every rank with exit 2 and one message)
 * and an empty mesh, replaced by their part right after (eo_dist_hooks.distribute_mesh). */
#if EO_PETSC_SCOTCH
#include <stdint.h>
#include <stdio.h>
#include <scotch.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/mesh.h"
#include "petsc_backend.h"

static eo_petsc_layout g_layout;
static char g_note[256];

const eo_petsc_layout *eo_petsc_layout_get(void) { return g_layout.active ? &g_layout : NULL; }
const char *eo_petsc_mesh_note(void) { return g_note; }

static void layout_free(void)
{
    free(g_layout.gid);
    free(g_layout.owned);
    PetscSFDestroy(&g_layout.vsf);
    memset(&g_layout, 0, sizeof g_layout);
}

/* ---------------------------------------------------------------- mesh source */

static int mesh_source(eo_ctx *ctx, const char *path, const eo_mesh_read_opts *opts, eo_mesh **out, void *user)
{
    (void)user;
    MPI_Comm comm = PETSC_COMM_WORLD;
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    *out = NULL;
    eo_mesh *m = NULL;
    int rc = EO_OK;
    char msg[1024] = "";
    if (rank == 0) {
        rc = eo_mesh_read_file(ctx, path, opts, &m);
        if (rc != EO_OK) snprintf(msg, sizeof msg, "%s", eo_ctx_message(ctx));
    }
    int st = rc;
    if (MPI_Bcast(&st, 1, MPI_INT, 0, comm) != MPI_SUCCESS || MPI_Bcast(msg, (int)sizeof msg, MPI_CHAR, 0, comm))
        st = eo_error(ctx, EO_ERR_IO, "petsc: the broadcast of the mesh read's outcome failed");
    if (st < 0) {
        eo_mesh_destroy(&m);
        return rank == 0 ? rc : eo_error(ctx, st, "%s", msg);
    }
    if (st > 0 && rank != 0) eo_error(ctx, st, "%s", msg); /* the same warning on every rank */
    if (rank != 0 && (rc = eo_mesh_create(ctx, 0, 0, &m)) < 0) return rc;
    *out = m;
    return st;
}

/* ---------------------------------------------------------------- reductions */

static int reduce(double *v, int n, eo_reduce_op op, void *user)
{
    (void)user;
    MPI_Op o = op == EO_REDUCE_MIN ? MPI_MIN : op == EO_REDUCE_MAX ? MPI_MAX : MPI_SUM;
    return MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, o, PETSC_COMM_WORLD) == MPI_SUCCESS ? 0 : EO_ERR_IO;
}

/* ---------------------------------------------------------------- partition */

#if EO_PETSC_SCOTCH
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

/* The partition DMPlexDistribute applies (PETSCPARTITIONERSHELL): Scotch on the face dual
 * graph of rank 0's cells in a context with a fixed seed and deterministic threads, the
 * same partition in every run. PETSc's own PT-Scotch partitioner (-petscpartitioner_type
 * ptscotch) gave another partition in every run, and with it other GAMG iteration counts. */
static int shell_partition(eo_ctx *ctx, PetscPartitioner part, const eo_mesh *m, int rank, int size)
{
    int rc = EO_OK, nt = rank == 0 ? m->nt : 0;
    int *nb = NULL, *owner = NULL;
    PetscInt *ia = NULL, *ja = NULL, *sizes = NULL, *points = NULL;
    EO_PC(PetscCalloc1(size, &sizes));
    EO_PC(PetscMalloc1(nt + 1, &points));
    if (rank == 0) {
        nb = malloc((size_t)(4 * nt + 1) * sizeof(int));
        owner = malloc((size_t)(nt + 1) * sizeof(int));
        if (!nb || !owner) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (partition)");
            goto fail;
        }
        if ((rc = dual_graph(ctx, m, nb)) < 0) goto fail;
        EO_PC(PetscMalloc1(nt + 1, &ia));
        EO_PC(PetscMalloc1(4 * nt + 1, &ja));
        ia[0] = 0;
        for (int q = 0; q < nt; q++) {
            ia[q + 1] = ia[q];
            for (int a = 0; a < 4; a++)
                if (nb[4 * q + a] >= 0) ja[ia[q + 1]++] = nb[4 * q + a];
        }
        if ((rc = scotch_part(ctx, nt, ia, ja, size, owner)) < 0) goto fail;
        int *next = calloc((size_t)size + 1, sizeof(int));
        if (!next) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "petsc: out of memory (partition)");
            goto fail;
        }
        for (int q = 0; q < nt; q++) sizes[owner[q]]++;
        for (int r = 1; r < size; r++) next[r] = next[r - 1] + (int)sizes[r - 1];
        for (int q = 0; q < nt; q++) points[next[owner[q]]++] = q;
        free(next);
    }
fail:;
    int st = rc; /* rank 0's outcome */
    if (MPI_Bcast(&st, 1, MPI_INT, 0, PETSC_COMM_WORLD) != MPI_SUCCESS) st = EO_ERR_IO;
    if (st < 0 && rank != 0) rc = eo_error(ctx, st, "petsc: the partition failed on rank 0");
    if (st >= 0) {
        PetscErrorCode e = PetscPartitionerSetType(part, PETSCPARTITIONERSHELL);
        if (!e) e = PetscPartitionerShellSetPartition(part, size, sizes, points);
        if (e) rc = eo_petsc_fail(ctx, e, "PetscPartitionerShellSetPartition");
    }
    free(nb);
    free(owner);
    PetscFree(ia);
    PetscFree(ja);
    PetscFree(sizes);
    PetscFree(points);
    return rc;
}
#endif

/* ---------------------------------------------------------------- distribution */

typedef struct gid_pair {
    PetscInt gid;
    int local;
} gid_pair;

static int gid_cmp(const void *a, const void *b)
{
    const gid_pair *x = a, *y = b;
    return x->gid < y->gid ? -1 : x->gid > y->gid;
}

/* Per point data carried by the migration: cells (v0, v1, v2, v3, attribute), vertices
 * (global id, marker, -, -, -). */
enum { PD = 5 };

static int distribute(eo_ctx *ctx, eo_mesh **mesh, void *user)
{
    (void)user;
    MPI_Comm comm = PETSC_COMM_WORLD;
    int rank, size, rc = EO_OK;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    eo_mesh *m = *mesh;
    DM dm = NULL, dist = NULL;
    PetscSF mig = NULL;
    PetscInt *cells = NULL, *root = NULL, *leaf = NULL, *vroot = NULL, *vleaf = NULL;
    PetscReal *coords = NULL;
    gid_pair *pairs = NULL;
    PetscPartitioner part;
    eo_mesh *lm = NULL;
    layout_free();
    int head[4] = {0, 0, 0, 0}; /* nt, nv, has attr, has markers (rank 0's) */
    if (rank == 0) {
        if (m->order != 1) {
            rc = eo_error(ctx, EO_ERR_UNSUPPORTED, "petsc backend: 10-node tets have no distributed form yet");
            head[0] = -1;
        } else {
            head[0] = m->nt, head[1] = m->nv, head[2] = m->tet_attr != NULL, head[3] = m->vmarker != NULL;
        }
    }
    if (MPI_Bcast(head, 4, MPI_INT, 0, comm) != MPI_SUCCESS) return eo_error(ctx, EO_ERR_IO, "petsc: broadcast failed");
    if (head[0] < 0) return rank == 0 ? rc : eo_error(ctx, EO_ERR_UNSUPPORTED, "petsc backend: 10-node tets have "
                                                      "no distributed form yet");
    const int nt = rank == 0 ? m->nt : 0, nv = rank == 0 ? m->nv : 0;
    EO_PC(PetscMalloc1(4 * (size_t)nt + 1, &cells));
    EO_PC(PetscMalloc1(3 * (size_t)nv + 1, &coords));
    for (size_t i = 0; i < 4 * (size_t)nt; i++) cells[i] = m->tets[i];
    for (size_t i = 0; i < 3 * (size_t)nv; i++) coords[i] = m->X[i];
    EO_PC(DMPlexCreateFromCellListPetsc(comm, 3, nt, nv, 4, PETSC_FALSE, cells, 3, coords, &dm));
    PetscFree(cells);
    PetscFree(coords);
    /* the rank-0 data of every input point: cells [0, nt), vertices [nt, nt + nv) */
    EO_PC(PetscMalloc1(PD * ((size_t)nt + nv) + 1, &root));
    for (int k = 0; k < nt; k++) {
        for (int a = 0; a < 4; a++) root[PD * k + a] = m->tets[4 * k + a];
        root[PD * k + 4] = m->tet_attr ? m->tet_attr[k] : 0;
    }
    for (int v = 0; v < nv; v++) {
        PetscInt *r = root + PD * ((size_t)nt + v);
        r[0] = v, r[1] = m->vmarker ? m->vmarker[v] : 0, r[2] = r[3] = r[4] = 0;
    }
    EO_PC(DMPlexGetPartitioner(dm, &part));
    PetscBool chosen = PETSC_FALSE; /* -petscpartitioner_type ...: PETSc's partitioner */
    EO_PC(PetscOptionsHasName(NULL, NULL, "-petscpartitioner_type", &chosen));
    const char *how = "ptscotch";
#if EO_PETSC_SCOTCH
    if (!chosen) {
        if ((rc = shell_partition(ctx, part, m, rank, size)) < 0) goto fail;
        how = "Scotch on rank 0, fixed seed";
    }
#endif
    if (chosen || strcmp(how, "ptscotch") == 0) {
        EO_PC(PetscPartitionerSetType(part, PETSCPARTITIONERPTSCOTCH));
        EO_PC(PetscPartitionerSetFromOptions(part));
        if (chosen) how = "-petscpartitioner_type";
    }
    EO_PC(DMPlexDistribute(dm, 0, &mig, &dist));
    if (!dist) { /* one rank: nothing moved */
        dist = dm;
        dm = NULL;
    }
    PetscInt cS, cE, vS, vE, pS, pE;
    EO_PC(DMPlexGetHeightStratum(dist, 0, &cS, &cE));
    EO_PC(DMPlexGetDepthStratum(dist, 0, &vS, &vE));
    EO_PC(DMPlexGetChart(dist, &pS, &pE));
    const int lnt = (int)(cE - cS), lnv = (int)(vE - vS);
    EO_PC(PetscMalloc1(PD * (size_t)(pE - pS) + 1, &leaf));
    if (mig) {
        MPI_Datatype unit;
        MPI_Type_contiguous(PD, MPIU_INT, &unit);
        MPI_Type_commit(&unit);
        PetscErrorCode e1 = PetscSFBcastBegin(mig, unit, root, leaf, MPI_REPLACE);
        PetscErrorCode e2 = e1 ? e1 : PetscSFBcastEnd(mig, unit, root, leaf, MPI_REPLACE);
        MPI_Type_free(&unit);
        EO_PC(e2);
    } else {
        memcpy(leaf, root, PD * ((size_t)nt + nv) * sizeof *leaf);
    }
    PetscFree(root);
    root = NULL;
    /* the local mesh: vertices in the DM's order, tets by their input vertex ids */
    int fail = lnt < 1;
    MPI_Allreduce(MPI_IN_PLACE, &fail, 1, MPI_INT, MPI_MAX, comm);
    if (fail) {
        rc = eo_error(ctx, EO_ERR_UNSUPPORTED, "petsc backend: the mesh (%d tets) is too small for %d ranks: a rank "
                      "got no tet", head[0], size);
        goto fail;
    }
    if ((rc = eo_mesh_create(ctx, lnv, lnt, &lm)) < 0) goto fail;
    if (head[2] && !(lm->tet_attr = eo_malloc(ctx, (size_t)lnt * sizeof(int)))) goto nomem;
    if (head[3] && !(lm->vmarker = eo_malloc(ctx, (size_t)lnv * sizeof(int)))) goto nomem;
    g_layout.gid = malloc((size_t)(lnv + 1) * sizeof *g_layout.gid);
    g_layout.owned = malloc((size_t)lnv + 1);
    pairs = malloc((size_t)(lnv + 1) * sizeof *pairs);
    if (!g_layout.gid || !g_layout.owned || !pairs) goto nomem;
    Vec cv;
    const PetscScalar *ca;
    EO_PC(DMGetCoordinatesLocal(dist, &cv));
    EO_PC(VecGetArrayRead(cv, &ca));
    for (int q = 0; q < lnv; q++) {
        const PetscInt *d = leaf + PD * (vS - pS + q);
        g_layout.gid[q] = d[0];
        if (lm->vmarker) lm->vmarker[q] = (int)d[1];
        for (int c = 0; c < 3; c++) lm->X[3 * q + c] = ca[3 * q + c];
        pairs[q] = (gid_pair){d[0], q};
    }
    EO_PC(VecRestoreArrayRead(cv, &ca));
    qsort(pairs, (size_t)lnv, sizeof *pairs, gid_cmp);
    for (int k = 0; k < lnt; k++) {
        const PetscInt *d = leaf + PD * (cS - pS + k);
        for (int a = 0; a < 4; a++) {
            gid_pair key = {d[a], 0}, *f = bsearch(&key, pairs, (size_t)lnv, sizeof *pairs, gid_cmp);
            if (!f) {
                rc = eo_error(ctx, EO_ERR_MESH, "petsc backend: tet %d of rank %d lost its vertex %d in the "
                              "distribution", k, rank, (int)d[a]);
                goto fail;
            }
            lm->tets[4 * k + a] = f->local;
        }
        if (lm->tet_attr) lm->tet_attr[k] = (int)d[4];
    }
    /* ownership and the vertex SF from the DM's point SF */
    PetscSF psf;
    PetscInt nroots, nleaves;
    const PetscInt *ilocal;
    const PetscSFNode *iremote;
    EO_PC(DMGetPointSF(dist, &psf));
    EO_PC(PetscSFGetGraph(psf, &nroots, &nleaves, &ilocal, &iremote));
    memset(g_layout.owned, 1, (size_t)lnv);
    EO_PC(PetscMalloc1(pE - pS + 1, &vroot));
    EO_PC(PetscMalloc1(pE - pS + 1, &vleaf));
    for (PetscInt p = pS; p < pE; p++) vroot[p - pS] = p >= vS && p < vE ? p - vS : -1;
    if (nroots >= 0) { /* collective: also on a rank without leaves */
        EO_PC(PetscSFBcastBegin(psf, MPIU_INT, vroot, vleaf, MPI_REPLACE));
        EO_PC(PetscSFBcastEnd(psf, MPIU_INT, vroot, vleaf, MPI_REPLACE));
    }
    PetscSFNode *vremote = NULL;
    PetscInt *vlocal = NULL, nvl = 0;
    EO_PC(PetscMalloc1(nleaves + 1, &vremote));
    EO_PC(PetscMalloc1(nleaves + 1, &vlocal));
    for (PetscInt l = 0; l < nleaves; l++) {
        const PetscInt p = ilocal ? ilocal[l] : l;
        if (p < vS || p >= vE) continue;
        g_layout.owned[p - vS] = 0;
        vlocal[nvl] = p - vS;
        vremote[nvl].rank = iremote[l].rank;
        vremote[nvl].index = vleaf[p - pS];
        nvl++;
    }
    EO_PC(PetscSFCreate(comm, &g_layout.vsf));
    EO_PC(PetscSFSetGraph(g_layout.vsf, lnv, nvl, vlocal, PETSC_OWN_POINTER, vremote, PETSC_OWN_POINTER));
    EO_PC(PetscSFSetUp(g_layout.vsf));
    g_layout.nv = lnv;
    g_layout.nt = lnt;
    g_layout.nown = 0;
    for (int q = 0; q < lnv; q++) g_layout.nown += g_layout.owned[q];
    g_layout.nv_global = head[1];
    g_layout.nt_global = head[0];
    g_layout.active = 1;
    snprintf(g_note, sizeof g_note,
             "mesh: %d vertices, %d tets distributed over %d ranks by DMPlex (%s, overlap 0); rank 0 holds %d tets, "
             "%d vertices (%d owned)",
             head[1], head[0], size, how, lnt, lnv, g_layout.nown);
    eo_mesh_destroy(mesh);
    *mesh = lm;
    lm = NULL;
    goto done;
nomem:
    rc = eo_error(ctx, EO_ERR_NOMEM, "petsc backend: out of memory (local mesh)");
fail:
    layout_free();
done:
    free(pairs);
    PetscFree(leaf);
    PetscFree(root);
    PetscFree(vroot);
    PetscFree(vleaf);
    PetscSFDestroy(&mig);
    DMDestroy(&dist);
    DMDestroy(&dm);
    eo_mesh_destroy(&lm);
    return rc;
}

/* ---------------------------------------------------------------- install */

static eo_dist_hooks g_hooks;

static const unsigned char *owned_vertices(void *user)
{
    (void)user;
    return g_layout.active ? g_layout.owned : NULL;
}

void eo_petsc_dist_install(eo_ctx *ctx)
{
    PetscBool on = PETSC_FALSE;
    PetscInitialized(&on);
    int size = 1, rank = 0;
    if (on) {
        MPI_Comm_size(PETSC_COMM_WORLD, &size);
        MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    }
    if (size < 2) return;
    eo_ctx_set_mesh_source(ctx, mesh_source, NULL);
    g_hooks = (eo_dist_hooks){.nparts = size, .part = rank, .reduce = reduce, .distribute_mesh = distribute,
                              .space = eo_petsc_space_hook, .owned_vertices = owned_vertices};
    eo_ctx_set_dist(ctx, &g_hooks);
}

/* Gather a per-vertex array of `width` doubles (local vertices) into the input order on
 * rank 0 (out: nv_global·width there; ignored elsewhere). Collective. */
int eo_petsc_gather_vertices(const double *local, int width, double *out)
{
    const eo_petsc_layout *L = eo_petsc_layout_get();
    if (!L) return -1;
    MPI_Comm comm = PETSC_COMM_WORLD;
    int rank, size;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    int n = L->nown, *counts = NULL, *displs = NULL, total = 0;
    double *sbuf = malloc(((size_t)n * (width + 1) + 1) * sizeof(double)), *rbuf = NULL;
    if (!sbuf) return -1;
    int k = 0;
    for (int q = 0; q < L->nv; q++) {
        if (!L->owned[q]) continue;
        sbuf[k++] = (double)L->gid[q];
        for (int c = 0; c < width; c++) sbuf[k++] = local[(size_t)width * q + c];
    }
    int mine = k, rc = 0;
    if (rank == 0) {
        counts = malloc((size_t)size * sizeof(int));
        displs = malloc((size_t)size * sizeof(int));
    }
    if (MPI_Gather(&mine, 1, MPI_INT, counts, 1, MPI_INT, 0, comm) != MPI_SUCCESS) rc = -1;
    if (rank == 0) {
        for (int r = 0; r < size; r++) displs[r] = total, total += counts[r];
        rbuf = malloc(((size_t)total + 1) * sizeof(double));
    }
    if (MPI_Gatherv(sbuf, mine, MPI_DOUBLE, rbuf, counts, displs, MPI_DOUBLE, 0, comm) != MPI_SUCCESS) rc = -1;
    if (rank == 0) {
        for (int i = 0; i < total; i += width + 1) {
            const long g = (long)rbuf[i];
            if (g < 0 || g >= L->nv_global) rc = -1;
            else memcpy(out + (size_t)width * g, rbuf + i + 1, (size_t)width * sizeof(double));
        }
        if (total != L->nv_global * (width + 1)) rc = -1;
    }
    free(sbuf);
    free(rbuf);
    free(counts);
    free(displs);
    return rc;
}
