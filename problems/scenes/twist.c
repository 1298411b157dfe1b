/* Built-in scene `twist`: bar whose ends rotate in opposite directions.
 * The same text as examples/twist.json (a test checks both parse to equal JSON). */
#include "elastopt/scene.h"

const eo_scene_type eo_scene_twist = {
    .info = {.name = "twist", .summary = "bar whose ends rotate in opposite directions"},
    .json =
    "{\n"
    "  \"description\": \"Twisting bar: the two ends of a 1 x 0.1 x 0.1 m bar are rotated in opposite directions about its axis, half a turn in total over 0.5 s.\",\n"
    "  \"mesh\": {\"generate\": {\"size\": [1.0, 0.1, 0.1], \"cells\": [20, 2, 2], \"split\": 5}},\n"
    "  \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e6, \"nu\": 0.4, \"density\": 1000},\n"
    "  \"gravity\": [0, 0, 0],\n"
    "  \"boundary\": [\n"
    "    {\"box\": [[-1, -1, -1], [0, 1, 1]], \"rotate\": {\"axis\": [1, 0, 0], \"center\": [0, 0.05, 0.05], \"rate\": 3.14159265}},\n"
    "    {\"box\": [[1, -1, -1], [2, 1, 1]], \"rotate\": {\"axis\": [1, 0, 0], \"center\": [0, 0.05, 0.05], \"rate\": -3.14159265}}\n"
    "  ],\n"
    "  \"time\": {\"integrator\": \"newmark\", \"dt\": 0.01, \"steps\": 50},\n"
    "  \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\"}\n"
    "}\n",
};
