/// @file io.h
/// Output: atomic file writing, VTU frames with a .pvd series, small text helpers.
///
/// Every file is written under a temporary name in the same folder and renamed over
/// the target when complete, so a crash never leaves a half-written file.
///
/// ```c
/// eo_afile *f; eo_afile_open(ctx, "out/summary.json", &f);
/// fprintf(eo_afile_fp(f), "{}\n");
/// rc = eo_afile_commit(ctx, &f);     // or eo_afile_abort(&f) on error
/// ```
#ifndef ELASTOPT_IO_H
#define ELASTOPT_IO_H

#include "export.h"
#include <stdio.h>
#include "mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_afile eo_afile;

/// Open `path` for writing through a temporary file. EO_ERR_IO names the path; the path
/// is checked first (eo_path_check, EO_PATH_WRITE): a folder, FIFO, device or socket at
/// it, or a missing or unwritable parent folder, is refused before anything is created.
EO_API int eo_afile_open(eo_ctx *ctx, const char *path, eo_afile **out);
EO_API FILE *eo_afile_fp(eo_afile *f);
/// Flush, fsync-less close and rename into place; frees f and sets *f = NULL.
EO_API int eo_afile_commit(eo_ctx *ctx, eo_afile **f);
/// Discard the temporary file; accepts NULL.
EO_API void eo_afile_abort(eo_ctx *ctx, eo_afile **f);

/// How a path is going to be used (eo_path_check).
typedef enum eo_path_mode { EO_PATH_READ = 0, EO_PATH_WRITE = 1 } eo_path_mode;

/// Check a file path before using it, without opening it (so a FIFO never blocks):
/// EO_ERR_IO with "PATH: <why>; expected ..." for a name longer than PATH_MAX (or a
/// component longer than NAME_MAX); reading: a missing or unreadable file, a folder,
/// a device, FIFO or socket, an empty file; writing: a folder, device, FIFO or socket
/// at the path, a missing parent folder or a parent that is not a folder, an
/// unwritable parent. EO_OK otherwise.
EO_API int eo_path_check(eo_ctx *ctx, const char *path, eo_path_mode mode);

/// Create a folder (and parents) if missing; EO_ERR_IO if impossible or not writable.
EO_API int eo_mkdir_p(eo_ctx *ctx, const char *path);
/// Read a whole file into a NUL-terminated buffer (eo_free it). EO_ERR_IO if missing,
/// unreadable or not a regular file (a FIFO, device or folder is refused at once: the
/// file is opened with O_NONBLOCK and checked before any read, so nothing blocks).
EO_API int eo_read_file(eo_ctx *ctx, const char *path, char **text, size_t *len);
/// eo_read_file for a file of at most max_bytes: a larger regular file is refused from its
/// size before anything is allocated or read (EO_ERR_RANGE: "PATH: N bytes; the limit for
/// WHAT is M bytes"); what names the kind of file ("a configuration file").
EO_API int eo_read_file_max(eo_ctx *ctx, const char *path, size_t max_bytes, const char *what, char **text,
                            size_t *len);

/// A double in the shortest decimal form that reads back (strtod) to the same value:
/// the first of %.15g, %.16g, %.17g that round-trips ("0.4", not "0.40000000000000002";
/// 0.1 + 0.2 stays "0.30000000000000004"). Non-finite values print as %g does ("nan",
/// "inf", "-inf"). Every text writer of times and coordinates uses it (.pvd times,
/// steps.csv, summary.json and run.json through eo_json_dumps, MEDIT/Gmsh/TetGen/OBJ
/// coordinates). Writes into buf and returns it.
EO_API const char *eo_fmt_double(char buf[32], double v);

/// Per-frame fields for VTU output; any pointer may be NULL to omit the field.
typedef struct eo_vtu_fields {
    const double *x;          ///< current positions 3*nv (NULL: rest positions)
    const double *displacement;  ///< 3*nv
    const double *velocity;      ///< 3*nv
    const double *energy_density;///< nt (ψ per tet)
    const double *J;             ///< nt (det F)
    const unsigned char *inverted; ///< nt (1 if J <= 0)
} eo_vtu_fields;

/// Sentinel written to VTU files in place of a non-finite value (NaN and +Inf: +1e300,
/// -Inf: -1e300); a UInt8 array "nonfinite" then flags the affected points/cells.
#define EO_VTU_NONFINITE 1e300

/// Write one VTU (XML, appended raw binary, little endian) frame. No non-finite value is
/// written (see EO_VTU_NONFINITE).
EO_API int eo_vtu_write(eo_ctx *ctx, const char *path, const eo_mesh *m, const eo_vtu_fields *f);

/// A ParaView .pvd time series: add frames, write the index atomically each time.
typedef struct eo_pvd eo_pvd;
EO_API int eo_pvd_create(eo_ctx *ctx, const char *pvd_path, eo_pvd **out);
/// Record frame `vtu_file` (relative to the pvd's folder) at time t and rewrite the .pvd.
EO_API int eo_pvd_add(eo_ctx *ctx, eo_pvd *p, double t, const char *vtu_file);
EO_API void eo_pvd_destroy(eo_pvd **p);

/// Boundary surface as Wavefront OBJ at positions x (NULL: rest).
EO_API int eo_obj_write(eo_ctx *ctx, const char *path, const eo_mesh *m, const double *x);

#ifdef __cplusplus
}
#endif
#endif
