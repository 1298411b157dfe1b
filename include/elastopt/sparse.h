/// @file sparse.h
/// Symmetric sparse matrices in compressed-column form (upper triangle stored) and a
/// fixed-pattern assembler.
///
/// The pattern of the Hessian is computed once per mesh: every term registers its
/// elements (groups of variables), the assembler builds the CSC pattern of the upper
/// triangle and, per element, a scatter map from its local dense matrix entries to
/// positions in `val`. Assembly is then a loop `val[map[k]] += Ke[k]` with no search
/// and no sorting per iteration.
///
/// ```c
/// eo_assembler *as; eo_assembler_create(ctx, n, &as);
/// int h = eo_assembler_add_elements(as, nt, 12, dofs);   // dofs: nt*12 variable ids (-1 = eliminated)
/// eo_assembler_finalize(ctx, as);                          // builds pattern and maps
/// eo_csc *H = eo_assembler_matrix(as);                     // borrowed, values zeroed by _zero
/// eo_assembler_zero(as); eo_assembler_add(as, h, e, Ke);  // Ke: 12×12 row-major
/// ```
#ifndef ELASTOPT_SPARSE_H
#define ELASTOPT_SPARSE_H

#include "ctx.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Symmetric matrix, upper triangle (row <= col) in CSC, rows sorted in each column.
typedef struct eo_csc {
    int n;          ///< dimension
    int nnz;        ///< stored entries (upper triangle incl. diagonal)
    int *colptr;    ///< n+1
    int *rowind;    ///< nnz
    double *val;    ///< nnz
} eo_csc;

int eo_csc_create(eo_ctx *ctx, int n, int nnz, eo_csc **out);
void eo_csc_destroy(eo_ctx *ctx, eo_csc **A);
/// y = A x for the symmetric matrix stored by its upper triangle.
void eo_csc_symv(const eo_csc *A, const double *x, double *y);
/// Position of entry (i,j) (either order) in val, or -1 if not in the pattern.
int eo_csc_find(const eo_csc *A, int i, int j);
/// Diagonal into d (n).
void eo_csc_diag(const eo_csc *A, double *d);
/// Dense n×n (row-major, full symmetric) copy, for tests and small problems.
void eo_csc_to_dense(const eo_csc *A, double *D);

typedef struct eo_assembler eo_assembler;

int eo_assembler_create(eo_ctx *ctx, int n, eo_assembler **out);
void eo_assembler_destroy(eo_ctx *ctx, eo_assembler **as);
/// Register `ne` elements of `k` variables each; `dofs` (ne*k, copied) gives the global
/// variable of each local one, -1 for eliminated variables. Returns a group handle >= 0
/// or a negative status. Only before finalize.
int eo_assembler_add_elements(eo_ctx *ctx, eo_assembler *as, int ne, int k, const int *dofs);
/// Also make sure every diagonal entry exists (always done) — and build the maps.
int eo_assembler_finalize(eo_ctx *ctx, eo_assembler *as);
/// The assembled matrix (borrowed; pattern fixed after finalize).
eo_csc *eo_assembler_matrix(eo_assembler *as);
/// Set all values to zero.
void eo_assembler_zero(eo_assembler *as);
/// Add the dense k×k (row-major, symmetric) element matrix of element e of group h.
void eo_assembler_add(eo_assembler *as, int h, int e, const double *Ke);
/// Add to one diagonal entry (e.g. a lumped mass or a shift).
void eo_assembler_add_diag(eo_assembler *as, int i, double v);

#ifdef __cplusplus
}
#endif
#endif
