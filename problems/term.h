/* Objective terms of a step problem (private to problems/).
 *
 * g(x) = Σ_terms term(x): each term adds its energy, its gradient (into the FULL
 * 3·nv gradient; the step gathers the free entries) and its Hessian (into the shared
 * fixed-pattern assembler over the free coordinates). Terms see the full coordinate
 * vector with constrained entries already set to their prescribed values, so they
 * never deal with elimination except through the free ids of the shared tet group.
 *
 * Life cycle: create (term_*_create, allocations here), `attach` each time the pattern
 * is (re)built — before eo_assembler_finalize, to register elements — and `prepare`
 * after finalize (precompute constant values such as the consistent mass). Energy,
 * gradient and Hessian never allocate. */
#ifndef EO_PROBLEMS_TERM_H
#define EO_PROBLEMS_TERM_H

#include "elastopt/element.h"
#include "elastopt/material.h"
#include "elastopt/mesh.h"
#include "elastopt/scene.h"
#include "elastopt/sparse.h"

/* Data shared by every term of one step problem (owned by step.c). */
typedef struct eo_sys {
    eo_ctx *ctx;
    const eo_mesh *mesh;
    int nv, nt, n_full;
    const double *Dminv;        /* 9·nt rest inverse edge matrices */
    const double *vol;          /* nt rest volumes */
    const double *rho;          /* nt densities */
    const double *psi_rest;     /* nt: ψ(I) of the tet's material; the elastic term reports
                                   Vₜ(ψ(Fₜ) − ψ(I)) so that g carries no large constant
                                   (it would eat the digits the Armijo test compares) */
    const eo_material_type *const *tet_type;   /* nt */
    const eo_material_coef *const *tet_coef;   /* nt */
    /* the element (element.h): npe nodes per tet, their ids enodes[npe·k ..] (the mesh's
     * tets for 4 nodes, its tet10 for 10); linear = 1 for the linear tet, whose own fast
     * paths (eo_tet_evaluate, the Morton-ordered copies) the terms keep */
    const struct eo_element_type *el;
    int npe, linear;
    const int *enodes;
    const double *vmass;        /* nv lumped vertex masses (the element's lumped weights ·ρV
                                   summed, ρV/4 for p1, + point masses) */
    const double *vload;        /* nv: Σ ρ∫N_v dV + point masses, the gravity load per unit
                                   acceleration (= vmass for p1: rows of M sum to ρV/4) */
    const double *pmass;        /* nv point masses (scene point_mass, point_masses), part of
                                   vmass; NULL if none. The consistent mass adds them on its
                                   diagonal */
    /* current pattern */
    const int *full2free;       /* n_full: free id or -1 */
    const int *tet_dofs;        /* 3·npe·nt free ids (-1 constrained) */
    eo_assembler *as;           /* NULL until attached */
    int tet_group;              /* assembler group of the tets (3·npe ids each) */
    /* element workspace for the blocked parallel loops */
    int block;                  /* tets per block */
    double *elem_g;             /* 3·npe·block */
    double *elem_H;             /* (3·npe)²·block */
    int parallel;               /* 1: use OpenMP in element loops */
    const unsigned char *proj_of; /* nt: per-tet projection during a hessian_masked call
                                     (overrides the hessian's proj for tets), else NULL */
    /* partitioned evaluation (eo_step_set_part, a distributed backend): the terms add
     * only the tets part_tets[0..part_nt) and the nodal contributions of the vertices
     * with vown[v] = 1; NULL = everything (the default) */
    const int *part_tets;
    int part_nt;
    const unsigned char *vown;
    /* visit order of the element loops without a part (eo_step_set_tet_order): nt tet
     * ids, a permutation, or NULL for the mesh order. Only the order in which the loops
     * visit the tets (the summation order of g, ∇g and H) changes: tet k is still tet k
     * in every per-tet array and in the assembler */
    const int *tet_order;
    /* with tet_order: the per-tet data the elastic loops read, copied in the visit order
     * (slot i holds tet tet_order[i]), so that those loops stream them instead of
     * jumping through the per-tet arrays: vertex ids (4), Dₘ⁻¹ (9), volume, ψ(I),
     * material, density (the inertia term's loops too); and ord_group, the assembler group of the tets in the same order (slot i
     * = element i; the same free ids as tet_group's element tet_order[i]) */
    const int *ord_tets;
    const double *ord_Dminv, *ord_vol, *ord_psi, *ord_rho;
    const eo_material_type *const *ord_type;
    const eo_material_coef *const *ord_coef;
    int ord_group;
    /* vertex -> incident tets (CSR: the tets of vertex v are vt_tet[vt_ptr[v] .. vt_ptr[v+1]),
     * increasing), for the terms' `vertex` op; NULL until the step objective's op
     * vertex_blocks first builds them (they depend on the mesh only) */
    const int *vt_ptr, *vt_tet;
} eo_sys;

/* Tets of the current part (all tets without one): i-th tet and their count. */
static inline int eo_sys_ntets(const eo_sys *s) { return s->part_tets ? s->part_nt : s->nt; }
static inline int eo_sys_tet(const eo_sys *s, int i)
{
    return s->part_tets ? s->part_tets[i] : s->tet_order ? s->tet_order[i] : i;
}
/* 1 if this part evaluates the nodal terms of vertex v. */
static inline int eo_sys_vertex_on(const eo_sys *s, int v) { return !s->vown || s->vown[v]; }

typedef struct eo_term eo_term;

typedef struct eo_term_ops {
    const char *name;
    /* Energy at full x; +INFINITY where undefined. */
    double (*energy)(eo_term *t, const eo_sys *s, const double *x);
    /* Energy, and gradient added into g (full). */
    double (*gradient)(eo_term *t, const eo_sys *s, const double *x, double *g);
    /* Hessian added into the assembler (free coordinates). */
    int (*hessian)(eo_term *t, const eo_sys *s, const double *x, eo_proj proj);
    /* Optional: register elements in s->as (before finalize). */
    int (*attach)(eo_term *t, eo_sys *s);
    /* Optional: precompute after finalize. */
    int (*prepare)(eo_term *t, eo_sys *s);
    void (*destroy)(eo_term *t, eo_ctx *ctx);
    /* Optional: add this term's constant projective-dynamics matrix (weight included)
     * into s->as. NULL: its Hessian at the rest positions, clamped, is used instead
     * (see pd_matrix.c). */
    int (*pd_hessian)(eo_term *t, const eo_sys *s);
    /* Optional: the part of this term that involves vertex v, every other vertex held
     * fixed (vertex block descent, solvers/optim/vbd.c): its energy is returned (+INFINITY
     * where undefined; constants of the other vertices may be included), its gradient
     * with respect to x_v is ADDED into g3 (3) unless g3 is NULL, and the 3×3 block
     * ∂²/∂x_v² of its Hessian, each element's Hessian projected with proj first, is
     * ADDED into H3 (row-major) unless H3 is NULL. Weight included. Full x, like the
     * other ops; reads s->vt_ptr/vt_tet. NULL: the term has no vertex form. */
    double (*vertex)(eo_term *t, const eo_sys *s, const double *x, int v, eo_proj proj, double *g3, double *H3);
} eo_term_ops;

struct eo_term {
    const eo_term_ops *ops;
    double weight;              /* integrator weight w (elastic, gravity, linear, spring);
                                   the inertia term ignores it (always 1) */
    double *vec;                /* term-specific full vector (x̃, c), may be NULL */
    void *data;                 /* term-specific */
};

/* Constructors (allocate through s->ctx; *out owned by the caller, freed with
 * eo_term_destroy). */
int eo_term_inertia_create(eo_sys *s, int lumped, eo_term **out);
int eo_term_elastic_create(eo_sys *s, eo_term **out);
/* Inverted tets (eo_tet_is_inverted, every tet of the mesh) at the x of the elastic
 * term's last gradient evaluation (counted there for free). */
int eo_term_elastic_inverted(const eo_term *t);
int eo_term_gravity_create(eo_sys *s, const double g[3], eo_term **out);
int eo_term_linear_create(eo_sys *s, eo_term **out);
/* Springs: the edges of the tets of an edge-model region (`material.model = "spring"`,
 * stiffness material.k) plus `nlist` scene springs (`springs` section or a generated
 * `mesh.lattice`: vertex pairs ab, stiffness klist[i] or, klist NULL, k; damping c along
 * the spring). EO_OK with *out NULL: no springs. */
int eo_term_spring_create(eo_sys *s, int nlist, const int *ab, double k, const double *klist, double damping,
                          eo_term **out);
/* Spring damping force f_d = −c ((v_a − v_b)·n̂) n̂ on a (and −f_d on b), n̂ the unit
 * spring direction at x; SUBTRACTED from g (g holds ∇E, the force is −g). Scene
 * springs only; used by the explicit integrators. */
void eo_term_spring_damping(eo_term *t, const eo_sys *s, const double *x, const double *v, double *g);
/* The springs at vertex v (for the step objective's vertex blocks): their number, and the
 * other end of the q-th one. */
int eo_term_spring_degree(const eo_term *t, int v);
int eo_term_spring_other(const eo_term *t, int v, int q);
/* Viscous + Rayleigh damping C = γI + αM + βK₀ (term_damping.c); EO_OK with *out NULL
 * when all three are 0. Per step: set_step (xₙ, κ, b of the stage velocity
 * v_s = κ(x − xₙ) + b; b NULL = 0) and, when needs_stiffness, set_stiffness (K₀ in the
 * current pattern, values copied). apply: out += C u (full vectors; explicit
 * integrators' damping force is −C v). */
int eo_term_damping_create(eo_sys *s, int lumped, double gamma, double alpha, double beta, eo_term **out);
void eo_term_damping_set_step(eo_term *t, const eo_sys *s, const double *xn, double kappa, const double *b);
int eo_term_damping_needs_stiffness(const eo_term *t);
void eo_term_damping_set_stiffness(eo_term *t, const eo_csc *K);
void eo_term_damping_apply(eo_term *t, const eo_sys *s, const double *u, double *out);
/* Penalty contact with the scene's static obstacles (term_collision.c; shapes in
 * obstacle.h). `ob` (nob entries) is borrowed. EO_OK with *out NULL: no obstacle. */
int eo_term_collision_create(eo_sys *s, int nob, const eo_scene_obstacle *ob, eo_term **out);
/* Lagged, smoothed Coulomb friction against the obstacles with friction μ > 0
 * (term_friction.c). EO_OK with *out NULL: no obstacle has friction. Per step:
 * eo_term_friction_lag at xₙ (contacts, normal forces, tangent planes) with the step's
 * end-of-step velocity map vel(vctx, x, v) on n_full vectors (the one the step uses,
 * history-aware for BDF2; affine in x), recomputed from scratch each time. force_n: the
 * integrator's linear term carries fₙ (the friction weight is doubled). */
typedef void (*eo_velocity_map)(const void *vctx, const double *x, double *v);
int eo_term_friction_create(eo_sys *s, int nob, const eo_scene_obstacle *ob, eo_term **out);
void eo_term_friction_lag(eo_term *t, const eo_sys *s, const double *xn, double h, int force_n,
                          eo_velocity_map vel, const void *vctx);
/* Register one 3×3 block per vertex with the assembler (dofs: n_full ints, filled with
 * the free index of every coordinate, -1 constrained): for the per-vertex terms
 * (penalty contact, friction). */
int eo_term_attach_vertex_blocks(eo_sys *s, int *dofs, int *group);
void eo_term_destroy(eo_ctx *ctx, eo_term **t);

/* Shared helper: allocate a term with a full-length vector if `with_vec`. */
int eo_term_alloc(eo_sys *s, const eo_term_ops *ops, int with_vec, eo_term **out);

/* element.c: ∂²J/∂F² (81, pairs (ij), (kl) row-major) at F, and H += w Gᵀ D G over n
 * nodes (G: n×3 shape gradients; H (3n)², row-major). */
void eo_elementi_det_hessian(const double F[9], double D[81]);
void eo_elementi_GtDG(int n, const double *G, const double *D, double w, double *H);
/* the lower block triangle of H from the upper (after eo_elementi_GtDG) */
void eo_elementi_mirror(int n, double *H);
/* element.c: the consistent mass matrix ρₖVₖ M_el ⊗ I₃ of tet k of a general element
 * (s->el; (3·npe)², row-major), for the terms and the explicit integrators' mass solve. */
void eo_sys_element_mass(const eo_sys *s, int k, double *Ke);
/* term_elastic_nodal.c: the nodal volumetric part of the average-nodal-pressure element
 * (EO_ELEMENT_NODAL_DILATATION), owned by the elastic term: energy (unweighted), gradient
 * (w·∇ added into g, returns the unweighted energy), Hessian (w·∇² into s->as). */
typedef struct eo_anp eo_anp;
int eo_anp_create(eo_sys *s, eo_anp **out);
int eo_anp_attach(eo_anp *a, eo_sys *s);
double eo_anp_energy(eo_anp *a, const eo_sys *s, const double *x);
double eo_anp_gradient(eo_anp *a, const eo_sys *s, const double *x, double w, double *g);
int eo_anp_hessian(eo_anp *a, const eo_sys *s, const double *x, eo_proj proj, double w);
void eo_anp_destroy(eo_anp **a, eo_ctx *ctx);

/* Element loop helpers. */
static inline void eo_gather12(const double *x, const int *tet, double x12[12])
{
    for (int a = 0; a < 4; a++)
        for (int c = 0; c < 3; c++) x12[3 * a + c] = x[3 * tet[a] + c];
}

#endif
