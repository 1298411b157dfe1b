/* 2D triangle meshes (trimesh.h): a Gmsh .msh reader for 3-node triangles, boundary
 * nodes from the edges used by one triangle, the longest edge.
 *
 * Reference: Gmsh reference manual, "MSH file format" (versions 2 and 4.1), as in
 * mesh_gmsh.c (which reads the tets of the same files):
 *  2.2  $Nodes: n, then "tag x y z"; $Elements: n, then "tag type ntags tags... nodes...".
 *  4.1  $Nodes: "numBlocks numNodes minTag maxTag", per block "dim entity parametric n",
 *       n tags, then n lines "x y z [u v w]"; $Elements: "numBlocks numElements minTag
 *       maxTag", per block "dim entity type n", then n lines "tag node1..nodeK".
 * Element type 2 (3-node triangle) is kept; the rest is skipped. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/io.h"
#include "elastopt/trimesh.h"
#include "../textscan.h"

int eo_trimesh_create(eo_ctx *ctx, int nv, int nt, eo_trimesh **out)
{
    *out = NULL;
    if (nv < 0 || nt < 0) return eo_error(ctx, EO_ERR_INVALID, "trimesh: nv = %d, nt = %d", nv, nt);
    eo_trimesh *m = eo_calloc(ctx, 1, sizeof *m);
    if (m) m->ctx = ctx;
    if (!m) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (trimesh)");
    m->nv = nv;
    m->nt = nt;
    m->xy = eo_malloc(ctx, 2 * (size_t)(nv ? nv : 1) * sizeof(double));
    m->tri = eo_malloc(ctx, 3 * (size_t)(nt ? nt : 1) * sizeof(int));
    if (!m->xy || !m->tri) {
        eo_trimesh_destroy(&m);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (trimesh %d nodes, %d triangles)", nv, nt);
    }
    *out = m;
    return EO_OK;
}

void eo_trimesh_destroy(eo_trimesh **mp)
{
    eo_ctx *ctx = mp && *mp ? (*mp)->ctx : NULL;
    if (!mp || !*mp) return;
    eo_free(ctx, (*mp)->xy);
    eo_free(ctx, (*mp)->tri);
    eo_free(ctx, *mp);
    *mp = NULL;
}

double eo_trimesh_max_edge(const eo_trimesh *m)
{
    double h = 0;
    for (int t = 0; t < m->nt; t++)
        for (int q = 0; q < 3; q++) {
            int a = m->tri[3 * t + q], b = m->tri[3 * t + (q + 1) % 3];
            h = fmax(h, hypot(m->xy[2 * a] - m->xy[2 * b], m->xy[2 * a + 1] - m->xy[2 * b + 1]));
        }
    return h;
}

static int cmp_edge(const void *pa, const void *pb)
{
    const int *a = pa, *b = pb;
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

int eo_trimesh_boundary(eo_ctx *ctx, const eo_trimesh *m, unsigned char *on_boundary)
{
    size_t ne = 3 * (size_t)m->nt;
    int *e = eo_malloc(ctx, 2 * (ne ? ne : 1) * sizeof(int));
    if (!e) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (trimesh edges)");
    for (int t = 0; t < m->nt; t++)
        for (int q = 0; q < 3; q++) {
            int a = m->tri[3 * t + q], b = m->tri[3 * t + (q + 1) % 3];
            int *p = e + 2 * (3 * (size_t)t + q);
            p[0] = a < b ? a : b;
            p[1] = a < b ? b : a;
        }
    qsort(e, ne, 2 * sizeof(int), cmp_edge);
    memset(on_boundary, 0, (size_t)m->nv);
    int rc = EO_OK;
    for (size_t i = 0; i < ne;) {
        size_t j = i + 1;
        while (j < ne && e[2 * j] == e[2 * i] && e[2 * j + 1] == e[2 * i + 1]) j++;
        if (j - i == 1) on_boundary[e[2 * i]] = on_boundary[e[2 * i + 1]] = 1;
        else if (j - i > 2) {
            rc = eo_error(ctx, EO_ERR_MESH, "trimesh: edge (%d, %d) is used by %zu triangles; expected at most 2",
                          e[2 * i], e[2 * i + 1], j - i);
            break;
        }
        i = j;
    }
    eo_free(ctx, e);
    return rc;
}

/* ---- Gmsh reader ------------------------------------------------------------------- */

typedef struct {
    eo_scan s;
    eo_ctx *ctx;
    int nv, nt, cap;
    double *xy;
    long *tags;
    int *tri;
    eo_tagmap map;
    int have_map;
} tri_reader;

static int tr_nodes(tri_reader *r, int v41)
{
    eo_scan *s = &r->s;
    int nb = 1, n, rc;
    long lo, hi;
    if (r->xy) return eo_scan_error(s, EO_ERR_PARSE, "second $Nodes section; expected one");
    if (v41 && (rc = eo_scan_count(s, "node block count", &nb)) < 0) return rc;
    if ((rc = eo_scan_count(s, "node count", &n)) < 0) return rc;
    if (v41 && ((rc = eo_scan_long(s, "minimum node tag", &lo)) < 0 || (rc = eo_scan_long(s, "maximum node tag", &hi)) < 0))
        return rc;
    r->xy = eo_malloc(r->ctx, 2 * (size_t)(n ? n : 1) * sizeof(double));
    r->tags = eo_malloc(r->ctx, (size_t)(n ? n : 1) * sizeof(long));
    if (!r->xy || !r->tags) return eo_error(r->ctx, EO_ERR_NOMEM, "out of memory (%d nodes)", n);
    int done = 0;
    for (int b = 0; b < nb; b++) {
        int k = n, dim = 0, param = 0;
        long ent;
        if (v41) {
            if ((rc = eo_scan_int(s, "entity dimension", 0, 3, &dim)) < 0) return rc;
            if ((rc = eo_scan_long(s, "entity tag", &ent)) < 0) return rc;
            if ((rc = eo_scan_int(s, "parametric flag", 0, 1, &param)) < 0) return rc;
            if ((rc = eo_scan_count(s, "nodes in block", &k)) < 0) return rc;
            if (k > n - done) return eo_scan_error(s, EO_ERR_PARSE, "block of %d nodes exceeds the %d announced", k, n);
            for (int i = done; i < done + k; i++)
                if ((rc = eo_scan_long(s, "node tag", &r->tags[i])) < 0) return rc;
        }
        for (int i = done; i < done + k; i++) {
            double z;
            eo_scan_record(s);
            if (!v41 && (rc = eo_scan_long(s, "node tag", &r->tags[i])) < 0) return rc;
            eo_scan_item(s, "vertex", r->tags[i]);
            if ((rc = eo_scan_double(s, "x coordinate", &r->xy[2 * i])) < 0 ||
                (rc = eo_scan_double(s, "y coordinate", &r->xy[2 * i + 1])) < 0 ||
                (rc = eo_scan_double(s, "z coordinate", &z)) < 0)
                return rc;
            for (int p = 0; p < (param ? dim : 0); p++)
                if ((rc = eo_scan_double(s, "parametric coordinate", &z)) < 0) return rc;
            if (!isfinite(r->xy[2 * i]) || !isfinite(r->xy[2 * i + 1]))
                return eo_scan_error(s, EO_ERR_MESH, "expected finite coordinates");
            if ((rc = eo_scan_eol(s, "x y z")) < 0) return rc;
            eo_scan_item(s, NULL, -1);
        }
        done += k;
    }
    if (done != n) return eo_scan_error(s, EO_ERR_PARSE, "expected %d nodes, the blocks hold %d", n, done);
    r->nv = n;
    if ((rc = eo_scan_expect(s, "$EndNodes")) < 0) return rc;
    int dup = -1;
    rc = eo_tagmap_build(r->ctx, r->tags, n, &r->map, &dup);
    if (rc == EO_ERR_PARSE) return eo_scan_error(s, rc, "node tag %ld repeated; expected unique node tags", r->tags[dup]);
    if (rc < 0) return rc;
    r->have_map = 1;
    return EO_OK;
}

static int tr_triangle(tri_reader *r, long tag)
{
    eo_scan *s = &r->s;
    int rc;
    eo_scan_item(s, "triangle", tag);
    for (int a = 0; a < 3; a++) {
        long nt;
        if ((rc = eo_scan_long(s, "node tag", &nt)) < 0) return rc;
        int v = eo_tagmap_find(&r->map, nt);
        if (v < 0) return eo_scan_error(s, EO_ERR_MESH, "node %ld: expected a node tag defined in $Nodes", nt);
        r->tri[3 * r->nt + a] = v;
    }
    if ((rc = eo_scan_eol(s, "the 3 nodes of a triangle")) < 0) return rc;
    eo_scan_item(s, NULL, -1);
    r->nt++;
    return EO_OK;
}

static int tr_elements(tri_reader *r, int v41)
{
    eo_scan *s = &r->s;
    int nb = 1, n, rc;
    long lo, hi;
    if (!r->have_map) return eo_scan_error(s, EO_ERR_PARSE, "$Elements before $Nodes; expected $Nodes first");
    if (r->tri) return eo_scan_error(s, EO_ERR_PARSE, "second $Elements section; expected one");
    if (v41 && (rc = eo_scan_count(s, "element block count", &nb)) < 0) return rc;
    if ((rc = eo_scan_count(s, "element count", &n)) < 0) return rc;
    if (v41 && ((rc = eo_scan_long(s, "minimum element tag", &lo)) < 0 ||
                (rc = eo_scan_long(s, "maximum element tag", &hi)) < 0))
        return rc;
    r->tri = eo_malloc(r->ctx, 3 * (size_t)(n ? n : 1) * sizeof(int));
    if (!r->tri) return eo_error(r->ctx, EO_ERR_NOMEM, "out of memory (%d elements)", n);
    int done = 0;
    for (int b = 0; b < nb; b++) {
        int k = n, dim, type = 0;
        long ent, tag;
        if (v41) {
            if ((rc = eo_scan_int(s, "entity dimension", 0, 3, &dim)) < 0) return rc;
            if ((rc = eo_scan_long(s, "entity tag", &ent)) < 0) return rc;
            if ((rc = eo_scan_int(s, "element type", 1, 1000, &type)) < 0) return rc;
            if ((rc = eo_scan_count(s, "elements in block", &k)) < 0) return rc;
            if (k > n - done)
                return eo_scan_error(s, EO_ERR_PARSE, "block of %d elements exceeds the %d announced", k, n);
            if (type != 2) {
                if ((rc = eo_scan_skip_lines(s, k, "element lines")) < 0) return rc;
                done += k;
                continue;
            }
            if ((rc = eo_scan_eol(s, "the element block header")) < 0) return rc;
        }
        for (int i = 0; i < k; i++) {
            eo_scan_record(s);
            if ((rc = eo_scan_long(s, "element tag", &tag)) < 0) return rc;
            if (!v41) {
                int ntags;
                eo_scan_item(s, "element", tag);
                if ((rc = eo_scan_int(s, "element type", 1, 1000, &type)) < 0) return rc;
                if ((rc = eo_scan_int(s, "number of tags", 0, 1000, &ntags)) < 0) return rc;
                for (int q = 0; q < ntags; q++) {
                    long v;
                    if ((rc = eo_scan_long(s, "element tag value", &v)) < 0) return rc;
                }
                if (type != 2) {
                    eo_scan_skip_line(s);
                    eo_scan_item(s, NULL, -1);
                    continue;
                }
            }
            if ((rc = tr_triangle(r, tag)) < 0) return rc;
        }
        done += k;
    }
    if (done != n) return eo_scan_error(s, EO_ERR_PARSE, "expected %d elements, the blocks hold %d", n, done);
    return eo_scan_expect(s, "$EndElements");
}

int eo_trimesh_read_gmsh(eo_ctx *ctx, const char *path, eo_trimesh **out)
{
    *out = NULL;
    char *text = NULL;
    size_t len = 0;
    int rc = eo_read_file(ctx, path, &text, &len);
    if (rc < 0) return rc;
    tri_reader r = {.ctx = ctx};
    eo_scan *s = &r.s;
    eo_scan_init(s, ctx, path, text, len, 0);
    int v41;
    if ((rc = eo_scan_gmsh_format(s, &v41)) < 0) goto done;
    while (eo_scan_skip(s)) {
        const char *tok;
        size_t n;
        eo_scan_word(s, "section", &tok, &n);
        if (n == 6 && !strncmp(tok, "$Nodes", 6)) rc = tr_nodes(&r, v41);
        else if (n == 9 && !strncmp(tok, "$Elements", 9)) rc = tr_elements(&r, v41);
        else if (n > 1 && tok[0] == '$') rc = eo_scan_gmsh_skip_section(s, tok, n);
        else rc = eo_scan_error(s, EO_ERR_PARSE, "expected a $Section, got '%.*s'", (int)(n > 40 ? 40 : n), tok);
        if (rc < 0) goto done;
    }
    if (!r.nt) {
        rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_FILE(path, s->line), "no 3-node triangles (element type 2)");
        goto done;
    }
    eo_trimesh *m;
    if ((rc = eo_trimesh_create(ctx, r.nv, r.nt, &m)) < 0) goto done;
    memcpy(m->xy, r.xy, 2 * (size_t)r.nv * sizeof(double));
    memcpy(m->tri, r.tri, 3 * (size_t)r.nt * sizeof(int));
    *out = m;
done:
    if (r.have_map) eo_tagmap_deinit(ctx, &r.map);
    eo_free(ctx, r.xy);
    eo_free(ctx, r.tags);
    eo_free(ctx, r.tri);
    eo_free(ctx, text);
    return rc;
}
