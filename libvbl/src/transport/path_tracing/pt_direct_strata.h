/* pt's stratified single scattering along camera rays (option pt.direct_strata = K > 1; issue 14).
 *
 * The camera segment's single scattering from a delta light l (the volume_direct class),
 *   I_l = int_t0^t1 T(t0, t) K(t, w_l) L_l(t) T_l(t) dt     (K = sum sigma_s p, the kernel),
 * is estimated with K distances stratified in the CDF of a free-flight proxy instead of the one
 * delta-tracking collision's NEE (the distance-sampling view of Kulla and Fajardo 2012, sec. 4,
 * with stratification in the CDF, sec. 4.3 "Stratification"). The proxy is the control density
 * of the majorant segments, c(t) = (majorant + minorant) / 2 (volume/control_depth.h; exact in
 * homogeneous segments), truncated to the media interval [t0, t1]:
 *   p(t) = c(t) exp(-tau_c(t0, t)) / (1 - exp(-tau_c(t0, t1))),
 * inverted analytically segment by segment at u_k = (k + xi_k) / K. Each sample is weighted by
 *   T^(t_k) K(t_k, w) L T^_l / (K p(t_k) / N_s)      (a delta light picked among the N_s),
 * with T^(t_k) read from one ratio-tracking pass along the camera ray (the cached ratio
 * estimator, volume/transmittance_cache.h; Novak et al. 2014, eq. 6, as a step function in t:
 * Novak, Georgiev, Hanika and Jarosz 2018, "Monte Carlo methods for volumetric light transport
 * simulation", sec. 6.2, eq. 29, the ratio-tracking estimator of T; its tentative points are a
 * Poisson process independent of the t_k, so E[T^(t_k) | t_k] = T(t0, t_k)) and T^_l the NEE's
 * shadow transmittance (pt.shadow_transmittance). p > 0 wherever sigma_t can be (c >= majorant / 2),
 * and each stratum k contributes int over its CDF slice, so the sum is unbiased.
 *
 * The lights it feeds: distant lights, and point/spot lights when pt.equiangular is off (with it
 * on they keep the equiangular / collision MIS, pt_equiangular.h). For those lights the first
 * collision's NEE is skipped (each path is counted once); quad and environment lights keep the
 * collision NEE with its phase-sampling MIS. Deeper vertices are unchanged. */
#ifndef VBL_TRANSPORT_PT_DIRECT_STRATA_H
#define VBL_TRANSPORT_PT_DIRECT_STRATA_H

#include "transport/common/estimator.h"

#define VBL_PT_DIRECT_STRATA_MAX 64

/* 1 if pt.direct_strata > 1, the scene has media, at least one scattering event is allowed and
 * a light is fed by the estimator. */
int vbl_pt_direct_strata_active(const vbl_render_context* ctx);

/* 1 if the estimator is active and feeds `light`: then the first collision's NEE skips it. */
int vbl_pt_direct_strata_skips(const vbl_render_context* ctx, const vbl_light* light);

/* The estimator on the camera segment (origin, unit direction, up to t_surface; INFINITY: none):
 * adds beta times the estimate of sum_l I_l into *L (the volume_direct class). Draws from rng. */
void vbl_pt_direct_strata(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                          vbl_vec3 direction, double t_surface, vbl_vec3 beta, vbl_rng* rng, vbl_vec3* L);

#endif
