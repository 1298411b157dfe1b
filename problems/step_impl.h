/* Private to the step engine (problems/step*.c and problems/sim.c): struct eo_step and
 * the helpers its files share. The files, by job:
 *   step.c            create / destroy, accessors, parallel switch
 *   step_bc.c         boundary conditions: active sets, prescribed motion, free map and
 *                     Hessian pattern
 *   step_objective.c  the step objective's ops, eo_step_begin / eo_step_end
 *   step_initial.c    initial state (eo_step_reset) and eo_step_set_state
 *   step_explicit.c   explicit integrators: the ODE, consistent mass solve, advance
 *   step_stats.c      diagnostics (eo_step_stats) and per-tet fields
 *   step_substep.c    substeps of the nominal step (eo_step_set_substep) */
#ifndef ELASTOPT_STEP_IMPL_H
#define ELASTOPT_STEP_IMPL_H

#include "elastopt/linsolve.h"
#include "elastopt/step.h"
#include "pd_matrix.h"
#include "term.h"


enum { MAX_TERMS = 24, BLOCK = 1024, PARALLEL_MIN_TETS = 2048 };

struct eo_step {
    eo_ctx *ctx;
    const eo_scene *sc;
    const eo_integrator_type *integ;
    eo_sys sys;
    int nv, nt, n_full;
    double h;             /* size of the next step: h_nom/2^sub_level */
    /* substeps (eo_step_set_substep): the nominal step h_nom = time.dt, the level of the
     * next steps, the fraction of the nominal step tₙ → tₙ + h_nom done (an exact binary
     * fraction, 0 at nominal boundaries) and tₙ (valid while sub_done > 0) */
    double h_nom;
    int sub_level;
    double sub_done, sub_t0;
    /* rest data */
    double *Dminv, *vol, *rho, *vmass;
    double *vload;        /* nv gravity loads (term.h eo_sys.vload); NULL: vmass (p1) */
    double *psi_rest;     /* nt: ψ(I) of each tet's material (reported energies are relative to it) */
    const eo_material_type **tet_type;
    const eo_material_coef **tet_coef;
    /* state */
    double *x, *v, *x0, t;
    int index;
    /* work */
    double *xw, *gfull, *vnew, *guess;
    /* terms */
    /* terms: one per registered term kind the scene uses (registry order); the roles the
     * engine singles out are found by their flags (impl/term.h EO_TERM_*), the two terms
     * with their own extra ops by their kind; NULL if absent */
    eo_term *terms[MAX_TERMS];
    int nterms;
    unsigned term_flags;        /* the union of the terms' flags */
    eo_term *inertia;           /* EO_TERM_INERTIA */
    eo_term *linear;            /* EO_TERM_FORCE_N */
    eo_term *damping;           /* EO_TERM_DAMPING: viscous + Rayleigh (term_damping.c) */
    eo_term *friction;          /* EO_TERM_LAGGED: lagged friction (term_friction.c) */
    eo_term *elastic;           /* the elastic term (inverted count) */
    eo_term *spring;            /* the spring term (vertex coupling, spring damping) */
    /* constraints and pattern */
    int *vbc, *vbc_new;   /* nv: active boundary entry per vertex, -1 free */
    int have_pattern;
    int *full2free, *free2full, nfree;
    int *tet_dofs;
    int *tet_order;     /* nt: tets in Morton order of their rest centroids (eo_sys.tet_order) */
    /* the per-tet data in that order (eo_sys.ord_*) */
    int *ord_tets, *ord_dofs;
    double *ord_Dminv, *ord_vol, *ord_psi, *ord_rho;
    const eo_material_type **ord_type;
    const eo_material_coef **ord_coef;
    eo_assembler *as;
    eo_objective obj;
    unsigned long pattern_id;   /* bumped by build_pattern */
    /* explicit integrators (eo_step_advance) */
    double *ework, *xe, *ve;    /* work_vectors·n_full; trial state */
    int erestart;               /* next explicit step restarts (leapfrog) */
    eo_linsolve *mls;           /* consistent mass: M_ff factored (eo_step_set_mass_solver) */
    int enonfinite;             /* a stage of this explicit step met a non-finite force */
    eo_csc *Mc;                 /* its values (a copy of the pattern) */
    unsigned long Mc_pattern;   /* pattern_id Mc was assembled on */
    eo_pd_matrix pd;            /* constant_hessian cache (pd_matrix.c) */
    /* multistep integrators (integ->history): xₙ₋₁, vₙ₋₁ and whether they are valid */
    double *xp, *vp;
    int hist_valid;
    double w;                   /* integrator weight of the current objective */
    /* objective op `inertia`: M over the free coordinates (per pattern), xₙ and x̃ gathered */
    eo_csc *Mi;
    unsigned long Mi_pattern;
    double *fin;                /* 2·n_full: xₙ, x̃ of the free coordinates */
    const eo_step_part *part;   /* partitioned evaluation (eo_step_set_part), NULL: whole */
    /* op inverted_count: the count of the last op_gradient (the elastic term counts while
     * it evaluates) and its x; valid until the step's prescribed positions or pattern change */
    double *inv_x;              /* n_full (the first nfree used) */
    /* objective op rounding_scale: per vertex a_v = Σ_{t ∋ v} (μₜ + λₜ) Vₜ^{2/3} (nv,
     * allocated at the first call) and Σₜ Vₜ (μₜ + λₜ)²/μₜ; both depend only on the
     * materials and the rest shape */
    double *rs_a, rs_el, rs_ev;
    /* objective op characteristic (BCQN scales): ‖a‖₂ with a_v = Σ_{t ∋ v} A_{t,v} h_t,
     * Σₜ Vₜ hₜ and Σₜ Vₜ (rest shape and materials only; computed at the first call) */
    double ch_anorm, ch_vh, ch_vol;
    int ch_done;
    /* objective ops split_*: the weight k of every tet in L (nt, allocated at the first
     * split_info call; depends only on the materials) */
    double *split_k;
    int inv_count, inv_valid;
    /* objective ops constant_factor / constant_solve: the own factor of L (step_pd.c) */
    int pd_mode;                /* EO_PD_FACTOR_* */
    eo_csc *pd_all;             /* L_all, or L₁ when scalar */
    double pd_w;                /* integrator weight pd_all was assembled with */
    eo_updown *pd_u;
    unsigned char *pd_free;     /* free set of the variables of pd_all (scratch) */
    double *pd_b, *pd_x;        /* n_full each: right-hand sides and solutions */
    eo_step_pd_info pd_info;
    /* energy balance (step_stats.c): work of the prescribed motions and the static
     * reaction ∇(potentials) at xₙ (rpot, valid while rpot_valid; rpot1 scratch); both
     * n_full, allocated only when the scene has boundary entries */
    double work;
    double *rpot, *rpot1;
    int rpot_valid;
    /* acceleration state (integ->accel, generalized_alpha): aₙ, valid while hist_valid;
     * anew scratch for aₙ₊₁ */
    double *an, *anew;
    /* objective ops vertex_blocks / vertex_block (step_objective.c): vertex -> tets (CSR,
     * built at the first call; the mesh's), and per pattern the blocks (free vertices
     * vb_vert, their free ids vb_dofs), their coupling (CSR vb_ptr / vb_adj) and a
     * scratch mark per vertex */
    int *vt_ptr, *vt_tet;
    int vb_nb, *vb_vert, *vb_dofs, *vb_ptr, *vb_adj, *vb_mark;
    unsigned long vb_pattern;
};

/* 1 if coordinate j is prescribed by the entry vbc[j/3] (-1: free): the entry's
 * `components` mask (a partial entry leaves the other components of its vertices free). */
static inline int eo_stepi_fixed(const eo_step *st, const int *vbc, int j)
{
    const int b = vbc[j / 3];
    return b >= 0 && st->sc->bc[b].mask[j % 3];
}

/* step_bc.c */
/* Active boundary entry per vertex at time t (-1 free) into vbc (nv). */
void eo_stepi_active_set(const eo_step *st, double t, int *vbc);
/* Prescribed position and velocity of vertex v under entry bc at time t. */
void eo_stepi_bc_motion(const eo_step *st, const eo_bc *bc, int v, double t, double p[3], double vel[3]);
/* Set the constrained set at time t; rebuild the free map and the pattern if it changed
 * (or none exists). *changed (may be NULL): 1 if it was rebuilt. */
int eo_stepi_update_constraints(eo_step *st, double t, int *changed);
/* step_objective.c */
void eo_stepi_scatter_free(eo_step *st, const double *x);
extern const eo_objective_ops eo_stepi_ops, eo_stepi_ops_element;
/* Weight of the next step's E (history-aware) and velocity vₙ₊₁ of end positions x. */
double eo_stepi_weight(const eo_step *st);
void eo_stepi_velocity(const eo_step *st, const double *x, double *v);
/* θ of the integrator's stage (1 unless it poses g in a stage, implicit_midpoint ½). */
double eo_stepi_theta(const eo_step *st);
/* K₀ of Rayleigh damping: the clamped Hessian of the elastic terms at st->x (xₙ) into
 * the damping term (no-op without β). */
int eo_stepi_damping_stiffness(eo_step *st);
/* L over all coordinates (the PD matrix of the pattern with every vertex free), into a
 * new *A owned by the caller; the pattern of the current constraints is rebuilt after. */
int eo_stepi_pd_matrix_all(eo_step *st, eo_csc **A);
/* step_pd.c: the objective ops constant_factor / constant_solve, and cleanup */
int eo_stepi_pd_factor(void *data);
int eo_stepi_pd_solve(void *data, const double *b, double *x);
void eo_stepi_pd_deinit(eo_step *st);
/* End time of the next step: tₙ₊₁ = t + h for a nominal step (bit for bit as always),
 * else tₙ + (done + 2^-level)·h_nom, exactly tₙ + h_nom for the last substep. */
double eo_stepi_t1(const eo_step *st);
/* Load fraction (index + done + 2^-level) of the step being posed (load stepping). */
double eo_stepi_load_steps_done(const eo_step *st);
/* After a step: advance the progress through the nominal step; 1 if the step ended a
 * nominal step (the index advances), 0 if it was an inner substep. */
int eo_stepi_substep_advance(eo_step *st);
/* r += ∇V(x) at weight 1 (the EO_TERM_POTENTIAL terms, the contact ones last): the
 * static reaction, the force fₙ (step_objective.c, step_stats.c). */
void eo_stepi_potential_gradient(eo_step *st, const double *x, double *r);
/* step_stats.c */
double eo_stepi_tet_J(const eo_step *st, const double *x, int k);
/* Add the work of the prescribed motions over the step xₙ, vₙ (st->x, st->v) → x1, v1
 * (full vectors) to st->work, with st->vbc the constrained set at tₙ₊₁. Call before the
 * new state is copied in. Uses st->gfull as scratch. */
void eo_stepi_work_update(eo_step *st, const double *x1, const double *v1);
/* step_explicit.c */
/* a = M⁻¹(−∇V(x) − C v) at time t (prescribed vertices at their positions at t, a = 0
 * there): the acceleration of the forces of the potentials (not the inertia, linear or
 * friction terms), with the scene's mass matrix (consistent: factored on demand).
 * Term weights are left at 1. Uses st->xw, gfull, vnew, guess as scratch. */
int eo_stepi_accel(eo_step *st, double t, const double *x, const double *v, double *a);

#endif
