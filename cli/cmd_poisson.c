/* elastopt poisson: the 2D Poisson FEM problem of notes 001 §3 (poisson.h) solved by
 * the configured optimizer / linear solver, with the error against the manufactured
 * solution u = sin(πx) sin(πy) (f = 2π²u), printed as JSON:
 *   {"n", "h", "unknowns", "nnz", "l2_error", "max_error", "reason", "converged",
 *    "iterations", "time", "g", "grad_norm", "evaluations": {...}, "linear": {...},
 *    "solver": <resolved solver section>}
 * The solver comes from `-o solver.*=...` (defaults: solver.h); every optimizer works
 * on g(u) = ½uᵀKu − Fᵀu, and Newton uses solver.linear for Ku = F.
 * Exit 0 if the solve converged, 1 if not, 2 on bad input. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/poisson.h"
#include "elastopt/solver.h"
#include "scene_args.h"

extern const eo_cli_command eo_cmd_poisson;

static json_t *num(double v) { return isfinite(v) ? json_real(v) : json_null(); }

static int run(eo_ctx *ctx, int argc, char **argv)
{
    eo_cli_scene_args a = {0};
    int n = 32;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--n") == 0 && i + 1 < argc) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 2 || v > 20000) return eo_cli_usage_error(&eo_cmd_poisson, "--n needs an integer in [2, 20000]");
            n = (int)v;
            continue;
        }
        int r = eo_cli_scene_arg(&eo_cmd_poisson, argc, argv, &i, &a);
        if (r < 0) return EO_EXIT_BAD_INPUT;
        if (r == 0 || a.file || a.scene) return eo_cli_usage_error(&eo_cmd_poisson, "unknown argument '%s'", argv[i]);
    }
    eo_cfg *cfg = NULL;
    eo_poisson *p = NULL;
    eo_solver *solver = NULL;
    double *u = NULL;
    int rc;
    static const char *const top[] = {"solver", NULL};
    EO_TRY(rc = eo_cfg_create_empty(ctx, &cfg));
    for (int k = 0; k < a.noverrides; k++) EO_TRY(rc = eo_cfg_override(ctx, cfg, a.overrides[k]));
    eo_cfg_expect(cfg, "", top);
    eo_solver_opts so;
    eo_solver_opts_default(&so);
    EO_TRY(rc = eo_solver_opts_load(ctx, cfg, &so));
    EO_TRY(rc = eo_poisson_create(ctx, n, &p));
    eo_objective *obj = eo_poisson_objective(p);
    EO_TRY(rc = eo_solver_create(ctx, &so, cfg, &solver));
    EO_TRY(rc = eo_cfg_finish(ctx, cfg));
    u = eo_calloc(ctx, (size_t)obj->n, sizeof(double));
    if (!u) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        goto fail;
    }
    eo_solve_result r;
    memset(&r, 0, sizeof r);
    EO_TRY(rc = eo_solver_minimize(solver, obj, u, NULL, NULL, &r));
    double l2 = NAN, mx = NAN;
    eo_poisson_error(p, u, &l2, &mx);
    json_t *o = json_object();
    json_object_set_new(o, "n", json_integer(n));
    json_object_set_new(o, "h", json_real(eo_poisson_h(p)));
    json_object_set_new(o, "unknowns", json_integer(obj->n));
    json_object_set_new(o, "nnz", json_integer(eo_poisson_matrix(p)->nnz));
    json_object_set_new(o, "l2_error", num(l2));
    json_object_set_new(o, "max_error", num(mx));
    json_object_set_new(o, "reason", json_string(eo_reason_name(r.reason)));
    json_object_set_new(o, "converged", json_boolean(eo_reason_is_converged(r.reason)));
    json_object_set_new(o, "iterations", json_integer(r.iterations));
    json_object_set_new(o, "time", json_real(r.time));
    json_object_set_new(o, "g", num(r.g));
    json_object_set_new(o, "grad_norm", num(r.grad_norm));
    json_object_set_new(o, "evaluations", json_pack("{s:I, s:I, s:I, s:I}", "value", (json_int_t)r.n_value, "gradient",
                                                    (json_int_t)r.n_gradient, "hessian", (json_int_t)r.n_hessian,
                                                    "factor", (json_int_t)r.n_factor));
    eo_linsolve *ls = eo_solver_get_linsolve(solver);
    if (ls) {
        const eo_linsolve_stats *st = eo_linsolve_get_stats(ls);
        json_object_set_new(o, "linear", json_pack("{s:s, s:i, s:o, s:I, s:I}", "method",
                                                   eo_linsolve_get_type(ls)->info.name, "last_iterations",
                                                   st->iterations, "last_residual", num(st->residual), "factors",
                                                   (json_int_t)st->n_factor, "solves", (json_int_t)st->n_solve));
    }
    json_t *sj = eo_solver_to_json(solver);
    json_object_set_new(o, "solver", sj ? sj : json_null());
    char *text = json_dumps(o, JSON_INDENT(2) | JSON_REAL_PRECISION(10));
    if (text) printf("%s\n", text);
    free(text);
    json_decref(o);
    rc = eo_reason_is_converged(r.reason) ? EO_EXIT_OK : EO_EXIT_NOT_CONVERGED;
    goto done;
fail:
    eo_cli_fail(ctx, rc);
    rc = EO_EXIT_BAD_INPUT;
done:
    eo_free(ctx, u);
    eo_solver_destroy(&solver);
    eo_poisson_destroy(&p);
    eo_cfg_destroy(ctx, &cfg);
    return rc;
}

const eo_cli_command eo_cmd_poisson = {
    .name = "poisson",
    .summary = "2D Poisson FEM (-Lap u = f, unit square) solved by any optimizer/linear solver",
    .usage = "elastopt poisson [--n N] [-o solver.key=value ...]\n\n"
             "Linear triangles on an N x N structured triangulation of the unit square (default\n"
             "N = 32), -Lap u = 2 pi^2 sin(pi x) sin(pi y), u = 0 on the boundary, solved as\n"
             "min 1/2 u'Ku - F'u with the configured solver (e.g. -o solver.optimizer=lbfgs, or\n"
             "newton with -o solver.linear=pcg). Prints JSON: the L2 and max nodal error against\n"
             "u = sin(pi x) sin(pi y) (O(h^2)), iterations, reason, evaluations, linear-solver\n"
             "statistics and the resolved solver section.\n"
             "Exit status: 0 converged, 1 not converged, 2 bad input.\n",
    .run = run,
};
