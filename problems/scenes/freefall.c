/* Built-in scene `freefall`: unconstrained cube falling under gravity.
 * The same text as examples/freefall.json (a test checks both parse to equal JSON). */
#include "elastopt/scene.h"

const eo_scene_type eo_scene_freefall = {
    .info = {.name = "freefall", .summary = "unconstrained cube falling under gravity"},
    .json =
    "{\n"
    "  \"description\": \"Free fall: an unconstrained 0.2 m cube falls under gravity; its centre of mass follows -g t^2/2 and it stays undeformed.\",\n"
    "  \"mesh\": {\"generate\": {\"size\": [0.2, 0.2, 0.2], \"cells\": [3, 3, 3], \"split\": 5}},\n"
    "  \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e6, \"nu\": 0.3, \"density\": 1000},\n"
    "  \"gravity\": [0, 0, -9.81],\n"
    "  \"time\": {\"integrator\": \"newmark\", \"dt\": 0.01, \"steps\": 30},\n"
    "  \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\"}\n"
    "}\n",
};
