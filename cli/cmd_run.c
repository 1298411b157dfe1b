/* elastopt run: simulate a scene, each implicit step solved by the configured solver.
 *
 * Everything is validated before anything is written (a bad scene exits 2 and leaves
 * no file): config + overrides, scene, solver section, unknown keys. Then into DIR:
 *   <name>.pvd + <name>_NNNN.vtu   frames (point data displacement, velocity; cell data
 *                                  energy density, J, inverted), every output.every steps
 *   iterations.csv                 one row per solver iteration of every step
 *   summary.json                   build info, the config as given and as resolved, and
 *                                  per step: iterations, reason, converged, time, g,
 *                                  ‖∇g‖, centre of mass, max displacement, min J,
 *                                  inverted tets, kinetic and elastic energy
 * all written atomically. Exit 0 if every step converged, 1 if some did not, 2 on bad
 * input.
 *
 * The steps run through eo_sim (sim.h), the library's one copy of the step protocol.
 * Explicit integrators (forward_euler, ..., leapfrog) advance without a solver: no
 * objective is minimized, so each step records iterations 0, reason
 * "converged_explicit", g and grad_norm null (NaN in the CSV) and one CSV row
 * (iteration 0). The solver section is still validated (and unused).
 * After every step the state is checked: a non-finite position, velocity, energy or
 * force (an explicit integrator beyond its stability limit, or a blown-up implicit
 * solve) stops the run with reason "diverged_nonfinite" on that step and as
 * "stop_reason" in summary.json (null when the run was not stopped), an error message
 * naming the step, and exit 1; the last finite state is kept for the frames and the
 * summary. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "eo_build_config.h"
#include "elastopt/io.h"
#include "elastopt/machine.h"
#include "elastopt/sim.h"
#include "profile.h"
#include "scene_args.h"

extern const eo_cli_command eo_cmd_run;

typedef struct step_record {
    int iterations, reason;
    double t, time, g, grad_norm;
    long n_value, n_gradient, n_hessian, n_factor;
    eo_step_stats stats;
} step_record;

typedef struct run_state {
    FILE *csv;
    int step;
    int progress;
    int nsteps;
    int iters_this_step;
} run_state;

static int on_iter(const eo_iter_info *it, void *user)
{
    run_state *rs = user;
    fprintf(rs->csv, "%d,%d,%.6e,%.17g,%.6e,%.6e,%.6e,%d,%d,%s\n", rs->step, it->iteration, it->time, it->g,
            it->grad_norm, it->decrement, it->alpha, it->ls_evals, it->inverted,
            it->reason ? eo_reason_name(it->reason) : "");
    rs->iters_this_step = it->iteration;
    return 0;
}

static void progress(const run_state *rs, int done, double t, int iters)
{
    if (!rs->progress) return;
    const int W = 30;
    int fill = rs->nsteps ? done * W / rs->nsteps : W;
    char bar[64];
    for (int i = 0; i < W; i++) bar[i] = i < fill ? '#' : '.';
    bar[W] = 0;
    fprintf(stderr, "\r[%s] step %d/%d  t = %.4g s  iterations %d   ", bar, done, rs->nsteps, t, iters);
    if (done == rs->nsteps) fprintf(stderr, "\n");
    fflush(stderr);
}

static int write_frame(eo_ctx *ctx, eo_step *st, const char *dir, const char *name, int frame, eo_pvd *pvd,
                       double *disp, double *psi, double *J, unsigned char *inv)
{
    const eo_mesh *m = eo_step_mesh(st);
    const double *x = eo_step_x(st);
    for (int i = 0; i < 3 * m->nv; i++) disp[i] = x[i] - m->X[i];
    eo_step_fields(st, psi, J, inv);
    eo_vtu_fields f = {.x = x, .displacement = disp, .velocity = eo_step_v(st), .energy_density = psi,
                       .J = J, .inverted = inv};
    char file[300], path[1400];
    snprintf(file, sizeof file, "%s_%04d.vtu", name, frame);
    snprintf(path, sizeof path, "%s/%s", dir, file);
    int rc = eo_vtu_write(ctx, path, m, &f);
    if (rc < 0) return rc;
    return eo_pvd_add(ctx, pvd, eo_step_time(st), file);
}

static json_t *vec3(const double *v) { return json_pack("[fff]", v[0], v[1], v[2]); }

static json_t *real_or_null(double v) { return isfinite(v) ? json_real(v) : json_null(); }

static int write_summary(eo_ctx *ctx, const char *dir, const char *name, eo_cfg *cfg, const eo_scene *sc,
                         const eo_solver *solver, const step_record *rec, int nrec, const eo_step_stats *s0,
                         int nframes, const char *pvd_file, const char *error)
{
    json_t *root = json_object();
    json_object_set_new(root, "scene", json_string(name));
    json_object_set_new(root, "config_file", json_string(eo_cfg_file(cfg)));
    eo_machine mach;
    eo_machine_get(&mach);
    json_object_set_new(root, "build", json_pack("{s:s, s:s, s:s, s:s}", "version", mach.version, "buildtype",
                                                 mach.build_type, "git_revision", mach.revision, "compiler",
                                                 mach.compiler));
    json_object_set_new(root, "config", json_deep_copy(eo_cfg_root(cfg)));
    json_t *res = json_object();
    json_object_set_new(res, "scene", eo_scene_to_json(sc));
    json_t *sj = eo_solver_to_json(solver);
    json_object_set_new(res, "solver", sj ? sj : json_null());
    json_object_set_new(root, "resolved", res);
    json_object_set_new(root, "initial", json_pack("{s:o, s:f, s:f, s:i, s:f, s:f}", "com", vec3(s0->com), "min_J",
                                                   s0->min_J, "max_disp", s0->max_disp, "inverted", s0->inverted,
                                                   "kinetic", s0->kinetic, "elastic", s0->elastic));
    json_t *steps = json_array(), *bad = json_array();
    int all = 1;
    long total_iters = 0;
    double total_time = 0;
    for (int k = 0; k < nrec; k++) {
        const step_record *r = rec + k;
        int conv = eo_reason_is_converged(r->reason);
        all &= conv;
        if (!conv) json_array_append_new(bad, json_integer(k + 1));
        total_iters += r->iterations;
        total_time += r->time;
        json_t *e = json_object();
        json_object_set_new(e, "step", json_integer(k + 1));
        json_object_set_new(e, "t", json_real(r->t));
        json_object_set_new(e, "iterations", json_integer(r->iterations));
        json_object_set_new(e, "reason", json_string(eo_reason_name(r->reason)));
        json_object_set_new(e, "converged", json_boolean(conv));
        json_object_set_new(e, "time", json_real(r->time));
        json_object_set_new(e, "g", real_or_null(r->g));
        json_object_set_new(e, "grad_norm", real_or_null(r->grad_norm));
        json_object_set_new(e, "evaluations", json_pack("{s:I, s:I, s:I, s:I}", "value", (json_int_t)r->n_value,
                                                        "gradient", (json_int_t)r->n_gradient, "hessian",
                                                        (json_int_t)r->n_hessian, "factor", (json_int_t)r->n_factor));
        json_object_set_new(e, "com", vec3(r->stats.com));
        json_object_set_new(e, "max_disp", real_or_null(r->stats.max_disp));
        json_object_set_new(e, "min_J", real_or_null(r->stats.min_J));
        json_object_set_new(e, "inverted", json_integer(r->stats.inverted));
        json_object_set_new(e, "kinetic", real_or_null(r->stats.kinetic));
        json_object_set_new(e, "elastic", real_or_null(r->stats.elastic));
        json_object_set_new(e, "gravity_potential", real_or_null(r->stats.gravity));
        json_array_append_new(steps, e);
    }
    if (nrec < sc->time.steps) all = 0;
    json_object_set_new(root, "steps", steps);
    json_object_set_new(root, "steps_run", json_integer(nrec));
    json_object_set_new(root, "all_converged", json_boolean(all));
    json_object_set_new(root, "not_converged", bad);
    json_object_set_new(root, "total_iterations", json_integer(total_iters));
    json_object_set_new(root, "total_solve_time", json_real(total_time));
    json_object_set_new(root, "frames", json_integer(nframes));
    json_object_set_new(root, "pvd", pvd_file ? json_string(pvd_file) : json_null());
    json_object_set_new(root, "error", error ? json_string(error) : json_null());
    int stopped = nrec > 0 && rec[nrec - 1].reason == EO_DIVERGED_NONFINITE;
    json_object_set_new(root, "stop_reason", stopped ? json_string(eo_reason_name(EO_DIVERGED_NONFINITE)) : json_null());
    char path[1100];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    eo_afile *f = NULL;
    int rc = eo_afile_open(ctx, path, &f);
    if (rc >= 0) {
        char *text = json_dumps(root, JSON_INDENT(2) | JSON_REAL_PRECISION(12));
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

static int run(eo_ctx *ctx, int argc, char **argv)
{
    eo_cli_scene_args a = {0};
    const char *out_dir = NULL;
    int quiet = 0, profile = 0;
    for (int i = 1; i < argc; i++) {
        int r = eo_cli_scene_arg(&eo_cmd_run, argc, argv, &i, &a);
        if (r < 0) return EO_EXIT_BAD_INPUT;
        if (r > 0) continue;
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) out_dir = argv[++i];
        else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) quiet = 1;
        else if (strcmp(argv[i], "--profile") == 0) profile = 1;
        else return eo_cli_usage_error(&eo_cmd_run, "unknown option '%s'", argv[i]);
    }
    eo_sim *sim = NULL;
    eo_afile *csv = NULL;
    eo_pvd *pvd = NULL;
    step_record *rec = NULL;
    double *fbuf = NULL;
    int rc, bad_input = 1, nrec = 0, nframes = 0;
    char name[256], dir[1024], path[1400], pvd_file[300], errtext[1024] = "";
    eo_cli_scene_name(&a, name, sizeof name);

    /* ---- validate everything before writing anything (eo_sim_create: scene, solver
     * section, every method's section, unknown keys) */
    const char *ov[EO_CLI_MAX_OVERRIDES + 1];
    for (int k = 0; k < a.noverrides; k++) ov[k] = a.overrides[k];
    ov[a.noverrides] = NULL;
    EO_TRY(rc = eo_sim_create_from(ctx, a.file, a.scene, ov, &sim));
    const eo_scene *sc = eo_sim_scene(sim);
    eo_step *st = eo_sim_step_problem(sim);
    snprintf(dir, sizeof dir, "%s", out_dir ? out_dir : sc->output.dir);
    const eo_mesh *m = sc->mesh;
    rec = eo_calloc(ctx, (size_t)sc->time.steps, sizeof *rec);
    fbuf = eo_malloc(ctx, (size_t)(3 * m->nv + 2 * m->nt) * sizeof(double) + (size_t)m->nt);
    if (!rec || !fbuf) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        goto fail;
    }
    double *disp = fbuf, *psi = fbuf + 3 * m->nv, *J = psi + m->nt;
    unsigned char *inv = (unsigned char *)(J + m->nt);

    eo_cli_scene_report(ctx, sc, quiet);
    /* ---- outputs */
    bad_input = 0;
    EO_TRY(rc = eo_mkdir_p(ctx, dir));
    snprintf(path, sizeof path, "%s/iterations.csv", dir);
    EO_TRY(rc = eo_afile_open(ctx, path, &csv));
    fprintf(eo_afile_fp(csv), "step,iteration,time,g,grad_norm,decrement,alpha,ls_evals,inverted,reason\n");
    int frames = sc->output.vtu && sc->output.every > 0;
    snprintf(pvd_file, sizeof pvd_file, "%s.pvd", name);
    if (frames) {
        snprintf(path, sizeof path, "%s/%s", dir, pvd_file);
        EO_TRY(rc = eo_pvd_create(ctx, path, &pvd));
        EO_TRY(rc = write_frame(ctx, st, dir, name, nframes++, pvd, disp, psi, J, inv));
    }
    eo_step_stats s0;
    eo_step_stats_compute(st, &s0);
    run_state rs = {.csv = eo_afile_fp(csv), .progress = !quiet && isatty(2), .nsteps = sc->time.steps};
    eo_sim_set_iter_callback(sim, on_iter, &rs);
    progress(&rs, 0, 0, 0);
    const int expl = eo_sim_is_explicit(sim);
    int all_converged = 1;
    long total_iters = 0;
    double t_start = eo_wtime();
    eo_cli_profile prof;
    eo_cli_profile_begin(&prof, profile, sim);
    for (int k = 0; k < sc->time.steps; k++) {
        rs.step = k + 1;
        eo_sim_step_result r;
        rc = eo_sim_step(sim, &r);
        if (rc < 0) {
            snprintf(errtext, sizeof errtext, "step %d: %s", k + 1, eo_ctx_message(ctx));
            all_converged = 0;
            break;
        }
        if (expl) fprintf(rs.csv, "%d,0,%.6e,nan,nan,nan,nan,0,-1,%s\n", k + 1, r.time, eo_reason_name(r.reason));
        if (r.reason == EO_DIVERGED_NONFINITE) {
            /* the sim kept the last finite state (tₙ) */
            snprintf(errtext, sizeof errtext,
                     "step %d (t = %g s): the state became non-finite (diverged_nonfinite)%s", k + 1,
                     eo_sim_time(sim) + sc->time.dt,
                     expl ? "; the explicit integrator is beyond its stability limit: reduce time.dt" : "");
            rec[nrec].reason = r.reason;
            rec[nrec].t = r.t;
            rec[nrec].stats = r.stats;
            rec[nrec].g = rec[nrec].grad_norm = NAN;
            nrec++;
            all_converged = 0;
            break;
        }
        step_record *e = rec + nrec++;
        e->iterations = r.iterations;
        e->reason = r.reason;
        e->t = r.t;
        e->time = r.time;
        e->g = r.g;
        e->grad_norm = r.grad_norm;
        e->n_value = r.n_value;
        e->n_gradient = r.n_gradient;
        e->n_hessian = r.n_hessian;
        e->n_factor = r.n_factor;
        e->stats = r.stats;
        all_converged &= eo_reason_is_converged(r.reason);
        total_iters += r.iterations;
        if (frames && (k + 1) % sc->output.every == 0)
            EO_TRY(rc = write_frame(ctx, st, dir, name, nframes++, pvd, disp, psi, J, inv));
        progress(&rs, k + 1, r.t, r.iterations);
        eo_cli_profile_step(&prof, sim, k + 1);
    }
    eo_cli_profile_total(&prof, sim, name);
    double wall = eo_wtime() - t_start;
    if (rs.progress && nrec < sc->time.steps) fprintf(stderr, "\n");
    EO_TRY(rc = eo_afile_commit(ctx, &csv));
    EO_TRY(rc = write_summary(ctx, dir, name, eo_sim_cfg(sim), sc, eo_sim_solver(sim), rec, nrec, &s0, nframes,
                              frames ? pvd_file : NULL, errtext[0] ? errtext : NULL));
    if (errtext[0]) fprintf(stderr, "elastopt: error: %s\n", errtext);
    if (!quiet) {
        int nconv = 0;
        for (int k = 0; k < nrec; k++) nconv += eo_reason_is_converged(rec[k].reason);
        printf("%s: %d/%d steps converged, %ld iterations, %.3f s; final min J %.4g, inverted %d -> %s/summary.json\n",
               name, nconv, sc->time.steps, total_iters, wall, nrec ? rec[nrec - 1].stats.min_J : s0.min_J,
               nrec ? rec[nrec - 1].stats.inverted : s0.inverted, dir);
    }
    rc = all_converged ? EO_EXIT_OK : EO_EXIT_NOT_CONVERGED;
    goto done;
fail:
    eo_cli_fail(ctx, rc);
    rc = bad_input ? EO_EXIT_BAD_INPUT : EO_EXIT_NOT_CONVERGED;
done:
    eo_afile_abort(ctx, &csv);
    eo_pvd_destroy(&pvd);
    eo_free(ctx, rec);
    eo_free(ctx, fbuf);
    eo_sim_destroy(&sim);
    return rc;
}

const eo_cli_command eo_cmd_run = {
    .name = "run",
    .summary = "simulate a scene (default: the built-in cantilever)",
    .usage = "elastopt run [SCENE.json | --scene NAME] [-o key=value ...] [--out DIR] [--quiet] [--profile]\n\n"
             "Runs the scene's time steps, each an optimization problem solved by the configured\n"
             "solver. Without a scene runs the built-in `cantilever`. `-o` overrides any config key\n"
             "(e.g. -o solver.hessian_fix=abs -o time.steps=10). Writes into DIR (default\n"
             "output.dir, \"out\"): NAME.pvd + NAME_NNNN.vtu frames, iterations.csv (one row per\n"
             "solver iteration) and summary.json (config, build, per-step results).\n"
             "A progress bar goes to stderr when it is a terminal (not with --quiet).\n"
             "--profile: per step and in total, the solver's time in assembly, factorization\n"
             "(symbolic, numeric), solves, line search, gradients and other, and the ratio of\n"
             "a Newton iteration to its numeric factorization (stdout).\n"
             "Exit status: 0 every step converged, 1 some step did not, 2 bad input (nothing\n"
             "written).\n",
    .run = run,
};
