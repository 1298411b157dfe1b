/* elastopt poisson: the 2D Poisson FEM problem of notes 001 §3 (poisson.h) solved by
 * the configured optimizer / linear solver, with the error against the manufactured
 * solution u = sin(πx) sin(πy) (f = 2π²u), on the unit square or on the triangles of a
 * Gmsh 2D mesh (--mesh; u = u_exact on its boundary nodes), optionally writing the
 * solution as a VTU of triangles (--vtu). Options: -o poisson.quadrature=midpoint|centroid
 * (right-hand-side rule; centroid is the notes' eq. 50). Printed as JSON:
 *   {"n", "mesh", "quadrature", "h", "unknowns", "nnz", "l2_error", "max_error", "reason", "converged",
 *    "iterations", "time", "g", "grad_norm", "evaluations": {...}, "linear": {...},
 *    "solver": <resolved solver section>}
 * The solver comes from `-o solver.*=...` (defaults: solver.h); every optimizer works
 * on g(u) = ½uᵀKu − Fᵀu, and Newton uses solver.linear for Ku = F.
 * Exit 0 if the solve converged, 1 if not, 2 on bad input. */
#include <jansson.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/params.h"
#include "elastopt/poisson.h"
#include "elastopt/impl/method.h"
#include "scene_args.h"

extern const eo_cli_command eo_cmd_poisson;

static json_t *num(double v) { return isfinite(v) ? json_real(v) : json_null(); }

/* the `poisson` section of -o overrides */
typedef struct {
    char quadrature[16];
} poisson_cfg;
static const char *const quad_choices[] = {"midpoint", "centroid", NULL};
static const eo_param_desc poisson_desc[] = {
    {.key = "quadrature", .kind = EO_PARAM_CHOICE, .offset = offsetof(poisson_cfg, quadrature),
     .size = sizeof(((poisson_cfg *)0)->quadrature), .def.s = "midpoint", .choices = quad_choices,
     .help = "right-hand side: midpoint = three edge midpoints (exact for quadratics), centroid = "
             "the notes' one-point barycentre rule (001 eq. 50)"},
    {0},
};

static int run(eo_ctx *ctx, int argc, char **argv)
{
    eo_cli_scene_args a = {0};
    int n = 32;
    const char *mesh_path = NULL, *vtu_path = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--mesh") == 0 && i + 1 < argc) {
            mesh_path = argv[++i];
            continue;
        }
        if (strcmp(argv[i], "--vtu") == 0 && i + 1 < argc) {
            vtu_path = argv[++i];
            continue;
        }
        if (strcmp(argv[i], "--n") == 0 && i + 1 < argc) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 2 || v > 20000) return eo_cli_usage_error(&eo_cmd_poisson, "--n needs an integer in [2, 20000]");
            n = (int)v;
            continue;
        }
        int r = eo_cli_scene_arg(&eo_cmd_poisson, argc, argv, &i, &a);
        if (r < 0) return EO_EXIT_BAD_INPUT;
        if (r == 0 || a.file || a.scene) return eo_cli_unknown_arg(&eo_cmd_poisson, "argument", argv[i]);
    }
    eo_cfg *cfg = NULL;
    eo_poisson *p = NULL;
    eo_trimesh *mesh = NULL;
    eo_solver *solver = NULL;
    double *u = NULL;
    int rc;
    static const char *const top[] = {"solver", "poisson", NULL};
    poisson_cfg pc;
    eo_params_default(poisson_desc, &pc);
    EO_TRY(rc = eo_cfg_create_empty(ctx, &cfg));
    for (int k = 0; k < a.noverrides; k++) EO_TRY(rc = eo_cfg_override(ctx, cfg, a.overrides[k]));
    eo_cfg_expect(cfg, "", top);
    eo_solver_opts so;
    eo_solver_opts_default(&so);
    EO_TRY(rc = eo_solver_opts_load(ctx, cfg, &so));
    EO_TRY(rc = eo_cfg_section(ctx, cfg, "poisson", poisson_desc, &pc, NULL));
    eo_poisson_opts po;
    eo_poisson_opts_default(&po);
    EO_TRY(rc = eo_poisson_quadrature_parse(ctx, pc.quadrature, &po.quadrature));
    if (mesh_path) {
        EO_TRY(rc = eo_trimesh_read_gmsh(ctx, mesh_path, &mesh));
        EO_TRY(rc = eo_poisson_create_mesh(ctx, mesh, &po, &p));
    } else {
        EO_TRY(rc = eo_poisson_create_opts(ctx, n, &po, &p));
    }
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
    if (vtu_path) EO_TRY(rc = eo_poisson_write_vtu(p, u, vtu_path));
    json_t *o = json_object();
    json_object_set_new(o, "n", mesh_path ? json_null() : json_integer(n));
    json_object_set_new(o, "mesh", mesh_path ? json_string(mesh_path) : json_null());
    json_object_set_new(o, "nodes", json_integer(eo_poisson_mesh(p)->nv));
    json_object_set_new(o, "triangles", json_integer(eo_poisson_mesh(p)->nt));
    json_object_set_new(o, "quadrature", json_string(eo_poisson_quadrature_name(po.quadrature)));
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
    eo_trimesh_destroy(&mesh);
    eo_cfg_destroy(&cfg);
    return rc;
}

const eo_cli_command eo_cmd_poisson = {
    .name = "poisson",
    .summary = "2D Poisson FEM (-Lap u = f, unit square or Gmsh 2D mesh) solved by any optimizer/linear solver",
    .usage = "elastopt poisson [--n N | --mesh FILE.msh] [--vtu FILE.vtu] [-o poisson.quadrature=Q]\n"
             "                 [-o solver.key=value ...]\n\n"
             "Linear triangles on an N x N structured triangulation of the unit square (default\n"
             "N = 32) or on the 3-node triangles of a Gmsh ASCII mesh (--mesh, .msh 2.2 or 4.1;\n"
             "boundary = nodes of edges used by one triangle, u = u_exact there),\n"
             "-Lap u = 2 pi^2 sin(pi x) sin(pi y), u = 0 on the square's boundary, solved as\n"
             "min 1/2 u'Ku - F'u with the configured solver (e.g. -o solver.optimizer=lbfgs, or\n"
             "newton with -o solver.linear=pcg). Prints JSON: the L2 and max nodal error against\n"
             "u = sin(pi x) sin(pi y) (O(h^2)), iterations, reason, evaluations, linear-solver\n"
             "statistics and the resolved solver section.\n"
             "--vtu FILE: the nodal solution u as a VTK unstructured grid of triangles.\n"
             "-o poisson.quadrature=midpoint (default: three edge midpoints, exact for\n"
             "quadratics) | centroid (the notes' one-point barycentre rule, 001 eq. 50).\n"
             "Exit status: 0 converged, 1 not converged, 2 bad input.\n",
    .run = run,
};
