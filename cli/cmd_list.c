/* elastopt list: every registered method of every kind with its one-line summary. */
#include <stdio.h>

#include "cli.h"
#include "elastopt/registry.h"

extern const eo_cli_command eo_cmd_list;

static int run(eo_ctx *ctx, int argc, char **argv)
{
    (void)ctx;
    (void)argv;
    if (argc > 1) return eo_cli_usage_error(&eo_cmd_list, "takes no arguments");
    for (int k = 0; k < EO_KIND_COUNT; k++) {
        printf("%s (%s):\n", eo_kind_label((eo_kind)k), eo_kind_key((eo_kind)k));
        const void *const *t = eo_registry_list((eo_kind)k);
        if (!t || !*t) printf("  (none built)\n");
        for (; t && *t; t++) {
            const eo_method_info *mi = eo_method_info_of(*t);
            printf("  %-22s %s\n", mi->name, mi->summary ? mi->summary : "");
        }
    }
    return EO_EXIT_OK;
}

const eo_cli_command eo_cmd_list = {
    .name = "list",
    .summary = "list every registered method of every kind",
    .usage = "elastopt list\n\nPrints each kind (material, optimizer, hessian_fix, linesearch, stop,\n"
             "linear, integrator, scene, element, term) and its registered methods with a one-line\n"
             "description (terms: the kinds of term of the step problem, in the order they are summed).\n",
    .run = run,
};
