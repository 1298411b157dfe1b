/* Rigid-body modes left free by the Dirichlet constraints of a scene (scene.h,
 * eo_scene_rigid_modes; the load-time check of static scenes).
 *
 * A static step minimizes E(x) = Σ Vₜψ(Fₜ) + springs − f_gᵀx over the free vertices, with
 * no inertia term. E is invariant under rigid motions of a body, so its Hessian at rest
 * annihilates every infinitesimal rigid motion u(x) = t + ω × x of a connected body that
 * the constraints do not stop: the Newton system is singular and every Cholesky
 * factorization fails. A dynamic integrator adds ½‖x − x̃‖²_M (M positive definite for any
 * finite dt), so only `static` (integrator without inertia) needs supports.
 *
 * Per connected component C of the mesh (vertices joined by tets and by scene/lattice
 * springs), with centroid c and rms radius L of its rest positions X, the rigid modes are
 * u_v(ξ) = B_v ξ, ξ = (t, ω) ∈ ℝ⁶, B_v = [I₃ | −[r_v]×], r_v = (X_v − c)/L. With the Gram
 * matrices
 *
 *     G_C = Σ_{v ∈ C} B_vᵀB_v,    G_F = Σ_{v ∈ C, v constrained} B_vᵀB_v,
 *
 * rank G_C is the number of independent rigid modes of C (6; 5 if its vertices are
 * collinear; 3 for a single point) and a mode ξ is stopped iff its restriction to the
 * constrained vertices is non-zero, i.e. G_F ξ ≠ 0. So the free modes number
 * rank G_C − rank G_F (null G_C ⊆ null G_F since G_F ≤ G_C). Ranks come from the
 * eigenvalues of the 6×6 matrices (cyclic Jacobi) with the relative tolerance
 * EO_RIGID_RTOL · λ_max; the null vectors of G_F name the free modes (a rotation's axis
 * passes through c + L(ω × t)/|ω|²). Constraints act on whole vertices (every boundary
 * motion — fixed, translate, rotate — prescribes all three coordinates), so the cases are:
 * no constrained vertex: 6 modes; all constrained vertices at one point: 3 rotations about
 * it; all on one line: 1 rotation about that line; otherwise 0.
 *
 * Terms that do NOT count as supports: gravity (linear, no stiffness); collision
 * obstacles (penalty k/2·max(0, d)²: no stiffness until a vertex penetrates, and a
 * plane in contact still leaves the tangential translations and the rotation about its
 * normal free; friction needs a velocity, which a static step has not); damping (not
 * allowed with `static`). A spring joins its two vertices into one component: a spring
 * to a constrained vertex supports the component (as a rigid link: a lone spring leaves
 * more modes free than counted, so the count is a lower bound for spring networks). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/scene.h"
#include "elastopt/step.h"
#include "supports.h"

/* ---------------------------------------------------------------- 6×6 symmetric eigen */

/* Cyclic Jacobi: A (6×6, destroyed) = V diag(w) Vᵀ, V's columns the eigenvectors. */
static void jacobi6(double A[6][6], double w[6], double V[6][6])
{
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) V[i][j] = i == j;
    for (int sweep = 0; sweep < 60; sweep++) {
        double off = 0, diag = 0;
        for (int i = 0; i < 6; i++) {
            diag += A[i][i] * A[i][i];
            for (int j = i + 1; j < 6; j++) off += A[i][j] * A[i][j];
        }
        if (off <= 1e-30 * diag || off == 0) break;
        for (int p = 0; p < 6; p++)
            for (int q = p + 1; q < 6; q++) {
                if (A[p][q] == 0) continue;
                double th = (A[q][q] - A[p][p]) / (2 * A[p][q]);
                double t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
                double c = 1 / sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 6; k++) { /* A ← Jᵀ A J */
                    double akp = A[k][p], akq = A[k][q];
                    A[k][p] = c * akp - s * akq;
                    A[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 6; k++) {
                    double apk = A[p][k], aqk = A[q][k];
                    A[p][k] = c * apk - s * aqk;
                    A[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 6; k++) {
                    double vkp = V[k][p], vkq = V[k][q];
                    V[k][p] = c * vkp - s * vkq;
                    V[k][q] = s * vkp + c * vkq;
                }
            }
    }
    for (int i = 0; i < 6; i++) w[i] = A[i][i];
}

/* Number of eigenvalues above rtol·λ_max (0 for a zero matrix). */
static int rank_of(const double w[6], double rtol)
{
    double mx = 0;
    for (int i = 0; i < 6; i++) mx = fmax(mx, fabs(w[i]));
    int r = 0;
    for (int i = 0; i < 6; i++) r += mx > 0 && fabs(w[i]) > rtol * mx;
    return r;
}

/* G += B_vᵀB_v for r = r_v: [[I, −[r]×], [[r]×, |r|²I − rrᵀ]]. */
static void gram_add(double G[6][6], const double r[3])
{
    const double rx[3][3] = {{0, -r[2], r[1]}, {r[2], 0, -r[0]}, {-r[1], r[0], 0}};
    double rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    for (int i = 0; i < 3; i++) {
        G[i][i] += 1;
        for (int j = 0; j < 3; j++) {
            G[i][3 + j] -= rx[i][j];
            G[3 + j][i] -= rx[i][j];
            G[3 + i][3 + j] += (i == j ? rr : 0) - r[i] * r[j];
        }
    }
}

/* ---------------------------------------------------------------- components */

static int uf_find(int *parent, int v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

static void uf_join(int *parent, int a, int b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a != b) parent[a < b ? b : a] = a < b ? a : b;
}

/* ---------------------------------------------------------------- naming */

static void axis_name(const double d[3], char *buf, size_t n)
{
    for (int k = 0; k < 3; k++)
        if (fabs(d[k]) > 1 - 1e-9) {
            snprintf(buf, n, "%c", "xyz"[k]);
            return;
        }
    snprintf(buf, n, "(%.3g, %.3g, %.3g)", d[0], d[1], d[2]);
}

static void cat(char *buf, size_t n, const char *fmt, ...)
{
    size_t l = strlen(buf);
    if (l >= n) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf + l, n - l, fmt, ap);
    va_end(ap);
}

/* Name the free modes of one component: nfix constrained vertices (first one v0 at p0),
 * free modes nfree, rank_all the component's rigid rank, null vectors (columns of V
 * with small eigenvalue flagged in isnull) of G_F, centroid c, radius L. */
static void name_modes(char *buf, size_t n, int nfix, int v0, const double *p0, int nfree, int rank_all,
                       double V[6][6], const int *isnull, const double c[3], double L)
{
    buf[0] = 0;
    if (nfix == 0) {
        cat(buf, n, "translations x, y, z%s", rank_all == 6   ? "; rotations about x, y, z"
                                              : rank_all == 5 ? "; rotations about the two axes across the line of "
                                                                "its vertices"
                                                              : "");
        return;
    }
    if (nfree == 3 && rank_all == 6) {
        if (nfix == 1)
            cat(buf, n, "rotations about x, y, z through the only constrained vertex, %d at (%.4g, %.4g, %.4g)", v0,
                p0[0], p0[1], p0[2]);
        else
            cat(buf, n, "rotations about x, y, z through (%.4g, %.4g, %.4g), where all %d constrained vertices are",
                p0[0], p0[1], p0[2], nfix);
        return;
    }
    int k = 0;
    for (int j = 0; j < 6; j++) {
        if (!isnull[j]) continue;
        double t[3] = {V[0][j], V[1][j], V[2][j]}, w[3] = {V[3][j], V[4][j], V[5][j]};
        double wn = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        char ax[64];
        if (k++) cat(buf, n, "; ");
        if (wn < 1e-6) {
            double tn = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
            double d[3] = {t[0] / tn, t[1] / tn, t[2] / tn};
            axis_name(d, ax, sizeof ax);
            cat(buf, n, "translation along %s", ax);
        } else {
            double d[3] = {w[0] / wn, w[1] / wn, w[2] / wn};
            double wt[3] = {w[1] * t[2] - w[2] * t[1], w[2] * t[0] - w[0] * t[2], w[0] * t[1] - w[1] * t[0]};
            double p[3];
            for (int i = 0; i < 3; i++) p[i] = c[i] + L * wt[i] / (wn * wn);
            /* a point of the axis nearest the first constrained vertex */
            double s = (p0[0] - p[0]) * d[0] + (p0[1] - p[1]) * d[1] + (p0[2] - p[2]) * d[2];
            for (int i = 0; i < 3; i++) p[i] += s * d[i];
            for (int i = 0; i < 3; i++) /* rounding noise of the projection: print 0 */
                if (fabs(p[i]) < 1e-12 * (L + fabs(c[0]) + fabs(c[1]) + fabs(c[2]))) p[i] = 0;
            axis_name(d, ax, sizeof ax);
            cat(buf, n, "rotation about the line through (%.4g, %.4g, %.4g) along %s%s", p[0], p[1], p[2], ax,
                nfix > 1 && nfree == 1 ? ", the line of all constrained vertices" : "");
        }
    }
}

/* ---------------------------------------------------------------- the count */

int eo_scene_rigid_modes(eo_ctx *ctx, const eo_scene *sc, const unsigned char *constrained, eo_rigid_modes *out)
{
    memset(out, 0, sizeof *out);
    out->worst = -1;
    const eo_mesh *m = sc->mesh;
    const int nv = m->nv;
    if (nv <= 0) return EO_OK;
    int *parent = eo_malloc(ctx, (size_t)nv * 2 * sizeof(int));
    if (!parent) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (rigid modes of %d vertices)", nv);
    int *comp = parent + nv;
    for (int v = 0; v < nv; v++) parent[v] = v;
    for (int t = 0; t < m->nt; t++)
        for (int a = 1; a < 4; a++) uf_join(parent, m->tets[4 * t], m->tets[4 * t + a]);
    for (int s = 0; s < sc->nspring; s++) uf_join(parent, sc->spring_ab[2 * s], sc->spring_ab[2 * s + 1]);
    int nc = 0;
    for (int v = 0; v < nv; v++) {
        int r = uf_find(parent, v);
        comp[v] = r == v ? nc++ : comp[r]; /* a root is the component's lowest vertex */
    }
    out->n_components = nc;
    /* per component: count, Σ X, constrained count (one pass each; no allocation per component) */
    typedef struct {
        int n, nfix, v0;
        double c[3], L;
    } cinfo;
    cinfo *ci = eo_calloc(ctx, (size_t)nc, sizeof *ci);
    double(*G)[2][6][6] = eo_calloc(ctx, (size_t)nc, sizeof *G);
    if (!ci || !G) {
        eo_free(ctx, ci);
        eo_free(ctx, G);
        eo_free(ctx, parent);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (rigid modes of %d components)", nc);
    }
    const double *X = m->X;
    for (int v = 0; v < nv; v++) {
        cinfo *q = ci + comp[v];
        if (q->n++ == 0) q->v0 = -1;
        for (int k = 0; k < 3; k++) q->c[k] += X[3 * v + k];
        if (constrained && constrained[v] && q->nfix++ == 0) q->v0 = v;
    }
    for (int i = 0; i < nc; i++)
        for (int k = 0; k < 3; k++) ci[i].c[k] /= ci[i].n;
    for (int v = 0; v < nv; v++) {
        cinfo *q = ci + comp[v];
        for (int k = 0; k < 3; k++) q->L += (X[3 * v + k] - q->c[k]) * (X[3 * v + k] - q->c[k]);
    }
    for (int i = 0; i < nc; i++) ci[i].L = ci[i].L > 0 ? sqrt(ci[i].L / ci[i].n) : 1;
    for (int v = 0; v < nv; v++) {
        cinfo *q = ci + comp[v];
        double r[3];
        for (int k = 0; k < 3; k++) r[k] = (X[3 * v + k] - q->c[k]) / q->L;
        gram_add(G[comp[v]][0], r);
        if (constrained && constrained[v]) gram_add(G[comp[v]][1], r);
    }
    for (int i = 0; i < nc; i++) {
        double w_all[6], w_fix[6], V[6][6], Vf[6][6], Ga[6][6];
        memcpy(Ga, G[i][0], sizeof Ga);
        jacobi6(G[i][0], w_all, V);
        jacobi6(G[i][1], w_fix, Vf);
        int r_all = rank_of(w_all, EO_RIGID_RTOL), r_fix = rank_of(w_fix, EO_RIGID_RTOL);
        int nfree = r_all - r_fix;
        if (nfree <= 0) continue;
        out->n_free += nfree;
        out->n_free_components++;
        if (nfree <= out->worst_free) continue;
        out->worst = i;
        out->worst_free = nfree;
        out->worst_vertices = ci[i].n;
        out->worst_first_vertex = -1;
        for (int v = 0; v < nv && out->worst_first_vertex < 0; v++)
            if (comp[v] == i) out->worst_first_vertex = v;
        double mx = 0;
        for (int j = 0; j < 6; j++) mx = fmax(mx, fabs(w_fix[j]));
        int isnull[6];
        double mx_all = 0;
        for (int j = 0; j < 6; j++) mx_all = fmax(mx_all, fabs(w_all[j]));
        for (int j = 0; j < 6; j++) {
            isnull[j] = !(mx > 0 && fabs(w_fix[j]) > EO_RIGID_RTOL * mx);
            /* not a mode of this body at all (a rotation about the line of a collinear body) */
            double q = 0;
            for (int a = 0; a < 6; a++)
                for (int b = 0; b < 6; b++) q += Vf[a][j] * Ga[a][b] * Vf[b][j];
            if (q <= EO_RIGID_RTOL * mx_all) isnull[j] = 0;
        }
        const double *p0 = ci[i].v0 >= 0 ? X + 3 * ci[i].v0 : ci[i].c;
        name_modes(out->modes, sizeof out->modes, ci[i].nfix, ci[i].v0, p0, nfree, r_all, Vf, isnull, ci[i].c,
                   ci[i].L);
    }
    eo_free(ctx, G);
    eo_free(ctx, ci);
    eo_free(ctx, parent);
    return EO_OK;
}

/* ---------------------------------------------------------------- the load-time check */

/* Constrained vertices at time t (as the step engine: the entries active at t, step_bc.c). */
static void constrained_at(const eo_scene *sc, double t, unsigned char *mask)
{
    memset(mask, 0, (size_t)sc->mesh->nv);
    for (int b = 0; b < sc->nbc; b++) {
        const eo_bc *bc = sc->bc + b;
        if (bc->opts.release >= 0 && t > bc->opts.release + 1e-9 * sc->time.dt) continue;
        for (int i = 0; i < bc->nverts; i++) mask[bc->verts[i]] = 1;
    }
}

int eo_scene_check_supports(eo_ctx *ctx, eo_cfg *cfg, const eo_scene *sc)
{
    const eo_integrator_type *it = sc->integrator;
    if (!it || it->inertia || it->explicit_step || sc->mesh->nv <= 0) return EO_OK;
    unsigned char *mask = eo_malloc(ctx, (size_t)sc->mesh->nv);
    if (!mask) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (supports of %d vertices)", sc->mesh->nv);
    /* the constrained set changes only when an entry is released: check the first step's
     * set and the set of the first step after each release within the run */
    const double h = sc->time.dt;
    int rc = EO_OK;
    for (int e = -1; e < sc->nbc && rc >= 0; e++) {
        double t = h;
        if (e >= 0) {
            double rel = sc->bc[e].opts.release;
            if (rel < 0) continue;
            long k = (long)floor((rel + 1e-9 * h) / h) + 1; /* first step with t_k > release */
            if (k > sc->time.steps || k <= 1) continue;
            t = (double)k * h;
        }
        constrained_at(sc, t, mask);
        eo_rigid_modes rm;
        rc = eo_scene_rigid_modes(ctx, sc, mask, &rm);
        if (rc < 0 || rm.n_free == 0) continue;
        char where[160] = "", when[96] = "";
        if (rm.n_components > 1)
            snprintf(where, sizeof where, " of body %d of %d (the %d vertices joined to vertex %d)", rm.worst + 1,
                     rm.n_components, rm.worst_vertices, rm.worst_first_vertex);
        if (e >= 0) snprintf(when, sizeof when, " from t = %g (after boundary.%d is released)", t, e);
        rc = eo_cfg_error(ctx, cfg, sc->nbc ? "boundary" : "time.integrator", EO_ERR_INVALID,
                          "static scene: the free set%s has %d unconstrained rigid-body mode%s (%s)%s%s: add supports "
                          "(boundary.N with fixed, translate or rotate, on at least three non-collinear vertices of "
                          "each body) or use a dynamic integrator (time.integrator)",
                          where, rm.worst_free, rm.worst_free == 1 ? "" : "s", rm.modes, when,
                          rm.n_free_components > 1 ? "; other bodies too" : "");
    }
    eo_free(ctx, mask);
    return rc;
}
