/* CPU time to a given accuracy of vertex block descent (Chen et al. 2024), Chebyshev
 * block-Jacobi and PD local/global with Chebyshev (Wang 2015) against Newton, PD
 * local/global and Anderson (bench/claims/vbd_chen2024.json, chebyshev_wang2015.json).
 *
 * Cases: the built-in cantilever (E = 1e7) and twist (E = 1e6), 189 vertices, 400 tets,
 * Newmark h = 0.01, each with stable_neo_hookean and with the PD energy pd_arap; the
 * step after one Newton step from the initial state. The reference x* is Newton
 * (project_on_demand, gradient rule 1e-11); the error of an iterate is the distance to it
 * relative to the step's motion, ‖x_k − x*‖/‖x* − x₀‖ (the tests' measure). Per
 * configuration and repeat (interleaved, `reps`, default 3): one minimization from x₀
 * with its own stopping rule (gradient, tol 1e-8, 20000 iterations; after an untimed
 * warm-up run of Newton and the PD configurations, whose first run factors), the process CPU
 * time (CLOCK_PROCESS_CPUTIME_ID; the program is single-threaded: OMP and BLAS threads
 * 1) at the first iterate within 1e-2 and within 1e-6 of the motion (the time spent in
 * the measuring callback itself is subtracted), and the iterations to get there. Printed:
 * median [min, max] over the repeats, '-' where not reached.
 *
 *   bench_vbd [--reps N] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/blas_fix.h"
#include "elastopt/sim.h"
#include "elastopt/impl/method.h"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct probe {
    const double *xs, *x0;
    int n;
    double motion, t0, overhead;
    double t[2];
    int it[2];
} probe;

static const double levels[2] = {1e-2, 1e-6};

static int on_iter(const eo_iter_info *info, void *user)
{
    probe *p = user;
    const double c0 = cpu_now();
    double e = 0;
    for (int i = 0; i < p->n; i++) e += (info->x[i] - p->xs[i]) * (info->x[i] - p->xs[i]);
    e = sqrt(e) / p->motion;
    for (int l = 0; l < 2; l++)
        if (p->it[l] < 0 && e <= levels[l]) {
            p->t[l] = c0 - p->t0 - p->overhead;
            p->it[l] = info->iteration;
        }
    p->overhead += cpu_now() - c0;
    return 0;
}

static int solve(eo_ctx *ctx, eo_objective *obj, const double *x0, double *x, const char *solver_json, probe *p,
                 eo_solve_result *r)
{
    char json[1024];
    snprintf(json, sizeof json, "{\"solver\": %s}", solver_json);
    eo_cfg *cfg = NULL;
    eo_solver *sv = NULL;
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    int rc = eo_cfg_load(ctx, NULL, json, &cfg);
    if (rc >= 0) rc = eo_solver_opts_load(ctx, cfg, &o);
    if (rc >= 0) rc = eo_solver_create(ctx, &o, cfg, &sv);
    if (rc >= 0) {
        memcpy(x, x0, (size_t)obj->n * sizeof(double));
        if (p) {
            p->t[0] = p->t[1] = NAN;
            p->it[0] = p->it[1] = -1;
            p->overhead = 0;
            p->t0 = cpu_now();
        }
        rc = eo_solver_minimize(sv, obj, x, p ? on_iter : NULL, p, r);
    }
    eo_solver_destroy(&sv);
    eo_cfg_destroy(&cfg);
    if (rc < 0) fprintf(stderr, "%s: %s\n", solver_json, eo_ctx_message(ctx));
    return rc;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

#define MAXREP 15

static const struct {
    const char *name, *json;
} configs[] = {
    {"newton", "{\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\", \"stop\": \"gradient\", \"tol\": 1e-8, "
               "\"max_iters\": 200}"},
    {"vbd", "{\"optimizer\": \"vbd\", \"stop\": \"gradient\", \"tol\": 1e-8, \"max_iters\": 20000}"},
    {"vbd-accelerated", "{\"optimizer\": \"vbd\", \"stop\": \"gradient\", \"tol\": 1e-8, \"max_iters\": 20000, "
                        "\"vbd\": {\"accelerated\": true}}"},
    {"jacobi", "{\"optimizer\": \"jacobi_chebyshev\", \"stop\": \"gradient\", \"tol\": 1e-8, \"max_iters\": 20000, "
               "\"jacobi_chebyshev\": {\"accelerated\": false}}"},
    {"jacobi_chebyshev", "{\"optimizer\": \"jacobi_chebyshev\", \"stop\": \"gradient\", \"tol\": 1e-8, "
                         "\"max_iters\": 20000}"},
    {"pd_local_global", "{\"optimizer\": \"pd_local_global\", \"stop\": \"gradient\", \"tol\": 1e-8, "
                        "\"max_iters\": 20000}"},
    {"pd-anderson", "{\"optimizer\": \"pd_local_global\", \"stop\": \"gradient\", \"tol\": 1e-8, "
                    "\"max_iters\": 20000, \"pd_local_global\": {\"anderson\": true}}"},
    {"pd-chebyshev", "{\"optimizer\": \"pd_local_global\", \"stop\": \"gradient\", \"tol\": 1e-8, "
                     "\"max_iters\": 20000, \"pd_local_global\": {\"chebyshev\": true}}"},
};
#define NCONF ((int)(sizeof configs / sizeof configs[0]))

static void run_case(const char *scene, const char *model, int reps)
{
    eo_ctx *ctx = NULL;
    eo_ctx_create(NULL, &ctx);
    eo_cfg *cfg = NULL;
    char mod[64];
    snprintf(mod, sizeof mod, "material.model=%s", model);
    eo_sim *s = NULL;
    int rc = eo_scene_cfg_load(ctx, NULL, scene, &cfg);
    if (rc >= 0) rc = eo_cfg_override(ctx, cfg, mod);
    if (rc >= 0) rc = eo_cfg_override(ctx, cfg, "solver.fallback=[]");
    if (rc >= 0) {
        rc = eo_sim_create(ctx, cfg, &s);
        cfg = NULL;
    }
    eo_sim_step_result sr;
    if (rc >= 0) rc = eo_sim_step(s, &sr); /* one step with the scene's Newton */
    eo_objective *obj = NULL;
    double *guess = NULL;
    if (rc >= 0) rc = eo_sim_prepare(s, &obj, &guess);
    if (rc < 0) {
        fprintf(stderr, "%s %s: %s\n", scene, model, eo_ctx_message(ctx));
        eo_cfg_destroy(&cfg);
        eo_sim_destroy(&s);
        eo_ctx_destroy(&ctx);
        return;
    }
    const int n = obj->n;
    double *x0 = malloc((size_t)n * sizeof(double)), *xs = malloc((size_t)n * sizeof(double));
    double *x = malloc((size_t)n * sizeof(double));
    memcpy(x0, guess, (size_t)n * sizeof(double));
    eo_solve_result r;
    solve(ctx, obj, x0, xs,
          "{\"optimizer\": \"newton\", \"hessian_fix\": \"project_on_demand\", \"stop\": \"gradient\", "
          "\"tol\": 1e-11, \"max_iters\": 200}",
          NULL, &r);
    const double gref = r.g;
    double m2 = 0;
    for (int i = 0; i < n; i++) m2 += (xs[i] - x0[i]) * (xs[i] - x0[i]);
    probe p = {.xs = xs, .x0 = x0, .n = n, .motion = sqrt(m2)};
    double t[NCONF][2][MAXREP];
    int it[NCONF][2], total[NCONF];
    const char *reason[NCONF];
    for (int c = 0; c < NCONF; c++) /* warm-up of the factoring ones (the objective's PD factor) */
        if (strstr(configs[c].json, "pd_local_global") || strstr(configs[c].json, "newton"))
            solve(ctx, obj, x0, x, configs[c].json, &p, &r);
    for (int k = 0; k < reps; k++)
        for (int c = 0; c < NCONF; c++) {
            solve(ctx, obj, x0, x, configs[c].json, &p, &r);
            for (int l = 0; l < 2; l++) {
                t[c][l][k] = p.t[l];
                it[c][l] = p.it[l];
            }
            total[c] = r.iterations;
            reason[c] = eo_reason_name(r.reason);
        }
    printf("\n%s, %s: n = %d, step motion %.3e m, reference g* = %.10g\n", scene, model, n, p.motion, gref);
    printf("%-18s %-30s %-30s %7s %s\n", "config", "CPU ms to 1e-2 [min, max] (it)", "CPU ms to 1e-6 [min, max] (it)",
           "its", "reason");
    for (int c = 0; c < NCONF; c++) {
        char col[2][64];
        for (int l = 0; l < 2; l++) {
            if (it[c][l] < 0) {
                snprintf(col[l], sizeof col[l], "-");
                continue;
            }
            double v[MAXREP];
            memcpy(v, t[c][l], (size_t)reps * sizeof(double));
            qsort(v, (size_t)reps, sizeof(double), cmp_double);
            snprintf(col[l], sizeof col[l], "%.3g [%.3g, %.3g] (%d)", 1e3 * v[reps / 2], 1e3 * v[0],
                     1e3 * v[reps - 1], it[c][l]);
        }
        printf("%-18s %-30s %-30s %7d %s\n", configs[c].name, col[0], col[1], total[c], reason[c]);
    }
    fflush(stdout);
    free(x0), free(xs), free(x);
    eo_sim_destroy(&s);
    eo_ctx_destroy(&ctx);
}

int main(int argc, char **argv)
{
    eo_cli_blas_fix(argv, 0); /* OpenBLAS on a generic core: run again with OPENBLAS_CORETYPE */
    int reps = 3;
    for (int i = 1; i < argc; i++)
        if (strcmp(argv[i], "--reps") == 0 && i + 1 < argc) reps = atoi(argv[++i]);
    if (reps < 1 || reps > MAXREP) {
        fprintf(stderr, "bench_vbd: --reps in [1, %d]\n", MAXREP);
        return 2;
    }
    printf("bench_vbd: CPU time (process) to 1e-2 and 1e-6 of the step's motion, median [min, max] of %d repeats\n",
           reps);
    const char *scenes[] = {"cantilever", "twist"}, *models[] = {"stable_neo_hookean", "pd_arap"};
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) run_case(scenes[a], models[b], reps);
    return 0;
}
