/* 2D Poisson FEM (suite 'unit', notes 001 §3–4): −Δu = 2π² sin(πx) sin(πy) on the unit
 * square, u = 0 on the boundary, linear triangles, exposed as g(u) = ½uᵀKu − Fᵀu.
 *
 *  - K is symmetric positive definite with the 5-point stencil on the structured mesh
 *    (diagonal 4, the four grid neighbours −1, the diagonal-edge couplings exactly 0);
 *  - O(h²) convergence: the L2 error for n = 8, 16, 32, 64 halves twice per refinement,
 *    measured rates 2 ± 0.15 (three refinements), max nodal error decreasing too;
 *  - every registered linear solver under Newton (cholmod, cholmod_ldlt, spqr, lapack,
 *    cg, pcg, gauss_seidel, sor, jacobi, ...) reaches the CHOLMOD solution to 1e-8, or
 *    (jacobi is allowed this) reports a negative reason cleanly;
 *  - every registered optimizer (newton, gradient_descent with exact line search,
 *    lbfgs, projective_dynamics, nlopt/ipopt when built) reaches it to 1e-8;
 *  - steepest descent with exact line search (001 eq. 62): the iteration count grows
 *    with n (the condition number of K grows like n²);
 *  - the notes' Fig. 2 two-triangle assembly (element 1 = nodes 1 2 3, element 2 = nodes
 *    2 4 3 of the unit square, no Dirichlet nodes): the exact 4×4 K (diagonal 1,
 *    K12 = K13 = K24 = K34 = −½, K14 = K23 = 0) and, for f = 1, F = (1/6, 1/3, 1/3, 1/6)
 *    with both quadratures;
 *  - quadrature: the centroid rule (001 eq. 50) and the midpoint rule give the same F
 *    for constant f and different F for the sine source; both converge at L2 rate 2 ± 0.15;
 *  - Gmsh 2D meshes written by the test (.msh 2.2 with line and point elements, .msh 4.1
 *    with $Entities and several blocks): the same mesh from both, the same solution
 *    as the built-in square; the unit square with perturbed interior nodes and
 *    alternating diagonals at n = 8, 16, 32: L2 rates 2 ± 0.2;
 *  - non-square domains read from .msh 4.1: an L-shape (−1,1)² \ [0,1)×(−1,0] with
 *    u = sin(πx) sin(πy), and a disk (rings of 6k nodes) with the harmonic
 *    u = eˣ sin y (f = 0, nonhomogeneous Dirichlet data): L2 rates 2 ± 0.25;
 *  - the VTU of triangles: header counts, cell type 5 and the u array read back equal
 *    to the nodal solution. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/io.h"
#include "elastopt/poisson.h"
#include "elastopt/impl/method.h"
#include "testutil.h"

/* Solve with overrides; u (n) out. Returns the reason (0 on setup error). */
static int solve(eo_ctx *ctx, eo_poisson *p, const char *const *ov, double *u, int *iters)
{
    eo_cfg *cfg = NULL;
    eo_solver *s = NULL;
    eo_solver_opts so;
    eo_solver_opts_default(&so);
    eo_objective *obj = eo_poisson_objective(p);
    int rc = eo_cfg_create_empty(ctx, &cfg);
    for (const char *const *o = ov; rc >= 0 && *o; o++) rc = eo_cfg_override(ctx, cfg, *o);
    static const char *const top[] = {"solver", NULL};
    if (rc >= 0) eo_cfg_expect(cfg, "", top);
    if (rc >= 0) rc = eo_solver_opts_load(ctx, cfg, &so);
    if (rc >= 0) rc = eo_solver_create(ctx, &so, cfg, &s);
    if (rc >= 0) rc = eo_cfg_finish(ctx, cfg);
    eo_solve_result r;
    memset(&r, 0, sizeof r);
    memset(u, 0, (size_t)obj->n * sizeof(double));
    if (rc >= 0) rc = eo_solver_minimize(s, obj, u, NULL, NULL, &r);
    if (rc < 0) fprintf(stderr, "solve: %s\n", eo_ctx_message(ctx));
    eo_solver_destroy(&s);
    eo_cfg_destroy(&cfg);
    if (iters) *iters = r.iterations;
    return rc < 0 ? 0 : r.reason;
}

static void test_matrix(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_poisson *p;
    CHECK(eo_poisson_create(ctx, 6, &p) == 0, "create");
    const eo_csc *K = eo_poisson_matrix(p);
    int n = K->n, bad = 0;
    double *D = malloc((size_t)n * n * sizeof(double));
    eo_csc_to_dense(K, D);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            int di = abs(i % 5 - j % 5) + abs(i / 5 - j / 5);
            double expect = i == j ? 4 : di == 1 ? -1 : 0;
            bad += fabs(D[i * n + j] - expect) > 1e-12;
        }
    CHECK(n == 25 && bad == 0, "5-point stencil: %d wrong entries", bad);
    free(D);
    eo_poisson *q = NULL;
    CHECK(eo_poisson_create(ctx, 1, &q) == EO_ERR_INVALID && q == NULL, "n = 1 rejected");
    eo_poisson_destroy(&p);
    eo_test_ctx_done(&ctx);
}

static void test_convergence(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const int ns[4] = {8, 16, 32, 64};
    double l2[4], mx[4];
    const char *ov[] = {"solver.tol=1e-24", NULL};
    for (int k = 0; k < 4; k++) {
        eo_poisson *p;
        CHECK(eo_poisson_create(ctx, ns[k], &p) == 0, "create");
        double *u = malloc((size_t)eo_poisson_objective(p)->n * sizeof(double));
        CHECK(solve(ctx, p, ov, u, NULL) > 0, "solve n = %d", ns[k]);
        eo_poisson_error(p, u, &l2[k], &mx[k]);
        free(u);
        eo_poisson_destroy(&p);
    }
    printf("Poisson L2 / max errors:");
    for (int k = 0; k < 4; k++) printf(" n=%d %.4e / %.4e;", ns[k], l2[k], mx[k]);
    printf("\n  L2 rates:");
    for (int k = 1; k < 4; k++) {
        double rate = log2(l2[k - 1] / l2[k]);
        printf(" %.4f", rate);
        CHECK(fabs(rate - 2) <= 0.15, "L2 rate n = %d -> %d: %g", ns[k - 1], ns[k], rate);
        CHECK(mx[k] < mx[k - 1], "max error decreases");
    }
    printf("\n");
    eo_test_ctx_done(&ctx);
}

static double maxdiff(int n, const double *a, const double *b)
{
    double d = 0;
    for (int i = 0; i < n; i++) d = fmax(d, fabs(a[i] - b[i]));
    return d;
}

static void test_solvers(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_poisson *p;
    CHECK(eo_poisson_create(ctx, 16, &p) == 0, "create");
    int n = eo_poisson_objective(p)->n, it;
    double *ref = malloc((size_t)n * sizeof(double)), *u = malloc((size_t)n * sizeof(double));
    const char *ovr[] = {"solver.linear=cholmod", "solver.tol=1e-26", NULL};
    CHECK(solve(ctx, p, ovr, ref, NULL) > 0, "reference");
    printf("linear solvers under newton (n = 16, %d unknowns):\n", n);
    for (const void *const *t = eo_registry_list(EO_KIND_LINSOLVE); *t; t++) {
        const char *name = eo_method_info_of(*t)->name;
        char o1[64];
        snprintf(o1, sizeof o1, "solver.linear=%s", name);
        const char *ov[] = {o1, "solver.tol=1e-22", "solver.max_iters=200", NULL};
        int reason = solve(ctx, p, ov, u, &it);
        double d = maxdiff(n, u, ref);
        printf("  %-14s %-22s %3d newton iterations  max |u - u_ref| %.2e\n", name, eo_reason_name(reason), it, d);
        if (strcmp(name, "jacobi") == 0 && reason < 0) {
            CHECK(reason != 0, "jacobi reports cleanly");
            continue;
        }
        CHECK(reason > 0, "%s: %s", name, eo_reason_name(reason));
        CHECK(d < 1e-8, "%s: distance %g", name, d);
    }
    printf("optimizers (n = 16):\n");
    for (const void *const *t = eo_registry_list(EO_KIND_OPTIMIZER); *t; t++) {
        const char *name = eo_method_info_of(*t)->name;
        char o1[64];
        snprintf(o1, sizeof o1, "solver.optimizer=%s", name);
        int newton_like = strcmp(name, "newton") == 0;
        const char *ov[] = {o1, newton_like ? "solver.stop=newton_decrement" : "solver.stop=gradient",
                            newton_like ? "solver.tol=1e-22" : "solver.tol=1e-13",
                            strcmp(name, "gradient_descent") == 0 ? "solver.linesearch=exact"
                            : strcmp(name, "ncg") == 0            ? "solver.linesearch=wolfe"
                                                                  : "solver.linesearch=backtracking",
                            "solver.max_iters=100000", "solver.nlopt.algorithm=tnewton", NULL};
        /* (nlopt: its L-BFGS ends with NLOPT_FTOL_REACHED near 3e-8 from the solution even
         * with ftol_rel = 0; the preconditioned truncated Newton reaches 1e-10 gradients) */
        int reason = solve(ctx, p, ov, u, &it);
        double d = maxdiff(n, u, ref);
        if (strcmp(name, "fixed_point") == 0) { /* needs a step objective's mass matrix */
            printf("  %-20s not applicable (no mass matrix): refused\n", name);
            CHECK(reason == 0 && strstr(eo_ctx_message(ctx), "mass matrix"), "fixed_point refuses: %s",
                  eo_ctx_message(ctx));
            continue;
        }
        if (strcmp(name, "admm_pd") == 0 || strcmp(name, "mixed_fem") == 0 ||
            strcmp(name, "vbd") == 0) { /* need a step objective's elements */
            const char *what = strcmp(name, "vbd") == 0 ? "vertex blocks" : "elastic elements";
            printf("  %-20s not applicable (no %s): refused\n", name, what);
            CHECK(reason == 0 && strstr(eo_ctx_message(ctx), what), "%s refuses: %s", name,
                  eo_ctx_message(ctx));
            continue;
        }
        printf("  %-20s %-26s %6d iterations  max |u - u_ref| %.2e\n", name, eo_reason_name(reason), it, d);
        CHECK(reason > 0, "%s: %s", name, eo_reason_name(reason));
        CHECK(d < 1e-8, "%s: distance %g", name, d);
    }
    free(ref);
    free(u);
    eo_poisson_destroy(&p);
    eo_test_ctx_done(&ctx);
}

static void test_steepest_descent(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const int ns[3] = {4, 8, 16};
    int its[3];
    const char *ov[] = {"solver.optimizer=gradient_descent", "solver.linesearch=exact", "solver.stop=gradient",
                        "solver.tol=1e-8", "solver.max_iters=100000", NULL};
    printf("steepest descent, exact line search, |grad| <= 1e-8 |grad0|:");
    for (int k = 0; k < 3; k++) {
        eo_poisson *p;
        CHECK(eo_poisson_create(ctx, ns[k], &p) == 0, "create");
        double *u = malloc((size_t)eo_poisson_objective(p)->n * sizeof(double));
        int reason = solve(ctx, p, ov, u, &its[k]);
        CHECK(reason > 0, "n = %d: %s", ns[k], eo_reason_name(reason));
        printf(" n=%d: %d iterations;", ns[k], its[k]);
        free(u);
        eo_poisson_destroy(&p);
    }
    printf("\n");
    CHECK(its[1] > 2 * its[0] && its[2] > 2 * its[1], "iterations grow with n (condition ~ n^2): %d %d %d", its[0],
          its[1], its[2]);
    eo_test_ctx_done(&ctx);
}


static double one_f(void *d, double x, double y)
{
    (void)d, (void)x, (void)y;
    return 1;
}

static void test_fig2(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_trimesh *m;
    CHECK(eo_trimesh_create(ctx, 4, 2, &m) == 0, "mesh");
    const double xy[8] = {0, 0, 1, 0, 0, 1, 1, 1};
    const int tri[6] = {0, 1, 2, 1, 3, 2}; /* Fig. 2: element 2's local 1, 2, 3 = global 2, 4, 3 */
    memcpy(m->xy, xy, sizeof xy);
    memcpy(m->tri, tri, sizeof tri);
    static const eo_poisson_problem one = {.f = one_f, .u = NULL, .data = NULL};
    const double Kx[16] = {1, -0.5, -0.5, 0, -0.5, 1, 0, -0.5, -0.5, 0, 1, -0.5, 0, -0.5, -0.5, 1};
    for (int q = 0; q < 2; q++) {
        eo_poisson_opts o;
        eo_poisson_opts_default(&o);
        o.dirichlet = 0;
        o.problem = &one;
        o.quadrature = q ? EO_POISSON_QUAD_CENTROID : EO_POISSON_QUAD_MIDPOINT;
        eo_poisson *p;
        CHECK(eo_poisson_create_mesh(ctx, m, &o, &p) == 0, "create");
        const eo_csc *K = eo_poisson_matrix(p);
        double D[16];
        CHECK(K->n == 4, "4 unknowns");
        eo_csc_to_dense(K, D);
        int bad = 0;
        for (int i = 0; i < 16; i++) bad += fabs(D[i] - Kx[i]) > 1e-15;
        CHECK(bad == 0, "Fig. 2 K: %d wrong entries (%s)", bad, eo_poisson_quadrature_name(o.quadrature));
        const double *F = eo_poisson_load(p), Fx[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
        for (int i = 0; i < 4; i++) CHECK(fabs(F[i] - Fx[i]) < 1e-15, "F[%d] = %.17g, expected %.17g", i, F[i], Fx[i]);
        eo_poisson_destroy(&p);
    }
    /* with Dirichlet on: every node of the two triangles is on the boundary */
    eo_poisson *p = NULL;
    CHECK(eo_poisson_create_mesh(ctx, m, NULL, &p) == EO_ERR_MESH && !p, "no free node rejected");
    eo_trimesh_destroy(&m);
    eo_test_ctx_done(&ctx);
}

static void test_quadrature(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static const eo_poisson_problem one = {.f = one_f, .u = NULL, .data = NULL};
    eo_poisson_opts o;
    eo_poisson_opts_default(&o);
    eo_poisson *a, *b;
    o.problem = &one;
    CHECK(eo_poisson_create_opts(ctx, 8, &o, &a) == 0, "midpoint");
    o.quadrature = EO_POISSON_QUAD_CENTROID;
    CHECK(eo_poisson_create_opts(ctx, 8, &o, &b) == 0, "centroid");
    int n = eo_poisson_objective(a)->n;
    CHECK(maxdiff(n, eo_poisson_load(a), eo_poisson_load(b)) < 1e-15, "constant f: same F");
    eo_poisson_destroy(&a);
    eo_poisson_destroy(&b);
    eo_poisson_opts_default(&o);
    CHECK(eo_poisson_create_opts(ctx, 8, &o, &a) == 0, "midpoint");
    o.quadrature = EO_POISSON_QUAD_CENTROID;
    CHECK(eo_poisson_create_opts(ctx, 8, &o, &b) == 0, "centroid");
    double d = maxdiff(n, eo_poisson_load(a), eo_poisson_load(b));
    CHECK(d > 1e-4, "sine f: F differs by %g", d);
    eo_poisson_destroy(&a);
    eo_poisson_destroy(&b);
    eo_poisson_quadrature q;
    CHECK(eo_poisson_quadrature_parse(ctx, "centroid", &q) == 0 && q == EO_POISSON_QUAD_CENTROID, "parse");
    CHECK(eo_poisson_quadrature_parse(ctx, "gauss", &q) == EO_ERR_UNKNOWN_NAME, "unknown rejected");
    /* both rules: O(h²) */
    const char *ov[] = {"solver.tol=1e-24", NULL};
    for (int r = 0; r < 2; r++) {
        double l2[3], mx;
        printf("quadrature %s: L2", r ? "centroid" : "midpoint");
        for (int k = 0; k < 3; k++) {
            eo_poisson_opts_default(&o);
            o.quadrature = r ? EO_POISSON_QUAD_CENTROID : EO_POISSON_QUAD_MIDPOINT;
            eo_poisson *p;
            CHECK(eo_poisson_create_opts(ctx, 8 << k, &o, &p) == 0, "create");
            double *u = malloc((size_t)eo_poisson_objective(p)->n * sizeof(double));
            CHECK(solve(ctx, p, ov, u, NULL) > 0, "solve");
            eo_poisson_error(p, u, &l2[k], &mx);
            printf(" n=%d %.4e", 8 << k, l2[k]);
            if (k) CHECK(fabs(log2(l2[k - 1] / l2[k]) - 2) <= 0.15, "rate %g", log2(l2[k - 1] / l2[k]));
            free(u);
            eo_poisson_destroy(&p);
        }
        printf("\n");
    }
    eo_test_ctx_done(&ctx);
}

/* ---- Gmsh files written by the test ---- */

typedef struct {
    int nv, nt;
    double *xy;
    int *tri;
} tmesh;

static void tmesh_free(tmesh *m)
{
    free(m->xy);
    free(m->tri);
}

/* unit square, n×n cells, alternating diagonals, interior nodes perturbed by ±0.15 h */
static tmesh square_mesh(int n)
{
    tmesh m = {(n + 1) * (n + 1), 2 * n * n, NULL, NULL};
    m.xy = malloc(2 * (size_t)m.nv * sizeof(double));
    m.tri = malloc(3 * (size_t)m.nt * sizeof(int));
    eo_test_seed(11);
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            int v = j * (n + 1) + i, in = i > 0 && i < n && j > 0 && j < n;
            m.xy[2 * v] = (i + (in ? eo_test_rand(-0.15, 0.15) : 0)) / n;
            m.xy[2 * v + 1] = (j + (in ? eo_test_rand(-0.15, 0.15) : 0)) / n;
        }
    int t = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            int T[2][3] = {{a, b, c}, {a, c, d}}, U[2][3] = {{a, b, d}, {b, c, d}};
            for (int k = 0; k < 2; k++, t++)
                for (int q = 0; q < 3; q++) m.tri[3 * t + q] = (i + j) % 2 ? U[k][q] : T[k][q];
        }
    return m;
}

/* L-shape (−1,1)² minus [0,1)×(−1,0]: the square grid of (−1,1)² with 2n cells per side,
 * cells in the removed quadrant dropped, unused nodes kept out (renumbered). */
static tmesh lshape_mesh(int n)
{
    int N = 2 * n, nn = (N + 1) * (N + 1);
    int *id = malloc((size_t)nn * sizeof(int));
    tmesh m = {0, 0, malloc(2 * (size_t)nn * sizeof(double)), malloc(6 * (size_t)N * N * sizeof(int))};
    for (int v = 0; v < nn; v++) id[v] = -1;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            if (i >= n && j < n) continue; /* x >= 0, y < 0 */
            int a = j * (N + 1) + i, b = a + 1, c = a + N + 2, d = a + N + 1;
            int T[2][3] = {{a, b, c}, {a, c, d}};
            for (int k = 0; k < 2; k++, m.nt++)
                for (int q = 0; q < 3; q++) {
                    int v = T[k][q];
                    if (id[v] < 0) {
                        id[v] = m.nv++;
                        m.xy[2 * id[v]] = -1 + (double)(v % (N + 1)) / n;
                        m.xy[2 * id[v] + 1] = -1 + (double)(v / (N + 1)) / n;
                    }
                    m.tri[3 * m.nt + q] = id[v];
                }
        }
    free(id);
    return m;
}

/* unit disk: centre + rings k = 1..N of 6k nodes at radius k/N */
static tmesh disk_mesh(int N)
{
    tmesh m = {1 + 3 * N * (N + 1), 6 * N * N, NULL, NULL};
    m.xy = malloc(2 * (size_t)m.nv * sizeof(double));
    m.tri = malloc(3 * (size_t)m.nt * sizeof(int));
    const double PI = 3.14159265358979323846;
    m.xy[0] = m.xy[1] = 0;
    for (int k = 1, v = 1; k <= N; k++)
        for (int j = 0; j < 6 * k; j++, v++) {
            double th = 2 * PI * j / (6 * k) + 0.1 * k; /* a twist per ring: no radial lines */
            m.xy[2 * v] = (double)k / N * cos(th);
            m.xy[2 * v + 1] = (double)k / N * sin(th);
        }
    int t = 0;
    for (int k = 1; k <= N; k++) {
        int M = 6 * k, o0 = 1 + 3 * k * (k - 1), mi = k == 1 ? 1 : 6 * (k - 1), i0 = k == 1 ? 0 : 1 + 3 * (k - 1) * (k - 2);
        double tin = k == 1 ? 0 : 0.1 * (k - 1), tout = 0.1 * k;
        /* merge walk by angle (unwrapped relative to the outer ring's node 0) */
        int i = 0;
        double ain0 = 0;
        if (k > 1) { /* start the inner ring at the node nearest (not after) outer angle 0 */
            double best = 1e9;
            for (int q = 0; q < mi; q++) {
                double a = fmod(2 * PI * q / mi + tin - tout + 4 * PI, 2 * PI);
                if (a > PI) a -= 2 * PI;
                if (a <= 0 && -a < best) best = -a, ain0 = a, i = q;
            }
        }
        int istart = i, ni = 0, nj = 0;
        while (ni < (k == 1 ? 0 : mi) || nj < M) {
            int a = k == 1 ? i0 : i0 + (istart + ni) % mi;
            int an = k == 1 ? i0 : i0 + (istart + ni + 1) % mi;
            int b = o0 + nj % M, bn = o0 + (nj + 1) % M;
            double next_in = ain0 + 2 * PI * (ni + 1) / mi, next_out = 2 * PI * (nj + 1) / M;
            if (k > 1 && ni < mi && (nj >= M || next_in < next_out)) {
                m.tri[3 * t] = a, m.tri[3 * t + 1] = an, m.tri[3 * t + 2] = b;
                ni++;
            } else {
                m.tri[3 * t] = a, m.tri[3 * t + 1] = b, m.tri[3 * t + 2] = bn;
                nj++;
            }
            t++;
        }
    }
    m.nt = t;
    return m;
}

/* Write .msh 2.2 (with boundary lines and a point element) or 4.1 (with $Entities, the
 * nodes in two blocks, a line block before the triangle block). Node tags 1-based + 100. */
static int write_msh(const char *path, int v41, const tmesh *m)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    const int T = 100;
    if (!v41) {
        fprintf(f, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"domain\"\n$EndPhysicalNames\n");
        fprintf(f, "$Nodes\n%d\n", m->nv);
        for (int v = 0; v < m->nv; v++) fprintf(f, "%d %.17g %.17g 0\n", v + T, m->xy[2 * v], m->xy[2 * v + 1]);
        fprintf(f, "$EndNodes\n$Elements\n%d\n", m->nt + 2);
        fprintf(f, "1 15 2 0 1 %d\n", T);
        fprintf(f, "2 1 2 0 1 %d %d\n", m->tri[0] + T, m->tri[1] + T);
        for (int t = 0; t < m->nt; t++)
            fprintf(f, "%d 2 2 1 1 %d %d %d\n", t + 3, m->tri[3 * t] + T, m->tri[3 * t + 1] + T, m->tri[3 * t + 2] + T);
        fprintf(f, "$EndElements\n");
    } else {
        int h = m->nv / 2;
        fprintf(f, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 1 0\n1 -1 -1 0 1 1 0 0 0\n$EndEntities\n");
        fprintf(f, "$Nodes\n2 %d %d %d\n", m->nv, T, m->nv - 1 + T);
        fprintf(f, "2 1 0 %d\n", h);
        for (int v = 0; v < h; v++) fprintf(f, "%d\n", v + T);
        for (int v = 0; v < h; v++) fprintf(f, "%.17g %.17g 0\n", m->xy[2 * v], m->xy[2 * v + 1]);
        fprintf(f, "2 1 1 %d\n", m->nv - h);
        for (int v = h; v < m->nv; v++) fprintf(f, "%d\n", v + T);
        for (int v = h; v < m->nv; v++) fprintf(f, "%.17g %.17g 0 0.5 0.5\n", m->xy[2 * v], m->xy[2 * v + 1]);
        fprintf(f, "$EndNodes\n$Elements\n2 %d 1 %d\n", m->nt + 1, m->nt + 1);
        fprintf(f, "1 1 1 1\n1 %d %d\n", m->tri[0] + T, m->tri[1] + T);
        fprintf(f, "2 1 2 %d\n", m->nt);
        for (int t = 0; t < m->nt; t++)
            fprintf(f, "%d %d %d %d\n", t + 2, m->tri[3 * t] + T, m->tri[3 * t + 1] + T, m->tri[3 * t + 2] + T);
        fprintf(f, "$EndElements\n");
    }
    return fclose(f);
}

/* read a written mesh back, solve, L2 error and h */
static int solve_msh(eo_ctx *ctx, const char *path, const eo_poisson_problem *pr, double *l2, double *h,
                     eo_trimesh **keep)
{
    eo_trimesh *m = NULL;
    eo_poisson *p = NULL;
    int rc = eo_trimesh_read_gmsh(ctx, path, &m);
    if (rc < 0) {
        fprintf(stderr, "read %s: %s\n", path, eo_ctx_message(ctx));
        return rc;
    }
    eo_poisson_opts o;
    eo_poisson_opts_default(&o);
    o.problem = pr;
    rc = eo_poisson_create_mesh(ctx, m, &o, &p);
    if (rc == 0) {
        const char *ov[] = {"solver.tol=1e-24", NULL};
        double *u = malloc((size_t)eo_poisson_objective(p)->n * sizeof(double)), mx;
        rc = solve(ctx, p, ov, u, NULL) > 0 ? 0 : -1;
        if (rc == 0) rc = eo_poisson_error(p, u, l2, &mx);
        *h = eo_poisson_h(p);
        free(u);
    } else {
        fprintf(stderr, "poisson %s: %s\n", path, eo_ctx_message(ctx));
    }
    eo_poisson_destroy(&p);
    if (keep) *keep = m;
    else eo_trimesh_destroy(&m);
    return rc;
}

static const double PI_ = 3.14159265358979323846;
static double sine_u(void *d, double x, double y)
{
    (void)d;
    return sin(PI_ * x) * sin(PI_ * y);
}
static double sine_f(void *d, double x, double y) { return 2 * PI_ * PI_ * sine_u(d, x, y); }
static double harm_u(void *d, double x, double y)
{
    (void)d;
    return exp(x) * sin(y);
}
static double zero_f(void *d, double x, double y)
{
    (void)d, (void)x, (void)y;
    return 0;
}

static void rates(const char *what, int nk, const double *l2, const double *h, double tol)
{
    printf("%s: L2", what);
    for (int k = 0; k < nk; k++) printf(" h=%.4f %.4e", h[k], l2[k]);
    printf("; rates");
    for (int k = 1; k < nk; k++) {
        double r = log(l2[k - 1] / l2[k]) / log(h[k - 1] / h[k]);
        printf(" %.3f", r);
        CHECK(fabs(r - 2) <= tol, "%s: rate %g", what, r);
    }
    printf("\n");
}

static void test_gmsh(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *dir = eo_test_tmpdir("test_poisson_gmsh");
    char path[1024], path2[1024];
    static const eo_poisson_problem sine = {.f = sine_f, .u = sine_u};
    static const eo_poisson_problem harm = {.f = zero_f, .u = harm_u};
    /* the built-in square through both file versions: identical meshes and errors */
    {
        eo_poisson *ref;
        CHECK(eo_poisson_create(ctx, 8, &ref) == 0, "square");
        const eo_trimesh *rm = eo_poisson_mesh(ref);
        tmesh t = {rm->nv, rm->nt, (double *)rm->xy, (int *)rm->tri};
        snprintf(path, sizeof path, "%s/sq22.msh", dir);
        snprintf(path2, sizeof path2, "%s/sq41.msh", dir);
        CHECK(write_msh(path, 0, &t) == 0 && write_msh(path2, 1, &t) == 0, "write");
        eo_trimesh *a = NULL, *b = NULL;
        double la, lb, ha, hb;
        CHECK(solve_msh(ctx, path, NULL, &la, &ha, &a) == 0, "2.2");
        CHECK(solve_msh(ctx, path2, NULL, &lb, &hb, &b) == 0, "4.1");
        if (a && b) {
            CHECK(a->nv == rm->nv && a->nt == rm->nt && b->nv == rm->nv && b->nt == rm->nt, "sizes");
            CHECK(!memcmp(a->tri, rm->tri, 3 * sizeof(int) * rm->nt) && !memcmp(b->tri, rm->tri, 3 * sizeof(int) * rm->nt),
                  "triangles");
            CHECK(!memcmp(a->xy, rm->xy, 2 * sizeof(double) * rm->nv) && !memcmp(b->xy, rm->xy, 2 * sizeof(double) * rm->nv),
                  "nodes");
        }
        double *u = malloc((size_t)eo_poisson_objective(ref)->n * sizeof(double)), l, mx;
        const char *ov[] = {"solver.tol=1e-24", NULL};
        CHECK(solve(ctx, ref, ov, u, NULL) > 0, "solve");
        eo_poisson_error(ref, u, &l, &mx);
        CHECK(fabs(la - l) < 1e-12 && fabs(lb - l) < 1e-12, "same L2 error %g %g %g", la, lb, l);
        /* VTU of triangles read back */
        snprintf(path, sizeof path, "%s/u.vtu", dir);
        CHECK(eo_poisson_write_vtu(ref, u, path) == 0, "vtu");
        char *text = NULL;
        size_t len = 0;
        CHECK(eo_read_file(ctx, path, &text, &len) == 0, "read vtu");
        if (text) {
            char want[96];
            snprintf(want, sizeof want, "NumberOfPoints=\"%d\" NumberOfCells=\"%d\"", rm->nv, rm->nt);
            CHECK(strstr(text, want) != NULL, "vtu counts");
            const char *us = strstr(text, "   _");
            if (us) {
                us += 4;
                unsigned long long nb;
                memcpy(&nb, us, 8);
                CHECK(nb == 8ull * (unsigned long long)rm->nv, "u bytes %llu", nb);
                double *nod = malloc((size_t)rm->nv * sizeof(double));
                eo_poisson_nodal(ref, u, nod);
                CHECK(!memcmp(us + 8, nod, 8 * (size_t)rm->nv), "u array = nodal solution");
                /* after u: points, connectivity, offsets, then the nt cell types */
                const unsigned char *ty = (const unsigned char *)us + 8 + 8 * (size_t)rm->nv + 8 + 24 * (size_t)rm->nv +
                                          8 + 24 * (size_t)rm->nt + 8 + 8 * (size_t)rm->nt;
                unsigned long long nty;
                memcpy(&nty, ty, 8);
                int ok = nty == (unsigned long long)rm->nt && (const char *)ty + 8 + rm->nt < text + len;
                for (int t2 = 0; ok && t2 < rm->nt; t2++) ok = ty[8 + t2] == 5;
                CHECK(ok, "cell types 5");
                free(nod);
            } else {
                CHECK(0, "no appended data");
            }
            eo_free(ctx, text);
        }
        free(u);
        eo_trimesh_destroy(&a);
        eo_trimesh_destroy(&b);
        eo_poisson_destroy(&ref);
    }
    /* perturbed unit square, both versions alternately */
    double l2[3], h[3];
    for (int k = 0; k < 3; k++) {
        tmesh m = square_mesh(8 << k);
        snprintf(path, sizeof path, "%s/square%d.msh", dir, k);
        CHECK(write_msh(path, k % 2, &m) == 0, "write");
        CHECK(solve_msh(ctx, path, &sine, &l2[k], &h[k], NULL) == 0, "solve %s", path);
        tmesh_free(&m);
    }
    rates("gmsh unit square (perturbed)", 3, l2, h, 0.2);
    for (int k = 0; k < 3; k++) {
        tmesh m = lshape_mesh(4 << k);
        snprintf(path, sizeof path, "%s/lshape%d.msh", dir, k);
        CHECK(write_msh(path, 1, &m) == 0, "write");
        CHECK(solve_msh(ctx, path, &sine, &l2[k], &h[k], NULL) == 0, "solve %s", path);
        tmesh_free(&m);
    }
    rates("gmsh L-shape, u = sin(pi x) sin(pi y)", 3, l2, h, 0.25);
    for (int k = 0; k < 3; k++) {
        tmesh m = disk_mesh(4 << k);
        int N = 4 << k, nb = 0;
        double area = 0;
        for (int t = 0; t < m.nt; t++) {
            const double *a = m.xy + 2 * m.tri[3 * t], *b = m.xy + 2 * m.tri[3 * t + 1], *c = m.xy + 2 * m.tri[3 * t + 2];
            area += 0.5 * fabs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
        }
        eo_trimesh tm = {m.nv, m.nt, m.xy, m.tri, NULL};
        unsigned char *fl = malloc((size_t)m.nv);
        CHECK(eo_trimesh_boundary(ctx, &tm, fl) == 0, "boundary");
        for (int v = 0; v < m.nv; v++) nb += fl[v];
        free(fl);
        CHECK(m.nt == 6 * N * N && nb == 6 * N, "disk N = %d: %d triangles, %d boundary nodes", N, m.nt, nb);
        CHECK(fabs(area - 3 * N * sin(PI_ / (3 * N))) < 1e-12, "disk area %.15g = inscribed %d-gon", area, 6 * N);
        snprintf(path, sizeof path, "%s/disk%d.msh", dir, k);
        CHECK(write_msh(path, 1, &m) == 0, "write");
        CHECK(solve_msh(ctx, path, &harm, &l2[k], &h[k], NULL) == 0, "solve %s", path);
        tmesh_free(&m);
    }
    rates("gmsh disk, u = exp(x) sin(y)", 3, l2, h, 0.25);
    /* errors */
    snprintf(path, sizeof path, "%s/bad.msh", dir);
    FILE *f = fopen(path, "w");
    fprintf(f, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n$Elements\n1\n1 2 0 1 1 7\n$EndElements\n");
    fclose(f);
    eo_trimesh *bad = NULL;
    CHECK(eo_trimesh_read_gmsh(ctx, path, &bad) == EO_ERR_MESH && !bad, "undefined node rejected");
    CHECK(strstr(eo_ctx_message(ctx), "bad.msh:10") != NULL, "message names the line: %s", eo_ctx_message(ctx));
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_matrix();
    test_convergence();
    test_solvers();
    test_steepest_descent();
    test_fig2();
    test_quadrature();
    test_gmsh();
    return eo_test_finish("test_poisson");
}
