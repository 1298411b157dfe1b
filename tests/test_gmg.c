/* Suite 'linsolve': the Galerkin multigrid gmg (solvers/linsys/gmg.c), as a solver and as
 * pcg's preconditioner.
 *
 *  1. Galerkin products: on a small cantilever Hessian with at least three levels, every
 *     coarse matrix equals Pᵀ A P formed densely from the previous level (both coarse
 *     spaces), to 1e-12 of max|A|; translations are reproduced by every prolongation
 *     (P·1 = 1 componentwise).
 *     Failure injection over the multilevel create: EO_ERR_NOMEM and no leak.
 *     A flat sheet of nodes inside a layer of grid cubes (dependent trilinear columns):
 *     the dependent coarsest nodes are dropped, setup succeeds on the SPD matrix and 30
 *     V-cycles reduce the residual below 1e-8; none is dropped on the solid bar.
 *  2. Mesh independence: the V-cycle's residual reduction per cycle (geometric mean of
 *     cycles 6..15 of x += V(b − Ax) from 0) on the clamp-projected Hessian of the first
 *     cantilever step at 3 refinements (cells 20·r × 2·r × 2·r, r = 1, 2, 4; coarse_size
 *     200 so that the hierarchy deepens with the mesh, the defaults otherwise): < 0.5 at each and the finest at
 *     most 1.5× the coarsest, for the default (linear) coarse spaces; the affine
 *     (skinning) ones are measured and printed, and must still reduce (< 0.9).
 *  3. PCG + gmg solves that Newton hsys to a relative residual 1e-10 (true residual),
 *     and so does the standalone gmg.
 *  4. Newton with pcg + gmg under the Eisenstat–Walker forcing (ew2), and Newton with
 *     the standalone gmg, reach the minimizer of Newton with CHOLMOD within 1e-8 of the
 *     step's motion on the first steps of the cantilever (refined 2×) and the twist
 *     (fallback chain off).
 * Without coordinates the hierarchy is one level (CHOLMOD): the linear-solver contract
 * (test_linsolve) covers that path. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/scene.h"
#include "elastopt/step.h"
#include "engine_util.h"
#include "solvers/linsys/gmg.h"

typedef struct hsys {
    eo_cfg *cfg;
    eo_scene *sc;
    eo_step *st;
    eo_csc *H; /* borrowed from the objective */
    double *b, *xyz;
    int n, nv;
} hsys;

static int hsys_build(eo_ctx *ctx, const char *scene, int r, hsys *S)
{
    memset(S, 0, sizeof *S);
    char ov[96];
    snprintf(ov, sizeof ov, "mesh.generate.cells=[%d,%d,%d]", 20 * r, 2 * r, 2 * r);
    int rc = eo_scene_cfg_load(ctx, NULL, scene, &S->cfg);
    if (rc >= 0) rc = eo_cfg_override(ctx, S->cfg, ov);
    if (rc >= 0) rc = eo_scene_load(ctx, S->cfg, &S->sc);
    if (rc >= 0) rc = eo_step_create(ctx, S->sc, &S->st);
    eo_objective *obj = NULL;
    if (rc >= 0) rc = eo_step_begin(S->st, &obj);
    if (rc < 0) return rc;
    S->n = obj->n;
    S->nv = obj->n / 3;
    double *x = eo_step_guess(S->st), gv;
    S->b = malloc((size_t)S->n * sizeof(double));
    S->xyz = malloc((size_t)S->n * sizeof(double));
    rc = eo_objective_gradient(obj, x, &gv, S->b);
    if (rc >= 0) rc = eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &S->H);
    for (int i = 0; i < S->n; i++) S->b[i] = -S->b[i];
    const double *x0 = eo_step_x0(S->st);
    for (int i = 0; i < S->n; i++) S->xyz[i] = x0[eo_step_free_to_full(S->st, i)];
    return rc;
}

static void hsys_free(hsys *S)
{
    free(S->b);
    free(S->xyz);
    eo_step_destroy(&S->st);
    eo_scene_destroy(&S->sc);
    eo_cfg_destroy(&S->cfg);
}

static double norm(int n, const double *v)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += v[i] * v[i];
    return sqrt(s);
}

static double rel_res(const eo_csc *A, const double *b, const double *x)
{
    double *y = malloc((size_t)A->n * sizeof(double));
    eo_csc_symv(A, x, y);
    for (int i = 0; i < A->n; i++) y[i] = b[i] - y[i];
    double r = norm(A->n, y) / norm(A->n, b);
    free(y);
    return r;
}

/* ---------------------------------------------------------------- 1. Galerkin ---------- */

static void galerkin_dense(eo_ctx *ctx, int prolongation)
{
    hsys S;
    CHECK(hsys_build(ctx, "cantilever", 1, &S) >= 0, "cantilever: %s", eo_ctx_message(ctx));
    if (!S.H) return;
    eo_gmg_opts o = {.prolongation = prolongation, .cell = 2, .coarse_size = 30, .max_levels = 6, .smooth_steps = 2,
                     .name = "gmg"};
    eo_gmg *g = NULL;
    int rc = eo_gmg_create(ctx, S.H, &o, S.nv, S.xyz, &g);
    eo_linsolve_stats st = {.not_pd_column = -1};
    if (rc >= 0) rc = eo_gmg_setup(g, S.H, &st, ctx);
    CHECK(rc == EO_OK, "create/setup: %s", eo_ctx_message(ctx));
    const int L = rc == EO_OK ? eo_gmg_levels(g) : 0;
    printf("%s coarse spaces, cantilever %d unknowns: %d levels:", prolongation ? "affine" : "linear", S.n, L);
    for (int l = 0; l < L; l++) printf(" %d", eo_gmg_level_n(g, l));
    printf("\n");
    CHECK(L >= 3, "at least three levels: %d", L);
    CHECK(rc != EO_OK || eo_gmg_dropped(g) == 0, "no coarsest node dropped on a solid bar: %d", eo_gmg_dropped(g));
    for (int l = 0; l + 1 < L; l++) {
        const int nf = eo_gmg_level_n(g, l), nc = eo_gmg_level_n(g, l + 1);
        double *A = malloc((size_t)nf * nf * sizeof(double)), *P = malloc((size_t)nf * nc * sizeof(double));
        double *C = malloc((size_t)nc * nc * sizeof(double)), *AP = calloc((size_t)nf * nc, sizeof(double));
        eo_gmg_level_dense(g, l, A);
        if (l == 0) { /* level 0 is H itself */
            double *D = malloc((size_t)nf * nf * sizeof(double)), e = 0;
            eo_csc_to_dense(S.H, D);
            for (size_t q = 0; q < (size_t)nf * nf; q++) e = fmax(e, fabs(D[q] - A[q]));
            CHECK(e == 0, "level 0 = H exactly: %g", e);
            free(D);
        }
        eo_gmg_prolongation_dense(g, l, P);
        eo_gmg_level_dense(g, l + 1, C);
        for (int i = 0; i < nf; i++)
            for (int k = 0; k < nf; k++) {
                double a = A[(size_t)i * nf + k];
                if (a != 0)
                    for (int j = 0; j < nc; j++) AP[(size_t)i * nc + j] += a * P[(size_t)k * nc + j];
            }
        double err = 0, amax = 0, pmax = 0; /* pmax: P is not empty */
        for (size_t q = 0; q < (size_t)nf * nf; q++) amax = fmax(amax, fabs(A[q]));
        for (int j = 0; j < nc; j++)
            for (int m = 0; m < nc; m++) {
                double s = 0;
                for (int i = 0; i < nf; i++) s += P[(size_t)i * nc + j] * AP[(size_t)i * nc + m];
                err = fmax(err, fabs(s - C[(size_t)j * nc + m]));
            }
        for (size_t q = 0; q < (size_t)nf * nc; q++) pmax = fmax(pmax, fabs(P[q]));
        printf("  level %d -> %d: n %d -> %d, max |C - P'AP| = %.3g (max |A| %.3g)\n", l, l + 1, nf, nc, err, amax);
        CHECK(err <= 1e-12 * amax, "level %d: Galerkin product = dense P'AP: %g vs %g", l, err, amax);
        CHECK(pmax > 0, "level %d: P not empty", l);
        free(A);
        free(P);
        free(C);
        free(AP);
    }
    /* P_0 P_1 ... reproduces translations: the translation part of a constant field */
    if (L >= 2) {
        const int nf = eo_gmg_level_n(g, 0), nc = eo_gmg_level_n(g, 1);
        double *P = malloc((size_t)nf * nc * sizeof(double));
        eo_gmg_prolongation_dense(g, 0, P);
        /* least-squares is overkill: the coarse translation nodes of the affine space and
         * all nodes of the linear one sum to 1 on each fine row for a unit field */
        double worst = 0;
        if (prolongation == EO_GMG_LINEAR)
            for (int i = 0; i < nf; i++) {
                double s = 0;
                for (int j = 0; j < nc; j++)
                    if (j % 3 == i % 3) s += P[(size_t)i * nc + j];
                worst = fmax(worst, fabs(s - 1));
            }
        else
            for (int i = 0; i < nf; i++) { /* exactly one weight 1: the cluster's translation */
                int ones = 0;
                for (int j = 0; j < nc; j++) ones += P[(size_t)i * nc + j] == 1.0;
                worst = fmax(worst, ones == 1 ? 0 : 1);
            }
        CHECK(worst < 1e-12, "level 0 prolongation reproduces translations: %g", worst);
        free(P);
    }
    eo_gmg_destroy(ctx, &g);
    hsys_free(&S);
}

/* failure injection over the multilevel create (both coarse spaces): every failing
 * allocation gives EO_ERR_NOMEM and leaks nothing; eventually it succeeds */
static void create_failures(eo_ctx *ctx)
{
    hsys S;
    CHECK(hsys_build(ctx, "cantilever", 1, &S) >= 0, "cantilever: %s", eo_ctx_message(ctx));
    for (int p = 0; p < 2 && S.H; p++) {
        eo_gmg_opts o = {.prolongation = p, .cell = 2, .coarse_size = 30, .max_levels = 6, .smooth_steps = 2,
                         .name = "gmg"};
        const size_t base = eo_ctx_live_bytes(ctx);
        int ok = 0, bad = 0;
        long f;
        for (f = 1; f < 400 && !ok; f++) {
            eo_gmg *g = NULL;
            eo_ctx_fail_after(ctx, f);
            int rc = eo_gmg_create(ctx, S.H, &o, S.nv, S.xyz, &g);
            eo_ctx_fail_after(ctx, 0);
            if (rc == EO_OK) ok = 1;
            else bad += rc != EO_ERR_NOMEM;
            eo_gmg_destroy(ctx, &g);
            if (eo_ctx_live_bytes(ctx) != base) bad++;
        }
        printf("%s: create makes %ld context allocations; a failure at each one is clean\n", p ? "affine" : "linear",
               f - 2);
        CHECK(ok && bad == 0, "%s: injected failures: ok %d, bad %d", p ? "affine" : "linear", ok, bad);
    }
    hsys_free(&S);
}

/* A sheet of nodes in one plane strictly inside a layer of grid cubes: the trilinear
 * columns of the grid nodes just below and just above the plane are proportional on every
 * node they reach, so the composite prolongation loses column rank and the coarsest
 * Galerkin matrix is singular for an SPD A (the thin parts of real meshes: Spot's legs and
 * ears failed so). The hierarchy must drop the dependent coarsest nodes, set up on the SPD
 * matrix, and its V-cycle must still converge. A = (graph Laplacian of the 8-neighbour grid
 * + I) ⊗ I₃; node 0 lies one unit below the plane so that the plane is inside the cubes. */
static void flat_sheet(eo_ctx *ctx)
{
    const int m = 18, nv = m * m, n = 3 * nv;
    int nnz = 0;
    for (int j = 0; j < nv; j++) {
        const int xj = j % m, yj = j / m;
        for (int i = 0; i <= j; i++) {
            const int dx = abs(xj - i % m), dy = abs(yj - i / m);
            if (dx <= 1 && dy <= 1) nnz += 3;
        }
    }
    eo_csc *A = NULL;
    CHECK(eo_csc_create(ctx, n, nnz, &A) == EO_OK, "csc");
    if (!A) return;
    double *xyz = malloc((size_t)n * sizeof(double)), *b = malloc((size_t)n * sizeof(double));
    double *x = calloc((size_t)n, sizeof(double)), *r = malloc((size_t)n * sizeof(double)),
           *z = malloc((size_t)n * sizeof(double));
    int w = 0;
    for (int j = 0; j < nv; j++) {
        const int xj = j % m, yj = j / m;
        for (int c = 0; c < 3; c++) {
            A->colptr[3 * j + c] = w;
            for (int i = 0; i <= j; i++) {
                const int dx = abs(xj - i % m), dy = abs(yj - i / m);
                if (dx > 1 || dy > 1) continue;
                int deg = 0;
                for (int ex = -1; ex <= 1; ex++)
                    for (int ey = -1; ey <= 1; ey++)
                        deg += (ex || ey) && xj + ex >= 0 && xj + ex < m && yj + ey >= 0 && yj + ey < m;
                A->rowind[w] = 3 * i + c;
                A->val[w++] = i == j ? deg + 1.0 : -1.0;
            }
        }
        xyz[3 * j] = xj, xyz[3 * j + 1] = yj, xyz[3 * j + 2] = j == 0 ? -1.0 : 0.0;
    }
    A->colptr[n] = w;
    for (int i = 0; i < n; i++) b[i] = sin(0.37 * i) + 0.1;
    eo_gmg_opts o = {.prolongation = EO_GMG_LINEAR, .cell = 2, .coarse_size = 30, .max_levels = 6, .smooth_steps = 2,
                     .name = "gmg"};
    eo_gmg *g = NULL;
    eo_linsolve_stats st = {.not_pd_column = -1};
    int rc = eo_gmg_create(ctx, A, &o, nv, xyz, &g);
    CHECK(rc == EO_OK, "create: %s", eo_ctx_message(ctx));
    if (rc == EO_OK) {
        rc = eo_gmg_setup(g, A, &st, ctx);
        const int L = eo_gmg_levels(g), dropped = eo_gmg_dropped(g);
        printf("flat sheet, %d unknowns: %d levels, coarsest %d unknowns, %d coarsest nodes dropped as dependent\n", n,
               L, eo_gmg_level_n(g, L - 1), dropped);
        CHECK(L >= 3, "at least three levels: %d", L);
        CHECK(dropped > 0, "dependent coarsest nodes found: %d", dropped);
        CHECK(rc == EO_OK, "setup on an SPD matrix: rc %d (%s)", rc, eo_ctx_message(ctx));
    }
    if (rc == EO_OK) {
        double r0 = 0, rk = 0;
        for (int k = 0; k <= 30; k++) {
            eo_csc_symv(A, x, r);
            for (int i = 0; i < n; i++) r[i] = b[i] - r[i];
            if (k == 0) r0 = norm(n, r);
            rk = norm(n, r);
            eo_gmg_apply(g, r, z);
            for (int i = 0; i < n; i++) x[i] += z[i];
        }
        printf("flat sheet: 30 V-cycles reduce the residual by %.3g\n", rk / r0);
        CHECK(rk <= 1e-8 * r0, "V-cycles converge: %.3g", rk / r0);
    }
    eo_gmg_destroy(ctx, &g);
    eo_csc_destroy(&A);
    free(xyz);
    free(b);
    free(x);
    free(r);
    free(z);
}

/* ---------------------------------------------------------------- 2. V-cycle factor ---- */

/* geometric mean residual factor of cycles 6..15 of x += V(b − Ax) */
static double vcycle_factor(eo_ctx *ctx, const hsys *S, int prolongation, int *levels)
{
    eo_gmg_opts o = {.prolongation = prolongation, .cell = 2, .coarse_size = 200, .max_levels = 10,
                     .smooth_steps = 2, .name = "gmg"};
    eo_gmg *g = NULL;
    eo_linsolve_stats st = {.not_pd_column = -1};
    int rc = eo_gmg_create(ctx, S->H, &o, S->nv, S->xyz, &g);
    if (rc >= 0) rc = eo_gmg_setup(g, S->H, &st, ctx);
    CHECK(rc == EO_OK, "gmg setup: %s", eo_ctx_message(ctx));
    if (rc != EO_OK) {
        eo_gmg_destroy(ctx, &g);
        return INFINITY;
    }
    *levels = eo_gmg_levels(g);
    const int n = S->n;
    double *x = calloc((size_t)n, sizeof(double)), *r = malloc((size_t)n * sizeof(double)),
           *z = malloc((size_t)n * sizeof(double));
    double r5 = 0, r15 = 0;
    for (int k = 0; k <= 15; k++) {
        eo_csc_symv(S->H, x, r);
        for (int i = 0; i < n; i++) r[i] = S->b[i] - r[i];
        if (k == 5) r5 = norm(n, r);
        if (k == 15) r15 = norm(n, r);
        eo_gmg_apply(g, r, z);
        for (int i = 0; i < n; i++) x[i] += z[i];
    }
    free(x);
    free(r);
    free(z);
    eo_gmg_destroy(ctx, &g);
    return pow(r15 / r5, 0.1);
}

static void mesh_independence(eo_ctx *ctx)
{
    double f[2][3];
    for (int r = 0; r < 3; r++) {
        hsys S;
        CHECK(hsys_build(ctx, "cantilever", 1 << r, &S) >= 0, "cantilever x%d: %s", 1 << r, eo_ctx_message(ctx));
        for (int p = 0; p < 2; p++) {
            int lev = 0;
            f[p][r] = vcycle_factor(ctx, &S, p, &lev);
            printf("cantilever cells x%d (%d unknowns): %s coarse spaces, %d levels, V-cycle residual factor %.3f\n",
                   1 << r, S.n, p ? "affine" : "linear", lev, f[p][r]);
        }
        hsys_free(&S);
    }
    for (int r = 0; r < 3; r++) {
        CHECK(f[0][r] < 0.5, "linear: V-cycle factor %.3f < 0.5 at refinement %d", f[0][r], r);
        CHECK(f[1][r] < 0.9, "affine: V-cycle factor %.3f < 0.9 at refinement %d", f[1][r], r);
    }
    CHECK(f[0][2] <= 1.5 * f[0][0], "linear: factor grows at most 1.5x: %.3f -> %.3f", f[0][0], f[0][2]);
}

/* ---------------------------------------------------------------- 3. solves ----------- */

static void solve_newton_system(eo_ctx *ctx)
{
    hsys S;
    CHECK(hsys_build(ctx, "cantilever", 2, &S) >= 0, "cantilever x2: %s", eo_ctx_message(ctx));
    const char *cases[][3] = {{"pcg", "preconditioner", "gmg"}, {"gmg", NULL, NULL}, {"pcg", "preconditioner", "jacobi"}};
    int its[3] = {0, 0, 0};
    for (int c = 0; c < 3; c++) {
        const eo_linsolve_type *t = NULL;
        eo_linsolve_find(ctx, cases[c][0], &t);
        double params[64];
        eo_params_default(t->info.params, params);
        if (cases[c][1]) {
            const eo_param_desc *d = eo_params_find(t->info.params, cases[c][1]);
            snprintf((char *)params + d->offset, d->size, "%s", cases[c][2]);
        }
        *(double *)((char *)params + eo_params_find(t->info.params, "tol")->offset) = 1e-10;
        if (!cases[c][1]) /* standalone: a hierarchy as deep as in the preconditioner */
            (void)0;
        eo_linsolve *ls = NULL;
        double *x = malloc((size_t)S.n * sizeof(double));
        size_t live = 0;
        int rc = eo_linsolve_create(ctx, t, params, &ls);
        if (rc >= 0) rc = eo_linsolve_set_coordinates(ls, S.nv, S.xyz);
        if (rc >= 0) rc = eo_linsolve_analyze(ls, S.H);
        if (rc >= 0) {
            live = eo_ctx_live_bytes(ctx);
            rc = eo_linsolve_factor(ls, S.H);
        }
        if (rc >= 0) rc = eo_linsolve_solve(ls, S.b, x);
        CHECK(rc == EO_OK, "%s %s: rc %d: %s", cases[c][0], cases[c][2] ? cases[c][2] : "", rc, eo_ctx_message(ctx));
        CHECK(eo_ctx_live_bytes(ctx) == live, "%s: no context allocation in factor/solve", cases[c][0]);
        double res = rel_res(S.H, S.b, x);
        its[c] = eo_linsolve_get_stats(ls)->iterations;
        printf("cantilever x2 Newton system (%d unknowns): %s %s: %d iterations, true relative residual %.3g\n", S.n,
               cases[c][0], cases[c][2] ? cases[c][2] : "", its[c], res);
        CHECK(res <= 1e-10 * 1.0001, "%s: residual %g <= 1e-10", cases[c][0], res);
        free(x);
        eo_linsolve_destroy(&ls);
    }
    CHECK(its[0] * 10 < its[2], "pcg+gmg needs far fewer iterations than pcg+jacobi: %d vs %d", its[0], its[2]);
    hsys_free(&S);
}

/* ---------------------------------------------------------------- 4. Newton ----------- */

static int run(eo_ctx *ctx, const char *scene, const char *const *ov, int steps, double **x, int *nv, long *lin)
{
    eo_sim *s = NULL;
    int rc = eo_test_sim_open(&s, ctx, scene, NULL, ov);
    if (rc < 0) return rc;
    int conv = 1;
    *lin = 0;
    for (int k = 0; k < steps && rc >= 0; k++) {
        eo_sim_step_result r;
        rc = eo_test_sim_step(s, NULL, NULL, &r);
        if (rc >= 0 && r.reason <= 0) conv = 0;
    }
    const eo_mesh *m = eo_step_mesh(eo_sim_step_problem(s));
    *nv = m->nv;
    *x = malloc((size_t)3 * m->nv * sizeof(double));
    eo_sim_get_state(s, *x, NULL, NULL, NULL);
    eo_sim_destroy(&s);
    return rc < 0 ? rc : conv;
}

/* max |x − y| / max |y − X| */
static double rel_diff(const double *x, const double *y, const double *X, int n)
{
    double d = 0, m = 0;
    for (int i = 0; i < n; i++) {
        d = fmax(d, fabs(x[i] - y[i]));
        m = fmax(m, fabs(y[i] - X[i]));
    }
    return m > 0 ? d / m : d;
}

static void same_minimizer(eo_ctx *ctx, const char *scene, const char *cells, int steps)
{
    const char *ref[] = {cells, "solver.fallback=[]", "solver.linear=cholmod", "solver.stop=gradient",
                         "solver.tol=1e-10", NULL};
    const char *rest[] = {cells, NULL};
    double *xr = NULL, *X = NULL;
    int nv = 0;
    long lin;
    int rc = run(ctx, scene, ref, steps, &xr, &nv, &lin);
    CHECK(rc == 1, "%s: cholmod reference converged: %s", scene, eo_ctx_message(ctx));
    run(ctx, scene, rest, 0, &X, &nv, &lin);
    const char *variants[][4] = {
        {"solver.linear=pcg", "solver.pcg.preconditioner=gmg", "solver.newton.forcing=ew2", "solver.pcg.tol=1e-12"},
        {"solver.linear=pcg", "solver.pcg.preconditioner=gmg", "solver.pcg.gmg_prolongation=affine",
         "solver.newton.forcing=ew2"},
        {"solver.linear=gmg", "solver.gmg.tol=1e-12", "solver.newton.forcing=none", NULL},
    };
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        const char *ov[12] = {cells, "solver.fallback=[]", "solver.stop=gradient", "solver.tol=1e-10"};
        int j = 4;
        for (int q = 0; q < 4 && variants[v][q]; q++) ov[j++] = variants[v][q];
        ov[j] = NULL;
        double *x = NULL;
        rc = run(ctx, scene, ov, steps, &x, &nv, &lin);
        CHECK(rc == 1, "%s %s %s: converged: rc %d %s", scene, variants[v][1], variants[v][2], rc, eo_ctx_message(ctx));
        double e = rc >= 0 ? rel_diff(x, xr, X, 3 * nv) : INFINITY;
        printf("%s %s (%d steps): %s %s: rel. difference to cholmod %.3g\n", scene, cells, steps, variants[v][1],
               variants[v][2], e);
        CHECK(e <= 1e-8, "%s %s %s: same minimizer as cholmod: %.3g", scene, variants[v][1], variants[v][2], e);
        free(x);
    }
    free(xr);
    free(X);
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    galerkin_dense(ctx, EO_GMG_LINEAR);
    galerkin_dense(ctx, EO_GMG_AFFINE);
    create_failures(ctx);
    flat_sheet(ctx);
    mesh_independence(ctx);
    solve_newton_system(ctx);
    same_minimizer(ctx, "cantilever", "mesh.generate.cells=[40,4,4]", 3);
    same_minimizer(ctx, "twist", "mesh.generate.cells=[40,4,4]", 2);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_gmg");
}
