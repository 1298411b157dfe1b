/* Mass-spring systems, explicit integrators in scenes, penalty collisions (suite
 * 'engine'):
 *
 *  - a single spring (mesh.points, one end fixed, point mass m, stiffness k, no
 *    gravity) under newmark oscillates with the period of the trapezoidal rule,
 *    T_h = π h / atan(ωh/2) (→ 2π√(m/k) as h → 0), to 1e-6, within 1e-3 of 2π√(m/k),
 *    and conserves ½mv² + ½k(l − L)² to 1e-6 over 10 periods;
 *  - a hanging chain of N point masses and springs under `static` reaches the analytic
 *    elongation: vertex i sits Σ_{j≤i} (N − j + 1) m g/k below its rest position;
 *  - material.model = "spring" (springs only, no tet elasticity) and springs.edges =
 *    "mesh" give the same objective (the same edges, k);
 *  - FD check (central differences, step sweep) of the step objective's gradient and
 *    Hessian with scene springs on a tet mesh, and with collision planes at a state where
 *    vertices penetrate;
 *  - a box dropped on a ground plane comes to rest with Σ_v k·depth_v = M g (the exact
 *    static balance of the penalty forces) and a mean depth M g/(N_bottom k);
 *  - explicit integrators in scenes: free fall with verlet is exact (a = g) for lumped
 *    and consistent mass (the CHOLMOD path); the single spring under verlet has the
 *    analytic period to O(h²); rk4 beyond its stability limit ends with
 *    EO_DIVERGED_NONFINITE and keeps the last finite state;
 *  - scene errors for the new keys. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

static const double PI = 3.14159265358979323846;

/* ------------------------------------------------------------------ single spring */

static const char *spring1 =
    "{\"mesh\": {\"points\": [[0, 0, 0], [0, 0, -1]]},"
    " \"point_mass\": 2, \"gravity\": [0, 0, 0],"
    " \"springs\": {\"edges\": \"list\", \"list\": [[0, 1]], \"k\": 50},"
    " \"boundary\": [{\"box\": [[-0.1, -0.1, -0.1], [0.1, 0.1, 0.1]], \"fixed\": true}],"
    " \"initial\": {\"velocity\": [0, 0, -0.1]},"
    " \"time\": {\"integrator\": \"newmark\", \"dt\": 0.01, \"steps\": 1},"
    " \"solver\": {\"tol\": 1e-26, \"max_iters\": 20}}";

/* Run `steps` steps; returns the mean period from upward zero crossings of z + 1. */
static double spring_period(const char *integrator, double dt, int steps, double *edev)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    char integ[64], dts[64];
    snprintf(integ, sizeof integ, "time.integrator=%s", integrator);
    snprintf(dts, sizeof dts, "time.dt=%.17g", dt);
    const char *ov[] = {integ, dts, NULL};
    double period = NAN;
    if (eo_test_sim_open(&s, ctx, NULL, spring1, ov) != 0) {
        CHECK(0, "open single spring");
        eo_sim_destroy(&s);
        eo_test_ctx_done(&ctx);
        return NAN;
    }
    eo_step_stats st;
    eo_step_stats_compute(eo_sim_step_problem(s), &st);
    double e0 = st.kinetic + st.elastic, dev = 0;
    double zprev = 0, tfirst = NAN, tlast = NAN;
    int ncross = 0;
    for (int k = 0; k < steps; k++) {
        eo_sim_step_result r;
        CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0 && eo_reason_is_converged(r.reason) &&
                  (r.reason == EO_REASON_EXPLICIT) == eo_sim_is_explicit(s),
              "step %d: %s", k, eo_reason_name(r.reason));
        double z = eo_step_x(eo_sim_step_problem(s))[5] + 1, t = eo_step_time(eo_sim_step_problem(s));
        if (k > 0 && zprev < 0 && z >= 0) {
            double tc = t - dt * z / (z - zprev);
            if (ncross == 0) tfirst = tc;
            tlast = tc;
            ncross++;
        }
        zprev = z;
        eo_step_stats_compute(eo_sim_step_problem(s), &st);
        dev = fmax(dev, fabs(st.kinetic + st.elastic - e0) / e0);
    }
    if (ncross >= 2) period = (tlast - tfirst) / (ncross - 1);
    if (edev) *edev = dev;
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return period;
}

static void test_single_spring(void)
{
    const double m = 2, k = 50, w = sqrt(k / m), T = 2 * PI / w, dt = T / 200;
    double dev;
    double Th = spring_period("newmark", dt, 2000, &dev);
    double Tdisc = PI * dt / atan(w * dt / 2);
    printf("single spring newmark: period %.10f (trapezoidal %.10f, analytic 2 pi sqrt(m/k) %.10f), max energy "
           "deviation %.2e\n", Th, Tdisc, T, dev);
    CHECK(fabs(Th - Tdisc) / Tdisc < 1e-6, "newmark period %.12g vs trapezoidal %.12g", Th, Tdisc);
    CHECK(fabs(Th - T) / T < 1e-3, "newmark period %.12g vs analytic %.12g", Th, T);
    CHECK(dev < 1e-6, "newmark energy deviation %g", dev);
    /* explicit velocity Verlet: second order in the period, energy within O(h²ω²) */
    double Tv1 = spring_period("verlet", T / 100, 1000, &dev);
    double Tv2 = spring_period("verlet", T / 200, 2000, NULL);
    double e1 = fabs(Tv1 - T), e2 = fabs(Tv2 - T);
    printf("single spring verlet: period error %.3e (h = T/100), %.3e (T/200): ratio %.2f; energy deviation %.2e\n",
           e1, e2, e1 / e2, dev);
    CHECK(e1 / e2 > 3.5 && e1 / e2 < 4.5, "verlet period error ratio %g", e1 / e2);
    CHECK(dev < (w * T / 100) * (w * T / 100), "verlet energy deviation %g", dev);
}

/* ------------------------------------------------------------------ hanging chain */

static void test_hanging_chain(void)
{
    enum { N = 5 };
    const double m = 0.3, k = 200, g = 9.81, L = 0.2;
    char json[2048], *p = json;
    p += sprintf(p, "{\"mesh\": {\"points\": [");
    for (int i = 0; i <= N; i++) p += sprintf(p, "%s[0, 0, %g]", i ? ", " : "", -i * L);
    p += sprintf(p, "]}, \"point_mass\": %g, \"springs\": {\"edges\": \"list\", \"k\": %g, \"list\": [", m, k);
    for (int i = 0; i < N; i++) p += sprintf(p, "%s[%d, %d]", i ? ", " : "", i, i + 1);
    p += sprintf(p, "]}, \"boundary\": [{\"box\": [[-1, -1, -0.01], [1, 1, 0.01]], \"fixed\": true}],"
                    " \"time\": {\"integrator\": \"static\", \"steps\": 1},"
                    " \"solver\": {\"tol\": 1e-24, \"max_iters\": 100}}");
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    CHECK(eo_test_sim_open(&s, ctx, NULL, json, NULL) == 0, "open chain");
    eo_sim_step_result r;
    CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0 && eo_reason_is_converged(r.reason), "static: %s",
          eo_reason_name(r.reason));
    const double *x = eo_step_x(eo_sim_step_problem(s));
    double worst = 0, total = 0;
    for (int i = 1; i <= N; i++) {
        double expect = 0;
        for (int j = 1; j <= i; j++) expect += (N - j + 1) * m * g / k;
        double got = -(x[3 * i + 2] + i * L);
        worst = fmax(worst, fabs(got - expect) / expect);
        CHECK(fabs(x[3 * i]) < 1e-12 && fabs(x[3 * i + 1]) < 1e-12, "chain stays vertical");
        if (i == N) total = got;
    }
    printf("hanging chain: total elongation %.12g m (analytic %.12g), worst relative error %.2e, %d iterations\n",
           total, m * g / k * N * (N + 1) / 2, worst, r.iterations);
    CHECK(worst < 1e-9, "chain elongation error %g", worst);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* ------------------------------------------------------------------ FD helpers */

/* Relative errors of the gradient (directional) and of H·v against central differences
 * of g and ∇g at x, best over a step sweep. */
static void fd_check(eo_objective *obj, const double *x, double scale, double *gerr, double *herr)
{
    int n = obj->n;
    double *buf = calloc(6 * (size_t)n, sizeof(double));
    double *v = buf, *g0 = buf + n, *xp = buf + 2 * n, *gp = buf + 3 * n, *gm = buf + 4 * n, *Hv = buf + 5 * n;
    for (int i = 0; i < n; i++) v[i] = eo_test_rand(-1, 1);
    double f0, fp, fm;
    eo_objective_gradient(obj, x, &f0, g0);
    eo_csc *H;
    eo_objective_hessian(obj, x, EO_PROJ_NONE, &H);
    eo_csc_symv(H, v, Hv);
    double dg = 0, nhv = 0;
    for (int i = 0; i < n; i++) {
        dg += g0[i] * v[i];
        nhv += Hv[i] * Hv[i];
    }
    nhv = sqrt(nhv);
    *gerr = *herr = INFINITY;
    for (int e = 2; e <= 9; e++) {
        double eps = scale * pow(10.0, -e);
        for (int i = 0; i < n; i++) xp[i] = x[i] + eps * v[i];
        eo_objective_gradient(obj, xp, &fp, gp);
        for (int i = 0; i < n; i++) xp[i] = x[i] - eps * v[i];
        eo_objective_gradient(obj, xp, &fm, gm);
        *gerr = fmin(*gerr, fabs((fp - fm) / (2 * eps) - dg) / fabs(dg));
        double d2 = 0;
        for (int i = 0; i < n; i++) {
            double d = (gp[i] - gm[i]) / (2 * eps) - Hv[i];
            d2 += d * d;
        }
        *herr = fmin(*herr, sqrt(d2) / nhv);
    }
    free(buf);
}

static void test_fd_springs(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"springs={\"edges\": \"mesh\", \"k\": 2e4}", "mesh.generate.cells=[4,1,1]",
                        "collisions=[{\"plane\": {\"point\": [0, 0, -0.03], \"normal\": [0, 0.2, 1]}, \"stiffness\": 3e5}]",
                        NULL};
    CHECK(eo_test_sim_open(&s, ctx, "cantilever", NULL, ov) == 0, "open");
    CHECK(eo_sim_scene(s)->nspring > 0 && eo_sim_scene(s)->ncollision == 1, "springs %d, planes %d", eo_sim_scene(s)->nspring, eo_sim_scene(s)->ncollision);
    int n = eo_test_sim_obj(s)->n, npen = 0;
    double *x = malloc((size_t)n * sizeof(double));
    eo_test_seed(7);
    /* perturbed, and sagged well into the tilted plane: some vertices penetrate by mm */
    for (int i = 0; i < n; i++) {
        int j = eo_step_free_to_full(eo_sim_step_problem(s), i);
        double X = eo_sim_scene(s)->mesh->X[j - j % 3];
        x[i] = eo_test_sim_guess(s)[i] + 2e-3 * eo_test_rand(-1, 1) - (j % 3 == 2 ? 0.2 * X * X : 0);
    }
    for (int i = 2; i < n; i += 3) {
        int j = eo_step_free_to_full(eo_sim_step_problem(s), i);
        double y = x[i - 1], z = x[i];
        (void)j;
        if (-((z + 0.03) * 1 + y * 0.2) / sqrt(1.04) > 1e-4) npen++;
    }
    double ge, he;
    fd_check(eo_test_sim_obj(s), x, 1.0, &ge, &he);
    printf("FD with springs (%d) and a collision plane (%d penetrating vertices): gradient %.2e, Hessian %.2e\n",
           eo_sim_scene(s)->nspring, npen, ge, he);
    CHECK(npen > 3, "penetrating vertices %d", npen);
    CHECK(ge < 1e-7 && he < 1e-6, "FD errors gradient %g Hessian %g", ge, he);
    free(x);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* springs only: material.model = spring vs an elastic-free... the same edges as
 * springs.edges = mesh with the same k (and a material of negligible stiffness) */
static void test_spring_material_equals_mesh_springs(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *a = NULL, *b = NULL;
    const char *ova[] = {"material.model=spring", "material.k=3000", "mesh.generate.cells=[3,1,1]", NULL};
    const char *ovb[] = {"material.model=linear", "material.E=1e-300", "material.nu=0",
                         "springs={\"edges\": \"mesh\", \"k\": 3000}", "mesh.generate.cells=[3,1,1]", NULL};
    CHECK(eo_test_sim_open(&a, ctx, "cantilever", NULL, ova) == 0, "open a");
    CHECK(eo_test_sim_open(&b, ctx, "cantilever", NULL, ovb) == 0, "open b");
    int n = eo_test_sim_obj(a)->n;
    CHECK(n == eo_test_sim_obj(b)->n, "same size");
    double *x = malloc((size_t)n * sizeof(double)), *ga = malloc((size_t)n * sizeof(double)),
           *gb = malloc((size_t)n * sizeof(double));
    eo_test_seed(3);
    for (int i = 0; i < n; i++) x[i] = eo_test_sim_guess(a)[i] + 0.01 * eo_test_rand(-1, 1);
    double fa, fb, d = 0, s2 = 0;
    eo_objective_gradient(eo_test_sim_obj(a), x, &fa, ga);
    eo_objective_gradient(eo_test_sim_obj(b), x, &fb, gb);
    for (int i = 0; i < n; i++) {
        d += (ga[i] - gb[i]) * (ga[i] - gb[i]);
        s2 += ga[i] * ga[i];
    }
    CHECK(fabs(fa - fb) <= 1e-12 * fabs(fa) && sqrt(d) <= 1e-12 * sqrt(s2),
          "spring material vs mesh springs: g %.17g vs %.17g, gradient diff %g", fa, fb, sqrt(d / s2));
    free(x), free(ga), free(gb);
    eo_sim_destroy(&a);
    eo_sim_destroy(&b);
    eo_test_ctx_done(&ctx);
}

/* ------------------------------------------------------------------ drop */

static void test_drop(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"solver.tol=1e-17", NULL}; /* tight (a resting state is a fixed point of the solve), above the roundoff of g ~ 1e-3 */
    if (eo_test_sim_open(&s, ctx, "drop", NULL, ov) != 0) {
        CHECK(0, "open drop");
        eo_sim_destroy(&s);
        eo_test_ctx_done(&ctx);
        return;
    }
    const double k = eo_sim_scene(s)->collision[0].opts.stiffness, g = 9.81;
    const double *pl = eo_sim_scene(s)->collision[0].shape; /* plane: point, unit normal */
    int bounced = 0;
    double zmin = INFINITY;
    for (int i = 0; i < eo_sim_scene(s)->time.steps; i++) {
        eo_sim_step_result r;
        CHECK(eo_test_sim_step(s, NULL, NULL, &r) == 0 && eo_reason_is_converged(r.reason), "step %d: %s", i,
              eo_reason_name(r.reason));
        eo_step_stats st;
        eo_step_stats_compute(eo_sim_step_problem(s), &st);
        zmin = fmin(zmin, st.com[2]);
        bounced |= st.com[2] < 0.1 + 1e-3;
    }
    const eo_mesh *m = eo_sim_scene(s)->mesh;
    const double *x = eo_step_x(eo_sim_step_problem(s)), *v = eo_step_v(eo_sim_step_problem(s)), *mass = eo_step_vertex_mass(eo_sim_step_problem(s));
    double M = 0, force = 0, vmax = 0, dsum = 0;
    int nb = 0, wrong = 0;
    for (int q = 0; q < m->nv; q++) {
        M += mass[q];
        double d = -((x[3 * q] - pl[0]) * pl[3] + (x[3 * q + 1] - pl[1]) * pl[4] + (x[3 * q + 2] - pl[2]) * pl[5]);
        int bottom = fabs(m->X[3 * q + 2] - 0.05) < 1e-9;
        if (d > 0) {
            force += k * d;
            dsum += d;
            nb++;
        }
        wrong += bottom != (d > 0);
        vmax = fmax(vmax, sqrt(v[3 * q] * v[3 * q] + v[3 * q + 1] * v[3 * q + 1] + v[3 * q + 2] * v[3 * q + 2]));
    }
    double expect_d = M * g / (nb * k);
    printf("drop: %d touching vertices, sum k d = %.9g N vs M g = %.9g N, mean depth %.4e m (M g/(N k) = %.4e), "
           "max speed %.2e m/s\n", nb, force, M * g, dsum / nb, expect_d, vmax);
    CHECK(bounced, "the box reached the ground");
    CHECK(wrong == 0, "exactly the bottom vertices touch (%d wrong)", wrong);
    CHECK(fabs(force - M * g) / (M * g) < 2e-5, "contact force %g vs weight %g", force, M * g);
    CHECK(fabs(dsum / nb - expect_d) / expect_d < 2e-5, "mean depth %g vs %g", dsum / nb, expect_d);
    CHECK(vmax < 1e-4, "at rest: max speed %g", vmax);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* ------------------------------------------------------------------ explicit in scenes */

static void test_explicit_freefall(void)
{
    const char *mass[2] = {"mass=lumped", "mass=consistent"};
    for (int i = 0; i < 2; i++) {
        eo_ctx *ctx = eo_test_ctx();
        eo_sim *s = NULL;
        const char *ov[] = {"time.integrator=verlet", "time.dt=5e-4", "time.steps=40", mass[i], NULL};
        CHECK(eo_test_sim_open(&s, ctx, "freefall", NULL, ov) == 0, "open");
        eo_step_stats s0, sk;
        eo_step_stats_compute(eo_sim_step_problem(s), &s0);
        for (int k = 0; k < 40; k++) {
            eo_sim_step_result r;
            CHECK(eo_sim_step(s, &r) == 0 && r.reason == EO_REASON_EXPLICIT && r.iterations == 0 && isnan(r.g),
                  "advance");
        }
        eo_step_stats_compute(eo_sim_step_problem(s), &sk);
        double t = eo_step_time(eo_sim_step_problem(s)), expect = -0.5 * 9.81 * t * t;
        printf("explicit freefall (%s): com dz %.15g, -g t^2/2 = %.15g\n", mass[i], sk.com[2] - s0.com[2], expect);
        CHECK(fabs(sk.com[2] - s0.com[2] - expect) < 1e-12, "%s: com error %g", mass[i],
              sk.com[2] - s0.com[2] - expect);
        CHECK(fabs(sk.max_J - 1) < 1e-9 && fabs(sk.min_J - 1) < 1e-9, "undeformed");
        eo_sim_destroy(&s);
        eo_test_ctx_done(&ctx);
    }
}

static void test_explicit_diverges(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"time.integrator=rk4", "time.dt=1.0", NULL}; /* h w = 5 > 2.83 */
    CHECK(eo_test_sim_open(&s, ctx, NULL, spring1, ov) == 0, "open");
    int reason = 0, k;
    for (k = 0; k < 2000; k++) {
        eo_sim_step_result r;
        CHECK(eo_sim_step(s, &r) == 0, "advance");
        reason = r.reason;
        if (reason != EO_REASON_EXPLICIT) break;
    }
    printf("rk4 at h w = 5: %s after %d steps (t = %g)\n", eo_reason_name(reason), k, eo_step_time(eo_sim_step_problem(s)));
    CHECK(reason == EO_DIVERGED_NONFINITE, "reason %s", eo_reason_name(reason));
    CHECK(k > 10 && k < 2000, "diverged after %d steps", k);
    CHECK(eo_step_state_finite(eo_sim_step_problem(s)) && eo_step_index(eo_sim_step_problem(s)) == k, "the last finite state is kept");
    /* the implicit step API refuses explicit integrators */
    CHECK(eo_step_end(eo_sim_step_problem(s), eo_test_sim_guess(s)) == EO_ERR_UNSUPPORTED, "end refuses explicit");
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* ------------------------------------------------------------------ errors */

static void expect_error(const char *json, int status, const char *needle)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_cfg *cfg = NULL;
    eo_scene *sc = NULL;
    eo_step *st = NULL;
    int rc = eo_cfg_load(ctx, NULL, json, &cfg);
    if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
    if (rc >= 0) rc = eo_step_create(ctx, sc, &st);
    int reason;
    if (rc >= 0 && eo_step_is_explicit(st)) rc = eo_step_advance(st, &reason);
    CHECK(rc == status, "%s: status %d, expected %d (%s)", json, rc, status, eo_ctx_message(ctx));
    CHECK(strstr(eo_ctx_message(ctx), needle) != NULL, "message '%s' lacks '%s'", eo_ctx_message(ctx), needle);
    eo_step_destroy(&st);
    eo_scene_destroy(&sc);
    eo_cfg_destroy(&cfg);
    eo_test_ctx_done(&ctx);
}

static void test_errors(void)
{
    expect_error("{\"springs\": {\"edges\": \"list\"}}", EO_ERR_INVALID, "springs.list");
    expect_error("{\"springs\": {\"list\": [[0, 1]]}}", EO_ERR_INVALID, "edges");
    expect_error("{\"springs\": {\"edges\": \"list\", \"list\": [[0, 100000]]}}", EO_ERR_RANGE, "vertex index");
    expect_error("{\"springs\": {\"edges\": \"list\", \"list\": [[0, 1], [1, 0]]}}", EO_ERR_INVALID, "twice");
    expect_error("{\"springs\": {\"edges\": \"mesh\", \"damping\": 1}}", EO_ERR_INVALID, "explicit");
    expect_error("{\"collisions\": [{\"stiffness\": 10}]}", EO_ERR_INVALID, "plane");
    expect_error("{\"collisions\": [{\"plane\": {\"normal\": [0, 0, 0]}}]}", EO_ERR_RANGE, "zero normal");
    expect_error("{\"point_masses\": [[0, -1]]}", EO_ERR_RANGE, ">= 0");
    expect_error("{\"mesh\": {\"points\": [[0, 0, 0], [1, 0]]}}", EO_ERR_TYPE, "point 1");
    expect_error("{\"mesh\": {\"points\": [[0, 0, 0], [1, 0, 0]]}, \"springs\": {\"edges\": \"mesh\"}}", EO_ERR_INVALID,
                 "no tets");
    expect_error("{\"mesh\": {\"points\": [[0, 0, 0], [1, 0, 0]]}, \"time\": {\"integrator\": \"verlet\"}}",
                 EO_ERR_INVALID, "no mass");
}

/* The cantilever beyond the stability limit of rk4 (dt = 3e-4) and forward Euler
 * (dt = 1e-4), through eo_sim: the first step that meets a non-finite energy or force
 * (or ends non-finite) returns EO_OK with reason diverged_nonfinite, before step 300;
 * the state is exactly the one before that step (index, time, positions, velocities),
 * and finite; a trial of an explicit step is refused. */
static void test_explicit_blowup_cantilever(void)
{
    const char *cases[2][2] = {{"time.integrator=rk4", "time.dt=3e-4"},
                               {"time.integrator=forward_euler", "time.dt=1e-4"}};
    for (int c = 0; c < 2; c++) {
        eo_ctx *ctx = eo_test_ctx();
        eo_sim *s = NULL;
        const char *ov[] = {cases[c][0], cases[c][1], "time.steps=300", "output.vtu=false", NULL};
        CHECK(eo_sim_create_from(ctx, NULL, "cantilever", ov, &s) == EO_OK, "%s", eo_ctx_message(ctx));
        if (!s) continue;
        const int nf = 3 * eo_sim_scene(s)->mesh->nv;
        const double dt = eo_sim_scene(s)->time.dt;
        double *xb = malloc(4 * (size_t)nf * sizeof(double)), *vb = xb + nf, *xa = vb + nf, *va = xa + nf;
        eo_sim_step_result r = {0};
        int k, rc = 0;
        for (k = 0; k < 300; k++) {
            eo_sim_get_state(s, xb, vb, NULL, NULL);
            if ((rc = eo_sim_step(s, &r)) < 0 || r.reason != EO_REASON_EXPLICIT) break;
        }
        double t;
        int index;
        eo_sim_get_state(s, xa, va, &t, &index);
        int same = 1;
        for (int i = 0; i < nf; i++) same &= xa[i] == xb[i] && va[i] == vb[i];
        printf("cantilever %s %s: %s at step %d, kept t = %g, max disp %.3g m\n", cases[c][0], cases[c][1],
               eo_reason_name(r.reason), k + 1, t, r.stats.max_disp);
        CHECK(rc == EO_OK && r.reason == EO_DIVERGED_NONFINITE, "%s: rc %d reason %s", cases[c][0], rc,
              eo_reason_name(r.reason));
        CHECK(k > 0 && k < 299, "%s: diverged at step %d of 300", cases[c][0], k + 1);
        CHECK(index == k && fabs(t - k * dt) < 1e-9 * dt * (k + 1) && fabs(r.t - t) == 0,
              "%s: the last finite state is kept (index %d, t %g)", cases[c][0], index, t);
        CHECK(same && eo_step_state_finite(eo_sim_step_problem(s)) && isfinite(r.stats.max_disp),
              "%s: state unchanged by the diverged step and finite", cases[c][0]);
        double *x = malloc((size_t)nf * sizeof(double));
        eo_solve_result sr;
        CHECK(eo_sim_trial(s, NULL, NULL, x, NULL, NULL, NULL, &sr) == EO_ERR_UNSUPPORTED, "trial refuses explicit");
        free(x);
        free(xb);
        eo_sim_destroy(&s);
        eo_test_ctx_done(&ctx);
    }
}

/* The consistent-mass solve of the explicit integrators takes solver.linear (with its
 * section): rk4 on the cantilever, 60 steps at dt = 2e-5, with cholmod (default) and with
 * pcg (ichol0, tol 1e-14): the trajectories differ (another solver ran) by at most
 * 1e-8 relative to the displacement. A bad linear solver name fails at create. */
static void test_mass_solver(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *lin[2][3] = {{"solver.linear=cholmod", "solver.max_iters=100", NULL},
                             {"solver.linear=pcg", "solver.pcg.tol=1e-14", "solver.pcg.preconditioner=ichol0"}};
    eo_sim *s[2] = {NULL, NULL};
    for (int q = 0; q < 2; q++) {
        const char *ov[] = {"time.integrator=rk4", "time.dt=2e-5", "time.steps=60", lin[q][0], lin[q][1], lin[q][2],
                            NULL};
        CHECK(eo_sim_create_from(ctx, NULL, "cantilever", ov, &s[q]) == EO_OK, "%s", eo_ctx_message(ctx));
        if (!s[q]) return;
        for (int k = 0; k < 60; k++) {
            eo_sim_step_result r;
            CHECK(eo_sim_step(s[q], &r) == EO_OK && r.reason == EO_REASON_EXPLICIT, "%s step %d", lin[q][0], k);
        }
    }
    const eo_step *a = eo_sim_step_problem(s[0]), *b = eo_sim_step_problem(s[1]);
    const double *X = eo_step_x0(a);
    double dmax = 0, umax = 0;
    for (int i = 0; i < 3 * eo_sim_scene(s[0])->mesh->nv; i++) {
        dmax = fmax(dmax, fabs(eo_step_x(a)[i] - eo_step_x(b)[i]));
        umax = fmax(umax, fabs(eo_step_x(a)[i] - X[i]));
    }
    printf("mass solve cholmod vs pcg, rk4 60 steps: max |dx| %.3g m, max displacement %.3g m\n", dmax, umax);
    CHECK(umax > 1e-7 && dmax > 0 && dmax <= 1e-8 * umax, "pcg vs cholmod: %g of %g", dmax, umax);
    eo_sim_destroy(&s[0]);
    eo_sim_destroy(&s[1]);
    const char *bad[] = {"time.integrator=rk4", "solver.linear=nosuch", NULL};
    eo_sim *sb = NULL;
    CHECK(eo_sim_create_from(ctx, NULL, "cantilever", bad, &sb) == EO_ERR_UNKNOWN_NAME && !sb, "bad linear name: %s",
          eo_ctx_message(ctx));
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_explicit_blowup_cantilever();
    test_mass_solver();
    test_errors();
    test_single_spring();
    test_hanging_chain();
    test_spring_material_equals_mesh_springs();
    test_fd_springs();
    test_drop();
    test_explicit_freefall();
    test_explicit_diverges();
    return eo_test_finish("test_mass_spring");
}
