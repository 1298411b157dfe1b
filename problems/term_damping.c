/* Damping term: global viscous and Rayleigh damping (001 §2.1/§2.2, a = (f − γv)/m),
 * damping matrix
 *
 *     C = γ I + α M + β K₀,
 *
 * γ = damping.viscous (N·s/m on every vertex coordinate), α = damping.rayleigh_alpha
 * (1/s, with the scene's mass matrix M, consistent or lumped), β = damping.rayleigh_beta
 * (s) with K₀ the stiffness at the START of the step: the Hessian of the elastic
 * energy (tets and springs) at xₙ, per-element clamped (PSD, so C never adds energy),
 * over the free coordinates (its coupling to prescribed vertices is left out).
 * The damping force is f_d = −C v.
 *
 * Implicit integrators (as a term of the step problem): the force acts at the stage
 * velocity v_s(x) = vₙ + θ(vₙ₊₁(x) − vₙ) (θ = 1 but for implicit_midpoint), affine in
 * the minimizer, v_s = κ(x − xₙ) + b (κ, b from the integrator's velocity op, set per
 * step by the step engine: backward Euler κ = 1/h, b = 0; Newmark κ = 2/h, b = −vₙ;
 * implicit midpoint κ = 2/h, b = 0; bdf2 κ = 3/(2h), b = (xₙ₋₁ − xₙ)/(2h)). With
 * d = x − xₙ the term
 *
 *     D(x) = w (κ/2 dᵀC d + bᵀC d),   ∇D = w C v_s(x),   ∇²D = w κ C,
 *
 * adds w·C v_s to the stationarity condition M(x − x̃) + w(∇E + C v_s) = 0, i.e. the
 * damping force −C v_s next to the elastic one (Newmark's trapezoidal linear term
 * fₙ also carries −C vₙ). Explicit integrators: a = M⁻¹(f − C v) at every stage
 * (eo_term_damping_apply), with K₀ taken at the start of the step too.
 * Nothing is allocated per evaluation; K₀ and M's values are stored per pattern. */
#include <string.h>

#include "elastopt/step.h"
#include "term.h"

typedef struct damping_data {
    double gamma, alpha, beta;
    int lumped;
    double kappa;               /* ∂v_s/∂x, per step */
    double *xn;                 /* n_full: xₙ */
    double *u, *cu;             /* n_full work: κd + b, C(κd + b) */
    double *uf, *kf;            /* nfree work for β K₀ */
    double *mass_val;           /* consistent M in the pattern (α > 0, consistent) */
    eo_csc *K0;                 /* β > 0: K₀ in the pattern (values set per step) */
    int nnz;
} damping_data;

/* out += C u (full vectors). */
void eo_term_damping_apply(eo_term *t, const eo_sys *s, const double *u, double *out)
{
    damping_data *d = t->data;
    if (d->gamma > 0)
        for (int j = 0; j < s->n_full; j++) out[j] += d->gamma * u[j];
    if (d->alpha > 0) {
        if (d->lumped || s->nt == 0) {
            for (int j = 0; j < s->n_full; j++) out[j] += d->alpha * s->vmass[j / 3] * u[j];
        } else {
            for (int k = 0; !s->linear && k < s->nt; k++) { /* a general element: ρV M_el ⊗ I₃ */
                const int n = s->npe, *en = s->enodes + (size_t)n * k;
                const double m = d->alpha * s->rho[k] * s->vol[k];
                for (int a = 0; a < n; a++)
                    for (int b = 0; b < n; b++)
                        for (int c = 0; c < 3; c++) out[3 * en[a] + c] += m * s->el->mass[n * a + b] * u[3 * en[b] + c];
            }
            for (int k = 0; s->linear && k < s->nt; k++) { /* (M_t u)_a = ρV/20 (u_a + Σ_b u_b) */
                const int *tet = s->mesh->tets + 4 * k;
                double sum[3] = {0, 0, 0}, m = d->alpha * s->rho[k] * s->vol[k] / 20.0;
                for (int a = 0; a < 4; a++)
                    for (int c = 0; c < 3; c++) sum[c] += u[3 * tet[a] + c];
                for (int a = 0; a < 4; a++)
                    for (int c = 0; c < 3; c++) out[3 * tet[a] + c] += m * (u[3 * tet[a] + c] + sum[c]);
            }
            for (int j = 0; s->pmass && j < s->n_full; j++) out[j] += d->alpha * s->pmass[j / 3] * u[j];
        }
    }
    if (d->beta > 0 && d->K0) {
        const int nf = d->K0->n;
        for (int j = 0; j < s->n_full; j++)
            if (s->full2free[j] >= 0) d->uf[s->full2free[j]] = u[j];
        if (nf > 0) eo_csc_symv(d->K0, d->uf, d->kf);
        for (int j = 0; j < s->n_full; j++)
            if (s->full2free[j] >= 0) out[j] += d->beta * d->kf[s->full2free[j]];
    }
}

static double energy_grad(eo_term *t, const eo_sys *s, const double *x, double *g)
{
    damping_data *d = t->data;
    const double *b = t->vec;
    for (int j = 0; j < s->n_full; j++) {
        d->u[j] = x[j] - d->xn[j];
        d->cu[j] = 0;
    }
    eo_term_damping_apply(t, s, d->u, d->cu); /* C d */
    double dCd = 0, bCd = 0;
    for (int j = 0; j < s->n_full; j++) {
        dCd += d->u[j] * d->cu[j];
        bCd += b[j] * d->cu[j];
    }
    if (g) { /* w C (κ d + b) */
        for (int j = 0; j < s->n_full; j++) {
            g[j] += t->weight * d->kappa * d->cu[j];
            d->cu[j] = 0;
        }
        eo_term_damping_apply(t, s, b, d->cu);
        for (int j = 0; j < s->n_full; j++) g[j] += t->weight * d->cu[j];
    }
    return t->weight * (0.5 * d->kappa * dCd + bCd);
}

static double energy(eo_term *t, const eo_sys *s, const double *x) { return energy_grad(t, s, x, NULL); }

static double gradient(eo_term *t, const eo_sys *s, const double *x, double *g) { return energy_grad(t, s, x, g); }

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    (void)x, (void)proj;
    damping_data *d = t->data;
    const double c = t->weight * d->kappa;
    if (c == 0) return EO_OK;
    double diag = d->gamma;
    for (int j = 0; j < s->n_full; j++) {
        int i = s->full2free[j];
        if (i < 0) continue;
        double m = d->alpha > 0 && (d->lumped || s->nt == 0) ? d->alpha * s->vmass[j / 3] : 0;
        if (d->alpha > 0 && !(d->lumped || s->nt == 0) && s->pmass) m += d->alpha * s->pmass[j / 3];
        if (diag + m != 0) eo_assembler_add_diag(s->as, i, c * (diag + m));
    }
    eo_csc *H = eo_assembler_matrix(s->as);
    if (d->mass_val) {
        EO_ASSERT(H->nnz == d->nnz);
        for (int k = 0; k < d->nnz; k++) H->val[k] += c * d->alpha * d->mass_val[k];
    }
    if (d->beta > 0 && d->K0) {
        EO_ASSERT(H->nnz == d->K0->nnz);
        for (int k = 0; k < d->K0->nnz; k++) H->val[k] += c * d->beta * d->K0->val[k];
    }
    return EO_OK;
}

/* Per pattern: the consistent mass values (without point masses: those are added on
 * the diagonal in hessian) and the K₀ storage. */
static int prepare(eo_term *t, eo_sys *s)
{
    damping_data *d = t->data;
    eo_csc *H = eo_assembler_matrix(s->as);
    d->nnz = H->nnz;
    if (d->alpha > 0 && !d->lumped && s->nt > 0) {
        eo_free(s->ctx, d->mass_val);
        d->mass_val = eo_malloc(s->ctx, (size_t)(H->nnz > 0 ? H->nnz : 1) * sizeof(double));
        if (!d->mass_val) return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (damping mass)");
        eo_assembler_zero(s->as);
        for (int k = 0; k < s->nt; k++) { /* ρV M_el ⊗ I₃ (elem_H: one element's worth, serial) */
            eo_sys_element_mass(s, k, s->elem_H);
            eo_assembler_add(s->as, s->tet_group, k, s->elem_H);
        }
        memcpy(d->mass_val, H->val, (size_t)H->nnz * sizeof(double));
        eo_assembler_zero(s->as);
    }
    if (d->beta > 0) {
        eo_csc_destroy(&d->K0);
        int rc = eo_csc_clone(s->ctx, H, &d->K0);
        if (rc < 0) return rc;
        memset(d->K0->val, 0, (size_t)d->K0->nnz * sizeof(double));
    }
    return EO_OK;
}

static void destroy(eo_term *t, eo_ctx *ctx)
{
    damping_data *d = t->data;
    if (!d) return;
    eo_free(ctx, d->xn);
    eo_free(ctx, d->mass_val);
    eo_csc_destroy(&d->K0);
    eo_free(ctx, d);
}

static const eo_term_ops damping_ops = {
    .name = "damping",
    .energy = energy,
    .gradient = gradient,
    .hessian = hessian,
    .prepare = prepare,
    .destroy = destroy,
};

int eo_term_damping_create(eo_sys *s, int lumped, double gamma, double alpha, double beta, eo_term **out)
{
    *out = NULL;
    if (!(gamma > 0 || alpha > 0 || beta > 0)) return EO_OK;
    int rc = eo_term_alloc(s, &damping_ops, 1, out);
    if (rc < 0) return rc;
    damping_data *d = eo_calloc(s->ctx, 1, sizeof *d);
    size_t nf = (size_t)(s->n_full > 0 ? s->n_full : 1);
    if (d) d->xn = eo_calloc(s->ctx, 5 * nf, sizeof(double));
    if (!d || !d->xn) {
        eo_free(s->ctx, d);
        eo_term_destroy(s->ctx, out);
        return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (damping)");
    }
    d->u = d->xn + nf;
    d->cu = d->xn + 2 * nf;
    d->uf = d->xn + 3 * nf;
    d->kf = d->xn + 4 * nf;
    d->gamma = gamma;
    d->alpha = alpha;
    d->beta = beta;
    d->lumped = lumped;
    (*out)->data = d;
    return EO_OK;
}

void eo_term_damping_set_step(eo_term *t, const eo_sys *s, const double *xn, double kappa, const double *b)
{
    damping_data *d = t->data;
    memcpy(d->xn, xn, (size_t)s->n_full * sizeof(double));
    d->kappa = kappa;
    if (b) memcpy(t->vec, b, (size_t)s->n_full * sizeof(double));
    else memset(t->vec, 0, (size_t)s->n_full * sizeof(double));
}

int eo_term_damping_needs_stiffness(const eo_term *t) { return ((const damping_data *)t->data)->beta > 0; }

void eo_term_damping_set_stiffness(eo_term *t, const eo_csc *K)
{
    damping_data *d = t->data;
    if (d->K0 && K->nnz == d->K0->nnz) memcpy(d->K0->val, K->val, (size_t)K->nnz * sizeof(double));
}

static int type_create(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out)
{
    (void)cfg;
    return eo_term_damping_create(s, sc->lumped, sc->damping.viscous, sc->damping.rayleigh_alpha,
                                  sc->damping.rayleigh_beta, out);
}

const eo_term_type eo_term_type_damping = {
    .info = {.name = "damping", .summary = "viscous and Rayleigh damping C = γI + αM + βK₀ (`damping`)"},
    .flags = EO_TERM_DAMPING | EO_TERM_NO_PD | EO_TERM_NO_PART,
    .create = type_create,
};
