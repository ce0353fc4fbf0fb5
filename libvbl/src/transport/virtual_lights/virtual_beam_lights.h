/* Virtual beam lights, media-to-media (Novak et al. 2012 (VBL), section 3.2, eq. 10), the beam
 * kernel of the virtual-light estimator (virtual_lights.h): the VRL
 * estimator (transport/virtual_lights/vrl.h) with every point of a VRL inflated into a volumetric VSL of radius
 * R_p, progressively shrunk per pass (eq 11, transport/common/radius_schedule.h, d = 2).
 *
 * Per camera sample:
 *   emission            quad/environment lights seen directly, pt's estimator (pt_camera_classes.h);
 *   volume_direct       pt's estimator (pt_camera_classes.h), as vrl, or the bounce-0 beams;
 *   volume_from_volume  for every VRL l of the pass (bounce k, k + 2 <= max_bounces), `samples`
 *                       pairs (u, v) from the two-stage sampler of section 3.2
 *                       (sampling/beam_light_pair.h), each contributing eq (10):
 *     Phi_l sum_ij sigma_s,i(u) sigma_s,j(v) K_R(x_c(u), g_i; x_l(v), g_j) T_c(u) T_l(v) T(u, v) / pdf(u, v)
 *                       with K_R the VSL kernel (vbl_vsl_kernel, `kernel_samples` directions per
 *                       strategy, random lattice jitter: an unbiased estimate of K_R) summed over
 *                       the media components i (camera point) and j (VSL), so mixtures of media
 *                       with different g are exact. K_R -> f f / w^2 as R -> 0: the VRL integrand.
 * Transmittances as in vrl.h: T_c from one cache per camera ray, T_l = 1 for short VRLs (the
 * VRL's cache for long ones), T(u, v) by one ctx->tracking estimate on the connecting segment.
 *
 * Radius: R_p = vbl_radius_at_pass(R_0, alpha, 2, pass). R_0 = settings.radius0 if > 0, else
 * vbl_radius_default_r0 over the media's box (the cube inscribed in the media's bounding sphere,
 * transport/common/light_emission.h) and the total length of THIS pass's VRLs (deterministic: the store
 * depends only on scene, seed and pass). Bias ~ R^2 falls like p^(alpha - 1), variance of the
 * pass average like p^(-alpha) (radius_schedule.h): both -> 0 with fixed memory per pass.
 * alpha = 1 (only through vbl_vl_pass_begin with explicit settings) keeps R fixed (tests).
 * Issue 13 item 4: the VSL at x has radius min(R_p, s_p radius_mfp / sigma_t(x)) (optical units,
 * s_p = R_p / R_0); the pair sampler uses min(R_p, s_p radius_mfp / majorant), below every VSL's
 * radius; R_p == 0 is the VRL limit (the VRL sampler and f f / w^2); the kernel is the thin-cone
 * midpoint wherever its error bound is below kernel_tolerance (sampling/beam_light_pair.h). */
#ifndef VBL_TRANSPORT_VBL_BEAMS_H
#define VBL_TRANSPORT_VBL_BEAMS_H

#include "transport/common/estimator.h"
#include "transport/virtual_lights/virtual_lights.h"

typedef struct vbl_beam_light_settings {
    double radius0;     /* world units; <= 0: default from scene scale and VRL density */
    double alpha;       /* (0, 1]: eq 11's reduction; 1: fixed radius */
    int samples;        /* (u, v) samples per VRL / camera-ray pair, >= 1 */
    int kernel_samples; /* directions per strategy of the VSL kernel, >= 1 */
    int long_vrls;      /* 1: VRLs to the media exit with cached transmittance */
    /* volume_direct: 0 pt's estimator (pt_camera_classes.h), 1 progressive photon
     * beams of bounce 0 from the same photon tracing (photon_beams.h; the trace then also keeps
     * the bounce-(M-1) segments the VBLs skip) with their own width schedule: */
    int beams_single_scattering;
    double beams_radius0; /* <= 0: default from the scene and the bounce-0 beams' length */
    double beams_alpha;   /* (0, 1]: eq 11 with d = 1 */
    int select;           /* > 0: K VRLs per camera sample from the light tree (vrl_tree.h, as vrl); 0: all */
    /* Optical radius (issue 13 item 4): the VSL at x has R_p(x) = s_p min(R_0, radius_mfp / sigma_t(x)),
     * s_p = R_p / R_0 of eq 11; <= 0: world units only (R_p). */
    double radius_mfp;
    /* Relative error bound of the thin-cone kernel (vbl_vsl_kernel_adaptive; beam_light_pair.h); pairs
     * whose every VSL is that thin take the VRL sampler; 0: always the cone quadrature. */
    double kernel_tolerance;
} vbl_beam_light_settings;

#define VBL_BEAM_LIGHT_KERNEL_SAMPLES_DEFAULT 16
/* The default fraction of the local mean free path (render option vbl_radius_mfp = 0) and the
 * default kernel tolerance (vbl_kernel_tolerance): measured in docs/readme/beams.md. */
#define VBL_BEAM_LIGHT_RADIUS_MFP_DEFAULT 0.1 /* = the vbl.radius_mfp row's default (measured: docs/readme/vrl.md) */
#define VBL_BEAM_LIGHT_KERNEL_TOLERANCE_DEFAULT 0.01
#define VBL_BEAM_LIGHT_SETTINGS_DEFAULT                                                                        \
    {0.0, 0.7, 1, VBL_BEAM_LIGHT_KERNEL_SAMPLES_DEFAULT, 0, 0, 0.0, 0.7, 0, VBL_BEAM_LIGHT_RADIUS_MFP_DEFAULT, \
     VBL_BEAM_LIGHT_KERNEL_TOLERANCE_DEFAULT}
/* What render options' vbl_single_scattering = 0 selects (measured on samples/cloud.json,
 * docs/readme/beams.md): 0 equiangular, 1 photon beams. */
#define VBL_BEAM_LIGHT_BEAMS_SINGLE_SCATTERING_DEFAULT 0

/* From render options: vbl_radius0, vbl_alpha (0: 0.7), vbl_radius_mfp (0: default), vbl_kernel_tolerance,
 * vrl_samples (0: 1), vrl_long,
 * vbl_single_scattering (0: VBL_BEAM_LIGHT_BEAMS_SINGLE_SCATTERING_DEFAULT, 1: equiangular, 2: beams),
 * beams_radius0, beams_alpha (0: 0.7). */
void vbl_beam_light_settings_from_options(const vbl_render_options* options, vbl_beam_light_settings* out);

/* The estimator: vbl_vl_pass_begin(ctx, &vbl_vl_kernel_beam, &settings, store),
 * vbl_vl_camera_sample and vbl_vl_pass_end (virtual_lights.h) with these settings; the photon
 * store: vbl_vl_photons. */
extern const vbl_estimator vbl_estimator_vbl;

#endif
