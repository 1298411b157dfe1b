/* The quadratic (10-node) tet, nodes in the VTK quadratic tetra order: corners 0–3, then
 * the midside nodes of edges 01, 12, 20, 03, 13, 23 (mesh.h, tet10). Straight-sided
 * (subparametric: the geometry is the corners', ∇λ constant per tet).
 *   corners  N_i = λ_i (2λ_i − 1),   edge (i, j)  N = 4 λ_i λ_j.
 * Energy quadrature: the symmetric 4-point rule of degree 2 (points a, b, b, b and
 * permutations, a = (5 + 3√5)/20, b = (5 − √5)/20, weights 1/4), exact for the stiffness
 * ∫ ∇Nᵀ C ∇N of linear elasticity (degree 2) and for the volume, so the patch tests hold
 * exactly; for nonlinear ψ it is the usual reduced rule (Zienkiewicz & Taylor).
 * Consistent mass (exact, degree 4, integrated symbolically): ρV/420 ·
 *   corner–corner 6 (diagonal) / 1, corner–edge −4 (edge through the corner) / −6,
 *   edge–edge 32 (diagonal) / 16 (edges sharing a corner) / 8 (opposite edges).
 * Lumped mass: the HRZ row scaling of that diagonal (Hinton, Rock & Zienkiewicz 1976),
 * ρV/36 on each corner and 4ρV/27 on each midside node, positive and summing to ρV (the
 * row sums are not positive: −ρV/20 at corners). Load ∫N_a dV = −V/20 (corners), V/5
 * (midside nodes): gravity's load with the consistent mass (with the lumped mass it is
 * the lumped masses times g, so that a free body falls uniformly). */
#include "elastopt/element.h"

static const int edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

static void shape(const double l[4], double *N, double *dN)
{
    if (dN)
        for (int k = 0; k < 40; k++) dN[k] = 0;
    for (int i = 0; i < 4; i++) {
        if (N) N[i] = l[i] * (2 * l[i] - 1);
        if (dN) dN[4 * i + i] = 4 * l[i] - 1;
    }
    for (int e = 0; e < 6; e++) {
        const int i = edge[e][0], j = edge[e][1];
        if (N) N[4 + e] = 4 * l[i] * l[j];
        if (dN) {
            dN[4 * (4 + e) + i] = 4 * l[j];
            dN[4 * (4 + e) + j] = 4 * l[i];
        }
    }
}

#define A_ 0.5854101966249685
#define B_ 0.1381966011250105
static const double qp[16] = {A_, B_, B_, B_, B_, A_, B_, B_, B_, B_, A_, B_, B_, B_, B_, A_};
static const double qw[4] = {0.25, 0.25, 0.25, 0.25};
#define M_(v) ((v) / 420.0)
static const double mass[100] = {
    M_(6),  M_(1),  M_(1),  M_(1),  M_(-4), M_(-6), M_(-4), M_(-4), M_(-6), M_(-6),
    M_(1),  M_(6),  M_(1),  M_(1),  M_(-4), M_(-4), M_(-6), M_(-6), M_(-4), M_(-6),
    M_(1),  M_(1),  M_(6),  M_(1),  M_(-6), M_(-4), M_(-4), M_(-6), M_(-6), M_(-4),
    M_(1),  M_(1),  M_(1),  M_(6),  M_(-6), M_(-6), M_(-6), M_(-4), M_(-4), M_(-4),
    M_(-4), M_(-4), M_(-6), M_(-6), M_(32), M_(16), M_(16), M_(16), M_(16), M_(8),
    M_(-6), M_(-4), M_(-4), M_(-6), M_(16), M_(32), M_(16), M_(8),  M_(16), M_(16),
    M_(-4), M_(-6), M_(-4), M_(-6), M_(16), M_(16), M_(32), M_(16), M_(8),  M_(16),
    M_(-4), M_(-6), M_(-6), M_(-4), M_(16), M_(8),  M_(16), M_(32), M_(16), M_(16),
    M_(-6), M_(-4), M_(-6), M_(-4), M_(16), M_(16), M_(8),  M_(16), M_(32), M_(16),
    M_(-6), M_(-6), M_(-4), M_(-4), M_(8),  M_(16), M_(16), M_(16), M_(16), M_(32),
};
static const double lumped[10] = {1 / 36.0, 1 / 36.0, 1 / 36.0, 1 / 36.0, 4 / 27.0,
                                  4 / 27.0, 4 / 27.0, 4 / 27.0, 4 / 27.0, 4 / 27.0};
static const double load[10] = {-0.05, -0.05, -0.05, -0.05, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2};

const eo_element_type eo_element_p2 = {
    .info = {.name = "p2", .summary = "quadratic 10-node tet (midside nodes per edge; 4-point degree-2 rule)"},
    .nodes = 10,
    .nq = 4,
    .qp = qp,
    .qw = qw,
    .degree = 2,
    .shape = shape,
    .mass = mass,
    .lumped = lumped,
    .load = load,
};

/* P2–P0: the same nodes, shape functions, quadrature and masses, with the volume
 * constraint enforced once per tet by the mean dilatation (element.h,
 * EO_ELEMENT_MEAN_DILATATION). P2–P0 is inf-sup stable (Boffi, Brezzi & Fortin 2013,
 * §8.6), so it does not lock as ν → 0.5, where p2 does (tests/test_element.c). */
const eo_element_type eo_element_p2p0 = {
    .info = {.name = "p2p0", .summary = "10-node tet with a constant pressure per tet (mean dilatation): no locking"},
    .nodes = 10,
    .flags = EO_ELEMENT_MEAN_DILATATION,
    .nq = 4,
    .qp = qp,
    .qw = qw,
    .degree = 2,
    .shape = shape,
    .mass = mass,
    .lumped = lumped,
    .load = load,
};
