/* Hostile conditions inside a run (issue 14, item 6): an allocation that fails in the
 * middle of a step is reported as EO_ERR_NOMEM with a message, never as a solver reason
 * (diverged_*) and never with a leak; for every optimizer that allocates lazily, every
 * allocation of its first two steps is made to fail in turn. Also: a barrier material
 * started from an inverted state is refused when the simulation is created, naming the
 * region and the first inverted tet, while an inversion-safe model runs from the same
 * start. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/ctx.h"
#include "elastopt/sim.h"
#include "elastopt/status.h"
#include "testutil.h"

/* an allocator whose n-th allocation after arming fails */
typedef struct {
    long armed;  /* 0: off; else allocations left before the failing one */
    int fired;
} fail_alloc;

static void *fa_malloc(size_t size, void *user)
{
    fail_alloc *a = user;
    if (a->armed > 0 && --a->armed == 0) {
        a->fired = 1;
        return NULL;
    }
    return malloc(size);
}

static void *fa_realloc(void *p, size_t size, void *user)
{
    fail_alloc *a = user;
    if (a->armed > 0 && --a->armed == 0) {
        a->fired = 1;
        return NULL;
    }
    return realloc(p, size);
}

static void fa_free(void *p, void *user)
{
    (void)user;
    free(p);
}

/* Run two steps with allocation n (after creation) failing; n = 0: no failure. Returns
 * the number of steps run; rcs/reasons per step; *fired_at: the step during which the
 * failure happened (-1 if it did not). */
static int run_two(const char *optimizer, const char *extra, long n, int rcs[2], int reasons[2], int *fired_at,
                   size_t *leaked, char *msg, size_t msgn)
{
    fail_alloc fa = {0, 0};
    eo_allocator al = {fa_malloc, fa_realloc, fa_free, &fa};
    eo_ctx *ctx = NULL;
    *fired_at = -1;
    *leaked = 0;
    msg[0] = 0;
    if (eo_ctx_create(&al, &ctx) < 0) return -1;
    char o1[96];
    snprintf(o1, sizeof o1, "solver.optimizer=%s", optimizer);
    const char *ov[] = {o1, "time.steps=2", "mesh.generate.cells=[6,2,2]", extra, NULL};
    eo_sim *sim = NULL;
    int rc = eo_sim_create_from(ctx, NULL, NULL, ov, &sim);
    if (rc < 0) {
        snprintf(msg, msgn, "create: %s", eo_ctx_message(ctx));
        eo_ctx_destroy(&ctx);
        return -1;
    }
    fa.armed = n;
    int k = 0;
    for (; k < 2; k++) {
        eo_sim_step_result r = {0};
        rc = eo_sim_step(sim, &r);
        rcs[k] = rc;
        reasons[k] = rc >= 0 ? r.reason : 0;
        if (fa.fired && *fired_at < 0) *fired_at = k;
        if (rc < 0) {
            snprintf(msg, msgn, "%s", eo_ctx_message(ctx));
            k++;
            break;
        }
    }
    fa.armed = 0;
    eo_sim_destroy(&sim);
    *leaked = eo_ctx_live_bytes(ctx);
    eo_ctx_destroy(&ctx);
    return k;
}

static void alloc_failure_in_steps(const char *optimizer, const char *extra)
{
    int rc0[2], re0[2], rcs[2], res[2], at;
    size_t leaked;
    char msg[1024];
    int ns = run_two(optimizer, extra, 0, rc0, re0, &at, &leaked, msg, sizeof msg);
    CHECK(ns == 2 && rc0[1] >= 0, "%s: reference run: %d steps %s", optimizer, ns, msg);
    if (ns != 2) return;
    int fired_runs = 0, clean = 0;
    long n = 1;
    for (; n <= 3000 && !clean; n++) {
        ns = run_two(optimizer, extra, n, rcs, res, &at, &leaked, msg, sizeof msg);
        CHECK(leaked == 0, "%s: allocation %ld failing: %zu bytes leaked", optimizer, n, leaked);
        if (at < 0) {
            clean = 1;
            CHECK(ns == 2 && res[0] == re0[0] && res[1] == re0[1], "%s: run past the last allocation", optimizer);
            break;
        }
        fired_runs++;
        /* the step where the allocation failed: an error EO_ERR_NOMEM with a message, or
         * (a graceful fallback) exactly the reference's reason; never another reason */
        int ok = (rcs[at] == EO_ERR_NOMEM && msg[0]) || (rcs[at] >= 0 && res[at] == re0[at]);
        CHECK(ok, "%s: allocation %ld failed in step %d: rc %d (%s), reason %d (reference %d), message '%s'",
              optimizer, n, at + 1, rcs[at], rcs[at] < 0 ? eo_status_name(rcs[at]) : "ok", res[at], re0[at], msg);
        if (!ok) break;
    }
    CHECK(clean && fired_runs > 0, "%s: %d injected failures, clean run reached at %ld: %d", optimizer, fired_runs, n,
          clean);
}

static void barrier_from_inverted(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *ov[] = {"material.model=neo_hookean", "initial.reflect.normal=[1,0,0]", "time.steps=1", NULL};
    eo_sim *sim = NULL;
    int rc = eo_sim_create_from(ctx, NULL, NULL, ov, &sim);
    const char *m = eo_ctx_message(ctx);
    CHECK(rc == EO_ERR_RANGE && sim == NULL, "barrier from an inverted start refused: rc %d", rc);
    CHECK(m && strstr(m, "barrier") && strstr(m, "initial.reflect") && strstr(m, "tet 0") &&
              strstr(m, "neo_hookean"),
          "message names the cause, the first tet and the model: %s", m ? m : "");
    /* the same start with an inversion-safe model runs */
    const char *ov2[] = {"material.model=stable_neo_hookean", "initial.reflect.normal=[1,0,0]", "time.steps=1", NULL};
    rc = eo_sim_create_from(ctx, NULL, NULL, ov2, &sim);
    CHECK(rc == EO_OK, "stable_neo_hookean from the reflected start: %s", eo_ctx_message(ctx));
    if (sim) {
        eo_sim_step_result r;
        rc = eo_sim_step(sim, &r);
        CHECK(rc >= 0 && r.reason > 0, "it steps: rc %d reason %d", rc, r.reason);
    }
    eo_sim_destroy(&sim);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    barrier_from_inverted();
    alloc_failure_in_steps("newton", "solver.hessian_fix=clamp");
    alloc_failure_in_steps("newton", "solver.hessian_fix=project_on_demand");
    alloc_failure_in_steps("lbfgs", "solver.linesearch=wolfe");
    alloc_failure_in_steps("ncg", "solver.linesearch=wolfe");
    alloc_failure_in_steps("gradient_descent", "solver.max_iters=50");
    alloc_failure_in_steps("projective_dynamics", "solver.max_iters=50");
    return eo_test_finish("test_hostile");
}
