/* elastopt run: simulate a scene, each implicit step solved by the configured solver.
 *
 * Everything is validated before anything is written (a bad scene exits 2 and leaves
 * no file): config + overrides, scene, solver section, unknown keys. Then into DIR
 * (--out, else output.dir, else out/<scene name>), locked by run.lock while the run
 * lasts (run_output.h lists the files):
 *   run.json                       how the run was set up (read by --restart)
 *   NAME.pvd + frame_NNNNNN.vtu    frames numbered by step (point data displacement,
 *                                  velocity; cell data energy density, J, inverted),
 *                                  every output.every steps
 *   steps.csv                      one row per step, appended and flushed every step
 *   iterations.csv                 one row per solver iteration, flushed every step
 *   restart.dat                    the state after the last completed step (atomic;
 *                                  with time.adaptive also the substep level and
 *                                  streak of the adaptive controller)
 *   restart.dat.R-of-P             under mpirun on P ranks: rank R's local state and the
 *                                  identity of its part (run_output.h), what --restart
 *                                  under mpirun continues from, on P ranks only
 *   summary.json                   build info, the config as given and as resolved, and
 *                                  per step: iterations, reason, converged, time, g,
 *                                  ‖∇g‖, centre of mass, max displacement, min J,
 *                                  inverted tets, kinetic, elastic, gravity and contact
 *                                  energy, work of prescribed motions, total energy;
 *                                  "energy_warning" when a conservative scene's total
 *                                  energy grew (eo_sim_energy_warning); rewritten
 *                                  atomically every output.summary_every steps and at
 *                                  the end
 * A folder holding an earlier run's files is refused unless --force (which removes
 * them first) or --restart DIR (which continues that run from restart.dat: positions,
 * velocities, time and step index; the constrained sets follow from t; the summary and
 * the pvd are rebuilt from steps.csv and the frames on disk).
 *
 * SIGINT / SIGTERM (under mpirun: to any rank; the ranks agree on the step and share the
 * signal's number): the handler only sets a flag; the iteration callback then returns
 * non-zero, the running step stops and is discarded (the state goes back to the last
 * completed step, its iteration rows are cut from iterations.csv), every file is
 * completed, summary.json says "stop_reason": "interrupted", and the exit status is
 * 130 / 143.
 *
 * Exit 0 if every step converged, 1 if some did not (or a solver error stopped the
 * run), 2 on bad input or an output that cannot be written.
 *
 * The steps run through eo_sim (sim.h), the library's one copy of the step protocol.
 * Explicit integrators (forward_euler, ..., leapfrog) advance without a solver: no
 * objective is minimized, so each step records iterations 0, reason
 * "explicit" (converged 0 / false: nothing was solved; not a failure either: such
 * steps count as "explicit" in summary.json's "step_counts" and the closing line,
 * and a run of them exits 0), g and grad_norm null (NaN in the CSV) and one CSV row
 * (iteration 0). The solver section is still validated (and unused).
 * After every step the state is checked: a non-finite position, velocity, energy or
 * force (an explicit integrator beyond its stability limit, or a blown-up implicit
 * solve) stops the run with reason "diverged_nonfinite" on that step and as
 * "stop_reason" in summary.json, an error message naming the step, and exit 1; the
 * last finite state is kept for the frames, the summary and restart.dat. */
#define _XOPEN_SOURCE 700
#include <jansson.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <ftw.h>
#include <unistd.h>

#include "eo_build_config.h"
#include "petsc_load.h"
#include "petsc/petsc_options.h"
#include "elastopt/io.h"
#include "elastopt/machine.h"
#include "elastopt/sim.h"
#include "progress.h"
#include "run_output.h"
#include "blas_fix.h"
#include "profile.h"
#include "scene_args.h"

extern const eo_cli_command eo_cmd_run;

/* ---------------------------------------------------------------- signals */

static volatile sig_atomic_t g_signal;

static void on_signal(int sig) { g_signal = sig; }

typedef struct signals {
    struct sigaction old_int, old_term;
} signals;

static void signals_install(signals *s)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    g_signal = 0;
    sigaction(SIGINT, &sa, &s->old_int);
    sigaction(SIGTERM, &sa, &s->old_term);
}

/* The signal seen by any rank (the largest number: SIGTERM over SIGINT), and with any
 * (may be NULL) whether `flag` was set on some rank; collective under MPI, g_signal
 * alone on one process. */
static int shared_signal(eo_ctx *ctx, int flag, int *any)
{
    if (eo_cli_size() <= 1) {
        if (any) *any = flag;
        return g_signal;
    }
    double v[2] = {g_signal, flag};
    if (eo_ctx_reduce(ctx, v, 2, EO_REDUCE_MAX) < 0) v[0] = g_signal ? g_signal : SIGTERM, v[1] = 1;
    if (any) *any = v[1] != 0;
    return (int)v[0];
}

static void signals_restore(const signals *s)
{
    sigaction(SIGINT, &s->old_int, NULL);
    sigaction(SIGTERM, &s->old_term, NULL);
}

/* ---------------------------------------------------------------- per iteration */

typedef struct run_state {
    FILE *csv;
    int step;
    int interrupted;  /* the callback stopped the running step */
    const eo_sim *sim; /* for the fallback entry running */
} run_state;

static int on_iter(const eo_iter_info *it, void *user)
{
    run_state *rs = user;
    char b[5][32];
    fprintf(rs->csv, "%d,%d,%s,%s,%s,%s,%s,%d,%d,%s,%d\n", rs->step, it->iteration, eo_run_num(b[0], it->time, 6),
            eo_run_num(b[1], it->g, 17), eo_run_num(b[2], it->grad_norm, 6), eo_run_num(b[3], it->decrement, 6),
            eo_run_num(b[4], it->alpha, 6), it->ls_evals, it->inverted, it->reason ? eo_reason_name(it->reason) : "",
            eo_sim_entry(rs->sim));
    if (g_signal) {
        rs->interrupted = 1;
        return 1;
    }
    return 0;
}

/* ---------------------------------------------------------------- frames */

typedef struct frame_buf {
    double *disp, *psi, *J;
    unsigned char *inv;
} frame_buf;

/* The fields of a frame of the step's (local) mesh, computed into b. */
static eo_vtu_fields frame_fields(eo_step *st, const frame_buf *b)
{
    const eo_mesh *m = eo_step_mesh(st);
    const double *x = eo_step_x(st);
    for (int i = 0; i < 3 * m->nv; i++) b->disp[i] = x[i] - m->X[i];
    eo_step_fields(st, b->psi, b->J, b->inv);
    return (eo_vtu_fields){.x = x, .displacement = b->disp, .velocity = eo_step_v(st), .energy_density = b->psi,
                           .J = b->J, .inverted = b->inv};
}

static int write_frame(eo_ctx *ctx, eo_step *st, const char *dir, int step, eo_pvd *pvd, const frame_buf *b)
{
    const eo_mesh *m = eo_step_mesh(st);
    eo_vtu_fields f = frame_fields(st, b);
    char file[64], path[1200];
    eo_run_frame_name(step, file, sizeof file);
    snprintf(path, sizeof path, "%s/%s", dir, file);
    int rc = eo_vtu_write(ctx, path, m, &f);
    if (rc < 0) return rc;
    return eo_pvd_add(ctx, pvd, eo_step_time(st), file);
}

/* A distributed run (dnv >= 0): x, v gathered on rank 0 in the input vertex order and the
 * work of the prescribed motions summed (every rank holds its part); nothing otherwise. */
static int gather_state(eo_ctx *ctx, int dnv, const double *xs, const double *vs, double *xg, double *vg,
                        double *work)
{
    if (dnv < 0) return EO_OK;
    if (eo_cli_dist_gather(xs, 3, xg) < 0 || eo_cli_dist_gather(vs, 3, vg) < 0)
        return eo_error(ctx, EO_ERR_IO, "the gather of the distributed state to rank 0 failed");
    eo_ctx_reduce(ctx, work, 1, EO_REDUCE_SUM); /* each rank's share of the prescribed work */
    return EO_OK;
}

/* A distributed run's frame: every rank writes its part of the mesh as the piece
 * frame_NNNNNN_rR.vtu in the run's folder, rank 0 the frame_NNNNNN.pvtu listing the pieces
 * (the arrays of eo_vtu_write) and adds it to the .pvd. */
static int write_piece(eo_ctx *ctx, eo_step *st, const char *dir, int step, eo_pvd *pvd, const frame_buf *b)
{
    const eo_mesh *m = eo_step_mesh(st);
    eo_vtu_fields f = frame_fields(st, b);
    char file[96], path[1200];
    snprintf(file, sizeof file, "frame_%06d_r%d.vtu", step, eo_cli_rank());
    snprintf(path, sizeof path, "%s/%s", dir, file);
    int rc = eo_vtu_write(ctx, path, m, &f);
    if (rc < 0 || eo_cli_rank() != 0) return rc;
    char pfile[64];
    snprintf(pfile, sizeof pfile, "frame_%06d.pvtu", step);
    snprintf(path, sizeof path, "%s/%s", dir, pfile);
    eo_afile *af = NULL; /* temporary + rename: an interrupted run leaves no half-written .pvtu */
    rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    FILE *o = eo_afile_fp(af);
    fprintf(o, "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" "
               "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n"
               "    <PPointData>\n"
               "      <PDataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\"/>\n"
               "      <PDataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\"/>\n"
               "    </PPointData>\n    <PCellData>\n"
               "      <PDataArray type=\"Float64\" Name=\"energy_density\"/>\n"
               "      <PDataArray type=\"Float64\" Name=\"J\"/>\n"
               "      <PDataArray type=\"UInt8\" Name=\"inverted\"/>\n%s"
               "    </PCellData>\n    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n"
               "    </PPoints>\n",
            m->tet_attr ? "      <PDataArray type=\"Int32\" Name=\"region\"/>\n" : "");
    for (int r = 0; r < eo_cli_size(); r++) fprintf(o, "    <Piece Source=\"frame_%06d_r%d.vtu\"/>\n", step, r);
    fprintf(o, "  </PUnstructuredGrid>\n</VTKFile>\n");
    rc = eo_afile_commit(ctx, &af);
    if (rc < 0) return rc;
    return eo_pvd_add(ctx, pvd, eo_step_time(st), pfile);
}

/* ---------------------------------------------------------------- summary.json */

static json_t *vec3(const double *v) { return json_pack("[fff]", v[0], v[1], v[2]); }

static json_t *real_or_null(double v) { return isfinite(v) ? json_real(v) : json_null(); }

typedef struct summary_info {
    const char *dir, *name, *pvd_file, *error;
    const char *status;       /* running | finished | interrupted | stopped */
    const char *stop_reason;  /* NULL, "interrupted", "diverged_nonfinite" */
    int nframes, restarted_at; /* restarted_at: step this process started from (0: fresh) */
    double wall;
} summary_info;

static int write_summary(eo_ctx *ctx, eo_cfg *cfg, const eo_scene *sc, const eo_solver *solver,
                         const eo_run_record *rec, int nrec, const eo_step_stats *s0, const summary_info *in,
                         const char *energy_warning)
{
    json_t *root = json_object();
    json_object_set_new(root, "scene", json_string(in->name));
    json_object_set_new(root, "config_file", json_string(eo_cfg_file(cfg)));
    eo_machine mach;
    eo_machine_get(&mach);
    json_object_set_new(root, "build", json_pack("{s:s, s:s, s:s, s:s}", "version", mach.version, "buildtype",
                                                 mach.build_type, "git_revision", mach.revision, "compiler",
                                                 mach.compiler));
    eo_blas_info blas;
    eo_blas_get(&blas);
    char blas_line[640];
    eo_blas_describe(blas_line, sizeof blas_line);
    json_object_set_new(root, "blas",
                        json_pack("{s:s, s:s, s:s, s:s, s:i, s:s, s:s, s:b, s:s?, s:s?, s:s}", "name", blas.name,
                                  "version", blas.version, "config", blas.config, "core", blas.core, "threads",
                                  blas.threads, "threads_policy", eo_cli_blas_threads_note(),
                                  "library", blas.library, "fallback", blas.fallback, "recommended_coretype",
                                  blas.recommended, "fixed_from", blas.fixed_from[0] ? blas.fixed_from : NULL,
                                  "line", blas_line));
    json_object_set_new(root, "config", json_deep_copy(eo_cfg_root(cfg)));
    json_t *res = json_object();
    json_object_set_new(res, "scene", eo_scene_to_json(sc));
    json_t *sj = eo_solver_to_json(solver);
    json_object_set_new(res, "solver", sj ? sj : json_null());
    json_object_set_new(root, "resolved", res);
    json_object_set_new(root, "initial", json_pack("{s:o, s:f, s:f, s:i, s:f, s:f}", "com", vec3(s0->com), "min_J",
                                                   s0->min_J, "max_disp", s0->max_disp, "inverted", s0->inverted,
                                                   "kinetic", s0->kinetic, "elastic", s0->elastic));
    json_t *ini = json_object_get(root, "initial");
    json_object_set_new(ini, "gravity_potential", real_or_null(s0->gravity));
    json_object_set_new(ini, "contact", real_or_null(s0->contact));
    json_object_set_new(ini, "potential", real_or_null(s0->potential));
    json_object_set_new(ini, "work_prescribed", real_or_null(s0->work_prescribed));
    json_object_set_new(ini, "total_energy", real_or_null(s0->total_energy));
    json_t *steps = json_array(), *bad = json_array();
    int all = 1, nconv = 0, nexpl = 0;
    long total_iters = 0, total_rejected = 0, total_substeps = 0, total_not_pd = 0;
    double total_time = 0, total_cpu = 0, min_substep = INFINITY;
    for (int k = 0; k < nrec; k++) {
        const eo_run_record *r = rec + k;
        int ok = eo_reason_is_converged(r->reason), expl_step = eo_reason_is_explicit(r->reason);
        int conv = ok && !expl_step; /* an explicit step solved nothing: counted apart */
        all &= ok;
        nconv += conv;
        nexpl += expl_step;
        if (!ok) json_array_append_new(bad, json_integer(r->step));
        total_iters += r->iterations;
        total_not_pd += r->n_not_pd;
        total_time += r->time;
        total_cpu += isfinite(r->cpu) ? r->cpu : 0;
        json_t *e = json_object();
        json_object_set_new(e, "step", json_integer(r->step));
        json_object_set_new(e, "t", json_real(r->t));
        json_object_set_new(e, "iterations", json_integer(r->iterations));
        json_object_set_new(e, "reason", json_string(eo_reason_name(r->reason)));
        json_object_set_new(e, "converged", json_boolean(conv));
        json_object_set_new(e, "entry", json_integer(r->entry)); /* 0 = solver, k = solver.fallback[k-1] */
        json_t *tried = json_array(); /* the entries that stopped before it, and why */
        for (int j = 0; j < r->n_entries && j < r->entry; j++)
            json_array_append_new(tried, json_pack("{s:i, s:s, s:i}", "entry", j, "reason",
                                                   eo_reason_name(r->entry_reason[j]), "iterations",
                                                   r->entry_iterations[j]));
        json_object_set_new(e, "fallback_from", tried);
        json_object_set_new(e, "time", real_or_null(r->time));
        json_object_set_new(e, "wall_time", real_or_null(r->wall));
        /* "time" is the wall time of the solve; cpu_time the solving thread's CPU time */
        json_object_set_new(e, "cpu_time", real_or_null(r->cpu));
        json_object_set_new(e, "g", real_or_null(r->g));
        json_object_set_new(e, "grad_norm", real_or_null(r->grad_norm));
        json_object_set_new(e, "evaluations", json_pack("{s:I, s:I, s:I, s:I, s:I}", "value", (json_int_t)r->n_value,
                                                        "gradient", (json_int_t)r->n_gradient, "hessian",
                                                        (json_int_t)r->n_hessian, "factor", (json_int_t)r->n_factor,
                                                        "not_pd", (json_int_t)r->n_not_pd));
        json_object_set_new(e, "com", vec3(r->stats.com));
        json_object_set_new(e, "max_disp", real_or_null(r->stats.max_disp));
        json_object_set_new(e, "min_J", real_or_null(r->stats.min_J));
        json_object_set_new(e, "inverted", json_integer(r->stats.inverted));
        json_object_set_new(e, "kinetic", real_or_null(r->stats.kinetic));
        json_object_set_new(e, "elastic", real_or_null(r->stats.elastic));
        json_object_set_new(e, "gravity_potential", real_or_null(r->stats.gravity));
        json_object_set_new(e, "contact", real_or_null(r->stats.contact));
        json_object_set_new(e, "potential", real_or_null(r->stats.potential));
        json_object_set_new(e, "work_prescribed", real_or_null(r->stats.work_prescribed));
        json_object_set_new(e, "total_energy", real_or_null(r->stats.total_energy));
        json_object_set_new(e, "rejected", json_integer(r->rejected)); /* adaptive stepping */
        json_object_set_new(e, "substeps", json_integer(r->substeps));
        json_object_set_new(e, "min_substep", real_or_null(r->min_substep));
        total_rejected += r->rejected;
        total_substeps += r->substeps;
        if (r->min_substep < min_substep) min_substep = r->min_substep;
        json_array_append_new(steps, e);
    }
    if (nrec < sc->time.steps) all = 0;
    json_object_set_new(root, "status", json_string(in->status));
    json_object_set_new(root, "steps", steps);
    json_object_set_new(root, "steps_run", json_integer(nrec));
    json_object_set_new(root, "steps_planned", json_integer(sc->time.steps));
    /* "all_converged": no step failed (every step converged or was explicit) */
    json_object_set_new(root, "all_converged", json_boolean(all));
    json_object_set_new(root, "not_converged", bad);
    json_object_set_new(root, "step_counts", json_pack("{s:i, s:i, s:i}", "converged", nconv, "explicit", nexpl,
                                                       "not_converged", nrec - nconv - nexpl));
    json_object_set_new(root, "total_iterations", json_integer(total_iters));
    json_object_set_new(root, "total_solve_time", json_real(total_time));
    json_object_set_new(root, "total_solve_cpu_time", json_real(total_cpu));
    /* factorizations that found the matrix not positive definite (project_on_demand's
     * fallbacks to the projected Hessian): counted here, not printed */
    json_object_set_new(root, "total_not_pd", json_integer(total_not_pd));
    json_object_set_new(root, "adaptive", json_pack("{s:b, s:I, s:I, s:o}", "on", sc->time.adaptive, "rejected",
                                                    (json_int_t)total_rejected, "substeps", (json_int_t)total_substeps,
                                                    "min_substep", real_or_null(min_substep)));
    json_object_set_new(root, "wall_time", json_real(in->wall));
    json_object_set_new(root, "restarted_at_step", in->restarted_at ? json_integer(in->restarted_at) : json_null());
    json_object_set_new(root, "frames", json_integer(in->nframes));
    json_object_set_new(root, "pvd", in->pvd_file ? json_string(in->pvd_file) : json_null());
    json_object_set_new(root, "error", in->error ? json_string(in->error) : json_null());
    json_object_set_new(root, "stop_reason", in->stop_reason ? json_string(in->stop_reason) : json_null());
    /* total energy of a conservative scene grown past EO_SIM_ENERGY_GROWTH (sim.h) */
    json_object_set_new(root, "energy_warning", energy_warning ? json_string(energy_warning) : json_null());
    char path[1100];
    snprintf(path, sizeof path, "%s/summary.json", in->dir);
    eo_afile *f = NULL;
    int rc = eo_afile_open(ctx, path, &f);
    if (rc >= 0) {
        char *text = eo_json_dumps(root, JSON_INDENT(2));
        if (text) {
            fputs(text, eo_afile_fp(f));
            fputc('\n', eo_afile_fp(f));
            free(text);
            rc = eo_afile_commit(ctx, &f);
        } else {
            eo_afile_abort(ctx, &f);
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (summary)");
        }
    }
    json_decref(root);
    return rc;
}

/* ---------------------------------------------------------------- run.json */

static int write_json_file(eo_ctx *ctx, const char *path, json_t *j)
{
    eo_afile *f = NULL;
    int rc = eo_afile_open(ctx, path, &f);
    if (rc < 0) return rc;
    char *text = eo_json_dumps(j, JSON_INDENT(2));
    if (!text) {
        eo_afile_abort(ctx, &f);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (%s)", path);
    }
    fputs(text, eo_afile_fp(f));
    fputc('\n', eo_afile_fp(f));
    free(text);
    return eo_afile_commit(ctx, &f);
}

/* The run's origin: absolute scene file or built-in name, every override so far. */
typedef struct run_origin {
    char name[256];
    char file[PATH_MAX];   /* "" for a built-in scene */
    char builtin[128];
    const char *ov[2 * EO_CLI_MAX_OVERRIDES + 1];  /* NULL-terminated */
    int nov;
} run_origin;

static int write_run_json(eo_ctx *ctx, const char *dir, const run_origin *o, eo_cfg *cfg)
{
    json_t *ov = json_array();
    for (int k = 0; k < o->nov; k++) json_array_append_new(ov, json_string(o->ov[k]));
    json_t *j = json_pack("{s:s, s:i, s:s, s:o, s:o, s:o, s:O}", "format", "elastopt-run", "version", 1, "name",
                          o->name, "scene_file", o->file[0] ? json_string(o->file) : json_null(), "builtin",
                          o->file[0] ? json_null() : json_string(o->builtin), "overrides", ov, "config",
                          eo_cfg_root(cfg));
    if (!j) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (run.json)");
    char path[1100];
    snprintf(path, sizeof path, "%s/run.json", dir);
    int rc = write_json_file(ctx, path, j);
    json_decref(j);
    return rc;
}

/* A continued run's outputs: the frame series so far (the frames of steps 0..first on disk,
 * .pvtu files with pvtu, else .vtu; pvd NULL: none) into pvd, run.json rewritten, the logs
 * opened for appending at their ends (so that ftell is the end from the start). */
static int resume_outputs(eo_ctx *ctx, const char *dir, int first, const eo_run_record *rec, int pvtu, eo_pvd *pvd,
                          int *nframes, const run_origin *org, eo_cfg *cfg, const char *itpath, const char *stpath,
                          FILE **csv, FILE **scsv)
{
    int rc;
    char path[4352];
    for (int s = 0; pvd && s <= first; s++) {
        char file[64];
        struct stat fst;
        if (pvtu) snprintf(file, sizeof file, "frame_%06d.pvtu", s);
        else eo_run_frame_name(s, file, sizeof file);
        snprintf(path, sizeof path, "%s/%s", dir, file);
        if (stat(path, &fst) != 0) continue;
        if ((rc = eo_pvd_add(ctx, pvd, s ? rec[s - 1].t : 0.0, file)) < 0) return rc;
        (*nframes)++;
    }
    if ((rc = write_run_json(ctx, dir, org, cfg)) < 0) return rc;
    if (!(*csv = fopen(itpath, "a")) || !(*scsv = fopen(stpath, "a")))
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(*csv ? stpath : itpath, -1), "cannot append");
    fseek(*csv, 0, SEEK_END);
    fseek(*scsv, 0, SEEK_END);
    return EO_OK;
}

/* Read DIR/run.json into o (override strings point into *doc: keep it until the end),
 * and load the scene's config document as the run had it, checked against the recorded
 * one. */
static int read_run_json(eo_ctx *ctx, const char *dir, run_origin *o, json_t **doc, eo_cfg **cfg)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/run.json", dir);
    char *text = NULL;
    size_t len;
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(dir, -1), "not a folder; expected the output folder of an "
                                                                   "earlier elastopt run");
    if (stat(path, &st) != 0)
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(dir, -1),
                           "no run.json: not the output folder of an elastopt run (or of one from a version without "
                           "restarts)");
    int rc = eo_read_file_max(ctx, path, 2 * EO_CFG_MAX_BYTES, "a run's run.json (2 EO_CFG_MAX_BYTES)", &text, &len);
    if (rc < 0) return rc;
    json_error_t err;
    *doc = json_loads(text, 0, &err);
    eo_free(ctx, text);
    if (!*doc) return eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(path, err.line), "%s", err.text);
    const char *name = json_string_value(json_object_get(*doc, "name"));
    const char *file = json_string_value(json_object_get(*doc, "scene_file"));
    const char *builtin = json_string_value(json_object_get(*doc, "builtin"));
    json_t *ov = json_object_get(*doc, "overrides"), *conf = json_object_get(*doc, "config");
    if (!name || (!file && !builtin) || !json_is_array(ov) || !json_is_object(conf) ||
        json_array_size(ov) > EO_CLI_MAX_OVERRIDES)
        return eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(path, -1),
                           "expected name, scene_file or builtin, overrides (at most %d) and config",
                           EO_CLI_MAX_OVERRIDES);
    snprintf(o->name, sizeof o->name, "%s", name);
    snprintf(o->file, sizeof o->file, "%s", file ? file : "");
    snprintf(o->builtin, sizeof o->builtin, "%s", builtin ? builtin : "");
    o->nov = 0;
    for (size_t k = 0; k < json_array_size(ov); k++) {
        const char *s = json_string_value(json_array_get(ov, k));
        if (!s) return eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(path, -1), "overrides: expected strings");
        o->ov[o->nov++] = s;
    }
    o->ov[o->nov] = NULL;
    rc = eo_scene_cfg_load(ctx, file, file ? NULL : builtin, cfg);
    for (int k = 0; rc >= 0 && k < o->nov; k++) rc = eo_cfg_override(ctx, *cfg, o->ov[k]);
    if (rc < 0) return rc;
    if (!json_equal(eo_cfg_root(*cfg), conf))
        return eo_error_at(ctx, EO_ERR_INVALID, EO_ERRLOC_FILE(file ? file : path, -1),
                           "the scene changed since the run in %s was started; continuing it would not continue "
                           "the same simulation (start a new run instead)",
                           dir);
    return EO_OK;
}

/* ---------------------------------------------------------------- adaptive state */

/* The adaptive controller's state as the restart array "adaptive": level, streak. */
static void get_adaptive(const eo_sim *sim, double as[2])
{
    int level, streak;
    eo_sim_get_adaptive_state(sim, &level, &streak);
    as[0] = level;
    as[1] = streak;
}

static int set_adaptive(eo_ctx *ctx, eo_sim *sim, const char *path, const double as[2])
{
    if (!(as[0] >= 0 && as[0] <= EO_STEP_MAX_SUBSTEP && as[0] == floor(as[0]) && as[1] >= 0 && as[1] <= INT_MAX &&
          as[1] == floor(as[1])))
        return eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(path, -1), "array adaptive: bad level %g or streak %g",
                           as[0], as[1]);
    return eo_sim_set_adaptive_state(sim, (int)as[0], (int)as[1]);
}

/* ---------------------------------------------------------------- distributed restart */

/* The identity of this rank's part: the backend's hash of its vertices' input numbers and
 * ownership (eo_cli_dist_layout_id) extended over the local mesh itself (tets and rest
 * positions, in their local order: the order of every local sum). */
static unsigned long long part_id(const eo_mesh *m)
{
    unsigned long long h = eo_cli_dist_layout_id();
    const unsigned char *p[2] = {(const unsigned char *)m->tets, (const unsigned char *)m->X};
    const size_t n[2] = {(size_t)4 * m->nt * sizeof(int), (size_t)3 * m->nv * sizeof(double)};
    for (int a = 0; a < 2; a++)
        for (size_t i = 0; i < n[a]; i++) h = (h ^ p[a][i]) * 1099511628211ULL;
    return h;
}

/* The "partition" array of a per-rank restart file (run_output.h). */
static void part_fill(double part[7], const eo_mesh *m, int dnv)
{
    const unsigned long long h = part_id(m);
    part[0] = eo_cli_size();
    part[1] = eo_cli_rank();
    part[2] = m->nv;
    part[3] = m->nt;
    part[4] = dnv;
    part[5] = (double)(h >> 32);
    part[6] = (double)(h & 0xffffffffULL);
}

/* Under mpirun on P ranks, is the run in dir one this process can continue? Every rank
 * looks at the same folder and takes the same decision (before anything is written). */
static int restart_ranks_check(eo_ctx *ctx, const char *dir)
{
    int q, nq;
    const int P = eo_cli_size(), kinds = eo_run_restart_ranks(dir, &q, &nq);
    if (kinds > 1)
        return eo_error_at(ctx, EO_ERR_INVALID, EO_ERRLOC_FILE(dir, -1),
                           "holds per-rank restart files (restart.dat.R-of-P) of runs on different rank counts; "
                           "cannot tell which one to continue");
    if (P > 1 && kinds == 0)
        return eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_FILE(dir, -1),
                           "the run ran on one process (no per-rank restart files restart.dat.R-of-P; or under "
                           "mpirun with a version that did not write them): continue it without mpirun (this is "
                           "mpirun with %d ranks)", P);
    if (kinds == 1 && q != P)
        return eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_FILE(dir, -1),
                           "the run ran distributed over %d MPI ranks (restart.dat.R-of-%d), this is %s%.0d%s; its "
                           "state is kept per rank and continues on the same rank count only: "
                           "mpirun -n %d elastopt run --restart %s",
                           q, q, P > 1 ? "mpirun with " : "one process", P > 1 ? P : 0, P > 1 ? " ranks" : "", q, dir);
    if (kinds == 1 && nq != q)
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(dir, -1),
                           "holds %d of the %d per-rank restart files restart.dat.R-of-%d; cannot continue the run",
                           nq, q, q);
    return EO_OK;
}

/* The partition recorded in a per-rank restart file against this run's. */
static int restart_part_check(eo_ctx *ctx, const char *path, const double rec[7], const double now[7])
{
    if (rec[0] != now[0] || rec[1] != now[1])
        return eo_error_at(ctx, EO_ERR_INVALID, EO_ERRLOC_FILE(path, -1),
                           "written by rank %g of %g; this is rank %g of %g", rec[1], rec[0], now[1], now[0]);
    if (rec[4] != now[4] || rec[2] != now[2] || rec[3] != now[3] || rec[5] != now[5] || rec[6] != now[6])
        return eo_error_at(ctx, EO_ERR_INVALID, EO_ERRLOC_FILE(path, -1),
                           "rank %g's part of the mesh differs from the one the run had (%g of %g vertices and %g "
                           "tets then, %g of %g and %g now, or the same counts in another distribution): the mesh "
                           "or its partitioning changed; continuing would not be the same simulation",
                           now[1], rec[2], rec[4], rec[3], now[2], now[4], now[3]);
    return EO_OK;
}

/* ---------------------------------------------------------------- the command */

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb, (void)flag, (void)ftw;
    return remove(path);
}

static int run(eo_ctx *ctx, int argc, char **argv)
{
    eo_cli_scene_args a = {0};
    const char *out_dir = NULL, *restart = NULL;
    int force = 0, profile = 0;
    eo_cli_verbosity verb = EO_CLI_NORMAL;
    for (int i = 1; i < argc; i++) {
        int r = eo_cli_scene_arg(&eo_cmd_run, argc, argv, &i, &a);
        if (r < 0) return EO_EXIT_BAD_INPUT;
        if (r > 0) continue;
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) out_dir = argv[++i];
        else if (strcmp(argv[i], "--restart") == 0 && i + 1 < argc) restart = argv[++i];
        else if (strcmp(argv[i], "--force") == 0) force = 1;
        else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) verb = EO_CLI_QUIET;
        else if (strcmp(argv[i], "--verbose") == 0 || strcmp(argv[i], "-v") == 0) verb = EO_CLI_VERBOSE;
        else if (strcmp(argv[i], "--profile") == 0) profile = 1;
        else return eo_cli_unknown_arg(&eo_cmd_run, "option", argv[i]);
    }
    if (restart && (a.file || a.scene || out_dir || force))
        return eo_cli_usage_error(&eo_cmd_run, "--restart DIR continues the run in DIR: give no scene, --out or "
                                               "--force with it (-o overrides, e.g. -o time.steps=N, are allowed)");
    eo_sim *sim = NULL;
    eo_cfg *cfg = NULL;
    eo_pvd *pvd = NULL;
    eo_run_record *rec = NULL;
    double *fbuf = NULL, *xs = NULL, *vs = NULL, *hs = NULL, *xg = NULL, *vg = NULL;
    double work = 0; /* the work of prescribed motions, for restart.dat */
    FILE *csv = NULL, *scsv = NULL;
    json_t *run_doc = NULL;
    eo_run_dir rd = {0};
    signals sig;
    int rc, nrec = 0, nframes = 0, first = 0, have_signals = 0, agreed = 0;
    char rank_tmp[1100] = "";
    char out_real[1024] = ""; /* the run's folder, on a rank other than 0 (its pieces go there) */
    char dir[1024], path[1400], pvd_file[300], errtext[1024] = "";
    static run_origin org; /* big (PATH_MAX); one per process */
    memset(&org, 0, sizeof org);
    eo_cli_progress pg;
    memset(&pg, 0, sizeof pg);

    /* ---- validate everything before writing anything (eo_sim_create: scene, solver
     * section, every method's section, unknown keys) */
    if (restart) {
        EO_TRY(rc = read_run_json(ctx, restart, &org, &run_doc, &cfg));
        /* the rank count the run had (per-rank restart files) against this one: every
         * rank, before anything is written */
        EO_TRY(rc = restart_ranks_check(ctx, restart));
    } else {
        eo_cli_scene_name(&a, org.name, sizeof org.name);
        if (a.file) {
            /* the file must be readable before realpath (a FIFO must not block) */
            EO_TRY(rc = eo_scene_cfg_load(ctx, a.file, NULL, &cfg));
            if (!realpath(a.file, org.file)) snprintf(org.file, sizeof org.file, "%s", a.file);
        } else {
            snprintf(org.builtin, sizeof org.builtin, "%s", a.scene ? a.scene : "cantilever");
            EO_TRY(rc = eo_scene_cfg_load(ctx, NULL, org.builtin, &cfg));
        }
    }
    for (int k = 0; k < a.noverrides; k++) {
        EO_TRY(rc = eo_cfg_override(ctx, cfg, a.overrides[k]));
        org.ov[org.nov++] = a.overrides[k];
    }
    org.ov[org.nov] = NULL;
    rc = eo_sim_create(ctx, cfg, &sim); /* takes cfg over */
    cfg = NULL;
    if (rc < 0) goto fail;
    if (eo_cli_size() > 1 && !eo_cli_agree(1)) { /* before the next collective (statistics, gathers) */
        agreed = 1;
        rc = eo_error(ctx, EO_ERR_IO, "another MPI rank could not load the scene");
        goto fail;
    }
    cfg = NULL;
    const eo_scene *sc = eo_sim_scene(sim);
    eo_step *st = eo_sim_step_problem(sim);
    if (eo_cli_size() > 1) { /* under mpirun every rank holds a part: only distributed solvers can run it */
        const eo_solver_opts *so = eo_solver_get_opts(eo_sim_solver(sim));
        const char *on = so->optimizer;
        const int dist_opt = strcmp(so->backend, "petsc") == 0 || strncmp(on, "petsc_", 6) == 0 ||
                             strncmp(on, "snes_", 5) == 0 || strncmp(on, "tao_", 4) == 0;
        if (eo_sim_is_explicit(sim)) {
            rc = eo_error(ctx, EO_ERR_UNSUPPORTED, "under mpirun (%d ranks): integrator %s is explicit and has no "
                          "distributed form; run it on one process", eo_cli_size(), sc->integrator->info.name);
            goto fail;
        }
        if (!dist_opt) {
            rc = eo_error(ctx, EO_ERR_UNSUPPORTED, "under mpirun (%d ranks) the solver must be distributed: add -o "
                          "solver.backend=petsc (or run on one process); optimizer '%s' would run on each rank's part "
                          "of the mesh alone", eo_cli_size(), on);
            goto fail;
        }
    }
    if (restart) snprintf(dir, sizeof dir, "%s", restart);
    else if (out_dir) snprintf(dir, sizeof dir, "%s", out_dir);
    else if (sc->output.dir[0]) snprintf(dir, sizeof dir, "%s", sc->output.dir);
    else snprintf(dir, sizeof dir, "out/%s", org.name);
    /* the handlers first: from here on a signal only sets the flag, so that a rank's scratch
     * folder made below is always removed */
    signals_install(&sig);
    have_signals = 1;
    if (eo_cli_rank() != 0) { /* under MPI, rank 0 writes the run; the others a private scratch folder */
        const char *tmpdir = getenv("TMPDIR");
        snprintf(rank_tmp, sizeof rank_tmp, "%s/elastopt-rank%d-XXXXXX", tmpdir && *tmpdir ? tmpdir : "/tmp",
                 eo_cli_rank());
        if (!mkdtemp(rank_tmp)) {
            rank_tmp[0] = 0;
            rc = eo_error(ctx, EO_ERR_IO, "rank %d: cannot make a scratch folder in $TMPDIR or /tmp", eo_cli_rank());
            goto fail;
        }
        snprintf(out_real, sizeof out_real, "%s", dir);
        snprintf(dir, sizeof dir, "%s", rank_tmp);
    }
    const eo_mesh *m = sc->mesh;
    const int nsteps = sc->time.steps;
    const size_t nf = (size_t)(3 * m->nv > 0 ? 3 * m->nv : 1);
    {   /* a step count whose records cannot be held: name the key, not "out of memory" */
        eo_machine mach;
        eo_machine_get(&mach);
        double need = (double)nsteps * sizeof *rec;
        if (mach.mem_bytes > 0 && need > 0.5 * mach.mem_bytes) {
            rc = eo_cfg_error(ctx, eo_sim_cfg(sim), "time.steps", EO_ERR_RANGE,
                              "%d steps: their per-step records need %.3g GB, more than half of this machine's "
                              "%.3g GB", nsteps, need / 1e9, mach.mem_bytes / 1e9);
            goto fail;
        }
    }
    rec = eo_calloc(ctx, (size_t)nsteps, sizeof *rec);
    fbuf = eo_malloc(ctx, (size_t)(3 * m->nv + 2 * m->nt) * sizeof(double) + (size_t)m->nt + 1);
    xs = eo_malloc(ctx, nf * sizeof(double));
    vs = eo_malloc(ctx, nf * sizeof(double));
    const size_t hlen = eo_sim_history_len(sim); /* a multistep integrator's history (bdf2) */
    hs = eo_malloc(ctx, (hlen ? hlen : 1) * sizeof(double));
    if (!rec || !fbuf || !xs || !vs || !hs) {
        rc = eo_cfg_error(ctx, eo_sim_cfg(sim), "time.steps", EO_ERR_NOMEM,
                          "out of memory for the records of %d steps", nsteps);
        goto fail;
    }
    /* a distributed run (each rank simulates its part of the mesh): restart.dat holds the
     * whole state, gathered on rank 0 in the input vertex order */
    const int dnv = eo_cli_dist_nv();
    const int nv_out = dnv >= 0 ? dnv : m->nv;
    if (dnv >= 0) {
        xg = eo_calloc(ctx, (size_t)(3 * dnv > 0 ? 3 * dnv : 1), sizeof(double));
        vg = eo_calloc(ctx, (size_t)(3 * dnv > 0 ? 3 * dnv : 1), sizeof(double));
        if (!xg || !vg) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (the gathered state)");
            goto fail;
        }
    }
    frame_buf fb = {.disp = fbuf, .psi = fbuf + 3 * m->nv, .J = fbuf + 3 * m->nv + m->nt};
    fb.inv = (unsigned char *)(fb.J + m->nt);
    eo_step_stats s0;
    EO_TRY(rc = eo_step_stats_compute(st, &s0)); /* the scene's initial state */
    eo_cli_scene_report(ctx, sc, verb == EO_CLI_QUIET);
    /* a distributed run: the lines above describe rank 0's part; this one the whole mesh */
    if ((verb == EO_CLI_VERBOSE || (dnv >= 0 && verb != EO_CLI_QUIET)) && eo_cli_mesh_note())
        printf("%s\n", eo_cli_mesh_note());

    /* ---- the folder: lock, earlier runs */
    EO_TRY(rc = eo_run_dir_open(ctx, dir, &rd));
    /* frames: rank 0 writes them; in a distributed run every rank writes its piece and rank
     * 0 the .pvtu that lists them */
    const int frames = sc->output.vtu && sc->output.every > 0 && (eo_cli_rank() == 0 || dnv >= 0);
    const char *piece_dir = out_real[0] ? out_real : dir;
    snprintf(pvd_file, sizeof pvd_file, "%s.pvd", org.name);
    snprintf(path, sizeof path, "%s/%s", dir, pvd_file);
    if (frames && eo_cli_rank() == 0) EO_TRY(rc = eo_pvd_create(ctx, path, &pvd));
    char itpath[1200], stpath[1200], rspath[1200];
    snprintf(itpath, sizeof itpath, "%s/iterations.csv", dir);
    snprintf(stpath, sizeof stpath, "%s/steps.csv", dir);
    snprintf(rspath, sizeof rspath, "%s/restart.dat", dir);
    /* adaptive stepping: the controller's substep level and converged substeps in a row
     * (steps end on nominal boundaries, so that is all a restart needs besides the state) */
    double as[2] = {0, 0};
    eo_run_array arrays[] = {
        {.name = "x", .data = dnv >= 0 ? xg : xs, .count = 3 * (size_t)nv_out, .required = 1},
        {.name = "v", .data = dnv >= 0 ? vg : vs, .count = 3 * (size_t)nv_out, .required = 1},
        {.name = "work_prescribed", .data = &work, .count = 1, .required = 0},
        {.name = "history", .data = hs, .count = hlen, .required = 0},
        {.name = "adaptive", .data = as, .count = 2, .required = 0},
    };
    /* restart.dat of a distributed run: the whole state for readers, without the history
     * (local to each rank: in the per-rank files) */
    int narrays = hlen && dnv < 0 ? 4 : 3;
    if (eo_sim_adaptive(sim)) { /* the table without the history, if none */
        arrays[narrays] = arrays[4];
        narrays++;
    }
    eo_run_array *aarr = eo_sim_adaptive(sim) ? arrays + narrays - 1 : NULL;
    /* a distributed run's per-rank restart file (run_output.h): this rank's local state,
     * what --restart under mpirun continues from */
    double part[7] = {0}, part_rec[7] = {0}, work_local = 0;
    char rkpath[1400] = "";
    eo_run_array rarrays[6];
    int nrarrays = 0;
    if (dnv >= 0) {
        char rkname[64];
        eo_run_restart_rank_name(eo_cli_rank(), eo_cli_size(), rkname, sizeof rkname);
        snprintf(rkpath, sizeof rkpath, "%s/%s", piece_dir, rkname);
        part_fill(part, m, dnv);
        rarrays[nrarrays++] = (eo_run_array){.name = "x", .data = xs, .count = 3 * (size_t)m->nv, .required = 1};
        rarrays[nrarrays++] = (eo_run_array){.name = "v", .data = vs, .count = 3 * (size_t)m->nv, .required = 1};
        rarrays[nrarrays++] = (eo_run_array){.name = "work_prescribed", .data = &work_local, .count = 1,
                                             .required = 1};
        if (hlen) rarrays[nrarrays++] = (eo_run_array){.name = "history", .data = hs, .count = hlen, .required = 1};
        if (eo_sim_adaptive(sim))
            rarrays[nrarrays++] = (eo_run_array){.name = "adaptive", .data = as, .count = 2, .required = 1};
        rarrays[nrarrays++] = (eo_run_array){.name = "partition", .data = part_rec, .count = 7, .required = 1};
    }
    if (restart && dnv < 0 && eo_cli_size() > 1) {
        rc = eo_error(ctx, EO_ERR_UNSUPPORTED, "--restart under mpirun: the scene is not distributed over the ranks");
        goto fail;
    }
    if (restart && dnv >= 0) { /* every rank its own file, checked on every rank before anything is written */
        double t = 0;
        rc = eo_run_restart_read(ctx, rkpath, &first, &t, m->nv, rarrays, nrarrays);
        if (rc >= 0) rc = restart_part_check(ctx, rkpath, part_rec, part);
        if (!eo_cli_agree(rc >= 0)) {
            agreed = 1; /* every rank took part in this agreement: no other one in fail */
            if (rc >= 0) rc = eo_error(ctx, EO_ERR_IO, "another MPI rank could not continue from its restart file");
            goto fail;
        }
        double lo[2] = {first, t}, hi[2] = {first, t};
        if (eo_ctx_reduce(ctx, lo, 2, EO_REDUCE_MIN) < 0 || eo_ctx_reduce(ctx, hi, 2, EO_REDUCE_MAX) < 0) {
            rc = eo_error(ctx, EO_ERR_IO, "the ranks could not compare their restart steps");
            goto fail;
        }
        if (lo[0] != hi[0] || lo[1] != hi[1]) { /* a rank killed between its file and the others' */
            rc = eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(restart, -1),
                             "the per-rank restart files are at different steps (%g to %g): a rank was stopped "
                             "while they were written; the run cannot be continued exactly", lo[0], hi[0]);
            goto fail;
        }
        if (first > nsteps) {
            rc = eo_error_at(ctx, EO_ERR_RANGE, EO_ERRLOC_FILE(rkpath, -1),
                             "the run is at step %d, beyond time.steps = %d; raise it (-o time.steps=N)", first,
                             nsteps);
            goto fail;
        }
        if (eo_cli_rank() == 0) { /* the logs (rank 0's): cut after the restart step, the records */
            EO_TRY(rc = eo_run_logs_resume(ctx, &rd, first, rec));
            eo_run_dir_remove_frames_after(&rd, first);
        }
        nrec = first;
        EO_TRY(rc = eo_sim_set_state(sim, xs, vs, t, first));
        if (eo_sim_adaptive(sim)) EO_TRY(rc = set_adaptive(ctx, sim, rkpath, as));
        if (hlen) EO_TRY(rc = eo_sim_set_history(sim, hs));
        eo_step_set_work_prescribed(st, work_local);
        EO_TRY(rc = resume_outputs(ctx, dir, first, rec, 1, pvd, &nframes, &org, eo_sim_cfg(sim), itpath, stpath,
                                   &csv, &scsv)); /* the series from rank 0's .pvtu files */
    } else if (restart) {
        double t;
        EO_TRY(rc = eo_run_restart_read(ctx, rspath, &first, &t, m->nv, arrays, narrays));
        if (first > nsteps) {
            rc = eo_error_at(ctx, EO_ERR_RANGE, EO_ERRLOC_FILE(rspath, -1),
                             "the run is at step %d, beyond time.steps = %d; raise it (-o time.steps=N)", first,
                             nsteps);
            goto fail;
        }
        EO_TRY(rc = eo_run_logs_resume(ctx, &rd, first, rec));
        nrec = first;
        EO_TRY(rc = eo_sim_set_state(sim, xs, vs, t, first));
        if (aarr && aarr->present) EO_TRY(rc = set_adaptive(ctx, sim, rspath, as));
        if (hlen && arrays[3].present) EO_TRY(rc = eo_sim_set_history(sim, hs));
        /* the work of prescribed motions so far (absent from older restart files: from steps.csv) */
        eo_step_set_work_prescribed(st, arrays[2].present ? work
                                        : first > 0 && isfinite(rec[first - 1].stats.work_prescribed)
                                            ? rec[first - 1].stats.work_prescribed : 0);
        eo_run_dir_remove_frames_after(&rd, first);
        EO_TRY(rc = resume_outputs(ctx, dir, first, rec, 0, frames ? pvd : NULL, &nframes, &org, eo_sim_cfg(sim),
                                   itpath, stpath, &csv, &scsv)); /* the series from the frames on disk */
    } else {
        char names[200];
        int n = eo_run_dir_count_earlier(&rd, names, sizeof names);
        if (n > 0 && !force) {
            rc = eo_error(ctx, EO_ERR_IO,
                          "%s holds %d files of an earlier run (%s%s); use --force to replace them, "
                          "--restart %s to continue that run, or --out DIR for another folder",
                          dir, n, names, n > 4 ? ", ..." : "", dir);
            goto fail;
        }
        if (n > 0) EO_TRY(rc = eo_run_dir_remove_earlier(ctx, &rd));
        EO_TRY(rc = write_run_json(ctx, dir, &org, eo_sim_cfg(sim)));
        if (!(csv = fopen(itpath, "w")) || !(scsv = fopen(stpath, "w"))) {
            rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(csv ? stpath : itpath, -1), "cannot write");
            goto fail;
        }
        fprintf(csv, "%s\n", EO_RUN_ITER_CSV_HEADER);
        fprintf(scsv, "%s\n", EO_RUN_STEPS_CSV_HEADER);
        fflush(csv);
        fflush(scsv);
        if (frames && dnv < 0) { /* a distributed run's first frame: once every rank is set up */
            EO_TRY(rc = write_frame(ctx, st, dir, 0, pvd, &fb));
            nframes++;
        }
        eo_sim_get_state(sim, xs, vs, NULL, NULL);
        if (hlen) EO_TRY(rc = eo_sim_get_history(sim, hs));
        work = work_local = eo_step_work_prescribed(st);
        get_adaptive(sim, as);
        /* a distributed run's gather (collective) waits until every rank is set up */
        if (dnv < 0) EO_TRY(rc = eo_run_restart_write(ctx, rspath, 0, eo_sim_time(sim), nv_out, arrays, narrays));
    }
    summary_info si = {.dir = dir, .name = org.name, .pvd_file = frames ? pvd_file : NULL, .status = "running",
                       .restarted_at = first};
    EO_TRY(rc = write_summary(ctx, eo_sim_cfg(sim), sc, eo_sim_solver(sim), rec, nrec, &s0, &si, eo_sim_energy_warning(sim)));

    memcpy(part_rec, part, sizeof part); /* what this run's per-rank restart files record */
    /* ---- every rank ready (under MPI: one rank's failure ends all of them, with exit 2) */
    agreed = 1;
    if (!eo_cli_agree(1)) {
        rc = eo_error(ctx, EO_ERR_IO, "another MPI rank could not set up the run");
        goto fail;
    }
    /* the other ranks' scratch folder goes now: their logs stay open (unlinked), they write
     * no restart.dat or summary.json (rank 0 does), so an abnormal end (a rank killed by
     * mpirun) leaves nothing in the temp dir */
    if (rank_tmp[0]) {
        nftw(rank_tmp, remove_entry, 8, FTW_DEPTH | FTW_PHYS);
        rank_tmp[0] = 0;
        rd.locked = 0;
    }
    const int writer = eo_cli_rank() == 0;
    if (dnv >= 0 && first == 0) { /* the initial state's restart.dat (gathered on rank 0), per-rank files */
        EO_TRY(rc = gather_state(ctx, dnv, xs, vs, xg, vg, &work));
        rc = writer ? eo_run_restart_write(ctx, rspath, 0, eo_sim_time(sim), nv_out, arrays, narrays) : EO_OK;
        if (rc >= 0) rc = eo_run_restart_write(ctx, rkpath, 0, eo_sim_time(sim), m->nv, rarrays, nrarrays);
        if (!eo_cli_agree(rc >= 0)) {
            if (rc >= 0) rc = eo_error(ctx, EO_ERR_IO, "another MPI rank could not write its restart file");
            goto fail;
        }
    }
    if (frames && dnv >= 0 && first == 0) { /* rank 0 has made (or cleared) the folder by now */
        rc = write_piece(ctx, st, piece_dir, 0, pvd, &fb);
        if (!eo_cli_agree(rc >= 0)) {
            if (rc >= 0) rc = eo_error(ctx, EO_ERR_IO, "another MPI rank could not write its frame piece");
            goto fail;
        }
        nframes++;
    }

    /* ---- the steps */
    run_state rs = {.csv = csv, .sim = sim};
    eo_sim_set_iter_callback(sim, on_iter, &rs);
    const int expl = eo_sim_is_explicit(sim);
    int all_converged = 1, diverged = 0;
    for (int k = 0; k < nrec; k++) all_converged &= eo_reason_is_converged(rec[k].reason);
    if (dnv >= 0 && first > 0) /* a continued distributed run: rank 0 read the records of the steps so far */
        all_converged = eo_cli_agree(eo_cli_rank() == 0 ? all_converged : 1);
    eo_cli_progress_init(&pg, verb, nsteps, first);
    double t_start = eo_wtime();
    eo_cli_profile prof;
    eo_cli_profile_begin(&prof, profile, sim);
    int stop_sig = 0; /* a signal seen by any rank (all ranks stop at the same step) */
    for (int k = first; k < nsteps; k++) {
        if ((stop_sig = shared_signal(ctx, 0, NULL))) break;
        rs.step = k + 1;
        double tb;
        eo_sim_get_state(sim, xs, vs, &tb, NULL);
        const double work_before = eo_step_work_prescribed(st);
        if (hlen) EO_TRY(rc = eo_sim_get_history(sim, hs));
        get_adaptive(sim, as);
        long off = ftell(csv);
        eo_sim_step_result r;
        double w0 = eo_wtime();
        rc = eo_sim_step(sim, &r);
        double wall = eo_wtime() - w0;
        if (eo_cli_size() > 1) { /* stopped on some rank: on all, with the signal it saw */
            int any = rs.interrupted;
            const int sg = shared_signal(ctx, rs.interrupted, &any);
            if (any) {
                rs.interrupted = 1;
                g_signal = sg ? sg : SIGTERM;
            }
        }
        if (rs.interrupted) { /* the step was stopped half-way: back to the last completed one */
            EO_TRY(rc = eo_sim_set_state(sim, xs, vs, tb, k));
            EO_TRY(rc = set_adaptive(ctx, sim, rspath, as));
            if (hlen) EO_TRY(rc = eo_sim_set_history(sim, hs));
            eo_step_set_work_prescribed(st, work_before);
            fflush(csv);
            if (off >= 0 && ftruncate(fileno(csv), (off_t)off) != 0) {
                rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(itpath, -1), "cannot cut the interrupted step");
                goto fail;
            }
            break;
        }
        if (rc < 0) {
            snprintf(errtext, sizeof errtext, "step %d: %s", k + 1, eo_ctx_message(ctx));
            all_converged = 0;
            rc = EO_OK;
            break;
        }
        if (expl) fprintf(csv, "%d,0,%.6e,,,,,0,-1,%s,0\n", k + 1, r.time, eo_reason_name(r.reason));
        eo_run_record *e = rec + nrec++;
        *e = (eo_run_record){.step = k + 1, .iterations = r.iterations, .reason = r.reason, .t = r.t,
                             .time = r.time, .cpu = r.cpu_time, .wall = wall, .g = r.g, .grad_norm = r.grad_norm,
                             .n_value = r.n_value, .n_gradient = r.n_gradient, .n_hessian = r.n_hessian,
                             .n_factor = r.n_factor, .n_not_pd = r.n_not_pd, .stats = r.stats, .entry = r.entry,
                             .n_entries = r.n_entries, .rejected = r.rejected, .substeps = r.substeps,
                             .min_substep = r.min_substep};
        memcpy(e->entry_reason, r.entry_reason, sizeof e->entry_reason);
        memcpy(e->entry_iterations, r.entry_iterations, sizeof e->entry_iterations);
        eo_run_record_write(scsv, e);
        if (fflush(csv) != 0 || fflush(scsv) != 0) {
            rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(stpath, -1), "write failed at step %d", k + 1);
            goto fail;
        }
        all_converged &= eo_reason_is_converged(r.reason);
        if (r.reason == EO_DIVERGED_NONFINITE) {
            /* the sim kept the last finite state (tₙ); restart.dat stays at it */
            snprintf(errtext, sizeof errtext,
                     "step %d (t = %g s): the state became non-finite (diverged_nonfinite)%s", k + 1,
                     eo_sim_time(sim) + sc->time.dt,
                     expl ? "; the explicit integrator is beyond its stability limit: reduce time.dt" : "");
            e->g = e->grad_norm = NAN;
            diverged = 1;
            break;
        }
        int io = EO_OK; /* this step's files; in a distributed run agreed over the ranks below */
        if (frames && (k + 1) % sc->output.every == 0) {
            io = dnv >= 0 ? write_piece(ctx, st, piece_dir, k + 1, pvd, &fb) : write_frame(ctx, st, dir, k + 1, pvd, &fb);
            if (io >= 0) nframes++;
        }
        eo_sim_get_state(sim, xs, vs, NULL, NULL);
        if (hlen) EO_TRY(rc = eo_sim_get_history(sim, hs));
        work = work_local = eo_step_work_prescribed(st);
        get_adaptive(sim, as);
        EO_TRY(rc = gather_state(ctx, dnv, xs, vs, xg, vg, &work));
        if (io >= 0 && writer) io = eo_run_restart_write(ctx, rspath, k + 1, eo_sim_time(sim), nv_out, arrays, narrays);
        if (io >= 0 && dnv >= 0) io = eo_run_restart_write(ctx, rkpath, k + 1, eo_sim_time(sim), m->nv, rarrays, nrarrays);
        if (io >= 0 && writer && sc->output.summary_every > 0 && (k + 1) % sc->output.summary_every == 0 &&
            k + 1 < nsteps) {
            si.nframes = nframes;
            si.wall = eo_wtime() - t_start;
            io = write_summary(ctx, eo_sim_cfg(sim), sc, eo_sim_solver(sim), rec, nrec, &s0, &si, eo_sim_energy_warning(sim));
        }
        if (dnv >= 0 ? !eo_cli_agree(io >= 0) : io < 0) {
            rc = io < 0 ? io : eo_error(ctx, EO_ERR_IO, "another MPI rank could not write its files of step %d", k + 1);
            goto fail;
        }
        eo_cli_progress_step(&pg, e);
        eo_cli_profile_step(&prof, sim, k + 1);
    }
    eo_cli_profile_total(&prof, sim, org.name);
    /* a signal that came after the last step's checks: under MPI seen the same on every rank */
    const int signo = stop_sig ? stop_sig : shared_signal(ctx, 0, NULL);
    double wall = eo_wtime() - t_start;
    eo_cli_progress_done(&pg);
    int bad_close = fclose(csv) != 0;
    bad_close |= fclose(scsv) != 0;
    csv = scsv = NULL;
    if (bad_close) {
        rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(stpath, -1), "write failed");
        goto fail;
    }
    si.nframes = nframes;
    si.wall = wall;
    si.error = errtext[0] ? errtext : NULL;
    si.stop_reason = diverged ? eo_reason_name(EO_DIVERGED_NONFINITE) : signo ? "interrupted" : NULL;
    si.status = signo ? "interrupted" : (diverged || errtext[0]) ? "stopped" : "finished";
    rc = writer ? write_summary(ctx, eo_sim_cfg(sim), sc, eo_sim_solver(sim), rec, nrec, &s0, &si,
                                eo_sim_energy_warning(sim)) : EO_OK;
    /* under MPI: no rank ends before rank 0 has completed the run's files (mpirun aborts the
     * job, SIGCONT, then SIGTERM and SIGKILL to the ranks still running, as soon as one rank
     * exits with a non-zero status: 1 after a step that did not converge, 130 / 143) */
    if (eo_cli_size() > 1 && !eo_cli_agree(rc >= 0) && rc >= 0)
        rc = eo_error(ctx, EO_ERR_IO, "rank 0 could not write the run's summary.json");
    if (rc < 0) goto fail;
    if (errtext[0]) fprintf(stderr, "elastopt: error: %s\n", errtext);
    if (signo && verb != EO_CLI_QUIET)
        fprintf(stderr, "elastopt: interrupted (%s) after step %d of %d; every file is complete; continue with: "
                        "elastopt run --restart %s\n",
                signo == SIGINT ? "SIGINT" : "SIGTERM", nrec, nsteps, dir);
    if (verb != EO_CLI_QUIET) {
        char closing[600];
        long total_iters = 0;
        for (int k = 0; k < nrec; k++) total_iters += rec[k].iterations;
        eo_cli_progress_closing(rec, nrec, nsteps, closing, sizeof closing);
        printf("%s: %s; %ld iterations, %.3f s; final min J %.4g, inverted %d; summary: %s/summary.json\n",
               org.name, closing, total_iters, wall, nrec ? rec[nrec - 1].stats.min_J : s0.min_J,
               nrec ? rec[nrec - 1].stats.inverted : s0.inverted, dir);
    }
    rc = signo ? 128 + signo : all_converged ? EO_EXIT_OK : EO_EXIT_NOT_CONVERGED;
    goto done;
fail:
    if (!agreed) eo_cli_agree(0);
    eo_cli_progress_done(&pg);
    eo_cli_fail(ctx, rc);
    rc = EO_EXIT_BAD_INPUT;
done:
    if (csv) fclose(csv);
    if (scsv) fclose(scsv);
    eo_run_dir_close(&rd);
    /* under MPI the flag-only handlers stay until the process exits: a SIGTERM from mpirun
     * tearing the job down after the run ended (another rank exited first with a non-zero
     * status) does not replace this rank's exit status */
    if (have_signals && eo_cli_size() <= 1) signals_restore(&sig);
    eo_pvd_destroy(&pvd);
    eo_free(ctx, rec);
    eo_free(ctx, fbuf);
    eo_free(ctx, xs);
    eo_free(ctx, vs);
    eo_free(ctx, hs);
    eo_free(ctx, xg);
    eo_free(ctx, vg);
    eo_cfg_destroy(&cfg);
    eo_sim_destroy(&sim);
    json_decref(run_doc);
    if (rank_tmp[0]) nftw(rank_tmp, remove_entry, 8, FTW_DEPTH | FTW_PHYS);
    return rc;
}

const eo_cli_command eo_cmd_run = {
    .name = "run",
    .summary = "simulate a scene (default: the built-in cantilever); continue one with --restart",
    .usage = "elastopt run [SCENE.json | --scene NAME] [-o key=value ...] [--out DIR] [--force]\n"
             "             [--quiet | --verbose] [--profile]\n"
             "elastopt run --restart DIR [-o key=value ...] [--quiet | --verbose]\n\n"
             "Runs the scene's time steps, each an optimization problem solved by the configured\n"
             "solver. Without a scene runs the built-in `cantilever`. `-o` overrides any config key\n"
             "(e.g. -o solver.hessian_fix=abs -o time.steps=10). Writes into DIR (default\n"
             "output.dir, else out/<scene name>): NAME.pvd + frame_NNNNNN.vtu frames (NNNNNN =\n"
             "the step), steps.csv (one row per step) and iterations.csv (one row per solver\n"
             "iteration), both appended and flushed every step, restart.dat (the state after\n"
             "the last step), run.json (how the run was set up) and summary.json (config, build,\n"
             "per-step results; rewritten every output.summary_every steps and at the end).\n"
             "A folder holding an earlier run's files is refused unless --force (which removes\n"
             "them first); a folder another run is writing into (run.lock) is refused.\n"
             "--restart DIR continues the run in DIR (interrupted or finished; raise time.steps\n"
             "with -o to go further) from its last completed step; the trajectory is the same,\n"
             "bit for bit, as that of an uninterrupted run. A run under mpirun continues under\n"
             "mpirun on the same number of ranks (each rank from its restart.dat.R-of-P; another\n"
             "count is refused, exit 2).\n"
             "Ctrl-C (SIGINT) or SIGTERM stops the running step and ends the run cleanly: every\n"
             "file complete, summary.json \"stop_reason\": \"interrupted\", exit 130 / 143.\n"
             "On a terminal a progress line is redrawn on stderr (step, simulated time, time per\n"
             "step, ETA, last step's iterations, worst reason); not on a terminal a line every\n"
             "5 s at most; --verbose: one line per step; --quiet: nothing but errors.\n"
             "--profile: the BLAS line (name, version, core, threads, \"(fixed from Prescott)\"\n"
             "after a re-execution with OPENBLAS_CORETYPE), then per step and in total, the\n"
             "solver's time in assembly, factorization (symbolic, numeric), solves, line search,\n"
             "gradients and other, and the ratio of a Newton iteration to its numeric\n"
             "factorization (stdout). summary.json carries the same BLAS facts under \"blas\".\n"
             "Exit status: 0 every step converged, 1 some step did not, 2 bad input or an output\n"
             "that cannot be written (nothing written), 130/143 interrupted.\n",
    .run = run,
};
