/* Minimal test harness: CHECK macros count passes and failures; eo_test_finish prints
 * "N passed, N failed" and returns the exit code (0 only if nothing failed). */
#ifndef EO_TESTUTIL_H
#define EO_TESTUTIL_H

#include <math.h>
#include <stdio.h>

#include "elastopt/ctx.h"

extern int eo_test_passed, eo_test_failed;

#define CHECK(cond, ...)                                                         \
    do {                                                                         \
        if (cond) {                                                              \
            eo_test_passed++;                                                    \
        } else {                                                                 \
            eo_test_failed++;                                                    \
            fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #cond);      \
            fprintf(stderr, __VA_ARGS__);                                        \
            fprintf(stderr, "\n");                                               \
        }                                                                        \
    } while (0)

/* |a - b| <= tol * max(1, |b|) */
#define CHECK_CLOSE(a, b, tol)                                                   \
    do {                                                                         \
        double eo_a_ = (a), eo_b_ = (b);                                         \
        double eo_s_ = fabs(eo_b_) > 1 ? fabs(eo_b_) : 1;                        \
        CHECK(fabs(eo_a_ - eo_b_) <= (tol)*eo_s_, "%s = %.17g, expected %.17g (tol %g)", #a, \
              eo_a_, eo_b_, (double)(tol));                                      \
    } while (0)

/* Fresh context with a logger that stays quiet unless EO_TEST_VERBOSE is set. */
eo_ctx *eo_test_ctx(void);
/* Check the context has no live bytes left, destroy it. */
void eo_test_ctx_done(eo_ctx **ctx);
/* Print the summary line and return the process exit code. */
int eo_test_finish(const char *name);
/* Deterministic uniform random in [a, b) (xorshift), seedable. */
void eo_test_seed(unsigned long long s);
double eo_test_rand(double a, double b);
/* Path under the source tree / shared folder (static buffer, valid until next call). */
const char *eo_test_src_path(const char *rel);
const char *eo_test_shared_path(const char *rel);
/* A fresh empty temporary folder for this test (static buffer). */
const char *eo_test_tmpdir(const char *name);

#endif
