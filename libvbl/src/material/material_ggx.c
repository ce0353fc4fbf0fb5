/* GGX (Trowbridge-Reitz) microfacet BRDF with height-correlated Smith shadowing and Schlick's
 * Fresnel (F0 = specular), plus a Lambertian lobe weighted by the Fresnel transmittance in and
 * out (Shirley et al. 1997 style coupling, which keeps the sum energy conserving):
 *   f = f_d + D(h) G2(wo, wi) F(wo.h) / (4 cos_o cos_i),  h = normalize(wo + wi),
 *   f_d = kd (1 - F0) / pi (1 - (1 - cos_o)^5) (1 - (1 - cos_i)^5)
 *       = kd / pi (1 - F(cos_o)) (1 - F(cos_i)) / (1 - F0),
 * whose albedo is (20/21) kd (1 - F(cos_o)) (int (1 - (1 - mu)^5) 2 mu dmu = 20/21). Reciprocal.
 * Energy: the specular albedo A_s(wo) stays below 1 - 0.998 (1 - F(cos_o)) (measured over
 * roughness x angle x F0 in tests/materials), so A_s + (20/21) kd (1 - F(cos_o)) <= 1 for kd <= 1.
 *   D(h) = a^2 / (pi (sin^2 theta_h + a^2 cos^2 theta_h)^2),
 *   G2 = 1 / (1 + L(wo) + L(wi)),  L(w) = (sqrt(cos^2 + a^2 sin^2) / cos - 1) / 2,
 *   F = F0 + (1 - F0) (1 - wo.h)^5.
 * With s(w) = sqrt(cos^2 + a^2 sin^2) the specular term is D F / (2 (cos_i s_o + cos_o s_i)):
 * no division by a single cosine. Sampling: the visible normals of wo (Heitz 2018, "Sampling
 * the GGX distribution of visible normals"), density G1(wo) max(0, wo.m) D(m) / cos_o, reflected
 * about m with the Jacobian 1 / (4 wo.m), so pdf(wi) = G1(wo) D(h) / (4 cos_o) =
 * D(h) / (2 (cos_o + s_o)); reflections below the surface are rejected. The lobe is chosen with
 * probability mean(F(cos_o)) / (mean(kd) + mean(F(cos_o))). */
#include "material/material_internal.h"

double vbl_ggx_alpha(const vbl_material* m) { return vbl_clamp(m->roughness, VBL_GGX_ROUGHNESS_MIN, 1.0); }

/* D for cos(theta_h) = c: the denominator is >= a^4 (a <= 1), so D <= 1 / (pi a^2). */
static double ggx_d(double a2, double c)
{
    double c2 = c * c;
    double den = fmax(0.0, 1.0 - c2) + a2 * c2;
    return a2 * VBL_INV_PI / (den * den);
}

/* s(w) = sqrt(cos^2 + a^2 sin^2) >= a for any direction, so 1 / s never overflows. */
static double ggx_s(double a2, double c) { return sqrt(c * c + a2 * fmax(0.0, 1.0 - c * c)); }

static vbl_vec3 schlick(vbl_vec3 f0, double c)
{
    double x = 1.0 - vbl_clamp(c, 0.0, 1.0), x5 = x * x * x * x * x;
    return vbl_v3_add(f0, vbl_v3_scale(vbl_v3_sub(vbl_v3(1.0, 1.0, 1.0), f0), x5));
}

/* (1 - (1 - c)^5): the Fresnel transmittance divided by (1 - F0). */
static double transmit5(double c)
{
    double x = 1.0 - vbl_clamp(c, 0.0, 1.0);
    return 1.0 - x * x * x * x * x;
}

/* Diffuse lobe f_d for cos_o, cos_i (per channel). */
static vbl_vec3 ggx_diffuse(const vbl_material* m, double cos_o, double cos_i)
{
    vbl_vec3 t0 = vbl_v3_sub(vbl_v3(1.0, 1.0, 1.0), m->specular);
    return vbl_v3_scale(vbl_v3_mul(m->albedo, t0), VBL_INV_PI * transmit5(cos_o) * transmit5(cos_i));
}

/* Lobe weights: the diffuse albedo kd (1 - F(cos_o)) against the specular F(cos_o). */
static double ggx_spec_probability(const vbl_material* m, double cos_o)
{
    vbl_vec3 fo = schlick(m->specular, cos_o);
    double s = vbl_mat_mean3(fo), d = vbl_mat_mean3(vbl_v3_mul(m->albedo, vbl_v3_sub(vbl_v3(1.0, 1.0, 1.0), fo)));
    return d + s > 0.0 ? s / (d + s) : 1.0;
}

/* f for cos_o, cos_i > 0, half vector cosine with n (cos_h) and with wo (cos_oh). */
static vbl_vec3 ggx_value(const vbl_material* m, double a2, double cos_o, double cos_i, double cos_h, double cos_oh)
{
    double den = 2.0 * (cos_i * ggx_s(a2, cos_o) + cos_o * ggx_s(a2, cos_i));
    vbl_vec3 fd = ggx_diffuse(m, cos_o, cos_i);
    if (!(den > 0.0)) return fd; /* only when cos_o cos_i underflows: the lobe has no solid angle there */
    return vbl_v3_add(fd, vbl_v3_scale(schlick(m->specular, cos_oh), ggx_d(a2, cos_h) / den));
}

static double ggx_density(const vbl_material* m, double a2, double cos_o, double cos_i, double cos_h)
{
    double ps = ggx_spec_probability(m, cos_o);
    return (1.0 - ps) * vbl_mat_cosine_pdf(cos_i) + ps * ggx_d(a2, cos_h) / (2.0 * (cos_o + ggx_s(a2, cos_o)));
}

vbl_vec3 vbl_ggx_eval(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    double cos_o = vbl_v3_dot(n, wo), cos_i = vbl_v3_dot(n, wi);
    if (cos_o <= 0.0 || cos_i <= 0.0) return vbl_v3(0.0, 0.0, 0.0);
    double a = vbl_ggx_alpha(m);
    vbl_vec3 h = vbl_v3_normalize(vbl_v3_add(wo, wi)); /* |wo + wi| > 0: both lie above the surface */
    return ggx_value(m, a * a, cos_o, cos_i, vbl_v3_dot(n, h), vbl_v3_dot(wo, h));
}

double vbl_ggx_pdf(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    double cos_o = vbl_v3_dot(n, wo), cos_i = vbl_v3_dot(n, wi);
    if (cos_o <= 0.0 || cos_i <= 0.0) return 0.0;
    double a = vbl_ggx_alpha(m);
    vbl_vec3 h = vbl_v3_normalize(vbl_v3_add(wo, wi));
    return ggx_density(m, a * a, cos_o, cos_i, vbl_v3_dot(n, h));
}

/* Visible normal in the local frame (z = n) for the local view direction v (v.z > 0), Heitz 2018:
 * stretch v to the hemisphere configuration, sample the projected disk with its lower half
 * warped onto the visible part, lift to the hemisphere and unstretch. */
static vbl_vec3 ggx_sample_visible_normal(double a, vbl_vec3 v, double u1, double u2)
{
    vbl_vec3 vh = vbl_v3_normalize(vbl_v3(a * v.x, a * v.y, v.z));
    double len2 = vh.x * vh.x + vh.y * vh.y;
    vbl_vec3 t1 = len2 > 0.0 ? vbl_v3_scale(vbl_v3(-vh.y, vh.x, 0.0), 1.0 / sqrt(len2)) : vbl_v3(1.0, 0.0, 0.0);
    vbl_vec3 t2 = vbl_v3_cross(vh, t1);
    double r = sqrt(u1), phi = 2.0 * VBL_PI * u2;
    double p1 = r * cos(phi), p2 = r * sin(phi);
    double s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(fmax(0.0, 1.0 - p1 * p1)) + s * p2;
    double p3 = sqrt(fmax(0.0, 1.0 - p1 * p1 - p2 * p2));
    vbl_vec3 nh = vbl_v3_add(vbl_v3_add(vbl_v3_scale(t1, p1), vbl_v3_scale(t2, p2)), vbl_v3_scale(vh, p3));
    return vbl_v3_normalize(vbl_v3(a * nh.x, a * nh.y, fmax(0.0, nh.z)));
}

int vbl_ggx_sample(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, double u0, double u1, double u2, vbl_vec3* wi,
                   double* pdf, vbl_vec3* f)
{
    double cos_o = vbl_v3_dot(n, wo);
    if (cos_o <= 0.0) return 0;
    double a = vbl_ggx_alpha(m), a2 = a * a;
    vbl_vec3 w;
    double ps = ggx_spec_probability(m, cos_o);
    if (u0 < ps || ps >= 1.0) { /* u0 in [0, 1); ps = 1 picks the lobe even for u0 = 1 */
        vbl_vec3 t, b;
        vbl_v3_basis(n, &t, &b);
        vbl_vec3 v = vbl_v3(vbl_v3_dot(wo, t), vbl_v3_dot(wo, b), cos_o);
        vbl_vec3 ml = ggx_sample_visible_normal(a, v, u1, u2);
        vbl_vec3 mw = vbl_v3_add(vbl_v3_add(vbl_v3_scale(t, ml.x), vbl_v3_scale(b, ml.y)), vbl_v3_scale(n, ml.z));
        mw = vbl_v3_normalize(mw);
        w = vbl_v3_normalize(vbl_mat_reflect(mw, wo));
    } else {
        w = vbl_mat_cosine_sample(n, u1, u2);
    }
    double cos_i = vbl_v3_dot(n, w);
    if (cos_i <= 0.0) return 0; /* reflected below the surface: rejected */
    /* f and pdf from (wo, wi) exactly as vbl_ggx_eval / vbl_ggx_pdf compute them, so MIS weights
     * built from either agree bit for bit (h from wo + wi rather than the sampled m, which differ
     * by rounding that D amplifies for small roughness at grazing wo). */
    vbl_vec3 h = vbl_v3_normalize(vbl_v3_add(wo, w));
    double cos_h = vbl_v3_dot(n, h);
    double p = ggx_density(m, a2, cos_o, cos_i, cos_h);
    if (!(p > 0.0)) return 0;
    *wi = w;
    *pdf = p;
    *f = ggx_value(m, a2, cos_o, cos_i, cos_h, vbl_v3_dot(wo, h));
    return 1;
}

/* Bound of f cos(theta_i) over the cone, factor by factor:
 *  - diffuse: f_d cos(theta_i) grows with cos(theta_i): its value at the largest cos(theta_i);
 *  - specular: f_s cos_i = D G2 F / (4 cos_o) = D F / (2 (s_o + cos_o s_i / cos_i)), where
 *    s_i / cos_i = sqrt(1 + a^2 tan^2 theta_i) is smallest at the cone's largest cos_i (Lambda
 *    grows towards the horizon, so G2 is largest there); theta_h >= angle(wi, r) / 2 (wi is r rotated by
 *    twice the angle between n and h: the product of the half-turns about h and n), so
 *    theta_h,min >= max(0, angle(r, axis) - half) / 2, and also cos theta_h = (cos_o + cos_i) /
 *    (2 cos(angle(wo, wi) / 2)) <= (cos_o + max cos_i) / (2 cos(widest / 2)) (the tighter one
 *    away from the plane of incidence at grazing wo); D decreases in theta_h; F decreases
 *    in wo.h = cos(angle(wo, wi) / 2), largest for the widest angle between wo and the cone. */
vbl_vec3 vbl_ggx_max_in_cone(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 axis, double cos_half)
{
    vbl_vec3 zero = vbl_v3(0.0, 0.0, 0.0);
    double cos_o = vbl_v3_dot(n, wo);
    if (cos_o <= 0.0) return zero;
    double half = vbl_mat_cone_half_angle(cos_half);
    double ti = vbl_mat_cone_min_angle(n, axis, half);
    if (ti >= 0.5 * VBL_PI) return zero;
    double a = vbl_ggx_alpha(m), a2 = a * a;
    double th = 0.5 * vbl_mat_cone_min_angle(vbl_mat_reflect(n, wo), axis, half);
    double wide = fmin(VBL_PI, vbl_mat_angle(wo, axis) + half), cos_half_wide = cos(0.5 * wide);
    /* second bound on theta_h: cos theta_h = (cos_o + cos_i) / |wo + wi| and |wo + wi| = 2 cos(angle / 2) */
    double cos_h = cos(th), num = cos_o + cos(ti);
    if (num < 2.0 * cos_half_wide * cos_h) cos_h = num / (2.0 * cos_half_wide);
    double ci = cos(ti); /* > 0: ti < pi / 2 */
    double spec = ggx_d(a2, cos_h) / (2.0 * (ggx_s(a2, cos_o) + cos_o * (ggx_s(a2, ci) / ci)));
    vbl_vec3 fs = vbl_v3_scale(schlick(m->specular, cos_half_wide), spec);
    return vbl_v3_add(vbl_v3_scale(ggx_diffuse(m, cos_o, ci), ci), fs);
}
