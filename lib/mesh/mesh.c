/* Tetrahedral meshes: storage, format dispatch, validation, statistics, boundary.
 *
 * Signed volume of tet (x0, x1, x2, x3):  V = det[x1-x0, x2-x0, x3-x0] / 6, positive
 * when x3 lies on the side of triangle (x0, x1, x2) its right-hand normal points to.
 * Quality is the normalized radius ratio q = 3 r / R (r inradius = 3V / sum of face
 * areas, R circumradius); q = 1 for a regular tet, -> 0 for a sliver.
 *
 * Validation order (eo_mesh_validate): finite coordinates; indices in range; negative
 * tets reoriented (swap vertices 1 and 2); zero-volume tets (|V| <= min_rel_volume *
 * mean |V|); duplicate tets (same vertex set); unreferenced vertices. The last three are
 * errors, or dropped with a warning (EO_WARN_DROPPED) when the options allow it.
 * Order-2 meshes (tet10) first get their structure checked: tet10's corners equal tets,
 * midside nodes in range and never a corner of any tet, one midside node per edge and one
 * edge per midside node (edges found by sorting the 6·nt (min, max) corner pairs), tri_mid
 * in range. Orientation and volume use the corners; reorienting a tet (corners 1 <-> 2)
 * permutes its midside nodes with it (edge 01 <-> 20, 13 <-> 23; 12 and 03 stay); dropped
 * tets drop their tet10 rows; midside nodes (tet10, tri_mid) count as referenced and are
 * renumbered with the rest. Last, tri_mid is filled from the tets' edges when a reader
 * left it empty (a triangle edge that is no tet's edge is an error). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "elastopt/io.h"
#include "elastopt/mesh.h"
#include "elastopt/suggest.h"
#include "mesh_io.h"

static const eo_mesh_io_type *const formats[] = {
    &eo_mesh_io_tetgen, &eo_mesh_io_medit, &eo_mesh_io_gmsh, &eo_mesh_io_vtu, &eo_mesh_io_obj,
    &eo_mesh_io_off, &eo_mesh_io_stl, &eo_mesh_io_ply, &eo_mesh_io_veg, NULL,
};

eo_mesh_read_opts eo_mesh_read_opts_default(void)
{
    return (eo_mesh_read_opts){.format = EO_MESH_AUTO, .drop_degenerate = 0, .drop_unreferenced = 0,
                               .min_rel_volume = 1e-12, .tetgen_quality = 2.0, .tetgen_max_volume = 0};
}

eo_mesh_gen_opts eo_mesh_gen_opts_default(void)
{
    return (eo_mesh_gen_opts){.size = {1, 1, 1}, .origin = {0, 0, 0}, .cells = {4, 4, 4}, .split = 6};
}

int eo_mesh_create(eo_ctx *ctx, int nv, int nt, eo_mesh **out)
{
    *out = NULL;
    if (nv < 0 || nt < 0) return eo_error(ctx, EO_ERR_INVALID, "negative mesh size %d, %d", nv, nt);
    eo_mesh *m = eo_calloc(ctx, 1, sizeof *m);
    if (m) m->ctx = ctx, m->order = 1;
    if (!m) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (mesh)");
    m->nv = nv;
    m->nt = nt;
    m->X = eo_malloc(ctx, (size_t)(nv ? nv : 1) * 3 * sizeof(double));
    m->tets = eo_malloc(ctx, (size_t)(nt ? nt : 1) * 4 * sizeof(int));
    if (!m->X || !m->tets) {
        eo_mesh_destroy(&m);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (mesh of %d vertices, %d tets)", nv, nt);
    }
    *out = m;
    return EO_OK;
}

void eo_mesh_destroy(eo_mesh **pm)
{
    eo_ctx *ctx = pm && *pm ? (*pm)->ctx : NULL;
    if (!pm || !*pm) return;
    eo_mesh *m = *pm;
    eo_free(ctx, m->X);
    eo_free(ctx, m->tets);
    eo_free(ctx, m->tet_attr);
    eo_free(ctx, m->vmarker);
    eo_free(ctx, m->tris);
    eo_free(ctx, m->tri_tag);
    eo_free(ctx, m->tet10);
    eo_free(ctx, m->tri_mid);
    eo_free(ctx, m);
    *pm = NULL;
}

int eo_mesh_src_alloc(eo_ctx *ctx, eo_mesh_src *src, int nv, int nt)
{
    int bad = 0;
    if (nv >= 0) {
        size_t v = (size_t)(nv ? nv : 1);
        src->v_line = eo_malloc(ctx, v * sizeof(long));
        src->v_id = eo_malloc(ctx, v * sizeof(long));
        bad |= !src->v_line || !src->v_id;
    }
    if (nt >= 0) {
        size_t t = (size_t)(nt ? nt : 1);
        src->t_line = eo_malloc(ctx, t * sizeof(long));
        src->t_id = eo_malloc(ctx, t * sizeof(long));
        bad |= !src->t_line || !src->t_id;
    }
    return bad ? eo_error(ctx, EO_ERR_NOMEM, "out of memory (source lines)") : EO_OK;
}

void eo_mesh_src_free(eo_ctx *ctx, eo_mesh_src *src)
{
    eo_free(ctx, src->v_line);
    eo_free(ctx, src->v_id);
    eo_free(ctx, src->t_line);
    eo_free(ctx, src->t_id);
    eo_free(ctx, src->owned);
    eo_free(ctx, src->f_line);
    src->f_line = NULL;
    src->v_line = src->v_id = src->t_line = src->t_id = NULL;
    src->owned = NULL;
}

int eo_mesh_add_tri(eo_ctx *ctx, eo_mesh *m, eo_mesh_src *src, int *cap, const int v[3], int tag, long line)
{
    if (m->ntri == *cap) {
        int nc = *cap ? 2 * *cap : 64;
        int *t = eo_realloc(ctx, m->tris, (size_t)nc * 3 * sizeof(int));
        if (t) m->tris = t;
        int *g = t ? eo_realloc(ctx, m->tri_tag, (size_t)nc * sizeof(int)) : NULL;
        if (g) m->tri_tag = g;
        long *l = g && src ? eo_realloc(ctx, src->f_line, (size_t)nc * sizeof(long)) : NULL;
        if (l) src->f_line = l;
        if (!t || !g || (src && !l)) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (%d triangles)", nc);
        *cap = nc;
    }
    memcpy(m->tris + 3 * m->ntri, v, 3 * sizeof(int));
    m->tri_tag[m->ntri] = tag;
    if (src) src->f_line[m->ntri] = line;
    m->ntri++;
    return EO_OK;
}

/* ---- formats ----------------------------------------------------------------------- */

static int ends_with(const char *s, const char *suf)
{
    size_t n = strlen(s), k = strlen(suf);
    if (k > n) return 0;
    for (size_t i = 0; i < k; i++) {
        char a = s[n - k + i], b = suf[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (a != b) return 0;
    }
    return 1;
}

static const eo_mesh_io_type *find_by_path(const char *path)
{
    for (const eo_mesh_io_type *const *f = formats; *f; f++)
        for (const char *const *e = (*f)->exts; *e; e++)
            if (ends_with(path, *e)) return *f;
    return NULL;
}

static const eo_mesh_io_type *find_by_format(eo_mesh_format fmt)
{
    for (const eo_mesh_io_type *const *f = formats; *f; f++)
        if ((*f)->format == fmt) return *f;
    return NULL;
}

eo_mesh_format eo_mesh_format_from_path(const char *path)
{
    const eo_mesh_io_type *t = find_by_path(path);
    return t ? t->format : EO_MESH_AUTO;
}

const char *eo_mesh_format_name(eo_mesh_format fmt)
{
    const eo_mesh_io_type *t = find_by_format(fmt);
    return t ? t->name : "auto";
}

static void list_exts(char *buf, size_t n, int readable)
{
    size_t k = 0;
    buf[0] = 0;
    for (const eo_mesh_io_type *const *f = formats; *f; f++) {
        if (readable && !(*f)->read_text && !(*f)->read_path) continue;
        for (const char *const *e = (*f)->exts; *e && k < n; e++)
            k += (size_t)snprintf(buf + k, n - k, "%s%s", k ? ", " : "", *e);
    }
}

static const eo_mesh_io_type *pick(eo_ctx *ctx, const char *path, eo_mesh_format fmt, int reading, int *rc)
{
    const eo_mesh_io_type *t = fmt == EO_MESH_AUTO ? find_by_path(path) : find_by_format(fmt);
    char exts[256];
    if (!t) {
        char hint[96] = "";
        list_exts(exts, sizeof exts, reading);
        const char *dot = strrchr(path, '.');
        if (dot && !strchr(dot, '/')) eo_suggest_hint(dot, exts, NULL, hint, sizeof hint);
        *rc = eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_FILE(path, -1),
                          "unknown mesh format%s; expected a file name ending in one of: %s", hint, exts);
        return NULL;
    }
    if (!reading && !t->write) {
        *rc = eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_FILE(path, -1),
                          "%s files can be read, not written; expected .node, .ele, .mesh, .msh, .vtu or .obj",
                          t->name);
        return NULL;
    }
    if (reading && !t->read_text && !t->read_path) {
        list_exts(exts, sizeof exts, 1);
        *rc = eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_FILE(path, -1),
                          "%s files can be written, not read; expected one of: %s", t->name, exts);
        return NULL;
    }
    return t;
}

static int finish_read(eo_ctx *ctx, int rc, eo_mesh **m, const eo_mesh_read_opts *opts, eo_mesh_src *src,
                       eo_mesh **out)
{
    eo_mesh_read_opts def = eo_mesh_read_opts_default();
    if (!opts) opts = &def;
    if (rc >= 0) rc = eo_mesh_validate_src(ctx, *m, opts, src);
    eo_mesh_src_free(ctx, src);
    if (rc < 0) {
        eo_mesh_destroy(m);
        return rc;
    }
    *out = *m;
    return rc;
}

/* A TetGen base name "a" given without extension: does "a.node" exist? */
static int base_has_node(const char *path)
{
    char buf[4096];
    struct stat st;
    if (snprintf(buf, sizeof buf, "%s.node", path) >= (int)sizeof buf) return 0;
    return stat(buf, &st) == 0; /* not fopen: a FIFO would block; eo_path_check reports the rest */
}

int eo_mesh_read(eo_ctx *ctx, const char *path, const eo_mesh_read_opts *opts, eo_mesh **out)
{
    void *user = NULL;
    eo_mesh_source_fn source = eo_ctx_mesh_source(ctx, &user);
    if (source) {
        *out = NULL;
        int rc = source(ctx, path, opts, out, user);
        if (rc < 0) eo_mesh_destroy(out);
        return rc;
    }
    return eo_mesh_read_file(ctx, path, opts, out);
}

int eo_mesh_read_file(eo_ctx *ctx, const char *path, const eo_mesh_read_opts *opts, eo_mesh **out)
{
    *out = NULL;
    int rc = EO_OK;
    eo_mesh_format fmt = opts ? opts->format : EO_MESH_AUTO;
    if (fmt == EO_MESH_AUTO && !find_by_path(path) && base_has_node(path)) fmt = EO_MESH_TETGEN;
    const eo_mesh_io_type *t = pick(ctx, path, fmt, 1, &rc);
    if (!t) return rc;
    eo_mesh *m = NULL;
    eo_mesh_src src = {.opts = opts};
    if (t->read_path) {
        rc = t->read_path(ctx, path, &m, &src);
    } else {
        char *text = NULL;
        size_t len = 0;
        rc = eo_path_check(ctx, path, EO_PATH_READ);
        if (rc >= 0) rc = eo_read_file(ctx, path, &text, &len);
        src.vert_file = src.tet_file = path;
        if (rc >= 0) rc = t->read_text(ctx, text, len, path, &m, &src);
        eo_free(ctx, text);
    }
    return finish_read(ctx, rc, &m, opts, &src, out);
}

int eo_mesh_read_buffer(eo_ctx *ctx, const char *text, size_t len, eo_mesh_format fmt, const char *name,
                        const eo_mesh_read_opts *opts, eo_mesh **out)
{
    *out = NULL;
    const eo_mesh_io_type *t = find_by_format(fmt);
    if (!t || (!t->read_text && fmt != EO_MESH_TETGEN))
        return eo_error(ctx, EO_ERR_INVALID, "%s: cannot read format '%s' from memory", name,
                        eo_mesh_format_name(fmt));
    char *buf = eo_malloc(ctx, len + 1);
    if (!buf) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    memcpy(buf, text, len);
    buf[len] = 0;
    eo_mesh *m = NULL;
    eo_mesh_src src = {.opts = opts};
    int rc;
    char *names = NULL;
    if (fmt == EO_MESH_TETGEN) {
        size_t n = strlen(buf), k = strlen(name) + 8;
        names = eo_malloc(ctx, 3 * k);
        if (!names) {
            eo_free(ctx, buf);
            return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        }
        snprintf(names, k, "%s.node", name);
        snprintf(names + k, k, "%s.ele", name);
        snprintf(names + 2 * k, k, "%s.face", name);
        src.vert_file = names;
        src.tet_file = names + k;
        const char *ele = n < len ? buf + n + 1 : buf + len;
        size_t ne = strlen(ele);
        const char *face = ele + ne < buf + len ? ele + ne + 1 : NULL;
        rc = eo_tetgen_read_texts(ctx, buf, n, names, ele, ne, names + k, &m, &src);
        if (rc >= 0 && face) {
            src.tri_file = names + 2 * k;
            rc = eo_tetgen_read_face(ctx, face, (size_t)(buf + len - face), names + 2 * k, m, &src);
        }
    } else {
        src.vert_file = src.tet_file = name;
        rc = t->read_text(ctx, buf, len, name, &m, &src);
    }
    rc = finish_read(ctx, rc, &m, opts, &src, out);
    eo_free(ctx, names);
    eo_free(ctx, buf);
    return rc;
}

int eo_mesh_write(eo_ctx *ctx, const eo_mesh *m, const char *path, eo_mesh_format fmt)
{
    int rc = EO_OK;
    const eo_mesh_io_type *t = pick(ctx, path, fmt, 0, &rc);
    if (!t) return rc;
    if (t->format != EO_MESH_TETGEN && (rc = eo_path_check(ctx, path, EO_PATH_WRITE)) < 0) return rc;
    return t->write(ctx, m, path);
}

/* ---- generator spec ----------------------------------------------------------------- */

static int parse_triple(const char **p, double v[3], int integer)
{
    for (int i = 0; i < 3; i++) {
        char *e;
        if (integer) {
            long x = strtol(*p, &e, 10);
            if (e == *p || x < 1 || x > 100000) return -1;
            v[i] = (double)x;
        } else {
            double x = strtod(*p, &e);
            if (e == *p || !(x > 0) || !isfinite(x)) return -1;
            v[i] = x;
        }
        *p = e;
        if (i < 2) {
            if (**p != ',') return -1;
            (*p)++;
        }
    }
    return 0;
}

int eo_mesh_gen_opts_parse(eo_ctx *ctx, const char *spec, eo_mesh_gen_opts *o)
{
    *o = eo_mesh_gen_opts_default();
    const char *p = spec;
    double size[3], cells[3];
    if (strncmp(p, "gen:", 4) != 0) goto bad;
    p += 4;
    if (parse_triple(&p, size, 0) < 0 || *p != ':') goto bad;
    p++;
    if (parse_triple(&p, cells, 1) < 0) goto bad;
    if (*p == ':') {
        p++;
        if ((p[0] != '5' && p[0] != '6') || p[1]) goto bad;
        o->split = p[0] - '0';
        p++;
    }
    if (*p) goto bad;
    for (int i = 0; i < 3; i++) {
        o->size[i] = size[i];
        o->cells[i] = (int)cells[i];
    }
    return EO_OK;
bad:
    return eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(spec, -1),
                       "expected gen:SX,SY,SZ:NX,NY,NZ[:5|6] (sizes > 0, 1 <= cells <= 100000), got '%s'",
                       p);
}

int eo_mesh_load(eo_ctx *ctx, const char *source, const eo_mesh_read_opts *opts, eo_mesh **out)
{
    *out = NULL;
    if (strncmp(source, "gen:", 4) == 0) {
        eo_mesh_gen_opts g;
        int rc = eo_mesh_gen_opts_parse(ctx, source, &g);
        if (rc < 0) return rc;
        return eo_mesh_generate_box(ctx, &g, out);
    }
    return eo_mesh_read(ctx, source, opts, out);
}

/* ---- geometry ----------------------------------------------------------------------- */

double eo_tet_volume(const double *x, const int *t)
{
    const double *a = x + 3 * t[0], *b = x + 3 * t[1], *c = x + 3 * t[2], *d = x + 3 * t[3];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
            u[2] * (v[0] * w[1] - v[1] * w[0])) /
           6.0;
}

/* Neumaier's compensated sum: the total volume of a 10^6-tet mesh stays exact to ~1 ulp. */
typedef struct {
    double s, c;
} ksum;
static void ksum_add(ksum *k, double x)
{
    double t = k->s + x;
    k->c += fabs(k->s) >= fabs(x) ? (k->s - t) + x : (x - t) + k->s;
    k->s = t;
}

double eo_mesh_volume(const eo_mesh *m)
{
    ksum k = {0, 0};
    for (int t = 0; t < m->nt; t++) ksum_add(&k, eo_tet_volume(m->X, m->tets + 4 * t));
    return k.s + k.c;
}

static void cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}
static double norm3(const double *a) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

static double tet_quality(const double *X, const int *t)
{
    const double *p[4] = {X + 3 * t[0], X + 3 * t[1], X + 3 * t[2], X + 3 * t[3]};
    double a[3], b[3], c[3];
    for (int i = 0; i < 3; i++) {
        a[i] = p[1][i] - p[0][i];
        b[i] = p[2][i] - p[0][i];
        c[i] = p[3][i] - p[0][i];
    }
    double bc[3], ca[3], ab[3];
    cross(b, c, bc);
    cross(c, a, ca);
    cross(a, b, ab);
    double six_v = a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2];
    if (six_v <= 0) return 0;
    double a2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    double b2 = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
    double c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    double num[3];
    for (int i = 0; i < 3; i++) num[i] = a2 * bc[i] + b2 * ca[i] + c2 * ab[i];
    double R = norm3(num) / (2 * six_v);
    /* face areas: |ab|/2, |bc|/2, |ca|/2 and the face opposite p0 */
    double e1[3], e2[3], n[3];
    for (int i = 0; i < 3; i++) {
        e1[i] = p[2][i] - p[1][i];
        e2[i] = p[3][i] - p[1][i];
    }
    cross(e1, e2, n);
    double area = 0.5 * (norm3(ab) + norm3(bc) + norm3(ca) + norm3(n));
    double r = (six_v / 2) / area; /* 3V / A */
    return 3 * r / R;
}

void eo_mesh_stats_compute(const eo_mesh *m, eo_mesh_stats *s)
{
    memset(s, 0, sizeof *s);
    for (int i = 0; i < 3; i++) {
        s->bbox[i] = m->nv ? INFINITY : 0;
        s->bbox[3 + i] = m->nv ? -INFINITY : 0;
    }
    for (int v = 0; v < m->nv; v++)
        for (int i = 0; i < 3; i++) {
            double x = m->X[3 * v + i];
            if (x < s->bbox[i]) s->bbox[i] = x;
            if (x > s->bbox[3 + i]) s->bbox[3 + i] = x;
        }
    s->min_volume = m->nt ? INFINITY : 0;
    s->worst_quality = m->nt ? INFINITY : 0;
    ksum k = {0, 0};
    for (int t = 0; t < m->nt; t++) {
        double v = eo_tet_volume(m->X, m->tets + 4 * t);
        ksum_add(&k, v);
        if (v < s->min_volume) s->min_volume = v;
        if (v > s->max_volume) s->max_volume = v;
        double q = tet_quality(m->X, m->tets + 4 * t);
        if (q < s->worst_quality) s->worst_quality = q;
    }
    s->volume = k.s + k.c;
}

/* ---- validation --------------------------------------------------------------------- */

/* Sort n records of `size` bytes (each starting with an int key k[0] in [0, nb)) with
 * `cmp`: a counting sort on k[0], then each bucket on its own (insertion sort when
 * small, qsort otherwise). Linear in n for meshes, where buckets hold a few records. */
static int bucket_sort(eo_ctx *ctx, void *recs, size_t n, size_t size, int nb, int (*cmp)(const void *, const void *))
{
    if (n < 2) return EO_OK;
    size_t *start = eo_calloc(ctx, (size_t)nb + 1, sizeof *start);
    char *tmp = eo_malloc(ctx, n * size);
    if (!start || !tmp) {
        eo_free(ctx, start);
        eo_free(ctx, tmp);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (sorting %zu records)", n);
    }
    char *r = recs;
    int key;
    for (size_t i = 0; i < n; i++) {
        memcpy(&key, r + i * size, sizeof key);
        start[key + 1]++;
    }
    for (int b = 0; b < nb; b++) start[b + 1] += start[b];
    for (size_t i = 0; i < n; i++) {
        memcpy(&key, r + i * size, sizeof key);
        memcpy(tmp + start[key]++ * size, r + i * size, size);
    }
    /* start[b] is now the end of bucket b */
    size_t b0 = 0;
    char swap[64];
    for (int b = 0; b < nb; b++) {
        size_t b1 = start[b], len = b1 - b0;
        char *q = tmp + b0 * size;
        if (len > 16) {
            qsort(q, len, size, cmp);
        } else {
            for (size_t i = 1; i < len; i++)
                for (size_t j = i; j > 0 && cmp(q + (j - 1) * size, q + j * size) > 0; j--) {
                    memcpy(swap, q + j * size, size);
                    memcpy(q + j * size, q + (j - 1) * size, size);
                    memcpy(q + (j - 1) * size, swap, size);
                }
        }
        b0 = b1;
    }
    memcpy(recs, tmp, n * size);
    eo_free(ctx, tmp);
    eo_free(ctx, start);
    return EO_OK;
}

typedef struct {
    int k[4];
    int t;
} tetkey;

static int cmp_tetkey(const void *a, const void *b)
{
    const tetkey *x = a, *y = b;
    for (int i = 0; i < 4; i++)
        if (x->k[i] != y->k[i]) return x->k[i] < y->k[i] ? -1 : 1;
    return (x->t > y->t) - (x->t < y->t);
}

static void sort_small(int *k, int n)
{
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && k[j - 1] > k[j]; j--) {
            int tmp = k[j];
            k[j] = k[j - 1];
            k[j - 1] = tmp;
        }
}

static eo_errloc tet_loc(const eo_mesh_src *src, int t)
{
    if (src && src->t_line)
        return EO_ERRLOC_ITEM(src->tet_file, src->t_line[t], "tet", src->t_id[t]);
    return EO_ERRLOC_ITEM(src ? src->tet_file : NULL, -1, "tet", t);
}

static eo_errloc vert_loc(const eo_mesh_src *src, int v)
{
    if (src && src->v_line)
        return EO_ERRLOC_ITEM(src->vert_file, src->v_line[v], "vertex", src->v_id[v]);
    return EO_ERRLOC_ITEM(src ? src->vert_file : NULL, -1, "vertex", v);
}

static long tet_id(const eo_mesh_src *src, int t) { return src && src->t_id ? src->t_id[t] : t; }

/* Keep tets with keep[t] != 0, compacting every per-tet array. */
static int compact_tets(eo_mesh *m, const unsigned char *keep, const eo_mesh_src *src)
{
    int n = 0;
    for (int t = 0; t < m->nt; t++) {
        if (!keep[t]) continue;
        if (n != t) {
            memcpy(m->tets + 4 * n, m->tets + 4 * t, 4 * sizeof(int));
            if (m->tet10) memcpy(m->tet10 + 10 * n, m->tet10 + 10 * t, 10 * sizeof(int));
            if (m->tet_attr) m->tet_attr[n] = m->tet_attr[t];
            if (src && src->t_line) {
                src->t_line[n] = src->t_line[t];
                src->t_id[n] = src->t_id[t];
            }
        }
        n++;
    }
    int dropped = m->nt - n;
    m->nt = n;
    return dropped;
}

/* ---- quadratic (10-node) tets -------------------------------------------------------- */

/* local edges of tet10 slots 4..9 (VTK quadratic tetra order, mesh.h) */
static const int p2_edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

typedef struct {
    int a, b; /* a < b: the edge's corner vertices */
    int n, t; /* its midside node in tet t */
} p2key;

static int cmp_p2key(const void *x, const void *y)
{
    const p2key *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return (p->t > q->t) - (p->t < q->t);
}

/* The 6·nt edges of the tets with their midside nodes, sorted by edge (then tet). */
static int p2_edge_table(eo_ctx *ctx, const eo_mesh *m, p2key **out)
{
    size_t n = 6 * (size_t)m->nt;
    p2key *k = eo_malloc(ctx, (n ? n : 1) * sizeof *k);
    *out = NULL;
    if (!k) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (quadratic mesh edges)");
    for (int t = 0; t < m->nt; t++)
        for (int e = 0; e < 6; e++) {
            int a = m->tet10[10 * t + p2_edge[e][0]], b = m->tet10[10 * t + p2_edge[e][1]];
            k[6 * (size_t)t + e] = (p2key){a < b ? a : b, a < b ? b : a, m->tet10[10 * t + 4 + e], t};
        }
    int rc = bucket_sort(ctx, k, n, sizeof *k, m->nv, cmp_p2key);
    if (rc < 0) {
        eo_free(ctx, k);
        return rc;
    }
    *out = k;
    return EO_OK;
}

/* Midside node of edge (a, b) in the sorted table, or -1. */
static int p2_find(const p2key *k, size_t n, int a, int b)
{
    if (a > b) {
        int s = a;
        a = b;
        b = s;
    }
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (k[mid].a < a || (k[mid].a == a && k[mid].b < b)) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && k[lo].a == a && k[lo].b == b ? k[lo].n : -1;
}

static long vert_id(const eo_mesh_src *src, int v) { return src && src->v_id ? src->v_id[v] : v; }

/* Structure of an order-2 mesh: tet10 present, its corners equal to tets, midside nodes
 * in range, no midside node a corner of any tet, one node per edge and one edge per node. */
static int p2_check(eo_ctx *ctx, const eo_mesh *m, const eo_mesh_src *src, unsigned char *flag)
{
    if (!m->tet10) return eo_error(ctx, EO_ERR_INVALID, "order-2 mesh without tet10");
    memset(flag, 0, (size_t)m->nv);
    for (int t = 0; t < m->nt; t++)
        for (int i = 0; i < 4; i++) {
            if (m->tet10[10 * t + i] != m->tets[4 * t + i])
                return eo_error_at(ctx, EO_ERR_MESH, tet_loc(src, t),
                                   "corner %d of the 10-node tet is vertex %d but the tet lists %d", i,
                                   m->tet10[10 * t + i], m->tets[4 * t + i]);
            flag[m->tets[4 * t + i]] = 1;
        }
    for (int t = 0; t < m->nt; t++)
        for (int e = 0; e < 6; e++) {
            int v = m->tet10[10 * t + 4 + e];
            if (v < 0 || v >= m->nv)
                return eo_error_at(ctx, EO_ERR_MESH, tet_loc(src, t),
                                   "expected midside node indices in [0, %d), got %d", m->nv, v);
            if (flag[v])
                return eo_error_at(ctx, EO_ERR_MESH, tet_loc(src, t),
                                   "midside node %ld of edge %d%d is a corner of a tet; expected a node of its own",
                                   vert_id(src, v), p2_edge[e][0], p2_edge[e][1]);
        }
    p2key *k = NULL;
    int rc = p2_edge_table(ctx, m, &k);
    if (rc < 0) return rc;
    size_t n = 6 * (size_t)m->nt;
    for (size_t i = 1; i < n && rc >= 0; i++)
        if (k[i].a == k[i - 1].a && k[i].b == k[i - 1].b && k[i].n != k[i - 1].n)
            rc = eo_error_at(ctx, EO_ERR_MESH, tet_loc(src, k[i].t),
                             "edge (%ld, %ld) has midside node %ld here and %ld in tet %ld; expected one node "
                             "per edge",
                             vert_id(src, k[i].a), vert_id(src, k[i].b), vert_id(src, k[i].n),
                             vert_id(src, k[i - 1].n), tet_id(src, k[i - 1].t));
    /* one edge per node: the first edge each node meets, by node */
    int *ea = rc >= 0 ? eo_malloc(ctx, (size_t)m->nv * 2 * sizeof(int)) : NULL;
    if (rc >= 0 && !ea) rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (validation)");
    if (ea) {
        for (int v = 0; v < 2 * m->nv; v++) ea[v] = -1;
        for (size_t i = 0; i < n && rc >= 0; i++) {
            int v = k[i].n;
            if (ea[2 * v] < 0) {
                ea[2 * v] = k[i].a;
                ea[2 * v + 1] = k[i].b;
            } else if (ea[2 * v] != k[i].a || ea[2 * v + 1] != k[i].b) {
                rc = eo_error_at(ctx, EO_ERR_MESH, tet_loc(src, k[i].t),
                                 "midside node %ld is on edge (%ld, %ld) here and on edge (%ld, %ld) elsewhere; "
                                 "expected one edge per midside node",
                                 vert_id(src, v), vert_id(src, k[i].a), vert_id(src, k[i].b), vert_id(src, ea[2 * v]),
                                 vert_id(src, ea[2 * v + 1]));
            }
        }
    }
    eo_free(ctx, ea);
    eo_free(ctx, k);
    for (int i = 0; rc >= 0 && m->tri_mid && i < 3 * m->ntri; i++)
        if (m->tri_mid[i] < 0 || m->tri_mid[i] >= m->nv)
            rc = eo_error_at(ctx, EO_ERR_MESH,
                             EO_ERRLOC_ITEM(src && src->tri_file ? src->tri_file : src ? src->tet_file : NULL,
                                            src && src->f_line ? src->f_line[i / 3] : -1, "triangle", i / 3 + 1),
                             "expected midside node indices in [0, %d), got %d", m->nv, m->tri_mid[i]);
    return rc;
}

/* Tagged triangles of an order-2 mesh: fill tri_mid from the tets' edges when absent
 * (p2_check checked a given one). */
static int p2_tri_mid(eo_ctx *ctx, eo_mesh *m, const eo_mesh_src *src)
{
    if (!m->ntri || m->tri_mid) return EO_OK;
    p2key *k = NULL;
    int rc = p2_edge_table(ctx, m, &k);
    if (rc < 0) return rc;
    m->tri_mid = eo_malloc(ctx, (size_t)m->ntri * 3 * sizeof(int));
    if (!m->tri_mid) rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (triangle midside nodes)");
    for (int f = 0; f < m->ntri && rc >= 0; f++)
        for (int e = 0; e < 3 && rc >= 0; e++) {
            int a = m->tris[3 * f + e], b = m->tris[3 * f + (e + 1) % 3];
            int v = p2_find(k, 6 * (size_t)m->nt, a, b);
            if (v < 0)
                rc = eo_error_at(ctx, EO_ERR_MESH,
                                 EO_ERRLOC_ITEM(src && src->tri_file ? src->tri_file : src ? src->tet_file : NULL,
                                                src && src->f_line ? src->f_line[f] : -1, "triangle", f + 1),
                                 "edge (%ld, %ld) is not an edge of any tet, so it has no midside node; expected "
                                 "the triangles of a quadratic mesh on tet edges",
                                 vert_id(src, a), vert_id(src, b));
            else m->tri_mid[3 * f + e] = v;
        }
    if (rc < 0) {
        eo_free(ctx, m->tri_mid);
        m->tri_mid = NULL;
    }
    eo_free(ctx, k);
    return rc;
}

/* Swap corners 1 and 2 of 10-node tet q: edge 01 <-> 20, 12 stays, 13 <-> 23, 03 stays. */
static void p2_swap12(int *q)
{
    static const int perm[10] = {0, 2, 1, 3, 6, 5, 4, 7, 9, 8};
    int o[10];
    memcpy(o, q, sizeof o);
    for (int i = 0; i < 10; i++) q[i] = o[perm[i]];
}

int eo_mesh_validate_src(eo_ctx *ctx, eo_mesh *m, const eo_mesh_read_opts *opts, const eo_mesh_src *src)
{
    eo_mesh_read_opts def = eo_mesh_read_opts_default();
    if (!opts) opts = &def;
    const char *vfile = src ? src->vert_file : NULL;
    const char *tfile = src ? src->tet_file : NULL;
    int rc = EO_OK;
    unsigned char *flag = NULL;
    tetkey *keys = NULL;
    int *map = NULL;
    int dropped_t = 0, dropped_v = 0;

    if (m->nv == 0) return eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_FILE(vfile, -1), "mesh has no vertices");
    if (m->nt == 0) return eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_FILE(tfile, -1), "mesh has no tetrahedra");
    for (int v = 0; v < m->nv; v++)
        for (int i = 0; i < 3; i++)
            if (!isfinite(m->X[3 * v + i]))
                return eo_error_at(ctx, EO_ERR_NONFINITE, vert_loc(src, v),
                                   "expected finite coordinates, got %c = %g", "xyz"[i], m->X[3 * v + i]);
    for (int t = 0; t < m->nt; t++)
        for (int i = 0; i < 4; i++) {
            int v = m->tets[4 * t + i];
            if (v < 0 || v >= m->nv)
                return eo_error_at(ctx, EO_ERR_MESH, tet_loc(src, t),
                                   "expected vertex indices in [0, %d), got %d", m->nv, v);
            for (int j = 0; j < i; j++)
                if (m->tets[4 * t + j] == v)
                    return eo_error_at(ctx, EO_ERR_MESH, tet_loc(src, t),
                                       "expected 4 distinct vertices, got vertex %d twice", v);
        }

    for (int f = 0; f < m->ntri; f++)
        for (int i = 0; i < 3; i++) {
            int v = m->tris[3 * f + i];
            eo_errloc loc = EO_ERRLOC_ITEM(src && src->tri_file ? src->tri_file : tfile,
                                           src && src->f_line ? src->f_line[f] : -1, "triangle", f + 1);
            if (v < 0 || v >= m->nv)
                return eo_error_at(ctx, EO_ERR_MESH, loc, "expected vertex indices in [0, %d), got %d", m->nv, v);
            for (int j = 0; j < i; j++)
                if (m->tris[3 * f + j] == v)
                    return eo_error_at(ctx, EO_ERR_MESH, loc, "expected 3 distinct vertices, got vertex %d twice", v);
        }

    flag = eo_malloc(ctx, (size_t)(m->nt > m->nv ? m->nt : m->nv) + 1);
    if (!flag) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (validation)");
        goto fail;
    }
    if (m->order == 2 || m->tet10) {
        m->order = 2;
        if ((rc = p2_check(ctx, m, src, flag)) < 0) goto fail;
    }

    /* orientation and zero volume (corners only; a 10-node tet's midside nodes follow) */
    double mean = 0;
    int reoriented = 0;
    for (int t = 0; t < m->nt; t++) {
        int *tt = m->tets + 4 * t;
        double v = eo_tet_volume(m->X, tt);
        if (!isfinite(v)) {
            rc = eo_error_at(ctx, EO_ERR_NONFINITE, tet_loc(src, t),
                             "the volume overflows (%g); expected coordinates of a sensible magnitude", v);
            goto fail;
        }
        if (v < 0) {
            int tmp = tt[1];
            tt[1] = tt[2];
            tt[2] = tmp;
            if (m->tet10) p2_swap12(m->tet10 + 10 * t);
            reoriented++;
        }
        mean += fabs(v);
    }
    mean /= m->nt;
    if (!isfinite(mean)) {
        rc = eo_error_at(ctx, EO_ERR_NONFINITE, EO_ERRLOC_FILE(tfile, -1),
                         "the total volume overflows; expected coordinates of a sensible magnitude");
        goto fail;
    }
    m->reoriented += reoriented;
    double vmin = opts->min_rel_volume * mean;
    int nzero = 0;
    for (int t = 0; t < m->nt; t++) {
        double v = eo_tet_volume(m->X, m->tets + 4 * t);
        flag[t] = !(v <= vmin);
        if (flag[t]) continue;
        if (!opts->drop_degenerate) {
            rc = eo_error_at(ctx, EO_ERR_MESH, tet_loc(src, t),
                             "zero volume (%g <= %g x mean volume %g); expected a non-degenerate tet "
                             "(or use drop_degenerate)",
                             v, opts->min_rel_volume, mean);
            goto fail;
        }
        if (nzero++ == 0) eo_log(ctx, EO_LOG_WARN, "%s: dropping zero-volume tet %ld", tfile ? tfile : "mesh", tet_id(src, t));
    }
    if (nzero) dropped_t += compact_tets(m, flag, src);
    if (m->nt == 0) {
        rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_FILE(tfile, -1), "every tet has zero volume");
        goto fail;
    }

    /* duplicates */
    keys = eo_malloc(ctx, (size_t)m->nt * sizeof *keys);
    if (!keys) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (validation)");
        goto fail;
    }
    for (int t = 0; t < m->nt; t++) {
        memcpy(keys[t].k, m->tets + 4 * t, 4 * sizeof(int));
        sort_small(keys[t].k, 4);
        keys[t].t = t;
    }
    if ((rc = bucket_sort(ctx, keys, (size_t)m->nt, sizeof *keys, m->nv, cmp_tetkey)) < 0) goto fail;
    memset(flag, 1, (size_t)m->nt);
    int ndup = 0;
    for (int i = 1; i < m->nt; i++) {
        if (memcmp(keys[i].k, keys[i - 1].k, sizeof keys[i].k) != 0) continue;
        int t = keys[i].t, first = t; /* becomes the first tet of the run of equal keys */
        for (int j = i - 1; j >= 0 && memcmp(keys[j].k, keys[i].k, sizeof keys[i].k) == 0; j--) first = keys[j].t;
        if (!opts->drop_degenerate) {
            rc = eo_error_at(ctx, EO_ERR_MESH, tet_loc(src, t),
                             "duplicate of tet %ld (same vertex set); expected each tet once "
                             "(or use drop_degenerate)",
                             tet_id(src, first));
            goto fail;
        }
        flag[t] = 0;
        if (ndup++ == 0)
            eo_log(ctx, EO_LOG_WARN, "%s: dropping duplicate tet %ld (of tet %ld)", tfile ? tfile : "mesh",
                   tet_id(src, t), tet_id(src, first));
    }
    if (ndup) dropped_t += compact_tets(m, flag, src);

    /* unreferenced vertices */
    memset(flag, 0, (size_t)m->nv);
    for (int i = 0; i < 4 * m->nt; i++) flag[m->tets[i]] = 1;
    if (m->tet10) /* midside nodes are referenced too */
        for (int i = 0; i < 10 * m->nt; i++) flag[m->tet10[i]] = 1;
    if (m->tri_mid)
        for (int i = 0; i < 3 * m->ntri; i++)
            flag[m->tri_mid[i]] = 1;
    int nunref = 0;
    for (int v = 0; v < m->nv; v++) {
        if (flag[v]) continue;
        if (!opts->drop_unreferenced) {
            rc = eo_error_at(ctx, EO_ERR_MESH, vert_loc(src, v),
                             "not used by any tet; expected every vertex referenced "
                             "(or use drop_unreferenced)");
            goto fail;
        }
        if (nunref++ == 0)
            eo_log(ctx, EO_LOG_WARN, "%s: dropping unreferenced vertex %ld", vfile ? vfile : "mesh",
                   src && src->v_id ? src->v_id[v] : (long)v);
    }
    if (nunref) {
        map = eo_malloc(ctx, (size_t)m->nv * sizeof(int));
        if (!map) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (validation)");
            goto fail;
        }
        int n = 0;
        for (int v = 0; v < m->nv; v++) {
            map[v] = flag[v] ? n : -1;
            if (!flag[v]) continue;
            if (n != v) {
                memcpy(m->X + 3 * n, m->X + 3 * v, 3 * sizeof(double));
                if (m->vmarker) m->vmarker[n] = m->vmarker[v];
            }
            n++;
        }
        for (int i = 0; i < 4 * m->nt; i++) m->tets[i] = map[m->tets[i]];
        if (m->tet10)
            for (int i = 0; i < 10 * m->nt; i++) m->tet10[i] = map[m->tet10[i]];
        int nf = 0; /* tagged triangles on a dropped vertex go too */
        for (int f = 0; f < m->ntri; f++) {
            const int *q = m->tris + 3 * f;
            if (map[q[0]] < 0 || map[q[1]] < 0 || map[q[2]] < 0) continue;
            int w[3] = {map[q[0]], map[q[1]], map[q[2]]};
            memcpy(m->tris + 3 * nf, w, sizeof w);
            if (m->tri_mid) {
                const int *r = m->tri_mid + 3 * f;
                int u[3] = {map[r[0]], map[r[1]], map[r[2]]};
                memcpy(m->tri_mid + 3 * nf, u, sizeof u);
            }
            m->tri_tag[nf] = m->tri_tag[f];
            if (src && src->f_line) src->f_line[nf] = src->f_line[f];
            nf++;
        }
        m->ntri = nf;
        dropped_v = m->nv - n;
        m->nv = n;
    }
    if (m->tet10 && (rc = p2_tri_mid(ctx, m, src)) < 0) goto fail;
    m->dropped_tets += dropped_t;
    m->dropped_vertices += dropped_v;
    if (dropped_t || dropped_v) {
        eo_log(ctx, EO_LOG_WARN, "%s: dropped %d degenerate/duplicate tets and %d unreferenced vertices",
               tfile ? tfile : "mesh", dropped_t, dropped_v);
        rc = EO_WARN_DROPPED;
    }
fail:
    eo_free(ctx, flag);
    eo_free(ctx, keys);
    eo_free(ctx, map);
    return rc;
}

int eo_mesh_validate(eo_ctx *ctx, eo_mesh *m, const eo_mesh_read_opts *opts, const char *file)
{
    eo_mesh_src src = {.vert_file = file, .tet_file = file};
    return eo_mesh_validate_src(ctx, m, opts, &src);
}

/* ---- boundary ------------------------------------------------------------------------ */

typedef struct {
    int k[3];
    int t, f;
} facekey;

static int cmp_facekey(const void *a, const void *b)
{
    const facekey *x = a, *y = b;
    for (int i = 0; i < 3; i++)
        if (x->k[i] != y->k[i]) return x->k[i] < y->k[i] ? -1 : 1;
    return 0;
}

static int cmp_ll(const void *a, const void *b)
{
    const long long x = *(const long long *)a, y = *(const long long *)b;
    return x < y ? -1 : x > y;
}

int eo_mesh_surface_vertices(eo_ctx *ctx, const eo_mesh *m, unsigned char *flag, int *count)
{
    int *faces = NULL, nf = 0;
    *count = 0;
    memset(flag, 0, (size_t)m->nv);
    int rc = eo_mesh_boundary_faces(ctx, m, &faces, &nf);
    if (rc < 0) return rc;
    for (int i = 0; i < 3 * nf; i++) {
        *count += !flag[faces[i]];
        flag[faces[i]] = 1;
    }
    if (m->tet10 && nf > 0) { /* the midside nodes of the boundary faces' edges */
        static const int edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
        long long *be = eo_malloc(ctx, 3 * (size_t)nf * sizeof *be);
        if (!be) {
            eo_free(ctx, faces);
            return eo_error(ctx, EO_ERR_NOMEM, "out of memory (surface nodes)");
        }
        for (int f = 0; f < nf; f++)
            for (int e = 0; e < 3; e++) {
                long long a = faces[3 * f + e], b = faces[3 * f + (e + 1) % 3];
                be[3 * f + e] = a < b ? a * m->nv + b : b * m->nv + a;
            }
        qsort(be, 3 * (size_t)nf, sizeof *be, cmp_ll);
        for (int t = 0; t < m->nt; t++)
            for (int e = 0; e < 6; e++) {
                const int n = m->tet10[10 * t + 4 + e];
                if (flag[n]) continue;
                long long a = m->tet10[10 * t + edge[e][0]], b = m->tet10[10 * t + edge[e][1]];
                long long key = a < b ? a * m->nv + b : b * m->nv + a;
                if (bsearch(&key, be, 3 * (size_t)nf, sizeof *be, cmp_ll)) {
                    flag[n] = 1;
                    ++*count;
                }
            }
        eo_free(ctx, be);
    }
    eo_free(ctx, faces);
    return EO_OK;
}

/* outward faces of a positive tet, local indices */
static const int tet_faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};

int eo_mesh_boundary_faces(eo_ctx *ctx, const eo_mesh *m, int **faces, int *nf)
{
    *faces = NULL;
    *nf = 0;
    size_t n = 4 * (size_t)m->nt;
    facekey *k = eo_malloc(ctx, (n ? n : 1) * sizeof *k);
    if (!k) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (boundary faces)");
    for (int t = 0; t < m->nt; t++)
        for (int f = 0; f < 4; f++) {
            facekey *q = &k[4 * t + f];
            for (int i = 0; i < 3; i++) q->k[i] = m->tets[4 * t + tet_faces[f][i]];
            sort_small(q->k, 3);
            q->t = t;
            q->f = f;
        }
    int rc = bucket_sort(ctx, k, n, sizeof *k, m->nv, cmp_facekey);
    if (rc < 0) {
        eo_free(ctx, k);
        return rc;
    }
    size_t count = 0;
    for (size_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && cmp_facekey(&k[i], &k[j]) == 0; j++) {}
        if (j - i == 1) count++;
    }
    int *out = eo_malloc(ctx, (count ? count : 1) * 3 * sizeof(int));
    if (!out) {
        eo_free(ctx, k);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (boundary faces)");
    }
    size_t c = 0;
    for (size_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && cmp_facekey(&k[i], &k[j]) == 0; j++) {}
        if (j - i != 1) continue;
        for (int a = 0; a < 3; a++) out[3 * c + a] = m->tets[4 * k[i].t + tet_faces[k[i].f][a]];
        c++;
    }
    eo_free(ctx, k);
    *faces = out;
    *nf = (int)count;
    return EO_OK;
}
