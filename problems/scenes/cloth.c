/* Built-in scene `cloth`: a pinned sheet of point masses and springs (mesh.lattice) swinging
 * onto a ground plane with friction. The same text as examples/cloth.json (a test checks
 * both parse to equal JSON). */
#include "elastopt/scene.h"

const eo_scene_type eo_scene_cloth = {
    .info = {.name = "cloth", .summary = "mass-spring cloth pinned at two corners, ground contact with friction"},
    .json =
    "{\n"
    "  \"description\": \"Cloth: a 1 m sheet of 17 x 17 point masses (mesh.lattice: structural, shear, bending springs), pinned at two corners, swings down under gravity onto a ground plane at z = 0.1 with friction 0.5. Backward Euler.\",\n"
    "  \"mesh\": {\"lattice\": {\"cells\": [16, 16, 0], \"size\": [1, 1, 0], \"origin\": [0, 0, 1], \"mass\": 0.2,\n"
    "                       \"structural_k\": 2000, \"shear_k\": 500, \"bending_k\": 20}},\n"
    "  \"gravity\": [0, 0, -9.81],\n"
    "  \"boundary\": [\n"
    "    {\"nearest\": [0, 0, 1], \"fixed\": true},\n"
    "    {\"nearest\": [1, 0, 1], \"fixed\": true}\n"
    "  ],\n"
    "  \"collisions\": [\n"
    "    {\"plane\": {\"point\": [0, 0, 0.1], \"normal\": [0, 0, 1]}, \"stiffness\": 1000, \"friction\": 0.5}\n"
    "  ],\n"
    "  \"time\": {\"integrator\": \"backward_euler\", \"dt\": 0.01, \"steps\": 150},\n"
    "  \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\", \"tol\": 1e-12, \"max_iters\": 100},\n"
    "  \"output\": {\"dir\": \"out\", \"every\": 5, \"vtu\": true}\n"
    "}\n",
};
