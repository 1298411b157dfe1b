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

/// What one step did (eo_sim_step).
typedef struct eo_sim_step_result {
    int iterations;       ///< solver iterations (0 for an explicit integrator)
    int reason;           ///< eo_reason: positive converged (converged_explicit for an
                          ///< explicit step), negative not (diverged_nonfinite: stopped)
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
    /// Factorizations of this step (every entry run) that found the matrix not positive
    /// definite (eo_solve_result.n_not_pd): the default project_on_demand's fallbacks to
    /// the projected Hessian are counted here, not printed.
    long n_not_pd;
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

/// Fallback chain: `solver.fallback` is a list of solver sections; each entry is the
/// `solver` section with the keys the entry names replaced (merged recursively, so
/// `{"hessian_fix": "clamp"}` or `{"optimizer": "lbfgs", "lbfgs": {"history": 20}}`).
/// When the configuration running a step stops without converging (any diverged_*
/// reason but diverged_external, the callback's stop), the step is solved again from the
/// same starting guess with the next entry; the first that converges is kept (else the
/// last). Every entry is validated at create (errors name `solver.fallback.N`).
/// eo_sim_trial uses only the solver it is given.
///
/// One time step, the whole protocol (see the file comment). Returns EO_OK also when
/// the step did not converge (r->reason negative; diverged_nonfinite leaves the state
/// at the last finite one and does not advance t); a negative status only for errors
/// (objective, linear solver, no memory). r may be NULL.
EO_API int eo_sim_step(eo_sim *s, eo_sim_step_result *r);
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
