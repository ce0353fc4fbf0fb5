/* Scattering in overlapping media on per-component sigma_t arrays (wrappers of media/medium.h,
 * which new code uses directly): coefficients add, the phase function is the sigma_s-weighted
 * mixture of the components' Henyey-Greenstein lobes. `component_sigma_t` is the per-component
 * extinction at the point (vbl_extinction_eval / vbl_free_flight_sample, media order). */
#ifndef VBL_SCENE_MEDIA_H
#define VBL_SCENE_MEDIA_H

#include "scene/scene.h"

/* sum_i sigma_s,i(x) p_i(cos_theta) per RGB channel (sigma_s,i = albedo_i * sigma_t,i): the
 * in-scattering kernel of the RTE. cos_theta is between the travel directions before and after
 * scattering (either transport direction: HG is symmetric). */
vbl_vec3 vbl_media_scatter_kernel(const vbl_scene* scene, const double* component_sigma_t, double cos_theta);

/* Pdf of vbl_media_sample_phase for cos_theta: sum_i q_i p_i(cos_theta), q_i proportional to the
 * mean-of-RGB sigma_s,i. */
double vbl_media_phase_pdf(const vbl_scene* scene, const double* component_sigma_t, double cos_theta);

/* Picks a component by sigma_s (u0), samples its HG lobe around `travel` (u1, u2). Returns 0 if
 * nothing scatters here; otherwise *wi (unit) and its mixture pdf *pdf. */
int vbl_media_sample_phase(const vbl_scene* scene, const double* component_sigma_t, vbl_vec3 travel,
                           double u0, double u1, double u2, vbl_vec3* wi, double* pdf);

/* A walk's scattering at a delta-tracking collision (sigma_t > 0 there; pt, photon_trace.c,
 * transport/surface/blue_noise/photon_paths.c): samples *wi with vbl_media_sample_phase (its pdf into *pdf unless
 * NULL) and multiplies *throughput by sigma_s p / (pdf sigma_t) (RGB). Returns 0 (throughput
 * untouched) if nothing scatters here. */
int vbl_media_scatter(const vbl_scene* scene, const double* component_sigma_t, double sigma_t, vbl_vec3 travel,
                      double u0, double u1, double u2, vbl_vec3* wi, double* pdf, vbl_vec3* throughput);

/* The same two at scene point p and path time `time` (seconds, 0 without motion blur): with an
 * albedo grid, sigma_s,i = albedo_i(p) sigma_t,i (media/medium_grids.h); otherwise bit for bit
 * the functions above. */
vbl_vec3 vbl_media_scatter_kernel_at(const vbl_scene* scene, const double* component_sigma_t, vbl_vec3 p, double time,
                                     double cos_theta);
int vbl_media_scatter_at(const vbl_scene* scene, const double* component_sigma_t, vbl_vec3 p, double time,
                         double sigma_t, vbl_vec3 travel, double u0, double u1, double u2, vbl_vec3* wi, double* pdf,
                         vbl_vec3* throughput);

/* sigma_s-weighted mean HG g of the media at a point with per-component sigma_t (0 if none). */
double vbl_media_mean_g(const vbl_scene* scene, const double* component_sigma_t);

#endif
