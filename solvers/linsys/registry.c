/* Registry of the linsys folder: one line per method. */
#include "elastopt/linsolve.h"

extern const eo_linsolve_type eo_linsolve_cholmod;
extern const eo_linsolve_type eo_linsolve_cholmod_ldlt;
extern const eo_linsolve_type eo_linsolve_spqr;
extern const eo_linsolve_type eo_linsolve_lapack;
extern const eo_linsolve_type eo_linsolve_cg;
extern const eo_linsolve_type eo_linsolve_pcg;
extern const eo_linsolve_type eo_linsolve_jacobi;
extern const eo_linsolve_type eo_linsolve_gauss_seidel;
extern const eo_linsolve_type eo_linsolve_sor;

const void *const eo_registry_linsolve[] = {
    &eo_linsolve_cholmod,
    &eo_linsolve_cholmod_ldlt,
    &eo_linsolve_spqr,
    &eo_linsolve_lapack,
    &eo_linsolve_cg,
    &eo_linsolve_pcg,
    &eo_linsolve_jacobi,
    &eo_linsolve_gauss_seidel,
    &eo_linsolve_sor,
    NULL,
};
