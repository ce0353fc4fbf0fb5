/* Material dispatch, Lambert, parameter validation and the maximum-direction search shared by
 * all models. The Phong and GGX lobes are in material_phong.c and material_ggx.c. */
#include "material/material.h"

#include <stdio.h>

#include "material/material_internal.h"

static vbl_vec3 vbl_lambert_eval(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    if (vbl_v3_dot(n, wo) <= 0.0 || vbl_v3_dot(n, wi) <= 0.0) return vbl_v3(0.0, 0.0, 0.0);
    return vbl_v3_scale(m->albedo, VBL_INV_PI);
}

/* Cosine-weighted hemisphere about n (Malley): pdf cos / pi. */
vbl_vec3 vbl_mat_cosine_sample(vbl_vec3 n, double u1, double u2)
{
    double r = sqrt(u1), phi = 2.0 * VBL_PI * u2;
    return vbl_mat_from_local(n, r * cos(phi), r * sin(phi), sqrt(fmax(0.0, 1.0 - u1)));
}

static int vbl_lambert_sample(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, double u1, double u2, vbl_vec3* wi,
                              double* pdf, vbl_vec3* f)
{
    if (vbl_v3_dot(n, wo) <= 0.0) return 0;
    vbl_vec3 w = vbl_mat_cosine_sample(n, u1, u2);
    double p = vbl_mat_cosine_pdf(vbl_v3_dot(n, w));
    if (!(p > 0.0)) return 0; /* u1 = 1 lands on the horizon */
    *wi = w;
    *pdf = p;
    *f = vbl_lambert_eval(m, n, wo, w);
    return 1;
}

vbl_vec3 vbl_material_eval(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    switch (m->type) {
    case VBL_MATERIAL_PHONG: return vbl_phong_eval(m, n, wo, wi);
    case VBL_MATERIAL_GGX: return vbl_ggx_eval(m, n, wo, wi);
    default: return vbl_lambert_eval(m, n, wo, wi);
    }
}

double vbl_material_pdf(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    switch (m->type) {
    case VBL_MATERIAL_PHONG: return vbl_phong_pdf(m, n, wo, wi);
    case VBL_MATERIAL_GGX: return vbl_ggx_pdf(m, n, wo, wi);
    default: return vbl_v3_dot(n, wo) > 0.0 ? vbl_mat_cosine_pdf(vbl_v3_dot(n, wi)) : 0.0;
    }
}

int vbl_material_sample(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, double u0, double u1, double u2,
                        vbl_vec3* wi, double* pdf, vbl_vec3* f)
{
    switch (m->type) {
    case VBL_MATERIAL_PHONG: return vbl_phong_sample(m, n, wo, u0, u1, u2, wi, pdf, f);
    case VBL_MATERIAL_GGX: return vbl_ggx_sample(m, n, wo, u0, u1, u2, wi, pdf, f);
    default: return vbl_lambert_sample(m, n, wo, u1, u2, wi, pdf, f);
    }
}

vbl_vec3 vbl_material_max_in_cone(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 cone_axis,
                                  double cos_half_angle)
{
    switch (m->type) {
    case VBL_MATERIAL_PHONG: return vbl_phong_max_in_cone(m, n, wo, cone_axis, cos_half_angle);
    case VBL_MATERIAL_GGX: return vbl_ggx_max_in_cone(m, n, wo, cone_axis, cos_half_angle);
    default: {
        if (vbl_v3_dot(n, wo) <= 0.0) return vbl_v3(0.0, 0.0, 0.0);
        double ti = vbl_mat_cone_min_angle(n, cone_axis, vbl_mat_cone_half_angle(cos_half_angle));
        return vbl_v3_scale(m->albedo, ti < 0.5 * VBL_PI ? VBL_INV_PI * cos(ti) : 0.0);
    }
    }
}

/* ---- maximum direction: channel-mean f cos(theta_i) along the plane of incidence ---------- */

typedef struct vbl_mat_arc { const vbl_material* m; vbl_vec3 n, wo, u; } vbl_mat_arc;

static vbl_vec3 arc_dir(const vbl_mat_arc* a, double t)
{
    return vbl_v3_normalize(vbl_v3_add(vbl_v3_scale(a->n, cos(t)), vbl_v3_scale(a->u, sin(t))));
}

static double arc_value(const vbl_mat_arc* a, double t)
{
    vbl_vec3 w = arc_dir(a, t);
    double c = vbl_v3_dot(a->n, w);
    return c > 0.0 ? vbl_mat_mean3(vbl_material_eval(a->m, a->n, a->wo, w)) * c : 0.0;
}

/* Best node of an evenly spaced grid of `count` angles on [lo, hi] (clipped to the hemisphere). */
static void arc_scan(const vbl_mat_arc* a, double lo, double hi, int count, double* best_t, double* best_v,
                     double* best_step)
{
    lo = fmax(lo, -0.5 * VBL_PI);
    hi = fmin(hi, 0.5 * VBL_PI);
    if (!(hi > lo)) return;
    double step = (hi - lo) / (count - 1);
    for (int i = 0; i < count; ++i) {
        double t = lo + step * i, v = arc_value(a, t);
        if (v > *best_v) {
            *best_v = v;
            *best_t = t;
            *best_step = step;
        }
    }
}

/* By the symmetry of both lobes about the plane of incidence, the maximiser of f cos lies on the
 * great circle through n and the mirror direction r (for Phong on the arc between them, VBL
 * paper section 6). A uniform 1-degree scan plus a fine scan about r (the lobe's width) bracket
 * the peak; golden-section search refines it to ~1e-12 rad. */
vbl_vec3 vbl_material_max_direction(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo)
{
    double cos_o = vbl_v3_dot(n, wo);
    if (cos_o <= 0.0 || vbl_material_is_diffuse(m)) return n;
    vbl_vec3 r = vbl_mat_reflect(n, wo);
    vbl_vec3 tang = vbl_v3_sub(r, vbl_v3_scale(n, vbl_v3_dot(n, r)));
    vbl_vec3 t, b;
    vbl_v3_basis(n, &t, &b);
    vbl_mat_arc a = {m, n, wo, vbl_v3_length(tang) > 1e-12 ? vbl_v3_normalize(tang) : t};
    double theta_r = vbl_mat_angle(n, r);
    double width = m->type == VBL_MATERIAL_PHONG ? 6.0 / sqrt(m->exponent + 1.0) : 8.0 * vbl_ggx_alpha(m);
    double best_t = 0.0, best_v = arc_value(&a, 0.0), step = VBL_PI / 180.0;
    arc_scan(&a, -0.5 * VBL_PI, 0.5 * VBL_PI, 181, &best_t, &best_v, &step);
    arc_scan(&a, theta_r - width, theta_r + width, 129, &best_t, &best_v, &step);
    if (!(best_v > 0.0)) return n;
    double lo = fmax(best_t - step, -0.5 * VBL_PI), hi = fmin(best_t + step, 0.5 * VBL_PI);
    const double g = 0.5 * (sqrt(5.0) - 1.0);
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = arc_value(&a, x1), f2 = arc_value(&a, x2);
    for (int i = 0; i < 80 && hi - lo > 1e-13; ++i) {
        if (f1 >= f2) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = arc_value(&a, x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = arc_value(&a, x2);
        }
    }
    double t_mid = 0.5 * (lo + hi);
    if (arc_value(&a, t_mid) >= best_v) best_t = t_mid;
    return arc_dir(&a, best_t);
}

int vbl_material_is_diffuse(const vbl_material* m)
{
    if (m->type == VBL_MATERIAL_LAMBERT) return 1;
    /* Phong without a specular lobe is Lambert; GGX always has Fresnel at grazing angles. */
    return m->type == VBL_MATERIAL_PHONG && vbl_v3_max_component(m->specular) <= 0.0;
}

double vbl_material_max_albedo(const vbl_material* m)
{
    switch (m->type) {
    case VBL_MATERIAL_PHONG: return vbl_v3_max_component(vbl_v3_add(m->albedo, m->specular));
    case VBL_MATERIAL_GGX:
        return vbl_v3_max_component(
            vbl_v3_add(m->specular, vbl_v3_mul(m->albedo, vbl_v3_sub(vbl_v3(1.0, 1.0, 1.0), m->specular))));
    default: return vbl_v3_max_component(m->albedo);
    }
}

/* ---- validation ---------------------------------------------------------------------------- */

static int check_channels(const char* field, vbl_vec3 v, char* why, size_t size)
{
    static const char* names[3] = {"r", "g", "b"};
    for (int c = 0; c < 3; ++c) {
        double x = vbl_v3_get(v, c);
        if (!(x >= 0.0 && x <= 1.0)) {
            snprintf(why, size, "%s.%s = %g is outside [0, 1]", field, names[c], x);
            return 0;
        }
    }
    return 1;
}

int vbl_material_validate(const vbl_material* m, char* why, size_t size)
{
    char dummy[1];
    if (!why || size == 0) {
        why = dummy;
        size = sizeof dummy;
    }
    why[0] = '\0';
    if (m->type != VBL_MATERIAL_LAMBERT && m->type != VBL_MATERIAL_PHONG && m->type != VBL_MATERIAL_GGX) {
        snprintf(why, size, "type = %d is not lambert (0), phong (1) or ggx (2)", (int)m->type);
        return 0;
    }
    if (!check_channels("albedo", m->albedo, why, size)) return 0;
    if (m->type == VBL_MATERIAL_LAMBERT) return 1;
    if (!check_channels("specular", m->specular, why, size)) return 0;
    if (m->type == VBL_MATERIAL_PHONG) {
        if (!(m->exponent >= 0.0 && m->exponent <= VBL_PHONG_EXPONENT_MAX)) {
            snprintf(why, size, "exponent = %g is outside [0, %g]", m->exponent, VBL_PHONG_EXPONENT_MAX);
            return 0;
        }
        static const char* names[3] = {"r", "g", "b"};
        for (int c = 0; c < 3; ++c) {
            double s = vbl_v3_get(m->albedo, c) + vbl_v3_get(m->specular, c);
            if (s > 1.0) {
                snprintf(why, size,
                         "albedo.%s + specular.%s = %g exceeds 1 (normalized Phong conserves energy only when "
                         "kd + ks <= 1)",
                         names[c], names[c], s);
                return 0;
            }
        }
        return 1;
    }
    if (!(m->roughness >= VBL_GGX_ROUGHNESS_MIN && m->roughness <= 1.0)) {
        snprintf(why, size, "roughness = %g is outside [%g, 1]", m->roughness, VBL_GGX_ROUGHNESS_MIN);
        return 0;
    }
    return 1;
}
