/* Built-in scene `inverted`: box starting fully inverted (reflected), recovers its rest shape.
 * The same text as examples/inverted.json (a test checks both parse to equal JSON). */
#include "elastopt/scene.h"

const eo_scene_type eo_scene_inverted = {
    .info = {.name = "inverted", .summary = "box starting fully inverted (reflected), recovers its rest shape"},
    .json =
    "{\n"
    "  \"description\": \"Inverted start: a unit box whose vertices are reflected through its bottom plane z = 0 (every tet inverted), bottom face fixed; it must recover its rest shape with no inverted tet at the end.\",\n"
    "  \"mesh\": {\"generate\": {\"size\": [1, 1, 1], \"cells\": [4, 4, 4], \"split\": 5}},\n"
    "  \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e5, \"nu\": 0.3, \"density\": 1000},\n"
    "  \"gravity\": [0, 0, 0],\n"
    "  \"initial\": {\"reflect\": {\"point\": [0, 0, 0], \"normal\": [0, 0, 1]}},\n"
    "  \"boundary\": [\n"
    "    {\"box\": [[-1, -1, -1], [2, 2, 0]], \"fixed\": true}\n"
    "  ],\n"
    "  \"time\": {\"integrator\": \"backward_euler\", \"dt\": 0.05, \"steps\": 40},\n"
    "  \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\", \"max_iters\": 200}\n"
    "}\n",
};
