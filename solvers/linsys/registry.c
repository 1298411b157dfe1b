/* Registry of the linsys folder: one line per method. */
#include "elastopt/linsolve.h"
#include "../solver_registry.h"

extern const eo_linsolve_type eo_linsolve_auto;
extern const eo_linsolve_type eo_linsolve_cholmod;
extern const eo_linsolve_type eo_linsolve_cholmod_ldlt;
extern const eo_linsolve_type eo_linsolve_spqr;
extern const eo_linsolve_type eo_linsolve_lapack;
extern const eo_linsolve_type eo_linsolve_lapack_lu;
extern const eo_linsolve_type eo_linsolve_lapack_ldlt;
extern const eo_linsolve_type eo_linsolve_umfpack;
extern const eo_linsolve_type eo_linsolve_gmres;
extern const eo_linsolve_type eo_linsolve_cg;
extern const eo_linsolve_type eo_linsolve_pcg;
extern const eo_linsolve_type eo_linsolve_jacobi;
extern const eo_linsolve_type eo_linsolve_gauss_seidel;
extern const eo_linsolve_type eo_linsolve_sor;
extern const eo_linsolve_type eo_linsolve_gmg;

const void *const eo_registry_linsolve[] = {
    &eo_linsolve_auto,
    &eo_linsolve_cholmod,
    &eo_linsolve_cholmod_ldlt,
    &eo_linsolve_spqr,
    &eo_linsolve_lapack,
    &eo_linsolve_lapack_lu,
    &eo_linsolve_lapack_ldlt,
    &eo_linsolve_umfpack,
    &eo_linsolve_cg,
    &eo_linsolve_pcg,
    &eo_linsolve_gmres,
    &eo_linsolve_jacobi,
    &eo_linsolve_gauss_seidel,
    &eo_linsolve_sor,
    &eo_linsolve_gmg,
    NULL,
};

static int check_linsolve(eo_ctx *ctx, const void *type)
{
    const eo_linsolve_type *t = type;
    if (!t->analyze || !t->factor || !t->solve)
        return eo_error(ctx, EO_ERR_INVALID, "register linear solver '%s': analyze, factor and solve are required",
                        t->info.name);
    return EO_OK;
}

eo_registry eo_reg_linsolve = EO_REGISTRY_INIT(EO_KIND_LINSOLVE, eo_registry_linsolve, check_linsolve);
