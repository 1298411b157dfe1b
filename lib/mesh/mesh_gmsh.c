/* Gmsh .msh reader (ASCII 2.2 and 4.1) and writer (ASCII 4.1).
 *
 * Reference: Gmsh reference manual, "MSH file format" (versions 2 and 4.1).
 *  2.2  $Nodes: n, then "tag x y z"; $Elements: n, then
 *       "tag type ntags tag1..tagN node1..nodeK" — tag1 is the physical group.
 *  4.1  $Nodes: "numBlocks numNodes minTag maxTag", per block "dim entity parametric n",
 *       n tags, then n lines "x y z [u v w]"; $Elements: "numBlocks numElements minTag
 *       maxTag", per block "dim entity type n", then n lines "tag node1..nodeK".
 *  4.1  $Entities: "nP nC nS nV", then one line per entity: "tag [x y z | 6 bbox
 *       numbers] numPhysicalTags physicalTags... [bounding entities...]".
 * Tets (type 4, or type 11: 10-node tets, giving an order-2 mesh) and triangles (type 2,
 * or type 9: 6-node triangles, of which the 3 corners are kept; their midside nodes are
 * the tets' ones) are kept. Gmsh lists a 10-node tet's nodes as the corners, then the
 * nodes of edges 01, 12, 20, 30, 32, 31 (manual, "Node ordering"): the last two are the
 * other way round from the VTK order of tet10 (edges ..., 13, 23), so both the reader
 * and the writer swap nodes 8 and 9. A file mixing types 4 and 11 is an error. tet_attr is the physical tag (2.2: the
 * first element tag, 0 if none; 4.1: the first physical tag of the tet's volume entity
 * in $Entities, else the entity tag). Triangles become tagged triangles (tris/tri_tag)
 * with the same rule, except that a 4.1 surface entity in several physical groups gives
 * its triangles once per group. Every other element type and every other section
 * ($PhysicalNames, IPC's $Surface, ...) is skipped line by line.
 * The writer emits one node block and one element block per run of equal tet_attr
 * (type 11 for an order-2 mesh). */
#include <string.h>

#include "elastopt/io.h"
#include "mesh_io.h"
#include "../textscan.h"

typedef struct {
    eo_scan s;
    eo_ctx *ctx;
    eo_mesh_src *src;
    eo_mesh *m;      /* created at $Nodes with its vertices */
    long *tags;      /* node tags */
    eo_tagmap map;
    int v41;         /* 1: version 4.1, 0: 2.x */
    int cap;         /* tet capacity */
    int n4, n10;     /* tets read of 4 and 10 nodes */
    int tcap;        /* triangle capacity */
    /* 4.1 $Entities of dimension 2 and 3: tag, physical tags ent_phys[first .. first+n) */
    long *ent_tag[2];
    int *ent_first[2], *ent_n[2], nent[2];
    long *ent_phys;
    int nphys, physcap;
} gmsh_reader;

static int make_map(gmsh_reader *r)
{
    int dup = -1;
    int rc = eo_tagmap_build(r->ctx, r->tags, r->m->nv, &r->map, &dup);
    if (rc == EO_ERR_PARSE)
        return eo_error_at(r->ctx, rc, EO_ERRLOC_ITEM(r->s.file, r->src->v_line[dup], "vertex", r->tags[dup]),
                           "node tag repeated; expected unique node tags");
    return rc;
}

static int alloc_nodes(gmsh_reader *r, int n)
{
    if (r->m) return eo_scan_error(&r->s, EO_ERR_PARSE, "second $Nodes section; expected one");
    int rc = eo_mesh_create(r->ctx, n, 0, &r->m);
    if (rc < 0) return rc;
    r->m->nt = 0;
    r->tags = eo_malloc(r->ctx, (size_t)(n ? n : 1) * sizeof(long));
    if (!r->tags) return eo_error(r->ctx, EO_ERR_NOMEM, "out of memory (node tags)");
    return eo_mesh_src_alloc(r->ctx, r->src, n, -1);
}

static int read_xyz(gmsh_reader *r, int i)
{
    eo_scan *s = &r->s;
    double *x = r->m->X + 3 * i;
    int rc;
    if ((rc = eo_scan_double(s, "x coordinate", &x[0])) < 0) return rc;
    if ((rc = eo_scan_double(s, "y coordinate", &x[1])) < 0) return rc;
    return eo_scan_double(s, "z coordinate", &x[2]);
}

static int nodes_22(gmsh_reader *r)
{
    eo_scan *s = &r->s;
    int n, rc;
    if ((rc = eo_scan_count(s, "node count", &n)) < 0) return rc;
    if ((rc = alloc_nodes(r, n)) < 0) return rc;
    for (int i = 0; i < n; i++) {
        eo_scan_item(s, NULL, -1);
        r->src->v_line[i] = eo_scan_record(s);
        if ((rc = eo_scan_long(s, "node tag", &r->tags[i])) < 0) return rc;
        r->src->v_id[i] = r->tags[i];
        eo_scan_item(s, "vertex", r->tags[i]);
        if ((rc = read_xyz(r, i)) < 0) return rc;
        if ((rc = eo_scan_eol(s, "x y z")) < 0) return rc;
    }
    eo_scan_item(s, NULL, -1);
    if ((rc = eo_scan_expect(s, "$EndNodes")) < 0) return rc;
    return make_map(r);
}

static int nodes_41(gmsh_reader *r)
{
    eo_scan *s = &r->s;
    int nb, n, rc;
    long mintag, maxtag;
    if ((rc = eo_scan_count(s, "node block count", &nb)) < 0) return rc;
    if ((rc = eo_scan_count(s, "node count", &n)) < 0) return rc;
    if ((rc = eo_scan_long(s, "minimum node tag", &mintag)) < 0) return rc;
    if ((rc = eo_scan_long(s, "maximum node tag", &maxtag)) < 0) return rc;
    if ((rc = alloc_nodes(r, n)) < 0) return rc;
    int done = 0;
    for (int b = 0; b < nb; b++) {
        int dim, param, k;
        long ent;
        if ((rc = eo_scan_int(s, "entity dimension", 0, 3, &dim)) < 0) return rc;
        if ((rc = eo_scan_long(s, "entity tag", &ent)) < 0) return rc;
        if ((rc = eo_scan_int(s, "parametric flag", 0, 1, &param)) < 0) return rc;
        if ((rc = eo_scan_count(s, "nodes in block", &k)) < 0) return rc;
        if (k > n - done)
            return eo_scan_error(s, EO_ERR_PARSE, "block of %d nodes exceeds the %d announced in the $Nodes header",
                                 k, n);
        for (int i = done; i < done + k; i++) {
            r->src->v_line[i] = eo_scan_record(s);
            if ((rc = eo_scan_long(s, "node tag", &r->tags[i])) < 0) return rc;
            r->src->v_id[i] = r->tags[i];
            if ((rc = eo_scan_eol(s, "a node tag")) < 0) return rc;
        }
        for (int i = done; i < done + k; i++) {
            eo_scan_item(s, "vertex", r->tags[i]);
            r->src->v_line[i] = eo_scan_record(s);
            if ((rc = read_xyz(r, i)) < 0) return rc;
            for (int p = 0; p < (param ? dim : 0); p++) {
                double u;
                if ((rc = eo_scan_double(s, "parametric coordinate", &u)) < 0) return rc;
            }
            if ((rc = eo_scan_eol(s, "x y z")) < 0) return rc;
        }
        eo_scan_item(s, NULL, -1);
        done += k;
    }
    if (done != n) {
        char w[96];
        snprintf(w, sizeof w, "another node block (%d of %d nodes read)", done, n);
        return eo_scan_fail(s, w);
    }
    if ((rc = eo_scan_expect(s, "$EndNodes")) < 0) return rc;
    for (int i = 0; i < n; i++)
        if (r->tags[i] < mintag || r->tags[i] > maxtag)
            return eo_error_at(r->ctx, EO_ERR_PARSE, EO_ERRLOC_ITEM(s->file, r->src->v_line[i], "vertex", r->tags[i]),
                               "expected a node tag in [%ld, %ld] as the $Nodes header says", mintag, maxtag);
    return make_map(r);
}

static int alloc_elements(gmsh_reader *r, int n)
{
    if (!r->m) return eo_scan_error(&r->s, EO_ERR_PARSE, "$Elements before $Nodes; expected $Nodes first");
    if (r->cap) return eo_scan_error(&r->s, EO_ERR_PARSE, "second $Elements section; expected one");
    eo_mesh *m = r->m;
    r->cap = n ? n : 1;
    eo_free(r->ctx, m->tets);
    m->tets = eo_malloc(r->ctx, (size_t)r->cap * 4 * sizeof(int));
    m->tet_attr = eo_malloc(r->ctx, (size_t)r->cap * sizeof(int));
    if (!m->tets || !m->tet_attr) return eo_error(r->ctx, EO_ERR_NOMEM, "out of memory (%d elements)", n);
    return eo_mesh_src_alloc(r->ctx, r->src, -1, r->cap);
}

/* Gmsh -> VTK order of a 10-node tet (an involution): vtk[i] = gmsh[gmsh_tet10[i]] */
static const int gmsh_tet10[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};

/* Read the nn (4 or 10) node tags of tet `tag` on the current line into the next tet slot. */
static int read_tet(gmsh_reader *r, long tag, long line, int attr, int nn)
{
    eo_scan *s = &r->s;
    eo_mesh *m = r->m;
    int t = m->nt, rc, v[10];
    eo_scan_item(s, "tet", tag);
    if ((nn == 10 && r->n4) || (nn == 4 && r->n10))
        return eo_scan_error(s, EO_ERR_MESH,
                             "a %d-node tet (element type %d) in a mesh of %d-node tets; expected one kind of tet",
                             nn, nn == 10 ? 11 : 4, nn == 10 ? 4 : 10);
    if (nn == 10 && !m->tet10 && !(m->tet10 = eo_malloc(r->ctx, (size_t)r->cap * 10 * sizeof(int))))
        return eo_error(r->ctx, EO_ERR_NOMEM, "out of memory (%d 10-node tets)", r->cap);
    for (int a = 0; a < nn; a++) {
        long nt;
        if ((rc = eo_scan_long(s, "node tag", &nt)) < 0) return rc;
        v[a] = eo_tagmap_find(&r->map, nt);
        if (v[a] < 0) return eo_scan_error(s, EO_ERR_MESH, "node %ld: expected a node tag defined in $Nodes", nt);
    }
    if ((rc = eo_scan_eol(s, nn == 10 ? "the 10 nodes of a tet" : "the 4 nodes of a tet")) < 0) return rc;
    memcpy(m->tets + 4 * t, v, 4 * sizeof(int));
    if (nn == 10)
        for (int a = 0; a < 10; a++) m->tet10[10 * t + a] = v[gmsh_tet10[a]];
    r->n4 += nn == 4;
    r->n10 += nn == 10;
    eo_scan_item(s, NULL, -1);
    m->tet_attr[t] = attr;
    r->src->t_line[t] = line;
    r->src->t_id[t] = tag;
    m->nt++;
    return EO_OK;
}

/* Read the nn (3 or 6) node tags of a triangle on the current line; add its corners once
 * per tag. */
static int read_tri(gmsh_reader *r, long tag, long line, const long *tags, int ntags, int nn)
{
    eo_scan *s = &r->s;
    int v[6], rc;
    eo_scan_item(s, "triangle", tag);
    for (int a = 0; a < nn; a++) {
        long nt;
        if ((rc = eo_scan_long(s, "node tag", &nt)) < 0) return rc;
        if ((v[a] = eo_tagmap_find(&r->map, nt)) < 0)
            return eo_scan_error(s, EO_ERR_MESH, "node %ld: expected a node tag defined in $Nodes", nt);
    }
    if ((rc = eo_scan_eol(s, nn == 6 ? "the 6 nodes of a triangle" : "the 3 nodes of a triangle")) < 0) return rc;
    eo_scan_item(s, NULL, -1);
    for (int k = 0; k < ntags; k++) {
        if (tags[k] < -2147483647L || tags[k] > 2147483647L)
            return eo_scan_error(s, EO_ERR_PARSE, "physical tag %ld out of range", tags[k]);
        if ((rc = eo_mesh_add_tri(r->ctx, r->m, r->src, &r->tcap, v, (int)tags[k], line)) < 0) return rc;
    }
    return EO_OK;
}

/* 4.1 $Entities: keep the physical tags of surfaces and volumes. */
static int entities_41(gmsh_reader *r)
{
    eo_scan *s = &r->s;
    int cnt[4], rc;
    if (r->nphys || r->ent_tag[0] || r->ent_tag[1])
        return eo_scan_error(s, EO_ERR_PARSE, "second $Entities section; expected one");
    for (int d = 0; d < 4; d++)
        if ((rc = eo_scan_count(s, "entity count", &cnt[d])) < 0) return rc;
    if ((rc = eo_scan_eol(s, "the 4 entity counts")) < 0) return rc;
    for (int d = 2; d < 4; d++) {
        size_t n = (size_t)(cnt[d] ? cnt[d] : 1);
        r->ent_tag[d - 2] = eo_malloc(r->ctx, n * sizeof(long));
        r->ent_first[d - 2] = eo_malloc(r->ctx, n * sizeof(int));
        r->ent_n[d - 2] = eo_malloc(r->ctx, n * sizeof(int));
        if (!r->ent_tag[d - 2] || !r->ent_first[d - 2] || !r->ent_n[d - 2])
            return eo_error(r->ctx, EO_ERR_NOMEM, "out of memory ($Entities)");
    }
    for (int d = 0; d < 4; d++)
        for (int e = 0; e < cnt[d]; e++) {
            long tag;
            int np;
            double x;
            eo_scan_record(s);
            if ((rc = eo_scan_long(s, "entity tag", &tag)) < 0) return rc;
            for (int k = 0; k < (d == 0 ? 3 : 6); k++)
                if ((rc = eo_scan_double(s, d == 0 ? "point coordinate" : "bounding box coordinate", &x)) < 0) return rc;
            if ((rc = eo_scan_int(s, "number of physical tags", 0, 1000000, &np)) < 0) return rc;
            if (d >= 2) {
                r->ent_tag[d - 2][e] = tag;
                r->ent_first[d - 2][e] = r->nphys;
                r->ent_n[d - 2][e] = np;
                r->nent[d - 2] = e + 1;
            }
            for (int k = 0; k < np; k++) {
                long p;
                if ((rc = eo_scan_long(s, "physical tag", &p)) < 0) return rc;
                if (d < 2) continue;
                if (r->nphys == r->physcap) {
                    int nc = r->physcap ? 2 * r->physcap : 16;
                    long *q = eo_realloc(r->ctx, r->ent_phys, (size_t)nc * sizeof(long));
                    if (!q) return eo_error(r->ctx, EO_ERR_NOMEM, "out of memory ($Entities)");
                    r->ent_phys = q;
                    r->physcap = nc;
                }
                r->ent_phys[r->nphys++] = p;
            }
            eo_scan_skip_line(s); /* bounding entities */
            s->in_record = 0;
        }
    return eo_scan_expect(s, "$EndEntities");
}

/* Physical tags of the entity (dim 2 or 3, 4.1): *tags points into ent_phys, or to the
 * entity tag itself when the entity has none (or $Entities is absent). */
static int entity_tags(const gmsh_reader *r, int dim, const long *ent, const long **tags)
{
    for (int e = 0; e < r->nent[dim - 2]; e++)
        if (r->ent_tag[dim - 2][e] == *ent && r->ent_n[dim - 2][e] > 0) {
            *tags = r->ent_phys + r->ent_first[dim - 2][e];
            return r->ent_n[dim - 2][e];
        }
    *tags = ent;
    return 1;
}

static int elements_22(gmsh_reader *r)
{
    eo_scan *s = &r->s;
    int n, rc;
    if ((rc = eo_scan_count(s, "element count", &n)) < 0) return rc;
    if ((rc = alloc_elements(r, n)) < 0) return rc;
    for (int i = 0; i < n; i++) {
        long tag;
        int type, ntags;
        long phys = 0;
        eo_scan_item(s, NULL, -1);
        long line = eo_scan_record(s);
        if ((rc = eo_scan_long(s, "element tag", &tag)) < 0) return rc;
        eo_scan_item(s, "element", tag);
        if ((rc = eo_scan_int(s, "element type", 1, 1000, &type)) < 0) return rc;
        if ((rc = eo_scan_int(s, "number of tags", 0, 1000, &ntags)) < 0) return rc;
        for (int k = 0; k < ntags; k++) {
            long v;
            if ((rc = eo_scan_long(s, "element tag value", &v)) < 0) return rc;
            if (k == 0) phys = v;
        }
        if (type == 4 || type == 11) {
            if (phys < -2147483647L || phys > 2147483647L)
                return eo_scan_error(s, EO_ERR_PARSE, "physical tag %ld out of range", phys);
            if ((rc = read_tet(r, tag, line, (int)phys, type == 11 ? 10 : 4)) < 0) return rc;
        } else if (type == 2 || type == 9) {
            if ((rc = read_tri(r, tag, line, &phys, 1, type == 9 ? 6 : 3)) < 0) return rc;
        } else {
            eo_scan_skip_line(s);
        }
        eo_scan_item(s, NULL, -1);
    }
    return eo_scan_expect(s, "$EndElements");
}

static int elements_41(gmsh_reader *r)
{
    eo_scan *s = &r->s;
    int nb, n, rc;
    long mintag, maxtag;
    if ((rc = eo_scan_count(s, "element block count", &nb)) < 0) return rc;
    if ((rc = eo_scan_count(s, "element count", &n)) < 0) return rc;
    if ((rc = eo_scan_long(s, "minimum element tag", &mintag)) < 0) return rc;
    if ((rc = eo_scan_long(s, "maximum element tag", &maxtag)) < 0) return rc;
    if ((rc = alloc_elements(r, n)) < 0) return rc;
    int done = 0;
    for (int b = 0; b < nb; b++) {
        int dim, type, k;
        long ent;
        if ((rc = eo_scan_int(s, "entity dimension", 0, 3, &dim)) < 0) return rc;
        if ((rc = eo_scan_long(s, "entity tag", &ent)) < 0) return rc;
        if ((rc = eo_scan_int(s, "element type", 1, 1000, &type)) < 0) return rc;
        if ((rc = eo_scan_count(s, "elements in block", &k)) < 0) return rc;
        if (k > n - done)
            return eo_scan_error(s, EO_ERR_PARSE,
                                 "block of %d elements exceeds the %d announced in the $Elements header", k, n);
        const int tet = (type == 4 || type == 11) && dim == 3, tri = (type == 2 || type == 9) && dim == 2;
        if (!tet && !tri) {
            if ((rc = eo_scan_skip_lines(s, k, "element lines")) < 0) return rc;
            done += k;
            continue;
        }
        const long *tags;
        int ntags = entity_tags(r, dim, &ent, &tags);
        if (tet && (tags[0] < -2147483647L || tags[0] > 2147483647L))
            return eo_scan_error(s, EO_ERR_PARSE, "physical tag %ld out of range", tags[0]);
        if ((rc = eo_scan_eol(s, "the element block header")) < 0) return rc;
        for (int i = 0; i < k; i++) {
            long tag;
            long line = eo_scan_record(s);
            if ((rc = eo_scan_long(s, "element tag", &tag)) < 0) return rc;
            if (tet) rc = read_tet(r, tag, line, (int)tags[0], type == 11 ? 10 : 4);
            else rc = read_tri(r, tag, line, tags, ntags, type == 9 ? 6 : 3);
            if (rc < 0) return rc;
        }
        done += k;
    }
    if (done != n) {
        char w[96];
        snprintf(w, sizeof w, "another element block (%d of %d elements read)", done, n);
        return eo_scan_fail(s, w);
    }
    return eo_scan_expect(s, "$EndElements");
}

static int read_gmsh(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src)
{
    gmsh_reader r = {.ctx = ctx, .src = src};
    eo_scan *s = &r.s;
    eo_scan_init(s, ctx, file, text, len, 0);
    int rc = EO_OK;
    if ((rc = eo_scan_gmsh_format(s, &r.v41)) < 0) goto fail;
    for (;;) {
        const char *t;
        size_t n;
        if (!eo_scan_peek(s, &t, &n)) break;
        if (eo_scan_accept(s, "$Nodes")) {
            rc = r.v41 ? nodes_41(&r) : nodes_22(&r);
        } else if (eo_scan_accept(s, "$Elements")) {
            rc = r.v41 ? elements_41(&r) : elements_22(&r);
        } else if (r.v41 && eo_scan_accept(s, "$Entities")) {
            rc = entities_41(&r);
        } else if (t[0] == '$' && n > 1 && !(n > 4 && memcmp(t, "$End", 4) == 0)) {
            s->p += n;
            rc = eo_scan_gmsh_skip_section(s, t, n);
        } else {
            rc = eo_scan_fail(s, "a section such as '$Nodes' or '$Elements'");
        }
        if (rc < 0) goto fail;
    }
    if (!r.m) {
        rc = eo_scan_error(s, EO_ERR_PARSE, "expected a $Nodes section, got end of file");
        goto fail;
    }
    if (!r.cap) {
        rc = eo_scan_error(s, EO_ERR_PARSE, "expected an $Elements section, got end of file");
        goto fail;
    }
    if (r.m->nt == 0) {
        rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_FILE(file, -1),
                         "no tetrahedra (element type 4 or 11) found; expected a volume mesh");
        goto fail;
    }
    if (r.n10) r.m->order = 2;
fail:
    eo_free(ctx, r.tags);
    for (int d = 0; d < 2; d++) {
        eo_free(ctx, r.ent_tag[d]);
        eo_free(ctx, r.ent_first[d]);
        eo_free(ctx, r.ent_n[d]);
    }
    eo_free(ctx, r.ent_phys);
    eo_tagmap_deinit(ctx, &r.map);
    if (rc < 0) eo_mesh_destroy(&r.m);
    *out = r.m;
    return rc;
}

static int write_gmsh(eo_ctx *ctx, const eo_mesh *m, const char *path)
{
    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    FILE *f = eo_afile_fp(af);
    fprintf(f, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    fprintf(f, "$Nodes\n1 %d 1 %d\n3 1 0 %d\n", m->nv, m->nv, m->nv);
    for (int v = 0; v < m->nv; v++) fprintf(f, "%d\n", v + 1);
    for (int v = 0; v < m->nv; v++) {
        char b[3][32];
        fprintf(f, "%s %s %s\n", eo_fmt_double(b[0], m->X[3 * v]), eo_fmt_double(b[1], m->X[3 * v + 1]),
                eo_fmt_double(b[2], m->X[3 * v + 2]));
    }
    fprintf(f, "$EndNodes\n");
    int nblocks = 0;
    for (int t = 0; t < m->nt; t++)
        if (t == 0 || (m->tet_attr && m->tet_attr[t] != m->tet_attr[t - 1])) nblocks++;
    fprintf(f, "$Elements\n%d %d 1 %d\n", nblocks, m->nt, m->nt);
    for (int t = 0; t < m->nt;) {
        int attr = m->tet_attr ? m->tet_attr[t] : 1, e = t + 1;
        while (e < m->nt && (!m->tet_attr || m->tet_attr[e] == attr)) e++;
        fprintf(f, "3 %d %d %d\n", attr, m->tet10 ? 11 : 4, e - t);
        for (; t < e; t++) {
            if (m->tet10) {
                const int *q = m->tet10 + 10 * t;
                fprintf(f, "%d", t + 1);
                for (int a = 0; a < 10; a++) fprintf(f, " %d", q[gmsh_tet10[a]] + 1);
                fputc('\n', f);
                continue;
            }
            const int *q = m->tets + 4 * t;
            fprintf(f, "%d %d %d %d %d\n", t + 1, q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
        }
    }
    fprintf(f, "$EndElements\n");
    return eo_afile_commit(ctx, &af);
}

static const char *const gmsh_exts[] = {".msh", NULL};

const eo_mesh_io_type eo_mesh_io_gmsh = {
    .format = EO_MESH_GMSH,
    .name = "gmsh",
    .exts = gmsh_exts,
    .read_text = read_gmsh,
    .write = write_gmsh,
};
