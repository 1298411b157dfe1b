/* The projective-dynamics matrix L of the step objective (objective op
 * constant_hessian), used by the projective_dynamics optimizer.
 *
 * Definition (over the free coordinates of the current pattern):
 *
 *     L = M + w·Σₜ Vₜ kₜ GₜᵀGₜ  [+ the rest Hessian of the springs, clamped]
 *
 *   M      the inertia term's mass matrix (consistent or lumped, as the scene says);
 *          absent for the static integrator
 *   w      the integrator weight (h² backward Euler, h²/4 Newmark, 1 static)
 *   Vₜ     rest volume, Gₜ = ∂vec(Fₜ)/∂x (9×12, from Dm⁻¹; Gₜ = Bₜ ⊗ I₃)
 *   kₜ     = (1/3) Σᵢ ∂²ψ/∂F_ii² at F = I (clamped) = λ + 2μ, the P-wave modulus, for
 *          every model that linearizes to linear elasticity (linear, stvk, corotated,
 *          fixed_corotated, neo_hookean, stable_neo_hookean)
 *   gravity and Newmark's linear term have zero Hessian and add nothing.
 *
 * Why this L. Projective dynamics (Bouaziz et al. 2014) writes each element energy as
 * a weighted distance k/2·‖Gx − p‖² to a projection p onto a constraint set, which
 * makes the global matrix M + w Σ V k GᵀG constant; Liu, Bouaziz & Kavan (2017) read
 * the PD iteration as quasi-Newton with this matrix as the Hessian approximation and
 * use it for arbitrary hyperelastic materials. The element block k·I₉ is invariant
 * under rotations (Gᵀ(R⊗I)ᵀ(R⊗I)G = GᵀG), so L stays a good model of ∇²g however far
 * the elements rotate (the twisting bar turns half a turn); the material's own rest
 * Hessian Vₜ GᵀC G is not: its 3 skew (rotation) modes have zero stiffness, and an
 * element rotated by 90° sees its stiff and soft directions swapped. The scalar k is
 * the rest stiffness C_iiii of a uniaxial strain (λ + 2μ): it lies between the rest
 * tensor's shear eigenvalue 2μ and its bulk eigenvalue 2μ + 3λ, matches the ARAP
 * weight 2μ of the corotated term plus λ for its volume term, and is taken from the
 * material kernel (no per-model table), so any model gets a consistent weight.
 * Measured on examples/twist.json (50 steps, tol 1e-10, iterations per step, plain PD /
 * L-BFGS-PD m = 5): k = λ + 2μ 114 / 24; k = 2μ 101 / 28; k = tr C/9 101 / 24;
 * the material's clamped rest Hessian instead of k·I₉: 412 / 39.
 * It is the weight of Liu, Bouaziz & Kavan's own code (TetConstraint::
 * ComputeLaplacianWeight, "section 4.1" of the paper): 2μ + λ for corotated, and fits
 * 2μ + 1.0033λ (StVK) and 2.0066μ + 1.0122λ (Neo-Hookean) over a 10% strain window,
 * within 1.3% of λ + 2μ. Spectrum of L⁻¹∇²g on the standard suite's cantilever (40×5×5
 * cells, stable_neo_hookean, its measured step; dense generalized eigenvalues): E = 1e7
 * [0.0031, 1.83], 20 eigenvalues below 0.1; E = 1e9 [0.00065, 1.85], 22 below 0.1 and
 * 4 below 0.01, 1%–90% quantiles 0.14–0.92, the same on 20×3×3 cells — the outliers
 * are the bending modes, in which k·I₉ also charges the element rotations that ∇²g does
 * not (against the lumped mass D: κ(D⁻¹∇²g) = 9.4e3 and 7.3e5, growing with E/h²).
 * Springs: the isotropic block k·[[1, −1], [−1, 1]] ⊗ I₃ of Liu, Bouaziz & Kavan 2013
 * (a spring is the constraint ‖x_a − x_b‖ = L; term_spring.c), rotation invariant too.
 * Materials that are PD constraint energies (pd_arap, pd_strain_limit, pd_volume) give
 * kₜ = their own weight (material op pd_weight): then L is exactly the global matrix of
 * their local/global iteration (solvers/optim/pd_local_global.c).
 *
 * L is SPD whenever the problem is well posed: M is SPD, and without inertia (static)
 * the elastic part is SPD as soon as every connected piece of the mesh has a
 * constrained vertex.
 *
 * Caching: L is assembled through the step's fixed-pattern assembler (each term's
 * pd_hessian op, or its hessian op at the rest positions with clamp), copied into its
 * own matrix, and the assembler's previous values restored (a Hessian a caller still
 * borrows is untouched). It is rebuilt, and its version bumped, only when the pattern
 * (constrained set) or the weight changes. */
#include <string.h>

#include "pd_matrix.h"

double eo_pd_tet_weight(const eo_material_type *mt, const eo_material_coef *c)
{
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (mt->pd_weight) return mt->pd_weight(c); /* a PD constraint energy: its own weight */
    eo_material_eval ev;
    if (eo_material_evaluate(mt, c, I3, EO_EVAL_HESS, EO_PROJ_CLAMP, &ev) < 0) return 0;
    return (ev.dPdF[0] + ev.dPdF[4 * 9 + 4] + ev.dPdF[8 * 9 + 8]) / 3;
}

void eo_pd_matrix_deinit(eo_ctx *ctx, eo_pd_matrix *pd)
{
    (void)ctx;
    eo_csc_destroy(&pd->L);
    pd->pattern_id = 0;
}

int eo_pd_matrix_get(eo_pd_matrix *pd, eo_sys *s, eo_term *const *terms, int nterms,
                     unsigned long pattern_id, double w, eo_csc **L, unsigned long *version)
{
    *L = NULL;
    if (!s->as) return eo_error(s->ctx, EO_ERR_INVALID, "pd matrix: no pattern (step not begun)");
    if (!(pd->L && pd->pattern_id == pattern_id && pd->w == w)) {
        eo_csc *H = eo_assembler_matrix(s->as);
        int rc;
        if (pd->L && pd->pattern_id == pattern_id) {
            memcpy(pd->L->val, H->val, (size_t)H->nnz * sizeof(double));
        } else {
            eo_csc_destroy(&pd->L);
            rc = eo_csc_clone(s->ctx, H, &pd->L); /* the pattern, and H's values saved */
            if (rc < 0) return rc;
        }
        eo_assembler_zero(s->as);
        rc = EO_OK;
        for (int i = 0; i < nterms && rc >= 0; i++) {
            eo_term *t = terms[i];
            rc = t->ops->pd_hessian ? t->ops->pd_hessian(t, s)
                                    : t->ops->hessian(t, s, s->mesh->X, EO_PROJ_CLAMP);
        }
        /* L gets the assembled values, the assembler its previous ones back */
        for (int q = 0; q < H->nnz; q++) {
            double tmp = H->val[q];
            H->val[q] = pd->L->val[q];
            pd->L->val[q] = tmp;
        }
        if (rc < 0) {
            eo_csc_destroy(&pd->L);
            return rc;
        }
        pd->pattern_id = pattern_id;
        pd->w = w;
        pd->version++;
    }
    *L = pd->L;
    *version = pd->version;
    return EO_OK;
}
