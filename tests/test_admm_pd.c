/* ADMM projective dynamics (suite 'solvers'): the optimizer admm_pd (solvers/optim/
 * admm_pd.c), its local step eo_material_prox (materials/prox.c) and the step
 * objective's split ops (problems/step_objective.c).
 *
 *  - the proximal problem z = argmin ψ(z) + (k/2)‖z − v‖² of six tet models (five in the
 *    reduced singular-value form, `linear` in the 9-entry form) at random
 *    v (small and large strain, one inverted): the returned z satisfies the optimality
 *    condition measured with central differences of ψ alone (‖∇φ‖ ≤ 1e-7·k·max(1,‖v‖),
 *    the difference error), and matches an independent direct minimization (Newton on
 *    finite-difference derivatives of φ) to 1e-7, or, where φ is not convex and the two
 *    land in different local minima, has the lower φ;
 *  - the split ops: F_e(x) agrees with the kernel's F at the step's guess, and the
 *    adjoint is the transpose of the map (⟨S, F(x + δ) − F(x)⟩ = ⟨Gᵀ S, δ⟩ to 1e-12);
 *  - admm_pd converges to Newton's minimizer: first steps of cantilever and twist with
 *    stable_neo_hookean, solver.tol = 1e-10 (the default), within
 *    1e-8 of the step's motion ‖x* − x₀‖; one factorization for the whole run;
 *  - an objective without the split ops is refused with a message; a scene with
 *    collisions is refused at configuration (as the solver and as a fallback entry). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/material.h"
#include "elastopt/objective.h"
#include "engine_util.h"

static double phi(const eo_material_type *mt, const eo_material_coef *c, const double v[9], double k,
                  const double z[9])
{
    eo_material_eval ev;
    eo_material_evaluate(mt, c, z, EO_EVAL_ENERGY, EO_PROJ_NONE, &ev);
    double d2 = 0;
    for (int i = 0; i < 9; i++) d2 += (z[i] - v[i]) * (z[i] - v[i]);
    return ev.psi + 0.5 * k * d2;
}

/* central-difference gradient of φ (step hs) */
static void fd_grad(const eo_material_type *mt, const eo_material_coef *c, const double v[9], double k,
                    const double z[9], double hs, double g[9])
{
    for (int i = 0; i < 9; i++) {
        double zp[9], zm[9];
        memcpy(zp, z, sizeof zp);
        memcpy(zm, z, sizeof zm);
        zp[i] += hs;
        zm[i] -= hs;
        g[i] = (phi(mt, c, v, k, zp) - phi(mt, c, v, k, zm)) / (2 * hs);
    }
}

/* direct minimization of φ from v, independent of the material's P and ∂P/∂F: Newton on
 * finite-difference gradient and Hessian (central differences), halving steps that raise φ */
static void direct_min(const eo_material_type *mt, const eo_material_coef *c, const double v[9], double k,
                       double z[9])
{
    memcpy(z, v, 9 * sizeof(double));
    if (!isfinite(phi(mt, c, v, k, z))) {
        for (int i = 0; i < 9; i++) z[i] = (i % 4 == 0);
    }
    const double hs = 1e-5;
    for (int it = 0; it < 40; it++) {
        double g[9], H[81];
        fd_grad(mt, c, v, k, z, hs, g);
        for (int j = 0; j < 9; j++) {
            double zp[9], zm[9], gp[9], gm[9];
            memcpy(zp, z, sizeof zp);
            memcpy(zm, z, sizeof zm);
            zp[j] += 1e-4;
            zm[j] -= 1e-4;
            fd_grad(mt, c, v, k, zp, hs, gp);
            fd_grad(mt, c, v, k, zm, hs, gm);
            for (int i = 0; i < 9; i++) H[9 * i + j] = (gp[i] - gm[i]) / 2e-4;
        }
        for (int i = 0; i < 9; i++) /* symmetrize, Gaussian elimination with partial pivoting */
            for (int j = 0; j < i; j++) H[9 * i + j] = H[9 * j + i] = 0.5 * (H[9 * i + j] + H[9 * j + i]);
        double A[9][10];
        for (int i = 0; i < 9; i++) {
            for (int j = 0; j < 9; j++) A[i][j] = H[9 * i + j];
            A[i][9] = -g[i];
        }
        for (int p = 0; p < 9; p++) {
            int best = p;
            for (int i = p + 1; i < 9; i++)
                if (fabs(A[i][p]) > fabs(A[best][p])) best = i;
            for (int j = 0; j < 10; j++) {
                double t = A[p][j];
                A[p][j] = A[best][j];
                A[best][j] = t;
            }
            for (int i = p + 1; i < 9; i++) {
                double f = A[i][p] / A[p][p];
                for (int j = p; j < 10; j++) A[i][j] -= f * A[p][j];
            }
        }
        double d[9];
        for (int i = 8; i >= 0; i--) {
            double s = A[i][9];
            for (int j = i + 1; j < 9; j++) s -= A[i][j] * d[j];
            d[i] = s / A[i][i];
        }
        double f0 = phi(mt, c, v, k, z), t = 1, zt[9];
        for (int ls = 0; ls < 40; ls++, t *= 0.5) {
            for (int i = 0; i < 9; i++) zt[i] = z[i] + t * d[i];
            if (phi(mt, c, v, k, zt) <= f0) break;
        }
        memcpy(z, zt, sizeof zt);
    }
}

static void check_prox(eo_ctx *ctx)
{
    static const char *const models[] = {"stable_neo_hookean", "neo_hookean", "corotated", "fixed_corotated", "stvk",
                                         "linear"};
    eo_test_seed(7);
    for (size_t m = 0; m < sizeof models / sizeof models[0]; m++) {
        const eo_material_type *mt = NULL;
        CHECK(eo_registry_find(ctx, EO_KIND_MATERIAL, models[m], (const void **)&mt) == EO_OK, "material %s",
              models[m]);
        if (!mt) continue;
        eo_material_coef c = eo_material_coef_from(1e5, 0.45, 1000, 0);
        const double kk = c.lambda + 2 * c.mu;
        double worst_opt = 0, worst_direct = 0;
        int worst_iters = 0;
        for (int trial = 0; trial < 12; trial++) {
            const double amp = trial < 4 ? 0.01 : trial < 10 ? 0.3 : 0.6;
            double v[9], z[9];
            for (int i = 0; i < 9; i++) v[i] = (i % 4 == 0) + eo_test_rand(-amp, amp);
            if (trial == 11 && !(mt->flags & EO_MATERIAL_BARRIER)) v[8] = -0.3; /* inverted v */
            const double k = trial % 2 ? kk : 0.1 * kk;
            for (int i = 0; i < 9; i++) z[i] = (i % 4 == 0); /* start at rest */
            int it = 0;
            int rc = eo_material_prox(mt, &c, v, k, 50, 1e-12, z, &it);
            CHECK(rc == EO_OK, "%s trial %d: prox converged (%d, %d iterations)", models[m], trial, rc, it);
            double vn = 0;
            for (int i = 0; i < 9; i++) vn += v[i] * v[i];
            const double scale = k * (sqrt(vn) > 1 ? sqrt(vn) : 1);
            double g[9], gn = 0;
            fd_grad(mt, &c, v, k, z, 1e-6, g);
            for (int i = 0; i < 9; i++) gn += g[i] * g[i];
            double zd[9], dd = 0, zz = 0;
            direct_min(mt, &c, v, k, zd);
            for (int i = 0; i < 9; i++) {
                dd += (z[i] - zd[i]) * (z[i] - zd[i]);
                zz += z[i] * z[i];
            }
            if (sqrt(gn) / scale > worst_opt) worst_opt = sqrt(gn) / scale;
            /* a non-convex φ (fixed_corotated near inversion) may have two local minima:
             * there the prox's must be the lower one */
            const double fz = phi(mt, &c, v, k, z), fd = phi(mt, &c, v, k, zd);
            if (sqrt(dd / zz) > 1e-7 && fz < fd - 1e-9 * k) {
                printf("  %s trial %d: a lower local minimum than the direct one (%.6g < %.6g)\n", models[m], trial,
                       fz, fd);
                continue;
            }
            if (sqrt(dd / zz) > worst_direct) worst_direct = sqrt(dd / zz);
            if (it > worst_iters) worst_iters = it;
        }
        printf("prox %-18s: worst |grad phi|_FD / (k max(1,|v|)) %.2e, |z - z_direct|/|z| %.2e, <= %d Newton "
               "iterations\n",
               models[m], worst_opt, worst_direct, worst_iters);
        CHECK(worst_opt <= 1e-7, "%s: optimality condition by central differences: %.2e", models[m], worst_opt);
        CHECK(worst_direct <= 1e-7, "%s: same minimizer as a direct minimization: %.2e", models[m], worst_direct);
    }
    /* bad input */
    const eo_material_type *sp = NULL;
    eo_registry_find(ctx, EO_KIND_MATERIAL, "spring", (const void **)&sp);
    double v[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, z[9];
    memcpy(z, v, sizeof z);
    eo_material_coef c = eo_material_coef_from(1e5, 0.45, 1000, 0);
    CHECK(sp && eo_material_prox(sp, &c, v, 1, 10, 1e-12, z, NULL) == EO_ERR_UNSUPPORTED, "spring: unsupported");
}


/* ‖x − x*‖/‖x* − x₀‖ of admm_pd against Newton on the first step */
static void check_converges(eo_ctx *ctx, const char *scene, const char *material, const char *tol)
{
    char mkey[64], tkey[64];
    snprintf(mkey, sizeof mkey, "material.model=%s", material);
    snprintf(tkey, sizeof tkey, "solver.tol=%s", tol);
    const char *ov[] = {mkey, NULL};
    const char *admm[] = {"solver.optimizer=admm_pd", tkey, "solver.max_iters=20000", "solver.fallback=[]", NULL};
    double *xr = NULL, *x0 = NULL, *x = NULL, *x0b = NULL;
    int n = 0, nb = 0;
    eo_solve_result rr, ra;
    long nf = 0;
    if (eo_test_solve_first(ctx, scene, ov, eo_test_newton_ref, &xr, &x0, &n, &rr, NULL) < 0 || rr.reason <= 0) {
        CHECK(0, "%s %s: Newton reference (%s)", scene, material, eo_reason_string(rr.reason));
        goto out;
    }
    if (eo_test_solve_first(ctx, scene, ov, admm, &x, &x0b, &nb, &ra, &nf) < 0 || nb != n) {
        CHECK(0, "%s %s: admm_pd ran", scene, material);
        goto out;
    }
    double e2 = 0, m2 = 0;
    for (int i = 0; i < n; i++) {
        e2 += (x[i] - xr[i]) * (x[i] - xr[i]);
        m2 += (xr[i] - x0[i]) * (xr[i] - x0[i]);
    }
    const double err = sqrt(e2 / m2);
    printf("%-10s %-18s tol %s: admm_pd %s after %d iterations (%ld factorizations), error %.2e of the motion "
           "(newton %d iterations)\n",
           scene, material, tol, eo_reason_string(ra.reason), ra.iterations, nf, err, rr.iterations);
    CHECK(ra.reason > 0, "%s %s: admm_pd converged: %s", scene, material, eo_reason_string(ra.reason));
    CHECK(err <= 1e-8, "%s %s: within 1e-8 of the motion of Newton's minimizer: %.2e", scene, material, err);
out:
    free(xr), free(x0), free(x), free(x0b);
}

/* the split ops of the step objective: the adjoint is the transpose of the linear part of
 * F(x), F at the guess is the kernel's, and k is λ + 2μ */
static void check_split(eo_ctx *ctx)
{
    const char *ov[] = {"material.model=stable_neo_hookean", NULL};
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, "twist", NULL, ov) < 0) {
        CHECK(0, "twist opens");
        return;
    }
    eo_objective *obj = eo_test_sim_obj(s);
    eo_objective_split sp;
    CHECK(eo_objective_split_get(obj, &sp) == EO_OK, "step objective has the split ops");
    const int n = obj->n, ne = sp.ne;
    double *x = malloc((size_t)n * sizeof(double)), *xd = malloc((size_t)n * sizeof(double)),
           *dl = malloc((size_t)n * sizeof(double)), *gs = malloc((size_t)n * sizeof(double));
    double *F0 = malloc(9 * (size_t)ne * sizeof(double)), *F1 = malloc(9 * (size_t)ne * sizeof(double)),
           *S = malloc(9 * (size_t)ne * sizeof(double));
    memcpy(x, eo_test_sim_guess(s), (size_t)n * sizeof(double));
    eo_test_seed(11);
    for (int i = 0; i < n; i++) {
        dl[i] = eo_test_rand(-1e-3, 1e-3);
        xd[i] = x[i] + dl[i];
    }
    for (int q = 0; q < 9 * ne; q++) S[q] = eo_test_rand(-1, 1);
    obj->ops->split_apply(obj->data, x, F0);
    obj->ops->split_apply(obj->data, xd, F1);
    obj->ops->split_adjoint(obj->data, S, gs);
    double lhs = 0, rhs = 0, mag = 0;
    for (int q = 0; q < 9 * ne; q++) {
        lhs += S[q] * (F1[q] - F0[q]);
        mag += fabs(S[q] * (F1[q] - F0[q]));
    }
    for (int i = 0; i < n; i++) rhs += gs[i] * dl[i];
    printf("split ops: <S, F(x+d) - F(x)> = %.15g, <G^T S, d> = %.15g (%d elements)\n", lhs, rhs, ne);
    CHECK(fabs(lhs - rhs) <= 1e-10 * mag, "adjoint of the split map: %.3e vs %.3e", lhs, rhs);
    /* the guess of the twist's first step is the rest shape rotated or at rest: F has det > 0 */
    int bad = 0;
    for (int e = 0; e < ne; e++) bad += !(eo_det3(F0 + 9 * e) > 0);
    CHECK(bad == 0, "F(x0) not inverted: %d bad", bad);
    const eo_material_coef *c = sp.coef[0];
    CHECK(fabs(sp.k[0] - (c->lambda + 2 * c->mu)) <= 1e-6 * sp.k[0], "k = lambda + 2 mu: %g vs %g", sp.k[0],
          c->lambda + 2 * c->mu);
    CHECK(sp.w > 0 && sp.vol[0] > 0, "weight %g, volume %g", sp.w, sp.vol[0]);
    free(x), free(xd), free(dl), free(gs), free(F0), free(F1), free(S);
    eo_sim_destroy(&s);
}

/* g = ½‖x − 1‖²: no split ops */
static int q_value(void *d, const double *x, double *g)
{
    (void)d;
    *g = 0;
    for (int i = 0; i < 3; i++) *g += 0.5 * (x[i] - 1) * (x[i] - 1);
    return EO_OK;
}
static int q_gradient(void *d, const double *x, double *g, double *grad)
{
    for (int i = 0; i < 3; i++) grad[i] = x[i] - 1;
    return q_value(d, x, g);
}
static int q_hessian(void *d, const double *x, eo_proj proj, eo_csc **H)
{
    (void)d, (void)x, (void)proj, (void)H;
    return EO_ERR_UNSUPPORTED;
}

static void check_refuses(eo_ctx *ctx)
{
    static const eo_objective_ops ops = {.value = q_value, .gradient = q_gradient, .hessian = q_hessian};
    eo_objective obj = {.n = 3, .ops = &ops};
    eo_cfg *cfg = NULL;
    eo_solver *sv = NULL;
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    int rc = eo_cfg_load(ctx, NULL, "{\"solver\": {\"optimizer\": \"admm_pd\", \"fallback\": []}}", &cfg);
    if (rc >= 0) rc = eo_solver_opts_load(ctx, cfg, &o);
    if (rc >= 0) rc = eo_solver_create(ctx, &o, cfg, &sv);
    double x[3] = {0, 0, 0};
    eo_solve_result r;
    if (rc >= 0) rc = eo_solver_minimize(sv, &obj, x, NULL, NULL, &r);
    printf("objective without split ops: %d, %s\n", rc, eo_ctx_message(ctx));
    CHECK(rc == EO_ERR_UNSUPPORTED && strstr(eo_ctx_message(ctx), "admm_pd needs"), "refused with a message: %d",
          rc);
    eo_solver_destroy(&sv);
    eo_cfg_destroy(&cfg);
}

/* a scene with collisions is refused at configuration (its penalty contact would enter
 * the global step explicitly): as the scene's solver and as a fallback entry; the same
 * scene without collisions, and admm_pd on a scene without them, are accepted */
static void check_refuses_contact(eo_ctx *ctx)
{
    const char *ov[] = {"solver.optimizer=admm_pd", "solver.fallback=[]", NULL};
    eo_sim *s = NULL;
    int rc = eo_sim_create_from(ctx, NULL, "drop", ov, &s);
    printf("drop with admm_pd: %d, %s\n", rc, eo_ctx_message(ctx));
    CHECK(rc == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "admm_pd") && strstr(eo_ctx_message(ctx), "collisions"),
          "refused with a message: %d", rc);
    eo_sim_destroy(&s);
    const char *ovf[] = {"solver.fallback=[{\"optimizer\": \"admm_pd\"}]", NULL};
    rc = eo_sim_create_from(ctx, NULL, "drop", ovf, &s);
    CHECK(rc == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "solver.fallback.0"), "as a fallback entry: %d %s", rc,
          eo_ctx_message(ctx));
    eo_sim_destroy(&s);
    const char *ovn[] = {"solver.optimizer=admm_pd", "solver.fallback=[]", "collisions=[]", NULL};
    rc = eo_sim_create_from(ctx, NULL, "drop", ovn, &s);
    CHECK(rc == EO_OK, "drop without collisions: %d %s", rc, eo_ctx_message(ctx));
    eo_sim_destroy(&s);
    rc = eo_sim_create_from(ctx, NULL, "cantilever", ov, &s);
    CHECK(rc == EO_OK, "cantilever: %d %s", rc, eo_ctx_message(ctx));
    eo_sim_destroy(&s);
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    check_prox(ctx);
    check_split(ctx);
    check_refuses(ctx);
    check_refuses_contact(ctx);
    check_converges(ctx, "cantilever", "stable_neo_hookean", "1e-10");
    check_converges(ctx, "twist", "stable_neo_hookean", "1e-10");
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_admm_pd");
}
