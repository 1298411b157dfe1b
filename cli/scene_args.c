/* Scene arguments shared by `elastopt run` and `elastopt check` (see scene_args.h). */
#include <stdio.h>
#include <string.h>

#include "scene_args.h"

int eo_cli_scene_arg(const eo_cli_command *cmd, int argc, char **argv, int *i, eo_cli_scene_args *a)
{
    const char *s = argv[*i];
    if (strcmp(s, "--scene") == 0) {
        if (*i + 1 >= argc) return eo_cli_usage_error(cmd, "--scene needs a NAME"), -1;
        if (a->file || a->scene) return eo_cli_usage_error(cmd, "give one scene (a file or --scene NAME)"), -1;
        a->scene = argv[++*i];
        return 1;
    }
    if (strcmp(s, "-o") == 0 || strncmp(s, "-o", 2) == 0) {
        const char *v = s[2] ? s + 2 : NULL;
        if (!v) {
            if (*i + 1 >= argc) return eo_cli_usage_error(cmd, "-o needs key=value"), -1;
            v = argv[++*i];
        }
        if (a->noverrides >= EO_CLI_MAX_OVERRIDES)
            return eo_cli_usage_error(cmd, "too many -o overrides (max %d)", EO_CLI_MAX_OVERRIDES), -1;
        a->overrides[a->noverrides++] = v;
        return 1;
    }
    if (s[0] == '-' && s[1]) return 0;
    if (a->file || a->scene) return eo_cli_usage_error(cmd, "give one scene (a file or --scene NAME)"), -1;
    a->file = s;
    return 1;
}

int eo_cli_scene_load(eo_ctx *ctx, const eo_cli_scene_args *a, eo_cfg **cfg, eo_scene **sc)
{
    *sc = NULL;
    int rc = eo_scene_cfg_load(ctx, a->file, a->scene, cfg);
    if (rc < 0) return rc;
    for (int k = 0; k < a->noverrides; k++) {
        rc = eo_cfg_override(ctx, *cfg, a->overrides[k]);
        if (rc < 0) return rc;
    }
    return eo_scene_load(ctx, *cfg, sc);
}

void eo_cli_scene_name(const eo_cli_scene_args *a, char *buf, size_t n)
{
    if (!a->file) {
        snprintf(buf, n, "%s", a->scene ? a->scene : "cantilever");
        return;
    }
    const char *b = strrchr(a->file, '/');
    b = b ? b + 1 : a->file;
    snprintf(buf, n, "%s", b);
    char *dot = strrchr(buf, '.');
    if (dot && dot != buf) *dot = 0;
}

void eo_cli_scene_report(eo_ctx *ctx, const eo_scene *sc, int quiet)
{
    if (quiet) return;
    char *text = NULL;
    if (eo_scene_describe(ctx, sc, &text) < 0) {
        fprintf(stderr, "elastopt: warning: no scene description: %s\n", eo_ctx_message(ctx));
        return;
    }
    for (char *line = text, *nl; line && *line; line = nl ? nl + 1 : NULL) {
        nl = strchr(line, '\n');
        int n = nl ? (int)(nl - line) : (int)strlen(line);
        if (strncmp(line, "warning: ", 9) == 0) fprintf(stderr, "elastopt: %.*s\n", n, line);
        else printf("%.*s\n", n, line);
    }
    fflush(stdout);
    eo_free(ctx, text);
}
