/// @file mesh.h
/// Tetrahedral meshes: generation, reading, validation and writing.
///
/// A mesh holds rest positions and tets (4 vertex indices each, 0-based, positively
/// oriented after loading), an optional per-tet attribute (region id), an optional
/// per-vertex marker and optional tagged triangles (boundary or interface faces with a
/// tag each). Readers: TetGen .node/.ele[/.face], MEDIT .mesh, Gmsh .msh 2.2 and 4.1
/// ASCII, VTU (ASCII, inline base64 binary, appended raw or base64; tets), Vega FEM .veg
/// (vertices and TET elements; *MATERIAL, *SET, *REGION ignored, *INCLUDE refused), and closed
/// surface meshes .obj, .off, .stl (ASCII/binary), .ply (ASCII/binary_little_endian)
/// tetrahedralized by the TetGen library (built with -Dtetgen; otherwise reading them
/// fails with EO_ERR_UNSUPPORTED naming the option). Writers: TetGen, MEDIT, Gmsh, VTU
/// (with a .pvd series, see io.h), boundary OBJ.
///
/// Quadratic (10-node) tets give an order-2 mesh (order = 2, tet10, tets = the corners):
/// | format | read | write |
/// |---|---|---|
/// | Gmsh 2.2 / 4.1 | element type 11 (Gmsh order: edges 01 12 20 30 32 31; nodes 8, 9 swapped into tet10); 6-node triangles (type 9) as their corners | type 11 (4.1) |
/// | TetGen | .ele with 10 nodes per tet (tetgen -o2: edges 23 03 01 12 13 02, permuted) | 10-node .ele |
/// | VTU | cell type 24 (tet10 order), every encoding; quadratic triangles (22) as corners | type 24 |
/// | MEDIT | TetrahedraP2: EO_ERR_UNSUPPORTED | EO_ERR_UNSUPPORTED |
/// | Vega .veg | no 10-node tets (vertices per tet must be 4) | - |
/// | OBJ boundary | - | the corners' boundary triangles |
/// A file mixing 4- and 10-node tets is an error naming the element. tri_mid is filled
/// from the tets' edges (a tagged triangle edge that is no tet edge is an error).
///
/// Where the tags come from (the `tag: K` boundary selector of scenes uses them):
/// | format | tet_attr | tris/tri_tag | vmarker |
/// |---|---|---|---|
/// | Gmsh 2.2 | physical tag (1st element tag) of each tet | triangles (type 2), physical tag | - |
/// | Gmsh 4.1 | physical tag of the tet's volume entity ($Entities), else the entity tag | triangles (type 2): each physical tag of the surface entity (a triangle appears once per group), else the entity tag | - |
/// | MEDIT | Tetrahedra reference | Triangles with their reference | Vertices reference |
/// | TetGen | first region attribute of .ele | .face (if present, with markers) | .node boundary marker |
/// | VTU | cell data "region" (Int) | - | - |
/// | Vega .veg | - | - | - |
/// | surface (TetGen) | - | - | - |
/// Triangles need not be on the boundary; they are kept as the file gives them
/// (0-based vertex indices, validated: in range, 3 distinct vertices).
///
/// ```c
/// eo_mesh *m = NULL;
/// eo_mesh_read_opts o = eo_mesh_read_opts_default();
/// int rc = eo_mesh_read(ctx, "bar.msh", &o, &m);  // format from the extension
/// if (rc < 0) { puts(eo_ctx_message(ctx)); }
/// printf("%d tets, volume %g\n", m->nt, eo_mesh_volume(m));
/// eo_mesh_destroy(&m);
/// ```
/// Ownership: the mesh owns its arrays (allocated through the context).
/// Errors name the file, the line and the element or vertex index.
#ifndef ELASTOPT_MESH_H
#define ELASTOPT_MESH_H

#include "export.h"
#include "ctx.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_mesh {
    int nv;          ///< vertex count
    int nt;          ///< tet count
    double *X;       ///< rest positions, 3*nv
    int *tets;       ///< 4*nt vertex indices, 0-based, positive rest volume
    int *tet_attr;   ///< nt region attributes (NULL if the input had none)
    int *vmarker;    ///< nv vertex markers (NULL if none)
    int ntri;        ///< tagged triangles (0 if the input had none)
    int *tris;       ///< 3*ntri vertex indices, 0-based (NULL if ntri == 0)
    int *tri_tag;    ///< ntri tags: physical group / reference / boundary marker
    /* load report */
    int reoriented;  ///< tets whose vertex order was flipped to make volume positive
    int dropped_tets;      ///< zero-volume or duplicate tets dropped (when allowed)
    int dropped_vertices;  ///< unreferenced vertices dropped (when allowed)
    eo_ctx *ctx;                       ///< context it was created with (its destroy uses it)
    /* quadratic meshes (eo_mesh_to_quadratic, or a reader given 10-node tets) */
    int order;       ///< 1: linear tets (tet10 NULL); 2: 10-node tets in tet10
    int *tet10;      ///< order 2: 10·nt node ids: the 4 corners (equal to tets[4k..4k+3]),
                     ///< then the nodes of edges 01, 12, 20, 03, 13, 23 (the VTK quadratic
                     ///< tetra order, cell type 24); NULL for order 1. Nodes are vertices
                     ///< of the mesh like the corners (X, vmarker cover them)
    int *tri_mid;    ///< order 2 with ntri > 0: 3·ntri nodes of the tagged triangles' edges
                     ///< 01, 12, 20 (so that tag selectors reach them); NULL otherwise
} eo_mesh;

typedef enum eo_mesh_format {
    EO_MESH_AUTO = 0,
    EO_MESH_TETGEN,   ///< .node + .ele (give either name, or the base name)
    EO_MESH_MEDIT,    ///< .mesh
    EO_MESH_GMSH,     ///< .msh (read 2.2 and 4.1 ASCII; write 4.1 ASCII)
    EO_MESH_VTU,      ///< .vtu (read: tets, 4- or 10-node; write: VTK XML, appended raw)
    EO_MESH_OBJ,      ///< .obj (read: closed surface, tetrahedralized; write: boundary)
    EO_MESH_OFF,      ///< .off closed surface (read only, tetrahedralized)
    EO_MESH_STL,      ///< .stl ASCII or binary closed surface (read only, tetrahedralized)
    EO_MESH_PLY,      ///< .ply ASCII or binary_little_endian surface (read only, tetrahedralized)
    EO_MESH_VEG       ///< .veg Vega FEM tet mesh (read only: vertices and TET elements)
} eo_mesh_format;

typedef struct eo_mesh_read_opts {
    eo_mesh_format format;   ///< EO_MESH_AUTO: from the extension. Default AUTO.
    int drop_degenerate;     ///< 1: drop zero-volume/duplicate tets with a warning
                             ///< instead of failing. Default 0.
    int drop_unreferenced;   ///< 1: drop unreferenced vertices with a warning instead
                             ///< of failing. Default 0.
    double min_rel_volume;   ///< a tet with |V| <= min_rel_volume * (mean |V|) is
                             ///< zero-volume. Default 1e-12.
    double tetgen_quality;   ///< surface input: TetGen radius-edge ratio bound (-q);
                             ///< 0 = no quality refinement, else >= 1. Default 2.0.
    double tetgen_max_volume;///< surface input: tet volume bound (-a), m^3; 0 = none. Default 0.
} eo_mesh_read_opts;

EO_API eo_mesh_read_opts eo_mesh_read_opts_default(void);
/// 1 if this build can tetrahedralize surface meshes (TetGen library found).
EO_API int eo_mesh_have_tetgen(void);

/// Box/bar generator options.
typedef struct eo_mesh_gen_opts {
    double size[3];    ///< box extent along x,y,z. Default 1 1 1.
    double origin[3];  ///< minimum corner. Default 0 0 0.
    int cells[3];      ///< cells along x,y,z. Default 4 4 4.
    int split;         ///< 5 or 6 tets per cube. Default 6.
} eo_mesh_gen_opts;

EO_API eo_mesh_gen_opts eo_mesh_gen_opts_default(void);

/// Allocate an empty mesh with nv vertices and nt tets (arrays uninitialised).
EO_API int eo_mesh_create(eo_ctx *ctx, int nv, int nt, eo_mesh **out);
EO_API void eo_mesh_destroy(eo_mesh **m);
/// Generate a box of hexahedral cells split into tets (conforming, positive).
EO_API int eo_mesh_generate_box(eo_ctx *ctx, const eo_mesh_gen_opts *o, eo_mesh **out);
/// Map a generated box [o, o + size] onto Cook's tapered panel (Cook 1974): in the
/// x-y plane the box's rectangle goes bilinearly onto the quadrilateral with corners
/// o + (0, 0), (L, H), (L, H + 16/44·H), (0, H) for L = size[0], H = size[1] (the classic
/// (0,0), (48,44), (48,60), (0,44) for L = 48, H = 44); z unchanged. Straight columns
/// x = const stay straight (a shear of each column), so the split stays conforming and
/// every tet keeps a positive volume.
EO_API void eo_mesh_map_cook(eo_mesh *m, const double origin[3], const double size[3]);
/// Read a mesh file; validates (see eo_mesh_validate). opts may be NULL.
/// Returns EO_OK, EO_WARN_DROPPED (items dropped as the options allow; counts in the
/// mesh), or an error: EO_ERR_IO (missing/unreadable file; a folder, device, FIFO or
/// socket; an empty file; a name longer than PATH_MAX — checked with stat before
/// opening, see eo_path_check, so a FIFO never blocks), EO_ERR_PARSE (truncated,
/// wrong counts, non-numeric token: "file:line: expected X, got 'tok'"),
/// EO_ERR_NONFINITE, EO_ERR_MESH (index out of range, zero-volume/duplicate tet,
/// unreferenced vertex, 4- and 10-node tets mixed, a bad midside node; names file, line
/// and tet/vertex as the file numbers it),
/// EO_ERR_UNSUPPORTED (binary or other versions, write-only formats, compressed VTU,
/// MEDIT TetrahedraP2,
/// surface meshes in a build without TetGen), EO_ERR_NOMEM.
/// On error *out is NULL. With a mesh source installed on ctx (eo_ctx_set_mesh_source),
/// the source answers instead.
EO_API int eo_mesh_read(eo_ctx *ctx, const char *path, const eo_mesh_read_opts *opts, eo_mesh **out);
/// The file reader behind eo_mesh_read, without the context's mesh source (below).
EO_API int eo_mesh_read_file(eo_ctx *ctx, const char *path, const eo_mesh_read_opts *opts, eo_mesh **out);

/// A mesh source replaces what eo_mesh_read does with a context (the scene loader, `elastopt
/// mesh` and `convert` read through it): called with eo_mesh_read's arguments and `user`,
/// same contract (status, message in ctx, *out NULL on error, the mesh allocated through
/// ctx). A distributed program installs one so that a single process opens the file: the
/// PETSc / MPI backend's source calls eo_mesh_read_file on rank 0 and broadcasts the mesh
/// (or the error) to the other ranks, which receive it instead of reading. The library
/// itself knows nothing of MPI.
typedef int (*eo_mesh_source_fn)(eo_ctx *ctx, const char *path, const eo_mesh_read_opts *opts, eo_mesh **out,
                                 void *user);
/// Install (fn != NULL) or remove (NULL) the context's mesh source.
EO_API void eo_ctx_set_mesh_source(eo_ctx *ctx, eo_mesh_source_fn fn, void *user);

/// Read a mesh from text in memory (copied; need not be NUL-terminated). `fmt` is any
/// readable format; `name` is used in messages. For TETGEN the text is the .node
/// contents, one NUL byte, then the .ele contents (named name.node / name.ele),
/// optionally one more NUL byte and the .face contents.
EO_API int eo_mesh_read_buffer(eo_ctx *ctx, const char *text, size_t len, eo_mesh_format fmt,
                        const char *name, const eo_mesh_read_opts *opts, eo_mesh **out);
/// Parse a generator spec "gen:SX,SY,SZ:NX,NY,NZ[:5|6]" (sizes > 0, cells >= 1) into *o
/// (origin 0). EO_ERR_PARSE naming the spec and what was expected.
EO_API int eo_mesh_gen_opts_parse(eo_ctx *ctx, const char *spec, eo_mesh_gen_opts *o);
/// Load from a file path or a "gen:..." spec (then opts are ignored).
EO_API int eo_mesh_load(eo_ctx *ctx, const char *source, const eo_mesh_read_opts *opts, eo_mesh **out);
/// Short name of a format ("tetgen", "medit", "gmsh", "vtu", "obj", "off", "stl", "ply"; "auto").
EO_API const char *eo_mesh_format_name(eo_mesh_format fmt);
/// Write a mesh (rest positions) in the given or guessed format, atomically.
EO_API int eo_mesh_write(eo_ctx *ctx, const eo_mesh *m, const char *path, eo_mesh_format fmt);
/// Reorient negative tets, reject/drop zero-volume or duplicate tets, out-of-range
/// indices, non-finite coordinates, unreferenced vertices. `file` is for messages.
/// Order 2 (tet10 set): tet10's corners must equal tets; midside nodes in range, never a
/// corner of a tet, one per edge and on one edge only (EO_ERR_MESH naming the tet);
/// reorientation (corners 1 <-> 2) carries the midside nodes (edges 01 <-> 20, 13 <-> 23);
/// drops remove tet10 rows; midside nodes (tet10, tri_mid) count as referenced and are
/// renumbered; tri_mid is filled from the tets' edges when NULL.
EO_API int eo_mesh_validate(eo_ctx *ctx, eo_mesh *m, const eo_mesh_read_opts *opts, const char *file);
/// Format from a file name's extension (EO_MESH_AUTO if unknown).
EO_API eo_mesh_format eo_mesh_format_from_path(const char *path);

/// Signed volume of tet t at positions x (3*nv).
EO_API double eo_tet_volume(const double *x, const int *tet);
/// Total rest volume.
EO_API double eo_mesh_volume(const eo_mesh *m);
/// Mesh statistics.
typedef struct eo_mesh_stats {
    double volume, min_volume, max_volume;
    double bbox[6];          ///< min xyz, max xyz
    double worst_quality;    ///< min over tets of the normalized radius ratio (1 = regular)
} eo_mesh_stats;
EO_API void eo_mesh_stats_compute(const eo_mesh *m, eo_mesh_stats *s);

/// The quadratic (10-node) version of a linear mesh, new in *out: the vertices of m
/// (same ids, X, vmarker), then one midside node per edge (at the edge's midpoint, straight
/// edges; vmarker 0), numbered in the order the tets first meet the edges; tets, tet_attr,
/// tris, tri_tag copied; tet10 and tri_mid filled (a tagged triangle's edge that no tet
/// has gets its own node). m must be order 1. EO_ERR_INVALID, EO_ERR_NOMEM.
EO_API int eo_mesh_to_quadratic(eo_ctx *ctx, const eo_mesh *m, eo_mesh **out);

/// Vertices of the boundary surface (faces used by one tet; with tet10 also the midside
/// nodes of those faces' edges): flag[v] = 1 for each, 0
/// otherwise (flag has nv entries, caller storage); *count = how many. EO_ERR_NOMEM.
EO_API int eo_mesh_surface_vertices(eo_ctx *ctx, const eo_mesh *m, unsigned char *flag, int *count);

/// Boundary faces (triangles with one adjacent tet) of a valid mesh, outward oriented; *faces has
/// 3*(*nf) vertex indices, allocated through ctx (caller frees with eo_free).
EO_API int eo_mesh_boundary_faces(eo_ctx *ctx, const eo_mesh *m, int **faces, int *nf);

#ifdef __cplusplus
}
#endif
#endif
