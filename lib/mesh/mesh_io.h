/* Private: the mesh file format table. One const instance per format file
 * (mesh_tetgen.c, mesh_medit.c, mesh_gmsh.c, mesh_veg.c, vtu.c), listed once in mesh.c; the generic
 * code in mesh.c picks one by extension or eo_mesh_format, reads the file in one go,
 * calls the reader, then validates with the reader's per-item source lines so
 * validation errors name file and line too. */
#ifndef EO_MESH_IO_H
#define EO_MESH_IO_H

#include "elastopt/mesh.h"

/* Where each vertex/tet came from, filled by readers (all optional). */
typedef struct eo_mesh_src {
    const char *vert_file;  /* file holding the vertices (borrowed) */
    const char *tet_file;   /* file holding the tets (borrowed) */
    long *v_line, *v_id;    /* nv: line and input id of each vertex */
    long *t_line, *t_id;    /* nt: line and input id of each tet */
    char *owned;            /* file names allocated by a reader, freed with the rest */
    const char *tri_file;   /* file holding the tagged triangles (borrowed; NULL: tet_file) */
    long *f_line;           /* ntri: line of each tagged triangle (NULL if unknown) */
    const eo_mesh_read_opts *opts; /* the caller's options (TetGen quality for surfaces) */
    int base;               /* TetGen: index base (0 or 1) of the .node file */
} eo_mesh_src;

/* The context's mesh source (eo_ctx_set_mesh_source) and its user pointer; NULL if none. */
eo_mesh_source_fn eo_ctx_mesh_source(const eo_ctx *ctx, void **user);

typedef struct eo_mesh_io_type {
    eo_mesh_format format;
    const char *name;            /* "gmsh" */
    const char *const *exts;     /* NULL-terminated: ".msh" */
    /* Parse NUL-terminated text (len bytes) named `file`; create *out. NULL: write-only. */
    int (*read_text)(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out,
                     eo_mesh_src *src);
    /* Optional: read from a path (formats spread over several files). */
    int (*read_path)(eo_ctx *ctx, const char *path, eo_mesh **out, eo_mesh_src *src);
    /* Write rest positions atomically. */
    int (*write)(eo_ctx *ctx, const eo_mesh *m, const char *path);
} eo_mesh_io_type;

extern const eo_mesh_io_type eo_mesh_io_tetgen, eo_mesh_io_medit, eo_mesh_io_gmsh, eo_mesh_io_vtu,
    eo_mesh_io_obj, eo_mesh_io_off, eo_mesh_io_stl, eo_mesh_io_ply, eo_mesh_io_veg;

/* Readers behind the format tables in vtu.c (VTU, OBJ). */
int eo_vtu_read_text(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src);
int eo_obj_read_text(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh **out, eo_mesh_src *src);

/* Append a tagged triangle (growing m->tris/tri_tag/src->f_line); line may be -1. */
int eo_mesh_add_tri(eo_ctx *ctx, eo_mesh *m, eo_mesh_src *src, int *cap, const int v[3], int tag, long line);

/* A closed triangle surface (mesh_surface.c): np points, nt triangles (0-based). */
typedef struct eo_surface {
    int np, nt;
    double *X;   /* 3*np */
    int *tri;    /* 3*nt */
    long *line;  /* nt: source line (or -1) of each triangle; NULL if unknown */
} eo_surface;
void eo_surface_deinit(eo_ctx *ctx, eo_surface *s);
/* Parse a surface file of format fmt (OBJ, OFF, STL, PLY) without tetrahedralizing it:
 * the fuzz target calls this directly. Checks indices, degenerate triangles, closedness. */
int eo_surface_parse(eo_ctx *ctx, eo_mesh_format fmt, const char *text, size_t len, const char *file,
                     eo_surface *s);
/* TetGen library shim (mesh_tetgen_lib.cpp; a stub that fails when not built):
 * tetrahedralize the closed surface with "pzQ" + q<quality> (if > 0) + a<max_volume>
 * (if > 0). Creates *out (vertices: the surface points first, then Steiner points). */
int eo_tetgen_tetrahedralize(eo_ctx *ctx, const eo_surface *s, double quality, double max_volume,
                             const char *file, eo_mesh **out);

/* TetGen's C++ library behind a C interface (mesh_tetgen_lib.cpp, built with
 * -Dtetgen): outputs are malloc'ed (caller frees); returns 0, or TetGen's error code
 * (1 memory, 2 internal, 3 self-intersection, 4 small feature, 5 close facets, 10 input)
 * or -1 (other exception) with a message in msg. */
int eo_tetgen_run(const double *X, int np, const int *tri, int nt, const char *switches, double **Xout,
                  int *npout, int **tets, int *ntout, char *msg, size_t msgn);

/* Rename n temporaries over their targets, all or nothing (mesh_path.c): an existing
 * target is hard-linked to a backup first; when a rename fails the targets already
 * renamed are restored from their backups and every temporary is removed. */
int eo_rename_all(eo_ctx *ctx, int n, const char *const *tmp, const char *const *dst);

/* Allocate the vertex arrays (if nv >= 0) and tet arrays (if nt >= 0). */
int eo_mesh_src_alloc(eo_ctx *ctx, eo_mesh_src *src, int nv, int nt);
void eo_mesh_src_free(eo_ctx *ctx, eo_mesh_src *src);
/* Validate with source locations (src may be NULL). */
int eo_mesh_validate_src(eo_ctx *ctx, eo_mesh *m, const eo_mesh_read_opts *opts, const eo_mesh_src *src);
/* TetGen from two texts (used by the path reader and eo_mesh_read_buffer). */
int eo_tetgen_read_texts(eo_ctx *ctx, const char *node, size_t node_len, const char *node_file,
                         const char *ele, size_t ele_len, const char *ele_file, eo_mesh **out,
                         eo_mesh_src *src);
/* TetGen .face text (marker flag 1: tagged triangles; 0: ignored) onto mesh m. */
int eo_tetgen_read_face(eo_ctx *ctx, const char *text, size_t len, const char *file, eo_mesh *m, eo_mesh_src *src);

#endif
