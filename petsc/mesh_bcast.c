/* The mesh read on one rank (issue 11): under mpirun the CLI's context gets this mesh
 * source (eo_ctx_set_mesh_source). Rank 0 reads the file with the library's reader
 * (eo_mesh_read_file: parsing, TetGen for surfaces, validation) and broadcasts the
 * outcome; the other ranks never open the file and build the same mesh from what they
 * receive:
 *
 *   header   status, nv, nt, ntri, which optional arrays exist, the load report
 *            (reoriented, dropped tets / vertices), length of the message
 *   message  rank 0's error or warning text (a bad file: every rank returns the same
 *            status and message, so every rank ends with exit 2 and rank 0 prints it once)
 *   arrays   X, tets, tet_attr, vmarker, tris, tri_tag (in pieces of at most 2^27
 *            entries, below MPI's int counts)
 *
 * Every rank reaches eo_mesh_read at the same point of the same program (the scene is
 * loaded everywhere), so the broadcasts pair up. A rank that cannot allocate the mesh
 * says so in an Allreduce before the arrays go out: then every rank fails with
 * EO_ERR_NOMEM instead of waiting. */
#include <stdio.h>
#include <string.h>

#include "elastopt/mesh.h"
#include "petsc_backend.h"

static char g_note[256]; /* "mesh: read on rank 0, ..." for the CLI's --verbose */

const char *eo_petsc_mesh_note(void) { return g_note; }

enum { H_RC, H_NV, H_NT, H_NTRI, H_ATTR, H_VMARK, H_REOR, H_DROPT, H_DROPV, H_MSG, H_N };

static int bcast(void *buf, size_t count, MPI_Datatype type, size_t size, MPI_Comm comm)
{
    const size_t piece = (size_t)1 << 27;
    char *p = buf;
    for (size_t done = 0; done < count; done += piece) {
        size_t k = count - done < piece ? count - done : piece;
        if (MPI_Bcast(p + done * size, (int)k, type, 0, comm) != MPI_SUCCESS) return -1;
    }
    return 0;
}

static int mesh_source(eo_ctx *ctx, const char *path, const eo_mesh_read_opts *opts, eo_mesh **out, void *user)
{
    (void)user;
    MPI_Comm comm = PETSC_COMM_WORLD;
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    *out = NULL;
    eo_mesh *m = NULL;
    int h[H_N] = {0};
    char msg[1024] = "";
    if (rank == 0) {
        h[H_RC] = eo_mesh_read_file(ctx, path, opts, &m);
        if (h[H_RC] != EO_OK) snprintf(msg, sizeof msg, "%s", eo_ctx_message(ctx));
        if (m) {
            h[H_NV] = m->nv, h[H_NT] = m->nt, h[H_NTRI] = m->ntri;
            h[H_ATTR] = m->tet_attr != NULL, h[H_VMARK] = m->vmarker != NULL;
            h[H_REOR] = m->reoriented, h[H_DROPT] = m->dropped_tets, h[H_DROPV] = m->dropped_vertices;
        }
        h[H_MSG] = (int)strlen(msg);
    }
    if (MPI_Bcast(h, H_N, MPI_INT, 0, comm) != MPI_SUCCESS ||
        (h[H_MSG] > 0 && MPI_Bcast(msg, h[H_MSG] + 1, MPI_CHAR, 0, comm) != MPI_SUCCESS)) {
        eo_mesh_destroy(&m);
        return eo_error(ctx, EO_ERR_IO, "%s: the broadcast of the mesh from rank 0 failed", path);
    }
    if (h[H_RC] < 0) { /* rank 0 could not read it: the same error on every rank */
        if (rank != 0) return eo_error(ctx, h[H_RC], "%s", msg);
        return h[H_RC];
    }
    int ok = 1;
    if (rank != 0) {
        ok = eo_mesh_create(ctx, h[H_NV], h[H_NT], &m) >= 0;
        if (ok) {
            const size_t nv = (size_t)(h[H_NV] ? h[H_NV] : 1), nt = (size_t)(h[H_NT] ? h[H_NT] : 1);
            if (h[H_ATTR]) ok &= (m->tet_attr = eo_malloc(ctx, nt * sizeof(int))) != NULL;
            if (h[H_VMARK]) ok &= (m->vmarker = eo_malloc(ctx, nv * sizeof(int))) != NULL;
            if (h[H_NTRI] > 0) {
                m->ntri = h[H_NTRI];
                ok &= (m->tris = eo_malloc(ctx, (size_t)h[H_NTRI] * 3 * sizeof(int))) != NULL;
                ok &= (m->tri_tag = eo_malloc(ctx, (size_t)h[H_NTRI] * sizeof(int))) != NULL;
            }
        }
    }
    int all = 0;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, comm);
    if (!all) {
        eo_mesh_destroy(&m);
        return eo_error(ctx, EO_ERR_NOMEM,
                        "%s: a rank has no memory for the mesh read on rank 0 (%d vertices, %d tets)", path, h[H_NV],
                        h[H_NT]);
    }
    const size_t nv = (size_t)h[H_NV], nt = (size_t)h[H_NT], ntri = (size_t)h[H_NTRI];
    int bad = bcast(m->X, 3 * nv, MPI_DOUBLE, sizeof(double), comm) < 0;
    bad |= bcast(m->tets, 4 * nt, MPI_INT, sizeof(int), comm) < 0;
    if (h[H_ATTR]) bad |= bcast(m->tet_attr, nt, MPI_INT, sizeof(int), comm) < 0;
    if (h[H_VMARK]) bad |= bcast(m->vmarker, nv, MPI_INT, sizeof(int), comm) < 0;
    if (ntri) {
        bad |= bcast(m->tris, 3 * ntri, MPI_INT, sizeof(int), comm) < 0;
        bad |= bcast(m->tri_tag, ntri, MPI_INT, sizeof(int), comm) < 0;
    }
    if (bad) {
        eo_mesh_destroy(&m);
        return eo_error(ctx, EO_ERR_IO, "%s: the broadcast of the mesh from rank 0 failed", path);
    }
    if (rank != 0) {
        m->reoriented = h[H_REOR];
        m->dropped_tets = h[H_DROPT];
        m->dropped_vertices = h[H_DROPV];
        if (h[H_RC] != EO_OK) eo_error(ctx, h[H_RC], "%s", msg); /* rank 0's warning, e.g. dropped tets */
    }
    if (rank == 0)
        snprintf(g_note, sizeof g_note, "mesh: %s read on rank 0, broadcast %d vertices, %d tets to %d other rank%s",
                 path, h[H_NV], h[H_NT], size - 1, size == 2 ? "" : "s");
    else
        snprintf(g_note, sizeof g_note, "mesh: %s received from rank 0, %d vertices, %d tets", path, h[H_NV],
                 h[H_NT]);
    *out = m;
    return h[H_RC];
}

void eo_petsc_mesh_source_install(eo_ctx *ctx)
{
    PetscBool on = PETSC_FALSE;
    PetscInitialized(&on);
    int size = 1;
    if (on) MPI_Comm_size(PETSC_COMM_WORLD, &size);
    if (size > 1) eo_ctx_set_mesh_source(ctx, mesh_source, NULL);
}
