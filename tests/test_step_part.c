/* Partitioned evaluation of the step objective (eo_step_set_part, step.h), the piece the
 * distributed backend (petsc/) builds on: for scenes with each kind of term that has a
 * partitioned form (consistent and lumped mass, elasticity, gravity, newmark's linear
 * term, contact with friction), the tets split into P parts and every vertex owned by
 * one part, the sums over the parts of value, gradient and Hessian (read, as the backend
 * does, only in the columns of each part's vertices) equal the whole objective's, at
 * the step's starting guess perturbed so that every term is active. Scenes with springs
 * or damping are refused (EO_ERR_UNSUPPORTED). */
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

typedef struct parts {
    int P;
    int *tets, *tstart;         /* tets of part p: tets[tstart[p] .. tstart[p+1]) */
    int *verts, *vstart;        /* vertices of part p */
    unsigned char *vown;        /* P·nv */
} parts;

/* tets by index modulo P (every part spans the whole bar: many shared vertices), vertex
 * owner = part of the first tet that holds it */
static void parts_make(parts *pp, const eo_mesh *m, int P)
{
    pp->P = P;
    pp->tets = malloc((size_t)m->nt * sizeof(int));
    pp->tstart = calloc((size_t)P + 1, sizeof(int));
    pp->verts = malloc((size_t)(4 * m->nt) * sizeof(int));
    pp->vstart = calloc((size_t)P + 1, sizeof(int));
    pp->vown = calloc((size_t)P * (size_t)m->nv, 1);
    int *owner = malloc((size_t)m->nv * sizeof(int)), *seen = malloc((size_t)m->nv * sizeof(int));
    for (int v = 0; v < m->nv; v++) owner[v] = -1;
    int nt = 0, nvl = 0;
    for (int p = 0; p < P; p++) {
        pp->tstart[p] = nt;
        pp->vstart[p] = nvl;
        for (int v = 0; v < m->nv; v++) seen[v] = 0;
        for (int k = p; k < m->nt; k += P) {
            pp->tets[nt++] = k;
            for (int a = 0; a < 4; a++) {
                int v = m->tets[4 * k + a];
                if (owner[v] < 0) {
                    owner[v] = p;
                    pp->vown[(size_t)p * m->nv + v] = 1;
                }
                if (!seen[v]) {
                    seen[v] = 1;
                    pp->verts[nvl++] = v;
                }
            }
        }
    }
    pp->tstart[P] = nt;
    pp->vstart[P] = nvl;
    free(owner);
    free(seen);
}

static void parts_free(parts *pp)
{
    free(pp->tets);
    free(pp->tstart);
    free(pp->verts);
    free(pp->vstart);
    free(pp->vown);
}

static void check_scene(const char *name, const char *json, const char *const *ov, int P)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *sim = NULL;
    if (eo_test_sim_open(&sim, ctx, name, json, ov) < 0) {
        CHECK(0, "%s: open", name ? name : json);
        eo_test_ctx_done(&ctx);
        return;
    }
    eo_objective *obj = eo_test_sim_obj(sim);
    eo_step *st = eo_step_of_objective(obj);
    CHECK(st == eo_sim_step_problem(sim), "%s: eo_step_of_objective", name);
    const eo_mesh *m = eo_step_mesh(st);
    const int n = obj->n;
    double *x = malloc((size_t)n * sizeof(double)), *g = malloc((size_t)n * sizeof(double));
    double *gs = calloc((size_t)n, sizeof(double)), *gp = malloc((size_t)n * sizeof(double));
    memcpy(x, eo_test_sim_guess(sim), (size_t)n * sizeof(double));
    for (int i = 0; i < n; i++) x[i] += 1e-3 * sin(1.0 + i); /* every term active, J ≠ 1 */
    double f, fs = 0, fp;
    eo_objective_gradient(obj, x, &f, g);
    eo_csc *H;
    eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);
    double *Hfull = malloc((size_t)H->nnz * sizeof(double)), *Hs = calloc((size_t)H->nnz, sizeof(double));
    memcpy(Hfull, H->val, (size_t)H->nnz * sizeof(double));
    int ninv = obj->ops->inverted_count(obj->data, x), ninvs = 0;
    parts pp;
    parts_make(&pp, m, P);
    unsigned char *col = malloc((size_t)n);
    for (int p = 0; p < P; p++) {
        eo_step_part part = {.nt = pp.tstart[p + 1] - pp.tstart[p], .tets = pp.tets + pp.tstart[p],
                             .nv = pp.vstart[p + 1] - pp.vstart[p], .verts = pp.verts + pp.vstart[p],
                             .vown = pp.vown + (size_t)p * m->nv};
        CHECK(eo_step_set_part(st, &part) == EO_OK, "%s: set_part", name);
        eo_objective_value(obj, x, &fp);
        double fg;
        eo_objective_gradient(obj, x, &fg, gp);
        CHECK(fg == fp, "%s part %d: value %.17g, gradient's value %.17g", name, p, fp, fg);
        fs += fp;
        memset(col, 0, (size_t)n);
        for (int q = 0; q < part.nv; q++)
            for (int c = 0; c < 3; c++) {
                int i = eo_step_full_to_free(st, 3 * part.verts[q] + c);
                if (i >= 0) {
                    col[i] = 1;
                    gs[i] += gp[i];
                }
            }
        eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);
        for (int j = 0; j < n; j++)
            if (col[j])
                for (int q = H->colptr[j]; q < H->colptr[j + 1]; q++) Hs[q] += H->val[q];
        ninvs += obj->ops->inverted_count(obj->data, x);
        eo_step_set_part(st, NULL);
    }
    CHECK_CLOSE(fs, f, 1e-12);
    double gmax = 0, gerr = 0, hmax = 0, herr = 0;
    for (int i = 0; i < n; i++) {
        gmax = fmax(gmax, fabs(g[i]));
        gerr = fmax(gerr, fabs(gs[i] - g[i]));
    }
    for (int q = 0; q < H->nnz; q++) {
        hmax = fmax(hmax, fabs(Hfull[q]));
        herr = fmax(herr, fabs(Hs[q] - Hfull[q]));
    }
    CHECK(gerr <= 1e-12 * gmax, "%s: gradient sum off by %g (max |g| %g)", name, gerr, gmax);
    CHECK(herr <= 1e-12 * hmax, "%s: Hessian sum off by %g (max |H| %g)", name, herr, hmax);
    CHECK(ninvs == ninv, "%s: inverted %d vs %d", name, ninvs, ninv);
    /* the whole objective again after the part is cleared */
    double f2;
    eo_objective_value(obj, x, &f2);
    CHECK(f2 == f, "%s: value after clearing the part %.17g vs %.17g", name, f2, f);
    if (getenv("EO_TEST_VERBOSE"))
        fprintf(stderr, "%s P=%d: n %d, value %.3g rel %.1e, grad %.1e, Hessian %.1e\n", name ? name : "json", P, n,
                f, fabs(fs - f) / fmax(1, fabs(f)), gerr / gmax, herr / hmax);
    parts_free(&pp);
    free(col);
    free(x);
    free(g);
    free(gs);
    free(gp);
    free(Hfull);
    free(Hs);
    eo_sim_destroy(&sim);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    /* newmark (linear term) + consistent mass + gravity + fixed end */
    check_scene("cantilever", NULL, NULL, 3);
    /* rotating boundary, backward Euler, lumped mass */
    const char *twist[] = {"time.integrator=backward_euler", "mass=lumped", NULL};
    check_scene("twist", NULL, twist, 2);
    /* inverted start: per-part inverted counts add up */
    check_scene("inverted", NULL, NULL, 4);
    /* contact and friction on a plane, point masses */
    const char *drop = "{\"mesh\": {\"generate\": {\"size\": [0.2, 0.2, 0.2], \"cells\": [3, 3, 3], "
                       "\"origin\": [0, 0, -0.001]}}, \"point_mass\": 0.01, "
                       "\"collisions\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 0, 1]}, "
                       "\"friction\": 0.3}], \"time\": {\"integrator\": \"backward_euler\"}}";
    check_scene(NULL, drop, NULL, 3);
    /* springs have no partitioned form yet: refused, and the objective stays whole */
    {
        eo_ctx *ctx = eo_test_ctx();
        eo_sim *sim = NULL;
        const char *ov[] = {"springs.edges=mesh", NULL};
        if (eo_test_sim_open(&sim, ctx, "cantilever", NULL, ov) >= 0) {
            eo_step *st = eo_sim_step_problem(sim);
            int one = 0;
            unsigned char own = 1;
            eo_step_part part = {.nt = 1, .tets = &one, .nv = 0, .verts = &one, .vown = &own};
            CHECK(eo_step_set_part(st, &part) == EO_ERR_UNSUPPORTED, "springs refused");
        } else {
            CHECK(0, "open cantilever with springs");
        }
        eo_sim_destroy(&sim);
        eo_test_ctx_done(&ctx);
    }
    return eo_test_finish("test_step_part");
}
