/* "Did you mean": the weighted edit distance (values by hand), the pick and its
 * threshold, and the messages of real configurations: a -o override and a scene file
 * with a misspelt key, an unknown method name, an unknown registry name. */
#include <stdio.h>
#include <string.h>

#include "elastopt/registry.h"
#include "elastopt/sim.h"
#include "elastopt/suggest.h"
#include "testutil.h"

static void test_distance(void)
{
    /* ordinary edits cost 2 */
    CHECK(eo_edit_distance("newton", "newton") == 0, "equal");
    CHECK(eo_edit_distance("newtn", "newton") == 2, "one insertion: %d", eo_edit_distance("newtn", "newton"));
    CHECK(eo_edit_distance("newtom", "newton") == 2, "one substitution");
    CHECK(eo_edit_distance("lbgfs", "lbfgs") == 2, "one swap (OSA): %d", eo_edit_distance("lbgfs", "lbfgs"));
    CHECK(eo_edit_distance("kitten", "sitting") == 6, "kitten/sitting = 3 edits: %d",
          eo_edit_distance("kitten", "sitting"));
    CHECK(eo_edit_distance("", "abc") == 6 && eo_edit_distance("abc", "") == 6, "empty");
    /* the cheap slips cost 1 */
    CHECK(eo_edit_distance("hessianfix", "hessian_fix") == 1, "missing '_': %d",
          eo_edit_distance("hessianfix", "hessian_fix"));
    CHECK(eo_edit_distance("Newton", "newton") == 1, "case");
    CHECK(eo_edit_distance("MAX_ITERS", "max_iters") == 8, "8 letters of another case");
    CHECK(eo_edit_distance("max-iters", "max_iters") == 1, "'-' for '_'");
    CHECK(eo_edit_distance("mesh", ".mesh") == 1, "missing '.'");
    /* symmetric */
    const char *w[] = {"relative_decrement", "gradient", "cholmod_ldlt", "x", "ab", "ba", "Time_Budget", NULL};
    for (int i = 0; w[i]; i++)
        for (int j = 0; w[j]; j++)
            CHECK(eo_edit_distance(w[i], w[j]) == eo_edit_distance(w[j], w[i]), "symmetry %s %s", w[i], w[j]);
    CHECK(eo_edit_distance(NULL, "a") == -1, "NULL");
}

static void test_pick(void)
{
    char out[64];
    const char *keys = "optimizer, hessian_fix, linesearch, stop, linear, tol, max_iters, time_budget";
    CHECK(eo_suggest("hessianfix", keys, out, sizeof out) == 1 && strcmp(out, "hessian_fix") == 0, "got '%s'", out);
    CHECK(eo_suggest("max_iter", keys, out, sizeof out) == 1 && strcmp(out, "max_iters") == 0, "got '%s'", out);
    CHECK(eo_suggest("LineSearch", keys, out, sizeof out) == 1 && strcmp(out, "linesearch") == 0, "got '%s'", out);
    /* too far: nothing */
    CHECK(eo_suggest("zzz", keys, out, sizeof out) == 0 && out[0] == 0, "got '%s'", out);
    CHECK(eo_suggest("optimization", keys, out, sizeof out) == 0, "3 edits in 12 characters: '%s'", out);
    /* the threshold grows with the length: 2 edits in 8+ characters */
    CHECK(eo_suggest("cantleve", "cantilever, twist", out, sizeof out) == 1 && strcmp(out, "cantilever") == 0,
          "got '%s'", out);
    CHECK(eo_suggest("cantve", "cantilever, twist", out, sizeof out) == 0, "4 edits: '%s'", out);
    /* closest wins over first */
    CHECK(eo_suggest("newton_t", "newton, newton_tr", out, sizeof out) == 1 && strcmp(out, "newton_tr") == 0,
          "got '%s'", out);
    /* blank-separated lists (CLI options), an exact match is skipped */
    CHECK(eo_suggest("--qiet", "--out --force --quiet --verbose", out, sizeof out) == 1 && strcmp(out, "--quiet") == 0,
          "got '%s'", out);
    CHECK(eo_suggest("tol", "tol, tl", out, sizeof out) == 1 && strcmp(out, "tl") == 0, "exact skipped: '%s'", out);
    char hint[96];
    CHECK(strcmp(eo_suggest_hint("hessianfix", keys, "solver.", hint, sizeof hint),
                 " (did you mean 'solver.hessian_fix'?)") == 0, "hint '%s'", hint);
    CHECK(strcmp(eo_suggest_hint("qqq", keys, "solver.", hint, sizeof hint), "") == 0, "no hint '%s'", hint);
}

static void expect_msg(int rc, int want, eo_ctx *ctx, const char *a, const char *b)
{
    const char *m = eo_ctx_message(ctx);
    CHECK(rc == want && strstr(m, a) && (!b || strstr(m, b)), "rc %d (want %d), message '%s'", rc, want, m);
}

static void test_real_configs(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *sim = NULL;
    /* -o override with a missing '_', as `elastopt run -o solver.hessianfix=abs` */
    const char *o1[] = {"solver.hessianfix=abs", NULL};
    int rc = eo_sim_create_from(ctx, NULL, NULL, o1, &sim);
    expect_msg(rc, EO_ERR_UNKNOWN_KEY, ctx,
               "command line -o solver.hessianfix: unknown key (did you mean 'solver.hessian_fix'?); valid keys here: ",
               "hessian_fix");
    CHECK(sim == NULL, "no sim on failure");
    /* a method name */
    const char *o2[] = {"solver.optimizer=newtn", NULL};
    rc = eo_sim_create_from(ctx, NULL, NULL, o2, &sim);
    expect_msg(rc, EO_ERR_UNKNOWN_NAME, ctx, "unknown optimizer 'newtn' (did you mean 'newton'?); valid: newton", NULL);
    /* a method's own section, nested */
    const char *o3[] = {"solver.newton.descent-eps=1e-3", NULL};
    rc = eo_sim_create_from(ctx, NULL, NULL, o3, &sim);
    expect_msg(rc, EO_ERR_UNKNOWN_KEY, ctx, "(did you mean 'solver.newton.descent_eps'?)", NULL);
    /* far from everything: no hint, the list only */
    const char *o4[] = {"solver.qqqqqqq=1", NULL};
    rc = eo_sim_create_from(ctx, NULL, NULL, o4, &sim);
    expect_msg(rc, EO_ERR_UNKNOWN_KEY, ctx, "unknown key; valid keys here: ", NULL);
    /* a scene file: file:line and the suggestion */
    const char *dir = eo_test_tmpdir("suggest");
    char path[4200];
    snprintf(path, sizeof path, "%s/s.json", dir);
    FILE *f = fopen(path, "w");
    fputs("{\n  \"description\": \"x\",\n  \"time\": {\"steps\": 1, \"Dt\": 0.01}\n}\n", f);
    fclose(f);
    rc = eo_sim_create_from(ctx, path, NULL, NULL, &sim);
    expect_msg(rc, EO_ERR_UNKNOWN_KEY, ctx, "s.json:3:", "(did you mean 'time.dt'?)");
    /* a registry lookup */
    const void *t = NULL;
    rc = eo_registry_find(ctx, EO_KIND_LINSOLVE, "cholmd", &t);
    expect_msg(rc, EO_ERR_UNKNOWN_NAME, ctx, "unknown linear solver 'cholmd' (did you mean 'cholmod'?); valid: ", NULL);
    CHECK(t == NULL, "nothing found");
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_distance();
    test_pick();
    test_real_configs();
    return eo_test_finish("test_suggest");
}
