/* TetGen .node/.ele reader and writer.
 *
 * Reference: H. Si, "TetGen user's manual", section 5.2 (file formats).
 *   .node: "<#points> <dim = 3> <#attributes> <#markers 0|1>", then per point
 *          "<index> <x> <y> <z> [attributes...] [marker]"          (marker -> vmarker)
 *   .ele:  "<#tets> <nodes per tet 4|10> <#attributes>", then per tet
 *          "<index> <n1> <n2> <n3> <n4> [6 more nodes] [attributes...]"
 *          (the first attribute, the region, -> tet_attr; it must be an integer)
 * Indices start at 0 or 1 (the first point's index decides, as TetGen's -z does) and
 * are consecutive. '#' starts a comment. Given "a.node", "a.ele" or "a", both files
 * a.node and a.ele are read. The writer uses 1-based indices. */
#include <math.h>
#include <string.h>

#include "elastopt/io.h"
#include "mesh_io.h"
#include "textscan.h"

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
    if (rc >= 0) {
        m->nt = 0;
        eo_scan_init(&s, ctx, ele_file, ele, ele_len, '#');
        rc = read_ele(&s, m, src, base);
    }
    if (rc < 0) {
        eo_mesh_destroy(ctx, &m);
        return rc;
    }
    *out = m;
    return EO_OK;
}

/* "a.node" / "a.ele" / "a" -> "a.node" and "a.ele" in one allocation: node at 0, ele at k. */
static char *tetgen_names(eo_ctx *ctx, const char *path, size_t *k)
{
    size_t n = strlen(path);
    if (n >= 5 && strcmp(path + n - 5, ".node") == 0) n -= 5;
    else if (n >= 4 && strcmp(path + n - 4, ".ele") == 0) n -= 4;
    *k = n + 6;
    char *b = eo_malloc(ctx, 2 * *k);
    if (!b) return NULL;
    snprintf(b, *k, "%.*s.node", (int)n, path);
    snprintf(b + *k, *k, "%.*s.ele", (int)n, path);
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
    int rc = eo_read_file(ctx, names, &node, &nn);
    if (rc >= 0) rc = eo_read_file(ctx, names + k, &ele, &ne);
    if (rc >= 0) rc = eo_tetgen_read_texts(ctx, node, nn, names, ele, ne, names + k, out, src);
    eo_free(ctx, node);
    eo_free(ctx, ele);
    return rc;
}

static int write_tetgen(eo_ctx *ctx, const eo_mesh *m, const char *path)
{
    size_t k;
    char *names = tetgen_names(ctx, path, &k);
    if (!names) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    eo_afile *an = NULL, *ae = NULL;
    int rc = eo_afile_open(ctx, names, &an);
    if (rc >= 0) rc = eo_afile_open(ctx, names + k, &ae);
    if (rc < 0) goto fail;
    FILE *f = eo_afile_fp(an);
    fprintf(f, "# written by elastopt\n%d 3 0 %d\n", m->nv, m->vmarker ? 1 : 0);
    for (int v = 0; v < m->nv; v++) {
        fprintf(f, "%d %.17g %.17g %.17g", v + 1, m->X[3 * v], m->X[3 * v + 1], m->X[3 * v + 2]);
        if (m->vmarker) fprintf(f, " %d", m->vmarker[v]);
        fputc('\n', f);
    }
    f = eo_afile_fp(ae);
    fprintf(f, "# written by elastopt\n%d 4 %d\n", m->nt, m->tet_attr ? 1 : 0);
    for (int t = 0; t < m->nt; t++) {
        const int *q = m->tets + 4 * t;
        fprintf(f, "%d %d %d %d %d", t + 1, q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
        if (m->tet_attr) fprintf(f, " %d", m->tet_attr[t]);
        fputc('\n', f);
    }
    if ((rc = eo_afile_commit(ctx, &an)) < 0) goto fail;
    if ((rc = eo_afile_commit(ctx, &ae)) < 0) {
        remove(names); /* do not leave half of a pair */
        goto fail;
    }
fail:
    eo_afile_abort(ctx, &an);
    eo_afile_abort(ctx, &ae);
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
