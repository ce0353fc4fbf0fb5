/* Progressive photon beams (Jarosz et al. 2011a, section 7.3, eq. 38, beam x beam 1D, biweight
 * kernel; transport/photon_beams/photon_beam_kernel.h), the `beams` render method, and the single-scattering
 * option of the `vbl` method.
 *
 * Per pass: the same photon tracing as vrl/vbl (transport/common/photon_trace.h, light paths from
 * vbl_rng_make(seed ^ VBL_RNG_DOMAIN_LIGHT, pass, i)) stores short photon beams (segments that end
 * at the free-flight collision: T along a beam is accounted for by its random length, T_b = 1).
 * A beam of bounce k carries light that scattered k times; scattering once more at the camera ray
 * makes k + 1 events, so beams with k + 1 <= max_bounces are used (the trace is asked for one
 * bounce more than vrl, see photon_beams.c). Bounce 0 (straight from the light) is single
 * scattering and goes to volume_direct (volume caustics of refracted light would too, libvbl has
 * no refraction); bounce >= 1 goes to volume_from_volume.
 *
 * The beams of the pass go into a BVH (transport/photon_beams/beam_bvh.h; long beams split into pieces of about
 * unit aspect ratio, section 8.3) with query radius sqrt(2) R_p: the eq-38 kernel with the
 * parallel-case box (photon_beam_kernel.h) reaches at most sqrt(2) R from the beam line, so no
 * contributing piece is missed. Per camera sample, the camera ray's overlap with the media,
 * clipped at the first surface (sample->t_max), is one query; every piece found adds
 *     sigma_s f(cos) (x_c) Phi_b T_c(t_c) K_R(d) |U| / (2 R)      (eq 38; |U| / (2 R) = 1 / sin)
 * with the piece's own part U of the kernel's passage, so the pieces of one beam partition its
 * contribution exactly (no de-duplication, no allocation per query). T_c comes from one cached
 * ratio-tracking estimate per camera ray (as vrl.c; unbiased at every point; cached-delta when
 * options.transmittance asks for it), sigma_s f over the media components at x_c (mixtures exact).
 *
 * Width: R_p = vbl_radius_at_pass(R_0, alpha, 1, pass) (eq 11 with d = 1: the width itself shrinks
 * by (p + 1 + alpha) / (p + 2) per pass, the progressive photon beams rule for the 1D beam x beam
 * blur). Bias ~ R^2 falls like p^(2 (alpha - 1)) and the variance of the pass average like
 * p^(-alpha) (each pass's variance grows like 1 / R for a 1D kernel), so RMSE ~ p^max(2(alpha-1),
 * -alpha/2); the balance point is alpha = 4 / (4 + d) = 0.8 for d = 1, the default is 0.7 (the
 * paper's and vbl's value: RMSE slope -0.35 against -0.40, but a faster falling bias, which
 * dominates at the pass counts artists use). R_0 default: vbl_beams_default_radius over the
 * media's box and this pass's total beam length. */
#ifndef VBL_TRANSPORT_PHOTON_BEAMS_H
#define VBL_TRANSPORT_PHOTON_BEAMS_H

#include "transport/common/estimator.h"
#include "transport/common/photon_trace.h"

typedef struct vbl_photon_beams_settings {
    double radius0;       /* world units; <= 0: default from scene scale and beam density */
    double alpha;         /* (0, 1]: eq 11 with d = 1; 1: fixed width */
    int single_scattering;   /* 1: bounce-0 beams -> volume_direct */
    int multiple_scattering; /* 1: bounce >= 1 beams -> volume_from_volume */
} vbl_photon_beams_settings;

#define VBL_PHOTON_BEAMS_SETTINGS_DEFAULT {0.0, 0.7, 1, 1}

/* From render options: beams_radius0, beams_alpha (0: 0.7). */
void vbl_photon_beams_settings_from_options(const vbl_render_options* options, vbl_photon_beams_settings* out);

extern const vbl_estimator vbl_estimator_beams;

vbl_result vbl_photon_beams_pass_begin_with(const vbl_render_context* ctx, const vbl_photon_beams_settings* settings,
                                            void** store);
void vbl_photon_beams_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                                    const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out);
void vbl_photon_beams_pass_end(const vbl_render_context* ctx, void* store);
/* The width R_p of the store (world units; tests). */
double vbl_photon_beams_store_radius(const void* store);

/* ---- pieces shared with the vbl method ----------------------------------------------------- */

/* The photon tracing both methods use: vbl_photon_trace with max_bounces raised by one (M >= 0),
 * so VRLs with bounce k + 1 <= M are stored (photon beams); vbl skips those with k + 2 > M. */
vbl_result vbl_photon_beams_trace(const vbl_render_context* ctx, int long_vrls, vbl_photon_store* out);

/* R_0 = vbl_radius_default_r0 (k sqrt(V / L)) over the cube inscribed in the media's bounding
 * sphere and the total length L of the store's VRLs with bounce + extra <= max_bounces
 * (extra = 1: photon beams, 2: VRLs / VBLs), only bounce 0 if bounce0_only. 0 without media. */
double vbl_beams_default_radius(const vbl_scene* scene, const vbl_photon_store* photons, int max_bounces, int extra,
                                int bounce0_only);

/* A photon-beam gather over a photon store (bounce-0 and/or higher beams), built per pass. */
typedef struct vbl_photon_beam_gather vbl_photon_beam_gather;
vbl_result vbl_photon_beam_gather_build(const vbl_render_context* ctx, const vbl_photon_store* photons,
                                        double radius, int single_scattering, int multiple_scattering,
                                        vbl_photon_beam_gather** out);
void vbl_photon_beam_gather_free(vbl_photon_beam_gather* gather);
/* Adds the beams' radiance along the camera ray [0, t_max] into out->L[volume_direct /
 * volume_from_volume] (builds the camera ray's transmittance cache, vbl_camera_segment_cache_to). */
void vbl_photon_beam_gather_eval(const vbl_render_context* ctx, const vbl_photon_beam_gather* gather,
                                 vbl_thread_state* ts, vbl_vec3 origin, vbl_vec3 direction, double t_max, vbl_rng* rng,
                                 vbl_sample_value* out);
/* The same with a cache the caller built over the ray's media overlap [u0, u1] (vbl shares its). */
struct vbl_transmittance_cache;
void vbl_photon_beam_gather_eval_cached(const vbl_render_context* ctx, const vbl_photon_beam_gather* gather,
                                        vbl_thread_state* ts, const struct vbl_transmittance_cache* cache,
                                        vbl_vec3 origin, vbl_vec3 direction, double u0, double u1,
                                        vbl_sample_value* out);

#endif
