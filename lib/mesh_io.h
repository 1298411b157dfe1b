/* Private: the mesh file format table. One const instance per format file
 * (mesh_tetgen.c, mesh_medit.c, mesh_gmsh.c, vtu.c), listed once in mesh.c; the generic
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
} eo_mesh_src;

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
    eo_mesh_io_obj;

/* Allocate the vertex arrays (if nv >= 0) and tet arrays (if nt >= 0). */
int eo_mesh_src_alloc(eo_ctx *ctx, eo_mesh_src *src, int nv, int nt);
void eo_mesh_src_free(eo_ctx *ctx, eo_mesh_src *src);
/* Validate with source locations (src may be NULL). */
int eo_mesh_validate_src(eo_ctx *ctx, eo_mesh *m, const eo_mesh_read_opts *opts, const eo_mesh_src *src);
/* TetGen from two texts (used by the path reader and eo_mesh_read_buffer). */
int eo_tetgen_read_texts(eo_ctx *ctx, const char *node, size_t node_len, const char *node_file,
                         const char *ele, size_t ele_len, const char *ele_file, eo_mesh **out,
                         eo_mesh_src *src);

#endif
