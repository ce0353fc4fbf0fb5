/* Surface materials (BRDFs): Lambert, normalized Phong, GGX microfacet. Every model has value,
 * pdf and sampling routines plus the analytic direction of its maximum, which the VBL PDFs of
 * virtual-beam-lights.txt section 3.1 / section 6 need.
 *
 * Conventions: n is the unit shading normal; wo (towards the viewer / previous vertex) and wi
 * (towards the light / next vertex) are unit vectors pointing AWAY from the surface. eval returns
 * the BRDF f(wo, wi) (1/sr, without the cosine); pdfs are per unit solid angle of wi. Directions
 * below the surface (dot(n, w) <= 0) have f = 0 and pdf = 0. */
#ifndef VBL_MATERIAL_MATERIAL_H
#define VBL_MATERIAL_MATERIAL_H

#include "core/math.h"

typedef enum vbl_material_type {
    VBL_MATERIAL_LAMBERT = 0, /* f = albedo / pi */
    VBL_MATERIAL_PHONG = 1,   /* kd / pi + ks (n + 2) / (2 pi) cos^n(alpha), alpha from the mirror dir */
    VBL_MATERIAL_GGX = 2      /* kd / pi + GGX (Trowbridge-Reitz) specular, Smith G, Schlick F */
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
/* The unit direction wi that maximises f(wo, wi) cos(theta_i) (or f alone for the diffuse
 * lobe: n); for Phong and GGX the mirror direction of wo when the specular lobe dominates. */
vbl_vec3 vbl_material_max_direction(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo);
/* 1 if f is constant in wi (Lambert): VSL emission is then a single value. */
int vbl_material_is_diffuse(const vbl_material* m);
/* Directional albedo bound: max over channels of the reflectance (<= 1 for valid materials). */
double vbl_material_max_albedo(const vbl_material* m);

#endif
