/* Mesh suite: box generator (counts, volume, orientation, conformity, boundary area),
 * round trips through every writer/reader pair, the shared IPC meshes, hand-written
 * Gmsh 2.2 / TetGen (0- and 1-based) / MEDIT files, VTU/PVD/OBJ output, every bad-input
 * case (status code and a message naming file, line or index), unwritable output,
 * allocation-failure injection over every reader and writer, and load time.
 *
 * The IPC bar meshes in ../shared/meshes come from ipc-sim/IPC (input/tetMeshes/
 * bar-2523.msh and bar-14114.msh, MIT licence, the IPC authors). */
#include <dirent.h>
#include <stdarg.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>

#include "elastopt/io.h"
#include "elastopt/mesh.h"
#include "elastopt/scene.h"
#include "lib/mesh/mesh_io.h"
#include "testutil.h"

static char tmp[4096];

static const char *tpath(const char *name)
{
    static char buf[8][8400];
    static int k;
    k = (k + 1) % 8;
    snprintf(buf[k], sizeof buf[k], "%s/%s", tmp, name);
    return buf[k];
}

static void put_file(const char *name, const char *text)
{
    FILE *f = fopen(tpath(name), "wb");
    if (!f) {
        fprintf(stderr, "cannot write %s\n", tpath(name));
        exit(1);
    }
    fputs(text, f);
    fclose(f);
}

/* rc must equal want and the message contain every (NULL-terminated) substring. */
static void expect_err(eo_ctx *ctx, int rc, int want, const char *label, ...)
{
    CHECK(rc == want, "%s: status %s, expected %s (message '%s')", label, eo_status_name(rc), eo_status_name(want),
          eo_ctx_message(ctx));
    va_list ap;
    va_start(ap, label);
    for (const char *s = va_arg(ap, const char *); s; s = va_arg(ap, const char *))
        CHECK(strstr(eo_ctx_message(ctx), s) != NULL, "%s: message '%s' lacks '%s'", label, eo_ctx_message(ctx), s);
    va_end(ap);
    eo_ctx_clear_error(ctx);
}

static int read_file_status(eo_ctx *ctx, const char *name, const eo_mesh_read_opts *o, eo_mesh **m)
{
    return eo_mesh_read(ctx, tpath(name), o, m);
}

/* Number of directory entries whose name contains sub. */
static int count_files(const char *dir, const char *sub)
{
    DIR *d = opendir(dir);
    int n = 0;
    if (!d) return 0;
    for (struct dirent *e; (e = readdir(d));)
        if (strstr(e->d_name, sub)) n++;
    closedir(d);
    return n;
}

/* ---- generator -------------------------------------------------------------------- */

typedef struct {
    int k[3];
} face3;

static int cmp_face(const void *a, const void *b) { return memcmp(a, b, sizeof(face3)); }

static void sort3(int *k)
{
    for (int i = 1; i < 3; i++)
        for (int j = i; j > 0 && k[j - 1] > k[j]; j--) {
            int t = k[j];
            k[j] = k[j - 1];
            k[j - 1] = t;
        }
}

static double tri_area(const double *X, const int *f)
{
    const double *a = X + 3 * f[0], *b = X + 3 * f[1], *c = X + 3 * f[2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

static void test_generator(void)
{
    eo_ctx *ctx = eo_test_ctx();
    for (int split = 5; split <= 6; split++) {
        eo_mesh_gen_opts g = eo_mesh_gen_opts_default();
        double L[3] = {2, 0.5, 1.5}, O[3] = {1, -1, 0.25};
        int C[3] = {3, 4, 5};
        for (int i = 0; i < 3; i++) {
            g.size[i] = L[i];
            g.origin[i] = O[i];
            g.cells[i] = C[i];
        }
        g.split = split;
        eo_mesh *m = NULL;
        CHECK(eo_mesh_generate_box(ctx, &g, &m) == EO_OK, "generate: %s", eo_ctx_message(ctx));
        if (!m) continue;
        CHECK(m->nv == 4 * 5 * 6 && m->nt == 3 * 4 * 5 * split, "split %d: %d vertices %d tets", split, m->nv, m->nt);
        CHECK_CLOSE(eo_mesh_volume(m), L[0] * L[1] * L[2], 1e-12);
        int nonpos = 0;
        for (int t = 0; t < m->nt; t++) nonpos += eo_tet_volume(m->X, m->tets + 4 * t) <= 0;
        CHECK(nonpos == 0, "split %d: %d non-positive tets", split, nonpos);
        /* conforming: every face shared by 2 tets, or by 1 tet and lying on the box boundary */
        face3 *f = malloc(sizeof *f * 4 * (size_t)m->nt);
        static const int lf[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
        for (int t = 0; t < m->nt; t++)
            for (int q = 0; q < 4; q++) {
                for (int a = 0; a < 3; a++) f[4 * t + q].k[a] = m->tets[4 * t + lf[q][a]];
                sort3(f[4 * t + q].k);
            }
        qsort(f, 4 * (size_t)m->nt, sizeof *f, cmp_face);
        int bad = 0, nbound = 0;
        for (int i = 0, j; i < 4 * m->nt; i = j) {
            for (j = i + 1; j < 4 * m->nt && cmp_face(&f[i], &f[j]) == 0; j++) {}
            if (j - i > 2) bad++;
            if (j - i == 1) {
                nbound++;
                int on = 0;
                for (int ax = 0; ax < 3; ax++)
                    for (int side = 0; side < 2; side++) {
                        double plane = O[ax] + side * L[ax];
                        int all = 1;
                        for (int a = 0; a < 3; a++) all &= fabs(m->X[3 * f[i].k[a] + ax] - plane) < 1e-12;
                        on |= all;
                    }
                if (!on) bad++;
            }
        }
        free(f);
        CHECK(bad == 0, "split %d: %d non-conforming faces", split, bad);
        int *bf = NULL, nf = 0;
        CHECK(eo_mesh_boundary_faces(ctx, m, &bf, &nf) == EO_OK, "boundary");
        CHECK(nf == nbound, "boundary faces %d vs %d", nf, nbound);
        double area = 0;
        for (int i = 0; i < nf; i++) area += tri_area(m->X, bf + 3 * i);
        CHECK_CLOSE(area, 2 * (L[0] * L[1] + L[1] * L[2] + L[0] * L[2]), 1e-12);
        /* outward: sum over faces of (centroid . n) dA = 3 V (divergence theorem) */
        double flux = 0;
        for (int i = 0; i < nf; i++) {
            const double *a = m->X + 3 * bf[3 * i], *b = m->X + 3 * bf[3 * i + 1], *c = m->X + 3 * bf[3 * i + 2];
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
            for (int k = 0; k < 3; k++) flux += (a[k] + b[k] + c[k]) / 3 * n[k] / 2;
        }
        CHECK_CLOSE(flux, 3 * L[0] * L[1] * L[2], 1e-12);
        eo_free(ctx, bf);
        CHECK(eo_mesh_validate(ctx, m, NULL, "gen") == EO_OK && m->reoriented == 0, "generated mesh validates: %s",
              eo_ctx_message(ctx));
        eo_mesh_stats s;
        eo_mesh_stats_compute(m, &s);
        CHECK(s.bbox[0] == O[0] && s.bbox[5] == O[2] + L[2], "bbox %g %g", s.bbox[0], s.bbox[5]);
        CHECK(s.worst_quality > 0.3 && s.worst_quality <= 1, "quality %g", s.worst_quality);
        eo_mesh_destroy(&m);
    }
    /* spec parsing */
    eo_mesh_gen_opts g;
    CHECK(eo_mesh_gen_opts_parse(ctx, "gen:10,0.5,1:20,2,3:5", &g) == EO_OK && g.cells[0] == 20 && g.split == 5 &&
              g.size[1] == 0.5,
          "parse");
    expect_err(ctx, eo_mesh_gen_opts_parse(ctx, "gen:1,1:2,2,2", &g), EO_ERR_PARSE, "bad spec", "gen:1,1:2,2,2",
               "expected gen:", NULL);
    expect_err(ctx, eo_mesh_gen_opts_parse(ctx, "gen:1,1,1:2,0,2", &g), EO_ERR_PARSE, "zero cells", "expected", NULL);
    expect_err(ctx, eo_mesh_gen_opts_parse(ctx, "gen:1,1,1:2,2,2:7", &g), EO_ERR_PARSE, "split 7", "expected", NULL);
    eo_mesh *m = NULL;
    CHECK(eo_mesh_load(ctx, "gen:1,1,1:2,2,2", NULL, &m) == EO_OK && m->nt == 48, "load gen");
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

/* ---- round trips ------------------------------------------------------------------- */

static void same_mesh(const eo_mesh *a, const eo_mesh *b, const char *label, int attrs)
{
    CHECK(a->nv == b->nv && a->nt == b->nt, "%s: counts %d/%d vs %d/%d", label, a->nv, a->nt, b->nv, b->nt);
    if (a->nv != b->nv || a->nt != b->nt) return;
    CHECK(memcmp(a->X, b->X, sizeof(double) * 3 * (size_t)a->nv) == 0, "%s: coordinates differ", label);
    CHECK(memcmp(a->tets, b->tets, sizeof(int) * 4 * (size_t)a->nt) == 0, "%s: tets differ", label);
    CHECK_CLOSE(eo_mesh_volume(b), eo_mesh_volume(a), 1e-12);
    if (attrs) {
        CHECK(b->tet_attr && memcmp(a->tet_attr, b->tet_attr, sizeof(int) * (size_t)a->nt) == 0, "%s: attrs", label);
    }
}

static void round_trip(eo_ctx *ctx, const eo_mesh *m, const char *tag, int attrs)
{
    static const char *const ext[] = {".node", ".mesh", ".msh", NULL};
    for (int i = 0; ext[i]; i++) {
        char name[128], label[160];
        snprintf(name, sizeof name, "rt_%s%s", tag, ext[i]);
        snprintf(label, sizeof label, "round trip %s", name);
        int rc = eo_mesh_write(ctx, m, tpath(name), EO_MESH_AUTO);
        CHECK(rc == EO_OK, "%s: write: %s", label, eo_ctx_message(ctx));
        eo_mesh *b = NULL;
        rc = eo_mesh_read(ctx, tpath(name), NULL, &b);
        CHECK(rc == EO_OK, "%s: read: %s", label, eo_ctx_message(ctx));
        if (!b) continue;
        same_mesh(m, b, label, attrs);
        /* and once more through the next format: read, write, read */
        eo_mesh_destroy(&b);
    }
    /* chain: msh -> node -> mesh -> msh gives the same mesh */
    eo_mesh *a = NULL, *b = NULL, *c = NULL;
    char n1[128], n2[128], n3[128];
    snprintf(n1, sizeof n1, "rt_%s.msh", tag);
    snprintf(n2, sizeof n2, "chain_%s.ele", tag);
    snprintf(n3, sizeof n3, "chain_%s.mesh", tag);
    CHECK(eo_mesh_read(ctx, tpath(n1), NULL, &a) == EO_OK, "chain read");
    CHECK(a && eo_mesh_write(ctx, a, tpath(n2), EO_MESH_AUTO) == EO_OK, "chain write ele");
    CHECK(eo_mesh_read(ctx, tpath(n2), NULL, &b) == EO_OK, "chain read ele: %s", eo_ctx_message(ctx));
    CHECK(b && eo_mesh_write(ctx, b, tpath(n3), EO_MESH_AUTO) == EO_OK, "chain write mesh");
    CHECK(eo_mesh_read(ctx, tpath(n3), NULL, &c) == EO_OK, "chain read mesh");
    if (c) same_mesh(m, c, "chain", attrs);
    eo_mesh_destroy(&a);
    eo_mesh_destroy(&b);
    eo_mesh_destroy(&c);
}

static void test_round_trips(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh_gen_opts g = eo_mesh_gen_opts_default();
    g.size[0] = 1.0 / 3; /* coordinates that need all 17 digits */
    g.cells[0] = 3;
    g.cells[1] = 2;
    g.cells[2] = 5;
    g.split = 5;
    eo_mesh *m = NULL;
    CHECK(eo_mesh_generate_box(ctx, &g, &m) == EO_OK, "gen");
    m->tet_attr = eo_malloc(ctx, sizeof(int) * (size_t)m->nt);
    for (int t = 0; t < m->nt; t++) m->tet_attr[t] = 1 + t / 7; /* runs of equal attributes */
    round_trip(ctx, m, "gen", 1);
    eo_mesh_destroy(&m);

    eo_mesh_read_opts o = eo_mesh_read_opts_default();
    CHECK(eo_mesh_read(ctx, eo_test_shared_path("meshes/ipc_bar-2523.msh"), &o, &m) == EO_OK, "ipc read: %s",
          eo_ctx_message(ctx));
    if (m) round_trip(ctx, m, "ipc", 1);
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

/* ---- real and hand-written files ------------------------------------------------- */

static void test_ipc(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static const struct {
        const char *file;
        int nv, nt;
    } ipc[] = {{"meshes/ipc_bar-2523.msh", 886, 2523}, {"meshes/ipc_bar-14114.msh", 3842, 14114}};
    for (int i = 0; i < 2; i++) {
        eo_mesh *m = NULL;
        int rc = eo_mesh_read(ctx, eo_test_shared_path(ipc[i].file), NULL, &m);
        CHECK(rc == EO_OK, "%s: %s", ipc[i].file, eo_ctx_message(ctx));
        if (!m) continue;
        CHECK(m->nv == ipc[i].nv && m->nt == ipc[i].nt, "%s: %d %d", ipc[i].file, m->nv, m->nt);
        CHECK_CLOSE(eo_mesh_volume(m), 5.0, 1e-12);
        CHECK(m->reoriented == 0, "reoriented %d", m->reoriented);
        eo_mesh_stats s;
        eo_mesh_stats_compute(m, &s);
        CHECK(s.bbox[0] == 0 && s.bbox[1] == 0 && s.bbox[2] == 0 && s.bbox[3] == 10 && s.bbox[4] == 0.5 && s.bbox[5] == 1,
              "bbox");
        CHECK(s.min_volume > 0 && s.worst_quality > 0, "positive");
        int *bf = NULL, nf = 0;
        CHECK(eo_mesh_boundary_faces(ctx, m, &bf, &nf) == EO_OK, "boundary");
        double area = 0;
        for (int f = 0; f < nf; f++) area += tri_area(m->X, bf + 3 * f);
        CHECK_CLOSE(area, 2 * (10 * 0.5 + 0.5 * 1 + 10 * 1), 1e-12);
        if (i == 0) CHECK(nf == 1618, "bar-2523 has 1618 surface triangles ($Surface), got %d", nf);
        eo_free(ctx, bf);
        eo_mesh_destroy(&m);
    }
    eo_test_ctx_done(&ctx);
}

/* unit cube corner tets: 5 nodes, two tets sharing a face */
static const char *gmsh22 =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
    "$PhysicalNames\n2\n2 5 \"skin with spaces\"\n3 7 \"body\"\n$EndPhysicalNames\n"
    "$Nodes\n5\n10 0 0 0\n20 1 0 0\n30 0 1 0\n40 0 0 1\n50 1 1 1\n$EndNodes\n"
    "$Elements\n4\n"
    "1 1 2 5 1 10 20\n"
    "2 2 2 5 1 10 20 30\n"
    "3 4 2 7 1 10 20 30 40\n"
    "4 4 2 8 1 20 40 30 50\n" /* negative orientation: reoriented */
    "$EndElements\n"
    "$NodeData\n1\n\"u\"\n$EndNodeData\n";

static void test_gmsh22(void)
{
    eo_ctx *ctx = eo_test_ctx();
    put_file("g22.msh", gmsh22);
    eo_mesh *m = NULL;
    int rc = read_file_status(ctx, "g22.msh", NULL, &m);
    CHECK(rc == EO_OK, "gmsh 2.2: %s", eo_ctx_message(ctx));
    if (m) {
        CHECK(m->nv == 5 && m->nt == 2, "counts %d %d", m->nv, m->nt);
        CHECK(m->tet_attr && m->tet_attr[0] == 7 && m->tet_attr[1] == 8, "physical tags");
        CHECK(m->reoriented == 1, "reoriented %d", m->reoriented);
        CHECK_CLOSE(eo_mesh_volume(m), 1.0 / 6 + 1.0 / 3, 1e-12);
        CHECK(m->tets[0] == 0 && m->tets[1] == 1, "node tags mapped to indices");
        CHECK(m->ntri == 1 && m->tri_tag[0] == 5 && m->tris[0] == 0 && m->tris[1] == 1 && m->tris[2] == 2,
              "2.2 triangle kept with its physical tag 5 (ntri %d)", m->ntri);
    }
    eo_mesh_destroy(&m);
    /* the same through the in-memory entry point */
    rc = eo_mesh_read_buffer(ctx, gmsh22, strlen(gmsh22), EO_MESH_GMSH, "mem.msh", NULL, &m);
    CHECK(rc == EO_OK && m && m->nt == 2, "buffer: %s", eo_ctx_message(ctx));
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

static const char *tg_node0 = "# cube corner + apex\n"
                              "5 3 2 1\n"
                              "0 0 0 0  0.5 1.5  3\n"
                              "1 1 0 0  0.5 1.5  0\n"
                              "2 0 1 0  0.5 1.5  0 # trailing comment\n"
                              "\n"
                              "3 0 0 1  0.5 1.5  4\n"
                              "4 1 1 1  0.5 1.5  -1\n";
static const char *tg_ele0 = "2 4 1\n"
                             "0 0 1 2 3 11\n"
                             "1 1 3 2 4 -2\n"
                             "# Generated by hand\n";

static void test_tetgen(void)
{
    eo_ctx *ctx = eo_test_ctx();
    put_file("tg0.node", tg_node0);
    put_file("tg0.ele", tg_ele0);
    put_file("tg1.node", "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n");
    put_file("tg1.ele", "2 4 0\n1 1 2 3 4\n2 2 4 3 5\n");
    /* 10 nodes per tet make an order-2 mesh: midside nodes that are corners are refused
     * (test_mesh_p2 reads real ones) */
    put_file("tg2.node", "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n");
    put_file("tg2.ele", "2 10 0\n1 1 2 3 4 1 1 1 1 1 1\n2 2 4 3 5 1 1 1 1 1 1\n");
    {
        eo_mesh *m2 = NULL;
        expect_err(ctx, read_file_status(ctx, "tg2.ele", NULL, &m2), EO_ERR_MESH, "10-node tets on corners",
                   "tg2.ele:2", "tet 1", "is a corner of a tet", NULL);
    }
    const char *names[] = {"tg0.node", "tg0.ele", "tg0", "tg1.ele"};
    for (int i = 0; i < 4; i++) {
        eo_mesh *m = NULL;
        int rc = read_file_status(ctx, names[i], NULL, &m);
        CHECK(rc == EO_OK, "%s: %s", names[i], eo_ctx_message(ctx));
        if (!m) continue;
        CHECK(m->nv == 5 && m->nt == 2, "%s: counts", names[i]);
        CHECK_CLOSE(eo_mesh_volume(m), 1.0 / 6 + 1.0 / 3, 1e-12);
        if (i < 3) {
            CHECK(m->vmarker && m->vmarker[0] == 3 && m->vmarker[4] == -1, "markers");
            CHECK(m->tet_attr && m->tet_attr[0] == 11 && m->tet_attr[1] == -2, "attributes");
        } else {
            CHECK(!m->vmarker && !m->tet_attr, "1-based without markers/attributes");
            CHECK(m->tets[0] == 0 && m->tets[3] == 3, "1-based indices shifted");
        }
        eo_mesh_destroy(&m);
    }
    /* in-memory: node text, NUL, ele text */
    size_t a = strlen(tg_node0), b = strlen(tg_ele0);
    char *buf = malloc(a + b + 1);
    memcpy(buf, tg_node0, a);
    buf[a] = 0;
    memcpy(buf + a + 1, tg_ele0, b);
    eo_mesh *m = NULL;
    CHECK(eo_mesh_read_buffer(ctx, buf, a + b + 1, EO_MESH_TETGEN, "mem", NULL, &m) == EO_OK && m && m->nt == 2,
          "tetgen buffer: %s", eo_ctx_message(ctx));
    eo_mesh_destroy(&m);
    free(buf);
    eo_test_ctx_done(&ctx);
}

static const char *medit_ok = "MeshVersionFormatted 2\n# comment\nDimension\n3\n"
                              "Vertices\n5\n0 0 0 1\n1 0 0 1\n0 1 0 2\n0 0 1 2\n1 1 1 9\n"
                              "Corners\n1\n1\n"
                              "Triangles\n2\n1 2 3 4\n2 3 4 4\n"
                              "Tetrahedra\n2\n1 2 3 4 3\n2 4 3 5 6\n"
                              "Edges\n1\n1 2 0\n"
                              "End\n";

static void test_medit(void)
{
    eo_ctx *ctx = eo_test_ctx();
    put_file("ok.mesh", medit_ok);
    eo_mesh *m = NULL;
    int rc = read_file_status(ctx, "ok.mesh", NULL, &m);
    CHECK(rc == EO_OK, "medit: %s", eo_ctx_message(ctx));
    if (m) {
        CHECK(m->nv == 5 && m->nt == 2, "counts");
        CHECK(m->tet_attr && m->tet_attr[0] == 3 && m->tet_attr[1] == 6, "tet references -> tet_attr");
        CHECK(m->vmarker && m->vmarker[4] == 9, "vertex references");
        CHECK_CLOSE(eo_mesh_volume(m), 0.5, 1e-12);
    }
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

/* ---- Vega .veg ---------------------------------------------------------------------- */

typedef struct {
    char text[2048];
} log_capture;

static void capture_log(eo_log_level level, const char *msg, void *user)
{
    log_capture *c = user;
    size_t k = strlen(c->text);
    if (level <= EO_LOG_INFO) snprintf(c->text + k, sizeof c->text - k, "%s\n", msg);
}

static void test_veg(void)
{
    eo_ctx *ctx = eo_test_ctx();
    log_capture logs = {{0}};
    eo_ctx_set_logger(ctx, capture_log, &logs, EO_LOG_INFO);
    eo_mesh *m = NULL;
    const char *path = eo_test_src_path("tests/data/cube6.veg");
    CHECK(eo_mesh_format_from_path(path) == EO_MESH_VEG && strcmp(eo_mesh_format_name(EO_MESH_VEG), "veg") == 0,
          "chosen by extension");
    int rc = eo_mesh_read(ctx, path, NULL, &m);
    CHECK(rc == EO_OK, "veg: %s", eo_ctx_message(ctx));
    if (m) {
        CHECK(m->nv == 8 && m->nt == 6, "counts %d %d", m->nv, m->nt);
        for (int v = 0; v < 8; v++) /* vertex n = i + 2 j + 4 k + 1 at (i, j, k) */
            CHECK(m->X[3 * v] == (v & 1) && m->X[3 * v + 1] == ((v >> 1) & 1) && m->X[3 * v + 2] == ((v >> 2) & 1),
                  "vertex %d at (%g, %g, %g)", v + 1, m->X[3 * v], m->X[3 * v + 1], m->X[3 * v + 2]);
        CHECK_CLOSE(eo_mesh_volume(m), 1.0, 1e-14);
        for (int t = 0; t < 6; t++) {
            CHECK_CLOSE(eo_tet_volume(m->X, m->tets + 4 * t), 1.0 / 6, 1e-14);
            CHECK(m->tets[4 * t] == 0 && m->tets[4 * t + 3] == 7, "tet %d runs along the diagonal 1-8", t + 1);
        }
        /* 0-based sets: tet 4 "1, 3, 7, 8" */
        int set4[4] = {m->tets[12], m->tets[13], m->tets[14], m->tets[15]};
        sort3(set4 + 1);
        CHECK(set4[0] == 0 && set4[1] == 2 && set4[2] == 6 && set4[3] == 7, "tet 4 with commas");
        round_trip(ctx, m, "veg", 0);
    }
    eo_mesh_destroy(&m);
    CHECK(strstr(logs.text, "cube6.veg:25: veg: section *MATERIAL ignored") &&
              strstr(logs.text, "cube6.veg:28: veg: section *SET ignored") &&
              strstr(logs.text, "veg: section *REGION ignored"),
          "notes: %s", logs.text);
    eo_ctx_set_logger(ctx, NULL, NULL, EO_LOG_ERROR);

    /* 0-based file (Vega accepts both): same mesh */
    put_file("zero.veg", "*VERTICES\n4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n*ELEMENTS\nTET\n1 4 0\n0 0 1 2 3\n");
    rc = read_file_status(ctx, "zero.veg", NULL, &m);
    CHECK(rc == EO_OK && m && m->nt == 1 && fabs(eo_mesh_volume(m) - 1.0 / 6) < 1e-15, "0-based: %s",
          eo_ctx_message(ctx));
    eo_mesh_destroy(&m);

    /* errors name file, line and item */
    static const struct {
        const char *name, *text;
        int status;
        const char *msg1, *msg2;
    } bad[] = {
        {"count.veg", "*VERTICES\n5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n*ELEMENTS\nTET\n1 4 0\n1 1 2 3 4\n",
         EO_ERR_PARSE, "count.veg:7: vertex 5: ", "expected vertex index, got '*ELEMENTS'"},
        {"range.veg", "*VERTICES\n4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n*ELEMENTS\nTET\n2 4 0\n1 1 2 3 4\n2 1 2 3 5\n",
         EO_ERR_MESH, "range.veg:11: tet 2: ", "expected vertex index in [1, 4], got 5"},
        {"trunc.veg", "*VERTICES\n4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n*ELEMENTS\nTET\n2 4 0\n1 1 2 3 4\n2 1 2",
         EO_ERR_PARSE, "trunc.veg:11: tet 2: ", "expected vertex index, got end of"},
        {"cut.veg", "*VERTICES\n4 3 0 0\n1 0 0 0\n2 1 0\n", EO_ERR_PARSE, "cut.veg:4: vertex 2: ",
         "expected z coordinate, got end of line"},
        {"bigcount.veg", "*VERTICES\n99999999 3 0 0\n1 0 0 0\n", EO_ERR_PARSE, "bigcount.veg:2:",
         "vertex count between 0 and"},
        {"order.veg", "*VERTICES\n3 3 0 0\n1 0 0 0\n3 1 0 0\n2 0 1 0\n", EO_ERR_PARSE, "order.veg:4: vertex 2: ",
         "expected vertex index 2 (indices follow on), got 3"},
        {"cubic.veg", "*VERTICES\n1 3 0 0\n1 0 0 0\n*ELEMENTS\nCUBIC\n1 8 0\n", EO_ERR_UNSUPPORTED, "cubic.veg:5:",
         "element type CUBIC (hexahedra) is not supported; expected TET"},
        {"hex.veg", "*VERTICES\n1 3 0 0\n1 0 0 0\n*ELEMENTS\nHEX\n", EO_ERR_PARSE, "hex.veg:5:",
         "expected element type TET, got 'HEX'"},
        {"width.veg", "*VERTICES\n1 2 0 0\n", EO_ERR_PARSE, "width.veg:2:", "expected coordinates per vertex 3 in [3, 3]"},
        {"incl.veg", "*VERTICES\n1 3 0 0\n1 0 0 0\n*INCLUDE more.veg\n", EO_ERR_UNSUPPORTED, "incl.veg:4:",
         "*INCLUDE is not supported"},
        {"none.veg", "# nothing\n*MATERIAL m\nENU, 1, 2, 0.3\n", EO_ERR_PARSE, "none.veg:", "expected a *VERTICES section"},
        {"notets.veg", "*VERTICES\n1 3 0 0\n1 0 0 0\n", EO_ERR_MESH, "notets.veg:", "expected an *ELEMENTS section"},
        {"junk.veg", "VERTICES\n", EO_ERR_PARSE, "junk.veg:1:", "expected a section keyword such as '*VERTICES'"},
        {"flat.veg", "*VERTICES\n4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n*ELEMENTS\nTET\n1 4 0\n1 1 2 3 4\n",
         EO_ERR_MESH, "flat.veg:10", "tet 1"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        put_file(bad[i].name, bad[i].text);
        expect_err(ctx, read_file_status(ctx, bad[i].name, NULL, &m), bad[i].status, bad[i].name, bad[i].msg1,
                   bad[i].msg2, NULL);
        CHECK(m == NULL, "%s: no mesh", bad[i].name);
    }
    /* a writer is not there: .veg is read only */
    eo_mesh *g = NULL;
    eo_mesh_gen_opts go = eo_mesh_gen_opts_default();
    CHECK(eo_mesh_generate_box(ctx, &go, &g) == EO_OK, "generate");
    expect_err(ctx, eo_mesh_write(ctx, g, tpath("out.veg"), EO_MESH_AUTO), EO_ERR_UNSUPPORTED, "write veg",
               "veg files can be read, not written", NULL);
    eo_mesh_destroy(&g);
    eo_test_ctx_done(&ctx);
}

/* ---- VTU / PVD / OBJ ------------------------------------------------------------- */

static char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)len + 1);
    *n = fread(b, 1, (size_t)len, f);
    b[*n] = 0;
    fclose(f);
    return b;
}

static long attr_long(const char *s, const char *key)
{
    const char *p = strstr(s, key);
    return p ? strtol(p + strlen(key), NULL, 10) : -1;
}

static uint64_t le64(const unsigned char *p)
{
    uint64_t v = 0;
    for (int i = 7; i >= 0; i--) v = v << 8 | p[i];
    return v;
}

static void test_vtu(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh *m = NULL;
    CHECK(eo_mesh_load(ctx, "gen:2,1,1:2,1,1:6", NULL, &m) == EO_OK, "gen");
    if (!m) return;
    int nv = m->nv, nt = m->nt;
    double *u = calloc(3 * (size_t)nv, sizeof(double)), *vel = calloc(3 * (size_t)nv, sizeof(double));
    double *psi = calloc((size_t)nt, sizeof(double)), *J = calloc((size_t)nt, sizeof(double));
    unsigned char *inv = calloc((size_t)nt, 1);
    for (int i = 0; i < 3 * nv; i++) u[i] = 0.01 * i;
    for (int t = 0; t < nt; t++) {
        J[t] = 1 - 0.1 * t;
        inv[t] = J[t] <= 0;
    }
    eo_vtu_fields f = {.displacement = u, .velocity = vel, .energy_density = psi, .J = J, .inverted = inv};
    CHECK(eo_vtu_write(ctx, tpath("f0.vtu"), m, &f) == EO_OK, "vtu: %s", eo_ctx_message(ctx));
    size_t n = 0;
    char *s = slurp(tpath("f0.vtu"), &n);
    CHECK(s != NULL, "vtu exists");
    if (s) {
        CHECK(strncmp(s, "<?xml", 5) == 0 && strstr(s, "header_type=\"UInt64\"") && strstr(s, "byte_order=\"LittleEndian\""),
              "header");
        CHECK(attr_long(s, "NumberOfPoints=\"") == nv && attr_long(s, "NumberOfCells=\"") == nt, "counts");
        const char *names[] = {"displacement", "velocity", "energy_density", "J", "inverted", "Points",
                               "connectivity", "offsets", "types"};
        const size_t bytes[] = {24u * nv, 24u * nv, 8u * nt, 8u * nt, 1u * nt, 24u * nv, 32u * nt, 8u * nt, 1u * nt};
        char *app = strstr(s, "<AppendedData encoding=\"raw\">");
        CHECK(app != NULL, "appended block");
        const unsigned char *data = app ? (const unsigned char *)strchr(app, '_') + 1 : NULL;
        uint64_t pos = 0;
        for (int i = 0; i < 9 && data; i++) {
            char key[64];
            snprintf(key, sizeof key, "Name=\"%s\"", names[i]);
            const char *d = strstr(s, key);
            CHECK(d != NULL, "array %s present", names[i]);
            if (!d) break;
            long off = attr_long(d, "offset=\"");
            CHECK((uint64_t)off == pos, "%s offset %ld, expected %llu", names[i], off, (unsigned long long)pos);
            uint64_t cnt = le64(data + pos);
            CHECK(cnt == bytes[i], "%s byte count %llu, expected %zu", names[i], (unsigned long long)cnt, bytes[i]);
            if (i == 5) CHECK(memcmp(data + pos + 8, m->X, 8) == 0, "first point bytes");
            pos += 8 + cnt;
        }
        if (data) {
            const char *tail = (const char *)data + pos;
            CHECK((size_t)(tail - s) <= n && strncmp(tail, "\n  </AppendedData>\n</VTKFile>\n", 30) == 0,
                  "appended data ends exactly before the closing tags");
            CHECK(data[pos - 1] == 10, "last cell type is VTK_TETRA");
        }
        free(s);
    }
    /* non-finite values: never written; sentinels + a "nonfinite" flag array (cell data:
     * energy_density, J, inverted, nonfinite; point data: displacement, velocity, nonfinite) */
    psi[1] = INFINITY;
    J[2] = NAN;
    vel[3 * 1 + 2] = -INFINITY;
    CHECK(eo_vtu_write(ctx, tpath("nf.vtu"), m, &f) == EO_OK, "vtu nonfinite: %s", eo_ctx_message(ctx));
    s = slurp(tpath("nf.vtu"), &n);
    CHECK(s != NULL, "nf.vtu exists");
    if (s) {
        char *app = strstr(s, "<AppendedData encoding=\"raw\">");
        const unsigned char *data = app ? (const unsigned char *)strchr(app, '_') + 1 : NULL;
        const char *cd = strstr(s, "<CellData>"), *pd = strstr(s, "<PointData>");
        const char *cflag = cd ? strstr(cd, "Name=\"nonfinite\"") : NULL;
        const char *pflag = pd ? strstr(pd, "Name=\"nonfinite\"") : NULL;
        CHECK(cflag && cflag < strstr(s, "</CellData>"), "cell nonfinite flag present");
        CHECK(pflag && pflag < strstr(s, "</PointData>"), "point nonfinite flag present");
        if (data && cflag && pflag) {
            const unsigned char *cf = data + attr_long(cflag, "offset=\"");
            const unsigned char *pf = data + attr_long(pflag, "offset=\"");
            CHECK(le64(cf) == (uint64_t)nt && le64(pf) == (uint64_t)nv, "flag sizes");
            int ok = 1;
            for (int t = 0; t < nt; t++) ok &= cf[8 + t] == (t == 1 || t == 2);
            for (int v = 0; v < nv; v++) ok &= pf[8 + v] == (v == 1);
            CHECK(ok, "flags mark exactly cells 1, 2 and point 1");
            double e1, j2, v1;
            const unsigned char *ed = data + attr_long(strstr(s, "Name=\"energy_density\""), "offset=\"");
            const unsigned char *jd = data + attr_long(strstr(s, "Name=\"J\""), "offset=\"");
            const unsigned char *vd = data + attr_long(strstr(s, "Name=\"velocity\""), "offset=\"");
            memcpy(&e1, ed + 8 + 8 * 1, 8);
            memcpy(&j2, jd + 8 + 8 * 2, 8);
            memcpy(&v1, vd + 8 + 8 * 5, 8);
            CHECK(e1 == EO_VTU_NONFINITE && j2 == EO_VTU_NONFINITE && v1 == -EO_VTU_NONFINITE,
                  "sentinels %g %g %g", e1, j2, v1);
            /* no non-finite double anywhere in the appended block (8-byte aligned scan
             * of every Float64 array: all arrays start at 8-byte multiples + 8) */
            int finite = 1;
            for (const char *q = s; (q = strstr(q, "type=\"Float64\"")); q++) {
                const unsigned char *a = data + attr_long(q, "offset=\"");
                uint64_t cnt = le64(a);
                for (uint64_t k = 0; k < cnt / 8; k++) {
                    double d;
                    memcpy(&d, a + 8 + 8 * k, 8);
                    finite &= isfinite(d) != 0;
                }
            }
            CHECK(finite, "every Float64 value written is finite");
        }
        free(s);
    }
    psi[1] = 0;
    J[2] = 1;
    vel[5] = 0;
    /* pvd series */
    eo_pvd *p = NULL;
    CHECK(eo_pvd_create(ctx, tpath("series.pvd"), &p) == EO_OK, "pvd");
    for (int k = 0; k < 3; k++) {
        char name[32];
        snprintf(name, sizeof name, "f%d.vtu", k);
        if (k) CHECK(eo_vtu_write(ctx, tpath(name), m, NULL) == EO_OK, "frame");
        CHECK(eo_pvd_add(ctx, p, 0.1 * k, name) == EO_OK, "pvd add");
        s = slurp(tpath("series.pvd"), &n);
        int count = 0;
        for (const char *q = s; q && (q = strstr(q, "<DataSet")); q++) count++;
        CHECK(count == k + 1, "pvd lists %d frames after %d adds", count, k + 1);
        CHECK(s && strstr(s, "</VTKFile>"), "pvd complete");
        free(s);
    }
    eo_pvd_destroy(&p);
    CHECK(p == NULL, "destroy sets NULL");
    /* obj: closed surface, Euler characteristic 2 */
    CHECK(eo_obj_write(ctx, tpath("b.obj"), m, NULL) == EO_OK, "obj");
    s = slurp(tpath("b.obj"), &n);
    int nvv = 0, nff = 0;
    for (char *line = s; line && *line;) {
        if (line[0] == 'v' && line[1] == ' ') nvv++;
        if (line[0] == 'f' && line[1] == ' ') nff++;
        char *e = strchr(line, '\n');
        line = e ? e + 1 : NULL;
    }
    CHECK(nff == 2 * 2 * (2 * 1 + 1 * 1 + 2 * 1) && nvv - nff / 2 == 2, "obj %d vertices %d faces", nvv, nff);
    free(s);
    CHECK(count_files(tmp, ".tmp.") == 0, "no temporary files left");
    free(u);
    free(vel);
    free(psi);
    free(J);
    free(inv);
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

/* ---- bad input ---------------------------------------------------------------------- */

static void test_bad_input(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh *m = NULL;
    eo_mesh_read_opts drop = eo_mesh_read_opts_default();
    drop.drop_degenerate = 1;
    drop.drop_unreferenced = 1;
    int rc;

    /* missing files */
    expect_err(ctx, read_file_status(ctx, "nope.msh", NULL, &m), EO_ERR_IO, "missing", "nope.msh", "cannot open", NULL);
    put_file("half.node", "1 3 0 0\n1 0 0 0\n");
    expect_err(ctx, read_file_status(ctx, "half.node", NULL, &m), EO_ERR_IO, "missing .ele", "half.ele", NULL);
    expect_err(ctx, read_file_status(ctx, "x.xyz", NULL, &m), EO_ERR_UNSUPPORTED, "unknown extension", "x.xyz", ".msh",
               NULL);
    CHECK(m == NULL, "no mesh on failure");

    /* empty files */
    put_file("empty.msh", "");
    put_file("empty.mesh", "  \n\n");
    put_file("empty.node", "# nothing\n");
    put_file("empty.ele", "");
    expect_err(ctx, read_file_status(ctx, "empty.msh", NULL, &m), EO_ERR_IO, "empty msh", "empty.msh:",
               "the file is empty (0 bytes)", NULL);
    expect_err(ctx, read_file_status(ctx, "empty.mesh", NULL, &m), EO_ERR_PARSE, "empty mesh", "empty.mesh:2:",
               "expected 'MeshVersionFormatted'", NULL);
    expect_err(ctx, read_file_status(ctx, "empty.node", NULL, &m), EO_ERR_IO, "empty node (.ele of 0 bytes)",
               "empty.ele:", "the file is empty (0 bytes)", NULL);

    /* truncated: the IPC mesh cut in the middle of its elements */
    char *text = NULL;
    size_t len = 0;
    CHECK(eo_read_file(ctx, eo_test_shared_path("meshes/ipc_bar-2523.msh"), &text, &len) == EO_OK, "read ipc");
    if (text) {
        char *cut = strstr(text, "$EndElements") - 100; /* inside the last element lines */
        *cut = 0;
        put_file("trunc.msh", text);
        long line = 1;
        for (char *q = text; *q; q++) line += *q == '\n' && q[1];
        char want[64];
        snprintf(want, sizeof want, "trunc.msh:%ld:", line);
        expect_err(ctx, read_file_status(ctx, "trunc.msh", NULL, &m), EO_ERR_PARSE, "truncated", want, "expected",
                   "end of file", NULL);
        /* truncated in the nodes */
        text[strstr(text, "$Nodes") - text + 5000] = 0;
        put_file("trunc2.msh", text);
        expect_err(ctx, read_file_status(ctx, "trunc2.msh", NULL, &m), EO_ERR_PARSE, "truncated nodes", "trunc2.msh:",
                   "got end of file", NULL);
        eo_free(ctx, text);
    }
    put_file("trunc.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n");
    expect_err(ctx, read_file_status(ctx, "trunc.mesh", NULL, &m), EO_ERR_PARSE, "truncated medit", "trunc.mesh:6:",
               "vertex 3", "expected x coordinate, got end of file", NULL);

    /* wrong counts */
    put_file("count.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                          "$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n");
    expect_err(ctx, read_file_status(ctx, "count.msh", NULL, &m), EO_ERR_PARSE, "node count too high", "count.msh:10:",
               "expected node tag, got '$EndNodes'", NULL);
    put_file("count2.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                           "$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n2 4 0 1 2 3 4\n$EndElements\n");
    expect_err(ctx, read_file_status(ctx, "count2.msh", NULL, &m), EO_ERR_PARSE, "element count too low",
               "count2.msh:14:", "expected '$EndElements', got '2'", NULL);
    put_file("count3.node", "3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    put_file("count3.ele", "1 4 0\n1 1 2 3 4\n");
    expect_err(ctx, read_file_status(ctx, "count3.node", NULL, &m), EO_ERR_PARSE, "tetgen count too low",
               "count3.node:5:", "expected end of file after 3 points, got '4'", NULL);
    put_file("count4.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    put_file("count4.ele", "2 4 0\n1 1 2 3 4\n");
    expect_err(ctx, read_file_status(ctx, "count4.ele", NULL, &m), EO_ERR_PARSE, "tetgen count too high",
               "count4.ele:2:", "expected tetrahedron index, got end of file", NULL);
    put_file("count5.ele", "1 4 0\n1 1 2 3 4\n");
    put_file("count6.ele", "1 4 0\n1 1 2 3 4\n");
    put_file("skip.ele", "1 4 0\n1 1 2 3 4\n");
    put_file("count5.node", "4 3 1 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    expect_err(ctx, read_file_status(ctx, "count5.node", NULL, &m), EO_ERR_PARSE, "missing attribute column",
               "count5.node:2:", "vertex 1", "expected point attribute, got end of line", NULL);
    put_file("count6.node", "4 3 0 0\n1 0 0 0 7\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    expect_err(ctx, read_file_status(ctx, "count6.node", NULL, &m), EO_ERR_PARSE, "extra column", "count6.node:2:",
               "vertex 1", "expected end of line", "got '7'", NULL);
    put_file("huge.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2000000000\n1 0 0 0\n$EndNodes\n");
    expect_err(ctx, read_file_status(ctx, "huge.msh", NULL, &m), EO_ERR_PARSE, "absurd count", "huge.msh:5:",
               "expected node count between 0 and", "got '2000000000'", NULL);
    put_file("block.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n3 1 0 4\n1\n2\n3\n4\n"
                          "0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n");
    expect_err(ctx, read_file_status(ctx, "block.msh", NULL, &m), EO_ERR_PARSE, "block larger than header",
               "block.msh:6:", "block of 4 nodes exceeds the 3", NULL);

    /* non-numeric tokens */
    put_file("nan_tok.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 one 0\n4 0 0 1\n");
    put_file("nan_tok.ele", "1 4 0\n1 1 2 3 4\n");
    expect_err(ctx, read_file_status(ctx, "nan_tok.node", NULL, &m), EO_ERR_PARSE, "non-numeric", "nan_tok.node:4:",
               "vertex 3", "expected y coordinate, got 'one'", NULL);
    put_file("tok.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
                         "Tetrahedra\n1\n1 2 3x 4 0\nEnd\n");
    expect_err(ctx, read_file_status(ctx, "tok.mesh", NULL, &m), EO_ERR_PARSE, "glued token", "tok.mesh:11:", "tet 1",
               "expected vertex index, got '3x'", NULL);
    put_file("tok.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n"
                        "0 0 0\n1 0 0\n0 1.5.2 0\n0 0 1\n$EndNodes\n");
    expect_err(ctx, read_file_status(ctx, "tok.msh", NULL, &m), EO_ERR_PARSE, "bad float", "tok.msh:13:", "vertex 3",
               "expected y coordinate, got '1.5.2'", NULL);

    /* NaN / Inf coordinates */
    put_file("nan.node", "4 3 0 0\n1 0 0 0\n2 nan 0 0\n3 0 1 0\n4 0 0 1\n");
    put_file("nan.ele", "1 4 0\n1 1 2 3 4\n");
    expect_err(ctx, read_file_status(ctx, "nan.node", NULL, &m), EO_ERR_NONFINITE, "nan", "nan.node:3:", "vertex 2",
               "finite", NULL);
    put_file("inf.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 -inf\n"
                        "$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n");
    expect_err(ctx, read_file_status(ctx, "inf.msh", NULL, &m), EO_ERR_NONFINITE, "inf", "inf.msh:9:", "vertex 4",
               "z = -inf", NULL);
    put_file("big.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1e999 0 0 0\n0 1 0 0\n0 0 1 0\n"
                         "Tetrahedra\n1\n1 2 3 4 0\nEnd\n");
    expect_err(ctx, read_file_status(ctx, "big.mesh", NULL, &m), EO_ERR_NONFINITE, "overflow", "big.mesh:6:",
               "vertex 2", NULL);

    /* indices out of range */
    put_file("range.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    put_file("range.ele", "2 4 0\n1 1 2 3 4\n2 1 2 3 9\n");
    expect_err(ctx, read_file_status(ctx, "range.ele", NULL, &m), EO_ERR_MESH, "tetgen range", "range.ele:3:", "tet 2",
               "expected point index in [1, 4], got 9", NULL);
    put_file("range0.node", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n");
    put_file("range0.ele", "1 4 0\n0 0 1 2 4\n");
    expect_err(ctx, read_file_status(ctx, "range0.node", NULL, &m), EO_ERR_MESH, "tetgen 0-based range",
               "range0.ele:2:", "tet 0", "[0, 3], got 4", NULL);
    put_file("range.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
                           "Tetrahedra\n1\n1 2 0 4 0\nEnd\n");
    expect_err(ctx, read_file_status(ctx, "range.mesh", NULL, &m), EO_ERR_MESH, "medit range", "range.mesh:11:",
               "tet 1", "[1, 4], got 0", NULL);
    put_file("range.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                          "$EndNodes\n$Elements\n1\n17 4 0 1 2 3 5\n$EndElements\n");
    expect_err(ctx, read_file_status(ctx, "range.msh", NULL, &m), EO_ERR_MESH, "gmsh undefined node", "range.msh:13:",
               "tet 17", "node 5: expected a node tag defined in $Nodes", NULL);
    {
        /* through the API: validate catches what a caller built */
        eo_mesh *b = NULL;
        eo_mesh_load(ctx, "gen:1,1,1:1,1,1", NULL, &b);
        b->tets[4 * 3 + 2] = -1;
        expect_err(ctx, eo_mesh_validate(ctx, b, NULL, "api"), EO_ERR_MESH, "api range", "api: tet 3",
                   "expected vertex indices in [0, 8), got -1", NULL);
        b->tets[4 * 3 + 2] = 5;
        b->X[3 * 6 + 1] = NAN;
        expect_err(ctx, eo_mesh_validate(ctx, b, NULL, "api"), EO_ERR_NONFINITE, "api nan", "api: vertex 6", NULL);
        eo_mesh_destroy(&b);
    }
    put_file("dupnode.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n2 0 1 0\n4 0 0 1\n"
                            "$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n");
    expect_err(ctx, read_file_status(ctx, "dupnode.msh", NULL, &m), EO_ERR_PARSE, "duplicate node tag",
               "dupnode.msh:8:", "vertex 2", "repeated", NULL);

    /* duplicate tets (same vertex set, other order) */
    put_file("dup.node", "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n");
    put_file("dup.ele", "3 4 0\n1 1 2 3 4\n2 2 4 3 5\n3 4 3 2 1\n");
    expect_err(ctx, read_file_status(ctx, "dup.ele", NULL, &m), EO_ERR_MESH, "duplicate tet", "dup.ele:4:", "tet 3",
               "duplicate of tet 1", NULL);
    rc = read_file_status(ctx, "dup.ele", &drop, &m);
    CHECK(rc == EO_WARN_DROPPED && m && m->nt == 2 && m->dropped_tets == 1, "duplicate dropped: rc %d", rc);
    if (m) CHECK_CLOSE(eo_mesh_volume(m), 0.5, 1e-12);
    eo_mesh_destroy(&m);

    /* zero-volume tet (coplanar points) */
    put_file("flat.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                         "5 1 1 0\n6 2 2 0\n$EndNodes\n$Elements\n2\n1 4 0 1 2 3 4\n2 4 0 2 3 5 6\n$EndElements\n");
    expect_err(ctx, read_file_status(ctx, "flat.msh", NULL, &m), EO_ERR_MESH, "zero volume", "flat.msh:16:", "tet 2",
               "zero volume", NULL);
    rc = read_file_status(ctx, "flat.msh", &drop, &m);
    CHECK(rc == EO_WARN_DROPPED && m && m->nt == 1 && m->nv == 4 && m->dropped_tets == 1 && m->dropped_vertices == 2,
          "zero-volume dropped (and its now unreferenced vertices): rc %d", rc);
    eo_mesh_destroy(&m);

    /* unreferenced vertex: error, then dropped + renumbered */
    put_file("unref.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n6\n0 0 0 0\n9 9 9 0\n1 0 0 0\n0 1 0 0\n"
                           "0 0 1 0\n1 1 1 5\nTetrahedra\n2\n1 3 4 5 0\n3 5 4 6 0\nEnd\n");
    expect_err(ctx, read_file_status(ctx, "unref.mesh", NULL, &m), EO_ERR_MESH, "unreferenced", "unref.mesh:6:",
               "vertex 2", "not used by any tet", NULL);
    eo_mesh_read_opts du = eo_mesh_read_opts_default();
    du.drop_unreferenced = 1;
    rc = read_file_status(ctx, "unref.mesh", &du, &m);
    CHECK(rc == EO_WARN_DROPPED && m && m->nv == 5 && m->dropped_vertices == 1, "unreferenced dropped: rc %d", rc);
    if (m) {
        CHECK(m->tets[1] == 1 && m->tets[7] == 4 && m->vmarker[4] == 5, "renumbered with markers");
        CHECK_CLOSE(eo_mesh_volume(m), 0.5, 1e-12);
    }
    eo_mesh_destroy(&m);

    /* format-level problems */
    put_file("bin.msh", "$MeshFormat\n4.1 1 8\n$EndMeshFormat\n");
    expect_err(ctx, read_file_status(ctx, "bin.msh", NULL, &m), EO_ERR_UNSUPPORTED, "binary", "bin.msh:2:", "ASCII",
               NULL);
    put_file("v3.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n");
    expect_err(ctx, read_file_status(ctx, "v3.msh", NULL, &m), EO_ERR_UNSUPPORTED, "version", "v3.msh:2:",
               "expected MSH version 2.2 or 4.1, got 3", NULL);
    put_file("nosurf.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Surface\n1\n1 2 3\n");
    expect_err(ctx, read_file_status(ctx, "nosurf.msh", NULL, &m), EO_ERR_PARSE, "unclosed section", "nosurf.msh:",
               "expected '$EndSurface'", NULL);
    put_file("notets.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                           "$Elements\n1\n1 2 0 1 2 3\n$EndElements\n");
    expect_err(ctx, read_file_status(ctx, "notets.msh", NULL, &m), EO_ERR_MESH, "no tets", "notets.msh",
               "no tetrahedra", NULL);
    put_file("dim2.mesh", "MeshVersionFormatted 1\nDimension 2\n");
    expect_err(ctx, read_file_status(ctx, "dim2.mesh", NULL, &m), EO_ERR_PARSE, "2d medit", "dim2.mesh:2:",
               "expected dimension 3 in [3, 3], got '2'", NULL);
    put_file("skip.node", "4 3 0 0\n1 0 0 0\n3 1 0 0\n4 0 1 0\n5 0 0 1\n");
    expect_err(ctx, read_file_status(ctx, "skip.node", NULL, &m), EO_ERR_PARSE, "non-consecutive", "skip.node:3:",
               "expected point index 2 (consecutive), got 3", NULL);
    CHECK(m == NULL, "no mesh after failures");
    eo_test_ctx_done(&ctx);
}

/* ---- unwritable output ------------------------------------------------------------- */

static void test_unwritable(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh *m = NULL;
    eo_mesh_load(ctx, "gen:1,1,1:2,2,2", NULL, &m);
    put_file("plainfile", "x");
    static const char *const ext[] = {".node", ".mesh", ".msh", ".vtu", ".obj"};
    for (int i = 0; i < 5; i++) {
        char p1[4300], p2[4300];
        snprintf(p1, sizeof p1, "%s/no/such/dir/out%s", tmp, ext[i]);
        snprintf(p2, sizeof p2, "%s/plainfile/out%s", tmp, ext[i]); /* parent is a file: fails even as root */
        expect_err(ctx, eo_mesh_write(ctx, m, p1, EO_MESH_AUTO), EO_ERR_IO, "missing folder", "no/such/dir/out",
                   "cannot write", NULL);
        expect_err(ctx, eo_mesh_write(ctx, m, p2, EO_MESH_AUTO), EO_ERR_IO, "parent is a file", "plainfile/out",
                   "cannot write", NULL);
    }
    expect_err(ctx, eo_mesh_write(ctx, m, tpath("out.xyz"), EO_MESH_AUTO), EO_ERR_UNSUPPORTED, "unknown ext",
               "out.xyz", NULL);
    CHECK(count_files(tmp, "out") == 0, "nothing written");
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

/* ---- failure injection ----------------------------------------------------------- */

static void inject(const char *label, int (*op)(eo_ctx *, void *), void *arg)
{
    eo_ctx *ctx = eo_test_ctx();
    int ok = 0, failures = 0;
    for (long n = 1; n < 10000 && !ok; n++) {
        eo_ctx_fail_after(ctx, n);
        int rc = op(ctx, arg);
        eo_ctx_fail_after(ctx, 0);
        if (rc >= 0) ok = 1;
        else {
            failures++;
            CHECK(rc == EO_ERR_NOMEM, "%s: allocation %ld: status %s (%s)", label, n, eo_status_name(rc),
                  eo_ctx_message(ctx));
        }
        CHECK(eo_ctx_live_bytes(ctx) == 0, "%s: allocation %ld failed: %zu bytes leaked", label, n,
              eo_ctx_live_bytes(ctx));
        /* a leak, or an error the injection did not cause (a missing input), repeats at
         * every n: report it once */
        if (eo_ctx_live_bytes(ctx) || (rc < 0 && rc != EO_ERR_NOMEM)) break;
    }
    CHECK(ok && failures > 0, "%s: succeeded after %d injected failures", label, failures);
    eo_test_ctx_done(&ctx);
}

static int op_read(eo_ctx *ctx, void *arg)
{
    eo_mesh *m = NULL;
    eo_mesh_read_opts o = eo_mesh_read_opts_default();
    o.drop_degenerate = o.drop_unreferenced = 1;
    int rc = eo_mesh_read(ctx, arg, &o, &m);
    eo_mesh_destroy(&m);
    return rc;
}

static int op_write(eo_ctx *ctx, void *arg)
{
    eo_mesh *m = NULL;
    int rc = eo_mesh_load(ctx, "gen:1,1,1:2,2,2:5", NULL, &m);
    if (rc >= 0) rc = eo_mesh_write(ctx, m, arg, EO_MESH_AUTO);
    eo_mesh_destroy(&m);
    return rc;
}

static int op_series(eo_ctx *ctx, void *arg)
{
    (void)arg;
    eo_mesh *m = NULL;
    eo_pvd *p = NULL;
    int rc = eo_mesh_load(ctx, "gen:1,1,1:1,1,1", NULL, &m);
    if (rc >= 0) rc = eo_pvd_create(ctx, tpath("inj.pvd"), &p);
    for (int k = 0; k < 3 && rc >= 0; k++) rc = eo_pvd_add(ctx, p, k, "frame.vtu");
    eo_pvd_destroy(&p);
    eo_mesh_destroy(&m);
    return rc;
}

static void test_injection(void)
{
    char p[6][4300];
    snprintf(p[0], sizeof p[0], "%s", eo_test_shared_path("meshes/ipc_bar-2523.msh"));
    snprintf(p[1], sizeof p[1], "%s", tpath("g22.msh"));
    snprintf(p[2], sizeof p[2], "%s", tpath("tg0"));
    snprintf(p[3], sizeof p[3], "%s", tpath("ok.mesh"));
    snprintf(p[4], sizeof p[4], "%s", tpath("unref.mesh"));
    snprintf(p[5], sizeof p[5], "%s", tpath("dup.ele"));
    for (int i = 0; i < 6; i++) inject(p[i], op_read, p[i]);
    static const char *const ext[] = {"inj.node", "inj.mesh", "inj.msh", "inj.vtu", "inj.obj"};
    for (int i = 0; i < 5; i++) {
        char q[4300];
        snprintf(q, sizeof q, "%s", tpath(ext[i]));
        inject(q, op_write, q);
    }
    inject("pvd", op_series, NULL);
    CHECK(count_files(tmp, ".tmp.") == 0, "no temporary files left after injected failures");
}

/* ---- load time ----------------------------------------------------------------------- */

static void test_load_time(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh *m = NULL;
    /* 34 x 34 x 29 cells x 6 = 201144 tets */
    CHECK(eo_mesh_load(ctx, "gen:1,1,1:34,34,29", NULL, &m) == EO_OK, "gen big");
    static const char *const names[] = {"big.msh", "big.mesh", "big.node"};
    for (int i = 0; i < 3; i++) {
        CHECK(eo_mesh_write(ctx, m, tpath(names[i]), EO_MESH_AUTO) == EO_OK, "write %s", names[i]);
        eo_mesh *b = NULL;
        double t0 = eo_wtime();
        clock_t c0 = clock();
        int rc = eo_mesh_read(ctx, tpath(names[i]), NULL, &b);
        double dt = eo_wtime() - t0, dc = (double)(clock() - c0) / CLOCKS_PER_SEC;
        CHECK(rc == EO_OK && b && b->nt == m->nt, "read %s", names[i]);
        printf("load %-9s %d vertices %d tets: %.3f s wall, %.3f s cpu\n", names[i], m->nv, m->nt, dt, dc);
        eo_mesh_destroy(&b);
    }
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

/* ---- tags, scene selectors, VTU input, hostile paths (issue 14) ---------------------- */

/* A unit cube of 6 tets (the generator's) as Gmsh 4.1 with $Entities: the x = 0 face is
 * surface 1 in physical groups 11 and 13, the x = 1 face surface 2 in group 12, the
 * volume entity 1 in physical group 5. entities = 0: the same without $Entities. */
static char *cube41(eo_ctx *ctx, int entities)
{
    eo_mesh_gen_opts g = eo_mesh_gen_opts_default();
    g.cells[0] = g.cells[1] = g.cells[2] = 1;
    eo_mesh *m = NULL;
    eo_mesh_generate_box(ctx, &g, &m);
    int *f = NULL, nf = 0;
    eo_mesh_boundary_faces(ctx, m, &f, &nf);
    static char buf[8192];
    size_t k = 0;
    k += (size_t)snprintf(buf + k, sizeof buf - k, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    if (entities)
        k += (size_t)snprintf(buf + k, sizeof buf - k,
                              "$Entities\n0 0 2 1\n1 0 0 0 0 1 1 2 11 13 0\n2 1 0 0 1 1 1 1 12 0\n"
                              "1 0 0 0 1 1 1 1 5 2 1 -2\n$EndEntities\n");
    k += (size_t)snprintf(buf + k, sizeof buf - k, "$Nodes\n1 8 1 8\n3 1 0 8\n");
    for (int v = 0; v < 8; v++) k += (size_t)snprintf(buf + k, sizeof buf - k, "%d\n", v + 1);
    for (int v = 0; v < 8; v++)
        k += (size_t)snprintf(buf + k, sizeof buf - k, "%g %g %g\n", m->X[3 * v], m->X[3 * v + 1], m->X[3 * v + 2]);
    k += (size_t)snprintf(buf + k, sizeof buf - k, "$EndNodes\n$Elements\n3 10 1 10\n");
    int e = 1;
    for (int side = 0; side < 2; side++) {
        k += (size_t)snprintf(buf + k, sizeof buf - k, "2 %d 2 2\n", side + 1);
        for (int i = 0; i < nf; i++) {
            int on = 1;
            for (int a = 0; a < 3; a++) on &= m->X[3 * f[3 * i + a]] == side;
            if (on)
                k += (size_t)snprintf(buf + k, sizeof buf - k, "%d %d %d %d\n", e++, f[3 * i] + 1, f[3 * i + 1] + 1,
                                      f[3 * i + 2] + 1);
        }
    }
    k += (size_t)snprintf(buf + k, sizeof buf - k, "3 1 4 6\n");
    for (int t = 0; t < 6; t++)
        k += (size_t)snprintf(buf + k, sizeof buf - k, "%d %d %d %d %d\n", e++, m->tets[4 * t] + 1, m->tets[4 * t + 1] + 1,
                              m->tets[4 * t + 2] + 1, m->tets[4 * t + 3] + 1);
    snprintf(buf + k, sizeof buf - k, "$EndElements\n");
    eo_free(ctx, f);
    eo_mesh_destroy(&m);
    return buf;
}

static int count_tag(const eo_mesh *m, int tag)
{
    int n = 0;
    for (int i = 0; i < m->ntri; i++) n += m->tri_tag[i] == tag;
    return n;
}

static void test_tags(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh *m = NULL, *b = NULL;
    put_file("cube41.msh", cube41(ctx, 1));
    int rc = read_file_status(ctx, "cube41.msh", NULL, &m);
    CHECK(rc == EO_OK, "gmsh 4.1 with entities: %s", eo_ctx_message(ctx));
    if (m) {
        CHECK(m->ntri == 6 && count_tag(m, 11) == 2 && count_tag(m, 13) == 2 && count_tag(m, 12) == 2,
              "4.1 triangles once per physical group: %d", m->ntri);
        int attr5 = 1;
        for (int t = 0; t < m->nt; t++) attr5 &= m->tet_attr[t] == 5;
        CHECK(attr5, "4.1 tets take the volume's physical group 5");
        for (int i = 0; i < m->ntri; i++) {
            double x = m->tri_tag[i] == 12 ? 1 : 0;
            for (int a = 0; a < 3; a++) CHECK(m->X[3 * m->tris[3 * i + a]] == x, "triangle %d on its face", i);
        }
        /* writers keep the triangles: MEDIT and TetGen (.face) round trips */
        CHECK(eo_mesh_write(ctx, m, tpath("cube_t.mesh"), EO_MESH_AUTO) == EO_OK, "write medit");
        CHECK(read_file_status(ctx, "cube_t.mesh", NULL, &b) == EO_OK && b->ntri == 6 && count_tag(b, 13) == 2 &&
                  memcmp(b->tris, m->tris, sizeof(int) * 18) == 0,
              "medit Triangles round trip: %s", eo_ctx_message(ctx));
        eo_mesh_destroy(&b);
        CHECK(eo_mesh_write(ctx, m, tpath("cube_t.node"), EO_MESH_AUTO) == EO_OK, "write tetgen");
        CHECK(read_file_status(ctx, "cube_t", NULL, &b) == EO_OK && b->ntri == 6 && count_tag(b, 12) == 2 &&
                  memcmp(b->tris, m->tris, sizeof(int) * 18) == 0,
              "tetgen .face round trip: %s", eo_ctx_message(ctx));
        eo_mesh_destroy(&b);
    }
    eo_mesh_destroy(&m);
    put_file("cube41n.msh", cube41(ctx, 0));
    rc = read_file_status(ctx, "cube41n.msh", NULL, &m);
    CHECK(rc == EO_OK && m->ntri == 4 && count_tag(m, 1) == 2 && count_tag(m, 2) == 2 && m->tet_attr[0] == 1,
          "4.1 without $Entities: entity tags (%s)", eo_ctx_message(ctx));
    eo_mesh_destroy(&m);
    /* MEDIT Triangles; TetGen .face through the buffer entry point */
    const char *medit = "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
                        "Triangles\n2\n1 2 3 7\n1 2 4 8\nTetrahedra\n1\n1 2 3 4 1\nEnd\n";
    rc = eo_mesh_read_buffer(ctx, medit, strlen(medit), EO_MESH_MEDIT, "t.mesh", NULL, &m);
    CHECK(rc == EO_OK && m->ntri == 2 && m->tri_tag[0] == 7 && m->tri_tag[1] == 8 && m->tris[5] == 3,
          "medit triangles: %s", eo_ctx_message(ctx));
    eo_mesh_destroy(&m);
    const char *bad = "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
                      "Triangles\n1\n1 2 9 7\nTetrahedra\n1\n1 2 3 4 1\nEnd\n";
    expect_err(ctx, eo_mesh_read_buffer(ctx, bad, strlen(bad), EO_MESH_MEDIT, "t.mesh", NULL, &m), EO_ERR_MESH,
               "medit triangle out of range", "t.mesh:11: triangle 1: expected vertex index in [1, 4], got 9", NULL);
    static const char tg[] = "4 3 0 1\n0 0 0 0 1\n1 1 0 0 2\n2 0 1 0 2\n3 0 0 1 3\n\0"
                             "1 4 0\n0 0 1 2 3\n\0"
                             "2 1\n0 0 2 1 21\n1 0 1 3 22\n";
    rc = eo_mesh_read_buffer(ctx, tg, sizeof tg - 1, EO_MESH_TETGEN, "t", NULL, &m);
    CHECK(rc == EO_OK && m->ntri == 2 && m->tri_tag[1] == 22 && m->tris[5] == 3 && m->vmarker[3] == 3,
          "tetgen .face (0-based) with markers: %s", eo_ctx_message(ctx));
    eo_mesh_destroy(&m);
    static const char tgb[] = "4 3 0 1\n0 0 0 0 1\n1 1 0 0 2\n2 0 1 0 2\n3 0 0 1 3\n\0"
                              "1 4 0\n0 0 1 2 3\n\0"
                              "1 1\n0 0 2 7 21\n";
    expect_err(ctx, eo_mesh_read_buffer(ctx, tgb, sizeof tgb - 1, EO_MESH_TETGEN, "t", NULL, &m), EO_ERR_MESH,
               ".face out of range", "t.face:2: triangle 0: expected point index in [0, 3], got 7", NULL);
    eo_test_ctx_done(&ctx);
}

static eo_scene *load_scene(eo_ctx *ctx, const char *name, const char *json, int *rc)
{
    put_file(name, json);
    eo_cfg *cfg = NULL;
    eo_scene *sc = NULL;
    *rc = eo_cfg_load(ctx, tpath(name), NULL, &cfg);
    if (*rc >= 0) *rc = eo_scene_load(ctx, cfg, &sc);
    eo_cfg_destroy(&cfg);
    return sc;
}

static void test_scene_selectors(void)
{
    eo_ctx *ctx = eo_test_ctx();
    put_file("cube41.msh", cube41(ctx, 1));
    int rc;
    eo_scene *sc = load_scene(ctx, "tags.json",
                              "{\"mesh\": {\"file\": \"cube41.msh\"},\n"
                              " \"boundary\": [{\"tag\": 11, \"fixed\": true},\n"
                              "   {\"tag\": 12, \"translate\": [0.1, 0, 0]},\n"
                              "   {\"tag\": 13, \"fixed\": true},\n"
                              "   {\"tag\": 5, \"fixed\": true},\n"
                              "   {\"surface\": true, \"fixed\": true},\n"
                              "   {\"nearest\": [1.1, 1.2, 0.9], \"fixed\": true}]}\n",
                              &rc);
    CHECK(rc == EO_OK && sc, "tag scene: %s", eo_ctx_message(ctx));
    if (sc) {
        const eo_bc *bc = sc->bc;
        const eo_mesh *m = sc->mesh;
        CHECK(bc[0].nverts == 4 && bc[0].tag_source == EO_TAG_TRIANGLES, "tag 11: %d vertices", bc[0].nverts);
        int x0 = 1, x1 = 1;
        for (int i = 0; i < 4; i++) {
            x0 &= m->X[3 * bc[0].verts[i]] == 0;
            x1 &= m->X[3 * bc[1].verts[i]] == 1;
        }
        CHECK(x0 && x1 && bc[1].nverts == 4, "tag 11 = the x = 0 face, tag 12 = the x = 1 face");
        CHECK(bc[2].nverts == 4 && memcmp(bc[2].verts, bc[0].verts, 4 * sizeof(int)) == 0, "tag 13 = tag 11's face");
        CHECK(bc[3].nverts == 8 && bc[3].tag_source == EO_TAG_TETS, "tag 5: the volume's 8 vertices (%d)", bc[3].nverts);
        CHECK(bc[4].nverts == 8 && bc[4].select == EO_BC_SURFACE, "surface: 8 vertices");
        int v = bc[5].verts[0];
        CHECK(bc[5].nverts == 1 && m->X[3 * v] == 1 && m->X[3 * v + 1] == 1 && m->X[3 * v + 2] == 1,
              "nearest [1.1, 1.2, 0.9] -> the (1, 1, 1) corner");
        CHECK_CLOSE(bc[5].nearest_dist, sqrt(0.01 + 0.04 + 0.01), 1e-15);
        char *text = NULL;
        CHECK(eo_scene_describe(ctx, sc, &text) == EO_OK, "describe");
        CHECK(text && strstr(text, "boundary.0 (tag 11 of the tagged triangles; fixed): 4 vertices\n") &&
                  strstr(text, "boundary.3 (tag 5 of the tets; fixed): 8 vertices\n") &&
                  strstr(text, "boundary.4 (boundary surface; fixed): 8 vertices\n") &&
                  strstr(text, "boundary.5 (nearest [1.1, 1.2, 0.9]: vertex ") && strstr(text, "): 1 vertex\n") &&
                  strstr(text, "region 0 (material, ") && strstr(text, "): 6 tets\n") && !strstr(text, "warning: gravity") &&
              strstr(text, "warning: boundary.1 and boundary.3 share 4 vertices but prescribe different motions"),
              "description:\n%s", text ? text : "(null)");
        eo_free(ctx, text);
    }
    eo_scene_destroy(&sc);
    sc = load_scene(ctx, "tag99.json",
                    "{\"mesh\": {\"file\": \"cube41.msh\"},\n \"boundary\": [\n  {\"tag\": 99, \"fixed\": true}]}\n", &rc);
    expect_err(ctx, rc, EO_ERR_INVALID, "absent tag", "tag99.json:3", "key 'boundary.0.tag'",
               "no tagged triangle, tet or vertex carries tag 99; the mesh has triangle tags: 11, 12, 13; tet "
               "attributes: 5; vertex markers: none",
               NULL);
    sc = load_scene(ctx, "surf0.json",
                    "{\"mesh\": {\"file\": \"cube41.msh\"},\n \"boundary\": [\n  {\"surface\": false, \"fixed\": true}]}\n",
                    &rc);
    expect_err(ctx, rc, EO_ERR_INVALID, "surface false", "surf0.json:3", "give true", NULL);
    sc = load_scene(ctx, "two.json",
                    "{\"mesh\": {\"file\": \"cube41.msh\"},\n \"boundary\": [\n  {\"surface\": true, \"tag\": 11, "
                    "\"fixed\": true}]}\n",
                    &rc);
    expect_err(ctx, rc, EO_ERR_INVALID, "two selectors", "exactly one of", "\"nearest\" (found 2)", NULL);
    sc = load_scene(ctx, "tg.json", "{\"mesh\": {\"file\": \"cube41.msh\", \"tetgen\": {\"quality\": 1.5}}}\n", &rc);
    expect_err(ctx, rc, EO_ERR_INVALID, "tetgen keys on a volume mesh", "mesh.tetgen applies to surface mesh files",
               NULL);
    /* gravity against an obvious up: a square pyramid (2 tets) standing on z = 0 */
    put_file("pyramid.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n0 0 0 0\n1 0 0 0\n1 1 0 0\n0 1 0 0\n"
                             "0.5 0.5 1 0\nTetrahedra\n2\n1 2 3 5 1\n1 3 4 5 1\nEnd\n");
    for (int k = 0; k < 2; k++) {
        sc = load_scene(ctx, "pyr.json",
                        k ? "{\"mesh\": {\"file\": \"pyramid.mesh\"}, \"gravity\": [0, -9.81, 0]}\n"
                          : "{\"mesh\": {\"file\": \"pyramid.mesh\"}}\n",
                        &rc);
        CHECK(rc == EO_OK, "pyramid: %s", eo_ctx_message(ctx));
        if (!sc) continue;
        eo_scene_up up;
        CHECK(eo_scene_up_guess(ctx, sc, &up) == EO_OK && up.axis == 2 && up.sign == -1 && up.warn == k,
              "pyramid base -z (axis %d sign %d warn %d)", up.axis, up.sign, up.warn);
        CHECK_CLOSE(up.support, 1.0, 1e-12);
        char *text = NULL;
        eo_scene_describe(ctx, sc, &text);
        CHECK(text && (strstr(text, "warning: gravity [0, -9.81, 0] does not point down this mesh: it rests on a flat "
                                    "base facing -z (100% of that bounding-box side") != NULL) == k &&
                  (!k || strstr(text, "looks z-up; set gravity [0, 0, -9.81]")),
              "pyramid description (gravity %s):\n%s", k ? "-y" : "-z", text);
        eo_free(ctx, text);
        eo_scene_destroy(&sc);
    }
    /* a box has no obvious up */
    sc = load_scene(ctx, "box.json", "{\"gravity\": [0, -9.81, 0]}\n", &rc);
    eo_scene_up up;
    CHECK(sc && eo_scene_up_guess(ctx, sc, &up) == EO_OK && up.axis == -1 && !up.warn, "box: no up, no warning");
    eo_scene_destroy(&sc);
    /* the IPC bunny is y-up: base -y, 26% support, 5.4x (when the shared meshes exist) */
    if (access(eo_test_shared_path("meshes/ipc_bunny.msh"), R_OK) == 0) {
        char js[600];
        snprintf(js, sizeof js, "{\"mesh\": {\"file\": \"%s\"}}\n", eo_test_shared_path("meshes/ipc_bunny.msh"));
        sc = load_scene(ctx, "bunny.json", js, &rc);
        CHECK(sc && eo_scene_up_guess(ctx, sc, &up) == EO_OK && up.axis == 1 && up.sign == -1 && up.warn &&
                  up.support > 0.25 && up.support < 0.27 && up.ratio > 5 && up.ratio < 6,
              "bunny: axis %d sign %d support %g ratio %g (%s)", up.axis, up.sign, up.support, up.ratio,
              eo_ctx_message(ctx));
        eo_scene_destroy(&sc);
    }
    eo_test_ctx_done(&ctx);
}

static void b64(const unsigned char *p, size_t n, char *out)
{
    static const char al[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t k = 0;
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)p[i] << 16 | (i + 1 < n ? (unsigned)p[i + 1] << 8 : 0) | (i + 2 < n ? p[i + 2] : 0);
        out[k++] = al[v >> 18 & 63];
        out[k++] = al[v >> 12 & 63];
        out[k++] = i + 1 < n ? al[v >> 6 & 63] : '=';
        out[k++] = i + 2 < n ? al[v & 63] : '=';
    }
    out[k] = 0;
}

/* base64 of a UInt32 byte count + data, encoded together (joint) or apart */
static void b64_block(const void *data, uint32_t n, int joint, char *out)
{
    unsigned char buf[512];
    memcpy(buf, &n, 4);
    memcpy(buf + 4, data, n);
    if (joint) {
        b64(buf, 4 + (size_t)n, out);
    } else {
        b64(buf, 4, out);
        b64(buf + 4, n, out + strlen(out));
    }
}

static void test_vtu_read(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh_gen_opts g = eo_mesh_gen_opts_default();
    g.cells[0] = 3;
    g.cells[1] = 2;
    g.cells[2] = 1;
    g.size[0] = 1.5;
    eo_mesh *m = NULL, *b = NULL;
    eo_mesh_generate_box(ctx, &g, &m);
    m->tet_attr = eo_malloc(ctx, sizeof(int) * (size_t)m->nt);
    for (int t = 0; t < m->nt; t++) m->tet_attr[t] = t % 3 - 1;
    for (int i = 0; i < 3 * m->nv; i++) m->X[i] += 1e-3 * sin(7.0 * i); /* not round numbers */
    eo_vtu_fields f = {0};
    double *disp = eo_calloc(ctx, 3 * (size_t)m->nv, sizeof(double));
    f.displacement = disp;
    CHECK(eo_vtu_write(ctx, tpath("rt.vtu"), m, &f) == EO_OK, "write");
    int rc = read_file_status(ctx, "rt.vtu", NULL, &b);
    CHECK(rc == EO_OK, "vtu round trip: %s", eo_ctx_message(ctx));
    if (b) {
        CHECK(b->nv == m->nv && b->nt == m->nt && memcmp(b->X, m->X, sizeof(double) * 3 * (size_t)m->nv) == 0 &&
                  memcmp(b->tets, m->tets, sizeof(int) * 4 * (size_t)m->nt) == 0,
              "vtu round trip exact: %d %d", b->nv, b->nt);
        CHECK(b->tet_attr && memcmp(b->tet_attr, m->tet_attr, sizeof(int) * (size_t)m->nt) == 0, "region -> tet_attr");
    }
    eo_mesh_destroy(&b);
    eo_free(ctx, disp);
    eo_mesh_destroy(&m);
    /* ASCII: one tet, a triangle (tag from region), a vertex cell (skipped) */
    const char *ascii =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n<UnstructuredGrid>\n"
        "<Piece NumberOfPoints=\"4\" NumberOfCells=\"3\">\n<CellData>\n"
        "<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">4 9 0</DataArray>\n</CellData>\n"
        "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">\n"
        "0 0 0  1 0 0  0 1 0  0 0 2\n</DataArray>\n</Points>\n<Cells>\n"
        "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3  0 2 1  3</DataArray>\n"
        "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4 7 8</DataArray>\n"
        "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 5 1</DataArray>\n"
        "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    rc = eo_mesh_read_buffer(ctx, ascii, strlen(ascii), EO_MESH_VTU, "a.vtu", NULL, &m);
    CHECK(rc == EO_OK && m->nv == 4 && m->nt == 1 && m->tet_attr[0] == 4 && m->ntri == 1 && m->tri_tag[0] == 9,
          "ascii vtu: %s", eo_ctx_message(ctx));
    if (m) CHECK_CLOSE(eo_mesh_volume(m), 2.0 / 6, 1e-15);
    eo_mesh_destroy(&m);
    /* inline binary (base64), header and data encoded together and apart; appended base64 */
    double X[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 3};
    int32_t conn[4] = {0, 1, 2, 3}, offs[1] = {4};
    unsigned char types[1] = {10};
    for (int joint = 0; joint < 2; joint++) {
        char px[256], pc[64], po[64], pt[64], text[2048];
        b64_block(X, sizeof X, joint, px);
        b64_block(conn, sizeof conn, joint, pc);
        b64_block(offs, sizeof offs, joint, po);
        b64_block(types, sizeof types, joint, pt);
        snprintf(text, sizeof text,
                 "<VTKFile type=\"UnstructuredGrid\" byte_order=\"LittleEndian\" header_type=\"UInt32\">\n"
                 "<UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n<Points>\n"
                 "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">\n  %s\n</DataArray>\n"
                 "</Points>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"binary\">%s</DataArray>\n"
                 "<DataArray type=\"Int32\" Name=\"offsets\" format=\"binary\">%s</DataArray>\n"
                 "<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">%s</DataArray>\n</Cells>\n"
                 "</Piece></UnstructuredGrid></VTKFile>\n",
                 px, pc, po, pt);
        rc = eo_mesh_read_buffer(ctx, text, strlen(text), EO_MESH_VTU, "b.vtu", NULL, &m);
        CHECK(rc == EO_OK && m->nt == 1 && memcmp(m->X, X, sizeof X) == 0, "binary vtu (joint %d): %s", joint,
              eo_ctx_message(ctx));
        if (m) CHECK_CLOSE(eo_mesh_volume(m), 0.5, 1e-15);
        eo_mesh_destroy(&m);
        /* the same as appended base64 */
        size_t lx = strlen(px), lc = strlen(pc), lo = strlen(po);
        snprintf(text, sizeof text,
                 "<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt32\">\n"
                 "<UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n<Points>\n"
                 "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>\n</Points>\n"
                 "<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"appended\" offset=\"%zu\"/>\n"
                 "<DataArray type=\"Int32\" Name=\"offsets\" format=\"appended\" offset=\"%zu\"/>\n"
                 "<DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"%zu\"/>\n</Cells>\n"
                 "</Piece></UnstructuredGrid>\n<AppendedData encoding=\"base64\">\n_%s%s%s%s\n</AppendedData></VTKFile>\n",
                 lx, lx + lc, lx + lc + lo, px, pc, po, pt);
        rc = eo_mesh_read_buffer(ctx, text, strlen(text), EO_MESH_VTU, "c.vtu", NULL, &m);
        CHECK(rc == EO_OK && m->nt == 1 && memcmp(m->X, X, sizeof X) == 0, "appended base64 vtu (joint %d): %s", joint,
              eo_ctx_message(ctx));
        eo_mesh_destroy(&m);
    }
    /* errors */
    char t2[2048];
    snprintf(t2, sizeof t2, "%s", ascii);
    char *p = strstr(t2, "10 5 1");
    p[0] = '1';
    p[1] = '2'; /* hexahedron */
    expect_err(ctx, eo_mesh_read_buffer(ctx, t2, strlen(t2), EO_MESH_VTU, "h.vtu", NULL, &m), EO_ERR_UNSUPPORTED,
               "hex cell", "h.vtu:16: cell 0: VTK cell type 12; expected tetrahedra (10 or quadratic 24)", NULL);
    snprintf(t2, sizeof t2, "%s", ascii);
    p = strstr(t2, "0 1 2 3 ");
    p[6] = '7';
    expect_err(ctx, eo_mesh_read_buffer(ctx, t2, strlen(t2), EO_MESH_VTU, "r.vtu", NULL, &m), EO_ERR_MESH,
               "index out of range", "r.vtu:14: cell 0: expected point indices in [0, 4), got 7", NULL);
    snprintf(t2, sizeof t2, "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkZLibDataCompressor\">\n%s",
             strstr(ascii, "<UnstructuredGrid>"));
    expect_err(ctx, eo_mesh_read_buffer(ctx, t2, strlen(t2), EO_MESH_VTU, "z.vtu", NULL, &m), EO_ERR_UNSUPPORTED,
               "compressed", "z.vtu:1: compressed VTU", NULL);
    snprintf(t2, sizeof t2, "%s", ascii);
    p = strstr(t2, "4 7 8");
    p[0] = ' ';
    expect_err(ctx, eo_mesh_read_buffer(ctx, t2, strlen(t2), EO_MESH_VTU, "o.vtu", NULL, &m), EO_ERR_PARSE,
               "short offsets", "o.vtu:15: DataArray 'offsets': expected 3 numbers, got 2", NULL);
    eo_test_ctx_done(&ctx);
}

static int file_is(const char *path, const char *text)
{
    size_t n = 0;
    char *s = slurp(path, &n);
    int same = s && n == strlen(text) && memcmp(s, text, n) == 0;
    free(s);
    return same;
}

static void test_paths(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_mesh *m = NULL;
    unlink(tpath("fifo.msh"));
    CHECK(mkfifo(tpath("fifo.msh"), 0600) == 0, "mkfifo: %s", strerror(errno));
    expect_err(ctx, read_file_status(ctx, "fifo.msh", NULL, &m), EO_ERR_IO, "FIFO input (no hang)", "fifo.msh: is a FIFO",
               "expected a mesh file", NULL);
    mkdir(tpath("dir.msh"), 0700);
    expect_err(ctx, read_file_status(ctx, "dir.msh", NULL, &m), EO_ERR_IO, "folder input", "dir.msh: is a folder", NULL);
    eo_mesh_read_opts o = eo_mesh_read_opts_default();
    o.format = EO_MESH_GMSH;
    expect_err(ctx, eo_mesh_read(ctx, "/dev/null", &o, &m), EO_ERR_IO, "device input", "/dev/null: is a character device",
               NULL);
    expect_err(ctx, eo_mesh_read(ctx, "/dev/zero", &o, &m), EO_ERR_IO, "endless device", "/dev/zero: is a character device",
               NULL);
    static char longname[6000];
    memset(longname, 'a', sizeof longname - 5);
    memcpy(longname + sizeof longname - 5, ".msh", 5);
    expect_err(ctx, eo_mesh_read(ctx, longname, NULL, &m), EO_ERR_IO, "name > PATH_MAX", "longer than the system allows",
               NULL);
    expect_err(ctx, eo_mesh_read(ctx, longname + sizeof longname - 300, NULL, &m), EO_ERR_IO, "component > NAME_MAX",
               "a component of 299 characters", NULL);
    put_file("unreadable.msh", "$MeshFormat\n");
    chmod(tpath("unreadable.msh"), 0);
    if (geteuid() != 0) /* root reads anything */
        expect_err(ctx, read_file_status(ctx, "unreadable.msh", NULL, &m), EO_ERR_IO, "unreadable", "cannot open", NULL);
    eo_mesh_gen_opts g = eo_mesh_gen_opts_default();
    g.cells[0] = g.cells[1] = g.cells[2] = 1;
    eo_mesh_generate_box(ctx, &g, &m);
    expect_err(ctx, eo_mesh_write(ctx, m, tpath("fifo.msh"), EO_MESH_AUTO), EO_ERR_IO, "FIFO output",
               "fifo.msh: cannot write: it is a FIFO", NULL);
    expect_err(ctx, eo_mesh_write(ctx, m, tpath("dir.msh"), EO_MESH_AUTO), EO_ERR_IO, "folder output",
               "dir.msh: cannot write: it is a folder", NULL);
    expect_err(ctx, eo_mesh_write(ctx, m, longname, EO_MESH_AUTO), EO_ERR_IO, "long output", "longer than the system", NULL);
    expect_err(ctx, eo_mesh_write(ctx, m, tpath("fifo.msh/x.msh"), EO_MESH_AUTO), EO_ERR_IO, "FIFO as folder",
               "is a FIFO (named pipe), not a folder", NULL);
    /* a TetGen pair never loses an existing file: .ele is a folder -> nothing touched */
    put_file("pair.node", "old node\n");
    mkdir(tpath("pair.ele"), 0700);
    expect_err(ctx, eo_mesh_write(ctx, m, tpath("pair.node"), EO_MESH_AUTO), EO_ERR_IO, "pair with a folder .ele",
               "pair.ele: cannot write: it is a folder", NULL);
    CHECK(file_is(tpath("pair.node"), "old node\n"), "pair.node kept");
    CHECK(count_files(tmp, ".tmp.") == 0 && count_files(tmp, ".bak.") == 0, "no temporaries left");
    /* overwriting an existing pair works and leaves no temporaries or backups */
    put_file("pair2.node", "old\n");
    put_file("pair2.ele", "old\n");
    CHECK(eo_mesh_write(ctx, m, tpath("pair2.ele"), EO_MESH_AUTO) == EO_OK, "overwrite pair: %s", eo_ctx_message(ctx));
    eo_mesh *b = NULL;
    CHECK(read_file_status(ctx, "pair2", NULL, &b) == EO_OK && b->nt == m->nt, "pair2 reads back");
    eo_mesh_destroy(&b);
    CHECK(count_files(tmp, ".tmp.") == 0 && count_files(tmp, ".bak.") == 0, "no temporaries or backups left");
    /* eo_rename_all: the second rename fails -> the first target is restored */
    put_file("ra.a", "A");
    put_file("ra.b", "B");
    put_file("ra.a.new", "A2");
    const char *tmps[2] = {tpath("ra.a.new"), tpath("ra.b.missing")};
    const char *dsts[2] = {tpath("ra.a"), tpath("ra.b")};
    expect_err(ctx, eo_rename_all(ctx, 2, tmps, dsts), EO_ERR_IO, "rename_all failure", "ra.b: cannot rename into place",
               NULL);
    CHECK(file_is(tpath("ra.a"), "A") && file_is(tpath("ra.b"), "B"), "both targets as before");
    CHECK(access(tpath("ra.a.new"), F_OK) != 0 && count_files(tmp, ".bak.") == 0, "temporary and backups removed");
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

/* The context's mesh source (eo_ctx_set_mesh_source: how the PETSc backend reads a mesh on
 * one MPI rank): eo_mesh_read answers through it with its status and message, a mesh it
 * returns along with an error is freed, eo_mesh_read_file still reads the file, and
 * removing the source restores reading. */
typedef struct src_log {
    int calls;
    char path[512];
    int fail;
} src_log;

static int fake_source(eo_ctx *ctx, const char *path, const eo_mesh_read_opts *opts, eo_mesh **out, void *user)
{
    src_log *l = user;
    l->calls++;
    snprintf(l->path, sizeof l->path, "%s", path);
    if (l->fail) { /* an error after making a mesh: eo_mesh_read must not leak it */
        eo_mesh_gen_opts g = eo_mesh_gen_opts_default();
        eo_mesh_generate_box(ctx, &g, out);
        return eo_error(ctx, EO_ERR_PARSE, "%s: rank 0 says no", path);
    }
    (void)opts;
    eo_mesh_gen_opts g = eo_mesh_gen_opts_default();
    g.cells[0] = g.cells[1] = g.cells[2] = 1;
    return eo_mesh_generate_box(ctx, &g, out); /* not the file's mesh: proves who answered */
}

static void test_mesh_source(void)
{
    eo_ctx *ctx = eo_test_ctx();
    put_file("src.mesh", medit_ok);
    src_log l = {0};
    eo_ctx_set_mesh_source(ctx, fake_source, &l);
    eo_mesh *m = NULL;
    int rc = eo_mesh_read(ctx, tpath("src.mesh"), NULL, &m);
    CHECK(rc == EO_OK && m && m->nv == 8 && m->nt == 6, "source: rc %d, %d vertices (the source's box: 8)", rc,
          m ? m->nv : -1);
    CHECK(l.calls == 1 && strcmp(l.path, tpath("src.mesh")) == 0, "source: %d calls, path '%s'", l.calls, l.path);
    eo_mesh_destroy(&m);
    rc = eo_mesh_read_file(ctx, tpath("src.mesh"), NULL, &m); /* the file itself, not the source */
    CHECK(rc == EO_OK && m && m->nv == 5 && m->nt == 2 && l.calls == 1, "read_file: rc %d, calls %d", rc, l.calls);
    eo_mesh_destroy(&m);
    rc = eo_mesh_load(ctx, "gen:1,1,1:2,2,2", NULL, &m); /* generated, not read: no source */
    CHECK(rc == EO_OK && m && m->nt == 48 && l.calls == 1, "gen: rc %d, calls %d", rc, l.calls);
    eo_mesh_destroy(&m);
    l.fail = 1;
    rc = eo_mesh_read(ctx, tpath("missing.mesh"), NULL, &m);
    CHECK(m == NULL, "source error: *out is NULL");
    expect_err(ctx, rc, EO_ERR_PARSE, "source error", "missing.mesh: rank 0 says no", NULL);
    eo_ctx_set_mesh_source(ctx, NULL, &l);
    rc = eo_mesh_read(ctx, tpath("src.mesh"), NULL, &m);
    CHECK(rc == EO_OK && m && m->nv == 5 && l.calls == 2, "source removed: rc %d, calls %d", rc, l.calls);
    eo_mesh_destroy(&m);
    eo_test_ctx_done(&ctx); /* counts live bytes: the failed source's mesh was freed */
}

int main(void)
{
    /* the real meshes live in the workspace's shared/ folder beside the repository */
    snprintf(tmp, sizeof tmp, "%s", eo_test_tmpdir("mesh"));
    test_tags();
    test_mesh_source();
    test_vtu_read();
    test_paths();
    test_scene_selectors();
    test_veg();
    FILE *probe = fopen(eo_test_shared_path("meshes/ipc_bar-2523.msh"), "rb");
    if (!probe) {
        printf("test_mesh: shared meshes not found at %s (set EO_SHARED): the rest skipped\n",
               eo_test_shared_path("meshes"));
        eo_test_finish("test_mesh");
        return eo_test_failed ? 1 : 77;
    }
    fclose(probe);
    test_generator();
    test_round_trips();
    test_ipc();
    test_gmsh22();
    test_tetgen();
    test_medit();
    test_vtu();
    test_bad_input();
    test_unwritable();
    test_injection();
    test_load_time();
    return eo_test_finish("test_mesh");
}
