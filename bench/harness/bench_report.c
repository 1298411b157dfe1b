/* Benchmark outputs (bench.h): summary.csv, report.md and the gnuplot plots.
 *
 *   summary.csv   one row per (scene, configuration): status and reason, time to each
 *                 threshold (median, min, max of the repeats, summed over the measured
 *                 steps), ratio to the baseline, error at each time budget (worst step),
 *                 trajectory results
 *   report.md     machine, build, protocol, headline (fastest to 1e-6 per scene and its
 *                 ratio over the next best), stability matrix, per-scene tables with the
 *                 plots, failures with reasons, resolved configurations
 *   plots/        <scene>.png: relative energy error against time (log-log), one line
 *                 per configuration (every measured step, same colour); pareto.png:
 *                 trajectory time (ratio to baseline) against trajectory error, both
 *                 geometric means over the scenes. The .gp scripts and .dat data stay
 *                 next to them so a plot can be remade with `gnuplot plots/x.gp`.
 * The `png` terminal (libgd, 8-bit palette) is used rather than pngcairo: the plots are
 * committed and its files are 5x smaller. gnuplot (Debian package gnuplot-nox) is run as a separate process; without it the
 * report says so and everything else is written. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bench_impl.h"
#include "elastopt/io.h"
#include "elastopt/machine.h"

int eo_bench_keep_row(int k, int n, int full_rows)
{
    if (full_rows <= 0 || k <= full_rows || k == n - 1) return 1;
    return floor(50 * log10((double)k)) != floor(50 * log10((double)(k - 1)));
}

void eo_bench_file_name(const char *name, char *buf, size_t n)
{
    size_t k = 0;
    for (; *name && k + 1 < n; name++) {
        char c = *name;
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
                 c == '.';
        buf[k++] = ok ? c : '_';
    }
    buf[k] = 0;
}

/* Index of the headline threshold: 1e-6 if listed, else the tightest. */
static int headline_thr(const eo_bench_suite *s)
{
    for (int j = 0; j < s->nthr; j++)
        if (fabs(s->thr[j] - 1e-6) < 1e-12) return j;
    int best = 0;
    for (int j = 1; j < s->nthr; j++)
        if (s->thr[j] < s->thr[best]) best = j;
    return best;
}

static void fmt_thr(double t, char *buf, size_t n) { snprintf(buf, n, "%.0e", t); }

static void fmt_ms(double t, char *buf, size_t n)
{
    if (!isfinite(t)) snprintf(buf, n, "—");
    else if (t < 0.01) snprintf(buf, n, "%.3f", 1e3 * t);
    else snprintf(buf, n, "%.4g", 1e3 * t);
}

static void fmt_sci(double v, char *buf, size_t n)
{
    if (isnan(v)) snprintf(buf, n, "—");
    else snprintf(buf, n, "%.1e", v);
}


static int pair_iters(const bench_pair *p)
{
    int n = 0;
    for (int k = 0; k < p->nsteps; k++) n += p->st[k].iters;
    return n;
}

/* "median (min–max)" of the time to threshold j, in ms. */
static void fmt_spread(const bench_pair *p, int j, int repeats, char *buf, size_t n)
{
    char a[32], lo[32], hi[32];
    fmt_ms(p->ttt_med[j], a, sizeof a);
    if (!isfinite(p->ttt_med[j]) || repeats < 2) {
        snprintf(buf, n, "%s", a);
        return;
    }
    fmt_ms(p->ttt_min[j], lo, sizeof lo);
    fmt_ms(p->ttt_max[j], hi, sizeof hi);
    snprintf(buf, n, "%s (%s–%s)", a, lo, hi);
}

/* Fastest and second fastest configuration of a scene at threshold j (-1 if none). */
static void fastest(const bench_out *b, int si, int j, int *first, int *second)
{
    *first = *second = -1;
    const bench_scene_res *sr = b->res + si;
    for (int c = 0; c < b->s->ncf; c++) {
        double t = sr->pair[c].ttt_med[j];
        if (!isfinite(t)) continue;
        if (*first < 0 || t < sr->pair[*first].ttt_med[j]) {
            *second = *first;
            *first = c;
        } else if (*second < 0 || t < sr->pair[*second].ttt_med[j]) {
            *second = c;
        }
    }
}

int eo_bench_write_summary(eo_ctx *ctx, bench_out *b)
{
    const eo_bench_suite *s = b->s;
    char path[1200], lab[32];
    snprintf(path, sizeof path, "%s/summary.csv", b->dir);
    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    FILE *f = eo_afile_fp(af);
    fprintf(f, "scene,config,baseline,tets,steps,status,reason,steps_reached,iterations");
    for (int j = 0; j < s->nthr; j++) {
        fmt_thr(s->thr[j], lab, sizeof lab);
        fprintf(f, ",t_%s_median,t_%s_min,t_%s_max,ratio_%s", lab, lab, lab, lab);
    }
    for (int j = 0; j < s->nbud; j++) fprintf(f, ",err_at_%gs", s->bud[j]);
    fprintf(f, ",final_rel_err,traj_converged,traj_time,traj_max_dist,traj_final_dist\n");
    for (int si = 0; si < s->nsc; si++) {
        const bench_scene_res *sr = b->res + si;
        const bench_pair *base = sr->pair + s->baseline;
        for (int c = 0; c < s->ncf; c++) {
            const bench_pair *p = sr->pair + c;
            int iters = 0;
            double fe = -INFINITY;
            for (int k = 0; k < p->nsteps; k++) {
                iters += p->st[k].iters;
                fe = fmax(fe, p->st[k].final_err);
            }
            fprintf(f, "%s,%s,%d,%d,%d,%s,\"%s\",%d,%d", s->sc[si].name, s->cf[c].name, c == s->baseline,
                    s->sc[si].nt, p->nsteps, p->status, p->reason, p->steps_reached, iters);
            for (int j = 0; j < s->nthr; j++) {
                eo_bench_csv_num(f, p->ttt_med[j]);
                eo_bench_csv_num(f, p->ttt_min[j]);
                eo_bench_csv_num(f, p->ttt_max[j]);
                double ratio = isfinite(p->ttt_med[j]) && isfinite(base->ttt_med[j]) && base->ttt_med[j] > 0
                                   ? p->ttt_med[j] / base->ttt_med[j]
                                   : NAN;
                eo_bench_csv_num(f, ratio);
            }
            for (int j = 0; j < s->nbud; j++) eo_bench_csv_num(f, p->eab_med[j]);
            eo_bench_csv_num(f, fe);
            fprintf(f, ",%d", p->traj_converged);
            eo_bench_csv_num(f, s->o.trajectory ? p->traj_time : NAN);
            eo_bench_csv_num(f, s->o.trajectory ? p->traj_max_dist : NAN);
            eo_bench_csv_num(f, s->o.trajectory ? p->traj_final_dist : NAN);
            fputc('\n', f);
        }
    }
    /* reference.csv next to it */
    rc = eo_afile_commit(ctx, &af);
    if (rc < 0) return rc;
    snprintf(path, sizeof path, "%s/reference.csv", b->dir);
    rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    f = eo_afile_fp(af);
    fprintf(f, "scene,step,t,n,iterations,reason,converged,rounding_floor,solve_time,g0,gstar,decrement,rel_err_floor,"
               "ipopt_reason,ipopt_iterations,ipopt_time,ipopt_rel_energy_diff,ipopt_rel_pos_diff\n");
    for (int si = 0; si < s->nsc; si++)
        for (int k = 0; k < s->sc[si].steps; k++) {
            const bench_ref *q = b->res[si].ref + k;
            fprintf(f, "%s,%d,%.6g,%d,%d,%s,%d,%d", s->sc[si].name, k + 1, q->t, q->n, q->iters,
                    eo_reason_name(q->reason), q->converged, q->rounding);
            eo_bench_csv_num(f, q->time);
            fprintf(f, ",%.17g,%.17g", q->g0, q->gstar);
            eo_bench_csv_num(f, q->dec);
            eo_bench_csv_num(f, q->floor);
            if (q->ip_reason == -1000) fputs(",,,,,", f);
            else {
                fprintf(f, ",%s,%d", eo_reason_name(q->ip_reason), q->ip_iters);
                eo_bench_csv_num(f, q->ip_time);
                eo_bench_csv_num(f, q->ip_de);
                eo_bench_csv_num(f, q->ip_pe);
            }
            fputc('\n', f);
        }
    return eo_afile_commit(ctx, &af);
}

/* ---------------------------------------------------------------- plots */

/* Colour by optimizer family (the optimizer's name, in order of first appearance in the
 * suite, so every plot of a report uses the same colour for it), dash type by line
 * search, point type by Hessian fix; the baseline is black. */
static const char *const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
                                      "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
#define NPAL ((int)(sizeof palette / sizeof palette[0]))
#define MAX_HIGHLIGHT 8

typedef struct cfg_style {
    int family, ls, fix;      /* indices in order of first appearance */
    char opt[64];             /* optimizer name */
} cfg_style;

static void resolved_name(const char *resolved, const char *key, char *buf, size_t n)
{
    snprintf(buf, n, "?");
    json_t *j = resolved ? json_loads(resolved, 0, NULL) : NULL;
    const char *v = j ? json_string_value(json_object_get(j, key)) : NULL;
    if (v) snprintf(buf, n, "%s", v);
    json_decref(j);
}

/* styles of every configuration (st: ncf entries) */
static void cfg_styles(const eo_bench_suite *s, cfg_style *st)
{
    char names[3][64][64];
    int nn[3] = {0, 0, 0};
    static const char *const keys[3] = {"optimizer", "linesearch", "hessian_fix"};
    for (int c = 0; c < s->ncf; c++) {
        int idx[3];
        for (int k = 0; k < 3; k++) {
            char v[64];
            resolved_name(s->cf[c].resolved, keys[k], v, sizeof v);
            if (k == 2 && !s->cf[c].needs_hessian) snprintf(v, sizeof v, "-");
            int i = 0;
            while (i < nn[k] && strcmp(names[k][i], v) != 0) i++;
            if (i == nn[k] && nn[k] < 64) snprintf(names[k][nn[k]++], 64, "%s", v);
            idx[k] = i;
            if (k == 0) snprintf(st[c].opt, sizeof st[c].opt, "%s", v);
        }
        st[c].family = idx[0];
        st[c].ls = idx[1];
        st[c].fix = idx[2];
    }
}

static const char *style_colour(const eo_bench_suite *s, const cfg_style *st, int c)
{
    return c == s->baseline ? "#000000" : palette[st[c].family % NPAL];
}

/* The configurations drawn in colour on a scene's plot: the baseline, the fastest at the
 * headline accuracy, and the best of each optimizer family (fastest to the headline, else
 * to the loosest threshold it reached), at most MAX_HIGHLIGHT; the rest are thin grey. */
static void pick_highlight(const bench_out *b, int si, int h, const cfg_style *st, int first, unsigned char *hl)
{
    const eo_bench_suite *s = b->s;
    const bench_scene_res *sr = b->res + si;
    memset(hl, 0, (size_t)s->ncf);
    int n = 0;
    hl[s->baseline] = 1;
    n++;
    if (first >= 0 && !hl[first]) hl[first] = 1, n++;
    /* score: (threshold index reached, time): tighter thresholds first, then faster */
    for (int pass = 0; pass < s->ncf && n < MAX_HIGHLIGHT; pass++) {
        int best = -1, bestj = -1;
        double bestt = INFINITY;
        for (int c = 0; c < s->ncf; c++) {
            if (hl[c]) continue;
            int fam_done = 0;
            for (int d = 0; d < s->ncf; d++)
                if (hl[d] && d != s->baseline && st[d].family == st[c].family) fam_done = 1;
            if (fam_done) continue;
            int jr = -1;
            for (int j = 0; j < s->nthr; j++)
                if (isfinite(sr->pair[c].ttt_med[j])) jr = j;
            double t = jr >= 0 ? sr->pair[c].ttt_med[jr < h ? jr : h] : INFINITY;
            if (jr > h) jr = h;
            if (best < 0 || jr > bestj || (jr == bestj && t < bestt)) best = c, bestj = jr, bestt = t;
        }
        if (best < 0) break;
        hl[best] = 1;
        n++;
    }
}

static int run_gnuplot(eo_ctx *ctx, const char *dir, const char *name)
{
    char cmd[3000];
    if (strchr(dir, '\'') || strchr(name, '\''))
        return eo_error(ctx, EO_ERR_INVALID, "plot: a quote in the output path");
    snprintf(cmd, sizeof cmd, "cd '%s/plots' && gnuplot '%s.gp' > '%s.log' 2>&1", dir, name, name);
    int st = system(cmd);
    if (st != 0) return eo_error(ctx, EO_ERR_IO, "gnuplot failed on %s/plots/%s.gp (see %s.log)", dir, name, name);
    char log[1500];
    snprintf(log, sizeof log, "%s/plots/%s.log", dir, name);
    FILE *lf = fopen(log, "rb");
    long sz = 0;
    if (lf) {
        fseek(lf, 0, SEEK_END);
        sz = ftell(lf);
        fclose(lf);
    }
    if (sz == 0) remove(log);
    return EO_OK;
}

int eo_bench_plot_scene(eo_ctx *ctx, bench_out *b, int si)
{
    const eo_bench_suite *s = b->s;
    const bench_scene *bs = s->sc + si;
    const bench_scene_res *sr = b->res + si;
    char name[200], path[1400], lab[32];
    eo_bench_file_name(bs->name, name, sizeof name);
    snprintf(path, sizeof path, "%s/plots/%s.gp", b->dir, name);
    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    FILE *f = eo_afile_fp(af);
    int h = headline_thr(s), first, second;
    fastest(b, si, h, &first, &second);
    fmt_thr(s->thr[h], lab, sizeof lab);
    char title[600];
    if (first >= 0 && second >= 0)
        snprintf(title, sizeof title, "fastest to %s: %s (%.2fx faster than %s)", lab, s->cf[first].name,
                 sr->pair[second].ttt_med[h] / sr->pair[first].ttt_med[h], s->cf[second].name);
    else if (first >= 0)
        snprintf(title, sizeof title, "fastest to %s: %s (the only one)", lab, s->cf[first].name);
    else
        snprintf(title, sizeof title, "no configuration reached %s", lab);
    cfg_style *sty = eo_malloc(ctx, (size_t)s->ncf * sizeof *sty);
    unsigned char *hl = eo_malloc(ctx, (size_t)s->ncf);
    if (!sty || !hl) {
        eo_free(ctx, sty);
        eo_free(ctx, hl);
        eo_afile_abort(ctx, &af);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (plot styles)");
    }
    cfg_styles(s, sty);
    pick_highlight(b, si, h, sty, first, hl);
    int nother = 0;
    for (int c = 0; c < s->ncf; c++) nother += !hl[c];
    fprintf(f, "# %s: relative energy error against solve time\n", bs->name);
    fprintf(f, "# colour = optimizer family (baseline black), dash = line search, point = Hessian fix;\n"
               "# in colour: the baseline, the fastest and the best of each family (at most %d)\n",
            MAX_HIGHLIGHT);
    fprintf(f, "set terminal png size 1400,850 font 'DejaVu Sans,11' noenhanced\n");
    fprintf(f, "set output '%s.png'\n", name);
    fprintf(f, "set title \"%s: %d tets, %s E=%g nu=%g, %d step(s), median of %d\\n%s\"\n", bs->name, bs->nt, bs->model,
            bs->E, bs->nu, bs->steps, sr->repeats, title);
    double left = isfinite(sr->tmin) ? pow(10, floor(log10(sr->tmin))) : 1e-4;
    fprintf(f, "left = %g  # the start point x0 (time 0) is drawn at the left edge\n", left);
    fprintf(f, "set xrange [left:*]\n");
    fprintf(f, "set logscale xy\nset grid xtics ytics mxtics mytics lc rgb '#e5e5e5'\n");
    fprintf(f, "set format y '1e%%L'\nset format x '%%g'\n");
    fprintf(f, "set xlabel 'solve time of the step (s), median of the timed repeats'\n");
    fprintf(f, "set ylabel 'relative energy error (g - g*) / |g0 - g*|'\n");
    fprintf(f, "set yrange [%g:3]\n", s->o.target / 10);
    fprintf(f, "set key inside left bottom opaque box spacing 1.05 font ',10'\n");
    for (int j = 0; j < s->nthr; j++) {
        fprintf(f, "set arrow from graph 0, first %g to graph 1, first %g nohead lc rgb '#999999' dt 3\n", s->thr[j],
                s->thr[j]);
        fprintf(f, "set label '%.0e' at graph 1, first %g offset char 0.5,0 left font ',9' tc rgb '#777777'\n",
                s->thr[j], s->thr[j]);
    }
    fprintf(f, "set rmargin 8\n");
    fprintf(f, "plot \\\n");
    int any = 0, grey_titled = 0;
    /* grey ones first (underneath), then the highlighted ones */
    for (int pass = 0; pass < 2; pass++)
        for (int c = 0; c < s->ncf; c++) {
            if (hl[c] != pass) continue;
            const char *col = hl[c] ? style_colour(s, sty, c) : "#c8c8c8";
            int dt = hl[c] ? 1 + sty[c].ls % 5 : 1;
            int pt = hl[c] ? (int[]){7, 5, 9, 11, 13, 15}[sty[c].fix % 6] : 7;
            double lw = !hl[c] ? 0.8 : c == first ? 3.2 : c == s->baseline ? 2.4 : 1.8;
            for (int k = 0; k < bs->steps; k++) {
                char t[300];
                if (k == 0 && hl[c])
                    snprintf(t, sizeof t, "title '%s%s%s'", s->cf[c].name, c == s->baseline ? " (baseline)" : "",
                             c == first ? " (fastest)" : "");
                else if (k == 0 && !grey_titled) {
                    snprintf(t, sizeof t, "title '%d other configuration%s'", nother, nother == 1 ? "" : "s");
                    grey_titled = 1;
                } else
                    snprintf(t, sizeof t, "notitle");
                fprintf(f, "%s  '%s.dat' index %d using ($1>0?$1:left):2 with linespoints lc rgb '%s' dt %d lw %.1f "
                           "pt %d ps %.1f %s",
                        any ? ", \\\n" : "", name, c * bs->steps + k, col, dt, lw, pt, hl[c] ? 0.6 : 0.2, t);
                any = 1;
            }
        }
    fprintf(f, "\nset terminal svg size 1400,850 font 'DejaVu Sans,11' noenhanced\n");
    fprintf(f, "set output '%s.svg'\nreplot\n", name);
    eo_free(ctx, sty);
    eo_free(ctx, hl);
    fprintf(f, "\n");
    rc = eo_afile_commit(ctx, &af);
    if (rc < 0) return rc;
    rc = run_gnuplot(ctx, b->dir, name);
    if (rc >= 0) b->res[si].plotted = 1;
    return rc;
}

/* Pareto chart over all scenes: x = geometric mean of the trajectory solve time per step
 * run / the baseline's (a trajectory stops at its first failing step, so the time per
 * step compares runs of different lengths), y = geometric mean of the max trajectory
 * distance / the reference displacement. */
int eo_bench_plot_pareto(eo_ctx *ctx, bench_out *b)
{
    const eo_bench_suite *s = b->s;
    if (!s->o.trajectory) return EO_ERR_UNSUPPORTED;
    char path[1400];
    snprintf(path, sizeof path, "%s/plots/pareto.dat", b->dir);
    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    FILE *f = eo_afile_fp(af);
    fprintf(f, "# number  time_ratio_geomean  rel_traj_err_geomean (clipped to 100)  all_converged  scenes  config\n");
    double *xs = eo_malloc(ctx, 2 * (size_t)s->ncf * sizeof(double));
    int *ok = eo_calloc(ctx, (size_t)s->ncf, sizeof(int));
    if (!xs || !ok) {
        eo_free(ctx, xs);
        eo_free(ctx, ok);
        eo_afile_abort(ctx, &af);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    }
    double *ys = xs + s->ncf;
    for (int c = 0; c < s->ncf; c++) {
        double lx = 0, ly = 0;
        int n = 0, conv = 1;
        for (int si = 0; si < s->nsc; si++) {
            const bench_pair *p = b->res[si].pair + c, *base = b->res[si].pair + s->baseline;
            conv &= strcmp(p->status, "converged") == 0;
            if (!(p->traj_time > 0) || !(base->traj_time > 0) || !isfinite(p->traj_max_dist) || p->traj_done < 1 ||
                base->traj_done < 1)
                continue;
            double d = p->traj_max_dist / fmax(b->res[si].ref_disp, 1e-12);
            lx += log((p->traj_time / p->traj_done) / (base->traj_time / base->traj_done));
            ly += log(fmax(d, 1e-16));
            n++;
        }
        xs[c] = n ? exp(lx / n) : NAN;
        ys[c] = n ? exp(ly / n) : NAN;
        ok[c] = conv;
        if (n) fprintf(f, "%d %.6e %.6e %d %d \"%s\"\n", c + 1, xs[c], fmin(ys[c], 100), conv, n, s->cf[c].name);
    }
    fprintf(f, "\n\n# Pareto front among the configurations that converged everywhere (none of them is both "
               "faster and more accurate)\n");
    for (int c = 0; c < s->ncf; c++) { /* sorted by time: the candidates in order of x */
        int best = -1;
        for (int d = 0; d < s->ncf; d++) {
            if (ok[d] != 1 || isnan(xs[d])) continue;
            if (best < 0 || xs[d] < xs[best]) best = d;
        }
        if (best < 0) break;
        ok[best] = 2; /* visited */
        int dominated = 0;
        for (int d = 0; d < s->ncf; d++)
            if (d != best && ok[d] >= 1 && !isnan(xs[d]) && xs[d] <= xs[best] && ys[d] <= ys[best] &&
                (xs[d] < xs[best] || ys[d] < ys[best]))
                dominated = 1;
        if (!dominated) fprintf(f, "%.6e %.6e\n", xs[best], fmin(ys[best], 100));
    }
    eo_free(ctx, xs);
    eo_free(ctx, ok);
    rc = eo_afile_commit(ctx, &af);
    if (rc < 0) return rc;
    snprintf(path, sizeof path, "%s/plots/pareto.gp", b->dir);
    rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    f = eo_afile_fp(af);
    fprintf(f, "set terminal png size 1500,950 font 'DejaVu Sans,11' noenhanced\n");
    fprintf(f, "set output 'pareto.png'\n");
    fprintf(f, "set rmargin at screen 0.70\n");
    fprintf(f, "# configurations by number (points are labelled with the number)\n");
    for (int c = 0; c < s->ncf; c++)
        fprintf(f, "set label %d \"%2d  %s\" at screen 0.72, screen %.4f left font ',10'\n", c + 1, c + 1,
                s->cf[c].name, 0.92 - 0.8 * c / (s->ncf > 20 ? s->ncf : 20));
    fprintf(f, "set title \"Speed against accuracy over %d scene(s), each configuration with its own stopping rule\\n"
               "lower left is better; the line joins the Pareto-optimal configurations\"\n", s->nsc);
    fprintf(f, "set logscale xy\nset grid lc rgb '#dddddd'\nset format y '1e%%L'\n");
    fprintf(f, "set xlabel \"traj. time per step / baseline's (%s): the report's 'traj. time' column, own stopping "
               "rule, geometric mean over scenes (not the headline's time to an accuracy)\"\n",
            s->cf[s->baseline].name);
    fprintf(f, "set ylabel \"traj. dist / reference displacement: the 'traj. dist' column (geometric mean; clipped "
               "at 100)\"\n");
    fprintf(f, "set key top left box opaque\nset offsets graph 0.05, graph 0.1, graph 0.1, graph 0.05\n");

    fprintf(f, "plot 'pareto.dat' index 1 using 1:2 with lines lc rgb '#999999' lw 2 title 'Pareto front of the converged configurations', \\\n"
               "  'pareto.dat' index 0 using ($4==1?$2:1/0):3 with points pt 7 ps 1.6 lc rgb '#1f77b4' "
               "title 'converged on every step of every scene', \\\n"
               "  'pareto.dat' index 0 using ($4==0?$2:1/0):3 with points pt 9 ps 1.6 lc rgb '#d62728' "
               "title 'failed or stopped somewhere', \\\n"
               "  'pareto.dat' index 0 using 2:3:(sprintf('%%d', $1)) with labels offset char 0.9,0.5 left font ',9' "
               "notitle\n");
    fprintf(f, "set terminal svg size 1500,950 font 'DejaVu Sans,11' noenhanced\nset output 'pareto.svg'\nreplot\n");
    rc = eo_afile_commit(ctx, &af);
    if (rc < 0) return rc;
    return run_gnuplot(ctx, b->dir, "pareto");
}

/* ---------------------------------------------------------------- report.md */

static const char *env_or(const char *name, const char *def)
{
    const char *v = getenv(name);
    return v && *v ? v : def;
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
    const int h = headline_thr(s);
    fmt_thr(s->thr[h], lab, sizeof lab);
    char date[64];
    eo_machine mach;
    eo_machine_get(&mach);
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", gmtime(&now));
    fprintf(f, "# Optimizer benchmark: %s\n\n", s->path);
    if (s->o.description[0]) fprintf(f, "%s\n\n", s->o.description);
    fprintf(f, "Run %s, %.1f s wall time, %d scene(s) × %d configuration(s), %d timed repeat(s) per run unless "
               "a scene says otherwise (median, min–max spread; an untimed warm-up run of at most %d iteration(s) "
               "first). Outputs: `curves.csv`, `summary.csv`, "
               "`reference.csv`, `trajectory.csv`, `plots/`.\n\n",
            date, b->sum->seconds, s->nsc, s->ncf, b->repeats, s->o.warmup_iters);
    fprintf(f, "## Machine and build\n\n");
    fprintf(f, "| | |\n|---|---|\n");
    fprintf(f, "| CPU | %s |\n| cores online | %ld |\n| OpenMP max threads | %d (element loops serial: "
               "eo_step default) |\n",
            mach.cpu, mach.cores, mach.omp_threads);
    fprintf(f, "| OMP_NUM_THREADS / OPENBLAS_NUM_THREADS | %s / %s |\n", env_or("OMP_NUM_THREADS", "unset"),
            env_or("OPENBLAS_NUM_THREADS", "unset"));
    fprintf(f, "| load average at start / end | %s / %s |\n", b->load_start, b->load_end);
    fprintf(f, "| elastopt | %s, build type %s, %s, git %s |\n\n", mach.version, mach.build_type, mach.compiler,
            mach.revision);
    fprintf(f, "## Protocol\n\n"
               "For every scene a reference trajectory is advanced step by step; each step's reference minimizer "
               "x* is Newton + clamp + backtracking stopped at λ²/2 ≤ %g·|g(x₀)| (or at the rounding floor: a step that "
               "no longer lowers g with λ²/2 ≤ 1e-9·|g(x₀)|). Each configuration then solves "
               "the same step problems from the same state and starting guess x₀ (the curve runs stop when the "
               "relative energy error (g − g*)/|g₀ − g*| ≤ %g, after %d iterations, after %s s per step "
               "unless the scene says otherwise, or when g has not decreased for 20 iterations: `stagnated`). Times to a threshold are log-interpolated between iterates and "
               "summed over the %s measured step(s); \"error at budget\" is the worst step's error of the last "
               "iterate within the budget. Ratios are to the baseline **%s** measured in the same run. The "
               "trajectory runs start from the scene's initial state and run every step of the scene (skipped and "
               "measured) with each configuration's own stopping rule, up to the first step that rule does not "
               "meet; their distance to the reference trajectory is the mass-weighted RMS over vertices (the "
               "table gives the largest over the frames run, and the trajectory's total solve time). Step numbers "
               "in the status table count from the scene's start. `rel. floor` in the reference table is "
               "2.2e-16·|g|/|g₀ − g*|: relative errors below it are rounding noise.\n\n",
            s->o.ref_tol, s->o.target, s->o.max_iters, "the suite's time_budget", "scene's", s->cf[s->baseline].name);
    if (!b->plots) fprintf(f, "Plots were disabled for this run.\n\n");
    else if (!b->gnuplot) fprintf(f, "**gnuplot was not found: no plots** (`apt-get install gnuplot-nox`).\n\n");

    /* ---- headline: one table per accuracy, the headline accuracy first */
    fprintf(f, "## Headline: fastest to relative energy error %s", lab);
    for (int j = 0; j < s->nthr; j++) {
        char l2[32];
        fmt_thr(s->thr[j], l2, sizeof l2);
        if (j != h) fprintf(f, ", %s", l2);
    }
    fprintf(f, "\n\n");
    fprintf(f, "Times are medians (min–max over the repeats). *Separated* says whether the two spreads do not "
               "overlap; when they do, the order of the two is within the machine's noise. Iterations are those of "
               "the median repeat, summed over the measured steps. *vs baseline* is the baseline's time over the "
               "fastest's (1.00× when the baseline is the fastest).\n\n");
    for (int jj = -1; jj < s->nthr; jj++) {
        const int j = jj < 0 ? h : jj;
        if (jj >= 0 && jj == h) continue;
        char l2[32];
        fmt_thr(s->thr[j], l2, sizeof l2);
        fprintf(f, "### to %s%s\n\n", l2, j == h ? " (headline)" : "");
        fprintf(f, "| scene | fastest | time (ms) | it. | next best | its time (ms) | it. | ratio | separated | "
                   "baseline time (ms) | vs baseline |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (int si = 0; si < s->nsc; si++) {
            int first, second;
            fastest(b, si, j, &first, &second);
            const bench_pair *P = b->res[si].pair;
            fmt_ms(P[s->baseline].ttt_med[j], a, sizeof a);
            if (first < 0) {
                fprintf(f, "| %s | none reached %s | — | — | — | — | — | — | — | %s | — |\n", s->sc[si].name, l2, a);
                continue;
            }
            char s1[160], s2[160], vb[32] = "—";
            if (isfinite(P[s->baseline].ttt_med[j]))
                snprintf(vb, sizeof vb, "%.2f×", P[s->baseline].ttt_med[j] / P[first].ttt_med[j]);
            fmt_spread(&P[first], j, b->res[si].repeats, s1, sizeof s1);
            if (second >= 0) {
                fmt_spread(&P[second], j, b->res[si].repeats, s2, sizeof s2);
                int sep = P[first].ttt_max[j] < P[second].ttt_min[j];
                fprintf(f, "| %s | **%s** | %s | %d | %s | %s | %d | %.2f× | %s | %s | %s |\n", s->sc[si].name,
                        s->cf[first].name, s1, pair_iters(&P[first]), s->cf[second].name, s2,
                        pair_iters(&P[second]), P[second].ttt_med[j] / P[first].ttt_med[j], sep ? "yes" : "no", a,
                        vb);
            } else {
                fprintf(f, "| %s | **%s** | %s | %d | — | — | — | only one | — | %s | %s |\n", s->sc[si].name,
                        s->cf[first].name, s1, pair_iters(&P[first]), a, vb);
            }
        }
        fprintf(f, "\n");
    }
    if (b->plots && b->gnuplot && s->o.trajectory)
        fprintf(f, "![speed/accuracy Pareto chart](plots/pareto.png)\n\n");

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
        fprintf(f, ". %d tets, %d vertices; %d measured step(s) after %d skipped; time budget %g s per solve "
                   "(unless a configuration sets its own); %d timed repeat(s).\n\n",
                bs->nt, bs->nv, bs->steps, bs->skip, bs->time_budget, sr->repeats);
        if (sr->plotted) fprintf(f, "![%s](plots/%s.png)\n\n", bs->name, fname);
        fprintf(f, "Reference: ");
        for (int k = 0; k < bs->steps; k++) {
            const bench_ref *q = sr->ref + k;
            fprintf(f, "%sstep %d: %d it., %s, λ²/2 = %.1e, rel. floor %.0e", k ? "; " : "", k + 1, q->iters,
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
            fmt_thr(s->thr[j], a, sizeof a);
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
            fprintf(f, "| %s%s%s | %s | %d |", bold, s->cf[c].name, bold, p->status, pair_iters(p));
            for (int j = 0; j < s->nthr; j++) {
                fmt_ms(p->ttt_med[j], a, sizeof a);
                if (isfinite(p->ttt_med[j]) && sr->repeats > 1) {
                    fmt_ms(p->ttt_min[j], c1, sizeof c1);
                    fmt_ms(p->ttt_max[j], c2, sizeof c2);
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
                fmt_sci(p->eab_med[j], a, sizeof a);
                fprintf(f, " %s |", a);
            }
            if (s->o.trajectory) {
                fmt_ms(p->traj_time, a, sizeof a);
                fmt_sci(p->traj_max_dist, c1, sizeof c1);
                fprintf(f, " %s | %s |", a, c1);
            }
            fprintf(f, "\n");
        }
        fprintf(f, "\n");
    }

    /* ---- failures */
    fprintf(f, "## Failures and their reasons\n\n");
    int nf = 0;
    for (int si = 0; si < s->nsc; si++) {
        for (int k = 0; k < s->sc[si].steps; k++)
            if (!b->res[si].ref[k].converged) {
                fprintf(f, "- **reference** on %s step %d: %s (λ²/2 = %.2e after %d iterations)\n", s->sc[si].name,
                        k + 1, eo_reason_name(b->res[si].ref[k].reason), b->res[si].ref[k].dec,
                        b->res[si].ref[k].iters);
                nf++;
            }
        for (int c = 0; c < s->ncf; c++) {
            const bench_pair *p = b->res[si].pair + c;
            if (!strcmp(p->status, "converged")) continue;
            fprintf(f, "- %s on %s: %s — %s", s->cf[c].name, s->sc[si].name, p->status, p->reason);
            /* curve run of the failing step, if it is a measured one */
            int m = s->o.trajectory ? p->first_bad_step - s->sc[si].skip : p->first_bad_step;
            if (p->first_bad_step >= 0 && m >= 0 && m < p->nsteps) {
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
    for (int q = 0; q < s->nreq; q++) {
        int bad = 0;
        for (int si = 0; si < s->nsc; si++) bad += strcmp(b->res[si].pair[s->req[q]].status, "converged") != 0;
        fprintf(f, "\nRequired to converge everywhere: **%s** — %s.\n", s->cf[s->req[q]].name,
                bad ? "FAILED" : "converged on every step of every scene");
    }
    fprintf(f, "\n");

    /* ---- resolved configurations */
    fprintf(f, "## Resolved configurations\n\n");
    fprintf(f, "The curve runs replace `tol` by 1e-300 (the harness stops them), `max_iters` by the scene's cap and "
               "`time_budget` by the scene's budget (unless the configuration sets its own `time_budget`, which "
               "then applies); the trajectory runs use everything as shown, with the same time budget.\n\n");
    for (int c = 0; c < s->ncf; c++) fprintf(f, "- `%s`: `%s`\n", s->cf[c].name, s->cf[c].resolved);
    fprintf(f, "\n");
    return eo_afile_commit(ctx, &af);
}
