/* The context: counted allocation, logging, last error with location.
 *
 * Every block carries a small header holding its size so eo_free can keep the
 * live-byte count exact with any allocator. */
#include "elastopt/ctx.h"

#include "elastopt/mesh.h"
#include "mesh/mesh_io.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define EO_MSG_MAX 1024

struct eo_ctx {
    eo_allocator alloc;
    size_t live;
    long fail_after; /* 0 = off; else countdown to an injected failure */
    eo_log_fn log_fn;
    void *log_user;
    eo_log_level log_level;
    int last_status;
    char message[EO_MSG_MAX];
    eo_mesh_source_fn mesh_source; /* eo_mesh_read's replacement (NULL: read the file) */
    void *mesh_source_user;
    int quiet_warnings; /* eo_ctx_set_quiet_warnings */
    eo_dist_hooks dist;  /* eo_ctx_set_dist (nparts 0: none) */
};

/* header keeps max alignment */
typedef union eo_blk {
    size_t size;
    max_align_t align;
} eo_blk;

static void *raw_malloc(const eo_allocator *a, size_t n)
{
    return a->malloc_fn ? a->malloc_fn(n, a->user) : malloc(n);
}
static void *raw_realloc(const eo_allocator *a, void *p, size_t n)
{
    return a->realloc_fn ? a->realloc_fn(p, n, a->user) : realloc(p, n);
}
static void raw_free(const eo_allocator *a, void *p)
{
    if (a->free_fn) a->free_fn(p, a->user);
    else free(p);
}

int eo_ctx_create(const eo_allocator *alloc, eo_ctx **out)
{
    eo_allocator a = {0};
    if (alloc) a = *alloc;
    *out = NULL;
    eo_ctx *c = raw_malloc(&a, sizeof *c);
    if (!c) return EO_ERR_NOMEM;
    memset(c, 0, sizeof *c);
    c->alloc = a;
    c->log_level = EO_LOG_INFO;
    *out = c;
    return EO_OK;
}

void eo_ctx_destroy(eo_ctx **ctx)
{
    if (!ctx || !*ctx) return;
    eo_allocator a = (*ctx)->alloc;
    raw_free(&a, *ctx);
    *ctx = NULL;
}

void eo_ctx_set_mesh_source(eo_ctx *ctx, eo_mesh_source_fn fn, void *user)
{
    ctx->mesh_source = fn;
    ctx->mesh_source_user = fn ? user : NULL;
}

eo_mesh_source_fn eo_ctx_mesh_source(const eo_ctx *ctx, void **user)
{
    *user = ctx->mesh_source_user;
    return ctx->mesh_source;
}

void eo_ctx_set_dist(eo_ctx *ctx, const eo_dist_hooks *h)
{
    if (h) ctx->dist = *h;
    else memset(&ctx->dist, 0, sizeof ctx->dist);
}

const eo_dist_hooks *eo_ctx_dist(const eo_ctx *ctx) { return ctx && ctx->dist.nparts > 1 ? &ctx->dist : NULL; }

int eo_ctx_reduce(eo_ctx *ctx, double *v, int n, eo_reduce_op op)
{
    const eo_dist_hooks *h = eo_ctx_dist(ctx);
    if (!h || !h->reduce || n <= 0) return 0;
    return h->reduce(v, n, op, h->user);
}

void eo_ctx_set_logger(eo_ctx *ctx, eo_log_fn fn, void *user, eo_log_level level)
{
    ctx->log_fn = fn;
    ctx->log_user = user;
    ctx->log_level = level;
}

void eo_log_stderr(eo_log_level level, const char *msg, void *user)
{
    static const char *const names[] = {"error", "warning", "info", "debug"};
    (void)user;
    fprintf(stderr, "%s: %s\n", names[level], msg);
}

void eo_log(eo_ctx *ctx, eo_log_level level, const char *fmt, ...)
{
    if (!ctx || !ctx->log_fn || level > ctx->log_level) return;
    char buf[EO_MSG_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    ctx->log_fn(level, buf, ctx->log_user);
}

static int inject_failure(eo_ctx *ctx)
{
    if (ctx->fail_after <= 0) return 0;
    if (--ctx->fail_after == 0) return 1;
    return 0;
}

void *eo_malloc(eo_ctx *ctx, size_t size)
{
    if (size > SIZE_MAX - sizeof(eo_blk)) return NULL;
    if (inject_failure(ctx)) return NULL;
    eo_blk *b = raw_malloc(&ctx->alloc, sizeof(eo_blk) + size);
    if (!b) return NULL;
    b->size = size;
    ctx->live += size;
    return b + 1;
}

void *eo_calloc(eo_ctx *ctx, size_t n, size_t size)
{
    if (size && n > SIZE_MAX / size) return NULL;
    void *p = eo_malloc(ctx, n * size);
    if (p) memset(p, 0, n * size);
    return p;
}

void *eo_realloc(eo_ctx *ctx, void *p, size_t size)
{
    if (!p) return eo_malloc(ctx, size);
    if (size > SIZE_MAX - sizeof(eo_blk)) return NULL;
    if (inject_failure(ctx)) return NULL;
    eo_blk *b = (eo_blk *)p - 1;
    size_t old = b->size;
    eo_blk *nb = raw_realloc(&ctx->alloc, b, sizeof(eo_blk) + size);
    if (!nb) return NULL;
    nb->size = size;
    ctx->live = ctx->live - old + size;
    return nb + 1;
}

void eo_free(eo_ctx *ctx, void *p)
{
    if (!p) return;
    eo_blk *b = (eo_blk *)p - 1;
    ctx->live -= b->size;
    raw_free(&ctx->alloc, b);
}

char *eo_strdup(eo_ctx *ctx, const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = eo_malloc(ctx, n);
    if (d) memcpy(d, s, n);
    return d;
}

size_t eo_ctx_live_bytes(const eo_ctx *ctx) { return ctx->live; }

void eo_ctx_fail_after(eo_ctx *ctx, long n) { ctx->fail_after = n; }

int eo_error_atv(eo_ctx *ctx, int status, eo_errloc loc, const char *fmt, va_list ap)
{
    if (!ctx) return status;
    size_t n = 0, cap = sizeof ctx->message;
    char *m = ctx->message;
    if (loc.file) {
        n += (size_t)snprintf(m + n, cap - n, "%s", loc.file);
        if (n < cap && loc.line > 0) n += (size_t)snprintf(m + n, cap - n, ":%ld", loc.line);
        if (n < cap && loc.line > 0 && loc.column > 0)
            n += (size_t)snprintf(m + n, cap - n, ":%ld", loc.column);
        if (n < cap) n += (size_t)snprintf(m + n, cap - n, ": ");
    }
    if (n < cap && loc.index >= 0)
        n += (size_t)snprintf(m + n, cap - n, "%s %ld: ", loc.kind ? loc.kind : "item", loc.index);
    if (n < cap) vsnprintf(m + n, cap - n, fmt, ap);
    ctx->last_status = status;
    if (status > 0 && ctx->quiet_warnings) return status;
    eo_log(ctx, status < 0 ? EO_LOG_DEBUG : EO_LOG_WARN, "%s", ctx->message);
    return status;
}

int eo_error_at(eo_ctx *ctx, int status, eo_errloc loc, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    eo_error_atv(ctx, status, loc, fmt, ap);
    va_end(ap);
    return status;
}

int eo_ctx_set_quiet_warnings(eo_ctx *ctx, int on)
{
    int old = ctx->quiet_warnings;
    ctx->quiet_warnings = on != 0;
    return old;
}

int eo_ctx_get_quiet_warnings(const eo_ctx *ctx) { return ctx->quiet_warnings; }

const char *eo_ctx_message(const eo_ctx *ctx) { return ctx->message; }
int eo_ctx_status(const eo_ctx *ctx) { return ctx->last_status; }
void eo_ctx_clear_error(eo_ctx *ctx)
{
    ctx->message[0] = 0;
    ctx->last_status = 0;
}

static void default_assert(const char *expr, const char *file, int line)
{
    fprintf(stderr, "elastopt: assertion failed: %s (%s:%d)\n", expr, file, line);
    abort();
}
static eo_assert_fn assert_handler = default_assert;
void eo_set_assert_handler(eo_assert_fn fn) { assert_handler = fn ? fn : default_assert; }
void eo_assert_fail(const char *expr, const char *file, int line) { assert_handler(expr, file, line); }

double eo_wtime(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double eo_cputime(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return (double)clock() / CLOCKS_PER_SEC;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double eo_cputime_process(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return (double)clock() / CLOCKS_PER_SEC;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
