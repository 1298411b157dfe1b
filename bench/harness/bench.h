/// @file bench.h
/// The optimizer benchmark: speed against error of solver configurations on the step
/// problems of scenes (`elastopt bench SUITE.json`).
///
/// Not part of libelastopt: the harness (bench/harness/, static library elastopt_bench,
/// linked by the CLI and the tests) spawns gnuplot and writes reports. Every step runs
/// through eo_sim (sim.h); a scene with an explicit integrator is refused at load
/// (EO_ERR_INVALID: no step problem to minimize).
///
/// A suite (JSON, loaded through config.h with descriptor tables; unknown keys are
/// errors listing the valid keys) names scenes and solver configurations. For every
/// scene the harness
///  1. advances a REFERENCE trajectory: each step solved by Newton + clamp +
///     backtracking + newton_decrement with λ²/2 ≤ ref_tol·|g(x₀)| (far tighter than any
///     configuration), giving x*ₖ and g(x*ₖ) of the step objective at each state;
///  2. for each configuration and each measured step k, from the same state (xₖ, vₖ) of
///     the reference and the same starting guess x₀, runs the configuration once as
///     warm-up (not timed, at most `warmup_iters` iterations: it pays the first-call
///     costs such as CHOLMOD's symbolic analysis) and `repeats` timed times, recording
///     every iteration through the solver's on_iter callback into preallocated arrays:
///     time, relative energy error eₖ = (g(xₖ) − g(x*)) / |g(x₀) − g(x*)|, position error
///     ‖xₖ − x*‖_M / ‖x₀ − x*‖_M (first timed repeat, the callback's own time excluded;
///     M = lumped vertex mass over the free coordinates) and ‖∇g(xₖ)‖. In these curve
///     runs the configuration's stopping rule is disabled (tol = 1e-300) and the harness
///     stops the run when e ≤ `target`; the time budget and iteration cap still apply.
///     The time of iterate k is when g(xₖ) is known: 0 for k = 0, else the time of
///     record k−1 (after the line search that produced xₖ). Time to an accuracy is the
///     time of the first iterate that meets it (never interpolated between iterates);
///  3. runs each configuration over the whole benchmark scene (its skip + steps steps,
///     from the scene's initial state) with its OWN stopping rule and the curve runs'
///     iteration cap and time budget (trajectory run: the configuration's own
///     solver.max_iters if it sets one, at most the scene's max_iters, else the scene's;
///     its own solver.time_budget if set, else the scene's), up
///     to the first step that rule does not meet, and measures the mass-weighted RMS
///     distance of its positions to the reference trajectory per frame,
///     √(Σᵥ mᵥ‖xᵥ − x*ᵥ‖² / Σᵥ mᵥ) (m). With `trajectory_start` = "window" the run
///     starts instead from the reference state before the first measured step and ends
///     after the last one (the measured window: cheap on long scenes);
///  4. for each `iter_budgets` entry k, runs each configuration over the measured window
///     (from the reference state before its first step) with exactly k iterations per
///     frame (stopping rule disabled; fewer only if the solver stops itself: line search
///     failure, stagnation at the rounding level, non-finite), recording the solve time
///     per frame and the distance to the reference trajectory (fixed.csv; the report's
///     "fixed iteration budget" table; summary.csv fixed_<k>_* columns).
/// Measured steps (`select`): "first" = the `steps` steps after `skip`; "largest_motion"
/// = the reference runs skip + horizon steps and the `steps` consecutive ones of them
/// (after `skip`) with the largest total per-step motion √(Σᵥ mᵥ‖xᵥ(tₖ₊₁) − xᵥ(tₖ)‖² / Σᵥ mᵥ)
/// are measured (consecutive, so the window runs below cost `steps` steps);
/// "largest_correction" = the same with the distance from the step's starting guess x₀
/// to its minimizer x* (mass-weighted RMS over the free vertices: the work the step
/// problem asks for; it singles out impacts, where the motion itself is not the largest).
/// reference.csv lists motion and correction of every reference step and marks the
/// measured ones.
/// Status of a configuration on a scene: converged (own rule satisfied on every step of
/// the trajectory run, within 1% of the reference motion), elsewhere (own rule
/// satisfied, but farther: another stationary point), stopped (with the first failing
/// step's reason), non-finite (the solver met a non-finite g or ∇g; `nan` counts runs
/// whose returned positions or recorded values were NaN).
/// Times: CPU seconds of the solving thread by default (`clock`: "cpu"; "wall" for
/// elapsed time; both are recorded): thread CPU time does not grow while the thread
/// waits for a core, so a shared machine changes it by a few percent where wall time
/// moved 8-9x. The harness runs the element loops serially and the CLI gives the BLAS one
/// thread, so the solving thread does all the work; with a multithreaded BLAS the report
/// warns that thread CPU time misses the BLAS threads' work (use "wall", or one BLAS
/// thread). Budgets (time_budget, `budgets`) count the same clock's seconds. Median of the
/// timed repeats with min–max spread; ratios against the suite's named baseline
/// configuration, measured in the same run.
///
/// ```c
/// eo_bench_suite *s;
/// rc = eo_bench_suite_load(ctx, "bench/smoke.json", &s);     // all checks happen here
/// eo_bench_run_opts o = eo_bench_run_opts_default();
/// o.out_dir = "out/smoke"; o.progress = my_progress;
/// eo_bench_summary sum;
/// rc = eo_bench_run(ctx, s, &o, &sum);   // writes curves.csv, summary.csv, report.md, PNGs
/// eo_bench_suite_destroy(&s);
/// ```
/// Ownership: the suite owns copies of everything it read; eo_bench_run borrows it.
///
/// Suite keys (top level; `eo_bench_opts_desc`):
///   description, repeats, baseline, target, ref_tol, ref_max_iters, max_iters,
///   time_budget, steps, skip, select, horizon, trajectory, trajectory_start,
///   warmup_iters, curve_rows, plots, ipopt_check, clock
///   thresholds  list of relative energy errors for the time table (default
///               [1e-2, 1e-3, 1e-4, 1e-6, 1e-8])
///   iter_budgets  list of iterations per frame for the fixed-budget runs (integers
///               >= 1, e.g. [1, 3, 10]; default none)
///   budgets     list of time budgets (s) for the "error reached at" table
///               (default [0.01, 0.1, 1])
///   require_converged  list of configuration names that must converge on every step
///               of every scene (exit status 1 otherwise)
///   scenes      list; each entry `eo_bench_scene_desc` (name, scene | file, steps, skip,
///               select, horizon, trajectory_start, time_budget, max_iters, repeats,
///               optional, stratum) + "iter_budgets": a subset of the suite's list run on this
///               scene (default all) + "set": {"key": value, ...} overrides of the
///               scene config + optional "vary": [{"label": {set}, ...}, ...] whose
///               product expands the entry into scenes named name-label-label...
///               An `optional` scene whose files cannot be read (EO_ERR_IO: e.g. the
///               shared meshes folder is absent) is dropped at load with a note
///               (eo_bench_suite_nskipped / eo_bench_suite_skipped, the report).
///   configs     list; each entry {"name": ..., "set": {"solver.key": value, ...}}
///               (only solver.* keys: a configuration changes the solver, not the scene;
///               its solver.time_budget, if set, replaces the scene's budget for it)
///   matrix      list; each entry {"optimizer": [...], "hessian_fix": [...],
///               "linesearch": [...], "set": {...}} expands to the product
///               optimizer × hessian_fix × linesearch named "opt-fix-ls". The Hessian
///               fix is meaningless for optimizers that use no Hessian (gradient_descent,
///               lbfgs: needs_hessian = 0 in the registry): for them one configuration
///               per line search is made, named "opt-ls".
/// Every configuration is resolved (solver created, keys checked) at load, so a bad
/// suite fails before anything runs.
#ifndef ELASTOPT_BENCH_H
#define ELASTOPT_BENCH_H

#include "elastopt/export.h"
#include "elastopt/config.h"
#include "elastopt/impl/method.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Scalar suite options (top level of the suite document).
typedef struct eo_bench_opts {
    char description[1024]; ///< free text. Default "".
    int repeats;            ///< timed repeats per run (median), >= 1. Default 3.
    char baseline[64];      ///< configuration the ratios refer to. Default "" (the first).
    double target;          ///< curve runs stop at relative energy error <= target. Default 1e-10.
    double ref_tol;         ///< reference: lambda^2/2 <= ref_tol*|g(x0)|. Default 1e-14.
    int ref_max_iters;      ///< reference iteration cap. Default 500.
    int max_iters;          ///< iteration cap of the curve runs. Default 10000.
    double time_budget;     ///< seconds per minimization (curve and trajectory runs). Default 10.
    int steps;              ///< measured steps per scene. Default 2.
    int skip;               ///< reference-only steps before the measured ones. Default 0.
    char select[32];        ///< which steps are measured: "first" (the `steps` after `skip`),
                            ///< "largest_motion", "largest_correction" (the `steps`
                            ///< consecutive ones of largest total score among the horizon
                            ///< reference steps after `skip`). Default "first".
    int horizon;            ///< reference steps after `skip` to choose from (select != first);
                            ///< 0 = `steps`. Default 0.
    int trajectory;         ///< run the trajectory comparison. Default true.
    char trajectory_start[16]; ///< "scene" (from the scene's initial state through the last
                            ///< measured step) or "window" (from the reference state before
                            ///< the first measured step). Default "scene".
    int warmup_iters;       ///< iterations of the untimed warm-up run. Default 3.
    int curve_rows;         ///< curves.csv: every iteration up to this one, then 50 per
                            ///< decade of iteration count (0 = every iteration). Default 200.
    int plots;              ///< make PNG plots with gnuplot (if installed). Default true.
    int ipopt_check;        ///< solve every measured step once more with Ipopt (exact
                            ///< clamped Hessian, tol 1e-12) from the same start, as a second
                            ///< reference: its relative energy and position differences to
                            ///< x* go to reference.csv and report.md. Default true (skipped
                            ///< when the build has no Ipopt).
    char clock[8];          ///< what every time, ratio and budget measures: "cpu" = CPU
                            ///< seconds of the thread that solves (eo_cputime,
                            ///< CLOCK_THREAD_CPUTIME_ID), "wall" = elapsed seconds
                            ///< (eo_wtime). Both are recorded (curves.csv, trajectory.csv,
                            ///< fixed.csv); the time budgets (time_budget, a configuration's
                            ///< solver.time_budget, `budgets`) are in this clock's seconds.
                            ///< Default "cpu".
} eo_bench_opts;
EO_API extern const eo_param_desc eo_bench_opts_desc[];

/// One `scenes` entry (scalar keys; -1 = the suite's value).
typedef struct eo_bench_scene_opts {
    char name[96];          ///< scene name in the outputs (required).
    char scene[64];         ///< built-in scene name. Default "" (then `file`).
    char file[512];         ///< scene config file, relative to the suite's folder. Default "".
    int steps, skip;        ///< Default -1.
    double time_budget;     ///< Default -1.
    int max_iters;          ///< Default -1.
    int repeats;            ///< timed repeats on this scene. Default -1.
    char select[32];        ///< as the suite's; "suite" = the suite's. Default "suite".
    int horizon;            ///< Default -1.
    char trajectory_start[16]; ///< as the suite's; "suite" = the suite's. Default "suite".
    int optional;           ///< drop the scene at load if its files cannot be read. Default false.
    char stratum[48];       ///< group of the scene in the performance and data profiles (one
                            ///< profile per stratum besides the one over every scene).
                            ///< Default "" (none).
    int stratum_axis;       ///< with "vary": the axis (0-based) whose label is the stratum of
                            ///< each expanded scene ("<stratum>-<label>" when stratum is set),
                            ///< e.g. the element or the ν of a sweep. Default -1 (none).
} eo_bench_scene_opts;
EO_API extern const eo_param_desc eo_bench_scene_desc[];

typedef struct eo_bench_suite eo_bench_suite;

/// Load and check a suite: every scene config (with its overrides) is loaded and every
/// configuration resolved. Errors: EO_ERR_IO, EO_ERR_PARSE, EO_ERR_UNKNOWN_KEY (valid
/// keys listed), EO_ERR_TYPE, EO_ERR_RANGE, EO_ERR_UNKNOWN_NAME, EO_ERR_INVALID
/// (duplicate or missing names, baseline not a configuration, empty suite), each
/// naming the suite file and the scene/configuration.
EO_API int eo_bench_suite_load(eo_ctx *ctx, const char *path, eo_bench_suite **out);
EO_API void eo_bench_suite_destroy(eo_bench_suite **s);
/// Scalar options (borrowed) and the expanded names.
EO_API const eo_bench_opts *eo_bench_suite_opts(const eo_bench_suite *s);
EO_API int eo_bench_suite_nscenes(const eo_bench_suite *s);
EO_API int eo_bench_suite_nconfigs(const eo_bench_suite *s);
EO_API const char *eo_bench_suite_scene_name(const eo_bench_suite *s, int i);
EO_API const char *eo_bench_suite_config_name(const eo_bench_suite *s, int i);
/// Stratum of scene i in the profiles ("" none; a `stratum_axis` expansion sets it).
EO_API const char *eo_bench_suite_scene_stratum(const eo_bench_suite *s, int i);
/// Optional scenes dropped at load (their files could not be read): count, and the i-th
/// as "name: message" (borrowed; NULL out of range).
EO_API int eo_bench_suite_nskipped(const eo_bench_suite *s);
EO_API const char *eo_bench_suite_skipped(const eo_bench_suite *s, int i);

/// Progress report: scene i of n, configuration j of m (-1 while the reference runs),
/// fraction done in [0, 1] and estimated seconds left (< 0 unknown).
typedef struct eo_bench_progress {
    int scene, nscenes, config, nconfigs;
    const char *scene_name, *config_name, *phase;  ///< phase: "reference", "curves", "trajectory", "fixed", "done" (scene finished)
    double elapsed, fraction, eta;
} eo_bench_progress;
typedef void (*eo_bench_progress_fn)(const eo_bench_progress *p, void *user);

typedef struct eo_bench_run_opts {
    const char *out_dir;          ///< output folder (created). Required.
    int repeats;                  ///< > 0 overrides the suite's and every scene's repeats. Default 0.
    int plots;                    ///< 0 disables the plots, -1 = the suite's choice. Default -1.
    eo_bench_progress_fn progress;
    void *user;
    /// Optional (NULL: none): called per scene × configuration with the solver profile
    /// (solver.h eo_profile) of that configuration's curve runs (warm-up and timed
    /// repeats of every measured step); `elastopt bench --profile` prints it.
    void (*profile)(const char *scene, const char *config, const eo_profile *p, void *user);
    void *profile_user;
    /// "cpu" or "wall": overrides the suite's `clock` (NULL: the suite's). The profile
    /// callback receives the CPU view of the profile (eo_profile_cpu_view) under "cpu".
    const char *clock;
    /// A distributed run (the context carries distribution hooks, ctx.h eo_dist_hooks:
    /// `elastopt bench` under mpirun): for the scene loaded last, a per-vertex value of this
    /// part's local vertices summed over every part holding the vertex, on the part that
    /// owns it, 0 on the others (collective; returns 0 or a negative status). The harness
    /// sums the parts' lumped vertex masses with it, so that the mass-weighted distances
    /// count a shared vertex once with its whole mass. Required when distributed
    /// (EO_ERR_INVALID otherwise); NULL by default.
    int (*owned_sum)(const double *local, double *out);
} eo_bench_run_opts;
EO_API eo_bench_run_opts eo_bench_run_opts_default(void);

/// What eo_bench_run found (counts over every scene × configuration).
typedef struct eo_bench_summary {
    int runs;                 ///< scene × configuration pairs
    int ref_failures;         ///< reference steps that did not converge
    int nonfinite;            ///< pairs whose solver met a non-finite g or ∇g (stopped cleanly)
    int nan;                  ///< pairs that recorded a NaN or returned non-finite positions
    int required_failures;    ///< required configurations that failed some step
    int plots_made;           ///< PNG files written
    double seconds;           ///< wall time of the whole run
} eo_bench_summary;

/// Run the suite and write into opts->out_dir: curves.csv, summary.csv, trajectory.csv,
/// perf_profile.csv, data_profile.csv, report.md and plots/ (PNG + SVG + gnuplot scripts
/// and data). Profiles: per suite (and per scene `stratum`), every instance being a
/// measured step, cost = time to the first iterate with relative energy error <= each
/// `thresholds` level: Dolan–Moré performance profiles (share of instances solved within
/// tau x the best time) and Moré–Wild data profiles (share solved within kappa
/// gradient-equivalents: kappa x the time of one gradient evaluation of the step's
/// objective at its starting guess). Returns EO_OK (the summary
/// says what failed), or a negative status (I/O, out of memory, an objective error).
EO_API int eo_bench_run(eo_ctx *ctx, const eo_bench_suite *s, const eo_bench_run_opts *opts,
                 eo_bench_summary *sum);

/* ---- pieces, exposed for tests */

/// Time to accuracy: the time t[k] of the FIRST iterate k with err[k] <= thr (a step
/// function: nothing is interpolated between iterates, so a threshold met by the first
/// iterate costs the whole first iteration); INFINITY if never (NaN never meets it).
/// t[] nondecreasing, err[] may be <= 0.
EO_API double eo_bench_time_to(int n, const double *t, const double *err, double thr);
/// Error of the last iterate whose time is <= budget (err[0] if none; NAN if n = 0).
EO_API double eo_bench_error_at(int n, const double *t, const double *err, double budget);
/// Median, minimum and maximum of n values (INFINITY counts as a value; NAN ignored).
/// Works on a copy of at most 64 values (more are ignored). Returns the median (NAN
/// if no value).
EO_API double eo_bench_median(int n, const double *v, double *vmin, double *vmax);

#ifdef __cplusplus
}
#endif
#endif
