/// @file impl/term.h
/// The term-author interface of the step engine (installed, for plug-ins and in-tree
/// terms): a step problem g(x) is a sum of terms, each a const ops table
/// (eo_term_ops) instantiated per step problem, and each kind of term a registered
/// eo_term_type (kind EO_KIND_TERM) that owns its scene section, creates its instance for a
/// scene, and declares by role flags (EO_TERM_*) where the engine uses it besides g:
/// the potential V (static reactions, the integrators' force fₙ, explicit forces), the
/// statistics, Rayleigh damping's stiffness, load stepping, the projective-dynamics
/// factor and partitioned evaluation.
///
/// A new force is one file defining its ops and its eo_term_type, plus one line in
/// problems/registry.c (or, from outside the tree, `eo_register(ctx, EO_KIND_TERM, &t)`
/// before the scene is loaded): see docs/library.md, "A new force".
///
/// g(x) = Σ_terms term(x): each term adds its energy, its gradient (into the FULL
/// 3·nv gradient; the step gathers the free entries) and its Hessian (into the shared
/// fixed-pattern assembler over the free coordinates). Terms see the full coordinate
/// vector with constrained entries already set to their prescribed values, so they
/// never deal with elimination except through the free ids of the shared tet group.
///
/// Life cycle: create (eo_term_type.create, allocations here), `attach` each time the
/// pattern is (re)built — before eo_assembler_finalize, to register elements — and
/// `prepare` after finalize (precompute constant values such as the consistent mass).
/// Energy, gradient and Hessian never allocate.
#ifndef ELASTOPT_IMPL_TERM_H
#define ELASTOPT_IMPL_TERM_H

#include "../config.h"
#include "../element.h"
#include "../export.h"
#include "../material.h"
#include "../mesh.h"
#include "../registry.h"
#include "../scene.h"
#include "../sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Data shared by every term of one step problem (owned by the step engine).
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
    const double *vload;        /* nv: the gravity load per unit acceleration, the row sums
                                   of the scene's mass matrix: Σ ρ∫N_v dV + point masses
                                   (consistent), vmass (lumped; and for p1 both) */
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
    /* a distributed run's local mesh (eo_dist_hooks.owned_vertices): nv flags, 1 = this
     * part owns the vertex. The local mesh's per-vertex data (lumped masses, loads) are
     * the part's shares and add up over the parts, but a term that is a function of one
     * vertex's position alone (penalty contact) must be counted once: by the owner
     * (eo_sys_vertex_once). NULL = every vertex (one process) */
    const unsigned char *vonce;
} eo_sys;

/* Tets of the current part (all tets without one): i-th tet and their count. */
static inline int eo_sys_ntets(const eo_sys *s) { return s->part_tets ? s->part_nt : s->nt; }
static inline int eo_sys_tet(const eo_sys *s, int i)
{
    return s->part_tets ? s->part_tets[i] : s->tet_order ? s->tet_order[i] : i;
}
/* 1 if this part evaluates the nodal terms of vertex v. */
static inline int eo_sys_vertex_on(const eo_sys *s, int v) { return !s->vown || s->vown[v]; }
/* 1 if this part evaluates the terms that depend on vertex v's position alone (penalty
 * contact): vertex_on, and in a distributed run only on the vertex's owner. */
static inline int eo_sys_vertex_once(const eo_sys *s, int v)
{
    return eo_sys_vertex_on(s, v) && (!s->vonce || s->vonce[v]);
}

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
    const struct eo_term_type *type; /* its kind (set by the engine after create) */
    unsigned flags;             /* type->flags (set by the engine) */
};

/// Role flags of a term kind (eo_term_type.flags): where the engine uses the term
/// besides g. Every term is summed into g (energy, gradient, Hessian) with the
/// integrator's weight w unless EO_TERM_INERTIA says otherwise.
enum {
    /// ½‖x − x̃‖²_M: weight 1 (never w), vec = x̃ (the integrator's prediction, set per
    /// step); the objective's `inertia` op. At most one per step.
    EO_TERM_INERTIA = 1u << 0,
    /// Part of the potential V(x) (weight 1 there): the static reaction (work of the
    /// prescribed motions), the force fₙ = −∇V(xₙ) of integrators with force_n, the force
    /// of explicit integrators, and the statistics' potential energy.
    EO_TERM_POTENTIAL = 1u << 1,
    /// Counted in the statistics' elastic energy and in Rayleigh damping's stiffness K₀
    /// (its clamped Hessian at xₙ).
    EO_TERM_ELASTIC_ENERGY = 1u << 2,
    /// Counted in the statistics' contact energy; summed after the other potentials.
    EO_TERM_CONTACT = 1u << 3,
    /// Reported as the statistics' gravity energy (−f_gᵀx, from eo_sys.vload and the
    /// scene's gravity), not through its own energy op.
    EO_TERM_GRAVITY = 1u << 4,
    /// Its weight is ramped by time.load_steps (w·min(1, k/L) in step k of a static run).
    EO_TERM_LOAD_STEPPED = 1u << 5,
    /// The integrators' linear term −cᵀx: vec = c = fₙ (the potentials' force and the
    /// damping force at xₙ, vₙ), set per step. At most one per step.
    EO_TERM_FORCE_N = 1u << 6,
    /// Velocity-dependent damping C v (term_damping.c: per-step stage velocity, Rayleigh
    /// K₀, explicit force −C v). At most one per step.
    EO_TERM_DAMPING = 1u << 7,
    /// Lagged at xₙ each step (friction: contacts, normal forces). At most one per step.
    EO_TERM_LAGGED = 1u << 8,
    /// Has no constant projective-dynamics matrix: the objective's constant_factor /
    /// constant_solve are unsupported when the scene has it.
    EO_TERM_NO_PD = 1u << 9,
    /// Has no partitioned form (eo_step_set_part is refused when the scene has it).
    EO_TERM_NO_PART = 1u << 10,
};

/// A kind of term (registry kind EO_KIND_TERM). The engine creates, for each step, one
/// instance of every registered kind that the scene uses, in registry order (the order
/// of summation of g).
typedef struct eo_term_type {
    /// name, summary (`elastopt list`), params: the descriptor table of the section (of
    /// each list entry with EO_TERM_SECTION_LIST; for `elastopt help`, the config
    /// reference and the schema), params_size.
    eo_method_info info;
    /// Key of the scene's JSON this kind reads ("tractions"), or NULL (none, or a
    /// section the scene loader reads itself into eo_scene).
    const char *section;
    unsigned flags;           ///< EO_TERM_* roles (and EO_TERM_SECTION_LIST)
    /// Optional, NULL-terminated: the keys of the section that are not params (a box, a
    /// list), full dotted paths ("tractions.N.box"), for help and the schema.
    const eo_cfg_raw_doc *raw_docs;
    /// Optional, NULL-terminated: sub-sections of the section read with a params table
    /// ("tractions.N.plane", the scene's plane table), for help and the schema.
    const eo_cfg_doc *sub_docs;
    /// Optional: read the section at scene load (called only when the scene has the key;
    /// errors through eo_cfg_error name the file:line). *out is kept in the scene and
    /// given to create; freed with free_cfg. NULL: with info.params the section is read
    /// with eo_cfg_section into a params_size struct (freed with eo_free).
    int (*load)(eo_ctx *ctx, eo_cfg *cfg, const eo_scene *sc, const char *section, void **out);
    void (*free_cfg)(eo_ctx *ctx, void *cfg);
    /// Create the term of one step problem: cfg is what load made (NULL when the scene
    /// has no such section). EO_OK with *out NULL when the scene does not use the term.
    /// Required.
    int (*create)(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out);
} eo_term_type;

/// eo_term_type.flags: the section is a list ("tractions": [ {...}, ... ]), its entries
/// documented as section.N by info.params.
#define EO_TERM_SECTION_LIST (1u << 16)

/// Allocate a term of ops (weight 1) with a full-length zeroed vector if with_vec, through
/// s->ctx; freed with eo_term_destroy (which calls ops->destroy first).
EO_API int eo_term_alloc(eo_sys *s, const eo_term_ops *ops, int with_vec, eo_term **out);
EO_API void eo_term_destroy(eo_ctx *ctx, eo_term **t);
/// The configuration a scene holds for a term kind (what its load made), NULL if none.
EO_API const void *eo_scene_term_cfg(const eo_scene *sc, const eo_term_type *type);

#ifdef __cplusplus
}
#endif
#endif
