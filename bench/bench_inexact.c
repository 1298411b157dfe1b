/* bench_inexact: inexact Newton with BoomerAMG against Newton with CHOLMOD, on generated
 * beams of about 5k, 50k and 100k+ tets (issue 15 item 2).
 *
 * Scene: the built-in `twist` (stable neo-Hookean, E = 1e6, Newmark h = 0.01, one end
 * fixed, the other rotated) with its mesh replaced by a generated 1 × 0.1 × 0.1 m beam
 * (5-tet split); every configuration uses the default stop (relative_decrement, 1e-10)
 * and Hessian fix (clamp). Per configuration and size: two steps, each timed (the first
 * pays CHOLMOD's symbolic analysis; AMG sets up at every Newton iteration anyway).
 * Configurations:
 *   cholmod       Newton + CHOLMOD supernodal Cholesky
 *   amg-ew2       Newton + PCG/BoomerAMG (3 dofs per node, nodal coarsening, no
 *                 rigid-body modes) + Eisenstat–Walker choice 2
 *   amg-ew2-rbm   the same with the rigid-body modes from the driver's coordinates
 *   amg-tight     PCG/BoomerAMG with the solver's own rtol 1e-10 (forcing none)
 *   (amg-tight only with --all)
 * Times are process CPU seconds of eo_sim_step (the machine is shared; run with
 * OPENBLAS_NUM_THREADS=1 so that CHOLMOD's BLAS time is one core's, as the printed
 * header records); wall seconds are printed beside them.
 * Repeats: `reps` rounds, configurations interleaved within each round (load changes hit
 * all alike); the table gives the median and min–max of each, and the ratio of medians
 * to cholmod measured in the same run.
 *
 * Usage: bench_inexact [--reps N] [--sizes a,b,c]  (sizes: cells along x; default
 * 40,100,160 = 5000, 50000, 115200 tets). Exit 77 without hypre. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "elastopt/ctx.h"
#include "cli/blas_fix.h"
#include "elastopt/machine.h"
#include "elastopt/sim.h"

typedef struct cfgdef {
    const char *label;
    const char *ov[8];
} cfgdef;

static const cfgdef cfgs[] = {
    {"cholmod", {"solver.linear=cholmod", NULL}},
    {"amg-ew2",
     {"solver.linear=pcg", "solver.pcg.preconditioner=amg", "solver.newton.forcing=ew2", "solver.pcg.amg_rbm=false",
      NULL}},
    {"amg-ew2-rbm",
     {"solver.linear=pcg", "solver.pcg.preconditioner=amg", "solver.newton.forcing=ew2", "solver.pcg.amg_rbm=true",
      NULL}},
    {"amg-tight",
     {"solver.linear=pcg", "solver.pcg.preconditioner=amg", "solver.newton.forcing=none", "solver.pcg.tol=1e-10",
      NULL}},
};
enum { NC = sizeof cfgs / sizeof cfgs[0], MAXREP = 9, STEPS = 2 };

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

typedef struct meas {
    double t[STEPS], wall[STEPS];
    int iters, lin_iters, ok;
} meas;

static int on_iter(const eo_iter_info *info, void *user)
{
    int *lin = user;
    *lin += info->lin_iters;
    return 0;
}

static int run(eo_ctx *ctx, int cx, const cfgdef *c, meas *m, int *ntets)
{
    char cells[96];
    /* cells across the 0.1 m section: 5 (40 along x), 10 (100), 12 (160): 5k, 50k, 115k tets */
    int cy = cx <= 40 ? 5 : cx <= 100 ? 10 : 12;
    snprintf(cells, sizeof cells, "mesh.generate.cells=[%d,%d,%d]", cx, cy, cy);
    const char *ov[16] = {cells, "time.steps=2"};
    int k = 2;
    for (int i = 0; c->ov[i]; i++) ov[k++] = c->ov[i];
    ov[k] = NULL;
    eo_sim *s = NULL;
    int rc = eo_sim_create_from(ctx, NULL, "twist", ov, &s);
    if (rc < 0) return rc;
    *ntets = eo_sim_scene(s)->mesh->nt;
    memset(m, 0, sizeof *m);
    m->ok = 1;
    eo_sim_set_iter_callback(s, on_iter, &m->lin_iters);
    for (int st = 0; st < STEPS && rc >= 0; st++) {
        eo_sim_step_result r;
        double c0 = cpu_seconds();
        rc = eo_sim_step(s, &r);
        if (rc < 0) break;
        m->t[st] = cpu_seconds() - c0;
        m->wall[st] = r.time;
        m->iters += r.iterations;
        if (r.reason <= 0) m->ok = 0;
    }
    eo_sim_destroy(&s);
    return rc;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    eo_cli_blas_fix(argv, 0); /* OpenBLAS on a generic core: run again with OPENBLAS_CORETYPE */
    int reps = 3, sizes[8] = {40, 100, 160}, ns = 3, nc = NC - 1;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--all")) nc = NC;
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc) reps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--sizes") && i + 1 < argc) {
            ns = 0;
            for (char *t = strtok(argv[++i], ","); t && ns < 8; t = strtok(NULL, ",")) sizes[ns++] = atoi(t);
        }
    }
    if (reps < 1) reps = 1;
    if (reps > MAXREP) reps = MAXREP;
    char machine[512];
    eo_machine_describe(machine, sizeof machine);
    const char *obt = getenv("OPENBLAS_NUM_THREADS");
    printf("bench_inexact: %s; OPENBLAS_NUM_THREADS=%s\n", machine, obt ? obt : "(unset)");
    char blas_line[640];
    eo_blas_describe(blas_line, sizeof blas_line);
    printf("bench_inexact: %s\n", blas_line);
    printf("scene twist (stable neo-Hookean E=1e6, Newmark h=0.01), %d steps, stop relative_decrement 1e-10, clamp; "
           "%d interleaved rounds\n",
           STEPS, reps);
    eo_ctx *ctx = NULL;
    eo_ctx_create(NULL, &ctx);
    {
        eo_sim *s = NULL;
        const char *ov[] = {"solver.linear=pcg", "solver.pcg.preconditioner=amg", NULL};
        if (eo_sim_create_from(ctx, NULL, "twist", ov, &s) < 0) {
            printf("no hypre (pcg amg unavailable): %s\n", eo_ctx_message(ctx));
            eo_ctx_destroy(&ctx);
            return 77;
        }
        eo_sim_destroy(&s);
    }
    for (int si = 0; si < ns; si++) {
        static meas M[NC][MAXREP];
        int nt = 0;
        for (int r = 0; r < reps; r++)
            for (int c = 0; c < nc; c++) {
                int rc = run(ctx, sizes[si], &cfgs[c], &M[c][r], &nt);
                if (rc < 0) {
                    printf("%s: error %d: %s\n", cfgs[c].label, rc, eo_ctx_message(ctx));
                    M[c][r].ok = 0;
                }
                fflush(stdout);
            }
        printf("\n%d tets (CPU s, median of %d):\n  %-12s %9s %19s %9s %19s %9s %6s %8s %s\n", nt, reps, "config",
               "step1", "(min-max)", "step2", "(min-max)", "wall2", "newton", "pcg its", "step2 ratio to cholmod");
        double base = NAN;
        for (int c = 0; c < nc; c++) {
            double a[STEPS][MAXREP], med[STEPS], w[MAXREP];
            int ok = 1;
            for (int st = 0; st < STEPS; st++) {
                for (int r = 0; r < reps; r++) a[st][r] = M[c][r].t[st];
                qsort(a[st], (size_t)reps, sizeof(double), cmp);
                med[st] = a[st][reps / 2];
            }
            for (int r = 0; r < reps; r++) ok &= M[c][r].ok, w[r] = M[c][r].wall[1];
            qsort(w, (size_t)reps, sizeof(double), cmp);
            if (c == 0) base = med[1];
            printf("  %-12s %9.3f %9.3f-%-9.3f %9.3f %9.3f-%-9.3f %9.3f %6d %8d %.2f%s\n", cfgs[c].label, med[0],
                   a[0][0], a[0][reps - 1], med[1], a[1][0], a[1][reps - 1], w[reps / 2], M[c][0].iters,
                   M[c][0].lin_iters, med[1] / base, ok ? "" : "  (a step did not converge)");
        }
        fflush(stdout);
    }
    eo_ctx_destroy(&ctx);
    return 0;
}
