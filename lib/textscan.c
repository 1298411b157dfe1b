/* Shared tokenizer of the text mesh readers (see textscan.h) and the tag map. */
#include "textscan.h"

#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void eo_scan_init(eo_scan *s, eo_ctx *ctx, const char *file, const char *text, size_t len, char comment)
{
    s->ctx = ctx;
    s->file = file;
    s->p = text;
    s->end = text + len;
    s->line = 1;
    s->comment = comment;
    s->kind = NULL;
    s->index = -1;
    s->in_record = 0;
    s->sep = 0;
}

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
/* a blank, or the reader's extra separator (',' for Vega .veg) */
static int is_blank(const eo_scan *s, char c) { return is_space(c) || (s->sep && c == s->sep); }

static int is_delim(const eo_scan *s, const char *q)
{
    return q >= s->end || *q == 0 || *q == '\n' || is_blank(s, *q) || (s->comment && *q == s->comment);
}

int eo_scan_skip(eo_scan *s)
{
    const char *p = s->p, *end = s->end;
    for (;;) {
        while (p < end && is_blank(s, *p)) p++;
        if (p >= end) break;
        if (*p == '\n') {
            if (s->in_record) break;
            s->line++;
            p++;
            continue;
        }
        if (s->comment && *p == s->comment) {
            while (p < end && *p != '\n') p++;
            continue;
        }
        if (*p == 0) { /* embedded NUL: treat as whitespace so binary junk still reports */
            p++;
            continue;
        }
        break;
    }
    s->p = p;
    return p < end && *p != '\n';
}

long eo_scan_record(eo_scan *s)
{
    s->in_record = 0;
    eo_scan_skip(s);
    s->in_record = 1;
    return s->line;
}

static size_t token_len(const eo_scan *s, const char *p)
{
    const char *q = p;
    while (!is_delim(s, q)) q++;
    return (size_t)(q - p);
}

int eo_scan_peek(eo_scan *s, const char **tok, size_t *n)
{
    if (!eo_scan_skip(s)) return 0;
    *tok = s->p;
    *n = token_len(s, s->p);
    return 1;
}

int eo_scan_accept(eo_scan *s, const char *word)
{
    const char *t;
    size_t n;
    if (!eo_scan_peek(s, &t, &n)) return 0;
    if (n != strlen(word) || memcmp(t, word, n) != 0) return 0;
    s->p += n;
    return 1;
}

static int verror(eo_scan *s, int status, const char *fmt, va_list ap)
{
    return eo_error_atv(s->ctx, status, EO_ERRLOC_ITEM(s->file, s->line, s->kind, s->index), fmt, ap);
}

int eo_scan_error(eo_scan *s, int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = verror(s, status, fmt, ap);
    va_end(ap);
    return rc;
}

int eo_scan_fail(eo_scan *s, const char *what)
{
    const char *t;
    size_t n;
    if (!eo_scan_peek(s, &t, &n)) {
        /* name the last line, not the empty one after the final newline */
        long line = s->line;
        if (s->p >= s->end && line > 1 && s->end[-1] == '\n') s->line = line - 1;
        int rc = s->p < s->end ? eo_scan_error(s, EO_ERR_PARSE, "expected %s, got end of line", what)
                               : eo_scan_error(s, EO_ERR_PARSE, "expected %s, got end of file", what);
        s->line = line;
        return rc;
    }
    /* printable excerpt of the token */
    char buf[40];
    size_t k = 0;
    for (size_t i = 0; i < n && k + 4 < sizeof buf; i++) {
        unsigned char c = (unsigned char)t[i];
        buf[k++] = (c >= 32 && c < 127) ? (char)c : '?';
    }
    if (k < n) {
        buf[k++] = '.';
        buf[k++] = '.';
        buf[k++] = '.';
    }
    buf[k] = 0;
    return eo_scan_error(s, EO_ERR_PARSE, "expected %s, got '%s'", what, buf);
}

int eo_scan_word(eo_scan *s, const char *what, const char **tok, size_t *n)
{
    if (!eo_scan_peek(s, tok, n)) return eo_scan_fail(s, what);
    s->p += *n;
    return EO_OK;
}

int eo_scan_expect(eo_scan *s, const char *word)
{
    if (eo_scan_accept(s, word)) return EO_OK;
    char what[64];
    snprintf(what, sizeof what, "'%s'", word);
    return eo_scan_fail(s, what);
}

int eo_scan_long(eo_scan *s, const char *what, long *v)
{
    if (!eo_scan_skip(s)) return eo_scan_fail(s, what);
    char *e;
    errno = 0;
    long x = strtol(s->p, &e, 10);
    if (e == s->p || errno == ERANGE || !is_delim(s, e)) return eo_scan_fail(s, what);
    s->p = e;
    *v = x;
    return EO_OK;
}

int eo_scan_int(eo_scan *s, const char *what, long lo, long hi, int *v)
{
    const char *save = s->p;
    long save_line = s->line, x;
    int rc = eo_scan_long(s, what, &x);
    if (rc < 0) return rc;
    if (x < lo || x > hi) {
        s->p = save;
        s->line = save_line;
        char w[160];
        snprintf(w, sizeof w, "%s in [%ld, %ld]", what, lo, hi);
        return eo_scan_fail(s, w);
    }
    *v = (int)x;
    return EO_OK;
}

int eo_scan_count(eo_scan *s, const char *what, int *v)
{
    long x;
    const char *save = s->p;
    long save_line = s->line;
    int rc = eo_scan_long(s, what, &x);
    if (rc < 0) return rc;
    long room = (long)((s->end - s->p) / 2);
    if (room > INT_MAX) room = INT_MAX;
    if (x < 0 || x > room) {
        s->p = save;
        s->line = save_line;
        char w[160];
        snprintf(w, sizeof w, "%s between 0 and %ld (what the rest of the file can hold)", what, room);
        return eo_scan_fail(s, w);
    }
    *v = (int)x;
    return EO_OK;
}

int eo_scan_double(eo_scan *s, const char *what, double *v)
{
    if (!eo_scan_skip(s)) return eo_scan_fail(s, what);
    char *e;
    double x = strtod(s->p, &e);
    if (e == s->p || !is_delim(s, e)) return eo_scan_fail(s, what);
    s->p = e;
    *v = x;
    return EO_OK;
}

int eo_scan_eol(eo_scan *s, const char *what)
{
    const char *p = s->p;
    while (p < s->end && is_blank(s, *p)) p++;
    if (p >= s->end || *p == '\n' || (s->comment && *p == s->comment)) {
        s->p = p;
        s->in_record = 0;
        return EO_OK;
    }
    s->p = p;
    char w[160];
    snprintf(w, sizeof w, "end of line after %s", what);
    return eo_scan_fail(s, w);
}

void eo_scan_skip_line(eo_scan *s)
{
    const char *p = s->p;
    s->in_record = 0;
    while (p < s->end && *p != '\n') p++;
    if (p < s->end) {
        p++;
        s->line++;
    }
    s->p = p;
}

int eo_scan_skip_lines(eo_scan *s, long n, const char *what)
{
    eo_scan_skip_line(s);
    for (long i = 0; i < n; i++) {
        if (!eo_scan_skip(s)) {
            char w[160];
            snprintf(w, sizeof w, "%ld %s (%ld found)", n, what, i);
            return eo_scan_fail(s, w);
        }
        eo_scan_skip_line(s);
    }
    return EO_OK;
}

/* ---- tag map ------------------------------------------------------------------- */

typedef struct {
    long key;
    int val;
} kv;

static int cmp_kv(const void *a, const void *b)
{
    const kv *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->val < y->val ? -1 : x->val > y->val;
}

int eo_tagmap_build(eo_ctx *ctx, const long *tags, int n, eo_tagmap *map, int *dup)
{
    memset(map, 0, sizeof *map);
    *dup = -1;
    map->n = n;
    if (n == 0) return EO_OK;
    long mn = tags[0], mx = tags[0];
    for (int i = 1; i < n; i++) {
        if (tags[i] < mn) mn = tags[i];
        if (tags[i] > mx) mx = tags[i];
    }
    /* span in unsigned arithmetic: tags may cover the whole long range */
    unsigned long span = (unsigned long)mx - (unsigned long)mn;
    if (span < 4ul * (unsigned long)n + 1024ul) {
        map->min = mn;
        map->span = (long)span + 1;
        map->dense = eo_malloc(ctx, (size_t)map->span * sizeof(int));
        if (!map->dense) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (node map)");
        for (long i = 0; i < map->span; i++) map->dense[i] = -1;
        for (int i = 0; i < n; i++) {
            int *slot = &map->dense[tags[i] - mn];
            if (*slot >= 0) {
                *dup = i;
                return EO_ERR_PARSE;
            }
            *slot = i;
        }
        return EO_OK;
    }
    kv *a = eo_malloc(ctx, (size_t)n * sizeof *a);
    map->keys = eo_malloc(ctx, (size_t)n * sizeof(long));
    map->vals = eo_malloc(ctx, (size_t)n * sizeof(int));
    if (!a || !map->keys || !map->vals) {
        eo_free(ctx, a);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (node map)");
    }
    for (int i = 0; i < n; i++) {
        a[i].key = tags[i];
        a[i].val = i;
    }
    qsort(a, (size_t)n, sizeof *a, cmp_kv);
    for (int i = 0; i < n; i++) {
        if (i > 0 && a[i].key == a[i - 1].key && (*dup < 0 || a[i].val < *dup)) *dup = a[i].val;
        map->keys[i] = a[i].key;
        map->vals[i] = a[i].val;
    }
    eo_free(ctx, a);
    return *dup >= 0 ? EO_ERR_PARSE : EO_OK;
}

int eo_tagmap_find(const eo_tagmap *map, long tag)
{
    if (map->dense) {
        unsigned long off = (unsigned long)tag - (unsigned long)map->min;
        if (tag < map->min || off >= (unsigned long)map->span) return -1;
        return map->dense[off];
    }
    int lo = 0, hi = map->n - 1;
    while (lo <= hi) {
        int mid = lo + (hi - lo) / 2;
        if (map->keys[mid] == tag) return map->vals[mid];
        if (map->keys[mid] < tag) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

void eo_tagmap_deinit(eo_ctx *ctx, eo_tagmap *map)
{
    eo_free(ctx, map->dense);
    eo_free(ctx, map->keys);
    eo_free(ctx, map->vals);
    memset(map, 0, sizeof *map);
}

int eo_scan_gmsh_format(eo_scan *s, int *v41)
{
    int rc, ftype, dsize;
    double version;
    if ((rc = eo_scan_expect(s, "$MeshFormat")) < 0) return rc;
    if ((rc = eo_scan_double(s, "format version", &version)) < 0) return rc;
    if (!(version >= 2.0 && version < 3.0) && version != 4.1)
        return eo_scan_error(s, EO_ERR_UNSUPPORTED, "expected MSH version 2.2 or 4.1, got %g", version);
    *v41 = version == 4.1;
    if ((rc = eo_scan_int(s, "file type", 0, 1, &ftype)) < 0) return rc;
    if (ftype != 0)
        return eo_scan_error(s, EO_ERR_UNSUPPORTED, "binary .msh files are not supported; expected ASCII (file type 0)");
    if ((rc = eo_scan_int(s, "data size", 1, 64, &dsize)) < 0) return rc;
    return eo_scan_expect(s, "$EndMeshFormat");
}

int eo_scan_gmsh_skip_section(eo_scan *s, const char *name, size_t len)
{
    char end[80];
    snprintf(end, sizeof end, "$End%.*s", (int)(len > 61 ? 60 : len - 1), name + 1);
    long start = s->line;
    for (;;) {
        eo_scan_skip_line(s);
        if (!eo_scan_skip(s))
            return eo_scan_error(s, EO_ERR_PARSE, "expected '%s' closing the section opened on line %ld, got end of file",
                                 end, start);
        if (eo_scan_accept(s, end)) return EO_OK;
    }
}
