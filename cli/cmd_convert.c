/* elastopt convert: read (or generate) a mesh and write it in the format of OUT's extension. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "elastopt/mesh.h"

extern const eo_cli_command eo_cmd_convert;

static int run(eo_ctx *ctx, int argc, char **argv)
{
    const char *in = NULL, *out = NULL;
    int order = 0; /* 0: as read */
    eo_mesh_read_opts o = eo_mesh_read_opts_default();
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--drop-degenerate") == 0) o.drop_degenerate = 1;
        else if (strcmp(argv[i], "--drop-unreferenced") == 0) o.drop_unreferenced = 1;
        else if (strcmp(argv[i], "--order") == 0) {
            if (i + 1 >= argc || strcmp(argv[i + 1], "2") != 0)
                return eo_cli_usage_error(&eo_cmd_convert, "--order needs 2 (write the quadratic mesh)");
            order = 2;
            i++;
        }
        else if (strcmp(argv[i], "--quality") == 0 || strcmp(argv[i], "--max-volume") == 0) {
            char *e = NULL;
            double v = i + 1 < argc ? strtod(argv[i + 1], &e) : 0;
            if (!e || e == argv[i + 1] || *e || !(v >= 0))
                return eo_cli_usage_error(&eo_cmd_convert, "%s needs a number >= 0", argv[i]);
            if (argv[i][2] == 'q') o.tetgen_quality = v;
            else o.tetgen_max_volume = v;
            i++;
        }
        else if (argv[i][0] == '-' && argv[i][1])
            return eo_cli_unknown_arg(&eo_cmd_convert, "option", argv[i]);
        else if (!in) in = argv[i];
        else if (!out) out = argv[i];
        else return eo_cli_usage_error(&eo_cmd_convert, "expected IN and OUT, got a third argument '%s'", argv[i]);
    }
    if (!in || !out) return eo_cli_usage_error(&eo_cmd_convert, "expected IN and OUT");
    eo_mesh_format fmt = eo_mesh_format_from_path(out);
    if (fmt == EO_MESH_AUTO)
        return eo_cli_usage_error(&eo_cmd_convert,
                                  "%s: expected an output name ending in .node, .ele, .mesh, .msh, .vtu or .obj", out);
    eo_mesh *m = NULL;
    int rc = eo_mesh_load(ctx, in, &o, &m);
    if (rc < 0) return eo_cli_fail(ctx, rc);
    if (order == 2 && m->order != 2) {
        eo_mesh *q = NULL;
        rc = eo_mesh_to_quadratic(ctx, m, &q);
        eo_mesh_destroy(&m);
        if (rc < 0) return eo_cli_fail(ctx, rc);
        m = q;
    }
    rc = eo_mesh_write(ctx, m, out, fmt);
    if (rc < 0) {
        eo_mesh_destroy(&m);
        return eo_cli_fail(ctx, rc);
    }
    printf("wrote %s (%s): %d vertices, %d tets%s\n", out, eo_mesh_format_name(fmt), m->nv, m->nt,
           m->order == 2 ? " (10-node)" : "");
    eo_mesh_destroy(&m);
    return EO_EXIT_OK;
}

const eo_cli_command eo_cmd_convert = {
    .name = "convert",
    .summary = "convert a mesh between TetGen, MEDIT, Gmsh, VTU and boundary OBJ",
    .usage = "elastopt convert IN OUT [--order 2] [--drop-degenerate] [--drop-unreferenced] [--quality Q] [--max-volume V]\n\n"
             "IN: .node/.ele (TetGen, file or base name), .mesh (MEDIT), .msh (Gmsh 2.2/4.1 ASCII),\n"
             ".vtu (tets), .veg (Vega FEM: vertices and TET elements), a closed surface .obj/.off/.stl/.ply (tetrahedralized by TetGen with\n"
             "radius-edge bound Q, default 2, 0 = none, and tet volume bound V, default 0 = none)\n"
             "or gen:SX,SY,SZ:NX,NY,NZ[:5|6]. OUT's extension picks the format: .node or .ele\n"
             "(TetGen pair, 1-based, plus .face when the mesh has tagged triangles), .mesh, .msh\n"
             "(Gmsh 4.1 ASCII), .vtu (VTK XML, rest state), .obj (boundary surface). IN is\n"
             "validated as by `elastopt mesh`. OUT is written atomically (a TetGen pair: both\n"
             "files to temporaries, renamed together): on any error nothing is left behind and\n"
             "no existing file is changed. A path that cannot be used (a folder, device, FIFO,\n"
             "empty or unreadable file, a name longer than the system allows) fails at once.\n"
             "--order 2 writes the quadratic (10-node tet) mesh: one node at the midpoint of each\n"
             "edge (Gmsh type 11, VTU type 24, TetGen 10-node .ele; MEDIT refuses it). A 10-node\n"
             "IN (Gmsh type 11, VTU type 24, TetGen -o2) stays quadratic.\n",
    .run = run,
};
