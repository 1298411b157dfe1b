/* Built-in scene `drop`: a box dropped on a ground plane (penalty collisions), comes to rest.
 * The same text as examples/drop.json (a test checks both parse to equal JSON). */
#include "elastopt/scene.h"

const eo_scene_type eo_scene_drop = {
    .info = {.name = "drop", .summary = "box dropped on a ground plane (penalty contact), backward Euler"},
    .json =
    "{\n"
    "  \"description\": \"Drop: a 0.2 m box (8 kg) falls 5 cm onto the plane z = 0 and comes to rest; penalty contact k/2 max(0, -(x-p).n)^2 per vertex: the 9 bottom vertices sink M g/(9 k) = 8.7e-5 m. Backward Euler damps the impact.\",\n"
    "  \"mesh\": {\"generate\": {\"size\": [0.2, 0.2, 0.2], \"cells\": [2, 2, 2], \"split\": 5, \"origin\": [0, 0, 0.05]}},\n"
    "  \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e7, \"nu\": 0.3, \"density\": 1000},\n"
    "  \"mass\": \"consistent\",\n"
    "  \"gravity\": [0, 0, -9.81],\n"
    "  \"collisions\": [\n"
    "    {\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 0, 1]}, \"stiffness\": 1e5}\n"
    "  ],\n"
    "  \"time\": {\"integrator\": \"backward_euler\", \"dt\": 0.01, \"steps\": 100},\n"
    "  \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\", \"tol\": 1e-14, \"max_iters\": 100},\n"
    "  \"output\": {\"every\": 5, \"vtu\": true}\n"
    "}\n",
};
