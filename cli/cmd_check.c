/* elastopt check: finite-difference check of the first step's objective of a scene.
 *
 * At the initial state (the starting guess of step 1) and at a randomly perturbed state
 * x + δr (δ = 1e-3 of the mean tet size, r uniform in [−1, 1]ⁿ), with central
 * differences over a step sweep ε = L·10⁻ᵏ, k = 2..9 (L = mesh bounding-box diagonal),
 * keeping the best relative error over the sweep:
 *   value     g from the gradient call equals g from the value call
 *   gradient  ∇gᵀv vs (g(x+εv) − g(x−εv))/2ε for 3 random directions v
 *   hessian   H·v vs (∇g(x+εv) − ∇g(x−εv))/2ε for 3 random v (unprojected H,
 *             EO_PROJ_NONE), and 3 exact columns H·e_j
 * Exit status 0 if every error is at most --tol (default 1e-5), 1 otherwise, 2 on bad
 * input. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/io.h"
#include "elastopt/mesh.h"
#include "elastopt/sim.h"
#include "scene_args.h"

extern const eo_cli_command eo_cmd_check;

typedef struct fd_ws {
    eo_objective *obj;
    int n;
    double L;
    double *xp, *xm, *gp, *gm, *g0, *v, *Hv, *fd;
    unsigned long long seed;
} fd_ws;

static double urand(fd_ws *w)
{
    w->seed ^= w->seed << 13;
    w->seed ^= w->seed >> 7;
    w->seed ^= w->seed << 17;
    return (double)(w->seed >> 11) * (1.0 / 9007199254740992.0);
}

static void axpy_to(int n, const double *x, double a, const double *v, double *out)
{
    for (int i = 0; i < n; i++) out[i] = x[i] + a * v[i];
}

static double norm2(int n, const double *a)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += a[i] * a[i];
    return sqrt(s);
}

/* Best relative error of the directional derivative along v. */
static int check_gradient(fd_ws *w, const double *x, double *best_err, double *best_eps)
{
    double g, gp, gm;
    int rc = eo_objective_gradient(w->obj, x, &g, w->g0);
    if (rc < 0) return rc;
    double an = 0;
    for (int i = 0; i < w->n; i++) an += w->g0[i] * w->v[i];
    *best_err = INFINITY;
    *best_eps = NAN;
    double scale = fabs(an) > 0 ? fabs(an) : 1e-300;
    for (int k = 2; k <= 9; k++) {
        double eps = w->L * pow(10.0, -k);
        axpy_to(w->n, x, eps, w->v, w->xp);
        axpy_to(w->n, x, -eps, w->v, w->xm);
        if ((rc = eo_objective_value(w->obj, w->xp, &gp)) < 0) return rc;
        if ((rc = eo_objective_value(w->obj, w->xm, &gm)) < 0) return rc;
        if (!isfinite(gp) || !isfinite(gm)) continue;
        double fd = (gp - gm) / (2 * eps);
        double err = fabs(fd - an) / scale;
        if (err < *best_err) {
            *best_err = err;
            *best_eps = eps;
        }
    }
    return EO_OK;
}

/* Best relative error ‖FD(∇g)·v − H v‖/‖H v‖ (H at x, unprojected). */
static int check_hessian(fd_ws *w, const double *x, double *best_err, double *best_eps)
{
    eo_csc *H;
    double gp, gm;
    int rc = eo_objective_hessian(w->obj, x, EO_PROJ_NONE, &H);
    if (rc < 0) return rc;
    eo_csc_symv(H, w->v, w->Hv);
    double scale = norm2(w->n, w->Hv);
    if (!(scale > 0)) scale = 1e-300;
    *best_err = INFINITY;
    *best_eps = NAN;
    for (int k = 2; k <= 9; k++) {
        double eps = w->L * pow(10.0, -k);
        axpy_to(w->n, x, eps, w->v, w->xp);
        axpy_to(w->n, x, -eps, w->v, w->xm);
        if ((rc = eo_objective_gradient(w->obj, w->xp, &gp, w->gp)) < 0) return rc;
        if ((rc = eo_objective_gradient(w->obj, w->xm, &gm, w->gm)) < 0) return rc;
        if (!isfinite(gp) || !isfinite(gm)) continue;
        double e2 = 0;
        for (int i = 0; i < w->n; i++) {
            double d = (w->gp[i] - w->gm[i]) / (2 * eps) - w->Hv[i];
            e2 += d * d;
        }
        double err = sqrt(e2) / scale;
        if (err < *best_err) {
            *best_err = err;
            *best_eps = eps;
        }
    }
    return EO_OK;
}

static void random_dir(fd_ws *w)
{
    for (int i = 0; i < w->n; i++) w->v[i] = 2 * urand(w) - 1;
}

static int report(const char *state, const char *what, double err, double eps, double tol)
{
    int ok = err <= tol;
    printf("  %-10s %-22s eps %-9.2g rel error %-10.3g %s\n", state, what, eps, err, ok ? "ok" : "FAIL");
    return ok;
}

static int check_state(fd_ws *w, const char *state, const double *x, double tol, int *all_ok)
{
    int rc;
    double g1, g2, err, eps;
    char what[64];
    if ((rc = eo_objective_value(w->obj, x, &g1)) < 0) return rc;
    if ((rc = eo_objective_gradient(w->obj, x, &g2, w->g0)) < 0) return rc;
    if (!isfinite(g1)) {
        printf("  %-10s g = %g (not finite): cannot check\n", state, g1);
        *all_ok = 0;
        return EO_OK;
    }
    err = fabs(g1 - g2) / (fabs(g1) > 1e-300 ? fabs(g1) : 1);
    *all_ok &= report(state, "value (grad vs value)", err, 0, tol);
    for (int d = 0; d < 3; d++) {
        random_dir(w);
        if ((rc = check_gradient(w, x, &err, &eps)) < 0) return rc;
        snprintf(what, sizeof what, "gradient dir %d", d + 1);
        *all_ok &= report(state, what, err, eps, tol);
    }
    for (int d = 0; d < 3; d++) {
        random_dir(w);
        if ((rc = check_hessian(w, x, &err, &eps)) < 0) return rc;
        snprintf(what, sizeof what, "hessian H.v dir %d", d + 1);
        *all_ok &= report(state, what, err, eps, tol);
    }
    for (int d = 0; d < 3; d++) {
        int j = (int)(urand(w) * w->n) % w->n;
        memset(w->v, 0, (size_t)w->n * sizeof(double));
        w->v[j] = 1;
        if ((rc = check_hessian(w, x, &err, &eps)) < 0) return rc;
        snprintf(what, sizeof what, "hessian column %d", j);
        *all_ok &= report(state, what, err, eps, tol);
    }
    return EO_OK;
}

static int run(eo_ctx *ctx, int argc, char **argv)
{
    eo_cli_scene_args a = {0};
    double tol = 1e-5;
    unsigned long long seed = 12345;
    for (int i = 1; i < argc; i++) {
        int r = eo_cli_scene_arg(&eo_cmd_check, argc, argv, &i, &a);
        if (r < 0) return EO_EXIT_BAD_INPUT;
        if (r > 0) continue;
        if (strcmp(argv[i], "--tol") == 0 && i + 1 < argc) {
            char *end;
            tol = strtod(argv[++i], &end);
            if (*end || !(tol > 0)) return eo_cli_usage_error(&eo_cmd_check, "--tol needs a positive number");
        } else if (strcmp(argv[i], "--seed") == 0 && i + 1 < argc) {
            seed = strtoull(argv[++i], NULL, 10);
        } else {
            return eo_cli_unknown_arg(&eo_cmd_check, "option", argv[i]);
        }
    }
    eo_sim *sim = NULL;
    fd_ws w = {0};
    double *buf = NULL;
    int exit_code = EO_EXIT_BAD_INPUT, rc;
    eo_objective *obj;
    char name[256];
    eo_cli_scene_name(&a, name, sizeof name);
    /* the sim's solver is not used; creating the sim validates the whole config */
    const char *ov[EO_CLI_MAX_OVERRIDES + 1];
    for (int k = 0; k < a.noverrides; k++) ov[k] = a.overrides[k];
    ov[a.noverrides] = NULL;
    EO_TRY(rc = eo_sim_create_from(ctx, a.file, a.scene, ov, &sim));
    const eo_scene *sc = eo_sim_scene(sim);
    double *guess;
    EO_TRY(rc = eo_sim_prepare(sim, &obj, &guess));
    int n = obj->n;
    if (n < 1) {
        rc = eo_error(ctx, EO_ERR_INVALID, "scene %s has no free coordinate", name);
        goto fail;
    }
    buf = eo_malloc(ctx, 10 * (size_t)n * sizeof(double));
    if (!buf) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        goto fail;
    }
    w.obj = obj;
    w.n = n;
    w.seed = seed ? seed : 1;
    w.xp = buf, w.xm = buf + n, w.gp = buf + 2 * n, w.gm = buf + 3 * n, w.g0 = buf + 4 * n;
    w.v = buf + 5 * n, w.Hv = buf + 6 * n, w.fd = buf + 7 * n;
    double *x = buf + 8 * n, *x2 = buf + 9 * n;
    eo_mesh_stats ms;
    eo_mesh_stats_compute(sc->mesh, &ms);
    const double *bb = ms.bbox;
    w.L = sqrt((bb[3] - bb[0]) * (bb[3] - bb[0]) + (bb[4] - bb[1]) * (bb[4] - bb[1]) + (bb[5] - bb[2]) * (bb[5] - bb[2]));
    double h = sc->mesh->nt ? cbrt(ms.volume / sc->mesh->nt) : w.L / 10; /* mesh.points: no tets */
    memcpy(x, guess, (size_t)n * sizeof(double));
    printf("check %s: %d free coordinates, %d tets, integrator %s, dt %g, tol %g\n", name, n, sc->mesh->nt,
           sc->time.integrator, sc->time.dt, tol);
    int all_ok = 1;
    EO_TRY(rc = check_state(&w, "initial", x, tol, &all_ok));
    for (int i = 0; i < n; i++) x2[i] = x[i] + 1e-3 * h * (2 * urand(&w) - 1);
    EO_TRY(rc = check_state(&w, "perturbed", x2, tol, &all_ok));
    printf("%s\n", all_ok ? "all checks passed" : "SOME CHECKS FAILED");
    exit_code = all_ok ? EO_EXIT_OK : EO_EXIT_NOT_CONVERGED;
    rc = EO_OK;
fail:
    if (rc < 0) eo_cli_fail(ctx, rc);
    eo_free(ctx, buf);
    eo_sim_destroy(&sim);
    return rc < 0 ? EO_EXIT_BAD_INPUT : exit_code;
}

const eo_cli_command eo_cmd_check = {
    .name = "check",
    .summary = "finite-difference check of a scene's step objective (g, gradient, Hessian)",
    .usage = "elastopt check [SCENE.json | --scene NAME] [-o key=value ...] [--tol T] [--seed S]\n\n"
             "Builds the first time step's objective of the scene (default: the built-in\n"
             "cantilever) and compares, at the initial state and at a randomly perturbed state,\n"
             "the gradient with central differences of g and the unprojected Hessian with\n"
             "central differences of the gradient (H.v for random v and a few exact columns),\n"
             "over a sweep of steps, reporting the best relative error of each.\n"
             "Exit status: 0 all errors <= T (default 1e-5), 1 some above, 2 bad input.\n",
    .run = run,
};
