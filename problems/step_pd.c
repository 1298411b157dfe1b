/* The step objective's own factorization of its projective-dynamics matrix (objective
 * ops constant_factor / constant_solve, objective.h; modes and counters in step.h).
 *
 * Matrix      L_all = the PD matrix of pd_matrix.c with every vertex free (assembled
 *             once through the pattern of the whole mesh, eo_stepi_pd_matrix_all, and
 *             again only when the integrator weight changes). If L_all = L₁ ⊗ I₃
 *             (eo_csc_kron_i3: isotropic element blocks k·(BᵀB) ⊗ I₃, lumped or
 *             consistent mass M₁ ⊗ I₃, springs k[[1,−1],[−1,1]] ⊗ I₃) the order-nv
 *             vertex matrix L₁ is kept instead, with the free set per vertex (the
 *             boundary conditions fix whole vertices).
 * Factor      eo_updown (solvers/linsys/updown.c): simplicial LDLᵀ of
 *                 Ã(S) = [L_SS 0; 0 diag(L_CC)],
 *             S the free variables of the current pattern, whose free block is exactly
 *             the eliminated matrix the optimizers would otherwise factor. When the
 *             constrained set changes — a release (S grows) or, after the state is set
 *             back before a release (the benchmark does this), a pin (S shrinks) — the
 *             factor follows by cholmod_updown, rank 2 per changed variable, instead of
 *             being factored again (EO_PD_FACTOR_UPDOWN; REFACTOR factors afresh at every
 *             change, the reference; tests/test_pd_local_global.c checks both give the
 *             same factor to 1e-10 and the same trajectory). The default AUTO updates
 *             when rank·nnz(L) ≤ the factorization's flops (CHOLMOD's analysis), where
 *             the update cannot cost more, and factors afresh otherwise. Measured (CPU
 *             time, L₁ of the stretched bar's release of one end face): 1476 vertices,
 *             rank 72: update 1.0 ms, factorization 1.9–2.5 ms (flops/nnz(L) = 32);
 *             2989 vertices, rank 98: 5.6 / 6.2–7.7 ms (46); 12221 vertices (50k tets), rank
 *             242: 144 / 85–92 ms (143) — a face of a hundred vertices is cheaper to
 *             refactor at that size, a few pinned or released vertices are not.
 * Solve       b (free coordinates) scattered into the variables of L_all (0 on the
 *             constrained ones, so x_C = 0), one solve — for L₁ with the 3 coordinates
 *             as 3 right-hand sides in one pass over the factor — and x gathered back.
 * Where not   terms whose rest Hessian is not part of L_all (damping: its K₀ lives in
 *             the pattern of the constraints; obstacles and friction) make the ops
 *             return EO_ERR_UNSUPPORTED: the optimizers then factor constant_hessian
 *             themselves (as with EO_PD_FACTOR_OFF).
 * Memory      L_all, the factor and 2·n_full doubles at the first constant_factor of a
 *             scene; solves allocate nothing (eo_updown_solve_multi keeps CHOLMOD's
 *             workspace). */
#include <string.h>

#include "step_impl.h"

static int pd_supported(const eo_step *st)
{
    return st->pd_mode != EO_PD_FACTOR_OFF && !(st->term_flags & EO_TERM_NO_PD) &&
           (st->integ->weight != NULL || st->integ->accel);
}

/* the free set of the variables of pd_all under the current constraints */
static void free_set(const eo_step *st, unsigned char *fr)
{
    if (st->pd_info.scalar)
        for (int v = 0; v < st->nv; v++) fr[v] = st->vbc[v] < 0;
    else
        for (int j = 0; j < st->n_full; j++) fr[j] = st->full2free[j] >= 0;
}

void eo_stepi_pd_deinit(eo_step *st)
{
    eo_updown_destroy(&st->pd_u);
    eo_csc_destroy(&st->pd_all);
    eo_free(st->ctx, st->pd_free);
    eo_free(st->ctx, st->pd_b);
    st->pd_free = NULL;
    st->pd_b = st->pd_x = NULL;
    st->pd_info.factored = 0;
}

/* Assemble L_all for the current weight and factor Ã(S) afresh. */
static int build_and_factor(eo_step *st)
{
    eo_ctx *ctx = st->ctx;
    eo_updown_destroy(&st->pd_u);
    st->pd_info.factored = 0;
    if (!st->pd_all || st->pd_w != st->w) {
        eo_csc_destroy(&st->pd_all);
        double t0 = eo_wtime();
        eo_csc *A = NULL, *A1 = NULL;
        int rc = eo_stepi_pd_matrix_all(st, &A);
        if (rc < 0) return rc;
        rc = eo_csc_kron_i3(ctx, A, 1e-13, &A1);
        if (rc < 0) {
            eo_csc_destroy(&A);
            return rc;
        }
        int partial = 0; /* an entry holding some components only: the free set is per coordinate */
        for (int b = 0; b < st->sc->nbc; b++) partial |= st->sc->bc[b].partial;
        st->pd_info.scalar = rc == 1 && !partial;
        if (st->pd_info.scalar) {
            eo_csc_destroy(&A);
            A = A1;
        } else if (rc == 1) {
            eo_csc_destroy(&A1);
        }
        st->pd_all = A;
        st->pd_w = st->w;
        st->pd_info.n = A->n;
        st->pd_info.t_build += eo_wtime() - t0;
    }
    const size_t nf = (size_t)(st->n_full > 0 ? st->n_full : 1);
    if (!st->pd_free && !(st->pd_free = eo_malloc(ctx, nf))) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (PD factor)");
    if (!st->pd_b) {
        if (!(st->pd_b = eo_malloc(ctx, 2 * nf * sizeof(double)))) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (PD factor)");
        st->pd_x = st->pd_b + nf;
    }
    free_set(st, st->pd_free);
    double t0 = eo_wtime();
    int rc = eo_updown_create(ctx, st->pd_all, st->pd_free, &st->pd_u);
    st->pd_info.t_factor += eo_wtime() - t0;
    if (rc < 0) return rc;
    st->pd_info.n_factor++;
    st->pd_info.factored = 1;
    return 1; /* one fresh factorization */
}

int eo_stepi_pd_factor(void *data)
{
    eo_step *st = data;
    if (!pd_supported(st)) return EO_ERR_UNSUPPORTED;
    st->pd_info.mode = st->pd_mode;
    if (!st->pd_u || st->pd_w != st->w) return build_and_factor(st);
    /* the constrained set of the current pattern against the factor's */
    const unsigned char *cur = eo_updown_free_set(st->pd_u);
    free_set(st, st->pd_free);
    if (memcmp(cur, st->pd_free, (size_t)st->pd_info.n) == 0) return EO_OK;
    if (st->pd_mode == EO_PD_FACTOR_REFACTOR) return build_and_factor(st);
    if (st->pd_mode == EO_PD_FACTOR_AUTO) { /* the update only where it cannot cost more */
        double fl = 0, lnz = 0;
        long changed = 0;
        for (int i = 0; i < st->pd_info.n; i++) changed += cur[i] != st->pd_free[i];
        eo_updown_costs(st->pd_u, &fl, &lnz);
        if ((double)(2 * changed) * lnz > fl) return build_and_factor(st);
    }
    int rank = 0;
    double t0 = eo_wtime();
    int rc = eo_updown_set_free(st->pd_u, st->pd_free, &rank);
    st->pd_info.t_updown += eo_wtime() - t0;
    if (rc < 0) { /* the factor is unusable: start again */
        eo_updown_destroy(&st->pd_u);
        st->pd_info.factored = 0;
        return rc;
    }
    st->pd_info.n_updown++;
    st->pd_info.rank += rank;
    st->pd_info.last_rank = rank;
    return EO_OK;
}

int eo_stepi_pd_solve(void *data, const double *b, double *x)
{
    eo_step *st = data;
    if (!st->pd_u) return eo_error(st->ctx, EO_ERR_INVALID, "PD solve before constant_factor");
    double *B = st->pd_b, *X = st->pd_x;
    int rc;
    if (st->pd_info.scalar) { /* B: nv × 3, column c = coordinate c of every vertex */
        const int nv = st->nv;
        for (int j = 0; j < st->n_full; j++) {
            const int f = st->full2free[j];
            B[j % 3 * nv + j / 3] = f >= 0 ? b[f] : 0;
        }
        rc = eo_updown_solve_multi(st->pd_u, 3, B, X);
        if (rc < 0) return rc;
        for (int i = 0; i < st->nfree; i++) {
            const int j = st->free2full[i];
            x[i] = X[j % 3 * nv + j / 3];
        }
    } else {
        for (int j = 0; j < st->n_full; j++) B[j] = st->full2free[j] >= 0 ? b[st->full2free[j]] : 0;
        rc = eo_updown_solve_multi(st->pd_u, 1, B, X);
        if (rc < 0) return rc;
        for (int i = 0; i < st->nfree; i++) x[i] = X[st->free2full[i]];
    }
    st->pd_info.n_solve++;
    return EO_OK;
}

int eo_step_set_pd_factor(eo_step *st, int mode)
{
    if (mode < EO_PD_FACTOR_OFF || mode > EO_PD_FACTOR_AUTO)
        return eo_error(st->ctx, EO_ERR_RANGE, "PD factor mode %d (0 off, 1 refactor, 2 updown, 3 auto)", mode);
    if (mode != st->pd_mode) {
        eo_updown_destroy(&st->pd_u);
        st->pd_info.factored = 0;
    }
    st->pd_mode = mode;
    st->pd_info.mode = mode;
    return EO_OK;
}

void eo_step_pd_info_get(const eo_step *st, eo_step_pd_info *out)
{
    *out = st->pd_info;
    out->mode = st->pd_mode;
    out->factored = st->pd_u != NULL;
}

eo_updown *eo_step_pd_updown(eo_step *st) { return st->pd_u; }
