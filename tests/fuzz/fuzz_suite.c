/* libFuzzer target over the benchmark suite loader (bench.h, eo_bench_suite_load): the
 * input is a suite JSON document, written to a file in the working folder and loaded
 * (scenes expanded with their `vary` products and loaded, configurations resolved,
 * `select`, `horizon`, `trajectory_start`, `iter_budgets`, `optional` checked), then the
 * accessors are read and the suite destroyed. Nothing is run (a run is minutes long).
 * Aborts on a failure without a message, on an error code outside the status range, on
 * a suite that loads with no scene or no configuration, and (ASan) on any memory error
 * or leak. Run it in an empty folder. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "elastopt/ctx.h"
#include "elastopt/status.h"

static void check(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_suite: %s\n", what);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0 || size > 16384 || memchr(data, 0, size)) return 0;
    FILE *f = fopen("suite.json", "wb");
    if (!f) return 0;
    fwrite(data, 1, size, f);
    fclose(f);
    eo_ctx *ctx = NULL;
    if (eo_ctx_create(NULL, &ctx) < 0) return 0;
    eo_bench_suite *s = NULL;
    int rc = eo_bench_suite_load(ctx, "suite.json", &s);
    if (rc < 0) {
        check(rc >= EO_ERR_INTERNAL, "error code outside the status range");
        check(eo_ctx_message(ctx) && eo_ctx_message(ctx)[0], "failure without a message");
        check(s == NULL, "a suite returned with an error");
    } else {
        check(s && eo_bench_suite_nscenes(s) > 0 && eo_bench_suite_nconfigs(s) > 0, "an empty suite loaded");
        for (int i = 0; i < eo_bench_suite_nscenes(s); i++) check(eo_bench_suite_scene_name(s, i)[0], "unnamed scene");
        for (int i = 0; i < eo_bench_suite_nconfigs(s); i++)
            check(eo_bench_suite_config_name(s, i)[0], "unnamed configuration");
        for (int i = 0; i < eo_bench_suite_nskipped(s); i++) check(eo_bench_suite_skipped(s, i) != NULL, "skipped");
        check(eo_bench_suite_opts(s)->baseline[0], "no baseline");
    }
    eo_bench_suite_destroy(&s);
    eo_ctx_destroy(&ctx);
    return 0;
}
