/* spring — a zero-mass elastic edge between points a and b (EO_MATERIAL_EDGE).
 *
 *   d = a − b, l = ‖d‖, n = d/l,   ψ = k/2 (l − L)²,
 *   ∂ψ/∂a = k(l − L) n = −∂ψ/∂b,
 *   K = ∂²ψ/∂a² = k[(1 − L/l) I + (L/l) n nᵀ],   Hessian = K ⊗ [[1, −1], [−1, 1]] (6×6,
 *   order a then b). K has eigenvalue k on n and k(1 − L/l) (twice) on n⊥, and
 *   [[1,−1],[−1,1]] has eigenvalues 0 and 2, so the projection only touches the n⊥
 *   part: clamp uses max(1 − L/l, 0), abs uses |1 − L/l| (closed form, no eigensolver).
 * At l = 0 ψ is not differentiable (n undefined): l is floored at 1e-12·max(L, 1) and
 * n = e_x when d = 0, which keeps every output finite. */
#include <math.h>
#include <string.h>

#include "elastopt/material.h"

static double edge_eval(const eo_material_coef *c, double L, const double a[3], const double b[3],
                        eo_eval_what what, eo_proj proj, double grad[6], double hess[36])
{
    double k = c->k, d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double psi = 0.5 * k * (l - L) * (l - L);
    if (what < EO_EVAL_GRAD) return psi;
    double n[3] = {1, 0, 0};
    if (l > 0)
        for (int i = 0; i < 3; i++) n[i] = d[i] / l;
    double lf = fmax(l, 1e-12 * fmax(L, 1));
    for (int i = 0; i < 3; i++) {
        grad[i] = k * (l - L) * n[i];
        grad[3 + i] = -grad[i];
    }
    if (what < EO_EVAL_HESS) return psi;
    double tan = 1 - L / lf; /* eigenvalue factor on n⊥ */
    if (proj == EO_PROJ_CLAMP) tan = fmax(tan, 0);
    else if (proj == EO_PROJ_ABS) tan = fabs(tan);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double K = k * ((i == j ? tan : 0) + (1 - tan) * n[i] * n[j]);
            hess[6 * i + j] = K;
            hess[6 * (i + 3) + j + 3] = K;
            hess[6 * i + j + 3] = -K;
            hess[6 * (i + 3) + j] = -K;
        }
    return psi;
}

const eo_material_type eo_material_spring = {
    .info = {.name = "spring", .summary = "linear spring on an edge, psi = k/2 (|xi - xj| - L)^2"},
    .flags = EO_MATERIAL_EDGE | EO_MATERIAL_INVERSION_SAFE,
    .edge_eval = edge_eval,
};
