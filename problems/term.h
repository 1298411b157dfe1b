/* Objective terms of a step problem (private to problems/): the built-in terms'
 * constructors and helpers. The term interface itself (eo_sys, eo_term_ops, eo_term,
 * eo_term_type and its role flags) is include/elastopt/impl/term.h. */
#ifndef EO_PROBLEMS_TERM_H
#define EO_PROBLEMS_TERM_H

#include "elastopt/impl/term.h"

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

/* The built-in term kinds (problems/registry.c lists them in the order of summation). */
extern const eo_term_type eo_term_type_inertia, eo_term_type_elastic, eo_term_type_spring, eo_term_type_collision,
    eo_term_type_damping, eo_term_type_friction, eo_term_type_gravity, eo_term_type_linear, eo_term_type_traction;

/* element.c: ∂²J/∂F² (81, pairs (ij), (kl) row-major) at F, and H += w Gᵀ D G over n
 * nodes (G: n×3 shape gradients; H (3n)², row-major). */
void eo_elementi_det_hessian(const double F[9], double D[81]);
void eo_elementi_GtDG(int n, const double *G, const double *D, double w, double *H);
/* the lower block triangle of H from the upper (after eo_elementi_GtDG) */
void eo_elementi_mirror(int n, double *H);
/* element.c: the consistent mass matrix ρₖVₖ M_el ⊗ I₃ of tet k ((3·npe)², row-major;
 * the linear tet's ρV/20 (1 + δ_ab) exactly as always), for the inertia and damping terms
 * and the explicit integrators' mass solve. */
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
