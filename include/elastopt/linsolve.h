/// @file linsolve.h
/// Linear solvers for symmetric systems A x = b, chosen by name (`solver.linear`).
///
/// Phases as in CHOLMOD: `analyze` once per sparsity pattern (ordering, symbolic
/// factorization), `factor` at every Newton iteration (numeric values changed, pattern
/// not), `solve` any number of times. Iterative methods (cg, pcg, jacobi, ...) do their
/// set-up in `factor` and iterate in `solve`.
///
/// `factor` returns EO_WARN_NOT_PD (positive) when the matrix is found not positive
/// definite (direct Cholesky: the failing column, in the matrix's own numbering, is in
/// `stats.not_pd_column` and in the context message "column j: ..."), so a Hessian fix
/// can react by shifting and factoring again. Iterative methods report what they find
/// in `solve`: cg/pcg return EO_WARN_NOT_PD on non-positive curvature pᵀAp <= 0;
/// every iterative method returns EO_WARN_NOT_CONVERGED (stats.residual set) when it
/// hits its iteration cap, diverges or produces non-finite values. They never loop
/// without bound and never allocate in `solve` (workspace is sized in `analyze`).
///
/// Registered methods (config `solver.linear = "<name>"`, parameters
/// `solver.<name>.<key>`; `elastopt list` / `--help` show keys and defaults):
///   auto (the default: a policy by size, see solvers/linsys/auto.c), cholmod (supernodal LLᵀ), cholmod_ldlt (simplicial LDLᵀ), spqr (sparse QR of the
///   full matrix), umfpack (sparse LU of the full matrix), lapack (dense Cholesky, small
///   n), lapack_lu (dense LU), lapack_ldlt (dense Bunch–Kaufman LDLᵀ with inertia), cg,
///   pcg (Jacobi, IC(0), reused CHOLMOD factor, BoomerAMG when built with hypre, Galerkin
///   multigrid), gmres (restarted GMRES(m) for indefinite systems), jacobi, gauss_seidel,
///   sor, gmg (Galerkin geometric multigrid V-cycles, Xian et al. 2019, from the node
///   coordinates).
///
/// Optional ops (a method that lacks one accepts the call and ignores it):
///   eo_linsolve_set_rtol        inner tolerance of an inexact Newton (Eisenstat–Walker
///                               forcing term η_k); iterative methods only
///   eo_linsolve_set_coordinates node coordinates, for the rigid-body near-null space of
///                               algebraic multigrid (pcg with preconditioner amg) and the
///                               coarse grids of gmg (solver and pcg preconditioner)
///
/// ```c
/// eo_linsolve *ls; eo_linsolve_create(ctx, type, params, &ls);
/// eo_linsolve_analyze(ls, A);         // once per pattern
/// rc = eo_linsolve_factor(ls, A);     // per iteration; rc == EO_WARN_NOT_PD possible
/// eo_linsolve_solve(ls, b, x);
/// eo_linsolve_destroy(&ls);
/// ```
/// Ownership: A is borrowed for the lifetime of the factorization (iterative solvers
/// keep the pointer to apply it); b and x are caller arrays of length A->n; params are
/// copied at create. On input x is ignored unless the method's `warm_start` is set.
#ifndef ELASTOPT_LINSOLVE_H
#define ELASTOPT_LINSOLVE_H

#include "export.h"
#include "registry.h"
#include "sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Statistics of the last solve.
typedef struct eo_linsolve_stats {
    int iterations;      ///< iterative methods: iterations of the last solve (direct: 0)
    double residual;     ///< relative residual ‖b − Ax‖/‖b‖ of the last solve; -1 if not computed
    int not_pd_column;   ///< column where positive definiteness failed, -1 if none
    double t_analyze, t_factor, t_solve;  ///< accumulated seconds
    long n_factor, n_solve;
    /// cg/pcg/gmres: the curvature pᵀAp <= 0 met in the last solve (EO_WARN_NOT_PD),
    /// 0 if none. The direction is never used: x is the last iterate before it.
    double curvature;
    /// lapack_ldlt (and other inertia-revealing factorizations): number of negative and
    /// zero eigenvalues of A at the last factor; -1 if the method does not know.
    int n_negative, n_zero;
    /// pcg with a reused factor (cholmod_reuse): numeric refactorizations done so far.
    long n_refactor;
    long n_analyze;      ///< analyze calls (symbolic factorizations) so far
    /// factorizations that reported EO_WARN_NOT_PD so far (expected or not, see
    /// eo_linsolve_set_expect_not_pd)
    long n_not_pd;
    double c_analyze, c_factor, c_solve;  ///< the t_* spans in CPU seconds (eo_cputime)
} eo_linsolve_stats;

typedef struct eo_linsolve_type {
    eo_method_info info;
    size_t state_size;   ///< private state, zeroed and allocated with the object
    int (*setup)(void *st, const void *params, eo_ctx *ctx);            ///< may be NULL
    int (*analyze)(void *st, const eo_csc *A, eo_ctx *ctx);
    int (*factor)(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx);
    int (*solve)(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx);
    void (*destroy)(void *st, eo_ctx *ctx);                              ///< may be NULL
    /// Optional: relative residual target of the next solves (overrides `tol`).
    void (*set_rtol)(void *st, double rtol);
    /// Optional: coordinates of the nv nodes whose dofs are 3i, 3i+1, 3i+2 (copied).
    int (*set_coordinates)(void *st, int nv, const double *xyz, eo_ctx *ctx);
    /// Optional: 1 if solves are iterative (they honour set_rtol), 0 if direct. Without
    /// it a method is iterative exactly when it has set_rtol.
    int (*is_iterative)(const void *st);
    /// Optional: what the method does, in words (e.g. the choice of a policy), into buf
    /// (snprintf semantics). Without it eo_linsolve_describe gives the method's name.
    int (*describe)(const void *st, char *buf, size_t size);
    /// Optional (types with EO_METHOD_DISTRIBUTED): the vector space (objective.h) of the
    /// next matrices and vectors: a distributed space means that A holds this part's
    /// terms only (the parts' matrices add up to the whole) and b, x are complete at every
    /// copy; NULL: the ordinary one. Appended last.
    int (*set_space)(void *st, const struct eo_vspace *space, eo_ctx *ctx);
    /// Optional: forget what was learnt from earlier matrices (a factor kept for reuse,
    /// multigrid interpolation kept between set-ups); keep the symbolic analysis. The
    /// next factor call is then as the first after analyze. Appended last.
    void (*forget)(void *st);
} eo_linsolve_type;

typedef struct eo_linsolve eo_linsolve;

/// Create a solver of `type` with `params` (the type's params struct, copied; NULL =
/// defaults of its descriptor table; checked against the table's ranges).
/// Returns EO_OK, EO_ERR_RANGE / EO_ERR_UNKNOWN_NAME (bad params), EO_ERR_NOMEM.
EO_API int eo_linsolve_create(eo_ctx *ctx, const eo_linsolve_type *type, const void *params,
                       eo_linsolve **out);
/// Free; sets *ls = NULL; accepts NULL.
EO_API void eo_linsolve_destroy(eo_linsolve **ls);
/// Symbolic phase for the pattern of A (values ignored). Call again if the pattern
/// changes. EO_OK, EO_ERR_INVALID, EO_ERR_NOMEM, EO_ERR_UNSUPPORTED (e.g. lapack n >
/// max_n), EO_ERR_LINSOLVE.
EO_API int eo_linsolve_analyze(eo_linsolve *ls, const eo_csc *A);
/// Numeric phase for A (same pattern as at analyze). EO_OK, EO_WARN_NOT_PD (column in
/// stats.not_pd_column), EO_ERR_INVALID (pattern changed / not analyzed), EO_ERR_*.
EO_API int eo_linsolve_factor(eo_linsolve *ls, const eo_csc *A);
/// A failed factorization (EO_WARN_NOT_PD) is counted in stats.n_not_pd and its message
/// ("cholmod: matrix not positive definite ...") kept as the context's message; it is
/// logged as a warning only when not expected (eo_linsolve_set_expect_not_pd) and only
/// the first time for this solver (the line says later ones are counted), later ones
/// at debug level.
///
/// Whether a not-positive-definite matrix is a normal outcome of the next factorizations
/// (on = 1: a Hessian fix factoring the true, possibly indefinite Hessian —
/// project_on_demand, shift, none — counts it silently) or a surprise (0, the default: a
/// projected Hessian, a mass or projective-dynamics matrix; warned once). Returns the
/// previous setting.
EO_API int eo_linsolve_set_expect_not_pd(eo_linsolve *ls, int on);
/// The current setting of eo_linsolve_set_expect_not_pd.
EO_API int eo_linsolve_get_expect_not_pd(const eo_linsolve *ls);
/// A solve that meets non-positive curvature (EO_WARN_NOT_PD from cg/pcg/gmres) is logged
/// like a failed factorization (silent when expected, else one warning per solver).
/// x = A⁻¹ b. EO_OK, EO_WARN_NOT_CONVERGED, EO_WARN_NOT_PD (cg/pcg; stats.curvature),
/// EO_ERR_*.
EO_API int eo_linsolve_solve(eo_linsolve *ls, const double *b, double *x);
/// Inexact Newton: make the next solves stop at ‖b − Ax‖ <= rtol ‖b‖ (0 < rtol < 1;
/// rtol <= 0 restores the method's own `tol`). Direct solvers ignore it (EO_OK).
/// Returns EO_OK or EO_ERR_RANGE (rtol >= 1 or not finite).
EO_API int eo_linsolve_set_rtol(eo_linsolve *ls, double rtol);
/// Node coordinates for methods that use the geometry (BoomerAMG's rigid-body modes, the
/// Galerkin multigrid's coarse grids; gmg without them is one level, CHOLMOD):
/// `xyz` (3 nv doubles, copied) are the positions of the nv nodes whose unknowns are
/// rows 3i, 3i+1, 3i+2 of the matrix (the step engine: its free vertices, in free
/// order, at rest or at the current iterate). Call before analyze, and again whenever
/// the free set changes. Methods without use for it ignore it (EO_OK). Where: whoever
/// holds both the step and the solver (the eo_sim driver / CLI run loop), after
/// eo_step_begin of the first step and after a release rebuilds the pattern:
/// xyz[i] = eo_step_x0(st)[eo_step_free_to_full(st, i)], nv = obj->n / 3, passed to
/// eo_linsolve_set_coordinates(eo_solver_get_linsolve(solver), nv, xyz) (as
/// bench/bench_linsolve.c does).
/// Returns EO_OK, EO_ERR_INVALID (nv < 0 or xyz NULL with nv > 0), EO_ERR_NOMEM.
EO_API int eo_linsolve_set_coordinates(eo_linsolve *ls, int nv, const double *xyz);
/// The vector space of the next analyze/factor/solve calls (objective.h, eo_vspace; NULL:
/// the ordinary one). A distributed space needs a linear solver that takes a part's
/// Hessian (flag EO_METHOD_DISTRIBUTED, e.g. the PETSc backend's petsc_ksp): others give
/// EO_ERR_UNSUPPORTED. The space is borrowed until the next call.
struct eo_vspace;
EO_API int eo_linsolve_set_space(eo_linsolve *ls, const struct eo_vspace *space);
EO_API const eo_linsolve_stats *eo_linsolve_get_stats(const eo_linsolve *ls);
/// A new problem begins: the next factor and solves must not depend on the matrices
/// factored before this call (pcg's cholmod_reuse factor, the `auto` policy's, the PETSc
/// backend's kept GAMG interpolation are rebuilt from the next matrix); the symbolic
/// analysis is kept. eo_solver_minimize calls it at the start of every minimization, so
/// that a time step's result depends on the state it starts from and nothing else (what
/// makes `elastopt run --restart` continue bit for bit). Methods that keep nothing from
/// one factor call to the next ignore it.
EO_API void eo_linsolve_forget(eo_linsolve *ls);
/// 1 if the solves are iterative (an inexact Newton's forcing term applies: set_rtol), 0
/// if they are direct (a policy such as `auto` answers for the method it chose at the
/// last analyze; 0 before any).
EO_API int eo_linsolve_is_iterative(const eo_linsolve *ls);
/// The method and what it chose, in words, into buf (NUL-terminated, truncated to size):
/// "cholmod", or for `auto` e.g. "pcg + cholmod_reuse (nesdis), n = 70623 >= reuse_min
/// 20000". Returns buf.
EO_API const char *eo_linsolve_describe(const eo_linsolve *ls, char *buf, size_t size);
/// 1 if the caller may use a CHOLMOD factor of its own instead of this solver for a
/// constant matrix (projective dynamics' prefactored matrix): the cholmod family and the
/// `auto` policy, whose choice for a matrix factored once is a direct CHOLMOD factor.
EO_API int eo_linsolve_allows_own_factor(const eo_linsolve *ls);
EO_API const eo_linsolve_type *eo_linsolve_get_type(const eo_linsolve *ls);
/// The solver's params struct (the copy it uses; borrowed).
EO_API const void *eo_linsolve_get_params(const eo_linsolve *ls);
/// Look up a registered solver by name (EO_ERR_UNKNOWN_NAME listing the valid names).
EO_API int eo_linsolve_find(eo_ctx *ctx, const char *name, const eo_linsolve_type **out);


/// A CHOLMOD LDLᵀ factor of Ã(S) = [A_SS 0; 0 diag(A_CC)] for an SPD matrix A over all n
/// variables and a free set S (C = the rest), kept current when S changes by rank
/// updates/downdates (cholmod_updown) instead of a refactorization: releasing or pinning
/// k variables costs a rank-2k change (solvers/linsys/updown.c has the construction).
/// The free block of Ã(S) is the matrix of the problem with C eliminated, so solving
/// Ã(S)x = b gives the eliminated solution on S (and b_C/A_CC on C).
/// ```c
/// eo_updown *u; eo_updown_create(ctx, A, is_free, &u);    // analyze + factor once
/// eo_updown_set_free(u, is_free2, &rank);                  // pins and releases
/// eo_updown_solve(u, b, x);
/// eo_updown_destroy(&u);
/// ```
/// A (upper-triangle CSC, every diagonal stored) and is_free (n bytes, NULL = all free)
/// are copied. Returns EO_OK, EO_ERR_INVALID (not positive definite), EO_ERR_NOMEM or
/// EO_ERR_INTERNAL (a CHOLMOD failure).
typedef struct eo_updown eo_updown;
EO_API int eo_updown_create(eo_ctx *ctx, const eo_csc *A, const unsigned char *is_free, eo_updown **out);
/// Change the free set to is_free (n bytes): pins by update+downdate, then releases.
/// *rank (may be NULL) = columns of the update/downdate matrices, 2·(changed variables).
EO_API int eo_updown_set_free(eo_updown *u, const unsigned char *is_free, int *rank);
/// Numeric refactorization of Ã(S) with the same symbolic analysis (the alternative the
/// update replaces; for tests and benchmarks).
EO_API int eo_updown_refactor(eo_updown *u);
/// x = Ã(S)⁻¹ b (n values each, distinct arrays).
EO_API int eo_updown_solve(eo_updown *u, const double *b, double *x);
/// X = Ã(S)⁻¹ B for nrhs right-hand sides at once (B, X column-major n×nrhs, distinct):
/// one pass over the factor for all of them. Allocates only when nrhs differs from the
/// previous call's (CHOLMOD's solution and workspace are kept).
EO_API int eo_updown_solve_multi(eo_updown *u, int nrhs, const double *b, double *x);
/// The matrix A of create (own copy, borrowed) and the current free set S (n bytes,
/// borrowed): what a fresh factorization of Ã(S) needs (eo_updown_create(ctx, A, S, ..)).
EO_API const eo_csc *eo_updown_matrix(const eo_updown *u);
EO_API const unsigned char *eo_updown_free_set(const eo_updown *u);
/// The factor as a dense n×n row-major matrix (permuted order; strictly lower part L,
/// diagonal D of LDLᵀ), for comparisons in tests.
EO_API int eo_updown_factor_dense(eo_updown *u, double *LD);
/// Columns passed to cholmod_updown so far.
EO_API long eo_updown_columns(const eo_updown *u);
/// Flops of a numeric factorization and nonzeros of L, from the symbolic analysis
/// (CHOLMOD's Common->fl and ->lnz): a rank-r update/downdate passes over at most r·lnz
/// entries, so r ≤ flops/lnz is where it cannot cost more than a new factorization.
EO_API void eo_updown_costs(const eo_updown *u, double *flops, double *lnz);
/// Free; sets *u = NULL; accepts NULL.
EO_API void eo_updown_destroy(eo_updown **u);

#ifdef __cplusplus
}
#endif
#endif
