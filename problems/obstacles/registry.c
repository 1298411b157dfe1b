/* The obstacle shapes of the `collisions` list (one line per shape; see obstacle.h). */
#include "../obstacle.h"

extern const eo_obstacle_type eo_obstacle_plane, eo_obstacle_sphere, eo_obstacle_box;

const eo_obstacle_type *const eo_obstacle_types[] = {
    &eo_obstacle_plane,
    &eo_obstacle_sphere,
    &eo_obstacle_box,
    NULL,
};
