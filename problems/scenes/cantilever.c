/* Built-in scene `cantilever`: bar clamped at x=0 sagging under gravity, newmark (default scene).
 * The same text as examples/cantilever.json (a test checks both parse to equal JSON). */
#include "elastopt/scene.h"

const eo_scene_type eo_scene_cantilever = {
    .info = {.name = "cantilever", .summary = "bar clamped at x=0 sagging under gravity, newmark (default scene)"},
    .json =
    "{\n"
    "  \"description\": \"Cantilever: a 1 x 0.1 x 0.1 m bar clamped at x = 0 sagging under gravity (implicit Newmark). The default scene of `elastopt run`.\",\n"
    "  \"mesh\": {\"generate\": {\"size\": [1.0, 0.1, 0.1], \"cells\": [20, 2, 2], \"split\": 5}},\n"
    "  \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e7, \"nu\": 0.3, \"density\": 1000},\n"
    "  \"mass\": \"consistent\",\n"
    "  \"gravity\": [0, 0, -9.81],\n"
    "  \"boundary\": [\n"
    "    {\"box\": [[-1, -1, -1], [0, 1, 1]], \"fixed\": true}\n"
    "  ],\n"
    "  \"time\": {\"integrator\": \"newmark\", \"dt\": 0.01, \"steps\": 40},\n"
    "  \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\", \"linesearch\": \"auto\",\n"
    "             \"stop\": \"relative_decrement\", \"tol\": 1e-10, \"max_iters\": 100},\n"
    "  \"output\": {\"every\": 1, \"vtu\": true}\n"
    "}\n",
};
