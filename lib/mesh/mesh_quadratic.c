/* Quadratic (10-node) tets from a linear mesh: one midside node per edge.
 *
 * Edges are found by sorting the 6·nt (min, max, slot) keys of the tets' edges (and the
 * 3·ntri edges of the tagged triangles, so that tag selectors reach their midside nodes),
 * so the cost is O(E log E) with no hash table; a node is numbered when the first tet (in
 * tet order, then its edge order 01, 12, 20, 03, 13, 23) meets its edge, which keeps the
 * numbering independent of the sort. Straight edges: the node is the edge's midpoint. */
#include <stdlib.h>
#include <string.h>

#include "elastopt/mesh.h"

/* local edge e of a tet in the VTK quadratic tetra order (mesh.h: tet10) */
static const int tet_edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
static const int tri_edge[3][2] = {{0, 1}, {1, 2}, {2, 0}};

typedef struct ekey {
    int a, b;   /* a < b */
    long slot;  /* 6·k + e for tets, 6·nt + 3·f + e for triangles: where the node id goes */
} ekey;

static int ekey_cmp(const void *p, const void *q)
{
    const ekey *x = p, *y = q;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    if (x->b != y->b) return x->b < y->b ? -1 : 1;
    return x->slot < y->slot ? -1 : x->slot > y->slot;
}

int eo_mesh_to_quadratic(eo_ctx *ctx, const eo_mesh *m, eo_mesh **out)
{
    *out = NULL;
    if (m->order == 2 || m->tet10) return eo_error(ctx, EO_ERR_INVALID, "the mesh is quadratic already");
    const long nt = m->nt, ntri = m->ntri, nk = 6 * nt + 3 * ntri;
    ekey *k = eo_malloc(ctx, (size_t)(nk ? nk : 1) * sizeof *k);
    long *gid = eo_malloc(ctx, (size_t)(nk ? nk : 1) * sizeof *gid); /* edge group -> node offset */
    int *node = eo_malloc(ctx, (size_t)(nk ? nk : 1) * sizeof *node);      /* slot -> node */
    if (!k || !gid || !node) {
        eo_free(ctx, k), eo_free(ctx, gid), eo_free(ctx, node);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (quadratic mesh of %d tets)", m->nt);
    }
    for (long t = 0; t < nt; t++)
        for (int e = 0; e < 6; e++) {
            int a = m->tets[4 * t + tet_edge[e][0]], b = m->tets[4 * t + tet_edge[e][1]];
            k[6 * t + e] = (ekey){a < b ? a : b, a < b ? b : a, 6 * t + e};
        }
    for (long f = 0; f < ntri; f++)
        for (int e = 0; e < 3; e++) {
            int a = m->tris[3 * f + tri_edge[e][0]], b = m->tris[3 * f + tri_edge[e][1]];
            k[6 * nt + 3 * f + e] = (ekey){a < b ? a : b, a < b ? b : a, 6 * nt + 3 * f + e};
        }
    qsort(k, (size_t)nk, sizeof *k, ekey_cmp);
    /* groups of equal edges (runs of the sorted keys): slot -> group, then the groups
     * numbered in the order the slots first meet them */
    long ne = 0;
    for (long i = 0; i < nk; i++) {
        if (i == 0 || k[i].a != k[i - 1].a || k[i].b != k[i - 1].b) ne++;
        node[k[i].slot] = (int)(ne - 1); /* provisional: the group id */
    }
    for (long g = 0; g < ne; g++) gid[g] = -1;
    long next = 0;
    for (long s = 0; s < nk; s++) {
        long g = node[s];
        if (gid[g] < 0) gid[g] = next++;
        node[s] = (int)(m->nv + gid[g]);
    }
    eo_free(ctx, gid);
    eo_free(ctx, k);
    if ((long)m->nv + ne > 0x7fffffffL) {
        eo_free(ctx, node);
        return eo_error(ctx, EO_ERR_INVALID, "quadratic mesh too large (%ld nodes)", (long)m->nv + ne);
    }
    eo_mesh *q = NULL;
    int rc = eo_mesh_create(ctx, (int)(m->nv + ne), m->nt, &q);
    if (rc < 0) {
        eo_free(ctx, node);
        return rc;
    }
    q->order = 2;
    q->tet10 = eo_malloc(ctx, (size_t)(nt ? nt : 1) * 10 * sizeof(int));
    if (m->tet_attr) q->tet_attr = eo_malloc(ctx, (size_t)(nt ? nt : 1) * sizeof(int));
    if (m->vmarker) q->vmarker = eo_calloc(ctx, (size_t)q->nv, sizeof(int));
    if (ntri) {
        q->ntri = m->ntri;
        q->tris = eo_malloc(ctx, (size_t)ntri * 3 * sizeof(int));
        q->tri_tag = eo_malloc(ctx, (size_t)ntri * sizeof(int));
        q->tri_mid = eo_malloc(ctx, (size_t)ntri * 3 * sizeof(int));
    }
    if (!q->tet10 || (m->tet_attr && !q->tet_attr) || (m->vmarker && !q->vmarker) ||
        (ntri && (!q->tris || !q->tri_tag || !q->tri_mid))) {
        eo_free(ctx, node);
        eo_mesh_destroy(&q);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (quadratic mesh of %d tets)", m->nt);
    }
    memcpy(q->X, m->X, (size_t)m->nv * 3 * sizeof(double));
    memcpy(q->tets, m->tets, (size_t)nt * 4 * sizeof(int));
    if (m->tet_attr) memcpy(q->tet_attr, m->tet_attr, (size_t)nt * sizeof(int));
    if (m->vmarker) memcpy(q->vmarker, m->vmarker, (size_t)m->nv * sizeof(int));
    if (ntri) {
        memcpy(q->tris, m->tris, (size_t)ntri * 3 * sizeof(int));
        memcpy(q->tri_tag, m->tri_tag, (size_t)ntri * sizeof(int));
    }
    for (long t = 0; t < nt; t++) {
        int *t10 = q->tet10 + 10 * t;
        memcpy(t10, m->tets + 4 * t, 4 * sizeof(int));
        for (int e = 0; e < 6; e++) {
            int n = node[6 * t + e];
            t10[4 + e] = n;
            const int a = m->tets[4 * t + tet_edge[e][0]], b = m->tets[4 * t + tet_edge[e][1]];
            for (int c = 0; c < 3; c++) q->X[3 * n + c] = 0.5 * (m->X[3 * a + c] + m->X[3 * b + c]);
        }
    }
    for (long f = 0; f < ntri; f++)
        for (int e = 0; e < 3; e++) {
            int n = node[6 * nt + 3 * f + e];
            q->tri_mid[3 * f + e] = n;
            const int a = m->tris[3 * f + tri_edge[e][0]], b = m->tris[3 * f + tri_edge[e][1]];
            for (int c = 0; c < 3; c++) q->X[3 * n + c] = 0.5 * (m->X[3 * a + c] + m->X[3 * b + c]);
        }
    eo_free(ctx, node);
    *out = q;
    return EO_OK;
}
