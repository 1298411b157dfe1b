/* The L-BFGS memory shared by lbfgs, bcqn and projective_dynamics (internal header).
 *
 * The last m pairs s_i = x_{i+1} − x_i, y_i = ∇g_{i+1} − ∇g_i with ρ_i = 1/y_iᵀs_i in
 * circular storage, and the two loops of the recursion that applies the inverse-Hessian
 * approximation H_k to a vector (Nocedal & Wright, Numerical Optimization, Alg. 7.4):
 *     first loop   q = v;  for i = newest … oldest:  a_i = ρ_i s_iᵀq,  q −= a_i y_i
 *     (caller)     r = H⁰ q          — lbfgs: γD⁻¹ q;  projective_dynamics: L⁻¹ q
 *     second loop  for i = oldest … newest:  b = ρ_i y_iᵀr,  r += s_i (a_i − b)
 * A pair with sᵀy ≤ 1e-10·‖s‖‖y‖ (or non-finite) is skipped, which keeps H_k positive
 * definite on non-convex g. Storage: 2mn + 2m doubles owned by the caller. */
#ifndef EO_LBFGS_MEMORY_H
#define EO_LBFGS_MEMORY_H

#include <math.h>
#include <stddef.h>

#include "descent.h"

typedef struct eo_lbfgs_memory {
    int n, m;           /* variables, capacity */
    int count, head;    /* pairs stored; slot of the next pair */
    double *S, *Y;      /* m×n each, circular */
    double *rho, *a;    /* m each */
    const eo_vspace *vs; /* the objective's vector space (NULL: ordinary), for the sums */
} eo_lbfgs_memory;

/* doubles of storage for n variables and m pairs */
static inline size_t eo_lbfgs_memory_size(int n, int m)
{
    return 2 * (size_t)m * (size_t)(n > 0 ? n : 1) + 2 * (size_t)m;
}

static inline void eo_lbfgs_memory_bind(eo_lbfgs_memory *h, int n, int m, double *store)
{
    size_t nn = (size_t)(n > 0 ? n : 1);
    h->n = n;
    h->m = m;
    h->count = h->head = 0;
    h->S = store;
    h->Y = store + (size_t)m * nn;
    h->rho = h->Y + (size_t)m * nn;
    h->a = h->rho + m;
}

static inline void eo_lbfgs_memory_clear(eo_lbfgs_memory *h) { h->count = h->head = 0; }

/* slot of the j-th newest pair (j = 0: newest) */
static inline int eo_lbfgs_memory_slot(const eo_lbfgs_memory *h, int j)
{
    return ((h->head - 1 - j) % h->m + h->m) % h->m;
}

/* 1 if a pair with these products keeps H_k positive definite (else it is skipped) */
static inline int eo_lbfgs_pair_ok(double sy, double ss, double yy)
{
    return sy > 1e-10 * sqrt(ss) * sqrt(yy) && isfinite(sy);
}

/* store the pair (s, y) given as vectors (bcqn: y blended), unless it would break
 * positive definiteness */
static inline void eo_lbfgs_memory_push_pair(eo_lbfgs_memory *h, const double *s_in, const double *y_in)
{
    const int n = h->n;
    if (h->m == 0) return;
    const double sy = eo_vdot(h->vs, n, s_in, y_in), ss = eo_vdot(h->vs, n, s_in, s_in),
                 yy = eo_vdot(h->vs, n, y_in, y_in);
    if (!eo_lbfgs_pair_ok(sy, ss, yy)) return; /* skip the pair */
    double *s = h->S + (size_t)h->head * n, *y = h->Y + (size_t)h->head * n;
    for (int i = 0; i < n; i++) {
        s[i] = s_in[i];
        y[i] = y_in[i];
    }
    h->rho[h->head] = 1 / sy;
    h->head = (h->head + 1) % h->m;
    if (h->count < h->m) h->count++;
}

/* store the pair of an accepted step x → x_new, unless it would break positive definiteness */
static inline void eo_lbfgs_memory_push(eo_lbfgs_memory *h, const double *x, const double *x_new,
                                        const double *grad, const double *grad_new)
{
    const int n = h->n;
    if (h->m == 0) return;
    double sy = 0, ss = 0, yy = 0;
    for (int i = 0; i < n; i++) {
        if (h->vs && !h->vs->own[i]) continue;
        double si = x_new[i] - x[i], yi = grad_new[i] - grad[i];
        sy += si * yi;
        ss += si * si;
        yy += yi * yi;
    }
    if (h->vs) {
        double v[3] = {sy, ss, yy};
        eo_vreduce(h->vs, v, 3, EO_REDUCE_SUM);
        sy = v[0], ss = v[1], yy = v[2];
    }
    if (!eo_lbfgs_pair_ok(sy, ss, yy)) return; /* skip the pair */
    double *s = h->S + (size_t)h->head * n, *y = h->Y + (size_t)h->head * n;
    for (int i = 0; i < n; i++) {
        s[i] = x_new[i] - x[i];
        y[i] = grad_new[i] - grad[i];
    }
    h->rho[h->head] = 1 / sy;
    h->head = (h->head + 1) % h->m;
    if (h->count < h->m) h->count++;
}

static inline void eo_lbfgs_memory_first_loop(eo_lbfgs_memory *h, double *q)
{
    const int n = h->n;
    for (int j = 0; j < h->count; j++) {
        int slot = eo_lbfgs_memory_slot(h, j);
        const double *s = h->S + (size_t)slot * n, *y = h->Y + (size_t)slot * n;
        h->a[slot] = h->rho[slot] * eo_vdot(h->vs, n, s, q);
        for (int i = 0; i < n; i++) q[i] -= h->a[slot] * y[i];
    }
}

static inline void eo_lbfgs_memory_second_loop(const eo_lbfgs_memory *h, double *r)
{
    const int n = h->n;
    for (int j = h->count - 1; j >= 0; j--) {
        int slot = eo_lbfgs_memory_slot(h, j);
        const double *s = h->S + (size_t)slot * n, *y = h->Y + (size_t)slot * n;
        double b = h->rho[slot] * eo_vdot(h->vs, n, y, r);
        for (int i = 0; i < n; i++) r[i] += s[i] * (h->a[slot] - b);
    }
}

/* 1 if p is a descent direction for grad beyond rounding */
static inline int eo_is_descent(const eo_vspace *vs, int n, const double *grad, const double *p)
{
    double dg = eo_vdot(vs, n, grad, p), pn = eo_vnorm2(vs, n, p), gn = eo_vnorm2(vs, n, grad);
    return isfinite(dg) && isfinite(pn) && dg < -1e-14 * gn * pn;
}

#endif
