/* Dahlquist stability, measured (stability.h, notes 001 §2.6): every registered
 * integrator's measured real and imaginary bounds within 1e-3 of the theory table (and
 * the ten of the theory table are all registered; a new one without a row is reported); the one-step amplification of the first-order-form
 * methods equals |R(z)| of their closed-form stability functions at sample points of the
 * complex plane; the spring's one-step matrix of symplectic Euler is the notes'
 * [[1 − h²ω², h], [−hω², 1]]. */
#include <complex.h>
#include <string.h>

#include "elastopt/registry.h"
#include "elastopt/stability.h"
#include "testutil.h"

static double complex R_of(const char *name, double complex z)
{
    if (!strcmp(name, "forward_euler")) return 1 + z;
    if (!strcmp(name, "heun") || !strcmp(name, "midpoint")) return 1 + z + z * z / 2;
    if (!strcmp(name, "rk4")) return 1 + z + z * z / 2 + z * z * z / 6 + z * z * z * z / 24;
    if (!strcmp(name, "backward_euler")) return 1 / (1 - z);
    if (!strcmp(name, "newmark") || !strcmp(name, "implicit_midpoint")) return (1 + z / 2) / (1 - z / 2);
    return NAN;
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    int n = 0, nknown = 0;
    for (const void *const *p = eo_registry_list(EO_KIND_INTEGRATOR); *p; p++, n++) {
        const eo_integrator_type *it = *p;
        const char *name = it->info.name;
        eo_stability_result m, t;
        CHECK(eo_stability_measure(ctx, it, &m) == EO_OK, "%s: measure", name);
        int known = eo_stability_theory(name, &t);
        if (!known) { /* a new integrator: measured, but no theory to hold it to yet */
            printf("test_stability: %s has no theory row (real %s %g, imag %s %g)\n", name,
                   eo_stability_kind_name(m.real.kind), m.real.bound, eo_stability_kind_name(m.imag.kind), m.imag.bound);
            continue;
        }
        nknown++;
        CHECK(eo_stability_axis_agrees(&m.real, &t.real, 1e-3), "%s real: measured %s %.9g, theory %s %.9g", name,
              eo_stability_kind_name(m.real.kind), m.real.bound, eo_stability_kind_name(t.real.kind), t.real.bound);
        CHECK(eo_stability_axis_agrees(&m.imag, &t.imag, 1e-3), "%s imag: measured %s %.9g, theory %s %.9g", name,
              eo_stability_kind_name(m.imag.kind), m.imag.bound, eo_stability_kind_name(t.imag.kind), t.imag.bound);
        if (t.real.kind == EO_STAB_BOUNDED) CHECK(fabs(m.real.bound - t.real.bound) < 1e-9, "%s real bisection", name);
        if (t.imag.kind == EO_STAB_BOUNDED) CHECK(fabs(m.imag.bound - t.imag.bound) < 1e-9, "%s imag bisection", name);
        if (!t.first_order_form) continue;
        eo_test_seed(7);
        for (int s = 0; s < 50; s++) {
            double re = eo_test_rand(-4, 1), im = eo_test_rand(-3, 3), rho;
            CHECK(eo_stability_rho(ctx, it, re, im, &rho) == EO_OK, "%s rho", name);
            double ex = cabs(R_of(name, re + I * im));
            CHECK(fabs(rho - ex) <= 1e-10 * fmax(1, ex), "%s: rho(%g%+gi) = %.15g, |R(z)| = %.15g", name, re, im, rho,
                  ex);
        }
    }
    CHECK(n >= 10 && nknown >= 10, "%d integrators, %d with theory", n, nknown);
    /* the notes' symplectic Euler matrix, hω = 1.5 */
    const eo_integrator_type *se;
    CHECK(eo_registry_find(ctx, EO_KIND_INTEGRATOR, "symplectic_euler", (const void **)&se) == EO_OK, "find");
    double M[4], w2 = 2.25;
    CHECK(eo_stability_matrix(ctx, se, w2, 0, M) == EO_OK, "matrix");
    CHECK_CLOSE(M[0], 1 - w2, 1e-15);
    CHECK_CLOSE(M[1], 1, 1e-15);
    CHECK_CLOSE(M[2], -w2, 1e-15);
    CHECK_CLOSE(M[3], 1, 1e-15);
    CHECK_CLOSE(eo_stability_spectral_radius(M), 1, 1e-14);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_stability");
}
