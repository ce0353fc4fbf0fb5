/* Single scattering along a camera ray (the volume_direct layer), shared by every method:
 *  - point and spot lights: equiangular distance sampling toward the light over the ray's
 *    overlap with the media (Kulla & Fajardo 2012), camera transmittance by one transmittance
 *    estimate T(0, t), weight T(0,t) sigma_s(t) p L_i T_shadow / pdf(t);
 *  - distant, quad and environment lights: one delta-tracking free flight (density
 *    sigma_t T(0, t)) shared by these lights, then light sampling at the collision for each,
 *    weight (kernel / sigma_t) L_i T_shadow / pdf_light.
 * Every light is sampled once per call (no light selection). Unbiased; agrees with pt's
 * volume_direct layer in expectation. */
#ifndef VBL_TRANSPORT_SINGLE_SCATTER_H
#define VBL_TRANSPORT_SINGLE_SCATTER_H

#include "transport/common/estimator.h"

/* Adds one estimate of single-scattered radiance arriving at origin from along `direction`
 * (unit) to *radiance. */
void vbl_single_scatter_estimate(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                 vbl_vec3 direction, vbl_rng* rng, vbl_vec3* radiance);
/* The same over the camera ray's first t_max units only (the first surface hit,
 * vbl_camera_sample.t_max); shadow rays are blocked by surfaces (vbl_ctx_transmittance). */
void vbl_single_scatter_estimate_to(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                    vbl_vec3 direction, double t_max, vbl_rng* rng, vbl_vec3* radiance);

/* An estimator that produces only volume_direct (tests, and the single-scattering preview). */
extern const vbl_estimator vbl_estimator_single_scatter;

#endif
