/// @file registry.h
/// Registries of pluggable methods, looked up by name.
///
/// Every pluggable kind (material, optimizer, Hessian fix, line search, stopping rule,
/// linear solver, integrator, scene) is a const ops table whose first member is an
/// `eo_method_info`: name, one-line summary, and the descriptor table of its parameters.
/// Each kind has one NULL-terminated array of pointers to the tables (in
/// lib/registry.c); a backend that is not built has no entry. Adding a method is one
/// file exporting one const table plus one line in that array.
///
/// ```c
/// const eo_linsolve_type *ls;
/// int rc = eo_registry_find(ctx, EO_KIND_LINSOLVE, "cholmod", (const void **)&ls);
/// // rc == EO_ERR_UNKNOWN_NAME, message "unknown linear solver 'x'; valid: cholmod, ..."
/// ```
#ifndef ELASTOPT_REGISTRY_H
#define ELASTOPT_REGISTRY_H

#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Common head of every method ops table (must be the first member).
typedef struct eo_method_info {
    const char *name;              ///< registry key and config value
    const char *summary;           ///< one line for `elastopt list`
    const eo_param_desc *params;   ///< method parameters (NULL if none)
    size_t params_size;            ///< sizeof the params struct (0 if none)
} eo_method_info;

/* X(enum, key, label) : key is the config word, label is for messages */
#define EO_KIND_LIST(X)                                                          \
    X(EO_KIND_MATERIAL, "material", "material")                                  \
    X(EO_KIND_OPTIMIZER, "optimizer", "optimizer")                               \
    X(EO_KIND_HESSFIX, "hessian_fix", "Hessian fix")                             \
    X(EO_KIND_LINESEARCH, "linesearch", "line search")                           \
    X(EO_KIND_STOP, "stop", "stopping rule")                                     \
    X(EO_KIND_LINSOLVE, "linear", "linear solver")                               \
    X(EO_KIND_INTEGRATOR, "integrator", "integrator")                            \
    X(EO_KIND_SCENE, "scene", "scene")

#define EO_X_ENUM(e, key, label) e,
typedef enum eo_kind { EO_KIND_LIST(EO_X_ENUM) EO_KIND_COUNT } eo_kind;
#undef EO_X_ENUM

/// Config word ("linear") and label ("linear solver") of a kind.
const char *eo_kind_key(eo_kind kind);
const char *eo_kind_label(eo_kind kind);
/// NULL-terminated array of the registered ops tables of a kind (each begins with
/// eo_method_info).
const void *const *eo_registry_list(eo_kind kind);
/// Info of a registered table.
static inline const eo_method_info *eo_method_info_of(const void *type)
{
    return (const eo_method_info *)type;
}
/// Look up by name. Unknown name: EO_ERR_UNKNOWN_NAME with the valid names listed.
int eo_registry_find(eo_ctx *ctx, eo_kind kind, const char *name, const void **out);
/// Comma-separated registered names of a kind.
void eo_registry_names(eo_kind kind, char *buf, size_t n);

#ifdef __cplusplus
}
#endif
#endif
