#include "testutil.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int eo_test_passed, eo_test_failed;

eo_ctx *eo_test_ctx(void)
{
    eo_ctx *ctx = NULL;
    if (eo_ctx_create(NULL, &ctx) < 0) {
        fprintf(stderr, "cannot create context\n");
        exit(1);
    }
    if (getenv("EO_TEST_VERBOSE")) eo_ctx_set_logger(ctx, eo_log_stderr, NULL, EO_LOG_DEBUG);
    return ctx;
}

void eo_test_ctx_done(eo_ctx **ctx)
{
    CHECK(eo_ctx_live_bytes(*ctx) == 0, "%zu bytes still allocated", eo_ctx_live_bytes(*ctx));
    eo_ctx_destroy(ctx);
}

int eo_test_finish(const char *name)
{
    printf("%s: %d passed, %d failed\n", name, eo_test_passed, eo_test_failed);
    return eo_test_failed ? 1 : 0;
}

static unsigned long long rng_state = 0x9E3779B97F4A7C15ULL;
void eo_test_seed(unsigned long long s) { rng_state = s ? s : 0x9E3779B97F4A7C15ULL; }
double eo_test_rand(double a, double b)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return a + (b - a) * (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static char pathbuf[4096];
const char *eo_test_src_path(const char *rel)
{
    const char *root = getenv("EO_SOURCE_ROOT");
    snprintf(pathbuf, sizeof pathbuf, "%s/%s", root ? root : ".", rel);
    return pathbuf;
}
const char *eo_test_shared_path(const char *rel)
{
    const char *root = getenv("EO_SHARED");
    snprintf(pathbuf, sizeof pathbuf, "%s/%s", root ? root : "../shared", rel);
    return pathbuf;
}
const char *eo_test_tmpdir(const char *name)
{
    const char *b = getenv("EO_BUILD_ROOT");
    static char dir[4096];
    snprintf(dir, sizeof dir, "%s/testtmp/%s", b ? b : "/tmp", name);
    char cmd[8400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", dir, dir);
    if (system(cmd) != 0) fprintf(stderr, "cannot make %s\n", dir);
    return dir;
}
