/// @file sim.h
/// The simulation driver: a scene, its step engine and a solver, advanced step by step.
///
/// eo_sim owns the per-step protocol that every program needs and that no program
/// should write again: build the next step's objective (eo_step_begin), for an implicit
/// integrator minimize it with the sim's solver (whose workspace follows a release of a
/// boundary set by itself) and accept the minimizer (eo_step_end), for an explicit one
/// advance (eo_step_advance); then check the new state (a non-finite position,
/// velocity, energy or force stops with EO_DIVERGED_NONFINITE and keeps the last finite
/// state) and compute the step's statistics. `elastopt run`, `check`, `bench` and the
/// tests all step through it.
///
/// ```c
/// eo_sim *sim;
/// const char *ov[] = {"time.steps=20", "solver.hessian_fix=abs", NULL};
/// rc = eo_sim_create_from(ctx, NULL, "cantilever", ov, &sim);  // everything validated
/// for (int k = 0; k < eo_sim_scene(sim)->time.steps; k++) {
///     eo_sim_step_result r;
///     if ((rc = eo_sim_step(sim, &r)) < 0) break;               // an error (ctx message)
///     printf("t = %g: %s, %d iterations\n", r.t, eo_reason_name(r.reason), r.iterations);
///     if (r.reason == EO_DIVERGED_NONFINITE) break;             // state: last finite one
/// }
/// eo_sim_destroy(&sim);
/// ```
/// Ownership: the sim owns the config document given to eo_sim_create (also when
/// create fails), the scene loaded from it, the step engine and its solver; every
/// accessor returns a borrowed pointer valid until eo_sim_destroy (the objective of
/// eo_sim_prepare until the next step, prepare, trial or state change). Solvers passed
/// to eo_sim_trial and configs passed to eo_sim_set_solver stay the caller's.
#ifndef ELASTOPT_SIM_H
#define ELASTOPT_SIM_H

#include "export.h"
#include "scene.h"
#include "solver.h"
#include "step.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_sim eo_sim;

/// Most solver configurations of one step: `solver` + up to 7 `solver.fallback` entries.
#define EO_SIM_MAX_ENTRIES 8

/// The fallback chain a scene's solver gets when its config names no `solver.fallback`
/// (an explicit `[]` turns it off; solver.backend = petsc gets it too, its entries distributed):
/// the same optimizer with the `abs` Hessian fix and 100 iterations, the scene's own
/// solver again (`{}`), then trust-region Newton with the Jacobi preconditioner and 1000.
/// Each entry is merged over the `solver` section and, with `solver.fallback_start` = best
/// (the default), continues from the best iterate so far: `abs` (|λ| per element) takes
/// full steps where the clamp-projected directions of project_on_demand are cut to
/// α ~ 1e-3 (many inverted elements); the scene's solver, from there, ends in Newton's
/// quadratic phase where `abs` alone converges linearly; `newton_tr` follows the negative
/// curvature out of the crawls (tangled states) where both projections take tiny full
/// steps. Chosen by measurement (docs/defaults.md, "Defaults that converge").
#define EO_SIM_DEFAULT_FALLBACK                                                                  \
    "[{\"hessian_fix\": \"abs\", \"max_iters\": 100}, {}, "                                      \
    "{\"optimizer\": \"newton_tr\", \"max_iters\": 1000, \"newton_tr\": {\"precond\": \"jacobi\"}}]"

/// What one step did (eo_sim_step).
typedef struct eo_sim_step_result {
    int iterations;       ///< solver iterations (0 for an explicit integrator)
    int reason;           ///< eo_reason: positive converged (EO_REASON_EXPLICIT,
                          ///< "explicit", for an explicit step: nothing solved),
                          ///< negative not (diverged_nonfinite: stopped)
    double t;             ///< time after the step (unchanged if diverged_nonfinite)
    double time;          ///< seconds spent minimizing / advancing
    double g, grad_norm;  ///< objective and ‖∇g‖ at the accepted point (NAN if explicit)
    long n_value, n_gradient, n_hessian, n_factor;  ///< evaluations of this step
    eo_step_stats stats;  ///< diagnostics of the state after the step
    /// Fallback chain (config `solver.fallback`): the configuration whose result the
    /// step kept, 0 = `solver`, k = solver.fallback[k−1] (the first that converged, or the
    /// last one tried), how many were tried and the reason each stopped with. iterations,
    /// reason, g and grad_norm are those of the kept run; time and the evaluation counts
    /// add up every run of the step.
    int entry;
    int n_entries;
    int entry_reason[EO_SIM_MAX_ENTRIES];
    int entry_iterations[EO_SIM_MAX_ENTRIES];
    /// Adaptive stepping (scene key time.adaptive, see eo_sim_step): attempts rejected
    /// (a solve that did not converge after the chain, or a non-finite new state, retried
    /// at half the size), substeps accepted (1 for a step without substeps, 0 for one
    /// undone as diverged_nonfinite) and the smallest step size tried, s (time.dt without
    /// substeps). With substeps, iterations add up the kept runs of every accepted
    /// substep, reason is the first accepted substep's that did not converge (else the
    /// last one's), g, grad_norm and the chain fields are those of the last solve, and
    /// time and the evaluation counts add up every run, rejected attempts included.
    int rejected;
    int substeps;
    double min_substep;
    /// Factorizations of this step that found the matrix not positive definite
    /// (eo_solve_result.n_not_pd, added up like the evaluation counts: every entry run and
    /// every substep attempt): the default project_on_demand's fallbacks to the projected
    /// Hessian are counted here, not printed.
    long n_not_pd;
    double cpu_time;      ///< CPU seconds of the calling thread for the same span as
                          ///< `time` (eo_solve_result.cpu_time added up; eo_cputime)
} eo_sim_step_result;

/// Create a simulation from a scene config document (eo_scene_cfg_load + the caller's
/// overrides), taken over by the sim (destroyed with it, or here on failure): loads the
/// scene, the `solver` section and every method's section, creates the solver (without
/// knowing the problem size), calls eo_cfg_finish (unknown keys are errors), and only
/// then builds the step engine in the scene's initial state. Errors: those of
/// eo_scene_load, eo_solver_create, eo_cfg_finish, eo_step_create.
EO_API int eo_sim_create(eo_ctx *ctx, eo_cfg *cfg, eo_sim **out);
/// Convenience: eo_scene_cfg_load(path, builtin) (both NULL: the built-in cantilever),
/// the NULL-terminated "key=value" overrides (may be NULL), eo_sim_create.
EO_API int eo_sim_create_from(eo_ctx *ctx, const char *path, const char *builtin,
                              const char *const *overrides, eo_sim **out);
/// Free; sets *s = NULL; accepts NULL.
EO_API void eo_sim_destroy(eo_sim **s);

/// Callback after every solver iteration of eo_sim_step (NULL: none); during a step the
/// callback can ask eo_sim_entry which configuration of the chain is running.
EO_API void eo_sim_set_iter_callback(eo_sim *s, eo_iter_fn fn, void *user);
/// The configuration eo_sim_step is running (or ran last): 0 = `solver`, k =
/// solver.fallback[k−1].
EO_API int eo_sim_entry(const eo_sim *s);
/// Number of fallback entries (config `solver.fallback`, 0 if none).
EO_API int eo_sim_n_fallback(const eo_sim *s);
/// Replace the sim's solver by one made from opts (NULL: defaults) and the method
/// sections of solver_cfg (NULL: defaults; borrowed during the call, not finished), and
/// its fallback chain by solver_cfg's `solver.fallback` (none if absent or solver_cfg
/// NULL). On error the old solver and chain stay.
EO_API int eo_sim_set_solver(eo_sim *s, const eo_solver_opts *opts, eo_cfg *solver_cfg);
/// Whether sv can solve this scene's steps (what eo_sim_set_solver and eo_sim_create
/// check for every entry): EO_OK, or EO_ERR_INVALID with the reason in the context's
/// message (an optimizer that needs the linear tet's split on another element; one that
/// cannot take contact on a scene with collisions). For callers that run a solver of
/// their own through eo_sim_trial (the benchmark).
EO_API int eo_sim_check_solver(eo_sim *s, const eo_solver *sv);

/// Fallback chain: `solver.fallback` is a list of solver sections; each entry is the
/// `solver` section with the keys the entry names replaced (merged recursively, so
/// `{"hessian_fix": "clamp"}` or `{"optimizer": "lbfgs", "lbfgs": {"history": 20}}`).
/// When the configuration running a step stops without converging (any diverged_*
/// reason but diverged_external, the callback's stop), the step is solved again with the
/// next entry, from the best iterate so far (`solver.fallback_start` = best, the default:
/// the lowest g among the starting guess and the entries' end points; its convergence is
/// measured against the step's references, eo_solver_set_reference) or from the same
/// starting guess (`guess`); the first that converges is kept (else the last). Every entry is validated at create (errors name `solver.fallback.N`).
/// eo_sim_trial uses only the solver it is given.
///
/// Adaptive stepping (scene keys time.adaptive, time.adaptive_min_fraction,
/// time.adaptive_grow_after; implicit integrators): eo_sim_step advances one nominal step
/// tₙ → tₙ + dt in substeps of dt/2^k (eo_step_set_substep; k = 0 at first and after a
/// set_state or reset, then kept from step to step). A substep that has not converged
/// after the fallback chain, or whose new state is not finite, is rejected and solved
/// again from the same state (positions, velocities, history) as two halves, recursively
/// down to the smallest size dt·adaptive_min_fraction, where it is accepted as it is
/// (not converged; a non-finite one is undone and the step stops with
/// diverged_nonfinite at the last finite state, possibly inside the nominal step). After
/// adaptive_grow_after converged substeps in a row the size doubles, up to dt and only
/// where the substeps still end on tₙ + dt: every step ends at the time a nominal step
/// ends at, so frames and restarts stay at t = n·dt. A step that converges at full size
/// does exactly what it does with adaptive stepping off, bit for bit. bdf2 takes a
/// backward Euler step after every change of size (eo_step_set_substep). A callback
/// stop (diverged_external) ends the call at once (inside the nominal step if it was in
/// a substep: the next call completes that step).
///
/// One time step, the whole protocol (see the file comment). Returns EO_OK also when
/// the step did not converge (r->reason negative; diverged_nonfinite leaves the state
/// at the last finite one and does not advance t); a negative status only for errors
/// (objective, linear solver, no memory). r may be NULL.
EO_API int eo_sim_step(eo_sim *s, eo_sim_step_result *r);
/// 1 if adaptive stepping is on (initially the scene's time.adaptive).
EO_API int eo_sim_adaptive(const eo_sim *s);
/// Turn adaptive stepping on or off for the following steps (EO_ERR_UNSUPPORTED to turn
/// it on for an explicit integrator). Off: nominal steps from the next nominal boundary.
EO_API int eo_sim_set_adaptive(eo_sim *s, int on);
/// The adaptive controller's state between steps: the substep level k (steps of
/// dt/2^k) and the converged substeps in a row. eo_sim_set_state and eo_sim_reset set
/// both to 0; to continue a run exactly, restore the state, then this, then the history
/// (a change of level invalidates a multistep history). `elastopt run` keeps them in
/// restart.dat. Set: EO_ERR_RANGE for a level outside 0..EO_STEP_MAX_SUBSTEP or one that
/// does not fit the progress through the nominal step, or a negative streak.
EO_API void eo_sim_get_adaptive_state(const eo_sim *s, int *level, int *streak);
EO_API int eo_sim_set_adaptive_state(eo_sim *s, int level, int streak);
/// The next step's objective and starting guess (obj->n free coordinates, writable)
/// without solving it; borrowed until the next step, trial or state change. A following
/// eo_sim_step or eo_sim_trial uses this objective and this guess. Either may be NULL.
EO_API int eo_sim_prepare(eo_sim *s, eo_objective **obj, double **guess);
/// Solve the NEXT step's problem from the current state without advancing: from x0
/// (obj->n values; NULL = the step's starting guess) into x (obj->n values, caller's),
/// with `solver` (NULL = the sim's) and callback fn (may be NULL). Repeated trials from
/// one state solve the same problem. Implicit integrators only (EO_ERR_UNSUPPORTED).
/// obj (may be NULL) receives the objective. Returns the minimize status.
EO_API int eo_sim_trial(eo_sim *s, eo_solver *solver, const double *x0, double *x, eo_iter_fn fn,
                        void *user, eo_objective **obj, eo_solve_result *res);

/// Back to the scene's initial state (t = 0, index 0).
EO_API int eo_sim_reset(eo_sim *s);
/// Copy the state out: positions and velocities (3·nv each, may be NULL), time, step
/// index (may be NULL).
EO_API void eo_sim_get_state(const eo_sim *s, double *x, double *v, double *t, int *index);
/// Set the state (copied); the constrained sets follow from t at the next step.
EO_API int eo_sim_set_state(eo_sim *s, const double *x, const double *v, double t, int index);

/// Restart data of a multistep integrator (bdf2: the previous state xₙ₋₁, vₙ₋₁ and a
/// valid flag, see eo_step_history_len); 0 for integrators without history.
EO_API size_t eo_sim_history_len(const eo_sim *s);
/// Copy the history out (h: eo_sim_history_len doubles). EO_ERR_UNSUPPORTED if none.
EO_API int eo_sim_get_history(const eo_sim *s, double *h);
/// Set the history (copied). eo_sim_set_state clears it (the next step is then the
/// integrator's one-step start), so restore the state first, then the history.
/// EO_ERR_UNSUPPORTED if the integrator has none, EO_ERR_RANGE for a bad valid flag.
EO_API int eo_sim_set_history(eo_sim *s, const double *h);

/// Energy watch. A scene is conservative when its integrator is dynamic and not
/// dissipative (eo_integrator_type.dissipative / is_dissipative: backward_euler, bdf2,
/// static and generalized_alpha with rho_inf < 1 are) and it has no damping, spring
/// damping or friction. After every step of a conservative scene the total energy
/// E = kinetic + potential − work of prescribed motions (eo_step_stats.total_energy) is
/// compared with its initial value E₀ (the scene's initial state, taken at create and
/// reset; a restored state keeps it):
///     growth = 1 + (E − E₀)/R,   R = max(kinetic + elastic + contact at t = 0,
///                                        m_total·|g|·L, max |W| so far),
/// L the diagonal of the rest mesh's bounding box (R is an energy scale that stays
/// positive when E₀ ≈ 0, e.g. a body at rest under gravity, and does not depend on
/// where the gravity potential's origin is). When growth exceeds EO_SIM_ENERGY_GROWTH
/// the warning text names the factor, the steps since t = 0 and the integrator, is
/// logged once (eo_log, EO_LOG_WARN) and kept, updated to each later maximum, for
/// eo_sim_energy_warning. Without gravity, prescribed motions or an initial velocity R
/// is E₀ and growth is E/E₀.
#define EO_SIM_ENERGY_GROWTH 1.5
/// The energy warning so far (borrowed, valid until the next step or reset), NULL if none.
EO_API const char *eo_sim_energy_warning(const eo_sim *s);
/// 1 if the scene is conservative in the sense above (its energy is watched).
EO_API int eo_sim_energy_conservative(const eo_sim *s);

/// Accessors (borrowed).
EO_API const eo_scene *eo_sim_scene(const eo_sim *s);
EO_API eo_step *eo_sim_step_problem(const eo_sim *s);
EO_API eo_solver *eo_sim_solver(const eo_sim *s);
EO_API eo_cfg *eo_sim_cfg(const eo_sim *s);
EO_API double eo_sim_time(const eo_sim *s);
EO_API int eo_sim_index(const eo_sim *s);
/// 1 if the scene's integrator is explicit (eo_sim_step advances without a solver).
EO_API int eo_sim_is_explicit(const eo_sim *s);

#ifdef __cplusplus
}
#endif
#endif
