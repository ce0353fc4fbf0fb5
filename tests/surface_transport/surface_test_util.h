/* Shared fixtures of the surface-transport tests: the papers' materials (Lambert, Phong 60,
 * GGX 0.3), a homogeneous medium, brute-force quadrature over a VSL cone. Header-only (static). */
#ifndef VBL_TEST_SURFACE_TEST_UTIL_H
#define VBL_TEST_SURFACE_TEST_UTIL_H

#include <math.h>
#include <stdio.h>

#include "core/math.h"
#include "material/material.h"
#include "quad.h"
#include "sampling/vsl_cone.h"
#include "transport/surface/surface_cone_kernel.h"

static inline vbl_material st_material(int which)
{
    vbl_material m;
    m.albedo = vbl_v3(0.6, 0.5, 0.4);
    m.specular = vbl_v3(0.0, 0.0, 0.0);
    m.exponent = 0.0;
    m.roughness = 1.0;
    if (which == 0) {
        m.type = VBL_MATERIAL_LAMBERT;
    } else if (which == 1) {
        m.type = VBL_MATERIAL_PHONG;
        m.albedo = vbl_v3(0.3, 0.25, 0.2);
        m.specular = vbl_v3(0.6, 0.6, 0.6);
        m.exponent = 60.0;
    } else {
        m.type = VBL_MATERIAL_GGX;
        m.albedo = vbl_v3(0.5, 0.4, 0.3);
        m.specular = vbl_v3(0.5, 0.5, 0.5);
        m.roughness = 0.3;
    }
    return m;
}
static inline const char* st_material_name(int which) { return which == 0 ? "lambert" : (which == 1 ? "phong60" : "ggx0.3"); }

static inline double st_mean3(vbl_vec3 v) { return (v.x + v.y + v.z) / 3.0; }
static inline int st_finite3(vbl_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }
static inline int st_nonneg3(vbl_vec3 v) { return v.x >= 0.0 && v.y >= 0.0 && v.z >= 0.0; }

/* Homogeneous medium: M = sigma_s exp(-sigma_t (along + |a - b|)). */
typedef struct st_medium { double sigma_s, sigma_t; } st_medium;
static inline double st_medium_fn(void* c, double along, vbl_vec3 a, vbl_vec3 b)
{
    const st_medium* m = (const st_medium*)c;
    return m->sigma_s * exp(-m->sigma_t * (along + vbl_v3_length(vbl_v3_sub(a, b))));
}

/* Brute force: 1/(pi R^2) int over the cone of mean(A B), adaptive quadrature in (theta, phi)
 * about the cone axis. */
typedef struct st_cone_ctx {
    const vbl_surface_lobe *a, *b;
    vbl_vec3 axis, t, s;
    double theta;
} st_cone_ctx;
static inline double st_cone_phi(double phi, void* c)
{
    st_cone_ctx* k = (st_cone_ctx*)c;
    double st = sin(k->theta), ct = cos(k->theta);
    vbl_vec3 w = vbl_v3_add(vbl_v3_scale(k->axis, ct),
                            vbl_v3_add(vbl_v3_scale(k->t, st * cos(phi)), vbl_v3_scale(k->s, st * sin(phi))));
    return st_mean3(vbl_v3_mul(vbl_surface_lobe_eval(k->a, w), vbl_surface_lobe_eval(k->b, w)));
}
static inline double st_cone_theta(double theta, void* c)
{
    st_cone_ctx* k = (st_cone_ctx*)c;
    k->theta = theta;
    double s = 0.0;
    for (int q = 0; q < 8; ++q) /* octants: the lobes' kinks converge faster split */
        s += vbl_quad_adaptive(st_cone_phi, k, q * VBL_PI / 4, (q + 1) * VBL_PI / 4, 1e-12, 1e-7);
    return s * sin(theta);
}
static inline double st_cone_reference(const vbl_surface_lobe* a, const vbl_surface_lobe* b, vbl_vec3 x, vbl_vec3 c,
                                double radius)
{
    vbl_vsl_cone cone;
    vbl_vsl_cone_init(&cone, vbl_v3_sub(x, c), radius, vbl_v3(0, 0, 1));
    st_cone_ctx k = {a, b, cone.axis, vbl_v3(0, 0, 0), vbl_v3(0, 0, 0), 0.0};
    vbl_v3_basis(cone.axis, &k.t, &k.s);
    double s = 0.0;
    for (int q = 0; q < 4; ++q)
        s += vbl_quad_adaptive(st_cone_theta, &k, cone.half_angle * q / 4, cone.half_angle * (q + 1) / 4, 1e-12,
                               1e-6);
    return s / (VBL_PI * radius * radius);
}

#endif
