/* Chebyshev semi-iterative acceleration and the per-vertex block step, shared by vbd.c,
 * jacobi_chebyshev.c and pd_local_global.c. Internal to solvers/optim.
 *
 * Chebyshev weights (Wang 2015, "A Chebyshev Semi-Iterative Approach for Accelerating
 * Projective and Position-based Dynamics", ACM TOG 34(6); the same schedule is
 * the accelerated iterations of Chen et al. 2024, "Vertex Block Descent"). For a
 * plain iteration x̂ = Φ(x) whose error contracts with spectral radius ρ:
 *     x⁽ᵏ⁺¹⁾ = ω_{k+1} (γ (x̂⁽ᵏ⁺¹⁾ − x⁽ᵏ⁾) + x⁽ᵏ⁾ − x⁽ᵏ⁻¹⁾) + x⁽ᵏ⁻¹⁾,
 *     ω_{k+1} = 1 for k < S,   ω_{S+1} = 2/(2 − ρ²),   ω_{k+1} = 4/(4 − ρ² ω_k) after,
 * S the delay (Wang: plain iterations first; VBD: S = 1, i.e. ω₁ = 1, ω₂ = 2/(2 − ρ²)),
 * γ the under-relaxation (1: none).
 * ρ estimate: Wang measures ρ offline from the error of the plain iteration against a
 * converged answer. Here (rho = 0) it is measured online from the S + 1 plain
 * corrections sₖ = ‖x⁽ᵏ⁺¹⁾ − x⁽ᵏ⁾‖ before the acceleration starts (at most the last
 * EO_CHEB_HIST), ρ̂ = (s_last/s_first)^(1/m) over their m ratios: for a linear iteration
 * the corrections shrink by the spectral radius once the dominant mode remains, and the
 * earlier ratios are smaller (fast modes still present), so ρ̂ errs low, on the safe
 * side. ρ̂ ≥ 1 (or not finite): no acceleration; the next plain corrections are
 * measured again. At most EO_CHEB_RHO_MAX.
 * Restart: the callers restart (eo_cheb_restart: plain iterate, S plain iterations
 * again, ρ re-estimated when automatic) when an accelerated iterate raises g
 * (eo_cheb_accept). Added here: where g no longer resolves the change (|Δg| ≤ 1e-12|g|,
 * near the minimizer) a rise of ‖∇g‖ counts as a rise, else an over-relaxed iteration
 * whose error grows again could run on unseen at the rounding level of g. */
#ifndef EO_OPTIM_CHEBYSHEV_H
#define EO_OPTIM_CHEBYSHEV_H

#include <math.h>

#include "elastopt/objective.h"

#define EO_CHEB_HIST 2
#define EO_CHEB_RHO_MAX 0.9999

typedef struct eo_cheb {
    double rho_set;            /* the manual ρ (0 = estimate) */
    int delay;                 /* S */
    double rho;                /* ρ in use (NAN until accelerating) */
    double omega;              /* ω of the last iterate */
    int k;                     /* iterations since the (re)start */
    int on;                    /* accelerating */
    double s[EO_CHEB_HIST];    /* the last plain corrections' norms (ring) */
    int ns;
    double rho_est;            /* the last estimate made (NAN if none) */
} eo_cheb;

static inline void eo_cheb_start(eo_cheb *c, double rho_set, int delay)
{
    c->rho_set = rho_set;
    c->delay = delay;
    c->rho = NAN;
    c->omega = 1;
    c->k = c->on = c->ns = 0;
    c->rho_est = NAN;
}

static inline void eo_cheb_restart(eo_cheb *c)
{
    c->omega = 1;
    c->k = c->on = c->ns = 0;
}

/* ρ̂ from the recorded corrections (NAN with fewer than two) */
static inline double eo_cheb_estimate(const eo_cheb *c)
{
    const int m = c->ns < EO_CHEB_HIST ? c->ns : EO_CHEB_HIST;
    if (m < 2) return NAN;
    const double first = c->s[(c->ns - m) % EO_CHEB_HIST], last = c->s[(c->ns - 1) % EO_CHEB_HIST];
    if (!(first > 0) || !(last >= 0)) return NAN;
    return pow(last / first, 1.0 / (m - 1));
}

/* The weight ω of the iterate formed now from the plain correction of norm sn (the
 * k-th call since the (re)start, k = 0, 1, ...). */
static inline double eo_cheb_next(eo_cheb *c, double sn)
{
    if (c->on) {
        const double r2 = c->rho * c->rho;
        c->k++;
        return c->omega = 4 / (4 - r2 * c->omega);
    }
    c->s[c->ns % EO_CHEB_HIST] = sn;
    c->ns++;
    c->k++;
    if (c->k <= c->delay) return c->omega = 1;
    double rho = c->rho_set;
    if (!(rho > 0)) rho = c->rho_est = eo_cheb_estimate(c);
    if (!(rho > 0 && rho < 1)) return c->omega = 1;
    if (rho > EO_CHEB_RHO_MAX) rho = EO_CHEB_RHO_MAX;
    c->rho = rho;
    c->on = 1;
    return c->omega = 2 / (2 - rho * rho);
}

/* 1 if an accelerated candidate with g = gt, ‖∇g‖ = gnt may replace the iterate
 * (g, gn): g not raised beyond rounding, and ‖∇g‖ not raised where g cannot tell. */
static inline int eo_cheb_accept(double g, double gn, double gt, double gnt)
{
    if (!isfinite(gt) || !isfinite(gnt)) return 0;
    const double tol = 1e-12 * fabs(g);
    if (gt > g + tol) return 0;
    return !(gt >= g - tol && gnt > gn);
}

/* One block Newton step d = −H⁻¹g over the block's free coordinates (dofs[c] ≥ 0), by
 * Cholesky of that principal submatrix; d = 0 on the others. Returns 0 and d = 0 when
 * the submatrix is not positive definite (a pivot ≤ 1e-14·its largest diagonal entry, or
 * not finite): the block is skipped, the paper's rule for a near-singular Hᵢ. */
static inline int eo_block3_newton(const double H[9], const double g[3], const int dofs[3], double d[3])
{
    int idx[3], k = 0;
    double L[9] = {0}, y[3];
    d[0] = d[1] = d[2] = 0;
    for (int c = 0; c < 3; c++)
        if (dofs[c] >= 0) idx[k++] = c;
    if (!k) return 0;
    double dmax = 0;
    for (int a = 0; a < k; a++) dmax = fmax(dmax, H[4 * idx[a]]);
    if (!(dmax > 0) || !isfinite(dmax)) return 0;
    for (int a = 0; a < k; a++)
        for (int b = 0; b <= a; b++) {
            double s = H[3 * idx[a] + idx[b]];
            for (int q = 0; q < b; q++) s -= L[3 * a + q] * L[3 * b + q];
            if (a == b) {
                if (!(s > 1e-14 * dmax)) return 0;
                L[4 * a] = sqrt(s);
            } else {
                L[3 * a + b] = s / L[4 * b];
            }
        }
    for (int a = 0; a < k; a++) {
        double s = -g[idx[a]];
        for (int q = 0; q < a; q++) s -= L[3 * a + q] * y[q];
        y[a] = s / L[4 * a];
    }
    for (int a = k - 1; a >= 0; a--) {
        double s = y[a];
        for (int q = a + 1; q < k; q++) s -= L[3 * q + a] * d[idx[q]];
        d[idx[a]] = s / L[4 * a];
    }
    for (int a = 0; a < k; a++)
        if (!isfinite(d[idx[a]])) {
            d[0] = d[1] = d[2] = 0;
            return 0;
        }
    return 1;
}

#endif
