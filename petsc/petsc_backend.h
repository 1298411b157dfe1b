/* The PETSc / MPI backend (private to petsc/): a plug-in module (elastopt_petsc.so, loaded
 * by the CLI with its own symbol scope, docs/petsc.md) that lets the library's own
 * optimizers run the step problem of eo_sim distributed over the ranks of PETSC_COMM_WORLD
 * (solver.backend=petsc), and registers
 *
 *   petsc_ksp           the linear solver of those runs (ksp.c): the ranks' Hessian parts
 *                       assembled into an MPIAIJ, KSP (MUMPS, CG + GAMG, BoomerAMG, ...),
 *                       or pc = cholmod (the whole matrix on rank 0, the library's CHOLMOD)
 *   snes_newtonls, snes_newtontr      PETSc SNES on ∇g = 0 with g as the line-search merit
 *   tao_nls, tao_ntr, tao_lmvm, tao_bqnls   PETSc TAO on min g
 *
 * Under mpirun with several ranks the scene's mesh is distributed with DMPlex (dmplex.c):
 * each rank runs eo_sim on its local mesh (its tets and their vertices), whose element
 * sums (energies, masses, gravity) add up to the whole problem; the library's decisions
 * over the whole mesh are reduced through the context's distribution hooks
 * (eo_ctx_set_dist), whose `space` hook (space.c) numbers the free coordinates over the
 * ranks for the library's distributed objective view (solvers/dist_objective.c). The SNES
 * and TAO optimizers sum the ranks' local g, ∇g and Hessians into distributed Vecs and an
 * MPIAIJ matrix themselves (dist.c). On one rank (an MPI singleton) the whole step engine
 * is the rank's part. */
#ifndef EO_PETSC_BACKEND_H
#define EO_PETSC_BACKEND_H

#include <petscdmplex.h>
#include <petscksp.h>
#include <petscsf.h>

#include "elastopt/impl/method.h"
#include "elastopt/step.h"

/* Parameters of petsc_ksp and of every PETSc optimizer (config section solver.<name>). */
typedef struct eo_petsc_params {
    char ksp[16];          /* preonly | cg | minres | gmres (default preonly) */
    char pc[16];           /* mumps | gamg | hypre | bjacobi_icc | jacobi (default mumps) */
    double rtol;           /* KSP relative tolerance for iterative solves (default 1e-10) */
    int max_lin_iters;     /* KSP iteration cap (default 10000) */
    char options[256];     /* PETSc options for experts, e.g. "-ksp_monitor" (default "") */
} eo_petsc_params;
extern const eo_param_desc eo_petsc_params_desc[];

/* The distributed mesh of a run under mpirun with several ranks (dmplex.c): each rank's
 * local mesh (its tets and their vertices) is the mesh of its eo_sim and step engine. */
typedef struct eo_petsc_layout {
    int active;
    int nv, nt;                 /* local vertices, tets */
    int nv_global, nt_global;
    int nown;                   /* owned local vertices */
    PetscInt *gid;              /* nv: input (global) vertex number */
    unsigned char *owned;       /* nv: 1 = this rank owns the vertex */
    PetscSF vsf;                /* roots: local vertices; leaves: ghosts -> owner's local vertex */
} eo_petsc_layout;
/* The layout of the distributed run, NULL if none (one rank, or a mesh not distributed). */
const eo_petsc_layout *eo_petsc_layout_get(void);
/* Under MPI with more than one rank: the context's mesh source (file read on rank 0 only)
 * and distribution hooks (eo_ctx_set_dist: DMPlex distribution, reductions). */
void eo_petsc_dist_install(eo_ctx *ctx);
const char *eo_petsc_mesh_note(void);
/* A per-vertex array (width doubles per local vertex) gathered to rank 0 in the input
 * vertex order (collective; 0 or -1). */
int eo_petsc_gather_vertices(const double *local, int width, double *out);

/* The distributed problem behind one optimizer instance: the local step engine of the
 * rank (a local mesh) or, on one rank, the whole one; global numbering of the free
 * coordinates (owned vertices' coordinates are rows [rstart, rstart + nown)), vectors,
 * the Hessian (MPIAIJ assembled from each rank's local Hessian by COO with summed
 * duplicates). Rebuilt when the step engine or its pattern (free set) changes on any rank. */
typedef struct eo_dist {
    eo_ctx *ctx;
    MPI_Comm comm;
    int rank, size;
    eo_step *st;                /* the step engine it was built for */
    unsigned long pattern;      /* eo_step_pattern_id it was numbered for */
    int have_pattern;
    const eo_petsc_params *params;  /* of the running minimization (borrowed) */
    int n;                      /* local free coordinates (the objective's n) */
    int nglobal;                /* global free coordinates */
    int nown, rstart;           /* owned rows, first global row */
    PetscInt *lglob;            /* n: local free index -> global row */
    double *grep;               /* n: local gradient */
    Vec xl;                     /* sequential, n: the local free coordinates */
    VecScatter to_local;        /* global -> xl (reverse: sum onto the owners) */
    PetscCount ncoo;            /* Hessian entries of the local CSC, both triangles */
    PetscScalar *coo_v;
    Mat A;
    Vec coords;                 /* rest coordinates of the owned rows (GAMG rigid-body modes) */
    MatNullSpace rbm;
    long n_value, n_gradient, n_hessian;
    unsigned long gen;          /* numberings made (vectors of an older one are stale) */
} eo_dist;

/* Build or update for the objective obj (a step objective; EO_ERR_UNSUPPORTED else). */
int eo_dist_setup(eo_dist *d, eo_ctx *ctx, eo_objective *obj, const eo_petsc_params *p);
void eo_dist_destroy(eo_dist *d);
/* Vectors laid out like the distributed free coordinates. */
int eo_dist_vec(eo_dist *d, Vec *v);
/* X <- x (the local free coordinates; each rank sets its owned rows); x <- X (every local
 * coordinate, ghosts included, from its owner). */
int eo_dist_from_rep(eo_dist *d, const double *x, Vec X);
int eo_dist_to_rep(eo_dist *d, Vec X, double *x);
/* g(X) (summed over the ranks; +INF where undefined); with G: ∇g(X). */
int eo_dist_value(eo_dist *d, eo_objective *obj, Vec X, double *g);
int eo_dist_gradient(eo_dist *d, eo_objective *obj, Vec X, double *g, Vec G);
/* d->A = ∇²g(X) with per-element projection proj (assembled). */
int eo_dist_hessian(eo_dist *d, eo_objective *obj, Vec X, eo_proj proj);
/* Inverted tets at X over all ranks. */
int eo_dist_inverted(eo_dist *d, eo_objective *obj, Vec X);
/* Sum of v over the ranks. */
double eo_dist_sum(eo_dist *d, double v);
/* V <- the parts' values v (local free coordinates) summed onto their owners (as the
 * gradient: a lumped mass diagonal becomes the whole body's). */
int eo_dist_sum_rep(eo_dist *d, const double *v, Vec V);

/* A MATAIJ (block size 3 where every rank's rows allow it, symmetric) preallocated for the
 * COO entries of both triangles of the part's upper-triangle CSC H in global numbering glob
 * (duplicates of shared vertices summed by MatSetValuesCOO); *ncoo entries (collective). */
int eo_petsc_coo_mat(eo_ctx *ctx, MPI_Comm comm, const eo_csc *H, const PetscInt *glob, int nown, int nglobal,
                     Mat *A, PetscCount *ncoo);
/* H's values in that COO order into v; returns their count. */
PetscCount eo_petsc_coo_fill(const eo_csc *H, PetscScalar *v);
/* GAMG's near-null space of A: the rigid-body modes of d's rest coordinates (block size 3
 * only). */
int eo_petsc_rigid_modes(const eo_dist *d, Mat A, Vec *coords, MatNullSpace *ns);

/* The vector space of the distributed step objective (space.c): the context hook
 * eo_dist_hooks.space, with which the library's optimizers run distributed. */
typedef struct eo_petsc_space {
    eo_vspace vs;
    eo_dist d;              /* the numbering (d.gen changes with it) */
    Vec G;                  /* global work vector of assemble */
    unsigned char *own;
    long *gid;
} eo_petsc_space;
int eo_petsc_space_hook(eo_ctx *ctx, eo_objective *obj, const eo_vspace **out, void *user);
/* 1 if vs is this backend's space (its user is an eo_petsc_space). */
int eo_petsc_space_is(const eo_vspace *vs);

/* The linear solver petsc_ksp (ksp.c): the Newton system of the library's optimizers
 * through KSP, from each rank's part of the Hessian. */
extern const eo_linsolve_type eo_linsolve_petsc_ksp;

/* KSP set up from the params (+ the options string, + the PETSc options database). */
int eo_petsc_ksp_configure(eo_ctx *ctx, KSP ksp, const eo_petsc_params *p, eo_dist *d, const char *prefix);

/* PETSc initialized (PetscInitialize once, MPI singleton if not launched by mpirun). */
int eo_petsc_ensure(eo_ctx *ctx);
/* Map a PETSc error code to an eo status with a message. */
int eo_petsc_fail(eo_ctx *ctx, PetscErrorCode ierr, const char *what);
#define EO_PC(call)                                                                      \
    do {                                                                                 \
        PetscErrorCode eo_ierr_ = (call);                                                \
        if (eo_ierr_) {                                                                  \
            rc = eo_petsc_fail(ctx, eo_ierr_, #call);                                    \
            goto fail;                                                                   \
        }                                                                                \
    } while (0)

extern const eo_optimizer_type eo_optimizer_snes_newtonls, eo_optimizer_snes_newtontr, eo_optimizer_tao_nls,
    eo_optimizer_tao_ntr, eo_optimizer_tao_lmvm, eo_optimizer_tao_bqnls;

#endif
