/* Built-in scene `stretch`: bar stretched by its right end, then released.
 * The same text as examples/stretch.json (a test checks both parse to equal JSON). */
#include "elastopt/scene.h"

const eo_scene_type eo_scene_stretch = {
    .info = {.name = "stretch", .summary = "bar stretched by its right end, then released"},
    .json =
    "{\n"
    "  \"description\": \"Stretch and release: the right end of a bar clamped at x = 0 is pulled at 0.5 m/s for 0.2 s (10% strain), held, and released at 0.3 s.\",\n"
    "  \"mesh\": {\"generate\": {\"size\": [1.0, 0.1, 0.1], \"cells\": [20, 2, 2], \"split\": 5}},\n"
    "  \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e6, \"nu\": 0.3, \"density\": 1000},\n"
    "  \"gravity\": [0, 0, 0],\n"
    "  \"boundary\": [\n"
    "    {\"box\": [[-1, -1, -1], [0, 1, 1]], \"fixed\": true},\n"
    "    {\"plane\": {\"point\": [1, 0, 0], \"normal\": [1, 0, 0]}, \"translate\": [0.5, 0, 0], \"until\": 0.2, \"release\": 0.3}\n"
    "  ],\n"
    "  \"time\": {\"integrator\": \"newmark\", \"dt\": 0.01, \"steps\": 60},\n"
    "  \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\"}\n"
    "}\n",
};
