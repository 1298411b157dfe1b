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
 * Gravity holds some free rotations. E is invariant under rotations but −f_gᵀx is not: a
 * body hanging from a point p swings until its centroid is below p, where the rotation
 * ω has the restoring curvature m|g|h(|ω|² − (ω·ĝ)²) (h: centroid below p; the step
 * Hessian's uᵀHu along u = ω × (x − p), the reaction at p doing no work): the rotations
 * about horizontal axes are held, the one about the vertical is not (for a collinear
 * body, a chain, that rotation is about its own line: not a mode). On a hinge line along
 * d the curvature is m|g × d|h⊥: held unless the line is vertical. Neither is held if g = 0
 * or the centroid (of the vertices) is on the point or line, and a body without any
 * constrained vertex never is (it falls; its horizontal translations are flat). The
 * load-time check refuses only modes gravity does not hold (n_unheld): a cloth pinned
 * along a horizontal edge or a chain hanging from one end solve fine statically (their
 * Hessian is singular at the rest start only, where the Hessian fixes shift it).
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

/* Describe mode ξ = (t, ω) of a body with centroid c and radius L; p0: a point the
 * constrained vertices pass through (the axis point printed is the nearest to it). */
static void describe_mode(char *buf, size_t n, const double xi[6], const double c[3], double L, const double *p0,
                          double d_out[3], double p_out[3])
{
    const double *t = xi, *w = xi + 3;
    double wn = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    char ax[64];
    if (wn < 1e-6) {
        double tn = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        double d[3] = {t[0] / tn, t[1] / tn, t[2] / tn};
        axis_name(d, ax, sizeof ax);
        cat(buf, n, "translation along %s", ax);
        for (int i = 0; i < 3; i++) d_out[i] = d[i], p_out[i] = NAN;
        return;
    }
    double d[3] = {w[0] / wn, w[1] / wn, w[2] / wn};
    double wt[3] = {w[1] * t[2] - w[2] * t[1], w[2] * t[0] - w[0] * t[2], w[0] * t[1] - w[1] * t[0]};
    double p[3];
    for (int i = 0; i < 3; i++) p[i] = c[i] + L * wt[i] / (wn * wn);
    double s = (p0[0] - p[0]) * d[0] + (p0[1] - p[1]) * d[1] + (p0[2] - p[2]) * d[2];
    for (int i = 0; i < 3; i++) p[i] += s * d[i];
    for (int i = 0; i < 3; i++) /* rounding noise of the projection: print 0 */
        if (fabs(p[i]) < 1e-12 * (L + fabs(c[0]) + fabs(c[1]) + fabs(c[2]))) p[i] = 0;
    axis_name(d, ax, sizeof ax);
    cat(buf, n, "rotation about the line through (%.4g, %.4g, %.4g) along %s", p[0], p[1], p[2], ax);
    for (int i = 0; i < 3; i++) d_out[i] = d[i], p_out[i] = p[i];
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
        for (int a = 1; a < (m->tet10 ? 10 : 4); a++) /* every node of the tet (tet10: midside too) */
            uf_join(parent, m->tets[4 * t], m->tet10 ? m->tet10[10 * t + a] : m->tets[4 * t + a]);
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
        double w_all[6], w_fix[6], V[6][6], Vf[6][6];
        jacobi6(G[i][0], w_all, V);
        jacobi6(G[i][1], w_fix, Vf);
        int r_all = rank_of(w_all, EO_RIGID_RTOL), r_fix = rank_of(w_fix, EO_RIGID_RTOL);
        int nfree = r_all - r_fix;
        if (nfree <= 0) continue;
        /* the free modes: null G_F with null G_C (not modes of this body) projected out */
        double mx_fix = 0, mx_all = 0, basis[6][6];
        int nb = 0;
        for (int j = 0; j < 6; j++) mx_fix = fmax(mx_fix, fabs(w_fix[j])), mx_all = fmax(mx_all, fabs(w_all[j]));
        for (int j = 0; j < 6 && nb < nfree; j++) {
            if (mx_fix > 0 && fabs(w_fix[j]) > EO_RIGID_RTOL * mx_fix) continue;
            double u[6];
            for (int a = 0; a < 6; a++) u[a] = Vf[a][j];
            for (int k = 0; k < 6; k++) { /* minus its part in null G_C */
                if (fabs(w_all[k]) > EO_RIGID_RTOL * mx_all) continue;
                double dot = 0;
                for (int a = 0; a < 6; a++) dot += u[a] * V[a][k];
                for (int a = 0; a < 6; a++) u[a] -= dot * V[a][k];
            }
            for (int k = 0; k < nb; k++) { /* and along the modes kept */
                double dot = 0;
                for (int a = 0; a < 6; a++) dot += u[a] * basis[k][a];
                for (int a = 0; a < 6; a++) u[a] -= dot * basis[k][a];
            }
            double un = 0;
            for (int a = 0; a < 6; a++) un += u[a] * u[a];
            if (!(sqrt(un) > 1e-6)) continue;
            for (int a = 0; a < 6; a++) basis[nb][a] = u[a] / sqrt(un);
            nb++;
        }
        /* which free modes gravity holds at the equilibrium it leads to: a body hanging
         * from one point (r_fix = 3, all constrained vertices there) swings until its
         * centroid is below the point, where the rotations about horizontal axes have the
         * restoring stiffness m|g|h (h: centroid below the point) and the rotation about the
         * vertical has none (for a collinear body that rotation is about its own line: not a
         * mode); a hinge (r_fix = 5: constrained vertices on one line, direction d) is held
         * unless g ∥ d; neither if g = 0 or the centroid is on the point / line; a free body
         * (no constrained vertex) is never held. */
        const double *g = sc->opts.gravity, *c = ci[i].c, L = ci[i].L;
        const double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        const double *p0 = ci[i].v0 >= 0 ? X + 3 * ci[i].v0 : c;
        double cp[3] = {c[0] - p0[0], c[1] - p0[1], c[2] - p0[2]};
        char names[sizeof out->modes] = "", held[sizeof out->held] = "";
        int unheld = nfree;
        if (ci[i].nfix == 0) {
            cat(names, sizeof names, "translations x, y, z%s",
                r_all == 6 ? "; rotations about x, y, z"
                : r_all == 5 ? "; rotations about the two axes across the line of its vertices" : "");
        } else if (r_fix == 3) {
            if (r_all == 6 && ci[i].nfix == 1)
                cat(names, sizeof names, "rotations about x, y, z through the only constrained vertex, %d at (%.4g, %.4g, %.4g)",
                    ci[i].v0, p0[0], p0[1], p0[2]);
            else if (r_all == 6)
                cat(names, sizeof names, "rotations about x, y, z through (%.4g, %.4g, %.4g), where all %d constrained vertices are",
                    p0[0], p0[1], p0[2], ci[i].nfix);
            double h = sqrt(cp[0] * cp[0] + cp[1] * cp[1] + cp[2] * cp[2]);
            if (gn > 0 && h > 1e-9 * L) {
                unheld = r_all == 6 ? 1 : 0;
                cat(held, sizeof held, "gravity holds %s (the body hangs below the point)%s",
                    r_all == 6 ? "the rotations about horizontal axes" : "them",
                    r_all == 6 ? ", not the rotation about the vertical through it" : "");
            } else {
                cat(held, sizeof held, "gravity holds none of them (%s)",
                    gn > 0 ? "the centroid is at the constrained point" : "no gravity");
            }
        } else if (r_fix == 5 && nfree == 1) {
            double d[3], p[3];
            for (int k = 0; k < nb; k++) {
                describe_mode(names, sizeof names, basis[k], c, L, p0, d, p);
                cat(names, sizeof names, ", the line of all constrained vertices");
            }
            double dg[3] = {d[1] * g[2] - d[2] * g[1], d[2] * g[0] - d[0] * g[2], d[0] * g[1] - d[1] * g[0]};
            double cd = cp[0] * d[0] + cp[1] * d[1] + cp[2] * d[2];
            double off = sqrt(fmax(0, cp[0] * cp[0] + cp[1] * cp[1] + cp[2] * cp[2] - cd * cd));
            double sin_gd = gn > 0 ? sqrt(dg[0] * dg[0] + dg[1] * dg[1] + dg[2] * dg[2]) / gn : 0;
            if (gn > 0 && sin_gd > 1e-9 && off > 1e-9 * L) {
                unheld = 0;
                cat(held, sizeof held, "gravity holds it (the body hangs below the line)");
            } else {
                cat(held, sizeof held, "gravity cannot hold it (%s)",
                    gn == 0 ? "no gravity" : sin_gd <= 1e-9 ? "the line is vertical" : "the centroid is on the line");
            }
        }
        if (!names[0])
            for (int k = 0; k < nb; k++) {
                double d[3], p[3];
                if (k) cat(names, sizeof names, "; ");
                describe_mode(names, sizeof names, basis[k], c, L, p0, d, p);
            }
        out->n_free += nfree;
        out->n_free_components++;
        out->n_unheld += unheld;
        if (unheld < out->worst_unheld || (unheld == out->worst_unheld && nfree <= out->worst_free)) continue;
        out->worst = i;
        out->worst_free = nfree;
        out->worst_unheld = unheld;
        out->worst_vertices = ci[i].n;
        out->worst_first_vertex = -1;
        for (int v = 0; v < nv && out->worst_first_vertex < 0; v++)
            if (comp[v] == i) out->worst_first_vertex = v;
        snprintf(out->modes, sizeof out->modes, "%s", names);
        snprintf(out->held, sizeof out->held, "%s", held);
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
    /* a distributed run (ctx.h, eo_dist_hooks): this part's mesh alone cannot tell the
     * whole body's supports (a part without a constrained vertex is not a free body);
     * not checked there */
    if (eo_ctx_dist(ctx)) return EO_OK;
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
        if (rc < 0 || rm.n_unheld == 0) continue;
        char where[160] = "", when[96] = "";
        if (rm.n_components > 1 && rm.worst_vertices == 1)
            snprintf(where, sizeof where, " of body %d of %d (the lone vertex %d)", rm.worst + 1, rm.n_components,
                     rm.worst_first_vertex);
        else if (rm.n_components > 1)
            snprintf(where, sizeof where, " of body %d of %d (the %d vertices joined to vertex %d)", rm.worst + 1,
                     rm.n_components, rm.worst_vertices, rm.worst_first_vertex);
        if (e >= 0) snprintf(when, sizeof when, " from t = %g (after boundary.%d is released)", t, e);
        rc = eo_cfg_error(ctx, cfg, sc->nbc ? "boundary" : "time.integrator", EO_ERR_INVALID,
                          "static scene: the free set%s has %d unconstrained rigid-body mode%s (%s)%s%s%s%s: add supports "
                          "(boundary.N with fixed, translate or rotate, on at least three non-collinear vertices of "
                          "each body) or use a dynamic integrator (time.integrator)",
                          where, rm.worst_free, rm.worst_free == 1 ? "" : "s", rm.modes, rm.held[0] ? "; " : "",
                          rm.held, when,
                          rm.n_free_components > 1 ? "; other bodies too" : "");
    }
    eo_free(ctx, mask);
    return rc;
}
