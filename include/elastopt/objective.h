/// @file objective.h
/// The objective interface every optimizer sees: g(x) over n free variables.
///
/// A step problem (problems/step.c) implements it as a sum of terms (inertia,
/// elasticity, gravity, springs, ...); tests implement it for small analytic problems;
/// the Poisson problem implements it too. Optimizers use only this interface, so
/// every optimizer works on every problem.
///
/// ```c
/// double g; eo_objective_gradient(obj, x, &g, grad);   // g may be +INFINITY (inverted)
/// eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);     // H borrowed, fixed pattern
/// eo_csc *L; unsigned long ver;                         // optional constant SPD matrix
/// if (eo_objective_constant_hessian(obj, &L, &ver) == EO_OK) { /* factor once per ver */ }
/// ```
/// Optional per-vertex ops (vertex block descent, solvers/optim/vbd.c):
/// ```c
/// eo_vertex_blocks vb; eo_objective_vertex_blocks(obj, &vb);   // blocks, coupling graph
/// eo_objective_vertex_block(obj, x, b, EO_PROJ_CLAMP, &e, g3, H3); // G_b, ∂g/∂x_b, 3×3 block
/// ```
/// Optional condensed assembly for mixed methods (mixed_fem), with the split ops:
/// ```c
/// eo_objective_split_assemble(obj, x, K, w, EO_PROJ_CLAMP, &H); // rest of g + w Σ GᵀKG
/// ```
/// Optional per-element ops (the Hessian fixes `progressive` and friends use them):
/// ```c
/// int ne = eo_objective_n_elements(obj);              // E elements, < 0: unsupported
/// eo_objective_element_residual(obj, grad, r);         // r[e] = max node |grad| of e
/// eo_objective_hessian_masked(obj, x, proj_of, &H);    // element e projected by proj_of[e]
/// ```
/// Ownership: the objective owns its Hessian matrix; callers borrow it until the next
/// hessian or hessian_masked call (both write the same matrix).
#ifndef ELASTOPT_OBJECTIVE_H
#define ELASTOPT_OBJECTIVE_H

#include "export.h"
#include "proj.h"
#include "sparse.h"
#include "status.h"
#include "ctx.h"

#ifdef __cplusplus
extern "C" {
#endif

/// The inertia part of a step objective g(x) = ½‖x − x̃‖²_M + w·E(x) (ops->inertia).
/// Everything over the free variables and borrowed from the objective.
typedef struct eo_objective_inertia {
    const eo_csc *M;          ///< constant SPD mass matrix (upper-triangle CSC, sparse.h);
                              ///< values unchanged while `version` is
    unsigned long version;    ///< changes when M does (a release rebuilt the pattern)
    const double *x_prev;     ///< xₙ: positions at the start of the step (n)
    const double *x_pred;     ///< x̃: the integrator's predictor (n)
    double w;                 ///< weight of E (backward Euler h², Newmark h²/4)
} eo_objective_inertia;

struct eo_objective_characteristic;
struct eo_material_type;
struct eo_material_coef;

/// Optional objective operations an optimizer may require (eo_optimizer_type.needs_ops):
/// the per-tet split F = D x (split_info, split_apply, split_adjoint and, where given,
/// split_assemble: one F per tet, the linear tet's), the vertex blocks (vertex_blocks,
/// vertex_block), the partitioned evaluation of linear tets (eo_step_set_part: the
/// distributed PETSc backend).
/// What an optimizer needs for the distributed path (solver.backend=petsc; the solver
/// names it when it refuses): the constant matrix and its factor of the whole problem
/// (constant_hessian, constant_factor), the inertia split (inertia), the whole vector in
/// one process (an external code).
/// EO_OBJ_NEEDS_NO_CONTACT: the terms outside the optimizer's split enter it explicitly
/// (admm_pd's global step), which a stiff penalty contact term makes diverge: a scene with
/// `collisions` is refused at configuration (eo_sim_check_solver).
enum { EO_OBJ_NEEDS_SPLIT = 1, EO_OBJ_NEEDS_VERTEX = 2, EO_OBJ_NEEDS_PARTS = 4, EO_OBJ_NEEDS_CONSTANT = 8,
       EO_OBJ_NEEDS_INERTIA = 16, EO_OBJ_NEEDS_WHOLE = 32, EO_OBJ_NEEDS_NO_CONTACT = 64 };


/// The elastic elements of an objective (ops->split_info), borrowed.
typedef struct eo_objective_split {
    int ne;                                         ///< elements E (= n_elements)
    double w;                                       ///< weight of E in g (h², h²/4, 1)
    const struct eo_material_type *const *type;     ///< E materials
    const struct eo_material_coef *const *coef;     ///< E coefficient sets
    const double *vol;                              ///< E rest volumes V_e
    const double *k;                                ///< E weights k_e of L (Pa; λ + 2μ for the
                                                    ///< classical models, 0 for edge tets)
} eo_objective_split;
/// The vertex blocks of an objective's free variables (ops->vertex_blocks), for per-vertex
/// block coordinate methods (vbd, jacobi_chebyshev). Everything borrowed from the
/// objective, valid while `version` is unchanged.
typedef struct eo_vertex_blocks {
    int nb;                   ///< number of blocks (the step objective: its free vertices)
    const int *dofs;          ///< 3·nb: free index of coordinate c of block b at dofs[3b + c]
                              ///< (-1: that coordinate is not free); every free variable
                              ///< lies in exactly one block
    const int *adj_ptr;       ///< nb + 1: the blocks coupled to block b (sharing an element
                              ///< or a spring) are adj[adj_ptr[b] .. adj_ptr[b + 1]), b itself
    const int *adj;           ///< excluded
    unsigned long version;    ///< changes when the blocks do (a release rebuilt the pattern)
} eo_vertex_blocks;

typedef struct eo_objective_ops {
    /// g(x). Return EO_OK; set *g = +INFINITY where undefined (never NaN).
    int (*value)(void *data, const double *x, double *g);
    /// g(x) and ∇g(x) (n). *g may be +INFINITY (then grad is unspecified).
    int (*gradient)(void *data, const double *x, double *g, double *grad);
    /// ∇²g(x) with per-element projection `proj`, into the fixed pattern; *H borrowed.
    int (*hessian)(void *data, const double *x, eo_proj proj, eo_csc **H);
    /// Optional: a diagonal metric (e.g. lumped mass) for scaled methods; NULL if none.
    int (*metric_diag)(void *data, double *d);
    /// Optional: number of inverted elements at x (for logs); NULL if not applicable.
    int (*inverted_count)(void *data, const double *x);
    /// Optional: a CONSTANT symmetric positive definite approximation L of ∇²g over the
    /// free variables (the projective-dynamics "global" matrix, Bouaziz et al. 2014; Liu,
    /// Bouaziz & Kavan 2017), for optimizers that factor it once and reuse the factors.
    /// *L is borrowed and stays valid, with unchanged values, as long as *version does
    /// not change (and at most until the objective is destroyed); a new version means a
    /// new matrix (pattern, size or values: the step objective bumps it when a release
    /// rebuilds its pattern or the integrator weight changes). Does not touch the matrix
    /// returned by `hessian`. Same upper-triangle CSC invariants as `hessian` (sparse.h).
    /// NULL if the objective cannot give one: projective_dynamics then factors ∇²g at
    /// the first iterate of each minimization instead. The step objective's L is defined
    /// in problems/pd_matrix.c.
    int (*constant_hessian)(void *data, eo_csc **L, unsigned long *version);
    /// Optional: the number E of elements whose Hessians a per-element projection acts
    /// on (the step objective: its tets; tets of an edge material count but are ignored
    /// by the mask). Fixed for the objective's pattern. NULL if none.
    int (*n_elements)(void *data);
    /// Optional (with n_elements): ∇²g(x) like `hessian`, but element e assembled with
    /// projection proj_of[e] (an eo_proj value, E entries, borrowed); contributions without
    /// a per-element form (inertia, springs, contact) are not projected. Same matrix and
    /// pattern as `hessian`; *H borrowed.
    int (*hessian_masked)(void *data, const double *x, const unsigned char *proj_of, eo_csc **H);
    /// Optional (with n_elements): r[e] = max over the nodes of element e of the 2-norm of
    /// v at that node's free coordinates (v: n entries, e.g. ∇g; constrained coordinates
    /// count as 0), E entries. Locates the residual on the elements.
    int (*element_residual)(void *data, const double *v, double *r);
    /// Optional (step objectives with an inertia term): M, xₙ, x̃ and w of
    /// g = ½‖x − x̃‖²_M + w·E (see eo_objective_inertia), for methods that need the mass
    /// matrix apart from ∇E (fixed_point: x ← x − M⁻¹∇g(x) = x̃ − w M⁻¹∇E(x)). May
    /// reassemble through the objective's Hessian storage: a matrix borrowed from
    /// `hessian` is invalid afterwards. EO_ERR_UNSUPPORTED where there is no inertia term
    /// (the static integrator).
    int (*inertia)(void *data, eo_objective_inertia *out);
    /// Optional (with constant_hessian): the objective's OWN factorization of L, for the
    /// optimizers that apply L⁻¹ (lbfgs h0 = pd, ncg precond = pd, projective_dynamics,
    /// pd_local_global; solvers/optim/pd_factor.c uses it when solver.linear is a
    /// CHOLMOD method). constant_factor brings it up to date with the current L: the step
    /// objective factors L once per scene over ALL coordinates and follows a change of the
    /// constrained set (a release, a pin) by CHOLMOD rank updates/downdates instead of a
    /// new factorization (problems/step_pd.c). Returns the number of fresh numeric
    /// factorizations it did (0: the factor was current or updated in place; 1);
    /// EO_ERR_UNSUPPORTED when it offers none in its current state (the caller then
    /// factors constant_hessian itself); another negative status on failure
    /// (EO_ERR_INVALID: L not positive definite).
    int (*constant_factor)(void *data);
    /// x = L⁻¹ b (n values each, distinct arrays) with that factor, after constant_factor
    /// returned EO_OK and until the objective changes. No allocation.
    int (*constant_solve)(void *data, const double *b, double *x);
    /// Optional: the rounding scales of g at x, in the units of g, for the stopping
    /// rules' floor (solver.h, "The convergence measure"): s[0] bounds the decrement
    /// λ² = ∇gᵀH⁻¹∇g that the rounding of ∇g alone produces, s[1] the metric gradient
    /// norm ‖∇g‖²_{D⁻¹} (D = metric_diag), both as s·ε², ε the double rounding unit.
    /// The step objective (problems/step_objective.c) gives
    ///   s[0] = Σᵢ Dᵢ xᵢ² + w Σₜ Vₜ (μₜ + λₜ)²/μₜ,
    ///   s[1] = Σᵢ Dᵢ xᵢ² + 3 w² Σ_v a_v²/m_v,   a_v = Σ_{t ∋ v} (μₜ + λₜ) Vₜ^{2/3},
    /// the rounding of x − x̃ (inertia) and of the stresses (elasticity: a stress
    /// rounded at (μ + λ)ε per unit area, seen through the softest element mode μ);
    /// s[2] the magnitude of the terms g is summed from (the plateau of the decrement
    /// rules compares with ε·s[2]): Σᵢ Dᵢ xᵢ² + w Σₜ Vₜ (μₜ + λₜ). s[0] grows as λ²/μ,
    /// s[2] only as λ: a nearly incompressible scene must not make the value plateau
    /// (λ/μ)× looser than g resolves.
    /// NULL: no floor (the rules then stop only on measured progress).
    int (*rounding_scale)(void *data, const double *x, double s[3]);
    /// Optional: the largest step along p that inverts no element, for barrier-aware line
    /// searches (solvers/linesearch/barrier_filter.c): *alpha_max = the smallest α > 0 at
    /// which an element with J = det F > 0 at x reaches J = 0 on x + αp (+INFINITY if none
    /// does). Elements already inverted at x (J ≤ 0) do not limit the step. Constrained
    /// coordinates do not move. x, p: n values each (borrowed). The step objective
    /// (problems/step_objective.c) solves J(α) = 0, a cubic in α, for each tet. NULL: the
    /// objective knows no elements (barrier_filter is then plain backtracking).
    int (*max_step)(void *data, const double *x, const double *p, double *alpha_max);
    /// Optional: the characteristic scales of g (Zhu, Bridson & Kaufman 2018, BCQN §6–7),
    /// for the characteristic_gradient stopping rule and the bcqn blend. NULL: none.
    int (*characteristic)(void *data, struct eo_objective_characteristic *out);
    /// Optional (step objectives; for splitting methods such as admm_pd): the elastic
    /// elements as linear maps of x. Element e (E = n_elements, the tets) has the
    /// deformation gradient F_e(x) = G_e x + c_e (9 values, row-major as material.h;
    /// c_e from the prescribed coordinates), energy w·V_e·ψ_e(F_e) in g, and weight k_e
    /// of the constant matrix: L = M + w·Σ_e V_e k_e G_eᵀG_e + (springs) (constant_hessian,
    /// problems/pd_matrix.c). Everything in *out is borrowed from the objective and valid
    /// until its pattern changes. Tets of an edge (spring) material have
    /// type->flags & EO_MATERIAL_EDGE and k_e = 0: they are not elastic elements here.
    int (*split_info)(void *data, eo_objective_split *out);
    /// F[9e..9e+8] = F_e(x) for every element e (9E values).
    int (*split_apply)(void *data, const double *x, double *F);
    /// out = Σ_e G_eᵀ S_e over the free variables (n values; S: 9E values, the element
    /// "stresses"; constrained coordinates dropped): the gradient of Σ_e S_e : F_e(x).
    int (*split_adjoint)(void *data, const double *S, double *out);
    /// Optional (with vertex_block): the vertex blocks of the free variables and their
    /// coupling (eo_vertex_blocks). May allocate once per pattern (the step objective
    /// builds its vertex-to-tet map at the first call). EO_ERR_UNSUPPORTED, with a
    /// message naming the reason, if a term of g has no per-vertex form (the step
    /// objective: damping, friction; inertia, elasticity, springs, gravity, the linear
    /// term and penalty obstacles have one).
    int (*vertex_blocks)(void *data, eo_vertex_blocks *out);
    /// Optional: the part G_b of g(x) that depends on block b with every other block held
    /// fixed (Chen et al. 2024, "Vertex Block Descent": the vertex's inertia, potentials and
    /// the energies of its elements): *e = G_b(x) (+INFINITY where undefined; G_b may
    /// carry constants of the other blocks, so only differences of *e at the same other
    /// blocks mean something); unless g3 is NULL, g3 = ∂g/∂x_b (the 3 coordinates of the
    /// block, also the full gradient's entries there; 0 where not free); unless H3 is
    /// NULL, H3 = the 3×3 block ∂²g/∂x_b² (row-major) of the Hessian whose elements are
    /// projected with proj (rows and columns of non-free coordinates: 0). No allocation.
    int (*vertex_block)(void *data, const double *x, int b, eo_proj proj, double *e, double g3[3], double H3[9]);
    /// Optional (with the split ops; for mixed methods that condense per-element variables,
    /// solvers/optim/mixed_fem.c): the Hessian at x of every term of g EXCEPT the elastic
    /// elements' energy w·Σ_e V_e ψ_e(F_e) (inertia, springs and edge materials, contact,
    /// friction, damping; assembled with projection `proj`), plus alpha·Σ_e G_eᵀ K_e G_e
    /// with the given per-element 9×9 matrices K (81 per element, row-major, the element
    /// order and F layout of split_apply; E = split_info's ne blocks; blocks of edge-
    /// material elements are ignored). Written into the matrix and pattern of `hessian`
    /// (the same borrowed *H, invalidating a matrix borrowed from hessian before).
    int (*split_assemble)(void *data, const double *x, const double *K, double alpha, eo_proj proj, eo_csc **H);
} eo_objective_ops;

/// Characteristic scales of an objective (ops->characteristic), in the units of g.
/// The step objective gives, with w the weight of E, a_v = Σ_{t ∋ v} A_{t,v} h_t
/// (A_{t,v} the rest area of the face of tet t opposite vertex v, h_t = ‖∂²ψ/∂σ²(I)‖₂ of
/// t's material, the norm of its Hessian in the singular values at rest: 2μ + 3λ for the
/// classical isotropic models), over every vertex of the mesh:
typedef struct eo_objective_characteristic {
    double grad;          ///< characteristic gradient norm w·‖a‖₂ (BCQN's g_c: ‖∇g‖ of a
                          ///< unit distortion; units of ∇g)
    double stiffness;     ///< w·(volume-weighted mean h_t): the factor between g's elastic
                          ///< part and a unit-modulus energy (units of g per m³)
    double volume;        ///< total rest volume Σ V_t (m³)
} eo_objective_characteristic;

/// The vector space of an objective's vectors (x, ∇g, directions): eo_objective.space.
/// NULL (every objective but a distributed one): the n entries are all this process's and
/// a sum over the vector is a plain loop. A distributed objective (one part of a problem
/// spread over processes, ctx.h eo_dist_hooks; solvers/dist_objective.c) has n LOCAL
/// entries: the ones its part owns and copies of entries other parts own, every copy
/// equal to its owner's value (a vector the objective hands out, ∇g or the metric, is
/// complete at every copy; entry-wise updates such as x + αp keep that). Sums over the
/// whole vector count the owned entries once and are reduced over the parts (eo_vdot,
/// eo_vnorm2, eo_vnorm_inf, eo_vreduce), so every part takes the same decisions. The
/// Hessian of a distributed objective holds only its part's terms (the parts' matrices
/// add up to the whole one, over the copies): a quadratic form pᵀHp of it is a partial sum
/// (eo_vreduce with EO_REDUCE_SUM), and only a linear solver that takes such matrices
/// (eo_linsolve_set_space) solves with it. Borrowed from the objective.
typedef struct eo_vspace {
    int n;                        ///< local entries (the objective's n)
    long nglobal;                 ///< entries of the whole vector
    const unsigned char *own;     ///< n flags: 1 = this part owns the entry
    const long *gid;              ///< n: the entry's index in the whole vector; the owned
                                  ///< entries of part r are a contiguous range, after part r − 1's
    /// Reduce v[0..k) over the parts in place (collective); 0 or a negative status.
    int (*reduce)(double *v, int k, eo_reduce_op op, void *user);
    /// v (n): this part's partial sums → the totals over the parts at every copy
    /// (collective); 0 or a negative status.
    int (*assemble)(double *v, void *user);
    void *user;
    int nparts, part;             ///< processes and this one (0-based)
} eo_vspace;

typedef struct eo_objective {
    int n;                          ///< number of free variables
    const eo_objective_ops *ops;
    void *data;
    long n_value, n_gradient, n_hessian;  ///< evaluation counters
    /// The vector space (above); NULL: the ordinary, undistributed one. Appended last.
    const eo_vspace *space;
} eo_objective;

/// Σ aᵢbᵢ over the whole vector (space NULL: the plain loop, bit for bit; else the owned
/// entries, reduced over the parts: collective).
EO_API double eo_vdot(const eo_vspace *space, int n, const double *a, const double *b);
/// √eo_vdot(a, a).
EO_API double eo_vnorm2(const eo_vspace *space, int n, const double *a);
/// max |aᵢ| over the whole vector.
EO_API double eo_vnorm_inf(const eo_vspace *space, int n, const double *a);
/// Reduce k values over the parts in place (nothing with space NULL or one part); a
/// failed reduction sets them NAN.
EO_API void eo_vreduce(const eo_vspace *space, double *v, int k, eo_reduce_op op);
/// Σ aᵢbᵢdᵢ over the whole vector (d may be NULL: eo_vdot).
EO_API double eo_vdot_w(const eo_vspace *space, int n, const double *d, const double *a, const double *b);
/// 1 if the space spreads over several processes.
static inline int eo_vspace_distributed(const eo_vspace *s) { return s && s->nparts > 1; }

static inline int eo_objective_value(eo_objective *o, const double *x, double *g)
{
    o->n_value++;
    return o->ops->value(o->data, x, g);
}
static inline int eo_objective_gradient(eo_objective *o, const double *x, double *g, double *grad)
{
    o->n_gradient++;
    return o->ops->gradient(o->data, x, g, grad);
}
static inline int eo_objective_hessian(eo_objective *o, const double *x, eo_proj proj, eo_csc **H)
{
    o->n_hessian++;
    return o->ops->hessian(o->data, x, proj, H);
}
/// The constant matrix of ops->constant_hessian; EO_ERR_UNSUPPORTED if the objective
/// has none (not counted as a Hessian evaluation).
static inline int eo_objective_constant_hessian(eo_objective *o, eo_csc **L, unsigned long *version)
{
    if (!o->ops->constant_hessian) return EO_ERR_UNSUPPORTED;
    return o->ops->constant_hessian(o->data, L, version);
}

/// The rounding scales of ops->rounding_scale at x; EO_ERR_UNSUPPORTED if none.
static inline int eo_objective_rounding_scale(eo_objective *o, const double *x, double s[3])
{
    if (!o->ops->rounding_scale) return EO_ERR_UNSUPPORTED;
    return o->ops->rounding_scale(o->data, x, s);
}

/// The largest step without inversion (ops->max_step); EO_ERR_UNSUPPORTED if none.
static inline int eo_objective_max_step(eo_objective *o, const double *x, const double *p, double *alpha_max)
{
    if (!o->ops->max_step) return EO_ERR_UNSUPPORTED;
    return o->ops->max_step(o->data, x, p, alpha_max);
}

/// The characteristic scales (ops->characteristic); EO_ERR_UNSUPPORTED if none.
static inline int eo_objective_characteristic_get(eo_objective *o, eo_objective_characteristic *out)
{
    if (!o->ops->characteristic) return EO_ERR_UNSUPPORTED;
    return o->ops->characteristic(o->data, out);
}

/// The elastic elements of ops->split_info; EO_ERR_UNSUPPORTED if the objective has no
/// split ops (then split_apply / split_adjoint are unavailable too).
static inline int eo_objective_split_get(eo_objective *o, eo_objective_split *out)
{
    if (!o->ops->split_info || !o->ops->split_apply || !o->ops->split_adjoint) return EO_ERR_UNSUPPORTED;
    return o->ops->split_info(o->data, out);
}

/// The condensed matrix of ops->split_assemble (counted as a Hessian evaluation);
/// EO_ERR_UNSUPPORTED if the objective has no such op.
static inline int eo_objective_split_assemble(eo_objective *o, const double *x, const double *K, double alpha,
                                              eo_proj proj, eo_csc **H)
{
    if (!o->ops->split_assemble) return EO_ERR_UNSUPPORTED;
    o->n_hessian++;
    return o->ops->split_assemble(o->data, x, K, alpha, proj, H);
}

/// Number of elements of the per-element ops, or EO_ERR_UNSUPPORTED (< 0) if the
/// objective has none (then hessian_masked and element_residual are unavailable too).
static inline int eo_objective_n_elements(eo_objective *o)
{
    if (!o->ops->n_elements || !o->ops->hessian_masked || !o->ops->element_residual)
        return EO_ERR_UNSUPPORTED;
    return o->ops->n_elements(o->data);
}
/// The Hessian with a per-element projection (counted as a Hessian evaluation);
/// EO_ERR_UNSUPPORTED if the objective has no per-element ops.
static inline int eo_objective_hessian_masked(eo_objective *o, const double *x,
                                              const unsigned char *proj_of, eo_csc **H)
{
    if (!o->ops->hessian_masked) return EO_ERR_UNSUPPORTED;
    o->n_hessian++;
    return o->ops->hessian_masked(o->data, x, proj_of, H);
}
/// The objective's own factorization of its constant matrix (ops->constant_factor):
/// fresh factorizations done (0 or 1), EO_ERR_UNSUPPORTED if it has none, or an error.
static inline int eo_objective_constant_factor(eo_objective *o)
{
    if (!o->ops->constant_factor || !o->ops->constant_solve) return EO_ERR_UNSUPPORTED;
    return o->ops->constant_factor(o->data);
}
/// The inertia part of a step objective (ops->inertia); EO_ERR_UNSUPPORTED if none.
static inline int eo_objective_inertia_get(eo_objective *o, eo_objective_inertia *out)
{
    if (!o->ops->inertia) return EO_ERR_UNSUPPORTED;
    return o->ops->inertia(o->data, out);
}
/// The vertex blocks (ops->vertex_blocks); EO_ERR_UNSUPPORTED if the objective has none.
static inline int eo_objective_vertex_blocks(eo_objective *o, eo_vertex_blocks *out)
{
    if (!o->ops->vertex_blocks || !o->ops->vertex_block) return EO_ERR_UNSUPPORTED;
    return o->ops->vertex_blocks(o->data, out);
}
/// Block b's part of g (ops->vertex_block; not counted as an evaluation of g).
static inline int eo_objective_vertex_block(eo_objective *o, const double *x, int b, eo_proj proj, double *e,
                                            double g3[3], double H3[9])
{
    return o->ops->vertex_block(o->data, x, b, proj, e, g3, H3);
}
/// Per-element residual r (see ops->element_residual); EO_ERR_UNSUPPORTED if none.
static inline int eo_objective_element_residual(eo_objective *o, const double *v, double *r)
{
    if (!o->ops->element_residual) return EO_ERR_UNSUPPORTED;
    return o->ops->element_residual(o->data, v, r);
}

#ifdef __cplusplus
}
#endif
#endif
