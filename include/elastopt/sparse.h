/// @file sparse.h
/// Symmetric sparse matrices in compressed-column form (upper triangle stored) and a
/// fixed-pattern assembler.
///
/// The pattern of the Hessian is computed once per mesh: every term registers its
/// elements (groups of variables), the assembler builds the CSC pattern of the upper
/// triangle and, per element, a scatter map from its local dense matrix entries to
/// positions in `val`. Assembly is then a loop `val[map[k]] += Ke[k]` with no search,
/// no sorting and no allocation per iteration.
///
/// ```c
/// eo_assembler *as; eo_assembler_create(ctx, n, &as);
/// int h = eo_assembler_add_elements(ctx, as, nt, 12, dofs); // dofs: nt*12 ids (-1 = eliminated)
/// eo_assembler_finalize(ctx, as);                          // builds pattern and maps
/// eo_csc *H = eo_assembler_matrix(as);                     // borrowed
/// eo_assembler_zero(as);
/// for (e = 0; e < nt; e++) eo_assembler_add(as, h, e, Ke); // Ke: 12×12 row-major
/// eo_assembler_add_diag(as, i, m_i);                       // lumped mass, shift c·I
/// ```
///
/// Invariants of every eo_csc made here (assembler, eo_csc_create users must keep them):
/// rows are sorted in each column, only rows <= column are stored, and every diagonal
/// entry is present, so (j,j) is the LAST entry of column j: `val[colptr[j+1]-1]`.
/// A shift c·I can therefore always be added in place (eo_csc_shift).
///
/// Ownership: eo_csc and eo_assembler own their arrays; eo_assembler_matrix returns a
/// borrowed pointer valid until eo_assembler_destroy. Element id arrays are copied.
#ifndef ELASTOPT_SPARSE_H
#define ELASTOPT_SPARSE_H

#include "export.h"
#include "ctx.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Symmetric matrix, upper triangle (row <= col) in CSC, rows sorted in each column,
/// diagonal always present (last entry of its column).
typedef struct eo_csc {
    int n;          ///< dimension
    int nnz;        ///< stored entries (upper triangle incl. diagonal)
    int *colptr;    ///< n+1
    int *rowind;    ///< nnz
    double *val;    ///< nnz
    eo_ctx *ctx;                       ///< context it was created with (its destroy uses it)
} eo_csc;

/// Allocate an n×n matrix with room for nnz entries (colptr zeroed, rowind/val
/// uninitialized: the caller fills them keeping the invariants above).
/// Returns EO_OK, EO_ERR_INVALID (n < 0, nnz < n) or EO_ERR_NOMEM.
EO_API int eo_csc_create(eo_ctx *ctx, int n, int nnz, eo_csc **out);
/// Deep copy (pattern and values).
EO_API int eo_csc_clone(eo_ctx *ctx, const eo_csc *A, eo_csc **out);
/// Free; sets *A = NULL; accepts NULL.
EO_API void eo_csc_destroy(eo_csc **A);
/// y = A x for the symmetric matrix stored by its upper triangle (y must not alias x).
EO_API void eo_csc_symv(const eo_csc *A, const double *x, double *y);
/// Position of entry (i,j) (either order) in val, or -1 if not in the pattern
/// (binary search in column max(i,j)).
EO_API int eo_csc_find(const eo_csc *A, int i, int j);
/// Diagonal into d (n).
EO_API void eo_csc_diag(const eo_csc *A, double *d);
/// A += c·I (in place; the diagonal is always stored).
EO_API void eo_csc_shift(eo_csc *A, double c);
/// Dense n×n (row-major, full symmetric) copy, for tests and small problems.
EO_API void eo_csc_to_dense(const eo_csc *A, double *D);
/// Check the invariants (sizes, sorted rows, upper only, diagonal last).
/// Returns EO_OK or EO_ERR_INVALID with the offending column in the message.
EO_API int eo_csc_check(eo_ctx *ctx, const eo_csc *A);

/// A = A₁ ⊗ I₃? For A of order n = 3m (upper triangle CSC as above) in which every 3×3
/// block (I, J) is a multiple a·I₃ — entries off the blocks' diagonals at most
/// tol·max|A| in magnitude, the three diagonal copies equal to within tol·max|A| —
/// returns 1 and the m×m matrix A₁ of the multiples (same invariants, rows of column J
/// = the block rows stored in column 3J, values taken from there) in a new *A1 (owned
/// by the caller). The projective-dynamics matrix of a mesh is of this form (isotropic
/// element blocks k·GᵀG = k·(BᵀB) ⊗ I₃, mass M₁ ⊗ I₃), and factoring A₁ instead of A
/// takes about 1/27 of the flops and each solve (three right-hand sides of order m)
/// about 1/3. Returns 0 (*A1 untouched) when A is not of this form or n is not a
/// multiple of 3, EO_ERR_NOMEM.
EO_API int eo_csc_kron_i3(eo_ctx *ctx, const eo_csc *A, double tol, eo_csc **A1);

/// Both triangles of a symmetric matrix, for methods that need whole rows
/// (Gauss–Seidel, SOR, QR). Column j of the full matrix equals row j, rows sorted.
/// The pattern is built once (`_create`); `_fill` gathers values: val[q] = A->val[src[q]].
typedef struct eo_csc_full {
    int n, nnz;
    int *colptr;    ///< n+1
    int *rowind;    ///< nnz, sorted in each column
    double *val;    ///< nnz
    int *src;       ///< nnz: position in the upper matrix's val of each full entry
    int *diag;      ///< n: position of (j,j) in val
    eo_ctx *ctx;                       ///< context it was created with (its destroy uses it)
} eo_csc_full;
EO_API int eo_csc_full_create(eo_ctx *ctx, const eo_csc *A, eo_csc_full **out);
/// Copy the values of A (same pattern as at create) into F. No allocation.
EO_API void eo_csc_full_fill(eo_csc_full *F, const eo_csc *A);
EO_API void eo_csc_full_destroy(eo_csc_full **F);

typedef struct eo_assembler eo_assembler;

/// Assembler for an n×n symmetric matrix. Returns EO_OK, EO_ERR_INVALID, EO_ERR_NOMEM.
EO_API int eo_assembler_create(eo_ctx *ctx, int n, eo_assembler **out);
/// Free; sets *as = NULL; accepts NULL.
EO_API void eo_assembler_destroy(eo_assembler **as);
/// Register `ne` elements of `k` variables each; `dofs` (ne*k, copied) gives the global
/// variable of each local one, -1 for eliminated variables. A global id may repeat
/// inside an element (contributions are summed). Returns a group handle >= 0 or a
/// negative status (EO_ERR_INVALID for an id out of [-1, n) with the element index,
/// or after finalize; EO_ERR_NOMEM). Only before finalize.
EO_API int eo_assembler_add_elements(eo_ctx *ctx, eo_assembler *as, int ne, int k, const int *dofs);
/// Build the pattern (upper triangle; every diagonal entry present even if no element
/// touches it) and the per-element scatter maps. O(nnz log(column length)) time.
/// Values start at zero. After this, nothing allocates. May be called once.
EO_API int eo_assembler_finalize(eo_ctx *ctx, eo_assembler *as);
/// The assembled matrix (borrowed; pattern fixed after finalize; NULL before).
EO_API eo_csc *eo_assembler_matrix(eo_assembler *as);
/// Set all values to zero.
EO_API void eo_assembler_zero(eo_assembler *as);
/// Add the dense k×k (row-major, symmetric) element matrix of element e of group h:
/// A += Σ_ab Ke[a*k+b] e_{g(a)} e_{g(b)}ᵀ over non-eliminated a, b. Only entries with
/// g(a) <= g(b) are read (for g(a) == g(b), both orientations, so repeated ids sum).
EO_API void eo_assembler_add(eo_assembler *as, int h, int e, const double *Ke);
/// A += w·Ke (eo_assembler_add with the element matrix scaled on the fly, no copy).
EO_API void eo_assembler_add_scaled(eo_assembler *as, int h, int e, const double *Ke, double w);
/// Add to one diagonal entry (e.g. a lumped mass or a shift).
EO_API void eo_assembler_add_diag(eo_assembler *as, int i, double v);
/// Scatter map of element e of group h: k*k positions in val, -1 where not stored
/// (for callers that assemble in their own loop). Borrowed. NULL for a block group
/// (eo_assembler_is_block), which is scattered by 3×3 blocks with 1 int per block.
EO_API const int *eo_assembler_map(const eo_assembler *as, int h, int e);
/// 1 if group h is scattered by 3×3 blocks (k a multiple of 3, every vertex triple of
/// variables all eliminated or three consecutive ids, verified against the pattern at
/// finalize), 0 if by its k×k map.
EO_API int eo_assembler_is_block(const eo_assembler *as, int h);

#ifdef __cplusplus
}
#endif
#endif
