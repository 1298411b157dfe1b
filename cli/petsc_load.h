/* The PETSc / MPI backend module (petsc/, built with -Dpetsc) as seen by the CLI: loaded
 * at start with its own symbol scope; under an MPI launcher it starts MPI and the ranks
 * other than 0 print nothing and write no output files. Without the module every rank
 * function below answers as a single process. */
#ifndef EO_CLI_PETSC_LOAD_H
#define EO_CLI_PETSC_LOAD_H

#include "elastopt/ctx.h"

/* Load the module if it was built (ELASTOPT_PETSC_MODULE names another file), take the
 * PETSc options (-ksp_*, -pc_*, -log_view, ...) out of argv. Returns 0, or 2 after
 * printing an error (a module that exists but cannot be loaded or started). */
int eo_cli_petsc_load(eo_ctx *ctx, int *argc, char **argv);
/* The context a command runs with: under MPI with several ranks, meshes are read on
 * rank 0 and broadcast to the others (the module's mesh source); else nothing. */
void eo_cli_petsc_attach(eo_ctx *ctx);
/* What the last mesh read under MPI did ("mesh: FILE read on rank 0, broadcast ..."), or
 * NULL when nothing was broadcast. */
const char *eo_cli_mesh_note(void);
/* Rank and number of processes (0 and 1 without MPI). */
int eo_cli_rank(void);
int eo_cli_size(void);
/* A distributed run (each rank simulates its part of the mesh): the whole mesh's vertex
 * count, or -1 when the scene is not distributed. */
int eo_cli_dist_nv(void);
/* Collective: a per-vertex array of `width` doubles per local vertex gathered to rank 0
 * in the input vertex order (out: nv·width doubles there). Returns 0 or -1. */
int eo_cli_dist_gather(const double *local, int width, double *out);
/* A distributed run: an identity (hash, never 0) of this rank's part of the mesh: rank
 * count, rank, the input numbers and ownership of its vertices; 0 when not distributed. */
unsigned long long eo_cli_dist_layout_id(void);
/* A distributed scene (the last one loaded), collective: a per-vertex value (local
 * vertices) summed over the ranks that hold the vertex, on its owner; 0 on the ranks that
 * do not own it. Returns 0, or -1 when not distributed. */
int eo_cli_dist_owned_sum(const double *local, double *out);
/* 1 if ok is 1 on every rank (collective over all ranks when there are several). */
int eo_cli_agree(int ok);

#endif
