/// @file status.h
/// Status codes and convergence reasons of elastopt.
///
/// Three channels report things going wrong:
///  - a status code (`eo_status`, an int): 0 ok, negative error, positive warning.
///    Every library call that can fail returns one; the context (ctx.h) holds the
///    message with file, line and element index of the last error.
///  - a convergence reason (`eo_reason`): positive = converged and why, negative =
///    stopped without converging and why, 0 = still iterating. Hitting the iteration
///    cap is a reason, not an error. An explicit integrator's step has its own positive
///    reason, EO_REASON_EXPLICIT ("explicit"): nothing was solved, nothing failed.
///  - assertions for programmer errors (EO_ASSERT in ctx.h).
///
/// Both lists are X-macros: the enum values and their strings come from one table.
///
/// ```c
/// int rc = eo_mesh_read(ctx, "bar.msh", &mesh);
/// if (rc < 0) fprintf(stderr, "%s: %s\n", eo_status_string(rc), eo_ctx_message(ctx));
/// ```
#ifndef ELASTOPT_STATUS_H
#define ELASTOPT_STATUS_H

#include "export.h"
#ifdef __cplusplus
extern "C" {
#endif

/* X(name, value, string) */
#define EO_STATUS_LIST(X)                                                        \
    X(EO_OK, 0, "ok")                                                            \
    X(EO_ERR_NOMEM, -1, "out of memory")                                         \
    X(EO_ERR_IO, -2, "input/output error")                                       \
    X(EO_ERR_PARSE, -3, "malformed input")                                       \
    X(EO_ERR_INVALID, -4, "invalid argument")                                    \
    X(EO_ERR_RANGE, -5, "value out of range")                                    \
    X(EO_ERR_UNKNOWN_KEY, -6, "unknown configuration key")                       \
    X(EO_ERR_UNKNOWN_NAME, -7, "unknown method name")                            \
    X(EO_ERR_TYPE, -8, "wrong value type")                                       \
    X(EO_ERR_MESH, -9, "invalid mesh")                                           \
    X(EO_ERR_NONFINITE, -10, "non-finite value")                                 \
    X(EO_ERR_LINSOLVE, -11, "linear solver failure")                             \
    X(EO_ERR_UNSUPPORTED, -12, "operation not supported")                        \
    X(EO_ERR_INTERNAL, -13, "internal error")                                    \
    X(EO_WARN_NOT_PD, 1, "matrix not positive definite")                         \
    X(EO_WARN_DROPPED, 2, "input items dropped")                                 \
    X(EO_WARN_NOT_CONVERGED, 3, "not converged")

/* X(name, value, string) */
#define EO_REASON_LIST(X)                                                        \
    X(EO_REASON_ITERATING, 0, "iterating")                                       \
    X(EO_CONVERGED_DECREMENT, 1, "newton decrement below tolerance")             \
    X(EO_CONVERGED_GRADIENT, 2, "gradient norm below tolerance")                 \
    X(EO_CONVERGED_STEP, 3, "step below tolerance")                              \
    X(EO_CONVERGED_ENERGY, 4, "energy change below tolerance")                   \
    X(EO_CONVERGED_EXTERNAL, 5, "external solver reports convergence")           \
    X(EO_REASON_EXPLICIT, 6, "explicit time step (nothing to solve)")           \
    X(EO_DIVERGED_MAX_ITERS, -1, "maximum iterations reached")                   \
    X(EO_DIVERGED_LINESEARCH, -2, "line search failed")                          \
    X(EO_DIVERGED_NONFINITE, -3, "non-finite objective or gradient")             \
    X(EO_DIVERGED_NOT_DESCENT, -4, "not a descent direction")                    \
    X(EO_DIVERGED_LINSOLVE, -5, "linear solve failed")                           \
    X(EO_DIVERGED_NOT_PD, -6, "hessian not positive definite")                   \
    X(EO_DIVERGED_TIME_BUDGET, -7, "time budget exhausted")                      \
    X(EO_DIVERGED_EXTERNAL, -8, "external solver failed")                       \
    X(EO_DIVERGED_STAGNATED, -9, "g stopped decreasing (tolerance below rounding level?)") \
    X(EO_DIVERGED_NOT_CONTRACTING, -10, "fixed-point iteration not contracting (its update grows)")

#define EO_X_ENUM(name, value, str) name = value,
typedef enum eo_status { EO_STATUS_LIST(EO_X_ENUM) } eo_status;
typedef enum eo_reason { EO_REASON_LIST(EO_X_ENUM) } eo_reason;
#undef EO_X_ENUM

/// Human-readable string of a status code; "unknown status" for values not listed.
EO_API const char *eo_status_string(int status);
/// Symbolic name ("EO_ERR_PARSE") of a status code.
EO_API const char *eo_status_name(int status);
/// Human-readable string of a convergence reason.
EO_API const char *eo_reason_string(int reason);
/// Short symbolic name of a reason, lower case without prefix ("converged_decrement").
EO_API const char *eo_reason_name(int reason);
/// Former name of EO_REASON_EXPLICIT (its reason name was "converged_explicit").
#define EO_CONVERGED_EXPLICIT EO_REASON_EXPLICIT

/// 1 if the reason is positive: nothing failed (an optimization converged, or an
/// explicit step had nothing to solve). Exit statuses and "all converged" use this.
static inline int eo_reason_is_converged(int reason) { return reason > 0; }
/// 1 if an explicit time step advanced the state (EO_REASON_EXPLICIT): no optimization
/// ran; reports count such steps as "explicit", not as converged.
static inline int eo_reason_is_explicit(int reason) { return reason == EO_REASON_EXPLICIT; }

#ifdef __cplusplus
}
#endif
#endif
