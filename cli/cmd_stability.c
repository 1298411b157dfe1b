/* elastopt stability: the measured Dahlquist stability of every registered integrator
 * (stability.h, notes 001 §2.6) against theory, as a table; with --png FILE the
 * boundaries |R(hλ)| = 1 of the first-order-form methods in the complex hλ plane,
 * sampled on a grid from the amplification of one step and drawn by gnuplot (run as a
 * separate process; FILE.dat, FILE.gp and the contour tables FILE.c<i> are left next
 * to the PNG).
 * Exit 0 if every measured bound agrees with theory within 1e-3, 1 if not, 2 on bad input
 * or a failed plot. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "elastopt/io.h"
#include "elastopt/registry.h"
#include "elastopt/stability.h"

extern const eo_cli_command eo_cmd_stability;

static void axis_str(const eo_stability_axis *a, char *buf, size_t n)
{
    if (a->kind == EO_STAB_BOUNDED) snprintf(buf, n, "%.6f", a->bound);
    else snprintf(buf, n, "%s", eo_stability_kind_name(a->kind));
}

/* grid: Re z in [RE0, RE1], Im z in [-IM, IM] */
#define RE0 (-4.5)
#define RE1 1.5
#define IM 3.5
#define NRE 241
#define NIM 281

static int write_png(eo_ctx *ctx, const char *png)
{
    if (strchr(png, '\'')) return eo_error(ctx, EO_ERR_INVALID, "stability: a quote in the PNG path");
    size_t len = strlen(png) + 8;
    char *dat = malloc(len), *gp = malloc(len), *cmd = malloc(3 * len + 64);
    FILE *fd = NULL, *fg = NULL;
    int rc = EO_OK, nm = 0;
    const char *names[32];
    if (!dat || !gp || !cmd) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        goto done;
    }
    snprintf(dat, len, "%s.dat", png);
    snprintf(gp, len, "%s.gp", png);
    if (!(fd = fopen(dat, "w")) || !(fg = fopen(gp, "w"))) {
        rc = eo_error(ctx, EO_ERR_IO, "stability: cannot write %s / %s", dat, gp);
        goto done;
    }
    fprintf(fd, "# Re(h lambda) Im(h lambda) rho(one step); one block per integrator\n");
    for (const void *const *p = eo_registry_list(EO_KIND_INTEGRATOR); *p && nm < 32; p++) {
        const eo_integrator_type *it = *p;
        eo_stability_result t;
        if (!eo_stability_theory(it->info.name, &t) || !t.first_order_form) continue;
        fprintf(fd, "# %s\n", it->info.name);
        for (int i = 0; i < NRE; i++) {
            double re = RE0 + (RE1 - RE0) * i / (NRE - 1);
            for (int j = 0; j < NIM; j++) {
                double im = -IM + 2 * IM * j / (NIM - 1), rho;
                if ((rc = eo_stability_rho(ctx, it, re, im, &rho)) < 0) goto done;
                fprintf(fd, "%.6g %.6g %.9g\n", re, im, isfinite(rho) ? fmin(rho, 1e6) : 1e6);
            }
            fprintf(fd, "\n");
        }
        fprintf(fd, "\n");
        names[nm++] = it->info.name;
    }
    fclose(fd);
    fd = NULL;
    static const char *const colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
                                         "#e377c2", "#17becf"};
    fprintf(fg, "# stability regions: contour rho = 1 of one step (elastopt stability --png)\n"
                "set view map\nunset surface\nset contour base\nset cntrparam levels discrete 1\n");
    for (int i = 0; i < nm; i++)
        fprintf(fg, "set table '%s.c%d'\nsplot '%s' index %d using 1:2:3 with lines\nunset table\n", png, i, dat, i);
    fprintf(fg, "set terminal png size 900,900 font 'DejaVu Sans,11' noenhanced\n"
                "set output '%s'\n"
                "set title '|R(h lambda)| = 1 (BE: stable outside its circle; heun = midpoint)'\n"
                "set xlabel 'Re(h lambda)'\nset ylabel 'Im(h lambda)'\n"
                "set size ratio -1\nset grid\nset key top left box opaque\n"
                "set xrange [%g:%g]\nset yrange [%g:%g]\n"
                "set xzeroaxis lt -1\nset yzeroaxis lt -1\nplot ",
            png, RE0, RE1, -IM, IM);
    for (int i = 0; i < nm; i++)
        fprintf(fg, "%s'%s.c%d' using 1:2 with lines lw %d lc rgb '%s' title '%s'", i ? ", \\\n     " : "", png,
                i, 2 + (nm - 1 - i), colors[i % 8], names[i]);
    fprintf(fg, "\n");
    fclose(fg);
    fg = NULL;
    snprintf(cmd, 3 * len + 64, "gnuplot '%s' > '%s.log' 2>&1", gp, png);
    if (system(cmd) != 0) rc = eo_error(ctx, EO_ERR_IO, "stability: gnuplot failed on %s (see %s.log; "
                                        "apt-get install gnuplot-nox)", gp, png);
done:
    if (fd) fclose(fd);
    if (fg) fclose(fg);
    free(dat);
    free(gp);
    free(cmd);
    return rc;
}

static int run(eo_ctx *ctx, int argc, char **argv)
{
    const char *png = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--png") == 0 && i + 1 < argc) png = argv[++i];
        else return eo_cli_unknown_arg(&eo_cmd_stability, "argument", argv[i]);
    }
    if (png) { /* before the measurements: a path that cannot be written fails at once */
        int rc = eo_path_check(ctx, png, EO_PATH_WRITE);
        if (rc < 0) return eo_cli_fail(ctx, rc);
    }
    printf("%-18s %-14s %-14s %-14s %-14s %s\n", "integrator", "real h*lambda", "theory", "imag h*omega", "theory",
           "agree");
    int all = 1;
    for (const void *const *p = eo_registry_list(EO_KIND_INTEGRATOR); *p; p++) {
        const eo_integrator_type *it = *p;
        eo_stability_result m, t;
        int rc = eo_stability_measure(ctx, it, &m);
        if (rc < 0) return eo_cli_fail(ctx, rc);
        int known = eo_stability_theory(it->info.name, &t);
        char mr[32], tr[32] = "?", mi[32], ti[32] = "?";
        axis_str(&m.real, mr, sizeof mr);
        axis_str(&m.imag, mi, sizeof mi);
        if (known) {
            axis_str(&t.real, tr, sizeof tr);
            axis_str(&t.imag, ti, sizeof ti);
        }
        int ok = known && eo_stability_agrees(&m, &t, 1e-3);
        if (!ok) all = 0;
        printf("%-18s %-14s %-14s %-14s %-14s %s\n", it->info.name, mr, tr, mi, ti,
               known ? (ok ? "yes" : "NO") : "no theory");
    }
    if (png) {
        int rc = write_png(ctx, png);
        if (rc < 0) return eo_cli_fail(ctx, rc);
        printf("wrote %s\n", png);
    }
    return all ? EO_EXIT_OK : EO_EXIT_NOT_CONVERGED;
}

const eo_cli_command eo_cmd_stability = {
    .name = "stability",
    .summary = "measured Dahlquist stability interval of every integrator vs theory",
    .usage = "elastopt stability [--png FILE]\n\n"
             "Applies one step of every registered integrator to the test equation y' = lambda y\n"
             "(real h*lambda < 0: a unit mass whose velocity obeys v' = lambda v) and to the\n"
             "undamped spring x'' = -omega^2 x (h*lambda = +-i h*omega), and finds the end of the\n"
             "stable interval by a scan and bisection on the amplification of one step (explicit\n"
             "integrators: their own explicit step; implicit ones: their weight/predict/velocity\n"
             "ops on the step problem min g(x), a 1D quadratic minimized in closed form). Prints\n"
             "integrator, measured real bound, theory, measured imaginary bound, theory, agreement\n"
             "(within 1e-3). 'unconditional': stable up to h*omega = 1e4; 'none': no stable\n"
             "interval. --png FILE: the curves |R(h lambda)| = 1 of the first-order-form methods\n"
             "(forward Euler, Heun, midpoint, RK4, backward Euler, Newmark) in the complex plane,\n"
             "drawn with gnuplot (FILE.dat and FILE.gp are kept).\n"
             "Exit status: 0 all agree, 1 some bound disagrees, 2 bad input or plot failed.\n",
    .run = run,
};
