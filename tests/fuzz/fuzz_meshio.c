/* libFuzzer target over the readers added for issue 14: VTU (through
 * eo_mesh_read_buffer), the surface parsers OBJ, OFF, STL (ASCII/binary), PLY
 * (ASCII/binary) up to the closed-surface checks (eo_surface_parse: the fuzz build has
 * no TetGen), and the tag paths of Gmsh 4.1 ($Entities, triangles), MEDIT (Triangles)
 * and TetGen (.face: node NUL ele NUL face), and Vega FEM .veg; 10-node tets (Gmsh type 11,
 * VTU type 24, TetGen 10-node .ele) on the same paths.
 * Input: byte 0 picks the reader (% 9: vtu, obj, off, stl, ply, gmsh, medit, tetgen, veg),
 * byte 1 the options (bit 0/1 drop_degenerate/drop_unreferenced; 0xE0 all set: run a
 * second pass with an allocation failure injected after 1 + (byte1 & 0x1C)). Aborts on
 * leaks, on success without a valid result (positive tets, indices in range, tagged
 * triangles in range; a surface: indices in range, no degenerate triangle, >= 4
 * points) and on failure without a message. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/mesh.h"
#include "lib/mesh/mesh_io.h"

static void check(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_meshio: %s\n", what);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2) return 0;
    static const eo_mesh_format fmts[9] = {EO_MESH_VTU, EO_MESH_OBJ,   EO_MESH_OFF,    EO_MESH_STL, EO_MESH_PLY,
                                           EO_MESH_GMSH, EO_MESH_MEDIT, EO_MESH_TETGEN, EO_MESH_VEG};
    eo_mesh_format fmt = fmts[data[0] % 9];
    eo_mesh_read_opts o = eo_mesh_read_opts_default();
    o.drop_degenerate = data[1] & 1;
    o.drop_unreferenced = (data[1] >> 1) & 1;
    eo_ctx *ctx = NULL;
    if (eo_ctx_create(NULL, &ctx) < 0) return 0;
    const char *text = (const char *)data + 2;
    size_t len = size - 2;
    for (int pass = 0; pass < ((data[1] & 0xE0) == 0xE0 ? 2 : 1); pass++) {
        if (pass == 1) eo_ctx_fail_after(ctx, 1 + (long)(data[1] & 0x1C));
        int rc;
        if (fmt == EO_MESH_OBJ || fmt == EO_MESH_OFF || fmt == EO_MESH_STL || fmt == EO_MESH_PLY) {
            /* the parsers read NUL-terminated text of len bytes, as eo_read_file gives it */
            char *buf = malloc(len + 1);
            if (!buf) break;
            memcpy(buf, text, len);
            buf[len] = 0;
            eo_surface s;
            rc = eo_surface_parse(ctx, fmt, buf, len, "fuzz", &s);
            eo_ctx_fail_after(ctx, 0);
            if (rc >= 0) {
                check(s.np >= 4 && s.nt >= 4, "surface too small accepted");
                for (int f = 0; f < s.nt; f++) {
                    const int *t = s.tri + 3 * f;
                    for (int a = 0; a < 3; a++) check(t[a] >= 0 && t[a] < s.np, "surface index");
                    check(t[0] != t[1] && t[1] != t[2] && t[0] != t[2], "degenerate triangle accepted");
                }
                eo_surface_deinit(ctx, &s);
            } else {
                check(eo_ctx_message(ctx)[0] != 0, "failure without a message");
            }
            free(buf);
        } else {
            eo_mesh *m = NULL;
            rc = eo_mesh_read_buffer(ctx, text, len, fmt, "fuzz", &o, &m);
            eo_ctx_fail_after(ctx, 0);
            if (rc >= 0) {
                check(m && m->nv > 0 && m->nt > 0, "success without a mesh");
                for (int t = 0; t < m->nt; t++) {
                    for (int a = 0; a < 4; a++) check(m->tets[4 * t + a] >= 0 && m->tets[4 * t + a] < m->nv, "index");
                    check(eo_tet_volume(m->X, m->tets + 4 * t) > 0, "non-positive tet accepted");
                }
                for (int i = 0; i < 3 * m->ntri; i++) check(m->tris[i] >= 0 && m->tris[i] < m->nv, "triangle index");
                check((m->order == 2) == (m->tet10 != NULL), "order and tet10 disagree");
                for (int t = 0; m->tet10 && t < m->nt; t++) /* order 2: corners = tets, nodes in range */
                    for (int a = 0; a < 10; a++)
                        check(m->tet10[10 * t + a] >= 0 && m->tet10[10 * t + a] < m->nv &&
                                  (a >= 4 || m->tet10[10 * t + a] == m->tets[4 * t + a]),
                              "tet10 index");
                for (int i = 0; m->tet10 && i < 3 * m->ntri; i++)
                    check(m->tri_mid && m->tri_mid[i] >= 0 && m->tri_mid[i] < m->nv, "tri_mid index");
                unsigned char *flag = malloc((size_t)m->nv);
                int n;
                if (flag && eo_mesh_surface_vertices(ctx, m, flag, &n) >= 0) check(n > 0 && n <= m->nv, "surface count");
                free(flag);
            } else {
                check(m == NULL, "failure with a mesh");
                check(eo_ctx_message(ctx)[0] != 0, "failure without a message");
            }
            eo_mesh_destroy(&m);
        }
        check(eo_ctx_live_bytes(ctx) == 0, "leak");
        eo_ctx_clear_error(ctx);
    }
    eo_ctx_destroy(&ctx);
    return 0;
}
