/* Scene configuration: descriptor tables of every scene section and the loader that
 * turns a configuration document into an eo_scene (mesh, per-tet materials, boundary
 * vertex sets, initial-state transform, integrator, output options).
 *
 * Each params section is read with eo_cfg_section (unknown keys fail at load with the
 * valid keys listed); the list sections (`materials`, `boundary`) are read item by item
 * with the same tables at paths "materials.N", "boundary.N". Semantic errors (a
 * boundary entry selecting no vertex, two selectors, a zero normal, ...) are reported
 * with the file:line of the offending key, or the -o override that set it. */
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/element.h"
#include "elastopt/impl/term.h"
#include "elastopt/machine.h"
#include "elastopt/scene.h"
#include "problem_registry.h"
#include "elastopt/step.h"
#include "lattice.h"
#include "obstacle.h"
#include "supports.h"

/* ---------------------------------------------------------------- descriptor tables */

static const char *const mass_choices[] = {"consistent", "lumped", NULL};
static const char *const shape_choices[] = {"box", "cook", NULL};

#define SZ(T, f) sizeof(((T *)0)->f)

const eo_param_desc eo_scene_opts_desc[] = {
    {.key = "description", .kind = EO_PARAM_STRING, .offset = offsetof(eo_scene_opts, description),
     .size = SZ(eo_scene_opts, description), .def.s = "", .help = "free text describing the scene (ignored)"},
    {.key = "mass", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_scene_opts, mass),
     .size = SZ(eo_scene_opts, mass), .def.s = "consistent", .choices = mass_choices,
     .help = "mass matrix: consistent (rhoV/10, rhoV/20 per tet) or lumped (rhoV/4 per vertex)"},
    {.key = "gravity", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_opts, gravity),
     .def.v = {0, 0, -9.81}, .help = "gravitational acceleration (m/s^2)"},
    {.key = "point_mass", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_opts, point_mass), .def.d = 0,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "point mass added to every vertex (kg); point_masses [[vertex, kg], ...] adds to single vertices"},
    {.key = "element", .kind = EO_PARAM_METHOD, .offset = offsetof(eo_scene_opts, element),
     .size = SZ(eo_scene_opts, element), .def.s = "p1", .registry = &eo_reg_element,
     .help = "finite element (registered name): p1 = linear tet, p2 = 10-node quadratic tet (a linear mesh gets one "
             "midside node per edge at load; boundary selectors, tags and obstacles then apply to every node)"},
    {0},
};

static const char *const spring_edge_choices[] = {"none", "mesh", "list", NULL};

const eo_param_desc eo_scene_springs_opts_desc[] = {
    {.key = "edges", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_scene_springs_opts, edges),
     .size = SZ(eo_scene_springs_opts, edges), .def.s = "none", .choices = spring_edge_choices,
     .help = "none, mesh (a spring on every unique tet edge) or list (springs.list: [[i, j], ...] vertex pairs)"},
    {.key = "k", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_springs_opts, k), .def.d = 1000, .min = 0,
     .range = EO_RANGE_POSITIVE, .help = "stiffness of every scene spring (N/m); rest lengths from the rest positions"},
    {.key = "damping", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_springs_opts, damping), .def.d = 0,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "damping along each spring (N s/m), f = -c((va - vb).n)n; explicit integrators only"},
    {0},
};

const eo_param_desc eo_scene_collision_opts_desc[] = {
    {.key = "stiffness", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_collision_opts, stiffness),
     .def.d = 1e5, .min = 0, .range = EO_RANGE_POSITIVE,
     .help = "penalty stiffness per vertex (N/m): E = k/2 max(0, d)^2 with d the depth inside the obstacle, not "
             "mass-weighted"},
    {.key = "friction", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_collision_opts, friction), .def.d = 0,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "Coulomb friction coefficient mu against this obstacle (0 = frictionless); lagged normal force, "
             "smoothed below eps_v; implicit integrators only"},
    {.key = "eps_v", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_collision_opts, eps_v), .def.d = 1e-3,
     .min = 0, .range = EO_RANGE_POSITIVE,
     .help = "friction smoothing velocity (m/s): the friction force grows from 0 to mu*lambda over tangential "
             "speeds [0, eps_v] (sticking = creep slower than eps_v)"},
    {0},
};

const eo_param_desc eo_scene_mesh_opts_desc[] = {
    {.key = "file", .kind = EO_PARAM_STRING, .offset = offsetof(eo_scene_mesh_opts, file),
     .size = SZ(eo_scene_mesh_opts, file), .def.s = "",
     .help = "mesh file (.node/.ele, .mesh, .msh, .vtu, .veg; or a closed surface .obj, .off, .stl, .ply tetrahedralized by "
             "TetGen with mesh.tetgen), relative to the config's folder; empty = mesh.generate"},
    {.key = "drop_degenerate", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_scene_mesh_opts, drop_degenerate),
     .def.i = 0, .help = "drop zero-volume/duplicate tets and unreferenced vertices with a warning"},
    {0},
};

const eo_param_desc eo_scene_tetgen_opts_desc[] = {
    {.key = "quality", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_tetgen_opts, quality), .def.d = 2.0,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "radius-edge ratio bound of the tets (TetGen -q): 0 = no quality refinement, else >= 1 (smaller = "
             "better shaped, more tets)"},
    {.key = "max_volume", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_tetgen_opts, max_volume), .def.d = 0,
     .min = 0, .range = EO_RANGE_MIN, .help = "largest tet volume (m^3, TetGen -a); 0 = no bound"},
    {0},
};

const eo_param_desc eo_scene_lattice_opts_desc[] = {
    {.key = "cells", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_lattice_opts, cells), .def.v = {10, 10, 0},
     .help = "grid cells along x, y, z (integers >= 0; 0 = flat along that axis: [n, n, 0] is a cloth)"},
    {.key = "size", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_lattice_opts, size), .def.v = {1, 1, 0},
     .help = "extent along x, y, z (m; > 0 where cells > 0)"},
    {.key = "origin", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_lattice_opts, origin), .def.v = {0, 0, 0},
     .help = "position of vertex 0, the minimum corner (m)"},
    {.key = "mass", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_lattice_opts, mass), .def.d = 1, .min = 0,
     .range = EO_RANGE_POSITIVE, .help = "total mass (kg), spread evenly over the cells and each cell's corners"},
    {.key = "structural_k", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_lattice_opts, structural_k),
     .def.d = 1000, .min = 0, .range = EO_RANGE_MIN,
     .help = "stiffness of the structural springs between grid neighbours (N/m; 0 = none)"},
    {.key = "shear_k", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_lattice_opts, shear_k), .def.d = 1000,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "stiffness of the shear springs, both diagonals of every grid square (N/m; 0 = none)"},
    {.key = "bending_k", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_lattice_opts, bending_k), .def.d = 100,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "stiffness of the bending springs between grid points two apart along an axis (N/m; 0 = none)"},
    {0},
};

const eo_param_desc eo_scene_generate_opts_desc[] = {
    {.key = "size", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_generate_opts, size),
     .def.v = {1, 0.1, 0.1}, .help = "box extent along x, y, z (m)"},
    {.key = "cells", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_generate_opts, cells),
     .def.v = {20, 2, 2}, .help = "hexahedral cells along x, y, z (integers >= 1)"},
    {.key = "split", .kind = EO_PARAM_INT, .offset = offsetof(eo_scene_generate_opts, split), .def.i = 5,
     .min = 5, .max = 6, .range = EO_RANGE_CLOSED,
     .help = "tets per cell: 5 (alternating, symmetric) or 6 (one diagonal: bends sideways)"},
    {.key = "origin", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_generate_opts, origin),
     .def.v = {0, 0, 0}, .help = "minimum corner (m)"},
    {.key = "shape", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_scene_generate_opts, shape),
     .size = SZ(eo_scene_generate_opts, shape), .def.s = "box", .choices = shape_choices,
     .help = "box; or cook: the box's x-y rectangle mapped onto Cook's tapered panel, corners origin + (0,0), "
             "(Lx, Ly), (Lx, Ly·60/44), (0, Ly) (the classic 48 × 44/60 mm panel for size [48, 44, t])"},
    {0},
};

const eo_param_desc eo_scene_time_opts_desc[] = {
    {.key = "integrator", .kind = EO_PARAM_METHOD, .offset = offsetof(eo_scene_time_opts, integrator),
     .size = SZ(eo_scene_time_opts, integrator), .def.s = "newmark", .registry = &eo_reg_integrator,
     .help = "time integrator (registered name); static (no inertia) is refused at load when a body keeps a free rigid-body mode (see boundary)"},
    {.key = "dt", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_time_opts, dt), .def.d = 0.01,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "time step (s)"},
    {.key = "steps", .kind = EO_PARAM_INT, .offset = offsetof(eo_scene_time_opts, steps), .def.i = 30,
     .min = 1, .range = EO_RANGE_MIN, .help = "number of time steps"},
    {.key = "load_steps", .kind = EO_PARAM_INT, .offset = offsetof(eo_scene_time_opts, load_steps), .def.i = 0,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "static only: ramp gravity and prescribed motions linearly over this many steps (0 = full load at once)"},
    {.key = "adaptive", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_scene_time_opts, adaptive), .def.i = 0,
     .help = "adaptive stepping (implicit integrators): a step that does not converge after solver.fallback is "
             "retried as two half steps, recursively down to adaptive_min_fraction*dt; the size doubles again after "
             "adaptive_grow_after converged substeps in a row, never beyond dt; steps still end at t = n*dt"},
    {.key = "adaptive_min_fraction", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_time_opts, adaptive_min_fraction),
     .def.d = 0.015625, .min = 0, .max = 1, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX,
     .help = "smallest substep of adaptive stepping as a fraction of dt (rounded down to a power of two, at least "
             "2^-30); default 1/64"},
    {.key = "adaptive_grow_after", .kind = EO_PARAM_INT, .offset = offsetof(eo_scene_time_opts, adaptive_grow_after),
     .def.i = 2, .min = 1, .range = EO_RANGE_MIN,
     .help = "adaptive stepping: converged substeps in a row after which the substep size doubles (up to dt)"},
    {0},
};

const eo_param_desc eo_scene_damping_opts_desc[] = {
    {.key = "viscous", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_damping_opts, viscous), .def.d = 0,
     .min = 0, .range = EO_RANGE_MIN, .help = "global viscous damping gamma (N s/m per vertex): a = (f - gamma v)/m"},
    {.key = "rayleigh_alpha", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_damping_opts, rayleigh_alpha),
     .def.d = 0, .min = 0, .range = EO_RANGE_MIN, .help = "Rayleigh mass-proportional damping alpha (1/s): C = alpha M"},
    {.key = "rayleigh_beta", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_damping_opts, rayleigh_beta),
     .def.d = 0, .min = 0, .range = EO_RANGE_MIN,
     .help = "Rayleigh stiffness-proportional damping beta (s): C = beta K, K the clamped elastic Hessian at the start of the step"},
    {0},
};

const eo_param_desc eo_scene_output_opts_desc[] = {
    {.key = "dir", .kind = EO_PARAM_STRING, .offset = offsetof(eo_scene_output_opts, dir),
     .size = SZ(eo_scene_output_opts, dir), .def.s = "", .help = "output folder; empty = out/<scene name> (elastopt run --out overrides)"},
    {.key = "every", .kind = EO_PARAM_INT, .offset = offsetof(eo_scene_output_opts, every), .def.i = 1,
     .min = 0, .range = EO_RANGE_MIN, .help = "write a VTU frame every k steps (0 = none)"},
    {.key = "vtu", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_scene_output_opts, vtu), .def.i = 1,
     .help = "write VTU frames and the .pvd series"},
    {.key = "summary_every", .kind = EO_PARAM_INT, .offset = offsetof(eo_scene_output_opts, summary_every),
     .def.i = 10, .min = 0, .range = EO_RANGE_MIN,
     .help = "rewrite summary.json (atomically) every k steps and at the end (0 = only at the end)"},
    {0},
};

const eo_param_desc eo_scene_initial_opts_desc[] = {
    {.key = "scale", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_initial_opts, scale),
     .def.v = {1, 1, 1}, .help = "scale of the rest shape about its centre of mass, per axis"},
    {.key = "velocity", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_initial_opts, velocity),
     .def.v = {0, 0, 0}, .help = "uniform initial velocity (m/s)"},
    {0},
};

const eo_param_desc eo_scene_plane_opts_desc[] = {
    {.key = "point", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_plane_opts, point),
     .def.v = {0, 0, 0}, .help = "a point of the plane (m)"},
    {.key = "normal", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_plane_opts, normal),
     .def.v = {1, 0, 0}, .help = "plane normal (non-zero; normalized)"},
    {0},
};

const eo_param_desc eo_scene_ball_opts_desc[] = {
    {.key = "radius", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_ball_opts, radius), .def.d = 1,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "radius of the ball around the centre of mass (m)"},
    {.key = "seed", .kind = EO_PARAM_INT, .offset = offsetof(eo_scene_ball_opts, seed), .def.i = 1,
     .help = "random seed"},
    {0},
};

const eo_param_desc eo_scene_bc_opts_desc[] = {
    {.key = "marker", .kind = EO_PARAM_INT, .offset = offsetof(eo_scene_bc_opts, marker), .def.i = -1,
     .help = "select the vertices with this mesh vertex marker"},
    {.key = "tag", .kind = EO_PARAM_INT, .offset = offsetof(eo_scene_bc_opts, tag), .def.i = 0,
     .help = "select the vertices of the tagged triangles with this tag (Gmsh physical surface, MEDIT triangle "
             "reference, TetGen .face marker); if none, of the tets with this attribute (physical volume); if none, "
             "the vertices with this marker"},
    {.key = "surface", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_scene_bc_opts, surface), .def.i = 0,
     .help = "true: select every vertex of the boundary surface (faces used by one tet)"},
    {.key = "nearest", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_bc_opts, nearest), .def.v = {0, 0, 0},
     .help = "select the single rest vertex nearest to this point (m)"},
    {.key = "fixed", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_scene_bc_opts, fixed), .def.i = 0,
     .help = "hold the vertices at their initial positions"},
    {.key = "translate", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_bc_opts, translate),
     .def.v = {0, 0, 0}, .help = "move the vertices with this velocity (m/s): x0 + t v"},
    {.key = "until", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_bc_opts, until), .def.d = -1,
     .help = "the motion stops at this time (s); < 0 = never"},
    {.key = "release", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_bc_opts, release), .def.d = -1,
     .help = "the vertices become free after this time (s); < 0 = never"},
    {.key = "components", .kind = EO_PARAM_STRING, .offset = offsetof(eo_scene_bc_opts, components),
     .size = SZ(eo_scene_bc_opts, components), .def.s = "xyz",
     .help = "displacement components the entry prescribes, a non-empty subset of xyz (e.g. \"z\" holds u_z only: a "
             "plane-strain slab); the others stay free. Where entries overlap, the later one decides a vertex"},
    {0},
};

const eo_param_desc eo_scene_rotate_opts_desc[] = {
    {.key = "axis", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_rotate_opts, axis),
     .def.v = {1, 0, 0}, .help = "rotation axis (non-zero; normalized)"},
    {.key = "center", .kind = EO_PARAM_VEC3, .offset = offsetof(eo_scene_rotate_opts, center),
     .def.v = {0, 0, 0}, .help = "a point on the axis (m)"},
    {.key = "rate", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_scene_rotate_opts, rate), .def.d = 0,
     .help = "angular velocity (rad/s); angle = rate * t"},
    {0},
};

const eo_cfg_doc eo_scene_docs[] = {
    {"", eo_scene_opts_desc, "top-level scene keys (also: mesh, material, materials, boundary, initial, springs, collisions, point_masses, damping, time, solver, output)"},
    {"mesh", eo_scene_mesh_opts_desc, "the mesh: a file, mesh.generate, or mesh.points [[x,y,z], ...] (points without tets: a mass-spring system)"},
    {"mesh.generate", eo_scene_generate_opts_desc, "generated box of hexahedral cells split into tets"},
    {"mesh.lattice", eo_scene_lattice_opts_desc, "generated mass-spring lattice without tets (cloth: one axis with 0 cells): structural, shear and bending springs"},
    {"mesh.tetgen", eo_scene_tetgen_opts_desc, "tetrahedralization of a surface mesh file (.obj, .off, .stl, .ply) by TetGen"},
    {"time", eo_scene_time_opts_desc, "time stepping"},
    {"damping", eo_scene_damping_opts_desc, "damping force -C v, C = viscous I + rayleigh_alpha M + rayleigh_beta K (explicit and implicit integrators)"},
    {"output", eo_scene_output_opts_desc, "what `elastopt run` writes"},
    {"initial", eo_scene_initial_opts_desc, "initial state (also initial.reflect {point, normal}, initial.random_ball)"},
    {"initial.reflect", eo_scene_plane_opts_desc, "reflect the rest shape through a plane (fully inverted start)"},
    {"initial.random_ball", eo_scene_ball_opts_desc, "scatter vertices uniformly in a ball (random start)"},
    {"boundary.N", eo_scene_bc_opts_desc, "boundary list entry: selector (box | plane | marker | tag | surface | nearest) and motion (fixed | translate | rotate)"},
    {"boundary.N.plane", eo_scene_plane_opts_desc, "select rest vertices with (X - point).normal >= 0"},
    {"boundary.N.rotate", eo_scene_rotate_opts_desc, "rotate the set about an axis"},
    {"springs", eo_scene_springs_opts_desc, "scene springs (mass-spring system) on top of the materials' tet elasticity; material.model = spring means springs only"},
    {"collisions.N", eo_scene_collision_opts_desc, "static obstacle (exactly one shape: plane, sphere or box): penalty contact and Coulomb friction"},
    {NULL, NULL, NULL},
};

/* ---------------------------------------------------------------- errors */

#define cfg_err eo_cfg_error

/* [[x0,y0,z0],[x1,y1,z1]] → box[6] */
static int read_box(eo_ctx *ctx, eo_cfg *cfg, const char *path, const json_t *v, double box[6])
{
    char got[32];
    if (!json_is_array(v) || json_array_size(v) != 2)
        return cfg_err(ctx, cfg, path, EO_ERR_TYPE, "expected an array of 2 corners [[x0,y0,z0],[x1,y1,z1]], got %s",
                       eo_json_describe(v, got, sizeof got));
    for (int i = 0; i < 2; i++) {
        json_t *c = json_array_get(v, (size_t)i);
        if (!json_is_array(c) || json_array_size(c) != 3)
            return cfg_err(ctx, cfg, path, EO_ERR_TYPE,
                           "expected [[x0,y0,z0],[x1,y1,z1]]; corner %d: expected an array of 3 numbers, got %s", i,
                           eo_json_describe(c, got, sizeof got));
        for (int k = 0; k < 3; k++) {
            json_t *e = json_array_get(c, (size_t)k);
            if (!json_is_number(e) || !isfinite(json_number_value(e)))
                return cfg_err(ctx, cfg, path, EO_ERR_TYPE, "corner %d component %d is not a finite number", i, k);
            box[3 * i + k] = json_number_value(e);
        }
    }
    for (int k = 0; k < 3; k++)
        if (box[k] > box[3 + k])
            return cfg_err(ctx, cfg, path, EO_ERR_RANGE, "empty box: lower corner above upper corner along axis %d", k);
    return EO_OK;
}

static int normalize(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(n > 0)) return -1;
    for (int k = 0; k < 3; k++) v[k] /= n;
    return 0;
}

static const json_t *member(const json_t *obj, const char *key)
{
    return json_is_object(obj) ? json_object_get(obj, key) : NULL;
}

/* ---------------------------------------------------------------- sections */

/* mesh.points: [[x,y,z], ...] → a mesh with vertices and no tets */
static int load_points(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc, const json_t *pts)
{
    if (!json_is_array(pts) || json_array_size(pts) < 1)
        return cfg_err(ctx, cfg, "mesh.points", EO_ERR_TYPE, "expected a non-empty list of [x,y,z] points, got %s",
                       eo_json_type_name(pts));
    int n = (int)json_array_size(pts);
    int rc = eo_mesh_create(ctx, n, 0, &sc->mesh);
    if (rc < 0) return rc;
    for (int v = 0; v < n; v++) {
        const json_t *p = json_array_get(pts, (size_t)v);
        char got[32];
        if (!json_is_array(p) || json_array_size(p) != 3)
            return cfg_err(ctx, cfg, "mesh.points", EO_ERR_TYPE, "point %d: expected an array of 3 numbers, got %s", v,
                           eo_json_describe(p, got, sizeof got));
        for (int k = 0; k < 3; k++) {
            const json_t *e = json_array_get(p, (size_t)k);
            if (!json_is_number(e) || !isfinite(json_number_value(e)))
                return cfg_err(ctx, cfg, "mesh.points", EO_ERR_TYPE, "point %d is not 3 finite numbers", v);
            sc->mesh->X[3 * v + k] = json_number_value(e);
        }
    }
    sc->points = 1;
    return EO_OK;
}

static int load_mesh(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    static const char *const extra[] = {"generate", "points", "tetgen", "lattice", NULL};
    int rc = eo_cfg_section(ctx, cfg, "mesh", eo_scene_mesh_opts_desc, &sc->mesh_opts, extra);
    if (rc < 0) return rc;
    eo_params_default(eo_scene_tetgen_opts_desc, &sc->tetgen);
    if ((rc = eo_cfg_section(ctx, cfg, "mesh.tetgen", eo_scene_tetgen_opts_desc, &sc->tetgen, NULL)) < 0) return rc;
    if (sc->tetgen.quality > 0 && sc->tetgen.quality < 1)
        return cfg_err(ctx, cfg, "mesh.tetgen.quality", EO_ERR_RANGE,
                       "expected 0 (no quality refinement) or a radius-edge bound >= 1, got %g", sc->tetgen.quality);
    if (eo_cfg_get(cfg, "mesh.tetgen")) {
        eo_mesh_format f = eo_mesh_format_from_path(sc->mesh_opts.file);
        if (f != EO_MESH_OBJ && f != EO_MESH_OFF && f != EO_MESH_STL && f != EO_MESH_PLY)
            return cfg_err(ctx, cfg, "mesh.tetgen", EO_ERR_INVALID,
                           "mesh.tetgen applies to surface mesh files (.obj, .off, .stl, .ply); mesh.file is '%s'",
                           sc->mesh_opts.file);
    }
    if (eo_cfg_get(cfg, "mesh.lattice")) {
        if (sc->mesh_opts.file[0] || eo_cfg_get(cfg, "mesh.generate") || eo_cfg_get(cfg, "mesh.points"))
            return cfg_err(ctx, cfg, "mesh.lattice", EO_ERR_INVALID,
                           "give one of mesh.file, mesh.generate, mesh.points, mesh.lattice");
        eo_params_default(eo_scene_lattice_opts_desc, &sc->lat);
        if ((rc = eo_cfg_section(ctx, cfg, "mesh.lattice", eo_scene_lattice_opts_desc, &sc->lat, NULL)) < 0) return rc;
        double nv = 1;
        for (int k = 0; k < 3; k++) {
            double c = sc->lat.cells[k];
            if (!(c >= 0) || c != floor(c) || c > 1e4)
                return cfg_err(ctx, cfg, "mesh.lattice.cells", EO_ERR_RANGE,
                               "cells must be integers >= 0; component %d is %g", k, c);
            if (c > 0 && !(sc->lat.size[k] > 0 && isfinite(sc->lat.size[k])))
                return cfg_err(ctx, cfg, "mesh.lattice.size", EO_ERR_RANGE,
                               "size must be positive along an axis with cells; component %d is %g", k, sc->lat.size[k]);
            nv *= c + 1;
        }
        if (nv > 1e7) return cfg_err(ctx, cfg, "mesh.lattice.cells", EO_ERR_RANGE, "%g points is too many", nv);
        rc = eo_lattice_build(ctx, &sc->lat, &sc->mesh, &sc->spring_ab, &sc->spring_k, &sc->nspring, &sc->pmass,
                              sc->lattice_count);
        if (rc < 0) return rc;
        sc->points = sc->lattice = 1;
        return EO_OK;
    }
    json_t *pts = eo_cfg_get(cfg, "mesh.points");
    if (pts) {
        if (sc->mesh_opts.file[0] || eo_cfg_get(cfg, "mesh.generate"))
            return cfg_err(ctx, cfg, "mesh.points", EO_ERR_INVALID, "give one of mesh.file, mesh.generate, mesh.points");
        return load_points(ctx, cfg, sc, pts);
    }
    rc = eo_cfg_section(ctx, cfg, "mesh.generate", eo_scene_generate_opts_desc, &sc->gen, NULL);
    if (rc < 0) return rc;
    int has_gen = eo_cfg_get(cfg, "mesh.generate") != NULL;
    if (sc->mesh_opts.file[0] && has_gen)
        return cfg_err(ctx, cfg, "mesh.generate", EO_ERR_INVALID, "give mesh.file or mesh.generate, not both");
    if (!sc->mesh_opts.file[0]) {
        eo_mesh_gen_opts g = eo_mesh_gen_opts_default();
        for (int k = 0; k < 3; k++) {
            double c = sc->gen.cells[k];
            if (!(c >= 1) || c != floor(c) || c > 1e6)
                return cfg_err(ctx, cfg, "mesh.generate.cells", EO_ERR_RANGE,
                               "cells must be integers >= 1; component %d is %g", k, c);
            if (!(sc->gen.size[k] > 0))
                return cfg_err(ctx, cfg, "mesh.generate.size", EO_ERR_RANGE,
                               "size must be positive; component %d is %g", k, sc->gen.size[k]);
            g.size[k] = sc->gen.size[k];
            g.origin[k] = sc->gen.origin[k];
            g.cells[k] = (int)c;
        }
        g.split = sc->gen.split;
        sc->generated = 1;
        /* a box that cannot be simulated here: name the key, not "out of memory" later */
        double nt_d = (double)g.cells[0] * g.cells[1] * g.cells[2] * g.split;
        eo_machine mach;
        eo_machine_get(&mach);
        if (mach.mem_bytes > 0 && nt_d * EO_SCENE_BYTES_PER_TET > mach.mem_bytes)
            return cfg_err(ctx, cfg, "mesh.generate.cells", EO_ERR_RANGE,
                           "[%d, %d, %d] cells make %.3g tets, which need about %.3g GB to simulate; this "
                           "machine has %.3g GB",
                           g.cells[0], g.cells[1], g.cells[2], nt_d, nt_d * EO_SCENE_BYTES_PER_TET / 1e9,
                           mach.mem_bytes / 1e9);
        rc = eo_mesh_generate_box(ctx, &g, &sc->mesh);
        if (rc >= 0 && strcmp(sc->gen.shape, "cook") == 0) eo_mesh_map_cook(sc->mesh, g.origin, g.size);
        if (rc == EO_ERR_RANGE || rc == EO_ERR_NOMEM) {
            char msg[512];
            snprintf(msg, sizeof msg, "%s", eo_ctx_message(ctx));
            return cfg_err(ctx, cfg, "mesh.generate.cells", rc, "%s", msg);
        }
        return rc;
    }
    /* a relative path is relative to the config file's folder */
    char path[1100];
    const char *cfile = eo_cfg_file(cfg);
    const char *slash = strrchr(cfile, '/');
    if (sc->mesh_opts.file[0] != '/' && cfile[0] != '<' && slash)
        snprintf(path, sizeof path, "%.*s/%s", (int)(slash - cfile), cfile, sc->mesh_opts.file);
    else
        snprintf(path, sizeof path, "%s", sc->mesh_opts.file);
    eo_mesh_read_opts ro = eo_mesh_read_opts_default();
    ro.drop_degenerate = sc->mesh_opts.drop_degenerate;
    ro.drop_unreferenced = sc->mesh_opts.drop_degenerate;
    ro.tetgen_quality = sc->tetgen.quality;
    ro.tetgen_max_volume = sc->tetgen.max_volume;
    rc = eo_mesh_read(ctx, path, &ro, &sc->mesh);
    return rc;
}

/* A distributed run (eo_ctx_dist): the whole mesh (on part 0) becomes this part's local
 * mesh. Mass-spring meshes have no tets to distribute. */
static int distribute_mesh(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    const eo_dist_hooks *h = eo_ctx_dist(ctx);
    if (sc->points)
        return cfg_err(ctx, cfg, sc->lattice ? "mesh.lattice" : "mesh.points", EO_ERR_UNSUPPORTED,
                       "a mesh without tets has no distributed form (run it on one process)");
    if (!h->distribute_mesh)
        return eo_error(ctx, EO_ERR_UNSUPPORTED, "distributed run without a mesh distribution");
    return h->distribute_mesh(ctx, &sc->mesh, h->user);
}

/* A distributed run: refuse what the local meshes cannot express as sums of their parts
 * (include/elastopt/ctx.h, eo_dist_hooks). */
static int check_distributed(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    static const char *const why = "has no distributed form yet (run it on one process)";
    for (int b = 0; b < sc->nbc; b++)
        if (sc->bc[b].select == EO_BC_TAG || sc->bc[b].select == EO_BC_SURFACE ||
            sc->bc[b].select == EO_BC_NEAREST) {
            char path[64];
            snprintf(path, sizeof path, "boundary.%d", b);
            return cfg_err(ctx, cfg, path, EO_ERR_UNSUPPORTED, "a %s selection %s; select by box, plane or marker",
                           sc->bc[b].select == EO_BC_TAG ? "tag" : sc->bc[b].select == EO_BC_SURFACE ? "surface"
                                                                                                 : "nearest",
                           why);
        }
    if (sc->has_ball) return cfg_err(ctx, cfg, "initial.random_ball", EO_ERR_UNSUPPORTED, "%s", why);
    if (sc->pmass) return cfg_err(ctx, cfg, "point_masses", EO_ERR_UNSUPPORTED, "point masses: %s", why);
    if (sc->nspring) return cfg_err(ctx, cfg, "springs", EO_ERR_UNSUPPORTED, "springs: %s", why);
    const eo_dist_hooks *dh = eo_ctx_dist(ctx);
    if (sc->ncollision && !(dh && dh->owned_vertices)) /* contact and friction: each vertex on its owner */
        return cfg_err(ctx, cfg, "collisions", EO_ERR_UNSUPPORTED, "collisions: %s", why);
    if (sc->damping.viscous > 0 || sc->damping.rayleigh_alpha > 0 || sc->damping.rayleigh_beta > 0)
        return cfg_err(ctx, cfg, "damping", EO_ERR_UNSUPPORTED, "damping: %s", why);
    for (int i = 0; i < sc->nterm_cfg; i++)
        if (sc->term_type[i]->section)
            return cfg_err(ctx, cfg, sc->term_type[i]->section, EO_ERR_UNSUPPORTED, "%s %s",
                           sc->term_type[i]->section, why);
    if (!(sc->element->flags & EO_ELEMENT_LINEAR))
        return cfg_err(ctx, cfg, "element", EO_ERR_UNSUPPORTED, "element %s %s; use p1", sc->element->info.name, why);
    return EO_OK;
}

static int load_materials(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    const eo_mesh *m = sc->mesh;
    eo_material_opts m0;
    eo_params_default(eo_material_opts_desc, &m0);
    int rc = eo_cfg_section(ctx, cfg, "material", eo_material_opts_desc, &m0, NULL);
    if (rc < 0) return rc;
    json_t *list = eo_cfg_get(cfg, "materials");
    if (list && !json_is_array(list))
        return cfg_err(ctx, cfg, "materials", EO_ERR_TYPE, "expected a list of region materials, got %s",
                       eo_json_type_name(list));
    int nreg = list ? (int)json_array_size(list) : 0;
    sc->nmat = 1 + nreg;
    sc->mat = eo_calloc(ctx, (size_t)sc->nmat, sizeof *sc->mat);
    sc->tet_mat = eo_calloc(ctx, (size_t)(m->nt > 0 ? m->nt : 1), sizeof(int));
    if (!sc->mat || !sc->tet_mat) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    sc->mat[0].opts = m0;
    static const char *const extra[] = {"attribute", "box", NULL};
    for (int r = 0; r < sc->nmat; r++) {
        char path[64];
        snprintf(path, sizeof path, r == 0 ? "material" : "materials.%d", r - 1);
        eo_scene_material *mat = sc->mat + r;
        if (r > 0) {
            mat->opts = m0;
            rc = eo_cfg_section(ctx, cfg, path, eo_material_opts_desc, &mat->opts, extra);
            if (rc < 0) return rc;
        }
        rc = eo_registry_find(ctx, EO_KIND_MATERIAL, mat->opts.model, (const void **)&mat->type);
        if (rc < 0) return cfg_err(ctx, cfg, path, rc, "%s", eo_ctx_message(ctx));
        mat->coef = eo_material_coef_from_opts(&mat->opts);
        if (!(mat->opts.pd_min <= mat->opts.pd_max))
            return cfg_err(ctx, cfg, path, EO_ERR_RANGE, "pd_min = %g is above pd_max = %g", mat->opts.pd_min,
                           mat->opts.pd_max);
        if (r == 0) continue;
        char sub[96];
        snprintf(sub, sizeof sub, "%s.attribute", path);
        json_t *attr = eo_cfg_get(cfg, sub);
        snprintf(sub, sizeof sub, "%s.box", path);
        json_t *boxv = eo_cfg_get(cfg, sub);
        if ((attr != NULL) == (boxv != NULL))
            return cfg_err(ctx, cfg, path, EO_ERR_INVALID,
                           "a region material selects its tets by exactly one of \"attribute\" or \"box\"");
        double box[6];
        long a = 0;
        if (attr) {
            snprintf(sub, sizeof sub, "%s.attribute", path);
            if (!json_is_integer(attr))
                return cfg_err(ctx, cfg, sub, EO_ERR_TYPE, "expected an integer, got %s", eo_json_type_name(attr));
            if (!m->tet_attr)
                return cfg_err(ctx, cfg, sub, EO_ERR_INVALID, "the mesh has no tet attributes");
            a = (long)json_integer_value(attr);
        } else {
            rc = read_box(ctx, cfg, sub, boxv, box);
            if (rc < 0) return rc;
        }
        int count = 0;
        for (int k = 0; k < m->nt; k++) {
            int hit;
            if (attr) {
                hit = m->tet_attr[k] == a;
            } else {
                double c[3] = {0, 0, 0};
                for (int q = 0; q < 4; q++)
                    for (int d = 0; d < 3; d++) c[d] += 0.25 * m->X[3 * m->tets[4 * k + q] + d];
                hit = c[0] >= box[0] && c[0] <= box[3] && c[1] >= box[1] && c[1] <= box[4] &&
                      c[2] >= box[2] && c[2] <= box[5];
            }
            if (hit) {
                sc->tet_mat[k] = r;
                count++;
            }
        }
        if (!count) return cfg_err(ctx, cfg, path, EO_ERR_INVALID, "region material selects no tet");
    }
    return EO_OK;
}

/* "1, 2, 5" (distinct values of v, at most 16 listed) or "none" */
static void list_values(const int *v, int n, char *buf, size_t size)
{
    int shown[16], ns = 0, more = 0;
    for (int i = 0; i < n; i++) {
        int seen = 0;
        for (int k = 0; k < ns && !seen; k++) seen = shown[k] == v[i];
        if (seen) continue;
        if (ns == 16) {
            more = 1;
            continue;
        }
        int k = ns++;
        while (k > 0 && shown[k - 1] > v[i]) { /* keep sorted */
            shown[k] = shown[k - 1];
            k--;
        }
        shown[k] = v[i];
    }
    size_t k = 0;
    buf[0] = 0;
    if (!ns) snprintf(buf, size, "none");
    for (int i = 0; i < ns && k < size; i++) k += (size_t)snprintf(buf + k, size - k, "%s%d", i ? ", " : "", shown[i]);
    if (more && k < size) snprintf(buf + k, size - k, ", ...");
}

/* tag / surface / nearest selection into bc->verts (capacity nv) */
static int select_special(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc, eo_bc *bc, const char *path)
{
    const eo_mesh *m = sc->mesh;
    char sub[96];
    if (bc->select == EO_BC_NEAREST) {
        const double *p = bc->opts.nearest;
        double best = INFINITY;
        int bv = -1;
        for (int v = 0; v < m->nv; v++) {
            const double *X = m->X + 3 * v;
            double d = (X[0] - p[0]) * (X[0] - p[0]) + (X[1] - p[1]) * (X[1] - p[1]) + (X[2] - p[2]) * (X[2] - p[2]);
            if (d < best) {
                best = d;
                bv = v;
            }
        }
        snprintf(sub, sizeof sub, "%s.nearest", path);
        if (bv < 0) return cfg_err(ctx, cfg, sub, EO_ERR_INVALID, "the mesh has no vertex");
        bc->verts[bc->nverts++] = bv;
        bc->nearest_dist = sqrt(best);
        return EO_OK;
    }
    unsigned char *flag = eo_calloc(ctx, (size_t)(m->nv > 0 ? m->nv : 1), 1);
    if (!flag) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    int rc = EO_OK, count = 0;
    if (bc->select == EO_BC_SURFACE) {
        rc = eo_mesh_surface_vertices(ctx, m, flag, &count);
    } else {
        const int K = bc->opts.tag;
        for (int f = 0; f < m->ntri; f++)
            if (m->tri_tag[f] == K)
                for (int a = 0; a < 3; a++) {
                    flag[m->tris[3 * f + a]] = 1;
                    if (m->tri_mid) flag[m->tri_mid[3 * f + a]] = 1;
                }
        bc->tag_source = EO_TAG_TRIANGLES;
        for (int v = 0; v < m->nv; v++) count += flag[v];
        if (!count && m->tet_attr) {
            for (int t = 0; t < m->nt; t++)
                if (m->tet_attr[t] == K)
                    for (int a = 0; a < (m->tet10 ? 10 : 4); a++) flag[m->tet10 ? m->tet10[10 * t + a] : m->tets[4 * t + a]] = 1;
            bc->tag_source = EO_TAG_TETS;
            for (int v = 0; v < m->nv; v++) count += flag[v];
        }
        if (!count && m->vmarker) {
            for (int v = 0; v < m->nv; v++) count += flag[v] = m->vmarker[v] == K;
            bc->tag_source = EO_TAG_VERTICES;
        }
        if (!count) {
            char a[160], b[160], c[160];
            list_values(m->tri_tag, m->ntri, a, sizeof a);
            list_values(m->tet_attr, m->tet_attr ? m->nt : 0, b, sizeof b);
            list_values(m->vmarker, m->vmarker ? m->nv : 0, c, sizeof c);
            snprintf(sub, sizeof sub, "%s.tag", path);
            bc->tag_source = EO_TAG_NONE;
            rc = cfg_err(ctx, cfg, sub, EO_ERR_INVALID,
                         "no tagged triangle, tet or vertex carries tag %d; the mesh has triangle tags: %s; tet "
                         "attributes: %s; vertex markers: %s",
                         K, a, b, c);
        }
    }
    if (rc >= 0)
        for (int v = 0; v < m->nv; v++)
            if (flag[v]) bc->verts[bc->nverts++] = v;
    eo_free(ctx, flag);
    if (rc >= 0 && !bc->nverts) rc = cfg_err(ctx, cfg, path, EO_ERR_INVALID, "boundary entry selects no vertex");
    return rc;
}

static int load_boundary(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    const eo_mesh *m = sc->mesh;
    json_t *list = eo_cfg_get(cfg, "boundary");
    if (!list) return EO_OK;
    if (!json_is_array(list))
        return cfg_err(ctx, cfg, "boundary", EO_ERR_TYPE, "expected a list of boundary conditions, got %s",
                       eo_json_type_name(list));
    sc->nbc = (int)json_array_size(list);
    if (!sc->nbc) return EO_OK;
    sc->bc = eo_calloc(ctx, (size_t)sc->nbc, sizeof *sc->bc);
    if (!sc->bc) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    /* tolerance for box/plane selection: relative to the mesh size */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++) {
            if (m->X[3 * v + k] < lo[k]) lo[k] = m->X[3 * v + k];
            if (m->X[3 * v + k] > hi[k]) hi[k] = m->X[3 * v + k];
        }
    { /* a distributed run: the whole mesh's box (the same tolerance on every part) */
        double b[6] = {-lo[0], -lo[1], -lo[2], hi[0], hi[1], hi[2]};
        eo_ctx_reduce(ctx, b, 6, EO_REDUCE_MAX);
        for (int k = 0; k < 3; k++) lo[k] = -b[k], hi[k] = b[3 + k];
    }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double tol = 1e-9 * (diag > 0 ? diag : 1);
    static const char *const extra[] = {"box", "plane", "rotate", NULL};
    for (int b = 0; b < sc->nbc; b++) {
        eo_bc *bc = sc->bc + b;
        char path[64], sub[96];
        snprintf(path, sizeof path, "boundary.%d", b);
        const json_t *item = json_array_get(list, (size_t)b);
        eo_params_default(eo_scene_bc_opts_desc, &bc->opts);
        eo_params_default(eo_scene_plane_opts_desc, &bc->plane);
        eo_params_default(eo_scene_rotate_opts_desc, &bc->rotate);
        int rc = eo_cfg_section(ctx, cfg, path, eo_scene_bc_opts_desc, &bc->opts, extra);
        if (rc < 0) return rc;
        int nsel = (member(item, "box") != NULL) + (member(item, "plane") != NULL) + (member(item, "marker") != NULL) +
                   (member(item, "tag") != NULL) + (member(item, "surface") != NULL) + (member(item, "nearest") != NULL);
        if (nsel != 1)
            return cfg_err(ctx, cfg, path, EO_ERR_INVALID,
                           "a boundary entry selects vertices by exactly one of \"box\", \"plane\", \"marker\", "
                           "\"tag\", \"surface\", \"nearest\" (found %d)",
                           nsel);
        int nmot = bc->opts.fixed + (member(item, "translate") != NULL) + (member(item, "rotate") != NULL);
        if (nmot != 1)
            return cfg_err(ctx, cfg, path, EO_ERR_INVALID,
                           "a boundary entry needs exactly one of \"fixed\": true, \"translate\", \"rotate\" (found %d)",
                           nmot);
        if (member(item, "box")) {
            bc->select = EO_BC_BOX;
            snprintf(sub, sizeof sub, "%s.box", path);
            rc = read_box(ctx, cfg, sub, eo_cfg_get(cfg, sub), bc->box);
            if (rc < 0) return rc;
        } else if (member(item, "plane")) {
            bc->select = EO_BC_PLANE;
            snprintf(sub, sizeof sub, "%s.plane", path);
            rc = eo_cfg_section(ctx, cfg, sub, eo_scene_plane_opts_desc, &bc->plane, NULL);
            if (rc < 0) return rc;
            snprintf(sub, sizeof sub, "%s.plane.normal", path);
            if (normalize(bc->plane.normal) < 0) return cfg_err(ctx, cfg, sub, EO_ERR_RANGE, "zero normal");
        } else if (member(item, "marker")) {
            bc->select = EO_BC_MARKER;
            snprintf(sub, sizeof sub, "%s.marker", path);
            if (!m->vmarker) return cfg_err(ctx, cfg, sub, EO_ERR_INVALID, "the mesh has no vertex markers");
        } else if (member(item, "tag")) {
            bc->select = EO_BC_TAG;
        } else if (member(item, "surface")) {
            bc->select = EO_BC_SURFACE;
            snprintf(sub, sizeof sub, "%s.surface", path);
            if (!bc->opts.surface)
                return cfg_err(ctx, cfg, sub, EO_ERR_INVALID,
                               "\"surface\" selects the boundary-surface vertices: give true (or another selector)");
            if (m->nt < 1) return cfg_err(ctx, cfg, sub, EO_ERR_INVALID, "the mesh has no tets, hence no surface");
        } else {
            bc->select = EO_BC_NEAREST;
        }
        { /* components: a non-empty subset of xyz, each at most once */
            memset(bc->mask, 0, sizeof bc->mask);
            const char *cs = bc->opts.components;
            int bad = !cs[0];
            for (const char *q = cs; *q && !bad; q++) {
                const int c = *q == 'x' ? 0 : *q == 'y' ? 1 : *q == 'z' ? 2 : -1;
                bad = c < 0 || bc->mask[c];
                if (!bad) bc->mask[c] = 1;
            }
            if (bad) {
                snprintf(sub, sizeof sub, "%s.components", path);
                return cfg_err(ctx, cfg, sub, EO_ERR_INVALID,
                               "\"%s\": expected a non-empty subset of \"xyz\" (each letter at most once)", cs);
            }
            bc->partial = !(bc->mask[0] && bc->mask[1] && bc->mask[2]);
        }
        if (bc->opts.fixed) {
            bc->motion = EO_BC_FIXED;
        } else if (member(item, "translate")) {
            bc->motion = EO_BC_TRANSLATE;
        } else {
            bc->motion = EO_BC_ROTATE;
            snprintf(sub, sizeof sub, "%s.rotate", path);
            rc = eo_cfg_section(ctx, cfg, sub, eo_scene_rotate_opts_desc, &bc->rotate, NULL);
            if (rc < 0) return rc;
            snprintf(sub, sizeof sub, "%s.rotate.axis", path);
            if (normalize(bc->rotate.axis) < 0) return cfg_err(ctx, cfg, sub, EO_ERR_RANGE, "zero axis");
        }
        /* select */
        bc->verts = eo_malloc(ctx, (size_t)(m->nv > 0 ? m->nv : 1) * sizeof(int));
        if (!bc->verts) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
        if (bc->select == EO_BC_TAG || bc->select == EO_BC_SURFACE || bc->select == EO_BC_NEAREST) {
            if ((rc = select_special(ctx, cfg, sc, bc, path)) < 0) return rc;
            continue;
        }
        for (int v = 0; v < m->nv; v++) {
            const double *X = m->X + 3 * v;
            int hit = 0;
            switch (bc->select) {
            case EO_BC_BOX:
                hit = 1;
                for (int k = 0; k < 3; k++) hit &= X[k] >= bc->box[k] - tol && X[k] <= bc->box[3 + k] + tol;
                break;
            case EO_BC_PLANE: {
                const double *p = bc->plane.point, *n = bc->plane.normal;
                hit = (X[0] - p[0]) * n[0] + (X[1] - p[1]) * n[1] + (X[2] - p[2]) * n[2] >= -tol;
                break;
            }
            case EO_BC_MARKER: hit = m->vmarker[v] == bc->opts.marker; break;
            default: break;
            }
            if (hit) bc->verts[bc->nverts++] = v;
        }
        double nsel_all = bc->nverts; /* over every part of a distributed run */
        eo_ctx_reduce(ctx, &nsel_all, 1, EO_REDUCE_SUM);
        if (!(nsel_all > 0)) return cfg_err(ctx, cfg, path, EO_ERR_INVALID, "boundary entry selects no vertex");
    }
    return EO_OK;
}

static int load_initial(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    static const char *const extra[] = {"reflect", "random_ball", NULL};
    int rc = eo_cfg_section(ctx, cfg, "initial", eo_scene_initial_opts_desc, &sc->initial, extra);
    if (rc < 0) return rc;
    eo_params_default(eo_scene_plane_opts_desc, &sc->reflect);
    eo_params_default(eo_scene_ball_opts_desc, &sc->ball);
    rc = eo_cfg_section(ctx, cfg, "initial.reflect", eo_scene_plane_opts_desc, &sc->reflect, NULL);
    if (rc < 0) return rc;
    rc = eo_cfg_section(ctx, cfg, "initial.random_ball", eo_scene_ball_opts_desc, &sc->ball, NULL);
    if (rc < 0) return rc;
    sc->has_reflect = eo_cfg_get(cfg, "initial.reflect") != NULL;
    sc->has_ball = eo_cfg_get(cfg, "initial.random_ball") != NULL;
    if (sc->has_reflect && normalize(sc->reflect.normal) < 0)
        return cfg_err(ctx, cfg, "initial.reflect.normal", EO_ERR_RANGE, "zero normal");
    return EO_OK;
}

/* [i, j] or [i, x] pairs of a list: an integer vertex index first */
static int read_vertex(eo_ctx *ctx, eo_cfg *cfg, const char *path, const json_t *e, int nv, int *v)
{
    if (!json_is_integer(e) || json_integer_value(e) < 0 || json_integer_value(e) >= nv)
        return cfg_err(ctx, cfg, path, EO_ERR_RANGE, "expected a vertex index in [0, %d)", nv);
    *v = (int)json_integer_value(e);
    return EO_OK;
}

static int load_point_masses(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    const int nv = sc->mesh->nv;
    json_t *list = eo_cfg_get(cfg, "point_masses");
    if (list && !json_is_array(list))
        return cfg_err(ctx, cfg, "point_masses", EO_ERR_TYPE, "expected a list of [vertex, kg] pairs, got %s",
                       eo_json_type_name(list));
    if (!(sc->opts.point_mass > 0) && !(list && json_array_size(list))) return EO_OK;
    if (!sc->pmass) sc->pmass = eo_calloc(ctx, (size_t)nv, sizeof(double)); /* (a lattice has its masses) */
    if (!sc->pmass) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    for (int v = 0; v < nv; v++) sc->pmass[v] += sc->opts.point_mass;
    for (size_t i = 0; list && i < json_array_size(list); i++) {
        char path[64];
        snprintf(path, sizeof path, "point_masses.%zu", i);
        const json_t *e = json_array_get(list, i);
        int v = -1;
        char got[32];
        if (!json_is_array(e) || json_array_size(e) != 2)
            return cfg_err(ctx, cfg, path, EO_ERR_TYPE, "expected an array of 2 [vertex, kg], got %s",
                           eo_json_describe(e, got, sizeof got));
        int rc = read_vertex(ctx, cfg, path, json_array_get(e, 0), nv, &v);
        if (rc < 0) return rc;
        const json_t *m = json_array_get(e, 1);
        if (!json_is_number(m) || !(json_number_value(m) >= 0) || !isfinite(json_number_value(m)))
            return cfg_err(ctx, cfg, path, EO_ERR_RANGE, "the mass must be a finite number >= 0 (kg)");
        sc->pmass[v] += json_number_value(m);
    }
    return EO_OK;
}

static int cmp_pair(const void *a, const void *b)
{
    const int *x = a, *y = b;
    return x[0] != y[0] ? (x[0] < y[0] ? -1 : 1) : (x[1] != y[1] ? (x[1] < y[1] ? -1 : 1) : 0);
}

/* springs: every unique tet edge ("mesh") or the listed pairs ("list"), stored a < b */
static int load_springs(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    static const char *const extra[] = {"list", NULL};
    static const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    const eo_mesh *m = sc->mesh;
    eo_params_default(eo_scene_springs_opts_desc, &sc->springs);
    int rc = eo_cfg_section(ctx, cfg, "springs", eo_scene_springs_opts_desc, &sc->springs, extra);
    if (rc < 0) return rc;
    json_t *list = eo_cfg_get(cfg, "springs.list");
    int is_list = strcmp(sc->springs.edges, "list") == 0, is_mesh = strcmp(sc->springs.edges, "mesh") == 0;
    if (sc->lattice) { /* its springs are generated; springs.damping applies to them */
        if (is_list || is_mesh || list)
            return cfg_err(ctx, cfg, "springs.edges", EO_ERR_INVALID,
                           "mesh.lattice makes its own springs (structural_k, shear_k, bending_k): springs.edges must "
                           "be \"none\"");
        return EO_OK;
    }
    if (list && !is_list)
        return cfg_err(ctx, cfg, "springs.list", EO_ERR_INVALID, "springs.list needs springs.edges = \"list\"");
    if (is_list && (!json_is_array(list) || !json_array_size(list)))
        return cfg_err(ctx, cfg, list ? "springs.list" : "springs", EO_ERR_INVALID,
                       "springs.edges = \"list\" needs springs.list: a non-empty list of [i, j] vertex pairs");
    if (is_mesh && !m->nt)
        return cfg_err(ctx, cfg, "springs.edges", EO_ERR_INVALID, "the mesh has no tets: no edges to put springs on");
    int ncand = is_list ? (int)json_array_size(list) : is_mesh ? 6 * m->nt : 0;
    if (!ncand) return EO_OK;
    sc->spring_ab = eo_malloc(ctx, 2 * (size_t)ncand * sizeof(int));
    if (!sc->spring_ab) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (springs)");
    int *ab = sc->spring_ab;
    for (int i = 0; i < ncand; i++) {
        int a = -1, b = -1;
        if (is_list) {
            char path[64];
            snprintf(path, sizeof path, "springs.list.%d", i);
            const json_t *e = json_array_get(list, (size_t)i);
            char got[32];
            if (!json_is_array(e) || json_array_size(e) != 2)
                return cfg_err(ctx, cfg, path, EO_ERR_TYPE, "expected a vertex pair [i, j], got %s",
                               eo_json_describe(e, got, sizeof got));
            if ((rc = read_vertex(ctx, cfg, path, json_array_get(e, 0), m->nv, &a)) < 0) return rc;
            if ((rc = read_vertex(ctx, cfg, path, json_array_get(e, 1), m->nv, &b)) < 0) return rc;
            double L2 = 0;
            for (int k = 0; k < 3; k++) L2 += (m->X[3 * a + k] - m->X[3 * b + k]) * (m->X[3 * a + k] - m->X[3 * b + k]);
            if (!(L2 > 0))
                return cfg_err(ctx, cfg, path, EO_ERR_INVALID, "spring %d-%d has zero rest length", a, b);
        } else {
            a = m->tets[4 * (i / 6) + pairs[i % 6][0]];
            b = m->tets[4 * (i / 6) + pairs[i % 6][1]];
        }
        ab[2 * i] = a < b ? a : b;
        ab[2 * i + 1] = a < b ? b : a;
    }
    qsort(ab, (size_t)ncand, 2 * sizeof(int), cmp_pair);
    int n = 0;
    for (int i = 0; i < ncand; i++) {
        if (n > 0 && cmp_pair(ab + 2 * i, ab + 2 * (n - 1)) == 0) {
            if (is_list)
                return cfg_err(ctx, cfg, "springs.list", EO_ERR_INVALID, "spring %d-%d is listed twice", ab[2 * i],
                               ab[2 * i + 1]);
            continue;
        }
        ab[2 * n] = ab[2 * i];
        ab[2 * n + 1] = ab[2 * i + 1];
        n++;
    }
    sc->nspring = n;
    return EO_OK;
}

static int load_collisions(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    const char *extra[16];
    int ne = 0;
    for (const eo_obstacle_type *const *t = eo_obstacle_types; *t && ne < 15; t++) extra[ne++] = (*t)->name;
    extra[ne] = NULL;
    json_t *list = eo_cfg_get(cfg, "collisions");
    if (!list) return EO_OK;
    if (!json_is_array(list))
        return cfg_err(ctx, cfg, "collisions", EO_ERR_TYPE, "expected a list of obstacles, got %s",
                       eo_json_type_name(list));
    int n = (int)json_array_size(list);
    if (!n) return EO_OK;
    sc->collision = eo_calloc(ctx, (size_t)n, sizeof *sc->collision);
    if (!sc->collision) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    char shapes[160] = "";
    for (int q = 0; extra[q]; q++)
        snprintf(shapes + strlen(shapes), sizeof shapes - strlen(shapes), "%s\"%s\"", q ? ", " : "", extra[q]);
    for (int i = 0; i < n; i++) {
        char path[64], sub[96];
        snprintf(path, sizeof path, "collisions.%d", i);
        eo_scene_obstacle *ob = sc->collision + i;
        eo_params_default(eo_scene_collision_opts_desc, &ob->opts);
        int rc = eo_cfg_section(ctx, cfg, path, eo_scene_collision_opts_desc, &ob->opts, extra);
        if (rc < 0) return rc;
        const json_t *item = json_array_get(list, (size_t)i);
        int nshape = 0;
        for (const eo_obstacle_type *const *t = eo_obstacle_types; *t; t++)
            if (member(item, (*t)->name)) {
                ob->type = *t;
                nshape++;
            }
        if (nshape != 1)
            return cfg_err(ctx, cfg, path, EO_ERR_INVALID, "an obstacle needs exactly one shape of %s (found %d)",
                           shapes, nshape);
        EO_ASSERT(ob->type->params_size <= sizeof ob->shape);
        eo_params_default(ob->type->params, ob->shape);
        snprintf(sub, sizeof sub, "%s.%s", path, ob->type->name);
        if ((rc = eo_cfg_section(ctx, cfg, sub, ob->type->params, ob->shape, NULL)) < 0) return rc;
        const char *key = "", *msg = ob->type->setup ? ob->type->setup(ob->shape, &key) : NULL;
        if (msg) {
            snprintf(sub, sizeof sub, "%s.%s.%s", path, ob->type->name, key);
            return cfg_err(ctx, cfg, sub, EO_ERR_RANGE, "%s", msg);
        }
    }
    sc->ncollision = n;
    return EO_OK;
}

/* `time`, with the parameter sections time.<integrator> of the registered integrators
 * that have parameters: the selected one's into sc->integrator_params, the others
 * checked (unknown keys and ranges) and dropped. */
static int load_time(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    enum { MAX_SECTIONS = 32 };
    const char *names[MAX_SECTIONS + 1];
    size_t k = 0;
    for (const void *const *t = eo_registry_list(EO_KIND_INTEGRATOR); t && *t && k < MAX_SECTIONS; t++) {
        const eo_method_info *mi = eo_method_info_of(*t);
        if (mi->params && mi->params_size) names[k++] = mi->name;
    }
    names[k] = NULL;
    int rc = eo_cfg_section(ctx, cfg, "time", eo_scene_time_opts_desc, &sc->time, names);
    if (rc < 0) return rc;
    if ((rc = eo_registry_find(ctx, EO_KIND_INTEGRATOR, sc->time.integrator, (const void **)&sc->integrator)) < 0)
        return rc;
    for (const void *const *t = eo_registry_list(EO_KIND_INTEGRATOR); t && *t; t++) {
        const eo_method_info *mi = eo_method_info_of(*t);
        if (!mi->params || !mi->params_size) continue;
        void *p = eo_calloc(ctx, 1, mi->params_size);
        if (!p) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (integrator parameters)");
        eo_params_default(mi->params, p);
        char path[96];
        snprintf(path, sizeof path, "time.%s", mi->name);
        if ((rc = eo_cfg_section(ctx, cfg, path, mi->params, p, NULL)) < 0) {
            eo_free(ctx, p);
            return rc;
        }
        if (*t == (const void *)sc->integrator && !sc->integrator_params) sc->integrator_params = p;
        else eo_free(ctx, p);
    }
    return EO_OK;
}

/* ---------------------------------------------------------------- public */

int eo_scene_cfg_load(eo_ctx *ctx, const char *path, const char *name, eo_cfg **out)
{
    *out = NULL;
    if (path) return eo_cfg_load(ctx, path, NULL, out);
    const eo_scene_type *t;
    int rc = eo_registry_find(ctx, EO_KIND_SCENE, name ? name : "cantilever", (const void **)&t);
    if (rc < 0) return rc;
    return eo_cfg_load(ctx, NULL, t->json, out);
}

void eo_scene_destroy(eo_scene **psc)
{
    eo_ctx *ctx = psc && *psc ? (*psc)->ctx : NULL;
    if (!psc || !*psc) return;
    eo_scene *sc = *psc;
    eo_mesh_destroy(&sc->mesh);
    eo_free(ctx, sc->mat);
    eo_free(ctx, sc->tet_mat);
    for (int b = 0; b < sc->nbc; b++) eo_free(ctx, sc->bc[b].verts);
    eo_free(ctx, sc->bc);
    eo_free(ctx, sc->pmass);
    eo_free(ctx, sc->spring_ab);
    eo_free(ctx, sc->spring_k);
    eo_free(ctx, sc->collision);
    eo_free(ctx, sc->integrator_params);
    for (int i = 0; i < sc->nterm_cfg; i++) {
        if (sc->term_type[i]->free_cfg) sc->term_type[i]->free_cfg(ctx, sc->term_cfg[i]);
        else eo_free(ctx, sc->term_cfg[i]);
    }
    eo_free(ctx, (void *)sc->term_type);
    eo_free(ctx, sc->term_cfg);
    eo_free(ctx, sc);
    *psc = NULL;
}

/* The element of opts.element and the mesh in its node layout: a linear mesh is made
 * quadratic (eo_mesh_to_quadratic) for a 10-node element; a quadratic mesh needs one. */
static int load_element(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    int rc = eo_registry_find(ctx, EO_KIND_ELEMENT, sc->opts.element, (const void **)&sc->element);
    if (rc < 0) return cfg_err(ctx, cfg, "element", rc, "%s", eo_ctx_message(ctx));
    eo_mesh *m = sc->mesh;
    if (sc->points && !(sc->element->flags & EO_ELEMENT_LINEAR))
        return cfg_err(ctx, cfg, "element", EO_ERR_INVALID, "element %s needs tets; the mesh (%s) has none",
                       sc->element->info.name, sc->lattice ? "mesh.lattice" : "mesh.points");
    if (sc->element->nodes == 4) {
        if (m->order == 2)
            return cfg_err(ctx, cfg, "element", EO_ERR_INVALID,
                           "the mesh has 10-node (quadratic) tets; element %s has 4 nodes: use element p2",
                           sc->element->info.name);
        return EO_OK;
    }
    if (sc->points)
        return cfg_err(ctx, cfg, "element", EO_ERR_INVALID, "element %s needs tets; the mesh (%s) has none",
                       sc->element->info.name, sc->lattice ? "mesh.lattice" : "mesh.points");
    if (m->order == 2) { /* straight-sided elements: a file's midside nodes must sit at their edges' midpoints */
        static const int edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
        for (int t = 0; t < m->nt; t++)
            for (int e = 0; e < 6; e++) {
                const int *n = m->tet10 + 10 * t;
                const double *a = m->X + 3 * n[edge[e][0]], *b = m->X + 3 * n[edge[e][1]], *c = m->X + 3 * n[4 + e];
                double d2 = 0, l2 = 0;
                for (int k = 0; k < 3; k++) {
                    const double d = c[k] - 0.5 * (a[k] + b[k]);
                    d2 += d * d;
                    l2 += (b[k] - a[k]) * (b[k] - a[k]);
                }
                if (d2 > 1e-16 * l2)
                    return cfg_err(ctx, cfg, "element", EO_ERR_MESH,
                                   "tet %d: midside node %d of edge %d-%d is %.3g off the edge's midpoint (%.3g of its "
                                   "length); element %s is straight-sided (geometry from the corners): curved 10-node "
                                   "tets are not supported",
                                   t, n[4 + e], n[edge[e][0]], n[edge[e][1]], sqrt(d2), sqrt(d2 / l2),
                                   sc->element->info.name);
            }
        return EO_OK;
    }
    eo_mesh *q = NULL;
    if ((rc = eo_mesh_to_quadratic(ctx, m, &q)) < 0) return rc;
    eo_mesh_destroy(&sc->mesh);
    sc->mesh = q;
    return EO_OK;
}

const void *eo_scene_term_cfg(const eo_scene *sc, const eo_term_type *type)
{
    for (int i = 0; sc && i < sc->nterm_cfg; i++)
        if (sc->term_type[i] == type) return sc->term_cfg[i];
    return NULL;
}

/* The sections of the registered term kinds the scene has (eo_term_type.section): read
 * by the kind's load, or as its params section. */
static int load_terms(eo_ctx *ctx, eo_cfg *cfg, eo_scene *sc)
{
    int n = 0;
    for (const void *const *tp = eo_registry_list(EO_KIND_TERM); tp && *tp; tp++) n++;
    if (!n) return EO_OK;
    sc->term_type = eo_calloc(ctx, (size_t)n, sizeof *sc->term_type);
    sc->term_cfg = eo_calloc(ctx, (size_t)n, sizeof *sc->term_cfg);
    if (!sc->term_type || !sc->term_cfg) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    for (const void *const *tp = eo_registry_list(EO_KIND_TERM); tp && *tp; tp++) {
        const eo_term_type *tt = *tp;
        if (!tt->section || !eo_cfg_get(cfg, tt->section)) continue;
        void *data = NULL;
        int rc;
        if (tt->load) {
            rc = tt->load(ctx, cfg, sc, tt->section, &data);
        } else {
            data = eo_calloc(ctx, 1, tt->info.params_size ? tt->info.params_size : 1);
            if (!data) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
            if (tt->info.params) eo_params_default(tt->info.params, data);
            rc = tt->info.params ? eo_cfg_section(ctx, cfg, tt->section, tt->info.params, data, NULL) : EO_OK;
        }
        if (rc >= 0 || data) { /* kept (freed with the scene) */
            sc->term_type[sc->nterm_cfg] = tt;
            sc->term_cfg[sc->nterm_cfg++] = data;
        }
        if (rc < 0) return rc;
    }
    return EO_OK;
}

int eo_scene_load(eo_ctx *ctx, eo_cfg *cfg, eo_scene **out)
{
    static const char *const top0[] = {"mesh", "material", "materials", "boundary", "initial",
                                       "time", "solver", "output", "springs", "collisions",
                                       "point_masses", "damping", NULL};
    /* the top-level sections: the loader's own, then those of the registered terms */
    enum { NTOP = sizeof top0 / sizeof top0[0] - 1, MAXTOP = NTOP + 32 };
    const char *top[MAXTOP + 1];
    int ntop = 0;
    for (; ntop < NTOP; ntop++) top[ntop] = top0[ntop];
    for (const void *const *tp = eo_registry_list(EO_KIND_TERM); tp && *tp && ntop < MAXTOP; tp++)
        if (((const eo_term_type *)*tp)->section) top[ntop++] = ((const eo_term_type *)*tp)->section;
    top[ntop] = NULL;
    *out = NULL;
    eo_scene *sc = eo_calloc(ctx, 1, sizeof *sc);
    if (sc) sc->ctx = ctx;
    if (!sc) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (scene)");
    eo_params_default(eo_scene_opts_desc, &sc->opts);
    eo_params_default(eo_scene_mesh_opts_desc, &sc->mesh_opts);
    eo_params_default(eo_scene_generate_opts_desc, &sc->gen);
    eo_params_default(eo_scene_time_opts_desc, &sc->time);
    eo_params_default(eo_scene_output_opts_desc, &sc->output);
    eo_params_default(eo_scene_initial_opts_desc, &sc->initial);
    snprintf(sc->file, sizeof sc->file, "%s", eo_cfg_file(cfg));
    int rc;
    EO_TRY(rc = eo_cfg_section(ctx, cfg, "", eo_scene_opts_desc, &sc->opts, top));
    sc->lumped = strcmp(sc->opts.mass, "lumped") == 0;
    EO_TRY(rc = load_time(ctx, cfg, sc));
    eo_params_default(eo_scene_damping_opts_desc, &sc->damping);
    EO_TRY(rc = eo_cfg_section(ctx, cfg, "damping", eo_scene_damping_opts_desc, &sc->damping, NULL));
    if ((sc->damping.viscous > 0 || sc->damping.rayleigh_alpha > 0 || sc->damping.rayleigh_beta > 0) &&
        !sc->integrator->inertia) {
        rc = cfg_err(ctx, cfg, "damping", EO_ERR_INVALID, "damping needs an integrator with a velocity; %s has none",
                     sc->integrator->info.name);
        goto fail;
    }
    if (sc->time.load_steps > 0 && sc->integrator->inertia) {
        rc = cfg_err(ctx, cfg, "time.load_steps", EO_ERR_INVALID,
                     "time.load_steps ramps the load of a quasi-static (static) run; %s is dynamic",
                     sc->integrator->info.name);
        goto fail;
    }
    if (sc->time.adaptive && sc->integrator->explicit_step) {
        rc = cfg_err(ctx, cfg, "time.adaptive", EO_ERR_INVALID,
                     "adaptive stepping retries steps whose minimization did not converge; %s is explicit (no "
                     "minimization): reduce time.dt instead",
                     sc->integrator->info.name);
        goto fail;
    }
    EO_TRY(rc = eo_cfg_section(ctx, cfg, "output", eo_scene_output_opts_desc, &sc->output, NULL));
    EO_TRY(rc = load_mesh(ctx, cfg, sc));
    if (eo_ctx_dist(ctx)) EO_TRY(rc = distribute_mesh(ctx, cfg, sc));
    if (sc->mesh->nt < 1 && !sc->points) {
        rc = cfg_err(ctx, cfg, "mesh", EO_ERR_MESH, "the mesh has no tet");
        goto fail;
    }
    EO_TRY(rc = load_element(ctx, cfg, sc));
    EO_TRY(rc = load_materials(ctx, cfg, sc));
    for (int r = 0; r < sc->nmat && !(sc->element->flags & EO_ELEMENT_LINEAR); r++)
        if (sc->mat[r].type->flags & EO_MATERIAL_EDGE) {
            rc = cfg_err(ctx, cfg, "element", EO_ERR_INVALID,
                         "material %s (region %d) is an edge (spring) model, defined on the linear tet's edges only; "
                         "element %s needs a tet material",
                         sc->mat[r].type->info.name, r, sc->element->info.name);
            goto fail;
        }
    EO_TRY(rc = load_boundary(ctx, cfg, sc));
    EO_TRY(rc = load_initial(ctx, cfg, sc));
    EO_TRY(rc = load_point_masses(ctx, cfg, sc));
    EO_TRY(rc = load_springs(ctx, cfg, sc));
    EO_TRY(rc = load_collisions(ctx, cfg, sc));
    EO_TRY(rc = load_terms(ctx, cfg, sc));
    EO_TRY(rc = eo_scene_check_supports(ctx, cfg, sc));
    if (eo_ctx_dist(ctx)) EO_TRY(rc = check_distributed(ctx, cfg, sc));
    *out = sc;
    return EO_OK;
fail:
    eo_scene_destroy(&sc);
    return rc;
}

json_t *eo_scene_to_json(const eo_scene *sc)
{
    json_t *o = eo_params_to_json(eo_scene_opts_desc, &sc->opts);
    json_t *mesh = eo_params_to_json(eo_scene_mesh_opts_desc, &sc->mesh_opts);
    if (sc->generated) json_object_set_new(mesh, "generate", eo_params_to_json(eo_scene_generate_opts_desc, &sc->gen));
    if (sc->lattice) {
        json_t *l = eo_params_to_json(eo_scene_lattice_opts_desc, &sc->lat);
        json_object_set_new(l, "springs", json_pack("{s:i, s:i, s:i}", "structural", sc->lattice_count[0], "shear",
                                                    sc->lattice_count[1], "bending", sc->lattice_count[2]));
        json_object_set_new(mesh, "lattice", l);
    }
    json_object_set_new(mesh, "tetgen", eo_params_to_json(eo_scene_tetgen_opts_desc, &sc->tetgen));
    json_object_set_new(mesh, "vertices", json_integer(sc->mesh->nv));
    json_object_set_new(mesh, "tets", json_integer(sc->mesh->nt));
    json_object_set_new(o, "mesh", mesh);
    json_object_set_new(o, "material", eo_params_to_json(eo_material_opts_desc, &sc->mat[0].opts));
    json_t *mats = json_array();
    for (int r = 1; r < sc->nmat; r++) {
        json_t *e = eo_params_to_json(eo_material_opts_desc, &sc->mat[r].opts);
        int n = 0;
        for (int k = 0; k < sc->mesh->nt; k++) n += sc->tet_mat[k] == r;
        json_object_set_new(e, "tets", json_integer(n));
        json_array_append_new(mats, e);
    }
    json_object_set_new(o, "materials", mats);
    static const char *const sel[] = {"box", "plane", "marker", "tag", "surface", "nearest"};
    static const char *const mot[] = {"fixed", "translate", "rotate"};
    json_t *bcs = json_array();
    for (int b = 0; b < sc->nbc; b++) {
        const eo_bc *bc = sc->bc + b;
        json_t *e = eo_params_to_json(eo_scene_bc_opts_desc, &bc->opts);
        json_object_set_new(e, "select", json_string(sel[bc->select]));
        json_object_set_new(e, "motion", json_string(mot[bc->motion]));
        if (bc->select == EO_BC_BOX)
            json_object_set_new(e, "box", json_pack("[[fff][fff]]", bc->box[0], bc->box[1], bc->box[2], bc->box[3],
                                                    bc->box[4], bc->box[5]));
        if (bc->select == EO_BC_PLANE) json_object_set_new(e, "plane", eo_params_to_json(eo_scene_plane_opts_desc, &bc->plane));
        if (bc->motion == EO_BC_ROTATE)
            json_object_set_new(e, "rotate", eo_params_to_json(eo_scene_rotate_opts_desc, &bc->rotate));
        json_object_set_new(e, "vertices", json_integer(bc->nverts));
        json_array_append_new(bcs, e);
    }
    json_object_set_new(o, "boundary", bcs);
    json_t *ini = eo_params_to_json(eo_scene_initial_opts_desc, &sc->initial);
    if (sc->has_reflect) json_object_set_new(ini, "reflect", eo_params_to_json(eo_scene_plane_opts_desc, &sc->reflect));
    if (sc->has_ball) json_object_set_new(ini, "random_ball", eo_params_to_json(eo_scene_ball_opts_desc, &sc->ball));
    json_object_set_new(o, "initial", ini);
    json_t *spr = eo_params_to_json(eo_scene_springs_opts_desc, &sc->springs);
    json_object_set_new(spr, "count", json_integer(sc->nspring));
    json_object_set_new(o, "springs", spr);
    json_t *cols = json_array();
    for (int i = 0; i < sc->ncollision; i++) {
        const eo_scene_obstacle *ob = sc->collision + i;
        json_t *e = eo_params_to_json(eo_scene_collision_opts_desc, &ob->opts);
        json_object_set_new(e, ob->type->name, eo_params_to_json(ob->type->params, ob->shape));
        json_array_append_new(cols, e);
    }
    json_object_set_new(o, "collisions", cols);
    json_t *time = eo_params_to_json(eo_scene_time_opts_desc, &sc->time);
    if (sc->integrator_params && sc->integrator->info.params)
        json_object_set_new(time, sc->integrator->info.name,
                            eo_params_to_json(sc->integrator->info.params, sc->integrator_params));
    json_object_set_new(o, "time", time);
    json_object_set_new(o, "damping", eo_params_to_json(eo_scene_damping_opts_desc, &sc->damping));
    json_object_set_new(o, "output", eo_params_to_json(eo_scene_output_opts_desc, &sc->output));
    return o;
}

/* ---------------------------------------------------------------- description */

int eo_scene_up_guess(eo_ctx *ctx, const eo_scene *sc, eo_scene_up *up)
{
    const eo_mesh *m = sc->mesh;
    memset(up, 0, sizeof *up);
    up->axis = -1;
    if (m->nt < 1) return EO_OK;
    int *faces = NULL, nf = 0;
    int rc = eo_mesh_boundary_faces(ctx, m, &faces, &nf);
    if (rc < 0) return rc;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->X[3 * v + k]);
            hi[k] = fmax(hi[k], m->X[3 * v + k]);
        }
    const double cos20 = 0.93969262078590838 /* cos 20° */;
    double S[6] = {0}; /* side d = 2k + (sign > 0) */
    for (int f = 0; f < nf; f++) {
        const double *a = m->X + 3 * faces[3 * f], *b = m->X + 3 * faces[3 * f + 1], *c = m->X + 3 * faces[3 * f + 2];
        double u[3], w[3], n[3];
        for (int k = 0; k < 3; k++) {
            u[k] = b[k] - a[k];
            w[k] = c[k] - a[k];
        }
        n[0] = u[1] * w[2] - u[2] * w[1];
        n[1] = u[2] * w[0] - u[0] * w[2];
        n[2] = u[0] * w[1] - u[1] * w[0];
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(len > 0)) continue;
        for (int k = 0; k < 3; k++) {
            double cen = (a[k] + b[k] + c[k]) / 3, ext = hi[k] - lo[k];
            if (n[k] / len >= cos20 && hi[k] - cen <= 0.05 * ext) S[2 * k + 1] += 0.5 * len;
            if (-n[k] / len >= cos20 && cen - lo[k] <= 0.05 * ext) S[2 * k] += 0.5 * len;
        }
    }
    eo_free(ctx, faces);
    for (int d = 0; d < 6; d++) {
        int k = d / 2;
        double side = (hi[(k + 1) % 3] - lo[(k + 1) % 3]) * (hi[(k + 2) % 3] - lo[(k + 2) % 3]);
        S[d] = side > 0 ? S[d] / side : 0;
    }
    int best = 0;
    for (int d = 1; d < 6; d++)
        if (S[d] > S[best]) best = d;
    double second = 0;
    for (int d = 0; d < 6; d++)
        if (d != best) second = fmax(second, S[d]);
    up->support = S[best];
    up->ratio = second > 0 ? S[best] / second : INFINITY;
    if (!(S[best] >= 0.02 && S[best] >= 3 * second)) return EO_OK;
    up->axis = best / 2;
    up->sign = best % 2 ? 1 : -1;
    const double *g = sc->opts.gravity;
    double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    up->warn = gn > 0 && up->sign * g[up->axis] / gn < 0.70710678118654752 /* cos 45° */;
    return EO_OK;
}

typedef struct {
    eo_ctx *ctx;
    char *s;
    size_t n, cap;
    int nomem;
} textbuf;

static void tb_printf(textbuf *t, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void tb_printf(textbuf *t, const char *fmt, ...)
{
    if (t->nomem) return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int k = vsnprintf(t->s ? t->s + t->n : NULL, t->s ? t->cap - t->n : 0, fmt, ap);
        va_end(ap);
        if (k < 0) return;
        if (t->s && t->n + (size_t)k < t->cap) {
            t->n += (size_t)k;
            return;
        }
        size_t nc = (t->cap ? 2 * t->cap : 1024) + (size_t)k;
        char *q = eo_realloc(t->ctx, t->s, nc);
        if (!q) {
            t->nomem = 1;
            return;
        }
        t->s = q;
        t->cap = nc;
    }
}

/* Two boundary entries prescribe the same motion (then a shared vertex is harmless). */
static int same_motion(const eo_bc *a, const eo_bc *b)
{
    if (a->motion != b->motion || a->opts.release != b->opts.release || memcmp(a->mask, b->mask, sizeof a->mask))
        return 0;
    if (a->motion == EO_BC_FIXED) return 1;
    if (a->opts.until != b->opts.until) return 0;
    if (a->motion == EO_BC_TRANSLATE) return memcmp(a->opts.translate, b->opts.translate, sizeof a->opts.translate) == 0;
    return memcmp(a->rotate.axis, b->rotate.axis, sizeof a->rotate.axis) == 0 &&
           memcmp(a->rotate.center, b->rotate.center, sizeof a->rotate.center) == 0 && a->rotate.rate == b->rotate.rate;
}

/* A warning line per pair of boundary entries that share vertices but prescribe
 * different motions: the later entry wins on the shared vertices (eo_stepi_active_set). */
static int describe_overlaps(eo_ctx *ctx, const eo_scene *sc, textbuf *t)
{
    int nb = sc->nbc, nv = sc->mesh->nv;
    if (nb < 2) return EO_OK;
    int *owner = eo_malloc(ctx, (size_t)nv * sizeof *owner);
    int *cnt = eo_calloc(ctx, (size_t)nb * (size_t)nb, sizeof *cnt);
    if (!owner || !cnt) {
        eo_free(ctx, owner);
        eo_free(ctx, cnt);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (boundary overlaps)");
    }
    for (int v = 0; v < nv; v++) owner[v] = -1;
    for (int b = 0; b < nb; b++) {
        const eo_bc *bc = sc->bc + b;
        for (int i = 0; i < bc->nverts; i++) {
            int v = bc->verts[i], a = owner[v];
            if (a >= 0 && a != b) cnt[a * nb + b]++;
            owner[v] = b;
        }
    }
    for (int a = 0; a < nb; a++)
        for (int b = a + 1; b < nb; b++) {
            int n = cnt[a * nb + b];
            if (!n || same_motion(sc->bc + a, sc->bc + b)) continue;
            tb_printf(t,
                      "warning: boundary.%d and boundary.%d share %d vert%s but prescribe different motions; "
                      "on %s, boundary.%d (the later entry) applies while it is active\n",
                      a, b, n, n == 1 ? "ex" : "ices", n == 1 ? "it" : "them", b);
        }
    eo_free(ctx, owner);
    eo_free(ctx, cnt);
    return EO_OK;
}

int eo_scene_describe(eo_ctx *ctx, const eo_scene *sc, char **text)
{
    *text = NULL;
    int rc_overlap;
    const eo_mesh *m = sc->mesh;
    textbuf t = {.ctx = ctx};
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = v ? fmin(lo[k], m->X[3 * v + k]) : m->X[k];
            hi[k] = v ? fmax(hi[k], m->X[3 * v + k]) : m->X[k];
        }
    tb_printf(&t, "mesh: %s: %d vertices, %d tets, bbox [%g, %g, %g] - [%g, %g, %g]\n",
              sc->lattice ? "mesh.lattice" : sc->points ? "mesh.points" : sc->generated ? "mesh.generate" : sc->mesh_opts.file, m->nv, m->nt, lo[0],
              lo[1], lo[2], hi[0], hi[1], hi[2]);
    for (int r = 0; r < sc->nmat; r++) {
        int n = 0;
        for (int k = 0; k < m->nt; k++) n += sc->tet_mat[k] == r;
        char name[32];
        snprintf(name, sizeof name, r ? "materials.%d" : "material", r - 1);
        tb_printf(&t, "region %d (%s, %s): %d tets\n", r, name, sc->mat[r].opts.model, n);
    }
    static const char *const mot[] = {"fixed", "translate", "rotate"};
    static const char *const src[] = {"", "tagged triangles", "tets", "vertex markers"};
    for (int b = 0; b < sc->nbc; b++) {
        const eo_bc *bc = sc->bc + b;
        char sel[200];
        switch (bc->select) {
        case EO_BC_BOX:
            snprintf(sel, sizeof sel, "box [%g, %g, %g] - [%g, %g, %g]", bc->box[0], bc->box[1], bc->box[2], bc->box[3],
                     bc->box[4], bc->box[5]);
            break;
        case EO_BC_PLANE:
            snprintf(sel, sizeof sel, "plane through [%g, %g, %g], normal [%g, %g, %g]", bc->plane.point[0],
                     bc->plane.point[1], bc->plane.point[2], bc->plane.normal[0], bc->plane.normal[1],
                     bc->plane.normal[2]);
            break;
        case EO_BC_MARKER: snprintf(sel, sizeof sel, "marker %d", bc->opts.marker); break;
        case EO_BC_TAG: snprintf(sel, sizeof sel, "tag %d of the %s", bc->opts.tag, src[bc->tag_source]); break;
        case EO_BC_SURFACE: snprintf(sel, sizeof sel, "boundary surface"); break;
        case EO_BC_NEAREST: {
            int v = bc->verts[0];
            snprintf(sel, sizeof sel, "nearest [%g, %g, %g]: vertex %d at [%g, %g, %g], distance %.3g",
                     bc->opts.nearest[0], bc->opts.nearest[1], bc->opts.nearest[2], v, m->X[3 * v], m->X[3 * v + 1],
                     m->X[3 * v + 2], bc->nearest_dist);
            break;
        }
        }
        tb_printf(&t, "boundary.%d (%s; %s): %d vert%s\n", b, sel, mot[bc->motion], bc->nverts, bc->nverts == 1 ? "ex" : "ices");
    }
    rc_overlap = describe_overlaps(ctx, sc, &t);
    if (rc_overlap < 0) {
        eo_free(ctx, t.s);
        return rc_overlap;
    }
    eo_scene_up up;
    int rc = eo_scene_up_guess(ctx, sc, &up);
    if (rc < 0) {
        eo_free(ctx, t.s);
        return rc;
    }
    if (up.warn) {
        const double *g = sc->opts.gravity;
        double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        double sug[3] = {0, 0, 0};
        sug[up.axis] = up.sign * gn;
        tb_printf(&t,
                  "warning: gravity [%g, %g, %g] does not point down this mesh: it rests on a flat base facing %c%c "
                  "(%.0f%% of that bounding-box side, %.1fx any other side), so it looks %c-up; set gravity "
                  "[%g, %g, %g] (or rotate the mesh) if that is its up\n",
                  g[0], g[1], g[2], up.sign < 0 ? '-' : '+', "xyz"[up.axis], 100 * up.support, up.ratio,
                  "xyz"[up.axis], sug[0], sug[1], sug[2]);
    }
    if (t.nomem || !t.s) {
        eo_free(ctx, t.s);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (scene description)");
    }
    *text = t.s;
    return EO_OK;
}
