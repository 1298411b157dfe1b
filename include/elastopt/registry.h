/// @file registry.h
/// Registries of pluggable methods, looked up by name; methods can be added at run time.
///
/// Every pluggable kind (material, optimizer, Hessian fix, line search, stopping rule,
/// linear solver, integrator, scene, element, term of the step problem) is a const ops table whose first member is an
/// `eo_method_info`: name, one-line summary, and the descriptor table of its parameters.
/// Each kind has one registry (`eo_registry`), defined in the layer that owns the kind
/// (materials/registry.c, solvers/<kind>/registry.c, problems/registry.c): its built-in
/// tables (a NULL-terminated const array, one line per method) plus the tables registered
/// at run time with `eo_register`. A backend that is not built has no entry.
///
/// Adding a method in-tree is one file exporting one const table plus one line in its
/// folder's array. From outside the tree (a program linking libelastopt, or a plug-in
/// shared object loaded with `eo_plugin_load`) it is one call:
///
/// ```c
/// static const eo_optimizer_type my_opt = { .info = {.name = "heavy_ball", ...}, ... };
/// rc = eo_register(ctx, EO_KIND_OPTIMIZER, &my_opt);  // now valid in configs, -o, list, help
/// const eo_linsolve_type *ls;
/// rc = eo_registry_find(ctx, EO_KIND_LINSOLVE, "cholmod", (const void **)&ls);
/// // unknown name: EO_ERR_UNKNOWN_NAME, message "unknown linear solver 'x'; valid: cholmod, ..."
/// ```
/// After registration a method is treated exactly like a built-in one: config files,
/// `-o` overrides (its parameter section `solver.<name>` is accepted and checked), `elastopt
/// list`, `help`, `run` and `bench`.
///
/// Ownership and threads: registries borrow the tables (they must stay valid, e.g. static
/// storage, until unregistered or the process ends). Registries are process-wide and NOT
/// thread-safe: register before creating objects or starting threads that look names up.
#ifndef ELASTOPT_REGISTRY_H
#define ELASTOPT_REGISTRY_H

#include "export.h"
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
    /// EO_METHOD_* flags (0 for most). Appended last.
    unsigned flags;
} eo_method_info;

/// eo_method_info.flags. EO_METHOD_DISTRIBUTED: a solver method (optimizer, Hessian fix,
/// line search, stopping rule) that runs on a distributed objective (objective.h,
/// eo_vspace): every sum over a vector goes through the objective's space (eo_vdot, ...),
/// every decision is taken on reduced values; a linear solver with it takes a part's
/// Hessian (eo_linsolve_set_space). Methods without it are refused when the solver is
/// configured for a distributed run (solver.backend=petsc).
enum { EO_METHOD_DISTRIBUTED = 1 };

/* X(enum, key, label) : key is the config word, label is for messages */
#define EO_KIND_LIST(X)                                                          \
    X(EO_KIND_MATERIAL, "material", "material")                                  \
    X(EO_KIND_OPTIMIZER, "optimizer", "optimizer")                               \
    X(EO_KIND_HESSFIX, "hessian_fix", "Hessian fix")                             \
    X(EO_KIND_LINESEARCH, "linesearch", "line search")                           \
    X(EO_KIND_STOP, "stop", "stopping rule")                                     \
    X(EO_KIND_LINSOLVE, "linear", "linear solver")                               \
    X(EO_KIND_INTEGRATOR, "integrator", "integrator")                            \
    X(EO_KIND_SCENE, "scene", "scene")                                           \
    X(EO_KIND_ELEMENT, "element", "element")                                     \
    X(EO_KIND_TERM, "term", "term")

#define EO_X_ENUM(e, key, label) e,
typedef enum eo_kind { EO_KIND_LIST(EO_X_ENUM) EO_KIND_COUNT } eo_kind;
#undef EO_X_ENUM

/// The registry of one kind. Defined (statically initialized with EO_REGISTRY_INIT) by
/// the layer owning the kind; the fields are for the registry functions only.
typedef struct eo_registry {
    eo_kind kind;
    const void *const *builtin;    ///< NULL-terminated built-in tables
    /// Kind-specific check of a table offered to eo_register (required ops present):
    /// EO_OK or an error with a message. May be NULL.
    int (*check)(eo_ctx *ctx, const void *type);
    const void **all;              ///< built-in + registered, NULL-terminated (NULL: builtin only)
    int nall, cap;
} eo_registry;
#define EO_REGISTRY_INIT(kind_, builtin_, check_) {(kind_), (builtin_), (check_), NULL, 0, 0}

/// Config word ("linear") and label ("linear solver") of a kind.
EO_API const char *eo_kind_key(eo_kind kind);
EO_API const char *eo_kind_label(eo_kind kind);
/// Info of a registered table.
static inline const eo_method_info *eo_method_info_of(const void *type)
{
    return (const eo_method_info *)type;
}

/* ---- one registry (used by the layers themselves; lib/registry.c) */

/// NULL-terminated tables of a registry: built-in first, then registered, in order.
EO_API const void *const *eo_registry_types(const eo_registry *r);
/// Look up by name. Unknown name: EO_ERR_UNKNOWN_NAME with the valid names listed.
EO_API int eo_registry_lookup(eo_ctx *ctx, const eo_registry *r, const char *name, const void **out);
/// Comma-separated names of a registry.
EO_API void eo_registry_name_list(const eo_registry *r, char *buf, size_t n);
/// Add a table: its name must be a non-empty word of letters, digits, '_' and '-' not
/// yet registered in this kind, and r->check must accept it. EO_OK, EO_ERR_INVALID
/// (bad or duplicate name, missing op), EO_ERR_NOMEM. The table is borrowed.
EO_API int eo_registry_add(eo_ctx *ctx, eo_registry *r, const void *type);
/// Remove a table added with eo_registry_add (built-ins cannot be removed). Returns
/// EO_OK or EO_ERR_INVALID if it was not registered.
EO_API int eo_registry_remove(eo_registry *r, const void *type);

/* ---- by kind (the public entry points; problems/registry.c) */

/// The registry of a kind (NULL for an invalid kind).
EO_API eo_registry *eo_registry_of(eo_kind kind);
/// NULL-terminated array of the tables of a kind (each begins with eo_method_info).
EO_API const void *const *eo_registry_list(eo_kind kind);
/// Look up by name. Unknown name: EO_ERR_UNKNOWN_NAME with the valid names listed.
EO_API int eo_registry_find(eo_ctx *ctx, eo_kind kind, const char *name, const void **out);
/// Comma-separated registered names of a kind.
EO_API void eo_registry_names(eo_kind kind, char *buf, size_t n);
/// Register a method table of a kind at run time (see the file comment). The table's
/// type must match the kind: eo_material_type, eo_optimizer_type, eo_hessfix_type,
/// eo_linesearch_type, eo_stop_type, eo_linsolve_type, eo_integrator_type,
/// eo_scene_type, eo_element_type, eo_term_type (impl/term.h; register a term before
/// loading the scenes that use its section). EO_OK, EO_ERR_INVALID (bad kind, name, duplicate, missing ops),
/// EO_ERR_NOMEM.
EO_API int eo_register(eo_ctx *ctx, eo_kind kind, const void *type);
/// Undo eo_register (e.g. before a plug-in is unloaded). EO_OK or EO_ERR_INVALID.
EO_API int eo_unregister(eo_kind kind, const void *type);

#ifdef __cplusplus
}
#endif
#endif
