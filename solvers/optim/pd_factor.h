/* The projective-dynamics matrix factored once (internal to solvers/optim), shared by
 * projective_dynamics, lbfgs (h0 = pd) and ncg (precond = pd).
 *
 * L = the objective's constant_hessian (objective.h; for the step objective the PD
 * global matrix M + w·Σₜ Vₜ(λ+2μ)GₜᵀGₜ, problems/pd_matrix.c) or, for an objective
 * without one, ∇²g(x₀) assembled with the Hessian fix's per-element projection at the
 * first iterate of each minimization. L is copied and factored with solver.linear ONCE:
 * the factors are reused by every later minimization while the objective, the matrix
 * pointer and its version are unchanged (one factorization per constrained set of a
 * scene). If L is not positive definite it is shifted, L + cI, by the Hessian fixes'
 * shared shift loop (solvers/hessfix/shift_loop.c; the selected fix's shift_* parameters).
 * Scalar form: when L = L₁ ⊗ I₃ (eo_csc_kron_i3: every 3×3 block a multiple of I₃, as
 * the PD matrix of a mesh is) and solver.linear does not use the node geometry (no
 * set_coordinates op, i.e. not AMG), the order-n/3 matrix L₁ is factored instead and
 * every solve is three solves with it, one per coordinate (Liu, Bouaziz & Kavan 2017
 * solve their Laplacian the same way): about 1/27 of the factorization flops and 1/3 of
 * the solve flops. Measured on the standard suite's 50k-tet bar (E = 1e9, solver.linear
 * cholmod, one BLAS thread, CPU time under load): numeric factorization 0.86 s -> 0.10 s,
 * lbfgs h0 = pd to relative energy error 1e-6 (79 iterations) 1.63 s -> 0.91 s.
 * The objective's own factor: when solver.linear is a CHOLMOD method and the objective
 * offers constant_factor / constant_solve (objective.h), those are used instead (the step
 * objective's factor of L over all coordinates, kept across releases and pins by rank
 * updates/downdates, problems/step_pd.c): nothing is factored or copied here. If the
 * objective has none for its current state, or its L is not positive definite, the own
 * factor above is made (the shift loop handles the latter).
 * Nothing is allocated in solve. */
#ifndef EO_OPTIM_PD_FACTOR_H
#define EO_OPTIM_PD_FACTOR_H

#include "elastopt/impl/method.h"
#include "../hessfix/shift_loop.h"

typedef struct eo_pd_factor {
    int n;
    const char *who;          /* optimizer name for messages */
    eo_shift_ws ws;           /* the shared shift loop's workspace (saved diagonal) */
    eo_csc *A;                /* own copy of L */
    const eo_objective *obj;  /* objective whose constant_hessian A is (NULL: none reusable) */
    const eo_csc *src;
    unsigned long version;
    const eo_linsolve *ls;    /* linear solver holding the analysis of A */
    int analyzed, factored;
    int fail_reason;          /* negative reason when no usable factorization */
    double shift;             /* shift c in the factors */
    int external;             /* the objective's own factor (ops constant_factor/_solve) is used */
    int scalar;               /* A is L₁ (L = L₁ ⊗ I₃): solves go coordinate by coordinate */
    double *bs, *xs;          /* n/3 each: one coordinate of b and of the solution */
} eo_pd_factor;

/* Size for n variables (allocates the diagonal). who: name used in messages. */
int eo_pd_factor_init(eo_ctx *ctx, int n, const char *who, eo_pd_factor *f);
void eo_pd_factor_deinit(eo_ctx *ctx, eo_pd_factor *f);
/* At the start of a minimization from x: make sure f holds the factors of the current L
 * (no work if they are still valid). A failure to factor is not an error: f->factored
 * = 0 and f->fail_reason says why (EO_DIVERGED_LINSOLVE, _NOT_PD, _NONFINITE). Negative
 * return: an error status (bad matrix, objective error, no linear solver). */
int eo_pd_factor_prepare(eo_pd_factor *f, const eo_solver_ctx *sc, const double *x,
                         eo_solve_result *res);
/* r = L⁻¹ b (b and r distinct). Returns 0, or a negative reason (linear solve failed). */
int eo_pd_factor_solve(const eo_pd_factor *f, const eo_solver_ctx *sc, const double *b, double *r,
                       eo_solve_result *res);

#endif
