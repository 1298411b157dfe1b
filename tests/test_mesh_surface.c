/* Surface meshes tetrahedralized by TetGen: procedurally written closed surfaces (a
 * unit cube, an icosphere of 320 triangles) in every surface format (OBJ, OFF, ASCII
 * and binary STL, ASCII and binary_little_endian PLY) become valid tet meshes whose
 * total volume equals the volume the surface encloses (divergence theorem) to 1e-9
 * relative, with and without quality refinement and a volume bound, and whose boundary
 * area equals the surface area. Bad surfaces (open, degenerate, index out of range)
 * fail with file:line. Exit 77 when the build has no TetGen (then it checks the error
 * names the meson option). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/io.h"
#include "elastopt/mesh.h"
#include "testutil.h"

static char dir[4096];

static const char *tpath(const char *name)
{
    static char buf[4][4400];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

/* ---- procedural surfaces ------------------------------------------------------------ */

typedef struct {
    int np, nt;
    double X[3 * 1000];
    int T[3 * 2000];
} surf;

static void cube(surf *s)
{
    static const int q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    s->np = 8;
    s->nt = 0;
    for (int v = 0; v < 8; v++) {
        s->X[3 * v] = (v == 1 || v == 2 || v == 5 || v == 6);
        s->X[3 * v + 1] = (v == 2 || v == 3 || v == 6 || v == 7);
        s->X[3 * v + 2] = v >= 4;
    }
    for (int f = 0; f < 6; f++) {
        int t[6] = {q[f][0], q[f][1], q[f][2], q[f][0], q[f][2], q[f][3]};
        memcpy(s->T + 3 * s->nt, t, sizeof t);
        s->nt += 2;
    }
}

static int midpoint(surf *s, int a, int b)
{
    double m[3];
    for (int k = 0; k < 3; k++) m[k] = 0.5 * (s->X[3 * a + k] + s->X[3 * b + k]);
    double n = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    for (int v = 0; v < s->np; v++)
        if (fabs(s->X[3 * v] - m[0] / n) + fabs(s->X[3 * v + 1] - m[1] / n) + fabs(s->X[3 * v + 2] - m[2] / n) < 1e-12)
            return v;
    for (int k = 0; k < 3; k++) s->X[3 * s->np + k] = m[k] / n;
    return s->np++;
}

/* icosahedron subdivided twice: 162 points, 320 triangles, outward */
static void sphere(surf *s)
{
    const double t = (1 + sqrt(5.0)) / 2;
    double v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    static const int f[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                 {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    s->np = 12;
    for (int i = 0; i < 12; i++) {
        double n = sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
        for (int k = 0; k < 3; k++) s->X[3 * i + k] = v[i][k] / n;
    }
    s->nt = 20;
    memcpy(s->T, f, sizeof f);
    for (int level = 0; level < 2; level++) {
        int T[3 * 2000], nt = 0;
        for (int i = 0; i < s->nt; i++) {
            int a = s->T[3 * i], b = s->T[3 * i + 1], c = s->T[3 * i + 2];
            int ab = midpoint(s, a, b), bc = midpoint(s, b, c), ca = midpoint(s, c, a);
            int n[12] = {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca};
            memcpy(T + 3 * nt, n, sizeof n);
            nt += 4;
        }
        memcpy(s->T, T, sizeof(int) * 3 * (size_t)nt);
        s->nt = nt;
    }
}

static double enclosed_volume(const surf *s)
{
    double v = 0;
    for (int i = 0; i < s->nt; i++) {
        const double *a = s->X + 3 * s->T[3 * i], *b = s->X + 3 * s->T[3 * i + 1], *c = s->X + 3 * s->T[3 * i + 2];
        v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    }
    return v;
}

static double tri_area(const double *a, const double *b, const double *c)
{
    double u[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        w[k] = c[k] - a[k];
    }
    double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

static double surface_area(const surf *s)
{
    double A = 0;
    for (int i = 0; i < s->nt; i++) A += tri_area(s->X + 3 * s->T[3 * i], s->X + 3 * s->T[3 * i + 1], s->X + 3 * s->T[3 * i + 2]);
    return A;
}

/* ---- writers ----------------------------------------------------------------------- */

static void put_le(FILE *f, const void *p, size_t n) { fwrite(p, 1, n, f); } /* x86/arm little endian */

static void write_surf(const surf *s, const char *name, const char *fmt)
{
    FILE *f = fopen(tpath(name), "wb");
    if (!f) exit(1);
    if (!strcmp(fmt, "obj")) {
        fprintf(f, "# procedural\no body\n");
        for (int v = 0; v < s->np; v++) fprintf(f, "v %.17g %.17g %.17g\n", s->X[3 * v], s->X[3 * v + 1], s->X[3 * v + 2]);
        fprintf(f, "vn 0 0 1\n");
        for (int t = 0; t < s->nt; t++) /* mix the index forms, with negative ones */
            fprintf(f, t % 3 == 0 ? "f %d/1/1 %d//1 %d\n" : "f %d %d %d\n", s->T[3 * t] + 1, s->T[3 * t + 1] + 1,
                    s->T[3 * t + 2] - s->np);
    } else if (!strcmp(fmt, "off")) {
        fprintf(f, "OFF\n# procedural\n%d %d 0\n", s->np, s->nt);
        for (int v = 0; v < s->np; v++) fprintf(f, "%.17g %.17g %.17g\n", s->X[3 * v], s->X[3 * v + 1], s->X[3 * v + 2]);
        for (int t = 0; t < s->nt; t++) fprintf(f, "3 %d %d %d\n", s->T[3 * t], s->T[3 * t + 1], s->T[3 * t + 2]);
    } else if (!strcmp(fmt, "stl")) {
        fprintf(f, "solid procedural\n");
        for (int t = 0; t < s->nt; t++) {
            fprintf(f, "  facet normal 0 0 0\n    outer loop\n");
            for (int a = 0; a < 3; a++) {
                const double *x = s->X + 3 * s->T[3 * t + a];
                fprintf(f, "      vertex %.17g %.17g %.17g\n", x[0], x[1], x[2]);
            }
            fprintf(f, "    endloop\n  endfacet\n");
        }
        fprintf(f, "endsolid procedural\n");
    } else if (!strcmp(fmt, "stlb")) { /* float32 coordinates: the volume is that of the rounded points */
        char hdr[80] = "solid binary header that starts like an ASCII file";
        put_le(f, hdr, 80);
        uint32_t n = (uint32_t)s->nt;
        put_le(f, &n, 4);
        for (int t = 0; t < s->nt; t++) {
            float r[12] = {0};
            for (int a = 0; a < 3; a++)
                for (int k = 0; k < 3; k++) r[3 + 3 * a + k] = (float)s->X[3 * s->T[3 * t + a] + k];
            put_le(f, r, 48);
            uint16_t attr = 0;
            put_le(f, &attr, 2);
        }
    } else if (!strcmp(fmt, "ply")) {
        fprintf(f, "ply\nformat ascii 1.0\ncomment procedural\nelement vertex %d\nproperty double x\nproperty double y\n"
                   "property double z\nproperty uchar red\nelement face %d\nproperty list uchar int vertex_indices\n"
                   "end_header\n", s->np, s->nt);
        for (int v = 0; v < s->np; v++) fprintf(f, "%.17g %.17g %.17g 255\n", s->X[3 * v], s->X[3 * v + 1], s->X[3 * v + 2]);
        for (int t = 0; t < s->nt; t++) fprintf(f, "3 %d %d %d\n", s->T[3 * t], s->T[3 * t + 1], s->T[3 * t + 2]);
    } else { /* plyb: float64 x y z, a float32 extra, int32 list count type uchar */
        fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float64 x\nproperty float64 y\n"
                   "property float64 z\nproperty float32 quality\nelement face %d\n"
                   "property list uint8 int32 vertex_indices\nend_header\n", s->np, s->nt);
        for (int v = 0; v < s->np; v++) {
            float q = 1;
            put_le(f, s->X + 3 * v, 24);
            put_le(f, &q, 4);
        }
        for (int t = 0; t < s->nt; t++) {
            unsigned char three = 3;
            put_le(f, &three, 1);
            put_le(f, s->T + 3 * t, 12);
        }
    }
    fclose(f);
}

/* Load name and check: valid, volume and boundary area as the surface's. */
static void check_volume(eo_ctx *ctx, const char *name, const surf *s, double quality, double maxvol, int f32)
{
    eo_mesh_read_opts o = eo_mesh_read_opts_default();
    o.tetgen_quality = quality;
    o.tetgen_max_volume = maxvol;
    eo_mesh *m = NULL;
    int rc = eo_mesh_read(ctx, tpath(name), &o, &m);
    CHECK(rc == EO_OK, "%s: %s", name, eo_ctx_message(ctx));
    if (rc < 0) return;
    surf r = *s;
    if (f32)
        for (int i = 0; i < 3 * r.np; i++) r.X[i] = (float)r.X[i];
    double want = enclosed_volume(&r), area = surface_area(&r);
    eo_mesh_stats st;
    eo_mesh_stats_compute(m, &st);
    CHECK(fabs(st.volume - want) <= 1e-9 * want, "%s (q %g, a %g): volume %.17g, enclosed %.17g", name, quality, maxvol,
          st.volume, want);
    CHECK(st.min_volume > 0, "%s: positive tets", name);
    int *faces = NULL, nf = 0;
    CHECK(eo_mesh_boundary_faces(ctx, m, &faces, &nf) == EO_OK, "faces");
    double A = 0;
    for (int i = 0; i < nf; i++) A += tri_area(m->X + 3 * faces[3 * i], m->X + 3 * faces[3 * i + 1], m->X + 3 * faces[3 * i + 2]);
    eo_free(ctx, faces);
    CHECK(fabs(A - area) <= 1e-9 * area, "%s: boundary area %.17g, surface area %.17g", name, A, area);
    if (maxvol > 0) CHECK(st.max_volume <= maxvol * (1 + 1e-9), "%s: max tet volume %g <= %g", name, st.max_volume, maxvol);
    if (maxvol > 0) CHECK(m->nt > 20, "%s: refined to %d tets", name, m->nt);
    printf("%-10s q=%-3g a=%-6g %5d vertices %6d tets volume %.15f (enclosed %.15f) worst quality %.3f\n", name, quality,
           maxvol, m->nv, m->nt, st.volume, want, st.worst_quality);
    eo_mesh_destroy(&m);
}

static void expect_fail(eo_ctx *ctx, const char *name, const char *text, const char *want)
{
    FILE *f = fopen(tpath(name), "wb");
    fputs(text, f);
    fclose(f);
    eo_mesh *m = NULL;
    int rc = eo_mesh_read(ctx, tpath(name), NULL, &m);
    CHECK(rc < 0 && m == NULL, "%s: expected a failure", name);
    CHECK(strstr(eo_ctx_message(ctx), want) != NULL, "%s: message '%s' lacks '%s'", name, eo_ctx_message(ctx), want);
    eo_ctx_clear_error(ctx);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", eo_test_tmpdir("mesh_surface"));
    eo_ctx *ctx = eo_test_ctx();
    static surf c, s;
    cube(&c);
    sphere(&s);
    CHECK(s.np == 162 && s.nt == 320, "icosphere %d points %d triangles", s.np, s.nt);
    write_surf(&c, "cube.obj", "obj");
    if (!eo_mesh_have_tetgen()) {
        eo_mesh *m = NULL;
        int rc = eo_mesh_read(ctx, tpath("cube.obj"), NULL, &m);
        CHECK(rc == EO_ERR_UNSUPPORTED && strstr(eo_ctx_message(ctx), "-Dtetgen"), "no TetGen: %s", eo_ctx_message(ctx));
        eo_test_ctx_done(&ctx);
        printf("test_mesh_surface: built without TetGen (-Dtetgen): skipped\n");
        return eo_test_failed ? 1 : 77;
    }
    static const char *const fmts[] = {"obj", "off", "stl", "stlb", "ply", "plyb"};
    for (int i = 0; i < 6; i++) {
        char name[64];
        const char *ext = !strcmp(fmts[i], "stlb") ? "stl" : !strcmp(fmts[i], "plyb") ? "ply" : fmts[i];
        snprintf(name, sizeof name, "cube_%s.%s", fmts[i], ext);
        write_surf(&c, name, fmts[i]);
        check_volume(ctx, name, &c, 2.0, 0, 0);
        check_volume(ctx, name, &c, 1.5, 0.01, 0);
        snprintf(name, sizeof name, "sphere_%s.%s", fmts[i], ext);
        write_surf(&s, name, fmts[i]);
        check_volume(ctx, name, &s, 2.0, 0, !strcmp(fmts[i], "stlb"));
        check_volume(ctx, name, &s, 0, 0, !strcmp(fmts[i], "stlb"));
        check_volume(ctx, name, &s, 1.2, 0.005, !strcmp(fmts[i], "stlb"));
    }
    /* bad surfaces */
    expect_fail(ctx, "open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n", "at least 4");
    expect_fail(ctx, "open2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 5 3\n",
                "open2.obj:7: triangle 2: the surface is not closed");
    /* 4 points and 4 triangles, but one point is a copy: after merging, one triangle
     * listed four times (every edge in an even number of triangles) on 3 points */
    expect_fail(ctx, "copies.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 0\nf 1 2 3\nf 1 3 2\nf 4 2 3\nf 4 3 2\n",
                "3 distinct points");
    /* two closed tetrahedra that pass through each other: TetGen 1.5 meshing this ('p')
     * crashes inside its own clean-up; the surface is refused before, naming the place */
    expect_fail(ctx, "crossing.obj",
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0.2 0.2 0.2\nv 1.2 0.2 0.2\nv 0.2 1.2 0.2\nv 0.2 0.2 1.2\n"
                "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\nf 5 7 6\nf 5 6 8\nf 6 7 8\nf 5 8 7\n",
                "the surface intersects itself (4 triangles intersect others, the first near (");
    expect_fail(ctx, "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "range.obj:4: expected a vertex index in [1, 3]");
    expect_fail(ctx, "degen.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 0 2\n",
                "degen.off:10: triangle 4: degenerate");
    expect_fail(ctx, "bad.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n", "bad.stl:4: expected a vertex coordinate");
    expect_fail(ctx, "bad.ply", "ply\nformat binary_big_endian 1.0\nend_header\n", "binary_big_endian");
    expect_fail(ctx, "short.ply",
                "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                "property float z\nend_header\nabc",
                "binary data ends early");
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_mesh_surface");
}
