/* Suite 'unit': Eisenstat–Walker forcing terms (solvers/optim/forcing.c).
 * Hand-computed values of choice 2 and of each safeguard, and the convergence order of
 * an inexact Newton iteration on F(x) = eˣ − 1 whose linear solve leaves exactly the
 * relative residual η_k: the order log(F_{k+1}/F_k)/log(F_k/F_{k−1}) approaches α = 2
 * with the forcing terms (> 1.8 over the last steps), while a constant η = 0.1 only
 * converges linearly (order < 1.2, rate F_{k+1}/F_k → 0.1). */
#include <math.h>

#include "../solvers/optim/forcing.h"
#include "testutil.h"

static void test_values(void)
{
    eo_forcing_params p;
    eo_forcing_params_default(&p);
    CHECK(p.gamma == 0.9 && p.alpha == 2 && p.eta0 == 0.5 && p.eta_max == 0.9, "defaults");
    CHECK(eo_forcing_eta(&p, 0, 3, 7, 0.1) == 0.5, "k = 0 gives eta0");
    /* choice 2: 0.9 (0.1)^2 = 0.009; safeguard (a) inactive: 0.9 * 0.01^2 < 0.1 */
    CHECK_CLOSE(eo_forcing_eta(&p, 3, 1e-2, 1e-1, 0.01), 0.009, 1e-15);
    /* (a): eta_prev = 0.5: 0.9 * 0.25 = 0.225 > 0.1 replaces 0.009 */
    CHECK_CLOSE(eo_forcing_eta(&p, 3, 1e-2, 1e-1, 0.5), 0.225, 1e-15);
    /* (a) only raises: raw 0.9 (0.5)^2 = 0.225 vs floor 0.9 * 0.4^2 = 0.144 */
    CHECK_CLOSE(eo_forcing_eta(&p, 2, 0.5, 1, 0.4), 0.225, 1e-15);
    /* (b): growth of the gradient caps at eta_max */
    CHECK(eo_forcing_eta(&p, 2, 2, 1, 0.1) == 0.9, "eta_max");
    /* (c): gtol = 1e-6, |g| = 1e-6: 0.5 gtol/|g| = 0.5 > raw 0.9e-6 */
    p.gtol = 1e-6;
    CHECK_CLOSE(eo_forcing_eta(&p, 5, 1e-6, 1e-3, 0.01), 0.5, 1e-15);
    CHECK_CLOSE(eo_forcing_eta(&p, 5, 1e-3, 1e-2, 0.01), 0.009, 1e-15); /* (c) inactive: 5e-4 < 0.009 */
    p.gtol = 0;
    /* (d) */
    p.eta_min = 0.05;
    CHECK_CLOSE(eo_forcing_eta(&p, 3, 1e-2, 1e-1, 0.01), 0.05, 1e-15);
    p.eta_min = 0;
    /* alpha = golden ratio (choice 2 with the other exponent of the paper) */
    p.alpha = (1 + sqrt(5.0)) / 2;
    CHECK_CLOSE(eo_forcing_eta(&p, 3, 1e-2, 1e-1, 0.01), 0.9 * pow(0.1, p.alpha), 1e-14);
    eo_forcing_params_default(&p);
    /* non-finite or zero norms: a safe loose solve */
    CHECK(eo_forcing_eta(&p, 2, NAN, 1, 0.1) == 0.9 && eo_forcing_eta(&p, 2, 1, 0, 0.1) == 0.9 &&
              eo_forcing_eta(&p, 2, INFINITY, 1, 0.1) == 0.9,
          "non-finite norms give eta_max");
    CHECK(eo_forcing_eta(&p, 2, 0, 1, 0.1) == 0, "zero gradient: raw 0 stays 0 (nothing to solve)");
}

/* inexact Newton on F(x) = e^x − 1 from x = 2; constant eta if eta_const > 0 */
static int run(double eta_const, double *F, double *eta)
{
    eo_forcing_params p;
    eo_forcing_params_default(&p);
    double x = 2, f = exp(x) - 1, fprev = 0, e = 0;
    int k = 0;
    F[0] = fabs(f);
    for (; k < 60 && fabs(f) > 1e-14; k++) {
        e = eta_const > 0 ? eta_const : eo_forcing_eta(&p, k, fabs(f), fabs(fprev), e);
        eta[k] = e;
        double s = -f * (1 - e) / exp(x); /* F'(x) s + F = e F: relative residual exactly e */
        fprev = f;
        x += s;
        f = exp(x) - 1;
        F[k + 1] = fabs(f);
    }
    return k;
}

static void test_order(void)
{
    double F[64], eta[64];
    int k = run(0, F, eta);
    CHECK(k <= 10, "Eisenstat-Walker inexact Newton: %d iterations to |F| <= 1e-14", k);
    double q1 = log(F[k - 1] / F[k - 2]) / log(F[k - 2] / F[k - 3]);
    double q2 = log(F[k - 2] / F[k - 3]) / log(F[k - 3] / F[k - 4]);
    CHECK(q1 > 1.8 && q2 > 1.8, "order -> 2: %.3f %.3f", q2, q1);
    CHECK(eta[0] == 0.5 && eta[k - 1] < 1e-6, "eta from %g down to %g", eta[0], eta[k - 1]);
    int mono = 1;
    for (int i = 1; i < k; i++) mono &= eta[i] <= eta[i - 1];
    CHECK(mono, "eta decreases monotonically on this convex problem");
    int kc = run(0.1, F, eta);
    double r = F[kc] / F[kc - 1], rp = F[kc - 1] / F[kc - 2];
    double qc = log(F[kc - 1] / F[kc - 2]) / log(F[kc - 2] / F[kc - 3]);
    CHECK(kc > k + 3 && qc < 1.2 && fabs(rp - 0.1) < 0.01, "constant eta 0.1: %d iterations, order %.3f, rate %g %g",
          kc, qc, rp, r);
}

int main(void)
{
    test_values();
    test_order();
    return eo_test_finish("test_forcing");
}
