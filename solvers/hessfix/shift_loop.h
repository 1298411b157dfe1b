/* The c·I shift loop of the Hessian fixes, written once (solvers/hessfix/shift_loop.c).
 * Internal to solvers/hessfix; every fix that factors a matrix goes through
 * eo_shift_factor. */
#ifndef EO_HESSFIX_SHIFT_LOOP_H
#define EO_HESSFIX_SHIFT_LOOP_H

#include "elastopt/impl/method.h"
#include "elastopt/impl/params.h"

/* Workspace: the saved diagonal (n) and the shift carried to the next direction. */
typedef struct eo_shift_ws {
    int n;
    double *diag;
    double *dsum;   /* n: the whole matrix's diagonal (distributed space only) */
    double c_next;
} eo_shift_ws;

int eo_shift_ws_setup(eo_shift_ws *w, int n, eo_ctx *ctx);
void eo_shift_ws_destroy(eo_shift_ws *w, eo_ctx *ctx);
static inline void eo_shift_ws_begin(eo_shift_ws *w) { w->c_next = 0; }

/* Shift parameters of a fix's params (NULL = defaults) into *hp. */
void eo_shift_params_get(const eo_hessfix_shift_params *p, eo_hessfix_shift_params *hp);

/* Factor A + cI with env->linear and, with env->want_direction, solve p = −(A + cI)⁻¹∇g
 * and test descent (∇gᵀp < −descent_eps·‖∇g‖‖p‖). s = mean |A_ii| (1 if 0):
 *   shifting = 0: one attempt with c = 0. Returns 1 when it succeeded (factored, and p
 *                 a descent direction), 0 when A is not PD or p is not a descent
 *                 direction (the caller decides what to do; the factors are stale).
 *   shifting = 1: c starts at w->c_next; on failure c ← max(c_min, shift_grow·c),
 *                 c_min = shift_init·s, until it succeeds (returns 1; w->c_next =
 *                 c/shift_shrink, or 0 below c_min; res->n_shifted++ if c > 0) or c >
 *                 shift_max·s (returns 0, out->reason = EO_DIVERGED_NOT_PD).
 * Also returns 0 with out->reason = EO_DIVERGED_LINSOLVE (factor/solve error, status in
 * res) or EO_DIVERGED_NONFINITE (non-finite diagonal). The diagonal of A is set in
 * place and restored before returning; res->n_factor counts factorizations; out->shift
 * = c (the c that failed for EO_DIVERGED_NOT_PD); out->factored = result. Nothing is
 * allocated. */
int eo_shift_factor(eo_shift_ws *w, const eo_hessfix_shift_params *hp, int shifting,
                    const eo_hessfix_env *env, eo_csc *A, double *p, eo_hessfix_out *out);

/* Assemble (env->assemble) with a uniform projection, then eo_shift_factor. Returns 1/0 as
 * eo_shift_factor (0 with out->reason also when assemble gave a reason) or a negative
 * status. */
int eo_shift_assemble_factor(eo_shift_ws *w, const eo_hessfix_shift_params *hp, int shifting,
                             const eo_hessfix_env *env, eo_proj proj,
                             const unsigned char *proj_of, double *p, eo_hessfix_out *out);

/* The −∇g fallback (res->n_fallback++, w->c_next = 0, out->shift = 0, not factored). */
void eo_shift_fallback(eo_shift_ws *w, const eo_hessfix_env *env, double *p, eo_hessfix_out *out);

/* pᵀAp for the upper-triangle CSC A (no workspace). */
double eo_csc_quad_upper(const eo_csc *A, const double *p);
/* The same of the whole matrix when A is a part's on a distributed space vs (collective;
 * vs NULL: eo_csc_quad_upper). */
double eo_csc_quad_space(const eo_csc *A, const double *p, const eo_vspace *vs);

/* Generic ops for fixes whose state begins with an eo_shift_ws (setup for n, begin resets
 * the carried shift, destroy frees it). */
int eo_shift_op_setup(void *st, const void *params, int n, eo_ctx *ctx);
int eo_shift_op_begin(void *st, const void *params, const eo_hessfix_env *env);
void eo_shift_op_destroy(void *st, eo_ctx *ctx);

#endif
