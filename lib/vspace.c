/* Sums over the vectors of an objective's vector space (objective.h, eo_vspace): a plain
 * loop for the ordinary space (NULL), the owned entries reduced over the parts for a
 * distributed one. */
#include <math.h>

#include "elastopt/objective.h"

void eo_vreduce(const eo_vspace *s, double *v, int k, eo_reduce_op op)
{
    if (!s || !s->reduce || s->nparts < 2) return;
    if (s->reduce(v, k, op, s->user) < 0)
        for (int i = 0; i < k; i++) v[i] = NAN;
}

double eo_vdot(const eo_vspace *s, int n, const double *a, const double *b)
{
    double d = 0;
    if (!s || !s->own) {
        for (int i = 0; i < n; i++) d += a[i] * b[i];
    } else {
        for (int i = 0; i < n; i++)
            if (s->own[i]) d += a[i] * b[i];
    }
    eo_vreduce(s, &d, 1, EO_REDUCE_SUM);
    return d;
}

double eo_vdot_w(const eo_vspace *s, int n, const double *w, const double *a, const double *b)
{
    if (!w) return eo_vdot(s, n, a, b);
    double d = 0;
    for (int i = 0; i < n; i++)
        if (!s || !s->own || s->own[i]) d += a[i] * b[i] * w[i];
    eo_vreduce(s, &d, 1, EO_REDUCE_SUM);
    return d;
}

double eo_vnorm2(const eo_vspace *s, int n, const double *a) { return sqrt(eo_vdot(s, n, a, a)); }

double eo_vnorm_inf(const eo_vspace *s, int n, const double *a)
{
    double m = 0;
    for (int i = 0; i < n; i++) m = fabs(a[i]) > m ? fabs(a[i]) : m;
    eo_vreduce(s, &m, 1, EO_REDUCE_MAX);
    return m;
}
