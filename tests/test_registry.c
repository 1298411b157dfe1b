/* Run-time registration (registry.h, issue 9): a method of every kind registered from
 * "outside" (tables defined here, copies of built-ins under new names) is found by name,
 * accepted in configs (its parameter section solver.<name> loaded and range-checked),
 * listed, and gives the same numbers as the built-in it copies; bad tables (bad name,
 * duplicate, missing ops) are refused with a message; eo_unregister restores the
 * registry. Also the config hygiene of -o: empty dotted components and invalid UTF-8
 * are errors (eo_utf8_invalid_at on valid and invalid sequences). */
#include <jansson.h>
#include <math.h>
#include <string.h>

#include "elastopt/sim.h"
#include "elastopt/config.h"
#include "elastopt/linsolve.h"
#include "elastopt/material.h"
#include "elastopt/registry.h"
#include "elastopt/scene.h"
#include "elastopt/impl/method.h"
#include "elastopt/step.h"
#include "testutil.h"

static int count(eo_kind k)
{
    int n = 0;
    for (const void *const *t = eo_registry_list(k); t && *t; t++) n++;
    return n;
}

static int listed(eo_kind k, const char *name)
{
    char buf[2048];
    eo_registry_names(k, buf, sizeof buf);
    return strstr(buf, name) != NULL;
}

/* A copy of a built-in table under a new name: same ops, so same numbers. */
static eo_optimizer_type opt_copy;
static eo_linsolve_type ls_copy;
static eo_material_type mat_copy;
static eo_linesearch_type lsr_copy;
static eo_stop_type stop_copy;
static eo_hessfix_type fix_copy;
static eo_integrator_type integ_copy;
static eo_scene_type scene_copy;

static void test_register_every_kind(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const void *t;
    struct {
        eo_kind kind;
        const char *builtin, *name;
        void *copy;
        size_t size;
    } k[] = {
        {EO_KIND_OPTIMIZER, "newton", "newton_ext", &opt_copy, sizeof opt_copy},
        {EO_KIND_LINSOLVE, "cholmod", "cholmod_ext", &ls_copy, sizeof ls_copy},
        {EO_KIND_MATERIAL, "stvk", "stvk_ext", &mat_copy, sizeof mat_copy},
        {EO_KIND_LINESEARCH, "backtracking", "backtracking_ext", &lsr_copy, sizeof lsr_copy},
        {EO_KIND_STOP, "newton_decrement", "decrement_ext", &stop_copy, sizeof stop_copy},
        {EO_KIND_HESSFIX, "clamp", "clamp_ext", &fix_copy, sizeof fix_copy},
        {EO_KIND_INTEGRATOR, "newmark", "newmark_ext", &integ_copy, sizeof integ_copy},
        {EO_KIND_SCENE, "cantilever", "cantilever_ext", &scene_copy, sizeof scene_copy},
    };
    int n0[8];
    for (int i = 0; i < 8; i++) {
        n0[i] = count(k[i].kind);
        CHECK(eo_registry_find(ctx, k[i].kind, k[i].builtin, &t) == EO_OK, "built-in %s", k[i].builtin);
        memcpy(k[i].copy, t, k[i].size);
        ((eo_method_info *)k[i].copy)->name = k[i].name;
        CHECK(eo_registry_find(ctx, k[i].kind, k[i].name, &t) == EO_ERR_UNKNOWN_NAME, "%s not there yet", k[i].name);
        CHECK(eo_register(ctx, k[i].kind, k[i].copy) == EO_OK, "register %s: %s", k[i].name, eo_ctx_message(ctx));
        CHECK(eo_registry_find(ctx, k[i].kind, k[i].name, &t) == EO_OK && t == k[i].copy, "find %s", k[i].name);
        CHECK(count(k[i].kind) == n0[i] + 1 && listed(k[i].kind, k[i].name), "%s listed", k[i].name);
        /* the same table or the same name again: refused, registry unchanged */
        CHECK(eo_register(ctx, k[i].kind, k[i].copy) == EO_ERR_INVALID &&
                  strstr(eo_ctx_message(ctx), "already registered"),
              "duplicate %s: %s", k[i].name, eo_ctx_message(ctx));
        CHECK(count(k[i].kind) == n0[i] + 1, "count after duplicate");
    }

    /* the registered optimizer and material in a config: parameter section accepted and
     * checked, same numbers as the built-ins on the cantilever's first step */
    double g[2] = {NAN, NAN};
    for (int v = 0; v < 2; v++) {
        eo_cfg *cfg = NULL;
        eo_sim *sim = NULL;
        int rc = eo_scene_cfg_load(ctx, NULL, v ? "cantilever_ext" : "cantilever", &cfg);
        const char *ov[] = {v ? "solver.optimizer=newton_ext" : "solver.optimizer=newton",
                            v ? "material.model=stvk_ext" : "material.model=stvk",
                            v ? "solver.newton_ext.descent_eps=1e-12" : "solver.newton.descent_eps=1e-12",
                            v ? "solver.linear=cholmod_ext" : "solver.linear=cholmod",
                            v ? "solver.linesearch=backtracking_ext" : "solver.linesearch=backtracking",
                            v ? "solver.stop=decrement_ext" : "solver.stop=newton_decrement",
                            v ? "solver.hessian_fix=clamp_ext" : "solver.hessian_fix=clamp",
                            v ? "time.integrator=newmark_ext" : "time.integrator=newmark",
                            "mesh.generate.cells=[6,2,2]"};
        for (size_t i = 0; rc >= 0 && i < sizeof ov / sizeof ov[0]; i++) rc = eo_cfg_override(ctx, cfg, ov[i]);
        if (rc >= 0) {
            rc = eo_sim_create(ctx, cfg, &sim); /* takes cfg over */
            cfg = NULL;
        }
        eo_sim_step_result r = {0};
        if (rc >= 0) rc = eo_sim_step(sim, &r);
        CHECK(rc == EO_OK && r.reason > 0, "variant %d: rc %d %s", v, rc, eo_ctx_message(ctx));
        if (rc == EO_OK) g[v] = r.g;
        eo_sim_destroy(&sim);
        eo_cfg_destroy(&cfg);
    }
    CHECK(g[0] == g[1], "registered copies give the built-ins' minimum: %.17g vs %.17g", g[0], g[1]);

    /* a registered method's parameter range is checked like a built-in's */
    {
        eo_cfg *cfg = NULL;
        eo_solver *s = NULL;
        eo_solver_opts so;
        eo_solver_opts_default(&so);
        int rc = eo_cfg_create_empty(ctx, &cfg);
        if (rc >= 0) rc = eo_cfg_override(ctx, cfg, "solver.newton_ext.descent_eps=2");
        if (rc >= 0) rc = eo_solver_opts_load(ctx, cfg, &so);
        if (rc >= 0) rc = eo_solver_create(ctx, &so, cfg, &s);
        CHECK(rc == EO_ERR_RANGE && strstr(eo_ctx_message(ctx), "descent_eps"), "range of a plug-in key: %d %s", rc,
              eo_ctx_message(ctx));
        eo_solver_destroy(&s);
        eo_cfg_destroy(&cfg);
    }

    for (int i = 0; i < 8; i++) {
        CHECK(eo_unregister(k[i].kind, k[i].copy) == EO_OK, "unregister %s", k[i].name);
        CHECK(count(k[i].kind) == n0[i] && !listed(k[i].kind, k[i].name), "%s gone", k[i].name);
        CHECK(eo_unregister(k[i].kind, k[i].copy) == EO_ERR_INVALID, "second unregister refused");
    }
    /* built-ins cannot be removed */
    CHECK(eo_registry_find(ctx, EO_KIND_OPTIMIZER, "newton", &t) == EO_OK && eo_unregister(EO_KIND_OPTIMIZER, t) < 0,
          "built-in removal refused");
    eo_test_ctx_done(&ctx);
}

static int dummy_setup(void *st, const void *p, int n, eo_ctx *ctx)
{
    (void)st, (void)p, (void)n, (void)ctx;
    return 0;
}

static void test_bad_tables(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static eo_optimizer_type no_min = {.info = {.name = "no_minimize", .summary = "x"}, .setup = dummy_setup};
    CHECK(eo_register(ctx, EO_KIND_OPTIMIZER, &no_min) == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "minimize"),
          "missing op: %s", eo_ctx_message(ctx));
    static eo_optimizer_type bad_name = {.info = {.name = "bad name!", .summary = "x"}};
    CHECK(eo_register(ctx, EO_KIND_OPTIMIZER, &bad_name) == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "name"),
          "bad name: %s", eo_ctx_message(ctx));
    static eo_optimizer_type no_summary = {.info = {.name = "no_summary"}};
    CHECK(eo_register(ctx, EO_KIND_OPTIMIZER, &no_summary) == EO_ERR_INVALID, "no summary");
    static eo_linsolve_type ls = {.info = {.name = "half_solver", .summary = "x"}};
    CHECK(eo_register(ctx, EO_KIND_LINSOLVE, &ls) == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "analyze"),
          "linsolve without ops: %s", eo_ctx_message(ctx));
    static eo_material_type mt = {.info = {.name = "formless", .summary = "x"}};
    CHECK(eo_register(ctx, EO_KIND_MATERIAL, &mt) == EO_ERR_INVALID, "material without an evaluation form");
    static eo_scene_type sc = {.info = {.name = "empty_scene", .summary = "x"}};
    CHECK(eo_register(ctx, EO_KIND_SCENE, &sc) == EO_ERR_INVALID, "scene without json");
    CHECK(eo_register(ctx, (eo_kind)99, &sc) == EO_ERR_INVALID, "bad kind");
    CHECK(eo_registry_of((eo_kind)99) == NULL && eo_registry_list((eo_kind)99) == NULL, "no registry for bad kind");
    eo_test_ctx_done(&ctx);
}

static void test_override_hygiene(void)
{
    eo_ctx *ctx = eo_test_ctx();
    CHECK(eo_utf8_invalid_at("plain ascii") == -1, "ascii");
    CHECK(eo_utf8_invalid_at("\xc3\xa9t\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80") == -1, "valid multibyte");
    CHECK(eo_utf8_invalid_at("ab\xff") == 2, "0xff at 2");
    CHECK(eo_utf8_invalid_at("\xc0\x80") == 0, "overlong NUL");
    CHECK(eo_utf8_invalid_at("x\xed\xa0\x80") == 1, "surrogate");
    CHECK(eo_utf8_invalid_at("\xe2\x82") == 0, "truncated sequence");
    CHECK(eo_utf8_invalid_at("\xf4\x90\x80\x80") == 0, "beyond U+10FFFF");
    const char *bad[] = {"time..dt=0.5", "time.dt.=0.5", ".time.dt=0.5", "time.d\xfft=1", "time.dt=\"\xc3\"",
                         "=1", "time.dt"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        eo_cfg *cfg = NULL;
        CHECK(eo_cfg_create_empty(ctx, &cfg) == EO_OK, "empty cfg");
        int rc = eo_cfg_override(ctx, cfg, bad[i]);
        CHECK(rc == EO_ERR_INVALID, "override %zu refused (rc %d)", i, rc);
        json_t *time = json_object_get(eo_cfg_root(cfg), "time");
        CHECK(!time || !json_object_get(time, "dt"), "override %zu left nothing behind", i);
        eo_cfg_destroy(&cfg);
    }
    eo_cfg *cfg = NULL;
    CHECK(eo_cfg_create_empty(ctx, &cfg) == EO_OK, "cfg");
    CHECK(eo_cfg_override(ctx, cfg, "time.dt=0.5") == EO_OK, "good override");
    CHECK(json_real_value(json_object_get(json_object_get(eo_cfg_root(cfg), "time"), "dt")) == 0.5, "dt set");
    CHECK(eo_cfg_override(ctx, cfg, "description=\xc3\xa9t\xc3\xa9") == EO_OK, "UTF-8 value accepted");
    eo_cfg_destroy(&cfg);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_register_every_kind();
    test_bad_tables();
    test_override_hygiene();
    return eo_test_finish("test_registry");
}
