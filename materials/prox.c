/* Proximal operator of a tet material (material.h, eo_material_prox):
 *
 *     z = argmin_z  φ(z) = ψ(z) + (k/2)‖z − v‖²_F,   k > 0,
 *
 * the local step of ADMM-type splittings of the elastic energy (Overby, Brown, Li &
 * Narain 2017, "ADMM ⊇ Projective Dynamics", eq. 8: z-update with U = Vψ and weight
 * W² = V k, divided by V). Newton's method on the nine entries of z:
 *     (∂P/∂F(z)⁺ + k I₉) Δz = −(P(z) + k(z − v)),
 * ∂P/∂F⁺ the analytic clamp projection of the material kernel (PSD, so the system is SPD
 * with smallest eigenvalue ≥ k: one 9×9 Cholesky per iteration), then an Armijo
 * backtracking on φ (a barrier model's φ is +∞ at J ≤ 0, so the iterate never crosses
 * inversion; ψ below rounding: the test allows 1e-14|φ|). Where ∂P/∂F is PSD this is
 * Newton's method on φ (quadratic convergence); where the clamp acts, a convergent
 * descent method. Start: the better of the given z and v (φ(v) = ψ(v)). The paper
 * solves the same problem in the rotation-invariant reduced form (three singular values,
 * isotropic models only); the 9-entry form here serves every tet model (F-space `linear`
 * too) with the same minimizer: for isotropic ψ the minimizer shares v's singular
 * vectors (von Neumann), which Newton reaches as well. Never allocates. */
#include <math.h>
#include <string.h>

#include "elastopt/material.h"

/* φ(z) and, with r, ∇φ(z) = P(z) + k(z − v); returns φ (+∞ where ψ is). */
static double prox_value(const eo_material_type *mt, const eo_material_coef *c, const double v[9], double k,
                         const double z[9], double r[9])
{
    eo_material_eval ev;
    if (eo_material_evaluate(mt, c, z, r ? EO_EVAL_GRAD : EO_EVAL_ENERGY, EO_PROJ_NONE, &ev) < 0) return INFINITY;
    double d2 = 0;
    for (int i = 0; i < 9; i++) {
        d2 += (z[i] - v[i]) * (z[i] - v[i]);
        if (r) r[i] = ev.P[i] + k * (z[i] - v[i]);
    }
    const double f = ev.psi + 0.5 * k * d2;
    return isnan(f) ? INFINITY : f;
}

static double norm9(const double a[9])
{
    double s = 0;
    for (int i = 0; i < 9; i++) s += a[i] * a[i];
    return sqrt(s);
}

/* Cholesky solve of the SPD 9×9 A (row-major, overwritten) with b -> x. 0 on failure. */
static int chol9(double A[81], const double b[9], double x[9])
{
    for (int j = 0; j < 9; j++) {
        double s = A[9 * j + j];
        for (int q = 0; q < j; q++) s -= A[9 * j + q] * A[9 * j + q];
        if (!(s > 0)) return 0;
        const double d = sqrt(s);
        A[9 * j + j] = d;
        for (int i = j + 1; i < 9; i++) {
            double t = A[9 * i + j];
            for (int q = 0; q < j; q++) t -= A[9 * i + q] * A[9 * j + q];
            A[9 * i + j] = t / d;
        }
    }
    for (int i = 0; i < 9; i++) {
        double s = b[i];
        for (int q = 0; q < i; q++) s -= A[9 * i + q] * x[q];
        x[i] = s / A[9 * i + i];
    }
    for (int i = 8; i >= 0; i--) {
        double s = x[i];
        for (int q = i + 1; q < 9; q++) s -= A[9 * q + i] * x[q];
        x[i] = s / A[9 * i + i];
    }
    return 1;
}

int eo_material_prox(const eo_material_type *mt, const eo_material_coef *c, const double v[9], double k,
                     int max_iters, double tol, double z[9], int *iters)
{
    if (iters) *iters = 0;
    if (!mt || (mt->flags & EO_MATERIAL_EDGE)) return EO_ERR_UNSUPPORTED;
    if (!(k > 0) || !isfinite(k)) return EO_ERR_INVALID;
    const double vn = norm9(v), scale = k * (vn > 1 ? vn : 1);
    const double fround = 1e-12 * k * (1 + vn * vn); /* rounding allowance of φ */
    double fz = prox_value(mt, c, v, k, z, NULL), fv = prox_value(mt, c, v, k, v, NULL);
    if (fv <= fz || !isfinite(fz)) {
        memcpy(z, v, 9 * sizeof(double));
        fz = fv;
    }
    if (!isfinite(fz)) return EO_ERR_NONFINITE; /* no finite start (barrier, both inverted) */
    /* the residual ∇φ from the model's P as the objective computes it (F_psi_grad where the
     * model has one: the SVD path's P differs by ~1e-12 relative, which would be the floor
     * of an outer method's gradient); the SVD path for the Newton matrix only */
    double r[9], rn, rn_prev = INFINITY;
    prox_value(mt, c, v, k, z, r);
    rn = norm9(r);
    for (int it = 0;; it++) {
        if (!isfinite(rn)) return EO_ERR_NONFINITE;
        if (rn <= tol * scale) return EO_OK;
        if (it >= max_iters) return EO_WARN_NOT_CONVERGED;
        /* no longer converging fast near the tolerance: the rounding level of ∇φ */
        if (rn > 0.25 * rn_prev && rn <= 1e3 * tol * scale) return EO_OK;
        eo_material_eval ev;
        int rc = eo_material_evaluate(mt, c, z, EO_EVAL_HESS, EO_PROJ_CLAMP, &ev);
        if (rc < 0) return rc;
        if (iters) (*iters)++;
        double A[81], dz[9], nr[9];
        memcpy(A, ev.dPdF, sizeof A);
        for (int i = 0; i < 9; i++) {
            A[9 * i + i] += k;
            nr[i] = -r[i];
        }
        if (!chol9(A, nr, dz))
            for (int i = 0; i < 9; i++) dz[i] = nr[i] / k; /* not SPD in rounding: a gradient step */
        double slope = 0;
        for (int i = 0; i < 9; i++) slope += r[i] * dz[i];
        /* Armijo on φ; where φ no longer resolves the decrease (ψ is rounded at ε times its
         * terms, ~μ·tr FᵀF, not at ε|ψ|), a step that keeps φ within that rounding and
         * reduces ‖∇φ‖ is taken */
        double t = 1, zt[9], rt[9], ft = INFINITY;
        int ok = 0;
        for (int ls = 0; ls < 60 && !ok; ls++) {
            for (int i = 0; i < 9; i++) zt[i] = z[i] + t * dz[i];
            ft = prox_value(mt, c, v, k, zt, rt);
            ok = ft <= fz + 1e-4 * t * slope || (ft <= fz + fround && norm9(rt) < rn);
            if (!ok) t *= 0.5;
        }
        if (!ok) return rn <= 1e3 * tol * scale ? EO_OK : EO_WARN_NOT_CONVERGED;
        memcpy(z, zt, sizeof zt);
        memcpy(r, rt, sizeof rt);
        fz = ft;
        rn_prev = rn;
        rn = norm9(r);
    }
}
