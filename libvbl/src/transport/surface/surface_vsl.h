/* Surface virtual spherical lights (Novak et al. 2012 (VBL), sections 3.3-3.4; Hasan et al.'s
 * VSLs): photon hits on surfaces stored as VSLs, gathered
 *   - at camera-visible surface points: surface_from_surface (section 3.4), and
 *   - along camera-ray segments in the media: volume_from_surface (section 3.3, the dual of 3.1).
 *
 * A VSL at y (unit shading normal n_y on the side the photon arrived from, material m_y) received
 * a photon of power Phi from the unit direction wi_y (pointing away from the surface, towards
 * where the light came from). Its radiant intensity towards the light-travel direction omega is
 * Phi f_y(omega, wi_y) max(0, n_y . omega) (the SENDER lobe of surface_cone_kernel.h). Spread over
 * a sphere of radius R (the paper's disc facing the gather direction) the contribution to a
 * receiver is Phi V T K_R with K_R = 1/(pi R^2) int_{Omega_vsl} A B d omega (surface_cone_kernel.h),
 * bounded by 2 max(A B) / R^2: no 1/w^2 singularity. R -> 0 gives the VPL value
 * Phi V T A B / w^2. Progressive rendering shrinks R per pass with eq 11 (dim 2):
 * R_p = vbl_radius_at_pass(R_0, alpha, 2, p) (transport/common/radius_schedule.h), so bias and variance
 * both vanish in the pass average (section 4.1).
 *
 * surface_from_surface at a surface point x (receiver lobe f_x(wo, wi) cos_x):
 *     L = sum_vsl Phi T(y, x) V(y, x) K_R(x, y).
 * volume_from_surface along the camera segment c_o + u c_d, u in [u0, u1], with camera-point
 * phase HG(g_c, -c_d . omega):
 *     L = sum_vsl Phi int_u0^u1 M(u) K_R(x(u), y) du,   M(u) = sigma_s(x_u) T(0, u) T(x_u, y) V,
 * one sample per VSL from the angular sampler about y (surface_line_sampler.h, product-aware:
 * vertex values HG(g_c, -c_d . omega) x the VSL's f cos, or for R > 0 their maxima over the cone;
 * hints at the VSL's BRDF peak and its horizon; mapping scale hypot(D, R)). */
#ifndef VBL_TRANSPORT_SURFACE_VSL_H
#define VBL_TRANSPORT_SURFACE_VSL_H

#include <stddef.h>

#include "core/math.h"
#include "core/rng.h"
#include "material/material.h"
#include "media/medium.h"
#include "transport/surface/surface_from_volume.h"
#include "transport/surface/surface_line_sampler.h"
#include "vbl/vbl_core.h"

typedef struct vbl_surface_vsl {
    vbl_vec3 position;
    vbl_vec3 normal;    /* unit shading normal on the incident side */
    vbl_vec3 incident;  /* unit wi: towards where the photon came from (away from the surface) */
    vbl_vec3 power;     /* flux arriving */
    int material;       /* index into the store's materials */
    int bounce;         /* scattering events before the photon reached the surface */
} vbl_surface_vsl;

typedef struct vbl_surface_vsl_store {
    vbl_surface_vsl* vsls;
    size_t count, capacity;
    const vbl_material* materials; /* not owned (the scene's) */
    size_t material_count;
} vbl_surface_vsl_store;

void vbl_surface_vsl_store_init(vbl_surface_vsl_store* store, const vbl_material* materials, size_t material_count);
/* Appends a copy. Errors (nothing appended): VBL_ERROR_INVALID_ARGUMENT naming the field for a
 * material index out of range or non-finite/negative power, non-unit normal/incident;
 * VBL_ERROR_OUT_OF_MEMORY. */
vbl_result vbl_surface_vsl_store_add(vbl_surface_vsl_store* store, const vbl_surface_vsl* vsl);
void vbl_surface_vsl_store_free(vbl_surface_vsl_store* store);

/* T(a, b) V(a, b) between two points (caller: ratio tracking + vbl_surfaces_occluded). */
typedef double (*vbl_surface_visibility_fn)(void* ctx, vbl_vec3 a, vbl_vec3 b);
/* M(u) of a camera point x_u seen from the VSL at y: sigma_s(x_u) T(0, u) T(x_u, y) V(x_u, y). */
typedef double (*vbl_surface_camera_medium_fn)(void* ctx, double u, vbl_vec3 camera_point, vbl_vec3 vsl_position);

/* K_R between one VSL (material vm) and the surface point sp (R == 0: the VPL value A B / w^2). */
vbl_vec3 vbl_surface_vsl_kernel_surface(const vbl_surface_point* sp, const vbl_surface_vsl* vsl,
                                        const vbl_material* vm, double radius, int n, const double jitter[3]);
/* K_R between one VSL and the camera point x with camera direction c_d (HG g_camera). */
vbl_vec3 vbl_surface_vsl_kernel_medium(vbl_vec3 x, vbl_vec3 c_d, double g_camera, const vbl_surface_vsl* vsl,
                                       const vbl_material* vm, double radius, int n, const double jitter[3]);

/* surface_from_surface: sum over the store's VSLs of Phi T V K_R (jitter drawn from rng, 3 numbers
 * per VSL; unbiased for the radius-R integral). visibility may be NULL (1). n: cone directions. */
vbl_vec3 vbl_surface_from_surface(const vbl_surface_point* sp, const vbl_surface_vsl_store* store, double radius,
                                  vbl_surface_visibility_fn visibility, void* ctx, int n, vbl_rng* rng);

/* A camera-medium callback with its context. */
typedef struct vbl_surface_camera_medium {
    vbl_surface_camera_medium_fn fn;
    void* ctx;
} vbl_surface_camera_medium;

/* The sampler of u in the camera segment [t0, t1] about one VSL (returns 0 without support). */
int vbl_surface_vsl_camera_sampler_init(vbl_surface_line_sampler* s, const vbl_segment* camera, double g_camera,
                                        const vbl_surface_vsl* vsl, const vbl_material* vm, double radius);
/* volume_from_surface for one VSL, one sample (xi picks u on the camera segment, kernel->jitter the
 * cone directions when R > 0): Phi M(u) K_R(x(u), y) / pdf(u). *u_out / *pdf_out may be NULL. */
vbl_vec3 vbl_volume_from_vsl(const vbl_segment* camera, double g_camera, const vbl_surface_vsl* vsl,
                             const vbl_material* vm, const vbl_surface_kernel* kernel, vbl_surface_camera_medium medium,
                             double xi, double* u_out, double* pdf_out);
/* volume_from_surface: the sum over the store's VSLs, 4 randoms per VSL from rng. */
vbl_vec3 vbl_volume_from_surface(const vbl_segment* camera, double g_camera, const vbl_surface_vsl_store* store,
                                 double radius, vbl_surface_camera_medium medium, int n, vbl_rng* rng);

#endif
