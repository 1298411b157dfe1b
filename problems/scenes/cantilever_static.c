/* Built-in scene `cantilever_static`: static equilibrium of the clamped bar under gravity.
 * The same text as examples/cantilever_static.json (a test checks both parse to equal JSON). */
#include "elastopt/scene.h"

const eo_scene_type eo_scene_cantilever_static = {
    .info = {.name = "cantilever_static", .summary = "static equilibrium of the clamped bar under gravity"},
    .json =
    "{\n"
    "  \"description\": \"Static cantilever: the equilibrium of the clamped bar under its own weight (one static solve).\",\n"
    "  \"mesh\": {\"generate\": {\"size\": [1.0, 0.1, 0.1], \"cells\": [20, 2, 2], \"split\": 5}},\n"
    "  \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e7, \"nu\": 0.3, \"density\": 1000},\n"
    "  \"gravity\": [0, 0, -9.81],\n"
    "  \"boundary\": [\n"
    "    {\"box\": [[-1, -1, -1], [0, 1, 1]], \"fixed\": true}\n"
    "  ],\n"
    "  \"time\": {\"integrator\": \"static\", \"dt\": 1, \"steps\": 1},\n"
    "  \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\", \"tol\": 1e-10, \"max_iters\": 200}\n"
    "}\n",
};
