/* pt's equiangular next-event estimation for point and spot lights (Kulla and Fajardo 2012,
 * "Importance Sampling Techniques for Path Tracing in Participating Media", sec. 4.1 equiangular
 * sampling, sec. 4.2 MIS with distance sampling), combined with the free-flight collision's NEE by
 * two-sample MIS (Veach 1997, eq. 9.13 / 9.14).
 *
 * For every segment of a path (origin, unit direction, up to the surface it hits) the single-
 * scattering integral towards light i
 *   I_i = int_t0^t1 T(t0, t) K(t, w_i) L_i(t) T_l(t) dt     (K = sum sigma_s p, the kernel)
 * is estimated twice: by the free-flight (delta-tracking) collision at density sigma_t(t) T(t0, t)
 * with the light picked uniformly among all N lights (pt's ordinary NEE), and by a distance t drawn
 * equiangularly towards a point/spot light picked uniformly among the N_eq such lights, with T(t0, t)
 * estimated by the render's transmittance estimator (ratio tracking: the product of (1 - sigma_t /
 * majorant) over tentative collisions, Novak et al. 2014, eq. 6) and sigma_t(t) looked up, so the
 * heterogeneous medium enters through the real/majorant density ratios, unbiased. The MIS weights
 * use q_ff(i, t) = sigma_t(t) exp(-tau_c(t0, t)) / N with tau_c the majorant segments' mid-bound
 * optical depth (volume/control_depth.h; exact in homogeneous media) and q_ea(i, t) = p_ea,i(t) /
 * N_eq: both are deterministic functions of (segment, i, t) and w_ff + w_ea = 1 wherever either
 * strategy can sample, so the sum stays unbiased whatever the approximation in q_ff costs in
 * variance. Quad lights keep the free-flight NEE alone (not done: needs the light point first). */
#ifndef VBL_TRANSPORT_PT_EQUIANGULAR_H
#define VBL_TRANSPORT_PT_EQUIANGULAR_H

#include "transport/common/estimator.h"

/* 1 if options select equiangular NEE and the scene has a point or spot light and media. */
int vbl_pt_equiangular_active(const vbl_render_context* ctx);

/* The equiangular sample of one segment: adds w_ea K L T T_l / (p_ea / N_eq) * beta into *L.
 * t_surface: where the segment ends (INFINITY: escapes). u_pick picks the light, u_t the distance
 * (the caller draws both, whatever follows, so later dimensions keep their place); the
 * transmittance estimates draw from rng. */
void vbl_pt_equiangular_nee(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                            vbl_vec3 direction, double t_surface, vbl_vec3 beta, double u_pick, double u_t,
                            vbl_rng* rng, vbl_vec3* L);

/* MIS weight of the free-flight collision NEE at distance t (sigma_t there) on the segment
 * (origin, direction, t_surface) when it picked `light`: 1 unless the light is a point/spot light
 * and equiangular NEE is active. */
double vbl_pt_equiangular_ff_weight(const vbl_render_context* ctx, const vbl_light* light, vbl_vec3 origin,
                                    vbl_vec3 direction, double t_surface, double t, double sigma_t);

#endif
