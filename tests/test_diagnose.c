/* Diagnoses instead of blind retries:
 *   - eo_scene_rigid_modes: the free rigid-body modes of each body under the constrained
 *     vertices (6 free, 3 about one vertex, 1 about the line of collinear vertices, 0 for
 *     a face; several bodies; collinear bodies), and eo_scene_load refusing a static
 *     scene with free modes (not a dynamic one);
 *   - eo_linsolve_factor: a not-positive-definite factorization is counted
 *     (stats.n_not_pd), warned once when unexpected, silent when expected;
 *   - eo_solver_minimize / eo_sim_step: project_on_demand's fallbacks counted in
 *     n_not_pd with no warning line. */
#include <stdlib.h>
#include <string.h>

#include "elastopt/config.h"
#include "elastopt/linsolve.h"
#include "elastopt/scene.h"
#include "elastopt/sim.h"
#include "elastopt/sparse.h"
#include "testutil.h"

/* ---------------------------------------------------------------- log capture */

typedef struct {
    int warnings, not_pd_lines;
    char last[512];
} logcap;

static void capture(eo_log_level level, const char *msg, void *user)
{
    logcap *c = user;
    if (level == EO_LOG_WARN) c->warnings++;
    if (level <= EO_LOG_WARN && strstr(msg, "not positive definite")) c->not_pd_lines++;
    snprintf(c->last, sizeof c->last, "%s", msg);
}

/* ---------------------------------------------------------------- rigid modes */

static const char *CUBE = "{\"mesh\": {\"generate\": {\"size\": [1, 1, 1], \"cells\": [2, 2, 2]}}, "
                          "\"time\": {\"integrator\": \"%s\", \"dt\": 0.25, \"steps\": 4}, \"boundary\": [%s]}";

static int load(eo_ctx *ctx, const char *integrator, const char *boundary, eo_scene **sc)
{
    char text[2048];
    snprintf(text, sizeof text, CUBE, integrator, boundary);
    eo_cfg *cfg = NULL;
    int rc = eo_cfg_load(ctx, NULL, text, &cfg);
    if (rc >= 0) rc = eo_scene_load(ctx, cfg, sc);
    eo_cfg_destroy(&cfg);
    return rc;
}

/* free modes of the cube with the vertices of `boundary` constrained (loaded as dynamic) */
static int cube_modes(eo_ctx *ctx, const char *boundary, eo_rigid_modes *rm)
{
    eo_scene *sc = NULL;
    int rc = load(ctx, "newmark", boundary, &sc);
    CHECK(rc == 0, "dynamic cube with [%s] loads: %s", boundary, eo_ctx_message(ctx));
    if (rc < 0) return rc;
    unsigned char *mask = calloc((size_t)sc->mesh->nv, 1);
    for (int b = 0; b < sc->nbc; b++)
        for (int i = 0; i < sc->bc[b].nverts; i++) mask[sc->bc[b].verts[i]] = 1;
    rc = eo_scene_rigid_modes(ctx, sc, mask, rm);
    free(mask);
    eo_scene_destroy(&sc);
    return rc;
}

static void test_cube_modes(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_rigid_modes rm;
    static const struct {
        const char *boundary;
        int free, unheld; /* free modes; those gravity (0, 0, −9.81) does not hold */
        const char *names;
    } cases[] = {
        {"", 6, 6, "translations x, y, z; rotations about x, y, z"},
        /* hanging from a corner: the rotation about the vertical through it stays free */
        {"{\"nearest\": [1, 1, 1], \"fixed\": true}", 3, 1, "rotations about x, y, z through the only constrained vertex"},
        /* the 3 vertices of the edge x = y = 0: one rotation, about z (vertical: not held) */
        {"{\"box\": [[-1, -1, -1], [0.1, 0.1, 2]], \"fixed\": true}", 1, 1, "along z, the line of all constrained"},
        /* two vertices on the face diagonal (0,0,0)-(1,1,0): about the horizontal line along
         * (1,1,0)/√2, the centroid off it: held */
        {"{\"nearest\": [0, 0, 0], \"fixed\": true}, {\"nearest\": [1, 1, 0], \"fixed\": true}", 1, 0,
         "along (0.707, 0.707, 0)"},
        /* the axle y = z = 0.5 through the centroid: balanced, not held */
        {"{\"box\": [[-1, 0.4, 0.4], [2, 0.6, 0.6]], \"fixed\": true}", 1, 1, "(0, 0.5, 0.5) along x"},
        {"{\"box\": [[-1, -1, -1], [0.1, 2, 2]], \"fixed\": true}", 0, 0, ""},
        /* three non-collinear vertices suffice; a moving set constrains as a fixed one */
        {"{\"nearest\": [0, 0, 0], \"fixed\": true}, {\"nearest\": [1, 0, 0], \"fixed\": true}, "
         "{\"nearest\": [0, 1, 0], \"translate\": [0, 0, 1]}", 0, 0, ""},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        if (cube_modes(ctx, cases[i].boundary, &rm) < 0) continue;
        CHECK(rm.n_components == 1, "cube: %d bodies", rm.n_components);
        CHECK(rm.n_free == cases[i].free, "cube [%s]: %d free modes, expected %d (%s)", cases[i].boundary, rm.n_free,
              cases[i].free, rm.modes);
        CHECK(rm.worst_free == cases[i].free && (cases[i].free ? rm.worst == 0 : rm.worst == -1),
              "worst body %d with %d", rm.worst, rm.worst_free);
        CHECK(rm.n_unheld == cases[i].unheld && rm.worst_unheld == cases[i].unheld,
              "cube [%s]: %d modes not held by gravity, expected %d (%s)", cases[i].boundary, rm.n_unheld,
              cases[i].unheld, rm.held);
        if (cases[i].free) CHECK(strstr(rm.modes, cases[i].names) != NULL, "names '%s'", rm.modes);
    }
    eo_test_ctx_done(&ctx);
}

/* Two bodies of points joined by springs: 0-1 (collinear: 5 modes) and the lone point 2
 * (3 translations). */
static void test_bodies(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *text = "{\"mesh\": {\"points\": [[0,0,0], [1,0,0], [0,1,0]]}, \"point_mass\": 1, "
                       "\"springs\": {\"edges\": \"list\", \"list\": [[0, 1]]}, \"time\": {\"integrator\": \"newmark\"}}";
    eo_cfg *cfg = NULL;
    eo_scene *sc = NULL;
    int rc = eo_cfg_load(ctx, NULL, text, &cfg);
    if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
    CHECK(rc == 0, "points load: %s", eo_ctx_message(ctx));
    if (rc == 0) {
        eo_rigid_modes rm;
        CHECK(eo_scene_rigid_modes(ctx, sc, NULL, &rm) == 0, "rigid modes");
        CHECK(rm.n_components == 2 && rm.n_free == 8 && rm.n_free_components == 2,
              "free points: %d bodies, %d modes in %d", rm.n_components, rm.n_free, rm.n_free_components);
        CHECK(rm.worst == 0 && rm.worst_free == 5 && rm.worst_vertices == 2, "worst %d: %d modes, %d vertices",
              rm.worst, rm.worst_free, rm.worst_vertices);
        CHECK(strstr(rm.modes, "the two axes across the line") != NULL, "names '%s'", rm.modes);
        unsigned char mask[3] = {1, 0, 0};
        CHECK(eo_scene_rigid_modes(ctx, sc, mask, &rm) == 0, "rigid modes");
        /* vertex 0 holds body 0 but for the rotations about y and z; point 2 stays free */
        CHECK(rm.n_free == 5 && rm.worst == 1 && rm.worst_free == 3 && rm.worst_first_vertex == 2,
              "one fixed: %d modes, worst %d with %d", rm.n_free, rm.worst, rm.worst_free);
        mask[2] = 1;
        CHECK(eo_scene_rigid_modes(ctx, sc, mask, &rm) == 0, "rigid modes");
        CHECK(rm.n_free == 2 && rm.worst == 0 && strstr(rm.modes, "along z") && strstr(rm.modes, "along y") &&
                  !strstr(rm.modes, "along x"),
              "the chain about its fixed end: %d modes '%s'", rm.n_free, rm.modes);
    }
    eo_scene_destroy(&sc);
    eo_cfg_destroy(&cfg);
    eo_test_ctx_done(&ctx);
}

/* eo_scene_load: static refuses free modes (also after a release), dynamic does not. */
static void test_static_load(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_scene *sc = NULL;
    int rc = load(ctx, "static", "", &sc);
    CHECK(rc == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "6 unconstrained rigid-body modes (translations x, y, "
                                                               "z; rotations about x, y, z)"),
          "free static cube: %d %s", rc, eo_ctx_message(ctx));
    rc = load(ctx, "static", "{\"nearest\": [0, 0, 0], \"fixed\": true}", &sc);
    CHECK(rc == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "3 unconstrained") &&
              strstr(eo_ctx_message(ctx), "not the rotation about the vertical through it"),
          "one vertex: %s", eo_ctx_message(ctx));
    /* a horizontal hinge (the edge y = z = 0): gravity holds the body below it */
    const char *hinge = "{\"box\": [[-1, -1, -1], [2, 0.1, 0.1]], \"fixed\": true}";
    rc = load(ctx, "static", hinge, &sc);
    CHECK(rc == 0, "horizontal hinge: %s", eo_ctx_message(ctx));
    eo_scene_destroy(&sc);
    {   /* ... but not without gravity */
        char text[2048];
        snprintf(text, sizeof text, CUBE, "static", hinge);
        eo_cfg *cfg = NULL;
        rc = eo_cfg_load(ctx, NULL, text, &cfg);
        if (rc >= 0) rc = eo_cfg_override(ctx, cfg, "gravity=[0,0,0]");
        if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
        CHECK(rc == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "gravity cannot hold it (no gravity)"),
              "hinge without gravity: %s", eo_ctx_message(ctx));
        eo_cfg_destroy(&cfg);
    }
    rc = load(ctx, "static", "{\"box\": [[-1, -1, -1], [0.1, 2, 2]], \"fixed\": true}", &sc);
    CHECK(rc == 0, "fixed face: %s", eo_ctx_message(ctx));
    eo_scene_destroy(&sc);
    /* the face x = 1 is released at t = 0.5: step 3 (t = 0.75) has only the edge x = y = 0 */
    rc = load(ctx, "static",
              "{\"box\": [[-1, -1, -1], [0.1, 0.1, 2]], \"fixed\": true}, "
              "{\"box\": [[0.9, -1, -1], [2, 2, 2]], \"fixed\": true, \"release\": 0.5}",
              &sc);
    CHECK(rc == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "1 unconstrained rigid-body mode") &&
              strstr(eo_ctx_message(ctx), "from t = 0.75 (after boundary.1 is released)"),
          "release: %s", eo_ctx_message(ctx));
    rc = load(ctx, "newmark", "", &sc);
    CHECK(rc == 0, "free dynamic cube loads: %s", eo_ctx_message(ctx));
    eo_scene_destroy(&sc);
    rc = load(ctx, "backward_euler", "{\"nearest\": [0, 0, 0], \"fixed\": true}", &sc);
    CHECK(rc == 0, "pinned dynamic cube loads: %s", eo_ctx_message(ctx));
    eo_scene_destroy(&sc);
    eo_test_ctx_done(&ctx);
}

/* ---------------------------------------------------------------- not PD: counted */

/* [[1, 2], [2, 1]] (eigenvalues 3, −1), upper CSC */
static eo_csc *indefinite(eo_ctx *ctx)
{
    eo_csc *A = NULL;
    if (eo_csc_create(ctx, 2, 3, &A) < 0) return NULL;
    A->colptr[0] = 0, A->colptr[1] = 1, A->colptr[2] = 3;
    A->rowind[0] = 0, A->rowind[1] = 0, A->rowind[2] = 1;
    A->val[0] = 1, A->val[1] = 2, A->val[2] = 1;
    return A;
}

static void test_not_pd_counted(void)
{
    eo_ctx *ctx = eo_test_ctx();
    logcap cap = {0};
    eo_ctx_set_logger(ctx, capture, &cap, EO_LOG_INFO);
    eo_csc *A = indefinite(ctx);
    const char *names[] = {"cholmod", "lapack", NULL};
    for (int k = 0; names[k]; k++) {
        const eo_linsolve_type *type = NULL;
        eo_linsolve *ls = NULL;
        if (eo_linsolve_find(ctx, names[k], &type) < 0) continue; /* not built */
        CHECK(eo_linsolve_create(ctx, type, NULL, &ls) == 0 && eo_linsolve_analyze(ls, A) == 0, "%s", names[k]);
        memset(&cap, 0, sizeof cap);
        CHECK(eo_linsolve_get_expect_not_pd(ls) == 0, "default: unexpected");
        /* expected: counted, not printed */
        CHECK(eo_linsolve_set_expect_not_pd(ls, 1) == 0, "previous setting");
        for (int i = 0; i < 3; i++) CHECK(eo_linsolve_factor(ls, A) == EO_WARN_NOT_PD, "%s: not PD", names[k]);
        CHECK(eo_linsolve_get_stats(ls)->n_not_pd == 3, "%s: n_not_pd %ld", names[k], eo_linsolve_get_stats(ls)->n_not_pd);
        CHECK(cap.warnings == 0, "%s: expected failures printed %d warnings (%s)", names[k], cap.warnings, cap.last);
        CHECK(strstr(eo_ctx_message(ctx), "not positive definite") != NULL, "message kept: %s", eo_ctx_message(ctx));
        /* unexpected: the first one warned, the rest counted */
        eo_linsolve_set_expect_not_pd(ls, 0);
        for (int i = 0; i < 3; i++) CHECK(eo_linsolve_factor(ls, A) == EO_WARN_NOT_PD, "%s: not PD", names[k]);
        CHECK(eo_linsolve_get_stats(ls)->n_not_pd == 6, "%s: n_not_pd %ld", names[k], eo_linsolve_get_stats(ls)->n_not_pd);
        CHECK(cap.warnings == 1 && cap.not_pd_lines == 1 && strstr(cap.last, "counted as n_not_pd"),
              "%s: unexpected failures printed %d warnings, last '%s'", names[k], cap.warnings, cap.last);
        eo_linsolve_destroy(&ls);
    }
    eo_csc_destroy(&A);
    eo_test_ctx_done(&ctx);
}

/* The inverted scene with project_on_demand: its fallbacks are counted in every layer
 * (solve result summed over the steps = the linear solver's counter = the profile), and
 * nothing says "not positive definite" at warning level. */
static void test_project_on_demand_quiet(void)
{
    eo_ctx *ctx = eo_test_ctx();
    logcap cap = {0};
    eo_ctx_set_logger(ctx, capture, &cap, EO_LOG_INFO);
    const char *ov[] = {"solver.hessian_fix=project_on_demand", "time.steps=6", NULL};
    eo_sim *sim = NULL;
    int rc = eo_sim_create_from(ctx, NULL, "inverted", ov, &sim);
    CHECK(rc == 0, "inverted: %s", eo_ctx_message(ctx));
    long sum = 0;
    for (int k = 0; rc == 0 && k < 6; k++) {
        eo_sim_step_result r;
        rc = eo_sim_step(sim, &r);
        CHECK(rc == 0 && r.reason > 0, "step %d: %d %s", k, rc, eo_reason_name(r.reason));
        CHECK(r.n_not_pd >= 0 && r.n_not_pd <= r.n_factor, "step %d: %ld of %ld factorizations", k, r.n_not_pd,
              r.n_factor);
        sum += r.n_not_pd;
    }
    if (sim) {
        const eo_profile *p = eo_solver_get_profile(eo_sim_solver(sim));
        CHECK(sum > 0, "project_on_demand fell back %ld times on the inverted start", sum);
        CHECK(p->n_not_pd == sum, "profile %ld vs steps %ld", p->n_not_pd, sum);
    }
    CHECK(cap.not_pd_lines == 0 && cap.warnings == 0, "%d warnings, %d not-PD lines (%s)", cap.warnings,
          cap.not_pd_lines, cap.last);
    eo_sim_destroy(&sim);
    eo_test_ctx_done(&ctx);
}

/* One -o assignment over EO_CFG_MAX_BYTES is refused before jansson sees it; one under
 * the cap is accepted. */
static void test_override_cap(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_cfg *cfg = NULL;
    CHECK(eo_cfg_load(ctx, NULL, "{}", &cfg) == 0, "empty config");
    size_t n = EO_CFG_MAX_BYTES + 16;
    char *a = malloc(n + 1);
    memcpy(a, "description=", 12);
    memset(a + 12, 'x', n - 12);
    a[n] = 0;
    int rc = eo_cfg_override(ctx, cfg, a);
    CHECK(rc == EO_ERR_RANGE && strstr(eo_ctx_message(ctx), "more than 8388608 bytes (EO_CFG_MAX_BYTES)"),
          "huge -o: %d %s", rc, eo_ctx_message(ctx));
    a[1000] = 0;
    CHECK(eo_cfg_override(ctx, cfg, a) == 0, "1000-byte -o: %s", eo_ctx_message(ctx));
    free(a);
    eo_cfg_destroy(&cfg);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_cube_modes();
    test_bodies();
    test_static_load();
    test_not_pd_counted();
    test_project_on_demand_quiet();
    test_override_cap();
    return eo_test_finish("test_diagnose");
}
