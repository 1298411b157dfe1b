/* Benchmark harness pieces (suite 'bench-smoke'): time-to-threshold interpolation,
 * error at a budget, median and spread, suite parsing (every bad suite is refused with
 * a message naming the key and the valid keys), matrix expansion, and a tiny suite run
 * end to end through the library with no leak. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/bench.h"
#include "testutil.h"

static void test_time_to(void)
{
    const double t[] = {0, 1, 2, 3};
    const double e[] = {1, 1e-2, 1e-4, 1e-8};
    CHECK_CLOSE(eo_bench_time_to(4, t, e, 1e-2), 1, 1e-14);
    /* log-linear between (1, 1e-2) and (2, 1e-4): 1e-3 is half way */
    CHECK_CLOSE(eo_bench_time_to(4, t, e, 1e-3), 1.5, 1e-12);
    CHECK_CLOSE(eo_bench_time_to(4, t, e, 1e-6), 2.5, 1e-12);
    CHECK_CLOSE(eo_bench_time_to(4, t, e, 1), 0, 0);
    CHECK(isinf(eo_bench_time_to(4, t, e, 1e-9)), "never reached is infinite");
    CHECK(isinf(eo_bench_time_to(0, t, e, 1e-2)), "empty curve");
    /* an error that drops to zero or below (rounding) counts at its iterate's time */
    const double e2[] = {1, 1e-3, -1e-17, 0};
    CHECK_CLOSE(eo_bench_time_to(4, t, e2, 1e-9), 2, 0);
    /* NaN never satisfies a threshold */
    const double e3[] = {1, NAN, 1e-9, 0};
    CHECK_CLOSE(eo_bench_time_to(4, t, e3, 1e-6), 2, 0);

    CHECK_CLOSE(eo_bench_error_at(4, t, e, 1.5), 1e-2, 0);
    CHECK_CLOSE(eo_bench_error_at(4, t, e, 3), 1e-8, 0);
    CHECK_CLOSE(eo_bench_error_at(4, t, e, -1), 1, 0);
    CHECK(isnan(eo_bench_error_at(0, t, e, 1)), "no iterate");
}

static void test_median(void)
{
    double lo, hi;
    const double a[] = {3, 1, 2};
    CHECK_CLOSE(eo_bench_median(3, a, &lo, &hi), 2, 0);
    CHECK(lo == 1 && hi == 3, "spread %g..%g", lo, hi);
    const double b[] = {4, 1, 3, 2};
    CHECK_CLOSE(eo_bench_median(4, b, &lo, &hi), 2.5, 0);
    const double c[] = {1, INFINITY, NAN};
    CHECK(isinf(eo_bench_median(3, c, &lo, &hi)), "median of {1, inf} with NaN ignored is inf");
    CHECK(lo == 1 && isinf(hi), "spread with inf");
    CHECK(isnan(eo_bench_median(0, c, &lo, &hi)) && isnan(lo), "empty");
    const double d[] = {5};
    CHECK_CLOSE(eo_bench_median(1, d, NULL, NULL), 5, 0);
}

static const char *write_suite(const char *dir, const char *name, const char *text)
{
    static char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
    return path;
}

#define SCENE "\"scenes\": [{\"name\": \"c\", \"scene\": \"cantilever\", \"set\": {\"mesh.generate.cells\": [4, 1, 1]}}]"
#define CONF "\"configs\": [{\"name\": \"n\", \"set\": {\"solver.optimizer\": \"newton\"}}]"

/* A suite that must be refused with status `want` and a message containing `needle`. */
static void refuse(const char *dir, const char *text, int want, const char *needle)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_bench_suite *s = NULL;
    int rc = eo_bench_suite_load(ctx, write_suite(dir, "bad.json", text), &s);
    CHECK(rc == want, "status %d, expected %d for %s (message: %s)", rc, want, text, eo_ctx_message(ctx));
    CHECK(strstr(eo_ctx_message(ctx), needle) != NULL, "message '%s' lacks '%s'", eo_ctx_message(ctx), needle);
    CHECK(s == NULL, "no suite on error");
    eo_test_ctx_done(&ctx);
}

static void test_parse_errors(const char *dir)
{
    refuse(dir, "{\"repeat\": 2, " SCENE ", " CONF "}", EO_ERR_UNKNOWN_KEY, "valid keys here: description, repeats");
    refuse(dir, "{\"repeats\": 0, " SCENE ", " CONF "}", EO_ERR_RANGE, "repeats");
    refuse(dir, "{" CONF "}", EO_ERR_INVALID, "scenes");
    refuse(dir, "{" SCENE "}", EO_ERR_INVALID, "at least one configuration");
    refuse(dir, "{\"scenes\": [{\"name\": \"c\", \"scene\": \"cantilever\", \"stpes\": 2}], " CONF "}",
           EO_ERR_UNKNOWN_KEY, "valid keys here: name, scene, file, steps");
    refuse(dir, "{\"scenes\": [{\"scene\": \"cantilever\"}], " CONF "}", EO_ERR_INVALID, "needs a \"name\"");
    refuse(dir, "{\"scenes\": [{\"name\": \"c\", \"scene\": \"cantilever\", \"repeats\": 99}], " CONF "}",
           EO_ERR_RANGE, "repeats");
    refuse(dir, "{\"warmup_iters\": -1, " SCENE ", " CONF "}", EO_ERR_RANGE, "warmup_iters");
    refuse(dir, "{\"scenes\": [{\"name\": \"c\", \"scene\": \"nosuch\"}], " CONF "}", EO_ERR_UNKNOWN_NAME,
           "scene 'c'");
    refuse(dir, "{\"scenes\": [{\"name\": \"c\", \"scene\": \"cantilever\", \"set\": {\"material.EE\": 1}}], " CONF "}",
           EO_ERR_UNKNOWN_KEY, "valid keys here: model, E, nu");
    refuse(dir, "{\"scenes\": [{\"name\": \"c\", \"scene\": \"cantilever\", \"set\": 3}], " CONF "}", EO_ERR_TYPE,
           "scenes.0.set");
    refuse(dir, "{" SCENE ", \"configs\": [{\"name\": \"n\", \"set\": {\"solver.newton.foo\": 1}}]}",
           EO_ERR_UNKNOWN_KEY, "configuration 'n'");
    refuse(dir, "{" SCENE ", \"configs\": [{\"name\": \"n\", \"set\": {\"material.E\": 1}}]}", EO_ERR_INVALID,
           "only solver.* keys");
    refuse(dir, "{" SCENE ", \"configs\": [{\"name\": \"n\", \"sett\": {}}]}", EO_ERR_UNKNOWN_KEY, "name, set");
    refuse(dir, "{" SCENE ", \"configs\": [{\"name\": \"n\"}, {\"name\": \"n\"}]}", EO_ERR_INVALID,
           "two configurations are named 'n'");
    refuse(dir, "{\"baseline\": \"x\", " SCENE ", " CONF "}", EO_ERR_INVALID, "configurations: n");
    refuse(dir, "{" SCENE ", \"matrix\": [{\"optimizer\": [\"newtn\"]}]}", EO_ERR_UNKNOWN_NAME,
           "valid: newton, newton_tr, gradient_descent, lbfgs");
    refuse(dir, "{" SCENE ", \"matrix\": [{\"optimizer\": [\"newton\"], \"fix\": [\"clamp\"]}]}",
           EO_ERR_UNKNOWN_KEY, "optimizer, hessian_fix, linesearch, set");
    refuse(dir, "{\"thresholds\": [1e-2, -1], " SCENE ", " CONF "}", EO_ERR_RANGE, "thresholds");
    refuse(dir, "{\"target\": 1e-3, " SCENE ", " CONF "}", EO_ERR_RANGE, "is not above target");
    refuse(dir, "{\"require_converged\": [\"zz\"], " SCENE ", " CONF "}", EO_ERR_INVALID, "require_converged");
    refuse(dir, "{" SCENE ", " CONF ", }", EO_ERR_PARSE, "bad.json");
    /* an explicit integrator has no step problem: refused at load, naming the scene */
    refuse(dir,
           "{\"scenes\": [{\"name\": \"c\", \"scene\": \"cantilever\", \"set\": {\"time.integrator\": \"rk4\"}}], " CONF "}",
           EO_ERR_INVALID, "rk4 is explicit");
    refuse(dir,
           "{\"scenes\": [{\"name\": \"c\", \"scene\": \"cantilever\", \"set\": {\"time.integrator\": \"forward_euler\"}}], " CONF "}",
           EO_ERR_INVALID, "scene 'c'");
}

static void test_expansion(const char *dir)
{
    const char *text =
        "{\"baseline\": \"newton-clamp-backtracking\","
        " \"scenes\": [{\"name\": \"c\", \"scene\": \"cantilever\", \"set\": {\"mesh.generate.cells\": [4, 1, 1]},"
        "   \"vary\": [{\"a\": {\"material.E\": 1e6}, \"b\": {\"material.E\": 1e7}},"
        "              {\"snh\": {}, \"stvk\": {\"material.model\": \"stvk\"}}]}],"
        " \"matrix\": [{\"optimizer\": [\"newton\", \"gradient_descent\"], \"hessian_fix\": [\"clamp\", \"abs\"],"
        "   \"linesearch\": [\"backtracking\", \"exact\"], \"set\": {\"solver.max_iters\": 50}}]}";
    eo_ctx *ctx = eo_test_ctx();
    eo_bench_suite *s = NULL;
    int rc = eo_bench_suite_load(ctx, write_suite(dir, "ok.json", text), &s);
    CHECK(rc == 0, "load: %s", eo_ctx_message(ctx));
    if (s) {
        CHECK(eo_bench_suite_nscenes(s) == 4, "2 x 2 scenes, got %d", eo_bench_suite_nscenes(s));
        CHECK(!strcmp(eo_bench_suite_scene_name(s, 0), "c-a-snh") && !strcmp(eo_bench_suite_scene_name(s, 3), "c-b-stvk"),
              "scene names %s .. %s", eo_bench_suite_scene_name(s, 0), eo_bench_suite_scene_name(s, 3));
        /* newton: 2 fixes x 2 line searches; gradient_descent (no Hessian): 2 line searches */
        CHECK(eo_bench_suite_nconfigs(s) == 6, "6 configurations, got %d", eo_bench_suite_nconfigs(s));
        CHECK(!strcmp(eo_bench_suite_config_name(s, 0), "newton-clamp-backtracking"), "%s",
              eo_bench_suite_config_name(s, 0));
        CHECK(!strcmp(eo_bench_suite_config_name(s, 5), "gradient_descent-exact"), "%s",
              eo_bench_suite_config_name(s, 5));
        CHECK(!strcmp(eo_bench_suite_opts(s)->baseline, "newton-clamp-backtracking"), "baseline");
    }
    eo_bench_suite_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* A tiny run through the library: outputs exist, the baseline reaches the target. */
static void test_run(const char *dir)
{
    const char *text = "{\"repeats\": 1, \"steps\": 1, \"time_budget\": 1, \"plots\": false,"
                       " \"scenes\": [{\"name\": \"c\", \"scene\": \"cantilever\", \"skip\": 2, \"repeats\": 2,"
                       "   \"set\": {\"mesh.generate.cells\": [4, 1, 1]}}],"
                       " \"configs\": [{\"name\": \"n\", \"set\": {\"solver.optimizer\": \"newton\"}},"
                       "   {\"name\": \"gd\", \"set\": {\"solver.optimizer\": \"gradient_descent\", \"solver.max_iters\": 50}}],"
                       " \"require_converged\": [\"n\"]}";
    eo_ctx *ctx = eo_test_ctx();
    eo_bench_suite *s = NULL;
    int rc = eo_bench_suite_load(ctx, write_suite(dir, "run.json", text), &s);
    CHECK(rc == 0, "load: %s", eo_ctx_message(ctx));
    if (s) {
        char out[4200];
        snprintf(out, sizeof out, "%s/out", dir);
        eo_bench_run_opts o = eo_bench_run_opts_default();
        o.out_dir = out;
        eo_bench_summary sum;
        rc = eo_bench_run(ctx, s, &o, &sum);
        CHECK(rc == 0, "run: %s", eo_ctx_message(ctx));
        CHECK(sum.runs == 2 && sum.ref_failures == 0 && sum.nonfinite == 0 && sum.required_failures == 0,
              "runs %d ref failures %d nonfinite %d required %d", sum.runs, sum.ref_failures, sum.nonfinite,
              sum.required_failures);
        CHECK(sum.plots_made == 0, "plots disabled");
        const char *files[] = {"curves.csv", "summary.csv", "reference.csv", "trajectory.csv", "report.md"};
        for (int i = 0; i < 5; i++) {
            char p[4400];
            snprintf(p, sizeof p, "%s/%s", out, files[i]);
            FILE *f = fopen(p, "r");
            CHECK(f != NULL, "%s written", p);
            if (f) fclose(f);
        }
        /* the trajectory covers the whole scene (2 skipped + 1 measured step) for the
         * converging Newton configuration; the scene's own repeats (2) are reported */
        char p[4400], line[1024];
        snprintf(p, sizeof p, "%s/trajectory.csv", out);
        FILE *f = fopen(p, "r");
        int newton_rows = 0;
        while (f && fgets(line, sizeof line, f))
            if (!strncmp(line, "c,n,", 4)) newton_rows++;
        if (f) fclose(f);
        CHECK(newton_rows == 3, "Newton trajectory has %d frames, expected skip + steps = 3", newton_rows);
        snprintf(p, sizeof p, "%s/report.md", out);
        f = fopen(p, "r");
        int found = 0;
        while (f && fgets(line, sizeof line, f))
            if (strstr(line, "2 timed repeat(s)")) found = 1;
        if (f) fclose(f);
        CHECK(found, "report names the scene's 2 timed repeats");
    }
    eo_bench_suite_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* The shipped suites load (every scene config and configuration resolved at load) and
 * have the shape the README describes. */
static void test_shipped_suites(void)
{
    const char *src = getenv("EO_SOURCE_ROOT");
    if (!src) {
        printf("EO_SOURCE_ROOT unset: shipped suites not checked\n");
        return;
    }
    static const struct {
        const char *file;
        int scenes, configs;
    } want[] = {{"standard.json", 16, 26}, {"standard-full.json", 24, 22}, {"hard.json", 8, 30}, {"smoke.json", 5, 4},
                {"liu2017.json", 8, 7}};
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        if (strcmp(want[i].file, "liu2017.json") == 0) { /* its scenes read the shared meshes */
            char mesh[4200];
            snprintf(mesh, sizeof mesh, "%s/../shared/meshes/ipc_bunny.msh", src);
            FILE *f = fopen(mesh, "r");
            if (!f) {
                printf("%s absent: liu2017.json not checked\n", mesh);
                continue;
            }
            fclose(f);
        }
        char path[4200];
        snprintf(path, sizeof path, "%s/bench/%s", src, want[i].file);
        eo_ctx *ctx = eo_test_ctx();
        eo_bench_suite *s = NULL;
        int rc = eo_bench_suite_load(ctx, path, &s);
        CHECK(rc == 0, "%s: %s", want[i].file, eo_ctx_message(ctx));
        if (s) {
            CHECK(eo_bench_suite_nscenes(s) == want[i].scenes, "%s: %d scenes, expected %d", want[i].file,
                  eo_bench_suite_nscenes(s), want[i].scenes);
            CHECK(eo_bench_suite_nconfigs(s) == want[i].configs, "%s: %d configurations, expected %d", want[i].file,
                  eo_bench_suite_nconfigs(s), want[i].configs);
        }
        eo_bench_suite_destroy(&s);
        eo_test_ctx_done(&ctx);
    }
}

int main(void)
{
    const char *d = eo_test_tmpdir("test_bench");
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", d);
    test_time_to();
    test_median();
    test_parse_errors(dir);
    test_expansion(dir);
    test_run(dir);
    test_shipped_suites();
    return eo_test_finish("test_bench");
}
