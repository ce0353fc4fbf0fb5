/* Equiangular sampling via the truncated Cauchy of VRL eq (14). */
#include "sampling/equiangular.h"

#include "sampling/cauchy.h"

/* Parameter of the point's projection onto the line and its perpendicular distance (the cross
 * product keeps the distance accurate for far points). */
static void project(vbl_vec3 o, vbl_vec3 d, vbl_vec3 point, double* delta, double* h)
{
    vbl_vec3 r = vbl_v3_sub(point, o);
    *delta = vbl_v3_dot(r, d);
    *h = vbl_v3_length(vbl_v3_cross(r, d));
}

double vbl_equiangular_sample(vbl_vec3 o, vbl_vec3 d, double t0, double t1, vbl_vec3 point, double u, double* pdf)
{
    double delta, h;
    project(o, d, point, &delta, &h);
    double p = 0.0;
    double x = vbl_cauchy_sample(h, t0 - delta, t1 - delta, u, &p);
    if (!(p > 0.0)) {
        if (pdf) *pdf = 0.0;
        return t0;
    }
    double t = vbl_clamp(delta + x, t0, t1);
    /* The density at the returned t, evaluated exactly as vbl_equiangular_pdf does. */
    if (pdf) *pdf = vbl_cauchy_pdf(h, t0 - delta, t1 - delta, t - delta);
    return t;
}

double vbl_equiangular_pdf(vbl_vec3 o, vbl_vec3 d, double t0, double t1, vbl_vec3 point, double t)
{
    if (t < t0 || t > t1) return 0.0;
    double delta, h;
    project(o, d, point, &delta, &h);
    return vbl_cauchy_pdf(h, t0 - delta, t1 - delta, t - delta);
}
