/* Vega FEM .veg reader (ASCII, tetrahedra).
 *
 * Reference: the .veg format of J. Barbič's Vega FEM library (volumetricMesh, the
 * VolumetricMesh ASCII loader):
 *   # comment
 *   *VERTICES
 *   n 3 0 0                 vertex count, coordinates per vertex (3), two zeros
 *   i x y z                 n lines; i consecutive from 1 (or from 0: a 0-based file)
 *   *ELEMENTS
 *   TET                     element type (CUBIC, Vega's hexahedra, is not a tet mesh)
 *   m 4 0                   element count, vertices per element (4), a zero
 *   j v1 v2 v3 v4           m lines; j consecutive; v in the base of the vertex indices
 *   *MATERIAL name          then "ENU, density, E, nu" (or another material line)
 *   *SET name               then lines of comma-separated element indices
 *   *REGION                 then "set, material" lines
 * Fields may be separated by blanks or commas. Only vertices and tets are read: the
 * *MATERIAL, *SET and *REGION sections (and any other "*KEYWORD" section, e.g. a
 * *MASS_SPRING_SYSTEM) are skipped up to the next line starting with '*', each with an
 * info message "veg: section *MATERIAL ignored" (materials come from the scene's
 * `material` / `materials`). *INCLUDE is refused with an error naming the line: a
 * mesh is read from one file (or buffer); inline the included file. Orientation: tets
 * of negative volume are reoriented by the common validation, as for every reader.
 * No writer: convert .veg to any other format with `elastopt convert`. */
#include <string.h>

#include "mesh_io.h"
#include "../textscan.h"

/* "*VERTICES"/"*ELEMENTS" count line: count, per-item width `want`, then optional
 * integers (Vega writes zeros) up to the end of the line. */
static int count_line(eo_scan *s, const char *what, const char *width_what, int want, int *n)
{
    int w, rc;
    eo_scan_record(s);
    if ((rc = eo_scan_count(s, what, n)) < 0 || (rc = eo_scan_int(s, width_what, want, want, &w)) < 0) return rc;
    const char *t;
    size_t len;
    while (eo_scan_peek(s, &t, &len)) {
        long z;
        if ((rc = eo_scan_long(s, "an integer (Vega writes 0)", &z)) < 0) return rc;
    }
    return eo_scan_eol(s, what);
}

/* The first index of a list fixes its base (0 or 1); the rest must follow on. */
static int item_index(eo_scan *s, const char *what, int k, int *base)
{
    long id;
    int rc = eo_scan_long(s, what, &id);
    if (rc < 0) return rc;
    if (k == 0 && (id == 0 || id == 1)) *base = (int)id;
    if (k == 0 && id != 0 && id != 1)
        return eo_scan_error(s, EO_ERR_PARSE, "expected %s 1 (or 0 in a 0-based file), got %ld", what, id);
    if (id != (long)k + *base)
        return eo_scan_error(s, EO_ERR_PARSE, "expected %s %ld (indices follow on), got %ld", what, (long)k + *base,
                             id);
    return EO_OK;
}

static int read_veg(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src)
{
    eo_scan sc, *s = &sc;
    eo_scan_init(s, ctx, file, text, len, '#');
    s->sep = ',';
    eo_mesh *m = NULL;
    int rc = EO_OK, have_tets = 0, vbase = 1;
    const char *t;
    size_t n;
    while (eo_scan_peek(s, &t, &n)) {
        if (t[0] != '*') {
            rc = eo_scan_fail(s, "a section keyword such as '*VERTICES' or '*ELEMENTS'");
            goto fail;
        }
        if (eo_scan_accept(s, "*VERTICES")) {
            int nv;
            if (m) {
                rc = eo_scan_error(s, EO_ERR_PARSE, "second *VERTICES section; expected one");
                goto fail;
            }
            if ((rc = eo_scan_eol(s, "*VERTICES")) < 0 ||
                (rc = count_line(s, "vertex count", "coordinates per vertex 3", 3, &nv)) < 0)
                goto fail;
            if ((rc = eo_mesh_create(ctx, nv, 0, &m)) < 0 || (rc = eo_mesh_src_alloc(ctx, src, nv, -1)) < 0) goto fail;
            for (int v = 0; v < nv; v++) {
                double *x = m->X + 3 * v;
                eo_scan_item(s, "vertex", v + vbase);
                src->v_line[v] = eo_scan_record(s);
                if ((rc = item_index(s, "vertex index", v, &vbase)) < 0) goto fail;
                eo_scan_item(s, "vertex", v + vbase);
                src->v_id[v] = v + vbase;
                if ((rc = eo_scan_double(s, "x coordinate", &x[0])) < 0 ||
                    (rc = eo_scan_double(s, "y coordinate", &x[1])) < 0 ||
                    (rc = eo_scan_double(s, "z coordinate", &x[2])) < 0 || (rc = eo_scan_eol(s, "i x y z")) < 0)
                    goto fail;
            }
            eo_scan_item(s, NULL, -1);
        } else if (eo_scan_accept(s, "*ELEMENTS")) {
            int nt, tbase = 1;
            if (!m) {
                rc = eo_scan_error(s, EO_ERR_PARSE, "*ELEMENTS before *VERTICES; expected *VERTICES first");
                goto fail;
            }
            if (have_tets) {
                rc = eo_scan_error(s, EO_ERR_PARSE, "second *ELEMENTS section; expected one");
                goto fail;
            }
            have_tets = 1;
            if ((rc = eo_scan_eol(s, "*ELEMENTS")) < 0) goto fail;
            eo_scan_record(s);
            if (!eo_scan_accept(s, "TET")) {
                if (eo_scan_peek(s, &t, &n) && n == 5 && memcmp(t, "CUBIC", 5) == 0)
                    rc = eo_scan_error(s, EO_ERR_UNSUPPORTED,
                                       "element type CUBIC (hexahedra) is not supported; expected TET");
                else rc = eo_scan_fail(s, "element type TET");
                goto fail;
            }
            if ((rc = eo_scan_eol(s, "element type TET")) < 0 ||
                (rc = count_line(s, "tet count", "vertices per tet 4", 4, &nt)) < 0)
                goto fail;
            eo_free(ctx, m->tets);
            m->tets = eo_malloc(ctx, (size_t)(nt ? nt : 1) * 4 * sizeof(int));
            if (!m->tets) {
                rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (%d tets)", nt);
                goto fail;
            }
            if ((rc = eo_mesh_src_alloc(ctx, src, -1, nt)) < 0) goto fail;
            for (int q = 0; q < nt; q++) {
                eo_scan_item(s, "tet", q + tbase);
                src->t_line[q] = eo_scan_record(s);
                if ((rc = item_index(s, "tet index", q, &tbase)) < 0) goto fail;
                eo_scan_item(s, "tet", q + tbase);
                src->t_id[q] = q + tbase;
                for (int a = 0; a < 4; a++) {
                    long v;
                    if ((rc = eo_scan_long(s, "vertex index", &v)) < 0) goto fail;
                    if (v < vbase || v >= (long)m->nv + vbase) {
                        rc = eo_scan_error(s, EO_ERR_MESH, "expected vertex index in [%d, %d], got %ld", vbase,
                                           m->nv - 1 + vbase, v);
                        goto fail;
                    }
                    m->tets[4 * q + a] = (int)(v - vbase);
                }
                if ((rc = eo_scan_eol(s, "j v1 v2 v3 v4")) < 0) goto fail;
            }
            m->nt = nt;
            eo_scan_item(s, NULL, -1);
        } else if (eo_scan_accept(s, "*INCLUDE")) {
            rc = eo_scan_error(s, EO_ERR_UNSUPPORTED,
                               "*INCLUDE is not supported: a .veg mesh is read from one file; inline the included file");
            goto fail;
        } else {
            /* *MATERIAL, *SET, *REGION, ...: skipped up to the next '*' line */
            eo_log(ctx, EO_LOG_INFO, "%s:%ld: veg: section %.*s ignored", file, s->line, (int)(n > 40 ? 40 : n), t);
            eo_scan_skip_line(s);
            while (eo_scan_peek(s, &t, &n) && t[0] != '*') eo_scan_skip_line(s);
        }
    }
    if (!m) {
        rc = eo_scan_error(s, EO_ERR_PARSE, "expected a *VERTICES section, got end of file");
        goto fail;
    }
    if (!have_tets) {
        rc = eo_scan_error(s, EO_ERR_MESH, "expected an *ELEMENTS section, got end of file");
        goto fail;
    }
    *out = m;
    return EO_OK;
fail:
    eo_mesh_destroy(&m);
    *out = NULL;
    return rc;
}

static const char *const veg_exts[] = {".veg", NULL};

const eo_mesh_io_type eo_mesh_io_veg = {
    .format = EO_MESH_VEG,
    .name = "veg",
    .exts = veg_exts,
    .read_text = read_veg,
};
