/* Glue between the virtual-light methods' camera samples and the surface transport kernels
 * (surface_from_volume.h, surface_vsl.h): the surface classes of one camera sample from one
 * photon store (photon_trace.h).
 *
 * At the camera ray's first surface hit x (re-intersected: wo = -camera direction, shading
 * normal n, material f), every term is multiplied by one estimate of the camera transmittance
 * T(o, x) (ctx->tracking over the media overlap):
 *   surface_direct        next-event estimation to EVERY light once (no light selection, no MIS:
 *                         unbiased for point/spot/distant and, by area sampling, quad and
 *                         environment lights): f(wo, wi) cos L_i T_shadow / pdf, shadow ray
 *                         from the spawn offset (surface occlusion + ctx->tracking), as pt's
 *                         surface NEE;
 *   surface_from_volume   VRLs: vbl_surface_from_vrl (VRL eq 6, unbiased) or, vrl_radius > 0,
 *                         vbl_surface_from_vbl (VBL eqs 8-9 with R_p); one sample per VRL with
 *                         M(v) = sigma_t(p) T_vrl(0, v) T(p, x) V(p, x), the result times the
 *                         sigma_t-weighted albedo at p (RGB sigma_s). VPLs (vpl): Phi I(theta)
 *                         f cos T V / max(w^2, c^2) (c = clamp_distance, 0: unbiased);
 *   surface_from_surface  surface VSLs: vsl_radius > 0: vbl_surface_from_surface (K_R, eq 11
 *                         radius), = 0: the VPL form Phi f_y cos_y f_x cos_x T V / max(w^2, c^2);
 *                         plus, when the store's caustics are active (photon_trace.h) and x is
 *                         not highly specular, the caustic photons within R_p
 *                         (vbl_caustic_gather, progressive photon mapping) INSTEAD of the highly
 *                         specular VSLs (the split of surface_caustics.h). A highly specular x
 *                         gathers every VSL as before and no caustics (the camera path is not
 *                         continued through the specular bounce);
 * and along the camera segment [u0, u1] in the media (u1 <= the hit distance):
 *   volume_from_surface   per surface VSL one vbl_volume_from_vsl sample (radius vsl_radius;
 *                         R = 0 with clamping as above), M(u) = sigma_t(x_u) T_c(u) T(x_u, y) V,
 *                         the result times the albedo at x_u; T_c from the camera cache.
 * T/V callbacks: vbl_ctx_transmittance (ratio tracking by default, 0 when a surface blocks);
 * segments leaving a VSL start at an offset of the surfaces' ray epsilon along the VSL's shading
 * normal (the side the segment leaves to). With one medium the kernels use its HG g (the VRL's
 * g, g_camera at camera points). With several media surface_from_volume and volume_from_surface
 * evaluate the true mixture sum_i w_i HG(g_i) of the media at the sampled point
 * (media/medium.h; the weights w_i replace the albedo) and the mean g only fits the samplers.
 * max_bounces M: surface_direct needs M != 0; VRLs of bounce k need k + 2 <= M, VPLs of bounce
 * b need b + 1 <= M (surface VSLs are stored only when they qualify, photon_trace.h). */
#ifndef VBL_TRANSPORT_SURFACE_GATHER_H
#define VBL_TRANSPORT_SURFACE_GATHER_H

#include "transport/common/estimator.h"
#include "transport/common/photon_trace.h"
#include "volume/transmittance_cache.h"

typedef struct vbl_surface_gather_settings {
    int vrls;              /* 1: surface_from_volume from the store's VRLs */
    double vrl_radius;     /* 0: VRL eq 6; > 0: VBL eqs 8-9 with this radius */
    int vpls;              /* 1: surface_from_volume from the store's VPLs */
    double vsl_radius;     /* surface VSLs: R_p; 0: the point (VPL) form */
    double clamp_distance; /* point forms: 1 / max(w^2, c^2); 0: no clamping (unbiased) */
    int kernel_samples;    /* cone-kernel directions per strategy when a radius is > 0 */
    double g_camera;       /* HG g at camera points (volume_from_surface) */
    /* Surface caustics (surface_caustics.h; fields added here are 0 in the callers' stores):
     * caustics VBL_SURFACE_CAUSTICS_GATHER (0) gathers the store's caustic photons into
     * surface_from_surface, VBL_SURFACE_CAUSTICS_SKIP leaves them out (tests: the VSL part alone);
     * caustic_radius > 0 overrides the store's R_p. */
    int caustics;
    double caustic_radius;
    /* Blue-noise surface VSLs (render.vsl_placement = blue_noise; docs/readme/blue_noise.md):
     * set by vbl_surface_gather_blue_noise_begin, NULL otherwise. */
    struct vbl_bn_prepared* blue_noise;
    int blue_noise_mode; /* 1: surface_from_surface from `blue_noise` (nothing when it is NULL) */
    int blue_noise_volume; /* blue_noise_mode: 1: volume_from_surface from `blue_noise` as well */
} vbl_surface_gather_settings;

/* Separates the blue-noise preparation's random streams: (seed ^ this, pass, 0). */
#define VBL_RNG_DOMAIN_BLUE_NOISE 0x424C55454E4F4953ull /* "BLUENOIS" */

#define VBL_SURFACE_CAUSTICS_GATHER 0
#define VBL_SURFACE_CAUSTICS_SKIP 1

#define VBL_SURFACE_KERNEL_SAMPLES_DEFAULT 8

/* The surface classes at the camera sample's first surface hit (nothing if t_max is infinite
 * or the scene has no surfaces). photons may be NULL (surface_direct only). */
void vbl_surface_gather_hit(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_photon_store* photons,
                            const vbl_surface_gather_settings* settings, const vbl_camera_sample* sample,
                            vbl_rng* rng, vbl_sample_value* out);

/* volume_from_surface over the camera segment [u0, u1] with T_c from `cache` (built by
 * vbl_camera_segment_cache_to), from the surface VSLs, or from the blue-noise lights when
 * settings->blue_noise_volume is set. Nothing without either. */
void vbl_surface_gather_segment(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_photon_store* photons,
                                const vbl_surface_gather_settings* settings, const vbl_camera_sample* sample,
                                const vbl_transmittance_cache* cache, double u0, double u1, vbl_rng* rng,
                                vbl_sample_value* out);

/* The per-pass hook of vpl/vrl/vbl (call at the end of pass_begin, after the photon store):
 * with options.vsl.placement == VBL_VSL_PLACEMENT_BLUE_NOISE and surfaces, prepares this pass's
 * blue-noise light set with vbl_bn_prepare (transport/surface/blue_noise/prepare.h), seeds drawn from
 * vbl_rng_make(seed ^ VBL_RNG_DOMAIN_BLUE_NOISE, pass, 0):
 *   N = vsl_lights (0: VBL_VSL_LIGHTS_DEFAULT) lights kept from 10 N camera candidates, 10 N
 *   light paths (through the media, if any) split with max_bounce = M - 2 (M = max_bounces;
 *   unlimited for M < 0), 16x16 profiles.
 * surface_from_surface at the camera's first surface hit x then comes from vbl_bn_gather (light
 * + BSDF sample, MIS, T(x, y) with media) plus, unless options.vsl.path_extension is OFF, the
 * path extension of eq 6 on the gather's BSDF sample: a pt path from x along it, weighted by
 * f cos / pdf (1 - w_v), of which the surface classes count (the light y reflects). In scenes
 * with media volume_from_surface comes from the same lights (blue_noise_volume: one
 * delta-tracking collision on the camera segment, shaded with the phase function in place of
 * the BSDF); the light-path surface VSLs are then not gathered. No caustic photons are gathered
 * (highly specular senders are part of the blue-noise lights' profiles). Otherwise (light paths,
 * no surfaces) it does nothing. */
vbl_result vbl_surface_gather_blue_noise_begin(const vbl_render_context* ctx, vbl_surface_gather_settings* gs);
void vbl_surface_gather_blue_noise_end(vbl_surface_gather_settings* gs);

/* Default R_0 of surface VSLs: sqrt(A / N) with A half the surface area of the surfaces'
 * bounding box (a plane's area for a flat scene) and N the surface VSLs of one pass (a point
 * then lies within R_0 of ~pi VSLs on a plane), clamped to [1e-3, 0.1] x the box diagonal
 * (0.01 x diagonal when N == 0). 0 without surfaces. */
double vbl_surface_vsl_default_r0(const vbl_scene* scene, size_t vsl_count);

#endif
