/// @file trimesh.h
/// 2D triangle meshes: read from Gmsh, boundary nodes, VTU output (for the Poisson
/// problem of poisson.h, notes 001 §3).
///
/// ```c
/// eo_trimesh *m; eo_trimesh_read_gmsh(ctx, "disk.msh", &m);  // .msh 2.2 or 4.1 ASCII
/// unsigned char *b = ...;  eo_trimesh_boundary(ctx, m, b);     // nv flags
/// eo_vtu_write_tri(ctx, "u.vtu", m->nv, m->xy, m->nt, m->tri, "u", u);
/// eo_trimesh_destroy(&m);
/// ```
/// Ownership: the mesh owns its arrays; eo_vtu_write_tri borrows its inputs.
#ifndef ELASTOPT_TRIMESH_H
#define ELASTOPT_TRIMESH_H

#include "ctx.h"
#include "export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_trimesh {
    int nv, nt;
    double *xy;  ///< 2·nv coordinates (x, y)
    int *tri;    ///< 3·nt 0-based node indices (either orientation)
    eo_ctx *ctx;                       ///< context it was created with (its destroy uses it)
} eo_trimesh;

/// Allocate a mesh of nv nodes and nt triangles (arrays uninitialized).
EO_API int eo_trimesh_create(eo_ctx *ctx, int nv, int nt, eo_trimesh **out);
EO_API void eo_trimesh_destroy(eo_trimesh **m);
/// Read the 3-node triangles (element type 2) of a Gmsh ASCII .msh file, version 2.2 or
/// 4.1; every other element type and section is skipped, z is ignored (the mesh lies in
/// the xy-plane), nodes used by no triangle are kept. Errors: EO_ERR_IO, EO_ERR_PARSE /
/// EO_ERR_MESH with file and line, EO_ERR_UNSUPPORTED (binary, other versions),
/// EO_ERR_MESH when there is no triangle.
EO_API int eo_trimesh_read_gmsh(eo_ctx *ctx, const char *path, eo_trimesh **out);
/// on_boundary[v] = 1 for the nodes of boundary edges (edges used by exactly one
/// triangle), else 0 (nv flags, caller storage). EO_ERR_MESH if an edge is used by more
/// than two triangles (with the edge's nodes in the message), EO_ERR_NOMEM.
EO_API int eo_trimesh_boundary(eo_ctx *ctx, const eo_trimesh *m, unsigned char *on_boundary);
/// Longest edge (the mesh size h).
EO_API double eo_trimesh_max_edge(const eo_trimesh *m);
/// VTK XML unstructured grid of triangles (cell type 5) with z = 0 and, if values is not
/// NULL, one Float64 point field named `field` (nv values). Written atomically.
/// (lib/mesh/vtu.c, next to the tet writer.)
EO_API int eo_vtu_write_tri(eo_ctx *ctx, const char *path, int nv, const double *xy, int nt, const int *tri,
                            const char *field, const double *values);

#ifdef __cplusplus
}
#endif
#endif
