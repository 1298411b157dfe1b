/* simulate: an external program built against the INSTALLED elastopt only
 *
 *     cc -std=c11 simulate.c $(pkg-config --cflags --libs elastopt) -o simulate
 *     ./simulate [--scene NAME | SCENE.json] [-o key=value ...]
 *
 * Runs a scene through the library's simulation driver (eo_sim) and prints one line:
 * steps converged, total iterations, and the mean z displacement of the vertices at the
 * far end of the mesh (largest rest x: the tip of a cantilever). Exit 0 if every step
 * converged, 1 if not, 2 on bad input. tests/test_install.sh builds and runs it. */
#include <elastopt/sim.h>
#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    const char *file = NULL, *scene = NULL, *ov[64];
    int nov = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--scene") == 0 && i + 1 < argc) scene = argv[++i];
        else if (strcmp(argv[i], "-o") == 0 && i + 1 < argc && nov < 63) ov[nov++] = argv[++i];
        else if (argv[i][0] != '-') file = argv[i];
        else {
            fprintf(stderr, "usage: simulate [--scene NAME | SCENE.json] [-o key=value ...]\n");
            return 2;
        }
    }
    ov[nov] = NULL;
    eo_ctx *ctx = NULL;
    if (eo_ctx_create(NULL, &ctx) < 0) return 2;
    eo_sim *sim = NULL;
    if (eo_sim_create_from(ctx, file, file ? NULL : scene, ov, &sim) < 0) {
        fprintf(stderr, "simulate: %s\n", eo_ctx_message(ctx));
        eo_ctx_destroy(&ctx);
        return 2;
    }
    const eo_scene *sc = eo_sim_scene(sim);
    int nconv = 0, nsteps = sc->time.steps, rc = 0;
    long iters = 0;
    for (int k = 0; k < nsteps; k++) {
        eo_sim_step_result r;
        if ((rc = eo_sim_step(sim, &r)) < 0) {
            fprintf(stderr, "simulate: step %d: %s\n", k + 1, eo_ctx_message(ctx));
            break;
        }
        nconv += eo_reason_is_converged(r.reason);
        iters += r.iterations;
        if (r.reason == EO_DIVERGED_NONFINITE) break;
    }
    /* tip: vertices with the largest rest x (within 1e-9 of the bar length) */
    const eo_mesh *m = sc->mesh;
    const double *x = eo_step_x(eo_sim_step_problem(sim));
    double xmax = -1e300, dz = 0;
    int ntip = 0;
    for (int v = 0; v < m->nv; v++) xmax = m->X[3 * v] > xmax ? m->X[3 * v] : xmax;
    for (int v = 0; v < m->nv; v++)
        if (m->X[3 * v] >= xmax - 1e-9) {
            dz += x[3 * v + 2] - m->X[3 * v + 2];
            ntip++;
        }
    printf("converged=%d/%d iterations=%ld tip_dz=%.10e\n", nconv, nsteps, iters, ntip ? dz / ntip : 0.0);
    eo_sim_destroy(&sim);
    eo_ctx_destroy(&ctx);
    return rc < 0 ? 2 : nconv == nsteps ? 0 : 1;
}
