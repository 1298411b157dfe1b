/* Mass-spring lattices (001 §2.3 spring topologies; cloth = a lattice flat along one
 * axis): point masses on an (nx+1)×(ny+1)×(nz+1) grid, vertex id(i, j, k) =
 * i + (nx+1)(j + (ny+1)k), and three kinds of springs, each with its own stiffness
 * (scene.h, eo_scene_lattice_opts):
 *   structural  id(p) – id(p + e_a)                   (stretching)
 *   shear       id(p) – id(p + e_a + e_b), id(p + e_a) – id(p + e_b), a < b   (shearing)
 *   bending     id(p) – id(p + 2 e_a)                 (bending, "interleaving" springs)
 * Mass: `mass` / (number of cells) per cell of dimension d (the axes with cells > 0),
 * split equally over its 2^d corners. */
#include <stdlib.h>

#include "lattice.h"

typedef struct gen {
    int n[3];
    int *ab;
    double *k;
    int ns;
} gen;

static int vid(const gen *g, const int p[3]) { return p[0] + (g->n[0] + 1) * (p[1] + (g->n[1] + 1) * p[2]); }

static void add(gen *g, int a, int b, double k)
{
    if (g->ab) {
        g->ab[2 * g->ns] = a < b ? a : b;
        g->ab[2 * g->ns + 1] = a < b ? b : a;
        g->k[g->ns] = k;
    }
    g->ns++;
}

/* every spring of the lattice (counting only when g->ab is NULL) */
static void springs(gen *g, const eo_scene_lattice_opts *o, int count[3])
{
    const int *n = g->n;
    int p[3];
    for (int kind = 0; kind < 3; kind++) {
        const double k = kind == 0 ? o->structural_k : kind == 1 ? o->shear_k : o->bending_k;
        const int before = g->ns;
        if (k > 0)
            for (p[2] = 0; p[2] <= n[2]; p[2]++)
                for (p[1] = 0; p[1] <= n[1]; p[1]++)
                    for (p[0] = 0; p[0] <= n[0]; p[0]++)
                        for (int a = 0; a < 3; a++) {
                            int q[3] = {p[0], p[1], p[2]};
                            if (kind == 0 || kind == 2) {
                                q[a] += kind == 0 ? 1 : 2;
                                if (q[a] <= n[a]) add(g, vid(g, p), vid(g, q), k);
                                continue;
                            }
                            for (int b = a + 1; b < 3; b++) {
                                if (p[a] + 1 > n[a] || p[b] + 1 > n[b]) continue;
                                int r[3] = {p[0], p[1], p[2]}, s[3] = {p[0], p[1], p[2]}, t[3] = {p[0], p[1], p[2]};
                                r[a]++, r[b]++; /* p + e_a + e_b */
                                s[a]++;         /* p + e_a */
                                t[b]++;         /* p + e_b */
                                add(g, vid(g, p), vid(g, r), k);
                                add(g, vid(g, s), vid(g, t), k);
                            }
                        }
        count[kind] = g->ns - before;
    }
}

int eo_lattice_build(eo_ctx *ctx, const eo_scene_lattice_opts *o, eo_mesh **mesh, int **ab, double **k, int *ns,
                     double **mass, int count[3])
{
    *mesh = NULL, *ab = NULL, *k = NULL, *mass = NULL, *ns = 0;
    gen g = {.n = {(int)o->cells[0], (int)o->cells[1], (int)o->cells[2]}};
    const int nv = (g.n[0] + 1) * (g.n[1] + 1) * (g.n[2] + 1);
    springs(&g, o, count);
    const int total = g.ns;
    int rc = eo_mesh_create(ctx, nv, 0, mesh);
    if (rc < 0) return rc;
    *mass = eo_calloc(ctx, (size_t)nv, sizeof(double));
    if (total > 0) {
        g.ab = *ab = eo_malloc(ctx, 2 * (size_t)total * sizeof(int));
        g.k = *k = eo_malloc(ctx, (size_t)total * sizeof(double));
    }
    if (!*mass || (total > 0 && (!*ab || !*k))) {
        eo_mesh_destroy(mesh);
        eo_free(ctx, *mass), eo_free(ctx, *ab), eo_free(ctx, *k);
        *mass = NULL, *ab = NULL, *k = NULL;
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (mesh.lattice of %d points)", nv);
    }
    g.ns = 0;
    int dummy[3];
    springs(&g, o, dummy);
    *ns = g.ns;
    /* positions, and the mass of the cells over their corners */
    int ncell = 1, dim = 0;
    for (int a = 0; a < 3; a++)
        if (g.n[a] > 0) ncell *= g.n[a], dim++;
    const double corner = o->mass / ncell / (double)(1 << dim);
    int p[3];
    for (p[2] = 0; p[2] <= g.n[2]; p[2]++)
        for (p[1] = 0; p[1] <= g.n[1]; p[1]++)
            for (p[0] = 0; p[0] <= g.n[0]; p[0]++) {
                const int v = vid(&g, p);
                double share = 1;
                for (int a = 0; a < 3; a++) {
                    (*mesh)->X[3 * v + a] = o->origin[a] + (g.n[a] > 0 ? o->size[a] * p[a] / g.n[a] : 0);
                    /* cells touching p along axis a: 1 at the ends, 2 inside */
                    if (g.n[a] > 0) share *= (p[a] > 0) + (p[a] < g.n[a]);
                }
                (*mass)[v] = dim ? corner * share : o->mass;
            }
    return EO_OK;
}
