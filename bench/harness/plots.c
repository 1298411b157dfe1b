/* The optimizer benchmark harness (bench.h): the gnuplot plots.
 *
 *   plots/<scene>.png + .svg   relative energy error against time (log-log), one panel
 *                 per measured step, one curve per configuration in each;
 *   pareto.png + .svg          trajectory time (ratio to baseline) against trajectory
 *                 error, both geometric means over the scenes;
 *   perf_profile-<stratum>, data_profile-<stratum> (.png + .svg)   the profiles, one
 *                 panel per accuracy level, one line per configuration.
 * The .gp scripts and .dat data stay next to them so a plot can be remade with
 * `gnuplot plots/x.gp`. The PNGs use the pngcairo terminal where gnuplot has it (it draws
 * the dash types that tell the line searches apart; files about 4x those of the libgd
 * `png` terminal, which draws every line solid and is the fallback). gnuplot (Debian
 * package gnuplot-nox) is run as a separate process; without it the report says so and
 * everything else is written. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_impl.h"
#include "elastopt/io.h"

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
    int h = bench_headline_thr(s), first, second;
    bench_fastest(b, si, h, &first, &second);
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
                    if (!strcmp(sr->pair[c].status, "refused")) continue; /* nothing run: an empty block */
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

/* Pareto chart over all scenes: x, y of pareto_compute, named as the report's "Own
 * stopping rule" headline table; colour = optimizer family (as in the scene plots),
 * filled circle = converged on every scene, open triangle = failed somewhere; points at
 * the same place share one label. */
int eo_bench_plot_pareto(eo_ctx *ctx, bench_out *b)
{
    const eo_bench_suite *s = b->s;
    if (!s->o.trajectory) return EO_ERR_UNSUPPORTED;
    pareto_pts pp;
    int rc = bench_pareto_compute(ctx, b, &pp);
    if (rc < 0) return rc;
    cfg_style *sty = eo_malloc(ctx, (size_t)s->ncf * sizeof *sty);
    int *lab = eo_malloc(ctx, (size_t)s->ncf * sizeof(int));
    if (!sty || !lab) {
        eo_free(ctx, sty);
        eo_free(ctx, lab);
        bench_pareto_free(ctx, &pp);
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
    bench_pareto_winners(s, &pp, &fast, &close);
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
    bench_pareto_free(ctx, &pp);
    return rc;
}

/* One gnuplot panel set (every level of the suite) into f for a stratum: perf = 1 the
 * performance profile, else the data profile, from the data file `dat` (index
 * j*ncf + c). */
static void prof_plot_body(FILE *f, const bench_out *b, const cfg_style *sty, const char *dat, const char *stratum,
                           int np, int perf)
{
    const eo_bench_suite *s = b->s;
    const int cols = s->nthr < 3 ? s->nthr : 3, rows = (s->nthr + cols - 1) / cols;
    fprintf(f, "set multiplot layout %d,%d title \"%s profile, %s (%d instances = measured steps; %s time)\"\n", rows,
            cols, perf ? "Performance (Dolan-More)" : "Data (More-Wild)", stratum, np, b->wall ? "wall" : "CPU");
    fprintf(f, "set logscale x 2\nset yrange [0:1.02]\nset grid lc rgb '#dddddd'\nset key bottom right font ',8'\n");
    if (!perf) fprintf(f, "set logscale x 10\nset format x '1e%%L'\n");
    for (int j = 0; j < s->nthr; j++) {
        fprintf(f, "set title 'relative energy error <= %.0e'\n", s->thr[j]);
        fprintf(f, "set xlabel '%s'\nset ylabel 'fraction of instances'\n",
                perf ? "tau (time / best time on the instance)" : "budget (gradient-equivalents of time)");
        fprintf(f, "plot ");
        for (int c = 0; c < s->ncf; c++)
            fprintf(f, "%s'%s' index %d using 1:2 with steps lw %s lc rgb '%s' dt %s title '%s'", c ? ", \\\n  " : "",
                    dat, j * s->ncf + c, c == s->baseline ? "2.5" : "1.5", style_colour(s, sty, c),
                    dashes[sty[c].ls % NDASH], s->cf[c].name);
        fprintf(f, "\n");
    }
    fprintf(f, "unset multiplot\n");
}

/* plots/perf_profile-<stratum> and data_profile-<stratum> (.dat, .gp, .png, .svg): one
 * panel per accuracy level, one line per configuration (the curves of the CSVs that
 * eo_bench_write_profiles writes). */
int eo_bench_plot_profiles(eo_ctx *ctx, bench_out *b)
{
    const eo_bench_suite *s = b->s;
    const char *names[64];
    const int nst = bench_prof_strata(s, names, 64);
    const int npmax = bench_prof_ninstances(s);
    double *t = eo_malloc(ctx, ((size_t)npmax * s->ncf + npmax + 1) * sizeof(double));
    cfg_style *sty = eo_malloc(ctx, (size_t)s->ncf * sizeof *sty);
    eo_afile *pdat = NULL, *ddat = NULL, *gp = NULL;
    int rc = EO_OK;
    if (!t || !sty) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        goto fail;
    }
    double *tg = t + (size_t)npmax * s->ncf;
    cfg_styles(s, sty);
    char path[1400];
    for (int q = 0; q < nst; q++) {
        char base[200], fname[160];
        eo_bench_file_name(names[q], fname, sizeof fname);
        snprintf(path, sizeof path, "%s/plots/perf_profile-%s.dat", b->dir, fname);
        EO_TRY(rc = eo_afile_open(ctx, path, &pdat));
        snprintf(path, sizeof path, "%s/plots/data_profile-%s.dat", b->dir, fname);
        EO_TRY(rc = eo_afile_open(ctx, path, &ddat));
        FILE *Pd = eo_afile_fp(pdat), *Dd = eo_afile_fp(ddat);
        int np = 0;
        for (int j = 0; j < s->nthr; j++) {
            np = bench_prof_costs(b, q, names, j, t, tg);
            for (int c = 0; c < s->ncf; c++) {
                fprintf(Pd, "# %s, %.0e, %s\n", names[q], s->thr[j], s->cf[c].name);
                fprintf(Dd, "# %s, %.0e, %s\n", names[q], s->thr[j], s->cf[c].name);
                for (int i = 0; i < PROF_NTAU; i++)
                    fprintf(Pd, "%.6g %.6g\n", bench_prof_tau(i), bench_prof_rho(t, np, s->ncf, c, bench_prof_tau(i)));
                for (int i = 0; i < PROF_NKAPPA; i++)
                    fprintf(Dd, "%.6g %.6g\n", bench_prof_kappa(i),
                            bench_prof_data(t, tg, np, s->ncf, c, bench_prof_kappa(i)));
                fprintf(Pd, "\n\n");
                fprintf(Dd, "\n\n");
            }
        }
        EO_TRY(rc = eo_afile_commit(ctx, &pdat));
        EO_TRY(rc = eo_afile_commit(ctx, &ddat));
        for (int perf = 1; perf >= 0; perf--) {
            snprintf(base, sizeof base, "%s_profile-%s", perf ? "perf" : "data", fname);
            snprintf(path, sizeof path, "%s/plots/%s.gp", b->dir, base);
            EO_TRY(rc = eo_afile_open(ctx, path, &gp));
            FILE *f = eo_afile_fp(gp);
            const int cols = s->nthr < 3 ? s->nthr : 3, rows = (s->nthr + cols - 1) / cols;
            char out[240], dname[240];
            snprintf(out, sizeof out, "%s.png", base);
            snprintf(dname, sizeof dname, "%s.dat", base);
            png_terminal(f, 520 * cols, 420 * rows + 40, out);
            prof_plot_body(f, b, sty, dname, names[q], np, perf);
            fprintf(f, "set terminal svg size %d,%d font 'DejaVu Sans,10' noenhanced\nset output '%s.svg'\n", 520 * cols,
                    420 * rows + 40, base);
            prof_plot_body(f, b, sty, dname, names[q], np, perf);
            EO_TRY(rc = eo_afile_commit(ctx, &gp));
            if (run_gnuplot(ctx, b->dir, base) >= 0) b->sum->plots_made++;
        }
    }
    rc = EO_OK;
fail:
    eo_afile_abort(ctx, &pdat);
    eo_afile_abort(ctx, &ddat);
    eo_afile_abort(ctx, &gp);
    eo_free(ctx, t);
    eo_free(ctx, sty);
    return rc;
}
