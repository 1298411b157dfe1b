/* Internal: Eisenstat–Walker forcing terms for inexact Newton (not a public header).
 *
 * Inexact Newton solves H_k p = −∇g_k only to ‖H_k p + ∇g_k‖ <= η_k ‖∇g_k‖ (with an
 * iterative linear solver: eo_linsolve_set_rtol(ls, η_k)). Eisenstat & Walker 1996,
 * "Choosing the forcing terms in an inexact Newton method", SIAM J. Sci. Comput. 17,
 * choice 2:
 *
 *   η_0 = eta0,   η_k = γ (‖∇g_k‖ / ‖∇g_{k−1}‖)^α          (k >= 1)
 *
 * with the safeguards of the paper and of Kelley (1995, §6.3):
 *   (a) no sudden drop: if γ η_{k−1}^α > 0.1, η_k = max(η_k, γ η_{k−1}^α)
 *       (the forcing term may shrink only as fast as the convergence allows);
 *   (b) η_k = min(η_k, eta_max);
 *   (c) no oversolving at the end: η_k = max(η_k, 0.5 gtol / ‖∇g_k‖) when gtol > 0
 *       (gtol: the absolute gradient tolerance of the stopping test);
 *   (d) η_k = max(η_k, eta_min).
 * With γ ∈ (0, 1] and α ∈ (1, 2] the local convergence is of order α (Theorem 2.2).
 * Defaults: γ = 0.9, α = 2, η_0 = 0.5, eta_max = 0.9, eta_min = 0, gtol = 0.
 * Non-finite or non-positive norms give eta_max (a safe, loose solve). */
#ifndef EO_OPTIM_FORCING_H
#define EO_OPTIM_FORCING_H

#include "elastopt/params.h"

typedef struct eo_forcing_params {
    double gamma;   /* γ, default 0.9 */
    double alpha;   /* α, default 2 */
    double eta0;    /* η_0, default 0.5 */
    double eta_max; /* default 0.9 */
    double eta_min; /* default 0 */
    double gtol;    /* absolute gradient tolerance for safeguard (c); 0: off (default) */
} eo_forcing_params;

/* Descriptor table of eo_forcing_params (keys = field names), for a caller's params. */
extern const eo_param_desc eo_forcing_desc[];

void eo_forcing_params_default(eo_forcing_params *p);

/* η_k for iteration k (k = 0: eta0, the norms are then ignored) from ‖∇g_k‖,
 * ‖∇g_{k−1}‖ and η_{k−1}. */
double eo_forcing_eta(const eo_forcing_params *p, int k, double gnorm, double gnorm_prev, double eta_prev);

/* Eisenstat–Walker choice 1 (the paper's eq. 2.1 with safeguard 2.2):
 *   η_k = | ‖∇g_k‖ − ‖∇g_{k−1} + H_{k−1} s_{k−1}‖ | / ‖∇g_{k−1}‖        (k >= 1)
 * (linres_prev = ‖∇g_{k−1} + H_{k−1}s_{k−1}‖, the linear model's residual at the step
 * taken), then if η_{k−1}^φ > 0.1 (φ = (1+√5)/2): η_k = max(η_k, η_{k−1}^φ); then
 * safeguards (b)–(d) above. Local convergence is superlinear of order φ (Thm 2.2). */
double eo_forcing_eta_ew1(const eo_forcing_params *p, int k, double gnorm, double gnorm_prev,
                          double linres_prev, double eta_prev);

/* Newton's use of the forcing terms (solver.newton.forcing): the state of one
 * minimization. eo_inexact_begin at the start (local_ratio 0.1, eta_global 1e-4; the caller
 * may set the fields after); eo_inexact_before before each direction (sets the linear solver's rtol,
 * returns η_k, 0 when forcing = none); eo_inexact_after once the step from that
 * direction is accepted (linres = ‖∇g_k + αH̃p_k‖, only read by ew1; alpha the step
 * length and dec the direction's λ²/2, read by auto). Nothing is allocated. */
/* EO_FORCING_AUTO: ew2 while the linear solver's solves are iterative
 * (eo_linsolve_is_iterative, asked at every direction) and Newton converges fast: the
 * previous step was full (accepted α = 1) and, from the third direction on, the last
 * decrement λ²/2 fell to at most local_ratio (default 0.1) times the one before; else
 * η = eta_global (default 1e-4): an inexact direction pays only where Newton is already
 * in its region of fast local convergence. None while the solves are direct. Measured
 * (docs/defaults.md, the linear solver policy): on the IPC bar twist with 10-node p2p0
 * tets (n = 14 631, PCG with a reused factor) ew2 at every direction took 212 and 247
 * Newton iterations over 4 steps at ν = 0.499 and 0.4999 where exact directions take
 * 61 and 59, because ‖∇g‖ did not fall and η stayed at 0.5–0.9; with this rule the
 * iterations are the exact ones. Where Newton converges fast from the start (the
 * 115k-tet bunny: every step full, the decrement falling 20–40× per iteration) it
 * changes nothing. A guarded solve that needs more than global_max_iters (20) linear
 * iterations ends the guard for the rest of the minimization: such a solver reaches
 * 1e-4 only at a high price and has no direct fallback (PCG + Galerkin multigrid on the
 * ν = 0.4999 hammer: 3.14 s against 2.61 s unguarded; with the escape 2.48 s), whereas
 * a reused factor's solve gives up by its cap and refactors (0 iterations reported). eta_global = 1e-4 rather than the solver's own 1e-10: the same Newton
 * iterations, 10 % less CPU on a ν = 0.499 linear-tet twist (the stale factor's extra
 * CG iterations). */
enum { EO_FORCING_NONE, EO_FORCING_CONSTANT, EO_FORCING_EW1, EO_FORCING_EW2, EO_FORCING_AUTO };
typedef struct eo_inexact {
    int kind;
    eo_forcing_params fp;
    int k;              /* directions computed in this minimization */
    double eta_prev, gnorm_prev, linres_prev;
    double alpha_prev;  /* step length accepted after the previous direction (NAN: none) */
    double dec_prev, dec_prev2; /* decrements λ²/2 of the last two accepted directions */
    double local_ratio; /* auto: fast local convergence = dec_prev <= local_ratio dec_prev2 */
    double eta_global;  /* auto: η before fast local convergence */
    int global_max_iters; /* auto: a solve at eta_global needing more iterations ends the guard */
    int guard_off;        /* auto: the guard ended for this minimization */
    int guarded;          /* auto: the last direction was solved at eta_global */
} eo_inexact;

/* kind from its name ("none", "constant", "ew1", "ew2", "auto"); -1 if unknown. */
int eo_forcing_kind(const char *name);
void eo_inexact_begin(eo_inexact *s, int kind, double eta, double gamma, double alpha, double eta_min,
                      double eta_max);
struct eo_linsolve;
double eo_inexact_before(eo_inexact *s, struct eo_linsolve *ls, double gnorm);
void eo_inexact_after(eo_inexact *s, double gnorm, double linres, double alpha, double dec);

#endif
