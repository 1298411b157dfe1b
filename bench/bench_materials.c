/* Material kernel throughput, single thread.
 *
 * Cases (table below, pick by name on the command line, default all):
 *   energy            eo_tet_evaluate(EO_EVAL_ENERGY) per registered tet model, tets/s
 *   energy_grad       eo_tet_evaluate(EO_EVAL_GRAD) per registered tet model, tets/s
 *                     (both take the model's F_psi_grad fast path when it has one)
 *   energy_grad_hess  eo_tet_evaluate(EO_EVAL_HESS, EO_PROJ_CLAMP) per model, tets/s
 *   svd               eo_svd3 vs eo_svd3_lapack, SVDs/s and their ratio (same run)
 *   polar             eo_polar3 (the corotated kinds' fast path), polar decompositions/s
 *   term              through the objective of a generated 98,415-tet box (backward Euler,
 *                     27³ cells × 5 tets, vertices jittered by ±10% of a cell), one thread
 *                     (eo_step_set_parallel(st, 0)): value, gradient and clamp-projected
 *                     Hessian (assembled into the CSC) per model, tets/s = tets / call time
 *                     (best of 3 calls; includes the inertia and gravity terms)
 * Inputs: 4096 random rest tets, each deformed by a random F with σ in [0.7, 1.4] plus
 * noise (fixed seed). Times are CPU seconds of the calling thread (eo_cputime; the loops
 * are serial). Each measurement is the best of 5 rounds of --min-time/5 seconds
 * (default --min-time 0.5). Prints machine and build (eo_machine_describe). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/config.h"
#include "elastopt/ctx.h"
#include "cli/blas_fix.h"
#include "elastopt/machine.h"
#include "elastopt/material.h"
#include "elastopt/objective.h"
#include "elastopt/registry.h"
#include "elastopt/scene.h"
#include "elastopt/step.h"

#define NT 4096
static double Dminv[NT][9], vol[NT], xs[NT][12], Fs[NT][9];
static double min_time = 0.5;
static volatile double sink;

static unsigned long long rng = 0x2545F4914F6CDD1DULL;
static double urand(double a, double b)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return a + (b - a) * (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

static void rand_rot(double R[9])
{
    double q[4], n;
    do {
        for (int i = 0; i < 4; i++) q[i] = urand(-1, 1);
        n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    } while (n < 0.1 || n > 1);
    double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    double M[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
    memcpy(R, M, sizeof M);
}

static void setup(void)
{
    for (int t = 0; t < NT; t++) {
        double X[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
        for (int i = 0; i < 12; i++) X[i] += urand(-0.2, 0.2);
        if (eo_tet_rest(X, Dminv[t], &vol[t]) != EO_OK) {
            t--;
            continue;
        }
        double R1[9], R2[9], s[3] = {urand(0.7, 1.4), urand(0.7, 1.4), urand(0.7, 1.4)}, F[9];
        rand_rot(R1), rand_rot(R2);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                F[3 * i + j] = R1[3 * i] * s[0] * R2[3 * j] + R1[3 * i + 1] * s[1] * R2[3 * j + 1] +
                               R1[3 * i + 2] * s[2] * R2[3 * j + 2];
        memcpy(Fs[t], F, sizeof F);
        for (int v = 0; v < 4; v++)
            for (int a = 0; a < 3; a++)
                xs[t][3 * v + a] = F[3 * a] * X[3 * v] + F[3 * a + 1] * X[3 * v + 1] + F[3 * a + 2] * X[3 * v + 2] +
                                   urand(-0.01, 0.01);
    }
}

/* Items per second: best of 5 rounds, each repeating passes for min_time/5 CPU seconds of
 * this thread (eo_cputime: the kernels run serially, so thread CPU time is their whole
 * cost and does not grow when other processes share the cores). */
static double rate(double (*pass)(const void *), const void *arg)
{
    pass(arg); /* warm-up */
    double best = 0;
    for (int round = 0; round < 5; round++) {
        long n = 0;
        double t0 = eo_cputime(), t;
        do {
            sink += pass(arg);
            n += NT;
            t = eo_cputime() - t0;
        } while (t < min_time / 5);
        if (n / t > best) best = n / t;
    }
    return best;
}

typedef struct tet_arg {
    const eo_material_type *mt;
    const eo_material_coef *c;
    eo_eval_what what;
} tet_arg;

static double pass_tet(const void *p)
{
    const tet_arg *a = p;
    eo_tet_out out;
    double s = 0;
    for (int t = 0; t < NT; t++) {
        eo_tet_evaluate(a->mt, a->c, Dminv[t], vol[t], xs[t], a->what, EO_PROJ_CLAMP, &out);
        s += out.energy + out.grad[0] + (a->what == EO_EVAL_HESS ? out.hess[13] : 0);
    }
    return s;
}

static double pass_svd_fast(const void *p)
{
    (void)p;
    double U[9], s[3], V[9], acc = 0;
    for (int t = 0; t < NT; t++) {
        eo_svd3(Fs[t], U, s, V);
        acc += s[2] + U[0] + V[8];
    }
    return acc;
}
static double pass_svd_lapack(const void *p)
{
    (void)p;
    double U[9], s[3], V[9], acc = 0;
    for (int t = 0; t < NT; t++) {
        eo_svd3_lapack(Fs[t], U, s, V);
        acc += s[2] + U[0] + V[8];
    }
    return acc;
}

static void run_tets(eo_eval_what what)
{
    eo_material_coef c = eo_material_coef_from(1e5, 0.45, 1000, 1000);
    for (const void *const *t = eo_registry_list(EO_KIND_MATERIAL); t && *t; t++) {
        const eo_material_type *mt = *t;
        if (mt->flags & EO_MATERIAL_EDGE) continue;
        tet_arg a = {mt, &c, what};
        double r = rate(pass_tet, &a);
        printf("  %-20s %12.0f tets/s  (%6.1f ns/tet)\n", mt->info.name, r, 1e9 / r);
    }
}
static void case_energy(void) { run_tets(EO_EVAL_ENERGY); }
static void case_energy_grad(void) { run_tets(EO_EVAL_GRAD); }
static void case_energy_grad_hess(void) { run_tets(EO_EVAL_HESS); }
static void case_svd(void)
{
    double f = rate(pass_svd_fast, NULL), l = rate(pass_svd_lapack, NULL);
    printf("  %-20s %12.0f SVD/s  (%6.1f ns)\n", "eo_svd3 (Jacobi)", f, 1e9 / f);
    printf("  %-20s %12.0f SVD/s  (%6.1f ns)\n", "eo_svd3_lapack", l, 1e9 / l);
    printf("  ratio fast / LAPACKE: %.2fx\n", f / l);
}

static double pass_polar(const void *p)
{
    (void)p;
    double R[9], acc = 0;
    for (int t = 0; t < NT; t++) {
        eo_polar3(Fs[t], R);
        acc += R[0] + R[8];
    }
    return acc;
}
static void case_polar(void)
{
    double r = rate(pass_polar, NULL);
    long it = 0;
    double R[9];
    for (int t = 0; t < NT; t++) it += eo_polar3(Fs[t], R);
    printf("  %-20s %12.0f polar/s  (%6.1f ns, %.2f iterations on average)\n", "eo_polar3", r, 1e9 / r, (double)it / NT);
}

static void case_term(void)
{
    static const char *const models[] = {"linear", "stvk", "corotated", "fixed_corotated", "neo_hookean",
                                         "stable_neo_hookean", NULL};
    for (const char *const *m = models; *m; m++) {
        char json[1024];
        snprintf(json, sizeof json,
                 "{\"mesh\": {\"generate\": {\"size\": [1, 1, 1], \"cells\": [27, 27, 27], \"split\": 5}},"
                 " \"material\": {\"model\": \"%s\", \"E\": 1e5, \"nu\": 0.45, \"density\": 1000},"
                 " \"time\": {\"integrator\": \"backward_euler\", \"dt\": 0.01, \"steps\": 1}}",
                 *m);
        eo_ctx *ctx = NULL;
        eo_cfg *cfg = NULL;
        eo_scene *sc = NULL;
        eo_step *st = NULL;
        eo_objective *obj = NULL;
        double *x = NULL, *g = NULL;
        int rc = eo_ctx_create(NULL, &ctx);
        if (rc >= 0) rc = eo_cfg_load(ctx, NULL, json, &cfg);
        if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
        if (rc >= 0) rc = eo_step_create(ctx, sc, &st);
        if (rc >= 0) rc = eo_step_set_parallel(st, 0);
        if (rc >= 0) rc = eo_step_begin(st, &obj);
        if (rc < 0) {
            printf("  %-20s setup failed: %s\n", *m, ctx ? eo_ctx_message(ctx) : "no context");
        } else {
            int n = obj->n, nt = eo_step_mesh(st)->nt;
            x = malloc((size_t)n * sizeof *x), g = malloc((size_t)n * sizeof *g);
            memcpy(x, eo_step_guess(st), (size_t)n * sizeof *x);
            for (int i = 0; i < n; i++) x[i] += urand(-0.1, 0.1) / 27;
            double best[3] = {INFINITY, INFINITY, INFINITY}, f = 0;
            for (int rep = 0; rep < 3; rep++) {
                double t0 = eo_cputime(); /* serial element loops: thread CPU time */
                eo_objective_value(obj, x, &f);
                double t1 = eo_cputime();
                eo_objective_gradient(obj, x, &f, g);
                double t2 = eo_cputime();
                eo_csc *H = NULL;
                eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);
                double t3 = eo_cputime();
                best[0] = fmin(best[0], t1 - t0), best[1] = fmin(best[1], t2 - t1), best[2] = fmin(best[2], t3 - t2);
                sink += f + g[0];
            }
            printf("  %-20s %d tets: value %10.0f tets/s (%6.1f ns)  gradient %10.0f tets/s (%6.1f ns)  "
                   "clamp Hessian %9.0f tets/s (%6.1f ns)\n",
                   *m, nt, nt / best[0], 1e9 * best[0] / nt, nt / best[1], 1e9 * best[1] / nt, nt / best[2],
                   1e9 * best[2] / nt);
        }
        free(x), free(g);
        eo_step_destroy(&st);
        if (ctx) eo_scene_destroy(&sc), eo_cfg_destroy(&cfg);
        eo_ctx_destroy(&ctx);
    }
}

typedef struct bench_case {
    const char *name;
    const char *title;
    void (*run)(void);
} bench_case;

static const bench_case cases[] = {
    {"energy", "(0) energy per tet", case_energy},
    {"energy_grad", "(a) energy + gradient per tet", case_energy_grad},
    {"energy_grad_hess", "(b) energy + gradient + clamp-projected 12x12 Hessian per tet", case_energy_grad_hess},
    {"svd", "3x3 SVD: one-sided Jacobi vs LAPACKE_dgesvd", case_svd},
    {"polar", "3x3 polar rotation (corotated fast path)", case_polar},
    {"term", "through the objective (elastic + inertia + gravity) of a generated box, one thread", case_term},
    {NULL, NULL, NULL},
};

int main(int argc, char **argv)
{
    eo_cli_blas_fix(argv, 0); /* OpenBLAS on a generic core: run again with OPENBLAS_CORETYPE */
    const char *pick[8];
    int npick = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--min-time") == 0 && i + 1 < argc) min_time = atof(argv[++i]);
        else if (npick < 8) pick[npick++] = argv[i];
    }
    char machine[512];
    eo_machine_describe(machine, sizeof machine);
    printf("bench_materials: %s; single thread; %d tets; E = 1e5, nu = 0.45\n", machine, NT);
    char blas_line[640];
    eo_blas_describe(blas_line, sizeof blas_line);
    printf("bench_materials: %s\n", blas_line);
    setup();
    int ran = 0;
    for (const bench_case *b = cases; b->name; b++) {
        int want = npick == 0;
        for (int i = 0; i < npick; i++) want |= strcmp(pick[i], b->name) == 0;
        if (!want) continue;
        printf("%s:\n", b->title);
        b->run();
        ran++;
    }
    if (!ran) {
        fprintf(stderr, "bench_materials: unknown case; valid:");
        for (const bench_case *b = cases; b->name; b++) fprintf(stderr, " %s", b->name);
        fprintf(stderr, "\n");
        return 2;
    }
    return sink == 12345.678 ? 1 : 0;
}
