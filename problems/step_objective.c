/* The step objective (step.h): one implicit time step as min over the FREE coordinates
 * of
 *
 *     g(x) = ½‖x − x̃‖²_M + w·(E_el(x) − f_gᵀx − cᵀx) [+ springs]
 *
 * (w, x̃, c per integrator). Before every evaluation the free values are scattered into
 * a full work vector whose constrained entries already hold their prescribed positions
 * at tₙ₊₁, the terms (term.h) evaluate on the full vector, and the gradient is gathered
 * back to the free coordinates; assembly scatters through the precomputed maps with no
 * search, sort or allocation. Also eo_step_begin (objective and starting guess of the
 * next step) and eo_step_end (accept xₙ₊₁). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "step_impl.h"

/* ---------------------------------------------------------------- objective ops */

void eo_stepi_scatter_free(eo_step *st, const double *x)
{
    for (int i = 0; i < st->nfree; i++) st->xw[st->free2full[i]] = x[i];
}

/* With a part set, only the coordinates of the part's vertices are read and written. */
static void scatter_part(eo_step *st, const double *x)
{
    const eo_step_part *p = st->part;
    for (int q = 0; q < p->nv; q++)
        for (int c = 0; c < 3; c++) {
            const int j = 3 * p->verts[q] + c, i = st->full2free[j];
            if (i >= 0) st->xw[j] = x[i];
        }
}

static void scatter(eo_step *st, const double *x)
{
    if (st->part) scatter_part(st, x);
    else eo_stepi_scatter_free(st, x);
}

static double sum_energy(eo_step *st, const double *xfull)
{
    double e = 0;
    for (int i = 0; i < st->nterms; i++) e += st->terms[i]->ops->energy(st->terms[i], &st->sys, xfull);
    return isnan(e) ? INFINITY : e;
}

static int op_value(void *data, const double *x, double *g)
{
    eo_step *st = data;
    scatter(st, x);
    *g = sum_energy(st, st->xw);
    return EO_OK;
}

static int op_gradient(void *data, const double *x, double *g, double *grad)
{
    eo_step *st = data;
    const eo_step_part *p = st->part;
    scatter(st, x);
    if (p)
        for (int q = 0; q < p->nv; q++)
            for (int c = 0; c < 3; c++) st->gfull[3 * p->verts[q] + c] = 0;
    else
        memset(st->gfull, 0, (size_t)st->n_full * sizeof(double));
    double e = 0;
    int elastic_done = 0;
    for (int i = 0; i < st->nterms; i++) {
        e += st->terms[i]->ops->gradient(st->terms[i], &st->sys, st->xw, st->gfull);
        elastic_done |= st->terms[i] == st->elastic;
        if (!(e < INFINITY)) break;
    }
    *g = isfinite(e) ? e : INFINITY;
    if (p) {
        for (int q = 0; q < p->nv; q++)
            for (int c = 0; c < 3; c++) {
                const int j = 3 * p->verts[q] + c, i = st->full2free[j];
                if (i >= 0) grad[i] = st->gfull[j];
            }
    } else {
        for (int i = 0; i < st->nfree; i++) grad[i] = st->gfull[st->free2full[i]];
        if (elastic_done && st->inv_x) { /* remembered for op_inverted_count at the same x */
            memcpy(st->inv_x, x, (size_t)st->nfree * sizeof(double));
            st->inv_count = eo_term_elastic_inverted(st->elastic);
            st->inv_valid = 1;
        }
    }
    return EO_OK;
}

/* Zero the Hessian columns of the part's free coordinates (the only ones its terms add to). */
static void zero_part_columns(eo_step *st)
{
    const eo_step_part *p = st->part;
    eo_csc *H = eo_assembler_matrix(st->as);
    for (int q = 0; q < p->nv; q++)
        for (int c = 0; c < 3; c++) {
            const int i = st->full2free[3 * p->verts[q] + c];
            if (i >= 0) memset(H->val + H->colptr[i], 0, (size_t)(H->colptr[i + 1] - H->colptr[i]) * sizeof(double));
        }
}

static int op_hessian(void *data, const double *x, eo_proj proj, eo_csc **H)
{
    eo_step *st = data;
    scatter(st, x);
    if (st->part) zero_part_columns(st);
    else eo_assembler_zero(st->as);
    for (int i = 0; i < st->nterms; i++) {
        int rc = st->terms[i]->ops->hessian(st->terms[i], &st->sys, st->xw, proj);
        if (rc < 0) return rc;
    }
    *H = eo_assembler_matrix(st->as);
    return EO_OK;
}

/* hessian_masked: tet k projected with proj_of[k] (term_elastic.c), the rest unprojected */
static int op_hessian_masked(void *data, const double *x, const unsigned char *proj_of, eo_csc **H)
{
    eo_step *st = data;
    st->sys.proj_of = proj_of;
    int rc = op_hessian(data, x, EO_PROJ_NONE, H);
    st->sys.proj_of = NULL;
    return rc;
}

static int op_n_elements(void *data) { return ((eo_step *)data)->nt; }

static int op_element_residual(void *data, const double *v, double *r)
{
    eo_step *st = data;
    const int npe = st->sys.npe;
    for (int k = 0; k < st->nt; k++) {
        const int *d = st->tet_dofs + (size_t)3 * npe * k;
        double m = 0;
        for (int a = 0; a < npe; a++) {
            double s2 = 0;
            for (int c = 0; c < 3; c++) s2 += d[3 * a + c] >= 0 ? v[d[3 * a + c]] * v[d[3 * a + c]] : 0;
            m = s2 > m ? s2 : m;
        }
        r[k] = sqrt(m);
    }
    return EO_OK;
}

static int op_metric_diag(void *data, double *d)
{
    eo_step *st = data;
    for (int i = 0; i < st->nfree; i++) d[i] = st->vmass[st->free2full[i] / 3];
    return EO_OK;
}

/* Rounding scales of g at x (objective.h, rounding_scale; s[2] = Σ Dᵢxᵢ² + w Σ V(μ + λ),
 * the magnitude of g's summands, for the plateau): the inertia part Σ Dᵢxᵢ²
 * (x − x̃ rounded at ε|x|, seen through M⁻¹), and the elastic part w Σ V(μ + λ)²/μ for
 * the decrement (stresses rounded at (μ + λ)ε, through the softest mode μ) and
 * 3w² Σ a_v²/m_v for the metric gradient norm (nodal forces rounded at ε(μ + λ)A). Tets
 * only: springs and contact add no scale (their stiffness is not a material's). */
static int op_rounding_scale(void *data, const double *x, double s[3])
{
    eo_step *st = data;
    const eo_mesh *m = st->sys.mesh;
    if (!st->rs_a) {
        st->rs_a = eo_calloc(st->ctx, (size_t)(m->nv > 0 ? m->nv : 1), sizeof(double));
        if (!st->rs_a) return eo_error(st->ctx, EO_ERR_NOMEM, "step: out of memory (rounding scale)");
        double el = 0, ev = 0;
        for (int t = 0; t < m->nt; t++) {
            const eo_material_coef *c = st->tet_coef[t];
            const double V = st->vol[t], ml = c->mu + c->lambda;
            if (!(ml > 0)) continue;
            const double mu = c->mu > 1e-12 * ml ? c->mu : 1e-12 * ml;
            el += V * ml * ml / mu;
            ev += V * ml;
            const double a = ml * cbrt(V * V);
            const int npe = st->sys.npe;
            for (int q = 0; q < npe; q++) st->rs_a[st->sys.enodes[(size_t)npe * t + q]] += a;
        }
        st->rs_el = el;
        st->rs_ev = ev;
    }
    double xd = 0, ag = 0;
    for (int i = 0; i < st->nfree; i++) {
        const int j = st->free2full[i], v = j / 3;
        const double mv = st->vmass[v];
        xd += mv * x[i] * x[i];
        if (mv > 0) ag += st->rs_a[v] * st->rs_a[v] / mv;
    }
    const double w = st->w;
    s[0] = xd + w * st->rs_el;
    s[1] = xd + w * w * ag;
    s[2] = xd + w * st->rs_ev;
    return EO_OK;
}

static int op_inverted_count(void *data, const double *x)
{
    eo_step *st = data;
    /* the iterate whose gradient was just evaluated (the optimizers' usual question);
     * the remembered count is of the whole problem, so not while a part is set */
    if (!st->part && st->inv_valid && memcmp(st->inv_x, x, (size_t)st->nfree * sizeof(double)) == 0)
        return st->inv_count;
    scatter(st, x);
    int n = 0;
    if (st->part)
        for (int q = 0; q < st->part->nt; q++) n += eo_tet_is_inverted(eo_stepi_tet_J(st, st->xw, st->part->tets[q]));
    else
        for (int k = 0; k < st->nt; k++) n += eo_tet_is_inverted(eo_stepi_tet_J(st, st->xw, k));
    return n;
}

/* ---------------------------------------------------------------- max_step */

/* c0 + c1 t + c2 t² + c3 t³ */
static double cubic(const double c[4], double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }

/* The smallest root in (lo, hi] of the cubic c (c[0] > 0), or +INFINITY if it has none
 * there. Robust: the real critical points (roots of c1 + 2c2 t + 3c3 t²) cut (0, hi] into
 * intervals on which the cubic is monotone; the first interval whose end value is ≤ 0
 * holds the root, found by bisection to the last bit (no cancellation-prone closed form).
 * hi may be +INFINITY: the last interval is then closed by doubling. */
static double cubic_first_root(const double c[4], double hi)
{
    double cut[4];
    int nc = 0;
    const double a = 3 * c[3], b = 2 * c[2], d = c[1];
    if (a != 0) {
        const double disc = b * b - 4 * a * d;
        if (disc >= 0) {
            const double q = -0.5 * (b + copysign(sqrt(disc), b));
            double r1 = q != 0 ? q / a : 0, r2 = q != 0 ? d / q : 0;
            if (r1 > r2) { double t = r1; r1 = r2; r2 = t; }
            if (r1 > 0 && r1 < hi) cut[nc++] = r1;
            if (r2 > 0 && r2 < hi && r2 != r1) cut[nc++] = r2;
        }
    } else if (b != 0) {
        const double r = -d / b;
        if (r > 0 && r < hi) cut[nc++] = r;
    }
    double lo = 0;
    for (int k = 0; k <= nc; k++) {
        double end = k < nc ? cut[k] : hi;
        if (isinf(end)) { /* last interval unbounded: monotone, so look for a sign change */
            if (c[3] > 0 || (c[3] == 0 && (c[2] > 0 || (c[2] == 0 && c[1] >= 0)))) return INFINITY;
            end = lo > 0 ? 2 * lo : 1;
            for (int j = 0; j < 2100 && cubic(c, end) > 0; j++) end *= 2;
            if (!(cubic(c, end) <= 0)) return INFINITY;
        }
        if (cubic(c, end) <= 0) { /* f(lo) > 0 ≥ f(end): bisection */
            double l = lo, r = end;
            for (int j = 0; j < 200; j++) {
                const double m = 0.5 * (l + r);
                if (!(m > l && m < r)) break;
                if (cubic(c, m) > 0) l = m;
                else r = m;
            }
            return r; /* J(r) ≤ 0 < J(l), r − l one ulp */
        }
        lo = end;
    }
    return INFINITY;
}

static void cross3(const double u[3], const double v[3], double w[3])
{
    w[0] = u[1] * v[2] - u[2] * v[1];
    w[1] = u[2] * v[0] - u[0] * v[2];
    w[2] = u[0] * v[1] - u[1] * v[0];
}
static double dot3(const double u[3], const double v[3]) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

/* det[a0 + t b0, a1 + t b1, a2 + t b2] = c0 + c1 t + c2 t² + c3 t³ (det is linear in each
 * column): four cross products and eight dot products */
static void det_cubic(const double a[3][3], const double b[3][3], double c[4])
{
    double aa[3], ba[3], ab[3], bb[3];
    cross3(a[1], a[2], aa);
    cross3(b[1], a[2], ba);
    cross3(a[1], b[2], ab);
    cross3(b[1], b[2], bb);
    c[0] = dot3(a[0], aa);
    c[1] = dot3(b[0], aa) + dot3(a[0], ba) + dot3(a[0], ab);
    c[2] = dot3(a[0], bb) + dot3(b[0], ab) + dot3(b[0], ba);
    c[3] = dot3(b[0], bb);
}

/* Objective op max_step (objective.h): the first α > 0 where a tet with J > 0 at x
 * reaches J = 0 on x + αp, over the tets (of the part, when one is set). p is scattered
 * into gfull (free coordinates; constrained ones 0: prescribed positions do not move).
 * J(α) = det(Dm⁻¹)·det Ds(α) ∝ det[xᵢ − x₀ + α(pᵢ − p₀)], so the cubic is taken of those
 * edge vectors (the signs of det Dm⁻¹ and of the column order folded in), ~70 flops a tet; a tet whose cubic cannot reach 0
 * before the smallest root found so far (|c1|A + |c2|A² + |c3|A³ < c0) is skipped
 * without root finding. */
static int op_max_step(void *data, const double *x, const double *p, double *alpha_max)
{
    eo_step *st = data;
    const eo_mesh *m = st->sys.mesh;
    scatter(st, x);
    memset(st->gfull, 0, (size_t)st->n_full * sizeof(double));
    for (int i = 0; i < st->nfree; i++) st->gfull[st->free2full[i]] = p[i];
    const int nt = st->part ? st->part->nt : st->nt;
    double best = INFINITY;
    for (int q = 0; q < nt; q++) {
        const int k = st->part ? st->part->tets[q] : q;
        const int *tet = m->tets + 4 * k;
        const double *x0 = st->xw + 3 * tet[0], *p0 = st->gfull + 3 * tet[0];
        double A[3][3], B[3][3], c[4];
        for (int i = 0; i < 3; i++) {
            const double *xi = st->xw + 3 * tet[i + 1], *pi = st->gfull + 3 * tet[i + 1];
            for (int d = 0; d < 3; d++) {
                A[i][d] = xi[d] - x0[d];
                B[i][d] = pi[d] - p0[d];
            }
        }
        det_cubic(A, B, c);
        /* the kernel's Ds has columns xᵢ − x₃ (i = 0, 1, 2): det = −det[x₁ − x₀, x₂ − x₀, x₃ − x₀] */
        if (eo_det3(st->Dminv + 9 * k) > 0)
            for (int j = 0; j < 4; j++) c[j] = -c[j];
        if (eo_tet_is_inverted(c[0])) continue; /* already inverted: not limited */
        if (isfinite(best) && (fabs(c[1]) + (fabs(c[2]) + fabs(c[3]) * best) * best) * best < c[0]) continue;
        const double r = cubic_first_root(c, best);
        if (r < best) best = r;
    }
    *alpha_max = best;
    return EO_OK;
}

/* ---------------------------------------------------------------- characteristic */

/* ‖H‖₂ of a symmetric 3×3 H (power iteration on H², from (1, 1, 1) plus a tilt) */
static double sym3_norm(const double H[9])
{
    double v[3] = {1, 0.7, 0.4}, n = 0;
    for (int it = 0; it < 200; it++) {
        double w[3], u[3];
        for (int i = 0; i < 3; i++) w[i] = H[3 * i] * v[0] + H[3 * i + 1] * v[1] + H[3 * i + 2] * v[2];
        for (int i = 0; i < 3; i++) u[i] = H[3 * i] * w[0] + H[3 * i + 1] * w[1] + H[3 * i + 2] * w[2];
        const double un = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        if (!(un > 0)) return 0;
        const double nn = sqrt(un);
        for (int i = 0; i < 3; i++) v[i] = u[i] / un;
        if (fabs(nn - n) <= 1e-15 * nn) return nn;
        n = nn;
    }
    return n;
}

static double tri_area(const double *a, const double *b, const double *c)
{
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Objective op characteristic (objective.h): BCQN's characteristic gradient norm
 * (Zhu, Bridson & Kaufman 2018 §7 and their code: the per-vertex "perimeter" — the sum of
 * the rest areas of the faces opposite the vertex in its tets — times the norm of the
 * energy's Hessian in the singular values at rest), with per-tet materials folded into
 * a_v, the weight w of E, and the mean stiffness and volume used by bcqn's blend. */
static int op_characteristic(void *data, eo_objective_characteristic *out)
{
    eo_step *st = data;
    const eo_mesh *m = st->sys.mesh;
    if (!st->ch_done) {
        double *a = eo_calloc(st->ctx, (size_t)(m->nv > 0 ? m->nv : 1), sizeof(double));
        if (!a) return eo_error(st->ctx, EO_ERR_NOMEM, "step: out of memory (characteristic scales)");
        double vh = 0, vol = 0;
        for (int t = 0; t < m->nt; t++) {
            const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
            eo_material_eval ev;
            if (eo_material_evaluate(st->tet_type[t], st->tet_coef[t], I, EO_EVAL_HESS, EO_PROJ_NONE, &ev) < 0)
                continue; /* an edge (spring) model: no tet stiffness */
            const double H[9] = {ev.dPdF[0], ev.dPdF[4], ev.dPdF[8], ev.dPdF[36], ev.dPdF[40],
                                 ev.dPdF[44], ev.dPdF[72], ev.dPdF[76], ev.dPdF[80]};
            const double h = sym3_norm(H);
            if (!isfinite(h)) continue;
            const int *tv = m->tets + 4 * t;
            const double *X[4];
            for (int q = 0; q < 4; q++) X[q] = m->X + 3 * tv[q];
            a[tv[0]] += h * tri_area(X[1], X[2], X[3]);
            a[tv[1]] += h * tri_area(X[0], X[2], X[3]);
            a[tv[2]] += h * tri_area(X[0], X[1], X[3]);
            a[tv[3]] += h * tri_area(X[0], X[1], X[2]);
            vh += st->vol[t] * h;
            vol += st->vol[t];
        }
        double a2 = 0;
        for (int v = 0; v < m->nv; v++) a2 += a[v] * a[v];
        eo_free(st->ctx, a);
        st->ch_anorm = sqrt(a2);
        st->ch_vh = vh;
        st->ch_vol = vol;
        st->ch_done = 1;
    }
    out->grad = st->w * st->ch_anorm;
    out->stiffness = st->ch_vol > 0 ? st->w * st->ch_vh / st->ch_vol : 0;
    out->volume = st->ch_vol;
    return EO_OK;
}

static int op_constant_hessian(void *data, eo_csc **L, unsigned long *version)
{
    eo_step *st = data;
    return eo_pd_matrix_get(&st->pd, &st->sys, st->terms, st->nterms, st->pattern_id, st->w, L, version);
}

static int op_inertia(void *data, eo_objective_inertia *out)
{
    eo_step *st = data;
    if (!st->inertia)
        return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "integrator %s has no inertia term (no mass matrix in g)",
                        st->integ->info.name);
    if (!st->Mi || st->Mi_pattern != st->pattern_id) { /* once per pattern */
        eo_assembler_zero(st->as);
        int rc = st->inertia->ops->hessian(st->inertia, &st->sys, st->xw, EO_PROJ_NONE);
        if (rc < 0) return rc;
        eo_csc_destroy(&st->Mi);
        if ((rc = eo_csc_clone(st->ctx, eo_assembler_matrix(st->as), &st->Mi)) < 0) return rc;
        eo_assembler_zero(st->as);
        st->Mi_pattern = st->pattern_id;
    }
    if (!st->fin && !(st->fin = eo_malloc(st->ctx, 2 * (size_t)(st->n_full > 0 ? st->n_full : 1) * sizeof(double))))
        return eo_error(st->ctx, EO_ERR_NOMEM, "out of memory (inertia data)");
    double *xn = st->fin, *xt = st->fin + st->nfree;
    for (int i = 0; i < st->nfree; i++) {
        xn[i] = st->x[st->free2full[i]];
        xt[i] = st->inertia->vec[st->free2full[i]];
    }
    out->M = st->Mi;
    out->version = st->pattern_id;
    out->x_prev = xn;
    out->x_pred = xt;
    out->w = st->w;
    return EO_OK;
}

/* Split ops (objective.h): F_e(x) = Ds(x) Dm⁻¹ of every tet, with the constrained
 * coordinates at their prescribed positions, and its adjoint. */
static int op_split_info(void *data, eo_objective_split *out)
{
    eo_step *st = data;
    if (st->part) return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "split ops: not with a partitioned evaluation");
    if (!st->split_k) {
        st->split_k = eo_calloc(st->ctx, (size_t)(st->nt > 0 ? st->nt : 1), sizeof(double));
        if (!st->split_k) return eo_error(st->ctx, EO_ERR_NOMEM, "step: out of memory (split weights)");
        for (int k = 0; k < st->nt; k++)
            st->split_k[k] = (st->tet_type[k]->flags & EO_MATERIAL_EDGE)
                                 ? 0
                                 : (k > 0 && st->tet_type[k] == st->tet_type[k - 1] && st->tet_coef[k] == st->tet_coef[k - 1])
                                       ? st->split_k[k - 1]
                                       : eo_pd_tet_weight(st->tet_type[k], st->tet_coef[k]);
    }
    out->ne = st->nt;
    out->w = st->w;
    out->type = (const struct eo_material_type *const *)st->tet_type;
    out->coef = (const struct eo_material_coef *const *)st->tet_coef;
    out->vol = st->vol;
    out->k = st->split_k;
    return EO_OK;
}

static int op_split_apply(void *data, const double *x, double *F)
{
    eo_step *st = data;
    eo_stepi_scatter_free(st, x);
    const int *tets = st->sys.mesh->tets;
    for (int k = 0; k < st->nt; k++) {
        double x12[12];
        eo_gather12(st->xw, tets + 4 * k, x12);
        eo_tet_F(st->Dminv + 9 * k, x12, F + 9 * (size_t)k);
    }
    return EO_OK;
}

static int op_split_adjoint(void *data, const double *S, double *out)
{
    eo_step *st = data;
    memset(st->gfull, 0, (size_t)st->n_full * sizeof(double));
    const int *tets = st->sys.mesh->tets;
    for (int k = 0; k < st->nt; k++) {
        const double *Sk = S + 9 * (size_t)k, *Dm = st->Dminv + 9 * k;
        const int *t = tets + 4 * k;
        for (int a = 0; a < 3; a++) { /* row a of F: coordinate a */
            double last = 0;
            for (int c = 0; c < 3; c++) { /* ∂F_ab/∂x_{c,a} = Dm⁻¹_cb; vertex 3 gets minus their sum */
                const double v = Sk[3 * a] * Dm[3 * c] + Sk[3 * a + 1] * Dm[3 * c + 1] + Sk[3 * a + 2] * Dm[3 * c + 2];
                st->gfull[3 * t[c] + a] += v;
                last += v;
            }
            st->gfull[3 * t[3] + a] -= last;
        }
    }
    for (int i = 0; i < st->nfree; i++) out[i] = st->gfull[st->free2full[i]];
    return EO_OK;
}

/* split_assemble (objective.h): every term but the elastic one, then per non-edge tet
 * alpha·GᵀK G with G = ∂vec(F)/∂x12 (F row-major: ∂F_ab/∂x_{c,a} = Dm⁻¹_cb for local
 * vertex c < 3, vertex 3 minus their sum), 12×12 into the tet assembler group. */
static int op_split_assemble(void *data, const double *x, const double *K, double alpha, eo_proj proj, eo_csc **H)
{
    eo_step *st = data;
    if (st->part) return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "split ops: not with a partitioned evaluation");
    eo_stepi_scatter_free(st, x);
    eo_assembler_zero(st->as);
    for (int i = 0; i < st->nterms; i++) {
        if (st->terms[i] == st->elastic) continue;
        int rc = st->terms[i]->ops->hessian(st->terms[i], &st->sys, st->xw, proj);
        if (rc < 0) return rc;
    }
    for (int k = 0; k < st->nt; k++) {
        if (st->tet_type[k]->flags & EO_MATERIAL_EDGE) continue;
        const double *Dm = st->Dminv + 9 * k, *Kk = K + 81 * (size_t)k;
        double b[4][3], KG[9][12], Ke[144];
        for (int c = 0; c < 3; c++) {
            b[3][c] = 0;
            for (int a = 0; a < 3; a++) {
                b[a][c] = Dm[3 * a + c];
                b[3][c] -= Dm[3 * a + c];
            }
        }
        /* G[(3a' + bb)][3v + c] = δ(a', c)·b[v][bb]: F_{a'bb} depends on coordinate c = a' of vertex v */
        for (int r = 0; r < 9; r++)
            for (int v = 0; v < 4; v++)
                for (int c = 0; c < 3; c++) {
                    double sum = 0;
                    for (int bb = 0; bb < 3; bb++) sum += Kk[9 * r + 3 * c + bb] * b[v][bb];
                    KG[r][3 * v + c] = sum;
                }
        for (int v = 0; v < 4; v++)
            for (int c = 0; c < 3; c++)
                for (int q = 0; q < 12; q++) {
                    double sum = 0;
                    for (int bb = 0; bb < 3; bb++) sum += b[v][bb] * KG[3 * c + bb][q];
                    Ke[(3 * v + c) * 12 + q] = alpha * sum;
                }
        eo_assembler_add(st->as, st->sys.tet_group, k, Ke);
    }
    *H = eo_assembler_matrix(st->as);
    return EO_OK;
}

/* ---------------------------------------------------------------- vertex blocks */

/* The terms without a vertex form, or NULL if every term has one. */
static const char *vertex_unsupported(const eo_step *st)
{
    if (st->part) return "a partitioned evaluation";
    for (int b = 0; b < st->sc->nbc; b++)
        if (st->sc->bc[b].partial) return "boundary entry holding some components only (blocks are whole vertices)";
    for (int i = 0; i < st->nterms; i++)
        if (!st->terms[i]->ops->vertex) return st->terms[i]->ops->name;
    return NULL;
}

/* vertex -> tets once (the mesh's), then per pattern the free vertices and their
 * coupling through the tets (allocations here only: once for the mesh, once per pattern) */
static int op_vertex_blocks(void *data, eo_vertex_blocks *out)
{
    eo_step *st = data;
    const char *why = vertex_unsupported(st);
    if (why)
        return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "vertex blocks: the step objective's %s has no per-vertex form",
                        why);
    const eo_mesh *m = st->sys.mesh;
    const int nv = m->nv, nt = m->nt;
    if (!st->vt_ptr) {
        st->vt_ptr = eo_calloc(st->ctx, (size_t)nv + 1, sizeof(int));
        st->vt_tet = eo_malloc(st->ctx, (size_t)(4 * nt > 0 ? 4 * nt : 1) * sizeof(int));
        st->vb_mark = eo_malloc(st->ctx, (size_t)(nv > 0 ? nv : 1) * sizeof(int));
        if (!st->vt_ptr || !st->vt_tet || !st->vb_mark) return eo_error(st->ctx, EO_ERR_NOMEM, "out of memory (vertex blocks)");
        for (int k = 0; k < 4 * nt; k++) st->vt_ptr[m->tets[k] + 1]++;
        for (int v = 0; v < nv; v++) st->vt_ptr[v + 1] += st->vt_ptr[v];
        for (int v = 0; v < nv; v++) st->vb_mark[v] = st->vt_ptr[v];
        for (int k = 0; k < nt; k++) /* increasing tet ids per vertex */
            for (int a = 0; a < 4; a++) st->vt_tet[st->vb_mark[m->tets[4 * k + a]]++] = k;
        st->sys.vt_ptr = st->vt_ptr;
        st->sys.vt_tet = st->vt_tet;
    }
    if (!st->vb_vert || st->vb_pattern != st->pattern_id) {
        int nb = 0;
        for (int v = 0; v < nv; v++) nb += st->full2free[3 * v] >= 0 || st->full2free[3 * v + 1] >= 0 ||
                                            st->full2free[3 * v + 2] >= 0;
        eo_free(st->ctx, st->vb_vert);
        eo_free(st->ctx, st->vb_dofs);
        eo_free(st->ctx, st->vb_ptr);
        eo_free(st->ctx, st->vb_adj);
        st->vb_adj = NULL;
        st->vb_vert = eo_malloc(st->ctx, (size_t)(nb > 0 ? nb : 1) * sizeof(int));
        st->vb_dofs = eo_malloc(st->ctx, (size_t)(3 * nb > 0 ? 3 * nb : 1) * sizeof(int));
        st->vb_ptr = eo_calloc(st->ctx, (size_t)nb + 1, sizeof(int));
        if (!st->vb_vert || !st->vb_dofs || !st->vb_ptr) return eo_error(st->ctx, EO_ERR_NOMEM, "out of memory (vertex blocks)");
        nb = 0;
        for (int v = 0; v < nv; v++) { /* vb_mark: block of v, -1 if none */
            const int *f = st->full2free + 3 * v;
            st->vb_mark[v] = -1;
            if (f[0] < 0 && f[1] < 0 && f[2] < 0) continue;
            st->vb_mark[v] = nb;
            st->vb_vert[nb] = v;
            for (int c = 0; c < 3; c++) st->vb_dofs[3 * nb + c] = f[c];
            nb++;
        }
        /* coupling: two passes (count, fill) over the tets of each block's vertex, a
         * neighbour counted once (last[u] = the block that saw it last) */
        int *last = eo_malloc(st->ctx, (size_t)(nb > 0 ? nb : 1) * sizeof(int));
        if (!last) return eo_error(st->ctx, EO_ERR_NOMEM, "out of memory (vertex blocks)");
        for (int pass = 0; pass < 2; pass++) {
            for (int b = 0; b < nb; b++) last[b] = -1;
            for (int b = 0; b < nb; b++) {
                const int v = st->vb_vert[b];
                int cnt = 0;
                for (int q = st->vt_ptr[v]; q < st->vt_ptr[v + 1]; q++)
                    for (int a = 0; a < 4; a++) {
                        const int u = st->vb_mark[m->tets[4 * st->vt_tet[q] + a]];
                        if (u < 0 || u == b || last[u] == b) continue;
                        last[u] = b;
                        if (pass) st->vb_adj[st->vb_ptr[b] + cnt] = u;
                        cnt++;
                    }
                const int ns = st->spring ? eo_term_spring_degree(st->spring, v) : 0;
                for (int q = 0; q < ns; q++) {
                    const int u = st->vb_mark[eo_term_spring_other(st->spring, v, q)];
                    if (u < 0 || u == b || last[u] == b) continue;
                    last[u] = b;
                    if (pass) st->vb_adj[st->vb_ptr[b] + cnt] = u;
                    cnt++;
                }
                if (!pass) st->vb_ptr[b + 1] = cnt;
            }
            if (!pass) {
                for (int b = 0; b < nb; b++) st->vb_ptr[b + 1] += st->vb_ptr[b];
                st->vb_adj = eo_malloc(st->ctx, (size_t)(st->vb_ptr[nb] > 0 ? st->vb_ptr[nb] : 1) * sizeof(int));
                if (!st->vb_adj) {
                    eo_free(st->ctx, last);
                    return eo_error(st->ctx, EO_ERR_NOMEM, "out of memory (vertex blocks)");
                }
            }
        }
        eo_free(st->ctx, last);
        st->vb_nb = nb;
        st->vb_pattern = st->pattern_id;
    }
    out->nb = st->vb_nb;
    out->dofs = st->vb_dofs;
    out->adj_ptr = st->vb_ptr;
    out->adj = st->vb_adj;
    out->version = st->pattern_id;
    return EO_OK;
}

/* G_b: the free values of the vertices of the block's tets and springs into the work
 * vector (the others are not read), then every term's vertex op */
static int op_vertex_block(void *data, const double *x, int b, eo_proj proj, double *e, double g3[3], double H3[9])
{
    eo_step *st = data;
    if (!st->vb_vert || st->vb_pattern != st->pattern_id || b < 0 || b >= st->vb_nb || vertex_unsupported(st))
        return eo_error(st->ctx, EO_ERR_INVALID, "vertex block %d: no current blocks (call vertex_blocks first)", b);
    const int v = st->vb_vert[b];
    const int *tets = st->sys.mesh->tets;
    for (int c = 0; c < 3; c++) {
        const int i = st->full2free[3 * v + c];
        if (i >= 0) st->xw[3 * v + c] = x[i];
    }
    for (int q = st->vt_ptr[v]; q < st->vt_ptr[v + 1]; q++)
        for (int a = 0; a < 4; a++) {
            const int u = tets[4 * st->vt_tet[q] + a];
            for (int c = 0; c < 3; c++) {
                const int i = st->full2free[3 * u + c];
                if (i >= 0) st->xw[3 * u + c] = x[i];
            }
        }
    const int ns = st->spring ? eo_term_spring_degree(st->spring, v) : 0;
    for (int q = 0; q < ns; q++) {
        const int u = eo_term_spring_other(st->spring, v, q);
        for (int c = 0; c < 3; c++) {
            const int i = st->full2free[3 * u + c];
            if (i >= 0) st->xw[3 * u + c] = x[i];
        }
    }
    if (g3) g3[0] = g3[1] = g3[2] = 0;
    if (H3) memset(H3, 0, 9 * sizeof(double));
    double s = 0;
    for (int i = 0; i < st->nterms; i++) s += st->terms[i]->ops->vertex(st->terms[i], &st->sys, st->xw, v, proj, g3, H3);
    *e = isnan(s) ? INFINITY : s;
    for (int c = 0; c < 3; c++) /* constrained coordinates of a partly free vertex: 0 */
        if (st->full2free[3 * v + c] < 0) {
            if (g3) g3[c] = 0;
            for (int d = 0; d < 3 && H3; d++) H3[3 * c + d] = H3[3 * d + c] = 0;
        }
    return EO_OK;
}

/* The ops every step objective has (whatever its element) */
#define STEPI_COMMON_OPS                                                                       \
    .inertia = op_inertia, .value = op_value, .gradient = op_gradient, .hessian = op_hessian,  \
    .metric_diag = op_metric_diag, .inverted_count = op_inverted_count,                        \
    .constant_hessian = op_constant_hessian, .n_elements = op_n_elements,                      \
    .hessian_masked = op_hessian_masked, .element_residual = op_element_residual,              \
    .constant_factor = eo_stepi_pd_factor, .constant_solve = eo_stepi_pd_solve,                \
    .rounding_scale = op_rounding_scale, .max_step = op_max_step, .characteristic = op_characteristic

/* the linear tet's: also the per-tet ops (one F per tet) and the vertex blocks */
const eo_objective_ops eo_stepi_ops = {
    STEPI_COMMON_OPS,
    .split_info = op_split_info,
    .split_apply = op_split_apply,
    .split_adjoint = op_split_adjoint,
    .split_assemble = op_split_assemble,
    .vertex_blocks = op_vertex_blocks,
    .vertex_block = op_vertex_block,
};

/* The ops of a step whose element is not the linear tet (element.h): without the ops that
 * assume one F per 4-node tet (split_*: ADMM, mixed FEM; vertex blocks: vertex block
 * descent); optimizers that need them are refused when the simulation is created
 * (eo_optimizer_type.needs_ops). */
const eo_objective_ops eo_stepi_ops_element = {STEPI_COMMON_OPS};


/* ---------------------------------------------------------------- partitioned evaluation */

int eo_step_set_part(eo_step *st, const eo_step_part *part)
{
    if (part) {
        if (st->integ->explicit_step)
            return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "partitioned evaluation: integrator %s is explicit",
                            st->integ->info.name);
        for (int i = 0; i < st->nterms; i++)
            if (st->terms[i]->flags & EO_TERM_NO_PART) {
                const eo_term_type *tt = st->terms[i]->type;
                return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "partitioned evaluation: the scene has %s, which has no "
                                "partitioned form yet", tt->section ? tt->section : tt == &eo_term_type_spring ? "springs" : tt->info.name);
            }
        for (int q = 0; q < part->nt; q++)
            if (part->tets[q] < 0 || part->tets[q] >= st->nt)
                return eo_error(st->ctx, EO_ERR_INVALID, "partitioned evaluation: tet %d out of range", part->tets[q]);
        for (int q = 0; q < part->nv; q++)
            if (part->verts[q] < 0 || part->verts[q] >= st->nv)
                return eo_error(st->ctx, EO_ERR_INVALID, "partitioned evaluation: vertex %d out of range",
                                part->verts[q]);
    }
    st->part = part;
    st->sys.part_tets = part ? part->tets : NULL;
    st->sys.part_nt = part ? part->nt : 0;
    st->sys.vown = part ? part->vown : NULL;
    return EO_OK;
}

eo_step *eo_step_of_objective(const eo_objective *obj)
{
    return obj && (obj->ops == &eo_stepi_ops || obj->ops == &eo_stepi_ops_element) ? obj->data : NULL;
}

unsigned long eo_step_pattern_id(const eo_step *st) { return st->pattern_id; }

/* ---------------------------------------------------------------- one step */

static int use_history(const eo_step *st) { return st->integ->history && st->hist_valid; }

double eo_stepi_weight(const eo_step *st)
{
    if (st->integ->accel) return st->integ->accel_weight(st->sc->integrator_params, st->h);
    if (!st->integ->weight) return 1.0; /* explicit: E(x) */
    return use_history(st) && st->integ->weight_history ? st->integ->weight_history(st->h) : st->integ->weight(st->h);
}

double eo_stepi_theta(const eo_step *st)
{
    if (st->integ->accel) return st->integ->accel_theta(st->sc->integrator_params);
    return st->integ->theta > 0 ? st->integ->theta : 1.0;
}

void eo_stepi_velocity(const eo_step *st, const double *x, double *v)
{
    if (st->integ->accel) /* aₙ is valid here: eo_step_begin set it up first */
        st->integ->accel_velocity(st->sc->integrator_params, st->n_full, st->h, st->x, st->v, st->an, x, v, NULL);
    else if (use_history(st) && st->integ->velocity_history)
        st->integ->velocity_history(st->n_full, st->h, st->x, st->xp, x, v);
    else
        st->integ->velocity(st->n_full, st->h, st->x, st->v, x, v);
}

static void step_velocity(const void *vctx, const double *x, double *v) { eo_stepi_velocity(vctx, x, v); }

int eo_stepi_damping_stiffness(eo_step *st)
{
    if (!st->damping || !eo_term_damping_needs_stiffness(st->damping)) return EO_OK;
    eo_assembler_zero(st->as);
    for (int i = 0; i < st->nterms; i++) { /* the elastic-energy terms */
        eo_term *t = st->terms[i];
        if (!(t->flags & EO_TERM_ELASTIC_ENERGY)) continue;
        double wsave = t->weight;
        t->weight = 1;
        int rc = t->ops->hessian(t, &st->sys, st->x, EO_PROJ_CLAMP);
        t->weight = wsave;
        if (rc < 0) return rc;
    }
    eo_term_damping_set_stiffness(st->damping, eo_assembler_matrix(st->as));
    eo_assembler_zero(st->as);
    return EO_OK;
}

/* Damping of an implicit step: the stage velocity v_s = vₙ + θ(vₙ₊₁ − vₙ) as an affine
 * function κ(z − xₙ) + b of the minimizer z (xₙ₊₁ = xₙ + (z − xₙ)/θ), read from two
 * calls of the velocity op (affine with one slope for every coordinate). */
static void damping_begin(eo_step *st)
{
    if (!st->inertia) { /* explicit (the E(x) objective) or static: no damping in g */
        eo_term_damping_set_step(st->damping, &st->sys, st->x, 0, NULL);
        return;
    }
    const double theta = eo_stepi_theta(st);
    double *v0 = st->vnew, *tmp = st->gfull; /* full work vectors, free here */
    eo_stepi_velocity(st, st->x, v0);
    for (int j = 0; j < st->n_full; j++) tmp[j] = st->x[j] + 1.0 / theta;
    eo_stepi_velocity(st, tmp, tmp);
    const double kappa = st->n_full > 0 ? theta * (tmp[0] - v0[0]) : 0;
    for (int j = 0; j < st->n_full; j++) v0[j] = st->v[j] + theta * (v0[j] - st->v[j]);
    eo_term_damping_set_step(st->damping, &st->sys, st->x, kappa, v0);
}

int eo_step_begin(eo_step *st, eo_objective **obj)
{
    const double h = st->h, t1 = eo_stepi_t1(st);
    int rc;
    st->inv_valid = 0; /* new prescribed positions */
    /* constrained set at tₙ₊₁; rebuild the pattern if it changed */
    if ((rc = eo_stepi_update_constraints(st, t1, NULL)) < 0) return rc;
    if (st->integ->accel && !st->hist_valid) { /* start: the consistent acceleration a = M⁻¹f(xₙ, vₙ) */
        if ((rc = eo_stepi_accel(st, st->t, st->x, st->v, st->an)) < 0) return rc;
        st->hist_valid = 1;
    }
    const double w = st->w = eo_stepi_weight(st), theta = eo_stepi_theta(st);
    for (int i = 0; i < st->nterms; i++) st->terms[i]->weight = w;
    if (st->sc->time.load_steps > 0) /* load stepping: λ = min(1, k/L) of the loads (gravity, tractions) */
        for (int i = 0; i < st->nterms; i++)
            if (st->terms[i]->flags & EO_TERM_LOAD_STEPPED)
                st->terms[i]->weight = w * fmin(1.0, eo_stepi_load_steps_done(st) / st->sc->time.load_steps);
    if (st->inertia) {
        st->inertia->weight = 1;
        if (st->integ->accel)
            st->integ->accel_predict(st->sc->integrator_params, st->n_full, h, st->x, st->v, st->an,
                                     st->inertia->vec);
        else if (use_history(st) && st->integ->predict_history)
            st->integ->predict_history(st->n_full, h, st->x, st->v, st->xp, st->vp, st->inertia->vec);
        else
            st->integ->predict(st->n_full, h, st->x, st->v, st->inertia->vec);
    }
    if (st->damping) {
        if ((rc = eo_stepi_damping_stiffness(st)) < 0) return rc;
        damping_begin(st);
    }
    if (st->friction) eo_term_friction_lag(st->friction, &st->sys, st->x, h, st->integ->force_n, step_velocity, st);
    if (st->linear) {
        /* c = fₙ = −∇V(xₙ) − C vₙ (V: the potential terms; C: damping) */
        memset(st->gfull, 0, (size_t)st->n_full * sizeof(double));
        if (st->damping) eo_term_damping_apply(st->damping, &st->sys, st->v, st->gfull);
        eo_stepi_potential_gradient(st, st->x, st->gfull);
        for (int j = 0; j < st->n_full; j++) st->linear->vec[j] = -st->gfull[j];
    }
    /* full work vector: xₙ with prescribed positions at tₙ₊₁ (in the stage: xₙ + θ(p − xₙ)) */
    memcpy(st->xw, st->x, (size_t)st->n_full * sizeof(double));
    for (int v = 0; v < st->nv; v++) {
        if (st->vbc[v] < 0) continue;
        double p[3], vel[3];
        eo_stepi_bc_motion(st, st->sc->bc + st->vbc[v], v, t1, p, vel);
        for (int k = 0; k < 3; k++)
            if (st->sc->bc[st->vbc[v]].mask[k]) st->xw[3 * v + k] = st->x[3 * v + k] + theta * (p[k] - st->x[3 * v + k]);
    }
    /* starting guess: the lower of g(xₙ) and g(x̃) */
    for (int i = 0; i < st->nfree; i++) st->guess[i] = st->x[st->free2full[i]];
    if (st->inertia) {
        double g0, g1;
        op_value(st, st->guess, &g0);
        for (int i = 0; i < st->nfree; i++) st->vnew[i] = st->inertia->vec[st->free2full[i]];
        op_value(st, st->vnew, &g1);
        double gg[2] = {g0, g1}; /* a distributed run: g of every part (ctx.h, eo_dist_hooks) */
        eo_ctx_reduce(st->ctx, gg, 2, EO_REDUCE_SUM);
        g0 = gg[0], g1 = gg[1];
        if (g1 < g0) memcpy(st->guess, st->vnew, (size_t)st->nfree * sizeof(double));
    }
    st->obj.n = st->nfree;
    st->obj.n_value = st->obj.n_gradient = st->obj.n_hessian = 0;
    *obj = &st->obj;
    return EO_OK;
}

double *eo_step_guess(eo_step *st) { return st->guess; }

int eo_step_end(eo_step *st, const double *x)
{
    if (st->integ->explicit_step)
        return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "integrator %s is explicit: advance with eo_step_advance",
                        st->integ->info.name);
    const double t1 = eo_stepi_t1(st), theta = eo_stepi_theta(st);
    st->inv_valid = 0;
    eo_stepi_scatter_free(st, x);
    if (theta != 1) /* the minimizer is the stage z: xₙ₊₁ = xₙ + (z − xₙ)/θ */
        for (int j = 0; j < st->n_full; j++) st->xw[j] = st->x[j] + (st->xw[j] - st->x[j]) / theta;
    for (int v = 0; v < st->nv; v++) { /* prescribed positions exactly */
        if (st->vbc[v] < 0) continue;
        double p[3], vel[3];
        eo_stepi_bc_motion(st, st->sc->bc + st->vbc[v], v, t1, p, vel);
        for (int k = 0; k < 3; k++)
            if (st->sc->bc[st->vbc[v]].mask[k]) st->xw[3 * v + k] = p[k];
    }
    if (st->integ->accel) /* vₙ₊₁ and aₙ₊₁ */
        st->integ->accel_velocity(st->sc->integrator_params, st->n_full, st->h, st->x, st->v, st->an, st->xw, st->vnew,
                                  st->anew);
    else
        eo_stepi_velocity(st, st->xw, st->vnew);
    for (int v = 0; v < st->nv; v++) {
        if (st->vbc[v] < 0) continue;
        double p[3], vel[3];
        eo_stepi_bc_motion(st, st->sc->bc + st->vbc[v], v, t1, p, vel);
        for (int k = 0; k < 3; k++)
            if (st->sc->bc[st->vbc[v]].mask[k]) st->vnew[3 * v + k] = st->integ->inertia ? vel[k] : 0;
    }
    eo_stepi_work_update(st, st->xw, st->vnew);
    if (st->integ->history) {
        memcpy(st->xp, st->x, (size_t)st->n_full * sizeof(double));
        memcpy(st->vp, st->v, (size_t)st->n_full * sizeof(double));
        st->hist_valid = 1;
    }
    if (st->integ->accel) memcpy(st->an, st->anew, (size_t)st->n_full * sizeof(double));
    memcpy(st->x, st->xw, (size_t)st->n_full * sizeof(double));
    memcpy(st->v, st->vnew, (size_t)st->n_full * sizeof(double));
    if (eo_stepi_substep_advance(st)) st->index++; /* a substep inside the nominal step: not yet */
    st->t = t1;
    return EO_OK;
}
