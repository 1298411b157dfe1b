/* The documented sections of the scene configuration, for `elastopt help`, the config
 * reference (docs/config-reference.md) and the JSON Schema (docs/scene.schema.json): the
 * scene loader's own sections, the material section, the solver section, and the keys
 * whose values are not params sections (lists, boxes: documented here with the JSON
 * Schema of their value). Method parameter sections (solver.<name>) come from the
 * registries, so a registered plug-in's parameters are documented too. */
#include <jansson.h>
#include <string.h>

#include "elastopt/config.h"
#include "elastopt/material.h"
#include "elastopt/scene.h"
#include "elastopt/impl/method.h"
#include "elastopt/impl/term.h"
#include "obstacle.h"

#define EO_MAX_DOCS 96

#define VEC3 "{\"type\": \"array\", \"items\": {\"type\": \"number\"}, \"minItems\": 3, \"maxItems\": 3}"
#define BOX "{\"type\": \"array\", \"items\": " VEC3 ", \"minItems\": 2, \"maxItems\": 2}"

/* Keys the scene loader reads itself (not through a params table). */
static const eo_cfg_raw_doc raw_docs[] = {
    {"mesh.points", "{\"type\": \"array\", \"items\": " VEC3 ", \"minItems\": 1}",
     "[[x,y,z], ...] vertices without tets: a pure mass-spring model (mass from point_mass, point_masses)"},
    {"materials", NULL,
     "list of material regions; each entry selects tets by `attribute` (mesh tet attribute) or `box` (tet "
     "centroid inside [[lo],[hi]]) and sets any key of `material` (inherited otherwise); the last match wins"},
    {"materials.N.attribute", "{\"type\": \"integer\"}", "select the tets whose mesh attribute equals this integer"},
    {"materials.N.box", BOX, "select the tets whose centroid is inside [[x0,y0,z0],[x1,y1,z1]]"},
    {"boundary", NULL, "list of constrained vertex sets, later entries override earlier ones; with time.integrator = static a body left with a rigid-body mode that gravity does not hold (no constrained vertex, one point, a vertical line) is an error at load naming the mode (docs/diagnostics.md)"},
    {"boundary.N.box", BOX,
     "select rest vertices inside [[x0,y0,z0],[x1,y1,z1]] (inclusive, tolerance 1e-9 of the mesh size)"},
    {"collisions", NULL, "list of static obstacles (plane, sphere, box): penalty contact, optional Coulomb friction"},
    {"point_masses",
     "{\"type\": \"array\", \"items\": {\"type\": \"array\", \"prefixItems\": [{\"type\": \"integer\", \"minimum\": 0}, "
     "{\"type\": \"number\", \"minimum\": 0}], \"minItems\": 2, \"maxItems\": 2}}",
     "[[vertex, kg], ...]: point masses added to single vertices (0-based)"},
    {"springs.list",
     "{\"type\": \"array\", \"items\": {\"type\": \"array\", \"items\": {\"type\": \"integer\", \"minimum\": 0}, "
     "\"minItems\": 2, \"maxItems\": 2}}",
     "[[i, j], ...]: scene springs between vertex pairs (springs.edges = \"list\")"},
    {"solver.fallback", "{\"type\": \"array\", \"items\": {\"type\": \"object\"}, \"maxItems\": 7}",
     "fallback chain: list of solver sections, each merged over `solver` (keys it names replace those); a "
     "step that stops diverged_* (not diverged_external) is solved again with the next entry, from where "
     "solver.fallback_start says"},
    {"solver.fallback_start", "{\"enum\": [\"best\", \"guess\"], \"default\": \"best\"}",
     "where a fallback entry starts: best = the iterate of lowest g so far (the starting guess or an earlier "
     "entry's end point), guess = the step's starting guess (each entry from scratch)"},
    {NULL, NULL, NULL},
};

#define EO_MAX_RAW_DOCS 64

/* raw_docs, then those of the registered terms (eo_term_type.raw_docs) */
const eo_cfg_raw_doc *eo_config_raw_docs(void)
{
    static eo_cfg_raw_doc all[EO_MAX_RAW_DOCS];
    static int built = 0;
    if (built) return all;
    int n = 0;
    for (const eo_cfg_raw_doc *d = raw_docs; d->path && n < EO_MAX_RAW_DOCS - 1; d++) all[n++] = *d;
    for (const void *const *t = eo_registry_list(EO_KIND_TERM); t && *t; t++)
        for (const eo_cfg_raw_doc *d = ((const eo_term_type *)*t)->raw_docs; d && d->path && n < EO_MAX_RAW_DOCS - 1; d++)
            all[n++] = *d;
    all[n] = (eo_cfg_raw_doc){NULL, NULL, NULL};
    built = 1;
    return all;
}

const eo_cfg_doc *eo_config_docs(void)
{
    static eo_cfg_doc docs[EO_MAX_DOCS];
    static int built = 0;
    if (built) return docs;
    int n = 0;
    for (const eo_cfg_doc *d = eo_scene_docs; d->path && n < EO_MAX_DOCS - 24; d++) docs[n++] = *d;
    for (const eo_obstacle_type *const *t = eo_obstacle_types; *t && n < EO_MAX_DOCS - 3; t++)
        docs[n++] = (eo_cfg_doc){(*t)->doc_path, (*t)->params, (*t)->summary};
    /* the sections of the registered terms (a list section's entries at section.N) */
    static char term_path[24][64];
    int nt = 0;
    for (const void *const *t = eo_registry_list(EO_KIND_TERM); t && *t && nt < 24 && n < EO_MAX_DOCS - 3; t++) {
        const eo_term_type *tt = *t;
        if (!tt->section || !tt->info.params) continue;
        snprintf(term_path[nt], sizeof term_path[nt], "%s%s", tt->section, tt->flags & EO_TERM_SECTION_LIST ? ".N" : "");
        docs[n++] = (eo_cfg_doc){term_path[nt++], tt->info.params, tt->info.summary};
        for (const eo_cfg_doc *d = tt->sub_docs; d && d->path && n < EO_MAX_DOCS - 3; d++) docs[n++] = *d;
    }
    docs[n++] = (eo_cfg_doc){"material", eo_material_opts_desc,
                             "default material of every tet (and of each `materials` list entry)"};
    docs[n++] = (eo_cfg_doc){"solver", eo_solver_opts_desc,
                             "how each step is minimized; per-method parameters in solver.<method>"};
    docs[n] = (eo_cfg_doc){NULL, NULL, NULL};
    built = 1;
    return docs;
}

/* The object schema at a dotted path below root, created as needed; "N" components are
 * list items. */
static json_t *node_at(json_t *root, const char *path)
{
    json_t *node = root;
    char buf[256];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *save = NULL, *c = strtok_r(buf, ".", &save); c; c = strtok_r(NULL, ".", &save)) {
        if (strcmp(c, "N") == 0) {
            json_object_set_new(node, "type", json_string("array"));
            json_t *items = json_object_get(node, "items");
            if (!items) {
                items = json_pack("{s:s, s:o, s:b}", "type", "object", "properties", json_object(),
                                  "additionalProperties", 0);
                json_object_set_new(node, "items", items);
            }
            node = items;
            continue;
        }
        if (!json_object_get(node, "type")) json_object_set_new(node, "type", json_string("object"));
        json_t *props = json_object_get(node, "properties");
        if (!props) {
            props = json_object();
            json_object_set_new(node, "properties", props);
            json_object_set_new(node, "additionalProperties", json_false());
        }
        json_t *child = json_object_get(props, c);
        if (!child) {
            child = json_object();
            json_object_set_new(props, c, child);
        }
        node = child;
    }
    return node;
}

/* Merge the keys of src (an object schema) into dst. */
static void merge(json_t *dst, json_t *src)
{
    const char *k;
    json_t *v;
    json_object_foreach(src, k, v) {
        if (strcmp(k, "properties") == 0) {
            json_t *props = json_object_get(dst, "properties");
            if (!props) {
                props = json_object();
                json_object_set_new(dst, "properties", props);
            }
            const char *pk;
            json_t *pv;
            json_object_foreach(v, pk, pv) {
                json_t *have = json_object_get(props, pk);
                if (have && json_object_get(have, "properties")) continue; /* a section wins over a key */
                json_object_set(props, pk, pv);
            }
        } else if (!json_object_get(dst, k)) {
            json_object_set(dst, k, v);
        }
    }
}

json_t *eo_cfg_docs_schema(const eo_cfg_doc *docs, const eo_cfg_raw_doc *raw, const char *title,
                           const char *description)
{
    json_t *root = json_pack("{s:s, s:s, s:s}", "$schema", "https://json-schema.org/draft/2020-12/schema", "title",
                             title, "type", "object");
    if (!root) return NULL;
    if (description) json_object_set_new(root, "description", json_string(description));
    for (const eo_cfg_doc *d = docs; d && d->path; d++) {
        json_t *node = d->path[0] ? node_at(root, d->path) : root;
        json_t *s = eo_params_schema(d->params, d->summary);
        merge(node, s);
        json_decref(s);
    }
    for (const eo_cfg_raw_doc *d = raw; d && d->path; d++) {
        json_t *node = node_at(root, d->path);
        if (d->schema) {
            json_t *s = json_loads(d->schema, 0, NULL);
            if (s) {
                merge(node, s);
                json_decref(s);
            }
        }
        if (!json_object_get(node, "description")) json_object_set_new(node, "description", json_string(d->summary));
    }
    return root;
}

json_t *eo_config_schema(void)
{
    json_t *root = eo_cfg_docs_schema(eo_config_docs(), eo_config_raw_docs(), "elastopt scene",
                                      "A scene configuration of elastopt (generated from the descriptor tables by "
                                      "`elastopt help --schema scene`).");
    if (!root) return NULL;
    /* each materials entry takes the material keys too */
    json_t *mat_items = node_at(root, "materials.N");
    json_t *ms = eo_params_schema(eo_material_opts_desc, NULL);
    merge(mat_items, ms);
    json_decref(ms);
    /* solver.<method>: the parameters of every registered method of the solver kinds */
    json_t *solver = node_at(root, "solver");
    eo_kind kinds[] = {EO_KIND_OPTIMIZER, EO_KIND_HESSFIX, EO_KIND_LINESEARCH, EO_KIND_STOP, EO_KIND_LINSOLVE};
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
        for (const void *const *t = eo_registry_list(kinds[i]); t && *t; t++) {
            const eo_method_info *mi = eo_method_info_of(*t);
            if (!mi->params || !mi->params_size) continue;
            char path[96];
            snprintf(path, sizeof path, "%s", mi->name);
            json_t *props = json_object_get(solver, "properties");
            if (json_object_get(props, path)) continue;
            json_object_set_new(props, path, eo_params_schema(mi->params, mi->summary));
        }
    /* time.<integrator>: the parameters of every registered integrator that has some */
    json_t *time = node_at(root, "time");
    for (const void *const *t = eo_registry_list(EO_KIND_INTEGRATOR); t && *t; t++) {
        const eo_method_info *mi = eo_method_info_of(*t);
        if (!mi->params || !mi->params_size) continue;
        json_t *props = json_object_get(time, "properties");
        if (props && !json_object_get(props, mi->name))
            json_object_set_new(props, mi->name, eo_params_schema(mi->params, mi->summary));
    }
    return root;
}
