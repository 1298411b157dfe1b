/* Mass-spring lattices and cloth (`mesh.lattice`, issue 12 item 5; suite 'engine'):
 *
 *  - spring counts of an nx×ny sheet (several sizes) and an nx×ny×nz block against the
 *    formulas, each kind identified independently by its rest length (h, h√2, 2h on a
 *    square grid of spacing h), each kind off when its k is 0; masses sum to `mass`;
 *  - the static sag of a hanging sheet (1 m × 1 m curtain in the xz plane, its top edge
 *    pinned, 0.1 kg under gravity) converges under refinement n = 4, 8, 16, 32: the
 *    differences of the mid-bottom displacement shrink by a factor > 1.4 per halving
 *    (measured 1.57, 1.79: towards first order, the pinned edge has corner singularities);
 *  - the volume collapse of notes 001 §2.8 (examples/volume_collapse.json): the cube
 *    with structural springs only collapses (volume < 5% of its rest volume after
 *    1.5 s), with shear springs it holds (volume within 2% of the rest volume);
 *  - scene errors of the new keys. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

/* ------------------------------------------------------------------ counts */

static void check_counts(int nx, int ny, int nz, double ks, double kh, double kb)
{
    char json[1024];
    const double h = 0.1;
    snprintf(json, sizeof json,
             "{\"mesh\": {\"lattice\": {\"cells\": [%d, %d, %d], \"size\": [%g, %g, %g], \"mass\": 2.5,"
             " \"structural_k\": %g, \"shear_k\": %g, \"bending_k\": %g}}, \"time\": {\"integrator\": \"backward_euler\"}}",
             nx, ny, nz, nx * h, ny * h, nz * h, ks, kh, kb);
    eo_ctx *ctx = eo_test_ctx();
    eo_cfg *cfg = NULL;
    eo_scene *sc = NULL;
    int rc = eo_cfg_load(ctx, NULL, json, &cfg);
    if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
    CHECK(rc == 0, "lattice %dx%dx%d: %s", nx, ny, nz, eo_ctx_message(ctx));
    if (rc == 0) {
        const int n[3] = {nx, ny, nz};
        long expect[3] = {0, 0, 0};
        for (int a = 0; a < 3; a++) {
            long p1 = n[a], p2 = n[a] > 1 ? n[a] - 1 : 0;
            for (int b = 0; b < 3; b++)
                if (b != a) p1 *= n[b] + 1, p2 *= n[b] + 1;
            expect[0] += p1;
            expect[2] += p2;
            for (int b = a + 1; b < 3; b++) {
                long q = 2L * n[a] * n[b];
                for (int c = 0; c < 3; c++)
                    if (c != a && c != b) q *= n[c] + 1;
                expect[1] += q;
            }
        }
        const double k[3] = {ks, kh, kb};
        for (int q = 0; q < 3; q++)
            if (!(k[q] > 0)) expect[q] = 0;
        /* by rest length */
        long got[3] = {0, 0, 0}, other = 0;
        const double *X = sc->mesh->X;
        for (int e = 0; e < sc->nspring; e++) {
            const int a = sc->spring_ab[2 * e], b = sc->spring_ab[2 * e + 1];
            double L = sqrt((X[3 * a] - X[3 * b]) * (X[3 * a] - X[3 * b]) +
                            (X[3 * a + 1] - X[3 * b + 1]) * (X[3 * a + 1] - X[3 * b + 1]) +
                            (X[3 * a + 2] - X[3 * b + 2]) * (X[3 * a + 2] - X[3 * b + 2]));
            int kind = fabs(L - h) < 1e-12 ? 0 : fabs(L - h * sqrt(2)) < 1e-12 ? 1 : fabs(L - 2 * h) < 1e-12 ? 2 : -1;
            if (kind < 0 || sc->spring_k[e] != k[kind])
                other++;
            else
                got[kind]++;
        }
        double M = 0;
        for (int v = 0; v < sc->mesh->nv; v++) M += sc->pmass[v];
        printf("lattice %dx%dx%d (k %g %g %g): structural %ld (formula %ld), shear %ld (%ld), bending %ld (%ld), "
               "%d points, mass %.15g\n", nx, ny, nz, ks, kh, kb, got[0], expect[0], got[1], expect[1], got[2],
               expect[2], sc->mesh->nv, M);
        CHECK(other == 0, "%ld springs of no kind", other);
        for (int q = 0; q < 3; q++)
            CHECK(got[q] == expect[q] && sc->lattice_count[q] == expect[q], "kind %d: %ld by length, %d counted, formula %ld",
                  q, got[q], sc->lattice_count[q], expect[q]);
        CHECK(sc->mesh->nv == (nx + 1) * (ny + 1) * (nz + 1) && sc->mesh->nt == 0, "points");
        CHECK(fabs(M - 2.5) < 1e-12, "total mass %g", M);
    }
    eo_scene_destroy(&sc);
    eo_cfg_destroy(&cfg);
    eo_test_ctx_done(&ctx);
}

static void test_counts(void)
{
    check_counts(8, 5, 0, 1000, 1000, 100);
    check_counts(1, 7, 0, 1000, 1000, 100);
    check_counts(4, 0, 6, 1000, 0, 100);
    check_counts(3, 4, 2, 1000, 1000, 100);
    check_counts(6, 6, 0, 0, 1000, 0);
}

/* ------------------------------------------------------------------ sag */

/* static sag (m) of the mid-bottom point of an n×n curtain, top edge pinned */
static double sag(int n, int *iters)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"mesh\": {\"lattice\": {\"cells\": [%d, 0, %d], \"size\": [1, 0, 1], \"origin\": [0, 0, -1],"
             " \"mass\": 0.1, \"structural_k\": 1000, \"shear_k\": 1000, \"bending_k\": 100}},"
             " \"gravity\": [0, 0, -9.81],"
             " \"boundary\": [{\"box\": [[-1, -1, -0.001], [2, 1, 1]], \"fixed\": true}],"
             " \"time\": {\"integrator\": \"static\", \"steps\": 1},"
             " \"solver\": {\"hessian_fix\": \"shift\", \"tol\": 1e-22, \"max_iters\": 100}}",
             n, n);
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    double z = NAN;
    if (eo_test_sim_open(&s, ctx, NULL, json, NULL) == 0) {
        eo_sim_step_result r;
        int rc = eo_test_sim_step(s, NULL, NULL, &r);
        CHECK(rc == 0 && eo_reason_is_converged(r.reason), "sag n %d: %s", n, eo_reason_name(r.reason));
        *iters = r.iterations;
        const double *x = eo_step_x(eo_sim_step_problem(s));
        const int v = n / 2; /* i = n/2, k = 0: the middle of the bottom edge at rest z = -1 */
        z = -(x[3 * v + 2] + 1);
        CHECK(fabs(x[3 * v + 1]) < 1e-12, "the curtain stays in its plane");
    } else {
        CHECK(0, "open sag n %d", n);
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return z;
}

static void test_sag(void)
{
    double s[4];
    int it[4];
    for (int q = 0; q < 4; q++) s[q] = sag(4 << q, &it[q]);
    double d1 = fabs(s[1] - s[0]), d2 = fabs(s[2] - s[1]), d3 = fabs(s[3] - s[2]);
    printf("curtain sag (mid-bottom, m): n=4 %.9f (%d it), 8 %.9f (%d), 16 %.9f (%d), 32 %.9f (%d); differences "
           "%.3e %.3e %.3e, ratios %.2f %.2f\n", s[0], it[0], s[1], it[1], s[2], it[2], s[3], it[3], d1, d2, d3,
           d1 / d2, d2 / d3);
    CHECK(s[0] > 1e-4 && s[3] < 0.1, "sag magnitude %g %g", s[0], s[3]);
    CHECK(d1 / d2 > 1.4 && d2 / d3 > 1.4, "sag differences shrink: ratios %g %g", d1 / d2, d2 / d3);
}

/* ------------------------------------------------------------------ volume collapse */

/* volume of the deformed lattice: every hexahedral cell as 6 tets around its diagonal */
static double lattice_volume(const eo_scene *sc, const double *x)
{
    const int nx = (int)sc->lat.cells[0], ny = (int)sc->lat.cells[1], nz = (int)sc->lat.cells[2];
    static const int tets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
    double vol = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                int c[8];
                for (int q = 0; q < 8; q++)
                    c[q] = (i + (q & 1)) + (nx + 1) * ((j + ((q >> 1) & 1)) + (ny + 1) * (k + ((q >> 2) & 1)));
                for (int t = 0; t < 6; t++) {
                    const double *a = x + 3 * c[tets[t][0]], *b = x + 3 * c[tets[t][1]], *d = x + 3 * c[tets[t][2]],
                                 *e = x + 3 * c[tets[t][3]];
                    double u[3], v[3], w[3];
                    for (int m = 0; m < 3; m++) u[m] = b[m] - a[m], v[m] = d[m] - a[m], w[m] = e[m] - a[m];
                    vol += (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                            u[2] * (v[0] * w[1] - v[1] * w[0])) / 6;
                }
            }
    return vol;
}

static double collapse(double shear_k, double *v0)
{
    char ov[64];
    snprintf(ov, sizeof ov, "mesh.lattice.shear_k=%g", shear_k);
    const char *ovs[] = {ov, NULL};
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    double vol = NAN;
    char path[4096];
    snprintf(path, sizeof path, "%s", eo_test_src_path("examples/volume_collapse.json"));
    if (eo_sim_create_from(ctx, path, NULL, ovs, &s) == EO_OK) {
        *v0 = lattice_volume(eo_sim_scene(s), eo_sim_scene(s)->mesh->X);
        int ok = 1;
        for (int k = 0; k < eo_sim_scene(s)->time.steps && ok; k++) {
            eo_sim_step_result r;
            ok = eo_sim_step(s, &r) == 0 && eo_reason_is_converged(r.reason);
            CHECK(ok, "collapse shear_k %g step %d: %s", shear_k, k, eo_reason_name(r.reason));
        }
        vol = lattice_volume(eo_sim_scene(s), eo_step_x(eo_sim_step_problem(s)));
    } else {
        CHECK(0, "open %s: %s", path, eo_ctx_message(ctx));
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return vol;
}

static void test_volume_collapse(void)
{
    double v0 = 0, v0b = 0;
    double without = collapse(0, &v0), with = collapse(4000, &v0b);
    printf("volume collapse: rest volume %.6f m^3; structural springs only %.6f m^3 (%.2f%%), with shear springs "
           "%.6f m^3 (%.2f%%)\n", v0, without, 100 * without / v0, with, 100 * with / v0);
    CHECK(fabs(v0 - 1) < 1e-12 && fabs(v0b - 1) < 1e-12, "rest volume %g", v0);
    CHECK(without < 0.05 * v0, "collapses without shear springs: %g", without);
    CHECK(fabs(with - v0) < 0.02 * v0, "holds with shear springs: %g", with);
}

/* ------------------------------------------------------------------ errors */

static void expect_error(const char *json, int status, const char *needle)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_cfg *cfg = NULL;
    eo_scene *sc = NULL;
    int rc = eo_cfg_load(ctx, NULL, json, &cfg);
    if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
    CHECK(rc == status, "%s: status %d, expected %d (%s)", json, rc, status, eo_ctx_message(ctx));
    CHECK(strstr(eo_ctx_message(ctx), needle) != NULL, "message '%s' lacks '%s'", eo_ctx_message(ctx), needle);
    eo_scene_destroy(&sc);
    eo_cfg_destroy(&cfg);
    eo_test_ctx_done(&ctx);
}

static void test_errors(void)
{
    expect_error("{\"mesh\": {\"lattice\": {\"cells\": [2.5, 1, 0]}}}", EO_ERR_RANGE, "integers");
    expect_error("{\"mesh\": {\"lattice\": {\"cells\": [2, 2, 2], \"size\": [1, 1, 0]}}}", EO_ERR_RANGE, "size");
    expect_error("{\"mesh\": {\"lattice\": {}, \"generate\": {}}}", EO_ERR_INVALID, "one of");
    expect_error("{\"mesh\": {\"lattice\": {}}, \"springs\": {\"edges\": \"mesh\"}}", EO_ERR_INVALID, "none");
    expect_error("{\"mesh\": {\"lattice\": {\"shear_k\": -1}}}", EO_ERR_RANGE, "shear_k");
}

int main(void)
{
    test_errors();
    test_counts();
    test_sag();
    test_volume_collapse();
    return eo_test_finish("test_lattice");
}
