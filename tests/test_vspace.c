/* Sums over an objective's vector space (objective.h, eo_vspace; lib/vspace.c): without a
 * space the plain loop, bit for bit eo_dot's order; on a distributed space the owned
 * entries once, reduced over the parts. Two parts are simulated in one process: part A
 * owns entries 0..2 of its local vector [a0 a1 a2 | copy of b0], part B the rest; the
 * reduce hook adds the other part's partial sum (or takes the max), as MPI_Allreduce would.
 * And the solver's configuration check: solver.backend=petsc refuses methods without
 * EO_METHOD_DISTRIBUTED, naming the method and why. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "elastopt/impl/method.h"
#include "testutil.h"

typedef struct part {
    double other; /* the other part's partial value of the next reduction */
} part;

static int reduce2(double *v, int k, eo_reduce_op op, void *user)
{
    part *p = user;
    for (int i = 0; i < k; i++) v[i] = op == EO_REDUCE_SUM ? v[i] + p->other : fmax(v[i], p->other);
    return 0;
}

static int assemble_none(double *v, void *user)
{
    (void)v, (void)user;
    return 0;
}

int main(void)
{
    /* the whole vector x = (1, 2, 3, 4, 5), y = (5, 4, 3, 2, -7) */
    const double x[5] = {1, 2, 3, 4, 5}, y[5] = {5, 4, 3, 2, -7};
    double plain = 0;
    for (int i = 0; i < 5; i++) plain += x[i] * y[i];
    CHECK(eo_vdot(NULL, 5, x, y) == plain, "no space: the plain loop (%g)", eo_vdot(NULL, 5, x, y));
    CHECK(eo_vnorm_inf(NULL, 5, y) == 7, "no space: max |y| = 7");
    /* part A: local (x0 x1 x2 x3), x3 a copy owned by B */
    const unsigned char ownA[4] = {1, 1, 1, 0};
    part pa = {0};
    eo_vspace A = {.n = 4, .nglobal = 5, .own = ownA, .reduce = reduce2, .assemble = assemble_none, .user = &pa,
                   .nparts = 2};
    pa.other = 4 * 2 + 5 * -7; /* B's owned entries 3, 4 */
    const double d = eo_vdot(&A, 4, x, y);
    CHECK(d == plain, "distributed dot %g, whole %g (the copy counted once)", d, plain);
    pa.other = 4 * 4 + 5 * 5;
    CHECK(fabs(eo_vnorm2(&A, 4, x) - sqrt(55)) < 1e-15, "distributed norm %g vs sqrt(55)", eo_vnorm2(&A, 4, x));
    pa.other = 7;
    CHECK(eo_vnorm_inf(&A, 4, y) == 7, "distributed max |y| from the other part: %g", eo_vnorm_inf(&A, 4, y));
    double v[2] = {1, 2};
    pa.other = 10;
    eo_vreduce(NULL, v, 2, EO_REDUCE_SUM);
    CHECK(v[0] == 1 && v[1] == 2, "no space: reduce leaves the values");
    eo_vreduce(&A, v, 2, EO_REDUCE_SUM);
    CHECK(v[0] == 11 && v[1] == 12, "reduce adds the other part's (%g %g)", v[0], v[1]);

    /* configuration: methods without a distributed form are refused under the backend */
    eo_ctx *ctx = eo_test_ctx();
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    snprintf(o.backend, sizeof o.backend, "petsc");
    snprintf(o.linear, sizeof o.linear, "cholmod");
    eo_solver *s = NULL;
    int rc = eo_solver_create(ctx, &o, NULL, &s);
    CHECK(rc == EO_ERR_UNSUPPORTED && strstr(eo_ctx_message(ctx), "linear solver 'cholmod' has no distributed form"),
          "cholmod refused: rc %d (%s)", rc, eo_ctx_message(ctx));
    eo_solver_opts_default(&o);
    snprintf(o.backend, sizeof o.backend, "petsc");
    snprintf(o.optimizer, sizeof o.optimizer, "projective_dynamics");
    snprintf(o.linear, sizeof o.linear, "cg"); /* auto would name petsc_ksp, absent without the module */
    rc = eo_solver_create(ctx, &o, NULL, &s);
    CHECK(rc == EO_ERR_UNSUPPORTED && strstr(eo_ctx_message(ctx), "'projective_dynamics' has no distributed form") &&
              strstr(eo_ctx_message(ctx), "constant matrix"),
          "projective_dynamics refused: rc %d (%s)", rc, eo_ctx_message(ctx));
    /* without the PETSc module the backend's linear solver is unknown, and said so */
    eo_solver_opts_default(&o);
    snprintf(o.backend, sizeof o.backend, "petsc");
    rc = eo_solver_create(ctx, &o, NULL, &s);
    CHECK(rc == EO_ERR_UNKNOWN_NAME && strstr(eo_ctx_message(ctx), "petsc_ksp"), "no module: rc %d (%s)", rc,
          eo_ctx_message(ctx));
    eo_solver_destroy(&s);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_vspace");
}
