/* Directions with the angle to an axis uniform (focus_cone.h). */
#include "sampling/focus_cone.h"

#include <math.h>

static int vbl_focus_cone_valid(double psi_max) { return psi_max > 0.0 && psi_max <= VBL_PI; }

/* 1 / (2 pi psi_max sin psi), or 0 where it is not finite */
static double vbl_focus_cone_density(double psi_max, double sin_psi)
{
    const double d = 2.0 * VBL_PI * psi_max * sin_psi;
    return d > 0.0 && isfinite(1.0 / d) ? 1.0 / d : 0.0;
}

int vbl_focus_cone_sample(vbl_vec3 axis, double psi_max, double u1, double u2, vbl_vec3* w, double* pdf)
{
    if (!vbl_focus_cone_valid(psi_max)) return 0;
    const double psi = u1 * psi_max, phi = 2.0 * VBL_PI * u2;
    const double s = sin(psi);
    *pdf = vbl_focus_cone_density(psi_max, s);
    if (!(*pdf > 0.0)) return 0;
    vbl_vec3 t, b;
    vbl_v3_basis(axis, &t, &b);
    const double c = cos(psi);
    *w = vbl_v3_normalize(vbl_v3_add(vbl_v3_scale(axis, c),
                                     vbl_v3_add(vbl_v3_scale(t, s * cos(phi)), vbl_v3_scale(b, s * sin(phi)))));
    return 1;
}

double vbl_focus_cone_pdf(vbl_vec3 axis, double psi_max, vbl_vec3 w)
{
    if (!vbl_focus_cone_valid(psi_max)) return 0.0;
    return vbl_focus_cone_pdf_cos(axis, psi_max, cos(psi_max), w);
}

double vbl_focus_cone_pdf_cos(vbl_vec3 axis, double psi_max, double cos_max, vbl_vec3 w)
{
    /* psi < psi_max <=> cos psi > cos psi_max (cos decreases on [0, pi]); sin psi = |axis x w|
     * for unit vectors (accurate near the axis, where 1 - cos^2 is not) */
    if (!(vbl_v3_dot(axis, w) > cos_max)) return 0.0;
    return vbl_focus_cone_density(psi_max, vbl_v3_length(vbl_v3_cross(axis, w)));
}
