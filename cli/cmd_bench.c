/* elastopt bench: the optimizer benchmark (bench.h) from the command line.
 *
 * Loads and checks the whole suite first (a bad suite exits 2 and writes nothing), then
 * runs it, printing progress to stderr (scene, configuration, phase, elapsed time and
 * an estimate of the time left), and writes curves.csv, summary.csv, reference.csv,
 * trajectory.csv, report.md and plots/ into DIR. Exit 0 if every reference converged,
 * no NaN was produced and every configuration named in `require_converged`
 * converged everywhere; 1 otherwise; 2 on bad input or an I/O error.
 *
 * Under mpirun (several ranks) every rank loads the suite and runs it on its part of each
 * scene's mesh (bench.h, distributed); every configuration must be a distributed one
 * (refused with exit 2 before anything is written otherwise). Rank 0 writes DIR and
 * prints; the other ranks write into a scratch folder in $TMPDIR, removed at the end. */
#define _XOPEN_SOURCE 700
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "petsc_load.h"
#include "bench.h"
#include "profile.h"

extern const eo_cli_command eo_cmd_bench;

typedef struct progress_state {
    int tty;
    int last_scene, last_config;
    const char *last_phase;
    double scene_start;   /* elapsed time when the current scene started */
    clock_t scene_cpu;    /* processor time then */
} progress_state;

static void fmt_dur(double s, char *buf, size_t n)
{
    if (s < 0) snprintf(buf, n, "?");
    else if (s < 60) snprintf(buf, n, "%.0fs", s);
    else if (s < 3600) snprintf(buf, n, "%dm%02ds", (int)(s / 60), (int)s % 60);
    else snprintf(buf, n, "%dh%02dm", (int)(s / 3600), (int)(s / 60) % 60);
}

static void on_progress(const eo_bench_progress *p, void *user)
{
    progress_state *ps = user;
    /* one line per change of scene/configuration/phase (a terminal gets \r updates) */
    int changed = p->scene != ps->last_scene || p->config != ps->last_config || p->phase != ps->last_phase;
    if (!changed && !ps->tty) return;
    if (p->scene != ps->last_scene) {
        ps->scene_start = p->elapsed;
        ps->scene_cpu = clock();
    }
    ps->last_scene = p->scene;
    ps->last_config = p->config;
    ps->last_phase = p->phase;
    char el[32], eta[32];
    fmt_dur(p->elapsed, el, sizeof el);
    fmt_dur(p->eta, eta, sizeof eta);
    if (strcmp(p->phase, "done") == 0) { /* one line per finished scene, also on a terminal */
        char took[32], cpu[32];
        fmt_dur(p->elapsed - ps->scene_start, took, sizeof took);
        fmt_dur((double)(clock() - ps->scene_cpu) / CLOCKS_PER_SEC, cpu, sizeof cpu);
        fprintf(stderr, "%s[%3.0f%%] scene %d/%d %s done in %s (processor %s)  elapsed %s, left ~%s\n",
                ps->tty ? "\r\033[K" : "", 100 * p->fraction, p->scene + 1, p->nscenes, p->scene_name, took, cpu, el,
                eta);
        fflush(stderr);
        return;
    }
    fprintf(stderr, "%s[%3.0f%%] scene %d/%d %s", ps->tty ? "\r\033[K" : "", 100 * p->fraction, p->scene + 1,
            p->nscenes, p->scene_name);
    if (p->config >= 0) fprintf(stderr, "  config %d/%d %s", p->config + 1, p->nconfigs, p->config_name);
    fprintf(stderr, "  (%s)  elapsed %s, left ~%s%s", p->phase, el, eta, ps->tty ? "" : "\n");
    fflush(stderr);
}

static void on_profile(const char *scene, const char *config, const eo_profile *p, void *user)
{
    char title[256];
    (void)user;
    snprintf(title, sizeof title, "%s / %s", scene, config);
    eo_cli_profile_print(stdout, title, p);
}

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb, (void)flag, (void)ftw;
    return remove(path);
}

static int run(eo_ctx *ctx, int argc, char **argv)
{
    const char *suite_path = NULL, *out = NULL;
    int repeats = 0, plots = -1, quiet = 0, profile = 0;
    const char *clock_name = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) out = argv[++i];
        else if (strcmp(argv[i], "--repeats") == 0 && i + 1 < argc) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 1 || v > 16) return eo_cli_usage_error(&eo_cmd_bench, "--repeats needs 1..16");
            repeats = (int)v;
        } else if (strcmp(argv[i], "--no-plots") == 0) plots = 0;
        else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) quiet = 1;
        else if (strcmp(argv[i], "--profile") == 0) profile = 1;
        else if (strcmp(argv[i], "--clock") == 0 && i + 1 < argc) {
            clock_name = argv[++i];
            if (strcmp(clock_name, "cpu") && strcmp(clock_name, "wall"))
                return eo_cli_usage_error(&eo_cmd_bench, "--clock needs cpu or wall");
        }
        else if (argv[i][0] == '-') return eo_cli_unknown_arg(&eo_cmd_bench, "option", argv[i]);
        else if (suite_path) return eo_cli_usage_error(&eo_cmd_bench, "give one SUITE.json");
        else suite_path = argv[i];
    }
    if (!suite_path) return eo_cli_usage_error(&eo_cmd_bench, "missing SUITE.json");
    char dir[1200];
    if (out) {
        snprintf(dir, sizeof dir, "%s", out);
    } else { /* out/bench-<suite base name> */
        const char *b = strrchr(suite_path, '/');
        b = b ? b + 1 : suite_path;
        snprintf(dir, sizeof dir, "out/bench-%s", b);
        char *dot = strrchr(dir, '.');
        if (dot && dot > dir + 10) *dot = 0;
    }
    eo_bench_suite *s = NULL;
    int rc = eo_bench_suite_load(ctx, suite_path, &s);
    if (rc < 0) return eo_cli_fail(ctx, rc);
    char scratch[1100] = ""; /* under mpirun, the ranks other than 0 write here (removed at the end) */
    if (eo_cli_rank() != 0) {
        const char *tmpdir = getenv("TMPDIR");
        snprintf(scratch, sizeof scratch, "%s/elastopt-bench-rank%d-XXXXXX", tmpdir && *tmpdir ? tmpdir : "/tmp",
                 eo_cli_rank());
        if (!mkdtemp(scratch)) {
            eo_bench_suite_destroy(&s);
            return eo_cli_fail(ctx, eo_error(ctx, EO_ERR_IO, "rank %d: cannot make a scratch folder in $TMPDIR",
                                             eo_cli_rank()));
        }
        snprintf(dir, sizeof dir, "%s", scratch);
        plots = 0;
    }
    progress_state ps = {.tty = isatty(2), .last_scene = -1, .last_config = -2, .last_phase = NULL};
    eo_bench_run_opts o = eo_bench_run_opts_default();
    o.out_dir = dir;
    o.repeats = repeats;
    o.plots = plots;
    o.clock = clock_name;
    o.owned_sum = eo_cli_dist_owned_sum; /* a distributed run: per-vertex sums over the parts */
    o.progress = quiet ? NULL : on_progress;
    o.user = &ps;
    if (profile) {
        o.profile = on_profile;
        eo_cli_profile_blas(stdout);
    }
    if (!quiet) {
        fprintf(stderr, "bench %s: %d scene(s) x %d configuration(s) -> %s\n", suite_path, eo_bench_suite_nscenes(s),
                eo_bench_suite_nconfigs(s), dir);
        for (int i = 0; i < eo_bench_suite_nskipped(s); i++)
            fprintf(stderr, "bench: optional scene not run: %s\n", eo_bench_suite_skipped(s, i));
    }
    eo_bench_summary sum;
    const clock_t c0 = clock();
    rc = eo_bench_run(ctx, s, &o, &sum);
    /* under mpirun: every rank waits for rank 0's report (mpirun aborts the ranks still
     * running as soon as one exits with a non-zero status) */
    if (eo_cli_size() > 1 && !eo_cli_agree(rc >= 0) && rc >= 0)
        rc = eo_error(ctx, EO_ERR_IO, "another MPI rank's bench run failed");
    const double cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
    if (scratch[0]) nftw(scratch, remove_entry, 8, FTW_DEPTH | FTW_PHYS);
    if (!quiet && ps.tty) fprintf(stderr, "\n");
    eo_bench_suite_destroy(&s);
    if (rc < 0) return eo_cli_fail(ctx, rc);
    int bad = sum.ref_failures || sum.nan || sum.required_failures;
    if (!quiet)
        printf("bench: %d runs in %.1f s (processor %.1f s); reference failures %d, NaN %d, non-finite stops %d, "
               "required failures %d, plots %d -> %s/report.md\n",
               sum.runs, sum.seconds, cpu, sum.ref_failures, sum.nan, sum.nonfinite, sum.required_failures,
               sum.plots_made, dir);
    return bad ? EO_EXIT_NOT_CONVERGED : EO_EXIT_OK;
}

const eo_cli_command eo_cmd_bench = {
    .name = "bench",
    .summary = "benchmark solver configurations: speed against error (suite in bench/)",
    .usage = "elastopt bench SUITE.json [--out DIR] [--repeats N] [--clock cpu|wall] [--no-plots] [--quiet]\n"
             "                [--profile]\n\n"
             "Runs a benchmark suite (bench/standard.json, bench/hard.json, bench/smoke.json; keys in\n"
             "bench/harness/bench.h): a tight Newton reference per step, then every configuration\n"
             "from the same state, timed (median of N repeats after a warm-up) in CPU seconds of\n"
             "the solving thread (--clock wall, or the suite key \"clock\": elapsed time; both are\n"
             "recorded; time budgets count the same clock). Writes into DIR\n"
             "(default out/bench-<suite>): curves.csv (every iteration), summary.csv, reference.csv,\n"
             "trajectory.csv, report.md and plots/*.png (gnuplot). Progress goes to stderr.\n"
             "--profile: per scene and configuration, the solver's time by phase over its curve\n"
             "runs (as `run --profile`, in the run's clock), on stdout.\n"
             "Under mpirun every rank runs its part of each scene (every configuration must be\n"
             "distributed: solver.backend=petsc or a petsc_/snes_/tao_ optimizer; the reference is\n"
             "newton on the PETSc backend; no Ipopt check); rank 0 writes DIR (bench/petsc-mpi.json).\n"
             "Exit status: 0 all references converged, no NaN produced and every required\n"
             "configuration converged; 1 otherwise; 2 bad input or I/O error.\n",
    .run = run,
};
