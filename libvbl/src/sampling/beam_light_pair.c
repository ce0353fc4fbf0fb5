/* VBL media-to-media sampling and VSL kernel: Novak et al. 2012 (VBL), sections 3.1-3.2,
 * eqs. 9-10. */
#include "sampling/beam_light_pair.h"

#include <stddef.h>

#include "sampling/cauchy.h"
#include "sampling/phase_hg.h"
#include "sampling/piecewise_linear.h"
#include "sampling/vrl_pair.h"
#include "sampling/vsl_cone.h"

int vbl_beam_light_pair_init(vbl_beam_light_pair* p, vbl_vec3 c_o, vbl_vec3 c_d, double u0, double u1, vbl_vec3 l_o,
                      vbl_vec3 l_d, double v0, double v1, double g_camera, double g_light, double radius)
{
    p->c_o = c_o;
    p->c_d = c_d;
    p->l_o = l_o;
    p->l_d = l_d;
    p->u0 = u0;
    p->u1 = u1;
    p->v0 = v0;
    p->v1 = v1;
    p->g_camera = g_camera;
    p->g_light = g_light;
    p->radius = (radius > 0.0 && isfinite(radius)) ? radius : 0.0;
    p->valid = 0;
    p->isotropic = g_camera == 0.0 && g_light == 0.0;
    if (!(u1 > u0) || !(v1 > v0) || !(radius >= 0.0) || !isfinite(radius)) {
        vbl_sinh_marginal_init(&p->marginal, 0.0, 0.0, 0.0, 0.0);
        return 0;
    }
    /* Same projection as the VRL sampler: distance of l(v0 + t) to the camera line is
     * sqrt(h^2 + (beta + s t)^2); stage 1 uses sqrt(h^2 + R^2 + (beta + s t)^2). */
    double beta, s, h;
    vbl_vrl_line_projection(c_o, c_d, l_o, l_d, v0, &beta, &s, &h);
    p->valid = vbl_sinh_marginal_init(&p->marginal, beta, s, hypot(h, p->radius), v1 - v0);
    return p->valid;
}

/* Stage-2 geometry about the VSL centre x = l(v): projection u_p on the camera line, the
 * perpendicular vector perp (camera-line foot -> x), true distance D = |perp|, softened distance
 * D' = hypot(D, R) (floored as in the VRL sampler), unit n from x towards the line, and the
 * angular range [phi0, phi1] with u = u_p + D' tan(phi). */
typedef struct arc {
    vbl_vec3 x, perp, n;
    double up, d, dsoft, phi0, phi1;
} arc;

static int arc_make(const vbl_beam_light_pair* p, double v, arc* a)
{
    a->x = vbl_v3_madd(p->l_o, p->l_d, v);
    vbl_vec3 rel = vbl_v3_sub(a->x, p->c_o);
    a->up = vbl_v3_dot(rel, p->c_d);
    a->perp = vbl_v3_cross(p->c_d, vbl_v3_cross(rel, p->c_d));
    a->d = vbl_v3_length(a->perp);
    double lo = p->u0 - a->up, hi = p->u1 - a->up;
    a->dsoft = fmax(hypot(a->d, p->radius), VBL_SAMPLING_H_FLOOR_REL * fmax(fabs(lo), fabs(hi)));
    if (!(a->dsoft > 0.0) || !isfinite(a->dsoft)) return 0;
    if (a->d > 0.0) {
        a->n = vbl_v3_scale(a->perp, -1.0 / a->d);
    } else {
        vbl_vec3 b;
        vbl_v3_basis(p->c_d, &a->n, &b);
    }
    a->phi0 = atan2(lo, a->dsoft);
    a->phi1 = atan2(hi, a->dsoft);
    return a->phi1 > a->phi0;
}

static double hg_product(const vbl_beam_light_pair* p, vbl_vec3 w)
{
    return vbl_hg_eval(p->g_light, vbl_v3_dot(p->l_d, w)) * vbl_hg_eval(p->g_camera, -vbl_v3_dot(p->c_d, w));
}

/* A vertex value of stage 2: f_l f_c over the VSL cone seen from the camera point at offset
 * du = u - u_p, as the larger of the axis and the two least-rotation directions to the lobes'
 * peaks (section 3.1's omega'_max; a lower estimate of the cone's maximum, exact for one flat lobe),
 * and the axis value alone for cones thinner than VBL_BEAM_LIGHT_PAIR_THIN (R / w). Any positive
 * vertex values give a valid density (draw and density share them); the 17-point geodesic search of
 * vbl_vsl_cone_hg_product_max cost ~75% of a vbl pass (perf, issue 13) for a few percent of shape. */
static double cone_value(const vbl_beam_light_pair* p, const arc* a, double du)
{
    vbl_vec3 d = vbl_v3_sub(vbl_v3_scale(p->c_d, du), a->perp); /* x_c - x */
    double w = vbl_v3_length(d);
    if (w > 0.0 && p->radius <= VBL_BEAM_LIGHT_PAIR_THIN * w) return hg_product(p, vbl_v3_scale(d, 1.0 / w));
    vbl_vsl_cone cone;
    vbl_vsl_cone_init(&cone, d, p->radius, vbl_v3_scale(a->n, -1.0));
    double f = hg_product(p, cone.axis);
    if (p->g_light != 0.0)
        f = fmax(f, hg_product(p, vbl_vsl_cone_closest(&cone, p->g_light > 0.0 ? p->l_d : vbl_v3_scale(p->l_d, -1.0))));
    if (p->g_camera != 0.0)
        f = fmax(f, hg_product(p, vbl_vsl_cone_closest(&cone, p->g_camera > 0.0 ? vbl_v3_scale(p->c_d, -1.0) : p->c_d)));
    return f;
}

static int arc_pwl(const vbl_beam_light_pair* p, const arc* a, vbl_pwl* pwl)
{
    const int m = VBL_BEAM_LIGHT_PAIR_VERTICES;
    double phi[VBL_BEAM_LIGHT_PAIR_VERTICES], f[VBL_BEAM_LIGHT_PAIR_VERTICES];
    double lo = a->phi0, hi = a->phi1, span = hi - lo;
    /* Light-lobe peak direction sign(g) l_d in the arc plane (x; n, c_d): the camera point it
     * reaches is du = D tan(psi), psi = atan2(ey, ex), i.e. phi = atan2(D ey, D' ex) (ex > 0). */
    int has_peak = 0;
    double peak = 0.0;
    if (p->g_light != 0.0) {
        vbl_vec3 dir = p->g_light > 0.0 ? p->l_d : vbl_v3_scale(p->l_d, -1.0);
        double ex = vbl_v3_dot(dir, a->n), ey = vbl_v3_dot(dir, p->c_d);
        if (ex > 0.0) {
            peak = atan2(a->d * ey, a->dsoft * ex);
            double margin = 1e-6 * span;
            has_peak = peak > lo + margin && peak < hi - margin;
        }
    }
    if (!has_peak) {
        for (int j = 0; j < m; ++j) phi[j] = lo + 0.5 * span * (1.0 - cos(VBL_PI * j / (m - 1))); /* VRL eq 19 */
    } else {
        int jp = (int)floor((peak - lo) / span * (m - 1) + 0.5); /* VRL eq 20 */
        jp = jp < 1 ? 1 : (jp > m - 2 ? m - 2 : jp);
        for (int j = 0; j <= jp; ++j) phi[j] = lo + 0.5 * (peak - lo) * (1.0 - cos(VBL_PI * j / jp));
        for (int j = jp; j < m; ++j) phi[j] = peak + 0.5 * (hi - peak) * (1.0 - cos(VBL_PI * (j - jp) / (m - 1 - jp)));
        phi[jp] = peak;
    }
    phi[0] = lo;
    phi[m - 1] = hi;
    for (int j = 1; j < m; ++j) phi[j] = vbl_clamp(phi[j], phi[j - 1], hi);
    for (int j = 0; j < m; ++j) {
        double du = j == 0 ? p->u0 - a->up : (j == m - 1 ? p->u1 - a->up : a->dsoft * tan(phi[j]));
        f[j] = cone_value(p, a, du);
    }
    return vbl_pwl_init(pwl, phi, f, m);
}

double vbl_beam_light_pair_marginal_pdf(const vbl_beam_light_pair* p, double v)
{
    if (!p->valid || v < p->v0 || v > p->v1) return 0.0;
    return vbl_sinh_marginal_pdf_t(&p->marginal, v - p->v0);
}

double vbl_beam_light_pair_conditional_pdf(const vbl_beam_light_pair* p, double v, double u)
{
    if (!p->valid || u < p->u0 || u > p->u1) return 0.0;
    arc a;
    vbl_pwl pwl;
    if (!arc_make(p, v, &a)) return 0.0;
    double du = u - a.up;
    if (p->isotropic) /* uniform in phi (see beam_light_pair.h) */
        return a.dsoft / ((a.phi1 - a.phi0) * (a.dsoft * a.dsoft + du * du));
    if (!arc_pwl(p, &a, &pwl)) return 0.0;
    double phi = vbl_clamp(atan2(du, a.dsoft), a.phi0, a.phi1);
    return vbl_pwl_pdf(&pwl, phi) * a.dsoft / (a.dsoft * a.dsoft + du * du);
}

int vbl_beam_light_pair_draw(const vbl_beam_light_pair* p, double xi1, double xi2, vbl_beam_light_pair_sample* out)
{
    out->u = p->u0;
    out->v = p->v0;
    out->pdf = 0.0;
    if (!p->valid) return 0;
    double t = vbl_sinh_marginal_sample_t(&p->marginal, xi1, NULL); /* VRL eq 13, h -> hypot(h, R) */
    double v = vbl_clamp(p->v0 + t, p->v0, p->v1);
    double pv = vbl_beam_light_pair_marginal_pdf(p, v);
    if (!(pv > 0.0)) return 0;
    arc a;
    vbl_pwl pwl;
    if (!arc_make(p, v, &a)) return 0;
    double phi;
    if (p->isotropic) { /* uniform in phi: the analytic (Cauchy) case */
        phi = a.phi0 + xi2 * (a.phi1 - a.phi0);
    } else {
        if (!arc_pwl(p, &a, &pwl)) return 0;
        phi = vbl_pwl_sample(&pwl, xi2, NULL);
    }
    double u = vbl_clamp(a.up + a.dsoft * tan(phi), p->u0, p->u1);
    double du = u - a.up;
    double phi_u = vbl_clamp(atan2(du, a.dsoft), a.phi0, a.phi1);
    double pphi = p->isotropic ? 1.0 / (a.phi1 - a.phi0) : vbl_pwl_pdf(&pwl, phi_u);
    double pu = pphi * a.dsoft / (a.dsoft * a.dsoft + du * du); /* dphi/du */
    if (!(pu > 0.0) || !isfinite(pu)) return 0;
    out->u = u;
    out->v = v;
    out->pdf = pv * pu;
    return 1;
}

double vbl_beam_light_pair_density(const vbl_beam_light_pair* p, double u, double v)
{
    double pv = vbl_beam_light_pair_marginal_pdf(p, v);
    return pv > 0.0 ? pv * vbl_beam_light_pair_conditional_pdf(p, v, u) : 0.0;
}

double vbl_beam_light_pair_target(const vbl_beam_light_pair* p, double u, double v)
{
    arc a;
    if (!p->valid || !arc_make(p, v, &a)) return 0.0;
    double du = u - a.up;
    double w2r2 = a.d * a.d + du * du + p->radius * p->radius;
    return w2r2 > 0.0 ? cone_value(p, &a, du) / w2r2 : 0.0;
}

/* ---- VSL kernel (eq 9 with two phase functions, beam radiance estimate over the cone) ---- */

static double fract(double x) { return x - floor(x); }

typedef struct lobe {
    double g;
    vbl_vec3 m; /* HG(g, m . omega); sampled as travel direction m */
    int used;
} lobe;

double vbl_vsl_kernel(vbl_vec3 x_c, vbl_vec3 c_d, double g_camera, vbl_vec3 x_l, vbl_vec3 l_d, double g_light,
                      double radius, int n, double jitter1, double jitter2)
{
    vbl_vec3 mc = vbl_v3_scale(c_d, -1.0);
    vbl_vsl_cone cone;
    if (!vbl_vsl_cone_init(&cone, vbl_v3_sub(x_c, x_l), radius, mc)) return 0.0;
    if (!(cone.solid_angle > 0.0)) /* R == 0: the VRL integrand f_l f_c / w^2 */
        return vbl_hg_eval(g_light, vbl_v3_dot(l_d, cone.axis)) * vbl_hg_eval(g_camera, vbl_v3_dot(mc, cone.axis)) *
               cone.geometry;
    if (g_light == 0.0 && g_camera == 0.0) { /* isotropic: the integrand is constant, exact */
        return cone.geometry * VBL_INV_4PI * VBL_INV_4PI;
    }
    if (n < 1) n = 1;
    lobe lobes[2] = {{g_light, l_d, 0}, {g_camera, mc, 0}};
    for (int k = 0; k < 2; ++k)
        lobes[k].used = fabs(lobes[k].g) >= 0.2 &&
                        cone.solid_angle * vbl_vsl_cone_hg_max(&cone, lobes[k].g, lobes[k].m, NULL) >= 0.01;
    const double golden = 0.61803398874989484820;
    double j1 = fract(jitter1), j2 = fract(jitter2);
    double sum = 0.0;
    for (int s = 0; s < 3; ++s) {
        if (s > 0 && !lobes[s - 1].used) continue;
        for (int i = 0; i < n; ++i) {
            double a = fract((i + j1) / n), b = fract(i * golden + j2);
            vbl_vec3 w;
            if (s == 0) {
                w = vbl_vsl_cone_sample(&cone, a, b, NULL);
            } else {
                w = vbl_hg_sample(lobes[s - 1].g, lobes[s - 1].m, a, b, NULL);
                if (!vbl_vsl_cone_contains(&cone, w)) continue;
            }
            double f = vbl_hg_eval(g_light, vbl_v3_dot(l_d, w)) * vbl_hg_eval(g_camera, vbl_v3_dot(mc, w));
            /* Balance heuristic, written relative to the cone pdf 1/Omega so that the thin-cone
             * limit needs no 1/Omega: f / (n sum_s p_s) = f Omega / (n (1 + Omega sum_lobes p)). */
            double extra = 0.0;
            for (int k = 0; k < 2; ++k)
                if (lobes[k].used) extra += vbl_hg_eval(lobes[k].g, vbl_v3_dot(lobes[k].m, w));
            sum += f / (1.0 + cone.solid_angle * extra);
        }
    }
    /* (1 / (pi R^2)) * Omega * (sum / n) = geometry * sum / n */
    return cone.geometry * sum / n;
}

/* ---- thin-cone shortcut (beam_light_pair.h) ---- */

double vbl_vsl_lobe_slope_bound(double g)
{
    double a = fabs(g);
    return a < 1.0 ? 3.0 * a / ((1.0 - a) * (1.0 + a)) : INFINITY;
}

double vbl_vsl_lobe_curvature_bound(double g)
{
    double a = fabs(g);
    return a < 1.0 ? 4.5 * a / ((1.0 - a) * (1.0 - a)) : INFINITY;
}

double vbl_vsl_midpoint_error_bound(double alpha, double b1, double b2)
{
    return 0.5 * alpha * alpha * (b2 + b1 * b1) * exp(alpha * b1);
}

void vbl_vsl_lobe_local_bounds(double g, double c, double sin_a, double cos_a, double* b1, double* b2)
{
    const double a = fabs(g);
    *b1 = *b2 = 0.0;
    if (a == 0.0) return;
    if (!(a < 1.0)) {
        *b1 = *b2 = INFINITY;
        return;
    }
    double cp = vbl_clamp(g > 0.0 ? c : -c, -1.0, 1.0), sp = sqrt(fmax(0.0, 1.0 - cp * cp));
    /* x = 1 - cos of the angle to the lobe's peak over the cone: [x0, x1] */
    double x0 = cp >= cos_a ? 0.0 : fmax(0.0, 1.0 - (cp * cos_a + sp * sin_a) - 1e-12);
    double cu = cp * cos_a - sp * sin_a; /* cos(theta + alpha) while theta + alpha <= pi */
    double x1 = (sp * cos_a + cp * sin_a) < 0.0 ? 2.0 : fmin(2.0, 1.0 - cu + 1e-12);
    const double om = (1.0 - a) * (1.0 - a);
    double xs = vbl_clamp(om / (2.0 * a), x0, x1); /* the peak of sqrt(2x) / q and of 2x / q^2 */
    double qs = om + 2.0 * a * xs, q0 = om + 2.0 * a * x0;
    *b1 = fmin(3.0 * a * sqrt(2.0 * xs) / qs, vbl_vsl_lobe_slope_bound(g)); /* sqrt(2x) >= sqrt(1 - c^2) */
    *b2 = 6.0 * a * a * 2.0 * xs / (qs * qs) + 3.0 * a / q0;
}

double vbl_vsl_thin_cone_sin(double g_max, double tolerance)
{
    if (!(tolerance > 0.0) || !(fabs(g_max) < 1.0)) return 0.0;
    const double b1 = 2.0 * vbl_vsl_lobe_slope_bound(g_max), b2 = 2.0 * vbl_vsl_lobe_curvature_bound(g_max);
    double lo = 0.0, hi = 0.5 * VBL_PI;
    if (vbl_vsl_midpoint_error_bound(hi, b1, b2) <= tolerance) return 1.0;
    for (int i = 0; i < 60; ++i) {
        double mid = 0.5 * (lo + hi);
        if (vbl_vsl_midpoint_error_bound(mid, b1, b2) <= tolerance) lo = mid;
        else hi = mid;
    }
    return sin(lo);
}

double vbl_vsl_kernel_adaptive(vbl_vec3 x_c, vbl_vec3 c_d, double g_camera, vbl_vec3 x_l, vbl_vec3 l_d, double g_light,
                               double radius, int n, double jitter1, double jitter2, double thin_sin)
{
    vbl_vec3 mc = vbl_v3_scale(c_d, -1.0);
    vbl_vsl_cone cone;
    if (!vbl_vsl_cone_init(&cone, vbl_v3_sub(x_c, x_l), radius, mc)) return 0.0;
    if (cone.radius <= thin_sin * cone.w) /* midpoint (R == 0: the VRL integrand, geometry 1 / w^2) */
        return vbl_hg_eval(g_light, vbl_v3_dot(l_d, cone.axis)) * vbl_hg_eval(g_camera, vbl_v3_dot(mc, cone.axis)) *
               cone.geometry;
    return vbl_vsl_kernel(x_c, c_d, g_camera, x_l, l_d, g_light, radius, n, jitter1, jitter2);
}
