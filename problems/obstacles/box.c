/* Obstacle `box`: a solid axis-aligned box [min, max],
 *
 *     d(x) = min_k min(x_k − min_k, max_k − x_k)   (> 0 inside: the distance to the nearest face),
 *
 * n = −e_k or +e_k of that face (the vertex is pushed out through the nearest face),
 * κ = 0. The penalty k/2 d² is C¹ inside a face's region; where two faces are equally
 * near (the box's medial planes) the push direction switches, a kink of the force. */
#include <stddef.h>

#include "../obstacle.h"

typedef struct box_opts {
    double min[3];      /* lower corner, m. Default [-0.5, -0.5, -0.5]. */
    double max[3];      /* upper corner, m. Default [0.5, 0.5, 0.5]. */
} box_opts;

static const eo_param_desc box_desc[] = {
    {.key = "min", .kind = EO_PARAM_VEC3, .offset = offsetof(box_opts, min), .def.v = {-0.5, -0.5, -0.5},
     .help = "lower corner of the box (m)"},
    {.key = "max", .kind = EO_PARAM_VEC3, .offset = offsetof(box_opts, max), .def.v = {0.5, 0.5, 0.5},
     .help = "upper corner of the box (m), above min along every axis"},
    {0},
};

static const char *setup(double *p, const char **key)
{
    const box_opts *b = (const box_opts *)p;
    for (int k = 0; k < 3; k++)
        if (!(b->max[k] > b->min[k])) {
            *key = "max";
            return "empty box: max must be above min along every axis";
        }
    return NULL;
}

static double depth(const double *p, const double x[3], double n[3], double *kappa)
{
    const box_opts *b = (const box_opts *)p;
    double d = x[0] - b->min[0];
    int axis = 0, sign = -1;
    for (int k = 0; k < 3; k++) {
        double lo = x[k] - b->min[k], hi = b->max[k] - x[k];
        if (lo < d) d = lo, axis = k, sign = -1;
        if (hi < d) d = hi, axis = k, sign = 1;
    }
    n[0] = n[1] = n[2] = 0;
    n[axis] = sign;
    *kappa = 0;
    return d;
}

const eo_obstacle_type eo_obstacle_box = {
    .name = "box",
    .summary = "solid axis-aligned box obstacle {min, max}: depth = distance to the nearest face",
    .doc_path = "collisions.N.box",
    .params = box_desc,
    .params_size = sizeof(box_opts),
    .setup = setup,
    .depth = depth,
};
