/* Generated mass-spring lattices (`mesh.lattice`, scene.h): private to problems/. */
#ifndef EO_PROBLEMS_LATTICE_H
#define EO_PROBLEMS_LATTICE_H

#include "elastopt/scene.h"

/* Build the lattice of `o` (cells already checked to be integers >= 0, size > 0 where
 * cells > 0): a mesh of points without tets, ns springs (2·ns vertex ids a < b in ab,
 * stiffnesses k; kinds with k = 0 omitted), per-vertex masses (nv) and the counts of
 * structural, shear and bending springs. Everything allocated through ctx (owned by the
 * caller). EO_ERR_NOMEM. */
int eo_lattice_build(eo_ctx *ctx, const eo_scene_lattice_opts *o, eo_mesh **mesh, int **ab, double **k, int *ns,
                     double **mass, int count[3]);

#endif
