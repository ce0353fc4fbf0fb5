/* Light sampling: point/spot/distant (delta), quad (uniform over its area, converted to solid
 * angle: pdf = r^2 / (cos_light * area)), environment (uniform sphere, pdf = 1 / 4 pi). */
#include "scene/lights.h"

#include <math.h>

#include "sampling/sphere.h"

double vbl_spot_falloff(const vbl_light* light, double cos_axis)
{
    if (cos_axis >= light->cos_inner) return 1.0;
    if (cos_axis <= light->cos_outer) return 0.0;
    double width = light->cos_inner - light->cos_outer; /* > 0 here: cos_outer < cos_axis < cos_inner */
    double s = (cos_axis - light->cos_outer) / width;
    return s * s * (3.0 - 2.0 * s);
}

static int vbl_light_sample_position(const vbl_light* light, vbl_vec3 point, vbl_light_sample* out)
{
    vbl_vec3 to_light = vbl_v3_sub(light->position, point);
    double d2 = vbl_v3_dot(to_light, to_light);
    if (!(d2 > 0.0)) return 0;
    double d = sqrt(d2);
    out->wi = vbl_v3_scale(to_light, 1.0 / d);
    out->distance = d;
    out->pdf = 1.0;
    out->is_delta = 1;
    double falloff = 1.0;
    if (light->type == VBL_LIGHT_SPOT) {
        falloff = vbl_spot_falloff(light, -vbl_v3_dot(out->wi, light->direction));
        if (falloff <= 0.0) return 0;
    }
    out->li = vbl_v3_scale(light->color, falloff / d2);
    return 1;
}

int vbl_light_sample_incident(const vbl_light* light, vbl_vec3 point, double u1, double u2,
                              vbl_light_sample* out)
{
    switch (light->type) {
    case VBL_LIGHT_POINT:
    case VBL_LIGHT_SPOT: return vbl_light_sample_position(light, point, out);
    case VBL_LIGHT_DISTANT:
        out->wi = vbl_v3_scale(light->direction, -1.0);
        out->distance = INFINITY;
        out->li = light->color;
        out->pdf = 1.0;
        out->is_delta = 1;
        return 1;
    case VBL_LIGHT_QUAD: {
        vbl_vec3 y = vbl_v3_add(light->corner, vbl_v3_add(vbl_v3_scale(light->edge1, u1), vbl_v3_scale(light->edge2, u2)));
        vbl_vec3 to_light = vbl_v3_sub(y, point);
        double d2 = vbl_v3_dot(to_light, to_light);
        if (!(d2 > 0.0)) return 0;
        double d = sqrt(d2);
        vbl_vec3 wi = vbl_v3_scale(to_light, 1.0 / d);
        double cos_light = -vbl_v3_dot(wi, light->normal);
        if (!(cos_light > 0.0) || !(light->area > 0.0)) return 0; /* back side: one-sided emitter */
        out->wi = wi;
        out->distance = d;
        out->li = light->color;
        out->pdf = d2 / (cos_light * light->area);
        out->is_delta = 0;
        return 1;
    }
    case VBL_LIGHT_ENVIRONMENT: {
        double pdf = 0.0;
        out->wi = vbl_sample_uniform_sphere(u1, u2, &pdf);
        out->distance = INFINITY;
        out->li = light->color;
        out->pdf = pdf;
        out->is_delta = 0;
        return pdf > 0.0;
    }
    }
    return 0;
}

int vbl_quad_intersect(const vbl_light* light, vbl_vec3 origin, vbl_vec3 direction, double* t_hit)
{
    double denom = vbl_v3_dot(direction, light->normal);
    if (!(denom < 0.0)) return 0; /* parallel or from behind */
    double t = vbl_v3_dot(vbl_v3_sub(light->corner, origin), light->normal) / denom;
    if (!(t > 0.0) || !isfinite(t)) return 0;
    vbl_vec3 q = vbl_v3_sub(vbl_v3_madd(origin, direction, t), light->corner);
    vbl_vec3 n = vbl_v3_cross(light->edge1, light->edge2);
    double nn = vbl_v3_dot(n, n);
    if (!(nn > 0.0)) return 0;
    double a = vbl_v3_dot(vbl_v3_cross(q, light->edge2), n) / nn;
    double b = vbl_v3_dot(vbl_v3_cross(light->edge1, q), n) / nn;
    if (a < 0.0 || a > 1.0 || b < 0.0 || b > 1.0) return 0;
    *t_hit = t;
    return 1;
}

double vbl_light_pdf(const vbl_light* light, vbl_vec3 point, vbl_vec3 wi)
{
    switch (light->type) {
    case VBL_LIGHT_QUAD: {
        double t;
        if (!vbl_quad_intersect(light, point, wi, &t)) return 0.0;
        double cos_light = -vbl_v3_dot(wi, light->normal);
        if (!(cos_light > 0.0) || !(light->area > 0.0)) return 0.0;
        return t * t / (cos_light * light->area);
    }
    case VBL_LIGHT_ENVIRONMENT: return VBL_INV_4PI;
    default: return 0.0;
    }
}
