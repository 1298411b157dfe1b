/* Registry of the optim folder: one line per method. */
#include "eo_build_config.h"
#include "elastopt/solver.h"

#if EO_HAVE_NLOPT
extern const eo_optimizer_type eo_optimizer_nlopt;   /* nlopt.c, optional backend */
#endif
#if EO_HAVE_IPOPT
extern const eo_optimizer_type eo_optimizer_ipopt;   /* ipopt.c, optional backend */
#endif

const void *const eo_registry_optimizer[] = {
    &eo_optimizer_newton,
    &eo_optimizer_gradient_descent,
    &eo_optimizer_lbfgs,
    &eo_optimizer_projective_dynamics,
#if EO_HAVE_NLOPT
    &eo_optimizer_nlopt,
#endif
#if EO_HAVE_IPOPT
    &eo_optimizer_ipopt,
#endif
    NULL,
};
