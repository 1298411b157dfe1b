/* Proximal operator of a tet material (material.h, eo_material_prox):
 *
 *     z = argmin_z  φ(z) = ψ(z) + (k/2)‖z − v‖²_F,   k > 0,
 *
 * the local step of ADMM-type splittings of the elastic energy (Overby, Brown, Li &
 * Narain 2017, "ADMM ⊇ Projective Dynamics": z-update with U = Vψ and weight W² = V k,
 * divided by V).
 * Isotropic models (sigma_eval): the paper's reduced form. For rotation-invariant ψ the
 * minimizer shares the singular vectors of v (von Neumann's trace inequality), so with
 * v = U diag(σv) Vᵀ (signed SVD, eo_svd3) z = U diag(s) Vᵀ and
 *     s = argmin ψ(s) + (k/2)‖s − σv‖²,
 * three unknowns: Newton with ∂²ψ/∂σ² + kI (Cholesky; a gradient step where it is not
 * positive definite). A barrier model at an inverted v starts from s = (1, 1, 1).
 * F-space models (`linear`), or where the reduced form does not converge: Newton on the
 * nine entries of z, (∂P/∂F(z)⁺ + k I₉) Δz = −(P(z) + k(z − v)), ∂P/∂F⁺ the analytic clamp
 * projection (PSD: the system is SPD, one 9×9 Cholesky), started from the better of the
 * given z and v.
 * Both: an Armijo backtracking on φ (+∞ at J ≤ 0 for a barrier model, so iterates never
 * cross inversion); where φ no longer resolves the decrease (ψ is rounded at ε times
 * its terms, ~μ tr FᵀF), a step keeping φ within that rounding and reducing ‖∇φ‖ is
 * taken. The residual ∇φ uses the model's P as the objective computes it (F_psi_grad
 * where it has one): the SVD path's P differs by ~1e-12 relative, and the residual of
 * the local steps is the floor of an outer method's gradient (measured: with φ's rounding
 * taken as ε|φ| the local steps stalled at 1e-12·k and admm_pd's ‖∇g‖ at 1e-8 of its
 * start). Never allocates. */
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

/* the 9-entry form (any tet model) */
static int prox_full(const eo_material_type *mt, const eo_material_coef *c, const double v[9], double k,
                     int max_iters, double tol, double z[9], int *iters)
{
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
        (*iters)++;
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

/* φ(s) = ψ(σ = s) + (k/2)‖s − sv‖² in signed singular values, with gradient r and
 * Hessian A (3×3) as asked */
static double prox_value3(const eo_material_type *mt, const eo_material_coef *c, const double sv[3], double k,
                          const double s[3], eo_eval_what what, double r[3], double A[9])
{
    eo_sigma_eval se;
    mt->sigma_eval(c, s, what, &se);
    double d2 = 0;
    for (int i = 0; i < 3; i++) {
        d2 += (s[i] - sv[i]) * (s[i] - sv[i]);
        if (r) r[i] = se.g[i] + k * (s[i] - sv[i]);
    }
    if (A)
        for (int i = 0; i < 9; i++) A[i] = se.H[i] + (i % 4 == 0 ? k : 0);
    const double f = se.psi + 0.5 * k * d2;
    return isnan(f) ? INFINITY : f;
}

static double norm3(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* 3×3 SPD solve by Cholesky (A row-major, copied); 0 if not positive definite */
static int chol3(const double A[9], const double b[3], double x[3])
{
    const double l00 = A[0];
    if (!(l00 > 0)) return 0;
    const double L00 = sqrt(l00), L10 = A[3] / L00, L20 = A[6] / L00;
    const double l11 = A[4] - L10 * L10;
    if (!(l11 > 0)) return 0;
    const double L11 = sqrt(l11), L21 = (A[7] - L20 * L10) / L11;
    const double l22 = A[8] - L20 * L20 - L21 * L21;
    if (!(l22 > 0)) return 0;
    const double L22 = sqrt(l22);
    const double y0 = b[0] / L00, y1 = (b[1] - L10 * y0) / L11, y2 = (b[2] - L20 * y0 - L21 * y1) / L22;
    x[2] = y2 / L22;
    x[1] = (y1 - L21 * x[2]) / L11;
    x[0] = (y0 - L10 * x[1] - L20 * x[2]) / L00;
    return 1;
}

/* The reduced form of an isotropic model (the paper's): v = U diag(σv) Vᵀ (signed SVD),
 * s = argmin ψ(s) + (k/2)‖s − σv‖² by Newton on 3 unknowns (∂²ψ/∂σ² + kI, a gradient step
 * where it is not positive definite) with the same Armijo/residual line search, and
 * z = U diag(s) Vᵀ: for rotation-invariant ψ the minimizer shares v's singular vectors.
 * Returns as eo_material_prox; EO_ERR_NONFINITE when ψ is +∞ at σv and at (1, 1, 1). */
static int prox_reduced(const eo_material_type *mt, const eo_material_coef *c, const double v[9], double k,
                        int max_iters, double tol, double z[9], int *iters)
{
    double U[9], V[9], sv[3], s[3], r[3], A[9];
    eo_svd3(v, U, sv, V);
    const double vn = norm9(v), scale = k * (vn > 1 ? vn : 1), fround = 1e-12 * k * (1 + vn * vn);
    memcpy(s, sv, sizeof s);
    double fs = prox_value3(mt, c, sv, k, s, EO_EVAL_GRAD, r, NULL);
    if (!isfinite(fs)) { /* a barrier model at an inverted v: start at rest */
        s[0] = s[1] = s[2] = 1;
        fs = prox_value3(mt, c, sv, k, s, EO_EVAL_GRAD, r, NULL);
        if (!isfinite(fs)) return EO_ERR_NONFINITE;
    }
    double rn = norm3(r), rn_prev = INFINITY;
    int rc = EO_WARN_NOT_CONVERGED;
    for (int it = 0;; it++) {
        if (!isfinite(rn)) return EO_ERR_NONFINITE;
        if (rn <= tol * scale || (rn > 0.25 * rn_prev && rn <= 1e3 * tol * scale)) {
            rc = EO_OK;
            break;
        }
        if (it >= max_iters) break;
        (*iters)++;
        prox_value3(mt, c, sv, k, s, EO_EVAL_HESS, NULL, A);
        double nr[3] = {-r[0], -r[1], -r[2]}, ds[3];
        if (!chol3(A, nr, ds))
            for (int i = 0; i < 3; i++) ds[i] = nr[i] / k;
        const double slope = r[0] * ds[0] + r[1] * ds[1] + r[2] * ds[2];
        double t = 1, st[3], rt[3], ft = INFINITY;
        int ok = 0;
        for (int ls = 0; ls < 60 && !ok; ls++) {
            for (int i = 0; i < 3; i++) st[i] = s[i] + t * ds[i];
            ft = prox_value3(mt, c, sv, k, st, EO_EVAL_GRAD, rt, NULL);
            ok = ft <= fs + 1e-4 * t * slope || (ft <= fs + fround && norm3(rt) < rn);
            if (!ok) t *= 0.5;
        }
        if (!ok) {
            rc = rn <= 1e3 * tol * scale ? EO_OK : EO_WARN_NOT_CONVERGED;
            break;
        }
        memcpy(s, st, sizeof s);
        memcpy(r, rt, sizeof r);
        fs = ft;
        rn_prev = rn;
        rn = norm3(r);
    }
    for (int i = 0; i < 3; i++) /* z = U diag(s) Vᵀ, row-major */
        for (int j = 0; j < 3; j++)
            z[3 * i + j] = U[3 * i] * s[0] * V[3 * j] + U[3 * i + 1] * s[1] * V[3 * j + 1] + U[3 * i + 2] * s[2] * V[3 * j + 2];
    return rc;
}

int eo_material_prox(const eo_material_type *mt, const eo_material_coef *c, const double v[9], double k,
                     int max_iters, double tol, double z[9], int *iters)
{
    int it = 0;
    if (iters) *iters = 0;
    if (!mt || (mt->flags & EO_MATERIAL_EDGE)) return EO_ERR_UNSUPPORTED;
    if (!(k > 0) || !isfinite(k)) return EO_ERR_INVALID;
    int rc = EO_WARN_NOT_CONVERGED;
    if (mt->sigma_eval) {
        double zr[9];
        rc = prox_reduced(mt, c, v, k, max_iters, tol, zr, &it);
        if (rc == EO_OK) memcpy(z, zr, sizeof zr);
    }
    if (rc != EO_OK) /* F-space models; the reduced form not converged: the 9-entry form */
        rc = prox_full(mt, c, v, k, max_iters, tol, z, &it);
    if (iters) *iters = it;
    return rc;
}
