/* Symmetric CSC matrices (upper triangle) and the fixed-pattern assembler.
 *
 * Pattern construction (eo_assembler_finalize), for n variables and E elements:
 *  1. incidence lists var -> elements (counting sort, O(Σ k));
 *  2. for every column j, the rows i <= j of the variables sharing an element with j,
 *     deduplicated with a marker array (mark[i] == j), then sorted (insertion sort for
 *     short columns, qsort otherwise): O(nnz log(column length));
 *  3. scatter maps: with pos[i] = position of row i in column j, each element touching j
 *     gets map[a*k+b] for the local pairs whose upper entry lies in column j.
 * Entry (a,b) of an element maps to the stored (g(a), g(b)) iff g(a) <= g(b); for
 * g(a) == g(b) both (a,b) and (b,a) map to the diagonal, which sums repeated ids
 * correctly. Every diagonal is present and is the last entry of its column.
 * Groups of vertex triples (the tets, springs and contacts of the step engine: k = 12,
 * 6, 3 with all three coordinates of a vertex free or eliminated together) are scattered
 * by 3×3 blocks instead, with one offset per block: 16 ints per tet instead of 144
 * (block_maps), the same sums in the same order per entry. */
#include "elastopt/sparse.h"
#include <math.h>

#include <stdlib.h>
#include <string.h>

/* ---- eo_csc ------------------------------------------------------------------------ */

int eo_csc_create(eo_ctx *ctx, int n, int nnz, eo_csc **out)
{
    *out = NULL;
    if (n < 0 || nnz < n) return eo_error(ctx, EO_ERR_INVALID, "csc: bad size n=%d nnz=%d", n, nnz);
    eo_csc *A = eo_calloc(ctx, 1, sizeof *A);
    if (A) A->ctx = ctx;
    if (!A) goto fail;
    A->n = n;
    A->nnz = nnz;
    A->colptr = eo_calloc(ctx, (size_t)n + 1, sizeof(int));
    A->rowind = eo_malloc(ctx, (size_t)(nnz ? nnz : 1) * sizeof(int));
    A->val = eo_malloc(ctx, (size_t)(nnz ? nnz : 1) * sizeof(double));
    if (!A->colptr || !A->rowind || !A->val) goto fail;
    *out = A;
    return EO_OK;
fail:
    eo_csc_destroy(&A);
    return eo_error(ctx, EO_ERR_NOMEM, "csc: out of memory (n=%d, nnz=%d)", n, nnz);
}

int eo_csc_clone(eo_ctx *ctx, const eo_csc *A, eo_csc **out)
{
    int rc = eo_csc_create(ctx, A->n, A->nnz, out);
    if (rc < 0) return rc;
    memcpy((*out)->colptr, A->colptr, ((size_t)A->n + 1) * sizeof(int));
    memcpy((*out)->rowind, A->rowind, (size_t)A->nnz * sizeof(int));
    memcpy((*out)->val, A->val, (size_t)A->nnz * sizeof(double));
    return EO_OK;
}

int eo_csc_kron_i3(eo_ctx *ctx, const eo_csc *A, double tol, eo_csc **A1)
{
    if (!A || A->n % 3 != 0 || A->n == 0) return 0;
    const int m = A->n / 3;
    double amax = 0;
    for (int q = 0; q < A->nnz; q++) amax = fmax(amax, fabs(A->val[q]));
    if (!isfinite(amax)) return 0;
    const double thr = tol * amax;
    double *w = eo_malloc(ctx, (size_t)m * sizeof(double));
    int *mark = eo_malloc(ctx, (size_t)m * sizeof(int));
    if (!w || !mark) {
        eo_free(ctx, w);
        eo_free(ctx, mark);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (block matrix of order %d)", A->n);
    }
    for (int I = 0; I < m; I++) mark[I] = -1;
    int ok = 1, nnz1 = 0;
    for (int J = 0; J < m && ok; J++) {
        /* column 3J: the multiples of the blocks (I, J), from its rows 3I */
        int big = 0;
        for (int q = A->colptr[3 * J]; q < A->colptr[3 * J + 1] && ok; q++) {
            const int i = A->rowind[q];
            if (i % 3 == 0) {
                mark[i / 3] = J;
                w[i / 3] = A->val[q];
                big += fabs(A->val[q]) > thr;
                nnz1++;
            } else if (fabs(A->val[q]) > thr) {
                ok = 0;
            }
        }
        for (int c = 1; c < 3 && ok; c++) { /* columns 3J+1, 3J+2: the same multiples on rows 3I+c */
            int matched = 0;
            for (int q = A->colptr[3 * J + c]; q < A->colptr[3 * J + c + 1] && ok; q++) {
                const int i = A->rowind[q], I = i / 3;
                const double v = A->val[q];
                if (i % 3 == c && mark[I] == J) {
                    if (fabs(v - w[I]) > thr) ok = 0;
                    matched += fabs(w[I]) > thr;
                } else if (fabs(v) > thr) {
                    ok = 0;
                }
            }
            if (matched != big) ok = 0;
        }
    }
    int rc = 0;
    if (ok) {
        eo_csc *B = NULL;
        rc = eo_csc_create(ctx, m, nnz1, &B);
        if (rc == EO_OK) {
            int p = 0;
            for (int J = 0; J < m; J++) {
                for (int q = A->colptr[3 * J]; q < A->colptr[3 * J + 1]; q++)
                    if (A->rowind[q] % 3 == 0) {
                        B->rowind[p] = A->rowind[q] / 3;
                        B->val[p++] = A->val[q];
                    }
                B->colptr[J + 1] = p;
            }
            *A1 = B;
            rc = 1;
        }
    }
    eo_free(ctx, w);
    eo_free(ctx, mark);
    return rc;
}

void eo_csc_destroy(eo_csc **A)
{
    eo_ctx *ctx = A && *A ? (*A)->ctx : NULL;
    if (!A || !*A) return;
    eo_free(ctx, (*A)->colptr);
    eo_free(ctx, (*A)->rowind);
    eo_free(ctx, (*A)->val);
    eo_free(ctx, *A);
    *A = NULL;
}

void eo_csc_symv(const eo_csc *A, const double *x, double *y)
{
    const int n = A->n;
    const int *cp = A->colptr, *ri = A->rowind;
    const double *v = A->val;
    for (int i = 0; i < n; i++) y[i] = 0;
    for (int j = 0; j < n; j++) {
        double xj = x[j], s = 0;
        int end = cp[j + 1];
        for (int p = cp[j]; p < end; p++) {
            int i = ri[p];
            if (i == j) {
                s += v[p] * xj;
            } else {
                y[i] += v[p] * xj;
                s += v[p] * x[i];
            }
        }
        y[j] += s;
    }
}

int eo_csc_find(const eo_csc *A, int i, int j)
{
    if (i > j) {
        int t = i;
        i = j;
        j = t;
    }
    if (i < 0 || j >= A->n) return -1;
    int lo = A->colptr[j], hi = A->colptr[j + 1] - 1;
    while (lo <= hi) {
        int mid = lo + (hi - lo) / 2, r = A->rowind[mid];
        if (r == i) return mid;
        if (r < i) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

void eo_csc_diag(const eo_csc *A, double *d)
{
    for (int j = 0; j < A->n; j++) d[j] = A->val[A->colptr[j + 1] - 1];
}

void eo_csc_shift(eo_csc *A, double c)
{
    for (int j = 0; j < A->n; j++) A->val[A->colptr[j + 1] - 1] += c;
}

void eo_csc_to_dense(const eo_csc *A, double *D)
{
    const size_t n = (size_t)A->n;
    memset(D, 0, n * n * sizeof(double));
    for (size_t j = 0; j < n; j++)
        for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) {
            size_t i = (size_t)A->rowind[p];
            D[i * n + j] = A->val[p];
            D[j * n + i] = A->val[p];
        }
}

int eo_csc_check(eo_ctx *ctx, const eo_csc *A)
{
    eo_errloc loc = EO_ERRLOC_ITEM(NULL, -1, "column", -1);
    if (A->n < 0 || A->colptr[0] != 0 || A->colptr[A->n] != A->nnz)
        return eo_error(ctx, EO_ERR_INVALID, "csc: inconsistent colptr (n=%d, nnz=%d)", A->n, A->nnz);
    for (int j = 0; j < A->n; j++) {
        int b = A->colptr[j], e = A->colptr[j + 1];
        loc.index = j;
        if (e <= b || A->rowind[e - 1] != j)
            return eo_error_at(ctx, EO_ERR_INVALID, loc, "csc: diagonal entry missing or not last");
        for (int p = b; p < e - 1; p++)
            if (A->rowind[p] < 0 || A->rowind[p] >= A->rowind[p + 1])
                return eo_error_at(ctx, EO_ERR_INVALID, loc, "csc: rows not sorted/unique/upper");
    }
    return EO_OK;
}

/* ---- full symmetric pattern --------------------------------------------------------- */

int eo_csc_full_create(eo_ctx *ctx, const eo_csc *A, eo_csc_full **out)
{
    *out = NULL;
    const int n = A->n;
    int *next = NULL;
    eo_csc_full *F = eo_calloc(ctx, 1, sizeof *F);
    if (F) F->ctx = ctx;
    if (!F) goto fail;
    F->n = n;
    F->nnz = 2 * A->nnz - n;
    size_t m = (size_t)(F->nnz > 0 ? F->nnz : 1);
    F->colptr = eo_calloc(ctx, (size_t)n + 1, sizeof(int));
    F->rowind = eo_malloc(ctx, m * sizeof(int));
    F->val = eo_calloc(ctx, m, sizeof(double));
    F->src = eo_malloc(ctx, m * sizeof(int));
    F->diag = eo_malloc(ctx, (size_t)(n ? n : 1) * sizeof(int));
    next = eo_malloc(ctx, (size_t)(n ? n : 1) * sizeof(int));
    if (!F->colptr || !F->rowind || !F->val || !F->src || !F->diag || !next) goto fail;
    /* full column c = upper column c (rows <= c) followed by rows j > c, ascending */
    for (int j = 0; j < n; j++)
        for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) {
            F->colptr[j + 1]++;
            if (A->rowind[p] != j) F->colptr[A->rowind[p] + 1]++;
        }
    for (int j = 0; j < n; j++) F->colptr[j + 1] += F->colptr[j];
    for (int j = 0; j < n; j++) {
        int len = A->colptr[j + 1] - A->colptr[j], q = F->colptr[j];
        for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++, q++) {
            F->rowind[q] = A->rowind[p];
            F->src[q] = p;
        }
        F->diag[j] = q - 1;
        next[j] = F->colptr[j] + len;
    }
    for (int j = 0; j < n; j++)
        for (int p = A->colptr[j]; p < A->colptr[j + 1] - 1; p++) {
            int i = A->rowind[p], q = next[i]++;
            F->rowind[q] = j;
            F->src[q] = p;
        }
    eo_free(ctx, next);
    eo_csc_full_fill(F, A);
    *out = F;
    return EO_OK;
fail:
    eo_free(ctx, next);
    eo_csc_full_destroy(&F);
    return eo_error(ctx, EO_ERR_NOMEM, "csc: out of memory expanding symmetric matrix (n=%d)", n);
}

void eo_csc_full_fill(eo_csc_full *F, const eo_csc *A)
{
    for (int q = 0; q < F->nnz; q++) F->val[q] = A->val[F->src[q]];
}

void eo_csc_full_destroy(eo_csc_full **F)
{
    eo_ctx *ctx = F && *F ? (*F)->ctx : NULL;
    if (!F || !*F) return;
    eo_free(ctx, (*F)->colptr);
    eo_free(ctx, (*F)->rowind);
    eo_free(ctx, (*F)->val);
    eo_free(ctx, (*F)->src);
    eo_free(ctx, (*F)->diag);
    eo_free(ctx, *F);
    *F = NULL;
}

/* ---- assembler --------------------------------------------------------------------- */

typedef struct eo_asm_group {
    int ne, k;
    long first;  /* global element number of element 0 */
    int *dofs;   /* ne*k */
    int *map;    /* ne*k*k, built at finalize (NULL for a block group) */
    int *bmap;   /* block group: ne*(k/3)² block offsets (see block_maps), else NULL */
} eo_asm_group;

struct eo_assembler {
    eo_ctx *ctx;
    int n;
    int ngroups, cap;
    long nelem;
    eo_asm_group *groups;
    eo_csc *A;
};

int eo_assembler_create(eo_ctx *ctx, int n, eo_assembler **out)
{
    *out = NULL;
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "assembler: negative size %d", n);
    eo_assembler *as = eo_calloc(ctx, 1, sizeof *as);
    if (!as) return eo_error(ctx, EO_ERR_NOMEM, "assembler: out of memory");
    as->ctx = ctx;
    as->n = n;
    *out = as;
    return EO_OK;
}

void eo_assembler_destroy(eo_assembler **as)
{
    eo_ctx *ctx = as && *as ? (*as)->ctx : NULL;
    if (!as || !*as) return;
    eo_assembler *a = *as;
    for (int g = 0; g < a->ngroups; g++) {
        eo_free(ctx, a->groups[g].dofs);
        eo_free(ctx, a->groups[g].map);
        eo_free(ctx, a->groups[g].bmap);
    }
    eo_free(ctx, a->groups);
    eo_csc_destroy(&a->A);
    eo_free(ctx, a);
    *as = NULL;
}

int eo_assembler_add_elements(eo_ctx *ctx, eo_assembler *as, int ne, int k, const int *dofs)
{
    if (as->A) return eo_error(ctx, EO_ERR_INVALID, "assembler: elements added after finalize");
    if (ne < 0 || k <= 0 || (ne > 0 && !dofs))
        return eo_error(ctx, EO_ERR_INVALID, "assembler: bad element group (ne=%d, k=%d)", ne, k);
    for (long t = 0; t < (long)ne * k; t++)
        if (dofs[t] < -1 || dofs[t] >= as->n)
            return eo_error_at(ctx, EO_ERR_INVALID, EO_ERRLOC_ITEM(NULL, -1, "element", t / k),
                               "assembler: variable id %d out of range [-1, %d)", dofs[t], as->n);
    if (as->ngroups == as->cap) {
        int cap = as->cap ? 2 * as->cap : 4;
        eo_asm_group *g = eo_realloc(ctx, as->groups, (size_t)cap * sizeof *g);
        if (!g) return eo_error(ctx, EO_ERR_NOMEM, "assembler: out of memory");
        as->groups = g;
        as->cap = cap;
    }
    eo_asm_group *g = &as->groups[as->ngroups];
    memset(g, 0, sizeof *g);
    size_t nd = (size_t)ne * (size_t)k;
    g->dofs = eo_malloc(ctx, (nd > 0 ? nd : 1) * sizeof(int));
    if (!g->dofs) return eo_error(ctx, EO_ERR_NOMEM, "assembler: out of memory (%d elements)", ne);
    if (ne) memcpy(g->dofs, dofs, (size_t)ne * (size_t)k * sizeof(int));
    g->ne = ne;
    g->k = k;
    g->first = as->nelem;
    as->nelem += ne;
    return as->ngroups++;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

static void sort_ints(int *v, int m)
{
    if (m > 32) {
        qsort(v, (size_t)m, sizeof(int), cmp_int);
        return;
    }
    for (int i = 1; i < m; i++) {
        int x = v[i], j = i - 1;
        while (j >= 0 && v[j] > x) {
            v[j + 1] = v[j];
            j--;
        }
        v[j + 1] = x;
    }
}

/* group of a global element number (binary search over the group offsets) */
static const eo_asm_group *group_of(const eo_assembler *as, long ge, int *e)
{
    int lo = 0, hi = as->ngroups - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (as->groups[mid].first <= ge) lo = mid;
        else hi = mid - 1;
    }
    *e = (int)(ge - as->groups[lo].first);
    return &as->groups[lo];
}

/* Rows i < j of column j: the variables sharing an element with j, each once (mark[i]
 * == j after the first). Writes them to rows (unsorted) unless rows is NULL; returns how
 * many. mark[] must not hold j on entry. */
static int column_rows(const eo_assembler *as, const int *incp, const int *ince, const long *inc,
                       int *mark, int j, int *rows)
{
    int cnt = 0;
    mark[j] = j;
    for (int q = incp[j]; q < ince[j]; q++) {
        int e;
        const eo_asm_group *G = group_of(as, inc[q], &e);
        const int *d = G->dofs + (size_t)e * G->k;
        for (int b = 0; b < G->k; b++)
            if (d[b] >= 0 && d[b] < j && mark[d[b]] != j) {
                mark[d[b]] = j;
                if (rows) rows[cnt] = d[b];
                cnt++;
            }
    }
    return cnt;
}

static void free_work(eo_ctx *ctx, int *a, int *b, int *c, int *d, long *e)
{
    eo_free(ctx, a);
    eo_free(ctx, b);
    eo_free(ctx, c);
    eo_free(ctx, d);
    eo_free(ctx, e);
}

/* Block scatter (3×3 blocks). A group whose k = 3m local variables come in vertex
 * triples — each triple all eliminated or three consecutive ids r, r+1, r+2 — is
 * scattered by blocks: for the local vertex pair (a, b) with row triple r = g(3a) and
 * column triple c = g(3b), r < c, the rows r, r+1, r+2 are consecutive in each of the
 * columns c, c+1, c+2 at the same offset o from the column start (the three columns
 * of a vertex have the same rows above c: the variables sharing an element with the
 * vertex), so one int o per block replaces nine map entries; r = c (the vertex's own
 * block) is the upper triangle at the end of the columns (o = -2), r > c is the
 * transposed block of (b, a) (o = -1, not read), as the per-entry map does. Every
 * offset is verified against the pattern; a group where one fails keeps the k×k map.
 * Returns 1 if the group is a block group (bmap built), 0 if not, < 0 out of memory. */
static int block_maps(eo_ctx *ctx, eo_asm_group *G, const eo_csc *A)
{
    if (G->k % 3 || G->ne == 0) return 0;
    const int m = G->k / 3, k = G->k;
    const int *cp = A->colptr, *ri = A->rowind;
    for (int e = 0; e < G->ne; e++) { /* vertex triples */
        const int *d = G->dofs + (size_t)e * k;
        for (int a = 0; a < m; a++) {
            const int r = d[3 * a];
            if (r < 0 ? (d[3 * a + 1] != -1 || d[3 * a + 2] != -1) : (d[3 * a + 1] != r + 1 || d[3 * a + 2] != r + 2))
                return 0;
        }
    }
    int *bm = eo_malloc(ctx, (size_t)G->ne * (size_t)(m * m) * sizeof(int));
    if (!bm) return EO_ERR_NOMEM;
    for (int e = 0; e < G->ne; e++) {
        const int *d = G->dofs + (size_t)e * k;
        int *o = bm + (size_t)e * m * m;
        for (int a = 0; a < m; a++)
            for (int b = 0; b < m; b++) {
                const int r = d[3 * a], c = d[3 * b];
                int ok = 1, off = -1;
                if (r < 0 || c < 0 || r > c) {
                    off = -1;
                } else if (r == c) {
                    off = -2;
                    for (int l = 0; l < 3 && ok; l++)
                        for (int i = 0; i <= l; i++) ok &= ri[cp[c + l + 1] - 1 - l + i] == c + i;
                } else {
                    int p = eo_csc_find(A, r, c);
                    ok = p >= 0;
                    off = ok ? p - cp[c] : -1;
                    for (int l = 0; l < 3 && ok; l++)
                        for (int i = 0; i < 3 && ok; i++) {
                            int q = cp[c + l] + off + i;
                            ok = q < cp[c + l + 1] && ri[q] == r + i;
                        }
                }
                if (!ok) {
                    eo_free(ctx, bm);
                    return 0;
                }
                o[a * m + b] = off;
            }
    }
    G->bmap = bm;
    return 1;
}

int eo_assembler_finalize(eo_ctx *ctx, eo_assembler *as)
{
    if (as->A) return eo_error(ctx, EO_ERR_INVALID, "assembler: finalize called twice");
    const int n = as->n;
    int *incp = NULL, *ince = NULL, *mark = NULL, *pos = NULL;
    long *inc = NULL;
    eo_csc *A = NULL;
    long ninc = 0;
    size_t n1 = (size_t)n + 1;

    /* 1. incidence var -> global element numbers */
    incp = eo_calloc(ctx, n1, sizeof(int));
    ince = eo_malloc(ctx, n1 * sizeof(int));
    mark = eo_malloc(ctx, n1 * sizeof(int));
    pos = eo_malloc(ctx, n1 * sizeof(int));
    if (!incp || !ince || !mark || !pos) goto nomem;
    for (int g = 0; g < as->ngroups; g++) {
        const eo_asm_group *G = &as->groups[g];
        for (long t = 0; t < (long)G->ne * G->k; t++)
            if (G->dofs[t] >= 0) {
                incp[G->dofs[t] + 1]++;
                ninc++;
            }
    }
    for (int i = 0; i < n; i++) incp[i + 1] += incp[i];
    inc = eo_malloc(ctx, (size_t)(ninc ? ninc : 1) * sizeof(long));
    if (!inc) goto nomem;
    for (int i = 0; i < n; i++) pos[i] = incp[i];
    for (int g = 0; g < as->ngroups; g++) {
        const eo_asm_group *G = &as->groups[g];
        for (int e = 0; e < G->ne; e++) {
            const int *d = G->dofs + (size_t)e * G->k;
            for (int a = 0; a < G->k; a++)
                if (d[a] >= 0 && (pos[d[a]] == incp[d[a]] || inc[pos[d[a]] - 1] != G->first + e))
                    inc[pos[d[a]]++] = G->first + e; /* skip an immediate repeat */
        }
    }
    for (int i = 0; i < n; i++) ince[i] = pos[i]; /* end of var i's incidence list */
    /* 2a. count rows per column */
    for (int i = 0; i < n; i++) mark[i] = -1;
    long nnz = 0;
    for (int j = 0; j < n; j++) nnz += 1 + column_rows(as, incp, ince, inc, mark, j, NULL); /* + diagonal */
    if (nnz > 2147483647L) {
        free_work(ctx, incp, ince, mark, pos, inc);
        return eo_error(ctx, EO_ERR_INVALID, "assembler: %ld nonzeros exceed the int index range", nnz);
    }
    if (eo_csc_create(ctx, n, (int)nnz, &A) < 0) goto nomem;
    /* 2b. fill rows, sort */
    for (int i = 0; i < n; i++) mark[i] = -1;
    int p = 0;
    for (int j = 0; j < n; j++) {
        A->colptr[j] = p;
        p += column_rows(as, incp, ince, inc, mark, j, A->rowind + p);
        sort_ints(A->rowind + A->colptr[j], p - A->colptr[j]);
        A->rowind[p++] = j;
    }
    A->colptr[n] = p;
    memset(A->val, 0, (size_t)(nnz ? nnz : 1) * sizeof(double));
    /* 3. maps: block offsets where the group allows, else the k×k map */
    for (int g = 0; g < as->ngroups; g++) {
        eo_asm_group *G = &as->groups[g];
        int b = block_maps(ctx, G, A);
        if (b < 0) goto nomem;
        if (b) continue;
        size_t m = (size_t)G->ne * (size_t)G->k * (size_t)G->k;
        G->map = eo_malloc(ctx, (m ? m : 1) * sizeof(int));
        if (!G->map) goto nomem;
        for (size_t t = 0; t < m; t++) G->map[t] = -1;
    }
    for (int j = 0; j < n; j++) {
        for (int r = A->colptr[j]; r < A->colptr[j + 1]; r++) pos[A->rowind[r]] = r;
        for (int q = incp[j]; q < ince[j]; q++) {
            int e;
            const eo_asm_group *G = group_of(as, inc[q], &e);
            if (!G->map) continue; /* block group */
            const int k = G->k;
            const int *d = G->dofs + (size_t)e * k;
            int *map = G->map + (size_t)e * k * k;
            for (int a = 0; a < k; a++) {
                if (d[a] != j) continue;
                for (int b = 0; b < k; b++) {
                    if (d[b] < 0 || d[b] > j) continue;
                    if (d[b] < j) map[b * k + a] = pos[d[b]]; /* upper entry (g(b), j) */
                    else map[a * k + b] = pos[j];             /* diagonal, both orientations */
                }
            }
        }
    }
    free_work(ctx, incp, ince, mark, pos, inc);
    as->A = A;
    return EO_OK;
nomem:
    free_work(ctx, incp, ince, mark, pos, inc);
    eo_csc_destroy(&A);
    for (int g = 0; g < as->ngroups; g++) {
        eo_free(ctx, as->groups[g].map);
        eo_free(ctx, as->groups[g].bmap);
        as->groups[g].map = as->groups[g].bmap = NULL;
    }
    return eo_error(ctx, EO_ERR_NOMEM, "assembler: out of memory building the pattern (n=%d)", n);
}

eo_csc *eo_assembler_matrix(eo_assembler *as) { return as->A; }

void eo_assembler_zero(eo_assembler *as)
{
    if (as->A) memset(as->A->val, 0, (size_t)as->A->nnz * sizeof(double));
}

/* A += w Ke by 3×3 blocks (block_maps) */
static void add_blocks(eo_assembler *as, const eo_asm_group *G, int e, const double *Ke, double w)
{
    const int k = G->k, m = k / 3;
    const int *d = G->dofs + (size_t)e * k, *bm = G->bmap + (size_t)e * m * m;
    const int *cp = as->A->colptr;
    double *val = as->A->val;
    for (int b = 0; b < m; b++) {
        const int c = d[3 * b];
        if (c < 0) continue;
        for (int a = 0; a < m; a++) {
            const int o = bm[a * m + b];
            if (o == -1) continue;
            const double *K = Ke + (size_t)(3 * a) * k + 3 * b;
            if (o >= 0) {
                for (int l = 0; l < 3; l++) {
                    double *v = val + cp[c + l] + o;
                    v[0] += w * K[l];
                    v[1] += w * K[k + l];
                    v[2] += w * K[2 * k + l];
                }
            } else { /* own block: upper triangle, rows c..c+l at the end of column c+l */
                for (int l = 0; l < 3; l++) {
                    double *v = val + cp[c + l + 1] - 1 - l;
                    for (int i = 0; i <= l; i++) v[i] += w * K[i * k + l];
                }
            }
        }
    }
}

void eo_assembler_add_scaled(eo_assembler *as, int h, int e, const double *Ke, double w)
{
    EO_ASSERT(as->A && h >= 0 && h < as->ngroups);
    const eo_asm_group *G = &as->groups[h];
    EO_ASSERT(e >= 0 && e < G->ne);
    if (G->bmap) {
        add_blocks(as, G, e, Ke, w);
        return;
    }
    const int kk = G->k * G->k;
    const int *map = G->map + (size_t)e * kk;
    double *val = as->A->val;
    for (int t = 0; t < kk; t++)
        if (map[t] >= 0) val[map[t]] += w * Ke[t];
}

void eo_assembler_add(eo_assembler *as, int h, int e, const double *Ke)
{
    EO_ASSERT(as->A && h >= 0 && h < as->ngroups);
    const eo_asm_group *G = &as->groups[h];
    EO_ASSERT(e >= 0 && e < G->ne);
    if (G->bmap) {
        add_blocks(as, G, e, Ke, 1.0);
        return;
    }
    const int kk = G->k * G->k;
    const int *map = G->map + (size_t)e * kk;
    double *val = as->A->val;
    for (int t = 0; t < kk; t++)
        if (map[t] >= 0) val[map[t]] += Ke[t];
}

void eo_assembler_add_diag(eo_assembler *as, int i, double v)
{
    EO_ASSERT(as->A && i >= 0 && i < as->n);
    as->A->val[as->A->colptr[i + 1] - 1] += v;
}

const int *eo_assembler_map(const eo_assembler *as, int h, int e)
{
    if (!as->A || h < 0 || h >= as->ngroups || e < 0 || e >= as->groups[h].ne) return NULL;
    const eo_asm_group *G = &as->groups[h];
    return G->map ? G->map + (size_t)e * G->k * G->k : NULL;
}

int eo_assembler_is_block(const eo_assembler *as, int h)
{
    return as->A && h >= 0 && h < as->ngroups && as->groups[h].bmap != NULL;
}
