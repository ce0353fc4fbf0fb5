/* Virtual point lights in media (VRL paper eq. 4, integrated along the camera ray by eq. 2).
 *
 * The point kernel of the virtual-light estimator (virtual_lights.h: the pass, the camera-ray
 * cache, single scattering, the surface gathers and hybrid masks are shared there).
 * Per pass: photon tracing (photon_trace.h) stores the scattering vertices as VPLs. Per camera
 * sample, with [u0, u1] the camera ray's overlap with the media:
 *   emission        quad/environment lights seen directly, pt's estimator (pt_camera_classes.h);
 *   volume_direct   pt's estimator (pt_camera_classes.h);
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
#include "transport/virtual_lights/virtual_lights.h"

typedef struct vbl_vpl_settings {
    double clamp_distance; /* world units; 0: no clamping (default, unbiased) */
} vbl_vpl_settings;

#define VBL_VPL_SETTINGS_DEFAULT {0.0}

/* The settings of render options (vpl_clamp_distance); vbl_estimator_vpl uses these. */
void vbl_vpl_settings_from_options(const vbl_render_options* options, vbl_vpl_settings* out);

/* The estimator: vbl_vl_pass_begin(ctx, &vbl_vl_kernel_point, &settings, store),
 * vbl_vl_camera_sample and vbl_vl_pass_end (virtual_lights.h) with these settings. */
extern const vbl_estimator vbl_estimator_vpl;

#endif
