/// @file config.h
/// A configuration document: JSON from a file (or built-in text) plus `-o key=value`
/// overrides, handed out section by section to descriptor tables (params.h).
///
/// Every key of the document must be consumed by some section load; `eo_cfg_finish`
/// reports any key nobody asked for as EO_ERR_UNKNOWN_KEY with the valid keys at that
/// level. Errors name the file with line and column (of the key), or the `-o` override
/// that set the value.
///
/// ```c
/// eo_cfg *cfg; rc = eo_cfg_load(ctx, "scene.json", NULL, &cfg);  // NULL path: builtin text
/// rc = eo_cfg_override(ctx, cfg, "solver.optimizer=lbfgs");
/// rc = eo_cfg_section(ctx, cfg, "time", time_desc, &time_opts, NULL);
/// json_t *b = eo_cfg_get(cfg, "boundary");            // borrowed, for list sections
/// rc = eo_cfg_finish(ctx, cfg);                        // unknown keys?
/// eo_cfg_destroy(&cfg);
/// ```
#ifndef ELASTOPT_CONFIG_H
#define ELASTOPT_CONFIG_H

#include "export.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_cfg eo_cfg;

/// Largest configuration file read (scene, suite, a run's run.json: twice this, it holds
/// the config with indentation) and largest `-o` assignment, bytes: 8 MiB. The size is
/// checked before anything is read (a larger file is refused with EO_ERR_RANGE naming its
/// size and this cap); jansson needs about ten times the text in memory, so the cap keeps
/// a config load under ~100 MB. A scene far beyond it (mesh.points of > 100k points,
/// springs.list of > 300k pairs) belongs in a mesh file (mesh.file), which has no cap.
#define EO_CFG_MAX_BYTES ((size_t)8 << 20)

/// Parse `path` (or, if path is NULL, `builtin_text` named "<builtin>"). Malformed JSON:
/// EO_ERR_PARSE with file:line:column and jansson's description (numbers that overflow a
/// double, 1e999, are malformed JSON: no value of a config is ever infinite or NaN).
/// Missing file: EO_ERR_IO. A file over EO_CFG_MAX_BYTES: EO_ERR_RANGE, nothing read.
EO_API int eo_cfg_load(eo_ctx *ctx, const char *path, const char *builtin_text, eo_cfg **out);
/// An empty document.
EO_API int eo_cfg_create_empty(eo_ctx *ctx, eo_cfg **out);
EO_API void eo_cfg_destroy(eo_cfg **cfg);
/// Apply "a.b.c=value": value parsed as JSON if it is JSON, else a string; creates
/// intermediate objects; list items by index ("boundary.0.fixed=true").
/// EO_ERR_INVALID for a text without '=' or an empty key.
EO_API int eo_cfg_override(eo_ctx *ctx, eo_cfg *cfg, const char *assignment);
/// The value at a dotted path, or NULL (borrowed). Marks it (and its parents) consumed.
EO_API json_t *eo_cfg_get(eo_cfg *cfg, const char *path);
/// Record the valid keys at a level that is not loaded by eo_cfg_section (e.g. the
/// top level: "mesh", "material", ...), for the unknown-key message.
EO_API void eo_cfg_expect(eo_cfg *cfg, const char *path, const char *const *keys);
/// Mark a path consumed without reading it (e.g. a subtree handled elsewhere).
EO_API void eo_cfg_consume(eo_cfg *cfg, const char *path);
/// Load the object at `path` into a params struct (keys in `extra` are skipped; they are
/// sub-sections the caller loads itself). Absent section: defaults kept, EO_OK.
EO_API int eo_cfg_section(eo_ctx *ctx, eo_cfg *cfg, const char *path, const eo_param_desc *d,
                   void *obj, const char *const *extra);
/// The error source for a path: file + text, or "-o" when an override set the value.
EO_API eo_param_src eo_cfg_src(eo_cfg *cfg, const char *path);
/// Record an error about the value at `path`, located where it came from: "command line
/// -o PATH: TEXT" when an override set it, else "FILE:LINE:COLUMN: key 'PATH': TEXT";
/// returns status.
EO_API int eo_cfg_error(eo_ctx *ctx, eo_cfg *cfg, const char *path, int status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;
/// Report the first key that no load consumed (EO_ERR_UNKNOWN_KEY listing the keys
/// that are valid at that level, as recorded by the section loads).
EO_API int eo_cfg_finish(eo_ctx *ctx, eo_cfg *cfg);
/// The whole document (borrowed), e.g. to echo it.
EO_API json_t *eo_cfg_root(eo_cfg *cfg);
/// File name the config came from ("<builtin>" if none).
EO_API const char *eo_cfg_file(const eo_cfg *cfg);

/// A documented config section: its dotted path ("N" stands for a list index), descriptor
/// table and one-line summary.
typedef struct eo_cfg_doc {
    const char *path;
    const eo_param_desc *params;
    const char *summary;
} eo_cfg_doc;
/// A documented key whose value is not a params section (a list of points, a box): its
/// dotted path, the JSON Schema of its value as JSON text (NULL: documented only), help.
typedef struct eo_cfg_raw_doc {
    const char *path;
    const char *schema;
    const char *summary;
} eo_cfg_raw_doc;

#ifdef __cplusplus
}
#endif
#endif
