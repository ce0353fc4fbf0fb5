/* surface_from_volume: light scattered by the media onto a camera-visible surface point, from one
 * virtual ray light (Novak et al. 2012 (VRL), section 3, eq. 6, sampled as in section 4.3) or
 * virtual beam light (Novak et al. 2012 (VBL), section 3.1, eqs. 8-9). Pure kernels: the caller
 * supplies the media terms through a callback, so tests use homogeneous/no media and the
 * renderer plugs in ratio tracking plus surface occlusion.
 *
 * Geometry and conventions: the VRL is l_o + v l_d, v in [0, length], carrying power Phi with
 * HG asymmetry g; the surface point x (shading normal n, material, wo towards the camera, all
 * unit). At the VRL point p(v) light travelling along l_d scatters towards x (light-travel
 * direction omega = (x - p) / w, w = |x - p|) and arrives at x from wi = -omega:
 *   eq 6:   L = Phi int_0^length M(v) HG(g, l_d . omega) f(wo, wi) max(0, n . wi) / w^2 dv,
 *   eq 8-9: L = Phi int_0^length M(v) K_R(x, p(v)) dv,
 *           K_R = 1/(pi R^2) int_{Omega_vsl} HG(g, l_d . omega') f(wo, -omega') cos dw'
 *           (transport/surface/surface_cone_kernel.h: -> the eq 6 integrand as R -> 0, <= 2 max / R^2),
 * M(v) = sigma_s(p) T_vrl(0, v) T(p, x) V(p, x) from the callback (for short VRLs T_vrl = 1,
 * photon_trace.h). One sample: L ~= Phi M(v) k(v) / pdf(v) with v from the angular sampler of
 * transport/surface/surface_line_sampler.h about x, fitted to the integrand without 1/w^2:
 *   VRL (R == 0): HG(g, l_d . omega) mean_channels(f cos) at each vertex (VRL section 4.3: the
 *     phase times the foreshortened BRDF in the angular domain), hints at the BRDF peak
 *     (vbl_material_max_direction) and the horizon n . wi = 0;
 *   VBL (R > 0): section 3.1's bound at each vertex: the HG maximum over the VSL's cone
 *     (vbl_vsl_cone_hg_max, exact) times the BRDF x cos maximum over the cone
 *     (vbl_material_max_in_cone): the product of the two maxima, an upper bound of the paper's
 *     "product at omega'_max" (overestimation costs little variance, section 3.1); the mapping
 *     scale is hypot(D, R), i.e. the softened 1 / (w^2 + R^2).
 * Both are unbiased for their integral (defensive equiangular mixture: the pdf is positive on the
 * whole VRL). */
#ifndef VBL_TRANSPORT_SURFACE_FROM_VOLUME_H
#define VBL_TRANSPORT_SURFACE_FROM_VOLUME_H

#include "core/math.h"
#include "material/material.h"
#include "media/medium.h"
#include "transport/surface/surface_line_sampler.h"

/* A camera-visible shading point, prepared once and reused for every virtual light. */
typedef struct vbl_surface_point {
    vbl_vec3 position, normal, wo;   /* unit normal on the camera's side, unit wo towards the camera */
    const vbl_material* material;
    vbl_vec3 max_direction;          /* vbl_material_max_direction(material, normal, wo) (~400 evals) */
} vbl_surface_point;

void vbl_surface_point_init(vbl_surface_point* sp, vbl_vec3 position, vbl_vec3 normal, vbl_vec3 wo,
                            const vbl_material* material);

/* M(v) of a VRL point p = l_o + v l_d seen from x: sigma_s(p) T_vrl(0, v) T(p, x) V(p, x) >= 0. */
typedef double (*vbl_surface_medium_fn)(void* ctx, double v, vbl_vec3 vrl_point, vbl_vec3 x);

/* A VRL as the kernels see it (photon_trace.h's vbl_vrl has the same fields). */
typedef struct vbl_surface_vrl {
    vbl_vec3 origin, direction; /* direction unit */
    double length;
    vbl_vec3 power;
    double g;
} vbl_surface_vrl;

/* Eq 6's integrand without Phi and M: HG(g, l_d . omega) f(wo, wi) cos_i / w^2 at p(v)
 * (0 at w == 0 and below the surface). */
vbl_vec3 vbl_vrl_surface_integrand(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, double v);
/* Eq 9 / Phi: K_R(x, p(v)) (R == 0: the integrand above). jitter: see surface_cone_kernel.h. */
vbl_vec3 vbl_beam_light_surface_kernel(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, double v, double radius,
                                int n, const double jitter[3]);

/* sum_i w_i k_i at p(v) over the lobes of the medium there (media/medium.h; w_i = albedo_i
 * sigma_t,i / sigma_t, k_i the kernel above with g = g_i, radius 0: the eq 6 integrand): the
 * in-scattering of overlapping media with different g, which one HG lobe of the VRL's g is not. */
vbl_vec3 vbl_surface_vrl_mixture_kernel(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, double v,
                                        double radius, int n, const double jitter[3], const vbl_medium_point* mp);

/* The sampler of v in [0, length] (R == 0: VRL target, R > 0: VBL target). Returns 0 without
 * support (zero length). */
int vbl_surface_vrl_sampler_init(vbl_surface_line_sampler* s, const vbl_surface_point* sp,
                                 const vbl_surface_vrl* vrl, double radius);

/* The VSL kernel's radius R (0: the point form) and its cone quadrature (n directions per
 * strategy, jitter: surface_cone_kernel.h). */
typedef struct vbl_surface_kernel {
    double radius;
    int n;
    double jitter[3];
} vbl_surface_kernel;

/* One-sample estimates of eq 6 (radius 0) / eqs 8-9 (kernel->radius > 0; the cone kernel with
 * kernel->n directions per strategy and the kernel->jitter randoms). xi picks v. *v_out and *pdf_out may be NULL.
 * Returns 0 contribution when the sampler has no support or M(v) == 0. */
vbl_vec3 vbl_surface_from_vrl(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, vbl_surface_medium_fn medium,
                              void* ctx, double xi, double* v_out, double* pdf_out);
vbl_vec3 vbl_surface_from_vbl(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, const vbl_surface_kernel* kernel,
                              vbl_surface_medium_fn medium, void* ctx, double xi, double* v_out, double* pdf_out);

/* Overlapping media with different g (media/medium.h): the same estimate with the true phase
 * mixture at the sampled point. `medium` returns sigma_t(p) T_vrl(0, v) T(p, x) V(p, x) and the
 * medium there (*mp); the estimate is Phi M sum_i w_i k_i(v) / pdf(v) (vbl_surface_vrl_mixture_kernel),
 * v from the sampler fitted to `hint`'s mixture (the lobes the VRL may meet; NULL: the VRL's g). */
typedef double (*vbl_surface_mixture_fn)(void* ctx, double v, vbl_vec3 vrl_point, vbl_vec3 x, vbl_medium_point* mp);
int vbl_surface_vrl_sampler_init_mixture(vbl_surface_line_sampler* s, const vbl_surface_point* sp,
                                         const vbl_surface_vrl* vrl, double radius, const vbl_medium_point* hint);
vbl_vec3 vbl_surface_from_vrl_mixture(const vbl_surface_point* sp, const vbl_surface_vrl* vrl,
                                      const vbl_surface_kernel* kernel, const vbl_medium_point* hint,
                                      vbl_surface_mixture_fn medium, void* ctx, double xi);

#endif
