/* Elements: kernel throughput and the cost of each element at equal accuracy.
 *
 * Cases (pick by name on the command line, default all):
 *   kernel    projected (clamp) element Hessian of stable_neo_hookean, single thread:
 *             p1 through the linear tet's kernel (eo_tet_hessian) and through the generic
 *             one (eo_element_evaluate), p2 and p2p0 (4 points each): elements/s and
 *             quadrature points/s (ratio to p1 in the same run).
 *   assembly  the step objective's clamp-projected Hessian (assembled into the CSC,
 *             inertia and gravity included) of the generated 20×2×2·k bar for each
 *             element: points/s = tets·points / call time.
 *   accuracy  the ν = 0.49 cantilever (1 × 0.1 × 0.1 m, clamped, gravity, stable
 *             neo-Hookean E = 1e9, static): for each element, the generated bars
 *             (20k)×(2k)×(2k) cells, k = 1, …, 6, until the tip is within 1% of the
 *             converged 3D answer (0.9744 of Timoshenko's δ; docs/elements.md): the CPU
 *             time of the whole static solve (Newton, clamp, default stop) on the first
 *             mesh that gets there, median [min, max] of 3 repeats, interleaved across
 *             elements.
 * Times are CPU seconds of the calling thread (eo_cputime); BLAS: one thread. Prints the
 * machine and BLAS core. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/blas_fix.h"
#include "elastopt/element.h"
#include "elastopt/machine.h"
#include "elastopt/registry.h"
#include "elastopt/sim.h"
#include "elastopt/status.h"

#define NE 2048
static volatile double sink;

static unsigned long long rng = 0x9E3779B97F4A7C15ULL;
static double urand(double a, double b)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return a + (b - a) * (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

static int cmp_d(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static const eo_element_type *element(eo_ctx *ctx, const char *name)
{
    const eo_element_type *el = NULL;
    eo_registry_find(ctx, EO_KIND_ELEMENT, name, (const void **)&el);
    return el;
}

static void bench_kernel(eo_ctx *ctx)
{
    static double X[NE][30], x[NE][30], Dm[NE][9], V[NE];
    static const int edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
    for (int e = 0; e < NE; e++) {
        for (;;) {
            static const double ref[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
            for (int i = 0; i < 12; i++) X[e][i] = ref[i] + urand(-0.2, 0.2);
            if (eo_tet_rest(X[e], Dm[e], &V[e]) == EO_OK && V[e] > 0.05) break;
        }
        for (int k = 0; k < 6; k++)
            for (int c = 0; c < 3; c++) X[e][3 * (4 + k) + c] = 0.5 * (X[e][3 * edge[k][0] + c] + X[e][3 * edge[k][1] + c]);
        for (int i = 0; i < 30; i++) x[e][i] = X[e][i] * (1 + urand(-0.1, 0.1));
    }
    const eo_material_type *mt = NULL;
    eo_registry_find(ctx, EO_KIND_MATERIAL, "stable_neo_hookean", (const void **)&mt);
    const eo_material_coef c = eo_material_coef_from(1e5, 0.45, 1000, 1);
    const char *names[4] = {"p1 (eo_tet_hessian)", "p1 (generic)", "p2", "p2p0"};
    const eo_element_type *els[4] = {NULL, element(ctx, "p1"), element(ctx, "p2"), element(ctx, "p2p0")};
    double rate[4][5];
    for (int r = 0; r < 5; r++) /* rounds interleaved across the variants */
        for (int v = 0; v < 4; v++) {
            static double H[900];
            double e, t0 = eo_cputime(), acc = 0;
            int n = 0;
            do {
                for (int k = 0; k < NE; k++) {
                    if (v == 0) {
                        eo_tet_out out;
                        eo_tet_hessian(mt, &c, Dm[k], V[k], x[k], EO_PROJ_CLAMP, &out);
                        acc += out.hess[0];
                    } else {
                        eo_element_evaluate(els[v], mt, &c, Dm[k], V[k], x[k], EO_EVAL_HESS, EO_PROJ_CLAMP, &e, NULL, H, NULL);
                        acc += H[0];
                    }
                }
                n += NE;
            } while (eo_cputime() - t0 < 0.2);
            sink += acc;
            rate[v][r] = n / (eo_cputime() - t0);
        }
    printf("\nkernel: clamp-projected element Hessian, stable_neo_hookean, %d random elements, single thread\n", NE);
    printf("| element | elements/s median [min, max] | points/s | points/s vs p1 |\n|---|---|---|---|\n");
    double p1 = 0;
    for (int v = 0; v < 4; v++) {
        qsort(rate[v], 5, sizeof(double), cmp_d);
        const int nq = v < 2 ? 1 : 4;
        if (v == 0) p1 = rate[v][2];
        printf("| %s | %.3g [%.3g, %.3g] | %.3g | %.2f |\n", names[v], rate[v][2], rate[v][0], rate[v][4],
               nq * rate[v][2], nq * rate[v][2] / p1);
    }
}

static eo_sim *cantilever(eo_ctx *ctx, const char *el, double nu, int k)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"mesh\": {\"generate\": {\"size\": [1, 0.1, 0.1], \"cells\": [%d, %d, %d], \"split\": 5}},"
             " \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e9, \"nu\": %g, \"density\": 1000},"
             " \"gravity\": [0, 0, -9.81], \"element\": \"%s\","
             " \"boundary\": [{\"box\": [[-1, -1, -1], [1e-9, 1, 1]], \"fixed\": true}],"
             " \"time\": {\"integrator\": \"static\", \"dt\": 1, \"steps\": 1},"
             " \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\"}}",
             20 * k, 2 * k, 2 * k, nu, el);
    eo_cfg *cfg = NULL;
    eo_sim *s = NULL;
    if (eo_cfg_load(ctx, NULL, json, &cfg) < 0 || eo_sim_create(ctx, cfg, &s) < 0) {
        fprintf(stderr, "bench_elements: %s\n", eo_ctx_message(ctx));
        return NULL;
    }
    return s;
}

static void bench_assembly(eo_ctx *ctx)
{
    const char *els[4] = {"p1", "p1anp", "p2", "p2p0"};
    const int nq[4] = {1, 1, 4, 4};
    printf("\nassembly: clamp-projected Hessian of the step objective (CSC), bar 80x8x8 cells (25.6k tets), single "
           "thread, best of 5 calls\n| element | nodes | call ms | points/s |\n|---|---|---|---|\n");
    for (int e = 0; e < 4; e++) {
        eo_sim *s = cantilever(ctx, els[e], 0.45, 4);
        if (!s) continue;
        eo_objective *obj = NULL;
        double *x = NULL;
        eo_sim_prepare(s, &obj, &x);
        double best = INFINITY;
        for (int r = 0; r < 5; r++) {
            eo_csc *H = NULL;
            const double t0 = eo_cputime();
            eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);
            best = fmin(best, eo_cputime() - t0);
        }
        const eo_mesh *m = eo_step_mesh(eo_sim_step_problem(s));
        printf("| %s | %d | %.1f | %.3g |\n", els[e], m->nv, 1e3 * best, m->nt * nq[e] / best);
        eo_sim_destroy(&s);
    }
}

static void bench_accuracy(eo_ctx *ctx)
{
    const char *els[4] = {"p1", "p1anp", "p2", "p2p0"};
    const double nu = 0.49, conv = 0.9744;
    const double E = 1e9, q = 1000 * 9.81 * 0.01, I = 0.1 * 0.001 / 12, G = E / (2 * (1 + nu));
    const double kap = 10 * (1 + nu) / (12 + 11 * nu), delta = conv * (q / (8 * E * I) + q / (2 * kap * G * 0.01));
    printf("\naccuracy: nu = 0.49 cantilever, time to 1%% tip error against the converged 3D answer; bars 20k x 2k x 2k "
           "cells (x5 tets), k = 1..6; CPU s of the static solve, median [min, max] of 3 interleaved repeats\n");
    printf("| element | k | tets | nodes | tip error | CPU s |\n|---|---|---|---|---|---|\n");
    int kk[4] = {0, 0, 0, 0}, nodes[4] = {0, 0, 0, 0};
    double err[4][7] = {{0}};
    for (int e = 0; e < 4; e++) /* the first k that gets within 1% */
        for (int k = 1; k <= 6 && !kk[e]; k++) {
            eo_sim *s = cantilever(ctx, els[e], nu, k);
            eo_sim_step_result r;
            if (!s || eo_sim_step(s, &r) < 0) break;
            const eo_step *st = eo_sim_step_problem(s);
            const eo_mesh *m = eo_step_mesh(st);
            const double *x = eo_step_x(st);
            double sum = 0;
            int n = 0;
            for (int v = 0; v < m->nv; v++)
                if (m->X[3 * v] > 1 - 1e-9) sum += x[3 * v + 2] - m->X[3 * v + 2], n++;
            err[e][k] = fabs(-sum / n - delta) / delta;
            if (err[e][k] <= 0.01) kk[e] = k, nodes[e] = m->nv;
            eo_sim_destroy(&s);
        }
    double t[4][3];
    for (int r = 0; r < 3; r++)
        for (int e = 0; e < 4; e++) {
            t[e][r] = NAN;
            if (!kk[e]) continue;
            eo_sim *s = cantilever(ctx, els[e], nu, kk[e]);
            eo_sim_step_result res;
            const double t0 = eo_cputime();
            if (s && eo_sim_step(s, &res) >= 0) t[e][r] = eo_cputime() - t0;
            eo_sim_destroy(&s);
        }
    for (int e = 0; e < 4; e++) {
        if (!kk[e]) {
            printf("| %s | > 6 | | | %.3g (k = 6) | not reached |\n", els[e], err[e][6]);
            continue;
        }
        qsort(t[e], 3, sizeof(double), cmp_d);
        const int k = kk[e];
        printf("| %s | %d | %d | %d | %.3g | %.3g [%.3g, %.3g] |\n", els[e], k, 400 * k * k * k, nodes[e], err[e][k],
               t[e][1], t[e][0], t[e][2]);
    }
}

int main(int argc, char **argv)
{
    eo_cli_blas_fix(argv, 0);
    eo_blas_set_threads(1);
    eo_ctx *ctx = NULL;
    if (eo_ctx_create(NULL, &ctx) < 0) return 2;
    char machine[512], blas[640];
    eo_machine_describe(machine, sizeof machine);
    eo_blas_describe(blas, sizeof blas);
    printf("bench_elements: %s\nbench_elements: %s\n", machine, blas);
    int all = argc < 2;
    for (int i = 1; i < argc || all; i++) {
        const char *c = all ? NULL : argv[i];
        if (all || !strcmp(c, "kernel")) bench_kernel(ctx);
        if (all || !strcmp(c, "assembly")) bench_assembly(ctx);
        if (all || !strcmp(c, "accuracy")) bench_accuracy(ctx);
        if (all) break;
    }
    eo_ctx_destroy(&ctx);
    return 0;
}
