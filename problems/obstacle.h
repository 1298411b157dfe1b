/* Static obstacle shapes of the `collisions` list (private to problems/).
 *
 * A shape is a const ops table plus one line in obstacles/registry.c: the key that
 * selects it inside a `collisions` entry ("plane", "sphere", "box"), the descriptor table
 * of that key's section (a struct of doubles, at most EO_OBSTACLE_PARAMS of them, stored
 * in eo_scene_obstacle.shape), an optional setup (check and normalize the values) and the
 * penetration depth
 *
 *     d(x) > 0 inside the obstacle (the vertex must move by d to leave it), d <= 0 outside,
 *
 * with the outward unit normal n = −∇d and ∇²d = −κ (I − n nᵀ): every shape's depth
 * Hessian is an isotropic tangential curvature κ >= 0 (plane and box faces κ = 0, a
 * sphere 1/|x − c|), so the penalty Hessian k (n nᵀ + d ∇²d) has the closed-form
 * eigenvalues k (along n) and −k d κ (twice, tangential) and is projected without an
 * eigensolver. The collision term (term_collision.c) and the friction term
 * (term_friction.c) use only `depth`. */
#ifndef EO_PROBLEMS_OBSTACLE_H
#define EO_PROBLEMS_OBSTACLE_H

#include <stddef.h>

#include "elastopt/params.h"
#include "elastopt/scene.h"

typedef struct eo_obstacle_type {
    const char *name;            /* key inside a collisions entry, e.g. "sphere" */
    const char *summary;         /* one line for `elastopt help` */
    const char *doc_path;        /* "collisions.N.<name>" (the docs' section path) */
    const eo_param_desc *params; /* keys of the shape's section (doubles / vec3 only) */
    size_t params_size;          /* sizeof its struct, <= EO_OBSTACLE_PARAMS doubles */
    /* Optional: check and normalize the loaded values; on error return a message and
     * set *key to the offending key of the section. NULL = fine. */
    const char *(*setup)(double *p, const char **key);
    /* Depth d at x (> 0 penetrating); when d > 0 also n (outward unit normal) and κ. */
    double (*depth)(const double *p, const double x[3], double n[3], double *kappa);
} eo_obstacle_type;

/* NULL-terminated list of the shapes. */
extern const eo_obstacle_type *const eo_obstacle_types[];

#endif
