/* elastopt help [KEY]: documents the configuration keys with their defaults.
 *
 *   elastopt help                 every config section and method parameter table
 *   elastopt help solver          one section (prefix match on the dotted path)
 *   elastopt help newton          a method's parameters (solver.newton.*)
 *   elastopt help optimizer       the registered methods of a kind
 *   elastopt help bench           the keys of a benchmark suite
 *   elastopt help --schema scene|suite   the JSON Schema of a scene or suite document */
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/impl/term.h"
#include "elastopt/suggest.h"
#include "cli.h"
#include "bench.h"
#include "elastopt/registry.h"
#include "elastopt/scene.h"

extern const eo_cli_command eo_cmd_help;

/* Sections of the scene config documented by the modules that own them. */
/* A key the loader reads itself: its value's JSON Schema. */
static void print_raw(const eo_cfg_raw_doc *d)
{
    printf("%s — %s\n", d->path, d->summary);
    if (d->schema) printf("  %-34s %-8s %s\n", d->path, "json", d->schema);
    printf("\n");
}

static void print_section(const eo_cfg_doc *d)
{
    printf("%s — %s\n", *d->path ? d->path : "(top level)", d->summary);
    eo_params_help(stdout, d->params, d->path);
    printf("\n");
}

#define VEC_NUM "{\"type\": \"array\", \"items\": {\"type\": \"number\", \"exclusiveMinimum\": 0}, \"maxItems\": 16}"
#define SET_OBJ "{\"type\": \"object\", \"description\": \"dotted config keys and their JSON values\"}"
#define NAMES "{\"type\": \"array\", \"items\": {\"type\": \"string\"}}"

/* The benchmark suite's documented sections (bench.h). */
static const eo_cfg_doc suite_docs[] = {
    {"", eo_bench_opts_desc,
     "top-level suite keys (also: thresholds, budgets, iter_budgets, require_converged, scenes, configs, matrix)"},
    {"scenes.N", eo_bench_scene_desc, "a benchmark scene: a built-in scene or a scene file, with overrides"},
    {NULL, NULL, NULL},
};
static const eo_cfg_raw_doc suite_raw_docs[] = {
    {"thresholds", VEC_NUM, "relative energy errors of the time table (default [1e-2, 1e-3, 1e-4, 1e-6, 1e-8])"},
    {"budgets", VEC_NUM, "time budgets (s) of the 'error reached at' table (default [0.01, 0.1, 1])"},
    {"iter_budgets", "{\"type\": \"array\", \"items\": {\"type\": \"integer\", \"minimum\": 1, \"maximum\": 1000000}, "
                     "\"maxItems\": 16}",
     "iterations per frame of the fixed-budget runs over the measured window (default none)"},
    {"scenes.N.iter_budgets", "{\"type\": \"array\", \"items\": {\"type\": \"integer\", \"minimum\": 1}, \"maxItems\": 16}",
     "the suite's iter_budgets run on this scene (a subset; default all, [] = none)"},
    {"require_converged", NAMES, "configuration names that must converge on every step of every scene (else exit 1)"},
    {"scenes.N.set", SET_OBJ, "overrides of the scene config: {\"dotted.key\": value, ...}"},
    {"scenes.N.vary", "{\"type\": \"array\", \"items\": {\"type\": \"object\", \"additionalProperties\": " SET_OBJ "}}",
     "[{\"label\": {set}, ...}, ...]: the product expands the entry into scenes name-label-..."},
    {"configs.N.name", "{\"type\": \"string\"}", "configuration name (unique)"},
    {"configs.N.set", SET_OBJ, "solver.* overrides of this configuration"},
    {"matrix.N.optimizer", NAMES, "optimizers of the product optimizer x hessian_fix x linesearch"},
    {"matrix.N.hessian_fix", NAMES, "Hessian fixes of the product (ignored for optimizers without a Hessian)"},
    {"matrix.N.linesearch", NAMES, "line searches of the product"},
    {"matrix.N.set", SET_OBJ, "solver.* overrides common to the product's configurations"},
    {NULL, NULL, NULL},
};

static int print_schema(const char *what)
{
    json_t *j = NULL;
    if (strcmp(what, "scene") == 0) j = eo_config_schema();
    else if (strcmp(what, "suite") == 0) j = eo_cfg_docs_schema(suite_docs, suite_raw_docs, "elastopt benchmark suite", NULL);
    else {
        fprintf(stderr, "elastopt help: --schema takes 'scene' or 'suite', not '%s'\n", what);
        return EO_EXIT_BAD_INPUT;
    }
    char *text = j ? json_dumps(j, JSON_INDENT(2) | JSON_SORT_KEYS | JSON_REAL_PRECISION(17)) : NULL;
    json_decref(j);
    if (!text) {
        fprintf(stderr, "elastopt help: out of memory\n");
        return EO_EXIT_BAD_INPUT;
    }
    printf("%s\n", text);
    free(text);
    return EO_EXIT_OK;
}

static int matches(const char *path, const char *key)
{
    size_t n = strlen(key);
    return strncmp(path, key, n) == 0 && (path[n] == 0 || path[n] == '.');
}

static int run(eo_ctx *ctx, int argc, char **argv)
{
    (void)ctx;
    if (argc == 3 && strcmp(argv[1], "--schema") == 0) return print_schema(argv[2]);
    if (argc > 2) return eo_cli_usage_error(&eo_cmd_help, "takes at most one KEY (or --schema scene|suite)");
    const char *key = argc == 2 ? argv[1] : NULL;
    int found = 0;
    if (key && (strcmp(key, "bench") == 0 || strcmp(key, "suite") == 0)) {
        printf("Benchmark suite keys (elastopt bench SUITE.json; bench/*.json are examples):\n\n");
        for (const eo_cfg_doc *d = suite_docs; d->path; d++) print_section(d);
        for (const eo_cfg_raw_doc *d = suite_raw_docs; d->path; d++) print_raw(d);
        return EO_EXIT_OK;
    }
    for (const eo_cfg_doc *d = eo_config_docs(); d && d->path; d++) {
        if (key && !matches(d->path, key) && !matches(key, d->path)) continue;
        print_section(d);
        found = 1;
    }
    for (const eo_cfg_raw_doc *d = eo_config_raw_docs(); d && d->path; d++) {
        if (key && !matches(d->path, key) && !matches(key, d->path)) continue;
        print_raw(d);
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
            if (!mi->params || !mi->params[0].key) {
                if (key && !kind_hit && strcmp(key, mi->name) == 0) { /* a method without parameters */
                    printf("%s '%s': %s; no parameters\n\n", eo_kind_label((eo_kind)k), mi->name, mi->summary);
                    found = 1;
                }
                continue;
            }
            if (k == EO_KIND_TERM) { /* its scene section, printed with the scene's; by name here */
                const eo_term_type *tt = *t;
                if (!key || strcmp(key, mi->name) != 0 || !tt->section) continue;
                snprintf(path, sizeof path, "%s%s", tt->section, tt->flags & EO_TERM_SECTION_LIST ? ".N" : "");
                printf("%s — section of %s '%s': %s\n", path, eo_kind_label((eo_kind)k), mi->name, mi->summary);
                eo_params_help(stdout, mi->params, path);
                printf("\n");
                found = 1;
                continue;
            }
            snprintf(path, sizeof path, "%s.%s",
                     k == EO_KIND_MATERIAL ? "material" : k == EO_KIND_INTEGRATOR ? "time" : "solver", mi->name);
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
    if (!found) { /* "did you mean": among the sections, kinds and method names */
        char names[8192], hint[160];
        size_t u = (size_t)snprintf(names, sizeof names, "bench");
        for (const eo_cfg_doc *d = eo_config_docs(); d && d->path && u < sizeof names; d++)
            u += (size_t)snprintf(names + u, sizeof names - u, " %s", d->path);
        for (const eo_cfg_raw_doc *d = eo_config_raw_docs(); d && d->path && u < sizeof names; d++)
            u += (size_t)snprintf(names + u, sizeof names - u, " %s", d->path);
        for (int k = 0; k < EO_KIND_COUNT && u < sizeof names; k++) {
            u += (size_t)snprintf(names + u, sizeof names - u, " %s", eo_kind_key((eo_kind)k));
            for (const void *const *t = eo_registry_list((eo_kind)k); t && *t && u < sizeof names; t++)
                u += (size_t)snprintf(names + u, sizeof names - u, " %s", eo_method_info_of(*t)->name);
        }
        eo_suggest_hint(key, names, NULL, hint, sizeof hint);
        fprintf(stderr, "elastopt help: no config section, method or kind named '%s'%s; try `elastopt help`\n", key,
                hint);
        return EO_EXIT_BAD_INPUT;
    }
    return EO_EXIT_OK;
}

const eo_cli_command eo_cmd_help = {
    .name = "help",
    .summary = "document config keys and method parameters with their defaults",
    .usage = "elastopt help [KEY]\n"
             "elastopt help --schema scene|suite\n\n"
             "Without KEY: every config section and every method's parameters (key, type,\n"
             "default, range, meaning). KEY may be a section path (solver, time, mesh.generate),\n"
             "a method name (newton, backtracking, cholmod) or a kind (optimizer, linesearch,\n"
             "stop, hessian_fix, linear, material, integrator, scene) to list its methods, or\n"
             "`bench` for the keys of a benchmark suite. --schema prints the JSON Schema of a\n"
             "scene or suite document (docs/scene.schema.json, docs/suite.schema.json).\n"
             "Any key can be set in the scene JSON or overridden with -o path.key=value.\n",
    .run = run,
};
