/* Projective-dynamics constraint energies in singular-value space (private to
 * materials/; used by pd_arap.c, pd_strain_limit.c, pd_volume.c).
 *
 * A PD constraint (Bouaziz, Martin, Liu, Kavan & Pauly, "Projective Dynamics", SIGGRAPH
 * 2014, §4–5) on the deformation gradient F is a set C of matrices with an element
 * energy  ψ(F) = (w/2)·min_{T∈C} ‖F − T‖²_F = (w/2)‖F − proj_C(F)‖²_F  (per unit rest
 * volume; the element energy is V·ψ). Every C used here is isotropic, so the closest
 * point shares the singular vectors of F = U diag(σ) Vᵀ (signed σ, material.h):
 * proj_C(F) = U diag(s) Vᵀ with s the closest point of the σ-space set, and
 *     ψ = (w/2)‖σ − s(σ)‖²,   ψ_i = w(σ_i − s_i)   (envelope theorem: s is a minimizer),
 *     ∂²ψ/∂σ² = w(I − ∂s/∂σ),
 *     twist_ij = w(1 − (s_i − s_j)/(σ_i − σ_j)),  flip_ij = w(1 − (s_i + s_j)/(σ_i + σ_j)).
 *
 * Strain box  C = {σ_i ∈ [a, b]}  (strain limiting; a = b = 1 is SO(3), ARAP):
 *     s_i = clamp(σ_i, a, b), ∂s_i/∂σ_i = 1 inside [a, b] (if a < b), 0 outside and for
 *     a = b. (s_i − s_j)/(σ_i − σ_j) is exact in floating point where σ_i ≠ σ_j (both
 *     inside: 1, both clamped to one bound: 0) and the derivative where σ_i = σ_j.
 * Volume      C = {σ₁σ₂σ₃ ∈ [a, b]}  (volume preservation, a = b = 1: det F = 1):
 *     inside (a < b): s = σ, no energy. Else v = a or b (the nearer bound; always when
 *     a = b) and s solves the KKT system of min ‖s − σ‖² s.t. s₁s₂s₃ = v:
 *         s − σ − t·c(s) = 0,  s₁s₂s₃ = v,   c(s) = (s₂s₃, s₁s₃, s₁s₂),
 *     by Newton's method on (s, t) from (σ, 0) (inverted: σ₃ replaced by v/(σ₁σ₂)); ∂s/∂σ from the same 4×4 Jacobian
 *     (implicit differentiation). With σ_i = s_i − t s_j s_k (k the third index):
 *         twist_ij = w t s_k/(1 + t s_k),   flip_ij = −w t s_k/(1 − t s_k),
 *     exact at repeated σ. */
#ifndef EO_MATERIALS_PD_CONSTRAINT_H
#define EO_MATERIALS_PD_CONSTRAINT_H

#include <math.h>
#include <string.h>

#include "elastopt/material.h"

static const int eo_pd_pi[3] = {0, 0, 1}, eo_pd_pj[3] = {1, 2, 2}, eo_pd_pk[3] = {2, 1, 0};

/* 1 if clamp(·, a, b) has slope 1 at x */
static inline int eo_pd_inside(double x, double a, double b) { return a < b && x >= a && x <= b; }

/* Add the strain-box constraint energy with weight w to o (filled up to `what`). */
static inline void eo_pd_strain_add(double w, double a, double b, const double sg[3], eo_eval_what what,
                                    eo_sigma_eval *o)
{
    double s[3];
    for (int i = 0; i < 3; i++) s[i] = sg[i] < a ? a : (sg[i] > b ? b : sg[i]);
    double d0 = sg[0] - s[0], d1 = sg[1] - s[1], d2 = sg[2] - s[2];
    o->psi += 0.5 * w * (d0 * d0 + d1 * d1 + d2 * d2);
    if (what < EO_EVAL_GRAD) return;
    for (int i = 0; i < 3; i++) o->g[i] += w * (sg[i] - s[i]);
    if (what < EO_EVAL_HESS) return;
    for (int i = 0; i < 3; i++) o->H[4 * i] += w * (1 - eo_pd_inside(sg[i], a, b));
    for (int p = 0; p < 3; p++) {
        int i = eo_pd_pi[p], j = eo_pd_pj[p];
        double r = sg[i] != sg[j] ? (s[i] - s[j]) / (sg[i] - sg[j]) : eo_pd_inside(sg[i], a, b);
        o->twist[p] += w * (1 - r);
        double den = sg[i] + sg[j];
        if (fabs(den) < 1e-12) den = den < 0 ? -1e-12 : 1e-12;
        o->flip[p] += w * (1 - (s[i] + s[j]) / den);
    }
}

/* Solve the 4×4 system A y = r in place (partial pivoting); 0 if singular. */
static inline int eo_pd_solve4(double A[16], double r[4])
{
    for (int c = 0; c < 4; c++) {
        int piv = c;
        for (int q = c + 1; q < 4; q++)
            if (fabs(A[4 * q + c]) > fabs(A[4 * piv + c])) piv = q;
        if (!(fabs(A[4 * piv + c]) > 0)) return 0;
        if (piv != c) {
            for (int k = 0; k < 4; k++) {
                double t = A[4 * c + k];
                A[4 * c + k] = A[4 * piv + k];
                A[4 * piv + k] = t;
            }
            double t = r[c];
            r[c] = r[piv];
            r[piv] = t;
        }
        for (int q = c + 1; q < 4; q++) {
            double f = A[4 * q + c] / A[4 * c + c];
            for (int k = c; k < 4; k++) A[4 * q + k] -= f * A[4 * c + k];
            r[q] -= f * r[c];
        }
    }
    for (int c = 3; c >= 0; c--) {
        double v = r[c];
        for (int k = c + 1; k < 4; k++) v -= A[4 * c + k] * r[k];
        r[c] = v / A[4 * c + c];
    }
    return 1;
}

/* KKT Jacobian of the volume projection at (s, t). */
static inline void eo_pd_vol_jac(const double s[3], double t, double J[16])
{
    const double c[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) J[4 * i + j] = i == j ? 1 : -t * s[3 - i - j]; /* ∂c_i/∂s_j = s_k */
        J[4 * i + 3] = -c[i];
        J[12 + i] = c[i];
    }
    J[15] = 0;
}

/* Add the volume constraint energy with weight w and det bounds [a, b] to o. */
static inline void eo_pd_volume_add(double w, double a, double b, const double sg[3], eo_eval_what what,
                                    eo_sigma_eval *o)
{
    double det = sg[0] * sg[1] * sg[2];
    if (a < b && det >= a && det <= b) return; /* inside: s = σ, zero energy and derivatives */
    const double v = det < a ? a : b; /* the violated bound (a = b: the target) */
    double s[3] = {sg[0], sg[1], sg[2]}, t = 0, J[16];
    if (!(det > 0) && sg[0] * sg[1] > 0) s[2] = v / (sg[0] * sg[1]); /* inverted: start on C */
    const double scale = 1 + fabs(sg[0]);
    for (int it = 0; it < 60; it++) {
        double c[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
        double r[4] = {-(s[0] - sg[0] - t * c[0]), -(s[1] - sg[1] - t * c[1]), -(s[2] - sg[2] - t * c[2]),
                       -(s[0] * s[1] * s[2] - v)};
        eo_pd_vol_jac(s, t, J);
        if (!eo_pd_solve4(J, r)) break;
        double step = 0;
        for (int i = 0; i < 3; i++) {
            s[i] += r[i];
            step = fmax(step, fabs(r[i]));
        }
        t += r[3];
        if (step <= 1e-15 * scale) break;
    }
    double d0 = sg[0] - s[0], d1 = sg[1] - s[1], d2 = sg[2] - s[2];
    o->psi += 0.5 * w * (d0 * d0 + d1 * d1 + d2 * d2);
    if (what < EO_EVAL_GRAD) return;
    for (int i = 0; i < 3; i++) o->g[i] += w * (sg[i] - s[i]);
    if (what < EO_EVAL_HESS) return;
    double ds[9]; /* ds[3i+j] = ∂s_i/∂σ_j */
    for (int j = 0; j < 3; j++) {
        double r[4] = {0, 0, 0, 0};
        r[j] = 1;
        eo_pd_vol_jac(s, t, J);
        if (!eo_pd_solve4(J, r)) r[0] = r[1] = r[2] = 0;
        for (int i = 0; i < 3; i++) ds[3 * i + j] = r[i];
    }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double h = 0.5 * (ds[3 * i + j] + ds[3 * j + i]); /* symmetric in exact arithmetic */
            o->H[3 * i + j] += w * ((i == j) - h);
        }
    for (int p = 0; p < 3; p++) {
        double tk = t * s[eo_pd_pk[p]];
        o->twist[p] += w * tk / (1 + tk);
        o->flip[p] += -w * tk / (1 - tk);
    }
}

#endif
