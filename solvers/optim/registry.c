/* Registry of the optim folder: one line per method. */
#include "eo_build_config.h"
#include "elastopt/impl/method.h"
#include "../solver_registry.h"

extern const eo_optimizer_type eo_optimizer_fixed_point;   /* fixed_point.c */
extern const eo_optimizer_type eo_optimizer_admm_pd;       /* admm_pd.c */
extern const eo_optimizer_type eo_optimizer_aqp;           /* aqp.c */
extern const eo_optimizer_type eo_optimizer_vbd;   /* vbd.c */
extern const eo_optimizer_type eo_optimizer_jacobi_chebyshev;   /* jacobi_chebyshev.c */
extern const eo_optimizer_type eo_optimizer_mixed_fem;   /* mixed_fem.c */
#if EO_HAVE_NLOPT
extern const eo_optimizer_type eo_optimizer_nlopt;   /* nlopt.c, optional backend */
#endif
#if EO_HAVE_IPOPT
extern const eo_optimizer_type eo_optimizer_ipopt;   /* ipopt.c, optional backend */
#endif

const void *const eo_registry_optimizer[] = {
    &eo_optimizer_newton,
    &eo_optimizer_newton_tr,
    &eo_optimizer_gradient_descent,
    &eo_optimizer_lbfgs,
    &eo_optimizer_bcqn,
    &eo_optimizer_ncg,
    &eo_optimizer_projective_dynamics,
    &eo_optimizer_fixed_point,
    &eo_optimizer_pd_local_global,
    &eo_optimizer_admm_pd,
    &eo_optimizer_aqp,
    &eo_optimizer_vbd,
    &eo_optimizer_jacobi_chebyshev,
    &eo_optimizer_mixed_fem,
#if EO_HAVE_NLOPT
    &eo_optimizer_nlopt,
#endif
#if EO_HAVE_IPOPT
    &eo_optimizer_ipopt,
#endif
    NULL,
};

static int check_optimizer(eo_ctx *ctx, const void *type)
{
    const eo_optimizer_type *t = type;
    if (!t->setup || !t->minimize)
        return eo_error(ctx, EO_ERR_INVALID, "register optimizer '%s': setup and minimize are required",
                        t->info.name);
    return EO_OK;
}

eo_registry eo_reg_optimizer = EO_REGISTRY_INIT(EO_KIND_OPTIMIZER, eo_registry_optimizer, check_optimizer);
