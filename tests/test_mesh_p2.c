/* Quadratic (10-node) tet meshes: eo_mesh_to_quadratic on generated boxes (node count =
 * vertices + edges with the edge count from Euler's formula, midpoints, one shared node
 * per edge, tri_mid), round trips through the Gmsh, VTU and TetGen writers and readers,
 * hand-written Gmsh 2.2 / 4.1 type-11 tets read into the VTK order, a real TetGen -o2
 * output (libtet 1.5), reorientation of a negative 10-node tet, drops and renumbering,
 * the structural errors (midside node on a corner, shared by two edges, two nodes on one
 * edge, out of range, 4- and 10-node tets mixed), MEDIT refusals and the VTU frame
 * writer's quadratic cells. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/io.h"
#include "elastopt/mesh.h"
#include "testutil.h"

static char tmp[4096];

static const char *tpath(const char *name)
{
    static char buf[4][8400];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", tmp, name);
    return buf[k];
}

/* VTK quadratic tetra: slot 4 + e holds the node of corners vtk_edge[e] */
static const int vtk_edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

/* Largest distance of a tet10 midside node from the midpoint of its edge. */
static double midpoint_error(const eo_mesh *m)
{
    double worst = 0;
    for (int t = 0; t < m->nt; t++)
        for (int e = 0; e < 6; e++) {
            const int *q = m->tet10 + 10 * t;
            const double *a = m->X + 3 * q[vtk_edge[e][0]], *b = m->X + 3 * q[vtk_edge[e][1]], *c = m->X + 3 * q[4 + e];
            for (int i = 0; i < 3; i++) {
                double d = fabs(c[i] - 0.5 * (a[i] + b[i]));
                if (d > worst) worst = d;
            }
        }
    return worst;
}

/* tets equal the tet10 corners and every tet has positive volume */
static int corners_ok(const eo_mesh *m)
{
    for (int t = 0; t < m->nt; t++) {
        if (memcmp(m->tets + 4 * t, m->tet10 + 10 * t, 4 * sizeof(int)) != 0) return 0;
        if (!(eo_tet_volume(m->X, m->tets + 4 * t) > 0)) return 0;
    }
    return 1;
}

static void expect_err(eo_ctx *ctx, int rc, int want, const char *label, const char *s1, const char *s2)
{
    CHECK(rc == want, "%s: status %s, expected %s (message '%s')", label, eo_status_name(rc), eo_status_name(want),
          eo_ctx_message(ctx));
    if (s1) CHECK(strstr(eo_ctx_message(ctx), s1) != NULL, "%s: message '%s' lacks '%s'", label, eo_ctx_message(ctx), s1);
    if (s2) CHECK(strstr(eo_ctx_message(ctx), s2) != NULL, "%s: message '%s' lacks '%s'", label, eo_ctx_message(ctx), s2);
    eo_ctx_clear_error(ctx);
}

static void test_to_quadratic(int split)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh_gen_opts g = eo_mesh_gen_opts_default();
    g.cells[0] = 3, g.cells[1] = 2, g.cells[2] = 2, g.split = split;
    g.size[0] = 1.5, g.size[1] = 0.7, g.size[2] = 1.1;
    eo_mesh *m = NULL, *q = NULL;
    CHECK(eo_mesh_generate_box(ctx, &g, &m) == EO_OK, "box");
    /* tag the boundary faces, so that tri_mid is exercised */
    int *faces = NULL, nf = 0;
    CHECK(eo_mesh_boundary_faces(ctx, m, &faces, &nf) == EO_OK && nf > 0, "boundary faces");
    m->ntri = nf;
    m->tris = faces;
    m->tri_tag = eo_malloc(ctx, (size_t)nf * sizeof(int));
    for (int f = 0; f < nf; f++) m->tri_tag[f] = 1 + f % 3;
    CHECK(eo_mesh_to_quadratic(ctx, m, &q) == EO_OK && q, "to_quadratic: %s", eo_ctx_message(ctx));
    /* Euler: V - E + F - T = 1 for a ball, F = (4T + boundary faces) / 2 */
    const long F = (4L * m->nt + nf) / 2, E = m->nv + F - m->nt - 1;
    CHECK(q->nv == m->nv + E, "split %d: %d nodes, expected %d vertices + %ld edges", split, q->nv, m->nv, E);
    CHECK(q->order == 2 && q->nt == m->nt && q->tet10 && q->tri_mid && q->ntri == nf, "split %d: order-2 mesh", split);
    CHECK(midpoint_error(q) == 0, "split %d: midside nodes at edge midpoints (error %g)", split, midpoint_error(q));
    CHECK(corners_ok(q), "split %d: tet10 corners = tets", split);
    /* node -> edge must be a function and every node in [nv, nv + E) used: one node per edge */
    int *ea = malloc(2 * (size_t)q->nv * sizeof(int)), bad = 0;
    unsigned char *used = calloc((size_t)q->nv, 1);
    for (int v = 0; v < 2 * q->nv; v++) ea[v] = -1;
    for (int t = 0; t < q->nt; t++)
        for (int e = 0; e < 6; e++) {
            int a = q->tets[4 * t + vtk_edge[e][0]], b = q->tets[4 * t + vtk_edge[e][1]], n = q->tet10[10 * t + 4 + e];
            if (a > b) a ^= b, b ^= a, a ^= b;
            if (n < m->nv) bad++;
            if (ea[2 * n] < 0) ea[2 * n] = a, ea[2 * n + 1] = b;
            else if (ea[2 * n] != a || ea[2 * n + 1] != b) bad++;
            used[n] = 1;
        }
    int nused = 0;
    for (int v = m->nv; v < q->nv; v++) nused += used[v];
    CHECK(bad == 0 && nused == E, "split %d: %d inconsistent edge nodes, %d of %ld edge nodes used", split, bad, nused, E);
    /* tri_mid: the tets' node of each triangle edge (the boundary edges are tet edges) */
    int tbad = 0;
    for (int f = 0; f < nf; f++)
        for (int e = 0; e < 3; e++) {
            int a = q->tris[3 * f + e], b = q->tris[3 * f + (e + 1) % 3], n = q->tri_mid[3 * f + e];
            if (a > b) a ^= b, b ^= a, a ^= b;
            if (n < 0 || n >= q->nv || ea[2 * n] != a || ea[2 * n + 1] != b) tbad++;
        }
    CHECK(tbad == 0, "split %d: %d triangle midside nodes off their edge", split, tbad);
    free(ea);
    free(used);
    /* a valid mesh: validation changes nothing */
    int *copy = malloc(10 * (size_t)q->nt * sizeof(int));
    memcpy(copy, q->tet10, 10 * (size_t)q->nt * sizeof(int));
    CHECK(eo_mesh_validate(ctx, q, NULL, "q") == EO_OK && q->reoriented == 0, "split %d: quadratic mesh valid: %s",
          split, eo_ctx_message(ctx));
    CHECK(memcmp(copy, q->tet10, 10 * (size_t)q->nt * sizeof(int)) == 0, "split %d: validation keeps tet10", split);
    free(copy);
    eo_mesh *qq = NULL;
    expect_err(ctx, eo_mesh_to_quadratic(ctx, q, &qq), EO_ERR_INVALID, "quadratic twice", "quadratic already", NULL);

    /* round trips: same nodes, tets and (to the printed precision: exactly) positions */
    const char *names[] = {"p2.msh", "p2.vtu", "p2.node"};
    for (int i = 0; i < 3; i++) {
        eo_mesh *r = NULL;
        int rc = eo_mesh_write(ctx, q, tpath(names[i]), EO_MESH_AUTO);
        CHECK(rc == EO_OK, "write %s: %s", names[i], eo_ctx_message(ctx));
        rc = eo_mesh_read(ctx, tpath(names[i]), NULL, &r);
        CHECK(rc == EO_OK && r, "read %s: %s", names[i], eo_ctx_message(ctx));
        if (!r) continue;
        CHECK(r->order == 2 && r->nv == q->nv && r->nt == q->nt && r->tet10, "%s: order %d, %d nodes, %d tets", names[i],
              r->order, r->nv, r->nt);
        if (r->nv == q->nv && r->nt == q->nt && r->tet10) {
            CHECK(memcmp(r->tet10, q->tet10, 10 * (size_t)q->nt * sizeof(int)) == 0, "%s: tet10 identical", names[i]);
            CHECK(memcmp(r->tets, q->tets, 4 * (size_t)q->nt * sizeof(int)) == 0, "%s: tets identical", names[i]);
            CHECK(memcmp(r->X, q->X, 3 * (size_t)q->nv * sizeof(double)) == 0, "%s: X identical", names[i]);
        }
        if (i == 2) { /* TetGen keeps the tagged triangles (.face); tri_mid comes from the tets */
            CHECK(r->ntri == q->ntri && r->tri_mid &&
                      memcmp(r->tri_mid, q->tri_mid, 3 * (size_t)q->ntri * sizeof(int)) == 0,
                  "tetgen: %d triangles, tri_mid rebuilt identical", r->ntri);
        }
        eo_mesh_destroy(&r);
    }
    expect_err(ctx, eo_mesh_write(ctx, q, tpath("p2.mesh"), EO_MESH_AUTO), EO_ERR_UNSUPPORTED, "medit write", "MEDIT",
               "10-node");
    eo_mesh_destroy(&q);
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

/* One 10-node tet: corners (0,0,0), (1,0,0), (0,1,0), (0,0,1) (tags 1..4), then tags 5..10
 * on Gmsh's edges 01, 12, 20, 30, 32, 31 */
#define P2_NODES                                                                                                      \
    "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 0.5 0 0\n6 0.5 0.5 0\n7 0 0.5 0\n8 0 0 0.5\n9 0 0.5 0.5\n10 0.5 0 0.5\n"

static void test_gmsh_order(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *g22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n" P2_NODES "$EndNodes\n"
                      "$Elements\n2\n1 9 2 7 1 1 2 3 5 6 7\n2 11 2 5 1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
    const char *g41 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 10 1 10\n3 1 0 10\n1\n2\n3\n4\n5\n6\n7\n8\n9\n10\n"
                      "0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 0 0\n0.5 0.5 0\n0 0.5 0\n0 0 0.5\n0 0.5 0.5\n0.5 0 0.5\n"
                      "$EndNodes\n$Elements\n1 1 1 1\n3 1 11 1\n1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
    const int want[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8}; /* VTK: edge 13 = tag 10, edge 23 = tag 9 */
    const char *text[2] = {g22, g41};
    for (int i = 0; i < 2; i++) {
        eo_mesh *m = NULL;
        int rc = eo_mesh_read_buffer(ctx, text[i], strlen(text[i]), EO_MESH_GMSH, "p2.msh", NULL, &m);
        CHECK(rc == EO_OK && m, "gmsh %s: %s", i ? "4.1" : "2.2", eo_ctx_message(ctx));
        if (!m) continue;
        CHECK(m->order == 2 && m->nt == 1 && m->nv == 10 && memcmp(m->tet10, want, sizeof want) == 0,
              "gmsh %s: tet10 %d %d %d %d | %d %d %d %d %d %d", i ? "4.1" : "2.2", m->tet10[0], m->tet10[1], m->tet10[2],
              m->tet10[3], m->tet10[4], m->tet10[5], m->tet10[6], m->tet10[7], m->tet10[8], m->tet10[9]);
        CHECK(midpoint_error(m) == 0 && corners_ok(m) && m->reoriented == 0, "gmsh %s: midpoints", i ? "4.1" : "2.2");
        if (i == 0) { /* the 6-node triangle (type 9): corners, tri_mid from the tet */
            const int tm[3] = {4, 5, 6};
            CHECK(m->ntri == 1 && m->tri_tag[0] == 7 && m->tri_mid && memcmp(m->tri_mid, tm, sizeof tm) == 0,
                  "gmsh 2.2: quadratic triangle, tri_mid %d %d %d", m->tri_mid ? m->tri_mid[0] : -1,
                  m->tri_mid ? m->tri_mid[1] : -1, m->tri_mid ? m->tri_mid[2] : -1);
        }
        eo_mesh_destroy(&m);
    }
    /* 4- and 10-node tets in one file */
    const char *mixed = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n" P2_NODES "$EndNodes\n"
                        "$Elements\n2\n1 4 0 1 2 3 4\n2 11 0 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
    eo_mesh *m = NULL;
    expect_err(ctx, eo_mesh_read_buffer(ctx, mixed, strlen(mixed), EO_MESH_GMSH, "mixed.msh", NULL, &m),
               EO_ERR_MESH, "mixed gmsh", "mixed.msh:20", "one kind of tet");
    /* a negatively oriented 10-node tet (Gmsh corners 0 and 1 swapped, midside nodes
     * listed for the swapped corners): reoriented, every node still at its edge's midpoint */
    const char *neg = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n" P2_NODES "$EndNodes\n"
                      "$Elements\n1\n1 11 0 2 1 3 4 5 7 6 10 9 8\n$EndElements\n";
    CHECK(eo_mesh_read_buffer(ctx, neg, strlen(neg), EO_MESH_GMSH, "neg.msh", NULL, &m) == EO_OK && m,
          "negative tet: %s", eo_ctx_message(ctx));
    if (m) {
        CHECK(m->reoriented == 1 && corners_ok(m), "negative tet reoriented (%d)", m->reoriented);
        CHECK(midpoint_error(m) == 0, "reoriented tet: midside nodes at their new edges' midpoints (error %g)",
              midpoint_error(m));
        eo_mesh_destroy(&m);
    }
    eo_test_ctx_done(&ctx);
}

/* libtet 1.5, tetrahedralize("o2") of 5 points: TetGen's own 10-node order */
static const char tg_node[] = "15 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1 1 1\n5 0.5 0.5 1\n6 0.5 0.5 0.5\n"
                              "7 0 0.5 0\n8 0 0.5 0.5\n9 0.5 1 0.5\n10 0 0 0.5\n11 1 0.5 0.5\n12 0.5 0 0\n"
                              "13 0.5 0.5 0\n14 0.5 0 0.5\n";
static const char tg_ele[] = "3 10 0\n0 0 2 3 4 5 6 7 8 9 10\n1 0 2 4 1 11 12 7 9 13 6\n2 3 0 4 1 11 14 10 6 12 5\n";

static void test_tetgen_o2(void)
{
    eo_ctx *ctx = eo_test_ctx();
    char buf[1024];
    size_t a = strlen(tg_node), b = strlen(tg_ele);
    memcpy(buf, tg_node, a + 1);
    memcpy(buf + a + 1, tg_ele, b + 1);
    eo_mesh *m = NULL;
    int rc = eo_mesh_read_buffer(ctx, buf, a + b + 1, EO_MESH_TETGEN, "o2", NULL, &m);
    CHECK(rc == EO_OK && m, "tetgen -o2: %s", eo_ctx_message(ctx));
    if (m) {
        CHECK(m->order == 2 && m->nt == 3 && m->nv == 15, "tetgen -o2: order %d, %d tets", m->order, m->nt);
        CHECK(midpoint_error(m) == 0 && corners_ok(m), "tetgen -o2: every node at its VTK edge's midpoint (error %g, "
              "%d reoriented)", midpoint_error(m), m->reoriented);
        CHECK_CLOSE(eo_mesh_volume(m), 0.5, 1e-14); /* hull: 1/6 + 1/3 */
        eo_mesh_destroy(&m);
    }
    /* a 10-node .ele naming a midside node out of range */
    char bad[1024];
    const char *ele = "1 10 0\n0 0 1 2 3 7 12 13 6 8 15\n";
    memcpy(bad, tg_node, a + 1);
    memcpy(bad + a + 1, ele, strlen(ele) + 1);
    expect_err(ctx, eo_mesh_read_buffer(ctx, bad, a + strlen(ele) + 1, EO_MESH_TETGEN, "o2", NULL, &m), EO_ERR_MESH,
               "tetgen range", "o2.ele:2", "point index");
    eo_test_ctx_done(&ctx);
}

/* A hand-built order-2 mesh of tets sharing edges, for the validation cases. */
static eo_mesh *two_tets(eo_ctx *ctx)
{
    /* corners 0..4: tets (0,1,2,3) and (1,2,3,4) share face 123 (edges 12, 13, 23) */
    static const double X[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    static const int T[2][4] = {{0, 1, 2, 3}, {2, 1, 4, 3}};
    eo_mesh *m = NULL, *q = NULL;
    eo_mesh_create(ctx, 5, 2, &m);
    memcpy(m->X, X, sizeof X);
    memcpy(m->tets, T, sizeof T);
    eo_mesh_to_quadratic(ctx, m, &q);
    eo_mesh_destroy(&m);
    return q;
}

static void test_validate(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh *m = two_tets(ctx);
    CHECK(m && m->nv == 5 + 9 && eo_mesh_validate(ctx, m, NULL, "two") == EO_OK, "two tets: 9 edges, valid: %s",
          eo_ctx_message(ctx));
    eo_mesh_destroy(&m);

    m = two_tets(ctx); /* a midside node that is a corner */
    m->tet10[10 + 5] = 4;
    expect_err(ctx, eo_mesh_validate(ctx, m, NULL, "c.msh"), EO_ERR_MESH, "midside = corner", "tet 1", "corner");
    eo_mesh_destroy(&m);

    m = two_tets(ctx); /* tet 1's edge 01 (its corners 2, 1: shared) given tet 0's node of edge 03 */
    m->tet10[10 + 4] = m->tet10[7];
    expect_err(ctx, eo_mesh_validate(ctx, m, NULL, "s.msh"), EO_ERR_MESH, "shared edge, other node", "tet",
               "one node per edge");
    eo_mesh_destroy(&m);

    m = two_tets(ctx); /* tet 1's unshared edge 23 (4, 3) given tet 0's node of edge 01 */
    m->tet10[10 + 9] = m->tet10[4];
    expect_err(ctx, eo_mesh_validate(ctx, m, NULL, "e.msh"), EO_ERR_MESH, "one node, two edges", "tet",
               "one edge per midside node");
    eo_mesh_destroy(&m);

    m = two_tets(ctx);
    m->tet10[8] = m->nv;
    expect_err(ctx, eo_mesh_validate(ctx, m, NULL, "r.msh"), EO_ERR_MESH, "midside out of range", "tet 0",
               "midside node indices");
    eo_mesh_destroy(&m);

    /* a duplicate 10-node tet dropped with its row; an unreferenced vertex dropped and
     * every tet10 and tri_mid entry renumbered */
    eo_mesh *q = two_tets(ctx), *d = NULL;
    eo_mesh_create(ctx, q->nv + 1, 3, &d);
    d->order = 2;
    d->tet10 = eo_malloc(ctx, 30 * sizeof(int));
    d->X[0] = 7, d->X[1] = 7, d->X[2] = 7; /* vertex 0 unreferenced, the rest shifted by one */
    memcpy(d->X + 3, q->X, 3 * (size_t)q->nv * sizeof(double));
    for (int t = 0; t < 3; t++)
        for (int i = 0; i < 10; i++) d->tet10[10 * t + i] = q->tet10[10 * (t == 2 ? 0 : t) + i] + 1;
    for (int t = 0; t < 3; t++) memcpy(d->tets + 4 * t, d->tet10 + 10 * t, 4 * sizeof(int));
    d->ntri = 1;
    d->tris = eo_malloc(ctx, 3 * sizeof(int));
    d->tri_tag = eo_malloc(ctx, sizeof(int));
    d->tri_mid = eo_malloc(ctx, 3 * sizeof(int));
    const int tri[3] = {1, 2, 3}; /* face 012 of tet 0 */
    memcpy(d->tris, tri, sizeof tri);
    d->tri_tag[0] = 5;
    d->tri_mid[0] = d->tet10[4], d->tri_mid[1] = d->tet10[5], d->tri_mid[2] = d->tet10[6];
    eo_mesh_read_opts o = eo_mesh_read_opts_default();
    expect_err(ctx, eo_mesh_validate(ctx, d, &o, "d.msh"), EO_ERR_MESH, "duplicate 10-node tet", "tet 2", "duplicate");
    o.drop_degenerate = 1, o.drop_unreferenced = 1;
    int rc = eo_mesh_validate(ctx, d, &o, "d.msh");
    CHECK(rc == EO_WARN_DROPPED && d->nt == 2 && d->nv == q->nv && d->dropped_tets == 1 && d->dropped_vertices == 1,
          "drops: %s, %d tets, %d nodes", eo_status_name(rc), d->nt, d->nv);
    CHECK(memcmp(d->tet10, q->tet10, 20 * sizeof(int)) == 0 && memcmp(d->X, q->X, 3 * (size_t)q->nv * sizeof(double)) == 0,
          "drops: tet10 and X renumbered back to the original");
    CHECK(d->ntri == 1 && d->tris[0] == 0 && d->tri_mid[0] == q->tet10[4] && d->tri_mid[2] == q->tet10[6],
          "drops: tri_mid renumbered");
    eo_mesh_destroy(&d);
    eo_mesh_destroy(&q);
    eo_test_ctx_done(&ctx);
}

static void test_formats(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh *m = NULL;
    const char *medit = "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
                        "TetrahedraP2\n1\n1 2 3 4 1 1 1 1 1 1 0\nEnd\n";
    expect_err(ctx, eo_mesh_read_buffer(ctx, medit, strlen(medit), EO_MESH_MEDIT, "p2.mesh", NULL, &m),
               EO_ERR_UNSUPPORTED, "medit P2", "p2.mesh:9", "TetrahedraP2");
    /* VTU: quadratic tetra and a linear one in one file */
    const char *vtu = "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"10\" "
                      "NumberOfCells=\"2\"><Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" "
                      "format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1 .5 0 0 .5 .5 0 0 .5 0 0 0 .5 .5 0 .5 0 .5 .5"
                      "</DataArray></Points><Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" "
                      "format=\"ascii\">0 1 2 3 4 5 6 7 8 9 0 1 2 3</DataArray>\n<DataArray type=\"Int32\" "
                      "Name=\"offsets\" format=\"ascii\">10 14</DataArray>\n<DataArray type=\"UInt8\" "
                      "Name=\"types\" format=\"ascii\">24 10</DataArray>\n</Cells></Piece></UnstructuredGrid>"
                      "</VTKFile>\n";
    expect_err(ctx, eo_mesh_read_buffer(ctx, vtu, strlen(vtu), EO_MESH_VTU, "mixed.vtu", NULL, &m), EO_ERR_MESH,
               "mixed vtu", "cell 1", "one kind of tet");
    /* the same with one cell: an order-2 mesh */
    char one[2048];
    snprintf(one, sizeof one, "%s", vtu);
    char *p = strstr(one, "NumberOfCells=\"2\"");
    p[15] = '1';
    p = strstr(one, " 0 1 2 3</DataArray>");
    memmove(p, p + 8, strlen(p + 8) + 1);
    p = strstr(one, "10 14");
    memmove(p + 2, p + 5, strlen(p + 5) + 1);
    p = strstr(one, "24 10");
    memmove(p + 2, p + 5, strlen(p + 5) + 1);
    int rc = eo_mesh_read_buffer(ctx, one, strlen(one), EO_MESH_VTU, "one.vtu", NULL, &m);
    CHECK(rc == EO_OK && m && m->order == 2 && m->nt == 1 && midpoint_error(m) == 0, "vtu type 24: %s",
          eo_ctx_message(ctx));
    /* the frame writer: quadratic cells over every node, per-cell data per tet */
    if (m) {
        double J[1] = {1.25}, u[30] = {0};
        eo_vtu_fields f = {.displacement = u, .J = J};
        CHECK(eo_vtu_write(ctx, tpath("frame.vtu"), m, &f) == EO_OK, "frame write: %s", eo_ctx_message(ctx));
        eo_mesh *r = NULL;
        CHECK(eo_mesh_read(ctx, tpath("frame.vtu"), NULL, &r) == EO_OK && r && r->order == 2 && r->nt == 1 &&
                  memcmp(r->tet10, m->tet10, 10 * sizeof(int)) == 0,
              "frame read back as one quadratic tetra: %s", eo_ctx_message(ctx));
        eo_mesh_destroy(&r);
        FILE *fp = fopen(tpath("frame.vtu"), "rb");
        char head[4096] = {0};
        size_t n = fp ? fread(head, 1, sizeof head - 1, fp) : 0;
        if (fp) fclose(fp);
        CHECK(n > 0 && strstr(head, "NumberOfPoints=\"10\" NumberOfCells=\"1\"") && strstr(head, "Name=\"J\""),
              "frame header: 10 points, 1 cell, J per cell");
        eo_mesh_destroy(&m);
    }
    eo_test_ctx_done(&ctx);
}

/* Allocation failure injected at every allocation of the quadratic paths: the 10-node
 * readers (Gmsh, TetGen, VTU files written above), eo_mesh_to_quadratic and validation
 * with drops fail cleanly (an error with a message, no mesh, no live bytes), and with
 * enough allocations they succeed. */
static void test_injection(void)
{
    const char *files[] = {"p2.msh", "p2.node", "p2.vtu"};
    for (int k = 0; k < 4; k++) {
        int done = 0;
        for (long n = 1; n < 400 && !done; n++) {
            eo_ctx *ctx = eo_test_ctx();
            eo_mesh *m = NULL, *g = NULL;
            int rc;
            if (k < 3) {
                eo_ctx_fail_after(ctx, n);
                rc = eo_mesh_read(ctx, tpath(files[k]), NULL, &m);
            } else {
                eo_mesh_gen_opts o = eo_mesh_gen_opts_default();
                o.cells[0] = o.cells[1] = o.cells[2] = 2;
                eo_mesh_generate_box(ctx, &o, &g);
                eo_ctx_fail_after(ctx, n);
                rc = eo_mesh_to_quadratic(ctx, g, &m);
                if (rc >= 0) rc = eo_mesh_validate(ctx, m, NULL, "q");
            }
            eo_ctx_fail_after(ctx, 0);
            if (rc >= 0) {
                CHECK(m && m->order == 2, "%s: success after %ld allocations gives an order-2 mesh", k < 3 ? files[k] : "to_quadratic", n);
                done = 1;
            } else {
                CHECK(rc == EO_ERR_NOMEM && eo_ctx_message(ctx)[0] && (k == 3 || !m),
                      "%s: allocation %ld failed: %s (%s)", k < 3 ? files[k] : "to_quadratic", n, eo_status_name(rc),
                      eo_ctx_message(ctx));
            }
            eo_mesh_destroy(&m);
            eo_mesh_destroy(&g);
            eo_test_ctx_done(&ctx);
        }
        CHECK(done, "%s: succeeds with enough allocations", k < 3 ? files[k] : "to_quadratic");
    }
}

int main(void)
{
    snprintf(tmp, sizeof tmp, "%s", eo_test_tmpdir("mesh_p2"));
    test_to_quadratic(6);
    test_to_quadratic(5);
    test_gmsh_order();
    test_tetgen_o2();
    test_validate();
    test_formats();
    test_injection();
    return eo_test_finish("test_mesh_p2");
}
