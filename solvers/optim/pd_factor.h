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
 * shared shift loop (solvers/hessfix/shift_loop.c; the selected fix's shift_* parameters). Nothing is allocated in solve. */
#ifndef EO_OPTIM_PD_FACTOR_H
#define EO_OPTIM_PD_FACTOR_H

#include "elastopt/solver.h"
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
