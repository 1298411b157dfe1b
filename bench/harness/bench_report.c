/* Benchmark outputs (bench.h): summary.csv, report.md and the gnuplot plots.
 *
 *   summary.csv   one row per (scene, configuration): status and reason, time to each
 *                 threshold (median, min, max of the repeats, summed over the measured
 *                 steps), ratio to the baseline, error at each time budget (worst step),
 *                 trajectory results
 *   report.md     machine, build, protocol, headline (fastest to 1e-6 per scene and its
 *                 ratio over the next best), stability matrix, per-scene tables with the
 *                 plots, failures with reasons, resolved configurations
 *   plots/        <scene>.png + .svg: relative energy error against time (log-log),
 *                 one panel per measured step, one curve per configuration in each;
 *                 pareto.png + .svg: trajectory time (ratio to baseline) against
 *                 trajectory error, both geometric means over the scenes. The .gp
 *                 scripts and .dat data stay next to them so a plot can be remade with
 *                 `gnuplot plots/x.gp`.
 * The PNGs use the pngcairo terminal where gnuplot has it (it draws the dash types that
 * tell the line searches apart; files about 4x those of the libgd `png` terminal, which
 * draws every line solid and is the fallback). gnuplot (Debian package gnuplot-nox) is
 * run as a separate process; without it the report says so and everything else is
 * written. */
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
    fprintf(f, ",final_rel_err,traj_converged,traj_time,traj_max_dist,traj_final_dist,traj_rel_dist");
    for (int j = 0; j < s->nibud; j++)
        fprintf(f, ",fixed_%d_time_per_frame,fixed_%d_time_min,fixed_%d_time_max,fixed_%d_iters_per_frame,"
                   "fixed_%d_max_dist,fixed_%d_rel_dist",
                s->ibud[j], s->ibud[j], s->ibud[j], s->ibud[j], s->ibud[j], s->ibud[j]);
    fprintf(f, "\n");
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
            eo_bench_csv_num(f, s->o.trajectory ? p->traj_max_dist / fmax(sr->ref_disp, 1e-300) : NAN);
            for (int j = 0; j < s->nibud; j++) {
                const bench_fixed_res *z = p->fixed + j;
                if (!z->frames) { /* not run on this scene */
                    fputs(",,,,,,", f);
                    continue;
                }
                eo_bench_csv_num(f, z->ms_med);
                eo_bench_csv_num(f, z->ms_min);
                eo_bench_csv_num(f, z->ms_max);
                eo_bench_csv_num(f, z->frames ? (double)z->iters / z->frames : NAN);
                eo_bench_csv_num(f, z->nan ? NAN : z->max_dist);
                eo_bench_csv_num(f, z->nan ? NAN : z->max_dist / fmax(sr->win_disp, 1e-300));
            }
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
    fprintf(f, "scene,step,scene_step,measured,t,n,iterations,reason,converged,rounding_floor,solve_time,g0,gstar,"
               "decrement,rel_err_floor,motion,correction,"
               "ipopt_reason,ipopt_iterations,ipopt_time,ipopt_rel_energy_diff,ipopt_rel_pos_diff\n");
    for (int si = 0; si < s->nsc; si++)
        for (int k = 0, m = 0; k < b->res[si].nref; k++) {
            /* every reference step; `step` numbers the measured ones (1..steps) */
            const bench_scene_res *sr = b->res + si;
            const int meas = m < s->sc[si].steps && sr->meas[m] == k;
            const bench_ref *q = meas ? sr->ref + m : sr->allref + k;
            fprintf(f, "%s,", s->sc[si].name);
            if (meas) fprintf(f, "%d", m + 1);
            fprintf(f, ",%d,%d,%.6g,%d,%d,%s,%d,%d", k + 1, meas, q->t, q->n, q->iters, eo_reason_name(q->reason),
                    q->converged, q->rounding);
            m += meas;
            eo_bench_csv_num(f, q->time);
            char gb[2][32];
            fprintf(f, ",%s,%s", eo_fmt_double(gb[0], q->g0), eo_fmt_double(gb[1], q->gstar));
            eo_bench_csv_num(f, q->dec);
            eo_bench_csv_num(f, q->floor);
            eo_bench_csv_num(f, sr->motion[k]);
            eo_bench_csv_num(f, sr->correction[k]);
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
 * search, point type by Hessian fix; the baseline is black. The PNGs are drawn with
 * pngcairo (anti-aliased, draws the dash types; the libgd `png` terminal draws every
 * line solid) where gnuplot has it, else with `png`; an SVG is written beside each. */
static const char *const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
                                      "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
#define NPAL ((int)(sizeof palette / sizeof palette[0]))
#define MAX_HIGHLIGHT 8
/* dash type per line search, point type per Hessian fix (cycled beyond) */
static const char *const dashes[] = {"1", "(16,8)", "(3,6)", "(16,6,3,6)", "(7,7)", "(16,6,3,6,3,6)"};
#define NDASH ((int)(sizeof dashes / sizeof dashes[0]))
static const int points[] = {7, 5, 9, 11, 13, 15, 6, 4, 8, 10};
#define NPT ((int)(sizeof points / sizeof points[0]))

typedef struct cfg_style {
    int family, ls, fix;      /* indices in order of first appearance */
    char opt[64];             /* optimizer name */
    char ls_name[64];         /* line search ("own": the optimizer's own, NLopt and Ipopt) */
    char fix_name[64];        /* Hessian fix ("-": the optimizer uses no Hessian) */
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
        char v[3][64];
        for (int k = 0; k < 3; k++) resolved_name(s->cf[c].resolved, keys[k], v[k], sizeof v[k]);
        /* NLopt and Ipopt search along their own directions with their own line searches;
         * fixed_point and admm_pd take the full update, aqp has its own backtracking;
         * solver.linesearch is not used by them */
        if (!strcmp(v[0], "nlopt") || !strcmp(v[0], "ipopt") || !strcmp(v[0], "aqp"))
            snprintf(v[1], sizeof v[1], "own");
        if (!strcmp(v[0], "fixed_point") || !strcmp(v[0], "admm_pd")) snprintf(v[1], sizeof v[1], "none");
        if (!s->cf[c].needs_hessian) snprintf(v[2], sizeof v[2], "-");
        for (int k = 0; k < 3; k++) {
            int i = 0;
            while (i < nn[k] && strcmp(names[k][i], v[k]) != 0) i++;
            if (i == nn[k] && nn[k] < 64) snprintf(names[k][nn[k]++], 64, "%.63s", v[k]);
            idx[k] = i;
        }
        snprintf(st[c].opt, sizeof st[c].opt, "%s", v[0]);
        snprintf(st[c].ls_name, sizeof st[c].ls_name, "%s", v[1]);
        snprintf(st[c].fix_name, sizeof st[c].fix_name, "%s", v[2]);
        st[c].family = idx[0];
        st[c].ls = idx[1];
        st[c].fix = idx[2];
    }
}

static const char *style_colour(const eo_bench_suite *s, const cfg_style *st, int c)
{
    return c == s->baseline ? "#000000" : palette[st[c].family % NPAL];
}

/* The PNG terminal (pngcairo if this gnuplot has it, else the libgd png) and its output. */
static void png_terminal(FILE *f, int w, int h, const char *out)
{
    fprintf(f, "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
               "    set terminal pngcairo size %d,%d font 'DejaVu Sans,10' noenhanced\n"
               "} else {\n"
               "    set terminal png size %d,%d font 'DejaVu Sans,11' noenhanced  # draws every dash type solid\n"
               "}\n"
               "set output '%s'\n",
            w, h, w, h, out);
}

/* The configurations drawn in colour on a scene's plot: the baseline, the fastest at the
 * headline accuracy and the best of each optimizer family (fastest to the headline, else
 * to the loosest threshold it reached), at most MAX_HIGHLIGHT; the rest are thin grey.
 * A suite of at most MAX_HIGHLIGHT configurations has every one in colour. */
static void pick_highlight(const bench_out *b, int si, int h, const cfg_style *st, int first, unsigned char *hl)
{
    const eo_bench_suite *s = b->s;
    const bench_scene_res *sr = b->res + si;
    memset(hl, 0, (size_t)s->ncf);
    int n = 0;
    hl[s->baseline] = 1;
    n++;
    if (first >= 0 && !hl[first]) hl[first] = 1, n++;
    if (s->ncf <= MAX_HIGHLIGHT) {
        memset(hl, 1, (size_t)s->ncf);
        return;
    }
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

/* Colours of the highlighted configurations (col: ncf strings of 8): the family's colour,
 * a darker then a lighter shade of it for a second and third highlighted member of the
 * same family (the baseline, black, not counted), grey for the rest. */
static void plot_colours(const eo_bench_suite *s, const cfg_style *st, const unsigned char *hl, char (*col)[8])
{
    for (int c = 0; c < s->ncf; c++) {
        if (!hl[c]) {
            snprintf(col[c], 8, "#c8c8c8");
            continue;
        }
        if (c == s->baseline) {
            snprintf(col[c], 8, "#000000");
            continue;
        }
        int k = 0;
        for (int d = 0; d < c; d++) k += hl[d] && d != s->baseline && st[d].family == st[c].family;
        unsigned rgb = 0;
        sscanf(palette[st[c].family % NPAL] + 1, "%x", &rgb);
        double ch[3] = {(rgb >> 16) & 255, (rgb >> 8) & 255, rgb & 255};
        for (int i = 0; i < 3; i++) {
            if (k % 3 == 1) ch[i] *= 0.55;                    /* darker */
            else if (k % 3 == 2) ch[i] += 0.5 * (255 - ch[i]); /* lighter */
        }
        snprintf(col[c], 8, "#%02x%02x%02x", (unsigned)ch[0] & 255, (unsigned)ch[1] & 255, (unsigned)ch[2] & 255);
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

/* A threshold as a plot label: 1e-6, 3e-4 (the y tics' format). */
static void plot_thr(double t, char *buf, size_t n)
{
    char m[32];
    snprintf(m, sizeof m, "%.0e", t); /* "1e-06" */
    char *e = strchr(m, 'e');
    if (!e) {
        snprintf(buf, n, "%s", m);
        return;
    }
    *e = 0;
    snprintf(buf, n, "%.8se%d", m, atoi(e + 1));
}

/* The shared legend's style key: the line searches and Hessian fixes of the highlighted
 * configurations, as dark grey samples (keyentry: no data). */
static void style_key(FILE *f, const eo_bench_suite *s, const cfg_style *sty, const unsigned char *hl)
{
    unsigned char seen[64];
    memset(seen, 0, sizeof seen);
    fprintf(f, ", \\\n  keyentry with lines lc rgb '#ffffff' title 'line style = line search:'");
    for (int c = 0; c < s->ncf; c++)
        if (hl[c] && sty[c].ls < 64 && !seen[sty[c].ls]++)
            fprintf(f, ", \\\n  keyentry with lines lc rgb '#555555' lw 1.8 dt %s title '  %s'", dashes[sty[c].ls % NDASH],
                    sty[c].ls_name);
    memset(seen, 0, sizeof seen);
    fprintf(f, ", \\\n  keyentry with lines lc rgb '#ffffff' title 'point = Hessian fix:'");
    for (int c = 0; c < s->ncf; c++)
        if (hl[c] && sty[c].fix < 64 && !seen[sty[c].fix]++)
            fprintf(f, ", \\\n  keyentry with points lc rgb '#555555' pt %d ps 1.0 title '  %s'", points[sty[c].fix % NPT],
                    strcmp(sty[c].fix_name, "-") ? sty[c].fix_name : "(no Hessian)");
}

/* Relative energy error against solve time, one panel per measured step (small
 * multiples on shared axes), one curve per configuration in each: at most
 * MAX_HIGHLIGHT in colour (pick_highlight), the rest thin grey underneath; one legend
 * in the right-hand column for every panel; the figure's title names the fastest to the
 * headline accuracy (time summed over the measured steps, as in the report). */
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
    const int S = bs->steps;
    int h = headline_thr(s), first, second;
    fastest(b, si, h, &first, &second);
    plot_thr(s->thr[h], lab, sizeof lab);
    char title[700], over[64] = "";
    char vsb[160] = "";
    if (S > 1) snprintf(over, sizeof over, " (time summed over the %d steps)", S);
    const double tb = sr->pair[s->baseline].ttt_med[h];
    if (first >= 0 && first != s->baseline && second != s->baseline)
        snprintf(vsb, sizeof vsb, isfinite(tb) ? "; %.2fx faster than the baseline" : "; the baseline never did",
                 tb / sr->pair[first].ttt_med[h]);
    if (first >= 0 && second >= 0)
        snprintf(title, sizeof title, "fastest to %s%s: %s, %.2fx faster than the next, %s%s", lab, over,
                 s->cf[first].name, sr->pair[second].ttt_med[h] / sr->pair[first].ttt_med[h], s->cf[second].name,
                 vsb);
    else if (first >= 0)
        snprintf(title, sizeof title, "fastest to %s%s: %s (the only one)", lab, over, s->cf[first].name);
    else
        snprintf(title, sizeof title, "no configuration reached %s", lab);
    cfg_style *sty = eo_malloc(ctx, (size_t)s->ncf * sizeof *sty);
    unsigned char *hl = eo_malloc(ctx, (size_t)s->ncf);
    char(*colour)[8] = eo_malloc(ctx, (size_t)s->ncf * sizeof *colour);
    if (!sty || !hl || !colour) {
        eo_free(ctx, sty);
        eo_free(ctx, hl);
        eo_free(ctx, colour);
        eo_afile_abort(ctx, &af);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (plot styles)");
    }
    cfg_styles(s, sty);
    pick_highlight(b, si, h, sty, first, hl);
    plot_colours(s, sty, hl, colour);
    int nother = 0;
    for (int c = 0; c < s->ncf; c++) nother += !hl[c];
    /* layout in pixels: panels in a grid, the legend in a column on the right */
    const int ncol = S <= 3 ? S : (int)ceil(sqrt((double)S)), nrow = (S + ncol - 1) / ncol;
    const int pw = S == 1 ? 940 : ncol == 2 ? 600 : 500, ph = S == 1 ? 660 : nrow == 1 ? 600 : 460;
    /* the legend's width from its longest title (gnuplot reserves about 8 px a character at 10 pt) */
    size_t maxlen = 28;
    for (int c = 0; c < s->ncf; c++)
        if (hl[c]) {
            const size_t l = strlen(s->cf[c].name) + (c == s->baseline ? 11 : 0) + (c == first ? 10 : 0);
            if (l > maxlen) maxlen = l;
        }
    const int lm = 90, gap = 40, keyw = 90 + (int)(8.2 * (double)maxlen), top = 80, bot = 60, vgap = 60;
    const int W = lm + ncol * pw + (ncol - 1) * gap + 30 + keyw, H = top + nrow * ph + (nrow - 1) * vgap + bot;
    fprintf(f, "# %s: relative energy error against solve time, one panel per measured step\n", bs->name);
    fprintf(f, "# colour = optimizer family (baseline black), dash = line search, point = Hessian fix;\n"
               "# in colour: the baseline, the fastest and the best of each family (at most %d)\n",
            MAX_HIGHLIGHT);
    /* the figure twice: PNG, then the same commands on the SVG terminal (a multiplot
     * cannot be replotted) */
    for (int term = 0; term < 2; term++) {
        char out[256];
        snprintf(out, sizeof out, "%s.%s", name, term ? "svg" : "png");
        if (term)
            fprintf(f, "\n# ---- the same figure as SVG\nreset\nset terminal svg size %d,%d font 'DejaVu Sans,10' "
                       "noenhanced\nset output '%s'\n",
                    W, H, out);
        else
            png_terminal(f, W, H, out);
        double left = isfinite(sr->tmin) ? pow(10, floor(log10(sr->tmin))) : 1e-4;
        fprintf(f, "left = %g  # the start point x0 (time 0) is drawn at the left edge\n", left);
        fprintf(f, "stats '%s.dat' using 1 nooutput\n", name);
        fprintf(f, "right = STATS_max > left ? 10**ceil(log10(STATS_max)) : 10*left\n");
        fprintf(f, "set xrange [left:right]\n");
        fprintf(f, "set yrange [%g:3]\n", s->o.target / 10);
        fprintf(f, "set logscale xy\nset grid xtics ytics lc rgb '#d8d8d8'\nset mxtics 10\nset mytics 10\n");
        fprintf(f, "set format y '1e%%L'\nset format x '%%g'\n");
        for (int j = 0; j < s->nthr; j++) {
            char t[32];
            plot_thr(s->thr[j], t, sizeof t);
            fprintf(f, "set arrow from graph 0, first %g to graph 1, first %g nohead lc rgb '#999999' dt (4,4) front\n",
                    s->thr[j], s->thr[j]);
            fprintf(f, "set label '%s' at graph 1, first %g offset char 0.4,0 left font ',8' tc rgb '#777777'\n", t,
                    s->thr[j]);
        }
        fprintf(f, "set key at screen %.4f, screen %.4f left top Left reverse box opaque samplen 4 spacing 1.1 "
                   "font ',10'\n",
                (double)(W - keyw + 20) / W, (double)(H - top) / H);
        fprintf(f, "set multiplot title \"%s: %d tets, %s E=%g nu=%g; %d measured step%s, median of %d repeat%s\\n%s\" "
                   "font ',12'\n",
                bs->name, bs->nt, bs->model, bs->E, bs->nu, S, S == 1 ? "" : "s", sr->repeats, sr->repeats == 1 ? "" : "s",
                title);
        for (int k = 0; k < S; k++) {
            const int col = k % ncol, row = k / ncol;
            const double x0 = lm + col * (pw + gap), y1 = top + row * (ph + vgap);
            fprintf(f, "\n# panel %d: measured step %d\n", k + 1, sr->meas[k] + 1);
            fprintf(f, "set lmargin at screen %.4f\nset rmargin at screen %.4f\n", x0 / W, (x0 + pw) / W);
            fprintf(f, "set tmargin at screen %.4f\nset bmargin at screen %.4f\n", 1 - y1 / H, 1 - (y1 + ph) / H);
            if (S > 1) fprintf(f, "set title 'step %d (t = %.4g s)' offset 0,-0.4\n", sr->meas[k] + 1, sr->ref[k].t);
            fprintf(f, "set ylabel %s\n", col == 0 ? "'relative energy error (g - g*) / |g0 - g*|'" : "''");
            fprintf(f, "set format y %s\n", col == 0 ? "'1e%L'" : "''");
            fprintf(f, "set xlabel %s\n", row == nrow - 1 || k + ncol >= S
                                              ? "'solve time of the step (s); median of the repeats; x0 at the left edge'"
                                              : "''");
            if (k == 1) fprintf(f, "unset key\n");
            fprintf(f, "plot \\\n");
            int any = 0, grey_titled = 0;
            /* grey ones first (underneath), then the highlighted ones */
            for (int pass = 0; pass < 2; pass++)
                for (int c = 0; c < s->ncf; c++) {
                    if (hl[c] != pass) continue;
                    const char *colr = colour[c];
                    const char *dt = dashes[sty[c].ls % NDASH];
                    const int pt = points[sty[c].fix % NPT];
                    double lw = !hl[c] ? 0.8 : c == first ? 3.0 : c == s->baseline ? 2.2 : 1.6;
                    /* about 25 points on a long curve (a first-order method's thousands;
                     * the data keeps curve_rows rows, then 50 a decade: eo_bench_keep_row) */
                    const int it = sr->pair[c].st[k].iters, cr = s->o.curve_rows;
                    const int rows = cr > 0 && it > cr ? cr + 1 + (int)ceil(50 * log10((double)it / cr)) : it + 1;
                    const int pi = rows > 50 ? rows / 25 : 1;
                    char t[300];
                    if (hl[c])
                        snprintf(t, sizeof t, "title '%s%s%s'", s->cf[c].name, c == s->baseline ? " (baseline)" : "",
                                 c == first ? " (fastest)" : "");
                    else if (!grey_titled) {
                        snprintf(t, sizeof t, "title '%d other configuration%s (grey)'", nother, nother == 1 ? "" : "s");
                        grey_titled = 1;
                    } else
                        snprintf(t, sizeof t, "notitle");
                    if (hl[c])
                        fprintf(f, "%s  '%s.dat' index %d using ($1>0?$1:left):2 with linespoints lc rgb '%s' dt %s "
                                   "lw %.1f pt %d ps 0.8 pi %d %s",
                                any ? ", \\\n" : "", name, c * S + k, colr, dt, lw, pt, pi, t);
                    else
                        fprintf(f, "%s  '%s.dat' index %d using ($1>0?$1:left):2 with lines lc rgb '%s' lw %.1f %s",
                                any ? ", \\\n" : "", name, c * S + k, colr, lw, t);
                    any = 1;
                }
            if (k == 0) style_key(f, s, sty, hl);
            fprintf(f, "\n");
        }
        fprintf(f, "unset multiplot\n");
    }
    eo_free(ctx, sty);
    eo_free(ctx, hl);
    eo_free(ctx, colour);
    rc = eo_afile_commit(ctx, &af);
    if (rc < 0) return rc;
    rc = run_gnuplot(ctx, b->dir, name);
    if (rc >= 0) b->res[si].plotted = 1;
    return rc;
}

/* The own-stopping-rule summary over every scene (the Pareto chart and its headline
 * table): x[c] = geometric mean over the scenes of the trajectory solve time per step
 * over the baseline's (a trajectory stops at its first failing step, so the time per
 * step compares runs of different lengths), y[c] = geometric mean of the largest
 * trajectory distance over the reference motion, n[c] scenes counted, conv[c] = 1 if c
 * converged on every scene, front[c] = 1 if c converged everywhere and no other such
 * configuration is both faster and closer (pareto_tie). */
typedef struct pareto_pts {
    double *x, *y;
    int *n, *conv, *front;
} pareto_pts;

/* Two ratios within 2 % of each other are a tie for the Pareto front: closer than the
 * table's digits and the timing noise (converged configurations share the reference's
 * distance to a few digits; without it a 1.3x slower one is "on the front" by 1e-3). */
static int pareto_tie(double a, double b) { return fabs(log(a / b)) < log(1.02); }

static int pareto_compute(eo_ctx *ctx, const bench_out *b, pareto_pts *pp)
{
    const eo_bench_suite *s = b->s;
    pp->x = eo_malloc(ctx, 2 * (size_t)s->ncf * sizeof(double));
    pp->n = eo_calloc(ctx, 3 * (size_t)s->ncf, sizeof(int));
    if (!pp->x || !pp->n) {
        eo_free(ctx, pp->x);
        eo_free(ctx, pp->n);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    }
    pp->y = pp->x + s->ncf;
    pp->conv = pp->n + s->ncf;
    pp->front = pp->conv + s->ncf;
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
        pp->x[c] = n ? exp(lx / n) : NAN;
        pp->y[c] = n ? exp(ly / n) : NAN;
        pp->n[c] = n;
        pp->conv[c] = conv && n > 0;
    }
    for (int c = 0; c < s->ncf; c++) {
        if (!pp->conv[c]) continue;
        int dominated = 0;
        for (int d = 0; d < s->ncf; d++) {
            if (d == c || !pp->conv[d]) continue;
            const int nx = pareto_tie(pp->x[d], pp->x[c]), ny = pareto_tie(pp->y[d], pp->y[c]);
            if ((nx || pp->x[d] < pp->x[c]) && (ny || pp->y[d] < pp->y[c]) &&
                ((!nx && pp->x[d] < pp->x[c]) || (!ny && pp->y[d] < pp->y[c])))
                dominated = 1;
        }
        pp->front[c] = !dominated;
    }
    return EO_OK;
}

static void pareto_free(eo_ctx *ctx, pareto_pts *pp)
{
    eo_free(ctx, pp->x);
    eo_free(ctx, pp->n);
}

/* The fastest configuration that converged everywhere (-1 if none) and the closest;
 * among ties (pareto_tie) with the fastest, the closer; with the closest, the faster. */
static void pareto_winners(const eo_bench_suite *s, const pareto_pts *pp, int *fast, int *close)
{
    *fast = *close = -1;
    for (int c = 0; c < s->ncf; c++) {
        if (!pp->conv[c]) continue;
        if (*fast < 0 || pp->x[c] < pp->x[*fast]) *fast = c;
        if (*close < 0 || pp->y[c] < pp->y[*close]) *close = c;
    }
    if (*fast < 0) return;
    const double x0 = pp->x[*fast], y0 = pp->y[*close];
    for (int c = 0; c < s->ncf; c++) {
        if (!pp->conv[c]) continue;
        if (pareto_tie(pp->x[c], x0) && pp->y[c] < pp->y[*fast]) *fast = c;
        if (pareto_tie(pp->y[c], y0) && pp->x[c] < pp->x[*close]) *close = c;
    }
}

/* Pareto chart over all scenes: x, y of pareto_compute, named as the report's "Own
 * stopping rule" headline table; colour = optimizer family (as in the scene plots),
 * filled circle = converged on every scene, open triangle = failed somewhere; points at
 * the same place share one label. */
int eo_bench_plot_pareto(eo_ctx *ctx, bench_out *b)
{
    const eo_bench_suite *s = b->s;
    if (!s->o.trajectory) return EO_ERR_UNSUPPORTED;
    pareto_pts pp;
    int rc = pareto_compute(ctx, b, &pp);
    if (rc < 0) return rc;
    cfg_style *sty = eo_malloc(ctx, (size_t)s->ncf * sizeof *sty);
    int *lab = eo_malloc(ctx, (size_t)s->ncf * sizeof(int));
    if (!sty || !lab) {
        eo_free(ctx, sty);
        eo_free(ctx, lab);
        pareto_free(ctx, &pp);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    }
    cfg_styles(s, sty);
    char path[1400];
    snprintf(path, sizeof path, "%s/plots/pareto.dat", b->dir);
    eo_afile *af = NULL;
    rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) goto done;
    FILE *f = eo_afile_fp(af);
    fprintf(f, "# number  traj_time_ratio  traj_dist_ratio (clipped to 100)  converged_everywhere  scenes  rgb  config\n");
    for (int c = 0; c < s->ncf; c++) {
        lab[c] = -1;
        if (!pp.n[c]) continue;
        unsigned rgb = 0;
        sscanf(style_colour(s, sty, c) + 1, "%x", &rgb);
        fprintf(f, "%d %.6e %.6e %d %d %u \"%s\"\n", c + 1, pp.x[c], fmin(pp.y[c], 100), pp.conv[c], pp.n[c], rgb,
                s->cf[c].name);
    }
    fprintf(f, "\n\n# Pareto front among the configurations that converged everywhere\n");
    for (int k = 0; k < s->ncf; k++) { /* in order of x */
        int best = -1;
        for (int c = 0; c < s->ncf; c++)
            if (pp.front[c] == 1 && (best < 0 || pp.x[c] < pp.x[best])) best = c;
        if (best < 0) break;
        pp.front[best] = 2;
        fprintf(f, "%.6e %.6e\n", pp.x[best], fmin(pp.y[best], 100));
    }
    /* labels: points closer than about a label's size on the chart (3 % of the axis'
     * decades, as gnuplot autoscales them) share one label "1,2,3" */
    double lx[2] = {INFINITY, -INFINITY}, ly[2] = {INFINITY, -INFINITY};
    for (int c = 0; c < s->ncf; c++)
        if (pp.n[c]) {
            const double u = log10(pp.x[c]), v = log10(fmin(pp.y[c], 100));
            lx[0] = fmin(lx[0], u), lx[1] = fmax(lx[1], u), ly[0] = fmin(ly[0], v), ly[1] = fmax(ly[1], v);
        }
    const double tolx = 0.03 * fmax(floor(lx[1]) + 1 - floor(lx[0]), 1),
                 toly = 0.03 * fmax(floor(ly[1]) + 1 - floor(ly[0]), 1);
    fprintf(f, "\n\n# labels\n");
    for (int c = 0; c < s->ncf; c++) {
        if (!pp.n[c] || lab[c] >= 0) continue;
        char text[400];
        size_t k = (size_t)snprintf(text, sizeof text, "%d", c + 1);
        int at = c; /* the label starts at the leftmost point of the group */
        for (int d = c + 1; d < s->ncf; d++)
            if (pp.n[d] && lab[d] < 0 && fabs(log10(pp.x[d] / pp.x[c])) < tolx &&
                fabs(log10(fmin(pp.y[d], 100) / fmin(pp.y[c], 100))) < toly && k + 8 < sizeof text) {
                lab[d] = c;
                k += (size_t)snprintf(text + k, sizeof text - k, ",%d", d + 1);
                if (pp.x[d] < pp.x[at]) at = d;
            }
        lab[c] = c;
        fprintf(f, "%.6e %.6e \"%s\"\n", pp.x[at], fmin(pp.y[at], 100), text);
    }
    rc = eo_afile_commit(ctx, &af);
    if (rc < 0) goto done;
    snprintf(path, sizeof path, "%s/plots/pareto.gp", b->dir);
    rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) goto done;
    f = eo_afile_fp(af);
    int fast, close;
    pareto_winners(s, &pp, &fast, &close);
    png_terminal(f, 1500, 950, "pareto.png");
    fprintf(f, "set rmargin at screen 0.70\nset lmargin at screen 0.08\nset bmargin at screen 0.17\n");
    fprintf(f, "# configurations by number (points are labelled with the number), coloured by optimizer family\n");
    for (int c = 0; c < s->ncf; c++)
        fprintf(f, "set label %d \"%2d  %s%s\" at screen 0.72, screen %.4f left font ',10' tc rgb '%s'\n", c + 1, c + 1,
                s->cf[c].name, c == s->baseline ? " (baseline)" : "", 0.92 - 0.8 * c / (s->ncf > 20 ? s->ncf : 20),
                style_colour(s, sty, c));
    char t2[400] = "no configuration converged on every step of every scene";
    if (fast >= 0)
        snprintf(t2, sizeof t2, "fastest converged everywhere: %s (%.2fx the baseline's time); closest: %s (%.1e)",
                 s->cf[fast].name, pp.x[fast], s->cf[close].name, pp.y[close]);
    fprintf(f, "set title \"Own stopping rule over %d scene(s) (the report's 'Own stopping rule' table): lower left is "
               "better\\n%s\"\n", s->nsc, t2);
    fprintf(f, "set logscale xy\nset grid lc rgb '#dddddd'\nset format y '1e%%L'\n");
    fprintf(f, "set xlabel \"traj. time / baseline (solve time per step over %s's; geometric mean over the scenes)\"\n",
            s->cf[s->baseline].name);
    fprintf(f, "set ylabel \"traj. dist / ref. motion (m/m; geometric mean over the scenes, clipped at 100)\"\n");
    fprintf(f, "set key at screen 0.08, screen 0.085 left top Left reverse box spacing 1.2\n"
               "set offsets graph 0.05, graph 0.1, graph 0.1, graph 0.05\n");
    fprintf(f, "plot 'pareto.dat' index 1 using 1:2 with lines lc rgb '#999999' lw 2 title 'Pareto front of the "
               "configurations that converged everywhere', \\\n"
               "  'pareto.dat' index 0 using ($4==1?$2:1/0):3:6 with points pt 7 ps 1.8 lc rgb variable notitle, \\\n"
               "  'pareto.dat' index 0 using ($4==0?$2:1/0):3:6 with points pt 8 ps 1.8 lw 2 lc rgb variable notitle, "
               "\\\n"
               "  'pareto.dat' index 2 using 1:2:3 with labels offset char 1.0,0.6 left font ',9' notitle, \\\n"
               "  keyentry with points pt 7 ps 1.8 lc rgb '#555555' "
               "title 'converged on every step of every scene (colour: optimizer family, as in the scene plots)', \\\n"
               "  keyentry with points pt 8 ps 1.8 lw 2 lc rgb '#555555' title 'failed or stopped somewhere'\n");
    fprintf(f, "set terminal svg size 1500,950 font 'DejaVu Sans,10' noenhanced\nset output 'pareto.svg'\nreplot\n");
    rc = eo_afile_commit(ctx, &af);
    if (rc >= 0) rc = run_gnuplot(ctx, b->dir, "pareto");
done:
    eo_afile_abort(ctx, &af);
    eo_free(ctx, sty);
    eo_free(ctx, lab);
    pareto_free(ctx, &pp);
    return rc;
}

/* The report's "Own stopping rule" headline table: the Pareto chart's numbers. */
static int write_pareto_table(eo_ctx *ctx, FILE *f, const bench_out *b)
{
    const eo_bench_suite *s = b->s;
    pareto_pts pp;
    int rc = pareto_compute(ctx, b, &pp);
    if (rc < 0) return rc;
    int fast, close;
    pareto_winners(s, &pp, &fast, &close);
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
    pareto_free(ctx, &pp);
    return EO_OK;
}

/* ---------------------------------------------------------------- report.md */

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
            fmt_ms(z->ms_med, a, sizeof a);
            fmt_ms(z->ms_min, lo, sizeof lo);
            fmt_ms(z->ms_max, hi, sizeof hi);
            if (z->nan) fprintf(f, " %s (%s–%s) / **NaN**", a, lo, hi);
            else fprintf(f, " %s (%s–%s) / %.1e", a, lo, hi, z->max_dist / fmax(sr->win_disp, 1e-300));
            if (z->short_frames)
                fprintf(f, "; %d of %d frame%s stopped early (%s)", z->short_frames, z->frames, z->frames > 1 ? "s" : "",
                        eo_reason_name(z->first_short_reason));
            fprintf(f, " |");
        }
        if (s->o.trajectory) {
            fmt_ms(p->traj_done ? p->traj_time / p->traj_done : NAN, a, sizeof a);
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
    const int h = headline_thr(s);
    fmt_thr(s->thr[h], lab, sizeof lab);
    char date[64];
    eo_machine mach;
    eo_machine_get(&mach);
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", gmtime(&now));
    fprintf(f, "# Optimizer benchmark: %s\n\n", s->path);
    if (s->o.description[0]) fprintf(f, "%s\n\n", s->o.description);
    fprintf(f, "Run %s, %.1f s wall time (%.1f s processor time: on a loaded machine, an estimate of the wall time "
               "unloaded), %d scene(s) × %d configuration(s), %d timed repeat(s) per run unless "
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
    if (s->o.trajectory) {
        rc = write_pareto_table(ctx, f, b);
        if (rc < 0) {
            eo_afile_abort(ctx, &af);
            return rc;
        }
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
        fprintf(f, ". %d tets, %d vertices; time budget %g s per solve (unless a configuration sets its own); %d "
                   "timed repeat(s).\n\n",
                bs->nt, bs->nv, bs->time_budget, sr->repeats);
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
    fprintf(f, "The curve runs replace `tol` by 1e-300 (the harness stops them), `max_iters` by the scene's cap and "
               "`time_budget` by the scene's budget (unless the configuration sets its own `time_budget`, which "
               "then applies); the trajectory runs use everything as shown, with the same time budget.\n\n");
    for (int c = 0; c < s->ncf; c++) fprintf(f, "- `%s`: `%s`\n", s->cf[c].name, s->cf[c].resolved);
    fprintf(f, "\n");
    return eo_afile_commit(ctx, &af);
}
