/// @file elastopt.h
/// Everything of the elastopt C API in one include (`#include <elastopt/elastopt.h>`,
/// link with `pkg-config --libs elastopt`).
///
/// Conventions (they hold for every header below):
///  - **Errors.** Functions that can fail return an `int` status: `EO_OK` (0) or a
///    negative `eo_status` (status.h); a positive value is a warning where a function
///    documents one. The message, naming the file, line and element where one applies,
///    is kept in the context: `eo_ctx_message(ctx)`. The library never prints (it logs
///    through the context's logger, `eo_ctx_set_logger`), never calls `exit` and never
///    spawns processes. Solvers report how a minimization ended separately, as an
///    `eo_reason` (positive: converged, negative: diverged); a negative reason is not an
///    error status.
///  - **Ownership.** Every object is created against an `eo_ctx` (ctx.h) with
///    `eo_<type>_create(ctx, ..., &out)` and freed with `eo_<type>_destroy(&p)`, which
///    accepts NULL and sets the pointer to NULL; destroy every object before its context
///    (`eo_ctx_live_bytes` is then 0). Pointers returned by a `get_` or borrowed through
///    a struct stay valid until the owner is changed or destroyed, as each function
///    says; arrays passed in are copied unless the function says it borrows them.
///  - **Naming.** Functions `eo_<module>_<verb>`, types `eo_<name>`, constants and enums
///    `EO_<NAME>`. Pluggable methods are registered kinds (registry.h): a const ops table
///    `eo_<kind>_type` whose `info.name` is the name used in configs.
///  - **Options.** Plain structs with documented defaults (`eo_<x>_opts_default`), filled
///    from JSON config sections; unknown keys and names are errors listing the valid ones.
///  - **Threads.** A context and the objects created with it are used by one thread at a
///    time; independent contexts may be used concurrently. Element loops may use OpenMP
///    internally (config `threads`); the BLAS thread count is the process's
///    (machine.h).
///  - **Audiences.** sim.h, scene.h, solver.h (creating and running solvers), mesh.h,
///    io.h, material.h are the user API; objective.h, impl/method.h (the `eo_*_type` ops
///    tables, `eo_solver_ctx`, `eo_stop_info`, eo_solver_stop_check), impl/params.h (the
///    built-in methods' parameter structs), linsolve.h, callback.h, registry.h, plugin.h
///    and params.h are for writing methods and plug-ins.
#ifndef ELASTOPT_ELASTOPT_H
#define ELASTOPT_ELASTOPT_H

#include "export.h"
#include "status.h"
#include "ctx.h"
#include "params.h"
#include "config.h"
#include "registry.h"
#include "mesh.h"
#include "trimesh.h"
#include "io.h"
#include "material.h"
#include "element.h"
#include "proj.h"
#include "sparse.h"
#include "linsolve.h"
#include "objective.h"
#include "solver.h"
#include "impl/method.h"
#include "impl/params.h"
#include "callback.h"
#include "scene.h"
#include "step.h"
#include "sim.h"
#include "stability.h"
#include "poisson.h"
#include "machine.h"
#include "suggest.h"
#include "plugin.h"

#endif
