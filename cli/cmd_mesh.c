/* elastopt mesh: load (or generate) a mesh, validate it, print its statistics. */
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "elastopt/mesh.h"

extern const eo_cli_command eo_cmd_mesh;

static int run(eo_ctx *ctx, int argc, char **argv)
{
    const char *src = NULL;
    int as_json = 0;
    eo_mesh_read_opts o = eo_mesh_read_opts_default();
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--json") == 0) as_json = 1;
        else if (strcmp(argv[i], "--drop-degenerate") == 0) o.drop_degenerate = 1;
        else if (strcmp(argv[i], "--drop-unreferenced") == 0) o.drop_unreferenced = 1;
        else if (strcmp(argv[i], "--quality") == 0 || strcmp(argv[i], "--max-volume") == 0) {
            char *e = NULL;
            double v = i + 1 < argc ? strtod(argv[i + 1], &e) : 0;
            if (!e || e == argv[i + 1] || *e || !(v >= 0))
                return eo_cli_usage_error(&eo_cmd_mesh, "%s needs a number >= 0", argv[i]);
            if (argv[i][2] == 'q') o.tetgen_quality = v;
            else o.tetgen_max_volume = v;
            i++;
        }
        else if (argv[i][0] == '-' && argv[i][1]) return eo_cli_unknown_arg(&eo_cmd_mesh, "option", argv[i]);
        else if (!src) src = argv[i];
        else return eo_cli_usage_error(&eo_cmd_mesh, "expected one mesh, got a second: '%s'", argv[i]);
    }
    if (!src) return eo_cli_usage_error(&eo_cmd_mesh, "expected a mesh file or gen: spec");
    eo_mesh *m = NULL;
    double t0 = eo_wtime();
    int rc = eo_mesh_load(ctx, src, &o, &m);
    double t_load = eo_wtime() - t0;
    if (rc < 0) return eo_cli_fail(ctx, rc);
    eo_mesh_stats s;
    eo_mesh_stats_compute(m, &s);
    int *faces = NULL, nf = 0;
    rc = eo_mesh_boundary_faces(ctx, m, &faces, &nf);
    eo_free(ctx, faces);
    if (rc < 0) {
        eo_mesh_destroy(&m);
        return eo_cli_fail(ctx, rc);
    }
    if (as_json) {
        json_t *j = json_object();
        json_object_set_new(j, "source", json_string(src));
        json_object_set_new(j, "vertices", json_integer(m->nv));
        json_object_set_new(j, "tets", json_integer(m->nt));
        json_object_set_new(j, "order", json_integer(m->order));
        json_object_set_new(j, "volume", json_real(s.volume));
        json_t *bb = json_array();
        for (int i = 0; i < 6; i++) json_array_append_new(bb, json_real(s.bbox[i]));
        json_object_set_new(j, "bbox", bb);
        json_object_set_new(j, "min_volume", json_real(s.min_volume));
        json_object_set_new(j, "max_volume", json_real(s.max_volume));
        json_object_set_new(j, "worst_quality", json_real(s.worst_quality));
        json_object_set_new(j, "boundary_faces", json_integer(nf));
        json_object_set_new(j, "tagged_triangles", json_integer(m->ntri));
        json_object_set_new(j, "reoriented", json_integer(m->reoriented));
        json_object_set_new(j, "dropped_tets", json_integer(m->dropped_tets));
        json_object_set_new(j, "dropped_vertices", json_integer(m->dropped_vertices));
        json_object_set_new(j, "load_seconds", json_real(t_load));
        char *text = eo_json_dumps(j, 0);
        printf("%s\n", text ? text : "{}");
        free(text);
        json_decref(j);
    } else {
        printf("mesh            %s\n", src);
        printf("vertices        %d\n", m->nv);
        printf("tets            %d\n", m->nt);
        printf("order           %d%s\n", m->order, m->order == 2 ? " (10-node tets; vertices count every node)" : "");
        printf("volume          %.17g\n", s.volume);
        printf("bbox            [%g, %g, %g] - [%g, %g, %g]\n", s.bbox[0], s.bbox[1], s.bbox[2], s.bbox[3], s.bbox[4],
               s.bbox[5]);
        printf("min tet volume  %.6g\n", s.min_volume);
        printf("max tet volume  %.6g\n", s.max_volume);
        printf("worst quality   %.6g (normalized radius ratio, 1 = regular)\n", s.worst_quality);
        printf("boundary faces  %d\n", nf);
        if (m->ntri) printf("tagged faces    %d\n", m->ntri);
        printf("reoriented      %d\n", m->reoriented);
        printf("dropped         %d tets, %d vertices\n", m->dropped_tets, m->dropped_vertices);
        printf("load time       %.3f s\n", t_load);
    }
    eo_mesh_destroy(&m);
    return EO_EXIT_OK;
}

const eo_cli_command eo_cmd_mesh = {
    .name = "mesh",
    .summary = "load or generate a tet mesh, validate it, print statistics",
    .usage = "elastopt mesh FILE [--json] [--drop-degenerate] [--drop-unreferenced] [--quality Q] [--max-volume V]\n\n"
             "FILE is a TetGen .node/.ele (file or base name), MEDIT .mesh, Gmsh .msh (2.2/4.1\n"
             "ASCII), VTU or Vega FEM .veg file, a closed surface .obj/.off/.stl/.ply tetrahedralized by TetGen\n"
             "(radius-edge bound Q, default 2, 0 = none; tet volume bound V, default 0 = none),\n"
             "or gen:SX,SY,SZ:NX,NY,NZ[:5|6] for a box of NX*NY*NZ cells of size\n"
             "SX*SY*SZ split into 5 or 6 (default) tets each.\n"
             "Prints vertex and tet counts, total rest volume, bounding box, smallest and largest\n"
             "tet volume, worst quality (normalized radius ratio), boundary faces, and how many tets\n"
             "were reoriented or dropped. Validation errors (non-finite coordinates, indices out\n"
             "of range, zero-volume or duplicate tets, unreferenced vertices) fail with exit 2\n"
             "unless --drop-degenerate / --drop-unreferenced allow dropping them with a warning.\n"
             "  --json   one JSON object: vertices, tets, volume, bbox [min xyz, max xyz],\n"
             "           min_volume, max_volume, worst_quality, boundary_faces, tagged_triangles, reoriented,\n"
             "           dropped_tets, dropped_vertices, load_seconds, source\n",
    .run = run,
};
