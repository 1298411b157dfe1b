/* Box generator: an nx × ny × nz grid of cells, each split into tets.
 *
 * Cell corners are numbered by bits (x = 1, y = 2, z = 4), so corner c sits at
 * (i + (c&1), j + (c>>1&1), k + (c>>2&1)).
 *  - 6 tets (Kuhn/Freudenthal): one tet per permutation of the axes, along the path
 *    0 -> e_a -> e_a + e_b -> 7. Every cell cuts each face along the diagonal through
 *    its lowest/highest corner, so neighbours agree: conforming with one pattern.
 *  - 5 tets: a central tet on four mutually non-adjacent corners plus the four corner
 *    tets. Even cells ((i+j+k) even) use the central tet {1,2,4,7}, odd ones {0,3,5,6};
 *    alternating flips every face diagonal so neighbours agree: conforming.
 * Each tet is made positive by swapping two vertices when its volume is negative. */
#include <math.h>

#include "elastopt/mesh.h"

static const int kuhn6[6][4] = {
    {0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7},
};
static const int split5_even[5][4] = {
    {0, 1, 2, 4}, {3, 1, 2, 7}, {5, 1, 4, 7}, {6, 2, 4, 7}, {1, 2, 4, 7},
};
static const int split5_odd[5][4] = {
    {1, 0, 3, 5}, {2, 0, 3, 6}, {4, 0, 5, 6}, {7, 3, 5, 6}, {0, 3, 5, 6},
};

int eo_mesh_generate_box(eo_ctx *ctx, const eo_mesh_gen_opts *o, eo_mesh **out)
{
    *out = NULL;
    eo_mesh_gen_opts def = eo_mesh_gen_opts_default();
    if (!o) o = &def;
    const int nx = o->cells[0], ny = o->cells[1], nz = o->cells[2];
    if (nx < 1 || ny < 1 || nz < 1)
        return eo_error(ctx, EO_ERR_RANGE, "box cells must be >= 1, got %d x %d x %d", nx, ny, nz);
    if (o->split != 5 && o->split != 6) return eo_error(ctx, EO_ERR_RANGE, "box split must be 5 or 6, got %d", o->split);
    for (int i = 0; i < 3; i++)
        if (!(o->size[i] > 0) || !isfinite(o->size[i]) || !isfinite(o->origin[i]))
            return eo_error(ctx, EO_ERR_RANGE, "box size must be finite and > 0, origin finite");
    double nv_d = (double)(nx + 1) * (ny + 1) * (nz + 1), nt_d = (double)nx * ny * nz * o->split;
    if (nv_d > 2e9 / 3 || nt_d > 2e9 / 4)
        return eo_error(ctx, EO_ERR_RANGE, "box of %d x %d x %d cells is too large", nx, ny, nz);
    eo_mesh *m = NULL;
    int rc = eo_mesh_create(ctx, (int)nv_d, (int)nt_d, &m);
    if (rc < 0) return rc;
    const int sx = nx + 1, sxy = (nx + 1) * (ny + 1);
    for (int k = 0; k <= nz; k++)
        for (int j = 0; j <= ny; j++)
            for (int i = 0; i <= nx; i++) {
                double *x = m->X + 3 * ((size_t)k * sxy + (size_t)j * sx + i);
                /* exact end points: i == nx gives origin + size */
                x[0] = o->origin[0] + o->size[0] * ((double)i / nx);
                x[1] = o->origin[1] + o->size[1] * ((double)j / ny);
                x[2] = o->origin[2] + o->size[2] * ((double)k / nz);
            }
    int t = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                int corner[8];
                for (int c = 0; c < 8; c++)
                    corner[c] = (k + (c >> 2 & 1)) * sxy + (j + (c >> 1 & 1)) * sx + i + (c & 1);
                const int(*pat)[4] = o->split == 6 ? kuhn6 : ((i + j + k) % 2 ? split5_odd : split5_even);
                for (int q = 0; q < o->split; q++, t++) {
                    int *tt = m->tets + 4 * t;
                    for (int a = 0; a < 4; a++) tt[a] = corner[pat[q][a]];
                    if (eo_tet_volume(m->X, tt) < 0) {
                        int tmp = tt[1];
                        tt[1] = tt[2];
                        tt[2] = tmp;
                    }
                }
            }
    *out = m;
    return EO_OK;
}

void eo_mesh_map_cook(eo_mesh *m, const double origin[3], const double size[3])
{
    const double L = size[0], H = size[1];
    for (int v = 0; v < m->nv; v++) {
        double *X = m->X + 3 * v;
        const double s = (X[0] - origin[0]) / L, t = (X[1] - origin[1]) / H; /* in [0, 1]² */
        const double lo = s * H, hi = H + s * (16.0 / 44.0) * H;          /* the column at x */
        X[1] = origin[1] + lo + t * (hi - lo);
    }
}
