/* MEDIT .mesh reader and writer (ASCII).
 *
 * Reference: P. Frey, "MEDIT: an interactive mesh visualization software", INRIA
 * RT-0253 (2001), appendix "the .mesh file format".
 *   MeshVersionFormatted 1|2
 *   Dimension 3
 *   Vertices  n   then n lines "x y z ref"      (ref -> vmarker)
 *   Tetrahedra n  then n lines "v1 v2 v3 v4 ref" (1-based; ref -> tet_attr)
 *   Triangles n   then n lines "v1 v2 v3 ref"    (1-based; -> tris/tri_tag)
 *   End
 * Comments start with '#'. Every other keyword (Triangles, Edges, Corners, Normals, ...)
 * is followed by a count and that many one-line entries, which are skipped, except the
 * 10-node tets (TetrahedraP2), which are refused (EO_ERR_UNSUPPORTED) rather than read as
 * a mesh without them; likewise the writer refuses an order-2 mesh. */
#include <string.h>

#include "elastopt/io.h"
#include "mesh_io.h"
#include "../textscan.h"

static int read_medit(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src)
{
    eo_scan sc, *s = &sc;
    eo_scan_init(s, ctx, file, text, len, '#');
    eo_mesh *m = NULL;
    int rc = EO_OK, ver, dim, have_tets = 0;
    int *tets = NULL, *attr = NULL, nt = 0, tcap = 0, have_tris = 0;
    if ((rc = eo_scan_expect(s, "MeshVersionFormatted")) < 0) goto fail;
    if ((rc = eo_scan_int(s, "mesh version", 1, 3, &ver)) < 0) goto fail;
    for (;;) {
        const char *t;
        size_t n;
        if (!eo_scan_peek(s, &t, &n)) break;
        if (eo_scan_accept(s, "End")) break;
        if (eo_scan_accept(s, "Dimension")) {
            if ((rc = eo_scan_int(s, "dimension 3", 3, 3, &dim)) < 0) goto fail;
        } else if (eo_scan_accept(s, "Vertices")) {
            int nv;
            if (m) {
                rc = eo_scan_error(s, EO_ERR_PARSE, "second Vertices section; expected one");
                goto fail;
            }
            if ((rc = eo_scan_count(s, "vertex count", &nv)) < 0) goto fail;
            if ((rc = eo_mesh_create(ctx, nv, 0, &m)) < 0) goto fail;
            m->vmarker = eo_malloc(ctx, (size_t)(nv ? nv : 1) * sizeof(int));
            if (!m->vmarker) {
                rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (markers)");
                goto fail;
            }
            if ((rc = eo_mesh_src_alloc(ctx, src, nv, -1)) < 0) goto fail;
            for (int v = 0; v < nv; v++) {
                double *x = m->X + 3 * v;
                eo_scan_item(s, "vertex", v + 1);
                src->v_line[v] = eo_scan_record(s);
                src->v_id[v] = v + 1;
                if ((rc = eo_scan_double(s, "x coordinate", &x[0])) < 0 ||
                    (rc = eo_scan_double(s, "y coordinate", &x[1])) < 0 ||
                    (rc = eo_scan_double(s, "z coordinate", &x[2])) < 0 ||
                    (rc = eo_scan_int(s, "vertex reference", -2147483647L, 2147483647L, &m->vmarker[v])) < 0 ||
                    (rc = eo_scan_eol(s, "x y z ref")) < 0)
                    goto fail;
            }
            eo_scan_item(s, NULL, -1);
        } else if (eo_scan_accept(s, "Tetrahedra")) {
            if (!m) {
                rc = eo_scan_error(s, EO_ERR_PARSE, "Tetrahedra before Vertices; expected Vertices first");
                goto fail;
            }
            if (have_tets) {
                rc = eo_scan_error(s, EO_ERR_PARSE, "second Tetrahedra section; expected one");
                goto fail;
            }
            have_tets = 1;
            if ((rc = eo_scan_count(s, "tetrahedron count", &nt)) < 0) goto fail;
            tets = eo_malloc(ctx, (size_t)(nt ? nt : 1) * 4 * sizeof(int));
            attr = eo_malloc(ctx, (size_t)(nt ? nt : 1) * sizeof(int));
            if (!tets || !attr) {
                rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (%d tets)", nt);
                goto fail;
            }
            if ((rc = eo_mesh_src_alloc(ctx, src, -1, nt)) < 0) goto fail;
            for (int q = 0; q < nt; q++) {
                eo_scan_item(s, "tet", q + 1);
                src->t_line[q] = eo_scan_record(s);
                src->t_id[q] = q + 1;
                for (int a = 0; a < 4; a++) {
                    long v;
                    if ((rc = eo_scan_long(s, "vertex index", &v)) < 0) goto fail;
                    if (v < 1 || v > m->nv) {
                        rc = eo_scan_error(s, EO_ERR_MESH, "expected vertex index in [1, %d], got %ld", m->nv, v);
                        goto fail;
                    }
                    tets[4 * q + a] = (int)v - 1;
                }
                if ((rc = eo_scan_int(s, "tet reference", -2147483647L, 2147483647L, &attr[q])) < 0 ||
                    (rc = eo_scan_eol(s, "v1 v2 v3 v4 ref")) < 0)
                    goto fail;
            }
            eo_scan_item(s, NULL, -1);
        } else if (eo_scan_accept(s, "Triangles")) {
            int nf;
            if (!m) {
                rc = eo_scan_error(s, EO_ERR_PARSE, "Triangles before Vertices; expected Vertices first");
                goto fail;
            }
            if (have_tris) {
                rc = eo_scan_error(s, EO_ERR_PARSE, "second Triangles section; expected one");
                goto fail;
            }
            have_tris = 1;
            if ((rc = eo_scan_count(s, "triangle count", &nf)) < 0) goto fail;
            for (int q = 0; q < nf; q++) {
                int v[3], ref;
                eo_scan_item(s, "triangle", q + 1);
                long line = eo_scan_record(s);
                for (int a = 0; a < 3; a++) {
                    long x;
                    if ((rc = eo_scan_long(s, "vertex index", &x)) < 0) goto fail;
                    if (x < 1 || x > m->nv) {
                        rc = eo_scan_error(s, EO_ERR_MESH, "expected vertex index in [1, %d], got %ld", m->nv, x);
                        goto fail;
                    }
                    v[a] = (int)x - 1;
                }
                if ((rc = eo_scan_int(s, "triangle reference", -2147483647L, 2147483647L, &ref)) < 0 ||
                    (rc = eo_scan_eol(s, "v1 v2 v3 ref")) < 0 || (rc = eo_mesh_add_tri(ctx, m, src, &tcap, v, ref, line)) < 0)
                    goto fail;
            }
            eo_scan_item(s, NULL, -1);
        } else if (t[0] >= 'A' && t[0] <= 'Z') {
            /* another section: keyword, count, count lines */
            char kw[48];
            snprintf(kw, sizeof kw, "%.*s", (int)(n > 40 ? 40 : n), t);
            if (strcmp(kw, "TetrahedraP2") == 0) {
                rc = eo_scan_error(s, EO_ERR_UNSUPPORTED,
                                   "MEDIT TetrahedraP2 (10-node tets) are not supported; expected Tetrahedra "
                                   "(or give the quadratic mesh as Gmsh .msh, VTU or TetGen)");
                goto fail;
            }
            s->p += n;
            long k;
            char what[96];
            snprintf(what, sizeof what, "entry count after '%s'", kw);
            if ((rc = eo_scan_long(s, what, &k)) < 0) goto fail;
            if (k < 0 || k > (long)(s->end - s->p)) {
                rc = eo_scan_error(s, EO_ERR_PARSE, "expected a plausible entry count after '%s', got %ld", kw, k);
                goto fail;
            }
            snprintf(what, sizeof what, "'%s' entries", kw);
            if ((rc = eo_scan_skip_lines(s, k, what)) < 0) goto fail;
        } else {
            rc = eo_scan_fail(s, "a section keyword such as 'Vertices', 'Tetrahedra' or 'End'");
            goto fail;
        }
    }
    if (!m) {
        rc = eo_scan_error(s, EO_ERR_PARSE, "expected a Vertices section, got end of file");
        goto fail;
    }
    if (!have_tets) {
        rc = eo_scan_error(s, EO_ERR_MESH, "expected a Tetrahedra section, got end of file");
        goto fail;
    }
    eo_free(ctx, m->tets);
    m->tets = tets;
    m->tet_attr = attr;
    m->nt = nt;
    *out = m;
    return EO_OK;
fail:
    eo_free(ctx, tets);
    eo_free(ctx, attr);
    eo_mesh_destroy(&m);
    *out = NULL;
    return rc;
}

static int write_medit(eo_ctx *ctx, const eo_mesh *m, const char *path)
{
    if (m->tet10)
        return eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_FILE(path, -1),
                           "MEDIT output of a quadratic (10-node) mesh is not supported; expected .msh, .vtu or "
                           ".node/.ele (or write the linear mesh)");
    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    FILE *f = eo_afile_fp(af);
    fprintf(f, "MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n%d\n", m->nv);
    for (int v = 0; v < m->nv; v++) {
        char b[3][32];
        fprintf(f, "%s %s %s %d\n", eo_fmt_double(b[0], m->X[3 * v]), eo_fmt_double(b[1], m->X[3 * v + 1]),
                eo_fmt_double(b[2], m->X[3 * v + 2]), m->vmarker ? m->vmarker[v] : 0);
    }
    fprintf(f, "\nTetrahedra\n%d\n", m->nt);
    for (int t = 0; t < m->nt; t++) {
        const int *q = m->tets + 4 * t;
        fprintf(f, "%d %d %d %d %d\n", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1, m->tet_attr ? m->tet_attr[t] : 0);
    }
    if (m->ntri) {
        fprintf(f, "\nTriangles\n%d\n", m->ntri);
        for (int t = 0; t < m->ntri; t++) {
            const int *q = m->tris + 3 * t;
            fprintf(f, "%d %d %d %d\n", q[0] + 1, q[1] + 1, q[2] + 1, m->tri_tag[t]);
        }
    }
    fprintf(f, "\nEnd\n");
    return eo_afile_commit(ctx, &af);
}

static const char *const medit_exts[] = {".mesh", NULL};

const eo_mesh_io_type eo_mesh_io_medit = {
    .format = EO_MESH_MEDIT,
    .name = "medit",
    .exts = medit_exts,
    .read_text = read_medit,
    .write = write_medit,
};
