/* Shared helpers of the material lobes (material.c, material_phong.c, material_ggx.c); not
 * part of the material interface. */
#ifndef VBL_MATERIAL_INTERNAL_H
#define VBL_MATERIAL_INTERNAL_H

#include "material/material.h"

/* Channel mean: the scalar used for lobe selection and for vbl_material_max_direction. */
static inline double vbl_mat_mean3(vbl_vec3 v) { return (v.x + v.y + v.z) / 3.0; }

/* Mirror direction of w about unit n: 2 (n.w) n - w. */
static inline vbl_vec3 vbl_mat_reflect(vbl_vec3 n, vbl_vec3 w)
{
    return vbl_v3_sub(vbl_v3_scale(n, 2.0 * vbl_v3_dot(n, w)), w);
}

/* Unit vector with local coordinates (x, y, z) in the frame whose z axis is the unit `axis`. */
static inline vbl_vec3 vbl_mat_from_local(vbl_vec3 axis, double x, double y, double z)
{
    vbl_vec3 t, b;
    vbl_v3_basis(axis, &t, &b);
    return vbl_v3_normalize(vbl_v3_add(vbl_v3_add(vbl_v3_scale(t, x), vbl_v3_scale(b, y)), vbl_v3_scale(axis, z)));
}

/* Angle between unit vectors, accurate at 0 and pi (atan2 of |a x b| and a.b). */
static inline double vbl_mat_angle(vbl_vec3 a, vbl_vec3 b)
{
    return atan2(vbl_v3_length(vbl_v3_cross(a, b)), vbl_v3_dot(a, b));
}

/* Smallest angle between unit `a` and a direction of the cone {w : angle(w, axis) <= half}. */
static inline double vbl_mat_cone_min_angle(vbl_vec3 a, vbl_vec3 axis, double half)
{
    return fmax(0.0, vbl_mat_angle(a, axis) - half);
}

/* Half-angle of a cone given by the cosine (read as a clamped value in [-1, 1]). */
static inline double vbl_mat_cone_half_angle(double cos_half) { return acos(vbl_clamp(cos_half, -1.0, 1.0)); }

/* Cosine-weighted hemisphere about n (pdf cos / pi) and its density. */
vbl_vec3 vbl_mat_cosine_sample(vbl_vec3 n, double u1, double u2);
static inline double vbl_mat_cosine_pdf(double cos_i) { return cos_i > 0.0 ? cos_i * VBL_INV_PI : 0.0; }

/* Normalized Phong (material_phong.c). */
vbl_vec3 vbl_phong_eval(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi);
double vbl_phong_pdf(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi);
int vbl_phong_sample(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, double u0, double u1, double u2, vbl_vec3* wi,
                     double* pdf, vbl_vec3* f);
vbl_vec3 vbl_phong_max_in_cone(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 axis, double cos_half);

/* GGX microfacet + Lambert (material_ggx.c). */
vbl_vec3 vbl_ggx_eval(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi);
double vbl_ggx_pdf(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi);
int vbl_ggx_sample(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, double u0, double u1, double u2, vbl_vec3* wi,
                   double* pdf, vbl_vec3* f);
vbl_vec3 vbl_ggx_max_in_cone(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 axis, double cos_half);
/* Roughness actually used: clamp(roughness, VBL_GGX_ROUGHNESS_MIN, 1). */
double vbl_ggx_alpha(const vbl_material* m);

#endif
