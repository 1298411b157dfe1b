// TetGen library shim: a closed triangle surface -> a constrained (quality) Delaunay
// tetrahedralization, behind a C interface (declared in mesh_io.h).
//
// Reference: H. Si, "TetGen, a Delaunay-based quality tetrahedral mesh generator",
// ACM TOMS 41(2), 2015; TetGen 1.5 user's manual, section 4 (switches) and 6.2 (library).
// The input is a PLC with one triangle facet per surface triangle; the switches come
// from the caller (mesh_surface.c: "pzQ" plus q<ratio> and a<volume>). 'p' keeps every
// input facet (Steiner points may be added on it, in its plane), so the volume of the
// result equals the volume the surface encloses up to rounding.
// TetGen built as a library (TETLIBRARY, as Debian's libtet does) reports errors by
// throwing an int; they are caught here and returned as codes, so nothing unwinds into
// C. Compiled only when meson finds the library (-Dtetgen=auto|enabled).
#define TETLIBRARY
#include <tetgen.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

extern "C" int eo_tetgen_run(const double *X, int np, const int *tri, int nt, const char *switches,
                             double **Xout, int *npout, int **tets, int *ntout, char *msg, size_t msgn);

extern "C" int eo_tetgen_run(const double *X, int np, const int *tri, int nt, const char *switches,
                             double **Xout, int *npout, int **tets, int *ntout, char *msg, size_t msgn)
{
    *Xout = nullptr;
    *tets = nullptr;
    *npout = *ntout = 0;
    msg[0] = 0;
    try {
        tetgenio in, out;
        in.firstnumber = 0;
        in.numberofpoints = np;
        in.pointlist = new REAL[3 * (size_t)np];
        for (size_t i = 0; i < 3 * (size_t)np; i++) in.pointlist[i] = X[i];
        in.numberoffacets = nt;
        in.facetlist = new tetgenio::facet[(size_t)nt];
        for (int f = 0; f < nt; f++) {
            tetgenio::facet *fc = &in.facetlist[f];
            tetgenio::init(fc);
            fc->numberofpolygons = 1;
            fc->polygonlist = new tetgenio::polygon[1];
            tetgenio::init(&fc->polygonlist[0]);
            fc->polygonlist[0].numberofvertices = 3;
            fc->polygonlist[0].vertexlist = new int[3];
            for (int a = 0; a < 3; a++) fc->polygonlist[0].vertexlist[a] = tri[3 * f + a];
        }
        // TetGen 1.5 meshing a self-intersecting surface ('p') fails in its own clean-up
        // (a segmentation fault inside tetgenmesh::freememory, not a thrown error), so the
        // surface is checked first with 'd' (detect intersections only; its output lists the
        // triangles that intersect others, nothing is meshed). About 0.1 s per 10k triangles.
        {
            tetgenio dout;
            char dsw[] = "dzQ";
            tetrahedralize(dsw, &in, &dout);
            if (dout.numberoftrifaces > 0) {
                const int *t = dout.trifacelist;
                const int f0 = dout.firstnumber;
                double c[3] = {0, 0, 0};
                for (int a = 0; a < 3; a++)
                    for (int k = 0; k < 3; k++) c[k] += dout.pointlist[3 * (size_t)(t[a] - f0) + k] / 3;
                std::snprintf(msg, msgn, "%d triangles intersect others, the first near (%.6g, %.6g, %.6g)",
                              dout.numberoftrifaces, c[0], c[1], c[2]);
                return 3;
            }
        }
        char sw[128];
        std::snprintf(sw, sizeof sw, "%s", switches);
        tetrahedralize(sw, &in, &out);
        if (out.numberofcorners != 4 || out.numberoftetrahedra <= 0) {
            std::snprintf(msg, msgn, "TetGen produced no tetrahedra");
            return 10;
        }
        *Xout = static_cast<double *>(std::malloc(3 * (size_t)out.numberofpoints * sizeof(double)));
        *tets = static_cast<int *>(std::malloc(4 * (size_t)out.numberoftetrahedra * sizeof(int)));
        if (!*Xout || !*tets) {
            std::free(*Xout);
            std::free(*tets);
            *Xout = nullptr;
            *tets = nullptr;
            std::snprintf(msg, msgn, "out of memory copying TetGen's output");
            return 1;
        }
        std::memcpy(*Xout, out.pointlist, 3 * (size_t)out.numberofpoints * sizeof(double));
        for (size_t i = 0; i < 4 * (size_t)out.numberoftetrahedra; i++)
            (*tets)[i] = out.tetrahedronlist[i] - out.firstnumber;
        *npout = out.numberofpoints;
        *ntout = out.numberoftetrahedra;
        return 0;
    } catch (int code) {
        std::snprintf(msg, msgn, "TetGen error %d", code);
        return code > 0 ? code : -1;
    } catch (std::bad_alloc &) {
        std::snprintf(msg, msgn, "out of memory in TetGen");
        return 1;
    } catch (...) {
        std::snprintf(msg, msgn, "unexpected exception in TetGen");
        return -1;
    }
}
