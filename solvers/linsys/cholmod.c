/* cholmod — sparse supernodal Cholesky factorization (CHOLMOD, Davis et al.).
 *
 *   P A Pᵀ = L Lᵀ,   x = Pᵀ L⁻ᵀ L⁻¹ P b
 *
 * P is a fill-reducing permutation (AMD, or CHOLMOD's default strategy) found with
 * the symbolic analysis in `analyze` (cholmod_analyze, once per pattern); `factor`
 * reuses that symbolic factor for every numeric cholmod_factorize. If a pivot
 * l_kk² = a_kk − Σ l_kj² is <= 0 the matrix is not positive definite: factor returns
 * EO_WARN_NOT_PD with the original column of the failing pivot (Perm[L->minor]).
 * A is passed to CHOLMOD as a header over our upper CSC (stype = +1), not copied.
 *
 * Default ordering chosen by measurement (bench/bench_linsolve bar cases, results in
 * bench/results/linsolve-bars-amd-epyc-2cpu.txt: clamp-projected Newton Hessians of the
 * generated twist bar, numeric supernodal factorization, one BLAS thread, 3-5
 * interleaved repeats, loaded 2-core machine). AMD needs the fewest flops on every bar
 * and has the shortest or an equal median time; METIS / NESDIS cost 5x more to analyze:
 *     tets     AMD flops / nnz(L) / factor    METIS flops / time   NESDIS flops / time   auto
 *     5 000    2.2e7 / 2.4e5 / 0.0154 s       5.3e7 / 0.97x        5.2e7 / 1.27x         AMD
 *     50 000   2.8e9 / 6.3e6 / 0.274 s        3.6e9 / 1.23x        3.5e9 / 1.92x         AMD
 *     108 160  1.5e10 / 2.0e7 / 1.64 s        1.6e10 / 1.14x       1.6e10 / 1.07x        METIS
 * (time ratios: median numeric factorization time / AMD's.) On these quasi-1D bars
 * minimum degree is as good as dissection; issue 15 measured METIS 24-39% faster on a
 * 108k-tet TetGen beam and a 119k-tet bunny, so for large unstructured meshes measure
 * ordering = "metis" (bench_linsolve prints both).
 *
 * Parameters (solver.cholmod.<key>):
 *   ordering    "auto" | "amd" | "metis" | "nesdis" | "natural"       default "amd"
 *   supernodal  true: supernodal LLᵀ (BLAS-3), false: simplicial LLᵀ   default true
 *   openmp      let CHOLMOD's own OpenMP loops run on 4 threads         default false
 *               (the BLAS threads are not affected; see eo_chm_factorize)
 */
#include <stddef.h>

#include "cholmod_util.h"

typedef struct cholmod_params {
    char ordering[16]; /* fill-reducing ordering; default "amd" */
    int supernodal;    /* supernodal (true) or simplicial LLᵀ; default true */
    int openmp;        /* CHOLMOD's internal OpenMP loops; default false */
} cholmod_params;

static const char *const orderings[] = EO_CHM_ORDERINGS;

static const eo_param_desc cholmod_desc[] = {
    {.key = "ordering", .kind = EO_PARAM_CHOICE, .offset = offsetof(cholmod_params, ordering),
     .size = sizeof(((cholmod_params *)0)->ordering), .def.s = "amd", .choices = orderings,
     .help = "fill-reducing ordering: auto (CHOLMOD's choice), amd, metis, nesdis (CHOLMOD nested "
             "dissection), natural. Default amd by measurement on the generated twist bars at 5k/50k/108k "
             "tets: fewest flops (METIS 2.4/1.28/1.06x, NESDIS 2.3/1.24/1.04x AMD's) and numeric "
             "factorization time METIS 0.97/1.23/1.14x, NESDIS 1.27/1.92/1.07x AMD's (bench_linsolve, "
             "loaded machine); on large unstructured meshes metis can be faster"},
    {.key = "supernodal", .kind = EO_PARAM_BOOL, .offset = offsetof(cholmod_params, supernodal),
     .def.i = 1, .help = "supernodal LL' (true) or simplicial LL' (false)"},
    {.key = "openmp", .kind = EO_PARAM_BOOL, .offset = offsetof(cholmod_params, openmp), .def.i = 0,
     .help = "run CHOLMOD's internal OpenMP loops (4 threads, compiled in) instead of serially; "
             "the BLAS keeps its own threads either way"},
    {0},
};

typedef struct cholmod_state {
    eo_chm chm;
    cholmod_params p;
    int n;
} cholmod_state;

static int chol_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    cholmod_state *s = st;
    s->p = *(const cholmod_params *)params;
    eo_chm_start(&s->chm);
    eo_chm_ordering(&s->chm, s->p.ordering);
    s->chm.c.supernodal = s->p.supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    s->chm.c.final_ll = 1;
    return EO_OK;
}

static int chol_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    cholmod_state *s = st;
    s->n = A->n;
    return eo_chm_analyze(&s->chm, A, "cholmod", ctx);
}

static int chol_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    cholmod_state *s = st;
    cholmod_sparse S = eo_chm_view(A);
    int ok = eo_chm_factorize(&s->chm, &S, s->p.openmp);
    int status = s->chm.c.status;
    if (status == CHOLMOD_NOT_POSDEF || (ok && s->chm.L->minor < (size_t)A->n)) {
        int k = (int)s->chm.L->minor, col = eo_chm_orig(&s->chm, k);
        stats->not_pd_column = col;
        return eo_error_at(ctx, EO_WARN_NOT_PD, EO_ERRLOC_ITEM(NULL, -1, "column", col),
                           "cholmod: matrix not positive definite (pivot %d of %d in the "
                           "factorization order)", k, A->n);
    }
    if (!ok || status < CHOLMOD_OK)
        return eo_error(ctx, status == CHOLMOD_OUT_OF_MEMORY ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                        "cholmod: cholmod_factorize failed (CHOLMOD status %d)", status);
    return EO_OK;
}

static int chol_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    cholmod_state *s = st;
    stats->iterations = 0;
    return eo_chm_solve(&s->chm, b, x, s->n, "cholmod", ctx);
}

static void chol_destroy(void *st, eo_ctx *ctx)
{
    (void)ctx;
    eo_chm_finish(&((cholmod_state *)st)->chm);
}

const eo_linsolve_type eo_linsolve_cholmod = {
    .info = {.name = "cholmod",
             .summary = "CHOLMOD supernodal sparse Cholesky LL' (analyze once, factor per iteration)",
             .params = cholmod_desc,
             .params_size = sizeof(cholmod_params)},
    .state_size = sizeof(cholmod_state),
    .setup = chol_setup,
    .analyze = chol_analyze,
    .factor = chol_factor,
    .solve = chol_solve,
    .destroy = chol_destroy,
};
