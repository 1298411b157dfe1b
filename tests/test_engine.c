/* Step engine tests (suite 'engine'): physics of the step objective and integrators.
 *
 *  - free fall (newmark, no constraints): centre of mass follows −½gt² to 1e-9, body
 *    undeformed;
 *  - static cantilever, `linear` material, ν = 0: tip deflection → Euler–Bernoulli
 *    qL⁴/(8EI) under refinement (error decreasing monotonically, finest within 3%);
 *  - small load: every nonlinear material within 2% of `linear`;
 *  - Newton (true Hessian) converges quadratically near the solution;
 *  - newmark + linear material, no gravity: total energy conserved to 1e-6 over 200
 *    steps; backward_euler: strictly decreasing;
 *  - inverted start recovers with no inverted tet;
 *  - every built-in scene equals its examples/<name>.json and loads; scene errors. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "elastopt/io.h"
#include "engine_util.h"

/* ------------------------------------------------------------------ free fall */

static void test_freefall(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"solver.tol=1e-24", "solver.max_iters=10", NULL};
    CHECK(eo_test_sim_open(&s, ctx, "freefall", NULL, ov) == 0, "open");
    eo_step_stats s0, sk;
    eo_step_stats_compute(eo_sim_step_problem(s), &s0);
    double worst = 0, worstJ = 0;
    const double g = 9.81;
    for (int k = 0; k < eo_sim_scene(s)->time.steps; k++) {
        eo_sim_step_result r;
        CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0, "step %d", k);
        CHECK(eo_reason_is_converged(r.reason), "step %d reason %s", k, eo_reason_name(r.reason));
        eo_step_stats_compute(eo_sim_step_problem(s), &sk);
        double t = eo_step_time(eo_sim_step_problem(s)), expect = -0.5 * g * t * t;
        double err = fabs((sk.com[2] - s0.com[2]) - expect) / fabs(expect);
        if (err > worst) worst = err;
        double dj = fmax(fabs(sk.min_J - 1), fabs(sk.max_J - 1));
        if (dj > worstJ) worstJ = dj;
        CHECK(fabs(sk.com[0] - s0.com[0]) < 1e-12 && fabs(sk.com[1] - s0.com[1]) < 1e-12, "no sideways drift");
    }
    printf("freefall: worst relative COM error %.3g, max |J-1| %.3g\n", worst, worstJ);
    CHECK(worst < 1e-9, "COM displacement relative error %g", worst);
    CHECK(worstJ < 1e-9, "max |J-1| %g", worstJ);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* ------------------------------------------------------------------ cantilever */

/* Static cantilever 1 × 0.1 × 0.1 m, cells (10n, n, n); returns the tip z displacement. */
static double static_cantilever(int n, const char *model, double E, double nu, const char *fix, int *iters)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    char cells[64], mod[64], e[64], v[64], hf[64];
    snprintf(hf, sizeof hf, "solver.hessian_fix=%s", fix);
    snprintf(cells, sizeof cells, "mesh.generate.cells=[%d,%d,%d]", 10 * n, n, n);
    snprintf(mod, sizeof mod, "material.model=%s", model);
    snprintf(e, sizeof e, "material.E=%g", E);
    snprintf(v, sizeof v, "material.nu=%g", nu);
    const char *ov[] = {cells, mod, e, v, hf, "solver.tol=1e-16", "solver.max_iters=100", NULL};
    double dz = NAN;
    if (eo_test_sim_open(&s, ctx, "cantilever_static", NULL, ov) == 0) {
        eo_sim_step_result r;
        CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0, "step");
        CHECK(eo_reason_is_converged(r.reason), "%s n=%d: %s", model, n, eo_reason_name(r.reason));
        if (iters) *iters = r.iterations;
        dz = eo_test_tip_dz(s, 1.0 - 1e-9);
    } else {
        CHECK(0, "open cantilever_static");
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return dz;
}

static void test_cantilever_refinement(void)
{
    const double E = 1e9, rho = 1000, g = 9.81, L = 1, b = 0.1, h = 0.1;
    const double q = rho * g * b * h, I = b * h * h * h / 12, delta = q * L * L * L * L / (8 * E * I);
    const int ns[] = {2, 4, 6, 8};
    double err[4];
    printf("cantilever refinement (linear, nu = 0, Euler-Bernoulli delta = %.6g m):\n", delta);
    for (int i = 0; i < 4; i++) {
        double dz = static_cantilever(ns[i], "linear", E, 0.0, "clamp", NULL);
        err[i] = fabs(-dz - delta) / delta;
        printf("  cells %3d x %d x %d: tip %.6g m, relative error %.4f\n", 10 * ns[i], ns[i], ns[i], -dz, err[i]);
        if (i > 0) CHECK(err[i] < err[i - 1], "error must decrease: %g then %g", err[i - 1], err[i]);
    }
    CHECK(err[3] < 0.03, "finest mesh error %g", err[3]);
}

static void test_materials_small_load(void)
{
    int it;
    /* the true Hessian (none): near rest it is positive definite for every model, and
     * Newton converges quadratically (clamp converges only linearly for
     * stable_neo_hookean here: its projected Hessian differs from the true one) */
    double ref = static_cantilever(2, "linear", 1e9, 0.3, "none", &it);
    /* models without a volume term (pd_arap, ...) linearize to linear elasticity with
     * λ = 0: compared at ν = 0, where linear has λ = 0 and the same μ */
    double ref0 = static_cantilever(2, "linear", 1e9, 0.0, "none", &it);
    for (const void *const *t = eo_registry_list(EO_KIND_MATERIAL); *t; t++) {
        const eo_material_type *mt = *t;
        if ((mt->flags & EO_MATERIAL_EDGE) || strcmp(mt->info.name, "linear") == 0) continue;
        const int nov = (mt->flags & EO_MATERIAL_NO_VOLUME) != 0;
        double dz = static_cantilever(2, mt->info.name, 1e9, nov ? 0.0 : 0.3, "none", &it);
        if (nov) dz *= ref / ref0; /* compare the ratio to linear at nu = 0 */
        double rel = fabs(dz - ref) / fabs(ref);
        printf("small load: %-20s tip %.6g vs linear %.6g (rel %.2e, %d iterations)\n", mt->info.name, dz, ref, rel, it);
        CHECK(rel < 0.02, "%s differs from linear by %g", mt->info.name, rel);
    }
}

/* ------------------------------------------------------------------ Newton rate */

typedef struct gn_log {
    double r[256];
    int n;
} gn_log;

static int log_grad(const eo_iter_info *it, void *user)
{
    gn_log *l = user;
    if (l->n < 256) l->r[l->n++] = it->grad_norm;
    return 0;
}

static void test_newton_quadratic(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"solver.hessian_fix=none", "solver.tol=1e-30", "solver.max_iters=12", NULL};
    CHECK(eo_test_sim_open(&s, ctx, "cantilever_static", NULL, ov) == 0, "open");
    gn_log l = {.n = 0};
    eo_sim_step_result r;
    CHECK(eo_test_sim_step(s, log_grad, &l, &r) == 0, "step");
    /* the floor: smallest gradient norm reached (rounding level) */
    double floor_ = INFINITY;
    for (int k = 0; k < l.n; k++) floor_ = fmin(floor_, l.r[k]);
    double last = 0;
    printf("newton (hessian_fix none) gradient norms:");
    for (int k = 0; k < l.n; k++) printf(" %.2e", l.r[k]);
    printf("\n");
    /* order from the last three iterates above the rounding floor */
    for (int k = 1; k + 1 < l.n; k++) {
        if (l.r[k + 1] < 1e3 * floor_ || !(l.r[k] < l.r[k - 1]) || !(l.r[k + 1] < l.r[k])) continue;
        last = log(l.r[k + 1] / l.r[k]) / log(l.r[k] / l.r[k - 1]);
    }
    printf("newton: observed order near the solution %.2f\n", last);
    CHECK(last > 1.8, "convergence order %g", last);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* ------------------------------------------------------------------ energy */

static const char *energy_scene =
    "{\"mesh\": {\"generate\": {\"size\": [0.2, 0.2, 0.2], \"cells\": [2, 2, 2]}},"
    " \"material\": {\"model\": \"linear\", \"E\": 1e5, \"nu\": 0.3, \"density\": 1000},"
    " \"gravity\": [0, 0, 0],"
    " \"initial\": {\"scale\": [1.05, 0.98, 1.0], \"velocity\": [0.1, 0, 0]},"
    " \"time\": {\"integrator\": \"newmark\", \"dt\": 0.005, \"steps\": 200},"
    " \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"none\", \"tol\": 1e-24, \"max_iters\": 10}}";

static void run_energy(const char *integrator, const char *mass, int steps, double *drift, int *monotone)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    char io[64], mo[64], so[64];
    snprintf(io, sizeof io, "time.integrator=%s", integrator);
    snprintf(mo, sizeof mo, "mass=%s", mass);
    snprintf(so, sizeof so, "time.steps=%d", steps);
    /* backward Euler: no rigid motion, so that the decay is not hidden under its constant energy */
    const char *ov[] = {io, mo, so, strcmp(integrator, "newmark") ? "initial.velocity=[0,0,0]" : NULL, NULL};
    CHECK(eo_test_sim_open(&s, ctx, NULL, energy_scene, ov) == 0, "open");
    eo_step_stats st;
    eo_step_stats_compute(eo_sim_step_problem(s), &st);
    double e0 = st.kinetic + st.elastic, prev = e0;
    *drift = 0;
    *monotone = 1;
    for (int k = 0; k < eo_sim_scene(s)->time.steps; k++) {
        eo_sim_step_result r;
        if (eo_test_sim_step(s, NULL, NULL, &r) != 0 || !eo_reason_is_converged(r.reason)) {
            CHECK(0, "%s step %d: %s", integrator, k, eo_reason_name(r.reason));
            break;
        }
        eo_step_stats_compute(eo_sim_step_problem(s), &st);
        double e = st.kinetic + st.elastic;
        *drift = fmax(*drift, fabs(e - e0) / e0);
        if (!(e < prev)) *monotone = 0;
        prev = e;
    }
    printf("energy %s (%s mass): initial %.6g, final %.6g, max relative drift %.3g\n", integrator, mass, e0, prev,
           *drift);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

static void test_energy(void)
{
    double drift;
    int mono;
    run_energy("newmark", "consistent", 200, &drift, &mono);
    CHECK(drift < 1e-6, "newmark energy drift %g", drift);
    run_energy("newmark", "lumped", 200, &drift, &mono);
    CHECK(drift < 1e-6, "newmark (lumped) energy drift %g", drift);
    run_energy("backward_euler", "consistent", 50, &drift, &mono);
    CHECK(mono, "backward Euler energy must decrease strictly at every step");
    CHECK(drift > 1e-3, "backward Euler should dissipate visibly (drift %g)", drift);
}

/* ------------------------------------------------------------------ inverted start */

static void test_inverted(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    CHECK(eo_test_sim_open(&s, ctx, "inverted", NULL, NULL) == 0, "open");
    eo_step_stats st;
    eo_step_stats_compute(eo_sim_step_problem(s), &st);
    CHECK(st.inverted == eo_sim_scene(s)->mesh->nt, "every tet starts inverted (%d of %d)", st.inverted, eo_sim_scene(s)->mesh->nt);
    int nconv = 0;
    for (int k = 0; k < eo_sim_scene(s)->time.steps; k++) {
        eo_sim_step_result r;
        CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0, "step %d", k);
        nconv += eo_reason_is_converged(r.reason);
    }
    eo_step_stats_compute(eo_sim_step_problem(s), &st);
    printf("inverted: %d/%d steps converged, final inverted %d, min J %.4g, max displacement %.4g\n", nconv,
           eo_sim_scene(s)->time.steps, st.inverted, st.min_J, st.max_disp);
    CHECK(st.inverted == 0, "%d tets still inverted", st.inverted);
    CHECK(st.max_disp < 0.05, "rest shape not recovered (max displacement %g)", st.max_disp);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* ------------------------------------------------------------------ scenes and errors */

static void test_examples(void)
{
    eo_ctx *ctx = eo_test_ctx();
    int n = 0;
    for (const void *const *t = eo_registry_list(EO_KIND_SCENE); *t; t++, n++) {
        const eo_scene_type *sty = *t;
        char rel[256];
        snprintf(rel, sizeof rel, "examples/%s.json", sty->info.name);
        const char *path = eo_test_src_path(rel);
        json_error_t je;
        json_t *a = json_load_file(path, 0, &je), *b = json_loads(sty->json, 0, &je);
        CHECK(a && b && json_equal(a, b), "%s: example file and built-in scene differ", sty->info.name);
        json_decref(a);
        json_decref(b);
        eo_sim *s = NULL;
        eo_ctx_clear_error(ctx);
        eo_cfg *cfg = NULL;
        eo_scene *sc = NULL;
        int rc = eo_scene_cfg_load(ctx, path, NULL, &cfg);
        if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
        CHECK(rc == 0, "%s: %s", path, eo_ctx_message(ctx));
        eo_scene_destroy(&sc);
        eo_cfg_destroy(&cfg);
        /* and the built-in runs one step */
        const char *ov[] = {"time.steps=1", NULL};
        CHECK(eo_test_sim_open(&s, ctx, sty->info.name, NULL, ov) == 0, "open %s", sty->info.name);
        eo_sim_step_result r;
        CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0 && eo_reason_is_converged(r.reason), "%s first step: %s",
              sty->info.name, eo_reason_name(r.reason));
        eo_sim_destroy(&s);
    }
    CHECK(n >= 6, "built-in scenes: %d", n);
    eo_test_ctx_done(&ctx);
}

static void expect_error(const char *json, const char *override, int status, const char *needle)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_cfg *cfg = NULL;
    eo_scene *sc = NULL;
    int rc = eo_cfg_load(ctx, NULL, json, &cfg);
    if (rc >= 0 && override) rc = eo_cfg_override(ctx, cfg, override);
    if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
    if (rc >= 0) rc = eo_cfg_finish(ctx, cfg);
    CHECK(rc == status, "expected %s, got %s (%s)", eo_status_name(status), eo_status_name(rc), eo_ctx_message(ctx));
    CHECK(strstr(eo_ctx_message(ctx), needle) != NULL, "message '%s' lacks '%s'", eo_ctx_message(ctx), needle);
    eo_scene_destroy(&sc);
    eo_cfg_destroy(&cfg);
    eo_test_ctx_done(&ctx);
}

static void test_scene_errors(void)
{
    const char *base = "{\n \"mesh\": {\"generate\": {\"cells\": [4, 1, 1]}},\n \"boundary\": [\n"
                       "  {\"box\": [[5, 5, 5], [6, 6, 6]], \"fixed\": true}\n ]\n}\n";
    expect_error(base, NULL, EO_ERR_INVALID, "<builtin>:4");
    expect_error(base, NULL, EO_ERR_INVALID, "selects no vertex");
    expect_error("{\"time\": {\n \"dt\": 0}}", NULL, EO_ERR_RANGE, "<builtin>:2");
    expect_error("{\"time\": {\"dt\": 0.1}}", "time.dt=-1", EO_ERR_RANGE, "-o time.dt");
    expect_error("{\n\"mesh\": {},\n\"gravty\": [0, 0, 1]}", NULL, EO_ERR_UNKNOWN_KEY, "<builtin>:3");
    expect_error("{\"time\": {\"integrator\": \"adams_bashforth\"}}", NULL, EO_ERR_UNKNOWN_NAME, "newmark");
    expect_error("{\"boundary\": [{\"box\": [[0,0,0],[1,1,1]]}]}", NULL, EO_ERR_INVALID, "exactly one of");
    expect_error("{\"boundary\": [{\"plane\": {\"point\": [0,0,0], \"normal\": [0,0,0]}, \"fixed\": true}]}", NULL,
                 EO_ERR_RANGE, "zero normal");
    expect_error("{\"boundary\": [{\"plane\": {\"pont\": [0,0,0]}, \"fixed\": true}]}", NULL, EO_ERR_UNKNOWN_KEY,
                 "point, normal");
    expect_error("{\"materials\": [{\"attribute\": 1}]}", NULL, EO_ERR_INVALID, "no tet attributes");
}

/* Per-region materials by box, and release of a boundary set (pattern rebuild). */
static void test_regions_and_release(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"materials=[{\"box\": [[0.5,-1,-1],[2,1,1]], \"E\": 1e5}]", "time.steps=40", NULL};
    CHECK(eo_test_sim_open(&s, ctx, "stretch", NULL, ov) == 0, "open");
    int soft = 0;
    for (int k = 0; k < eo_sim_scene(s)->mesh->nt; k++) soft += eo_sim_scene(s)->tet_mat[k] == 1;
    CHECK(soft > 0 && soft < eo_sim_scene(s)->mesh->nt, "region tets %d", soft);
    const eo_objective *obj = eo_test_sim_obj(s); /* the engine's objective: n of the last step built */
    int n_before = obj->n, n_after = -1;
    for (int k = 0; k < eo_sim_scene(s)->time.steps; k++) {
        eo_sim_step_result r;
        CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0 && eo_reason_is_converged(r.reason), "step %d: %s", k,
              eo_reason_name(r.reason));
        n_after = obj->n;
    }
    CHECK(n_after > n_before, "release frees the right end: n %d -> %d", n_before, n_after);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* The eo_sim API on the cantilever (newmark, Newton): a trial solves the next step
 * without advancing (index and time unchanged, two trials bit-identical, and the step
 * then accepted has exactly the trial's minimizer); get/set_state replays steps
 * bit-identically; set_solver swaps the method (Newton + abs, capped at 7 iterations, converges the
 * next steps; a bad name keeps the old solver);
 * creation refuses an unknown key and an unknown solver name (no sim). */
static void test_sim_api(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"time.steps=10", NULL};
    CHECK(eo_sim_create_from(ctx, NULL, "cantilever", ov, &s) == EO_OK, "%s", eo_ctx_message(ctx));
    if (!s) return;
    const int nf = 3 * eo_sim_scene(s)->mesh->nv;
    double *buf = malloc(6 * (size_t)nf * sizeof(double));
    double *x1 = buf, *x2 = buf + nf, *xs = buf + 2 * nf, *vs = buf + 3 * nf, *xa = buf + 4 * nf, *xb = buf + 5 * nf;
    eo_sim_step_result r;
    for (int k = 0; k < 2; k++) CHECK(eo_sim_step(s, &r) == EO_OK && r.reason > 0, "step %d", k);
    eo_objective *obj;
    eo_solve_result t1, t2;
    CHECK(eo_sim_trial(s, NULL, NULL, x1, NULL, NULL, &obj, &t1) == EO_OK && t1.reason > 0, "trial 1");
    CHECK(eo_sim_trial(s, NULL, NULL, x2, NULL, NULL, NULL, &t2) == EO_OK, "trial 2");
    CHECK(eo_sim_index(s) == 2 && fabs(eo_sim_time(s) - 2 * eo_sim_scene(s)->time.dt) < 1e-15, "trial does not advance");
    int same = t1.iterations == t2.iterations;
    for (int i = 0; i < obj->n; i++) same &= x1[i] == x2[i];
    CHECK(same, "two trials from one state are identical");
    CHECK(eo_sim_step(s, &r) == EO_OK && r.iterations == t1.iterations && r.g == t1.g, "step = trial: %d vs %d",
          r.iterations, t1.iterations);
    const eo_step *st = eo_sim_step_problem(s);
    same = 1;
    for (int i = 0; i < obj->n; i++) same &= eo_step_x(st)[eo_step_free_to_full(st, i)] == x1[i];
    CHECK(same, "the accepted step is the trial's minimizer");
    /* replay */
    double ts;
    int is;
    eo_sim_get_state(s, xs, vs, &ts, &is);
    for (int k = 0; k < 2; k++) eo_sim_step(s, &r);
    eo_sim_get_state(s, xa, NULL, NULL, NULL);
    CHECK(eo_sim_set_state(s, xs, vs, ts, is) == EO_OK && eo_sim_index(s) == 3, "set_state");
    for (int k = 0; k < 2; k++) eo_sim_step(s, &r);
    eo_sim_get_state(s, xb, NULL, NULL, NULL);
    same = eo_sim_index(s) == 5;
    for (int i = 0; i < nf; i++) same &= xa[i] == xb[i];
    CHECK(same, "set_state + 2 steps replays bit-identically");
    /* swap the solver */
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    snprintf(o.hessian_fix, sizeof o.hessian_fix, "abs");
    o.max_iters = 7;
    CHECK(eo_sim_set_solver(s, &o, NULL) == EO_OK, "%s", eo_ctx_message(ctx));
    CHECK(strcmp(eo_solver_get_opts(eo_sim_solver(s))->hessian_fix, "abs") == 0, "solver swapped");
    for (int k = 0; k < 2; k++)
        CHECK(eo_sim_step(s, &r) == EO_OK && r.reason > 0 && r.iterations <= 7, "swapped solver's step: %s",
              eo_reason_name(r.reason));
    snprintf(o.optimizer, sizeof o.optimizer, "nosuch");
    CHECK(eo_sim_set_solver(s, &o, NULL) == EO_ERR_UNKNOWN_NAME &&
              strcmp(eo_solver_get_opts(eo_sim_solver(s))->hessian_fix, "abs") == 0,
          "a bad solver keeps the old one");
    eo_sim_reset(s);
    CHECK(eo_sim_index(s) == 0 && eo_sim_time(s) == 0, "reset");
    free(buf);
    eo_sim_destroy(&s);
    CHECK(s == NULL, "destroy clears");
    const char *bad1[] = {"solver.optimizer=newtn", NULL}, *bad2[] = {"time.stepz=3", NULL};
    CHECK(eo_sim_create_from(ctx, NULL, "cantilever", bad1, &s) == EO_ERR_UNKNOWN_NAME && !s, "bad optimizer");
    CHECK(eo_sim_create_from(ctx, NULL, "cantilever", bad2, &s) < 0 && !s, "unknown key: %s", eo_ctx_message(ctx));
    eo_test_ctx_done(&ctx);
}

/* Fallback chain (solver.fallback, in eo_sim_step): newton + hessian_fix none with a
 * budget of 20 iterations does not finish the inverted start's first step
 * (diverged_max_iters); the chain's entry 1 (hessian_fix clamp, 100 iterations) solves it
 * again. With solver.fallback_start = guess it starts from the step's starting guess and
 * ends at the same point as newton + clamp alone; with best (the default) it starts where
 * entry 0 stopped (its first record has entry 0's last g, below the starting guess's) and
 * converges below it. The step record names entry 1 and the first entry's
 * reason; the callback sees the entry running; a later step that entry 0 solves records
 * entry 0. Bad entries and a bad fallback_start are errors naming the key. */
typedef struct entry_seen {
    const eo_sim *sim;
    int rows[3];
    double g_first[2], g_last[2]; /* g of each entry's first and last record */
} entry_seen;

static int count_entry(const eo_iter_info *info, void *user)
{
    entry_seen *e = user;
    int k = eo_sim_entry(e->sim);
    e->rows[k >= 0 && k < 2 ? k : 2]++;
    if (k >= 0 && k < 2) {
        if (info->iteration == 0) e->g_first[k] = info->g;
        e->g_last[k] = info->g;
    }
    return 0;
}

static void test_fallback(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *ov[] = {"solver.hessian_fix=none", "solver.max_iters=20", "time.steps=2",
                        "solver.fallback=[{\"hessian_fix\": \"clamp\", \"max_iters\": 100}]",
                        "solver.fallback_start=guess", NULL};
    const char *ref[] = {"solver.hessian_fix=clamp", "solver.max_iters=100", "time.steps=2", "solver.fallback=[]", NULL};
    eo_sim *s = NULL, *sr = NULL;
    CHECK(eo_test_sim_open(&s, ctx, "inverted", NULL, ov) == 0, "open with fallback");
    CHECK(eo_test_sim_open(&sr, ctx, "inverted", NULL, ref) == 0, "open clamp");
    if (s && sr) {
        CHECK(eo_sim_n_fallback(s) == 1 && eo_sim_n_fallback(sr) == 0, "fallback entries");
        eo_sim_step_result r, rr;
        entry_seen es = {.sim = s};
        CHECK(eo_test_sim_step(s, count_entry, &es, &r) == 0, "step: %s", eo_ctx_message(ctx));
        CHECK(eo_test_sim_step(sr, NULL, NULL, &rr) == 0, "step: %s", eo_ctx_message(ctx));
        printf("fallback: step 1 entry %d of %d tried: entry 0 %s after %d it., entry 1 %s after %d it.; "
               "newton+clamp alone %s after %d it.\n", r.entry, r.n_entries, eo_reason_name(r.entry_reason[0]),
               r.entry_iterations[0], eo_reason_name(r.entry_reason[1]), r.entry_iterations[1],
               eo_reason_name(rr.reason), rr.iterations);
        CHECK(r.entry == 1 && r.n_entries == 2, "entry %d of %d", r.entry, r.n_entries);
        CHECK(r.entry_reason[0] == EO_DIVERGED_MAX_ITERS && r.entry_iterations[0] == 20, "entry 0: %s",
              eo_reason_name(r.entry_reason[0]));
        CHECK(eo_reason_is_converged(r.reason) && r.reason == r.entry_reason[1] && r.iterations == rr.iterations,
              "entry 1: %s after %d (clamp alone %d)", eo_reason_name(r.reason), r.iterations, rr.iterations);
        CHECK(r.n_gradient > rr.n_gradient, "evaluations of both runs counted");
        CHECK(es.rows[0] == 21 && es.rows[1] == r.iterations + 1 && es.rows[2] == 0,
              "callback records per entry: %d, %d, %d", es.rows[0], es.rows[1], es.rows[2]);
        const int nv = eo_sim_scene(s)->mesh->nv;
        double *x = malloc((size_t)nv * 3 * sizeof(double)), *xr = malloc((size_t)nv * 3 * sizeof(double));
        eo_sim_get_state(s, x, NULL, NULL, NULL);
        eo_sim_get_state(sr, xr, NULL, NULL, NULL);
        double d = 0;
        for (int i = 0; i < 3 * nv; i++) d = fmax(d, fabs(x[i] - xr[i]));
        CHECK(d == 0, "fallback result differs from newton+clamp from the same guess by %g", d);
        CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0, "step 2");
        CHECK(r.entry == 0 && r.n_entries == 1 && eo_reason_is_converged(r.reason), "step 2: entry %d, %s", r.entry,
              eo_reason_name(r.reason));
        CHECK(es.g_first[1] == es.g_first[0], "guess: entry 1 starts at the starting guess (g %.17g, %.17g)",
              es.g_first[1], es.g_first[0]);
        /* the default start: entry 1 continues from entry 0's end point */
        eo_sim *sb = NULL;
        ov[4] = NULL;
        CHECK(eo_test_sim_open(&sb, ctx, "inverted", NULL, ov) == 0, "open with fallback_start best");
        if (sb) {
            eo_sim_step_result rb;
            entry_seen eb = {.sim = sb};
            CHECK(eo_test_sim_step(sb, count_entry, &eb, &rb) == 0, "step: %s", eo_ctx_message(ctx));
            printf("fallback best: entry 0 ended at g = %.10g (start %.10g), entry 1 started at %.10g and %s after "
                   "%d it. (newton+clamp alone: %d)\n", eb.g_last[0], eb.g_first[0], eb.g_first[1],
                   eo_reason_name(rb.reason), rb.iterations, rr.iterations);
            CHECK(rb.entry == 1 && eo_reason_is_converged(rb.reason), "best: entry %d, %s", rb.entry,
                  eo_reason_name(rb.reason));
            CHECK(eb.g_first[1] == eb.g_last[0] && eb.g_last[0] < eb.g_first[0],
                  "best: entry 1 starts where entry 0 stopped (g %.17g, entry 0 ended at %.17g, started at %.17g)",
                  eb.g_first[1], eb.g_last[0], eb.g_first[0]);
            /* a minimizer below entry 0's end point (the inverted start has several: which one
             * a run reaches depends on where it starts, so it need not be clamp's) */
            eo_sim_get_state(sb, x, NULL, NULL, NULL);
            double db = 0;
            for (int i = 0; i < 3 * nv; i++) db = fmax(db, fabs(x[i] - xr[i]));
            printf("fallback best: g = %.10g (newton+clamp from the guess: %.10g), max distance %g\n", rb.g, rr.g, db);
            CHECK(rb.g <= eb.g_last[0] && eb.g_last[1] == rb.g, "best: ends below entry 0's end point (g %.17g, %.17g)",
                  rb.g, eb.g_last[0]);
        }
        eo_sim_destroy(&sb);
        free(x);
        free(xr);
    }
    eo_sim_destroy(&s);
    eo_sim_destroy(&sr);
    const char *bad4[] = {"solver.fallback_start=last", NULL};
    CHECK(eo_sim_create_from(ctx, NULL, "cantilever", bad4, &s) < 0 && !s &&
              strstr(eo_ctx_message(ctx), "solver.fallback_start"),
          "bad fallback_start: %s", eo_ctx_message(ctx));
    const char *bad1[] = {"solver.fallback=[{\"hessian_fx\": \"clamp\"}]", NULL};
    const char *bad2[] = {"solver.fallback=[{\"optimizer\": \"newtn\"}]", NULL};
    const char *bad3[] = {"solver.fallback={\"optimizer\": \"lbfgs\"}", NULL};
    CHECK(eo_sim_create_from(ctx, NULL, "cantilever", bad1, &s) == EO_ERR_UNKNOWN_KEY && !s &&
              strstr(eo_ctx_message(ctx), "solver.fallback.0"),
          "unknown key in an entry: %s", eo_ctx_message(ctx));
    CHECK(eo_sim_create_from(ctx, NULL, "cantilever", bad2, &s) == EO_ERR_UNKNOWN_NAME && !s, "bad name: %s",
          eo_ctx_message(ctx));
    CHECK(eo_sim_create_from(ctx, NULL, "cantilever", bad3, &s) == EO_ERR_TYPE && !s, "not a list: %s",
          eo_ctx_message(ctx));
    eo_test_ctx_done(&ctx);
}

/* A fallback entry measuring by the gradient (lbfgs, loose tol 1e-3 in its section) after
 * a Newton that ran out of iterations (3 on the twist's first step, which needs 6): lbfgs
 * accepts Newton's third iterate at once by its gradient ratio; the scene's Newton then
 * continues from it and decides, so the step ends at Newton's accuracy (within 1e-9 of
 * the motion of the Newton-only answer) with Newton's reason, not at the third iterate. */
static void test_fallback_confirm(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *ov[] = {"solver.max_iters=3", "time.steps=1",
                        "solver.fallback=[{\"optimizer\": \"lbfgs\", \"tol\": 1e-3, \"max_iters\": 2000}]", NULL};
    const char *ref[] = {"time.steps=1", "solver.fallback=[]", NULL};
    eo_sim *s = NULL, *sr = NULL;
    CHECK(eo_test_sim_open(&s, ctx, "twist", NULL, ov) == 0, "open with fallback");
    CHECK(eo_test_sim_open(&sr, ctx, "twist", NULL, ref) == 0, "open newton");
    if (s && sr) {
        const int nv = eo_sim_scene(s)->mesh->nv;
        double *x0 = malloc((size_t)nv * 3 * sizeof(double)), *x = malloc((size_t)nv * 3 * sizeof(double)),
               *xr = malloc((size_t)nv * 3 * sizeof(double));
        eo_sim_get_state(s, x0, NULL, NULL, NULL);
        eo_sim_step_result r, rr;
        CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0, "step: %s", eo_ctx_message(ctx));
        CHECK(eo_test_sim_step(sr, NULL, NULL, &rr) == 0, "step: %s", eo_ctx_message(ctx));
        eo_sim_get_state(s, x, NULL, NULL, NULL);
        eo_sim_get_state(sr, xr, NULL, NULL, NULL);
        double d = 0, m = 0;
        for (int i = 0; i < 3 * nv; i++) d = fmax(d, fabs(x[i] - xr[i])), m = fmax(m, fabs(xr[i] - x0[i]));
        printf("fallback confirm: entry %d (%s after %d it.), step %s after %d it.; |x - x_newton| %.3g of motion %.3g\n",
               r.entry, eo_reason_name(r.entry_reason[1]), r.entry_iterations[1], eo_reason_name(r.reason),
               r.iterations, d, m);
        CHECK(r.entry == 1 && r.entry_reason[1] == EO_CONVERGED_GRADIENT, "lbfgs entry converged by the gradient");
        CHECK(r.reason == EO_CONVERGED_DECREMENT && r.iterations > r.entry_iterations[1],
              "Newton decided after the entry: %s, %d iterations", eo_reason_name(r.reason), r.iterations);
        CHECK(d <= 1e-9 * m, "step answer %.3g from Newton's (motion %.3g)", d, m);
        free(x0), free(x), free(xr);
    }
    eo_sim_destroy(&s);
    eo_sim_destroy(&sr);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_sim_api();
    test_scene_errors();
    test_examples();
    test_freefall();
    test_energy();
    test_newton_quadratic();
    test_materials_small_load();
    test_cantilever_refinement();
    test_inverted();
    test_regions_and_release();
    test_fallback();
    test_fallback_confirm();
    return eo_test_finish("test_engine");
}
