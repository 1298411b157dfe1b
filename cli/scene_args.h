/* Shared by `elastopt run` and `elastopt check`: parse [SCENE.json | --scene NAME]
 * [-o key=value ...] and load the configuration document and the scene from it. */
#ifndef ELASTOPT_CLI_SCENE_ARGS_H
#define ELASTOPT_CLI_SCENE_ARGS_H

#include "cli.h"
#include "elastopt/scene.h"

enum { EO_CLI_MAX_OVERRIDES = 64 };

typedef struct eo_cli_scene_args {
    const char *file;    /* SCENE.json, or NULL */
    const char *scene;   /* --scene NAME, or NULL */
    const char *overrides[EO_CLI_MAX_OVERRIDES];
    int noverrides;
} eo_cli_scene_args;

/* Try to consume argv[*i] (and its value) as a scene argument: returns 1 if consumed,
 * 0 if not a scene argument, -1 on a usage error (message printed, exit 2). */
int eo_cli_scene_arg(const eo_cli_command *cmd, int argc, char **argv, int *i, eo_cli_scene_args *a);
/* Load the document (file or built-in scene, default cantilever), apply the
 * overrides, load the scene. Errors are in ctx (bad input). */
int eo_cli_scene_load(eo_ctx *ctx, const eo_cli_scene_args *a, eo_cfg **cfg, eo_scene **sc);
/* Print the scene description (eo_scene_describe): vertex count of every boundary
 * set, tet count of every material region to stdout, "elastopt: warning: ..." lines
 * (gravity against the mesh's obvious up) to stderr. Nothing when quiet. */
void eo_cli_scene_report(eo_ctx *ctx, const eo_scene *sc, int quiet);
/* Name of the run: the built-in scene name or the file's base name without .json. */
void eo_cli_scene_name(const eo_cli_scene_args *a, char *buf, size_t n);

#endif
