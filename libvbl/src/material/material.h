/* Surface materials (BRDFs): Lambert, normalized Phong, GGX microfacet. Every model has value,
 * pdf and sampling routines plus the analytic direction of its maximum, which the VBL PDFs of
 * Novak et al. 2012 (VBL), sections 3.1 and 6, need.
 *
 * Conventions: n is the unit shading normal; wo (towards the viewer / previous vertex) and wi
 * (towards the light / next vertex) are unit vectors pointing AWAY from the surface. eval returns
 * the BRDF f(wo, wi) (1/sr, without the cosine); pdfs are per unit solid angle of wi. Directions
 * below the surface (dot(n, w) <= 0) have f = 0 and pdf = 0. */
#ifndef VBL_MATERIAL_MATERIAL_H
#define VBL_MATERIAL_MATERIAL_H

#include <stddef.h>

#include "core/math.h"

/* Validated parameter ranges (vbl_material_validate). A Phong exponent above 1e6 is a mirror for
 * any practical purpose; GGX roughness below 1e-3 would put D's peak 1 / (pi a^2) near overflow
 * (GGX evaluates clamp(roughness, 1e-3, 1) for unvalidated input). */
#define VBL_PHONG_EXPONENT_MAX 1e6
#define VBL_GGX_ROUGHNESS_MIN 1e-3

typedef enum vbl_material_type {
    VBL_MATERIAL_LAMBERT = 0, /* f = albedo / pi */
    VBL_MATERIAL_PHONG = 1,   /* kd / pi + ks (n + 2) / (2 pi) cos^n(alpha), alpha from the mirror dir */
    VBL_MATERIAL_GGX = 2      /* GGX (Trowbridge-Reitz) specular, Smith G, Schlick F, plus a Lambertian
                                 kd lobe weighted by the Fresnel transmittance (material_ggx.c) */
} vbl_material_type;

typedef struct vbl_material {
    vbl_material_type type;
    vbl_vec3 albedo;   /* diffuse reflectance kd (all types), each channel in [0, 1] */
    vbl_vec3 specular; /* Phong: ks (kd + ks <= 1 per channel); GGX: F0 of Schlick's Fresnel */
    double exponent;   /* Phong exponent n >= 0 (the papers use 60..100) */
    double roughness;  /* GGX alpha in (0, 1] */
} vbl_material;

/* f(wo, wi), not multiplied by cos. */
vbl_vec3 vbl_material_eval(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi);
/* Density of vbl_material_sample choosing wi (solid angle). */
double vbl_material_pdf(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi);
/* Samples wi from (u0 selects the lobe, u1, u2 the direction); returns 1 with *wi, *pdf > 0 and
 * *f = f(wo, wi), or 0 when no valid direction was drawn (below the surface). */
int vbl_material_sample(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, double u0, double u1, double u2,
                        vbl_vec3* wi, double* pdf, vbl_vec3* f);
/* The unit direction wi that maximises the channel-mean f(wo, wi) cos(theta_i) (VBL paper
 * section 3.1 "omega_max"): n for Lambert (and when wo is below the surface); for Phong and GGX
 * a point of the plane of incidence between n and the mirror direction r of wo (r itself only
 * at normal incidence: the cosine tilts the peak towards n), found by a scan plus golden-section
 * search (~400 evaluations; compute once per shading point). */
vbl_vec3 vbl_material_max_direction(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo);
/* Upper bound, per channel, of f(wo, wi) cos(theta_i) over the directions wi within
 * acos(cos_half_angle) of the unit cone_axis (the VBL section 3.1 PDF for surface VSLs: "the
 * maximum of the BRDF within the VSL's cone"). O(1), no search. Lambert: exact. Phong and GGX:
 * exact for cones about the plane of incidence (and for tiny cones about max_direction),
 * otherwise a bound (median 1.0-1.1x, 90th percentile 1.01-1.5x the largest value found in
 * 0.1 rad test cones; up to ~7x for GGX a <= 0.05 at grazing wo). 0 when the cone lies
 * entirely below the surface or wo does. Never below the true maximum. */
vbl_vec3 vbl_material_max_in_cone(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 cone_axis,
                                  double cos_half_angle);
/* Returns 1 if the parameters are valid; otherwise 0 and a reason naming the field, e.g.
 * "exponent = -1 is outside [0, 1e+06]" (callers prefix their path: "surfaces[2].material.").
 * Ranges: channels in [0, 1]; Phong exponent in [0, 1e6] and albedo + specular <= 1 per
 * channel; GGX roughness in [1e-3, 1]. `why` may be NULL. */
int vbl_material_validate(const vbl_material* m, char* why, size_t size);
/* 1 if f is constant in wi (Lambert): VSL emission is then a single value. */
int vbl_material_is_diffuse(const vbl_material* m);
/* Directional albedo bound: max over channels of the reflectance (<= 1 for valid materials).
 * Lambert: kd; Phong: kd + ks (attained at normal incidence); GGX: F0 + (1 - F0) kd, the
 * normal-incidence mirror-limit value (Fresnel raises the albedo towards 1 at grazing angles). */
double vbl_material_max_albedo(const vbl_material* m);

#endif
