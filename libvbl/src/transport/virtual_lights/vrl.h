/* Virtual ray lights (Novak et al. 2012 (VRL), section 3), the ray kernel of the virtual-light
 * estimator (virtual_lights.h owns the pass, the camera-ray cache, single scattering, the surface
 * gathers, the light tree and hybrid masks): media-to-media transport from
 * photon path segments to whole camera rays, eq. (7):
 *   L = Phi int_u0^u1 int_0^len sigma_s(u) sigma_s(v) f(theta_u) f(theta_v) T_c(u) T_l(v) T(w)
 *                                  / w(u,v)^2 dv du
 * per VRL, estimated with the two-stage product importance sampling of section 4
 * (sampling/vrl_pair.h: v from the sinh marginal of eqs. 10-13, u given v by the
 * piecewise-linear fit of the two HG lobes, appendix A; analytic Cauchy for isotropic media).
 *
 * Per camera sample:
 *   emission            quad/environment lights seen directly, pt's estimator (pt_camera_classes.h);
 *   volume_direct       pt's estimator (pt_camera_classes.h);
 *   volume_from_volume  the sum over VRLs of the estimate above (a VRL of bounce k yields light
 *                       that scattered k + 2 times; only VRLs with k + 2 <= max_bounces count);
 * and with surfaces (surface_gather.h; the photon walk continues through surfaces and records
 * surface VSLs, photon_trace.h):
 *   surface_direct      next-event estimation at the camera ray's first surface hit;
 *   surface_from_volume every VRL by VRL eq 6 (one product-sampled point per VRL, unbiased);
 *   surface_from_surface, volume_from_surface
 *                       the surface VSLs with radius R_p = vbl_radius_at_pass(R_0, alpha, 2, p)
 *                       (VBL section 3.3-3.4, eq 11; R_0 = surface_radius0 or
 *                       vbl_surface_vsl_default_r0), consistent as R_p -> 0.
 * Transmittances: T_c from one cache per camera ray (vbl_camera_segment_cache), T_l = 1 for short
 * VRLs (the random segment length accounts for it) or the VRL's own cache for long VRLs, T(w)
 * along the connecting segment by one ctx->tracking estimate (ratio tracking by default,
 * unbiased) or, opt-in, ray marching (biased, cheaper, as the paper suggests).
 *
 * Russian-roulette pruning (rr_radius > 0): with h the minimum distance between the camera
 * segment and the VRL segment and R = rr_radius * (radius of the media's bounding sphere), a VRL
 * is kept with probability q = clamp(R / h, rr_min_probability, 1) and its estimate divided by q,
 * so pruning is unbiased; the floor bounds the added variance (the estimate grows at most by
 * 1 / rr_min_probability).
 *
 * Light selection (select = K > 0): instead of every VRL, each camera sample draws K VRLs from a
 * light tree over the pass's VRLs by stochastic traversal (vrl_tree.h; Yuksel 2019, Estevez and
 * Kulla 2018) and weights each estimate by 1 / (K pdf): unbiased, O(K log N) per camera sample
 * instead of O(N), so a pass can afford many more light paths.
 *
 * Opt-in, settings only (issue 13, second round; measured not to win, docs/readme/vrl.md):
 * camera_mis = 1 draws each (u, v) by one-sample MIS of the product sampler and a technique that
 * follows the camera ray's cached transmittance (sampling/vrl_camera_mis.h), and
 * transmittance_rr sets the ratio-tracking roulette threshold of the camera cache and the
 * connections (0.1 = the renderer's default). Both unbiased. */
#ifndef VBL_TRANSPORT_VRL_H
#define VBL_TRANSPORT_VRL_H

#include "transport/common/estimator.h"
#include "transport/virtual_lights/virtual_lights.h"
#include "volume/transmittance_cache.h"

typedef struct vbl_vrl_settings {
    int samples;               /* (u, v) samples per VRL / camera-ray pair, >= 1 */
    int long_vrls;             /* 1: VRLs to the media exit with cached transmittance */
    int connect_marching;      /* 1: ray marching on the connecting segment (biased) */
    double march_step;         /* ray marching step in world units; <= 0: adaptive */
    double rr_radius;          /* pruning radius as a fraction of the media's bounding radius; 0: off */
    double rr_min_probability; /* floor of the survival probability, in (0, 1] */
    double surface_radius0;    /* surface VSL R_0 in world units; <= 0: vbl_surface_vsl_default_r0 */
    double surface_alpha;      /* eq 11 alpha of the surface VSL radius, (0, 1]; 0: 0.7 */
    int select;                /* > 0: K VRLs drawn per camera sample from the light tree
                                  (vrl_tree.h, unbiased; rr_radius is then unused); 0: every VRL */
    int camera_mis;            /* vbl_vrl_pair_sampler (vrl.pair_sampler): 1: (u, v) by MIS of the
                                  product sampler and a camera-transmittance sampler
                                  (sampling/vrl_camera_mis.h); 2: MIS with u ~ Tc(u) / dist(u)
                                  (sampling/vrl_tc_pair.h); 0: product sampler only */
    double transmittance_rr;   /* Russian-roulette threshold of the ratio-tracked camera cache and
                                  connections, (0, 1]; 0.1 = the renderer's default (and this one's) */
} vbl_vrl_settings;

/* Defaults: the product sampler alone and the renderer's roulette threshold 0.1 (the images of
 * before); camera_mis = 1 with transmittance_rr = 0.01 is the opt-in variant of issue 13's second
 * round (measured in docs/readme/vrl.md: it does not win yet). */
#define VBL_VRL_SETTINGS_DEFAULT {1, 0, 0, 0.0, 0.0, 0.1, 0.0, 0.0, 0, 0, 0.1}

struct vbl_step_pdf;
/* The camera ray's cached transmittance on [u0, u1] as a step density (the u density of the
 * camera technique, vrl_camera_mis.h). Returns 0 if it has no usable mass. */
int vbl_vrl_camera_step_pdf(const struct vbl_transmittance_cache* cache, double u0, double u1,
                            struct vbl_step_pdf* out);

/* The settings of render options (vrl_* fields; zeros in samples / min probability mean the
 * defaults). The estimator vbl_estimator_vrl uses these. */
void vbl_vrl_settings_from_options(const vbl_render_options* options, vbl_vrl_settings* out);

extern const vbl_estimator vbl_estimator_vrl;

/* The estimator is vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &settings, store),
 * vbl_vl_camera_sample and vbl_vl_pass_end (virtual_lights.h) with these settings; the photon
 * store: vbl_vl_photons. */

/* Diagnostics (bench/bench_vrl_profile.c): each VRL's volume_from_volume estimate (sum of R, G,
 * B) for one camera sample into contribution[0 .. vrl_count-1] (0 for VRLs that cannot
 * contribute), and the fraction of the camera ray's media overlap before its cached
 * transmittance falls below VBL_VRL_SELECT_VISIBLE_CUT; pdf (may be NULL; the store must have
 * select > 0): each VRL's light-tree selection probability for this ray. Returns 0 if the ray
 * misses the media. */
int vbl_vrl_contributions(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                          const vbl_camera_sample* sample, vbl_rng* rng, double* contribution, double* visible,
                          double* pdf);

/* Diagnostics (bench/bench_vrl_tail.c): the factors of one pair-sampler draw of eq 7 for VRL
 * `vrl` of the store (whole VRL) and the camera segment with its cache (vbl_vl_camera_cache): the estimate is
 * f Tc Tl Tw / (w2 pdf) with f = sum RGB of the two scattering kernels times the power;
 * phase_geometry = the sampler's target (vrl_pair.h); tw_march / tc_march: ray-marched
 * (near-exact) transmittances of the connection and of the camera ray to u. Returns 0 when the
 * draw failed (no support). */
typedef struct vbl_vrl_factors {
    double pdf, w2, phase_geometry, tc, tl, tw, tw_march, tc_march, sigma_u, sigma_v, f, power;
} vbl_vrl_factors;
int vbl_vrl_sample_factors(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts, size_t vrl,
                           const vbl_vl_camera* camera, vbl_rng* rng, vbl_vrl_factors* out);

#endif
