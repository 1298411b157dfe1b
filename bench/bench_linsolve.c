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
 * Newton systems of a generated bar (the built-in `twist` scene, stable neo-Hookean,
 * E = 1e6, Newmark h = 0.01, with mesh.generate.cells set for the size: bar5k = 40×5×5
 * cells × 5 tets = 5 000 tets, bar50k = 100×10×10 → 50 000, bar100k = 128×13×13 →
 * 108 160 tets), assembled by the step engine: the clamp-projected Hessians H_k and
 * gradients at the first `nsys` iterates of Newton on step 0 (x_{k+1} = x_k + α p_k,
 * p_k from CHOLMOD, α halved until g decreases). Two tables per bar:
 *   ordering  CHOLMOD supernodal numeric factorization of H_0 with AMD, METIS, NESDIS
 *             and CHOLMOD's own choice (auto): flops (common->fl), nnz(L) (common->lnz),
 *             analyze time, numeric factorization time (median and min–max over the
 *             repeats; orderings interleaved inside each repeat);
 *   newton    PCG+AMG, PCG+IC(0), PCG+cholmod_reuse, PCG+gmg and CHOLMOD (default
 *             ordering) on the nsys systems, rtol 1e-8: setup (analyze + factor: AMG
 *             hierarchy, IC(0), Galerkin products, CHOLMOD numeric factor) and solve time
 *             per system in PROCESS CPU seconds (wall time before the gmg runs; the
 *             results committed before them are wall), PCG iterations;
 *             pcg+amg-r0 is AMG without the rigid-body modes; methods interleaved inside each repeat; median and spread of the
 *             per-repeat totals. cholmod_reuse factors H_0 and reuses it for H_1, ...
 *
 *   bench_linsolve [case ...]     cases: grid10 (3 000 dofs), grid20 (24 000 dofs),
 *                                 bar5k, bar50k, bar100k, bar300k (180×18×18 → 291 600
 *                                 tets); default: grid10 grid20 bar5k bar50k (bar100k,
 *                                 bar300k on request: minutes)
 *   bench_linsolve --gmg [--reps R] bar100k bar300k
 *                                 only the newton table, for the Galerkin multigrid
 *                                 (solvers/linsys/gmg.c) against BoomerAMG and CHOLMOD:
 *                                 pcg+gmg (linear coarse spaces), pcg+gmg-aff (affine
 *                                 skinning spaces), gmg (standalone V-cycles), pcg+amg
 *                                 (BoomerAMG with its defaults: no rigid-body modes),
 *                                 cholmod; times are PROCESS CPU seconds (the machine is
 *                                 shared), R interleaved repeats (default: the case's)
 *   bench_linsolve --blas-threads [--reps R] bar50k
 *                                 instead of the two tables: the BLAS's threads, 1 vs 2
 *                                 (eo_blas_set_threads), for the CHOLMOD numeric
 *                                 factorization of H_0 (default ordering, CHOLMOD's own
 *                                 OpenMP serial as in the solver); R interleaved repeats
 *                                 (default 5, the order alternating), wall and process CPU
 *                                 seconds, median [min, max], load average before/after
 */
#include <math.h>
#include <stdio.h>
#include <time.h>
#include <stdlib.h>
#include <string.h>

#include "eo_build_config.h"
#include "elastopt/config.h"
#include "elastopt/linsolve.h"
#include "cli/blas_fix.h"
#include "elastopt/machine.h"
#include "elastopt/scene.h"
#include "elastopt/sparse.h"
#include "elastopt/step.h"
#include "solvers/linsys/cholmod_util.h"

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
        eo_assembler_destroy(&as);
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
    eo_assembler_destroy(&as);
    eo_ctx_destroy(&ctx);
}

/* ------------------------------------------------------ Newton systems of a bar ---------- */

typedef struct bar_case {
    const char *name;
    int cx, cy, cz;
    int reps, nsys;
} bar_case;

static const bar_case bars[] = {
    {"bar5k", 40, 5, 5, 5, 3},
    {"bar50k", 100, 10, 10, 3, 3},
    {"bar100k", 128, 13, 13, 3, 2},
    {"bar300k", 180, 18, 18, 3, 2},
};

typedef struct bar_systems {
    int n, nsys, nv;
    eo_csc *H[8];
    double *b[8];
    double *xyz; /* free vertices' rest positions, 3 per node, free order */
    int ntets;
} bar_systems;

static double nrm(int n, const double *v)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += v[i] * v[i];
    return sqrt(s);
}

static int bar_build(eo_ctx *ctx, const bar_case *bc, bar_systems *S)
{
    memset(S, 0, sizeof *S);
    eo_cfg *cfg = NULL;
    eo_scene *sc = NULL;
    eo_step *st = NULL;
    eo_linsolve *ls = NULL;
    double *x = NULL, *g = NULL, *p = NULL, *xt = NULL;
    char ov[128];
    int rc = eo_scene_cfg_load(ctx, NULL, "twist", &cfg);
    snprintf(ov, sizeof ov, "mesh.generate.cells=[%d,%d,%d]", bc->cx, bc->cy, bc->cz);
    if (rc >= 0) rc = eo_cfg_override(ctx, cfg, ov);
    if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
    if (rc >= 0) rc = eo_step_create(ctx, sc, &st);
    eo_objective *obj = NULL;
    if (rc >= 0) rc = eo_step_begin(st, &obj);
    if (rc < 0) goto done;
    const int n = obj->n;
    S->n = n;
    S->ntets = eo_step_mesh(st)->nt;
    x = malloc((size_t)n * sizeof(double));
    g = malloc((size_t)n * sizeof(double));
    p = malloc((size_t)n * sizeof(double));
    xt = malloc((size_t)n * sizeof(double));
    memcpy(x, eo_step_guess(st), (size_t)n * sizeof(double));
    /* rest positions of the free vertices (free dofs come in vertex triples) */
    S->nv = n / 3;
    S->xyz = malloc((size_t)n * sizeof(double));
    const double *x0 = eo_step_x0(st);
    for (int i = 0; i < n; i++) S->xyz[i] = x0[eo_step_free_to_full(st, i)];
    const eo_linsolve_type *lt = NULL;
    eo_linsolve_find(ctx, "cholmod", &lt);
    rc = eo_linsolve_create(ctx, lt, NULL, &ls);
    for (int k = 0; rc >= 0 && k < bc->nsys; k++) {
        double gv;
        eo_csc *H = NULL;
        rc = eo_objective_gradient(obj, x, &gv, g);
        if (rc >= 0) rc = eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);
        if (rc < 0) break;
        if (k == 0) rc = eo_linsolve_analyze(ls, H);
        if (rc >= 0) rc = eo_linsolve_factor(ls, H);
        if (rc >= 0) rc = eo_csc_clone(ctx, H, &S->H[k]);
        if (rc < 0) break;
        S->b[k] = malloc((size_t)n * sizeof(double));
        for (int i = 0; i < n; i++) S->b[k][i] = -g[i];
        S->nsys = k + 1;
        rc = eo_linsolve_solve(ls, S->b[k], p);
        double a = 1, gt = INFINITY;
        for (int t = 0; t < 30; t++, a *= 0.5) {
            for (int i = 0; i < n; i++) xt[i] = x[i] + a * p[i];
            eo_objective_value(obj, xt, &gt);
            if (gt < gv) break;
        }
        printf("  Newton iterate %d: g = %.6e, |grad| = %.3e, step %g\n", k, gv, nrm(n, g), a);
        memcpy(x, xt, (size_t)n * sizeof(double));
    }
done:
    if (rc < 0) printf("cannot build %s: %s\n", bc->name, eo_ctx_message(ctx));
    eo_linsolve_destroy(&ls);
    eo_step_destroy(&st);
    eo_scene_destroy(&sc);
    eo_cfg_destroy(&cfg);
    free(x);
    free(g);
    free(p);
    free(xt);
    return rc < 0 ? rc : EO_OK;
}

static void bar_free(eo_ctx *ctx, bar_systems *S)
{
    (void)ctx;
    for (int k = 0; k < S->nsys; k++) {
        eo_csc_destroy(&S->H[k]);
        free(S->b[k]);
    }
    free(S->xyz);
}

static void med_spread(double *v, int m, double *med, double *lo, double *hi)
{
    qsort(v, (size_t)m, sizeof(double), cmp_d);
    *med = v[m / 2];
    *lo = v[0];
    *hi = v[m - 1];
}

static void bench_orderings(const bar_case *bc, const bar_systems *S)
{
    enum { NORD = 4, MAXR = 16 };
    const char *ords[NORD] = {"amd", "metis", "nesdis", "auto"};
    eo_chm chm[NORD];
    double ta[NORD], tf[NORD][MAXR], fl[NORD], lnz[NORD];
    int ok[NORD];
    eo_ctx *ctx = NULL;
    eo_ctx_create(NULL, &ctx);
    const eo_csc *A = S->H[0];
    for (int o = 0; o < NORD; o++) {
        memset(&chm[o], 0, sizeof chm[o]);
        eo_chm_start(&chm[o]);
        eo_chm_ordering(&chm[o], ords[o]);
        chm[o].c.supernodal = CHOLMOD_SUPERNODAL;
        chm[o].c.final_ll = 1;
        double t0 = eo_wtime();
        ok[o] = eo_chm_analyze(&chm[o], A, "bench", ctx) >= 0;
        ta[o] = eo_wtime() - t0;
    }
    cholmod_sparse M = eo_chm_view(A);
    for (int r = 0; r < bc->reps; r++)
        for (int o = 0; o < NORD; o++) {
            if (!ok[o]) continue;
            double t0 = eo_wtime();
            ok[o] = eo_chm_factorize(&chm[o], &M, 0) && chm[o].c.status == CHOLMOD_OK;
            tf[o][r] = eo_wtime() - t0;
            fl[o] = chm[o].c.fl;
            lnz[o] = chm[o].c.lnz;
        }
    printf("ordering (CHOLMOD supernodal LL' of H_0, n = %d, nnz(upper) = %d, %d interleaved repeats)\n", A->n, A->nnz,
           bc->reps);
    printf("  %-8s %12s %12s %10s %12s %19s %9s\n", "ordering", "flops", "nnz(L)", "analyze s", "factor s (med)",
           "min-max", "vs amd");
    double ref = 0;
    for (int o = 0; o < NORD; o++) {
        if (!ok[o]) {
            printf("  %-8s failed (CHOLMOD status %d)\n", ords[o], chm[o].c.status);
            continue;
        }
        double med, lo, hi;
        med_spread(tf[o], bc->reps, &med, &lo, &hi);
        if (o == 0) ref = med;
        const char *sel = "";
        if (!strcmp(ords[o], "auto"))
            sel = chm[o].c.method[chm[o].c.selected].ordering == CHOLMOD_METIS    ? " (chose metis)"
                  : chm[o].c.method[chm[o].c.selected].ordering == CHOLMOD_AMD    ? " (chose amd)"
                  : chm[o].c.method[chm[o].c.selected].ordering == CHOLMOD_NESDIS ? " (chose nesdis)"
                                                                                  : " (chose other)";
        printf("  %-8s %12.4g %12.4g %10.3f %12.4f   [%.4f, %.4f] %8.2fx%s\n", ords[o], fl[o], lnz[o], ta[o], med, lo,
               hi, ref > 0 ? med / ref : 0, sel);
    }
    for (int o = 0; o < NORD; o++) eo_chm_finish(&chm[o]);
    eo_ctx_destroy(&ctx);
}

typedef struct nt_method {
    const char *label, *solver, *precond;
} nt_method;

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int g_blas_threads_only, g_reps_override, g_gmg_only;

static void bench_newton(const bar_case *bc, const bar_systems *S)
{
    static const nt_method all[] = {
#if EO_HAVE_HYPRE
        {"pcg+amg", "pcg", "amg"},
        {"pcg+amg-r0", "pcg", "amg"}, /* without the rigid-body modes */
#endif
        {"pcg+ic0", "pcg", "ic0"},
        {"pcg+reuse", "pcg", "cholmod_reuse"},
        {"pcg+gmg", "pcg", "gmg"},
        {"cholmod", "cholmod", NULL},
    };
    static const nt_method gmg[] = { /* --gmg */
        {"pcg+gmg", "pcg", "gmg"},
        {"pcg+gmg-aff", "pcg", "gmg"}, /* affine (skinning) coarse spaces */
        {"gmg", "gmg", NULL},
#if EO_HAVE_HYPRE
        {"pcg+amg-r0", "pcg", "amg"},
#endif
        {"cholmod", "cholmod", NULL},
    };
    const nt_method *ms = g_gmg_only ? gmg : all;
    const int NM = g_gmg_only ? (int)(sizeof gmg / sizeof gmg[0]) : (int)(sizeof all / sizeof all[0]);
    enum { MAXM = 8, MAXR = 16 };
    const int reps = g_reps_override > 0 && g_reps_override <= MAXR ? g_reps_override : bc->reps;
    double tset[MAXM][MAXR], tsol[MAXM][MAXR];
    int its[MAXM][8], rcs[MAXM];
    double res[MAXM];
    eo_ctx *ctx = NULL;
    eo_ctx_create(NULL, &ctx);
    const int n = S->n;
    double *x = malloc((size_t)n * sizeof(double));
    memset(rcs, 0, sizeof rcs);
    for (int r = 0; r < reps; r++)
        for (int m = 0; m < NM; m++) {
            const eo_linsolve_type *t = NULL;
            eo_linsolve_find(ctx, ms[m].solver, &t);
            double params[64];
            eo_params_default(t->info.params, params);
            if (!strcmp(ms[m].solver, "gmg"))
                *(double *)((char *)params + eo_params_find(t->info.params, "tol")->offset) = 1e-8;
            if (ms[m].precond && !strcmp(ms[m].precond, "gmg") && strstr(ms[m].label, "-aff"))
                snprintf((char *)params + eo_params_find(t->info.params, "gmg_prolongation")->offset, 16, "affine");
            if (ms[m].precond) {
                const eo_param_desc *d = eo_params_find(t->info.params, "preconditioner");
                snprintf((char *)params + d->offset, d->size, "%s", ms[m].precond);
                *(double *)((char *)params + eo_params_find(t->info.params, "tol")->offset) = 1e-8;
                if (!strcmp(ms[m].precond, "amg")) /* explicit: rigid-body modes on / off */
                    *(int *)((char *)params + eo_params_find(t->info.params, "amg_rbm")->offset) =
                        strstr(ms[m].label, "-r0") == NULL;
            }
            eo_linsolve *ls = NULL;
            int rc = eo_linsolve_create(ctx, t, params, &ls);
            if (rc >= 0) rc = eo_linsolve_set_coordinates(ls, S->nv, S->xyz);
            double ts = 0, tv = 0, rmax = 0;
            for (int k = 0; rc >= 0 && k < S->nsys; k++) {
                double t0 = cpu_seconds();
                if (k == 0) rc = eo_linsolve_analyze(ls, S->H[0]);
                if (rc >= 0) rc = eo_linsolve_factor(ls, S->H[k]);
                ts += cpu_seconds() - t0;
                t0 = cpu_seconds();
                if (rc == EO_OK) rc = eo_linsolve_solve(ls, S->b[k], x);
                tv += cpu_seconds() - t0;
                its[m][k] = eo_linsolve_get_stats(ls)->iterations;
                double *y = malloc((size_t)n * sizeof(double)), rr = 0;
                eo_csc_symv(S->H[k], x, y);
                for (int i = 0; i < n; i++) rr += (S->b[k][i] - y[i]) * (S->b[k][i] - y[i]);
                free(y);
                rmax = fmax(rmax, sqrt(rr) / nrm(n, S->b[k]));
            }
            if (rc != EO_OK) {
                rcs[m] = rc;
                printf("  %s: %s: %s\n", ms[m].label, eo_status_name(rc), eo_ctx_message(ctx));
            }
            tset[m][r] = ts;
            tsol[m][r] = tv;
            res[m] = rmax;
            eo_linsolve_destroy(&ls);
        }
    printf("newton systems (%d tets, n = %d, %d systems H_0..H_%d, rtol 1e-8 for PCG and gmg, %d interleaved "
           "repeats, process CPU seconds)\n",
           S->ntets, n, S->nsys, S->nsys - 1, reps);
    printf("  %-11s %14s %19s %14s %19s %14s %19s %12s %10s  %s\n", "method", "setup s/sys", "min-max", "solve s/sys",
           "min-max", "total s/sys", "min-max", "total/chol", "max res", "iterations per system");
    double ref = 0;
    for (int m = 0; m < NM; m++) {
        double tot[MAXR];
        for (int r = 0; r < reps; r++) tot[r] = tset[m][r] + tsol[m][r];
        qsort(tot, (size_t)reps, sizeof(double), cmp_d);
        if (!strcmp(ms[m].label, "cholmod")) ref = tot[reps / 2];
    }
    for (int m = 0; m < NM; m++) {
        double sm, sl, sh, vm, vl, vh, tm, tl, th, tot[MAXR];
        for (int r = 0; r < reps; r++) tot[r] = tset[m][r] + tsol[m][r];
        med_spread(tot, reps, &tm, &tl, &th);
        med_spread(tset[m], reps, &sm, &sl, &sh);
        med_spread(tsol[m], reps, &vm, &vl, &vh);
        const double q = 1.0 / S->nsys;
        char itb[64] = "", *w = itb;
        for (int k = 0; k < S->nsys; k++) w += snprintf(w, sizeof itb - (size_t)(w - itb), "%d ", its[m][k]);
        printf("  %-11s %14.4f   [%.4f, %.4f] %14.4f   [%.4f, %.4f] %14.4f   [%.4f, %.4f] %12.2f %10.2e  %s%s\n",
               ms[m].label, sm * q, sl * q, sh * q, vm * q, vl * q, vh * q, tm * q, tl * q, th * q,
               ref > 0 ? tm / ref : 0, res[m], itb, rcs[m] ? eo_status_name(rcs[m]) : "");
    }
    free(x);
    eo_ctx_destroy(&ctx);
}

static void loadavg(char *buf, size_t n)
{
    snprintf(buf, n, "unknown");
    FILE *f = fopen("/proc/loadavg", "r");
    if (!f) return;
    double a, b, c;
    if (fscanf(f, "%lf %lf %lf", &a, &b, &c) == 3) snprintf(buf, n, "%.2f %.2f %.2f", a, b, c);
    fclose(f);
}

/* 1 vs 2 BLAS threads on the numeric factorization of H_0 (the header's --blas-threads). */
static void bench_blas_threads(const bar_case *bc, const bar_systems *S)
{
    enum { NT = 2, MAXR = 32 };
    const int nthr[NT] = {1, 2};
    int reps = g_reps_override > 0 ? g_reps_override : 5;
    if (reps > MAXR) reps = MAXR;
    double tw[NT][MAXR], tc[NT][MAXR];
    eo_ctx *ctx = NULL;
    eo_ctx_create(NULL, &ctx);
    eo_chm chm;
    memset(&chm, 0, sizeof chm);
    eo_chm_start(&chm);
    eo_chm_ordering(&chm, EO_CHM_DEFAULT_ORDERING);
    chm.c.supernodal = CHOLMOD_SUPERNODAL;
    chm.c.final_ll = 1;
    eo_blas_info b0;
    eo_blas_get(&b0);
    char la0[64], la1[64];
    if (eo_chm_analyze(&chm, S->H[0], "bench", ctx) >= 0) {
        cholmod_sparse M = eo_chm_view(S->H[0]);
        eo_chm_factorize(&chm, &M, 0); /* warm-up: first touch of L, BLAS thread start */
        loadavg(la0, sizeof la0);
        int ok = 1;
        for (int r = 0; r < reps && ok; r++)
            for (int j = 0; j < NT; j++) {
                int k = (r % 2) ? NT - 1 - j : j;
                if (eo_blas_set_threads(nthr[k]) != EO_OK) ok = 0;
                double w0 = eo_wtime(), c0 = cpu_seconds();
                ok = ok && eo_chm_factorize(&chm, &M, 0) && chm.c.status == CHOLMOD_OK;
                tc[k][r] = cpu_seconds() - c0;
                tw[k][r] = eo_wtime() - w0;
            }
        loadavg(la1, sizeof la1);
        printf("BLAS threads, %s (CHOLMOD supernodal LL' of H_0, %s ordering, n = %d, flops %.4g, %d interleaved repeats; "
               "load average %s before, %s after)\n",
               bc->name, EO_CHM_DEFAULT_ORDERING, S->H[0]->n, chm.c.fl, reps, la0, la1);
        if (!ok) printf("  failed (BLAS threads not settable, or CHOLMOD status %d)\n", chm.c.status);
        else {
            printf("  %-8s %12s %19s %12s %19s %8s\n", "threads", "wall s (med)", "min-max", "cpu s (med)", "min-max",
                   "cpu/wall");
            for (int k = 0; k < NT; k++) {
                double wm, wl, wh, cm, cl, ch;
                med_spread(tw[k], reps, &wm, &wl, &wh);
                med_spread(tc[k], reps, &cm, &cl, &ch);
                printf("  %-8d %12.4f   [%.4f, %.4f] %12.4f   [%.4f, %.4f] %8.2f\n", nthr[k], wm, wl, wh, cm, cl, ch,
                       cm / wm);
            }
        }
    }
    eo_blas_set_threads(b0.threads > 0 ? b0.threads : 1);
    eo_chm_finish(&chm);
    eo_ctx_destroy(&ctx);
}

static void run_bar(const bar_case *bc)
{
    eo_ctx *ctx = NULL;
    eo_ctx_create(NULL, &ctx);
    bar_systems S;
    printf("\ncase %s: twist bar, %d x %d x %d cells x 5 tets\n", bc->name, bc->cx, bc->cy, bc->cz);
    double t0 = eo_wtime();
    if (bar_build(ctx, bc, &S) == EO_OK) {
        printf("  %d tets, n = %d free dofs, nnz(upper H) = %d; systems built in %.2f s\n", S.ntets, S.n,
               S.H[0]->nnz, eo_wtime() - t0);
        if (g_blas_threads_only) {
            bench_blas_threads(bc, &S);
        } else {
            if (!g_gmg_only) bench_orderings(bc, &S);
            bench_newton(bc, &S);
        }
    }
    bar_free(ctx, &S);
    eo_ctx_destroy(&ctx);
}

int main(int argc, char **argv)
{
    eo_cli_blas_fix(argv, 0); /* OpenBLAS on a generic core: run again with OPENBLAS_CORETYPE */
    char machine[512];
    eo_machine_describe(machine, sizeof machine);
    printf("bench_linsolve: %s\n", machine);
    char blas_line[640];
    eo_blas_describe(blas_line, sizeof blas_line);
    printf("bench_linsolve: %s\n", blas_line);
    const char *thr = getenv("OPENBLAS_NUM_THREADS");
    printf("OPENBLAS_NUM_THREADS=%s; times are medians of the factor+solve repetitions; stationary\n"
           "methods are capped at 2000 iterations (default tol 1e-10)\n", thr ? thr : "(unset)");
    int out = 1;
    for (int a = 1; a < argc; a++) { /* options out of argv: what remains are case names */
        if (strcmp(argv[a], "--blas-threads") == 0) g_blas_threads_only = 1;
        else if (strcmp(argv[a], "--gmg") == 0) g_gmg_only = 1;
        else if (strcmp(argv[a], "--reps") == 0 && a + 1 < argc) g_reps_override = atoi(argv[++a]);
        else argv[out++] = argv[a];
    }
    argc = out;
    int ran = 0;
    for (size_t c = 0; c < sizeof bars / sizeof bars[0]; c++) {
        int pick = argc <= 1 && strcmp(bars[c].name, "bar100k") && strcmp(bars[c].name, "bar300k");
        for (int a = 1; a < argc; a++) pick |= strcmp(argv[a], bars[c].name) == 0;
        if (pick) {
            run_bar(&bars[c]);
            ran++;
        }
    }
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        int pick = argc <= 1 && !g_gmg_only;
        for (int a = 1; a < argc; a++) pick |= strcmp(argv[a], cases[c].name) == 0;
        if (pick) {
            run_case(&cases[c]);
            ran++;
        }
    }
    if (!ran) {
        fprintf(stderr, "unknown case; valid:");
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) fprintf(stderr, " %s", cases[c].name);
        for (size_t c = 0; c < sizeof bars / sizeof bars[0]; c++) fprintf(stderr, " %s", bars[c].name);
        fprintf(stderr, "\n");
        return 1;
    }
    return 0;
}
