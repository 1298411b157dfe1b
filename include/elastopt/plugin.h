/// @file plugin.h
/// Methods from outside the tree: plug-in shared objects loaded at run time.
///
/// A plug-in is a shared object, built against the installed library
/// (`cc -shared -fPIC my.c $(pkg-config --cflags --libs elastopt) -o my.so`), that
/// exports one entry point, declared with EO_PLUGIN_ENTRY. It registers its methods with
/// eo_register (registry.h); from then on they are valid in configs, `-o`, `elastopt
/// list`, `help`, `run` and `bench`, exactly like built-in ones.
///
/// ```c
/// #include <elastopt/plugin.h>
/// static const eo_optimizer_type heavy_ball = { .info = {.name = "heavy_ball", ...}, ... };
/// EO_PLUGIN_ENTRY(ctx)
/// {
///     return eo_register(ctx, EO_KIND_OPTIMIZER, &heavy_ball);
/// }
/// ```
/// The CLI loads plug-ins named by `--plugin FILE` (any number, anywhere on the command
/// line) and by the environment variable ELASTOPT_PLUGINS (a ':'-separated list); a
/// program calls eo_plugin_load itself. A program linking the library can also call
/// eo_register directly, without a shared object.
///
/// Compatibility: the entry point receives the library's EO_ABI_VERSION; the macro makes
/// the plug-in refuse to load (EO_ERR_UNSUPPORTED) when it was compiled against another
/// one. Loaded objects are never unloaded (their tables stay registered).
#ifndef ELASTOPT_PLUGIN_H
#define ELASTOPT_PLUGIN_H

#include "export.h"
#include "registry.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Version of the method-table layouts (bumped when an ops table changes incompatibly).
/// 3: eo_integrator_type (theta, history ops), eo_objective_ops (inertia),
/// eo_optimizer_type (linesearch), eo_material_type (pd_weight), eo_iter_info (eta,
/// lin_iters, neg_curvature), eo_stop_info (decrement0, decrement_prev), eo_ls_extra
/// (g_hist, n_hist), eo_hessfix_out (neg_curvature), eo_solve_result and
/// eo_newton_params grew. 4: eo_solver_opts grew (backend), eo_objective_ops grew
/// (constant_factor, constant_solve). 5: eo_newton_params grew (estimate_gate).
/// 7: eo_stop_info (the convergence measure), eo_solver_ctx (stop_state), eo_optimizer_type
/// (newton_decrement), eo_objective_ops (rounding_scale). 8: eo_objective_ops grew (max_step,
/// characteristic, split_info, split_apply, split_adjoint), eo_stop_info grew (grad_char); vertex_blocks, vertex_block; eo_pd_local_global_params grew (chebyshev, rho,
/// delay, gamma); CPU-time fields appended to the solve,
/// profile, linear-solver and step results. 9: eo_optimizer_type grew (needs_ops), the
/// kind EO_KIND_ELEMENT (eo_element_type), eo_scene_opts / eo_scene (element) and eo_mesh
/// (order, tet10, tri_mid) grew; eo_objective_ops.rounding_scale fills s[3] (the value scale);
/// eo_objective_ops grew (split_assemble); the kind EO_KIND_TERM (eo_term_type, impl/term.h:
/// the terms of the step problem, eo_sys, eo_term_ops, eo_term) and eo_scene grew
/// (nterm_cfg, term_type, term_cfg). 10: eo_linsolve_type grew (is_iterative, describe).
/// 11: the distributed solver core (eo_vspace, eo_objective.space, eo_method_info.flags,
/// eo_dist_hooks.space). 12: eo_dist_hooks grew (owned_vertices), eo_sys grew (vonce).
/// 13: eo_linsolve_type grew (forget).
#define EO_ABI_VERSION 13

/// The library's EO_ABI_VERSION.
EO_API int eo_abi_version(void);

/// Name of the entry point a plug-in exports.
#define EO_PLUGIN_SYMBOL "elastopt_plugin_init"

/// Define a plug-in's entry point: `EO_PLUGIN_ENTRY(ctx) { return eo_register(...); }`.
/// The body runs only when the library's ABI version matches the plug-in's.
#define EO_PLUGIN_ENTRY(ctx)                                                             \
    static int eo_plugin_body_(eo_ctx *ctx);                                             \
    __attribute__((visibility("default"))) int elastopt_plugin_init(eo_ctx *ctx, int abi) \
    {                                                                                    \
        if (abi != EO_ABI_VERSION)                                                       \
            return eo_error(ctx, EO_ERR_UNSUPPORTED,                                     \
                            "plug-in built for elastopt ABI %d, library has ABI %d",     \
                            EO_ABI_VERSION, abi);                                        \
        return eo_plugin_body_(ctx);                                                     \
    }                                                                                    \
    static int eo_plugin_body_(eo_ctx *ctx)

/// Load a plug-in shared object and run its entry point. Errors name the file:
/// EO_ERR_IO (cannot be loaded: the loader's message), EO_ERR_INVALID (no entry point),
/// or the entry point's own status (e.g. a duplicate name from eo_register).
EO_API int eo_plugin_load(eo_ctx *ctx, const char *path);

#ifdef __cplusplus
}
#endif
#endif
