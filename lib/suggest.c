/* "Did you mean": the weighted optimal-string-alignment distance and the pick of the
 * closest valid name (see suggest.h for the costs and the threshold). */
#include "elastopt/suggest.h"

#include <stdio.h>
#include <string.h>

#define EO_SUGGEST_MAX 63

static int lower(int c) { return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c; }
static int is_sep(int c) { return c == '_' || c == '-' || c == '.'; }

/* cost of turning character a into b */
static int sub_cost(char a, char b)
{
    if (a == b) return 0;
    if (lower((unsigned char)a) == lower((unsigned char)b)) return 1;
    if ((a == '_' || a == '-') && (b == '_' || b == '-')) return 1;
    return 2;
}
static int indel_cost(char c) { return is_sep((unsigned char)c) ? 1 : 2; }

static int min3(int a, int b, int c) { return a < b ? (a < c ? a : c) : (b < c ? b : c); }

static int distance_n(const char *a, size_t na, const char *b, size_t nb)
{
    /* three rows of the (na+1) x (nb+1) table: i-2, i-1, i */
    int r0[EO_SUGGEST_MAX + 1], r1[EO_SUGGEST_MAX + 1], r2[EO_SUGGEST_MAX + 1];
    int *pp = r0, *p = r1, *c = r2;
    p[0] = 0;
    for (size_t j = 1; j <= nb; j++) p[j] = p[j - 1] + indel_cost(b[j - 1]);
    for (size_t i = 1; i <= na; i++) {
        c[0] = p[0] + indel_cost(a[i - 1]);
        for (size_t j = 1; j <= nb; j++) {
            int d = min3(p[j] + indel_cost(a[i - 1]), c[j - 1] + indel_cost(b[j - 1]),
                         p[j - 1] + sub_cost(a[i - 1], b[j - 1]));
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && a[i - 1] != b[j - 1] &&
                pp[j - 2] + 2 < d)
                d = pp[j - 2] + 2;
            c[j] = d;
        }
        int *t = pp;
        pp = p;
        p = c;
        c = t;
    }
    return p[nb];
}

int eo_edit_distance(const char *a, const char *b)
{
    if (!a || !b) return -1;
    size_t na = strlen(a), nb = strlen(b);
    if (na > EO_SUGGEST_MAX || nb > EO_SUGGEST_MAX) return -1;
    return distance_n(a, na, b, nb);
}

int eo_suggest(const char *name, const char *list, char *out, size_t n)
{
    if (out && n) out[0] = 0;
    if (!name || !list || !out || !n) return 0;
    size_t len = strlen(name);
    if (len == 0 || len > EO_SUGGEST_MAX) return 0;
    int limit = 2 * (len / 4 > 1 ? (int)(len / 4) : 1);
    int best = limit + 1;
    const char *bp = NULL;
    size_t bn = 0;
    for (const char *s = list; *s;) {
        while (*s == ',' || *s == ' ' || *s == '\t' || *s == '\n') s++;
        const char *t = s;
        while (*s && *s != ',' && *s != ' ' && *s != '\t' && *s != '\n') s++;
        size_t k = (size_t)(s - t);
        if (k == 0 || k > EO_SUGGEST_MAX || (k == len && memcmp(t, name, k) == 0)) continue;
        int d = distance_n(name, len, t, k);
        if (d < best) {
            best = d;
            bp = t;
            bn = k;
        }
    }
    if (!bp) return 0;
    snprintf(out, n, "%.*s", (int)bn, bp);
    return 1;
}

const char *eo_suggest_hint(const char *name, const char *list, const char *prefix, char *buf, size_t n)
{
    char pick[EO_SUGGEST_MAX + 1];
    if (!buf || !n) return "";
    buf[0] = 0;
    if (eo_suggest(name, list, pick, sizeof pick))
        snprintf(buf, n, " (did you mean '%s%s'?)", prefix ? prefix : "", pick);
    return buf;
}
