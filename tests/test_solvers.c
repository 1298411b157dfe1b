/* Optimizer contract suite: every optimizer × line search × Hessian fix × stopping rule
 * on small analytic problems (convex quadratic, the notes' ill-conditioned quadratic,
 * extended Rosenbrock, a −log barrier that is +∞ outside its domain, separable double
 * wells), plus: the notes' Example 2 iterates of exact-line-search gradient descent,
 * Newton's quadratic convergence and decrement ≈ g − g*, the iteration cap, no
 * allocation inside minimize, config sections, non-finite start, callback stop. */
#include <jansson.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/config.h"
#include "elastopt/impl/method.h"
#include "elastopt/impl/params.h"
#include "testutil.h"

#include "solver_problems.h"

/* ---- iteration log ------------------------------------------------------------------ */
#define LOGMAX 6000
typedef struct tlog {
    int count, bad_order, nonfinite_g, last_reason, inverted_seen, stop_at;
    eo_iter_info rec[LOGMAX];
    double x[LOGMAX][2];
} tlog;

static int on_iter(const eo_iter_info *info, void *user)
{
    tlog *L = user;
    if (info->iteration != L->count) L->bad_order++;
    if (!isfinite(info->g)) L->nonfinite_g++;
    if (info->inverted != -1) L->inverted_seen++;
    if (L->count < LOGMAX) {
        L->rec[L->count] = *info;
        L->x[L->count][0] = info->x[0];
        L->x[L->count][1] = info->x[1];
    }
    L->count++;
    L->last_reason = info->reason;
    return L->stop_at > 0 && info->iteration + 1 >= L->stop_at;
}

/* ---- running one configuration ------------------------------------------------------ */
typedef struct run_cfg {
    const char *opt, *hf, *ls, *stop, *linear;
    double tol;
    int max_iters;
    const char *overrides[4];
    double time_budget;
} run_cfg;

static int run(eo_ctx *ctx, tprob *p, const run_cfg *rc, double *x, tlog *L, eo_solve_result *res)
{
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    snprintf(o.optimizer, sizeof o.optimizer, "%s", rc->opt);
    snprintf(o.hessian_fix, sizeof o.hessian_fix, "%s", rc->hf ? rc->hf : "clamp");
    snprintf(o.linesearch, sizeof o.linesearch, "%s", rc->ls ? rc->ls : "backtracking");
    snprintf(o.stop, sizeof o.stop, "%s", rc->stop ? rc->stop : "newton_decrement");
    snprintf(o.linear, sizeof o.linear, "%s", rc->linear ? rc->linear : "cholmod");
    if (rc->tol > 0) o.tol = rc->tol;
    if (rc->max_iters > 0) o.max_iters = rc->max_iters;
    o.time_budget = rc->time_budget;
    eo_cfg *cfg = NULL;
    if (eo_cfg_create_empty(ctx, &cfg) < 0) abort();
    for (int i = 0; i < 4 && rc->overrides[i]; i++)
        if (eo_cfg_override(ctx, cfg, rc->overrides[i]) < 0) abort();
    eo_solver *s = NULL;
    int st = eo_solver_create(ctx, &o, cfg, &s);
    CHECK(st == EO_OK, "create %s/%s/%s: %s", rc->opt, o.hessian_fix, o.linesearch, eo_ctx_message(ctx));
    if (st == EO_OK) st = eo_cfg_finish(ctx, cfg);
    CHECK(st == EO_OK, "cfg finish: %s", eo_ctx_message(ctx));
    eo_cfg_destroy(&cfg);
    if (!s) return st;
    memcpy(x, p->x0, sizeof(double) * p->n);
    eo_objective obj = prob_objective(p);
    if (L) memset(L, 0, sizeof *L);
    st = eo_solver_minimize(s, &obj, x, L ? on_iter : NULL, L, res);
    eo_solver_destroy(&s);
    return st;
}

/* ---- the sweep ----------------------------------------------------------------------- */
static const char *const optimizers[] = {"newton", "gradient_descent", "lbfgs", "ncg", "newton_tr"};
#define N_OPT 5
static const char *hessfixes[32]; /* every registered Hessian fix (main fills it) */
static size_t n_hessfixes;
static const char *const linesearches[] = {"backtracking", "exact", "none", "wolfe"};
#define N_LS 4
static const char *const stops[] = {"newton_decrement", "gradient"};

/* 1 if the combination must reach the minimizer (else it must only end with a reason). */
static int must_converge(int prob, const char *opt, const char *hf, const char *ls)
{
    int nonconvex = prob == P_ROSEN || prob == P_DWELL;
    if (strcmp(opt, "newton_tr") == 0) return 1; /* no line search; the true Hessian + trust region */
    if (strcmp(ls, "none") == 0) /* full steps: only where they provably work */
        return (prob == P_QUAD || prob == P_ILL) && strcmp(opt, "lbfgs") != 0 && strcmp(opt, "ncg") != 0;
    if (strcmp(opt, "ncg") == 0) /* CG needs a (near-)exact search: Armijo alone may stall */
        return strcmp(ls, "backtracking") != 0;
    if (strcmp(opt, "newton") == 0) return !(nonconvex && strcmp(hf, "none") == 0);
    if (strcmp(opt, "gradient_descent") == 0) return prob != P_ROSEN;
    return 1;
}

static void test_sweep(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static tlog L;
    int combos = 0, converged = 0;
    for (int pk = 0; pk < P_COUNT; pk++) {
        tprob p;
        prob_init(ctx, &p, pk);
        for (size_t oi = 0; oi < N_OPT; oi++)
            for (size_t hi = 0; hi < n_hessfixes; hi++) {
                int newton = oi == 0;
                if (!newton && strcmp(hessfixes[hi], "clamp") != 0) continue; /* only newton's */
                for (size_t li = 0; li < N_LS; li++)
                    for (size_t si = 0; si < 2; si++) {
                        run_cfg rc = {.opt = optimizers[oi], .hf = hessfixes[hi], .ls = linesearches[li],
                                      .stop = stops[si], .tol = si == 0 ? 1e-16 : 1e-10,
                                      .max_iters = newton || oi == 4 ? 100 : oi == 1 || oi == 3 ? 5000 : 1000};
                        double x[NMAX];
                        eo_solve_result res;
                        p.n_inf = 0;
                        int st = run(ctx, &p, &rc, x, &L, &res);
                        int must = must_converge(pk, rc.opt, rc.hf, rc.ls);
                        char tag[160];
                        snprintf(tag, sizeof tag, "%s: %s/%s/%s/%s", p.name, rc.opt, newton ? rc.hf : "-",
                                 rc.ls, rc.stop);
                        combos++;
                        CHECK(st == EO_OK, "%s: status %d %s", tag, st, eo_ctx_message(ctx));
                        CHECK(res.reason != 0, "%s: no reason", tag);
                        CHECK(L.count == res.iterations + 1 || res.reason == EO_DIVERGED_EXTERNAL,
                              "%s: %d records for %d iterations", tag, L.count, res.iterations);
                        CHECK(L.bad_order == 0 && L.last_reason == res.reason, "%s: log order/reason", tag);
                        CHECK(L.nonfinite_g == 0, "%s: an infinite g was accepted", tag);
                        CHECK(isnan(L.rec[(L.count - 1) % LOGMAX].alpha), "%s: last alpha", tag);
                        CHECK(L.inverted_seen == (pk == P_BARRIER ? L.count : 0), "%s: inverted count", tag);
                        double err = prob_error(&p, x);
                        if (must) {
                            CHECK(res.reason > 0 && err <= 1e-6, "%s: reason %s, |x - x*| = %.3g after %d it",
                                  tag, eo_reason_name(res.reason), err, res.iterations);
                            converged += res.reason > 0 && err <= 1e-6;
                        }
                        if (newton && strcmp(rc.hf, "none") == 0 && (pk == P_ROSEN || pk == P_DWELL))
                            CHECK(res.n_fallback > 0, "%s: expected steepest-descent fallbacks", tag);
                        if (newton && strcmp(rc.hf, "none") != 0 && pk == P_DWELL)
                            CHECK(res.n_shifted > 0 && res.n_fallback == 0, "%s: expected shifts", tag);
                        if (getenv("EO_TEST_VERBOSE"))
                            printf("%-60s %-22s it %4d  err %.2e  fb %ld sh %ld  nv %ld ng %ld\n", tag,
                                   eo_reason_name(res.reason), res.iterations, err, res.n_fallback,
                                   res.n_shifted, res.n_value, res.n_gradient);
                    }
            }
        prob_done(ctx, &p);
    }
    printf("sweep: %d combinations, %d required to converge did\n", combos, converged);
    eo_test_ctx_done(&ctx);
}

/* Barrier: the first Newton step leaves the domain; every line search must shrink. */
static void test_barrier_infinite_trials(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static tlog L;
    tprob p;
    prob_init(ctx, &p, P_BARRIER);
    for (size_t li = 0; li < N_LS; li++) {
        run_cfg rc = {.opt = "newton", .hf = "shift", .ls = linesearches[li], .tol = 1e-16};
        double x[NMAX];
        eo_solve_result res;
        p.n_inf = 0;
        run(ctx, &p, &rc, x, &L, &res);
        CHECK(p.n_inf > 0, "%s: no trial outside the domain", rc.ls);
        CHECK(L.nonfinite_g == 0 && res.reason != 0, "%s: accepted +inf or no reason", rc.ls);
        for (int i = 0; i < p.n; i++) CHECK(x[i] > 0, "%s: x outside the domain", rc.ls);
    }
    prob_done(ctx, &p);
    eo_test_ctx_done(&ctx);
}

/* 002 Example 2: exact line search gradient descent on ½(x₁² + γx₂²) from (γ, 1). */
static void test_example2(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static tlog L;
    const double gammas[] = {10, 3, 100};
    for (int gi = 0; gi < 3; gi++) {
        tprob p;
        prob_init(ctx, &p, P_ILL);
        double gm = gammas[gi];
        p.gamma = gm, p.x0[0] = gm, p.x0[1] = 1;
        run_cfg rc = {.opt = "gradient_descent", .ls = "exact", .stop = "gradient", .tol = 1e-300,
                      .max_iters = 40,
                      .overrides = {"solver.gradient_descent.scaled=false", "solver.exact.tol=1e-14"}};
        double x[NMAX];
        eo_solve_result res;
        run(ctx, &p, &rc, x, &L, &res);
        double r = (gm - 1) / (gm + 1), maxerr = 0;
        int k;
        for (k = 0; k < L.count && k <= 40; k++) {
            double e1 = fabs(L.x[k][0] - gm * pow(r, k)), e2 = fabs(L.x[k][1] - pow(-r, k));
            maxerr = fmax(maxerr, fmax(e1, e2));
        }
        CHECK(L.count >= 30, "gamma %g: only %d iterates", gm, L.count);
        CHECK(maxerr <= 1e-10, "gamma %g: max |x_k - analytic| = %.3g over %d iterates", gm, maxerr, k);
        prob_done(ctx, &p);
    }
    eo_test_ctx_done(&ctx);
}

/* Newton: quadratic convergence and λ²/2 ≈ g − g* from the iteration log. */
static void test_newton_rates(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static tlog L;
    const int probs[] = {P_BARRIER, P_ROSEN};
    for (int q = 0; q < 2; q++) {
        tprob p;
        prob_init(ctx, &p, probs[q]);
        run_cfg rc = {.opt = "newton", .hf = "shift", .ls = "backtracking", .stop = "gradient",
                      .tol = 1e-300, .max_iters = 100,
                      .overrides = {"solver.gradient.floor=1"}};
        double x[NMAX];
        eo_solve_result res;
        run(ctx, &p, &rc, x, &L, &res);
        CHECK(prob_error(&p, x) <= 1e-8, "%s: not converged (%s)", p.name, eo_reason_name(res.reason));
        /* quadratic: last steps with ‖∇g_k‖ < 1e-1 and ‖∇g_{k+1}‖ above rounding */
        int pairs = 0;
        double cmax = 0;
        for (int k = 0; k + 1 < L.count; k++) {
            double a = L.rec[k].grad_norm, b = L.rec[k + 1].grad_norm;
            if (a < 1e-1 && b > 1e-13 && L.rec[k].alpha == 1) {
                pairs++;
                cmax = fmax(cmax, b / (a * a));
            }
        }
        CHECK(pairs >= 2, "%s: only %d pairs in the quadratic phase", p.name, pairs);
        CHECK(cmax <= 1e3, "%s: |g_k+1| <= C |g_k|^2 needs C = %g", p.name, cmax);
        /* decrement estimates g − g* */
        int checked = 0;
        for (int k = 0; k < L.count; k++) {
            double dec = L.rec[k].decrement, gap = L.rec[k].g - p.gstar;
            if (!(dec < 1e-3 && dec > 1e-11)) continue;
            checked++;
            CHECK(fabs(gap - dec) <= 0.05 * dec, "%s it %d: lambda^2/2 = %.6g, g - g* = %.6g", p.name, k,
                  dec, gap);
        }
        CHECK(checked >= 1, "%s: no decrement in range", p.name);
        prob_done(ctx, &p);
    }
    eo_test_ctx_done(&ctx);
}

static void test_max_iters_and_stops(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static tlog L;
    tprob p;
    prob_init(ctx, &p, P_ROSEN);
    double x[NMAX];
    eo_solve_result res;
    run_cfg rc = {.opt = "gradient_descent", .stop = "gradient", .tol = 1e-12, .max_iters = 5};
    run(ctx, &p, &rc, x, &L, &res);
    CHECK(res.reason == EO_DIVERGED_MAX_ITERS && res.iterations == 5 && L.count == 6,
          "reason %s, %d iterations", eo_reason_name(res.reason), res.iterations);
    run_cfg rn = {.opt = "newton", .hf = "shift", .tol = 1e-16, .max_iters = 2};
    run(ctx, &p, &rn, x, &L, &res);
    CHECK(res.reason == EO_DIVERGED_MAX_ITERS && res.iterations == 2, "newton: %s",
          eo_reason_name(res.reason));
    /* time budget */
    run_cfg rt = {.opt = "lbfgs", .stop = "gradient", .tol = 1e-12, .time_budget = 1e-12};
    run(ctx, &p, &rt, x, &L, &res);
    CHECK(res.reason == EO_DIVERGED_TIME_BUDGET && L.count == 1, "time budget: %s",
          eo_reason_name(res.reason));
    /* callback stop */
    run_cfg rl = {.opt = "lbfgs", .stop = "gradient", .tol = 1e-12};
    memset(&L, 0, sizeof L);
    L.stop_at = 3;
    {
        eo_solver_opts o;
        eo_solver_opts_default(&o);
        snprintf(o.optimizer, sizeof o.optimizer, "%s", rl.opt);
        eo_solver *s;
        CHECK(eo_solver_create(ctx, &o, NULL, &s) == EO_OK, "%s", eo_ctx_message(ctx));
        eo_objective obj = prob_objective(&p);
        memcpy(x, p.x0, sizeof x);
        eo_solver_minimize(s, &obj, x, on_iter, &L, &res);
        CHECK(res.reason == EO_DIVERGED_EXTERNAL && L.count == 3 && res.iterations == 2,
              "callback stop: %s, %d records", eo_reason_name(res.reason), L.count);
        CHECK(x[0] == L.x[2][0] && x[1] == L.x[2][1], "x is the last reported iterate");
        eo_solver_destroy(&s);
    }
    /* start at the minimizer: gradient exactly 0 */
    {
        tprob q;
        prob_init(ctx, &q, P_ILL);
        q.x0[0] = q.x0[1] = 0;
        run_cfg r0 = {.opt = "newton", .hf = "clamp"};
        run(ctx, &q, &r0, x, &L, &res);
        CHECK(res.reason == EO_CONVERGED_GRADIENT && res.iterations == 0, "zero gradient: %s",
              eo_reason_name(res.reason));
        prob_done(ctx, &q);
    }
    /* non-finite start */
    {
        tprob q;
        prob_init(ctx, &q, P_BARRIER);
        q.x0[2] = -1;
        for (size_t oi = 0; oi < N_OPT; oi++) {
            run_cfg r1 = {.opt = optimizers[oi]};
            run(ctx, &q, &r1, x, &L, &res);
            CHECK(res.reason == EO_DIVERGED_NONFINITE && res.iterations == 0 && L.count == 1,
                  "%s: non-finite start gives %s", r1.opt, eo_reason_name(res.reason));
        }
        prob_done(ctx, &q);
    }
    /* not PD beyond the shift cap */
    {
        tprob q;
        prob_init(ctx, &q, P_DWELL);
        run_cfg r2 = {.opt = "newton", .hf = "shift",
                      .overrides = {"solver.shift.shift_max=1e-6", "solver.shift.shift_init=1e-9"}};
        run(ctx, &q, &r2, x, &L, &res);
        CHECK(res.reason == EO_DIVERGED_NOT_PD, "shift cap: %s", eo_reason_name(res.reason));
        prob_done(ctx, &q);
    }
    prob_done(ctx, &p);
    eo_test_ctx_done(&ctx);
}

/* Newton with other linear solvers (NOT_PD from LDLᵀ pivots, cg curvature, dense). */
static void test_newton_linear(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static tlog L;
    const char *const linear[] = {"cholmod", "cholmod_ldlt", "lapack", "pcg", "cg"};
    const int probs[] = {P_ROSEN, P_BARRIER, P_DWELL};
    for (int q = 0; q < 3; q++) {
        tprob p;
        prob_init(ctx, &p, probs[q]);
        for (int li = 0; li < 5; li++)
            for (size_t hi = 0; hi < n_hessfixes; hi++) {
                const void *t;
                if (strcmp(hessfixes[hi], "none") == 0) continue; /* may stop at a saddle */
                if (eo_registry_find(ctx, EO_KIND_LINSOLVE, linear[li], &t) < 0) continue;
                run_cfg rc = {.opt = "newton", .hf = hessfixes[hi], .linear = linear[li], .tol = 1e-16};
                double x[NMAX];
                eo_solve_result res;
                run(ctx, &p, &rc, x, &L, &res);
                CHECK(res.reason > 0 && prob_error(&p, x) <= 1e-6, "%s %s/%s: %s, err %.3g", p.name,
                      rc.hf, rc.linear, eo_reason_name(res.reason), prob_error(&p, x));
            }
        prob_done(ctx, &p);
    }
    eo_test_ctx_done(&ctx);
}

/* ---- allocation counting ------------------------------------------------------------- */
typedef struct counter {
    long calls;
} counter;
static void *c_malloc(size_t n, void *u)
{
    ((counter *)u)->calls++;
    return malloc(n);
}
static void *c_realloc(void *p, size_t n, void *u)
{
    ((counter *)u)->calls++;
    return realloc(p, n);
}
static void c_free(void *p, void *u)
{
    (void)u;
    free(p);
}

static void test_no_alloc(void)
{
    counter cnt = {0};
    eo_allocator al = {c_malloc, c_realloc, c_free, &cnt};
    eo_ctx *ctx = NULL;
    eo_ctx_create(&al, &ctx);
    for (int pk = 0; pk < P_COUNT; pk++) {
        tprob p;
        prob_init(ctx, &p, pk);
        for (size_t oi = 0; oi < N_OPT; oi++)
            for (size_t li = 0; li < N_LS; li++) {
                eo_solver_opts o;
                eo_solver_opts_default(&o);
                snprintf(o.optimizer, sizeof o.optimizer, "%s", optimizers[oi]);
                snprintf(o.linesearch, sizeof o.linesearch, "%s", linesearches[li]);
                snprintf(o.hessian_fix, sizeof o.hessian_fix, "shift");
                eo_solver *s = NULL;
                CHECK(eo_solver_create(ctx, &o, NULL, &s) == EO_OK, "%s", eo_ctx_message(ctx));
                if (!s) continue;
                eo_objective obj = prob_objective(&p);
                double x[NMAX];
                eo_solve_result res;
                for (int rep = 0; rep < 2; rep++) {
                    memcpy(x, p.x0, sizeof x);
                    long c0 = cnt.calls;
                    size_t live0 = eo_ctx_live_bytes(ctx);
                    eo_solver_minimize(s, &obj, x, NULL, NULL, &res);
                    /* the first minimize sizes the workspace (the solver is created without
                     * the problem size) and newton analyzes the pattern once */
                    if (rep == 1) {
                        CHECK(cnt.calls == c0, "%s/%s on %s: %ld allocations inside minimize",
                              optimizers[oi], linesearches[li], p.name, cnt.calls - c0);
                        CHECK(eo_ctx_live_bytes(ctx) == live0, "live bytes changed");
                    }
                }
                eo_solver_destroy(&s);
            }
        prob_done(ctx, &p);
    }
    CHECK(eo_ctx_live_bytes(ctx) == 0, "%zu bytes leaked", eo_ctx_live_bytes(ctx));
    eo_ctx_destroy(&ctx);
}

/* ---- configuration ------------------------------------------------------------------ */
static void test_config(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *text =
        "{\"solver\": {\"optimizer\": \"lbfgs\", \"tol\": 1e-9, \"max_iters\": 50,\n"
        "  \"lbfgs\": {\"history\": 5}, \"newton\": {\"descent_eps\": 1e-10},\n"
        "  \"backtracking\": {\"c1\": 0.001}, \"shift\": {\"shift_grow\": 4},\n"
        "  \"gradient\": {\"floor\": 1e-8}}}";
    eo_cfg *cfg;
    CHECK(eo_cfg_load(ctx, NULL, text, &cfg) == EO_OK, "%s", eo_ctx_message(ctx));
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    CHECK(strcmp(o.optimizer, "newton") == 0 && strcmp(o.hessian_fix, "project_on_demand") == 0 &&
              o.tol == 1e-10 && o.max_iters == 100 && strcmp(o.linear, "auto") == 0,
          "defaults");
    CHECK(eo_solver_opts_load(ctx, cfg, &o) == EO_OK, "%s", eo_ctx_message(ctx));
    CHECK(strcmp(o.optimizer, "lbfgs") == 0 && o.tol == 1e-9 && o.max_iters == 50, "loaded");
    eo_solver *s = NULL;
    CHECK(eo_solver_create(ctx, &o, cfg, &s) == EO_OK, "%s", eo_ctx_message(ctx));
    CHECK(eo_cfg_finish(ctx, cfg) == EO_OK, "unselected sections consumed: %s", eo_ctx_message(ctx));
    CHECK(s && eo_solver_get_linsolve(s) != NULL, "lbfgs has a linear solver (used with h0 = pd)");
    if (s) {
        json_t *j = eo_solver_to_json(s);
        json_t *h = json_object_get(json_object_get(j, "lbfgs"), "history");
        CHECK(h && json_integer_value(h) == 5, "echo of lbfgs.history");
        /* solver.linesearch = auto (default) resolves to lbfgs's choice, wolfe */
        CHECK(json_object_get(j, "wolfe") != NULL && json_object_get(j, "backtracking") == NULL,
              "echo of the line search lbfgs chose");
        json_t *lsn = json_object_get(j, "linesearch");
        CHECK(lsn && strcmp(json_string_value(lsn), "wolfe") == 0, "linesearch echoed as wolfe");
        CHECK(strcmp(eo_solver_get_opts(s)->linesearch, "wolfe") == 0, "resolved name in the opts");
        json_decref(j);
    }
    eo_solver_destroy(&s);
    eo_cfg_destroy(&cfg);
    /* auto per optimizer: newton, gradient_descent and projective_dynamics backtracking,
     * ncg wolfe; an explicit choice wins */
    {
        const char *opt_ls[][3] = {{"newton", "auto", "backtracking"}, {"gradient_descent", "auto", "backtracking"},
                                   {"projective_dynamics", "auto", "backtracking"}, {"ncg", "auto", "wolfe"},
                                   {"lbfgs", "backtracking", "backtracking"}, {"ncg", "exact", "exact"}};
        for (int i = 0; i < 6; i++) {
            eo_solver_opts_default(&o);
            CHECK(strcmp(o.linesearch, "auto") == 0, "default linesearch is auto");
            snprintf(o.optimizer, sizeof o.optimizer, "%s", opt_ls[i][0]);
            snprintf(o.linesearch, sizeof o.linesearch, "%s", opt_ls[i][1]);
            CHECK(eo_solver_create(ctx, &o, NULL, &s) == EO_OK, "%s", eo_ctx_message(ctx));
            CHECK(s && strcmp(eo_solver_get_opts(s)->linesearch, opt_ls[i][2]) == 0, "%s + %s -> %s, got %s",
                  opt_ls[i][0], opt_ls[i][1], opt_ls[i][2], s ? eo_solver_get_opts(s)->linesearch : "-");
            eo_solver_destroy(&s);
        }
    }

    /* unknown sub-section, unknown key, wrong type, unknown names */
    const char *bad[] = {
        "{\"solver\": {\"newtn\": {}}}",
        "{\"solver\": {\"lbfgs\": {\"histroy\": 3}}}",
        "{\"solver\": {\"backtracking\": {\"c1\": \"x\"}}}",
        "{\"solver\": {\"exact\": {\"tol\": 2}}}",
        "{\"solver\": {\"optimizer\": \"newtonn\"}}",
    };
    const int want[] = {EO_ERR_UNKNOWN_KEY, EO_ERR_UNKNOWN_KEY, EO_ERR_TYPE, EO_ERR_RANGE,
                        EO_ERR_UNKNOWN_NAME};
    for (int i = 0; i < 5; i++) {
        CHECK(eo_cfg_load(ctx, NULL, bad[i], &cfg) == EO_OK, "load");
        eo_solver_opts_default(&o);
        int rc = eo_solver_opts_load(ctx, cfg, &o);
        if (rc == EO_OK) {
            rc = eo_solver_create(ctx, &o, cfg, &s);
            eo_solver_destroy(&s);
        }
        CHECK(rc == want[i], "bad config %d: rc %d (%s)", i, rc, eo_ctx_message(ctx));
        eo_cfg_destroy(&cfg);
    }
    /* names set in C, not from a config */
    eo_solver_opts_default(&o);
    snprintf(o.linesearch, sizeof o.linesearch, "wolf");
    CHECK(eo_solver_create(ctx, &o, NULL, &s) == EO_ERR_UNKNOWN_NAME &&
              strstr(eo_ctx_message(ctx), "backtracking, nonmonotone, wolfe, exact, none"),
          "unknown line search message: %s", eo_ctx_message(ctx));
    CHECK(s == NULL, "no object on failure");
    /* no two solver-section methods with parameters share a name across kinds */
    const eo_kind kinds[] = {EO_KIND_OPTIMIZER, EO_KIND_HESSFIX, EO_KIND_LINESEARCH, EO_KIND_STOP,
                             EO_KIND_LINSOLVE};
    int clash = 0;
    for (int a = 0; a < 5; a++)
        for (int b = a + 1; b < 5; b++)
            for (const void *const *t = eo_registry_list(kinds[a]); *t; t++)
                for (const void *const *u = eo_registry_list(kinds[b]); *u; u++) {
                    const eo_method_info *ma = eo_method_info_of(*t), *mb = eo_method_info_of(*u);
                    if (strcmp(ma->name, mb->name) == 0 && (ma->params || mb->params)) {
                        clash++;
                        fprintf(stderr, "section solver.%s is ambiguous\n", ma->name);
                    }
                }
    CHECK(clash == 0, "%d ambiguous solver.<name> sections", clash);
    /* failure injection: every allocation of create can fail cleanly */
    for (long k = 1; k < 40; k++) {
        eo_solver_opts_default(&o);
        eo_ctx_fail_after(ctx, k);
        int rc = eo_solver_create(ctx, &o, NULL, &s);
        eo_ctx_fail_after(ctx, 0);
        if (rc == EO_OK) {
            eo_solver_destroy(&s);
            break;
        }
        CHECK(rc < 0 && s == NULL, "fail after %ld: rc %d", k, rc);
    }
    eo_test_ctx_done(&ctx);
}

static void test_proj2(void)
{
    double K[4] = {1, 2, 2, 1}, A[4] = {1, 2, 2, 1};
    proj2(K, EO_PROJ_CLAMP);
    proj2(A, EO_PROJ_ABS);
    CHECK(fabs(K[0] - 1.5) + fabs(K[1] - 1.5) + fabs(K[2] - 1.5) + fabs(K[3] - 1.5) < 1e-14, "clamp");
    CHECK(fabs(A[0] - 2) + fabs(A[1] - 1) + fabs(A[2] - 1) + fabs(A[3] - 2) < 1e-14, "abs");
}

/* ---- wolfe on the test functions of Moré & Thuente (1994), Table 1-3 --------------------
 * φ(α) as a 1-variable objective g(x) = φ(x), searched from x = 0 along p = 1. */
typedef struct mt_fun {
    int which;
    double beta;
} mt_fun;

static double mt_phi(const mt_fun *f, double a, double *d)
{
    double b = f->beta;
    switch (f->which) {
    case 1: { /* φ = −α/(α² + β) */
        double q = a * a + b;
        *d = (a * a - b) / (q * q);
        return -a / q;
    }
    case 2: { /* φ = (α + β)⁵ − 2(α + β)⁴ */
        double t = a + b;
        *d = 5 * pow(t, 4) - 8 * pow(t, 3);
        return pow(t, 5) - 2 * pow(t, 4);
    }
    default: { /* φ = φ₀(α) + 2(1 − β)/(lπ) sin(lπα/2), l = 39, β = 0.01 */
        const double l = 39, pi = 3.14159265358979323846;
        double p0, d0;
        if (a <= 1 - b) p0 = 1 - a, d0 = -1;
        else if (a >= 1 + b) p0 = a - 1, d0 = 1;
        else p0 = (a - 1) * (a - 1) / (2 * b) + b / 2, d0 = (a - 1) / b;
        *d = d0 + (1 - b) * cos(l * pi * a / 2);
        return p0 + 2 * (1 - b) / (l * pi) * sin(l * pi * a / 2);
    }
    }
}

static int mt_value(void *data, const double *x, double *g)
{
    double d;
    *g = mt_phi(data, x[0], &d);
    return EO_OK;
}
static int mt_gradient(void *data, const double *x, double *g, double *grad)
{
    *g = mt_phi(data, x[0], grad);
    return EO_OK;
}
static const eo_objective_ops mt_ops = {.value = mt_value, .gradient = mt_gradient};

static void test_wolfe_more_thuente(void)
{
    eo_ctx *ctx = eo_test_ctx();
    /* Moré–Thuente's parameters: functions 1, 2 with c1 = 1e-3, c2 = 0.1; function 3 with
     * c1 = c2 = 0.1; starts 1e-3, 1e-1, 1e1, 1e3 */
    const mt_fun funs[3] = {{1, 2}, {2, 0.004}, {3, 0.01}};
    const double c1s[3] = {1e-3, 1e-3, 0.1}, c2s[3] = {0.1, 0.1, 0.1};
    const double starts[4] = {1e-3, 1e-1, 1e1, 1e3};
    int accepted = 0;
    for (int fi = 0; fi < 3; fi++)
        for (int si = 0; si < 4; si++) {
            mt_fun f = funs[fi];
            eo_objective obj = {.n = 1, .ops = &mt_ops, .data = &f};
            double x = 0, p = 1, d0, g0 = mt_phi(&f, 0, &d0), xnew, gnew = NAN, alpha = 0, work, gradnew = NAN;
            int nev = 0;
            eo_wolfe_params wp = {.c1 = c1s[fi], .c2 = c2s[fi], .max_evals = 40, .noise = 1e-10};
            eo_ls_extra ex = {.grad_new = &gradnew, .have_grad = 0, .c2 = 0};
            int rc = eo_linesearch_wolfe.search(&wp, &obj, &x, &p, g0, d0, starts[si], &xnew, &gnew, &alpha,
                                                &nev, &work, ctx, &ex);
            double d, fa = mt_phi(&f, alpha, &d);
            printf("  More-Thuente %d from %-6g: alpha %-12.6g phi' %-11.3g evals %2d %s\n", fi + 1, starts[si],
                   alpha, d, nev, rc == EO_OK ? "ok" : "not converged");
            CHECK(rc == EO_OK, "MT%d from %g: rc %d", fi + 1, starts[si], rc);
            CHECK(nev == (int)obj.n_gradient && obj.n_value == 0, "MT%d: %d trials, %ld gradient and %ld value calls",
                  fi + 1, nev, obj.n_gradient, obj.n_value);
            if (rc != EO_OK) continue;
            accepted++;
            CHECK(xnew == alpha && gnew == fa, "MT%d from %g: returned point/value", fi + 1, starts[si]);
            CHECK(fa <= g0 + wp.c1 * alpha * d0, "MT%d from %g: sufficient decrease %g > %g", fi + 1, starts[si],
                  fa, g0 + wp.c1 * alpha * d0);
            CHECK(fabs(d) <= wp.c2 * fabs(d0), "MT%d from %g: |phi'| = %g > c2|phi'(0)| = %g", fi + 1, starts[si],
                  fabs(d), wp.c2 * fabs(d0));
            CHECK(ex.have_grad == 1 && gradnew == d, "MT%d from %g: returned gradient %g, exact %g", fi + 1,
                  starts[si], gradnew, d);
        }
    CHECK(accepted == 12, "%d of 12 searches accepted", accepted);
    eo_test_ctx_done(&ctx);
}

/* The first trial with its gradient (eo_ls_extra.grad_first) in the value-only searches:
 * accepted, one gradient call and no value call, the gradient handed back exactly;
 * rejected, the handed-back flag stays 0 (the buffer holds a rejected trial's gradient)
 * and the later trials are value calls. In the descent loop (newton with each of them)
 * every iteration whose first trial is accepted after an accepted first trial (or at
 * k = 0) costs one call, every other iteration its trials plus one gradient call. */
static void test_first_trial_gradient(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const eo_linesearch_type *lss[3] = {&eo_linesearch_backtracking, &eo_linesearch_nonmonotone,
                                        &eo_linesearch_none};
    for (int li = 0; li < 3; li++)
        for (int start = 0; start < 2; start++) {
            mt_fun f = {1, 2}; /* phi = -a/(a^2 + 2): a0 = 1 passes Armijo, a0 = 1e3 does not */
            eo_objective obj = {.n = 1, .ops = &mt_ops, .data = &f};
            const double a0 = start ? 1e3 : 1;
            double x = 0, p = 1, d0, g0 = mt_phi(&f, 0, &d0), xnew, gnew = NAN, alpha = 0, work, gradnew = NAN;
            int nev = 0;
            eo_ls_extra ex = {.grad_new = &gradnew, .have_grad = 0, .grad_first = 1};
            int rc = lss[li]->search(NULL, &obj, &x, &p, g0, d0, a0, &xnew, &gnew, &alpha, &nev, &work, ctx, &ex);
            const char *nm = lss[li]->info.name;
            CHECK(rc == EO_OK, "%s from %g: rc %d", nm, a0, rc);
            double d, fa = mt_phi(&f, alpha, &d);
            CHECK(xnew == alpha && gnew == fa, "%s from %g: returned point/value", nm, a0);
            if (start == 0 || li == 2) { /* accepted at once (none accepts every finite trial) */
                CHECK(nev == 1 && alpha == a0 && obj.n_gradient == 1 && obj.n_value == 0,
                      "%s from %g: %d trials, alpha %g, %ld gradient and %ld value calls", nm, a0, nev, alpha,
                      obj.n_gradient, obj.n_value);
                CHECK(ex.have_grad == 1 && gradnew == d, "%s from %g: gradient handed back %d (%g, exact %g)", nm,
                      a0, ex.have_grad, gradnew, d);
            } else {
                CHECK(nev > 1 && alpha < a0 && obj.n_gradient == 1 && obj.n_value == nev - 1,
                      "%s from %g: %d trials, alpha %g, %ld gradient and %ld value calls", nm, a0, nev, alpha,
                      obj.n_gradient, obj.n_value);
                CHECK(ex.have_grad == 0, "%s from %g: a rejected trial's gradient was handed back", nm, a0);
            }
        }
    static tlog L;
    const char *ls[3] = {"backtracking", "nonmonotone", "none"};
    int pks[3] = {P_QUAD, P_ILL, P_BARRIER};
    long saved = 0;
    for (int pi = 0; pi < 3; pi++) {
        tprob p;
        prob_init(ctx, &p, pks[pi]);
        for (int li = 0; li < 3; li++) {
            run_cfg rc = {.opt = "newton", .ls = ls[li], .stop = "gradient", .tol = 1e-8, .max_iters = 200};
            double x[NMAX];
            eo_solve_result res;
            run(ctx, &p, &rc, x, &L, &res);
            CHECK(res.reason == EO_CONVERGED_GRADIENT, "%s/%s: %s", p.name, ls[li], eo_reason_name(res.reason));
            long expect = 1; /* the start's gradient */
            int first_ok = 1;
            for (int k = 0; k < L.count && k < LOGMAX; k++) {
                const int nev = L.rec[k].ls_evals;
                if (nev == 0) continue; /* the last record: stopped before a search */
                expect += nev + !(first_ok && nev == 1);
                saved += first_ok && nev == 1;
                first_ok = nev == 1;
            }
            CHECK(res.n_value + res.n_gradient == expect, "%s/%s: %ld value + %ld gradient calls, expected %ld",
                  p.name, ls[li], res.n_value, res.n_gradient, expect);
        }
        prob_done(ctx, &p);
    }
    CHECK(saved > 0, "no first trial was evaluated with its gradient");
    eo_test_ctx_done(&ctx);
}

/* lbfgs and ncg with wolfe: one gradient call per trial plus the start, no value call. */
static void test_wolfe_evaluations(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static tlog L;
    const char *opts[2] = {"lbfgs", "ncg"};
    for (int pk = 0; pk < P_COUNT; pk++) {
        tprob p;
        prob_init(ctx, &p, pk);
        for (int oi = 0; oi < 2; oi++) {
            run_cfg rc = {.opt = opts[oi], .ls = "wolfe", .stop = "gradient", .tol = 1e-8, .max_iters = 5000};
            double x[NMAX];
            eo_solve_result res;
            run(ctx, &p, &rc, x, &L, &res);
            long trials = 0;
            for (int k = 0; k < L.count && k < LOGMAX; k++) trials += L.rec[k].ls_evals;
            CHECK(res.reason == EO_CONVERGED_GRADIENT && res.grad_norm <= 1e-8 * L.rec[0].grad_norm,
                  "%s/%s: %s, |grad| %g", p.name, rc.opt, eo_reason_name(res.reason), res.grad_norm);
            CHECK(res.n_value == 0 && res.n_gradient == 1 + trials,
                  "%s/%s: %ld value, %ld gradient calls for %ld trials", p.name, rc.opt, res.n_value,
                  res.n_gradient, trials);
        }
        prob_done(ctx, &p);
    }
    eo_test_ctx_done(&ctx);
}

/* A solver is created without the problem size: it sizes its workspace at the first
 * minimize and again whenever obj->n changes. One newton / lbfgs solver alternating
 * between problems of different n (5, 4, 5) gives exactly the iterations and the
 * minimizer of a fresh solver on each. */
static void test_lazy_size(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const char *const opts[] = {"newton", "lbfgs"};
    const int seq[] = {P_QUAD, P_BARRIER, P_QUAD};
    for (int oi = 0; oi < 2; oi++) {
        eo_solver_opts o;
        eo_solver_opts_default(&o);
        snprintf(o.optimizer, sizeof o.optimizer, "%s", opts[oi]);
        snprintf(o.stop, sizeof o.stop, "gradient");
        o.tol = 1e-10;
        eo_solver *shared = NULL;
        CHECK(eo_solver_create(ctx, &o, NULL, &shared) == EO_OK, "%s", eo_ctx_message(ctx));
        int prev_n = -1;
        for (int q = 0; q < 3; q++) {
            tprob p;
            prob_init(ctx, &p, seq[q]);
            CHECK(p.n != prev_n, "sizes alternate (%d after %d)", p.n, prev_n);
            prev_n = p.n;
            eo_objective obj = prob_objective(&p);
            double x[NMAX], y[NMAX];
            eo_solve_result ra, rb;
            memcpy(x, p.x0, sizeof x);
            memcpy(y, p.x0, sizeof y);
            eo_solver *fresh = NULL;
            CHECK(eo_solver_create(ctx, &o, NULL, &fresh) == EO_OK, "%s", eo_ctx_message(ctx));
            CHECK(eo_solver_minimize(shared, &obj, x, NULL, NULL, &ra) == EO_OK, "%s", eo_ctx_message(ctx));
            CHECK(eo_solver_minimize(fresh, &obj, y, NULL, NULL, &rb) == EO_OK, "%s", eo_ctx_message(ctx));
            CHECK(ra.reason > 0 && ra.iterations == rb.iterations, "%s on %s (n = %d): %s in %d vs fresh %d",
                  opts[oi], p.name, p.n, eo_reason_name(ra.reason), ra.iterations, rb.iterations);
            double dmax = 0, emax = 0;
            for (int i = 0; i < p.n; i++) {
                dmax = fmax(dmax, fabs(x[i] - y[i]));
                emax = fmax(emax, fabs(x[i] - p.xstar[i]));
            }
            CHECK(dmax == 0 && emax < 1e-6, "%s on %s: |x - x_fresh| = %g, |x - x*| = %g", opts[oi], p.name,
                  dmax, emax);
            eo_solver_destroy(&fresh);
            prob_done(ctx, &p);
        }
        eo_solver_destroy(&shared);
    }
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    for (const void *const *t = eo_registry_list(EO_KIND_HESSFIX); *t && n_hessfixes < 32; t++)
        hessfixes[n_hessfixes++] = eo_method_info_of(*t)->name;
    test_wolfe_more_thuente();
    test_wolfe_evaluations();
    test_first_trial_gradient();
    test_lazy_size();
    test_proj2();
    test_config();
    test_example2();
    test_newton_rates();
    test_barrier_infinite_trials();
    test_max_iters_and_stops();
    test_no_alloc();
    test_newton_linear();
    test_sweep();
    return eo_test_finish("test_solvers");
}
