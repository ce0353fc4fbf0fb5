/* Normalized (modified) Phong BRDF, Lafortune & Willems 1994, the glossy model of the VBL paper
 * (Novak et al. 2012 (VBL), section 5: exponents 60-100):
 *   f(wo, wi) = kd / pi + ks (e + 2) / (2 pi) max(0, cos alpha)^e,   cos alpha = r . wi,
 * r = 2 (n.wo) n - wo the mirror direction of wo. The (e + 2) / (2 pi) factor makes the
 * specular directional albedo exactly 1 at normal incidence and smaller elsewhere (horizon
 * clipping, cos(theta_i) < cos(alpha) on average), so kd + ks <= 1 per channel conserves energy.
 * Sampling: lobe chosen with probability mean(ks) / (mean(kd) + mean(ks)); diffuse is
 * cosine-weighted about n, specular draws cos alpha = u^(1 / (e + 1)) about r (density
 * (e + 1) / (2 pi) cos^e alpha); specular draws below the surface are rejected (return 0), so the
 * pdf below is the unnormalized mixture density and integrates to the acceptance probability. */
#include "material/material_internal.h"

static double phong_spec_probability(const vbl_material* m)
{
    double d = vbl_mat_mean3(m->albedo), s = vbl_mat_mean3(m->specular);
    return d + s > 0.0 ? s / (d + s) : 0.0;
}

/* max(0, c)^e with 0^0 read as 0 (the lobe is empty on the far side of the mirror plane). */
static double phong_lobe(double cos_alpha, double e) { return cos_alpha > 0.0 ? pow(cos_alpha, e) : 0.0; }

static vbl_vec3 phong_value(const vbl_material* m, double lobe)
{
    double spec = (m->exponent + 2.0) * (0.5 * VBL_INV_PI) * lobe;
    return vbl_v3_add(vbl_v3_scale(m->albedo, VBL_INV_PI), vbl_v3_scale(m->specular, spec));
}

static double phong_density(const vbl_material* m, double cos_i, double lobe)
{
    double ps = phong_spec_probability(m);
    return (1.0 - ps) * vbl_mat_cosine_pdf(cos_i) + ps * (m->exponent + 1.0) * (0.5 * VBL_INV_PI) * lobe;
}

vbl_vec3 vbl_phong_eval(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    if (vbl_v3_dot(n, wo) <= 0.0 || vbl_v3_dot(n, wi) <= 0.0) return vbl_v3(0.0, 0.0, 0.0);
    return phong_value(m, phong_lobe(vbl_v3_dot(vbl_mat_reflect(n, wo), wi), m->exponent));
}

double vbl_phong_pdf(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    double cos_i = vbl_v3_dot(n, wi);
    if (vbl_v3_dot(n, wo) <= 0.0 || cos_i <= 0.0) return 0.0;
    return phong_density(m, cos_i, phong_lobe(vbl_v3_dot(vbl_mat_reflect(n, wo), wi), m->exponent));
}

int vbl_phong_sample(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, double u0, double u1, double u2, vbl_vec3* wi,
                     double* pdf, vbl_vec3* f)
{
    if (vbl_v3_dot(n, wo) <= 0.0) return 0;
    vbl_vec3 r = vbl_mat_reflect(n, wo);
    vbl_vec3 w;
    double ps = phong_spec_probability(m);
    if (u0 < ps || ps >= 1.0) { /* u0 in [0, 1); ps = 1 picks the lobe even for u0 = 1 */
        double ca = pow(u1, 1.0 / (m->exponent + 1.0)); /* CDF of (e + 1) c^e on [0, 1] inverted */
        double sa = sqrt(fmax(0.0, 1.0 - ca * ca)), phi = 2.0 * VBL_PI * u2;
        w = vbl_mat_from_local(r, sa * cos(phi), sa * sin(phi), ca);
    } else {
        w = vbl_mat_cosine_sample(n, u1, u2);
    }
    double cos_i = vbl_v3_dot(n, w);
    if (cos_i <= 0.0) return 0; /* below the surface: rejected, counted in the pdf's missing mass */
    double lobe = phong_lobe(vbl_v3_dot(r, w), m->exponent);
    double p = phong_density(m, cos_i, lobe);
    if (!(p > 0.0)) return 0;
    *wi = w;
    *pdf = p;
    *f = phong_value(m, lobe);
    return 1;
}

/* Bound of f cos(theta_i) over the cone. Diffuse: kd / pi cos(ti), ti the cone's smallest angle
 * to n (exact). Specular: a direction at angle a from r has cos(theta_i) <= cos(theta_r - a)
 * (triangle inequality, theta_r = angle(n, r)) and <= cos(ti), so over the cone
 *   f_s cos(theta_i) <= ks (e + 2) / (2 pi) max_{a in [ta, ta_max]} cos^e(a) min(cos ti, cos(theta_r - a)),
 * [ta, ta_max] the cone's range of angles to r. cos^e(a) cos(theta_r - a) is log-concave with its
 * peak where e tan a = tan(theta_r - a), i.e. tan a = 2 T / ((1 + e) + sqrt((1 + e)^2 + 4 e T^2)),
 * T = tan theta_r; beyond a = theta_r - ti the min is cos ti and the product decreases. So the
 * maximum is at the peak clamped to [ta, ta_max]: exact for cones about the plane of incidence,
 * never below the true maximum. */
vbl_vec3 vbl_phong_max_in_cone(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 axis, double cos_half)
{
    vbl_vec3 zero = vbl_v3(0.0, 0.0, 0.0);
    double cos_o = vbl_v3_dot(n, wo);
    if (cos_o <= 0.0) return zero;
    double half = vbl_mat_cone_half_angle(cos_half);
    double ti = vbl_mat_cone_min_angle(n, axis, half);
    if (ti >= 0.5 * VBL_PI) return zero; /* the whole cone lies below the surface */
    double cos_ti = cos(ti), e = m->exponent;
    vbl_vec3 r = vbl_mat_reflect(n, wo);
    double theta_r = vbl_mat_angle(n, r);
    double ta = vbl_mat_cone_min_angle(r, axis, half), ta_max = fmin(VBL_PI, vbl_mat_angle(r, axis) + half);
    double sr = sin(theta_r), cr = cos(theta_r); /* cr = cos_o >= 0 */
    double peak = atan2(2.0 * sr, (1.0 + e) * cr + sqrt((1.0 + e) * (1.0 + e) * cr * cr + 4.0 * e * sr * sr));
    peak = fmax(0.0, fmin(peak, theta_r - ti));
    double a = vbl_clamp(peak, ta, ta_max);
    double lobe = a < 0.5 * VBL_PI ? pow(cos(a), e) * fmin(cos_ti, cos(theta_r - a)) : 0.0;
    vbl_vec3 fd = vbl_v3_scale(m->albedo, VBL_INV_PI * cos_ti);
    return vbl_v3_add(fd, vbl_v3_scale(m->specular, (e + 2.0) * (0.5 * VBL_INV_PI) * lobe));
}
