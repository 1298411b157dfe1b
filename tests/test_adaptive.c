/* Adaptive time stepping (time.adaptive, eo_sim_step; suite 'engine'), on the built-in
 * cantilever (400 tets) with every implicit integrator (newmark, backward_euler, bdf2,
 * implicit_midpoint, static with time.load_steps):
 *
 *  (a) rescue: dt = 0.03 and solver.max_iters = 4 with a weak fallback entry (clamp,
 *      4 iterations): without adaptive stepping some step ends not converged; with it
 *      every step converges, attempts are rejected (rejected > 0, substeps > 1,
 *      min_substep < dt) and every step still ends at the time of the run without
 *      substeps, bit for bit;
 *  (b) adaptive on but every step converging (the scene's solver): positions,
 *      velocities, g, iterations and time identical, bit for bit, to adaptive off;
 *      rejected 0, substeps 1, min_substep dt;
 *  (c) a step rejected once and completed in two halves equals two steps of a run with
 *      nominal dt/2 from the same state (positions to 1e-12 relative): substeps are real
 *      integrator steps (bdf2: both take the backward Euler start first; static: the
 *      load fraction of a half step is that of dt/2 with twice the load steps);
 *  (d) restart inside an adaptive run at a boundary where the controller is at a
 *      reduced size: state, eo_sim_set_adaptive_state and history into a new sim
 *      reproduce the uninterrupted run bit for bit (rejections per step too); without
 *      the controller's state the continuation differs;
 *  (e) errors: time.adaptive with an explicit integrator is a config error naming the
 *      key; eo_step_set_substep rejects a level out of range and a progress that is not
 *      a multiple of 2^-level. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

#define MAXS 16

static const char *const integrators[] = {"newmark", "backward_euler", "bdf2", "implicit_midpoint", "static"};
enum { NI = 5 };

/* The cantilever with integrator integ, dt, and extra overrides (NULL-terminated, may be NULL). */
static eo_sim *open_sim(eo_ctx *ctx, const char *integ, double dt, const char *const *extra)
{
    char a[64], b[64];
    snprintf(a, sizeof a, "time.integrator=%s", integ);
    snprintf(b, sizeof b, "time.dt=%.17g", dt);
    const char *ov[16] = {a, b, "output.vtu=false"};
    int n = 3;
    /* static: the load ramps over the first 2 steps (a substep applies its share) */
    if (strcmp(integ, "static") == 0) ov[n++] = dt < 0.02 ? "time.load_steps=4" : "time.load_steps=2";
    for (const char *const *e = extra; e && *e && n < 15; e++) ov[n++] = *e;
    ov[n] = NULL;
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, "cantilever", NULL, ov) < 0) {
        CHECK(0, "open cantilever %s dt %g", integ, dt);
        eo_sim_destroy(&s);
    }
    return s;
}

/* The hard case: few iterations and a weak fallback entry, restarted from the step's
 * starting guess (solver.fallback_start = guess: continuing from the first entry's end
 * point, 4 + 4 iterations finish the step); the static integrator needs more (its step is
 * the whole load increment, no inertia term): its full first step takes 13 iterations,
 * its halves fewer. adaptive: 0 off, 1 on, 2 on with at most one halving. */
static const char *const *hard(const char *integ, int adaptive)
{
    static const char *ov[8];
    int n = 0;
    ov[n++] = "solver.fallback_start=guess";
    ov[n++] = strcmp(integ, "static") == 0 ? "solver.max_iters=12" : "solver.max_iters=4";
    ov[n++] = strcmp(integ, "static") == 0 ? "solver.fallback=[{\"hessian_fix\": \"clamp\", \"max_iters\": 12}]"
                                            : "solver.fallback=[{\"hessian_fix\": \"clamp\", \"max_iters\": 4}]";
    if (adaptive) ov[n++] = "time.adaptive=true";
    if (adaptive == 2) ov[n++] = "time.adaptive_min_fraction=0.5";
    ov[n] = NULL;
    return ov;
}

/* steps of the hard case where adaptive stepping rescues every step */
static int hard_steps(const char *integ) { return strcmp(integ, "static") == 0 ? 1 : 3; }

static int verbose(void) { return getenv("EO_TEST_VERBOSE") != NULL; }

/* ---------------------------------------------------------------- (a) */

static void test_rescue(eo_ctx *ctx)
{
    for (int i = 0; i < NI; i++) {
        const char *integ = integrators[i];
        const int N = hard_steps(integ);
        eo_sim *off = open_sim(ctx, integ, 0.03, hard(integ, 0)), *on = open_sim(ctx, integ, 0.03, hard(integ, 1));
        if (!off || !on) {
            eo_sim_destroy(&off);
            eo_sim_destroy(&on);
            continue;
        }
        int off_failed = 0, on_failed = 0, rejected = 0, more = 0, ok = 1;
        double hmin = INFINITY;
        for (int k = 0; k < N; k++) {
            eo_sim_step_result a, b;
            ok &= eo_sim_step(off, &a) == EO_OK && eo_sim_step(on, &b) == EO_OK;
            off_failed += !eo_reason_is_converged(a.reason);
            on_failed += !eo_reason_is_converged(b.reason);
            rejected += b.rejected;
            more += b.substeps > 1;
            hmin = fmin(hmin, b.min_substep);
            CHECK(a.rejected == 0 && a.substeps == 1 && a.min_substep == 0.03, "%s off: %d rejected, %d substeps",
                  integ, a.rejected, a.substeps);
            CHECK(b.t == a.t && eo_sim_index(on) == k + 1, "%s step %d: t %.17g with substeps, %.17g without", integ,
                  k + 1, b.t, a.t);
            if (verbose())
                fprintf(stderr, "  %s step %d: off %s (%d it.), on %s (%d it., %d rejected, %d substeps, min %g)\n",
                        integ, k + 1, eo_reason_name(a.reason), a.iterations, eo_reason_name(b.reason), b.iterations,
                        b.rejected, b.substeps, b.min_substep);
        }
        CHECK(ok, "%s: steps ran", integ);
        CHECK(off_failed >= 1, "%s: without adaptive stepping %d of %d steps failed (the case needs >= 1)", integ,
              off_failed, N);
        CHECK(on_failed == 0, "%s: with adaptive stepping %d of %d steps failed", integ, on_failed, N);
        CHECK(rejected >= 1 && more >= 1 && hmin < 0.03, "%s: %d rejected, %d steps in substeps, smallest %g", integ,
              rejected, more, hmin);
        eo_sim_destroy(&off);
        eo_sim_destroy(&on);
    }
}

/* ---------------------------------------------------------------- (b) */

static void test_identical(eo_ctx *ctx)
{
    const int N = 8;
    static const char *const on_ov[] = {"time.adaptive=true", NULL};
    for (int i = 0; i < NI; i++) {
        const char *integ = integrators[i];
        eo_sim *off = open_sim(ctx, integ, 0.01, NULL), *on = open_sim(ctx, integ, 0.01, on_ov);
        if (!off || !on) {
            eo_sim_destroy(&off);
            eo_sim_destroy(&on);
            continue;
        }
        const size_t nf = 3 * (size_t)eo_sim_scene(off)->mesh->nv * sizeof(double);
        int same = 1, conv = 1, plain = 1;
        for (int k = 0; k < N; k++) {
            eo_sim_step_result a, b;
            if (eo_sim_step(off, &a) < 0 || eo_sim_step(on, &b) < 0) {
                same = 0;
                break;
            }
            conv &= eo_reason_is_converged(a.reason) && eo_reason_is_converged(b.reason);
            plain &= b.rejected == 0 && b.substeps == 1 && b.min_substep == 0.01;
            same &= memcmp(eo_step_x(eo_sim_step_problem(off)), eo_step_x(eo_sim_step_problem(on)), nf) == 0 &&
                    memcmp(eo_step_v(eo_sim_step_problem(off)), eo_step_v(eo_sim_step_problem(on)), nf) == 0 &&
                    a.t == b.t && a.g == b.g && a.grad_norm == b.grad_norm && a.iterations == b.iterations &&
                    a.reason == b.reason && a.n_value == b.n_value && a.n_hessian == b.n_hessian;
        }
        CHECK(conv, "%s: every step converged (the case needs it)", integ);
        CHECK(plain, "%s: adaptive on, nothing rejected", integ);
        CHECK(same, "%s: adaptive on == off, bit for bit", integ);
        eo_sim_destroy(&off);
        eo_sim_destroy(&on);
    }
}

/* ---------------------------------------------------------------- (c) */

static double rel_diff(int n, const double *a, const double *b)
{
    double d = 0, s = 0;
    for (int i = 0; i < n; i++) {
        d = fmax(d, fabs(a[i] - b[i]));
        s = fmax(s, fabs(b[i]));
    }
    return d / (s > 0 ? s : 1);
}

static void test_half_steps(eo_ctx *ctx)
{
    const double dt = 0.03;
    for (int i = 0; i < NI; i++) {
        const char *integ = integrators[i];
        eo_sim *a = open_sim(ctx, integ, dt, hard(integ, 2));
        if (!a) continue;
        const int nv = eo_sim_scene(a)->mesh->nv;
        double *x = malloc(3 * (size_t)nv * sizeof(double)), *v = malloc(3 * (size_t)nv * sizeof(double));
        double *xa = malloc(3 * (size_t)nv * sizeof(double));
        double t = 0;
        int index = 0, found = 0;
        /* the first step that starts at full size, is rejected and completes in two halves
         * (the smallest size is dt/2: accepted there, converged or not) */
        for (int k = 0; k < MAXS && !found; k++) {
            int level, streak;
            eo_sim_get_adaptive_state(a, &level, &streak);
            eo_sim_get_state(a, x, v, &t, &index);
            eo_sim_step_result r;
            if (eo_sim_step(a, &r) < 0) break;
            found = level == 0 && r.rejected == 1 && r.substeps == 2 && r.min_substep == dt / 2;
        }
        CHECK(found, "%s: a step completed in two halves within %d steps", integ, MAXS);
        if (found) {
            eo_sim_get_state(a, xa, NULL, NULL, NULL);
            /* dt/2 nominal, from the same state (bdf2: set_state clears the history, the
             * level change in a did too) */
            eo_sim *b = open_sim(ctx, integ, dt / 2, hard(integ, 0));
            int ok = b && eo_sim_set_state(b, x, v, t, 2 * index) == EO_OK;
            for (int j = 0; ok && j < 2; j++) {
                eo_sim_step_result r;
                ok = eo_sim_step(b, &r) == EO_OK && r.rejected == 0;
            }
            CHECK(ok, "%s: two steps of dt/2", integ);
            if (ok) {
                double d = rel_diff(3 * nv, xa, eo_step_x(eo_sim_step_problem(b)));
                double tb = eo_sim_time(b), ta = eo_sim_time(a);
                if (verbose()) fprintf(stderr, "  %s: halves vs dt/2: %.3g relative, t %.17g %.17g\n", integ, d, ta, tb);
                CHECK(d <= 1e-12, "%s: two halves vs two steps of dt/2: positions differ by %.3g relative", integ, d);
                CHECK(fabs(ta - tb) <= 1e-15, "%s: t %.17g vs %.17g", integ, ta, tb);
            }
            eo_sim_destroy(&b);
        }
        free(x);
        free(v);
        free(xa);
        eo_sim_destroy(&a);
    }
}

/* ---------------------------------------------------------------- (d) */

static void test_restart(eo_ctx *ctx)
{
    for (int i = 0; i < NI; i++) {
        const char *integ = integrators[i];
        const int N = hard_steps(integ) + 2;
        eo_sim *a = open_sim(ctx, integ, 0.03, hard(integ, 1));
        if (!a) continue;
        const int nv = eo_sim_scene(a)->mesh->nv;
        const size_t nf = 3 * (size_t)nv, hlen = eo_sim_history_len(a);
        double *x = malloc(nf * sizeof(double)), *v = malloc(nf * sizeof(double));
        double *h = malloc((hlen ? hlen : 1) * sizeof(double)), t = 0;
        int index = 0, split = -1, level = 0, streak = 0, rej[MAXS] = {0}, ok = 1;
        for (int k = 0; k < N && ok; k++) {
            eo_sim_step_result r;
            ok = eo_sim_step(a, &r) == EO_OK;
            rej[k] = r.rejected;
            int lv, sk;
            eo_sim_get_adaptive_state(a, &lv, &sk);
            if (split < 0 && lv > 0 && k + 1 < N) { /* a boundary at a reduced size: save everything */
                split = k + 1;
                level = lv;
                streak = sk;
                eo_sim_get_state(a, x, v, &t, &index);
                if (hlen) ok &= eo_sim_get_history(a, h) == EO_OK;
            }
        }
        CHECK(ok && split > 0, "%s: a step boundary at a reduced substep size within %d steps (split %d)", integ, N,
              split);
        if (ok && split > 0) {
            for (int with = 1; with >= 0; with--) {
                eo_sim *b = open_sim(ctx, integ, 0.03, hard(integ, 1));
                int good = b && eo_sim_set_state(b, x, v, t, index) == EO_OK;
                if (good && with) good = eo_sim_set_adaptive_state(b, level, streak) == EO_OK;
                if (good && hlen) good = eo_sim_set_history(b, h) == EO_OK;
                int same_rej = 1;
                for (int k = split; good && k < N; k++) {
                    eo_sim_step_result r;
                    good = eo_sim_step(b, &r) == EO_OK;
                    same_rej &= r.rejected == rej[k];
                }
                CHECK(good, "%s: continued run", integ);
                if (good) {
                    int same = memcmp(eo_step_x(eo_sim_step_problem(a)), eo_step_x(eo_sim_step_problem(b)),
                                      nf * sizeof(double)) == 0 &&
                               memcmp(eo_step_v(eo_sim_step_problem(a)), eo_step_v(eo_sim_step_problem(b)),
                                      nf * sizeof(double)) == 0 &&
                               eo_sim_time(a) == eo_sim_time(b) && eo_sim_index(a) == eo_sim_index(b);
                    if (with) CHECK(same && same_rej, "%s: restart at step %d (level %d, streak %d) == uninterrupted",
                                    integ, split, level, streak);
                    /* static: a converged equilibrium does not depend on the substeps that
                     * reached it, so only the dynamic integrators can tell the difference */
                    else if (strcmp(integ, "static") != 0)
                        CHECK(!(same && same_rej), "%s: restart without the controller's state is the same run "
                                                   "(the test cannot tell)", integ);
                }
                eo_sim_destroy(&b);
            }
        }
        free(x);
        free(v);
        free(h);
        eo_sim_destroy(&a);
    }
}

/* ---------------------------------------------------------------- (e) */

static void test_errors(eo_ctx *ctx)
{
    const char *ov[] = {"time.integrator=rk4", "time.adaptive=true", NULL};
    eo_sim *s = NULL;
    int rc = eo_sim_create_from(ctx, NULL, "cantilever", ov, &s);
    CHECK(rc == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "time.adaptive") &&
              strstr(eo_ctx_message(ctx), "explicit"),
          "explicit + adaptive: %d %s", rc, eo_ctx_message(ctx));
    eo_sim_destroy(&s);
    const char *ov2[] = {"time.adaptive_min_fraction=0", NULL};
    rc = eo_sim_create_from(ctx, NULL, "cantilever", ov2, &s);
    CHECK(rc == EO_ERR_RANGE, "min_fraction 0: %d %s", rc, eo_ctx_message(ctx));
    eo_sim_destroy(&s);
    if (eo_sim_create_from(ctx, NULL, "cantilever", NULL, &s) < 0) {
        CHECK(0, "open cantilever");
        return;
    }
    eo_step *st = eo_sim_step_problem(s);
    eo_step_substep ss = {.level = EO_STEP_MAX_SUBSTEP + 1};
    CHECK(eo_step_set_substep(st, &ss) == EO_ERR_RANGE, "level out of range");
    ss = (eo_step_substep){.level = 1, .done = 0.25};
    CHECK(eo_step_set_substep(st, &ss) == EO_ERR_RANGE, "progress 1/4 at level 1");
    ss = (eo_step_substep){.level = 2, .done = 0.75, .t_start = 0};
    CHECK(eo_step_set_substep(st, &ss) == EO_OK, "progress 3/4 at level 2");
    /* the last quarter ends the nominal step exactly: index 1, t = dt */
    eo_sim_step_result r;
    CHECK(eo_sim_step(s, &r) == EO_OK && r.substeps == 1 && eo_sim_index(s) == 1 && r.t == 0.01 &&
              r.min_substep == 0.0025,
          "a quarter step completes the nominal step: index %d, t %.17g, %d substeps, min %g", eo_sim_index(s), r.t,
          r.substeps, r.min_substep);
    eo_step_get_substep(st, &ss);
    CHECK(ss.level == 0 && ss.done == 0, "adaptive off: nominal steps after it (level %d, done %g)", ss.level, ss.done);
    eo_sim_destroy(&s);
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    test_rescue(ctx);
    test_identical(ctx);
    test_half_steps(ctx);
    test_restart(ctx);
    test_errors(ctx);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_adaptive");
}
