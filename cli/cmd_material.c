/* elastopt material: evaluate one material model at one deformation gradient and print
 * ψ, P, ∂P/∂F, its clamp projection, the signed singular values, J and the inversion
 * flag (eo_tet_is_inverted) as one JSON object (full precision; ψ = +∞ prints as null). The coefficients come from the `material` config section,
 * so -o material.E=… / -o material.nu=… are checked exactly as in a scene file. */
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "elastopt/config.h"
#include "elastopt/material.h"

extern const eo_cli_command eo_cmd_material;

/* 9 finite numbers separated by blanks or commas; 0 on success. */
static int parse_F(const char *text, double F[9])
{
    const char *p = text;
    int n = 0;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == ',' || *p == '\n') p++;
        if (!*p) break;
        if (n == 9) return -1;
        char *end;
        errno = 0;
        double v = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(v)) return -1;
        if (*end && !strchr(" \t,\n", *end)) return -1;
        F[n++] = v;
        p = end;
    }
    return n == 9 ? 0 : -1;
}

static json_t *array_of(const double *v, int n)
{
    json_t *a = json_array();
    for (int i = 0; i < n; i++) json_array_append_new(a, isfinite(v[i]) ? json_real(v[i]) : json_null());
    return a;
}

static int run(eo_ctx *ctx, int argc, char **argv)
{
    const eo_cli_command *cmd = &eo_cmd_material;
    const char *model = NULL, *Ftext = NULL;
    eo_cfg *cfg = NULL;
    int rc, ret = EO_EXIT_BAD_INPUT;
    if (eo_cfg_create_empty(ctx, &cfg) < 0) return eo_cli_fail(ctx, EO_ERR_NOMEM);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--model") == 0 || strcmp(a, "--F") == 0 || strcmp(a, "-o") == 0) {
            if (i + 1 >= argc) {
                ret = eo_cli_usage_error(cmd, "%s needs a value", a);
                goto done;
            }
            const char *v = argv[++i];
            if (a[2] == 'm') model = v;
            else if (a[2] == 'F') Ftext = v;
            else if ((rc = eo_cfg_override(ctx, cfg, v)) < 0) {
                ret = eo_cli_fail(ctx, rc);
                goto done;
            }
        } else if (strncmp(a, "--model=", 8) == 0) {
            model = a + 8;
        } else if (strncmp(a, "--F=", 4) == 0) {
            Ftext = a + 4;
        } else {
            ret = eo_cli_unknown_arg(cmd, "argument", a);
            goto done;
        }
    }
    if (!Ftext) {
        ret = eo_cli_usage_error(cmd, "--F \"f11 f12 f13 f21 f22 f23 f31 f32 f33\" is required");
        goto done;
    }
    double F[9];
    if (parse_F(Ftext, F) < 0) {
        fprintf(stderr, "elastopt material: --F must be 9 finite numbers (row-major F), got '%s'\n", Ftext);
        goto done;
    }
    static const char *const top[] = {"material", NULL};
    eo_cfg_expect(cfg, "", top);
    eo_material_opts opts;
    eo_params_default(eo_material_opts_desc, &opts);
    if ((rc = eo_cfg_section(ctx, cfg, "material", eo_material_opts_desc, &opts, NULL)) < 0 ||
        (rc = eo_cfg_finish(ctx, cfg)) < 0) {
        ret = eo_cli_fail(ctx, rc);
        goto done;
    }
    if (model) snprintf(opts.model, sizeof opts.model, "%s", model);
    const void *tv;
    if ((rc = eo_registry_find(ctx, EO_KIND_MATERIAL, opts.model, &tv)) < 0) {
        ret = eo_cli_fail(ctx, rc);
        goto done;
    }
    const eo_material_type *mt = tv;
    if (mt->flags & EO_MATERIAL_EDGE) {
        fprintf(stderr, "elastopt material: '%s' is an edge (2-node) model; this command evaluates models of F\n",
                mt->info.name);
        goto done;
    }
    eo_material_coef coef = eo_material_coef_from_opts(&opts);
    eo_material_eval e, ep;
    eo_material_evaluate(mt, &coef, F, EO_EVAL_HESS, EO_PROJ_NONE, &e);
    eo_material_evaluate(mt, &coef, F, EO_EVAL_HESS, EO_PROJ_CLAMP, &ep);
    json_t *o = json_object();
    json_object_set_new(o, "model", json_string(mt->info.name));
    json_object_set_new(o, "E", json_real(opts.E));
    json_object_set_new(o, "nu", json_real(opts.nu));
    json_object_set_new(o, "mu", json_real(coef.mu));
    json_object_set_new(o, "lambda", json_real(coef.lambda));
    json_object_set_new(o, "F", array_of(F, 9));
    json_object_set_new(o, "psi", isfinite(e.psi) ? json_real(e.psi) : json_null());
    json_object_set_new(o, "P", array_of(e.P, 9));
    json_object_set_new(o, "dPdF", array_of(e.dPdF, 81));
    json_object_set_new(o, "dPdF_psd", array_of(ep.dPdF, 81));
    json_object_set_new(o, "eig", array_of(e.eig, 9));
    json_object_set_new(o, "sigma", array_of(e.sigma, 3));
    json_object_set_new(o, "J", json_real(e.J));
    json_object_set_new(o, "inverted", json_boolean(eo_tet_is_inverted(e.J)));
    char *s = json_dumps(o, JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(17));
    json_decref(o);
    if (!s) {
        fprintf(stderr, "elastopt material: out of memory\n");
        goto done;
    }
    printf("%s\n", s);
    free(s);
    ret = EO_EXIT_OK;
done:
    eo_cfg_destroy(&cfg);
    return ret;
}

const eo_cli_command eo_cmd_material = {
    .name = "material",
    .summary = "evaluate a material model at one deformation gradient (JSON)",
    .usage = "elastopt material [--model NAME] [-o material.KEY=VALUE ...] --F \"f11 f12 f13 f21 f22 f23 f31 f32 f33\"\n\n"
             "Prints one JSON object: model, E, nu, mu, lambda, F, psi, P (9, row-major),\n"
             "dPdF (81, dPdF[(3i+j)*9+(3k+l)] = dP_ij/dF_kl), dPdF_psd (negative eigenvalues\n"
             "clamped to 0), eig (the nine analytic eigenvalues: 3 scaling, 3 twist, 3 flip),\n"
             "sigma (signed singular values), J = det F and inverted (J <= 0, the one rule the\n"
             "library uses everywhere). psi is null (JSON has no infinity) where the model is\n"
             "+infinity: neo_hookean exactly where inverted is true. Numbers are printed with\n"
             "17 significant digits.\n\n"
             "  --model NAME   material model (default: material.model, stable_neo_hookean)\n"
             "  -o KEY=VALUE   material.model, material.E (default 1e5), material.nu (0.45),\n"
             "                 material.density, material.k\n"
             "  --F \"...\"      the deformation gradient, 9 numbers row-major\n"
             "exit status: 0 ok, 2 bad input (bad --F, unknown model or key, value out of range).\n",
    .run = run,
};
