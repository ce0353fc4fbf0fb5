/* Virtual point lights in media (VRL paper eq. 4, integrated along the camera ray by eq. 2).
 *
 * Per pass: photon tracing (photon_trace.h) stores the scattering vertices as VPLs. Per camera
 * sample, with [u0, u1] the camera ray's overlap with the media:
 *   emission        quad/environment lights seen directly, attenuated (light_emission.h);
 *   volume_direct   the shared single-scattering estimator (single_scatter.h), as pt;
 *   volume_from_volume
 *       sum over VPLs j of  T_c(u) sigma_s(u) f(theta_u) I_j(theta_j) T(x_u, x_j) / (w^2 pdf(u)),
 *       u equiangular toward the VPL (pdf(u) proportional to 1/w^2 on [u0, u1]); T_c from one
 *       cached transmittance per camera ray, T(x_u, x_j) one ctx->tracking estimate;
 *       I_j = Phi_j sum_i fraction_i albedo_i HG_i(cos theta_j), the VPL's intensity.
 * With surfaces (surface_gather.h; the photon walk continues through surfaces and records
 * surface VSLs, photon_trace.h): surface_direct by next-event estimation at the camera ray's
 * first surface hit; surface_from_volume from the VPLs, and surface_from_surface /
 * volume_from_surface from the surface VSLs used as point lights (R = 0), all with the same
 * clamping as the media VPLs.
 * Unbiased unless clamping is enabled: clamp_distance > 0 replaces 1/w^2 by
 * 1/max(w^2, clamp_distance^2) (biased, darker; removes the P2L singularity's fireflies). */
#ifndef VBL_TRANSPORT_VPL_H
#define VBL_TRANSPORT_VPL_H

#include "transport/common/estimator.h"

typedef struct vbl_vpl_settings {
    double clamp_distance; /* world units; 0: no clamping (default, unbiased) */
} vbl_vpl_settings;

#define VBL_VPL_SETTINGS_DEFAULT {0.0}

/* The settings of render options (vpl_clamp_distance); vbl_estimator_vpl uses these. */
void vbl_vpl_settings_from_options(const vbl_render_options* options, vbl_vpl_settings* out);

extern const vbl_estimator vbl_estimator_vpl;

/* The estimator's pieces with explicit settings (tests and benchmarks build variants). */
vbl_result vbl_vpl_pass_begin_with(const vbl_render_context* ctx, const vbl_vpl_settings* settings, void** store);
void vbl_vpl_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                           const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out);
void vbl_vpl_pass_end(const vbl_render_context* ctx, void* store);
/* The photon store of a pass's vpl store (benchmarks swap in other VPL sets; the store frees
 * whatever vpls array it holds at pass end with free()). */
struct vbl_photon_store* vbl_vpl_store_photons(void* store);
/* Its surface gather settings (benchmarks and tests compare variants). */
struct vbl_surface_gather_settings* vbl_vpl_store_gather(void* store);

#endif
