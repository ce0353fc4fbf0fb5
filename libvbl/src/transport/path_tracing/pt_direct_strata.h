/* pt's stratified single scattering along camera rays (option pt.direct_strata = K > 1; issue 14).
 *
 * The camera segment's single scattering from a delta light l (the volume_direct class),
 *   I_l = int_t0^t1 T(t0, t) K(t, w_l) L_l(t) T_l(t) dt     (K = sum sigma_s p, the kernel),
 * is estimated from K NEE points instead of the one delta-tracking collision's NEE:
 *  1. one ratio-tracking walk along the camera ray over the media interval, the camera split's
 *     (vbl_pt_camera_split_walk: tentative points p_i at VBL_PT_WALK_MAJORANT_SCALE = 8x the
 *     majorant rate; Novak et al. 2014,
 *     eq. 6) gives each point the weight w_i = T^_{i-1} sigma_s(p_i) / mu_i, T^_{i-1} the product
 *     of (1 - sigma_t / mu) before p_i. Summing w_i f(p_i) is the null-collision estimator of
 *     int T sigma_s f dt (Novak, Georgiev, Hanika and Jarosz 2018, "Monte Carlo methods for
 *     volumetric light transport simulation", sec. 5.2 and 6.2, the ratio-tracking form of
 *     the collision estimator; the points are a Poisson process, so by Campbell's theorem
 *     E[sum_i w_i f(p_i)] = int T sigma_s f dt); the walk ends at the roulette (threshold 0.1)
 *     or past 256 points with one delta-tracking collision from the last (the collision
 *     estimator, weight T^ sigma_s / sigma_t);
 *  2. K points are picked from the discrete distribution w_i / W (W = sum w_i), one per stratum
 *     [k, k + 1) / K of its CDF (stratified resampling, as in Kulla and Fajardo 2012, sec. 4.3,
 *     distance samples stratified along the ray), and each gets the NEE of a delta light picked
 *     among the N_s fed here: (W / K) (K(p, w) / sigma_s(p)) L T^_l N_s, T^_l the NEE's shadow
 *     transmittance (pt.shadow_transmittance). Every pick has marginal probability w_i / W, so the
 *     sum is unbiased for sum_i w_i f(p_i), hence for I_l.
 * The medium's part (T sigma_s) is thus carried exactly by the weights; only the light term
 * (phase, T_l) is sampled, and every camera ray through media gets K NEEs, collision or not.
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
