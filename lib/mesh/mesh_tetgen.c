/* TetGen .node/.ele reader and writer.
 *
 * Reference: H. Si, "TetGen user's manual", section 5.2 (file formats).
 *   .node: "<#points> <dim = 3> <#attributes> <#markers 0|1>", then per point
 *          "<index> <x> <y> <z> [attributes...] [marker]"          (marker -> vmarker)
 *   .ele:  "<#tets> <nodes per tet 4|10> <#attributes>", then per tet
 *          "<index> <n1> <n2> <n3> <n4> [6 more nodes] [attributes...]"
 *          (the first attribute, the region, -> tet_attr; it must be an integer).
 *          10 nodes per tet (tetgen -o2) give an order-2 mesh: TetGen lists the nodes of
 *          edges 23, 03, 01, 12, 13, 02 (its edge2ver table; checked against libtet 1.5
 *          output, each node at the midpoint of that edge), permuted here into the VTK
 *          order of tet10 (01, 12, 20, 03, 13, 23) and back by the writer.
 *   .face: "<#faces> <#markers 0|1>", then per face "<index> <n1> <n2> <n3> [marker]"
 *          (optional; with markers -> tagged triangles tris/tri_tag, without: ignored)
 * Indices start at 0 or 1 (the first point's index decides, as TetGen's -z does) and
 * are consecutive. '#' starts a comment. Given "a.node", "a.ele" or "a", both files
 * a.node and a.ele are read, and a.face when it exists. The writer uses 1-based
 * indices and writes a.face when the mesh has tagged triangles; it writes every file
 * to a temporary first and renames them together (eo_rename_all), so a failure
 * leaves existing files untouched. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "elastopt/io.h"
#include "mesh_io.h"
#include "../textscan.h"

static int read_node(eo_scan *s, eo_mesh **out, eo_mesh_src *src, int *base)
{
    eo_ctx *ctx = s->ctx;
    int n, dim, nattr, nmark, rc;
    eo_mesh *m = NULL;
    if ((rc = eo_scan_count(s, "point count", &n)) < 0) return rc;
    if ((rc = eo_scan_int(s, "dimension 3", 3, 3, &dim)) < 0) return rc;
    if ((rc = eo_scan_int(s, "attribute count", 0, 1000, &nattr)) < 0) return rc;
    if ((rc = eo_scan_int(s, "boundary marker flag", 0, 1, &nmark)) < 0) return rc;
    if ((rc = eo_scan_eol(s, "the .node header")) < 0) return rc;
    if ((rc = eo_mesh_create(ctx, n, 0, &m)) < 0) return rc;
    *out = m;
    if (nmark && !(m->vmarker = eo_malloc(ctx, (size_t)(n ? n : 1) * sizeof(int))))
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (markers)");
    if ((rc = eo_mesh_src_alloc(ctx, src, n, -1)) < 0) return rc;
    *base = 0;
    for (int v = 0; v < n; v++) {
        long idx;
        eo_scan_item(s, NULL, -1);
        src->v_line[v] = eo_scan_record(s);
        if ((rc = eo_scan_long(s, "point index", &idx)) < 0) return rc;
        if (v == 0) {
            if (idx != 0 && idx != 1) {
                eo_scan_item(s, "vertex", idx);
                return eo_scan_error(s, EO_ERR_PARSE, "expected the first point index to be 0 or 1, got %ld", idx);
            }
            *base = (int)idx;
        } else if (idx != *base + v) {
            eo_scan_item(s, "vertex", idx);
            return eo_scan_error(s, EO_ERR_PARSE, "expected point index %d (consecutive), got %ld", *base + v, idx);
        }
        src->v_id[v] = idx;
        eo_scan_item(s, "vertex", idx);
        double *x = m->X + 3 * v, a;
        if ((rc = eo_scan_double(s, "x coordinate", &x[0])) < 0 || (rc = eo_scan_double(s, "y coordinate", &x[1])) < 0 ||
            (rc = eo_scan_double(s, "z coordinate", &x[2])) < 0)
            return rc;
        for (int k = 0; k < nattr; k++)
            if ((rc = eo_scan_double(s, "point attribute", &a)) < 0) return rc;
        if (nmark && (rc = eo_scan_int(s, "boundary marker", -2147483647L, 2147483647L, &m->vmarker[v])) < 0)
            return rc;
        if ((rc = eo_scan_eol(s, "the point's fields (header says so)")) < 0) return rc;
    }
    eo_scan_item(s, NULL, -1);
    if (eo_scan_skip(s)) {
        char w[96];
        snprintf(w, sizeof w, "end of file after %d points", n);
        return eo_scan_fail(s, w);
    }
    return EO_OK;
}

/* TetGen -> VTK order of a 10-node tet: TetGen's node j is tet10 slot tg_to[j] (and VTK
 * slot i holds TetGen's node {0, 1, 2, 3, 6, 7, 9, 5, 8, 4}[i]) */
static const int tg_to[10] = {0, 1, 2, 3, 9, 7, 4, 5, 8, 6};

static int read_ele(eo_scan *s, eo_mesh *m, eo_mesh_src *src, int base)
{
    eo_ctx *ctx = s->ctx;
    int n, npt, nattr, rc;
    if ((rc = eo_scan_count(s, "tetrahedron count", &n)) < 0) return rc;
    if ((rc = eo_scan_int(s, "nodes per tetrahedron (4 or 10)", 4, 10, &npt)) < 0) return rc;
    if (npt != 4 && npt != 10) return eo_scan_error(s, EO_ERR_PARSE, "expected 4 or 10 nodes per tetrahedron, got %d", npt);
    if ((rc = eo_scan_int(s, "attribute count", 0, 1000, &nattr)) < 0) return rc;
    if ((rc = eo_scan_eol(s, "the .ele header")) < 0) return rc;
    eo_free(ctx, m->tets);
    m->tets = eo_malloc(ctx, (size_t)(n ? n : 1) * 4 * sizeof(int));
    if (!m->tets) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (%d tets)", n);
    if (npt == 10) {
        if (!(m->tet10 = eo_malloc(ctx, (size_t)(n ? n : 1) * 10 * sizeof(int))))
            return eo_error(ctx, EO_ERR_NOMEM, "out of memory (%d 10-node tets)", n);
        m->order = 2;
    }
    if (nattr && !(m->tet_attr = eo_malloc(ctx, (size_t)(n ? n : 1) * sizeof(int))))
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (%d tets)", n);
    if ((rc = eo_mesh_src_alloc(ctx, src, -1, n)) < 0) return rc;
    int ebase = 0;
    for (int t = 0; t < n; t++) {
        long idx;
        eo_scan_item(s, NULL, -1);
        src->t_line[t] = eo_scan_record(s);
        if ((rc = eo_scan_long(s, "tetrahedron index", &idx)) < 0) return rc;
        eo_scan_item(s, "tet", idx);
        if (t == 0) {
            if (idx != 0 && idx != 1)
                return eo_scan_error(s, EO_ERR_PARSE, "expected the first tetrahedron index to be 0 or 1, got %ld", idx);
            ebase = (int)idx;
        } else if (idx != ebase + t) {
            return eo_scan_error(s, EO_ERR_PARSE, "expected tetrahedron index %d (consecutive), got %ld", ebase + t, idx);
        }
        src->t_id[t] = idx;
        for (int a = 0; a < npt; a++) {
            long v;
            if ((rc = eo_scan_long(s, "point index", &v)) < 0) return rc;
            if (v < base || v >= (long)base + m->nv)
                return eo_scan_error(s, EO_ERR_MESH, "expected point index in [%d, %d], got %ld", base,
                                     base + m->nv - 1, v);
            if (a < 4) m->tets[4 * t + a] = (int)(v - base);
            if (npt == 10) m->tet10[10 * t + tg_to[a]] = (int)(v - base);
        }
        for (int k = 0; k < nattr; k++) {
            double a;
            if ((rc = eo_scan_double(s, "tetrahedron attribute", &a)) < 0) return rc;
            if (k > 0) continue;
            if (!(a == floor(a) && fabs(a) < 2147483647.0))
                return eo_scan_error(s, EO_ERR_PARSE, "expected an integer region attribute, got %g", a);
            m->tet_attr[t] = (int)a;
        }
        if ((rc = eo_scan_eol(s, "the tetrahedron's fields (header says so)")) < 0) return rc;
        m->nt = t + 1;
    }
    eo_scan_item(s, NULL, -1);
    m->nt = n;
    if (eo_scan_skip(s)) {
        char w[96];
        snprintf(w, sizeof w, "end of file after %d tetrahedra", n);
        return eo_scan_fail(s, w);
    }
    return EO_OK;
}

int eo_tetgen_read_texts(eo_ctx *ctx, const char *node, size_t node_len, const char *node_file, const char *ele,
                         size_t ele_len, const char *ele_file, eo_mesh **out, eo_mesh_src *src)
{
    eo_scan s;
    eo_mesh *m = NULL;
    int base = 0, rc;
    *out = NULL;
    eo_scan_init(&s, ctx, node_file, node, node_len, '#');
    rc = read_node(&s, &m, src, &base);
    src->base = base;
    if (rc >= 0) {
        m->nt = 0;
        eo_scan_init(&s, ctx, ele_file, ele, ele_len, '#');
        rc = read_ele(&s, m, src, base);
    }
    if (rc < 0) {
        eo_mesh_destroy(&m);
        return rc;
    }
    *out = m;
    return EO_OK;
}

int eo_tetgen_read_face(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh *m, eo_mesh_src *src)
{
    eo_scan sc, *s = &sc;
    int n, nmark, rc, cap = 0;
    eo_scan_init(s, ctx, file, text, len, '#');
    if ((rc = eo_scan_count(s, "face count", &n)) < 0) return rc;
    if ((rc = eo_scan_int(s, "boundary marker flag", 0, 1, &nmark)) < 0) return rc;
    if ((rc = eo_scan_eol(s, "the .face header")) < 0) return rc;
    for (int f = 0; f < n; f++) {
        long idx, line = eo_scan_record(s);
        int v[3], tag = 0;
        if ((rc = eo_scan_long(s, "face index", &idx)) < 0) return rc;
        eo_scan_item(s, "triangle", idx);
        for (int a = 0; a < 3; a++) {
            long x;
            if ((rc = eo_scan_long(s, "point index", &x)) < 0) return rc;
            if (x < src->base || x >= (long)src->base + m->nv)
                return eo_scan_error(s, EO_ERR_MESH, "expected point index in [%d, %d], got %ld", src->base,
                                     src->base + m->nv - 1, x);
            v[a] = (int)(x - src->base);
        }
        if (nmark && (rc = eo_scan_int(s, "boundary marker", -2147483647L, 2147483647L, &tag)) < 0) return rc;
        if ((rc = eo_scan_eol(s, "the face's fields (header says so)")) < 0) return rc;
        eo_scan_item(s, NULL, -1);
        if (nmark && (rc = eo_mesh_add_tri(ctx, m, src, &cap, v, tag, line)) < 0) return rc;
    }
    if (eo_scan_skip(s)) {
        char w[96];
        snprintf(w, sizeof w, "end of file after %d faces", n);
        return eo_scan_fail(s, w);
    }
    return EO_OK;
}

/* "a.node" / "a.ele" / "a" -> "a.node", "a.ele", "a.face" in one allocation: node at 0,
 * ele at k, face at 2k. */
static char *tetgen_names(eo_ctx *ctx, const char *path, size_t *k)
{
    size_t n = strlen(path);
    if (n >= 5 && strcmp(path + n - 5, ".node") == 0) n -= 5;
    else if (n >= 4 && strcmp(path + n - 4, ".ele") == 0) n -= 4;
    *k = n + 6;
    char *b = eo_malloc(ctx, 3 * *k);
    if (!b) return NULL;
    snprintf(b, *k, "%.*s.node", (int)n, path);
    snprintf(b + *k, *k, "%.*s.ele", (int)n, path);
    snprintf(b + 2 * *k, *k, "%.*s.face", (int)n, path);
    return b;
}

static int read_tetgen(eo_ctx *ctx, const char *path, eo_mesh **out, eo_mesh_src *src)
{
    size_t k;
    char *names = tetgen_names(ctx, path, &k), *node = NULL, *ele = NULL;
    size_t nn = 0, ne = 0;
    if (!names) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    src->owned = names;
    src->vert_file = names;
    src->tet_file = names + k;
    int rc = eo_path_check(ctx, names, EO_PATH_READ);
    if (rc >= 0) rc = eo_path_check(ctx, names + k, EO_PATH_READ);
    if (rc >= 0) rc = eo_read_file(ctx, names, &node, &nn);
    if (rc >= 0) rc = eo_read_file(ctx, names + k, &ele, &ne);
    if (rc >= 0) rc = eo_tetgen_read_texts(ctx, node, nn, names, ele, ne, names + k, out, src);
    struct stat st;
    if (rc >= 0 && stat(names + 2 * k, &st) == 0) { /* optional .face */
        eo_free(ctx, node);
        node = NULL;
        src->tri_file = names + 2 * k;
        rc = eo_path_check(ctx, names + 2 * k, EO_PATH_READ);
        if (rc >= 0) rc = eo_read_file(ctx, names + 2 * k, &node, &nn);
        if (rc >= 0) rc = eo_tetgen_read_face(ctx, node, nn, names + 2 * k, *out, src);
        if (rc < 0) eo_mesh_destroy(out);
    }
    eo_free(ctx, node);
    eo_free(ctx, ele);
    return rc;
}

static int write_tetgen(eo_ctx *ctx, const eo_mesh *m, const char *path)
{
    size_t k;
    char *names = tetgen_names(ctx, path, &k);
    if (!names) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    const int nfile = m->ntri ? 3 : 2;
    const char *dst[3] = {names, names + k, names + 2 * k};
    char tmp[3][4200] = {{0}, {0}, {0}};
    const char *tmpp[3] = {tmp[0], tmp[1], tmp[2]};
    FILE *f[3] = {NULL, NULL, NULL};
    int rc = EO_OK;
    for (int i = 0; i < nfile && rc >= 0; i++) rc = eo_path_check(ctx, dst[i], EO_PATH_WRITE);
    for (int i = 0; i < nfile && rc >= 0; i++) {
        snprintf(tmp[i], sizeof tmp[i], "%s.tmp.%ld", dst[i], (long)getpid());
        if (!(f[i] = fopen(tmp[i], "wb")))
            rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(dst[i], -1), "cannot write: %s", strerror(errno));
    }
    if (rc < 0) goto fail;
    fprintf(f[0], "# written by elastopt\n%d 3 0 %d\n", m->nv, m->vmarker ? 1 : 0);
    for (int v = 0; v < m->nv; v++) {
        char b[3][32];
        fprintf(f[0], "%d %s %s %s", v + 1, eo_fmt_double(b[0], m->X[3 * v]), eo_fmt_double(b[1], m->X[3 * v + 1]),
                eo_fmt_double(b[2], m->X[3 * v + 2]));
        if (m->vmarker) fprintf(f[0], " %d", m->vmarker[v]);
        fputc('\n', f[0]);
    }
    fprintf(f[1], "# written by elastopt\n%d %d %d\n", m->nt, m->tet10 ? 10 : 4, m->tet_attr ? 1 : 0);
    for (int t = 0; t < m->nt; t++) {
        const int *q = m->tets + 4 * t;
        fprintf(f[1], "%d %d %d %d %d", t + 1, q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
        for (int j = 4; m->tet10 && j < 10; j++) fprintf(f[1], " %d", m->tet10[10 * t + tg_to[j]] + 1);
        if (m->tet_attr) fprintf(f[1], " %d", m->tet_attr[t]);
        fputc('\n', f[1]);
    }
    if (nfile == 3) {
        fprintf(f[2], "# written by elastopt\n%d 1\n", m->ntri);
        for (int t = 0; t < m->ntri; t++) {
            const int *q = m->tris + 3 * t;
            fprintf(f[2], "%d %d %d %d %d\n", t + 1, q[0] + 1, q[1] + 1, q[2] + 1, m->tri_tag[t]);
        }
    }
    for (int i = 0; i < nfile; i++) {
        int bad = ferror(f[i]);
        if (fclose(f[i]) != 0) bad = 1;
        f[i] = NULL;
        if (bad && rc >= 0) rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(dst[i], -1), "write failed: %s", strerror(errno));
    }
    if (rc >= 0) {
        rc = eo_rename_all(ctx, nfile, tmpp, dst); /* removes the temporaries on failure */
        eo_free(ctx, names);
        return rc;
    }
fail:
    for (int i = 0; i < nfile; i++) {
        if (f[i]) fclose(f[i]);
        if (tmp[i][0]) remove(tmp[i]);
    }
    eo_free(ctx, names);
    return rc;
}

static const char *const tetgen_exts[] = {".node", ".ele", NULL};

const eo_mesh_io_type eo_mesh_io_tetgen = {
    .format = EO_MESH_TETGEN,
    .name = "tetgen",
    .exts = tetgen_exts,
    .read_path = read_tetgen,
    .write = write_tetgen,
};
