/// @file solver.h
/// Optimizers, Hessian fixes, line searches and stopping rules, each chosen by name: the
/// user API (options, create, minimize, results, profile). Writing a method (its ops
/// table, eo_solver_ctx, the stopping test) is in <elastopt/impl/method.h>; the
/// built-in methods' parameter structs, for code that fills them directly, in
/// <elastopt/impl/params.h> (everyone else sets them through the config).
///
/// The solver of one step problem is assembled from four pluggable pieces:
///   solver.optimizer   newton, newton_tr, gradient_descent, lbfgs, bcqn, ncg,
///                      projective_dynamics, pd_local_global, fixed_point, vbd,
///                      jacobi_chebyshev, admm_pd, aqp, mixed_fem
///                                                               (eo_optimizer_type)
///   solver.hessian_fix none, shift, clamp, abs, project_on_demand,
///                      progressive, trust_region_filter         (eo_hessfix_type)
///   solver.linesearch  backtracking, nonmonotone, wolfe, exact, barrier_filter, none
///                                                               (eo_linesearch_type)
///   solver.stop        relative_decrement, newton_decrement, gradient,
///                      characteristic_gradient                  (eo_stop_type)
///   solver.linear      cholmod, cholmod_ldlt, ...               (eo_linsolve_type)
/// solver.linesearch defaults to `auto`: the optimizer's own choice
/// (eo_optimizer_type.linesearch): `wolfe` for lbfgs and ncg, `barrier_filter` for bcqn,
/// `backtracking` for newton,
/// gradient_descent and projective_dynamics (and for a plug-in that names none); the
/// solver echoes the resolved name. wolfe's curvature constant c2 then defaults to the
/// optimizer's preference (0.9 lbfgs, 0.1 ncg; eo_ls_extra.c2) and it hands back ∇g of
/// the accepted point (one value+gradient call per trial). Any registered line search
/// can still be named explicitly.
/// plus solver.tol, solver.max_iters, solver.time_budget (eo_solver_opts), and each
/// method's parameters live in config section `solver.<method name>` (e.g.
/// `solver.backtracking.c1`, `solver.shift.shift_init`, `solver.lbfgs.history`). Sections
/// of methods that are registered but not selected are read and checked too, so one
/// config may carry settings for several methods and switch with `-o solver.optimizer=...`.
///
/// ```c
/// eo_solver_opts o; eo_solver_opts_default(&o);
/// rc = eo_solver_opts_load(ctx, cfg, &o);                  // section "solver" (cfg may be NULL)
/// eo_solver *s; rc = eo_solver_create(ctx, &o, cfg, &s);     // + sections solver.<name>
/// eo_solve_result r;
/// rc = eo_solver_minimize(s, obj, x, on_iter, user, &r);   // x: start in, minimizer out
/// printf("%s after %d iterations\n", eo_reason_string(r.reason), r.iterations);
/// eo_solver_destroy(&s);
/// ```
/// Ownership: the solver copies opts and all params; the objective and x are borrowed
/// for the duration of minimize. A solver is created without knowing the problem size:
/// the optimizer's workspace is sized at the first minimize and again whenever obj->n
/// differs from the previous call (a released boundary set), so one solver serves every
/// step of a simulation. No allocation happens inside the iterations; the only exception
/// is Newton's first iteration on a Hessian whose pattern it has not seen
/// (eo_linsolve_analyze, once per pattern).
///
/// The convergence measure. Every optimizer tests its iterates through
/// eo_solver_stop_check, so `solver.tol` means the same accuracy whichever runs:
///  - progress is relative to the start x₀ of the minimization (each time step starts
///    one) and measured the same way for all: by the Newton decrement λ_k/λ_0
///    (λ² = −∇gᵀp = ‖p‖²_H) for optimizers whose direction is a Newton direction
///    (eo_optimizer_type.newton_decrement: newton), by the metric gradient norm
///    ‖∇g_k‖_{D⁻¹}/‖∇g_0‖_{D⁻¹} (D the objective's metric, the lumped mass) for every
///    other one. Both estimate ‖x_k − x*‖ relative to the step's motion ‖x_0 − x*‖; the
///    gradient ratio bounds it from above where H ≥ D (stiff modes weigh more), so a
///    first-order method is never declared converged further from x* than Newton.
///  - an absolute floor tied to the rounding level at x₀: λ²/2 (or ‖∇g‖²_{D⁻¹}/2) below
///    EO_STOP_FLOOR·ε²·s, s the objective's rounding scales (objective.h), is converged:
///    a step that starts at (or reaches) its minimizer, a body at rest, converges.
///  - no optimizer is declared converged without measuring its own progress: where no
///    first decrement exists the ratio is of gradients, never an absolute test.
/// The rules (solver.stop; tol = solver.tol, default 1e-10):
///  - relative_decrement (the default): the measure above ≤ tol; for Newton also
///    converged at the plateau, λ²/2 ≤ plateau·max(|g(x₀)|, |g|) (1e-16) with λ² no longer
///    falling (λ_k² > λ_{k−1}²/4), where g cannot resolve further progress. With
///    tol = 1e-10 the static StVK cantilever's tip is within 3.7e-11 and the dynamic
///    cantilever's after 50 steps within 2.3e-10 of the converged answer; at tol = 1e-8
///    newton, newton_tr, lbfgs, ncg, gradient_descent and projective_dynamics all end
///    within 4e-9 of the motion on the first cantilever step (tests/test_converge.c).
///    Linearly converging methods need many iterations for 1e-10: give them a looser tol.
///  - newton_decrement: λ²/2 = −∇gᵀp/2 ≤ tol, in the units of g (for the step objective
///    ½‖x − x̃‖²_M + w E, kg·m²). λ²/2 estimates g(x) − g*, so tol = 1e-10 means
///    ‖x − x*‖_H ≲ √(2·tol) ≈ 1.4e-5 m·√kg.
///  - gradient: ‖∇g‖₂ ≤ tol·max(‖∇g(x₀)‖₂, floor) (relative to the start of this
///    minimization).
///  - characteristic_gradient: ‖∇g‖₂ ≤ tol·g_c, g_c the objective's characteristic
///    gradient norm (objective.h, characteristic; Zhu, Bridson & Kaufman 2018): an
///    absolute test in the units of ∇g, independent of the start; the paper's tol is 1e-3.
///    Objectives without g_c: relative to ‖∇g(x₀)‖₂ as `gradient`.
#ifndef ELASTOPT_SOLVER_H
#define ELASTOPT_SOLVER_H

#include "config.h"
#include "export.h"
#include "linsolve.h"
#include "objective.h"

#ifdef __cplusplus
extern "C" {
#endif

/// What one iteration reports (to the CSV log and the benchmark recorder).
///
/// Record k describes the iterate x_k and what was done from it: g and ‖∇g‖ at x_k, the
/// direction computed at x_k (its decrement and the Hessian shift used for it) and the
/// line search from x_k along it (α, evaluations). The last record (reason ≠ 0) has
/// α = NAN and, if the run stopped before a direction was computed, decrement = NAN.
/// A callback that returns non-zero stops the run before the step of its record is
/// accepted (reason EO_DIVERGED_EXTERNAL; x out = that record's x_k).
typedef struct eo_iter_info {
    int iteration;        ///< 0 = the start point, then 1, 2, ...
    double time;          ///< seconds since the start of this minimization
    double g;             ///< objective at x_k
    double grad_norm;     ///< ‖∇g(x_k)‖₂
    double decrement;     ///< λ²/2 = −α₀∇gᵀp/2 of the direction computed at x_k (NAN if none)
    double alpha;         ///< step length accepted from x_k (NAN on the last record)
    int ls_evals;         ///< objective evaluations in the line search from x_k
    double shift;         ///< Hessian shift c used for the direction (0 if none)
    double projected;     ///< fraction of elements whose Hessian the Hessian fix projected
                          ///< for the direction (0 for optimizers without a fix)
    int inverted;         ///< inverted elements at x_k (-1 if unknown)
    int reason;           ///< reason if this is the last iteration, else 0
    const double *x;      ///< the iterate x_k (borrowed, valid during the callback)
    /// Inexact Newton (solver.newton.forcing ≠ none): forcing term η_k = relative inner
    /// tolerance given to the iterative linear solver for the direction (0 if none).
    double eta;
    int lin_iters;        ///< iterations of the last inner linear solve (0 direct/none)
    /// 1 if the inner CG met non-positive curvature pᵀHp ≤ 0 for this direction (the
    /// Hessian fix then used another system: `none` the clamp-projected one, `shift` a
    /// larger shift, ...); the offending CG direction is never used.
    int neg_curvature;
    /// CPU seconds of the calling thread since the start of this minimization
    /// (eo_cputime; filled by eo_solver_report like `time`).
    double cpu_time;
} eo_iter_info;

/// Callback after every iteration; return non-zero to stop (reason EO_DIVERGED_EXTERNAL).
typedef int (*eo_iter_fn)(const eo_iter_info *info, void *user);

typedef struct eo_solver eo_solver;

/// Result of one minimization.
typedef struct eo_solve_result {
    int reason;           ///< eo_reason
    int iterations;       ///< accepted steps
    double g, grad_norm, decrement;  ///< at the returned x (decrement NAN if not computed)
    double time;          ///< seconds
    long n_value, n_gradient, n_hessian, n_factor;  ///< calls during this minimization
    int status;           ///< eo_status of the last library call (0 unless an error)
    long n_fallback;      ///< directions replaced by the (scaled) steepest descent one
                          ///< (newton + hessian_fix none; lbfgs memory resets; ncg
                          ///< restarts because p was not a descent direction)
    long n_shifted;       ///< newton iterations whose direction needed a shift c > 0
                          ///< (the fix for `shift`, the safeguard for clamp/abs)
    double projected;     ///< mean over the directions of this minimization of the
                          ///< fraction of elements projected (0 if none computed)
    long n_inner;         ///< inner iterations (newton_tr: CG iterations; else 0)
    long n_negcurv;       ///< newton_tr: inner solves that met negative curvature dᵀHd ≤ 0
                          ///< and stepped to the trust-region boundary along d (else 0)
    long lin_iters;       ///< newton: inner linear-solver iterations, summed (0 direct)
    long n_neg_curvature; ///< newton: directions whose inner CG met pᵀHp ≤ 0 (handled by
                          ///< the Hessian fix, see eo_iter_info.neg_curvature)
    /// Timers of this minimization (wall seconds) kept by the optimizers that know the
    /// phase (the descent loop, newton); 0 where not measured. Linear-solver times come
    /// from eo_linsolve_stats; eo_solver_get_profile adds both up.
    double t_assembly;    ///< Hessian assembly (objective hessian calls for directions)
    double t_linesearch;  ///< inside the line search, its objective evaluations included
    double t_gradient;    ///< gradient evaluations outside the line search
    long n_assembly, n_ls_evals, n_gradient_outside;  ///< the calls timed above
    int decrement_estimated;  ///< 1: stopped on the decrement estimated from the previous
                              ///< factor (newton + newton_decrement), `decrement` is that
                              ///< estimate; 0: from the direction at the returned x
    long n_not_pd;        ///< factorizations of the solver's linear solver that found the matrix
                          ///< not positive definite (EO_WARN_NOT_PD; for project_on_demand the
                          ///< directions that fell back to the projected Hessian), counted
                          ///< by eo_solver_minimize from eo_linsolve_stats.n_not_pd
    /// CPU seconds of the calling thread (eo_cputime) for the same spans: the whole
    /// minimization (set by eo_solver_minimize) and the timed phases above.
    double cpu_time;
    double c_assembly, c_linesearch, c_gradient;
} eo_solve_result;

/// Where a solver's time went: wall seconds (t_*), CPU seconds of the calling thread
/// (c_*, eo_cputime: the same spans) and counts accumulated over every
/// eo_solver_minimize since eo_solver_create or eo_solver_reset_profile (read with
/// eo_solver_get_profile). The parts do not overlap; eo_profile_other is the rest
/// (stopping tests, Hessian-fix bookkeeping, vector updates, callbacks).
typedef struct eo_profile {
    long minimizations;   ///< eo_solver_minimize calls
    long iterations;      ///< accepted steps
    double t_total;       ///< inside eo_solver_minimize
    double t_assembly;    ///< Hessian assembly (element kernels + scatter)
    double t_analyze;     ///< symbolic factorization (eo_linsolve_analyze)
    double t_factor;      ///< numeric factorization (eo_linsolve_factor)
    double t_solve;       ///< solves (eo_linsolve_solve)
    double t_linesearch;  ///< line searches, their value/gradient calls included
    double t_gradient;    ///< gradients outside the line search (start point, accepted point)
    long n_assembly, n_analyze, n_factor, n_solve, n_ls_evals, n_gradient;
    long n_not_pd;        ///< numeric factorizations that found the matrix not positive definite
    /// the t_* spans in CPU seconds of the calling thread (eo_cputime)
    double c_total, c_assembly, c_analyze, c_factor, c_solve, c_linesearch, c_gradient;
} eo_profile;

/// The solver's accumulated profile (borrowed, updated by every minimize).
EO_API const eo_profile *eo_solver_get_profile(const eo_solver *s);
/// Zero the accumulated profile.
EO_API void eo_solver_reset_profile(eo_solver *s);
/// out = a − b field by field (the profile of what happened between two snapshots).
EO_API void eo_profile_diff(const eo_profile *a, const eo_profile *b, eo_profile *out);
/// t_total minus the timed parts.
EO_API double eo_profile_other(const eo_profile *p);
/// The CPU view of a profile: *out = *p with every t_* replaced by its c_* (so that
/// eo_profile_other and eo_profile_iteration_ratio give CPU figures).
EO_API void eo_profile_cpu_view(const eo_profile *p, eo_profile *out);
/// Seconds per iteration over seconds per numeric factorization:
/// (t_total / iterations) / (t_factor / n_factor); NAN without iterations or factors.
EO_API double eo_profile_iteration_ratio(const eo_profile *p);

/// Solver choice: config section `solver` (descriptor eo_solver_opts_desc).
typedef struct eo_solver_opts {
    char optimizer[32];    ///< registered optimizer (default "newton")
    char hessian_fix[32];  ///< registered Hessian fix (default "project_on_demand")
    char linesearch[32];   ///< registered line search, or "auto" (default): the
                           ///< optimizer's choice (eo_optimizer_type.linesearch),
                           ///< replaced by the resolved name in eo_solver_get_opts
    char stop[32];         ///< registered stopping rule (default "relative_decrement")
    char linear[32];       ///< registered linear solver (default "auto": the policy by size), used only by
                           ///< optimizers that solve systems (newton, projective_dynamics)
    double tol;            ///< stopping tolerance, see the file comment (default 1e-10)
    int max_iters;         ///< iteration cap → EO_DIVERGED_MAX_ITERS (default 100)
    double time_budget;    ///< seconds per minimization, 0 = none (default 0)
    /// "native" (default) or "petsc": run `optimizer` distributed with the PETSc / MPI
    /// backend: under mpirun each rank minimizes its part of the step problem with the
    /// library's optimizer on distributed vectors (objective.h eo_vspace; optimizers, Hessian
    /// fixes, line searches and stopping rules with EO_METHOD_DISTRIBUTED, the others are
    /// refused by eo_solver_create), `linear` = auto meaning the backend's petsc_ksp; the
    /// backend's own snes_* and tao_* optimizers run as they are. The backend is a module
    /// the CLI loads when built with -Dpetsc (docs/petsc.md); without it eo_solver_create
    /// fails with EO_ERR_UNKNOWN_NAME naming petsc_ksp.
    char backend[16];
    /// 1: the linear solver keeps what it learnt from one minimization to the next (pcg's
    /// cholmod_reuse factor, hence `auto` from reuse_min unknowns; the PETSc backend's GAMG
    /// interpolation): fewer factorizations (twist at 85k unknowns, 10 steps: 12 % less
    /// CPU), but a time step then depends on the steps before it, and `--restart` no
    /// longer continues bit for bit. 0 (default): eo_linsolve_forget at every
    /// minimization.
    int carry_linear;
} eo_solver_opts;
EO_API extern const eo_param_desc eo_solver_opts_desc[];

/// Defaults of every field.
EO_API void eo_solver_opts_default(eo_solver_opts *o);
/// Load config section `solver` into o (keys of eo_solver_opts_desc; the names of all
/// registered solver methods are accepted as sub-sections, read by eo_solver_create;
/// anything else is EO_ERR_UNKNOWN_KEY). cfg NULL: no-op.
EO_API int eo_solver_opts_load(eo_ctx *ctx, eo_cfg *cfg, eo_solver_opts *o);
/// Resolve every name (EO_ERR_UNKNOWN_NAME listing the valid ones), load each method's
/// params from `solver.<name>` (cfg may be NULL: defaults), check the sections of the
/// registered but unselected methods too and create the linear solver if the optimizer
/// needs one. The problem size is not needed: the workspace is sized lazily by
/// eo_solver_minimize. opts NULL = defaults; copied.
/// Returns EO_OK, EO_ERR_UNKNOWN_NAME, EO_ERR_UNKNOWN_KEY, EO_ERR_TYPE, EO_ERR_RANGE,
/// EO_ERR_INVALID, EO_ERR_NOMEM.
EO_API int eo_solver_create(eo_ctx *ctx, const eo_solver_opts *opts, eo_cfg *cfg, eo_solver **out);
/// Minimize obj from x (obj->n values, in/out); (re)sizes the optimizer's workspace
/// when obj->n differs from the previous call. on_iter may be NULL. Returns EO_OK with
/// the reason in res (negative reasons are not errors), or a negative status
/// (EO_ERR_INVALID for no objective, an objective error, EO_ERR_NOMEM).
EO_API int eo_solver_minimize(eo_solver *s, eo_objective *obj, double *x, eo_iter_fn on_iter,
                       void *user, eo_solve_result *res);
/// The references of the relative convergence measure for the NEXT eo_solver_minimize
/// only (then cleared): that minimization compares its decrement with max(its own first
/// λ²/2, decrement0) and its metric gradient norm with max(its own ‖∇g(x₀)‖_{D⁻¹},
/// grad_metric0) instead of its own alone (0 or NAN: its own). For a minimization that
/// continues another one's work from a better point (the fallback chain with
/// solver.fallback_start = best): the tolerance stays relative to the step's start, not to
/// the point where the continuation began (measured: newton_tr continuing on the inverted
/// bunny reached the rounding floor of ∇g, 1e-8 of the step's ‖∇g₀‖, but not 1e-10 of its
/// own start's and wandered 40 iterations to diverged_stagnated).
EO_API void eo_solver_set_reference(eo_solver *s, double decrement0, double grad_metric0);
/// The references the last eo_solver_minimize measured against (the larger of its own
/// and the ones given by eo_solver_set_reference; NAN before any or where not measured).
EO_API void eo_solver_get_reference(const eo_solver *s, double *decrement0, double *grad_metric0);
/// Free; sets *s = NULL; accepts NULL.
EO_API void eo_solver_destroy(eo_solver **s);
/// The options in use (borrowed).
EO_API const eo_solver_opts *eo_solver_get_opts(const eo_solver *s);
/// The linear solver (borrowed; NULL if the optimizer needs none), e.g. for its stats.
EO_API eo_linsolve *eo_solver_get_linsolve(const eo_solver *s);
/// Echo of the effective configuration: the `solver` section with the selected
/// methods' parameter sections. New reference (NULL on out of memory).
EO_API json_t *eo_solver_to_json(const eo_solver *s);
#ifdef __cplusplus
}
#endif
#endif
