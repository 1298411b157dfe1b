/* elastopt help [KEY]: documents the configuration keys with their defaults.
 *
 *   elastopt help                 every config section and method parameter table
 *   elastopt help solver          one section (prefix match on the dotted path)
 *   elastopt help newton          a method's parameters (solver.newton.*)
 *   elastopt help optimizer       the registered methods of a kind */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "elastopt/registry.h"
#include "elastopt/scene.h"

extern const eo_cli_command eo_cmd_help;

/* Sections of the scene config documented by the modules that own them. */
static void print_section(const eo_cfg_doc *d)
{
    printf("%s — %s\n", *d->path ? d->path : "(top level)", d->summary);
    eo_params_help(stdout, d->params, d->path);
    printf("\n");
}

static int matches(const char *path, const char *key)
{
    size_t n = strlen(key);
    return strncmp(path, key, n) == 0 && (path[n] == 0 || path[n] == '.');
}

static int run(eo_ctx *ctx, int argc, char **argv)
{
    (void)ctx;
    if (argc > 2) return eo_cli_usage_error(&eo_cmd_help, "takes at most one KEY");
    const char *key = argc == 2 ? argv[1] : NULL;
    int found = 0;
    for (const eo_cfg_doc *d = eo_config_docs(); d && d->path; d++) {
        if (key && !matches(d->path, key) && !matches(key, d->path)) continue;
        print_section(d);
        found = 1;
    }
    char path[160];
    for (int k = 0; k < EO_KIND_COUNT; k++) {
        const char *kk = eo_kind_key((eo_kind)k);
        int kind_hit = key && strcmp(key, kk) == 0;
        if (kind_hit) {
            printf("%s (%s): registered methods\n", eo_kind_label((eo_kind)k), kk);
            found = 1;
        }
        for (const void *const *t = eo_registry_list((eo_kind)k); t && *t; t++) {
            const eo_method_info *mi = eo_method_info_of(*t);
            if (kind_hit) printf("  %-22s %s\n", mi->name, mi->summary);
            if (!mi->params || !mi->params[0].key) continue;
            snprintf(path, sizeof path, "%s.%s", k == EO_KIND_MATERIAL ? "material" : "solver", mi->name);
            if (key && !kind_hit && strcmp(key, mi->name) != 0 && !matches(path, key) && !matches(key, path))
                continue;
            if (!key || !kind_hit) {
                printf("%s — parameters of %s '%s': %s\n", path, eo_kind_label((eo_kind)k), mi->name, mi->summary);
                eo_params_help(stdout, mi->params, path);
                printf("\n");
                found = 1;
            }
        }
        if (kind_hit) printf("\n");
    }
    if (!found) {
        fprintf(stderr, "elastopt help: no config section, method or kind named '%s'; try `elastopt help`\n", key);
        return EO_EXIT_BAD_INPUT;
    }
    return EO_EXIT_OK;
}

const eo_cli_command eo_cmd_help = {
    .name = "help",
    .summary = "document config keys and method parameters with their defaults",
    .usage = "elastopt help [KEY]\n\n"
             "Without KEY: every config section and every method's parameters (key, type,\n"
             "default, range, meaning). KEY may be a section path (solver, time, mesh.generate),\n"
             "a method name (newton, backtracking, cholmod) or a kind (optimizer, linesearch,\n"
             "stop, hessian_fix, linear, material, integrator, scene) to list its methods.\n"
             "Any key can be set in the scene JSON or overridden with -o path.key=value.\n",
    .run = run,
};
