/* VTK XML unstructured grid (.vtu) frames, ParaView .pvd series, boundary OBJ.
 *
 * Reference: "VTK File Formats" (VTK user's guide, XML formats). A frame is written
 * with every array in one <AppendedData encoding="raw"> block: after the '_' marker,
 * each array is a UInt64 byte count followed by its little-endian bytes; a DataArray's
 * `offset` is the position of its count relative to the byte after '_'.
 *   Points: Float64 ×3; Cells: connectivity Int64, offsets Int64, types UInt8 (10 = tet;
 *   24 = quadratic tet, 10 ids each in the order of tet10, for an order-2 mesh)
 *   PointData: displacement, velocity (Float64 ×3); CellData: energy_density, J
 *   (Float64), inverted (UInt8), region (Int32, when the mesh has tet attributes).
 * Non-finite values (e.g. the barrier energy density of an inverted tet) are never
 * written: NaN and +Inf become +EO_VTU_NONFINITE (1e300), -Inf -EO_VTU_NONFINITE, and a
 * UInt8 array "nonfinite" (point or cell data) marks every tuple that held one.
 * The .pvd index lists every frame so far and is rewritten atomically after each one.
 * The OBJ holds the outward boundary triangles and only the vertices they use. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "elastopt/io.h"
#include "elastopt/trimesh.h"
#include "mesh_io.h"

/* ---- little-endian output -------------------------------------------------------- */

static int host_is_le(void)
{
    const uint16_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

/* Write n items of `size` bytes in little-endian order. */
static void put_le(FILE *f, const void *data, size_t size, size_t n)
{
    if (host_is_le()) {
        fwrite(data, size, n, f);
        return;
    }
    const unsigned char *p = data;
    unsigned char buf[8];
    for (size_t i = 0; i < n; i++, p += size) {
        for (size_t k = 0; k < size; k++) buf[k] = p[size - 1 - k];
        fwrite(buf, size, 1, f);
    }
}

static void put_u64(FILE *f, uint64_t v) { put_le(f, &v, 8, 1); }

typedef enum { A_F64, A_I64, A_U8, A_I32 } atype;
static const char *const atype_name[] = {"Float64", "Int64", "UInt8", "Int32"};
static const size_t atype_size[] = {8, 8, 1, 4};

typedef struct {
    const char *name;
    atype type;
    int ncomp;
    size_t n;          /* items (tuples * ncomp) */
    const void *data;
} varray;

static void header_array(FILE *f, const varray *a, uint64_t *offset)
{
    fprintf(f, "        <DataArray type=\"%s\" Name=\"%s\"", atype_name[a->type], a->name);
    if (a->ncomp > 1) fprintf(f, " NumberOfComponents=\"%d\"", a->ncomp);
    fprintf(f, " format=\"appended\" offset=\"%llu\"/>\n", (unsigned long long)*offset);
    *offset += 8 + a->n * atype_size[a->type];
}

/* A Float64 value as written: non-finite values become the finite sentinels
 * +EO_VTU_NONFINITE (NaN, +Inf) and -EO_VTU_NONFINITE (-Inf). */
static double finite_or_sentinel(double v)
{
    if (isfinite(v)) return v;
    return (isinf(v) && v < 0) ? -EO_VTU_NONFINITE : EO_VTU_NONFINITE;
}

static void put_array(FILE *f, const varray *a)
{
    put_u64(f, a->n * atype_size[a->type]);
    if (a->type != A_F64) {
        put_le(f, a->data, atype_size[a->type], a->n);
        return;
    }
    const double *d = a->data;
    for (size_t i = 0; i < a->n; i++) {
        double v = finite_or_sentinel(d[i]);
        put_le(f, &v, 8, 1);
    }
}

/* Mark in flag[] (tuples of `a`) every tuple holding a non-finite value; returns the
 * count of tuples newly marked (flag may be NULL: count only). */
static size_t mark_nonfinite(const varray *a, unsigned char *flag)
{
    if (a->type != A_F64) return 0;
    const double *d = a->data;
    size_t marked = 0;
    for (size_t i = 0; i < a->n; i++) {
        if (isfinite(d[i])) continue;
        size_t t = i / (size_t)a->ncomp;
        if (!flag) return 1;
        if (!flag[t]) marked++;
        flag[t] = 1;
    }
    return marked;
}

/* One unstructured grid of nc cells with npc nodes each (VTK type vtk_type); points are
 * xyz (3 per vertex) or, when dim == 2, xy with z = 0. pd/cd: point and cell arrays
 * (Float64 arrays are written with the sentinel policy and, if any value was not
 * finite, a UInt8 array "nonfinite" of the same association marks the tuples). */
static int write_grid(eo_ctx *ctx, const char *path, size_t nv, const double *pts, int dim, size_t nc, int npc,
                      const int *conn, unsigned char vtk_type, varray *pd, int npd, varray *cd, int ncd,
                      const char *scalars)
{
    unsigned char *flag_p = NULL, *flag_c = NULL;
    int any_p = 0, any_c = 0;
    for (int i = 0; i < npd; i++) any_p |= mark_nonfinite(&pd[i], NULL) > 0;
    for (int i = 0; i < ncd; i++) any_c |= mark_nonfinite(&cd[i], NULL) > 0;
    if (any_p && !(flag_p = eo_calloc(ctx, nv ? nv : 1, 1))) return eo_error(ctx, EO_ERR_NOMEM, "vtu %s: flags", path);
    if (any_c && !(flag_c = eo_calloc(ctx, nc ? nc : 1, 1))) {
        eo_free(ctx, flag_p);
        return eo_error(ctx, EO_ERR_NOMEM, "vtu %s: flags", path);
    }
    varray pdx[8], cdx[8];
    if (npd) memcpy(pdx, pd, (size_t)npd * sizeof *pd);
    if (ncd) memcpy(cdx, cd, (size_t)ncd * sizeof *cd);
    if (any_p) {
        for (int i = 0; i < npd; i++) mark_nonfinite(&pd[i], flag_p);
        pdx[npd++] = (varray){"nonfinite", A_U8, 1, nv, flag_p};
    }
    if (any_c) {
        for (int i = 0; i < ncd; i++) mark_nonfinite(&cd[i], flag_c);
        cdx[ncd++] = (varray){"nonfinite", A_U8, 1, nc, flag_c};
    }
    varray ptsa = {"Points", A_F64, 3, 3 * nv, NULL};
    varray conna = {"connectivity", A_I64, 1, (size_t)npc * nc, NULL};
    varray offsa = {"offsets", A_I64, 1, nc, NULL};
    varray typesa = {"types", A_U8, 1, nc, NULL};

    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) goto out;
    FILE *f = eo_afile_fp(af);
    uint64_t off = 0;
    fprintf(f, "<?xml version=\"1.0\"?>\n"
               "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
               "header_type=\"UInt64\">\n"
               "  <UnstructuredGrid>\n"
               "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n",
            nv, nc);
    if (npd) {
        fprintf(f, "      <PointData");
        if (scalars) {
            fputs(" Scalars=\"", f);
            fputs(scalars, f);
            fputc('"', f);
        }
        fprintf(f, ">\n");
        for (int i = 0; i < npd; i++) header_array(f, &pdx[i], &off);
        fprintf(f, "      </PointData>\n");
    }
    if (ncd) {
        fprintf(f, "      <CellData>\n");
        for (int i = 0; i < ncd; i++) header_array(f, &cdx[i], &off);
        fprintf(f, "      </CellData>\n");
    }
    fprintf(f, "      <Points>\n");
    header_array(f, &ptsa, &off);
    fprintf(f, "      </Points>\n      <Cells>\n");
    header_array(f, &conna, &off);
    header_array(f, &offsa, &off);
    header_array(f, &typesa, &off);
    fprintf(f, "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _");
    /* data in the same order as the headers */
    for (int i = 0; i < npd; i++) put_array(f, &pdx[i]);
    for (int i = 0; i < ncd; i++) put_array(f, &cdx[i]);
    put_u64(f, ptsa.n * 8);
    for (size_t i = 0; i < nv; i++) {
        double p[3] = {pts[dim * i], pts[dim * i + 1], dim == 3 ? pts[3 * i + 2] : 0};
        for (int k = 0; k < 3; k++) p[k] = finite_or_sentinel(p[k]);
        put_le(f, p, 8, 3);
    }
    put_u64(f, conna.n * 8);
    for (size_t i = 0; i < conna.n; i++) {
        int64_t v = conn[i];
        put_le(f, &v, 8, 1);
    }
    put_u64(f, offsa.n * 8);
    for (size_t t = 0; t < nc; t++) {
        int64_t v = (int64_t)((size_t)npc * (t + 1));
        put_le(f, &v, 8, 1);
    }
    put_u64(f, typesa.n);
    for (size_t t = 0; t < nc; t++) fputc(vtk_type, f);
    fprintf(f, "\n  </AppendedData>\n</VTKFile>\n");
    rc = eo_afile_commit(ctx, &af);
out:
    eo_free(ctx, flag_p);
    eo_free(ctx, flag_c);
    return rc;
}

int eo_vtu_write(eo_ctx *ctx, const char *path, const eo_mesh *m, const eo_vtu_fields *fl)
{
    eo_vtu_fields none = {0};
    if (!fl) fl = &none;
    const size_t nv = (size_t)m->nv, nt = (size_t)m->nt;
    varray pd[2], cd[4];
    int npd = 0, ncd = 0;
    if (fl->displacement) pd[npd++] = (varray){"displacement", A_F64, 3, 3 * nv, fl->displacement};
    if (fl->velocity) pd[npd++] = (varray){"velocity", A_F64, 3, 3 * nv, fl->velocity};
    if (fl->energy_density) cd[ncd++] = (varray){"energy_density", A_F64, 1, nt, fl->energy_density};
    if (fl->J) cd[ncd++] = (varray){"J", A_F64, 1, nt, fl->J};
    if (fl->inverted) cd[ncd++] = (varray){"inverted", A_U8, 1, nt, fl->inverted};
    if (m->tet_attr) cd[ncd++] = (varray){"region", A_I32, 1, nt, m->tet_attr};
    if (m->tet10) /* order 2: quadratic tetra cells over every node; cell data stays per tet */
        return write_grid(ctx, path, nv, fl->x ? fl->x : m->X, 3, nt, 10, m->tet10, 24, pd, npd, cd, ncd, NULL);
    return write_grid(ctx, path, nv, fl->x ? fl->x : m->X, 3, nt, 4, m->tets, 10, pd, npd, cd, ncd, NULL);
}

/* Triangles (trimesh.h): Points Float64 ×3 with z = 0, cells of type 5, one optional
 * Float64 point field. Same appended-raw layout as the tet frames. */
int eo_vtu_write_tri(eo_ctx *ctx, const char *path, int nv, const double *xy, int nt, const int *tri,
                     const char *field, const double *values)
{
    if (nv < 0 || nt < 0) return eo_error(ctx, EO_ERR_INVALID, "vtu: nv = %d, nt = %d", nv, nt);
    const char *name = field ? field : "u";
    varray pd = {name, A_F64, 1, (size_t)nv, values};
    return write_grid(ctx, path, (size_t)nv, xy, 2, (size_t)nt, 3, tri, 5, &pd, values ? 1 : 0, NULL, 0,
                      values ? name : NULL);
}

static int write_vtu_rest(eo_ctx *ctx, const eo_mesh *m, const char *path) { return eo_vtu_write(ctx, path, m, NULL); }

/* ---- .pvd series ------------------------------------------------------------------- */

typedef struct {
    double t;
    char *file;
} pvd_frame;

struct eo_pvd {
    char *path;
    pvd_frame *frames;
    int n, cap;
    eo_ctx *ctx;                       ///< context it was created with (its destroy uses it)
};

int eo_pvd_create(eo_ctx *ctx, const char *pvd_path, eo_pvd **out)
{
    *out = NULL;
    eo_pvd *p = eo_calloc(ctx, 1, sizeof *p);
    if (p) p->ctx = ctx;
    if (!p || !(p->path = eo_strdup(ctx, pvd_path))) {
        eo_free(ctx, p);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (pvd)");
    }
    *out = p;
    return EO_OK;
}

static void xml_attr(FILE *f, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
    }
}

int eo_pvd_add(eo_ctx *ctx, eo_pvd *p, double t, const char *vtu_file)
{
    if (p->n == p->cap) {
        int cap = p->cap ? 2 * p->cap : 16;
        pvd_frame *nf = eo_realloc(ctx, p->frames, (size_t)cap * sizeof *nf);
        if (!nf) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (pvd)");
        p->frames = nf;
        p->cap = cap;
    }
    char *file = eo_strdup(ctx, vtu_file);
    if (!file) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (pvd)");
    p->frames[p->n++] = (pvd_frame){t, file};
    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, p->path, &af);
    if (rc < 0) return rc;
    FILE *f = eo_afile_fp(af);
    fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "  <Collection>\n");
    for (int i = 0; i < p->n; i++) {
        char tb[32];
        fprintf(f, "    <DataSet timestep=\"%s\" group=\"\" part=\"0\" file=\"", eo_fmt_double(tb, p->frames[i].t));
        xml_attr(f, p->frames[i].file);
        fprintf(f, "\"/>\n");
    }
    fprintf(f, "  </Collection>\n</VTKFile>\n");
    return eo_afile_commit(ctx, &af);
}

void eo_pvd_destroy(eo_pvd **pp)
{
    eo_ctx *ctx = pp && *pp ? (*pp)->ctx : NULL;
    if (!pp || !*pp) return;
    eo_pvd *p = *pp;
    for (int i = 0; i < p->n; i++) eo_free(ctx, p->frames[i].file);
    eo_free(ctx, p->frames);
    eo_free(ctx, p->path);
    eo_free(ctx, p);
    *pp = NULL;
}

/* ---- boundary OBJ -------------------------------------------------------------------- */

int eo_obj_write(eo_ctx *ctx, const char *path, const eo_mesh *m, const double *x)
{
    if (!x) x = m->X;
    int *faces = NULL, nf = 0, *map = NULL;
    eo_afile *af = NULL;
    int rc = eo_mesh_boundary_faces(ctx, m, &faces, &nf);
    if (rc < 0) return rc;
    map = eo_malloc(ctx, (size_t)(m->nv ? m->nv : 1) * sizeof(int));
    if (!map) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (obj)");
        goto fail;
    }
    for (int v = 0; v < m->nv; v++) map[v] = -1;
    if ((rc = eo_afile_open(ctx, path, &af)) < 0) goto fail;
    FILE *f = eo_afile_fp(af);
    fprintf(f, "# boundary surface written by elastopt: %d triangles\n", nf);
    int n = 0;
    for (int i = 0; i < 3 * nf; i++) {
        int v = faces[i];
        if (map[v] >= 0) continue;
        map[v] = ++n;
        char b[3][32];
        fprintf(f, "v %s %s %s\n", eo_fmt_double(b[0], x[3 * v]), eo_fmt_double(b[1], x[3 * v + 1]),
                eo_fmt_double(b[2], x[3 * v + 2]));
    }
    for (int i = 0; i < nf; i++)
        fprintf(f, "f %d %d %d\n", map[faces[3 * i]], map[faces[3 * i + 1]], map[faces[3 * i + 2]]);
    rc = eo_afile_commit(ctx, &af);
fail:
    eo_afile_abort(ctx, &af);
    eo_free(ctx, map);
    eo_free(ctx, faces);
    return rc;
}

static int write_obj_rest(eo_ctx *ctx, const eo_mesh *m, const char *path) { return eo_obj_write(ctx, path, m, NULL); }

static const char *const vtu_exts[] = {".vtu", NULL};
static const char *const obj_exts[] = {".obj", NULL};

const eo_mesh_io_type eo_mesh_io_vtu = {
    .format = EO_MESH_VTU,
    .name = "vtu",
    .exts = vtu_exts,
    .read_text = eo_vtu_read_text, /* lib/mesh_vtu.c */
    .write = write_vtu_rest,
};

const eo_mesh_io_type eo_mesh_io_obj = {
    .format = EO_MESH_OBJ,
    .name = "obj",
    .exts = obj_exts,
    .read_text = eo_obj_read_text, /* lib/mesh_surface.c: tetrahedralized by TetGen */
    .write = write_obj_rest,
};
