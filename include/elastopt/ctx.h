/// @file ctx.h
/// The elastopt context: allocator with a live-byte counter, logger, last error.
///
/// Every library object is created against a context; all its allocations go through
/// `eo_malloc`/`eo_free` of that context, so `eo_ctx_live_bytes` returning 0 after
/// everything is destroyed proves there is no leak. The library never prints and never
/// calls `exit`: errors are returned as negative status codes and the message (with
/// file, line and element index where one applies) is kept in the context.
///
/// ```c
/// eo_ctx *ctx = NULL;
/// eo_ctx_create(NULL, &ctx);                  // default allocator, no logger
/// eo_ctx_set_logger(ctx, eo_log_stderr, NULL, EO_LOG_INFO);
/// int rc = eo_mesh_read(ctx, path, &mesh);
/// if (rc < 0) fprintf(stderr, "error: %s\n", eo_ctx_message(ctx));
/// eo_ctx_destroy(&ctx);
/// ```
/// Ownership: the context owns nothing but its own state; objects created with it
/// must be destroyed before it.
#ifndef ELASTOPT_CTX_H
#define ELASTOPT_CTX_H

#include "export.h"
#include <stddef.h>
#include <stdarg.h>
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_ctx eo_ctx;

/// Allocator hooks; any may be NULL to use the C library. `user` is passed back.
typedef struct eo_allocator {
    void *(*malloc_fn)(size_t size, void *user);
    void *(*realloc_fn)(void *p, size_t size, void *user);
    void (*free_fn)(void *p, void *user);
    void *user;
} eo_allocator;

typedef enum eo_log_level {
    EO_LOG_ERROR = 0,
    EO_LOG_WARN = 1,
    EO_LOG_INFO = 2,
    EO_LOG_DEBUG = 3
} eo_log_level;

typedef void (*eo_log_fn)(eo_log_level level, const char *msg, void *user);

/// Location attached to an error. Fields that do not apply are NULL / -1.
typedef struct eo_errloc {
    const char *file;  ///< input file (or config key path); NULL if none
    long line;         ///< 1-based line in that file, -1 if none
    long column;       ///< 1-based column, -1 if none
    const char *kind;  ///< what `index` counts ("tet", "vertex", "node"); NULL = "item"
    long index;        ///< element/vertex/item index (as the input numbers it), -1 if none
} eo_errloc;

#define EO_ERRLOC_NONE ((eo_errloc){NULL, -1, -1, NULL, -1})
/// Location in a file: EO_ERRLOC_FILE(path, line).
#define EO_ERRLOC_FILE(f, l) ((eo_errloc){(f), (l), -1, NULL, -1})
/// Location of an indexed item, optionally in a file.
#define EO_ERRLOC_ITEM(f, l, k, i) ((eo_errloc){(f), (l), -1, (k), (i)})

/// Create a context. `alloc` is copied (may be NULL). Returns EO_OK or EO_ERR_NOMEM.
EO_API int eo_ctx_create(const eo_allocator *alloc, eo_ctx **out);
/// Destroy a context; sets *ctx to NULL; accepts NULL.
EO_API void eo_ctx_destroy(eo_ctx **ctx);

/// Install a logger (NULL = silent) and the most verbose level passed to it.
EO_API void eo_ctx_set_logger(eo_ctx *ctx, eo_log_fn fn, void *user, eo_log_level level);
/// A ready-made logger writing "level: msg" lines to stderr.
EO_API void eo_log_stderr(eo_log_level level, const char *msg, void *user);
/// Log a printf-style message through the context's logger (no-op without one).
EO_API void eo_log(eo_ctx *ctx, eo_log_level level, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/// Allocation through the context; counted in live bytes. eo_free accepts NULL.
EO_API void *eo_malloc(eo_ctx *ctx, size_t size);
EO_API void *eo_calloc(eo_ctx *ctx, size_t n, size_t size);
EO_API void *eo_realloc(eo_ctx *ctx, void *p, size_t size);
EO_API void eo_free(eo_ctx *ctx, void *p);
/// Copy a string into context memory.
EO_API char *eo_strdup(eo_ctx *ctx, const char *s);
/// Bytes currently allocated through the context.
EO_API size_t eo_ctx_live_bytes(const eo_ctx *ctx);
/// Failure injection for tests: the n-th allocation from now (1-based) fails; 0 disables.
EO_API void eo_ctx_fail_after(eo_ctx *ctx, long n);

/// Record an error (or warning) and return `status`. The message is formatted as
/// "<file>:<line>:<column>: <kind> <index>: <text>" with absent parts left out.
EO_API int eo_error_at(eo_ctx *ctx, int status, eo_errloc loc, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
EO_API int eo_error_atv(eo_ctx *ctx, int status, eo_errloc loc, const char *fmt, va_list ap);
/// Shorthand without location.
#define eo_error(ctx, status, ...) eo_error_at((ctx), (status), EO_ERRLOC_NONE, __VA_ARGS__)

/// Quiet warnings: while on (1), a warning recorded with eo_error_at (positive status) is
/// kept as the context's message but not passed to the logger (errors are logged at
/// debug level either way). For a caller that reports the warning itself, or counts an
/// expected one (eo_linsolve_factor and a not-positive-definite factorization). Returns
/// the previous setting; default 0.
EO_API int eo_ctx_set_quiet_warnings(eo_ctx *ctx, int on);
/// The current setting of eo_ctx_set_quiet_warnings.
EO_API int eo_ctx_get_quiet_warnings(const eo_ctx *ctx);

/// A simulation distributed over several processes (a distributed backend installs this on
/// the context; the library itself knows nothing of MPI). With hooks installed and
/// nparts > 1, the scene loader hands the whole mesh (given on part 0; the other parts'
/// mesh is ignored) to distribute_mesh, which replaces it by this part's local mesh (its
/// tets and their vertices), and every decision the scene loader and the step engine
/// take on sums or extremes over the mesh (the box-selection tolerance, a boundary entry
/// selecting no vertex, the step's starting guess, a finite state, the statistics) is
/// reduced over the parts with `reduce`, so that every part takes the same one. Element
/// sums (energies, masses, gravity loads) of the local meshes add up to the whole; the
/// scene features whose local form would not (contact, friction, tractions, springs,
/// point masses, damping, surface/tag/nearest selections, random initial balls,
/// mass-spring meshes) are refused at load with a message.
typedef enum eo_reduce_op { EO_REDUCE_SUM = 0, EO_REDUCE_MIN = 1, EO_REDUCE_MAX = 2 } eo_reduce_op;
struct eo_mesh;
struct eo_objective;
struct eo_vspace;
typedef struct eo_dist_hooks {
    int nparts; ///< number of processes (> 1: distributed)
    int part;   ///< this process (0 .. nparts-1)
    /// In place over the parts (collective); returns 0 or a negative status.
    int (*reduce)(double *v, int n, eo_reduce_op op, void *user);
    /// Collective: *mesh (the whole mesh on part 0) -> this part's local mesh (allocated
    /// through ctx; the old one destroyed). Returns EO_OK or a negative status with a
    /// message in ctx (then every part fails).
    int (*distribute_mesh)(eo_ctx *ctx, struct eo_mesh **mesh, void *user);
    void *user;
    /// Optional (a backend that runs the library's optimizers distributed): the vector
    /// space (objective.h, eo_vspace) of the free variables of the step objective `obj` on
    /// this part, numbered over the parts (collective; rebuilt when a part's free set
    /// changed). EO_OK with *out borrowed until the next call, or a negative status. Without
    /// it the solvers refuse to run distributed (solvers/dist_objective.c).
    int (*space)(eo_ctx *ctx, struct eo_objective *obj, const struct eo_vspace **out, void *user);
    /// Optional: after distribute_mesh, nv flags of this part's local mesh, 1 = this part
    /// owns the vertex (borrowed, valid while the mesh is). Terms of one vertex's position
    /// alone (penalty contact) are counted by the owner only; without it such terms are
    /// refused in a distributed run.
    const unsigned char *(*owned_vertices)(void *user);
} eo_dist_hooks;
/// Install (h != NULL, copied) or remove (NULL) the distribution hooks.
EO_API void eo_ctx_set_dist(eo_ctx *ctx, const eo_dist_hooks *h);
/// The hooks if the context runs one part of a distributed simulation (nparts > 1), else NULL.
EO_API const eo_dist_hooks *eo_ctx_dist(const eo_ctx *ctx);
/// v[0..n) reduced over the parts in place (nothing on a serial context); returns 0 or a
/// negative status.
EO_API int eo_ctx_reduce(eo_ctx *ctx, double *v, int n, eo_reduce_op op);

/// The last error message ("" if none) and its status.
EO_API const char *eo_ctx_message(const eo_ctx *ctx);
EO_API int eo_ctx_status(const eo_ctx *ctx);
/// Forget the last error.
EO_API void eo_ctx_clear_error(eo_ctx *ctx);
/// Assertion handler for programmer errors (not input errors). Replaceable; the
/// default prints and aborts.
typedef void (*eo_assert_fn)(const char *expr, const char *file, int line);
EO_API void eo_set_assert_handler(eo_assert_fn fn);
EO_API void eo_assert_fail(const char *expr, const char *file, int line);
#define EO_ASSERT(c) ((c) ? (void)0 : eo_assert_fail(#c, __FILE__, __LINE__))

/// Propagate a negative status: `EO_TRY(rc = f(...));` jumps to `fail` on error.
#define EO_TRY(expr)                                                             \
    do {                                                                         \
        if ((expr) < 0) goto fail;                                               \
    } while (0)

/// Monotonic wall clock in seconds.
EO_API double eo_wtime(void);
/// CPU time of the calling thread in seconds (CLOCK_THREAD_CPUTIME_ID): what the
/// library's cpu timers (eo_solve_result.cpu_time, eo_profile c_*) measure. It does not
/// move while the thread waits for the processor, so it stays put on a loaded machine
/// where wall time does not; it misses work done by other threads (OpenMP element loops,
/// a multithreaded BLAS): use eo_cputime_process then.
EO_API double eo_cputime(void);
/// CPU time of the whole process in seconds, every thread added up
/// (CLOCK_PROCESS_CPUTIME_ID): the work measure when OpenMP or BLAS threads compute.
EO_API double eo_cputime_process(void);

#ifdef __cplusplus
}
#endif
#endif
