/* Camera-transmittance x geometry sampling of a camera-ray / VRL pair, one-sample MIS with the
 * product sampler (vrl_tc_pair.h). */
#include "sampling/vrl_tc_pair.h"

#include <stddef.h>


#include "sampling/cauchy.h"

#define TC_FLAT_SLOPE 1e-4

int vbl_vrl_tc_marginal_init(vbl_vrl_tc_marginal* m, const vbl_vrl_pair* p, const vbl_step_pdf* camera, int drops)
{
    m->valid = 0;
    m->count = 0;
    if (!p->valid || !camera || camera->count < 1 || !(p->u1 > p->u0)) return 0;
    /* The camera segment from u0 against the VRL line (the roles of eqs 10-13 swapped); h floored
     * like the sinh marginal's (sampling/sinh_marginal.h). */
    double beta, s, h;
    vbl_vrl_line_projection(p->l_o, p->l_d, p->c_o, p->c_d, p->u0, &beta, &s, &h);
    const double len = p->u1 - p->u0;
    h = fmax(fabs(h), VBL_SAMPLING_H_FLOOR_REL * (len + hypot(h, beta)));
    if (!(h > 0.0) || !isfinite(h) || !isfinite(beta)) return 0;
    m->beta = beta;
    m->s = s;
    m->h = h;
    m->u0 = p->u0;
    m->flat = !(s * len > TC_FLAT_SLOPE * h);
    vbl_vrl_pair_swap(p, &m->swapped);
    /* Merge the camera steps into at most VBL_VRL_TC_MAX_PIECES groups of consecutive steps,
     * each with its length-weighted mean Tc (contiguous: each group starts where one ended). */
    const int n = camera->count;
    const int groups = n < VBL_VRL_TC_MAX_PIECES ? n : VBL_VRL_TC_MAX_PIECES;
    int k = 0;
    double mass = 0.0;
    m->cdf[0] = 0.0;
    for (int gi = 0; gi < groups; ++gi) {
        int ia = (int)((long)gi * n / groups), ib = (int)((long)(gi + 1) * n / groups);
        double xa = vbl_clamp(camera->x[ia], p->u0, p->u1), xb = vbl_clamp(camera->x[ib], p->u0, p->u1);
        if (!(xb > xa)) continue;
        double ty = 0.0;
        for (int i = ia; i < ib; ++i) {
            double lo = vbl_clamp(camera->x[i], p->u0, p->u1), hi = vbl_clamp(camera->x[i + 1], p->u0, p->u1);
            if (drops) ty += i + 1 < n ? fmax(0.0, camera->y[i] - camera->y[i + 1]) : 0.0; /* the drop at x[i+1] */
            else if (hi > lo) ty += camera->y[i] * (hi - lo);
        }
        double y = ty / (xb - xa);
        y = y > 0.0 && isfinite(y) ? y : 0.0;
        if (k == 0) {
            m->x[0] = xa;
            m->a[0] = m->flat ? 0.0 : asinh((beta + s * (xa - p->u0)) / h);
        }
        m->x[k + 1] = xb;
        if (m->flat) {
            double um = 0.5 * (xa + xb) - p->u0;
            m->y[k] = y / hypot(h, beta + s * um);
            mass += m->y[k] * (xb - xa);
        } else {
            m->a[k + 1] = asinh((beta + s * (xb - p->u0)) / h); /* eq 12 */
            m->y[k] = y;
            mass += y * fmax(0.0, m->a[k + 1] - m->a[k]);
        }
        m->cdf[k + 1] = mass;
        ++k;
    }
    m->count = k;
    m->valid = k > 0 && mass > 0.0 && isfinite(mass);
    return m->valid;
}

/* The piece holding u: x[k] <= u < x[k+1] (u == x[n] in the last). */
static int tc_piece(const vbl_vrl_tc_marginal* m, double u)
{
    int lo = 0, hi = m->count - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) >> 1;
        if (m->x[mid] <= u) lo = mid;
        else hi = mid - 1;
    }
    return lo;
}

double vbl_vrl_tc_marginal_pdf(const vbl_vrl_tc_marginal* m, double u)
{
    if (!m->valid || !(u >= m->x[0] && u <= m->x[m->count])) return 0.0;
    int k = tc_piece(m, u);
    if (!(m->y[k] > 0.0) || !(m->cdf[k + 1] > m->cdf[k])) return 0.0;
    const double total = m->cdf[m->count];
    if (m->flat) return m->y[k] / total;
    /* Tc_k / dist(u) over the integral sum_j Tc_j (A_j+1 - A_j) / s */
    return m->s * m->y[k] / (total * hypot(m->h, m->beta + m->s * (u - m->u0)));
}

double vbl_vrl_tc_marginal_sample(const vbl_vrl_tc_marginal* m, double xi, double* pdf)
{
    if (!m->valid) {
        if (pdf) *pdf = 0.0;
        return m->count > 0 ? m->x[0] : 0.0;
    }
    const double total = m->cdf[m->count];
    double target = vbl_clamp(xi, 0.0, 1.0) * total;
    int k = 0;
    while (k < m->count - 1 && m->cdf[k + 1] <= target) ++k;
    while (k > 0 && !(m->cdf[k + 1] > m->cdf[k])) --k; /* xi == 1 past trailing empty pieces */
    double piece_mass = m->cdf[k + 1] - m->cdf[k];
    double xr = piece_mass > 0.0 ? vbl_clamp((target - m->cdf[k]) / piece_mass, 0.0, 1.0) : 0.5;
    double u;
    if (m->flat) {
        u = m->x[k] + xr * (m->x[k + 1] - m->x[k]);
    } else {
        double a = m->a[k] + xr * (m->a[k + 1] - m->a[k]); /* eq 13 within the piece */
        u = m->u0 + (m->h * sinh(a) - m->beta) / m->s;
    }
    u = vbl_clamp(u, m->x[k], m->x[k + 1]);
    if (pdf) *pdf = vbl_vrl_tc_marginal_pdf(m, u);
    return u;
}

double vbl_vrl_tc_technique_pdf(const vbl_vrl_pair* p, const vbl_vrl_tc_marginal* m, double u, double v)
{
    if (!p->valid || !m->valid) return 0.0;
    double pu = vbl_vrl_tc_marginal_pdf(m, u);
    if (!(pu > 0.0)) return 0.0;
    return pu * vbl_vrl_pair_conditional_pdf(&m->swapped, u, v);
}

double vbl_vrl_tc_pair_density(const vbl_vrl_pair* p, const vbl_vrl_tc_marginal* m, double u, double v)
{
    if (!m->valid) return vbl_vrl_pair_density(p, u, v);
    const double c = VBL_VRL_TC_PAIR_SHARE;
    return c * vbl_vrl_pair_density(p, u, v) + (1.0 - c) * vbl_vrl_tc_technique_pdf(p, m, u, v);
}

int vbl_vrl_tc_pair_draw(const vbl_vrl_pair* p, const vbl_vrl_tc_marginal* m, double xi_choice, double xi1,
                         double xi2, vbl_vrl_pair_sample* out)
{
    out->pdf = 0.0;
    if (!p->valid) return 0;
    if (!m->valid) return vbl_vrl_pair_draw(p, xi1, xi2, out) && out->pdf > 0.0;
    if (xi_choice < VBL_VRL_TC_PAIR_SHARE) {
        if (!vbl_vrl_pair_draw(p, xi1, xi2, out) || !(out->pdf > 0.0)) return 0;
    } else {
        double pu;
        double u = vbl_vrl_tc_marginal_sample(m, xi1, &pu);
        if (!(pu > 0.0) || u < p->u0 || u > p->u1) return 0;
        double pv;
        double v = vbl_vrl_pair_draw_conditional(&m->swapped, u, xi2, &pv);
        if (!(pv > 0.0)) return 0;
        out->u = u;
        out->v = v;
    }
    /* both densities as vbl_vrl_tc_pair_density evaluates them at (u, v) */
    out->pdf = vbl_vrl_tc_pair_density(p, m, out->u, out->v);
    return out->pdf > 0.0;
}
