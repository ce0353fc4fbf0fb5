/* Henyey-Greenstein phase function (Henyey & Greenstein 1941). */
#include "sampling/phase_hg.h"

double vbl_hg_eval(double g, double cos_theta)
{
    if (g == 0.0) return VBL_INV_4PI;
    double c = vbl_clamp(cos_theta, -1.0, 1.0);
    /* 1 + g^2 - 2 g c written as (1 - g)^2 + 2 g (1 - c): no cancellation near g -> 1, c -> 1. */
    double one_minus_g = 1.0 - g;
    double denom = one_minus_g * one_minus_g + 2.0 * g * (1.0 - c);
    return VBL_INV_4PI * (1.0 - g * g) / (denom * sqrt(denom));
}

double vbl_hg_pdf(double g, double cos_theta) { return vbl_hg_eval(g, cos_theta); }

double vbl_hg_sample_cos(double g, double u)
{
    u = vbl_clamp(u, 0.0, 1.0);
    /* Classic inversion cos = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g), expanded with
     * a = 1 - 2u so the 1/g cancels analytically: exact uniform cos = 2u - 1 at g = 0 and no loss
     * of precision for small |g|. */
    double a = 1.0 - 2.0 * u;
    double d = 1.0 - g * a; /* = 1 - g + 2 g u >= 1 - |g| > 0 */
    double num = -2.0 * a + 3.0 * g + g * a * a - 2.0 * g * g * a + g * g * g * (a * a - 1.0);
    return vbl_clamp(num / (2.0 * d * d), -1.0, 1.0);
}

vbl_vec3 vbl_hg_sample(double g, vbl_vec3 travel_direction, double u1, double u2, double* pdf)
{
    double c = vbl_hg_sample_cos(g, u1);
    double s = sqrt(fmax(0.0, (1.0 - c) * (1.0 + c)));
    double phi = 2.0 * VBL_PI * u2;
    vbl_vec3 t, b;
    vbl_v3_basis(travel_direction, &t, &b);
    vbl_vec3 w = vbl_v3_add(vbl_v3_scale(travel_direction, c),
                            vbl_v3_add(vbl_v3_scale(t, s * cos(phi)), vbl_v3_scale(b, s * sin(phi))));
    if (pdf) *pdf = vbl_hg_eval(g, c);
    return w;
}
