/* Contact beyond half-spaces (issue 12 item 6; suite 'engine'):
 *
 *  - FD check (central differences, step sweep) of the penalty terms of a sphere and a
 *    box obstacle, isolated as the difference of two step objectives (with and without
 *    the obstacles), at a state where 20+ vertices penetrate them; the sphere's true
 *    Hessian has the negative tangential eigenvalue −k d/ρ and its clamped one not;
 *  - FD check of the lagged friction term (objective with μ = 0.5 minus μ = 0), at
 *    states inside the smoothing zone (slips ~ ε = ε_v h) and beyond it (sliding);
 *  - a block on a slope (the slope's frame: ground plane z = 0, gravity tilted by θ =
 *    30°): with μ = 0.8 > tan θ it stops (speed below ε_v, no further travel), with
 *    μ = 0.3 < tan θ it slides with acceleration g (sin θ − μ cos θ) within 1e-6: a block of
 *    tets under backward_euler, a particle under newmark (the slip is measured by the
 *    integrator's vₙ₊₁, the friction weight doubled for its trapezoidal rule);
 *  - the same slope under bdf2 (particle), and the order of a curved slide: a particle
 *    launched along x on the plane with gravity tilted into y curves while friction
 *    brakes it; the end position after 0.4 s converges at order 2 under bdf2 (the slip
 *    measured by BDF2's history velocity, not backward Euler's) and order 1 under
 *    backward Euler;
 *  - a block dropped on a sphere obstacle: on top it comes to rest with the contact
 *    forces balancing M g; a particle on the sphere 20° from the top rests with μ = 0.6 >
 *    tan 20° (normal force M g cos 20°) and slides off without friction;
 *  - scene errors of the new keys. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

static const double PI = 3.14159265358979323846;

/* ------------------------------------------------------------------ FD of a difference */

/* Relative errors of the directional derivative of gA − gB and of (HA − HB)·v against
 * central differences of gA − gB and ∇gA − ∇gB at x (best over a step sweep); *gnorm:
 * ‖∇gA − ∇gB‖ at x (a term that is absent would pass any FD check). */
static void fd_diff(eo_objective *A, eo_objective *B, const double *x, double scale, eo_proj proj, double *gerr,
                    double *herr, double *gnorm)
{
    int n = A->n;
    double *buf = calloc(9 * (size_t)n, sizeof(double));
    double *v = buf, *ga = buf + n, *gb = buf + 2 * n, *xp = buf + 3 * n, *gp = buf + 4 * n, *gm = buf + 5 * n,
           *Hv = buf + 6 * n, *Hb = buf + 7 * n, *t = buf + 8 * n;
    for (int i = 0; i < n; i++) v[i] = eo_test_rand(-1, 1);
    double fa, fb, fp, fm, f2;
    eo_objective_gradient(A, x, &fa, ga);
    eo_objective_gradient(B, x, &fb, gb);
    eo_csc *H;
    eo_objective_hessian(A, x, proj, &H);
    eo_csc_symv(H, v, Hv);
    eo_objective_hessian(B, x, proj, &H);
    eo_csc_symv(H, v, Hb);
    double dg = 0, nhv = 0, gn = 0;
    for (int i = 0; i < n; i++) {
        Hv[i] -= Hb[i];
        dg += (ga[i] - gb[i]) * v[i];
        nhv += Hv[i] * Hv[i];
        gn += (ga[i] - gb[i]) * (ga[i] - gb[i]);
    }
    nhv = sqrt(nhv);
    *gnorm = sqrt(gn);
    *gerr = *herr = INFINITY;
    for (int e = 1; e <= 8; e++) {
        double eps = scale * pow(10.0, -e);
        for (int i = 0; i < n; i++) xp[i] = x[i] + eps * v[i];
        eo_objective_gradient(A, xp, &fp, gp);
        eo_objective_gradient(B, xp, &f2, t);
        fp -= f2;
        for (int i = 0; i < n; i++) gp[i] -= t[i];
        for (int i = 0; i < n; i++) xp[i] = x[i] - eps * v[i];
        eo_objective_gradient(A, xp, &fm, gm);
        eo_objective_gradient(B, xp, &f2, t);
        fm -= f2;
        for (int i = 0; i < n; i++) gm[i] -= t[i];
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

/* a 0.3 m cube of 3×3×3 cells starting inside a sphere (below) and a box (a corner) */
static const char *fd_scene =
    "{\"mesh\": {\"generate\": {\"size\": [0.3, 0.3, 0.3], \"cells\": [3, 3, 3]}},"
    " \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e5, \"nu\": 0.3},"
    " \"time\": {\"integrator\": \"backward_euler\", \"dt\": 0.01, \"steps\": 1}}";
static const char *fd_obstacles =
    "collisions=[{\"sphere\": {\"center\": [0.15, 0.15, -0.3], \"radius\": 0.37}, \"stiffness\": 2e4, \"friction\": %g},"
    " {\"box\": {\"min\": [-0.1, -0.1, 0.15], \"max\": [0.12, 0.4, 0.5]}, \"stiffness\": 3e4, \"friction\": %g}]";

static int count_inside(const eo_sim *s, const double *xfull)
{
    int n = 0;
    const eo_mesh *m = eo_sim_scene(s)->mesh;
    for (int v = 0; v < m->nv; v++) {
        const double *p = xfull + 3 * v;
        double r = sqrt((p[0] - 0.15) * (p[0] - 0.15) + (p[1] - 0.15) * (p[1] - 0.15) + (p[2] + 0.3) * (p[2] + 0.3));
        n += r < 0.37;
        n += p[0] > -0.1 && p[0] < 0.12 && p[1] > -0.1 && p[1] < 0.4 && p[2] > 0.15 && p[2] < 0.5;
    }
    return n;
}

static void test_fd_obstacles(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *a = NULL, *b = NULL, *c = NULL;
    char ob0[512], ob1[512];
    snprintf(ob0, sizeof ob0, fd_obstacles, 0.0, 0.0);
    snprintf(ob1, sizeof ob1, fd_obstacles, 0.5, 0.5);
    const char *ova[] = {ob0, NULL}, *ovc[] = {ob1, NULL};
    CHECK(eo_test_sim_open(&a, ctx, NULL, fd_scene, ova) == 0, "open with obstacles");
    CHECK(eo_test_sim_open(&b, ctx, NULL, fd_scene, NULL) == 0, "open without");
    CHECK(eo_test_sim_open(&c, ctx, NULL, fd_scene, ovc) == 0, "open with friction");
    if (!a || !b || !c) goto done;
    {
        eo_objective *A = eo_test_sim_obj(a), *B = eo_test_sim_obj(b), *C = eo_test_sim_obj(c);
        const int n = A->n;
        double *x = malloc((size_t)n * sizeof(double)), *xf = malloc((size_t)n * sizeof(double));
        eo_test_seed(11);
        for (int i = 0; i < n; i++) x[i] = eo_test_sim_guess(a)[i] + 5e-3 * eo_test_rand(-1, 1);
        for (int i = 0; i < n; i++) xf[eo_step_free_to_full(eo_sim_step_problem(a), i)] = x[i];
        int nin = count_inside(a, xf);
        double ge, he, gn;
        fd_diff(A, B, x, 1e-2, EO_PROJ_NONE, &ge, &he, &gn);
        printf("FD sphere + box penalty (%d vertex-obstacle contacts): gradient %.2e, Hessian %.2e, |grad| %.3g\n", nin,
               ge, he, gn);
        CHECK(nin >= 20, "penetrating vertices %d", nin);
        CHECK(gn > 0.1 && ge < 1e-8 && he < 1e-7, "obstacle FD errors gradient %g Hessian %g", ge, he);
        /* the sphere's tangential eigenvalue: v = a tangent at a vertex inside the sphere */
        int vin = -1;
        for (int i = 0; i < n && vin < 0; i += 3) {
            const double *p = xf + 3 * (eo_step_free_to_full(eo_sim_step_problem(a), i) / 3);
            double r = sqrt((p[0] - 0.15) * (p[0] - 0.15) + (p[1] - 0.15) * (p[1] - 0.15) + (p[2] + 0.3) * (p[2] + 0.3));
            if (r < 0.35 && eo_step_free_to_full(eo_sim_step_problem(a), i) % 3 == 0) vin = i;
        }
        CHECK(vin >= 0, "a free vertex inside the sphere");
        if (vin >= 0) {
            const double *p = xf + eo_step_free_to_full(eo_sim_step_problem(a), vin);
            double r[3] = {p[0] - 0.15, p[1] - 0.15, p[2] + 0.3}, t[3] = {r[1], -r[0], 0};
            double rho = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]), tn = sqrt(t[0] * t[0] + t[1] * t[1]);
            double *v = calloc((size_t)n, sizeof(double)), *Hv = calloc((size_t)n, sizeof(double));
            double q[2][2];
            eo_proj pr[2] = {EO_PROJ_NONE, EO_PROJ_CLAMP};
            for (int k = 0; k < 3; k++) v[vin + k] = t[k] / tn;
            for (int w = 0; w < 2; w++) {
                eo_objective *O[2] = {A, B};
                for (int o = 0; o < 2; o++) {
                    eo_csc *H;
                    eo_objective_hessian(O[o], x, pr[w], &H);
                    eo_csc_symv(H, v, Hv);
                    q[w][o] = Hv[vin] * v[vin] + Hv[vin + 1] * v[vin + 1] + Hv[vin + 2] * v[vin + 2];
                }
            }
            const double wgt = 1e-4 /* h² */, expect = -wgt * 2e4 * (0.37 - rho) / rho;
            printf("sphere tangent curvature: t'H t = %.6e (true), %.3e (clamp); -w k d/rho = %.6e\n", q[0][0] - q[0][1],
                   q[1][0] - q[1][1], expect);
            CHECK(fabs(q[0][0] - q[0][1] - expect) <= 1e-6 * fabs(expect) + 1e-12 * fabs(q[0][0]),
                  "tangential eigenvalue %g vs %g", q[0][0] - q[0][1], expect);
            CHECK(fabs(q[1][0] - q[1][1]) <= 1e-9 * fabs(q[1][0]), "clamped tangential eigenvalue %g",
                  q[1][0] - q[1][1]);
            free(v), free(Hv);
        }
        /* friction: C − A is w·D; contacts lagged at the start (penetrating) state */
        /* slips around ε = ε_v h = 1e-5 m (f₀ is C² there, not C³: a looser gradient
         * bound), and sliding */
        const double scales[2] = {1e-5, 3e-3}, gtol[2] = {5e-6, 1e-7};
        for (int k = 0; k < 2; k++) {
            for (int i = 0; i < n; i++) x[i] = eo_test_sim_guess(a)[i] + scales[k] * eo_test_rand(-1, 1);
            fd_diff(C, A, x, scales[k], EO_PROJ_NONE, &ge, &he, &gn);
            printf("FD friction, perturbation %.0e m: gradient %.2e, Hessian %.2e, |grad| %.3g\n", scales[k], ge, he, gn);
            CHECK(gn > 1e-4 && ge < gtol[k] && he < 1e-6, "friction FD (%g) errors gradient %g Hessian %g", scales[k], ge,
                  he);
        }
        free(x), free(xf);
    }
done:
    eo_sim_destroy(&a);
    eo_sim_destroy(&b);
    eo_sim_destroy(&c);
    eo_test_ctx_done(&ctx);
}

/* ------------------------------------------------------------------ slope */

/* A 0.1 m block of tets (1 kg; particle = 0) or a particle (1 kg point mass, started at
 * its penetration m g cos θ/k) on the ground z = 0 with gravity g (sin θ, 0, −cos θ): run 1 s;
 * *a = x-acceleration of the centre of mass from its velocity at 0.5 s and 1 s, *vend
 * the largest vertex speed at the end, *dx the com travel over [0.5, 1] s. */
static int slope(const char *integrator, int particle, double mu, double theta, double *a, double *vend, double *dx)
{
    char json[2048], body[256];
    const double g = 9.81, dt = 0.005;
    if (particle)
        snprintf(body, sizeof body, "\"mesh\": {\"points\": [[0, 0, %.17g]]}, \"point_mass\": 1", -g * cos(theta) / 1e5);
    else
        snprintf(body, sizeof body, "\"mesh\": {\"generate\": {\"size\": [0.1, 0.1, 0.1], \"cells\": [1, 1, 1]}}");
    snprintf(json, sizeof json,
             "{%s,"
             " \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e6, \"nu\": 0.3, \"density\": 1000},"
             " \"mass\": \"lumped\", \"gravity\": [%.17g, 0, %.17g],"
             " \"collisions\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 0, 1]}, \"stiffness\": 1e5,"
             " \"friction\": %g, \"eps_v\": 1e-4}],"
             " \"time\": {\"integrator\": \"%s\", \"dt\": %g, \"steps\": 200},"
             " \"solver\": {\"tol\": 1e-16, \"max_iters\": 100}}",
             body, g * sin(theta), -g * cos(theta), mu, integrator, dt);
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    int ok = eo_test_sim_open(&s, ctx, NULL, json, NULL) == 0;
    double v1 = 0, x1 = 0;
    for (int k = 0; ok && k < 200; k++) {
        eo_sim_step_result r;
        ok = eo_test_sim_step(s, NULL, NULL, &r) == 0 && eo_reason_is_converged(r.reason);
        CHECK(ok, "slope %s mu %g step %d: %s", integrator, mu, k, eo_reason_name(r.reason));
        if (k == 99 || k == 199) {
            const eo_step *st = eo_sim_step_problem(s);
            const double *x = eo_step_x(st), *v = eo_step_v(st), *m = eo_step_vertex_mass(st);
            double M = 0, vc = 0, xc = 0, vmax = 0;
            for (int q = 0; q < eo_sim_scene(s)->mesh->nv; q++) {
                M += m[q];
                vc += m[q] * v[3 * q];
                xc += m[q] * x[3 * q];
                vmax = fmax(vmax, sqrt(v[3 * q] * v[3 * q] + v[3 * q + 1] * v[3 * q + 1] + v[3 * q + 2] * v[3 * q + 2]));
            }
            vc /= M, xc /= M;
            if (k == 99) {
                v1 = vc, x1 = xc;
            } else {
                *a = (vc - v1) / 0.5;
                *vend = vmax;
                *dx = xc - x1;
            }
        }
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return ok;
}

static void test_slope(void)
{
    const double theta = 30 * PI / 180, g = 9.81;
    /* newmark conserves energy: a block of tets keeps the vibration of its landing on
     * the penalty springs (rocking, bouncing), which modulates the lagged normal force;
     * a particle started at its resting depth has none */
    const char *integ[3] = {"backward_euler", "newmark", "bdf2"}, *body[3] = {"block", "particle", "particle"};
    for (int i = 0; i < 3; i++) {
        double a, v, dx;
        /* μ = 0.8 > tan 30° = 0.577: stops */
        if (slope(integ[i], i > 0, 0.8, theta, &a, &v, &dx)) {
            printf("slope %s %s, mu 0.8 > tan 30: com acceleration %.3e m/s^2, max speed at 1 s %.2e m/s, travel over "
                   "[0.5, 1] s %.2e m\n", integ[i], body[i], a, v, dx);
            CHECK(v < 1e-4 && fabs(dx) < 1e-4, "%s: stuck block moves: speed %g, travel %g", integ[i], v, dx);
        }
        /* μ = 0.3 < tan 30°: slides with a = g (sin θ − μ cos θ) */
        const double mu = 0.3, expect = g * (sin(theta) - mu * cos(theta));
        if (slope(integ[i], i > 0, mu, theta, &a, &v, &dx)) {
            printf("slope %s %s, mu 0.3 < tan 30: com acceleration %.6f m/s^2, g (sin - mu cos) = %.6f (rel. error %.2e), "
                   "travel %.3f m\n", integ[i], body[i], a, expect, fabs(a - expect) / expect, dx);
            CHECK(fabs(a - expect) < 1e-6 * expect, "%s: sliding acceleration %g vs %g", integ[i], a, expect);
        }
    }
}

/* ------------------------------------------------------------------ curved slide, order */

/* A 1 kg particle on the plane z = 0 (stiffness 1e5, started at its resting depth),
 * gravity (0, 2, −9.81), initial velocity (2, 0, 0), μ = 0.3: its end position after
 * 0.4 s at step dt (x, y into p). */
static int curved_slide(const char *integrator, double dt, double p[2])
{
    char json[2048];
    const double g = 9.81;
    const int n = (int)lround(0.4 / dt);
    snprintf(json, sizeof json,
             "{\"mesh\": {\"points\": [[0, 0, %.17g]]}, \"point_mass\": 1,"
             " \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e6, \"nu\": 0.3, \"density\": 1000},"
             " \"mass\": \"lumped\", \"gravity\": [0, 2, %.17g], \"initial\": {\"velocity\": [2, 0, 0]},"
             " \"collisions\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 0, 1]}, \"stiffness\": 1e5,"
             " \"friction\": 0.3, \"eps_v\": 1e-4}],"
             " \"time\": {\"integrator\": \"%s\", \"dt\": %.17g, \"steps\": %d},"
             " \"solver\": {\"tol\": 1e-16, \"max_iters\": 100}}",
             -g / 1e5, -g, integrator, dt, n);
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    int ok = eo_test_sim_open(&s, ctx, NULL, json, NULL) == 0;
    for (int k = 0; ok && k < n; k++) {
        eo_sim_step_result r;
        ok = eo_test_sim_step(s, NULL, NULL, &r) == 0 && eo_reason_is_converged(r.reason);
        CHECK(ok, "curved slide %s dt %g step %d: %s", integrator, dt, k, eo_reason_name(r.reason));
    }
    if (ok) {
        const double *x = eo_step_x(eo_sim_step_problem(s));
        p[0] = x[0], p[1] = x[1];
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return ok;
}

static void test_curved_slide_order(void)
{
    const char *integ[2] = {"bdf2", "backward_euler"};
    const double expect[2] = {2, 1};
    for (int i = 0; i < 2; i++) {
        double p[4][2];
        const double dt0 = 0.01;
        int ok = 1;
        for (int l = 0; l < 4 && ok; l++) ok = curved_slide(integ[i], dt0 / (1 << l), p[l]);
        if (!ok) continue;
        /* order from three successive differences (no reference solution needed) */
        const double d1 = hypot(p[1][0] - p[0][0], p[1][1] - p[0][1]);
        const double d2 = hypot(p[2][0] - p[1][0], p[2][1] - p[1][1]);
        const double d3 = hypot(p[3][0] - p[2][0], p[3][1] - p[2][1]);
        const double q1 = log2(d1 / d2), q2 = log2(d2 / d3);
        printf("curved slide %s: end (%.9f, %.9f), differences %.3e %.3e %.3e, orders %.3f %.3f\n", integ[i],
               p[3][0], p[3][1], d1, d2, d3, q1, q2);
        CHECK(fabs(q2 - expect[i]) < 0.15, "curved slide %s: order %.3f, expected %g", integ[i], q2, expect[i]);
    }
}

/* ------------------------------------------------------------------ block on a sphere */

/* phi = 0: a 0.1 m block (1 kg) dropped (5 cm gap) onto the top of the ball of radius
 * 0.5 about the origin; phi > 0: a particle (1 kg point mass) placed on the ball's
 * surface at angle phi from the top. 1.5 s of backward Euler. Returns the com distance
 * travelled after 0.75 s, the largest speed at the end, and Σ contact forces · ẑ / (M g)
 * at the end. */
static int on_sphere(double phi, double mu, double *travel, double *vend, double *fratio)
{
    char json[2048], body[512];
    const double R = 0.5;
    if (phi == 0)
        snprintf(body, sizeof body,
                 "\"mesh\": {\"generate\": {\"size\": [0.1, 0.1, 0.1], \"cells\": [1, 1, 1], \"origin\": [-0.05, -0.05, "
                 "%.17g]}}", R + 0.05);
    else
        snprintf(body, sizeof body, "\"mesh\": {\"points\": [[%.17g, 0, %.17g]]}, \"point_mass\": 1", R * sin(phi),
                 R * cos(phi));
    snprintf(json, sizeof json,
             "{%s,"
             " \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e6, \"nu\": 0.3, \"density\": 1000},"
             " \"mass\": \"lumped\", \"gravity\": [0, 0, -9.81],"
             " \"collisions\": [{\"sphere\": {\"center\": [0, 0, 0], \"radius\": %g}, \"stiffness\": 1e5, "
             "\"friction\": %g, \"eps_v\": 1e-4}],"
             " \"time\": {\"integrator\": \"backward_euler\", \"dt\": 0.005, \"steps\": 300},"
             " \"solver\": {\"tol\": 1e-16, \"max_iters\": 100}}",
             body, R, mu);
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    int ok = eo_test_sim_open(&s, ctx, NULL, json, NULL) == 0;
    double c1[3] = {0, 0, 0};
    for (int k = 0; ok && k < 300; k++) {
        eo_sim_step_result r;
        ok = eo_test_sim_step(s, NULL, NULL, &r) == 0 && eo_reason_is_converged(r.reason);
        CHECK(ok, "sphere phi %g mu %g step %d: %s", phi, mu, k, eo_reason_name(r.reason));
        const eo_step *st = eo_sim_step_problem(s);
        const double *x = eo_step_x(st), *v = eo_step_v(st), *m = eo_step_vertex_mass(st);
        if (k != 149 && k != 299) continue;
        double M = 0, cm[3] = {0, 0, 0}, vmax = 0, fz = 0;
        for (int q = 0; q < eo_sim_scene(s)->mesh->nv; q++) {
            const double *p = x + 3 * q;
            M += m[q];
            for (int d = 0; d < 3; d++) cm[d] += m[q] * p[d];
            vmax = fmax(vmax, sqrt(v[3 * q] * v[3 * q] + v[3 * q + 1] * v[3 * q + 1] + v[3 * q + 2] * v[3 * q + 2]));
            double rho = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            if (rho < R) fz += 1e5 * (R - rho) * p[2] / rho;
        }
        for (int d = 0; d < 3; d++) cm[d] /= M;
        if (k == 149) {
            memcpy(c1, cm, sizeof c1);
        } else {
            *travel = sqrt((cm[0] - c1[0]) * (cm[0] - c1[0]) + (cm[1] - c1[1]) * (cm[1] - c1[1]) +
                           (cm[2] - c1[2]) * (cm[2] - c1[2]));
            *vend = vmax;
            *fratio = fz / (M * 9.81);
        }
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return ok;
}

static void test_on_sphere(void)
{
    double tr, v, fr;
    if (on_sphere(0, 0, &tr, &v, &fr)) {
        printf("block on top of a sphere, frictionless: travel over [0.75, 1.5] s %.2e m, max speed %.2e m/s, "
               "sum of vertical contact forces / M g = %.9f\n", tr, v, fr);
        CHECK(tr < 1e-5 && v < 1e-4 && fabs(fr - 1) < 1e-4, "rests on top: travel %g speed %g force ratio %g", tr, v, fr);
    }
    const double phi = 20 * PI / 180;
    if (on_sphere(phi, 0.6, &tr, &v, &fr)) {
        printf("particle 20 deg from the top, mu 0.6 > tan 20 = %.3f: travel %.2e m, max speed %.2e m/s, vertical "
               "penalty force / M g = %.6f (cos^2 20 = %.6f)\n", tan(phi), tr, v, fr, cos(phi) * cos(phi));
        CHECK(tr < 1e-4 && v < 1e-3, "rests with friction: travel %g speed %g", tr, v);
    }
    if (on_sphere(phi, 0, &tr, &v, &fr)) {
        printf("particle 20 deg from the top, frictionless: travel %.3f m, speed %.3f m/s\n", tr, v);
        CHECK(tr > 0.1 && v > 0.5, "slides off without friction: travel %g speed %g", tr, v);
    }
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
    CHECK(rc == status, "%s: status %d, expected %d (%s)", json, rc, status, eo_ctx_message(ctx));
    CHECK(strstr(eo_ctx_message(ctx), needle) != NULL, "message '%s' lacks '%s'", eo_ctx_message(ctx), needle);
    eo_step_destroy(&st);
    eo_scene_destroy(&sc);
    eo_cfg_destroy(&cfg);
    eo_test_ctx_done(&ctx);
}

static void test_errors(void)
{
    expect_error("{\"collisions\": [{\"stiffness\": 10}]}", EO_ERR_INVALID, "exactly one shape");
    expect_error("{\"collisions\": [{\"plane\": {}, \"sphere\": {}}]}", EO_ERR_INVALID, "found 2");
    expect_error("{\"collisions\": [{\"plane\": {\"normal\": [0, 0, 0]}}]}", EO_ERR_RANGE, "zero normal");
    expect_error("{\"collisions\": [{\"box\": {\"min\": [0, 0, 0], \"max\": [1, 0, 1]}}]}", EO_ERR_RANGE,
                 "collisions.0.box.max");
    expect_error("{\"collisions\": [{\"sphere\": {\"radius\": 0}}]}", EO_ERR_RANGE, "radius");
    expect_error("{\"collisions\": [{\"cylinder\": {}}]}", EO_ERR_UNKNOWN_KEY, "sphere");
    expect_error("{\"collisions\": [{\"plane\": {}, \"friction\": -1}]}", EO_ERR_RANGE, "friction");
    expect_error("{\"collisions\": [{\"plane\": {}, \"friction\": 0.5}], \"time\": {\"integrator\": \"verlet\"}}",
                 EO_ERR_INVALID, "implicit integrators only");
}

int main(void)
{
    test_errors();
    test_fd_obstacles();
    test_slope();
    test_curved_slide_order();
    test_on_sphere();
    return eo_test_finish("test_contact");
}
