/* Linear-solver benchmark: every registered solver on an elasticity-like SPD matrix.
 *
 * Matrix of an nx×nx×nx node grid with 3 dofs per node: every grid edge (i,j) is an
 * element of 6 variables with Ke = [K −K; −K K], K = I₃ + 0.5 (random SPD 3×3, fixed
 * seed) — the 7-point Laplacian ⊗ I₃ with a random 3×3 coupling — plus `shift` on the
 * diagonal (the mass term M/h² of an implicit step). Assembled with eo_assembler.
 *
 * For each solver: analyze, factor and solve time (median of `reps` factor+solve),
 * iterations, relative residual, status, and the ratio of factor+solve to CHOLMOD's
 * factor+solve measured in the same run.
 *
 *   bench_linsolve [case ...]     cases: grid10 (3 000 dofs), grid20 (24 000 dofs);
 *                                 default: all
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/linsolve.h"
#include "elastopt/machine.h"
#include "elastopt/sparse.h"

typedef struct bench_case {
    const char *name;
    int nx;       /* nodes per side */
    double shift; /* diagonal shift */
    int reps;     /* factor+solve repetitions (median reported) */
} bench_case;

static const bench_case cases[] = {
    {"grid10", 10, 0.05, 5},
    {"grid20", 20, 0.05, 3},
};

static unsigned long long rng = 0x2545F4914F6CDD1DULL;
static double urand(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) * (1.0 / 9007199254740992.0) * 2 - 1;
}

static int build_matrix(eo_ctx *ctx, const bench_case *bc, eo_assembler **out, double *t_build)
{
    const int nx = bc->nx, nv = nx * nx * nx;
    int *dofs = malloc((size_t)3 * nv * 6 * sizeof(int)), ne = 0;
    for (int k = 0; k < nx; k++)
        for (int j = 0; j < nx; j++)
            for (int i = 0; i < nx; i++) {
                int v = (k * nx + j) * nx + i, nb[3] = {i + 1 < nx ? v + 1 : -1,
                                                        j + 1 < nx ? v + nx : -1,
                                                        k + 1 < nx ? v + nx * nx : -1};
                for (int d = 0; d < 3; d++) {
                    if (nb[d] < 0) continue;
                    for (int c = 0; c < 3; c++) {
                        dofs[ne * 6 + c] = 3 * v + c;
                        dofs[ne * 6 + 3 + c] = 3 * nb[d] + c;
                    }
                    ne++;
                }
            }
    double t0 = eo_wtime();
    eo_assembler *as = NULL;
    int rc = eo_assembler_create(ctx, 3 * nv, &as);
    int h = rc >= 0 ? eo_assembler_add_elements(ctx, as, ne, 6, dofs) : rc;
    if (h >= 0) rc = eo_assembler_finalize(ctx, as);
    free(dofs);
    if (h < 0 || rc < 0) {
        eo_assembler_destroy(ctx, &as);
        return h < 0 ? h : rc;
    }
    eo_assembler_zero(as);
    for (int e = 0; e < ne; e++) {
        double G[9], K[9], Ke[36];
        for (int t = 0; t < 9; t++) G[t] = urand();
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                double s = 0;
                for (int c = 0; c < 3; c++) s += G[c * 3 + a] * G[c * 3 + b];
                K[a * 3 + b] = (a == b) + 0.5 * s / 3;
            }
        for (int a = 0; a < 6; a++)
            for (int b = 0; b < 6; b++) Ke[a * 6 + b] = ((a < 3) == (b < 3) ? 1 : -1) * K[(a % 3) * 3 + b % 3];
        eo_assembler_add(as, h, e, Ke);
    }
    for (int i = 0; i < 3 * nv; i++) eo_assembler_add_diag(as, i, bc->shift);
    *t_build = eo_wtime() - t0;
    *out = as;
    return EO_OK;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

typedef struct result {
    const char *name;
    int rc;
    double ta, tf, ts;
    int its;
    double res, true_res;
    char note[160];
} result;

static void run_case(const bench_case *bc)
{
    eo_ctx *ctx = NULL;
    eo_ctx_create(NULL, &ctx);
    eo_assembler *as = NULL;
    double tb = 0;
    if (build_matrix(ctx, bc, &as, &tb) < 0) {
        printf("%s: cannot build matrix: %s\n", bc->name, eo_ctx_message(ctx));
        eo_ctx_destroy(&ctx);
        return;
    }
    eo_csc *A = eo_assembler_matrix(as);
    const int n = A->n;
    printf("\ncase %s: %d^3 nodes x 3 dofs: n = %d, nnz(upper) = %d, shift %g, assembly (pattern + values) %.3f s\n",
           bc->name, bc->nx, n, A->nnz, bc->shift, tb);
    double *b = malloc((size_t)n * sizeof(double)), *x = malloc((size_t)n * sizeof(double));
    for (int i = 0; i < n; i++) b[i] = urand();
    result res[32];
    int nr = 0;
    for (const void *const *t = eo_registry_list(EO_KIND_LINSOLVE); *t && nr < 32; t++, nr++) {
        const eo_linsolve_type *type = *t;
        result *r = &res[nr];
        memset(r, 0, sizeof *r);
        r->name = type->info.name;
        eo_linsolve *ls = NULL;
        /* stationary/Krylov: the default tol 1e-10; cap stationary sweeps for time */
        double params[64];
        eo_params_default(type->info.params, params);
        const eo_param_desc *mi = eo_params_find(type->info.params, "max_iters");
        if (mi && !eo_params_find(type->info.params, "preconditioner") && strcmp(r->name, "cg"))
            *(int *)((char *)params + mi->offset) = 2000;
        r->rc = eo_linsolve_create(ctx, type, type->info.params_size ? params : NULL, &ls);
        if (r->rc >= 0) r->rc = eo_linsolve_analyze(ls, A);
        if (r->rc < 0) {
            snprintf(r->note, sizeof r->note, "%s", eo_ctx_message(ctx));
            eo_linsolve_destroy(&ls);
            continue;
        }
        double tf[16], ts[16];
        int reps = bc->reps;
        for (int k = 0; k < reps; k++) {
            double t0 = eo_wtime();
            r->rc = eo_linsolve_factor(ls, A);
            tf[k] = eo_wtime() - t0;
            t0 = eo_wtime();
            if (r->rc == EO_OK) r->rc = eo_linsolve_solve(ls, b, x);
            ts[k] = eo_wtime() - t0;
            if (r->rc != EO_OK && k == 0) {
                snprintf(r->note, sizeof r->note, "%s", eo_ctx_message(ctx));
                reps = 1; /* a failing method is timed once */
            }
        }
        qsort(tf, (size_t)reps, sizeof(double), cmp_d);
        qsort(ts, (size_t)reps, sizeof(double), cmp_d);
        const eo_linsolve_stats *st = eo_linsolve_get_stats(ls);
        r->ta = st->t_analyze;
        r->tf = tf[reps / 2];
        r->ts = ts[reps / 2];
        r->its = st->iterations;
        r->res = st->residual;
        r->true_res = -1;
        if (r->rc == EO_OK || r->rc == EO_WARN_NOT_CONVERGED) { /* ‖b − Ax‖/‖b‖ measured here */
            double *y = malloc((size_t)n * sizeof(double)), rr = 0, bb = 0;
            eo_csc_symv(A, x, y);
            for (int i = 0; i < n; i++) {
                rr += (b[i] - y[i]) * (b[i] - y[i]);
                bb += b[i] * b[i];
            }
            r->true_res = sqrt(rr / bb);
            free(y);
        }
        eo_linsolve_destroy(&ls);
    }
    double ref = 0;
    for (int i = 0; i < nr; i++)
        if (!strcmp(res[i].name, "cholmod") && res[i].rc == EO_OK) ref = res[i].tf + res[i].ts;
    printf("%-14s %10s %10s %10s %9s %7s %10s  %s\n", "solver", "analyze s", "factor s", "solve s",
           "f+s/chol", "iters", "|b-Ax|/|b|", "status");
    for (int i = 0; i < nr; i++) {
        const result *r = &res[i];
        if (r->rc < 0 && r->tf == 0 && r->ts == 0 && r->ta == 0) {
            printf("%-14s %10s %10s %10s %9s %7s %10s  %s: %s\n", r->name, "-", "-", "-", "-", "-", "-",
                   eo_status_name(r->rc), r->note);
            continue;
        }
        char ratio[32] = "-";
        if (ref > 0) snprintf(ratio, sizeof ratio, "%.2f", (r->tf + r->ts) / ref);
        printf("%-14s %10.4f %10.4f %10.4f %9s %7d %10.2e  %s%s%s\n", r->name, r->ta, r->tf, r->ts, ratio,
               r->its, r->true_res, eo_status_name(r->rc), r->note[0] ? ": " : "", r->note);
    }
    free(b);
    free(x);
    eo_assembler_destroy(ctx, &as);
    eo_ctx_destroy(&ctx);
}

int main(int argc, char **argv)
{
    char machine[512];
    eo_machine_describe(machine, sizeof machine);
    printf("bench_linsolve: %s\n", machine);
    const char *thr = getenv("OPENBLAS_NUM_THREADS");
    printf("OPENBLAS_NUM_THREADS=%s; times are medians of the factor+solve repetitions; stationary\n"
           "methods are capped at 2000 iterations (default tol 1e-10)\n", thr ? thr : "(unset)");
    int ran = 0;
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        int pick = argc <= 1;
        for (int a = 1; a < argc; a++) pick |= strcmp(argv[a], cases[c].name) == 0;
        if (pick) {
            run_case(&cases[c]);
            ran++;
        }
    }
    if (!ran) {
        fprintf(stderr, "unknown case; valid:");
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) fprintf(stderr, " %s", cases[c].name);
        fprintf(stderr, "\n");
        return 1;
    }
    return 0;
}
