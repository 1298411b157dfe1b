/// @file scene.h
/// A scene: mesh, materials, mass, gravity, boundary conditions, initial state, time
/// stepping and output options — everything of a simulation except the solver, loaded
/// from a configuration document (config.h) or a built-in scene by name.
///
/// ```c
/// eo_cfg *cfg; eo_scene *sc;
/// rc = eo_scene_cfg_load(ctx, "examples/twist.json", NULL, &cfg);  // or (NULL, "twist")
/// rc = eo_cfg_override(ctx, cfg, "time.steps=10");
/// rc = eo_scene_load(ctx, cfg, &sc);      // every key but `solver`
/// ... load the solver from cfg (solver.h), then eo_cfg_finish(ctx, cfg) ...
/// printf("%d tets, %d steps of %g s\n", sc->mesh->nt, sc->time.steps, sc->time.dt);
/// eo_scene_destroy(&sc); eo_cfg_destroy(&cfg);
/// ```
/// Ownership: the scene owns its mesh, material and boundary arrays; it borrows
/// nothing from the cfg after eo_scene_load returns.
///
/// Config keys (top level; `elastopt help` prints the tables with defaults):
///   description        free text, ignored
///   mesh.file | mesh.generate.{size, cells, split, origin} | mesh.points |
///   mesh.lattice.{cells, size, origin, mass, structural_k, shear_k, bending_k},
///   mesh.drop_degenerate, mesh.tetgen.{quality, max_volume}
///                      a relative mesh.file is resolved against the config's folder;
///                      it is a volume mesh (.node/.ele, .mesh, .msh, .vtu) or a closed
///                      surface (.obj, .off, .stl, .ply) tetrahedralized by TetGen with
///                      mesh.tetgen (radius-edge bound `quality`, default 2, 0 = none;
///                      `max_volume` m³, 0 = none; a build without TetGen fails naming
///                      the meson option -Dtetgen);
///                      mesh.points [[x,y,z], ...] is a point cloud without tets (a pure
///                      mass-spring system: mass from point_mass/point_masses, forces
///                      from springs, gravity, collisions)
///   material.*         eo_material_opts_desc (model, E, nu, density, k)
///   materials          list of per-region materials: each entry selects tets by
///                      "attribute": k (mesh tet attribute) or "box": [[x0,y0,z0],[x1,y1,z1]]
///                      (tet centroid inside) and has the keys of `material`, whose values
///                      it inherits; the last matching entry wins
///   mass               "consistent" (ρV/10, ρV/20 per tet) | "lumped" (ρV/4 per vertex)
///   point_mass         kg added to EVERY vertex (lumped; on the diagonal of a consistent
///                      mass too); point_masses [[vertex, kg], ...] adds to single vertices
///   springs            {"edges": "none" | "mesh" | "list", "k", "damping", "list": [[i,j],
///                      ...]}: scene springs (001 §2) on every unique tet edge ("mesh") or
///                      between listed vertex pairs, rest length from the rest positions,
///                      on top of the tet elasticity of the materials. A region with
///                      material.model = "spring" instead has NO tet elasticity and
///                      springs (material.k) on its tet edges: "springs only". damping c
///                      (N·s/m along each scene spring) acts in explicit integrators only
///   collisions         list of static obstacles, each exactly one shape: "plane":
///                      {"point", "normal"} (half-space), "sphere": {"center", "radius"}
///                      (solid ball), "box": {"min", "max"} (solid axis-aligned box); with
///                      "stiffness": k (penalty k/2·max(0, d)² per vertex, d the depth, N/m
///                      per vertex, not mass-weighted), "friction": μ (Coulomb, 0 = none;
///                      implicit integrators) and "eps_v" (m/s, the friction smoothing
///                      velocity)
///   gravity            3-vector, m/s², default [0, 0, -9.81]
///   boundary           list; each entry selects rest vertices by exactly one of
///                      "box": [[lo],[hi]] (inside, inclusive, with a tolerance of 1e-9
///                      of the mesh size), "plane": {"point", "normal"} (on the side the
///                      normal points to, (X − p)·n ≥ −tol), "marker": k (vertex marker),
///                      "tag": k (the vertices of the mesh's tagged triangles with tag k
///                      — Gmsh physical surface, MEDIT triangle reference, TetGen .face
///                      marker —; if no triangle has tag k, of the tets with attribute k
///                      — Gmsh physical volume, MEDIT tet reference, TetGen region —; if
///                      none, the vertices with marker k; an absent tag is an error
///                      listing the tags the mesh has), "surface": true (every vertex
///                      of the boundary surface: faces used by one tet), "nearest":
///                      [x,y,z] (the single rest vertex nearest to the point; ties: the
///                      lowest index),
///                      and prescribes their motion: "fixed": true | "translate": velocity
///                      (position x₀ + t·v) | "rotate": {"axis", "center", "rate"} (angle
///                      rate·t about the axis through center); optional "until": t (the
///                      motion stops, the set stays where it is) and "release": t (after
///                      it the set is free). Later entries override earlier ones.
///   initial            {"scale": [sx,sy,sz], "velocity": [vx,vy,vz],
///                       "reflect": {"point", "normal"}, "random_ball": {"radius", "seed"}}
///                      applied to the rest positions in the order scale, reflect,
///                      random_ball; velocity is the uniform initial velocity
///   damping.{viscous, rayleigh_alpha, rayleigh_beta}
///                      damping force −C v, C = γI + αM + βK₀ (eo_scene_damping_opts)
///   time.integrator, time.dt, time.steps, time.load_steps, time.adaptive (+ _min_fraction,
///   _grow_after)
///   output.dir, output.every, output.vtu, output.summary_every
///   solver.*           the solver's section (solver.h), loaded by the caller
#ifndef ELASTOPT_SCENE_H
#define ELASTOPT_SCENE_H

#include "export.h"
#include "config.h"
#include "material.h"
#include "mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

struct eo_integrator_type;

/// Top-level scalar keys.
typedef struct eo_scene_opts {
    char description[256];  ///< free text. Default "".
    char mass[16];          ///< "consistent" | "lumped". Default "consistent".
    double gravity[3];      ///< m/s². Default [0, 0, -9.81].
    double point_mass;      ///< kg added to every vertex, >= 0. Default 0.
    char element[32];       ///< finite element (registered name, element.h): "p1" (linear
                            ///< tet) or "p2" (10-node tet; a linear mesh gets midside nodes
                            ///< at load). Default "p1".
} eo_scene_opts;

/// `springs` section (scalar part; the pairs are `springs.list`).
typedef struct eo_scene_springs_opts {
    char edges[16];         ///< "none" | "mesh" (every unique tet edge) | "list". Default "none".
    double k;               ///< stiffness, N/m, > 0. Default 1000.
    double damping;         ///< c along each spring, N·s/m, >= 0 (explicit integrators). Default 0.
} eo_scene_springs_opts;

/// Scalar keys of one `collisions` entry (its shape is `collisions.N.plane`, `.sphere`
/// or `.box`).
typedef struct eo_scene_collision_opts {
    double stiffness;       ///< penalty stiffness k per vertex, N/m, > 0. Default 1e5.
    double friction;        ///< Coulomb coefficient μ, >= 0; 0 = frictionless. Default 0.
    double eps_v;           ///< friction smoothing velocity ε_v, m/s, > 0: below it the friction
                            ///< force grows smoothly from 0 (static friction is approximated by
                            ///< creep slower than ε_v). Default 1e-3.
} eo_scene_collision_opts;

/// Largest number of doubles of an obstacle shape's parameters.
#define EO_OBSTACLE_PARAMS 12

/// One `collisions` entry: a static obstacle shape with its penalty and friction.
typedef struct eo_scene_obstacle {
    const struct eo_obstacle_type *type;   ///< the shape (problems/obstacle.h): plane, sphere, box
    double shape[EO_OBSTACLE_PARAMS];      ///< its section's values (e.g. plane: point, unit normal)
    eo_scene_collision_opts opts;          ///< stiffness, friction, eps_v
} eo_scene_obstacle;

/// `mesh` section.
typedef struct eo_scene_mesh_opts {
    char file[512];         ///< mesh file (TetGen, MEDIT, Gmsh). Default "" (generate).
    int drop_degenerate;    ///< drop zero-volume/duplicate tets with a warning. Default false.
} eo_scene_mesh_opts;

/// `mesh.lattice` section: a generated mass-spring lattice (cloth when one axis has 0
/// cells): (nx+1)(ny+1)(nz+1) point masses on a grid, vertex i + (nx+1)(j + (ny+1)k) at
/// origin + (i sx/nx, j sy/ny, k sz/nz), no tets. Springs (rest length = the grid
/// distance), each kind off when its k is 0:
///   structural  between grid neighbours along each axis,
///       count Σ_a n_a Π_{b≠a}(n_b+1)          (2D nx×ny: nx(ny+1) + ny(nx+1));
///   shear       both diagonals of every grid square (cell face),
///       count 2 Σ_{a<b} n_a n_b Π_{c≠a,b}(n_c+1)  (2D: 2 nx ny);
///   bending     between grid points two apart along each axis (skip one),
///       count Σ_a max(n_a−1, 0) Π_{b≠a}(n_b+1)   (2D: (nx−1)(ny+1) + (ny−1)(nx+1)).
/// `mass` is spread over the cells (segments, squares or cubes) evenly, each cell's share
/// equally over its corners. On a square grid the sheet's effective stiffness does not
/// change under refinement (n springs in series, n+1 in parallel).
typedef struct eo_scene_lattice_opts {
    double cells[3];        ///< cells per axis (integers >= 0; 0 = flat along that axis). Default [10, 10, 0].
    double size[3];         ///< extent per axis, m (> 0 where cells > 0, else ignored). Default [1, 1, 0].
    double origin[3];       ///< position of vertex 0, m. Default [0, 0, 0].
    double mass;            ///< total mass, kg, > 0. Default 1.
    double structural_k;    ///< N/m, >= 0 (0 = none). Default 1000.
    double shear_k;         ///< N/m, >= 0 (0 = none). Default 1000.
    double bending_k;       ///< N/m, >= 0 (0 = none). Default 100.
} eo_scene_lattice_opts;

/// `mesh.tetgen` section: tetrahedralization of a surface mesh file.
typedef struct eo_scene_tetgen_opts {
    double quality;         ///< radius-edge ratio bound (TetGen -q), 0 = none, else >= 1. Default 2.
    double max_volume;      ///< tet volume bound (TetGen -a), m³, 0 = none. Default 0.
} eo_scene_tetgen_opts;

/// `mesh.generate` section (a box of hexahedral cells split into tets).
typedef struct eo_scene_generate_opts {
    double size[3];         ///< m. Default [1, 0.1, 0.1].
    double cells[3];        ///< cells per axis (integers >= 1). Default [20, 2, 2].
    int split;              ///< 5 or 6 tets per cell. Default 5: the alternating 5-tet split
                            ///< is mirror symmetric; the 6-tet split along one diagonal
                            ///< makes a bar bent in z also bend in y (measured: tip com
                            ///< drifts 5 mm sideways on the 20×2×2 cantilever).
    double origin[3];       ///< minimum corner, m. Default [0, 0, 0].
    char shape[8];          ///< "box" (default) | "cook": the box mapped onto Cook's tapered
                            ///< panel (eo_mesh_map_cook), size[0..1] its x and left-edge y extent
} eo_scene_generate_opts;

/// `time` section.
typedef struct eo_scene_time_opts {
    char integrator[32];    ///< a registered integrator (newmark, implicit_midpoint,
                            ///< generalized_alpha, backward_euler, bdf2, static, explicit
                            ///< ones); its parameters, if any, in time.<name> (e.g.
                            ///< time.generalized_alpha.rho_inf). Default "newmark".
    double dt;              ///< step, s; > 0. Default 0.01.
    int steps;              ///< number of steps, >= 1. Default 30.
    int load_steps;         ///< static only: gravity and prescribed motions ramp linearly over
                            ///< this many steps (step k applies k/load_steps of the load; then
                            ///< the full load), 0 = full load from the first step. Default 0.
    /// Adaptive stepping (eo_sim_step, sim.h; implicit integrators only: an explicit one
    /// with adaptive on is a config error). A step that does not converge after the
    /// solver.fallback chain is retried as two half steps, recursively, down to
    /// adaptive_min_fraction·dt; the substep size doubles again after adaptive_grow_after
    /// consecutive converged substeps, never beyond dt and never past the end of the
    /// nominal step (steps end at t = n·dt as without adaptive stepping).
    int adaptive;           ///< Default false.
    double adaptive_min_fraction;  ///< smallest substep / dt, in (0, 1]; rounded down to a power
                            ///< of two, at least 2^-30. Default 1/64 (0.015625).
    int adaptive_grow_after;       ///< converged substeps in a row before the size doubles, >= 1. Default 2.
} eo_scene_time_opts;

/// `damping` section (001 §2.1–2.2): damping force −C v with
/// C = viscous·I + rayleigh_alpha·M + rayleigh_beta·K₀ (K₀: the clamped elastic Hessian
/// at the start of each step). Explicit integrators: a = M⁻¹(f − C v); implicit ones: a
/// term of the step problem (problems/term_damping.c). Not with `static` (no velocity).
typedef struct eo_scene_damping_opts {
    double viscous;         ///< γ, N·s/m on every vertex coordinate (a = (f − γv)/m), >= 0. Default 0.
    double rayleigh_alpha;  ///< α, 1/s: mass-proportional part, >= 0. Default 0.
    double rayleigh_beta;   ///< β, s: stiffness-proportional part, >= 0. Default 0.
} eo_scene_damping_opts;

/// `output` section.
typedef struct eo_scene_output_opts {
    char dir[512];          ///< output folder; "" = out/<scene name>. Default "".
    int every;              ///< write a VTU frame every k steps, 0 = none. Default 1.
    int vtu;                ///< write VTU frames and the .pvd. Default true.
    int summary_every;      ///< rewrite summary.json every k steps (and at the end), 0 =
                            ///< only at the end. Default 10.
} eo_scene_output_opts;

/// `initial` section (scalar part).
typedef struct eo_scene_initial_opts {
    double scale[3];        ///< per-axis scale about the rest centroid. Default [1, 1, 1].
    double velocity[3];     ///< uniform initial velocity, m/s. Default [0, 0, 0].
} eo_scene_initial_opts;

/// A plane {point, normal} (`initial.reflect`, `boundary.N.plane`).
typedef struct eo_scene_plane_opts {
    double point[3];        ///< Default [0, 0, 0].
    double normal[3];       ///< non-zero. Default [1, 0, 0].
} eo_scene_plane_opts;

/// `initial.random_ball`.
typedef struct eo_scene_ball_opts {
    double radius;          ///< m, > 0. Default 1.
    int seed;               ///< random seed. Default 1.
} eo_scene_ball_opts;

/// Scalar keys of one `boundary` entry.
typedef struct eo_scene_bc_opts {
    int marker;             ///< vertex marker selector, -1 = not used. Default -1.
    int tag;                ///< tag selector (used when the entry has "tag"). Default 0.
    int surface;            ///< select the boundary-surface vertices (must be true if given). Default false.
    double nearest[3];      ///< select the rest vertex nearest this point (used when given), m. Default [0, 0, 0].
    int fixed;              ///< fixed at the initial position. Default false.
    double translate[3];    ///< velocity of a translation, m/s. Default [0, 0, 0].
    double until;           ///< motion stops at this time, s; < 0 = never. Default -1.
    double release;         ///< set becomes free after this time, s; < 0 = never. Default -1.
    char components[4];     ///< the displacement components the entry prescribes: a
                            ///< non-empty subset of "xyz" (e.g. "z": u_z held, u_x, u_y
                            ///< free; a plane-strain slab). Where entries overlap, the
                            ///< later one decides a vertex. Default "xyz".
} eo_scene_bc_opts;

/// `boundary.N.rotate`.
typedef struct eo_scene_rotate_opts {
    double axis[3];         ///< rotation axis (normalized on load). Default [1, 0, 0].
    double center[3];       ///< a point on the axis, m. Default [0, 0, 0].
    double rate;            ///< angular velocity, rad/s. Default 0.
} eo_scene_rotate_opts;

EO_API extern const eo_param_desc eo_scene_opts_desc[];
EO_API extern const eo_param_desc eo_scene_mesh_opts_desc[];
EO_API extern const eo_param_desc eo_scene_generate_opts_desc[];
EO_API extern const eo_param_desc eo_scene_tetgen_opts_desc[];
EO_API extern const eo_param_desc eo_scene_lattice_opts_desc[];
EO_API extern const eo_param_desc eo_scene_time_opts_desc[];
EO_API extern const eo_param_desc eo_scene_output_opts_desc[];
EO_API extern const eo_param_desc eo_scene_initial_opts_desc[];
EO_API extern const eo_param_desc eo_scene_plane_opts_desc[];
EO_API extern const eo_param_desc eo_scene_ball_opts_desc[];
EO_API extern const eo_param_desc eo_scene_bc_opts_desc[];
EO_API extern const eo_param_desc eo_scene_rotate_opts_desc[];
EO_API extern const eo_param_desc eo_scene_springs_opts_desc[];
EO_API extern const eo_param_desc eo_scene_collision_opts_desc[];
EO_API extern const eo_param_desc eo_scene_damping_opts_desc[];
/// The scene's documented sections ({NULL} terminated), for `elastopt help`.
EO_API extern const eo_cfg_doc eo_scene_docs[];
/// Every fixed section of a scene configuration: the scene's, `material` and `solver`,
/// terminated by a {NULL} entry (method parameter sections come from the registries).
EO_API const eo_cfg_doc *eo_config_docs(void);
/// The keys of a scene the loader reads itself (not params sections), {NULL}-terminated.
EO_API const eo_cfg_raw_doc *eo_config_raw_docs(void);
/// JSON Schema (draft 2020-12) of a scene document, generated from eo_config_docs and
/// the registries (docs/scene.schema.json is its output). New reference.
EO_API json_t *eo_config_schema(void);
/// JSON Schema (draft 2020-12) of any documented tree: params sections `docs` and raw
/// keys `raw` (either may be NULL), dotted paths with "N" for list items, every object
/// closed (additionalProperties false). eo_config_schema and the suite schema use it.
EO_API json_t *eo_cfg_docs_schema(const eo_cfg_doc *docs, const eo_cfg_raw_doc *raw, const char *title,
                                  const char *description);

typedef enum eo_bc_select { EO_BC_BOX, EO_BC_PLANE, EO_BC_MARKER, EO_BC_TAG, EO_BC_SURFACE, EO_BC_NEAREST } eo_bc_select;
/// Where a `tag` selector found its tag.
typedef enum eo_bc_tag_source { EO_TAG_NONE, EO_TAG_TRIANGLES, EO_TAG_TETS, EO_TAG_VERTICES } eo_bc_tag_source;
typedef enum eo_bc_motion { EO_BC_FIXED, EO_BC_TRANSLATE, EO_BC_ROTATE } eo_bc_motion;

/// One boundary condition with its selected vertices.
typedef struct eo_bc {
    eo_bc_select select;
    eo_bc_motion motion;
    double box[6];          ///< lo xyz, hi xyz (EO_BC_BOX)
    eo_scene_plane_opts plane;  ///< EO_BC_PLANE (normal normalized)
    eo_scene_bc_opts opts;  ///< marker, translate, until, release
    eo_scene_rotate_opts rotate;  ///< EO_BC_ROTATE (axis normalized)
    int nverts;             ///< selected vertices (>= 1)
    int *verts;             ///< owned
    eo_bc_tag_source tag_source;  ///< EO_BC_TAG: triangles, tets or vertex markers
    double nearest_dist;    ///< EO_BC_NEAREST: distance of the selected vertex, m
    unsigned char mask[3];  ///< the displacement components the entry prescribes (opts.components)
    int partial;            ///< 1 if not all three (the others stay free)
} eo_bc;

/// One material region.
typedef struct eo_scene_material {
    eo_material_opts opts;
    const eo_material_type *type;
    eo_material_coef coef;
} eo_scene_material;

typedef struct eo_scene {
    eo_scene_opts opts;
    eo_scene_mesh_opts mesh_opts;
    eo_scene_generate_opts gen;
    eo_scene_tetgen_opts tetgen;       ///< mesh.tetgen (used for surface mesh files)
    int generated;                     ///< 1 if the mesh was generated
    int points;                        ///< 1 if the mesh is mesh.points or mesh.lattice (vertices, no tets)
    int lattice;                       ///< 1 if the mesh is mesh.lattice
    eo_scene_lattice_opts lat;         ///< mesh.lattice (when lattice)
    int lattice_count[3];              ///< structural, shear, bending springs of the lattice
    eo_mesh *mesh;                     ///< owned
    int lumped;                        ///< 1: lumped mass
    int nmat;                          ///< regions (>= 1); region 0 is `material`
    eo_scene_material *mat;            ///< owned, nmat
    int *tet_mat;                      ///< owned, nt: region of each tet
    int nbc;
    eo_bc *bc;                         ///< owned, nbc
    eo_scene_initial_opts initial;
    int has_reflect, has_ball;
    eo_scene_plane_opts reflect;
    eo_scene_ball_opts ball;
    eo_scene_time_opts time;
    const struct eo_integrator_type *integrator;
    eo_scene_output_opts output;
    double *pmass;                     ///< owned, nv point masses (NULL if none)
    eo_scene_springs_opts springs;
    int nspring;                       ///< scene springs (0 if edges = "none")
    int *spring_ab;                    ///< owned, 2·nspring vertex pairs (a < b, unique)
    double *spring_k;                  ///< owned, nspring stiffnesses (a lattice), NULL: springs.k for all
    int ncollision;
    eo_scene_damping_opts damping;     ///< `damping` section
    eo_scene_obstacle *collision;      ///< owned, ncollision obstacles (`collisions`)
    char file[512];                    ///< config file ("<builtin>" if none)
    eo_ctx *ctx;                       ///< context it was created with (its destroy uses it)
    void *integrator_params;           ///< owned: the integrator's params struct (its info.params,
                                       ///< section time.<integrator>), NULL if it has none
    const struct eo_element_type *element; ///< the element (opts.element); the mesh has its
                                       ///< node layout (order 2 for 10-node elements)
    /* the sections of registered term kinds (impl/term.h eo_term_type.section) the scene
     * has: nterm_cfg of them, their kinds and what each kind's load made */
    int nterm_cfg;
    const struct eo_term_type **term_type; ///< owned array (the kinds are borrowed), nterm_cfg
    void **term_cfg;                   ///< owned (each freed by its kind's free_cfg), nterm_cfg
} eo_scene;

/// Memory an implicit simulation needs per tet, bytes (mesh, step engine, Hessian pattern
/// and values, factor fill at moderate sizes): a lower estimate used to refuse generated
/// boxes that cannot be simulated on this machine (key mesh.generate.cells).
#define EO_SCENE_BYTES_PER_TET 1500.0

/// Load a configuration document: `path` if not NULL, else the built-in scene `name`
/// (NULL: "cantilever", the default). EO_ERR_UNKNOWN_NAME lists the built-in scenes.
EO_API int eo_scene_cfg_load(eo_ctx *ctx, const char *path, const char *name, eo_cfg **out);
/// Read every scene key of cfg (all but `solver`, which is declared valid at the top
/// level), build or read the mesh, select boundary vertices, check everything.
/// Errors name the file with the line of the key (or the -o override): unknown keys,
/// wrong types, ranges, a boundary entry selecting no vertex, mesh problems.
EO_API int eo_scene_load(eo_ctx *ctx, eo_cfg *cfg, eo_scene **out);
EO_API void eo_scene_destroy(eo_scene **sc);
/// The resolved options (every section with its defaults filled in) as a new JSON object.
EO_API json_t *eo_scene_to_json(const eo_scene *sc);

/// Up-axis guess of a scene's mesh (see eo_scene_describe).
typedef struct eo_scene_up {
    int axis;               ///< axis (0..2) of the flat base, -1 if no obvious one
    int sign;               ///< -1 or +1: the base's outward normal is sign·e_axis ("down")
    double support;         ///< base area / bounding-box side area, of the base side
    double ratio;           ///< support of the base side / largest support of the other 5 sides
    int warn;               ///< 1: gravity is more than 45° away from the down direction
} eo_scene_up;

/// Guess where "down" is for the scene's mesh and whether gravity disagrees.
/// Heuristic: for each of the 6 bounding-box sides ±e_k, the support S is the area of
/// the boundary faces whose outward normal is within 20° of ±e_k and whose centroid is
/// within 5% of the box extent from that side, divided by the area of the side. The
/// side with the largest S is an obvious base when S >= 0.02 and S >= 3 × the S of
/// every other side (a box has 6 equal sides: no base; the IPC bunny: S = 0.26 on −y,
/// 5.4 × any other). Then warn when gravity is non-zero and more than 45° from the
/// base's outward normal (e.g. a y-up mesh with gravity −z). Meshes without tets are
/// not checked (axis -1). EO_ERR_NOMEM.
EO_API int eo_scene_up_guess(eo_ctx *ctx, const eo_scene *sc, eo_scene_up *up);

/// Describe the loaded scene as text (allocated through ctx, eo_free it), one line
/// each: the mesh (source, vertices, tets, bounding box), every material region with
/// its tet count, every boundary entry with its selector, motion and vertex count, and
/// lines starting "warning: " (gravity against the mesh's obvious up, see
/// eo_scene_up_guess). EO_ERR_NOMEM.
EO_API int eo_scene_describe(eo_ctx *ctx, const eo_scene *sc, char **text);

/// Relative tolerance of the rigid-mode ranks (eo_scene_rigid_modes): an eigenvalue of a
/// 6×6 Gram matrix below EO_RIGID_RTOL × its largest counts as zero (constrained vertices
/// off a common line by less than about 1e-5 of the body's size count as collinear).
#define EO_RIGID_RTOL 1e-10

/// Rigid-body modes left free by a set of constrained vertices (eo_scene_rigid_modes).
typedef struct eo_rigid_modes {
    int n_components;       ///< bodies: connected components of the vertices (tets and springs join them)
    int n_free;             ///< free rigid modes summed over every body
    int n_free_components;  ///< bodies with at least one free mode
    int n_unheld;           ///< free modes that gravity does not hold either (see eo_scene_rigid_modes)
    int worst;              ///< the body (0-based, numbered by lowest vertex) with the most unheld, then
                            ///< free, modes; -1 if none is free
    int worst_free;         ///< its free modes (0..6)
    int worst_unheld;       ///< its free modes gravity does not hold (0..worst_free)
    int worst_vertices;     ///< its vertex count
    int worst_first_vertex; ///< its lowest vertex index
    char modes[320];        ///< its free modes named, e.g. "translations x, y, z; rotations about x, y, z"
    char held[160];         ///< what gravity does to them, e.g. "gravity holds it (the body hangs below
                            ///< the line)"; "" for a body without constrained vertex (never held)
} eo_rigid_modes;

/// Count the rigid-body modes (infinitesimal translations and rotations of a body) that
/// the constrained vertices leave free, per body (connected component of the rest mesh:
/// tets and scene/lattice springs join vertices). Mathematics: problems/rigid_modes.c
/// (rank of the 6×6 Gram matrix of the modes restricted to the constrained vertices, with
/// EO_RIGID_RTOL). constrained: nv flags (1 = prescribed position), NULL = none. Free
/// modes per body: 6 with no constrained vertex, 3 rotations if they all sit at one point,
/// 1 rotation about their line if they are collinear, else 0. Gravity (sc->opts.gravity)
/// holds some of them at the equilibrium it leads to: a body hanging from one point keeps
/// only the rotation about the vertical through it free (a collinear body, a chain: none),
/// a body on a hinge line is held unless the line is vertical; neither if g = 0 or the
/// centroid is on the point or line; a body without constrained vertex never. A scene with
/// the `static` integrator is refused at eo_scene_load when a body has a free mode that
/// gravity does not hold (n_unheld > 0: the step Hessian is singular at every candidate
/// equilibrium); collision obstacles are not supports. EO_OK, EO_ERR_NOMEM.
EO_API int eo_scene_rigid_modes(eo_ctx *ctx, const eo_scene *sc, const unsigned char *constrained,
                                eo_rigid_modes *out);

/// A built-in scene: the registry (EO_KIND_SCENE) entry, JSON text identical in
/// meaning to examples/<name>.json.
typedef struct eo_scene_type {
    eo_method_info info;
    const char *json;
} eo_scene_type;

#ifdef __cplusplus
}
#endif
#endif
