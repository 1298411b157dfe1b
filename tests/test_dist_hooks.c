/* The context's distribution hooks (ctx.h, eo_dist_hooks: how the PETSc backend runs each
 * MPI rank on its part of the mesh), exercised in one process with a fake second part:
 *  - the scene loader hands the whole mesh to distribute_mesh once and uses the local mesh
 *    it returns (here: the tets whose centroid has x < 0.5);
 *  - a boundary entry that selects no local vertex is accepted when the reduction says
 *    another part has one, refused when no part has any (the count is reduced);
 *  - the statistics are reduced: with a reduce that doubles sums (a second, identical
 *    part), the gravity potential and the mass double, the centre of mass does not;
 *  - the scene features without a distributed form are refused at load, naming the key.
 * Without hooks nothing of this happens (nparts < 2: eo_ctx_dist is NULL). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "elastopt/config.h"
#include "elastopt/mesh.h"
#include "elastopt/scene.h"
#include "elastopt/sim.h"
#include "elastopt/step.h"
#include "testutil.h"

typedef struct fake {
    int calls, whole_nt;
    double sum_extra;  /* added to every SUM (what the "other part" has) */
    double sum_factor; /* every SUM multiplied by it first */
} fake;

static int fake_reduce(double *v, int n, eo_reduce_op op, void *user)
{
    fake *f = user;
    for (int i = 0; i < n; i++)
        if (op == EO_REDUCE_SUM) v[i] = v[i] * f->sum_factor + f->sum_extra;
    return 0;
}

/* the tets with centroid x < 0.5 and their vertices */
static int fake_distribute(eo_ctx *ctx, struct eo_mesh **mesh, void *user)
{
    fake *f = user;
    eo_mesh *m = *mesh, *l = NULL;
    f->calls++;
    f->whole_nt = m->nt;
    int nt = 0, nv = 0;
    int *map = eo_malloc(ctx, (size_t)m->nv * sizeof(int));
    if (!map) return EO_ERR_NOMEM;
    for (int v = 0; v < m->nv; v++) map[v] = -1;
    for (int k = 0; k < m->nt; k++) {
        double c = 0;
        for (int a = 0; a < 4; a++) c += m->X[3 * m->tets[4 * k + a]] / 4;
        if (c >= 0.5) continue;
        nt++;
        for (int a = 0; a < 4; a++)
            if (map[m->tets[4 * k + a]] < 0) map[m->tets[4 * k + a]] = nv++;
    }
    int rc = eo_mesh_create(ctx, nv, nt, &l);
    if (rc < 0) {
        eo_free(ctx, map);
        return rc;
    }
    for (int v = 0; v < m->nv; v++)
        if (map[v] >= 0) memcpy(l->X + 3 * map[v], m->X + 3 * v, 3 * sizeof(double));
    int q = 0;
    for (int k = 0; k < m->nt; k++) {
        double c = 0;
        for (int a = 0; a < 4; a++) c += m->X[3 * m->tets[4 * k + a]] / 4;
        if (c >= 0.5) continue;
        for (int a = 0; a < 4; a++) l->tets[4 * q + a] = map[m->tets[4 * k + a]];
        q++;
    }
    eo_free(ctx, map);
    eo_mesh_destroy(mesh);
    *mesh = l;
    return EO_OK;
}

static void install(eo_ctx *ctx, fake *f)
{
    eo_dist_hooks h = {.nparts = 2, .part = 0, .reduce = fake_reduce, .distribute_mesh = fake_distribute, .user = f};
    eo_ctx_set_dist(ctx, &h);
}

static int load(eo_ctx *ctx, const char *scene, const char *ov, eo_scene **sc)
{
    eo_cfg *cfg = NULL;
    int rc = eo_scene_cfg_load(ctx, NULL, scene, &cfg);
    if (rc >= 0 && ov) rc = eo_cfg_override(ctx, cfg, ov);
    if (rc >= 0) rc = eo_scene_load(ctx, cfg, sc);
    eo_cfg_destroy(&cfg);
    return rc;
}

static void test_local_mesh_and_counts(void)
{
    eo_ctx *ctx = eo_test_ctx();
    CHECK(eo_ctx_dist(ctx) == NULL, "no hooks: not distributed");
    fake f = {.sum_factor = 1, .sum_extra = 1};
    install(ctx, &f);
    CHECK(eo_ctx_dist(ctx) != NULL, "hooks with 2 parts: distributed");
    eo_scene *sc = NULL;
    int rc = load(ctx, "twist", NULL, &sc); /* boundary.1 (x >= 1) has no local vertex */
    CHECK(rc == EO_OK, "twist, other part selects boundary.1: rc %d (%s)", rc, eo_ctx_message(ctx));
    CHECK(f.calls == 1 && f.whole_nt == 400, "distribute called %d times with %d tets", f.calls, f.whole_nt);
    CHECK(sc && sc->mesh->nt == 200 && sc->nbc == 2 && sc->bc[1].nverts == 0 && sc->bc[0].nverts == 9,
          "local mesh %d tets, boundary %d / %d vertices", sc ? sc->mesh->nt : -1, sc ? sc->bc[0].nverts : -1,
          sc ? sc->bc[1].nverts : -1);
    eo_scene_destroy(&sc);
    f.sum_extra = 0; /* no part selects it */
    rc = load(ctx, "twist", NULL, &sc);
    CHECK(rc == EO_ERR_INVALID && strstr(eo_ctx_message(ctx), "boundary.1") &&
              strstr(eo_ctx_message(ctx), "selects no vertex"),
          "no part selects boundary.1: rc %d (%s)", rc, eo_ctx_message(ctx));
    eo_scene_destroy(&sc);
    eo_ctx_set_dist(ctx, NULL);
    CHECK(eo_ctx_dist(ctx) == NULL, "hooks removed");
    rc = load(ctx, "twist", NULL, &sc);
    CHECK(rc == EO_OK && sc && sc->mesh->nt == 400 && f.calls == 2, "without hooks: the whole mesh (%d tets)",
          sc ? sc->mesh->nt : -1);
    eo_scene_destroy(&sc);
    eo_test_ctx_done(&ctx);
}

static void test_stats_reduced(void)
{
    eo_ctx *ctx = eo_test_ctx();
    fake f = {.sum_factor = 1, .sum_extra = 0};
    install(ctx, &f);
    const char *ov[] = {"boundary=[{\"box\": [[-1, -1, -1], [0, 1, 1]], \"fixed\": true}]", NULL};
    eo_sim *sim = NULL;
    int rc = eo_sim_create_from(ctx, NULL, "cantilever", ov, &sim);
    CHECK(rc == EO_OK, "local cantilever: rc %d (%s)", rc, eo_ctx_message(ctx));
    if (rc < 0) {
        eo_test_ctx_done(&ctx);
        return;
    }
    eo_step_stats a, b;
    CHECK(eo_step_stats_compute(eo_sim_step_problem(sim), &a) == EO_OK, "stats");
    f.sum_factor = 2; /* a second part identical to this one */
    CHECK(eo_step_stats_compute(eo_sim_step_problem(sim), &b) == EO_OK, "stats, two parts");
    CHECK(fabs(a.gravity) > 0 && fabs(b.gravity - 2 * a.gravity) <= 1e-14 * fabs(a.gravity),
          "gravity potential %.17g -> %.17g (doubled)", a.gravity, b.gravity);
    for (int c = 0; c < 3; c++)
        CHECK(fabs(b.com[c] - a.com[c]) <= 1e-15 * (fabs(a.com[c]) + 1e-300) + 1e-300,
              "centre of mass %d: %.17g vs %.17g", c, a.com[c], b.com[c]);
    CHECK(b.min_J == a.min_J && b.inverted == 2 * a.inverted, "min J %g, inverted %d", b.min_J, b.inverted);
    eo_sim_destroy(&sim);
    eo_test_ctx_done(&ctx);
}

static void test_refusals(void)
{
    eo_ctx *ctx = eo_test_ctx();
    fake f = {.sum_factor = 1, .sum_extra = 1};
    install(ctx, &f);
    static const struct {
        const char *ov, *key;
    } cases[] = {
        {"collisions=[{\"plane\": {\"point\": [0, 0, -1], \"normal\": [0, 0, 1]}, \"stiffness\": 1e4}]", "collisions"},
        {"tractions=[{\"box\": [[0.4, -1, -1], [2, 1, 1]], \"t\": [0, 0, -1]}]", "tractions"},
        {"boundary=[{\"surface\": true, \"fixed\": true}]", "boundary.0"},
        {"point_mass=0.01", "point_masses"},
        {"damping={\"viscous\": 1}", "damping"},
        {"element=p2", "element"},
        {"initial={\"random_ball\": {\"radius\": 1}}", "initial.random_ball"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        eo_scene *sc = NULL;
        int rc = load(ctx, "cantilever", cases[i].ov, &sc);
        CHECK(rc == EO_ERR_UNSUPPORTED && strstr(eo_ctx_message(ctx), cases[i].key) &&
                  strstr(eo_ctx_message(ctx), "distributed"),
              "%s: rc %d (%s)", cases[i].ov, rc, eo_ctx_message(ctx));
        eo_scene_destroy(&sc);
    }
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_local_mesh_and_counts();
    test_stats_reduced();
    test_refusals();
    return eo_test_finish("test_dist_hooks");
}
