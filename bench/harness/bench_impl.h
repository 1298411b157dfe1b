/* Private structures of the benchmark harness (bench/harness/bench.c runs,
 * bench/harness/bench_report.c writes the report and plots). Not installed. */
#ifndef ELASTOPT_BENCH_IMPL_H
#define ELASTOPT_BENCH_IMPL_H

#include <stdio.h>

#include "bench.h"

enum { BENCH_MAX_LIST = 16, BENCH_MAX_REPEATS = 16 };
enum { BENCH_SELECT_FIRST, BENCH_SELECT_MOTION, BENCH_SELECT_CORRECTION };

typedef struct bench_scene {
    char name[160];
    eo_bench_scene_opts o;
    char file[1600];      /* resolved path of the scene config, "" = built-in o.scene */
    char **set;           /* "key=<json>" overrides, eo_malloc'd */
    int nset;
    int steps, skip, max_iters, repeats;
    int select;           /* BENCH_SELECT_* */
    int horizon;          /* reference steps after skip to choose from (>= steps) */
    int traj_window;      /* trajectory from the reference state before the first measured step */
    unsigned char ibud_on[BENCH_MAX_LIST]; /* which of the suite's iter_budgets run on this scene */
    int nibud_on;
    double time_budget;
    int nt, nv;           /* mesh size, known after the load check */
    char model[32];
    double E, nu;
} bench_scene;

typedef struct bench_config {
    char name[128];
    char **set;
    int nset;
    int needs_hessian;
    int own_max_iters;    /* the configuration sets solver.max_iters itself */
    char *resolved;       /* JSON text of eo_solver_to_json (eo_malloc'd) */
} bench_config;

struct eo_bench_suite {
    eo_bench_opts o;
    char path[1024], dir[1024];
    double thr[BENCH_MAX_LIST];
    int nthr;
    double bud[BENCH_MAX_LIST];
    int nbud;
    int ibud[BENCH_MAX_LIST];  /* fixed iteration budgets per frame */
    int nibud;
    char **skipped;       /* optional scenes dropped at load: "name: message" */
    int nskipped;
    bench_scene *sc;
    int nsc, capsc;
    bench_config *cf;
    int ncf, capcf;
    int baseline;
    int *req;             /* required configurations (indices) */
    int nreq;
    eo_ctx *ctx;                       ///< context it was created with (its destroy uses it)
};

/* Per-step result of one configuration. */
typedef struct bench_step_res {
    int iters;            /* iterations of the median-time repeat */
    int reached;          /* curve reached the target */
    int stagnated;        /* stopped: no decrease of g for STAGNATION_ITERS iterations */
    int reason;           /* reason of the first timed repeat (EXTERNAL = reached) */
    double final_err;     /* last relative energy error */
    double ttt[BENCH_MAX_LIST][BENCH_MAX_REPEATS];
    double eab[BENCH_MAX_LIST][BENCH_MAX_REPEATS];
    int nrep;
    int nonfinite;        /* the solver met a non-finite g or gradient (and stopped) */
    int nan;              /* a NaN was recorded or the returned x is not finite */
} bench_step_res;

/* One frame of a trajectory run. */
typedef struct bench_traj_res {
    int iters, reason;
    double time, g, dist;
    double time2;         /* the other clock's solve time */
    int nonfinite, nan;
} bench_traj_res;

/* Fixed iteration budget runs of one (scene, configuration, budget) over the window. */
typedef struct bench_fixed_res {
    int frames;           /* frames run (the window, or fewer after a non-finite state) */
    int iters;            /* iterations over the frames run */
    int short_frames;     /* frames that stopped before the budget (the solver's own reason) */
    int first_short_reason;
    double ms_med, ms_min, ms_max; /* solve time per frame (s): median, min, max over frames */
    double max_dist, final_dist;   /* RMS distance to the reference (m) */
    int nonfinite, nan;
} bench_fixed_res;

/* Aggregated result of one (scene, configuration). */
typedef struct bench_pair {
    int nsteps;           /* measured steps */
    int ntraj;            /* steps of the trajectory run (scene steps traj_first ..) */
    int traj_first;       /* scene step (0-based) the trajectory starts with */
    bench_step_res *st;   /* nsteps */
    bench_traj_res *tr;   /* ntraj */
    bench_fixed_res fixed[BENCH_MAX_LIST]; /* per iter_budgets entry */
    int traj_done;        /* frames run */
    double ttt_med[BENCH_MAX_LIST], ttt_min[BENCH_MAX_LIST], ttt_max[BENCH_MAX_LIST];
    double eab_med[BENCH_MAX_LIST];
    int steps_reached;
    int nonfinite, nan;
    int traj_converged;   /* steps converged in the trajectory run */
    int first_bad_step, first_bad_reason; /* trajectory index (scene step traj_first + it) or measured step */
    double traj_time, traj_max_dist, traj_final_dist;
    int max_iters;        /* iteration cap of its curve and trajectory runs */
    double budget;        /* time budget (s, the suite's clock) of its curve and trajectory runs */
    char status[16];      /* converged | stopped | non-finite */
    char reason[160];
} bench_pair;

/* Reference of one step. */
typedef struct bench_ref {
    double t, g0, gstar, dec, time, floor;
    double tgrad;         /* one gradient evaluation at x0 (s, the suite's clock): the data profiles' unit */
    int iters, reason, converged, n;
    int rounding;         /* converged at the rounding floor, not at ref_tol */
    /* the Ipopt check (ipopt_check): -1 not run; else Ipopt's reason and its differences
     * to x*: (g_ip - g*)/|g0 - g*| and ||x_ip - x*||_M / ||x0 - x*||_M */
    int ip_reason, ip_iters;
    double ip_de, ip_pe, ip_time;
} bench_ref;

typedef struct bench_scene_res {
    int nv;               /* vertices of the whole mesh (a distributed run: summed over the owners) */
    bench_ref *ref;       /* steps: the measured ones (with the Ipopt check) */
    bench_ref *allref;    /* nref: every reference step (Ipopt check not filled in) */
    int *meas;            /* steps: scene step (0-based) of each measured step, increasing */
    int nref;             /* reference steps run (skip + steps, or skip + horizon) */
    double *motion;       /* nref: per-step RMS motion of the reference (m) */
    double *correction;   /* nref: RMS distance from each step's start guess to x* (m) */
    int win0, win1;       /* measured window: scene steps meas[0] .. meas[steps-1] (inclusive) */
    bench_pair *pair;     /* ncf */
    double ref_disp;      /* RMS displacement of the reference over the trajectory run's steps */
    double win_disp;      /* RMS displacement of the reference over the measured window */
    double tmin;          /* smallest positive iterate time (plot's left edge) */
    int repeats;          /* timed repeats of every run on this scene */
    double start_minJ, end_minJ, start_elastic, end_elastic;
    int start_inverted, end_inverted;   /* reference state before the first and after the last step */
    int plotted;
} bench_scene_res;

typedef struct bench_out {
    const eo_bench_suite *s;
    const char *dir;
    int repeats;
    int plots;
    bench_scene_res *res; /* nsc */
    double t_start, t_end;
    double cpu_seconds;   /* CPU time of the thread that ran the suite (eo_cputime) */
    int wall;             /* times are wall seconds (clock "wall"), else thread CPU seconds */
    char load_start[64], load_end[64];
    eo_bench_summary *sum;
    int gnuplot;          /* 1 if gnuplot was found */
} bench_out;

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

#define PROF_NTAU 101   /* tau = 2^(i/10), i = 0..100: 1 .. 1024 */
#define PROF_NKAPPA 71  /* kappa = 10^(i/10), i = 0..70: 1 .. 1e7 gradient-equivalents */

/* output.c: number formats shared by the report and the plots */
int bench_headline_thr(const eo_bench_suite *s);
void bench_fmt_thr(double t, char *buf, size_t n);
void bench_fmt_ms(double t, char *buf, size_t n);
void bench_fmt_sci(double v, char *buf, size_t n);
int bench_pair_iters(const bench_pair *p);

/* stats.c: fastest and second fastest configuration of a scene at threshold j (-1 if none) */
void bench_fastest(const bench_out *b, int si, int j, int *first, int *second);
/* the own-stopping-rule summary (pareto_pts above): computed, freed, its winners */
int bench_pareto_compute(eo_ctx *ctx, const bench_out *b, pareto_pts *pp);
void bench_pareto_free(eo_ctx *ctx, pareto_pts *pp);
void bench_pareto_winners(const eo_bench_suite *s, const pareto_pts *pp, int *fast, int *close);
/* the profiles: tau and kappa grids, strata (0 = "all"), instances, costs of every
 * configuration on every instance of a stratum at level j, rho_c(tau), d_c(kappa) */
double bench_prof_tau(int i);
double bench_prof_kappa(int i);
int bench_prof_strata(const eo_bench_suite *s, const char **names, int cap);
int bench_prof_ninstances(const eo_bench_suite *s);
int bench_prof_costs(const bench_out *b, int stratum, const char *const *names, int j, double *t, double *tg);
double bench_prof_rho(const double *t, int np, int ncf, int c, double tau);
double bench_prof_data(const double *t, const double *tg, int np, int ncf, int c, double kappa);

/* suite.c: the pieces run.c uses */
int bench_wrap_err(eo_ctx *ctx, int rc, const char *file, const char *what, const char *name);
int bench_scene_cfg(eo_ctx *ctx, const bench_scene *b, eo_cfg **cfg);
int bench_config_cfg(eo_ctx *ctx, const bench_config *c, eo_cfg **cfg, eo_solver_opts *so);

/* stats.c: a configuration's status and aggregates on a scene */
void bench_aggregate(const eo_bench_suite *s, int repeats, bench_pair *p, int is_traj, double ref_disp,
                     const int *meas);

/* output.c, plots.c, report.c */
int eo_bench_write_summary(eo_ctx *ctx, bench_out *b);
int eo_bench_write_report(eo_ctx *ctx, bench_out *b);
int eo_bench_plot_scene(eo_ctx *ctx, bench_out *b, int si);
int eo_bench_plot_pareto(eo_ctx *ctx, bench_out *b);
/* perf_profile.csv and data_profile.csv (output.c), their plots (plots.c), the report's
 * section (report.c) */
int eo_bench_write_profiles(eo_ctx *ctx, bench_out *b);
int eo_bench_plot_profiles(eo_ctx *ctx, bench_out *b);
int eo_bench_write_profile_section(eo_ctx *ctx, FILE *f, const bench_out *b);
/* Keep row k of a curve of n iterates in the CSV / plot data. */
void eo_bench_csv_num(FILE *f, double v);
int eo_bench_keep_row(int k, int n, int full_rows);
/* Base file name of a scene for the plots (letters, digits, - _ .). */
void eo_bench_file_name(const char *name, char *buf, size_t n);

#endif
