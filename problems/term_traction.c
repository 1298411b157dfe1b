/* Surface traction term: −w · Σ_faces ∫ t·x dA over selected faces of the rest boundary,
 * a dead load t (Pa: force per unit rest area, constant; ramped by time.load_steps like
 * gravity). Linear in x (no Hessian): −w fᵀx with f the consistent nodal loads
 * f_a = t ∫ N_a dA of the face's element:
 *   3-node triangle (linear tets: p1, p1anp)     A/3 at each corner;
 *   6-node triangle (10-node tets: p2, p2p0)     0 at the corners, A/3 at each midside
 *                                                node (the face's edge nodes of its tet).
 * Σ_a f_a = t·A exactly (up to rounding) for both.
 *
 * Scene section `tractions`: a list; each entry selects faces by exactly one of
 *   box   [[x0,y0,z0],[x1,y1,z1]]: the boundary faces (faces of one tet) whose rest
 *         centroid is inside (tolerance 1e-9 of the mesh size)
 *   plane {point, normal}: the boundary faces whose rest centroid c has
 *         (c − point)·normal >= 0 (same tolerance)
 *   tag   the mesh's tagged triangles with this tag (Gmsh physical surface, ...)
 * and gives the traction vector `t`. The loads are computed at scene load (the section's
 * config is the nodal load vector per unit weight). This file and one registry line
 * are the whole term (impl/term.h). */
#include <jansson.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/config.h"
#include "elastopt/scene.h"
#include "term.h"

typedef struct traction_opts {
    double t[3];
    int tag;
} traction_opts;

static const eo_param_desc traction_desc[] = {
    {.key = "t", .kind = EO_PARAM_VEC3, .offset = offsetof(traction_opts, t), .def.v = {0, 0, 0},
     .help = "traction vector (Pa: force per unit rest area), a dead load on the selected faces; ramped by "
             "time.load_steps like gravity"},
    {.key = "tag", .kind = EO_PARAM_INT, .offset = offsetof(traction_opts, tag), .def.i = 0,
     .help = "select the mesh's tagged triangles with this tag (Gmsh physical surface, MEDIT triangle reference, "
             "TetGen .face marker)"},
    {0},
};

#define VEC3 "{\"type\": \"array\", \"items\": {\"type\": \"number\"}, \"minItems\": 3, \"maxItems\": 3}"
static const eo_cfg_raw_doc traction_raw[] = {
    {"tractions", NULL,
     "list of surface tractions: each entry selects faces (exactly one of box, plane, tag) and gives the traction "
     "t (Pa, per unit rest area; consistent nodal loads of the element's faces)"},
    {"tractions.N.box", "{\"type\": \"array\", \"items\": " VEC3 ", \"minItems\": 2, \"maxItems\": 2}",
     "select the boundary faces whose rest centroid is inside [[x0,y0,z0],[x1,y1,z1]] (tolerance 1e-9 of the mesh "
     "size)"},
    {NULL, NULL, NULL},
};

static const eo_cfg_doc traction_sub_docs[] = {
    {"tractions.N.plane", eo_scene_plane_opts_desc, "select the boundary faces whose rest centroid c has (c - point).normal >= 0"},
    {NULL, NULL, NULL},
};

/* the section's config: the nodal loads f (3·nv) at weight 1 */
typedef struct traction_cfg {
    int n_full;
    double area;     /* total selected rest area (all entries) */
    double *f;
} traction_cfg;

static void free_cfg(eo_ctx *ctx, void *p)
{
    traction_cfg *c = p;
    if (!c) return;
    eo_free(ctx, c->f);
    eo_free(ctx, c);
}

static int read_vec3(const json_t *v, double out[3])
{
    if (!json_is_array(v) || json_array_size(v) != 3) return -1;
    for (int k = 0; k < 3; k++) {
        const json_t *e = json_array_get(v, (size_t)k);
        if (!json_is_number(e) || !isfinite(json_number_value(e))) return -1;
        out[k] = json_number_value(e);
    }
    return 0;
}

/* sorted (a, b) → midside node, for the faces of a 10-node mesh */
typedef struct edge_node {
    int a, b, mid;
} edge_node;

static int cmp_edge(const void *p, const void *q)
{
    const edge_node *x = p, *y = q;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    return (x->b > y->b) - (x->b < y->b);
}

static int edge_mid(const edge_node *e, int ne, int a, int b)
{
    edge_node key = {a < b ? a : b, a < b ? b : a, -1};
    const edge_node *hit = bsearch(&key, e, (size_t)ne, sizeof *e, cmp_edge);
    return hit ? hit->mid : -1;
}

/* loads of one face (corners c[3], midside nodes mid[3] or NULL) with traction t into f */
static double add_face(const eo_mesh *m, const int c[3], const int *mid, const double t[3], double *f)
{
    const double *A = m->X + 3 * c[0], *B = m->X + 3 * c[1], *C = m->X + 3 * c[2];
    double u[3], v[3];
    for (int k = 0; k < 3; k++) u[k] = B[k] - A[k], v[k] = C[k] - A[k];
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double area = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const int *nodes = mid ? mid : c; /* 6-node triangle: ∫N = 0 at corners, A/3 at midsides */
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++) f[3 * nodes[a] + k] += t[k] * area / 3.0;
    return area;
}

static int load(eo_ctx *ctx, eo_cfg *cfg, const eo_scene *sc, const char *section, void **out)
{
    *out = NULL;
    const eo_mesh *m = sc->mesh;
    json_t *list = eo_cfg_get(cfg, section);
    if (!json_is_array(list))
        return eo_cfg_error(ctx, cfg, section, EO_ERR_TYPE, "expected a list of tractions, got %s",
                            eo_json_type_name(list));
    traction_cfg *c = eo_calloc(ctx, 1, sizeof *c);
    if (!c) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (tractions)");
    *out = c;
    c->n_full = 3 * m->nv;
    c->f = eo_calloc(ctx, (size_t)(c->n_full > 0 ? c->n_full : 1), sizeof(double));
    int *faces = NULL, nf = 0, ne = 0, rc = EO_OK;
    edge_node *edges = NULL;
    if (!c->f) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (tractions)");
    if (m->nt > 0 && (rc = eo_mesh_boundary_faces(ctx, m, &faces, &nf)) < 0) return rc;
    if (m->tet10) { /* the midside node of every tet edge, to find those of a boundary face */
        static const int E[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
        edges = eo_malloc(ctx, 6 * (size_t)(m->nt > 0 ? m->nt : 1) * sizeof *edges);
        if (!edges) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (tractions)");
            goto done;
        }
        for (int k = 0; k < m->nt; k++)
            for (int e = 0; e < 6; e++) {
                const int a = m->tet10[10 * k + E[e][0]], b = m->tet10[10 * k + E[e][1]];
                edges[ne++] = (edge_node){a < b ? a : b, a < b ? b : a, m->tet10[10 * k + 4 + e]};
            }
        qsort(edges, (size_t)ne, sizeof *edges, cmp_edge);
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], m->X[3 * v + k]), hi[k] = fmax(hi[k], m->X[3 * v + k]);
    double diag = 0;
    for (int k = 0; k < 3 && m->nv > 0; k++) diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    const double tol = 1e-9 * (diag > 0 ? sqrt(diag) : 1);
    static const char *const extra[] = {"box", "plane", NULL};
    for (size_t i = 0; i < json_array_size(list); i++) {
        char path[64], sub[96];
        snprintf(path, sizeof path, "%s.%zu", section, i);
        const json_t *item = json_array_get(list, i);
        traction_opts o;
        eo_params_default(traction_desc, &o);
        if ((rc = eo_cfg_section(ctx, cfg, path, traction_desc, &o, extra)) < 0) goto done;
        const json_t *jbox = json_object_get(item, "box"), *jplane = json_object_get(item, "plane");
        const int has_tag = json_object_get(item, "tag") != NULL;
        if ((jbox != NULL) + (jplane != NULL) + has_tag != 1) {
            rc = eo_cfg_error(ctx, cfg, path, EO_ERR_INVALID,
                              "a traction selects faces by exactly one of \"box\", \"plane\", \"tag\" (found %d)",
                              (jbox != NULL) + (jplane != NULL) + has_tag);
            goto done;
        }
        if (!json_object_get(item, "t")) {
            rc = eo_cfg_error(ctx, cfg, path, EO_ERR_INVALID, "a traction needs \"t\": [tx, ty, tz] (Pa)");
            goto done;
        }
        double box[6] = {0}, pp[3] = {0}, pn[3] = {0};
        if (jbox) {
            snprintf(sub, sizeof sub, "%s.box", path);
            jbox = eo_cfg_get(cfg, sub);
            if (!json_is_array(jbox) || json_array_size(jbox) != 2 || read_vec3(json_array_get(jbox, 0), box) < 0 ||
                read_vec3(json_array_get(jbox, 1), box + 3) < 0) {
                rc = eo_cfg_error(ctx, cfg, sub, EO_ERR_TYPE, "expected [[x0,y0,z0],[x1,y1,z1]] (finite numbers)");
                goto done;
            }
        } else if (jplane) { /* the boundary's plane selector */
            eo_scene_plane_opts pl;
            eo_params_default(eo_scene_plane_opts_desc, &pl);
            snprintf(sub, sizeof sub, "%s.plane", path);
            if ((rc = eo_cfg_section(ctx, cfg, sub, eo_scene_plane_opts_desc, &pl, NULL)) < 0) goto done;
            const double nn = sqrt(pl.normal[0] * pl.normal[0] + pl.normal[1] * pl.normal[1] + pl.normal[2] * pl.normal[2]);
            if (!(nn > 0)) {
                snprintf(sub, sizeof sub, "%s.plane.normal", path);
                rc = eo_cfg_error(ctx, cfg, sub, EO_ERR_RANGE, "zero normal");
                goto done;
            }
            for (int k = 0; k < 3; k++) pp[k] = pl.point[k], pn[k] = pl.normal[k] / nn;
        }
        double area = 0;
        int count = 0;
        if (has_tag) {
            for (int q = 0; q < m->ntri; q++) {
                if (m->tri_tag[q] != o.tag) continue;
                area += add_face(m, m->tris + 3 * q, m->tet10 ? m->tri_mid + 3 * q : NULL, o.t, c->f);
                count++;
            }
        } else {
            for (int q = 0; q < nf; q++) {
                const int *fc = faces + 3 * q;
                double ctr[3];
                for (int k = 0; k < 3; k++)
                    ctr[k] = (m->X[3 * fc[0] + k] + m->X[3 * fc[1] + k] + m->X[3 * fc[2] + k]) / 3.0;
                int hit = 1;
                if (jbox)
                    for (int k = 0; k < 3; k++) hit &= ctr[k] >= box[k] - tol && ctr[k] <= box[3 + k] + tol;
                else
                    hit = (ctr[0] - pp[0]) * pn[0] + (ctr[1] - pp[1]) * pn[1] + (ctr[2] - pp[2]) * pn[2] >= -tol;
                if (!hit) continue;
                int mid[3];
                if (m->tet10) {
                    for (int a = 0; a < 3; a++) mid[a] = edge_mid(edges, ne, fc[a], fc[(a + 1) % 3]);
                    if (mid[0] < 0 || mid[1] < 0 || mid[2] < 0) {
                        rc = eo_error(ctx, EO_ERR_INTERNAL, "tractions: boundary face %d has no midside node", q);
                        goto done;
                    }
                }
                area += add_face(m, fc, m->tet10 ? mid : NULL, o.t, c->f);
                count++;
            }
        }
        if (!count) {
            rc = eo_cfg_error(ctx, cfg, path, EO_ERR_INVALID, "traction entry selects no %s",
                              has_tag ? "tagged triangle" : "boundary face");
            goto done;
        }
        eo_log(ctx, EO_LOG_DEBUG, "%s: %d faces, rest area %g", path, count, area);
        c->area += area;
    }
done:
    eo_free(ctx, faces);
    eo_free(ctx, edges);
    return rc;
}

/* ---------------------------------------------------------------- the term: −w fᵀx */

static double energy(eo_term *t, const eo_sys *s, const double *x)
{
    double e = 0;
    for (int v = 0; v < s->nv; v++)
        if (eo_sys_vertex_on(s, v))
            for (int c = 0; c < 3; c++) e -= t->vec[3 * v + c] * x[3 * v + c];
    return t->weight * e;
}

static double gradient(eo_term *t, const eo_sys *s, const double *x, double *grad)
{
    for (int v = 0; v < s->nv; v++)
        for (int c = 0; c < 3 && eo_sys_vertex_on(s, v); c++) grad[3 * v + c] -= t->weight * t->vec[3 * v + c];
    return energy(t, s, x);
}

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    (void)t, (void)s, (void)x, (void)proj;
    return EO_OK;
}

static double vertex(eo_term *t, const eo_sys *s, const double *x, int v, eo_proj proj, double *g3, double *H3)
{
    (void)s, (void)proj, (void)H3;
    double e = 0;
    for (int c = 0; c < 3; c++) {
        e -= t->weight * t->vec[3 * v + c] * x[3 * v + c];
        if (g3) g3[c] -= t->weight * t->vec[3 * v + c];
    }
    return e;
}

static const eo_term_ops traction_ops = {
    .name = "traction",
    .energy = energy,
    .gradient = gradient,
    .hessian = hessian,
    .vertex = vertex,
};

static int create(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out)
{
    (void)sc;
    const traction_cfg *c = cfg;
    *out = NULL;
    if (!c) return EO_OK;
    if (c->n_full != s->n_full)
        return eo_error(s->ctx, EO_ERR_INVALID, "tractions: loads of %d coordinates for a mesh of %d", c->n_full,
                        s->n_full);
    int rc = eo_term_alloc(s, &traction_ops, 1, out);
    if (rc < 0) return rc;
    memcpy((*out)->vec, c->f, (size_t)s->n_full * sizeof(double));
    return EO_OK;
}

const eo_term_type eo_term_type_traction = {
    .info = {.name = "traction",
             .summary = "surface tractions (`tractions`): dead loads t (Pa) on selected boundary faces, consistent "
                        "nodal loads",
             .params = traction_desc,
             .params_size = sizeof(traction_opts)},
    .section = "tractions",
    .flags = EO_TERM_POTENTIAL | EO_TERM_LOAD_STEPPED | EO_TERM_SECTION_LIST,
    .raw_docs = traction_raw,
    .sub_docs = traction_sub_docs,
    .load = load,
    .free_cfg = free_cfg,
    .create = create,
};
