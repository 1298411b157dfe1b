/* Newton-iteration benchmark: what one full Newton iteration costs against the one
 * numeric factorization it cannot avoid (issue 15, item 3).
 *
 * Per case, one implicit step of a scene (the first step from its initial state) is
 * solved again and again with the default Newton (clamp, backtracking, newton_decrement (--stop),
 * tol 1e-10, CHOLMOD supernodal LLᵀ) through eo_sim_trial, and the clamp-projected
 * Hessian H_0 of the step's starting guess is factored bare (CHOLMOD numeric
 * factorization only, symbolic analysis done once, the same wrapper settings as the
 * `cholmod` linear solver: one OpenMP level, the BLAS threads of the environment):
 *
 *   ordering    analyze + two numeric factorizations of H_0 with AMD, METIS and NESDIS;
 *               the ordering with the smallest numeric CPU time (the faster of the two) is
 *               "best", and Newton runs with solver.cholmod.ordering = best;
 *   assembly    the clamp-projected Hessian at the guess assembled 3 times (best CPU time):
 *               tets/s inside the assembler (element kernel + scatter, inertia included);
 *   warm-up     one untimed Newton trial (the solver's symbolic analysis happens once per
 *               pattern, i.e. once per simulation, and is left out of the repeats);
 *   repeats     interleaved: a Newton trial, then a bare numeric factorization of H_0
 *               (best ordering), `reps` times (default 3). Per repeat
 *                   iteration = trial CPU time / accepted Newton iterations,
 *                   ratio     = iteration / bare factorization (same repeat);
 *               median and [min, max] over the repeats, CPU time (process, all threads:
 *               the figure that does not depend on the other jobs of a shared machine)
 *               and wall time. Per trial also: iterations, Hessians assembled, numeric
 *               factorizations, and the solver profile (eo_solver_get_profile:
 *               assembly, analyze, factor, solve, line search, gradients, other).
 *
 * Cases (all stable neo-Hookean, Newmark h = 0.01):
 *   beam100k   the built-in twist scene, mesh.generate.cells = 128 x 13 x 13 (108 160 tets)
 *   beam20k    twist, 64 x 8 x 8 cells (20 480 tets)
 *   bunny100k  the IPC bunny (../shared/meshes/ipc_bunny.msh) re-tetrahedralized by TetGen
 *              from its boundary (written as OBJ next to the program's working folder),
 *              mesh.tetgen.quality = 0, max_volume = 3.5e-4 m³; y-up, E = 1e5, gravity −y,
 *              base (y < −0.2) fixed, top (y > 2.3) turned about y at 3 rad/s
 *   bunny20k   the same scene on the IPC bunny itself (19 379 tets)
 *
 *   bench_newton [--reps N] [--stop RULE] [--defaults] [case ...]   default: every case
 * --stop: solver.stop of the Newton runs, default newton_decrement (tol 1e-10 absolute:
 * the rule of the committed results; the library's default became relative_decrement,
 * which runs these steps down to the rounding floor, 12 instead of 6 iterations on the
 * IPC bunny). Where the library has eo_step_set_tet_order, the assembly throughput is
 * also printed with the tets visited in the mesh order.
 * EO_SHARED (environment) overrides the shared folder (default: ../shared beside the
 * source tree). Prints the machine, build and settings first. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include <string.h>
#include <time.h>

#include "eo_build_config.h"
#include "elastopt/config.h"
#include "cli/blas_fix.h"
#include "elastopt/machine.h"
#include "elastopt/mesh.h"
#include "elastopt/sim.h"
#include "elastopt/step.h"
#include "solvers/linsys/cholmod_util.h"

static char g_scratch[1100]; /* the re-mesh's surface file, removed at exit */
static void remove_scratch(void)
{
    if (g_scratch[0]) remove(g_scratch);
}

#ifndef EO_SHARED_DIR
#define EO_SHARED_DIR "../shared"
#endif

static double cputime(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void med_spread(const double *v, int m, double *med, double *lo, double *hi)
{
    double s[64];
    memcpy(s, v, (size_t)m * sizeof(double));
    qsort(s, (size_t)m, sizeof(double), cmp_d);
    *med = m % 2 ? s[m / 2] : 0.5 * (s[m / 2 - 1] + s[m / 2]);
    *lo = s[0];
    *hi = s[m - 1];
}

typedef struct bench_case {
    const char *name;
    const char *builtin;   /* built-in scene, or NULL: the bunny scene below */
    const char *cells;     /* twist: mesh.generate.cells */
    int refine;            /* bunny: 1 = TetGen from the boundary OBJ, 0 = the .msh itself */
} bench_case;

static const bench_case cases[] = {
    {"beam100k", "twist", "[128,13,13]", 0},
    {"beam20k", "twist", "[64,8,8]", 0},
    {"bunny100k", NULL, NULL, 1},
    {"bunny20k", NULL, NULL, 0},
};

static const char *shared_dir(void)
{
    const char *e = getenv("EO_SHARED");
    return e && *e ? e : EO_SHARED_DIR;
}

/* The bunny scene (JSON text) on mesh file `file`, tetgen settings when refine. */
static void bunny_text(char *buf, size_t n, const char *file, int refine)
{
    snprintf(buf, n,
             "{\"mesh\": {\"file\": \"%s\"%s},\n"
             " \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e5, \"nu\": 0.4, \"density\": 1000},\n"
             " \"gravity\": [0, -9.81, 0],\n"
             " \"boundary\": [{\"box\": [[-9, -9, -9], [9, -0.2, 9]], \"fixed\": true},\n"
             "   {\"box\": [[-9, 2.3, -9], [9, 9, 9]], \"rotate\": {\"axis\": [0, 1, 0], \"center\": [-0.3, 2.5, 0], "
             "\"rate\": 3.0}}],\n"
             " \"time\": {\"integrator\": \"newmark\", \"dt\": 0.01, \"steps\": 1},\n"
             " \"output\": {\"vtu\": false}}\n",
             file, refine ? ", \"tetgen\": {\"quality\": 0, \"max_volume\": 3.5e-4}" : "");
}

/* the case's config document (NULL + message on failure) */
static eo_cfg *case_cfg(eo_ctx *ctx, const bench_case *bc)
{
    eo_cfg *cfg = NULL;
    char ov[128];
    if (bc->builtin) {
        if (eo_scene_cfg_load(ctx, NULL, bc->builtin, &cfg) < 0) return NULL;
        snprintf(ov, sizeof ov, "mesh.generate.cells=%s", bc->cells);
        if (eo_cfg_override(ctx, cfg, ov) < 0 || eo_cfg_override(ctx, cfg, "output.vtu=false") < 0) {
            eo_cfg_destroy(&cfg);
            return NULL;
        }
        return cfg;
    }
    char msh[1024], file[1100], text[4096];
    snprintf(msh, sizeof msh, "%s/meshes/ipc_bunny.msh", shared_dir());
    if (bc->refine) {
        if (!eo_mesh_have_tetgen()) {
            eo_error(ctx, EO_ERR_UNSUPPORTED, "built without TetGen");
            return NULL;
        }
        eo_mesh *m = NULL;
        /* the surface for TetGen, a scratch file in $TMPDIR removed at exit (not in the
         * working directory) */
        const char *tmp = getenv("TMPDIR");
        snprintf(file, sizeof file, "%s/bench_newton_bunny_%ld.obj", tmp && *tmp ? tmp : "/tmp", (long)getpid());
        if (!g_scratch[0]) atexit(remove_scratch); /* once, however many cases re-mesh */
        snprintf(g_scratch, sizeof g_scratch, "%s", file);
        int rc = eo_mesh_read(ctx, msh, NULL, &m);
        if (rc >= 0) rc = eo_mesh_write(ctx, m, file, EO_MESH_AUTO);
        eo_mesh_destroy(&m);
        if (rc < 0) return NULL;
    } else {
        snprintf(file, sizeof file, "%s", msh);
    }
    bunny_text(text, sizeof text, file, bc->refine);
    if (eo_cfg_load(ctx, NULL, text, &cfg) < 0) return NULL;
    return cfg;
}

typedef struct trial_rec {
    double cpu, wall;
    int iterations;
    long n_hessian, n_factor, n_refactor;
    int reason;
    eo_profile prof;
} trial_rec;

static void print_profile(const char *label, const eo_profile *p, int iterations)
{
    double other = p->t_total - (p->t_assembly + p->t_analyze + p->t_factor + p->t_solve + p->t_linesearch +
                                 p->t_gradient);
    printf("    %-9s total %7.3f s: assembly %6.3f (%ld), analyze %6.3f (%ld), factor %6.3f (%ld), solve %6.3f (%ld), "
           "line search %6.3f (%ld evals), gradient %6.3f (%ld), other %6.3f; iteration / factor = %.3f\n",
           label, p->t_total, p->t_assembly, p->n_assembly, p->t_analyze, p->n_analyze, p->t_factor, p->n_factor,
           p->t_solve, p->n_solve, p->t_linesearch, p->n_ls_evals, p->t_gradient, p->n_gradient, other,
           iterations > 0 && p->n_factor > 0 ? (p->t_total / iterations) / (p->t_factor / (double)p->n_factor) : NAN);
}

/* solver.stop of the Newton runs (--stop; default newton_decrement, the rule of the
 * results in bench/results/newton-amd-epyc-2cpu.txt, pinned since the library's default
 * became relative_decrement) */
static const char *stop_rule = "newton_decrement";
static int par_elems; /* --parallel: the step's OpenMP element loops (eo_step_set_parallel) */
/* --defaults: Newton with the library's default solver settings (project_on_demand,
 * relative_decrement, solver.linear = auto with its own ordering and factor reuse)
 * instead of clamp + --stop + the best ordering; the bare factorization stays the best
 * ordering's. Repeated trials of one step then reuse the factor the previous trial left,
 * as consecutive time steps do. */
static int use_defaults;

static int run_case(const bench_case *bc, int reps)
{
    enum { NORD = 3, MAXR = 64 };
    const char *ords[NORD] = {"amd", "metis", "nesdis"};
    eo_ctx *ctx = NULL;
    eo_ctx_create(NULL, &ctx);
    eo_sim *sim = NULL;
    eo_csc *H0 = NULL;
    eo_chm chm[NORD];
    memset(chm, 0, sizeof chm);
    double *x = NULL;
    int rc = EO_OK;
    printf("\ncase %s\n", bc->name);
    double t0 = eo_wtime();
    eo_cfg *cfg = case_cfg(ctx, bc);
    if (!cfg) {
        printf("  skipped: %s\n", eo_ctx_message(ctx));
        eo_ctx_destroy(&ctx);
        return 0;
    }
    rc = eo_sim_create(ctx, cfg, &sim);
    eo_objective *obj = NULL;
    double *guess = NULL;
    if (rc >= 0) rc = eo_sim_prepare(sim, &obj, &guess);
    if (rc < 0) goto done;
    const eo_mesh *mesh = eo_step_mesh(eo_sim_step_problem(sim));
    const int n = obj->n;
    printf("  %d vertices, %d tets, n = %d free dofs; set up in %.2f s\n", mesh->nv, mesh->nt, n, eo_wtime() - t0);
    /* H_0: the clamp-projected Hessian at the step's starting guess (copied) */
    eo_csc *H = NULL;
    rc = eo_objective_hessian(obj, guess, EO_PROJ_CLAMP, &H);
    if (rc >= 0) rc = eo_csc_clone(ctx, H, &H0);
    if (rc < 0) goto done;
    printf("  H_0: nnz(upper) = %d\n", H0->nnz);
    if (par_elems)
        printf("  element loops: %s\n", eo_step_set_parallel(eo_sim_step_problem(sim), 1)
                                            ? "OpenMP (eo_step_set_parallel)"
                                            : "serial (eo_step_set_parallel refused: no OpenMP or one thread)");
    {   /* Hessian assembly throughput: clamp-projected H at the guess, all terms, CPU time */
        double best_a = INFINITY;
        for (int rep = 0; rep < 3 && rc >= 0; rep++) {
            double c0 = cputime();
            rc = eo_objective_hessian(obj, guess, EO_PROJ_CLAMP, &H);
            best_a = fmin(best_a, cputime() - c0);
        }
        if (rc < 0) goto done;
        printf("  assembly: clamp-projected Hessian (elastic + inertia, kernel + scatter into the CSC) %.4f s cpu "
               "(best of 3) = %.3g tets/s\n", best_a, mesh->nt / best_a);
#ifdef EO_STEP_TET_ORDER
        /* the same with the tets visited in the mesh order instead of the default Morton order */
        eo_step *sp = eo_sim_step_problem(sim);
        if (eo_step_set_tet_order(sp, 0) == 0) {
            double best_m = INFINITY;
            for (int rep = 0; rep < 3 && rc >= 0; rep++) {
                double c0 = cputime();
                rc = eo_objective_hessian(obj, guess, EO_PROJ_CLAMP, &H);
                best_m = fmin(best_m, cputime() - c0);
            }
            eo_step_set_tet_order(sp, 1);
            if (rc < 0) goto done;
            printf("  assembly, tets in the mesh order (not the default Morton order): %.4f s cpu (best of 3) = %.3g "
                   "tets/s\n", best_m, mesh->nt / best_m);
        }
#endif
    }
    cholmod_sparse S = eo_chm_view(H0);
    double tf_ord[NORD];
    int best = -1;
    printf("  %-8s %12s %12s %11s %13s\n", "ordering", "flops", "nnz(L)", "analyze s", "factor cpu s"); /* min of 2 */
    for (int o = 0; o < NORD; o++) {
        eo_chm_start(&chm[o]);
        eo_chm_ordering(&chm[o], ords[o]);
        chm[o].c.supernodal = CHOLMOD_SUPERNODAL;
        chm[o].c.final_ll = 1;
        double ta = eo_wtime();
        if (eo_chm_analyze(&chm[o], H0, "bench_newton", ctx) < 0) {
            printf("  %-8s analyze failed: %s\n", ords[o], eo_ctx_message(ctx));
            tf_ord[o] = INFINITY;
            continue;
        }
        ta = eo_wtime() - ta;
        int ok = 1;
        tf_ord[o] = INFINITY;
        for (int rep = 0; ok && rep < 2; rep++) { /* the first call also pays first-touch costs */
            double c0 = cputime();
            ok = eo_chm_factorize(&chm[o], &S, 0) && chm[o].c.status == CHOLMOD_OK;
            tf_ord[o] = ok ? fmin(tf_ord[o], cputime() - c0) : INFINITY;
        }
        printf("  %-8s %12.4g %12.4g %11.3f %13.4f\n", ords[o], chm[o].c.fl, chm[o].c.lnz, ta, tf_ord[o]);
        if (ok && (best < 0 || tf_ord[o] < tf_ord[best])) best = o;
    }
    if (best < 0) {
        printf("  no ordering factored H_0\n");
        goto done;
    }
    for (int o = 0; o < NORD; o++)
        if (o != best) eo_chm_finish(&chm[o]);
    printf("  best ordering: %s\n", ords[best]);
    /* Newton with the best ordering (or, --defaults, the library's default solver as it is) */
    if (!use_defaults) {
        eo_solver_opts so;
        eo_solver_opts_default(&so);
        /* the fix the header names (the library default became project_on_demand, whose
         * iterations include failed factorization attempts) */
        snprintf(so.hessian_fix, sizeof so.hessian_fix, "clamp");
        eo_cfg *scfg = NULL;
        char ov[64];
        snprintf(ov, sizeof ov, "solver.cholmod.ordering=%s", ords[best]);
        snprintf(so.stop, sizeof so.stop, "%s", stop_rule);
        rc = eo_cfg_create_empty(ctx, &scfg);
        if (rc >= 0) rc = eo_cfg_override(ctx, scfg, ov);
        if (rc >= 0) rc = eo_sim_set_solver(sim, &so, scfg);
        eo_cfg_destroy(&scfg);
        if (rc < 0) goto done;
    }
    x = malloc((size_t)n * sizeof(double));
    trial_rec tr[MAXR];
    double fcpu[MAXR], fwall[MAXR], rcpu[MAXR], rwall[MAXR];
    eo_solver *solver = eo_sim_solver(sim);
    {   /* untimed warm-up: the solver's symbolic analysis (once per pattern), first touches */
        eo_solve_result res;
        rc = eo_sim_trial(sim, NULL, NULL, x, NULL, NULL, NULL, &res);
        if (rc < 0) goto done;
    }
    for (int r = 0; r < reps; r++) {
        eo_solve_result res;
        eo_profile p0 = *eo_solver_get_profile(solver);
        const eo_linsolve *lsv = eo_solver_get_linsolve(solver);
        const long nref0 = lsv ? eo_linsolve_get_stats(lsv)->n_refactor : 0;
        double w0 = eo_wtime(), c0 = cputime();
        rc = eo_sim_trial(sim, NULL, NULL, x, NULL, NULL, NULL, &res);
        tr[r].cpu = cputime() - c0;
        tr[r].wall = eo_wtime() - w0;
        if (rc < 0) goto done;
        eo_profile_diff(eo_solver_get_profile(solver), &p0, &tr[r].prof);
        tr[r].iterations = res.iterations;
        tr[r].n_hessian = res.n_hessian;
        tr[r].n_factor = res.n_factor;
        tr[r].reason = res.reason;
        tr[r].n_refactor = lsv ? eo_linsolve_get_stats(lsv)->n_refactor - nref0 : 0;
        w0 = eo_wtime();
        c0 = cputime();
        int ok = eo_chm_factorize(&chm[best], &S, 0) && chm[best].c.status == CHOLMOD_OK;
        fcpu[r] = cputime() - c0;
        fwall[r] = eo_wtime() - w0;
        if (!ok) {
            printf("  bare factorization failed (CHOLMOD status %d)\n", chm[best].c.status);
            goto done;
        }
        const int it = tr[r].iterations > 0 ? tr[r].iterations : 1;
        rcpu[r] = tr[r].cpu / it / fcpu[r];
        rwall[r] = tr[r].wall / it / fwall[r];
        printf("  repeat %d: Newton %d iterations (%s), %ld Hessians, %ld factorizations, %.3f s cpu / %.3f s wall; "
               "bare factor %.4f s cpu / %.4f s wall; ratio %.3f cpu, %.3f wall\n",
               r, tr[r].iterations, eo_reason_name(tr[r].reason), tr[r].n_hessian, tr[r].n_factor, tr[r].cpu,
               tr[r].wall, fcpu[r], fwall[r], rcpu[r], rwall[r]);
        if (tr[r].n_refactor > 0)
            printf("    of the %ld factor calls, %ld numeric factorizations (the others reuse a factor)\n", tr[r].n_factor,
                   tr[r].n_refactor);
        print_profile("profile", &tr[r].prof, tr[r].iterations);
    }
    {
        double m, lo, hi, mw, lw, hw, fm, fl, fh;
        med_spread(rcpu, reps, &m, &lo, &hi);
        med_spread(rwall, reps, &mw, &lw, &hw);
        med_spread(fcpu, reps, &fm, &fl, &fh);
        printf("  RESULT %s: %d tets, Newton iteration / numeric factorization (%s) = %.3f cpu [%.3f, %.3f], %.3f "
               "wall [%.3f, %.3f]; bare factor %.4f s cpu [%.4f, %.4f]; %d iterations, %ld factorizations per step\n",
               bc->name, mesh->nt, ords[best], m, lo, hi, mw, lw, hw, fm, fl, fh, tr[0].iterations, tr[0].n_factor);
        const eo_linsolve *lsv = eo_solver_get_linsolve(solver);
        char d[256];
        if (lsv) printf("  linear solver: %s\n", eo_linsolve_describe(lsv, d, sizeof d));
    }
done:
    if (rc < 0) printf("  error: %s\n", eo_ctx_message(ctx));
    free(x);
    for (int o = 0; o < NORD; o++) eo_chm_finish(&chm[o]);
    eo_csc_destroy(&H0);
    eo_sim_destroy(&sim);
    eo_ctx_destroy(&ctx);
    return rc < 0;
}

int main(int argc, char **argv)
{
    eo_cli_blas_fix(argv, 0); /* OpenBLAS on a generic core: run again with OPENBLAS_CORETYPE */
    char machine[512];
    eo_machine_describe(machine, sizeof machine);
    printf("bench_newton: %s\n", machine);
    char blas_line[640];
    eo_blas_describe(blas_line, sizeof blas_line);
    printf("bench_newton: %s\n", blas_line);
    const char *thr = getenv("OPENBLAS_NUM_THREADS");
    int reps = 3, picked = 0, fails = 0;
    for (int a = 1; a < argc; a++)
        if (!strcmp(argv[a], "--stop") && a + 1 < argc) {
            stop_rule = argv[++a];
        } else if (!strcmp(argv[a], "--parallel")) {
            par_elems = 1;
        } else if (!strcmp(argv[a], "--defaults")) {
            use_defaults = 1;
        } else if (!strcmp(argv[a], "--reps") && a + 1 < argc) {
            reps = atoi(argv[++a]);
            if (reps < 1) reps = 1;
            if (reps > 64) reps = 64;
        } else {
            int found = 0;
            for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++)
                if (!strcmp(argv[a], cases[c].name)) found = 1;
            if (!found) {
                fprintf(stderr, "bench_newton: unknown case '%s'; valid:", argv[a]);
                for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) fprintf(stderr, " %s", cases[c].name);
                fprintf(stderr, "\n");
                return 2;
            }
            picked++;
        }
    if (use_defaults)
        printf("OPENBLAS_NUM_THREADS=%s; solver: the library defaults (newton, project_on_demand, backtracking, "
               "relative_decrement 1e-10, solver.linear = auto); bare factorization: the best of amd/metis/nesdis on "
               "H_0; first step of each scene\n", thr ? thr : "(unset)");
    else
        printf("OPENBLAS_NUM_THREADS=%s; solver: newton, clamp, backtracking, %s, tol 1e-10, cholmod "
               "supernodal (ordering: the best of amd/metis/nesdis on H_0); first step of each scene\n",
               thr ? thr : "(unset)", stop_rule);
    printf("repeats: %d (interleaved: Newton trial, bare factorization)\n", reps);
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        int pick = !picked;
        for (int a = 1; a < argc; a++) pick |= !strcmp(argv[a], cases[c].name);
        if (pick) fails += run_case(&cases[c], reps);
    }
    return fails ? 1 : 0;
}
