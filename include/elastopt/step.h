/// @file step.h
/// The step engine: each implicit time step of a scene as an optimization problem
///
///     min_x g(x) = ½‖x − x̃‖²_M + w·(E(x) − cᵀx)
///
/// over the FREE coordinates (constrained vertices take their prescribed positions and
/// are eliminated, not penalized). E is the elastic energy Σₜ Vₜ ψ(Fₜ) plus the gravity
/// potential −f_gᵀx (f_g = M g, ρV/4·g per tet vertex for both masses); the integrator
/// (eo_integrator_type, registry kind EO_KIND_INTEGRATOR) gives the weight w, the
/// predictor x̃, the linear term c and the velocity update:
///
///   newmark (β = ¼, γ = ½)  w = h²/4, x̃ = xₙ + h vₙ, c = fₙ = −∇E(xₙ),
///                           vₙ₊₁ = 2(xₙ₊₁ − xₙ)/h − vₙ       (energy conserving)
///   backward_euler          w = h², x̃ = xₙ + h vₙ, c = 0, vₙ₊₁ = (xₙ₊₁ − xₙ)/h
///   static                  no inertia term, w = 1, c = 0, v = 0   (equilibrium); with
///                           time.load_steps = L > 0: gravity and prescribed motions
///                           ramped linearly over L increments (quasi-static loading)
///   implicit_midpoint       w = h²/4 in the midpoint z = (xₙ + xₙ₊₁)/2, x̃ = xₙ + (h/2)vₙ,
///                           xₙ₊₁ = 2z − xₙ, vₙ₊₁ = 2(xₙ₊₁ − xₙ)/h − vₙ  (θ = ½)
///   bdf2                    w = 4h²/9, x̃ = (4xₙ − xₙ₋₁)/3 + (2h/9)(4vₙ − vₙ₋₁),
///                           vₙ₊₁ = (3xₙ₊₁ − 4xₙ + xₙ₋₁)/(2h); backward Euler on the
///                           first step (history: eo_step_get_history)
///   generalized_alpha       (Chung & Hulbert 1993, parameter ρ∞) in the stage
///                           z = xₙ + (1 − α_f)(xₙ₊₁ − xₙ): w = (1 − α_f)βh²/(1 − α_m),
///                           z̃ = xₙ + (1 − α_f)(h vₙ + h²((½ − β) − βα_m/(1 − α_m)) aₙ),
///                           keeps the acceleration aₙ (history; problems/integrators/
///                           generalized_alpha.c)
///   forward_euler, symplectic_euler, symplectic_euler_x, heun, midpoint, rk4, verlet,
///   leapfrog
///                           explicit (001 §2.5): no optimization problem, see
///                           eo_integrator_type.explicit_step and eo_step_advance
///
/// (Newmark in this form equals ½‖x − y‖²_M + (h²/4)E(x) with y = xₙ + h vₙ + (h²/4)M⁻¹fₙ
/// up to a constant, without solving with M; see ERRATA for 002 §3.1.)
///
/// This is the engine under eo_sim (sim.h), which runs the whole per-step protocol
/// (implicit or explicit branch, divergence check, statistics); programs use eo_sim,
/// only the step engine's own tests call begin / end / advance directly.
///
/// ```c
/// eo_step *st; eo_step_create(ctx, scene, &st);      // scene borrowed, must outlive st
/// for (int k = 0; k < scene->time.steps; k++) {
///     eo_objective *obj; eo_step_begin(st, &obj);    // objective of step k (borrowed)
///     double *x = eo_step_guess(st);                 // obj->n free coordinates, in/out
///     eo_solver_minimize(solver, obj, x, NULL, NULL, &res);
///     eo_step_end(st, x);                            // xₙ₊₁, vₙ₊₁, t += h
/// }
/// eo_step_destroy(&st);
/// ```
/// Ownership: the step owns the objective, its Hessian (assembled into a pattern built
/// once per set of constrained vertices, rebuilt only when a boundary set is released)
/// and all state vectors; accessors return borrowed pointers.
/// No allocation happens inside objective evaluations.
#ifndef ELASTOPT_STEP_H
#define ELASTOPT_STEP_H

#include <stddef.h>

#include "export.h"
#include "linsolve.h"
#include "objective.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/// The second-order ODE an explicit integrator advances, n coordinates:
///     x' = v,   v' = a(t, x, v).
/// For a scene, a = M⁻¹ f(x, v) with f = −∇E(x) (elastic, springs, gravity, collisions)
/// minus spring damping; prescribed vertices take their positions at t and get a = 0
/// (the step overwrites them with their motion after each step).
typedef struct eo_ode {
    int n;
    void *data;
    /// a (n) at time t, state x, v. Returns EO_OK or a negative status.
    int (*accel)(void *data, double t, const double *x, const double *v, double *a);
} eo_ode;

/// A time integrator (registry kind EO_KIND_INTEGRATOR).
///
/// Implicit integrators (explicit_step NULL) turn a step into min g(x) through weight,
/// predict, force_n and velocity. Explicit integrators set the optional op
/// explicit_step instead (weight, predict, velocity NULL): the step engine then calls
/// it (eo_step_advance) and builds no optimization problem.
typedef struct eo_integrator_type {
    eo_method_info info;
    int inertia;        ///< 1: the state has a velocity (and, implicit: the ½‖x − x̃‖²_M term)
    int force_n;        ///< 1: linear term c = fₙ = −∇E(xₙ) (trapezoidal forces)
    /// Weight w of E for step h.
    double (*weight)(double h);
    /// Predictor x̃ (n coordinates) from xₙ, vₙ.
    void (*predict)(int n, double h, const double *xn, const double *vn, double *xt);
    /// Velocity vₙ₊₁ from xₙ, vₙ and the solution x.
    void (*velocity)(int n, double h, const double *xn, const double *vn, const double *x,
                     double *v);
    /// Optional (explicit integrators): advance x, v (ode->n each, in place) from t to
    /// t + h. `work` holds work_vectors·n doubles owned by the caller that persist
    /// between steps (leapfrog keeps its staggered velocity there); `restart` is 1 on the
    /// first step after a reset, a set_state or a failed step. Returns EO_OK or the
    /// status of ode->accel. Never allocates.
    int (*explicit_step)(const eo_ode *ode, double t, double h, double *x, double *v,
                         double *work, int restart);
    int work_vectors;   ///< scratch n-vectors explicit_step needs
    /// Implicit, optional: the minimizer z of g is the stage z = xₙ + θ(xₙ₊₁ − xₙ), not
    /// xₙ₊₁ itself (implicit_midpoint: θ = ½, g posed in the midpoint). 0 means 1. The
    /// engine prescribes constrained coordinates as xₙ + θ(p(tₙ₊₁) − xₙ), maps the
    /// minimizer back with xₙ₊₁ = xₙ + (z − xₙ)/θ and gives `velocity` xₙ₊₁.
    double theta;
    /// Implicit multistep, optional: 1 if the previous state (xₙ₋₁, vₙ₋₁) is used (bdf2),
    /// 0 = none (the only values). While the engine has no valid previous state (first step, after a
    /// reset, a set_state or a rejected step) it uses weight/predict/velocity (the
    /// one-step start, e.g. backward Euler); afterwards the *_history ops below.
    int history;
    double (*weight_history)(double h);
    /// Predictor x̃ from xₙ, vₙ and the previous state xp = xₙ₋₁, vp = vₙ₋₁.
    void (*predict_history)(int n, double h, const double *xn, const double *vn, const double *xp,
                            const double *vp, double *xt);
    /// Velocity vₙ₊₁ from xₙ, xp = xₙ₋₁ and the solution x.
    void (*velocity_history)(int n, double h, const double *xn, const double *xp, const double *x, double *v);
    /// 1: the integrator removes energy from oscillations by design (numerical
    /// dissipation: backward_euler, bdf2), or has no dynamics (static); eo_sim then does
    /// not watch the total energy for growth (eo_sim_energy_warning). 0: meant to keep it.
    int dissipative;
    /// Optional: dissipation that depends on the parameters (params: the integrator's
    /// params struct, info.params; NULL = its defaults); 1 = dissipative. Overrides
    /// `dissipative` when set.
    int (*is_dissipative)(const void *params);
    /// Implicit with an acceleration state, optional (generalized_alpha). accel = 1: the
    /// engine keeps the algorithmic acceleration aₙ (n coordinates) with the state and
    /// uses the four accel_* ops in place of weight, predict, velocity and theta (the
    /// minimizer is the stage z = xₙ + θ(xₙ₊₁ − xₙ), as for `theta`). `params` is the
    /// integrator's params struct (info.params, loaded from the scene's time.<name>
    /// section; NULL = its defaults). While the engine has no valid aₙ (first step, after
    /// a reset, a set_state or a rejected step) it starts from the consistent
    /// a₀ = M⁻¹(−∇V(xₙ) − C vₙ) (prescribed vertices: a = 0). aₙ and its valid flag are
    /// the restart history (eo_step_get_history).
    int accel;
    double (*accel_weight)(const void *params, double h);
    double (*accel_theta)(const void *params);
    /// Predictor z̃ of the stage from xₙ, vₙ, aₙ.
    void (*accel_predict)(const void *params, int n, double h, const double *xn, const double *vn,
                          const double *an, double *zt);
    /// vₙ₊₁, and aₙ₊₁ into a (unless NULL), from xₙ, vₙ, aₙ and the end positions x.
    void (*accel_velocity)(const void *params, int n, double h, const double *xn, const double *vn,
                           const double *an, const double *x, double *v, double *a);
} eo_integrator_type;

typedef struct eo_step eo_step;

/// Create the step problem of a scene (borrowed; must outlive the step) and set the
/// initial state (eo_step_reset). Errors: EO_ERR_MESH (bad rest tet), EO_ERR_NOMEM.
EO_API int eo_step_create(eo_ctx *ctx, const eo_scene *sc, eo_step **out);
EO_API void eo_step_destroy(eo_step **st);
/// Initial state of the scene: rest positions transformed by `initial`, its velocity,
/// t = 0, step index 0.
EO_API int eo_step_reset(eo_step *st);
/// Set the state (3·nv positions and velocities, copied) and time. A state at t = 0 is
/// the initial state: prescribed motions (boundary entries) start from its positions.
EO_API int eo_step_set_state(eo_step *st, const double *x, const double *v, double t);
/// Set the step index (eo_step_index; eo_sim_set_state restores it with the state).
EO_API int eo_step_set_index(eo_step *st, int index);
/// Build the objective of the next step (t → t + h) and the starting guess; *obj is
/// borrowed until the next begin. Its n may change between steps when a boundary set
/// is released.
EO_API int eo_step_begin(eo_step *st, eo_objective **obj);
/// The free coordinates of the starting guess (obj->n values, borrowed, writable):
/// the better (lower g) of xₙ and the predictor x̃; the solver works on it in place.
EO_API double *eo_step_guess(eo_step *st);
/// Element loops with OpenMP (on = 1; only with >= 2048 tets and > 1 thread) or serial
/// (default). Results are identical either way (per-element buffers, serial scatter).
/// Measured on a 2-core machine shared with other jobs, the parallel loops were slower
/// (30k tets: Hessian 50–70 ms serial vs 215–230 ms with 2 threads), hence off by default.
/// Returns 1 if the parallel path is active.
EO_API int eo_step_set_parallel(eo_step *st, int on);
/// Order in which the element loops (energy, gradient, Hessian of the elastic and
/// inertia terms) visit the tets: on = 1 (the default) the Morton (Z-curve) order of the
/// tets' rest centroids, so that consecutive tets share vertices and the vertices' entries
/// of x, ∇g and the Hessian's columns are still in cache (a mesh from TetGen lists its tets
/// in no spatial order: on a 115k-tet bunny a vertex was met again a median 2288 tets
/// later in the mesh order); on = 0 the mesh order. The elastic loops read copies of the
/// per-tet data (vertex ids, Dₘ⁻¹, volume, material) and a second assembler group of the
/// tets kept in the Morton order, so they stream them (without those copies the Morton
/// visit was slower than the mesh order: the per-tet reads jumped instead). Nothing is
/// renumbered: only the summation order changes, so g, ∇g and H agree to rounding
/// (tests/test_tet_order.c). No effect on a part (eo_step_set_part). Returns the order
/// in use (1 Morton, 0 mesh).
EO_API int eo_step_set_tet_order(eo_step *st, int on);
/// Defined where eo_step_set_tet_order exists (for code built against older versions).
#define EO_STEP_TET_ORDER 1
/// Accept the free coordinates x as xₙ₊₁: update positions, velocities, time, index.
/// EO_ERR_UNSUPPORTED for an explicit integrator (use eo_step_advance).
EO_API int eo_step_end(eo_step *st, const double *x);

/// The previous state of a multistep integrator (eo_integrator_type.history = 1; bdf2),
/// for restarts: 2·3·nv + 1 doubles laid out as xₙ₋₁ (3·nv), vₙ₋₁ (3·nv), then 1 if
/// they are valid, 0 if not (right after a reset, set_state or rejected step: the next
/// step is the one-step start). With an acceleration state (eo_integrator_type.accel;
/// generalized_alpha): 3·nv + 1 doubles, aₙ then the valid flag (0: the next step starts
/// from the consistent acceleration). 0 for integrators without history.
EO_API size_t eo_step_history_len(const eo_step *st);
/// Copy the history out (h: eo_step_history_len doubles). EO_ERR_UNSUPPORTED if none.
EO_API int eo_step_get_history(const eo_step *st, double *h);
/// Set the history (copied; after eo_step_set_state, which clears it). EO_ERR_UNSUPPORTED
/// if the integrator has none, EO_ERR_RANGE if the last entry is neither 0 nor 1.
EO_API int eo_step_set_history(eo_step *st, const double *h);

/// Substeps of the nominal step h = time.dt (implicit integrators; eo_sim's adaptive
/// stepping, sim.h). At level k the following steps are h/2^k long: eo_step_begin poses
/// the step problem with that size (weight, predictor, velocity update, damping and
/// friction follow it) and the engine counts the progress p through the current nominal
/// step tₙ → tₙ + h as an exact binary fraction. A substep ends at tₙ + (p + 2^-k)·h,
/// the last one (p + 2^-k = 1) exactly at tₙ + h, the time a nominal step ends at; only
/// that one advances the step index (eo_step_index counts nominal steps). Level 0 with
/// p = 0 is the nominal step, bit for bit as without substeps. Prescribed motions,
/// releases and time.load_steps follow the time (a substep applies its share).
/// A multistep integrator (bdf2) keeps the previous step only while the size does not
/// change: a change of level marks the history invalid, so the first step after it is
/// the one-step start (backward Euler for bdf2) and the following steps of the new size
/// the fixed-step formula again (the restart choice; variable-step BDF2 coefficients are
/// not used). eo_step_reset and eo_step_set_state go back to level 0, p = 0.
#define EO_STEP_MAX_SUBSTEP 30
typedef struct eo_step_substep {
    int level;          ///< steps of h/2^level, 0..EO_STEP_MAX_SUBSTEP
    double done;        ///< p: fraction of the current nominal step done, a multiple of 2^-level in [0, 1)
    double t_start;     ///< tₙ, where the current nominal step started (the time when done = 0)
} eo_step_substep;
/// The current level, progress and start of the nominal step.
EO_API void eo_step_get_substep(const eo_step *st, eo_step_substep *s);
/// Set the level of the following steps (and the progress, to restore a saved state:
/// after eo_step_set_state, before eo_step_set_history). EO_ERR_RANGE for a level outside
/// 0..EO_STEP_MAX_SUBSTEP or a progress that is not a multiple of 2^-level in [0, 1);
/// EO_ERR_UNSUPPORTED for an explicit integrator.
EO_API int eo_step_set_substep(eo_step *st, const eo_step_substep *s);

/// 1 if the scene's integrator is explicit (eo_integrator_type.explicit_step set). For
/// those, eo_step_begin builds the potential-energy objective E(x) (weight 1, no
/// inertia: its −∇ is the force the integrator uses), which `elastopt check` verifies;
/// the run advances with eo_step_advance and needs no solver.
EO_API int eo_step_is_explicit(const eo_step *st);
/// Explicit integrators: advance one step t → t + h. Accelerations a = M⁻¹f: with lumped
/// mass a division per vertex; with consistent mass M (over the free coordinates,
/// prescribed accelerations taken as 0 in its coupling) is factored once per set of
/// constrained vertices with the mass solver (eo_step_set_mass_solver; default
/// cholmod). Prescribed vertices follow their motion exactly.
/// *reason: EO_REASON_EXPLICIT, or EO_DIVERGED_NONFINITE when a non-finite energy or
/// force was met at any stage of the step (any term) or the new state is not finite
/// (the state then stays at tₙ, the last finite one, and the step counter does not
/// advance).
/// Returns EO_OK (also when diverged), EO_ERR_UNSUPPORTED for an implicit integrator,
/// EO_ERR_INVALID for a free vertex without mass, or a linear solver error.
EO_API int eo_step_advance(eo_step *st, int *reason);
/// Linear solver of the consistent-mass solve of eo_step_advance (ls: taken over, NULL =
/// the default cholmod); the mass matrix is factored again at the next advance. eo_sim
/// sets it from the scene's `solver.linear` (with its `solver.<name>` parameters).
EO_API int eo_step_set_mass_solver(eo_step *st, eo_linsolve *ls);
/// 1 if the current state is finite: every position and velocity, ‖x‖² and Σ m‖v‖²
/// (an overflowing square counts as diverged).
EO_API int eo_step_state_finite(const eo_step *st);

/// Borrowed state: positions and velocities (3·nv), rest positions, mesh.
EO_API const double *eo_step_x(const eo_step *st);
EO_API const double *eo_step_v(const eo_step *st);
EO_API const double *eo_step_x0(const eo_step *st);   ///< positions at t = 0
EO_API double eo_step_time(const eo_step *st);
EO_API int eo_step_index(const eo_step *st);
EO_API const eo_mesh *eo_step_mesh(const eo_step *st);
/// Full coordinate of free coordinate i, and the free index of full coordinate j (-1 if
/// constrained) for the current objective.
EO_API int eo_step_free_to_full(const eo_step *st, int i);
EO_API int eo_step_full_to_free(const eo_step *st, int j);
/// Lumped mass of each vertex (nv), borrowed.
EO_API const double *eo_step_vertex_mass(const eo_step *st);

/// Partitioned evaluation, for distributed backends that keep the whole step engine on
/// every process (the PETSc module no longer does: each rank runs its own step engine on
/// its local mesh, ctx.h eo_dist_hooks): while a
/// part is set, the step objective's value, gradient, hessian and inverted_count add only
///  - the tets tets[0..nt) (elastic energy, consistent mass), and
///  - the nodal terms (lumped mass, point masses, gravity, the linear term of newmark,
///    contact, friction) of the vertices v with vown[v] = 1,
/// so summing the results of parts that together hold every tet once and own every vertex
/// once gives the whole objective (up to rounding). x is read only at the free
/// coordinates of verts[0..nv) (every vertex of the part's tets; owned vertices belong
/// to a tet of the part), the gradient is written only there (other entries
/// unspecified), and the Hessian (the step's matrix and pattern) is zeroed and assembled
/// only in the columns of those coordinates. The arrays are borrowed until the part is
/// cleared (eo_step_set_part(st, NULL)); eo_step_begin/end and the statistics always see
/// the whole problem, so set a part only around the evaluations that want it.
/// Returns EO_OK, or EO_ERR_UNSUPPORTED for a scene with terms that have no partitioned
/// form (springs, damping) or an explicit integrator.
typedef struct eo_step_part {
    int nt;                       ///< tets of this part
    const int *tets;              ///< nt tet indices
    int nv;                       ///< vertices touched by the part
    const int *verts;             ///< nv vertex indices (each once)
    const unsigned char *vown;    ///< mesh nv flags: 1 = this part adds the vertex's nodal terms
} eo_step_part;
EO_API int eo_step_set_part(eo_step *st, const eo_step_part *part);
/// The step engine whose objective obj is, or NULL if obj is not a step objective.
EO_API eo_step *eo_step_of_objective(const eo_objective *obj);
/// Changes whenever the free set and the Hessian pattern are rebuilt (a release).
EO_API unsigned long eo_step_pattern_id(const eo_step *st);
/// The step objective's own factorization of its projective-dynamics matrix L
/// (problems/pd_matrix.c), offered to the optimizers that apply L⁻¹ through the
/// objective ops constant_factor / constant_solve (objective.h; used when solver.linear
/// is a CHOLMOD method). L is assembled once over ALL coordinates (L_all, pattern of the
/// whole mesh); when L_all = L₁ ⊗ I₃ (every term isotropic: elasticity, springs, mass)
/// the vertex matrix L₁ is factored instead and a solve is one pass with 3 right-hand
/// sides. The factor is of Ã(S) = [L_SS 0; 0 diag(L_CC)] for the free set S (eo_updown,
/// linsolve.h): its free block is the eliminated matrix of the current constraints.
///   EO_PD_FACTOR_AUTO      (default) a change of the constrained set (a release, or a
///                          pin when the state is set back) of rank r = 2 per changed
///                          vertex (per coordinate if not isotropic) is a rank update/
///                          downdate of the factor when r·nnz(L) ≤ the flops of a
///                          factorization (the update cannot cost more), else a fresh
///                          factorization
///   EO_PD_FACTOR_UPDOWN    always the update/downdate; a fresh factorization only for the
///                          first step and when the integrator weight changes
///   EO_PD_FACTOR_REFACTOR  a fresh factorization at every change (the reference the
///                          update is compared against)
///   EO_PD_FACTOR_OFF       no own factor: the optimizers factor constant_hessian (the
///                          eliminated L) with solver.linear, once per constrained set
/// Scenes with damping, obstacles or friction terms get no own factor (their rest
/// Hessians are not part of L_all): they behave as EO_PD_FACTOR_OFF.
enum { EO_PD_FACTOR_OFF = 0, EO_PD_FACTOR_REFACTOR = 1, EO_PD_FACTOR_UPDOWN = 2, EO_PD_FACTOR_AUTO = 3 };
/// Set the mode (takes effect at the next constant_factor; a mode change drops the
/// factor). EO_OK or EO_ERR_RANGE.
EO_API int eo_step_set_pd_factor(eo_step *st, int mode);
/// Counters of the own PD factor.
typedef struct eo_step_pd_info {
    int mode;             ///< EO_PD_FACTOR_*
    int factored;         ///< a factor exists
    int scalar;           ///< 1: L_all = L₁ ⊗ I₃, the vertex matrix L₁ is factored
    int n;                ///< order of the factored matrix (vertices, or coordinates)
    long n_factor;        ///< fresh factorizations (analysis + numeric)
    long n_updown;        ///< constraint changes applied by update/downdate
    long rank;            ///< columns of all updates and downdates so far
    int last_rank;        ///< of the last change
    long n_solve;         ///< solves (each with 3 right-hand sides when scalar)
    double t_factor, t_updown, t_build;  ///< seconds: factorizations, updates, assembly of L_all
} eo_step_pd_info;
EO_API void eo_step_pd_info_get(const eo_step *st, eo_step_pd_info *out);
/// The factor (borrowed; NULL before the first constant_factor), e.g. to compare it with
/// a fresh factorization: eo_updown_create(ctx, eo_updown_matrix(u), eo_updown_free_set(u), ..).
EO_API eo_updown *eo_step_pd_updown(eo_step *st);

/// Diagnostics of the current state.
typedef struct eo_step_stats {
    double com[3];          ///< centre of mass
    double max_disp;        ///< max over vertices of ‖x − X‖ (X rest)
    double min_J;           ///< min over tets of det F
    double max_J;
    int inverted;           ///< tets with det F <= 0
    double kinetic;         ///< ½ vᵀMv with the scene's mass matrix
    double elastic;         ///< Σₜ Vₜ (ψ(Fₜ) − ψ(I)): zero at rest
    double gravity;         ///< −f_gᵀx
    /* appended: the energy balance (fields above keep their offsets) */
    double contact;         ///< penalty potential of the obstacles (collisions), 0 if none
    double potential;       ///< elastic + gravity + contact: every conservative potential
    double work_prescribed; ///< work done ON the body by the prescribed motions since t = 0
                            ///< (eo_step_work_prescribed; trapezoidal, see there)
    double total_energy;    ///< kinetic + potential − work_prescribed: constant for an exact
                            ///< integration of a scene without damping or friction
} eo_step_stats;
/// Statistics of the current state (energies with weight 1, whatever the integrator's).
EO_API int eo_step_stats_compute(eo_step *st, eo_step_stats *s);
/// Work W done on the body by the prescribed motions (moving Dirichlet boundaries) from
/// t = 0 to the current state, J. Accumulated by every accepted step (eo_step_end,
/// eo_step_advance) as the trapezoidal rule of reaction force · boundary increment,
///     ΔW = Σ_c ½(r_c(xₙ) + r_c(xₙ₊₁))·(x_c,ₙ₊₁ − x_c,ₙ) + v̄_cᵀ[M(vₙ₊₁ − vₙ)]_c,
/// over the coordinates c constrained at tₙ₊₁, with r = ∇(E_el + springs + gravity +
/// contact) the static reaction and v̄_c = ½(v_c,ₙ + v_c,ₙ₊₁) (the second sum, the
/// inertial reaction, is the exact change of the constrained vertices' kinetic energy
/// with lumped mass; a trapezoidal approximation of its coupling with consistent mass).
/// Fixed vertices do no work (ΔW = 0 without evaluating anything). Damping and friction
/// forces at constrained vertices are not counted. eo_step_reset sets W = 0;
/// eo_step_set_state keeps it (restore it with eo_step_set_work_prescribed).
EO_API double eo_step_work_prescribed(const eo_step *st);
EO_API void eo_step_set_work_prescribed(eo_step *st, double w);
/// Per-tet fields of the current state: energy density ψ, det F, inverted flag (any
/// pointer may be NULL; arrays of nt).
EO_API int eo_step_fields(eo_step *st, double *psi, double *J, unsigned char *inverted);

#ifdef __cplusplus
}
#endif
#endif
