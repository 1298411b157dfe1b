/* libFuzzer target over the scene path of `elastopt run` (issue 14, item 6): the input is
 * a scene JSON document, optionally followed by a line "--" and one `-o key=value`
 * override per line. It goes through exactly what `run` does (eo_cfg_load of the text,
 * eo_cfg_override for each line, eo_scene_load to check the size, eo_sim_create with its
 * eo_cfg_finish), then up to three steps of the simulation with a small iteration cap.
 * Scenes larger than FUZZ_MAX_VERTS vertices or tets stop after loading (the fuzzer
 * looks for wrong handling of input, not for slow big scenes).
 * Aborts on a failure without a message, on an error code outside the status range, on
 * a step that returns success with a non-finite state, and (ASan) on any memory error or
 * leak. Paths in the document are read as given: run it in an empty folder. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/config.h"
#include "elastopt/ctx.h"
#include "elastopt/mesh.h"
#include "elastopt/scene.h"
#include "elastopt/sim.h"
#include "elastopt/status.h"

enum { FUZZ_MAX_VERTS = 300, FUZZ_MAX_OVERRIDES = 16, FUZZ_STEPS = 3 };

static void check(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_scene: %s\n", what);
        abort();
    }
}

static void check_error(eo_ctx *ctx, int rc)
{
    check(rc >= EO_ERR_INTERNAL, "error code outside the status range");
    const char *m = eo_ctx_message(ctx);
    check(m && m[0], "failure without a message");
}

/* One BLAS thread: OpenBLAS's worker threads spin in sched_yield under the sanitizers
 * and turned small factorizations into libFuzzer timeouts (weak: other BLAS builds). */
extern void openblas_set_num_threads(int) __attribute__((weak));
int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    if (openblas_set_num_threads) openblas_set_num_threads(1);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0 || size > 65536) return 0;
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = 0;
    if (strlen(text) != size) { /* an embedded NUL: the JSON text ends there anyway */
        free(text);
        return 0;
    }
    const char *ov[FUZZ_MAX_OVERRIDES];
    int nov = 0;
    char *sep = strstr(text, "\n--\n");
    if (sep) {
        *sep = 0;
        for (char *line = sep + 4, *nl; line && *line && nov < FUZZ_MAX_OVERRIDES; line = nl) {
            nl = strchr(line, '\n');
            if (nl) *nl++ = 0;
            if (*line) ov[nov++] = line;
        }
    }
    eo_ctx *ctx = NULL;
    if (eo_ctx_create(NULL, &ctx) < 0) {
        free(text);
        return 0;
    }
    eo_cfg *cfg = NULL;
    int rc = eo_cfg_load(ctx, NULL, text, &cfg);
    for (int k = 0; rc >= 0 && k < nov; k++) rc = eo_cfg_override(ctx, cfg, ov[k]);
    if (rc < 0) {
        check_error(ctx, rc);
        goto done;
    }
    /* the size check on a separate load of the same document (eo_scene_load consumes
     * the keys it reads; eo_sim_create below loads it again from scratch) */
    {
        eo_cfg *probe = NULL;
        rc = eo_cfg_load(ctx, NULL, text, &probe);
        for (int k = 0; rc >= 0 && k < nov; k++) rc = eo_cfg_override(ctx, probe, ov[k]);
        eo_scene *sc = NULL;
        if (rc >= 0) rc = eo_scene_load(ctx, probe, &sc);
        int big = rc >= 0 && (sc->mesh->nv > FUZZ_MAX_VERTS ||
                              sc->mesh->nt > 4 * FUZZ_MAX_VERTS || sc->time.steps > 100000);
        eo_scene_destroy(&sc);
        eo_cfg_destroy(&probe);
        if (rc < 0) check_error(ctx, rc);
        if (rc < 0 || big) goto done;
    }
    rc = eo_cfg_override(ctx, cfg, "solver.max_iters=30");
    check(rc >= 0, "solver.max_iters override rejected");
    eo_sim *sim = NULL;
    rc = eo_sim_create(ctx, cfg, &sim);
    cfg = NULL; /* taken over by the sim, or destroyed on failure */
    if (rc < 0) {
        check_error(ctx, rc);
        goto done;
    }
    for (int k = 0; k < FUZZ_STEPS; k++) {
        eo_sim_step_result r;
        rc = eo_sim_step(sim, &r);
        if (rc < 0) {
            check_error(ctx, rc);
            break;
        }
        if (r.reason == EO_DIVERGED_NONFINITE) break;
        size_t n = 3 * (size_t)eo_sim_scene(sim)->mesh->nv;
        double *x = malloc(n * sizeof *x);
        if (!x) break;
        double t;
        int index;
        eo_sim_get_state(sim, x, NULL, &t, &index);
        for (size_t i = 0; i < n; i++) check(isfinite(x[i]), "a finite step left a non-finite position");
        check(isfinite(t), "non-finite time");
        free(x);
    }
    eo_sim_destroy(&sim);
done:
    eo_cfg_destroy(&cfg);
    eo_ctx_destroy(&ctx);
    free(text);
    return 0;
}
