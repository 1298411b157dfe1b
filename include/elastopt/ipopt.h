/// @file ipopt.h
/// Constrained minimization through Ipopt (optional backend: built only when Ipopt is
/// found, EO_HAVE_IPOPT in eo_build_config.h; without it these symbols do not exist).
///
///     min_x g(x)   subject to   lower ≤ c(x) ≤ upper   (lower = upper: equality)
///
/// The registry optimizer "ipopt" solves unconstrained step problems with the elastopt
/// stopping rule; this entry point poses m general constraints and lets Ipopt's own
/// termination (its scaled KKT error ≤ tol) decide, because at a constrained optimum
/// ∇g ≠ 0 and no elastopt rule on ∇g applies. The Lagrangian Hessian Ipopt asks for is
/// σ∇²g + Σᵢ λᵢ∇²cᵢ: ∇²g from the objective (its upper CSC) and the constraint part from
/// the dense callback, summed into a DENSE lower triangle (n(n+1)/2 entries): meant for
/// small problems (notes 002 Example 1, n ≲ 1000). The Jacobian is dense m×n.
///
/// ```c
/// // min ½‖Ax‖² s.t. xᵀx = 1 (002 Example 1)
/// static const double one = 1;
/// eo_constraints con = {.m = 1, .lower = &one, .upper = &one, .value = c_val,
///                       .jacobian = c_jac, .hessian = c_hess, .data = NULL};
/// eo_solve_result res;
/// eo_ipopt_minimize_constrained(ctx, obj, &con, NULL, x, lambda, &res);
/// ```
/// Ownership: everything borrowed; workspace is allocated per call through the context
/// (Ipopt and MUMPS allocate internally, outside the context's counter).
#ifndef ELASTOPT_IPOPT_H
#define ELASTOPT_IPOPT_H

#include "export.h"
#include "objective.h"
#include "solver.h"

#ifdef __cplusplus
extern "C" {
#endif

/// m constraints lower ≤ c(x) ≤ upper on n variables.
typedef struct eo_constraints {
    int m;
    const double *lower, *upper;  ///< m bounds each (±1e19 = none)
    /// c(x) (m). EO_OK or a negative status (stops Ipopt, returned).
    int (*value)(void *data, const double *x, double *c);
    /// Dense Jacobian ∂c/∂x, m×n row-major.
    int (*jacobian)(void *data, const double *x, double *J);
    /// Dense Σᵢ λᵢ ∇²cᵢ(x), n×n row-major (the lower triangle is read). NULL: the
    /// constraints are linear (their Hessians vanish).
    int (*hessian)(void *data, const double *x, const double *lambda, double *H);
    void *data;
} eo_constraints;

typedef struct eo_ipopt_constrained_opts {
    double tol;       ///< Ipopt's tol (default 1e-10)
    int max_iter;     ///< Ipopt's max_iter (default 200)
    int print_level;  ///< Ipopt's print_level (default 0 = silent)
} eo_ipopt_constrained_opts;

EO_API void eo_ipopt_constrained_opts_default(eo_ipopt_constrained_opts *o);
/// Minimize obj (exact Hessian) subject to con from x (in: start, out: solution).
/// lambda (m, may be NULL) receives the constraint multipliers (Ipopt's sign: ∇g + Jᵀλ = 0).
/// res: reason (EO_CONVERGED_EXTERNAL on Solve_Succeeded, the mapping of ipopt.c
/// otherwise), iterations, g and ‖∇g‖ at the solution, evaluation counts, time.
/// Returns EO_OK (also when the reason is negative), EO_ERR_INVALID (m < 0, missing
/// callbacks, Ipopt rejected the problem), EO_ERR_NOMEM or the callbacks' status.
EO_API int eo_ipopt_minimize_constrained(eo_ctx *ctx, eo_objective *obj, const eo_constraints *con,
                                         const eo_ipopt_constrained_opts *opts, double *x, double *lambda,
                                         eo_solve_result *res);

#ifdef __cplusplus
}
#endif
#endif
