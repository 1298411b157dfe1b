/* Core library: status/reason strings, counted allocation and failure injection,
 * descriptor-driven params (defaults, load, types, ranges, names, echo), config
 * documents with -o overrides and unknown-key detection with file:line. */
#include <jansson.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/config.h"
#include "elastopt/io.h"
#include "elastopt/registry.h"
#include "elastopt/sim.h"
#include "elastopt/status.h"
#include "testutil.h"

typedef struct {
    int max_iters;
    double c1;
    int verbose;
    char mode[16];
    double g[3];
} demo_params;

static const char *const modes[] = {"fast", "safe", NULL};
static const eo_param_desc demo_desc[] = {
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(demo_params, max_iters), .def.i = 50,
     .min = 1, .range = EO_RANGE_MIN, .help = "iteration cap"},
    {.key = "c1", .kind = EO_PARAM_DOUBLE, .offset = offsetof(demo_params, c1), .def.d = 1e-4, .min = 0,
     .max = 1, .range = EO_RANGE_OPEN, .help = "Armijo constant"},
    {.key = "verbose", .kind = EO_PARAM_BOOL, .offset = offsetof(demo_params, verbose), .def.i = 0,
     .help = "talk"},
    {.key = "mode", .kind = EO_PARAM_CHOICE, .offset = offsetof(demo_params, mode),
     .size = sizeof(((demo_params *)0)->mode), .def.s = "safe", .choices = modes, .help = "mode"},
    {.key = "g", .kind = EO_PARAM_VEC3, .offset = offsetof(demo_params, g), .def.v = {0, 0, -9.81},
     .help = "gravity"},
    {0},
};

static void test_status(void)
{
    CHECK(strcmp(eo_status_string(EO_ERR_PARSE), "malformed input") == 0, "parse string");
    CHECK(strcmp(eo_status_name(EO_WARN_NOT_PD), "EO_WARN_NOT_PD") == 0, "name");
    CHECK(EO_WARN_NOT_PD > 0 && EO_ERR_NOMEM < 0, "signs");
    CHECK(strcmp(eo_reason_name(EO_CONVERGED_DECREMENT), "converged_decrement") == 0, "%s",
          eo_reason_name(EO_CONVERGED_DECREMENT));
    CHECK(strcmp(eo_reason_name(EO_DIVERGED_MAX_ITERS), "diverged_max_iters") == 0, "%s",
          eo_reason_name(EO_DIVERGED_MAX_ITERS));
    CHECK(strcmp(eo_reason_name(EO_REASON_ITERATING), "iterating") == 0, "%s", eo_reason_name(0));
    CHECK(eo_reason_is_converged(EO_CONVERGED_GRADIENT) && !eo_reason_is_converged(EO_DIVERGED_NONFINITE), "sign");
    /* an explicit step: its own name, not a failure, not a convergence */
    CHECK(strcmp(eo_reason_name(EO_REASON_EXPLICIT), "explicit") == 0, "%s", eo_reason_name(EO_REASON_EXPLICIT));
    CHECK(eo_reason_is_converged(EO_REASON_EXPLICIT) && eo_reason_is_explicit(EO_REASON_EXPLICIT) &&
              !eo_reason_is_explicit(EO_CONVERGED_STEP) && !eo_reason_is_explicit(EO_DIVERGED_MAX_ITERS),
          "explicit: positive (no failure), told apart");
    CHECK(EO_CONVERGED_EXPLICIT == EO_REASON_EXPLICIT, "former name kept");
}

static void test_ctx(void)
{
    eo_ctx *ctx = eo_test_ctx();
    void *a = eo_malloc(ctx, 100);
    CHECK(eo_ctx_live_bytes(ctx) == 100, "live %zu", eo_ctx_live_bytes(ctx));
    a = eo_realloc(ctx, a, 300);
    CHECK(eo_ctx_live_bytes(ctx) == 300, "live %zu", eo_ctx_live_bytes(ctx));
    eo_free(ctx, a);
    eo_ctx_fail_after(ctx, 2);
    void *b = eo_malloc(ctx, 8);
    void *c = eo_malloc(ctx, 8);
    CHECK(b != NULL && c == NULL, "second allocation must fail");
    eo_free(ctx, b);
    int rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_ITEM("a.ele", 7, "tet", 3), "zero volume");
    CHECK(rc == EO_ERR_MESH, "returns status");
    CHECK(strcmp(eo_ctx_message(ctx), "a.ele:7: tet 3: zero volume") == 0, "message '%s'", eo_ctx_message(ctx));
    eo_test_ctx_done(&ctx);
}

static void test_params(void)
{
    eo_ctx *ctx = eo_test_ctx();
    demo_params p;
    eo_params_default(demo_desc, &p);
    CHECK(p.max_iters == 50 && p.c1 == 1e-4 && !p.verbose && strcmp(p.mode, "safe") == 0 && p.g[2] == -9.81,
          "defaults");
    eo_param_src src = {"x.json", "{\n  \"s\": {\n    \"c1\": 2\n  }\n}\n", "s", NULL};
    json_t *sec = json_loads("{\"max_iters\": 7, \"c1\": 0.5, \"verbose\": true, \"mode\": \"fast\", \"g\": [1,2,3]}", 0, NULL);
    CHECK(eo_params_load(ctx, demo_desc, &p, sec, NULL, &src) == EO_OK, "load: %s", eo_ctx_message(ctx));
    CHECK(p.max_iters == 7 && p.c1 == 0.5 && p.verbose && strcmp(p.mode, "fast") == 0 && p.g[1] == 2, "loaded");
    json_decref(sec);

    /* rejected sections: status, and what the message must name */
    static const struct {
        const char *what, *json;
        int status;
        const char *msg[2]; /* substrings of the message (NULL: not checked) */
    } bad[] = {
        {"out of range, with the file line of the key", "{\"c1\": 2}", EO_ERR_RANGE, {"x.json:3:5", "s.c1"}},
        {"wrong type", "{\"max_iters\": \"ten\"}", EO_ERR_TYPE, {"expected an integer, got string", NULL}},
        {"non-integer for int", "{\"max_iters\": 2.5}", EO_ERR_TYPE, {NULL, NULL}},
        {"unknown key lists the valid keys", "{\"c2\": 1}", EO_ERR_UNKNOWN_KEY, {"max_iters, c1, verbose, mode, g", NULL}},
        {"unknown choice lists the choices", "{\"mode\": \"slow\"}", EO_ERR_UNKNOWN_NAME, {"valid: fast, safe", NULL}},
        {"vec3 wrong length", "{\"g\": [1,2]}", EO_ERR_TYPE, {NULL, NULL}},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sec = json_loads(bad[i].json, 0, NULL);
        int rc = eo_params_load(ctx, demo_desc, &p, sec, NULL, &src);
        CHECK(rc == bad[i].status, "%s: rc %d, expected %d", bad[i].what, rc, bad[i].status);
        for (int m = 0; m < 2; m++)
            if (bad[i].msg[m])
                CHECK(strstr(eo_ctx_message(ctx), bad[i].msg[m]) != NULL, "%s: msg '%s'", bad[i].what,
                      eo_ctx_message(ctx));
        json_decref(sec);
    }
    /* echo round trip */
    json_t *echo = eo_params_to_json(demo_desc, &p);
    demo_params q;
    eo_params_default(demo_desc, &q);
    CHECK(eo_params_load(ctx, demo_desc, &q, echo, NULL, &src) == EO_OK, "reload echo");
    CHECK(p.max_iters == q.max_iters && p.c1 == q.c1 && p.verbose == q.verbose && strcmp(p.mode, q.mode) == 0 &&
              memcmp(p.g, q.g, sizeof p.g) == 0,
          "echo round trip equal");
    json_decref(echo);
    CHECK(eo_params_check(ctx, demo_desc, &p, &src) == EO_OK, "check ok");
    p.c1 = 0;
    CHECK(eo_params_check(ctx, demo_desc, &p, &src) == EO_ERR_RANGE, "open range excludes 0");
    eo_test_ctx_done(&ctx);
}

static void test_locate(void)
{
    const char *t = "{\n \"a\": {\"b\": 1,\n   \"c\": [10, {\"d\": 2}]}\n}";
    long l = 0, c = 0;
    CHECK(eo_json_locate(t, "a.b", &l, &c) == 0 && l == 2 && c == 8, "a.b at %ld:%ld", l, c);
    CHECK(eo_json_locate(t, "a.c.1.d", &l, &c) == 0 && l == 3 && c == 15, "a.c.1.d at %ld:%ld", l, c);
    CHECK(eo_json_locate(t, "a.x", &l, &c) == -1, "absent");
    CHECK(eo_json_locate("{\"a\": [1, 2", "a.5", &l, &c) == -1, "truncated text is safe");
}

static void test_config(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *dir = eo_test_tmpdir("core_config");
    char path[4200];
    snprintf(path, sizeof path, "%s/c.json", dir);
    FILE *f = fopen(path, "w");
    fputs("{\n  \"s\": {\"max_iters\": 9},\n  \"extra\": {\"zzz\": 1}\n}\n", f);
    fclose(f);
    eo_cfg *cfg = NULL;
    CHECK(eo_cfg_load(ctx, path, NULL, &cfg) == EO_OK, "load %s", eo_ctx_message(ctx));
    CHECK(eo_cfg_override(ctx, cfg, "s.c1=0.25") == EO_OK, "override");
    CHECK(eo_cfg_override(ctx, cfg, "s.mode=fast") == EO_OK, "string override");
    CHECK(eo_cfg_override(ctx, cfg, "novalue") == EO_ERR_INVALID, "no '='");
    demo_params p;
    eo_params_default(demo_desc, &p);
    CHECK(eo_cfg_section(ctx, cfg, "s", demo_desc, &p, NULL) == EO_OK, "section %s", eo_ctx_message(ctx));
    CHECK(p.max_iters == 9 && p.c1 == 0.25 && strcmp(p.mode, "fast") == 0, "values %d %g %s", p.max_iters, p.c1, p.mode);
    static const char *const top[] = {"s", NULL};
    eo_cfg_expect(cfg, "", top);
    int rc = eo_cfg_finish(ctx, cfg);
    CHECK(rc == EO_ERR_UNKNOWN_KEY, "unknown top-level key");
    CHECK(strstr(eo_ctx_message(ctx), "c.json:3:3") && strstr(eo_ctx_message(ctx), "'extra'") &&
              strstr(eo_ctx_message(ctx), "valid keys here: s"),
          "msg '%s'", eo_ctx_message(ctx));
    eo_cfg_destroy(&cfg);

    /* overrides that are wrong are attributed to the command line */
    CHECK(eo_cfg_load(ctx, NULL, "{\"s\": {}}", &cfg) == EO_OK, "builtin");
    CHECK(eo_cfg_override(ctx, cfg, "s.max_iters=abc") == EO_OK, "set");
    rc = eo_cfg_section(ctx, cfg, "s", demo_desc, &p, NULL);
    CHECK(rc == EO_ERR_TYPE && strstr(eo_ctx_message(ctx), "command line -o s.max_iters"), "msg '%s'",
          eo_ctx_message(ctx));
    CHECK(eo_cfg_override(ctx, cfg, "s.bogus=1") == EO_OK, "set");
    eo_cfg_consume(cfg, "s.max_iters");
    eo_cfg_expect(cfg, "", top);
    rc = eo_cfg_finish(ctx, cfg);
    CHECK(rc == EO_ERR_UNKNOWN_KEY && strstr(eo_ctx_message(ctx), "-o s.bogus"), "msg '%s'", eo_ctx_message(ctx));
    eo_cfg_destroy(&cfg);

    /* malformed JSON gives line and column */
    f = fopen(path, "w");
    fputs("{\n  \"s\": {\"max_iters\": 9,}\n}\n", f);
    fclose(f);
    rc = eo_cfg_load(ctx, path, NULL, &cfg);
    CHECK(rc == EO_ERR_PARSE && cfg == NULL, "parse error rc %d", rc);
    CHECK(strstr(eo_ctx_message(ctx), "c.json:2:") != NULL, "msg '%s'", eo_ctx_message(ctx));
    /* missing file */
    rc = eo_cfg_load(ctx, "/nonexistent/x.json", NULL, &cfg);
    CHECK(rc == EO_ERR_IO && strstr(eo_ctx_message(ctx), "/nonexistent/x.json"), "msg '%s'", eo_ctx_message(ctx));
    /* failure injection: every allocation failure is reported, nothing leaks */
    for (long n = 1; n < 40; n++) {
        eo_ctx_fail_after(ctx, n);
        rc = eo_cfg_load(ctx, NULL, "{\"s\": {\"c1\": 0.5}}", &cfg);
        eo_ctx_fail_after(ctx, 0);
        if (rc == EO_OK) eo_cfg_destroy(&cfg);
        CHECK(rc == EO_OK || rc == EO_ERR_NOMEM, "rc %d", rc);
        CHECK(eo_ctx_live_bytes(ctx) == 0, "leak after failure %ld", n);
    }
    eo_test_ctx_done(&ctx);
}

static void test_registry(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const void *t = NULL;
    int rc = eo_registry_find(ctx, EO_KIND_LINSOLVE, "no_such_solver", &t);
    CHECK(rc == EO_ERR_UNKNOWN_NAME && t == NULL, "unknown name");
    CHECK(strstr(eo_ctx_message(ctx), "unknown linear solver 'no_such_solver'; valid:") != NULL, "msg '%s'",
          eo_ctx_message(ctx));
    for (int k = 0; k < EO_KIND_COUNT; k++)
        for (const void *const *p = eo_registry_list((eo_kind)k); p && *p; p++) {
            const eo_method_info *mi = eo_method_info_of(*p);
            CHECK(mi->name && mi->summary && *mi->summary, "kind %d entry has name and summary", k);
            const void *found = NULL;
            CHECK(eo_registry_find(ctx, (eo_kind)k, mi->name, &found) == EO_OK && found == *p, "find %s", mi->name);
        }
    eo_test_ctx_done(&ctx);
}

/* Fixed-length arrays: the message names the expected and the given length, for the
 * 3-vector parameters (gravity) and the scene's pairs, boxes and points. */
static void test_fixed_arrays(void)
{
    char b[32];
    json_t *a2 = json_pack("[ii]", 0, 1), *a0 = json_array(), *str = json_string("x"), *obj = json_object();
    json_t *i1 = json_integer(1), *nul = json_null();
    CHECK(strcmp(eo_json_describe(a2, b, sizeof b), "an array of 2") == 0, "'%s'", b);
    CHECK(strcmp(eo_json_describe(a0, b, sizeof b), "an empty array") == 0, "'%s'", b);
    CHECK(strcmp(eo_json_describe(str, b, sizeof b), "a string") == 0, "'%s'", b);
    CHECK(strcmp(eo_json_describe(obj, b, sizeof b), "an object") == 0, "'%s'", b);
    CHECK(strcmp(eo_json_describe(i1, b, sizeof b), "an integer") == 0, "'%s'", b);
    CHECK(strcmp(eo_json_describe(nul, b, sizeof b), "null") == 0, "'%s'", b);
    CHECK(strcmp(eo_json_describe(NULL, b, sizeof b), "nothing") == 0, "'%s'", b);
    json_decref(a2), json_decref(a0), json_decref(str), json_decref(obj), json_decref(i1), json_decref(nul);

    static const struct {
        const char *override, *message;
    } cases[] = {
        {"gravity=[0,-9.81]", "command line -o gravity: expected an array of 3 numbers, got an array of 2"},
        {"gravity=[0,0,-9.81,1]", "expected an array of 3 numbers, got an array of 4"},
        {"gravity=[]", "expected an array of 3 numbers, got an empty array"},
        {"gravity=9.81", "expected an array of 3 numbers, got a number"},
        {"gravity=[0,true,1]", "expected an array of 3 numbers, item 1 is a boolean"},
        {"point_masses=[[0,1,2]]", "'point_masses.0': expected an array of 2 [vertex, kg], got an array of 3"},
        {"boundary.0.box=[[0,0,0]]", "expected an array of 2 corners [[x0,y0,z0],[x1,y1,z1]], got an array of 1"},
        {"boundary.0.box=[[0,0,0],[1,1]]", "corner 1: expected an array of 3 numbers, got an array of 2"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        eo_ctx *ctx = eo_test_ctx();
        eo_sim *sim = NULL;
        const char *o[] = {cases[i].override, NULL};
        int rc = eo_sim_create_from(ctx, NULL, NULL, o, &sim);
        CHECK(rc == EO_ERR_TYPE && strstr(eo_ctx_message(ctx), cases[i].message), "%s: rc %d, '%s'",
              cases[i].override, rc, eo_ctx_message(ctx));
        eo_sim_destroy(&sim);
        eo_test_ctx_done(&ctx);
    }
}

/* Shortest round-trip decimal form: known values, random doubles of every exponent, the
 * .pvd writer and eo_json_dumps. */
static void test_fmt_double(void)
{
    char b[32];
    static const struct {
        double v;
        const char *s;
    } known[] = {{0.4, "0.4"}, {0.1 + 0.2, "0.30000000000000004"}, {1.0, "1"}, {-2.5e-7, "-2.5e-07"},
                 {1e300, "1e+300"}, {0.1 * 3, "0.30000000000000004"}, {4 * 0.1, "0.4"}, {1.0 / 3, "0.3333333333333333"},
                 {5e-324, "4.94065645841247e-324"}, {123456789012345680.0, "1.2345678901234568e+17"}};
    for (size_t i = 0; i < sizeof known / sizeof *known; i++)
        CHECK(strcmp(eo_fmt_double(b, known[i].v), known[i].s) == 0, "%.17g -> '%s', expected '%s'", known[i].v, b,
              known[i].s);
    /* 0.40000000000000002 is the %.17g form of 0.4: both name the same double */
    CHECK(strtod("0.40000000000000002", NULL) == 0.4, "same double");
    CHECK(strcmp(eo_fmt_double(b, NAN), "nan") == 0 || strcmp(b, "-nan") == 0, "nan '%s'", b);
    eo_test_seed(42);
    int bad = 0, shorter = 0;
    for (int i = 0; i < 100000; i++) {
        unsigned long long bits = 0;
        for (int k = 0; k < 4; k++) bits = (bits << 16) ^ (unsigned long long)eo_test_rand(0, 65536);
        double v;
        memcpy(&v, &bits, sizeof v);
        if (!isfinite(v)) continue;
        eo_fmt_double(b, v);
        if (strtod(b, NULL) != v || (v == 0 && signbit(v) != signbit(strtod(b, NULL)))) bad++;
        char l[32];
        snprintf(l, sizeof l, "%.17g", v);
        shorter += strlen(b) < strlen(l);
        /* shortest: one digit less does not read back */
        char e[512];
        int digits = 0;
        const char *c = b + (b[0] == '-');
        while (*c == '0' || *c == '.') c++; /* leading zeros are not significant */
        for (; *c && *c != 'e'; c++) digits += *c >= '0' && *c <= '9';
        if (digits > 15) {
            snprintf(e, sizeof e, "%.*g", digits - 1, v);
            if (strtod(e, NULL) == v) bad++;
        }
    }
    CHECK(bad == 0, "%d random doubles did not round-trip or were not shortest", bad);
    CHECK(shorter > 1000, "only %d of the random doubles got shorter than %%.17g", shorter);
    /* the doubles nearest to k / 1000 print as k / 1000 */
    for (int k = 0; k <= 1000; k++) {
        char want[32];
        snprintf(want, sizeof want, k % 1000 ? "%d.%03d" : "%d", k / 1000, k % 1000);
        while (strchr(want, '.') && want[strlen(want) - 1] == '0') want[strlen(want) - 1] = 0;
        CHECK(strcmp(eo_fmt_double(b, k / 1000.0), want) == 0, "%d/1000 -> '%s', expected '%s'", k, b, want);
    }

    /* the .pvd index */
    eo_ctx *ctx = eo_test_ctx();
    const char *dir = eo_test_tmpdir("core_fmt");
    char path[4200];
    snprintf(path, sizeof path, "%s/t.pvd", dir);
    eo_pvd *pvd = NULL;
    CHECK(eo_pvd_create(ctx, path, &pvd) == EO_OK, "pvd");
    double t = 0;
    for (int k = 0; k < 4; k++) t += 0.1; /* 0.30000000000000004 + 0.1 = 0.4 exactly */
    CHECK(eo_pvd_add(ctx, pvd, 0.4, "a.vtu") == EO_OK && eo_pvd_add(ctx, pvd, 0.1 + 0.2, "b.vtu") == EO_OK &&
              eo_pvd_add(ctx, pvd, t, "c.vtu") == EO_OK,
          "pvd add");
    eo_pvd_destroy(&pvd);
    char *text = NULL;
    size_t len = 0;
    CHECK(eo_read_file(ctx, path, &text, &len) == EO_OK, "read pvd");
    CHECK(text && strstr(text, "timestep=\"0.4\" ") && strstr(text, "timestep=\"0.30000000000000004\" ") &&
              !strstr(text, "0.40000000000000002"),
          "pvd text: %s", text ? text : "");
    eo_free(ctx, text);
    /* JSON: reals in their shortest form, still reals; strings untouched */
    json_t *j = json_pack("{s:f, s:f, s:f, s:i, s:s, s:[f]}", "t", 0.4, "one", 1.0, "third", 1.0 / 3, "n", 7, "s",
                          "0.40000000000000002", "a", 1e-7);
    char *js = eo_json_dumps(j, JSON_COMPACT | JSON_PRESERVE_ORDER);
    CHECK(js && strcmp(js, "{\"t\":0.4,\"one\":1.0,\"third\":0.3333333333333333,\"n\":7,"
                           "\"s\":\"0.40000000000000002\",\"a\":[1e-07]}") == 0,
          "json '%s'", js ? js : "");
    json_t *back = js ? json_loads(js, 0, NULL) : NULL;
    CHECK(back && json_is_real(json_object_get(back, "one")) &&
              json_real_value(json_object_get(back, "third")) == 1.0 / 3,
          "reads back");
    json_decref(back);
    free(js);
    json_decref(j);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_status();
    test_ctx();
    test_params();
    test_locate();
    test_config();
    test_registry();
    test_fixed_arrays();
    test_fmt_double();
    return eo_test_finish("test_core");
}
