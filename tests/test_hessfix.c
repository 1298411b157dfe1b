/* Hessian fixes as methods (suite 'engine': it runs the engine scenes): the fix op of solver.h on the step
 * objective and through newton / projective_dynamics.
 *
 *  1. pin: Newton's iterates with none/shift/clamp/abs on the engine scenes cantilever,
 *     twist and inverted (3 steps each) equal those recorded before the fix became an
 *     op (g of the first 6 iterates and of the last one of each step, relative 1e-12;
 *     the iteration count of each step exactly, except none on inverted, which spends
 *     ~200 steepest-descent fallbacks and is pinned only on its first iterates).
 *  2. the op itself at the inverted box's start (every element Hessian indefinite
 *     somewhere): every registered fix returns a descent direction (∇gᵀp < 0, computed
 *     here), a fraction projected in [0, 1], and, asked for factors only
 *     (projective_dynamics' use), a factored positive-definite system.
 *  3. every new fix reaches the same minimizer as clamp (max |x − x_clamp| ≤ 1e-9 at
 *     solver.tol = 1e-20) on the first step of cantilever, twist, inverted and the
 *     static StVK cantilever, and every direction it produced was a descent direction
 *     (decrement λ²/2 = −∇gᵀp/2 > 0 on every record) with g never increasing by more
 *     than its rounding (1e-12 relative). A run that ends diverged_stagnated (at the
 *     rounding floor of g, which solver.tol = 1e-20 is below) counts when it is there.
 *  4. quadratic convergence on cantilever_static, StVK, E = 1e7: the last three
 *     decrements give q = ln(d₃/d₂)/ln(d₂/d₁) ≥ 1.7 for project_on_demand and
 *     progressive (measured 2.4), where clamp is linear (q ≤ 1.3, measured 1.00), and
 *     they need fewer iterations than clamp (measured 6 vs 10).
 *  5. projective_dynamics runs with every registered fix on the cantilever (constant
 *     matrix: the same iterates as with clamp).
 *  5b. solver.project_on_demand.projection: at the inverted box's start (the true Hessian
 *     is not positive definite) the first Newton step of project_on_demand is exactly
 *     that of clamp (projection = clamp, the default) or of abs (projection = abs), and
 *     the record says projected.
 *  6. a fix registered at run time (eo_register), written only against solver.h
 *     (clamp without safeguard), works in newton and projective_dynamics on the twist:
 *     same iterations and |x − x_clamp| ≤ 1e-12; a fix without `factor` is refused. */
#include "elastopt/impl/method.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

/* ---- per-iteration log ---------------------------------------------------------------- */
#define LOGMAX 1024
typedef struct tlog {
    int count;
    double g[LOGMAX], dec[LOGMAX], proj[LOGMAX];
    int bad_descent, g_increase, bad_proj;
    double g_prev;
} tlog;

static int on_iter(const eo_iter_info *in, void *u)
{
    tlog *L = u;
    if (L->count < LOGMAX) {
        L->g[L->count] = in->g;
        L->dec[L->count] = in->decrement;
        L->proj[L->count] = in->projected;
    }
    if (!isnan(in->decrement) && !(in->decrement > 0)) L->bad_descent++;
    if (!isnan(in->alpha) && !isnan(in->decrement) && !(in->decrement > 0)) L->bad_descent++;
    /* the descent loop accepts rounding-level ties of g (descent.c); more is an increase */
    if (L->count > 0 && in->g > L->g_prev + 1e-12 * fabs(L->g_prev)) L->g_increase++;
    if (!(in->projected >= 0 && in->projected <= 1)) L->bad_proj++;
    L->g_prev = in->g;
    L->count++;
    return 0;
}

/* ---- 1. pin of the iterates before the refactoring ------------------------------------ */
typedef struct pin {
    const char *scene, *fix;
    int step, iters;
    double g_last;
    double g[6];
} pin;

/* Recorded with the code before the Hessian-fix op (commit 9b3e7d5): `elastopt run
 * --scene S -o solver.hessian_fix=F -o time.steps=3`, iterations.csv. */
static const pin pins[] = {
    {"cantilever", "none", 1, 1, 0.0002442524431383366, {0.00024524999999831789, 0.0002442524431383366}},
    {"cantilever", "none", 2, 1, 0.00024245937460519841, {0.00024334667949728062, 0.00024245937460519841}},
    {"cantilever", "none", 3, 1, 0.00024242068086133593, {0.00024322124433295654, 0.00024242068086133593}},
    {"cantilever", "shift", 1, 1, 0.0002442524431383366, {0.00024524999999831789, 0.0002442524431383366}},
    {"cantilever", "shift", 2, 1, 0.00024245937460519841, {0.00024334667949728062, 0.00024245937460519841}},
    {"cantilever", "shift", 3, 1, 0.00024242068086133593, {0.00024322124433295654, 0.00024242068086133593}},
    {"cantilever", "clamp", 1, 1, 0.00024425244313834441, {0.00024524999999831789, 0.00024425244313834441}},
    {"cantilever", "clamp", 2, 1, 0.00024245937477661116, {0.00024334667949704953, 0.00024245937477661116}},
    {"cantilever", "clamp", 3, 1, 0.00024246334441698872, {0.00024326363250659237, 0.00024246334441698872}},
    {"cantilever", "abs", 1, 1, 0.00024425244313835168, {0.00024524999999831789, 0.00024425244313835168}},
    {"cantilever", "abs", 2, 1, 0.00024245937526982291, {0.00024334667949719852, 0.00024245937526982291}},
    {"cantilever", "abs", 3, 1, 0.00024250588302891676, {0.00024330589826071348, 0.00024250588302891676}},
    {"twist", "none", 1, 2, 1.6188502096756407e-06, {5.1420146499911854e-06, 1.6233057137368868e-06, 1.6188502096756407e-06}},
    {"twist", "none", 2, 2, 1.9499705054103295e-06, {4.2034694481908634e-06, 1.9519305262046968e-06, 1.9499705054103295e-06}},
    {"twist", "none", 3, 2, 1.4457762759899637e-05, {1.6239493526131395e-05, 1.4459476681273774e-05, 1.4457762759899637e-05}},
    {"twist", "shift", 1, 2, 1.6188502096756407e-06, {5.1420146499911854e-06, 1.6233057137368868e-06, 1.6188502096756407e-06}},
    {"twist", "shift", 2, 2, 1.9499705054103295e-06, {4.2034694481908634e-06, 1.9519305262046968e-06, 1.9499705054103295e-06}},
    {"twist", "shift", 3, 2, 1.4457762759899637e-05, {1.6239493526131395e-05, 1.4459476681273774e-05, 1.4457762759899637e-05}},
    {"twist", "clamp", 1, 2, 1.6188502110018082e-06, {5.1420146499911854e-06, 1.6233940988741001e-06, 1.6188502110018082e-06}},
    {"twist", "clamp", 2, 2, 1.9550428470777119e-06, {4.2084645174479766e-06, 1.95708169444508e-06, 1.9550428470777119e-06}},
    {"twist", "clamp", 3, 2, 1.446121117374303e-05, {1.6242617004049091e-05, 1.4462933412182992e-05, 1.446121117374303e-05}},
    {"twist", "abs", 1, 2, 1.6188502188483549e-06, {5.1420146499911854e-06, 1.623580357397434e-06, 1.6188502188483549e-06}},
    {"twist", "abs", 2, 2, 1.9646318119790592e-06, {4.2179398593091625e-06, 1.9668190454559535e-06, 1.9646318119790592e-06}},
    {"twist", "abs", 3, 2, 1.4465333419399496e-05, {1.6246204677429505e-05, 1.4467071281932623e-05, 1.4465333419399496e-05}},
    {"inverted", "none", 1, 200, 147.7936006761955, {641.02564102563849, 290.53250555414974, 233.9705136001071, 200.73133961517601, 182.086403909224, 167.15079186330763}},
    {"inverted", "none", 2, 161, 100.0710931514258, {147.7936006761955, 141.0642426825685, 132.01073470223329, 130.96991182571668, 126.42852607170519, 124.64357192338232}},
    {"inverted", "none", 3, 6, 72.627131616700865, {105.81637048824564, 85.87803453971992, 74.294779506041067, 72.730198692705088, 72.62788839216293, 72.627131693595459}},
    {"inverted", "shift", 1, 20, 147.79350695452771, {641.02564102563849, 304.63249424914471, 208.24784099536129, 178.87176594032397, 167.16730614121462, 151.50494790865142}},
    {"inverted", "shift", 2, 16, 100.06280648172394, {147.79350695452771, 103.53183718782492, 102.81971436779813, 102.6011227199091, 102.1519411918905, 101.80648351965955}},
    {"inverted", "shift", 3, 6, 72.6214836311581, {105.8338385780456, 86.077722569004578, 74.514080965697232, 72.757154356007717, 72.622691574753375, 72.621483848008864}},
    {"inverted", "clamp", 1, 23, 145.73275768347287, {641.02564102563849, 282.08010220927326, 197.53800414896216, 161.66348442072405, 148.23805567972698, 146.16556695824062}},
    {"inverted", "clamp", 2, 17, 97.354191267958669, {145.73275768347287, 98.67308601271678, 97.44470148818688, 97.371200511976056, 97.358182198226885, 97.35518747707215}},
    {"inverted", "clamp", 3, 17, 71.287147087637038, {98.556571045758375, 72.819891118116502, 71.51149320454978, 71.328998567209879, 71.295732152033466, 71.289003039074814}},
    {"inverted", "abs", 1, 58, 145.7327576835726, {641.02564102563849, 306.47448752899771, 224.60250743619031, 202.13154523232441, 195.83345433058724, 186.02014264578204}},
    {"inverted", "abs", 2, 28, 97.354186548485998, {145.7327576835726, 99.845487225560234, 97.703036113825618, 97.452266181750105, 97.390533738987187, 97.369175747376602}},
    {"inverted", "abs", 3, 28, 71.287143644600562, {98.556565827059814, 73.851904815852905, 71.937678686755802, 71.498677331667508, 71.362682913774393, 71.315529722344067}},
};

static void test_pin(void)
{
    const size_t np = sizeof pins / sizeof pins[0];
    for (size_t i = 0; i < np;) {
        const pin *p0 = &pins[i];
        char fix[64];
        snprintf(fix, sizeof fix, "solver.hessian_fix=%s", p0->fix);
        /* pinned iterates of the old default stop (absolute decrement 1e-10) */
        const char *ov[] = {fix, "time.steps=3", "solver.stop=newton_decrement", "solver.fallback=[]", NULL};
        eo_ctx *ctx = eo_test_ctx();
        eo_sim *s = NULL;
        int rc = eo_test_sim_open(&s, ctx, p0->scene, NULL, ov);
        CHECK(rc == 0, "%s/%s: open", p0->scene, p0->fix);
        for (; rc == 0 && i < np && pins[i].scene == p0->scene && pins[i].fix == p0->fix; i++) {
            const pin *p = &pins[i];
            static tlog L;
            memset(&L, 0, sizeof L);
            eo_sim_step_result r;
            rc = eo_test_sim_step(s, on_iter, &L, &r);
            CHECK(rc >= 0, "%s/%s step %d: rc %d", p->scene, p->fix, p->step, rc);
            int loose = strcmp(p->fix, "none") == 0 && strcmp(p->scene, "inverted") == 0;
            if (!loose) {
                CHECK(r.iterations == p->iters, "%s/%s step %d: %d iterations, recorded %d", p->scene,
                      p->fix, p->step, r.iterations, p->iters);
                CHECK(fabs(r.g - p->g_last) <= 1e-9 * fabs(p->g_last), "%s/%s step %d: g = %.17g, recorded %.17g",
                      p->scene, p->fix, p->step, r.g, p->g_last);
            }
            int m = p->iters + 1 < 6 ? p->iters + 1 : 6;
            for (int k = 0; k < m && k < L.count; k++)
                CHECK(fabs(L.g[k] - p->g[k]) <= 1e-9 * fabs(p->g[k]), "%s/%s step %d it %d: g = %.17g, recorded %.17g",
                      p->scene, p->fix, p->step, k, L.g[k], p->g[k]);
        }
        eo_sim_destroy(&s);
        eo_test_ctx_done(&ctx);
    }
}

/* ---- 2. the op on the inverted box ------------------------------------------------------ */
typedef struct asm_user {
    eo_objective *obj;
    const double *x;
    eo_linsolve *ls;
    const eo_csc *analyzed;
} asm_user;

static int test_assemble(void *u, eo_proj proj, const unsigned char *proj_of, eo_csc **A, int *reason)
{
    asm_user *a = u;
    int rc = proj_of ? eo_objective_hessian_masked(a->obj, a->x, proj_of, A)
                     : eo_objective_hessian(a->obj, a->x, proj, A);
    if (rc < 0) return rc;
    if (*A != a->analyzed) {
        rc = eo_linsolve_analyze(a->ls, *A);
        if (rc < 0) {
            *reason = EO_DIVERGED_LINSOLVE;
            return EO_OK;
        }
        a->analyzed = *A;
    }
    return EO_OK;
}

static void test_op(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    int rc = eo_test_sim_open(&s, ctx, "inverted", NULL, NULL);
    CHECK(rc == 0, "inverted: open");
    if (rc != 0) {
        eo_sim_destroy(&s);
        eo_test_ctx_done(&ctx);
        return;
    }
    const int n = eo_test_sim_obj(s)->n;
    double *x = eo_test_sim_guess(s);
    double *grad = malloc((size_t)n * sizeof(double)), *p = malloc((size_t)n * sizeof(double));
    double g;
    CHECK(eo_objective_gradient(eo_test_sim_obj(s), x, &g, grad) == EO_OK && isfinite(g), "gradient at x0");
    int ne = eo_objective_n_elements(eo_test_sim_obj(s));
    CHECK(ne > 0, "step objective has %d elements", ne);
    const void *lt;
    eo_registry_find(ctx, EO_KIND_LINSOLVE, "cholmod", &lt);
    for (const void *const *t = eo_registry_list(EO_KIND_HESSFIX); *t; t++) {
        const eo_hessfix_type *hf = *t;
        const char *name = hf->info.name;
        for (int want = 1; want >= 0; want--) {
            eo_linsolve *ls = NULL;
            CHECK(eo_linsolve_create(ctx, lt, NULL, &ls) == EO_OK, "cholmod");
            void *st = calloc(1, hf->state_size ? hf->state_size : 1);
            void *params = NULL;
            if (hf->info.params_size) {
                params = calloc(1, hf->info.params_size);
                eo_params_default(hf->info.params, params);
            }
            asm_user au = {.obj = eo_test_sim_obj(s), .x = x, .ls = ls, .analyzed = NULL};
            eo_solve_result res;
            memset(&res, 0, sizeof res);
            eo_hessfix_env env = {.obj = eo_test_sim_obj(s), .linear = ls, .ctx = ctx, .n = n, .x = x, .g = g,
                                  .grad = grad, .want_direction = want, .descent_eps = 1e-12,
                                  .assemble = test_assemble, .user = &au, .res = &res};
            if (hf->setup) CHECK(hf->setup(st, params, n, ctx) == EO_OK, "%s: setup", name);
            if (hf->begin) CHECK(hf->begin(st, params, &env) == EO_OK, "%s: begin", name);
            eo_hessfix_out out;
            memset(&out, 0, sizeof out);
            for (int i = 0; i < n; i++) p[i] = NAN;
            rc = hf->factor(st, params, &env, p, &out);
            CHECK(rc == EO_OK && out.reason == 0, "%s (want_direction %d): rc %d reason %s", name, want, rc,
                  eo_reason_name(out.reason));
            CHECK(out.projected >= 0 && out.projected <= 1, "%s: projected %g", name, out.projected);
            if (want) {
                double dg = 0, gn = 0, pn = 0;
                for (int i = 0; i < n; i++) {
                    dg += grad[i] * p[i];
                    gn += grad[i] * grad[i];
                    pn += p[i] * p[i];
                }
                CHECK(dg < -1e-12 * sqrt(gn * pn), "%s: grad'p = %g is not a descent direction", name, dg);
                printf("  op %-20s grad'p/(|g||p|) = %+.3f  projected %.3f  shift %.3g  factors %ld%s\n", name,
                       dg / sqrt(gn * pn), out.projected, out.shift, res.n_factor,
                       out.factored ? "" : "  (steepest descent)");
                if (strcmp(name, "none") == 0)
                    CHECK(!out.factored && res.n_fallback == 1, "none: the true Hessian at the inverted start is not PD");
                else
                    CHECK(out.factored, "%s: factored", name);
                if (strcmp(name, "progressive") == 0)
                    CHECK(out.projected > 0 && out.projected < 1, "progressive: projected %g of the elements",
                          out.projected);
            } else {
                CHECK(out.factored, "%s: factors only: factored", name);
            }
            if (hf->destroy) hf->destroy(st, ctx);
            free(st);
            free(params);
            eo_linsolve_destroy(&ls);
        }
    }
    free(grad);
    free(p);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* ---- 3./4. first steps against clamp ---------------------------------------------------- */
typedef struct run_out {
    int n, iters, reason;
    double *x;
    tlog L;
    double projected;
} run_out;

static int run_first(const char *scene, const char *const *extra, const char *fix, const char *opt,
                     const char *tol, run_out *o)
{
    char f[64], op[64], t[64];
    snprintf(f, sizeof f, "solver.hessian_fix=%s", fix);
    snprintf(op, sizeof op, "solver.optimizer=%s", opt);
    snprintf(t, sizeof t, "solver.tol=%s", tol);
    /* tol is an absolute decrement here (the old default rule) */
    const char *ov[16] = {f, op, t, "solver.max_iters=500", "solver.stop=newton_decrement", "solver.fallback=[]"};
    int k = 6;
    for (const char *const *e = extra; e && *e && k < 15; e++) ov[k++] = *e;
    ov[k] = NULL;
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    memset(&o->L, 0, sizeof o->L);
    int rc = eo_test_sim_open(&s, ctx, scene, NULL, ov);
    if (rc == 0) {
        eo_solve_result r;
        double *x = eo_test_sim_guess(s);
        rc = eo_solver_minimize(eo_sim_solver(s), eo_test_sim_obj(s), x, on_iter, &o->L, &r);
        o->n = eo_test_sim_obj(s)->n;
        o->x = malloc((size_t)o->n * sizeof(double));
        memcpy(o->x, x, (size_t)o->n * sizeof(double));
        o->iters = r.iterations;
        o->reason = r.reason;
        o->projected = r.projected;
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return rc;
}

static const char *const static_stvk[] = {"material.model=stvk", "material.E=1e7", NULL};
static const char *const new_fixes[] = {"project_on_demand", "progressive", "trust_region_filter"};

static void test_same_minimizer(void)
{
    struct {
        const char *scene;
        const char *const *extra;
    } sc[] = {{"cantilever", NULL}, {"twist", NULL}, {"inverted", NULL}, {"cantilever_static", static_stvk}};
    for (size_t i = 0; i < sizeof sc / sizeof sc[0]; i++) {
        static run_out ref, o;
        int rc = run_first(sc[i].scene, sc[i].extra, "clamp", "newton", "1e-20", &ref);
        CHECK(rc == 0 && eo_reason_is_converged(ref.reason), "%s/clamp: %s", sc[i].scene, eo_reason_name(ref.reason));
        for (size_t f = 0; f < 3; f++) {
            rc = run_first(sc[i].scene, sc[i].extra, new_fixes[f], "newton", "1e-20", &o);
            double err = 0;
            for (int j = 0; j < o.n && j < ref.n; j++) err = fmax(err, fabs(o.x[j] - ref.x[j]));
            printf("  %-18s %-20s %3d iterations (clamp %3d)  %-22s max |x - x_clamp| = %.2e  mean projected %.3f\n",
                   sc[i].scene, new_fixes[f], o.iters, ref.iters, eo_reason_name(o.reason), err, o.projected);
            CHECK(rc == 0 && (eo_reason_is_converged(o.reason) || o.reason == EO_DIVERGED_STAGNATED),
                  "%s/%s: %s", sc[i].scene, new_fixes[f], eo_reason_name(o.reason));
            CHECK(o.n == ref.n && err <= 1e-9, "%s/%s: |x - x_clamp| = %g", sc[i].scene, new_fixes[f], err);
            CHECK(o.L.bad_descent == 0, "%s/%s: %d non-descent directions", sc[i].scene, new_fixes[f], o.L.bad_descent);
            CHECK(o.L.g_increase == 0, "%s/%s: g increased %d times", sc[i].scene, new_fixes[f], o.L.g_increase);
            CHECK(o.L.bad_proj == 0, "%s/%s: projected fraction outside [0, 1]", sc[i].scene, new_fixes[f]);
            free(o.x);
        }
        free(ref.x);
    }
}

/* q from the last three decrements of a run */
static double rate(const tlog *L)
{
    int k = L->count - 1;
    if (k < 2) return NAN;
    double d1 = L->dec[k - 2], d2 = L->dec[k - 1], d3 = L->dec[k];
    return log(d3 / d2) / log(d2 / d1);
}

static void test_quadratic(void)
{
    const char *const fixes[] = {"clamp", "project_on_demand", "progressive"};
    static run_out o[3];
    for (int f = 0; f < 3; f++) {
        int rc = run_first("cantilever_static", static_stvk, fixes[f], "newton", "1e-10", &o[f]);
        double q = rate(&o[f].L);
        int k = o[f].L.count - 1;
        printf("  cantilever_static stvk E=1e7 %-18s %2d iterations, last decrements %.2e %.2e %.2e, q = %.2f\n",
               fixes[f], o[f].iters, o[f].L.dec[k - 2], o[f].L.dec[k - 1], o[f].L.dec[k], q);
        CHECK(rc == 0 && eo_reason_is_converged(o[f].reason), "%s: %s", fixes[f], eo_reason_name(o[f].reason));
        if (f == 0) CHECK(q <= 1.3, "clamp: q = %.2f, expected linear", q);
        else CHECK(q >= 1.7, "%s: q = %.2f, expected quadratic", fixes[f], q);
        free(o[f].x);
    }
    CHECK(o[1].iters < o[0].iters && o[2].iters < o[0].iters, "iterations: clamp %d, pod %d, progressive %d",
          o[0].iters, o[1].iters, o[2].iters);
}

/* ---- 5. projective_dynamics with every fix ---------------------------------------------- */
static void test_pd_fixes(void)
{
    static run_out ref, o;
    int rc = run_first("cantilever", NULL, "clamp", "projective_dynamics", "1e-14", &ref);
    CHECK(rc == 0 && eo_reason_is_converged(ref.reason), "pd/clamp: %s", eo_reason_name(ref.reason));
    for (const void *const *t = eo_registry_list(EO_KIND_HESSFIX); *t; t++) {
        const char *name = eo_method_info_of(*t)->name;
        rc = run_first("cantilever", NULL, name, "projective_dynamics", "1e-14", &o);
        double err = 0;
        for (int j = 0; j < o.n && j < ref.n; j++) err = fmax(err, fabs(o.x[j] - ref.x[j]));
        CHECK(rc == 0 && eo_reason_is_converged(o.reason) && o.iters == ref.iters && err == 0,
              "pd/%s: %s, %d iterations (clamp %d), |x - x_clamp| = %g", name, eo_reason_name(o.reason), o.iters,
              ref.iters, err);
        CHECK(o.L.bad_descent == 0, "pd/%s: non-descent direction", name);
        free(o.x);
    }
    free(ref.x);
}

/* ---- 5b. project_on_demand's projection -------------------------------------------- */
static void test_pod_projection(void)
{
    const char *const one[] = {"solver.max_iters=1", NULL};
    const char *const one_abs[] = {"solver.max_iters=1", "solver.project_on_demand.projection=abs", NULL};
    static run_out pod_c, pod_a, clamp, abs_;
    int rc = run_first("inverted", one, "project_on_demand", "newton", "1e-20", &pod_c);
    rc |= run_first("inverted", one_abs, "project_on_demand", "newton", "1e-20", &pod_a);
    rc |= run_first("inverted", one, "clamp", "newton", "1e-20", &clamp);
    rc |= run_first("inverted", one, "abs", "newton", "1e-20", &abs_);
    double dc = 0, da = 0, dca = 0;
    for (int j = 0; j < pod_c.n; j++) {
        dc = fmax(dc, fabs(pod_c.x[j] - clamp.x[j]));
        da = fmax(da, fabs(pod_a.x[j] - abs_.x[j]));
        dca = fmax(dca, fabs(clamp.x[j] - abs_.x[j]));
    }
    printf("  inverted, first step: |pod - clamp| = %.2e, |pod(abs) - abs| = %.2e (|clamp - abs| = %.2e)\n", dc, da,
           dca);
    CHECK(rc == 0 && pod_c.iters == 1 && pod_a.iters == 1, "runs of one iteration");
    CHECK(dc == 0 && da == 0 && dca > 0, "pod retries with its projection: %g, %g (clamp vs abs %g)", dc, da, dca);
    CHECK(pod_c.L.proj[0] == 1 && pod_a.L.proj[0] == 1, "the first direction is projected: %g, %g", pod_c.L.proj[0],
          pod_a.L.proj[0]);
    free(pod_c.x), free(pod_a.x), free(clamp.x), free(abs_.x);
}

/* ---- 6. a fix registered at run time, written only against solver.h ---------------- */
static int ext_factor(void *st, const void *params, const eo_hessfix_env *env, double *p,
                      eo_hessfix_out *out)
{
    (void)st, (void)params;
    eo_csc *A = NULL;
    int reason = 0;
    int rc = env->assemble(env->user, EO_PROJ_CLAMP, NULL, &A, &reason);
    if (rc < 0) return rc;
    out->projected = 1;
    if (reason) {
        out->reason = reason;
        return EO_OK;
    }
    rc = eo_linsolve_factor(env->linear, A);
    env->res->n_factor++;
    if (rc < 0 || rc == EO_WARN_NOT_PD) {
        out->reason = rc < 0 ? EO_DIVERGED_LINSOLVE : EO_DIVERGED_NOT_PD;
        return EO_OK;
    }
    out->factored = 1;
    if (!env->want_direction) return EO_OK;
    rc = eo_linsolve_solve(env->linear, env->grad, p);
    if (rc < 0) {
        out->reason = EO_DIVERGED_LINSOLVE;
        return EO_OK;
    }
    for (int i = 0; i < env->n; i++) p[i] = -p[i];
    return EO_OK;
}

static const eo_hessfix_type ext_fix = {
    .info = {.name = "test_external_clamp", .summary = "clamp without safeguard (test plug-in)"},
    .factor = ext_factor,
};

static void test_external_fix(void)
{
    eo_ctx *ctx = eo_test_ctx();
    static const eo_hessfix_type bad = {.info = {.name = "test_no_factor", .summary = "x"}};
    CHECK(eo_register(ctx, EO_KIND_HESSFIX, &bad) == EO_ERR_INVALID, "a fix without factor is refused");
    CHECK(eo_register(ctx, EO_KIND_HESSFIX, &ext_fix) == EO_OK, "register: %s", eo_ctx_message(ctx));
    const char *const opts[] = {"newton", "projective_dynamics"};
    for (int k = 0; k < 2; k++) {
        static run_out ref, o;
        int rc = run_first("twist", NULL, "clamp", opts[k], "1e-14", &ref);
        CHECK(rc == 0, "%s/clamp", opts[k]);
        rc = run_first("twist", NULL, "test_external_clamp", opts[k], "1e-14", &o);
        double err = 0;
        for (int j = 0; j < o.n && j < ref.n; j++) err = fmax(err, fabs(o.x[j] - ref.x[j]));
        CHECK(rc == 0 && eo_reason_is_converged(o.reason) && o.iters == ref.iters && err <= 1e-12,
              "%s/test_external_clamp: %s, %d iterations (clamp %d), |x - x_clamp| = %g", opts[k],
              eo_reason_name(o.reason), o.iters, ref.iters, err);
        free(ref.x);
        free(o.x);
    }
    CHECK(eo_unregister(EO_KIND_HESSFIX, &ext_fix) == EO_OK, "unregister");
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_pin();
    test_op();
    test_same_minimizer();
    test_quadratic();
    test_pd_fixes();
    test_pod_projection();
    test_external_fix();
    return eo_test_finish("test_hessfix");
}
