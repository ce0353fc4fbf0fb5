/* One virtual-light estimator for vpl, vrl and vbl (issue 13 item 1).
 *
 * The three methods share everything but the light-to-camera-segment kernel, and that shared part
 * lives here once (virtual_lights.c):
 *   pass begin   settings checks of the kernel, photon tracing into one store (photon_trace.h;
 *                photon_beams.h for vbl's beam single scattering), the light tree when
 *                select = K > 0 (vrl_tree.h), the surface gather settings and blue-noise VSLs
 *                (surface_gather.h), all freed by one pass end;
 *   per camera sample
 *     emission            quad/environment lights seen directly, and volume_emission: pt's estimator
 *                         (pt_camera_classes.h), the emissive media's surface_direct
 *                         (emission_estimate.h);
 *     volume_direct       pt's estimator (pt_camera_classes.h: pt's camera path with every other
 *                         class skipped, the same numbers as pt's layer), or vbl's bounce-0
 *                         photon beams (photon_beams.h);
 *     surface_*           the surface gathers at the first hit and along the camera segment
 *                         (surface_gather.h);
 *     volume_from_volume  one camera-ray transmittance cache (vbl_vl_camera_cache), then every
 *                         light of the pass through the kernel (with vrl's distance Russian
 *                         roulette, unbiased) or K lights drawn from the light tree, each
 *                         weighted 1 / (K pdf) (Yuksel 2019; Estevez and Kulla 2018);
 *     render.hybrid masks (vbl_ctx_wants) and stop checks (VBL_STOP_CHECK_EVERY) once, here.
 * The kernels (virtual_lights_kernel.h) are the per-light estimates:
 *   point (vpl.h)                  VRL paper eq 4, equiangular u toward the VPL;
 *   ray   (vrl.h)                  Novak et al. 2012 (VRL) eq 7 by the product pair sampler;
 *   beam  (virtual_beam_lights.h)  Novak et al. 2012 (VBL) eq 10 with the VSL cone kernel. */
#ifndef VBL_TRANSPORT_VIRTUAL_LIGHTS_H
#define VBL_TRANSPORT_VIRTUAL_LIGHTS_H

#include "transport/common/estimator.h"
#include "volume/transmittance_cache.h"

/* A per-method kernel (virtual_lights_kernel.h). */
typedef struct vbl_vl_kernel vbl_vl_kernel;
extern const vbl_vl_kernel vbl_vl_kernel_point; /* vpl.c: settings = vbl_vpl_settings */
extern const vbl_vl_kernel vbl_vl_kernel_ray;   /* vrl.c: settings = vbl_vrl_settings */
extern const vbl_vl_kernel vbl_vl_kernel_beam;  /* virtual_beam_lights.c: settings = vbl_beam_light_settings */

/* The estimator's pieces with a kernel and its explicit settings (the methods' estimators pass
 * their settings from render options; tests and benchmarks build variants). */
vbl_result vbl_vl_pass_begin(const vbl_render_context* ctx, const vbl_vl_kernel* kernel, const void* settings,
                             void** store);
/* vbl_estimator.camera_aovs of the family: pt's camera walk inside vbl_vl_camera_sample gives the
 * alpha and Z AOVs wherever it runs on every sample (pt_camera_classes.h). */
int vbl_vl_camera_aovs(const vbl_render_context* ctx, const void* store);

void vbl_vl_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                          const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out);
void vbl_vl_pass_end(const vbl_render_context* ctx, void* store);

/* The pass's photon store (tests; benchmarks swap in other VPL sets through the mutable one: the
 * store frees whatever vpls array it holds at pass end with free()). */
struct vbl_photon_store;
const struct vbl_photon_store* vbl_vl_photons(const void* store);
struct vbl_photon_store* vbl_vl_photons_mutable(void* store);
/* Its surface gather settings (benchmarks and tests compare variants). */
struct vbl_surface_gather_settings* vbl_vl_gather_settings(void* store);

/* The camera ray inside the media as the kernels gather along it: ray = (origin, direction,
 * [u0, u1]), the media overlap, and the cached transmittance T(u) on it. */
typedef struct vbl_vl_camera {
    vbl_segment ray;
    vbl_transmittance_cache cache;
} vbl_vl_camera;
/* The camera ray's media overlap [u0, u1] (first t_max units) and its cached transmittance as the
 * store builds it (ratio tracking with the store's roulette threshold; vrl.transmittance_rr).
 * 0: misses. */
int vbl_vl_camera_cache(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts, vbl_vec3 origin,
                        vbl_vec3 direction, double t_max, vbl_rng* rng, vbl_vl_camera* out);

/* Light-tree selection: distance floor as a fraction of the media's bounding radius, and the
 * camera transmittance below which the camera segment is not used for the importance. */
#define VBL_VRL_SELECT_FLOOR_REL 1e-3
#define VBL_VRL_SELECT_VISIBLE_CUT 1e-3
#define VBL_VRL_SELECT_DENSITY_POINTS 4 /* sigma_s samples along a piece for its tree mass */
#define VBL_VRL_SELECT_PIECE_REL 0.05   /* tree pieces at most this x the media's bounding radius */

struct vbl_vrl_tree;
/* The light tree of a pass's photon store as the estimator builds it (floor
 * VBL_VRL_SELECT_FLOOR_REL x the media's bounding radius, ctx->options.max_bounces). */
vbl_result vbl_vrl_select_tree_build(const vbl_render_context* ctx, const struct vbl_photon_store* photons,
                                     struct vbl_vrl_tree* tree);

/* One estimate of T along a + t dir, t in [0, len] (the segment connecting a virtual-light point
 * and a camera-ray point), clipped to the media; 1 outside them; 0 when a surface blocks it. */
double vbl_vrl_connect_transmittance(const vbl_render_context* ctx, const vbl_tracking_settings* settings,
                                     vbl_thread_state* ts, vbl_vec3 a, vbl_vec3 dir, double len, vbl_rng* rng);

/* Minimum distance between segments p0 + s a (s in [0, la]) and q0 + t b (t in [0, lb]), unit a, b. */
double vbl_segment_distance(vbl_vec3 p0, vbl_vec3 a, double la, vbl_vec3 q0, vbl_vec3 b, double lb);

#endif
