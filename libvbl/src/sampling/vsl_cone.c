/* Cone of directions subtended by a volumetric VSL (Novak et al. 2012 (VBL), section 3.1,
 * figure 5). */
#include "sampling/vsl_cone.h"

#include <stddef.h>

#include "sampling/phase_hg.h"

int vbl_vsl_cone_init(vbl_vsl_cone* c, vbl_vec3 d, double radius, vbl_vec3 fallback_axis)
{
    double r = (radius > 0.0 && isfinite(radius)) ? radius : 0.0;
    double w = vbl_v3_length(d);
    c->w = w;
    c->radius = r;
    c->axis = w > 0.0 ? vbl_v3_scale(d, 1.0 / w) : vbl_v3_normalize(fallback_axis);
    if (w <= r) { /* hemisphere (also w == 0 < r) */
        c->sin_half = 1.0;
        c->cos_half = 0.0;
    } else {
        double q = r / w; /* < 1 */
        c->sin_half = q;
        c->cos_half = sqrt((1.0 - q) * (1.0 + q));
    }
    c->half_angle = atan2(c->sin_half, c->cos_half);
    c->one_minus_cos = c->sin_half * c->sin_half / (1.0 + c->cos_half);
    c->solid_angle = 2.0 * VBL_PI * c->one_minus_cos;
    double m = fmax(w, r);
    c->geometry = m > 0.0 ? 2.0 / (m * m * (1.0 + c->cos_half)) : 0.0;
    c->valid = m > 0.0;
    return c->valid;
}

static double angle_between(vbl_vec3 a, vbl_vec3 b)
{
    return atan2(vbl_v3_length(vbl_v3_cross(a, b)), vbl_v3_dot(a, b));
}

int vbl_vsl_cone_contains(const vbl_vsl_cone* c, vbl_vec3 dir)
{
    return angle_between(c->axis, dir) <= c->half_angle;
}

vbl_vec3 vbl_vsl_cone_closest(const vbl_vsl_cone* c, vbl_vec3 target)
{
    vbl_vec3 a = c->axis;
    vbl_vec3 perp = vbl_v3_cross(a, vbl_v3_cross(target, a)); /* target minus its axis part */
    double sp = vbl_v3_length(perp), cp = vbl_v3_dot(target, a);
    if (atan2(sp, cp) <= c->half_angle) return target;
    vbl_vec3 p;
    if (sp > 0.0) {
        p = vbl_v3_scale(perp, 1.0 / sp);
    } else {
        vbl_vec3 b;
        vbl_v3_basis(a, &p, &b); /* target == -axis: fixed boundary direction */
    }
    return vbl_v3_add(vbl_v3_scale(a, c->cos_half), vbl_v3_scale(p, c->sin_half));
}

/* Peak direction of HG(g, m . omega): m for g > 0, -m for g < 0 (flat for g == 0: axis). */
static vbl_vec3 hg_peak(const vbl_vsl_cone* c, double g, vbl_vec3 m)
{
    return g > 0.0 ? m : (g < 0.0 ? vbl_v3_scale(m, -1.0) : c->axis);
}

double vbl_vsl_cone_hg_max(const vbl_vsl_cone* c, double g, vbl_vec3 m, vbl_vec3* argmax)
{
    vbl_vec3 w = vbl_vsl_cone_closest(c, hg_peak(c, g, m));
    if (argmax) *argmax = w;
    return vbl_hg_eval(g, vbl_v3_dot(m, w));
}

static double product(double g1, vbl_vec3 m1, double g2, vbl_vec3 m2, vbl_vec3 w)
{
    return vbl_hg_eval(g1, vbl_v3_dot(m1, w)) * vbl_hg_eval(g2, vbl_v3_dot(m2, w));
}

/* Spherical interpolation between unit a and b (angle < pi), t in [0, 1]. */
static vbl_vec3 slerp(vbl_vec3 a, vbl_vec3 b, double omega, double t)
{
    double s = sin(omega);
    if (!(s > 1e-12)) return vbl_v3_normalize(vbl_v3_add(vbl_v3_scale(a, 1.0 - t), vbl_v3_scale(b, t)));
    double wa = sin((1.0 - t) * omega) / s, wb = sin(t * omega) / s;
    return vbl_v3_normalize(vbl_v3_add(vbl_v3_scale(a, wa), vbl_v3_scale(b, wb)));
}

double vbl_vsl_cone_hg_product_max(const vbl_vsl_cone* c, double g1, vbl_vec3 m1, double g2, vbl_vec3 m2,
                                   vbl_vec3* argmax)
{
    if (g1 == 0.0 || g2 == 0.0) { /* one lobe flat: the other lobe's exact maximum */
        double f = g1 == 0.0 ? vbl_vsl_cone_hg_max(c, g2, m2, argmax) : vbl_vsl_cone_hg_max(c, g1, m1, argmax);
        return f * VBL_INV_4PI;
    }
    vbl_vec3 p1 = vbl_vsl_cone_closest(c, hg_peak(c, g1, m1));
    vbl_vec3 p2 = vbl_vsl_cone_closest(c, hg_peak(c, g2, m2));
    vbl_vec3 best = c->axis;
    double fbest = product(g1, m1, g2, m2, best);
    double omega = angle_between(p1, p2);
    /* Thin cone (or coincident candidates): the product cannot vary much across the geodesic;
     * the two least-rotation directions and the axis suffice. */
    const int k = (c->half_angle < 0.02 || omega < 1e-3) ? 1 : 16;
    for (int i = 0; i <= k; ++i) {
        vbl_vec3 w = i == 0 ? p1 : (i == k ? p2 : slerp(p1, p2, omega, (double)i / k));
        double f = product(g1, m1, g2, m2, w);
        if (f > fbest) {
            fbest = f;
            best = w;
        }
    }
    if (argmax) *argmax = best;
    return fbest;
}

vbl_vec3 vbl_vsl_cone_sample(const vbl_vsl_cone* c, double u1, double u2, double* pdf)
{
    if (!(c->solid_angle > 0.0)) {
        if (pdf) *pdf = 0.0;
        return c->axis;
    }
    double omc = vbl_clamp(u1, 0.0, 1.0) * c->one_minus_cos; /* 1 - cos theta, uniform */
    double ct = 1.0 - omc;
    double st = sqrt(fmax(0.0, omc * (2.0 - omc)));
    double phi = 2.0 * VBL_PI * u2;
    vbl_vec3 t, b;
    vbl_v3_basis(c->axis, &t, &b);
    if (pdf) *pdf = 1.0 / c->solid_angle;
    return vbl_v3_add(vbl_v3_scale(c->axis, ct), vbl_v3_add(vbl_v3_scale(t, st * cos(phi)), vbl_v3_scale(b, st * sin(phi))));
}

double vbl_vsl_cone_pdf(const vbl_vsl_cone* c, vbl_vec3 dir)
{
    if (!(c->solid_angle > 0.0)) return 0.0;
    return vbl_vsl_cone_contains(c, dir) ? 1.0 / c->solid_angle : 0.0;
}
