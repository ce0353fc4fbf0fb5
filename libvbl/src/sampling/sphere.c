/* Uniform sphere and cone sampling (area-preserving map z = lerp, phi = 2 pi u). */
#include "sampling/sphere.h"

vbl_vec3 vbl_sample_uniform_sphere(double u1, double u2, double* pdf)
{
    double z = vbl_clamp(1.0 - 2.0 * u1, -1.0, 1.0);
    double r = sqrt(fmax(0.0, (1.0 - z) * (1.0 + z)));
    double phi = 2.0 * VBL_PI * u2;
    if (pdf) *pdf = VBL_INV_4PI;
    return vbl_v3(r * cos(phi), r * sin(phi), z);
}

double vbl_uniform_sphere_pdf(void) { return VBL_INV_4PI; }

vbl_vec3 vbl_sample_uniform_cone(vbl_vec3 axis, double cos_max, double u1, double u2, double* pdf)
{
    double one_minus_cos_max = 1.0 - fmax(cos_max, -1.0);
    if (!(one_minus_cos_max > 0.0)) {
        if (pdf) *pdf = 0.0;
        return axis;
    }
    /* 1 - cos uniform in [0, 1 - cos_max]; sin^2 = (1 - cos)(1 + cos) keeps precision for thin cones. */
    double one_minus_c = vbl_clamp(u1, 0.0, 1.0) * one_minus_cos_max;
    double c = 1.0 - one_minus_c;
    double s = sqrt(fmax(0.0, one_minus_c * (2.0 - one_minus_c)));
    double phi = 2.0 * VBL_PI * u2;
    vbl_vec3 t, b;
    vbl_v3_basis(axis, &t, &b);
    if (pdf) *pdf = 1.0 / (2.0 * VBL_PI * one_minus_cos_max);
    return vbl_v3_add(vbl_v3_scale(axis, c), vbl_v3_add(vbl_v3_scale(t, s * cos(phi)), vbl_v3_scale(b, s * sin(phi))));
}

double vbl_uniform_cone_pdf(vbl_vec3 axis, double cos_max, vbl_vec3 dir)
{
    double one_minus_cos_max = 1.0 - fmax(cos_max, -1.0);
    if (!(one_minus_cos_max > 0.0)) return 0.0;
    return vbl_v3_dot(axis, dir) >= cos_max ? 1.0 / (2.0 * VBL_PI * one_minus_cos_max) : 0.0;
}
