/* Projective dynamics (suite 'solvers'): the constant matrix L of the step objective
 * (problems/pd_matrix.c) and the projective_dynamics optimizer.
 *
 *  - L equals its definition M + w·Σₜ Vₜ kₜ GₜᵀGₜ, kₜ = mean ∂²ψ/∂F_ii² at F = I
 *    (= λ + 2μ), rebuilt here independently as a dense matrix from the mesh, for
 *    consistent and lumped mass; it is symmetric positive definite (factors), stable
 *    (same pointer and version on a second call) and does not disturb the Hessian a
 *    caller holds;
 *  - projective_dynamics with lbfgs_history 0 and 5 reaches Newton's minimizer of a
 *    corotated and a stable Neo-Hookean step, with one factorization;
 *  - the factorization count stays 1 over several time steps while the boundary
 *    conditions are unchanged, and a release (new pattern) costs one more;
 *  - L-BFGS-PD needs fewer iterations than plain PD on a stiff step;
 *  - an objective without the op (the step objective with constant_hessian = NULL,
 *    and an analytic quadratic) gets ∇²g at the first iterate;
 *  - nothing is allocated inside minimize once L is factored. */
#include <stdlib.h>
#include <string.h>

#include "elastopt/linsolve.h"
#include "engine_util.h"
#include "solver_problems.h"

/* The cube step of test_engine_solvers: 0.2 m cube clamped at its bottom, started
 * stretched 20% along x and squeezed 10% along y, one step of 0.02 s under gravity. */
static const char *cube =
    "{\"mesh\": {\"generate\": {\"size\": [0.2, 0.2, 0.2], \"cells\": [3, 3, 3]}},"
    " \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e5, \"nu\": 0.3, \"density\": 1000},"
    " \"boundary\": [{\"box\": [[-1, -1, -1], [1, 1, 0]], \"fixed\": true}],"
    " \"initial\": {\"scale\": [1.2, 0.9, 1.0]},"
    " \"time\": {\"integrator\": \"backward_euler\", \"dt\": 0.02, \"steps\": 1}}";

/* ---- L against its definition --------------------------------------------------------- */

static void check_matrix(const char *model, const char *integrator, int lumped)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    char mod[64], integ[64], lm[64];
    snprintf(mod, sizeof mod, "material.model=%s", model);
    snprintf(integ, sizeof integ, "time.integrator=%s", integrator);
    snprintf(lm, sizeof lm, "mass=lumped");
    const char *ov[] = {mod, integ, lumped ? lm : NULL, NULL};
    if (eo_test_sim_open(&s, ctx, NULL, cube, ov) != 0) {
        CHECK(0, "open %s", model);
        eo_sim_destroy(&s);
        eo_test_ctx_done(&ctx);
        return;
    }
    const int n = eo_test_sim_obj(s)->n;
    const eo_mesh *m = eo_step_mesh(eo_sim_step_problem(s));
    const eo_scene_material *mat = eo_sim_scene(s)->mat;
    const double h = eo_sim_scene(s)->time.dt, w = strcmp(integrator, "newmark") == 0 ? h * h / 4 : h * h;

    /* a Hessian held by a caller must survive the constant_hessian call */
    eo_csc *H = NULL;
    CHECK(eo_objective_hessian(eo_test_sim_obj(s), eo_test_sim_guess(s), EO_PROJ_CLAMP, &H) == EO_OK, "hessian");
    double *Hsave = malloc((size_t)H->nnz * sizeof(double));
    memcpy(Hsave, H->val, (size_t)H->nnz * sizeof(double));

    eo_csc *L = NULL, *L2 = NULL;
    unsigned long ver = 0, ver2 = 0;
    CHECK(eo_objective_constant_hessian(eo_test_sim_obj(s), &L, &ver) == EO_OK, "constant_hessian: %s", eo_ctx_message(ctx));
    CHECK(eo_objective_constant_hessian(eo_test_sim_obj(s), &L2, &ver2) == EO_OK && L2 == L && ver2 == ver && ver > 0,
          "second call: same matrix and version");
    CHECK(memcmp(Hsave, H->val, (size_t)H->nnz * sizeof(double)) == 0, "the held Hessian is untouched");
    CHECK(L && L->n == n && eo_csc_check(ctx, L) == EO_OK, "L invariants");

    /* the definition, dense */
    double *R = calloc((size_t)n * n, sizeof(double)), *D = malloc((size_t)n * n * sizeof(double));
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    eo_material_eval ev;
    eo_material_evaluate(mat->type, &mat->coef, I3, EO_EVAL_HESS, EO_PROJ_CLAMP, &ev);
    const double k = (ev.dPdF[0] + ev.dPdF[40] + ev.dPdF[80]) / 3;
    const double lame = mat->coef.lambda + 2 * mat->coef.mu;
    printf("  %-19s k = %.10g, lambda + 2 mu = %.10g\n", model, k, lame);
    CHECK(fabs(k - lame) <= 1e-6 * lame, "%s: k = %g is lambda + 2 mu = %g", model, k, lame);
    for (int t = 0; t < m->nt; t++) {
        const int *tet = m->tets + 4 * t;
        double X12[12], Dm[9], V, b[4][3];
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) X12[3 * a + c] = m->X[3 * tet[a] + c];
        CHECK(eo_tet_rest(X12, Dm, &V) == EO_OK, "rest tet");
        for (int c = 0; c < 3; c++) {
            b[3][c] = -(Dm[c] + Dm[3 + c] + Dm[6 + c]);
            for (int a = 0; a < 3; a++) b[a][c] = Dm[3 * a + c];
        }
        const double mt = mat->coef.density * V;
        for (int a = 0; a < 4; a++)
            for (int bb = 0; bb < 4; bb++)
                for (int r = 0; r < 3; r++) {
                    int i = eo_step_full_to_free(eo_sim_step_problem(s), 3 * tet[a] + r), j = eo_step_full_to_free(eo_sim_step_problem(s), 3 * tet[bb] + r);
                    if (i < 0 || j < 0) continue;
                    double mass = lumped ? (a == bb ? mt / 4 : 0) : mt / 20 * (a == bb ? 2 : 1);
                    R[(size_t)i * n + j] +=
                        mass + w * V * k * (b[a][0] * b[bb][0] + b[a][1] * b[bb][1] + b[a][2] * b[bb][2]);
                }
    }
    eo_csc_to_dense(L, D);
    double err = 0, scale = 0, asym = 0;
    for (size_t q = 0; q < (size_t)n * n; q++) {
        err = fmax(err, fabs(D[q] - R[q]));
        scale = fmax(scale, fabs(R[q]));
    }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < i; j++) asym = fmax(asym, fabs(R[(size_t)i * n + j] - R[(size_t)j * n + i]));
    printf("  %-19s %-14s %s mass: n = %d, max |L - def| = %.2e (max entry %.2e)\n", model, integrator,
           lumped ? "lumped" : "consistent", n, err, scale);
    CHECK(err <= 1e-12 * scale, "%s: L differs from its definition by %g", model, err);
    CHECK(asym <= 1e-12 * scale, "definition symmetric");

    /* SPD: Cholesky succeeds */
    const eo_linsolve_type *lt = NULL;
    eo_linsolve *ls = NULL;
    CHECK(eo_linsolve_find(ctx, "cholmod", &lt) == EO_OK, "cholmod");
    if (lt && eo_linsolve_create(ctx, lt, NULL, &ls) == EO_OK) {
        CHECK(eo_linsolve_analyze(ls, L) == EO_OK, "analyze");
        CHECK(eo_linsolve_factor(ls, L) == EO_OK, "%s: L is not positive definite", model);
        eo_linsolve_destroy(&ls);
    }
    free(R);
    free(D);
    free(Hsave);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* ---- convergence to Newton's minimizer ------------------------------------------------ */

typedef struct run_out {
    int n, iterations, reason;
    long n_factor;
    double *x;
} run_out;

/* One step of `scene` (JSON) with overrides; x copied out (caller frees). */
static int run_step(const char *scene, const char *const *ov, int drop_op, run_out *o)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    memset(o, 0, sizeof *o);
    int rc = eo_test_sim_open(&s, ctx, NULL, scene, ov);
    if (rc == 0) {
        eo_objective_ops ops = *eo_test_sim_obj(s)->ops;
        eo_objective obj = *eo_test_sim_obj(s);
        if (drop_op) {
            ops.constant_hessian = NULL;
            obj.ops = &ops;
        }
        eo_solve_result r;
        double *x = eo_test_sim_guess(s);
        rc = eo_solver_minimize(eo_sim_solver(s), &obj, x, NULL, NULL, &r);
        o->n = eo_test_sim_obj(s)->n;
        o->x = malloc((size_t)o->n * sizeof(double));
        memcpy(o->x, x, (size_t)o->n * sizeof(double));
        o->iterations = r.iterations;
        o->reason = r.reason;
        o->n_factor = r.n_factor;
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return rc;
}

static double max_diff(const run_out *a, const run_out *b)
{
    if (a->n != b->n || !a->x || !b->x) return INFINITY;
    double e = 0;
    for (int i = 0; i < a->n; i++) e = fmax(e, fabs(a->x[i] - b->x[i]));
    return e;
}

static void check_converges(const char *model)
{
    char mod[64];
    snprintf(mod, sizeof mod, "material.model=%s", model);
    const char *ref_ov[] = {mod, "solver.hessian_fix=none", "solver.tol=1e-24", NULL};
    run_out ref;
    CHECK(run_step(cube, ref_ov, 0, &ref) == 0 && eo_reason_is_converged(ref.reason), "%s reference: %s", model,
          eo_reason_name(ref.reason));
    for (int drop = 0; drop < 2; drop++)
        for (int hist = 0; hist <= 5; hist += 5) {
            char hs[64];
            snprintf(hs, sizeof hs, "solver.projective_dynamics.lbfgs_history=%d", hist);
            const char *ov[] = {mod, "solver.optimizer=projective_dynamics", hs, "solver.tol=1e-20",
                                "solver.max_iters=5000", NULL};
            run_out r;
            int rc = run_step(cube, ov, drop, &r);
            double err = max_diff(&r, &ref);
            printf("  %-19s history %d%s: %4d iterations (newton %d), %ld factorization(s), %-22s max |x - x*| = %.2e\n",
                   model, hist, drop ? " (no op: Hessian at x0)" : "", r.iterations, ref.iterations, r.n_factor,
                   eo_reason_name(r.reason), err);
            CHECK(rc == 0 && eo_reason_is_converged(r.reason), "%s history %d drop %d: %s", model, hist, drop,
                  eo_reason_name(r.reason));
            CHECK(err < 1e-7, "%s history %d drop %d: distance to Newton's minimizer %g", model, hist, drop, err);
            CHECK(r.n_factor == 1, "%s: %ld factorizations in one minimization", model, r.n_factor);
            free(r.x);
        }
    free(ref.x);
}

/* ---- L-BFGS-PD against plain PD on a stiff step ---------------------------------------- */

static void check_lbfgs_faster(void)
{
    int it[2] = {0, 0};
    for (int i = 0; i < 2; i++) {
        const char *ov[] = {"material.E=1e7", "material.nu=0.45", "solver.optimizer=projective_dynamics",
                            i ? "solver.projective_dynamics.lbfgs_history=5" : "solver.projective_dynamics.lbfgs_history=0",
                            "solver.tol=1e-14", "solver.max_iters=20000", "solver.stop=newton_decrement", NULL};
        run_out r;
        CHECK(run_step(cube, ov, 0, &r) == 0 && eo_reason_is_converged(r.reason), "stiff %d: %s", i,
              eo_reason_name(r.reason));
        it[i] = r.iterations;
        free(r.x);
    }
    printf("  stiff step (E = 1e7, nu = 0.45): PD %d iterations, L-BFGS-PD (m = 5) %d\n", it[0], it[1]);
    CHECK(it[1] < it[0], "L-BFGS-PD %d iterations, plain PD %d", it[1], it[0]);
}

/* ---- one factorization per scene (own factor, releases by update) or per pattern
 * (solver.linear on the eliminated L) over time steps ------------------------------------ */

/* stretch: right end pulled until 0.2 s, held, released at 0.3 s (new pattern). Runs the
 * 40 steps with the step's PD factor mode `mode`; positions after every step into traj
 * (steps × 3nv). */
static void factor_count_run(int mode, double *traj)
{
    static const char *names[] = {"off (solver.linear)", "refactor", "updown"};
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"solver.optimizer=projective_dynamics", "solver.projective_dynamics.lbfgs_history=5",
                        "solver.max_iters=2000", "solver.tol=1e-12", "time.steps=40", NULL};
    CHECK(eo_test_sim_open(&s, ctx, "stretch", NULL, ov) == 0, "open stretch");
    eo_step *st = eo_sim_step_problem(s);
    CHECK(eo_step_set_pd_factor(st, mode) == EO_OK, "mode %d", mode);
    long total = 0, before = -1;
    eo_objective *obj = eo_test_sim_obj(s); /* the engine's objective: n of the last step built */
    int n0 = obj->n, released_at = -1, ok = 1;
    const int nf = 3 * eo_step_mesh(st)->nv;
    const eo_linsolve_stats *ls = eo_linsolve_get_stats(eo_solver_get_linsolve(eo_sim_solver(s)));
    for (int k = 0; k < eo_sim_scene(s)->time.steps; k++) {
        eo_sim_step_result r;
        int rc = eo_test_sim_step(s, NULL, NULL, &r);
        ok &= rc == 0 && eo_reason_is_converged(r.reason);
        if (!(rc == 0 && eo_reason_is_converged(r.reason)))
            fprintf(stderr, "step %d: rc %d %s\n", k, rc, eo_reason_name(r.reason));
        total += r.n_factor;
        memcpy(traj + (size_t)k * nf, eo_step_x(st), (size_t)nf * sizeof(double));
        if (obj->n != n0 && released_at < 0) {
            released_at = k;
            before = total - r.n_factor;
        }
        if (k == 10) {
            CHECK(ls->n_factor == (mode == EO_PD_FACTOR_OFF), "%s: linsolve: %ld factorizations in 11 steps",
                  names[mode], ls->n_factor);
            CHECK(total == 1, "%s: %ld factorizations in 11 steps", names[mode], total);
        }
    }
    eo_step_pd_info info;
    eo_step_pd_info_get(st, &info);
    printf("  stretch, 40 steps, PD factor %-19s: %ld factorization(s) (%ld before the release at step %d); "
           "own factor: %ld factorization(s), %ld update(s) of rank %ld, %s, order %d\n",
           names[mode], total, before, released_at, info.n_factor, info.n_updown, info.rank,
           info.scalar ? "vertex matrix L1" : "coordinates", info.n);
    CHECK(ok, "%s: every step converges", names[mode]);
    CHECK(released_at > 0 && before == 1, "%s: one factorization before the release: %ld", names[mode], before);
    /* off / refactor: one per pattern; updown: one per scene, the release an update */
    CHECK(total == (mode == EO_PD_FACTOR_UPDOWN ? 1 : 2), "%s: %ld factorizations", names[mode], total);
    if (mode != EO_PD_FACTOR_OFF) {
        CHECK(info.scalar == 1 && info.n == nf / 3, "%s: the vertex matrix L1 is factored (order %d)", names[mode],
              info.n);
        CHECK(info.n_factor == total && info.n_updown == (mode == EO_PD_FACTOR_UPDOWN), "%s: %ld / %ld",
              names[mode], info.n_factor, info.n_updown);
        CHECK(ls->n_factor == 0, "%s: solver.linear factored %ld times", names[mode], ls->n_factor);
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

static void check_factor_count(void)
{
    enum { STEPS = 40 };
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    CHECK(eo_test_sim_open(&s, ctx, "stretch", NULL, NULL) == 0, "open stretch");
    const size_t nf = 3 * (size_t)eo_step_mesh(eo_sim_step_problem(s))->nv;
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    double *tr[3];
    for (int m = 0; m < 3; m++) {
        tr[m] = calloc(STEPS * nf, sizeof(double));
        factor_count_run(m, tr[m]);
    }
    /* the same trajectory whichever way the factor is kept (each step to tol 1e-12) */
    double d[2] = {0, 0}, motion = 0;
    for (size_t q = 0; q < STEPS * nf; q++) {
        motion = fmax(motion, fabs(tr[0][q] - tr[0][q % nf]));
        for (int m = 1; m < 3; m++) d[m - 1] = fmax(d[m - 1], fabs(tr[m][q] - tr[0][q]));
    }
    printf("  stretch trajectory, max |x - x_off| / max motion: refactor %.2e, updown %.2e\n", d[0] / motion,
           d[1] / motion);
    CHECK(d[0] <= 1e-9 * motion && d[1] <= 1e-9 * motion, "trajectories differ: %g, %g (motion %g)", d[0], d[1],
          motion);
    for (int m = 0; m < 3; m++) free(tr[m]);
}

/* ---- analytic objective without the op; no allocation inside minimize ------------------ */

typedef struct counter {
    long calls;
} counter;
static void *c_malloc(size_t n, void *u)
{
    ((counter *)u)->calls++;
    return malloc(n);
}
static void *c_realloc(void *p, size_t n, void *u)
{
    ((counter *)u)->calls++;
    return realloc(p, n);
}
static void c_free(void *p, void *u)
{
    (void)u;
    free(p);
}

static void check_fallback_and_alloc(void)
{
    counter cnt = {0};
    eo_allocator al = {c_malloc, c_realloc, c_free, &cnt};
    eo_ctx *ctx = NULL;
    eo_ctx_create(&al, &ctx);
    /* quadratic: L = ∇²g exactly, one step */
    tprob p;
    prob_init(ctx, &p, P_QUAD);
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    snprintf(o.optimizer, sizeof o.optimizer, "projective_dynamics");
    o.tol = 1e-20;
    snprintf(o.stop, sizeof o.stop, "newton_decrement"); /* tol is absolute here */
    eo_solver *sv = NULL;
    CHECK(eo_solver_create(ctx, &o, NULL, &sv) == EO_OK, "%s", eo_ctx_message(ctx));
    if (sv) {
        eo_objective obj = prob_objective(&p);
        double x[NMAX];
        eo_solve_result res;
        for (int rep = 0; rep < 2; rep++) {
            memcpy(x, p.x0, sizeof x);
            long c0 = cnt.calls;
            eo_solver_minimize(sv, &obj, x, NULL, NULL, &res);
            CHECK(eo_reason_is_converged(res.reason) && prob_error(&p, x) < 1e-8, "quadratic: %s, error %g",
                  eo_reason_name(res.reason), prob_error(&p, x));
            CHECK(res.iterations <= 1, "quadratic: %d iterations with its exact Hessian", res.iterations);
            CHECK(res.n_factor == 1, "fallback factors once per minimization: %ld", res.n_factor);
            if (rep == 1) CHECK(cnt.calls == c0, "%ld allocations inside minimize", cnt.calls - c0);
        }
        eo_solver_destroy(&sv);
    }
    prob_done(ctx, &p);

    /* step objective: after the first minimization nothing allocates */
    eo_sim *s = NULL;
    /* the old absolute stop: PD converges linearly, relative_decrement's 1e-10 of the step's
     * motion takes it ~100 iterations per step here */
    const char *ov[] = {"solver.optimizer=projective_dynamics", "solver.projective_dynamics.lbfgs_history=5",
                        "time.steps=3", "solver.stop=newton_decrement", NULL};
    if (eo_test_sim_open(&s, ctx, "twist", NULL, ov) == 0) {
        for (int k = 0; k < 3; k++) {
            long c0 = cnt.calls;
            eo_sim_step_result r;
            CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0 && eo_reason_is_converged(r.reason), "twist step %d", k);
            if (k > 0) CHECK(cnt.calls == c0, "twist step %d: %ld allocations", k, cnt.calls - c0);
        }
    } else {
        CHECK(0, "open twist");
    }
    eo_sim_destroy(&s);
    CHECK(eo_ctx_live_bytes(ctx) == 0, "%zu bytes leaked", eo_ctx_live_bytes(ctx));
    eo_ctx_destroy(&ctx);
}

int main(void)
{
    printf("L against its definition:\n");
    const char *models[] = {"corotated", "stable_neo_hookean", "stvk", "linear"};
    for (int i = 0; i < 4; i++) check_matrix(models[i], "backward_euler", 0);
    check_matrix("corotated", "newmark", 1);
    printf("convergence to Newton's minimizer:\n");
    check_converges("corotated");
    check_converges("stable_neo_hookean");
    check_lbfgs_faster();
    check_factor_count();
    check_fallback_and_alloc();
    return eo_test_finish("test_pd");
}
