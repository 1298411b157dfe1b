/* The documented sections of the scene configuration, for `elastopt help` and the
 * README's config reference: the scene loader's own sections, the material section
 * and the solver section. Method parameter sections (solver.<name>) come from the
 * registries, so they are not listed here. */
#include "elastopt/config.h"
#include "elastopt/material.h"
#include "elastopt/scene.h"
#include "elastopt/solver.h"

#define EO_MAX_DOCS 64

const eo_cfg_doc *eo_config_docs(void)
{
    static eo_cfg_doc docs[EO_MAX_DOCS];
    static int built = 0;
    if (built) return docs;
    int n = 0;
    for (const eo_cfg_doc *d = eo_scene_docs; d->path && n < EO_MAX_DOCS - 3; d++) docs[n++] = *d;
    docs[n++] = (eo_cfg_doc){"material", eo_material_opts_desc,
                             "default material of every tet (and of each `materials` list entry)"};
    docs[n++] = (eo_cfg_doc){"solver", eo_solver_opts_desc,
                             "how each step is minimized; per-method parameters in solver.<method>"};
    docs[n] = (eo_cfg_doc){NULL, NULL, NULL};
    built = 1;
    return docs;
}
