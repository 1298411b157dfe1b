/* libFuzzer target over every mesh reader, through eo_mesh_read_buffer.
 * Input: byte 0 picks the reader (% 3: Gmsh, MEDIT, TetGen), byte 1 the drop options
 * (bit 0 drop_degenerate, bit 1 drop_unreferenced); the rest is the file text (for
 * TetGen: .node text, a NUL byte, .ele text). Every 8th input also runs with an
 * allocation failure injected. Aborts if a read leaves bytes allocated, or returns
 * success with a mesh that breaks the guarantees (positive tets, indices in range). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "elastopt/mesh.h"

static void check(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_mesh: %s\n", what);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2) return 0;
    static const eo_mesh_format fmts[3] = {EO_MESH_GMSH, EO_MESH_MEDIT, EO_MESH_TETGEN};
    eo_mesh_format fmt = fmts[data[0] % 3];
    eo_mesh_read_opts o = eo_mesh_read_opts_default();
    o.drop_degenerate = data[1] & 1;
    o.drop_unreferenced = (data[1] >> 1) & 1;
    eo_ctx *ctx = NULL;
    if (eo_ctx_create(NULL, &ctx) < 0) return 0;
    for (int pass = 0; pass < ((data[1] & 0xE0) == 0xE0 ? 2 : 1); pass++) {
        if (pass == 1) eo_ctx_fail_after(ctx, 1 + (long)(data[1] & 0x1C));
        eo_mesh *m = NULL;
        int rc = eo_mesh_read_buffer(ctx, (const char *)data + 2, size - 2, fmt, "fuzz", &o, &m);
        eo_ctx_fail_after(ctx, 0);
        if (rc >= 0) {
            check(m && m->nv > 0 && m->nt > 0, "success without a mesh");
            for (int t = 0; t < m->nt; t++) {
                for (int a = 0; a < 4; a++) check(m->tets[4 * t + a] >= 0 && m->tets[4 * t + a] < m->nv, "index");
                check(eo_tet_volume(m->X, m->tets + 4 * t) > 0, "non-positive tet accepted");
            }
            eo_mesh_stats s;
            eo_mesh_stats_compute(m, &s);
            int *faces = NULL, nf = 0;
            if (eo_mesh_boundary_faces(ctx, m, &faces, &nf) >= 0) eo_free(ctx, faces);
        } else {
            check(m == NULL, "failure with a mesh");
            check(eo_ctx_message(ctx)[0] != 0, "failure without a message");
        }
        eo_mesh_destroy(&m);
        check(eo_ctx_live_bytes(ctx) == 0, "leak");
    }
    eo_ctx_destroy(&ctx);
    return 0;
}
