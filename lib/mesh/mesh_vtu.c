/* VTK XML unstructured grid (.vtu) reader: tets (and tagged triangles).
 *
 * Reference: "VTK File Formats", XML file formats (VTK user's guide). Read:
 *   <VTKFile type="UnstructuredGrid" byte_order="LittleEndian" header_type="UInt32|UInt64">
 *   one <Piece NumberOfPoints NumberOfCells>, <Points> with one 3-component array,
 *   <Cells> with connectivity, offsets, types, optional <CellData> Int array "region".
 * Every DataArray may be format="ascii" (numbers), "binary" (base64 of a header_type
 * byte count followed by the bytes; the count and the data may be encoded together or
 * apart) or "appended" (offset into <AppendedData encoding="raw|base64">, after the
 * '_' marker: again a byte count and the bytes) — eo_vtu_write writes appended raw.
 * Types: Int8..UInt64, Float32, Float64. Compressed files (compressor=...) and
 * big-endian files are rejected (EO_ERR_UNSUPPORTED).
 * Cells of type 10 (tetra) become tets, "region" their tet_attr; cells of type 24
 * (quadratic tetra, 10 nodes in the order of tet10) instead give an order-2 mesh (a file
 * mixing types 10 and 24 is an error); cells of type 5 (triangle) or 22 (quadratic
 * triangle: its 3 corners) become tagged triangles (tag = region, or 0); vertices and
 * lines (1, 3) are skipped; any other type is an error naming the cell. Errors name file:line of
 * the XML element (binary payloads have no lines). */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_io.h"

typedef struct {
    eo_ctx *ctx;
    const char *file, *text, *end;
    int hsize;            /* header bytes: 4 or 8 */
    const char *app;      /* first byte after '_' in AppendedData, or NULL */
    int app_b64;
} vtu_reader;

typedef struct {
    const char *tag;      /* '<' of the DataArray */
    const char *body, *body_end;  /* inline content */
    char type[16], name[64], format[16];
    int ncomp;
    long offset;
} darray;

static long line_of(const vtu_reader *r, const char *p)
{
    long l = 1;
    for (const char *q = r->text; q < p && q < r->end; q++) l += *q == '\n';
    return l;
}

static int err_at(const vtu_reader *r, const char *p, int status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
static int err_at(const vtu_reader *r, const char *p, int status, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return eo_error_at(r->ctx, status, EO_ERRLOC_FILE(r->file, p ? line_of(r, p) : -1), "%s", msg);
}

/* value of attribute `key` in the tag starting at p (its '<', from find_tag; up to '>');
 * 1 if found. The scan starts after the '<', so that q[-1] stays inside the text. */
static int attr(const char *p, const char *end, const char *key, char *out, size_t n)
{
    size_t k = strlen(key);
    const char *gt = p;
    while (gt < end && *gt != '>') gt++;
    for (const char *q = p + 1; q + k + 2 < gt; q++) {
        if ((q[-1] == ' ' || q[-1] == '\t' || q[-1] == '\n' || q[-1] == '\r') && memcmp(q, key, k) == 0) {
            const char *v = q + k;
            while (v < gt && (*v == ' ' || *v == '\t')) v++;
            if (v >= gt || *v != '=') continue;
            v++;
            while (v < gt && (*v == ' ' || *v == '\t')) v++;
            if (v >= gt || (*v != '"' && *v != '\'')) continue;
            char qc = *v++;
            const char *e = v;
            while (e < gt && *e != qc) e++;
            if (e >= gt) return 0;
            snprintf(out, n, "%.*s", (int)(e - v), v);
            return 1;
        }
    }
    return 0;
}

/* next '<name' (followed by a delimiter) at or after p, before end */
static const char *find_tag(const char *p, const char *end, const char *name)
{
    size_t k = strlen(name);
    for (; p + k < end; p++) {
        if (*p != '<' || memcmp(p + 1, name, k) != 0) continue;
        char c = p[1 + k];
        if (c == ' ' || c == '>' || c == '/' || c == '\t' || c == '\n' || c == '\r') return p;
    }
    return NULL;
}

static const char *find_str(const char *p, const char *end, const char *s)
{
    size_t k = strlen(s);
    for (; p + k <= end; p++)
        if (*p == s[0] && memcmp(p, s, k) == 0) return p;
    return NULL;
}

static const struct {
    const char *name;
    int size, isfloat, issigned;
} vtypes[] = {{"Int8", 1, 0, 1},  {"UInt8", 1, 0, 0},  {"Int16", 2, 0, 1},   {"UInt16", 2, 0, 0},
              {"Int32", 4, 0, 1}, {"UInt32", 4, 0, 0}, {"Int64", 8, 0, 1},   {"UInt64", 8, 0, 0},
              {"Float32", 4, 1, 1}, {"Float64", 8, 1, 1}, {NULL, 0, 0, 0}};

static int vtype(const char *name)
{
    for (int i = 0; vtypes[i].name; i++)
        if (strcmp(vtypes[i].name, name) == 0) return i;
    return -1;
}

static double get_le(const unsigned char *p, int t)
{
    uint64_t u = 0;
    int n = vtypes[t].size;
    for (int i = n - 1; i >= 0; i--) u = u << 8 | p[i];
    if (vtypes[t].isfloat) {
        if (n == 4) {
            uint32_t w = (uint32_t)u;
            float f;
            memcpy(&f, &w, 4);
            return f;
        }
        double d;
        memcpy(&d, &u, 8);
        return d;
    }
    if (vtypes[t].issigned && n < 8 && (u >> (8 * n - 1)) & 1) u |= ~(uint64_t)0 << (8 * n);
    return vtypes[t].issigned ? (double)(int64_t)u : (double)u;
}

static int b64val(char c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

/* A base64 stream: whitespace skipped; '=' padding may end a quantum in the middle
 * (blocks encoded separately concatenate); stops at '<' or the end. */
typedef struct {
    const char *p, *end;
    unsigned char pend[3];
    int npend, ipend;
} b64_stream;

/* Read up to `want` bytes into out; returns the count read. */
static size_t b64_read(b64_stream *st, unsigned char *out, size_t want)
{
    size_t n = 0;
    int q[4], k = 0;
    while (n < want) {
        if (st->ipend < st->npend) {
            out[n++] = st->pend[st->ipend++];
            continue;
        }
        if (st->p >= st->end || *st->p == '<') break;
        char c = *st->p++;
        int v = c == '=' ? -2 : b64val(c);
        if (v == -1) continue;
        if (v >= 0) q[k++] = v;
        if (k == 4 || (v == -2 && k >= 2)) {
            unsigned char b[3] = {(unsigned char)(q[0] << 2 | q[1] >> 4),
                                  (unsigned char)((q[1] & 15) << 4 | (k > 2 ? q[2] >> 2 : 0)),
                                  (unsigned char)((k > 2 ? (q[2] & 3) << 6 : 0) | (k > 3 ? q[3] : 0))};
            int nb = k == 4 ? 3 : k - 1;
            memcpy(st->pend, b, 3);
            st->npend = nb;
            st->ipend = 0;
            k = 0;
        }
        if (v == -2) k = 0;
    }
    return n;
}

/* Values of array a (count numbers) as doubles into v. */
static int decode(vtu_reader *r, const darray *a, size_t count, double *v)
{
    int t = vtype(a->type);
    if (t < 0) return err_at(r, a->tag, EO_ERR_UNSUPPORTED, "DataArray '%s': unsupported type '%s'", a->name, a->type);
    size_t es = (size_t)vtypes[t].size;
    if (strcmp(a->format, "ascii") == 0) {
        const char *p = a->body;
        for (size_t i = 0; i < count; i++) {
            while (p < a->body_end && (*p == ' ' || *p == '\n' || *p == '\r' || *p == '\t')) p++;
            char *e;
            double x = p < a->body_end ? strtod(p, &e) : 0;
            if (p >= a->body_end || e == p || e > a->body_end)
                return err_at(r, p, EO_ERR_PARSE, "DataArray '%s': expected %zu numbers, got %zu", a->name, count, i);
            v[i] = x;
            p = e;
        }
        while (p < a->body_end && (*p == ' ' || *p == '\n' || *p == '\r' || *p == '\t')) p++;
        if (p < a->body_end)
            return err_at(r, p, EO_ERR_PARSE, "DataArray '%s': more numbers than the %zu expected", a->name, count);
        return EO_OK;
    }
    const char *p;
    int b64;
    if (strcmp(a->format, "binary") == 0) {
        p = a->body;
        b64 = 1;
    } else if (strcmp(a->format, "appended") == 0) {
        if (!r->app) return err_at(r, a->tag, EO_ERR_PARSE, "DataArray '%s': format appended but no <AppendedData> with '_'", a->name);
        if (a->offset < 0 || a->offset >= (long)(r->end - r->app))
            return err_at(r, a->tag, EO_ERR_PARSE, "DataArray '%s': offset %ld beyond the appended data", a->name, a->offset);
        p = r->app + a->offset;
        b64 = r->app_b64;
    } else {
        return err_at(r, a->tag, EO_ERR_UNSUPPORTED, "DataArray '%s': unsupported format '%s'", a->name, a->format);
    }
    size_t need = count * es;
    unsigned char hdr[8];
    const char *end = r->end;
    b64_stream st = {.p = p, .end = end};
    if (b64) {
        if (b64_read(&st, hdr, (size_t)r->hsize) != (size_t)r->hsize) goto short_data;
    } else {
        if (p + r->hsize > end) goto short_data;
        memcpy(hdr, p, (size_t)r->hsize);
        p += r->hsize;
    }
    uint64_t nbytes = 0;
    for (int i = r->hsize - 1; i >= 0; i--) nbytes = nbytes << 8 | hdr[i];
    if (nbytes != need) {
        char w[200];
        snprintf(w, sizeof w, "DataArray '%s': the byte count says %llu bytes; expected %zu (%zu values of %s)", a->name,
                 (unsigned long long)nbytes, need, count, a->type);
        return eo_error_at(r->ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(r->file, line_of(r, a->tag)), "%s", w);
    }
    if (b64) {
        unsigned char buf[8 * 64];
        size_t i = 0;
        while (i < count) {
            size_t chunk = count - i < 64 ? count - i : 64;
            if (b64_read(&st, buf, chunk * es) != chunk * es) goto short_data;
            for (size_t j = 0; j < chunk; j++) v[i + j] = get_le(buf + j * es, t);
            i += chunk;
        }
    } else {
        if ((size_t)(end - p) < need) goto short_data;
        for (size_t i = 0; i < count; i++) v[i] = get_le((const unsigned char *)p + i * es, t);
    }
    return EO_OK;
short_data:
    return err_at(r, a->tag, EO_ERR_PARSE, "DataArray '%s': the data ends early; expected %zu values", a->name, count);
}

static int read_darray(vtu_reader *r, const char *p, const char *lim, darray *a)
{
    memset(a, 0, sizeof *a);
    a->tag = p;
    char buf[32];
    attr(p, lim, "type", a->type, sizeof a->type);
    attr(p, lim, "Name", a->name, sizeof a->name);
    if (!attr(p, lim, "format", a->format, sizeof a->format)) snprintf(a->format, sizeof a->format, "ascii");
    a->ncomp = attr(p, lim, "NumberOfComponents", buf, sizeof buf) ? atoi(buf) : 1;
    a->offset = attr(p, lim, "offset", buf, sizeof buf) ? strtol(buf, NULL, 10) : -1;
    const char *gt = p;
    while (gt < lim && *gt != '>') gt++;
    if (gt >= lim) return err_at(r, p, EO_ERR_PARSE, "DataArray tag not closed with '>'");
    if (gt[-1] == '/') {
        a->body = a->body_end = gt;
        return EO_OK;
    }
    a->body = gt + 1;
    a->body_end = find_str(a->body, lim, "</DataArray>");
    if (!a->body_end) return err_at(r, p, EO_ERR_PARSE, "expected '</DataArray>' closing the array '%s'", a->name);
    return EO_OK;
}

int eo_vtu_read_text(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src)
{
    vtu_reader r = {.ctx = ctx, .file = file, .text = text, .end = text + len, .hsize = 4};
    eo_mesh *m = NULL;
    double *pts = NULL, *conn = NULL, *offs = NULL, *types = NULL, *region = NULL;
    int rc = EO_OK, tcap = 0;
    *out = NULL;
    char buf[64];
    const char *vf = find_tag(text, r.end, "VTKFile");
    if (!vf) return err_at(&r, NULL, EO_ERR_PARSE, "expected a <VTKFile> element");
    if (!attr(vf, r.end, "type", buf, sizeof buf) || strcmp(buf, "UnstructuredGrid") != 0)
        return err_at(&r, vf, EO_ERR_UNSUPPORTED, "expected VTKFile type=\"UnstructuredGrid\", got '%s'", buf);
    if (attr(vf, r.end, "byte_order", buf, sizeof buf) && strcmp(buf, "LittleEndian") != 0)
        return err_at(&r, vf, EO_ERR_UNSUPPORTED, "byte_order '%s' is not supported; expected LittleEndian", buf);
    if (attr(vf, r.end, "header_type", buf, sizeof buf)) {
        if (strcmp(buf, "UInt64") == 0) r.hsize = 8;
        else if (strcmp(buf, "UInt32") != 0)
            return err_at(&r, vf, EO_ERR_UNSUPPORTED, "header_type '%s'; expected UInt32 or UInt64", buf);
    }
    if (attr(vf, r.end, "compressor", buf, sizeof buf))
        return err_at(&r, vf, EO_ERR_UNSUPPORTED, "compressed VTU (%s) is not supported; expected uncompressed data", buf);
    /* the XML part ends at the appended data */
    const char *xml_end = r.end;
    const char *ad = find_tag(vf, r.end, "AppendedData");
    if (ad) {
        xml_end = ad;
        if (attr(ad, r.end, "encoding", buf, sizeof buf)) r.app_b64 = strcmp(buf, "base64") == 0;
        const char *u = ad;
        while (u < r.end && *u != '>') u++;
        while (u < r.end && *u != '_') u++;
        if (u < r.end) r.app = u + 1;
    }
    const char *piece = find_tag(vf, xml_end, "Piece");
    if (!piece) return err_at(&r, vf, EO_ERR_PARSE, "expected a <Piece> element");
    if (find_tag(piece + 1, xml_end, "Piece"))
        return err_at(&r, piece, EO_ERR_UNSUPPORTED, "more than one <Piece>; expected one");
    long np = -1, nc = -1;
    if (attr(piece, xml_end, "NumberOfPoints", buf, sizeof buf)) np = strtol(buf, NULL, 10);
    if (attr(piece, xml_end, "NumberOfCells", buf, sizeof buf)) nc = strtol(buf, NULL, 10);
    if (np < 1 || nc < 1 || np > (long)len || nc > (long)len)
        return err_at(&r, piece, EO_ERR_PARSE, "expected NumberOfPoints and NumberOfCells >= 1 (and plausible)");
    /* sections */
    const char *sp = find_tag(piece, xml_end, "Points"), *sc = find_tag(piece, xml_end, "Cells");
    const char *scd = find_tag(piece, xml_end, "CellData");
    if (!sp || !sc) return err_at(&r, piece, EO_ERR_PARSE, "expected <Points> and <Cells> in the <Piece>");
    const char *sp_end = find_str(sp, xml_end, "</Points>"), *sc_end = find_str(sc, xml_end, "</Cells>");
    const char *scd_end = scd ? find_str(scd, xml_end, "</CellData>") : NULL;
    if (!sp_end || !sc_end) return err_at(&r, piece, EO_ERR_PARSE, "expected </Points> and </Cells>");
    darray a_pts, a_conn = {0}, a_offs = {0}, a_types = {0}, a_reg = {0};
    int have_conn = 0, have_offs = 0, have_types = 0, have_reg = 0;
    const char *p = find_tag(sp, sp_end, "DataArray");
    if (!p) return err_at(&r, sp, EO_ERR_PARSE, "expected a DataArray in <Points>");
    if ((rc = read_darray(&r, p, xml_end, &a_pts)) < 0) return rc;
    if (a_pts.ncomp != 3) return err_at(&r, p, EO_ERR_PARSE, "Points: expected NumberOfComponents=\"3\", got %d", a_pts.ncomp);
    for (p = find_tag(sc, sc_end, "DataArray"); p; p = find_tag(p + 1, sc_end, "DataArray")) {
        darray a;
        if ((rc = read_darray(&r, p, xml_end, &a)) < 0) return rc;
        if (strcmp(a.name, "connectivity") == 0) a_conn = a, have_conn = 1;
        else if (strcmp(a.name, "offsets") == 0) a_offs = a, have_offs = 1;
        else if (strcmp(a.name, "types") == 0) a_types = a, have_types = 1;
    }
    if (!have_conn || !have_offs || !have_types)
        return err_at(&r, sc, EO_ERR_PARSE, "<Cells> needs DataArrays connectivity, offsets and types");
    for (p = scd && scd_end ? find_tag(scd, scd_end, "DataArray") : NULL; p; p = find_tag(p + 1, scd_end, "DataArray")) {
        darray a;
        if ((rc = read_darray(&r, p, xml_end, &a)) < 0) return rc;
        if (strcmp(a.name, "region") == 0 && a.ncomp == 1 && a.type[0] != 'F') a_reg = a, have_reg = 1;
    }
    pts = eo_malloc(ctx, 3 * (size_t)np * sizeof(double));
    offs = eo_malloc(ctx, (size_t)nc * sizeof(double));
    types = eo_malloc(ctx, (size_t)nc * sizeof(double));
    region = have_reg ? eo_malloc(ctx, (size_t)nc * sizeof(double)) : NULL;
    if (!pts || !offs || !types || (have_reg && !region)) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (vtu)");
        goto fail;
    }
    if ((rc = decode(&r, &a_pts, 3 * (size_t)np, pts)) < 0) goto fail;
    if ((rc = decode(&r, &a_offs, (size_t)nc, offs)) < 0) goto fail;
    if ((rc = decode(&r, &a_types, (size_t)nc, types)) < 0) goto fail;
    if (have_reg && (rc = decode(&r, &a_reg, (size_t)nc, region)) < 0) goto fail;
    double prev = 0;
    for (long c = 0; c < nc; c++) {
        if (!(offs[c] >= prev) || offs[c] > 1e15 || offs[c] != floor(offs[c])) {
            rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_ITEM(file, line_of(&r, a_offs.tag), "cell", c),
                             "offsets must increase (got %g after %g)", offs[c], prev);
            goto fail;
        }
        prev = offs[c];
    }
    size_t nconn = (size_t)offs[nc - 1];
    if (nconn > len * 8 + 64) {
        rc = eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(file, line_of(&r, a_offs.tag)),
                         "offsets announce %zu connectivity entries, more than the file can hold", nconn);
        goto fail;
    }
    conn = eo_malloc(ctx, (nconn ? nconn : 1) * sizeof(double));
    if (!conn) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (vtu)");
        goto fail;
    }
    if ((rc = decode(&r, &a_conn, nconn, conn)) < 0) goto fail;
    long ntet = 0, n10 = 0;
    for (long c = 0; c < nc; c++) {
        ntet += types[c] == 10 || types[c] == 24;
        n10 += types[c] == 24;
        if (types[c] != 10 && types[c] != 24 && types[c] != 5 && types[c] != 22 && types[c] != 3 && types[c] != 1) {
            rc = eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_ITEM(file, line_of(&r, a_types.tag), "cell", c),
                             "VTK cell type %g; expected tetrahedra (10 or quadratic 24), optionally with "
                             "triangles (5 or quadratic 22), lines (3) or vertices (1)",
                             types[c]);
            goto fail;
        }
    }
    if (!ntet) {
        rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_FILE(file, line_of(&r, a_types.tag)),
                         "no tetrahedra (VTK cell type 10 or 24) found; expected a volume mesh");
        goto fail;
    }
    if (n10 && n10 != ntet) {
        long c = 0;
        while (types[c] != 10) c++;
        rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_ITEM(file, line_of(&r, a_types.tag), "cell", c),
                         "a linear tetra (type 10) among %ld quadratic ones (type 24); expected one kind of tet", n10);
        goto fail;
    }
    if ((rc = eo_mesh_create(ctx, (int)np, (int)ntet, &m)) < 0) goto fail;
    if (n10) {
        if (!(m->tet10 = eo_malloc(ctx, (size_t)ntet * 10 * sizeof(int)))) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (vtu)");
            goto fail;
        }
        m->order = 2;
    }
    memcpy(m->X, pts, 3 * (size_t)np * sizeof(double));
    if (have_reg && !(m->tet_attr = eo_malloc(ctx, (size_t)ntet * sizeof(int)))) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (vtu)");
        goto fail;
    }
    if ((rc = eo_mesh_src_alloc(ctx, src, -1, (int)ntet)) < 0) goto fail;
    long t = 0, tline = line_of(&r, a_conn.tag);
    for (long c = 0; c < nc; c++) {
        size_t b0 = c ? (size_t)offs[c - 1] : 0, b1 = (size_t)offs[c];
        int type = types[c] == floor(types[c]) && fabs(types[c]) < 1e6 ? (int)types[c] : -1;
        int need = type == 10 ? 4 : type == 24 ? 10 : type == 5 ? 3 : type == 22 ? 6 : type == 1 ? 1 : type == 3 ? 2 : -1;
        if (need < 0) {
            rc = eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_ITEM(file, line_of(&r, a_types.tag), "cell", c),
                             "VTK cell type %g; expected tetrahedra (10 or quadratic 24), optionally with "
                             "triangles (5 or quadratic 22), lines (3) or vertices (1)",
                             types[c]);
            goto fail;
        }
        if (b1 - b0 != (size_t)need) {
            rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_ITEM(file, line_of(&r, a_offs.tag), "cell", c),
                             "cell of type %d with %zu points; expected %d", type, b1 - b0, need);
            goto fail;
        }
        int v[10];
        for (int k = 0; k < need; k++) {
            double x = conn[b0 + (size_t)k];
            if (!(x >= 0 && x < (double)np) || x != floor(x)) {
                rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_ITEM(file, tline, "cell", c),
                                 "expected point indices in [0, %ld), got %g", np, x);
                goto fail;
            }
            v[k] = (int)x;
        }
        int tag = 0;
        if (have_reg) {
            double g = region[c];
            if (!(fabs(g) < 2147483647.0) || g != floor(g)) {
                rc = eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_ITEM(file, line_of(&r, a_reg.tag), "cell", c),
                                 "region %g is not an int", g);
                goto fail;
            }
            tag = (int)g;
        }
        if (type == 10 || type == 24) {
            memcpy(m->tets + 4 * t, v, 4 * sizeof(int));
            if (type == 24) memcpy(m->tet10 + 10 * t, v, 10 * sizeof(int));
            if (m->tet_attr) m->tet_attr[t] = tag;
            src->t_line[t] = tline;
            src->t_id[t] = c;
            t++;
        } else if ((type == 5 || type == 22) && (rc = eo_mesh_add_tri(ctx, m, src, &tcap, v, tag, tline)) < 0) {
            goto fail;
        }
    }
fail:
    eo_free(ctx, pts);
    eo_free(ctx, conn);
    eo_free(ctx, offs);
    eo_free(ctx, types);
    eo_free(ctx, region);
    if (rc < 0) eo_mesh_destroy(&m);
    *out = m;
    return rc;
}
