/// @file linsolve.h
/// Linear solvers for symmetric systems A x = b, chosen by name (`solver.linear`).
///
/// Phases as in CHOLMOD: `analyze` once per sparsity pattern (ordering, symbolic
/// factorization), `factor` at every Newton iteration (numeric values changed, pattern
/// not), `solve` any number of times. Iterative methods (cg, pcg, jacobi, ...) do their
/// set-up in `factor` and iterate in `solve`.
///
/// `factor` returns EO_WARN_NOT_PD (positive) when the matrix is found not positive
/// definite (direct Cholesky: the failing column is in the context message), so a
/// Hessian fix can react by shifting and factoring again.
///
/// ```c
/// eo_linsolve *ls; eo_linsolve_create(ctx, type, params, &ls);
/// eo_linsolve_analyze(ls, A);         // once per pattern
/// rc = eo_linsolve_factor(ls, A);     // per iteration; rc == EO_WARN_NOT_PD possible
/// eo_linsolve_solve(ls, b, x);
/// eo_linsolve_destroy(&ls);
/// ```
/// Ownership: A is borrowed for the lifetime of the factorization (iterative solvers
/// keep the pointer to apply it); b and x are caller arrays of length A->n.
#ifndef ELASTOPT_LINSOLVE_H
#define ELASTOPT_LINSOLVE_H

#include "registry.h"
#include "sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Statistics of the last solve.
typedef struct eo_linsolve_stats {
    int iterations;      ///< iterative methods: iterations of the last solve (direct: 0)
    double residual;     ///< relative residual ‖b − Ax‖/‖b‖ of the last solve, if known
    int not_pd_column;   ///< column where positive definiteness failed, -1 if none
    double t_analyze, t_factor, t_solve;  ///< accumulated seconds
    long n_factor, n_solve;
} eo_linsolve_stats;

typedef struct eo_linsolve_type {
    eo_method_info info;
    size_t state_size;   ///< private state, zeroed and allocated with the object
    int (*setup)(void *st, const void *params, eo_ctx *ctx);            ///< may be NULL
    int (*analyze)(void *st, const eo_csc *A, eo_ctx *ctx);
    int (*factor)(void *st, const eo_csc *A, eo_ctx *ctx);
    int (*solve)(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx);
    void (*destroy)(void *st, eo_ctx *ctx);                              ///< may be NULL
} eo_linsolve_type;

typedef struct eo_linsolve eo_linsolve;

/// Create a solver of `type` with `params` (copied; NULL = defaults).
int eo_linsolve_create(eo_ctx *ctx, const eo_linsolve_type *type, const void *params,
                       eo_linsolve **out);
void eo_linsolve_destroy(eo_linsolve **ls);
int eo_linsolve_analyze(eo_linsolve *ls, const eo_csc *A);
int eo_linsolve_factor(eo_linsolve *ls, const eo_csc *A);
int eo_linsolve_solve(eo_linsolve *ls, const double *b, double *x);
const eo_linsolve_stats *eo_linsolve_get_stats(const eo_linsolve *ls);
const eo_linsolve_type *eo_linsolve_get_type(const eo_linsolve *ls);

#ifdef __cplusplus
}
#endif
#endif
