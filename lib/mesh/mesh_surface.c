/* Closed surface meshes (.obj, .off, .stl, .ply) read and tetrahedralized by TetGen.
 *
 * Formats (references: Wavefront OBJ, "Object Files" appendix B1 of the Advanced
 * Visualizer manual; Geomview OFF; 3D Systems "StereoLithography Interface
 * Specification" (1988); G. Turk, "The PLY Polygon File Format" (1994)):
 *   OBJ   "v x y z [w]" and "f i j k ..." (i, i/t, i//n or i/t/n; 1-based, negative =
 *         relative to the last vertex); every other record (vt, vn, g, o, s, usemtl,
 *         mtllib, l, ...) is ignored. Polygons are fan-triangulated.
 *   OFF   "OFF" (or COFF/NOFF/CNOFF), "nv nf ne", nv lines "x y z ...", nf lines
 *         "n i0 .. in-1 [colour]" (0-based). '#' comments.
 *   STL   ASCII ("solid", facets of "outer loop" with 3 "vertex x y z", "endsolid") or
 *         binary (80-byte header, uint32 count, 50 bytes per triangle: normal, 3
 *         vertices as float32 LE, uint16). Binary when the size is 84 + 50 n exactly.
 *   PLY   ascii or binary_little_endian 1.0; element "vertex" with properties x, y, z
 *         (any scalar type), element "face" with a list property vertex_indices (or
 *         vertex_index); other elements and properties are skipped.
 * Then: points with equal coordinates are merged (STL stores each triangle's corners),
 * points on no triangle are dropped (with a warning), triangles with a repeated point
 * are rejected, and the surface must be closed: every edge in an even number (>= 2) of
 * triangles. Errors name file:line (the triangle's line; binary: the byte offset).
 *
 * The closed surface is tetrahedralized by the TetGen library (mesh_tetgen_lib.cpp)
 * with switches "pzQ" + "q<quality>" (radius-edge ratio bound, when > 0) +
 * "a<max_volume>" (when > 0): a constrained Delaunay mesh of the enclosed volume whose
 * boundary lies on the input surface, so the total volume equals the enclosed one (to
 * rounding). Quality and volume bound come from eo_mesh_read_opts (scene keys
 * mesh.tetgen.quality, mesh.tetgen.max_volume). Without TetGen built, reading these
 * files fails with EO_ERR_UNSUPPORTED naming the meson option. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "eo_build_config.h"
#include "mesh_io.h"
#include "../textscan.h"

#if defined(EO_HAVE_TETGEN) && EO_HAVE_TETGEN && !defined(EO_NO_TETGEN)
#define USE_TETGEN 1
#else
#define USE_TETGEN 0
#endif

int eo_mesh_have_tetgen(void) { return USE_TETGEN; }

void eo_surface_deinit(eo_ctx *ctx, eo_surface *s)
{
    eo_free(ctx, s->X);
    eo_free(ctx, s->tri);
    eo_free(ctx, s->line);
    memset(s, 0, sizeof *s);
}

/* ---- building -------------------------------------------------------------------- */

typedef struct {
    eo_ctx *ctx;
    eo_surface *s;
    int pcap, tcap;
} builder;

static int add_point(builder *b, const double x[3])
{
    eo_surface *s = b->s;
    if (s->np == b->pcap) {
        int nc = b->pcap ? 2 * b->pcap : 256;
        if (nc > 200000000) return eo_error(b->ctx, EO_ERR_NOMEM, "too many points");
        double *q = eo_realloc(b->ctx, s->X, (size_t)nc * 3 * sizeof(double));
        if (!q) return eo_error(b->ctx, EO_ERR_NOMEM, "out of memory (%d surface points)", nc);
        s->X = q;
        b->pcap = nc;
    }
    memcpy(s->X + 3 * s->np, x, 3 * sizeof(double));
    s->np++;
    return EO_OK;
}

static int add_tri(builder *b, int i, int j, int k, long line)
{
    eo_surface *s = b->s;
    if (s->nt == b->tcap) {
        int nc = b->tcap ? 2 * b->tcap : 256;
        if (nc > 200000000) return eo_error(b->ctx, EO_ERR_NOMEM, "too many triangles");
        int *q = eo_realloc(b->ctx, s->tri, (size_t)nc * 3 * sizeof(int));
        if (q) s->tri = q;
        long *l = q ? eo_realloc(b->ctx, s->line, (size_t)nc * sizeof(long)) : NULL;
        if (l) s->line = l;
        if (!q || !l) return eo_error(b->ctx, EO_ERR_NOMEM, "out of memory (%d surface triangles)", nc);
        b->tcap = nc;
    }
    s->tri[3 * s->nt] = i;
    s->tri[3 * s->nt + 1] = j;
    s->tri[3 * s->nt + 2] = k;
    s->line[s->nt] = line;
    s->nt++;
    return EO_OK;
}

/* ---- OBJ --------------------------------------------------------------------------- */

static int parse_obj(builder *b, eo_scan *s)
{
    int rc, poly[64];
    for (;;) {
        const char *t;
        size_t n;
        long line = eo_scan_record(s);
        if (!eo_scan_peek(s, &t, &n)) {
            if (s->p >= s->end) break;
            eo_scan_skip_line(s);
            continue;
        }
        if (n == 1 && t[0] == 'v') {
            double x[3];
            s->p += n;
            eo_scan_item(s, "vertex", b->s->np + 1);
            for (int k = 0; k < 3; k++)
                if ((rc = eo_scan_double(s, "a vertex coordinate", &x[k])) < 0) return rc;
            eo_scan_item(s, NULL, -1);
            if ((rc = add_point(b, x)) < 0) return rc;
            eo_scan_skip_line(s);
        } else if (n == 1 && t[0] == 'f') {
            s->p += n;
            int k = 0;
            while (eo_scan_skip(s)) {
                const char *w;
                size_t wn;
                eo_scan_word(s, "a vertex index", &w, &wn);
                char *e;
                long v = strtol(w, &e, 10);
                if (e == w || (e < w + wn && *e != '/'))
                    return eo_scan_error(s, EO_ERR_PARSE, "expected a vertex index (i, i/t, i//n, i/t/n), got '%.*s'",
                                         (int)(wn > 40 ? 40 : wn), w);
                if (v < 0) v += (long)b->s->np + 1;
                if (v < 1 || v > b->s->np)
                    return eo_scan_error(s, EO_ERR_MESH, "expected a vertex index in [1, %d] (or negative), got '%.*s'",
                                         b->s->np, (int)(wn > 40 ? 40 : wn), w);
                if (k == 64) return eo_scan_error(s, EO_ERR_PARSE, "face with more than 64 vertices");
                poly[k++] = (int)v - 1;
            }
            if (k < 3) return eo_scan_error(s, EO_ERR_MESH, "expected a face of at least 3 vertices, got %d", k);
            for (int i = 1; i + 1 < k; i++)
                if ((rc = add_tri(b, poly[0], poly[i], poly[i + 1], line)) < 0) return rc;
            eo_scan_skip_line(s);
        } else {
            eo_scan_skip_line(s);
        }
    }
    return EO_OK;
}

/* ---- OFF --------------------------------------------------------------------------- */

static int parse_off(builder *b, eo_scan *s)
{
    const char *t;
    size_t n;
    int nv, nf, ne, rc;
    if (!eo_scan_peek(s, &t, &n) || n < 3 || n > 5 || memcmp(t + n - 3, "OFF", 3) != 0)
        return eo_scan_fail(s, "'OFF'");
    s->p += n;
    if ((rc = eo_scan_count(s, "vertex count", &nv)) < 0) return rc;
    if ((rc = eo_scan_count(s, "face count", &nf)) < 0) return rc;
    if ((rc = eo_scan_count(s, "edge count", &ne)) < 0) return rc;
    for (int v = 0; v < nv; v++) {
        double x[3];
        eo_scan_record(s);
        eo_scan_item(s, "vertex", v);
        for (int k = 0; k < 3; k++)
            if ((rc = eo_scan_double(s, "a vertex coordinate", &x[k])) < 0) return rc;
        if ((rc = add_point(b, x)) < 0) return rc;
        eo_scan_skip_line(s);
    }
    for (int f = 0; f < nf; f++) {
        int k, poly[64];
        long line = eo_scan_record(s);
        eo_scan_item(s, "face", f);
        if ((rc = eo_scan_int(s, "number of face vertices (3..64)", 3, 64, &k)) < 0) return rc;
        for (int i = 0; i < k; i++)
            if ((rc = eo_scan_int(s, "a vertex index", 0, nv - 1, &poly[i])) < 0) return rc;
        for (int i = 1; i + 1 < k; i++)
            if ((rc = add_tri(b, poly[0], poly[i], poly[i + 1], line)) < 0) return rc;
        eo_scan_skip_line(s);
    }
    eo_scan_item(s, NULL, -1);
    return EO_OK;
}

/* ---- STL --------------------------------------------------------------------------- */

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float lef32(const unsigned char *p)
{
    uint32_t u = le32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static int parse_stl(builder *b, eo_scan *s, const char *text, size_t len)
{
    int rc;
    if (len >= 84) {
        uint32_t n = le32((const unsigned char *)text + 80);
        if ((uint64_t)len == 84 + 50 * (uint64_t)n) {
            for (uint32_t f = 0; f < n; f++) {
                const unsigned char *p = (const unsigned char *)text + 84 + 50 * (size_t)f + 12;
                for (int c = 0; c < 3; c++) {
                    double x[3] = {lef32(p + 12 * c), lef32(p + 12 * c + 4), lef32(p + 12 * c + 8)};
                    if ((rc = add_point(b, x)) < 0) return rc;
                }
                /* binary: the "line" is the triangle's byte offset, negated */
                if ((rc = add_tri(b, b->s->np - 3, b->s->np - 2, b->s->np - 1, -(long)(84 + 50 * (size_t)f))) < 0)
                    return rc;
            }
            return EO_OK;
        }
    }
    if ((rc = eo_scan_expect(s, "solid")) < 0) {
        return eo_scan_error(s, EO_ERR_PARSE,
                             "expected an ASCII STL ('solid ...') or a binary STL of 84 + 50 n bytes (%zu bytes)", len);
    }
    eo_scan_skip_line(s);
    for (;;) {
        if (eo_scan_accept(s, "endsolid")) {
            eo_scan_skip_line(s);
            if (!eo_scan_skip(s)) break;
            if ((rc = eo_scan_expect(s, "solid")) < 0) return rc;
            eo_scan_skip_line(s);
            continue;
        }
        long line = s->line;
        if ((rc = eo_scan_expect(s, "facet")) < 0) return rc;
        double nrm[3];
        if ((rc = eo_scan_expect(s, "normal")) < 0) return rc;
        for (int k = 0; k < 3; k++)
            if ((rc = eo_scan_double(s, "a normal component", &nrm[k])) < 0) return rc;
        if ((rc = eo_scan_expect(s, "outer")) < 0 || (rc = eo_scan_expect(s, "loop")) < 0) return rc;
        for (int c = 0; c < 3; c++) {
            double x[3];
            if ((rc = eo_scan_expect(s, "vertex")) < 0) return rc;
            for (int k = 0; k < 3; k++)
                if ((rc = eo_scan_double(s, "a vertex coordinate", &x[k])) < 0) return rc;
            if ((rc = add_point(b, x)) < 0) return rc;
        }
        if ((rc = eo_scan_expect(s, "endloop")) < 0 || (rc = eo_scan_expect(s, "endfacet")) < 0) return rc;
        if ((rc = add_tri(b, b->s->np - 3, b->s->np - 2, b->s->np - 1, line)) < 0) return rc;
    }
    return EO_OK;
}

/* ---- PLY --------------------------------------------------------------------------- */

enum { PLY_MAXP = 32, PLY_MAXE = 16 };

typedef struct {
    int type;      /* scalar type index, see ply_types */
    int list;      /* 1: list, count type ctype */
    int ctype;
    int role;      /* 0 other, 1..3 x y z, 4 vertex_indices */
} ply_prop;

typedef struct {
    char name[32];
    long count;
    int np;
    ply_prop p[PLY_MAXP];
} ply_elem;

static const char *const ply_types[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double",
                                        "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64",
                                        NULL};
static const int ply_size[] = {1, 1, 2, 2, 4, 4, 4, 8, 1, 1, 2, 2, 4, 4, 4, 8};

static int ply_type(const char *t, size_t n)
{
    for (int i = 0; ply_types[i]; i++)
        if (strlen(ply_types[i]) == n && memcmp(ply_types[i], t, n) == 0) return i % 8;
    return -1;
}

static int tok_is(const char *t, size_t n, const char *w) { return strlen(w) == n && memcmp(t, w, n) == 0; }

/* one binary scalar at p (type < 8 after folding) */
static double ply_bin(const unsigned char *p, int type)
{
    switch (type) {
    case 0: return (double)(int8_t)p[0];
    case 1: return (double)p[0];
    case 2: return (double)(int16_t)(p[0] | p[1] << 8);
    case 3: return (double)(uint16_t)(p[0] | p[1] << 8);
    case 4: return (double)(int32_t)le32(p);
    case 5: return (double)le32(p);
    case 6: return (double)lef32(p);
    default: {
        uint64_t u = (uint64_t)le32(p) | (uint64_t)le32(p + 4) << 32;
        double d;
        memcpy(&d, &u, 8);
        return d;
    }
    }
}

static int parse_ply(builder *b, eo_scan *s, const char *text, size_t len)
{
    int rc, binary = 0, ne = 0;
    ply_elem el[PLY_MAXE];
    const char *t;
    size_t n;
    if ((rc = eo_scan_expect(s, "ply")) < 0) return rc;
    eo_scan_skip_line(s);
    for (;;) {
        eo_scan_record(s);
        if (!eo_scan_peek(s, &t, &n)) return eo_scan_fail(s, "'end_header'");
        if (eo_scan_accept(s, "end_header")) break;
        if (eo_scan_accept(s, "format")) {
            if (eo_scan_accept(s, "ascii")) binary = 0;
            else if (eo_scan_accept(s, "binary_little_endian")) binary = 1;
            else if (eo_scan_accept(s, "binary_big_endian"))
                return eo_scan_error(s, EO_ERR_UNSUPPORTED, "binary_big_endian PLY is not supported; expected ascii or binary_little_endian");
            else return eo_scan_fail(s, "ascii or binary_little_endian");
        } else if (eo_scan_accept(s, "element")) {
            if (ne == PLY_MAXE) return eo_scan_error(s, EO_ERR_UNSUPPORTED, "more than %d elements", PLY_MAXE);
            ply_elem *e = &el[ne++];
            memset(e, 0, sizeof *e);
            if ((rc = eo_scan_word(s, "an element name", &t, &n)) < 0) return rc;
            snprintf(e->name, sizeof e->name, "%.*s", (int)(n > 31 ? 31 : n), t);
            if ((rc = eo_scan_long(s, "an element count", &e->count)) < 0) return rc;
            if (e->count < 0 || e->count > (long)len)
                return eo_scan_error(s, EO_ERR_PARSE, "expected a plausible element count, got %ld", e->count);
        } else if (eo_scan_accept(s, "property")) {
            if (!ne) return eo_scan_error(s, EO_ERR_PARSE, "property before any element");
            ply_elem *e = &el[ne - 1];
            if (e->np == PLY_MAXP) return eo_scan_error(s, EO_ERR_UNSUPPORTED, "more than %d properties", PLY_MAXP);
            ply_prop *p = &e->p[e->np++];
            memset(p, 0, sizeof *p);
            if (eo_scan_accept(s, "list")) {
                p->list = 1;
                if ((rc = eo_scan_word(s, "a list count type", &t, &n)) < 0) return rc;
                if ((p->ctype = ply_type(t, n)) < 0 || p->ctype >= 6)
                    return eo_scan_error(s, EO_ERR_PARSE, "expected an integer list count type, got '%.*s'", (int)(n > 20 ? 20 : n), t);
            }
            if ((rc = eo_scan_word(s, "a property type", &t, &n)) < 0) return rc;
            if ((p->type = ply_type(t, n)) < 0)
                return eo_scan_error(s, EO_ERR_PARSE, "expected a PLY type (char .. double), got '%.*s'", (int)(n > 20 ? 20 : n), t);
            if ((rc = eo_scan_word(s, "a property name", &t, &n)) < 0) return rc;
            int isv = strcmp(e->name, "vertex") == 0, isf = strcmp(e->name, "face") == 0;
            if (isv && !p->list && n == 1 && t[0] >= 'x' && t[0] <= 'z') p->role = 1 + (t[0] - 'x');
            if (isf && p->list && (tok_is(t, n, "vertex_indices") || tok_is(t, n, "vertex_index"))) {
                if (p->type >= 6) return eo_scan_error(s, EO_ERR_PARSE, "expected integer vertex indices");
                p->role = 4;
            }
        }
        eo_scan_skip_line(s);
    }
    /* data starts after the end_header line */
    eo_scan_skip_line(s);
    const char *p = s->p;
    const unsigned char *q = (const unsigned char *)p, *qend = (const unsigned char *)text + len;
    int base_np = b->s->np;
    for (int ei = 0; ei < ne; ei++) {
        ply_elem *e = &el[ei];
        int isv = strcmp(e->name, "vertex") == 0, isf = strcmp(e->name, "face") == 0;
        for (long i = 0; i < e->count; i++) {
            double x[3] = {0, 0, 0};
            int poly[64], k = 0;
            long line = binary ? -(long)((const char *)q - text) : eo_scan_record(s);
            if (!binary) eo_scan_item(s, e->name, i);
            for (int pi = 0; pi < e->np; pi++) {
                ply_prop *pp = &e->p[pi];
                long cnt = 1;
                double v;
                if (pp->list) {
                    if (binary) {
                        if (q + ply_size[pp->ctype] > qend) goto truncated;
                        cnt = (long)ply_bin(q, pp->ctype);
                        q += ply_size[pp->ctype];
                    } else if ((rc = eo_scan_long(s, "a list count", &cnt)) < 0) {
                        return rc;
                    }
                    if (cnt < 0 || (pp->role == 4 && (cnt < 3 || cnt > 64)))
                        return eo_error_at(b->ctx, EO_ERR_PARSE, EO_ERRLOC_ITEM(s->file, line, e->name, i),
                                           "expected a list count%s, got %ld", pp->role == 4 ? " in [3, 64]" : " >= 0", cnt);
                }
                for (long c = 0; c < cnt; c++) {
                    if (binary) {
                        if (q + ply_size[pp->type] > qend) goto truncated;
                        v = ply_bin(q, pp->type);
                        q += ply_size[pp->type];
                    } else if ((rc = eo_scan_double(s, "a property value", &v)) < 0) {
                        return rc;
                    }
                    if (pp->role >= 1 && pp->role <= 3) x[pp->role - 1] = v;
                    if (pp->role == 4) {
                        if (!(v >= 0 && v < (double)e->count + 1e9) || v != floor(v) || v >= 2147483647.0)
                            return eo_error_at(b->ctx, EO_ERR_MESH, EO_ERRLOC_ITEM(s->file, line, e->name, i),
                                               "expected a vertex index >= 0, got %g", v);
                        poly[k++] = base_np + (int)v;
                    }
                }
            }
            if (!binary) {
                if ((rc = eo_scan_eol(s, "the element's properties (header says so)")) < 0) return rc;
                eo_scan_item(s, NULL, -1);
            }
            if (isv && (rc = add_point(b, x)) < 0) return rc;
            if (isf)
                for (int j = 1; j + 1 < k; j++)
                    if ((rc = add_tri(b, poly[0], poly[j], poly[j + 1], line)) < 0) return rc;
        }
    }
    for (int f = 0; f < b->s->nt; f++)
        for (int a = 0; a < 3; a++)
            if (b->s->tri[3 * f + a] >= b->s->np) {
                long l = b->s->line[f];
                return eo_error_at(b->ctx, EO_ERR_MESH, EO_ERRLOC_FILE(s->file, l > 0 ? l : -1),
                                   "face %d: vertex index %d out of range [0, %d)%s", f, b->s->tri[3 * f + a] - base_np,
                                   b->s->np - base_np, l < 0 ? " (binary face)" : "");
            }
    return EO_OK;
truncated:
    return eo_error_at(b->ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(s->file, -1),
                       "binary data ends early (at byte %zu of %zu); expected the elements the header announces",
                       (size_t)((const char *)q - text), len);
}

/* ---- checks ------------------------------------------------------------------------ */

typedef struct {
    double x[3];
    int i;
} pkey;

static int cmp_point(const void *a, const void *b)
{
    const pkey *p = a, *q = b;
    for (int k = 0; k < 3; k++)
        if (p->x[k] != q->x[k]) return p->x[k] < q->x[k] ? -1 : 1;
    return (p->i > q->i) - (p->i < q->i);
}

typedef struct {
    int a, b, f;
} edge;

static int cmp_edge(const void *p, const void *q)
{
    const edge *x = p, *y = q;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    if (x->b != y->b) return x->b < y->b ? -1 : 1;
    return (x->f > y->f) - (x->f < y->f);
}

static eo_errloc tri_loc(const eo_surface *s, const char *file, int f)
{
    long l = s->line ? s->line[f] : -1;
    return EO_ERRLOC_ITEM(file, l > 0 ? l : -1, "triangle", f + 1);
}

/* merge equal points, drop unused ones, reject degenerate triangles, check closedness */
static int clean_surface(eo_ctx *ctx, eo_surface *s, const char *file)
{
    int rc = EO_OK;
    pkey *ord = NULL;
    int *map = NULL;
    edge *e = NULL;
    if (s->nt < 4 || s->np < 4)
        return eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_FILE(file, -1),
                           "%d points and %d triangles; expected a closed surface (at least 4 of each)", s->np, s->nt);
    for (int i = 0; i < 3 * s->np; i++)
        if (!isfinite(s->X[i]))
            return eo_error_at(ctx, EO_ERR_NONFINITE, EO_ERRLOC_ITEM(file, -1, "point", i / 3 + 1),
                               "expected finite coordinates, got %g", s->X[i]);
    ord = eo_malloc(ctx, (size_t)s->np * sizeof *ord);
    map = eo_malloc(ctx, (size_t)s->np * sizeof(int));
    e = eo_malloc(ctx, 3 * (size_t)s->nt * sizeof(edge));
    if (!ord || !map || !e) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (surface checks)");
        goto done;
    }
    for (int i = 0; i < s->np; i++) {
        memcpy(ord[i].x, s->X + 3 * i, sizeof ord[i].x);
        ord[i].i = i;
    }
    qsort(ord, (size_t)s->np, sizeof *ord, cmp_point);
    for (int i = 0; i < s->np; i++) /* each point -> the first of its run of equal points */
        map[ord[i].i] = i > 0 && memcmp(ord[i].x, ord[i - 1].x, sizeof ord[i].x) == 0 ? map[ord[i - 1].i] : ord[i].i;
    for (int i = 0; i < 3 * s->nt; i++) s->tri[i] = map[s->tri[i]];
    /* used points (merged duplicates are unused now), renumbered in their order */
    int nmerged = 0;
    for (int i = 0; i < s->np; i++) nmerged += map[i] != i;
    for (int i = 0; i < s->np; i++) map[i] = -1;
    for (int i = 0; i < 3 * s->nt; i++) map[s->tri[i]] = 0;
    int n = 0, unused = -nmerged;
    for (int i = 0; i < s->np; i++) {
        if (map[i] < 0) {
            unused++;
            continue;
        }
        map[i] = n;
        if (n != i) memcpy(s->X + 3 * n, s->X + 3 * i, 3 * sizeof(double));
        n++;
    }
    s->np = n;
    for (int i = 0; i < 3 * s->nt; i++) s->tri[i] = map[s->tri[i]];
    if (s->np < 4) { /* e.g. a triangle listed twice, or corners that are all the same few points */
        rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_FILE(file, -1),
                         "%d distinct points on the triangles (after merging equal points); expected a closed "
                         "surface (at least 4)", s->np);
        goto done;
    }
    for (int f = 0; f < s->nt; f++) {
        const int *t = s->tri + 3 * f;
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            rc = eo_error_at(ctx, EO_ERR_MESH, tri_loc(s, file, f),
                             "degenerate: two corners are the same point; expected 3 distinct points");
            goto done;
        }
        for (int k = 0; k < 3; k++) {
            int a = t[k], b = t[(k + 1) % 3];
            e[3 * f + k] = (edge){a < b ? a : b, a < b ? b : a, f};
        }
    }
    qsort(e, 3 * (size_t)s->nt, sizeof(edge), cmp_edge);
    for (size_t i = 0, j; i < 3 * (size_t)s->nt; i = j) {
        for (j = i + 1; j < 3 * (size_t)s->nt && e[j].a == e[i].a && e[j].b == e[i].b; j++) {}
        if ((j - i) % 2) {
            rc = eo_error_at(ctx, EO_ERR_MESH, tri_loc(s, file, e[i].f),
                             "the surface is not closed: the edge between points (%g, %g, %g) and (%g, %g, %g) "
                             "belongs to %zu triangle(s); expected a closed surface (every edge in 2)",
                             s->X[3 * e[i].a], s->X[3 * e[i].a + 1], s->X[3 * e[i].a + 2], s->X[3 * e[i].b],
                             s->X[3 * e[i].b + 1], s->X[3 * e[i].b + 2], j - i);
            goto done;
        }
    }
    if (unused) eo_log(ctx, EO_LOG_WARN, "%s: dropped %d points on no triangle", file, unused);
done:
    eo_free(ctx, ord);
    eo_free(ctx, map);
    eo_free(ctx, e);
    return rc;
}

int eo_surface_parse(eo_ctx *ctx, eo_mesh_format fmt, const char *text, size_t len, const char *file, eo_surface *s)
{
    memset(s, 0, sizeof *s);
    builder b = {.ctx = ctx, .s = s};
    eo_scan sc;
    eo_scan_init(&sc, ctx, file, text, len, fmt == EO_MESH_STL || fmt == EO_MESH_PLY ? 0 : '#');
    int rc;
    switch (fmt) {
    case EO_MESH_OBJ: rc = parse_obj(&b, &sc); break;
    case EO_MESH_OFF: rc = parse_off(&b, &sc); break;
    case EO_MESH_STL: rc = parse_stl(&b, &sc, text, len); break;
    case EO_MESH_PLY: rc = parse_ply(&b, &sc, text, len); break;
    default: rc = eo_error(ctx, EO_ERR_INVALID, "%s: not a surface format", file);
    }
    if (rc >= 0) rc = clean_surface(ctx, s, file);
    if (rc < 0) eo_surface_deinit(ctx, s);
    return rc;
}

/* ---- tetrahedralization -------------------------------------------------------------- */

int eo_tetgen_tetrahedralize(eo_ctx *ctx, const eo_surface *s, double quality, double max_volume, const char *file,
                             eo_mesh **out)
{
    *out = NULL;
    if (!(quality == 0 || quality >= 1.0) || !isfinite(quality))
        return eo_error_at(ctx, EO_ERR_RANGE, EO_ERRLOC_FILE(file, -1),
                           "TetGen quality (radius-edge ratio bound) must be 0 (none) or >= 1, got %g", quality);
    if (!(max_volume >= 0) || !isfinite(max_volume))
        return eo_error_at(ctx, EO_ERR_RANGE, EO_ERRLOC_FILE(file, -1),
                           "TetGen max_volume must be >= 0 (0 = none), got %g", max_volume);
#if USE_TETGEN
    char sw[128], msg[256];
    int k = snprintf(sw, sizeof sw, "pzQ");
    if (quality > 0) k += snprintf(sw + k, sizeof sw - (size_t)k, "q%.9g", quality);
    if (max_volume > 0) snprintf(sw + k, sizeof sw - (size_t)k, "a%.9g", max_volume);
    double *X = NULL;
    int *tets = NULL, np = 0, nt = 0;
    int code = eo_tetgen_run(s->X, s->np, s->tri, s->nt, sw, &X, &np, &tets, &nt, msg, sizeof msg);
    if (code != 0) {
        free(X);
        free(tets);
        const char *why = code == 1    ? "out of memory"
                          : code == 2  ? "internal error"
                          : code == 3  ? "the surface intersects itself"
                          : code == 4  ? "a very small input feature (near-coincident points or edges)"
                          : code == 5  ? "two very close input facets"
                          : code == 10 ? "invalid input surface"
                                       : msg;
        return eo_error_at(ctx, code == 1 ? EO_ERR_NOMEM : EO_ERR_MESH, EO_ERRLOC_FILE(file, -1),
                           "TetGen (switches -%s) failed: %s (%s); expected a closed, non-self-intersecting surface",
                           sw, why, msg);
    }
    int rc = eo_mesh_create(ctx, np, nt, out);
    if (rc >= 0) {
        memcpy((*out)->X, X, 3 * (size_t)np * sizeof(double));
        memcpy((*out)->tets, tets, 4 * (size_t)nt * sizeof(int));
    }
    free(X);
    free(tets);
    return rc;
#else
    (void)s;
    return eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_FILE(file, -1),
                       "surface meshes (.obj, .off, .stl, .ply) are tetrahedralized by the TetGen library, which this "
                       "build lacks: install libtet1.5-dev and configure with meson -Dtetgen=enabled");
#endif
}

/* ---- format tables -------------------------------------------------------------------- */

static int read_surface(eo_ctx *ctx, eo_mesh_format fmt, const char *text, size_t len, const char *file,
                        eo_mesh **out, eo_mesh_src *src)
{
    eo_surface s;
    *out = NULL;
    eo_mesh_read_opts def = eo_mesh_read_opts_default();
    const eo_mesh_read_opts *o = src && src->opts ? src->opts : &def;
    int rc = eo_surface_parse(ctx, fmt, text, len, file, &s);
    if (rc < 0) return rc;
    rc = eo_tetgen_tetrahedralize(ctx, &s, o->tetgen_quality, o->tetgen_max_volume, file, out);
    eo_surface_deinit(ctx, &s);
    return rc;
}

int eo_obj_read_text(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src)
{
    return read_surface(ctx, EO_MESH_OBJ, text, len, file, out, src);
}
static int read_off(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src)
{
    return read_surface(ctx, EO_MESH_OFF, text, len, file, out, src);
}
static int read_stl(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src)
{
    return read_surface(ctx, EO_MESH_STL, text, len, file, out, src);
}
static int read_ply(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src)
{
    return read_surface(ctx, EO_MESH_PLY, text, len, file, out, src);
}

static const char *const off_exts[] = {".off", NULL};
static const char *const stl_exts[] = {".stl", NULL};
static const char *const ply_exts[] = {".ply", NULL};

const eo_mesh_io_type eo_mesh_io_off = {.format = EO_MESH_OFF, .name = "off", .exts = off_exts, .read_text = read_off};
const eo_mesh_io_type eo_mesh_io_stl = {.format = EO_MESH_STL, .name = "stl", .exts = stl_exts, .read_text = read_stl};
const eo_mesh_io_type eo_mesh_io_ply = {.format = EO_MESH_PLY, .name = "ply", .exts = ply_exts, .read_text = read_ply};
