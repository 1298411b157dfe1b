/* The linear (4-node) tet: N_a = λ_a, F constant per tet (notes 002 §4.2–4.3). The
 * engine evaluates it with its own per-tet kernel (eo_tet_evaluate, EO_ELEMENT_LINEAR);
 * the table's quadrature (one point, the centroid, exact for F constant) serves
 * eo_element_evaluate, which agrees with that kernel (tests/test_element.c).
 * Mass: consistent ρV/20 (1 + δ_ab) (exact), lumped ρV/4 per vertex, load V/4. */
#include "elastopt/element.h"

static void shape(const double l[4], double *N, double *dN)
{
    for (int a = 0; a < 4; a++) {
        if (N) N[a] = l[a];
        for (int j = 0; dN && j < 4; j++) dN[4 * a + j] = a == j;
    }
}

static const double qp[4] = {0.25, 0.25, 0.25, 0.25}, qw[1] = {1};
static const double mass[16] = {0.1, 0.05, 0.05, 0.05, 0.05, 0.1, 0.05, 0.05,
                                0.05, 0.05, 0.1, 0.05, 0.05, 0.05, 0.05, 0.1};
static const double quarter[4] = {0.25, 0.25, 0.25, 0.25};

const eo_element_type eo_element_p1 = {
    .info = {.name = "p1", .summary = "linear 4-node tet (constant strain; locks as nu -> 0.5)"},
    .nodes = 4,
    .flags = EO_ELEMENT_LINEAR,
    .nq = 1,
    .qp = qp,
    .qw = qw,
    .degree = 1,
    .shape = shape,
    .mass = mass,
    .lumped = quarter,
    .load = quarter,
};

/* The average-nodal-pressure linear tet (Bonet & Burton 1998): the same nodes, shape
 * functions and masses; the volume constraint moved from the tets to the vertices'
 * patches (element.h, EO_ELEMENT_NODAL_DILATATION; problems/term_elastic_nodal.c). */
const eo_element_type eo_element_p1anp = {
    .info = {.name = "p1anp", .summary = "linear tet with an average nodal pressure (Bonet & Burton 1998): no locking"},
    .nodes = 4,
    .flags = EO_ELEMENT_NODAL_DILATATION,
    .nq = 1,
    .qp = qp,
    .qw = qw,
    .degree = 1,
    .shape = shape,
    .mass = mass,
    .lumped = quarter,
    .load = quarter,
};
