/* The optimizer benchmark harness (bench.h): report.md. Machine and build (the BLAS line,
 * the load average), protocol and clock, headline (fastest per scene and accuracy, with
 * the repeats behind each figure and whether the spreads separate), the own stopping
 * rule's table, the performance profile, stability matrix, per-scene tables with the
 * plots, failures with reasons, resolved configurations. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_impl.h"
#include "elastopt/io.h"
#include "elastopt/machine.h"

/* "median (min–max)" of the time to threshold j, in ms. */
static void fmt_spread(const bench_pair *p, int j, int repeats, char *buf, size_t n)
{
    char a[32], lo[32], hi[32];
    bench_fmt_ms(p->ttt_med[j], a, sizeof a);
    if (!isfinite(p->ttt_med[j]) || repeats < 2) {
        snprintf(buf, n, "%s", a);
        return;
    }
    bench_fmt_ms(p->ttt_min[j], lo, sizeof lo);
    bench_fmt_ms(p->ttt_max[j], hi, sizeof hi);
    snprintf(buf, n, "%s (%s–%s)", a, lo, hi);
}

/* Two medians are "separated" only when each has at least SEPARATE_MIN_REPEATS timed
 * repeats and their [min, max] ranges do not overlap: with fewer repeats a range says
 * nothing about the noise. */
enum { SEPARATE_MIN_REPEATS = 3 };
static const char *separated(const bench_pair *a, const bench_pair *b2, int j, int repeats)
{
    if (repeats < SEPARATE_MIN_REPEATS) return "n/a (< 3 repeats)";
    return a->ttt_max[j] < b2->ttt_min[j] || b2->ttt_max[j] < a->ttt_min[j] ? "yes" : "no";
}

/* The report's "Own stopping rule" headline table: the Pareto chart's numbers. */
static int write_pareto_table(eo_ctx *ctx, FILE *f, const bench_out *b)
{
    const eo_bench_suite *s = b->s;
    pareto_pts pp;
    int rc = bench_pareto_compute(ctx, b, &pp);
    if (rc < 0) return rc;
    int fast, close;
    bench_pareto_winners(s, &pp, &fast, &close);
    fprintf(f, "### Own stopping rule (the Pareto chart)\n\n"
               "Each configuration over the trajectory runs of every scene with its own stopping rule: `traj. time / "
               "baseline` = geometric mean over the scenes of its solve time per step over the baseline's; `traj. "
               "dist / ref. motion` = geometric mean of its largest distance to the reference trajectory over the "
               "reference's motion. Pareto = converged everywhere and no such configuration is both faster and "
               "closer (ratios within 2%% count as equal).");
    if (fast >= 0)
        fprintf(f, " Fastest that converged everywhere: **%s** (%.2f× the baseline's time); closest: **%s**.",
                s->cf[fast].name, pp.x[fast], s->cf[close].name);
    fprintf(f, "\n\n| # | configuration | traj. time / baseline | traj. dist / ref. motion | scenes converged | Pareto |\n"
               "|---|---|---|---|---|---|\n");
    for (int c = 0; c < s->ncf; c++) {
        int nconv = 0;
        for (int si = 0; si < s->nsc; si++) nconv += strcmp(b->res[si].pair[c].status, "converged") == 0;
        char xa[32] = "—", ya[32] = "—";
        if (pp.n[c]) {
            snprintf(xa, sizeof xa, "%.2f", pp.x[c]);
            snprintf(ya, sizeof ya, "%.1e", pp.y[c]);
        }
        fprintf(f, "| %d | %s | %s | %s | %d/%d | %s |\n", c + 1, s->cf[c].name, xa, ya, nconv, s->nsc,
                pp.front[c] ? "yes" : "");
    }
    fprintf(f, "\n");
    bench_pareto_free(ctx, &pp);
    return EO_OK;
}

static const char *env_or(const char *name, const char *def)
{
    const char *v = getenv(name);
    return v && *v ? v : def;
}

/* Which steps are measured and why. */
static void describe_steps(FILE *f, const bench_scene *bs, const bench_scene_res *sr)
{
    fprintf(f, "Measured step%s ", bs->steps > 1 ? "s" : "");
    for (int k = 0; k < bs->steps; k++) fprintf(f, "%s%d", k ? ", " : "", sr->meas[k] + 1);
    if (bs->select == BENCH_SELECT_FIRST) {
        if (bs->skip) fprintf(f, " (after %d reference-only step%s)", bs->skip, bs->skip == 1 ? "" : "s");
    } else {
        const int mot = bs->select == BENCH_SELECT_MOTION;
        const double *sc = mot ? sr->motion : sr->correction;
        double out = -INFINITY; /* the largest score not measured */
        int outk = -1;
        for (int k = bs->skip; k < sr->nref; k++) {
            int in = 0;
            for (int m = 0; m < bs->steps; m++) in |= sr->meas[m] == k;
            if (!in && sc[k] > out) out = sc[k], outk = k;
        }
        const char *what = mot ? "per-step motion" : "correction (distance from the starting guess to x*)";
        if (bs->steps == 1) fprintf(f, " of steps %d–%d: the step of largest %s (", bs->skip + 1, sr->nref, what);
        else
            fprintf(f, " of steps %d–%d: the %d consecutive steps of largest total %s (", bs->skip + 1, sr->nref,
                    bs->steps, what);
        for (int k = 0; k < bs->steps; k++) fprintf(f, "%s%.3g", k ? ", " : "", sc[sr->meas[k]]);
        fprintf(f, " m RMS");
        if (outk >= 0) fprintf(f, "; the largest outside: step %d, %.3g m", outk + 1, out);
        fprintf(f, ")");
    }
    fprintf(f, "; reference motion over the measured window %.3g m RMS%s.\n\n", sr->win_disp,
            bs->traj_window ? "; trajectory runs start before the first measured step (window)"
                            : "; trajectory runs start at t = 0");
}

/* The fixed-iteration-budget table of a scene: time per frame and trajectory error per
 * budget, beside the own stopping rule's trajectory. */
static void write_fixed_table(FILE *f, const bench_out *b, int si)
{
    const eo_bench_suite *s = b->s;
    const bench_scene_res *sr = b->res + si;
    char a[64], lo[64], hi[64];
    fprintf(f, "Fixed iteration budget over the measured window (steps %d–%d): ms per frame, median (min–max over "
               "the frames) / largest distance to the reference, relative to its motion over the window (%.3g m)%s.\n\n",
            sr->win0 + 1, sr->win1 + 1, sr->win_disp,
            s->o.trajectory ? "; last column: the configuration's own stopping rule (trajectory run: ms per frame / "
                              "largest distance relative to the reference motion over its steps)"
                            : "");
    const bench_scene *bs = s->sc + si;
    fprintf(f, "| configuration |");
    for (int j = 0; j < s->nibud; j++)
        if (bs->ibud_on[j]) fprintf(f, " %d it./frame |", s->ibud[j]);
    if (s->o.trajectory) fprintf(f, " own rule |");
    fprintf(f, "\n|---|");
    for (int j = 0; j < bs->nibud_on + (s->o.trajectory ? 1 : 0); j++) fprintf(f, "---|");
    fprintf(f, "\n");
    for (int c = 0; c < s->ncf; c++) {
        const bench_pair *p = sr->pair + c;
        fprintf(f, "| %s |", s->cf[c].name);
        for (int j = 0; j < s->nibud; j++) {
            const bench_fixed_res *z = p->fixed + j;
            if (!bs->ibud_on[j]) continue;
            if (!z->frames) {
                fprintf(f, " — |");
                continue;
            }
            bench_fmt_ms(z->ms_med, a, sizeof a);
            bench_fmt_ms(z->ms_min, lo, sizeof lo);
            bench_fmt_ms(z->ms_max, hi, sizeof hi);
            if (z->nan) fprintf(f, " %s (%s–%s) / **NaN**", a, lo, hi);
            else fprintf(f, " %s (%s–%s) / %.1e", a, lo, hi, z->max_dist / fmax(sr->win_disp, 1e-300));
            if (z->short_frames)
                fprintf(f, "; %d of %d frame%s stopped early (%s)", z->short_frames, z->frames, z->frames > 1 ? "s" : "",
                        eo_reason_name(z->first_short_reason));
            fprintf(f, " |");
        }
        if (s->o.trajectory) {
            bench_fmt_ms(p->traj_done ? p->traj_time / p->traj_done : NAN, a, sizeof a);
            fprintf(f, " %s / %.1e%s |", a, p->traj_max_dist / fmax(sr->ref_disp, 1e-300),
                    strcmp(p->status, "converged") ? " (not converged)" : "");
        }
        fprintf(f, "\n");
    }
    fprintf(f, "\n");
}

int eo_bench_write_report(eo_ctx *ctx, bench_out *b)
{
    const eo_bench_suite *s = b->s;
    char path[1200], a[64], c1[64], c2[64], lab[32];
    snprintf(path, sizeof path, "%s/report.md", b->dir);
    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    FILE *f = eo_afile_fp(af);
    const int h = bench_headline_thr(s);
    bench_fmt_thr(s->thr[h], lab, sizeof lab);
    char date[64];
    eo_machine mach;
    eo_machine_get(&mach);
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", gmtime(&now));
    fprintf(f, "# Optimizer benchmark: %s\n\n", s->path);
    if (s->o.description[0]) fprintf(f, "%s\n\n", s->o.description);
    fprintf(f, "**Clock: %s.** Every time, ratio and time budget below is in %s (`clock`; curves.csv, "
               "trajectory.csv and fixed.csv record wall and CPU seconds both).\n\n",
            b->wall ? "wall" : "CPU", b->wall ? "elapsed (wall) seconds" :
            "CPU seconds of the thread that solves (CLOCK_THREAD_CPUTIME_ID): they do not grow while the "
            "thread waits for a core, so a shared machine moves them by a few percent where wall time moved 8-9×");
    fprintf(f, "Run %s, %.1f s wall time (%.1f s CPU time of the solving thread), "
               "%d scene(s) × %d configuration(s), %d timed repeat(s) per run unless "
               "a scene says otherwise (median, min–max spread; an untimed warm-up run of at most %d iteration(s) "
               "first). Outputs: `curves.csv`, `summary.csv`, "
               "`reference.csv`, `trajectory.csv`, `fixed.csv`, `plots/`.\n\n",
            date, b->sum->seconds, b->cpu_seconds, s->nsc, s->ncf, b->repeats, s->o.warmup_iters);
    if (s->nskipped) {
        fprintf(f, "**Scenes not run** (optional, their files could not be read):\n\n");
        for (int i = 0; i < s->nskipped; i++) fprintf(f, "- %s\n", s->skipped[i]);
        fprintf(f, "\n");
    }
    fprintf(f, "## Machine and build\n\n");
    fprintf(f, "| | |\n|---|---|\n");
    fprintf(f, "| CPU | %s |\n| cores online | %ld |\n| OpenMP max threads | %d (element loops serial: "
               "eo_step default) |\n",
            mach.cpu, mach.cores, mach.omp_threads);
    fprintf(f, "| OMP_NUM_THREADS / OPENBLAS_NUM_THREADS | %s / %s |\n", env_or("OMP_NUM_THREADS", "unset"),
            env_or("OPENBLAS_NUM_THREADS", "unset"));
    char blas_line[640];
    eo_blas_describe(blas_line, sizeof blas_line);
    fprintf(f, "| BLAS | %s |\n", blas_line + (strncmp(blas_line, "BLAS ", 5) == 0 ? 5 : 0));
    eo_blas_info binfo;
    eo_blas_get(&binfo);
    if (!b->wall && binfo.threads > 1)
        fprintf(f, "| **warning** | the BLAS runs %d threads: thread CPU time misses the work of the others "
                   "(factorizations look cheaper than they are); rerun with one BLAS thread (the CLI's default) "
                   "or `--clock wall` |\n",
                binfo.threads);
    fprintf(f, "| load average at start / end | %s / %s |\n", b->load_start, b->load_end);
    fprintf(f, "| elastopt | %s, build type %s, %s, git %s |\n\n", mach.version, mach.build_type, mach.compiler,
            mach.revision);
    fprintf(f, "## Protocol\n\n"
               "For every scene a reference trajectory is advanced step by step; each step's reference minimizer "
               "x* is Newton + clamp + backtracking stopped at λ²/2 ≤ %g·|g(x₀)| (|g(x₀)| at least ε times the terms "
               "g sums; or at the rounding floor: λ²/2 at the level the rounding of ∇g produces, 1e4·ε²·s₀ of the "
               "objective's rounding scale, or a step that no longer lowers g with λ²/2 ≤ 1e-9·|g(x₀)|). Each "
               "configuration then solves "
               "the same step problems from the same state and starting guess x₀ (the curve runs stop when the "
               "relative energy error (g − g*)/|g₀ − g*| ≤ %g, after %d iterations, after %s s per step "
               "unless the scene says otherwise, or when g has not decreased for 20 iterations: `stagnated`). Time to a threshold is the time of the first "
               "iterate that meets it (iterate k exists when the iteration that produced it, line search "
               "included, has ended; nothing is interpolated between iterates), "
               "summed over the %s measured step(s); \"error at budget\" is the worst step's error of the last "
               "iterate within the budget. Ratios are to the baseline **%s** measured in the same run. "
               "Measured steps: the `steps` after `skip` (select `first`), or the `steps` consecutive ones among "
               "the `horizon` reference steps after `skip` with the largest total per-step motion (`largest_motion`: "
               "mass-weighted RMS of x(tₖ₊₁) − x(tₖ)) or correction (`largest_correction`: mass-weighted RMS distance "
               "from the step's starting guess to x*; it finds impacts); each scene names its steps, and "
               "reference.csv lists both scores for every reference step. The "
               "trajectory runs start from the scene's initial state (or, for a scene with trajectory start "
               "`window`, from the reference state before its first measured step; an untimed warm-up of at most "
               "`warmup_iters` iterations first) and run every step up to the last measured one "
               "with each configuration's own stopping rule, up to the first step that rule does not "
               "meet; their distance to the reference trajectory is the mass-weighted RMS over vertices (the "
               "table gives the largest over the frames run, and the trajectory's total solve time). Step numbers "
               "count from the scene's start. `rel. floor` in the reference table is "
               "2.2e-16·|g|/|g₀ − g*|: relative errors below it are rounding noise.%s\n\n",
            s->o.ref_tol, s->o.target, s->o.max_iters, "the suite's time_budget", "scene's", s->cf[s->baseline].name,
            s->nibud ? " **Fixed iteration budget**: each configuration also runs the measured window (from the "
                       "reference state before the first measured step through the last one) with exactly k "
                       "iterations per frame for each k of `iter_budgets` (stopping rule off; a frame stops "
                       "earlier only on the solver's own failure: line search, stagnation at the rounding level, "
                       "non-finite), after an untimed warm-up; the tables give the median solve time per frame "
                       "(min–max over the frames) and the largest distance to the reference over the window, "
                       "relative to the reference's motion over the window (`fixed.csv` has every frame)."
                     : ""); 
    if (!b->plots) fprintf(f, "Plots were disabled for this run.\n\n");
    else if (!b->gnuplot) fprintf(f, "**gnuplot was not found: no plots** (`apt-get install gnuplot-nox`).\n\n");

    /* ---- headline: one table per accuracy, the headline accuracy first */
    fprintf(f, "## Headline: fastest to relative energy error %s", lab);
    for (int j = 0; j < s->nthr; j++) {
        char l2[32];
        bench_fmt_thr(s->thr[j], l2, sizeof l2);
        if (j != h) fprintf(f, ", %s", l2);
    }
    fprintf(f, "\n\n");
    fprintf(f, "Times are medians (min–max over the repeats; *rep.* = the timed repeats behind each figure). "
               "*Separated* = yes only with at least 3 repeats and non-overlapping [min, max] ranges of the two; "
               "`no` = the order of the two is within the machine's noise; `n/a` = fewer than 3 repeats, too few "
               "to tell. Iterations are those of "
               "the median repeat, summed over the measured steps. *vs baseline* is the baseline's time over the "
               "fastest's (1.00× when the baseline is the fastest).\n\n");
    for (int jj = -1; jj < s->nthr; jj++) {
        const int j = jj < 0 ? h : jj;
        if (jj >= 0 && jj == h) continue;
        char l2[32];
        bench_fmt_thr(s->thr[j], l2, sizeof l2);
        fprintf(f, "### to %s%s\n\n", l2, j == h ? " (headline)" : "");
        fprintf(f, "| scene | rep. | fastest | time (ms) | it. | next best | its time (ms) | it. | ratio | separated | "
                   "baseline time (ms) | vs baseline |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (int si = 0; si < s->nsc; si++) {
            int first, second;
            bench_fastest(b, si, j, &first, &second);
            const bench_pair *P = b->res[si].pair;
            bench_fmt_ms(P[s->baseline].ttt_med[j], a, sizeof a);
            if (first < 0) {
                fprintf(f, "| %s | %d | none reached %s | — | — | — | — | — | — | — | %s | — |\n", s->sc[si].name,
                        b->res[si].repeats, l2, a);
                continue;
            }
            char s1[160], s2[160], vb[32] = "—";
            if (isfinite(P[s->baseline].ttt_med[j]))
                snprintf(vb, sizeof vb, "%.2f×", P[s->baseline].ttt_med[j] / P[first].ttt_med[j]);
            fmt_spread(&P[first], j, b->res[si].repeats, s1, sizeof s1);
            if (second >= 0) {
                fmt_spread(&P[second], j, b->res[si].repeats, s2, sizeof s2);
                fprintf(f, "| %s | %d | **%s** | %s | %d | %s | %s | %d | %.2f× | %s | %s | %s |\n", s->sc[si].name,
                        b->res[si].repeats, s->cf[first].name, s1, bench_pair_iters(&P[first]), s->cf[second].name, s2,
                        bench_pair_iters(&P[second]), P[second].ttt_med[j] / P[first].ttt_med[j],
                        separated(&P[first], &P[second], j, b->res[si].repeats), a, vb);
            } else {
                fprintf(f, "| %s | %d | **%s** | %s | %d | — | — | — | only one | — | %s | %s |\n", s->sc[si].name,
                        b->res[si].repeats, s->cf[first].name, s1, bench_pair_iters(&P[first]), a, vb);
            }
        }
        fprintf(f, "\n");
    }
    if (s->o.trajectory) {
        rc = write_pareto_table(ctx, f, b);
        if (rc < 0) {
            eo_afile_abort(ctx, &af);
            return rc;
        }
    }
    if (b->plots && b->gnuplot && s->o.trajectory)
        fprintf(f, "![speed/accuracy Pareto chart](plots/pareto.png)\n\n");
    rc = eo_bench_write_profile_section(ctx, f, b);
    if (rc < 0) {
        eo_afile_abort(ctx, &af);
        return rc;
    }

    /* ---- stability matrix */
    fprintf(f, "## Status per scene and configuration\n\n"
               "`ok` = converged on every step%s; otherwise the first failing step and its reason; "
               "`elsewhere (x%% off)` = the own stopping rule was satisfied on every step but the trajectory "
               "ended x%% of the reference motion away from the reference (another stationary point); "
               "`non-finite, stopped` = the solver met a non-finite g or ∇g (a divergent run) and stopped cleanly "
               "with finite positions; `NaN` = a NaN was recorded or returned.\n\n",
            s->o.trajectory ? " of the trajectory run (own stopping rule)" : " (curve runs reached the target)");
    fprintf(f, "| configuration |");
    for (int si = 0; si < s->nsc; si++) fprintf(f, " %s |", s->sc[si].name);
    fprintf(f, "\n|---|");
    for (int si = 0; si < s->nsc; si++) fprintf(f, "---|");
    fprintf(f, "\n");
    for (int c = 0; c < s->ncf; c++) {
        fprintf(f, "| %s |", s->cf[c].name);
        for (int si = 0; si < s->nsc; si++) {
            const bench_pair *p = b->res[si].pair + c;
            if (!strcmp(p->status, "converged")) fprintf(f, " ok |");
            else if (p->nan) fprintf(f, " **NaN** |");
            else if (p->nonfinite) fprintf(f, " non-finite, stopped |");
            else if (!strcmp(p->status, "elsewhere"))
                fprintf(f, " elsewhere (%.0f%% off) |", 100 * p->traj_max_dist / fmax(b->res[si].ref_disp, 1e-12));
            else fprintf(f, " %s |", p->reason);
        }
        fprintf(f, "\n");
    }
    fprintf(f, "\n");

    /* ---- per scene */
    fprintf(f, "## Scenes\n\n");
    for (int si = 0; si < s->nsc; si++) {
        const bench_scene *bs = s->sc + si;
        const bench_scene_res *sr = b->res + si;
        char fname[200];
        eo_bench_file_name(bs->name, fname, sizeof fname);
        fprintf(f, "### %s\n\n", bs->name);
        fprintf(f, "%s `%s`", bs->file[0] ? "file" : "built-in scene", bs->file[0] ? bs->o.file : bs->o.scene);
        for (int k = 0; k < bs->nset; k++) fprintf(f, ", `%s`", bs->set[k]);
        fprintf(f, ". %d tets, %d vertices; time budget %g %s s per solve and iteration cap %d (unless a configuration "
                   "sets its own: the same in the curve and the trajectory runs); every time below is the median of "
                   "%d timed repeat(s) (min–max in parentheses when there are more than one).\n\n",
                bs->nt, sr->nv ? sr->nv : bs->nv, bs->time_budget, b->wall ? "wall" : "CPU", bs->max_iters, sr->repeats);
        describe_steps(f, bs, sr);
        if (sr->plotted) fprintf(f, "![%s](plots/%s.png)\n\n", bs->name, fname);
        fprintf(f, "Reference: ");
        for (int k = 0; k < bs->steps; k++) {
            const bench_ref *q = sr->ref + k;
            fprintf(f, "%sstep %d: %d it., %s, λ²/2 = %.1e, rel. floor %.0e", k ? "; " : "", sr->meas[k] + 1, q->iters,
                    q->rounding ? "converged to the rounding floor" : q->converged ? "converged" : eo_reason_name(q->reason),
                    q->dec, q->floor);
            if (q->ip_reason != -1000)
                fprintf(f, " (Ipopt check: %s, %d it., rel. energy diff %.1e, rel. position diff %.1e)",
                        eo_reason_name(q->ip_reason), q->ip_iters, q->ip_de, q->ip_pe);
        }
        fprintf(f, ".\n\nReference state at t = 0 → after the last measured step: min det F %.3g → %.3g, inverted tets "
                   "%d → %d, elastic energy %.4g → %.4g J.\n\n",
                sr->start_minJ, sr->end_minJ, sr->start_inverted, sr->end_inverted, sr->start_elastic, sr->end_elastic);
        fprintf(f, "| configuration | status | it. |");
        for (int j = 0; j < s->nthr; j++) {
            bench_fmt_thr(s->thr[j], a, sizeof a);
            fprintf(f, " t→%s (ms) |", a);
        }
        fprintf(f, " ratio at %s |", lab);
        for (int j = 0; j < s->nbud; j++) fprintf(f, " err@%gs |", s->bud[j]);
        if (s->o.trajectory) fprintf(f, " traj. time (ms) | traj. dist (m) |");
        fprintf(f, "\n|---|---|---|");
        for (int j = 0; j < s->nthr + 1 + s->nbud + (s->o.trajectory ? 2 : 0); j++) fprintf(f, "---|");
        fprintf(f, "\n");
        /* rows sorted by the headline time */
        int order[512];
        int no = s->ncf < 512 ? s->ncf : 512;
        for (int c = 0; c < no; c++) order[c] = c;
        for (int i = 1; i < no; i++)
            for (int j = i; j > 0; j--) {
                double x = sr->pair[order[j]].ttt_med[h], y = sr->pair[order[j - 1]].ttt_med[h];
                if (x < y || (isfinite(x) && !isfinite(y))) {
                    int t = order[j];
                    order[j] = order[j - 1];
                    order[j - 1] = t;
                }
            }
        const bench_pair *base = sr->pair + s->baseline;
        for (int i = 0; i < no; i++) {
            int c = order[i];
            const bench_pair *p = sr->pair + c;
            const char *bold = c == s->baseline ? "**" : "";
            fprintf(f, "| %s%s%s | %s | %d |", bold, s->cf[c].name, bold, p->status, bench_pair_iters(p));
            for (int j = 0; j < s->nthr; j++) {
                bench_fmt_ms(p->ttt_med[j], a, sizeof a);
                if (isfinite(p->ttt_med[j]) && sr->repeats > 1) {
                    bench_fmt_ms(p->ttt_min[j], c1, sizeof c1);
                    bench_fmt_ms(p->ttt_max[j], c2, sizeof c2);
                    fprintf(f, " %s (%s–%s) |", a, c1, c2);
                } else {
                    fprintf(f, " %s |", a);
                }
            }
            if (isfinite(p->ttt_med[h]) && isfinite(base->ttt_med[h]) && base->ttt_med[h] > 0)
                fprintf(f, " %.2f |", p->ttt_med[h] / base->ttt_med[h]);
            else
                fprintf(f, " — |");
            for (int j = 0; j < s->nbud; j++) {
                bench_fmt_sci(p->eab_med[j], a, sizeof a);
                fprintf(f, " %s |", a);
            }
            if (s->o.trajectory) {
                bench_fmt_ms(p->traj_time, a, sizeof a);
                bench_fmt_sci(p->traj_max_dist, c1, sizeof c1);
                fprintf(f, " %s | %s |", a, c1);
            }
            fprintf(f, "\n");
        }
        fprintf(f, "\n");
        if (bs->nibud_on) write_fixed_table(f, b, si);
    }

    /* ---- failures */

    fprintf(f, "## Failures and their reasons\n\n");
    int nf = 0;
    for (int si = 0; si < s->nsc; si++) {
        for (int k = 0; k < b->res[si].nref; k++)
            if (!b->res[si].allref[k].converged) {
                fprintf(f, "- **reference** on %s step %d: %s (λ²/2 = %.2e after %d iterations)\n", s->sc[si].name,
                        k + 1, eo_reason_name(b->res[si].allref[k].reason), b->res[si].allref[k].dec,
                        b->res[si].allref[k].iters);
                nf++;
            }
        for (int c = 0; c < s->ncf; c++) {
            const bench_pair *p = b->res[si].pair + c;
            if (!strcmp(p->status, "converged")) continue;
            fprintf(f, "- %s on %s: %s — %s", s->cf[c].name, s->sc[si].name, p->status, p->reason);
            /* curve run of the failing step, if it is a measured one */
            int m = p->first_bad_step;
            if (s->o.trajectory) { /* trajectory index -> measured index (-1: not a measured step) */
                const int k = p->traj_first + p->first_bad_step;
                m = -1;
                for (int q = 0; q < p->nsteps; q++)
                    if (b->res[si].meas[q] == k) m = q;
            }
            if (p->first_bad_step >= 0 && m >= 0 && m < p->nsteps && strcmp(p->status, "refused") != 0) {
                const bench_step_res *q = p->st + m;
                fprintf(f, " (curve run of that step: %s after %d iterations, rel. error %.1e)",
                        q->reached ? "reached target" : q->stagnated ? "stagnated" : eo_reason_name(q->reason),
                        q->iters, q->final_err);
            }
            fprintf(f, "\n");
            nf++;
        }
    }
    if (!nf) fprintf(f, "None.\n");
    fprintf(f, "\nConverged on every step of every scene%s: ", s->o.trajectory ? " (own stopping rule)" : "");
    int nall = 0;
    for (int c = 0; c < s->ncf; c++) {
        int bad = 0;
        for (int si = 0; si < s->nsc; si++) bad += strcmp(b->res[si].pair[c].status, "converged") != 0;
        if (!bad) fprintf(f, "%s%s", nall++ ? ", " : "", s->cf[c].name);
    }
    fprintf(f, "%s.\n", nall ? "" : "none");
    for (int q = 0; q < s->nreq; q++) {
        int bad = 0;
        for (int si = 0; si < s->nsc; si++) bad += strcmp(b->res[si].pair[s->req[q]].status, "converged") != 0;
        fprintf(f, "\nRequired to converge everywhere: **%s** — %s.\n", s->cf[s->req[q]].name,
                bad ? "FAILED" : "converged on every step of every scene");
    }
    fprintf(f, "\n");

    /* ---- resolved configurations */
    fprintf(f, "## Resolved configurations\n\n");
    fprintf(f, "Caps and budgets are the same in the speed (curve) and the status (trajectory) runs: the iteration "
               "cap is the configuration's own `max_iters` if it sets one (at most the scene's), else the scene's "
               "`max_iters`; the time budget is the configuration's own `time_budget` if it sets one, else the "
               "scene's, in the suite's clock (the harness enforces it; the solver's own wall-clock budget is off). "
               "The curve runs also replace `tol` by 1e-300 (the harness stops them at the target); the trajectory "
               "runs keep every other key as shown.\n\n");
    for (int c = 0; c < s->ncf; c++) fprintf(f, "- `%s`: `%s`\n", s->cf[c].name, s->cf[c].resolved);
    fprintf(f, "\n");
    return eo_afile_commit(ctx, &af);
}

/* The report's "Performance profile" section: per stratum and level, the configuration
 * within 2x of the best time on the most instances (rho(2)), the one fastest on the most
 * (rho(1)), and the share solved at all. */
int eo_bench_write_profile_section(eo_ctx *ctx, FILE *f, const bench_out *b)
{
    const eo_bench_suite *s = b->s;
    const char *names[64];
    const int nst = bench_prof_strata(s, names, 64);
    const int npmax = bench_prof_ninstances(s);
    double *t = eo_malloc(ctx, ((size_t)npmax * s->ncf + npmax + 1) * sizeof(double));
    if (!t) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    double *tg = t + (size_t)npmax * s->ncf;
    fprintf(f, "## Performance profile\n\n"
               "Convergence criterion, the same for every method: relative energy error (g − g*)/|g₀ − g*| ≤ level, "
               "g* the reference minimizer's energy (above), at the first iterate that meets it. Instances: the "
               "measured steps (%d in all). Cost: the median over the timed repeats of the time (%s) to that "
               "iterate. **Performance profile** (Dolan–Moré): ρ(τ) = share of the instances a configuration solves "
               "within τ × the best configuration's time on that instance; **data profile** (Moré–Wild): share "
               "solved within κ gradient-equivalents, one gradient-equivalent being the time of one gradient "
               "evaluation of that step's objective at its starting guess (median of 5, same clock). Every curve: "
               "`perf_profile.csv`, `data_profile.csv`%s. *Within 2×* = the configuration with the largest ρ(2); "
               "*fastest* = the largest ρ(1) (the share of instances where it was the fastest); ties list every "
               "configuration.\n\n",
            npmax, b->wall ? "wall seconds" : "CPU seconds of the solving thread",
            b->plots && b->gnuplot ? ", plots `plots/perf_profile-<stratum>.png`/`.svg` and "
                                     "`plots/data_profile-<stratum>.png`/`.svg`"
                                   : "");
    fprintf(f, "| stratum | level | instances | within 2× of the best on the most | ρ(2) | fastest on the most | ρ(1) | "
               "solved by any |\n|---|---|---|---|---|---|---|---|\n");
    for (int q = 0; q < nst; q++)
        for (int j = 0; j < s->nthr; j++) {
            const int np = bench_prof_costs(b, q, names, j, t, tg);
            double best2 = -1, best1 = -1;
            for (int c = 0; c < s->ncf; c++) {
                best2 = fmax(best2, bench_prof_rho(t, np, s->ncf, c, 2));
                best1 = fmax(best1, bench_prof_rho(t, np, s->ncf, c, 1));
            }
            int any = 0;
            for (int p = 0; p < np; p++) {
                int solved = 0;
                for (int c = 0; c < s->ncf; c++) solved |= isfinite(t[(size_t)p * s->ncf + c]);
                any += solved;
            }
            fprintf(f, "| %s | %.0e | %d | ", names[q], s->thr[j], np);
            int k = 0;
            for (int c = 0; c < s->ncf; c++)
                if (best2 > 0 && bench_prof_rho(t, np, s->ncf, c, 2) == best2) fprintf(f, "%s%s", k++ ? ", " : "", s->cf[c].name);
            fprintf(f, "%s | %.2f | ", k ? "" : "none", best2 > 0 ? best2 : 0.0);
            k = 0;
            for (int c = 0; c < s->ncf; c++)
                if (best1 > 0 && bench_prof_rho(t, np, s->ncf, c, 1) == best1) fprintf(f, "%s%s", k++ ? ", " : "", s->cf[c].name);
            fprintf(f, "%s | %.2f | %d/%d |\n", k ? "" : "none", best1 > 0 ? best1 : 0.0, any, np);
        }
    fprintf(f, "\n");
    if (b->plots && b->gnuplot)
        for (int q = 0; q < nst; q++) {
            char fname[160];
            eo_bench_file_name(names[q], fname, sizeof fname);
            fprintf(f, "![performance profile, %s](plots/perf_profile-%s.png)\n\n", names[q], fname);
            fprintf(f, "![data profile, %s](plots/data_profile-%s.png)\n\n", names[q], fname);
        }
    eo_free(ctx, t);
    return EO_OK;
}
