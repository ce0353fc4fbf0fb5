/* The estimator interface of the progressive driver (render/render.c).
 *
 * An estimator is a pure function of (scene, virtual-light store, camera sample, rng) that adds
 * radiance into the film by transport class. Per pass the driver:
 *   1. calls pass_begin(ctx, &store) once (single-threaded entry; it may run its own
 *      `#pragma omp parallel for num_threads(ctx->threads)`), e.g. to trace ctx->options.light_paths
 *      light paths into a virtual-light store. Light path i of pass p must draw its numbers from
 *      vbl_rng_make(ctx->options.seed ^ VBL_RNG_DOMAIN_LIGHT, p, i) so the store depends only on
 *      (scene, seed, pass), never on threads;
 *   2. for every pixel, in parallel over tiles, draws spp camera samples from the pixel's stream
 *      vbl_rng_make(seed, pass, pixel_index) and calls camera_sample(ctx, store, ts, sample, rng,
 *      out) for each; `out` is zeroed before the call and the estimator adds into out->L[class];
 *      the store is read-only here;
 *   3. calls pass_end(ctx, store) to free it.
 * Per-thread state (extinction cursor, estimator scratch) comes in `ts`. The driver computes the
 * alpha and Z AOVs itself, so estimators only produce radiance. */
#ifndef VBL_TRANSPORT_ESTIMATOR_H
#define VBL_TRANSPORT_ESTIMATOR_H

#include <math.h>

#include "core/rng.h"
#include "vbl/vbl_film.h"
#include "media/media_emission.h"
#include "media/medium.h"
#include "scene/scene.h"
#include "volume/transmittance.h"

/* Transport classes = film layers: vbl_transport_class (vbl/vbl_film.h, public). */

/* Class of light that scattered `scatter_events` times before reaching the camera. */
static inline vbl_transport_class vbl_class_for_scatter_events(int scatter_events)
{
    return scatter_events <= 0 ? VBL_CLASS_EMISSION
                               : (scatter_events == 1 ? VBL_CLASS_VOLUME_DIRECT : VBL_CLASS_VOLUME_FROM_VOLUME);
}

/* Keys that separate random streams of different purposes within one (seed, pass). */
#define VBL_RNG_DOMAIN_LIGHT 0x4C49474854504154ull /* light paths: (seed ^ this, pass, path) */

typedef struct vbl_render_context {
    const vbl_scene* scene;
    const vbl_extinction* extinction;
    vbl_render_options options;   /* validated; options.transmittance may be a cached kind; the
                                     vrl_* / vpl_* fields are the estimators' settings
                                     (vbl_vrl_settings_from_options, vbl_vpl_settings_from_options) */
    vbl_tracking_settings tracking; /* for single transmittance estimates (cached kinds mapped
                                       to their uncached counterparts) */
    uint32_t pass;                /* current pass, 0-based */
    int threads;                  /* threads the driver uses */
    double deadline;              /* omp_get_wtime() at which options.time_limit ends (0: none) */
    volatile int* stop_latch;     /* the driver's: set once vbl_render_stop_requested said 1, so a
                                     stop seen anywhere in a pass is seen by the driver too (NULL ok) */
    const struct vbl_pt_guide* pt_guide; /* pt.guided_rr: the radiance cache of the render's pre-pass
                                            (transport/path_tracing/pt_guide.h; NULL: plain RR) */
    const struct vbl_pt_light_focus* pt_light_focus; /* pt.light_focus: the lights inside the media,
                                            once per render (pt_light_focus.h; NULL: off) */
    unsigned skip_classes;        /* bit c (1u << vbl_transport_class): another estimator owns class c
                                     (render.hybrid, render/hybrid.h), so this one may skip work whose
                                     every class is skipped; what it adds there anyway the hybrid drops.
                                     0 (a memset context): every class */
    const struct vbl_hybrid_plan* hybrid; /* render.hybrid: the plan (render/hybrid.h), else NULL */
    const struct vbl_pixel_foci* pixel_foci; /* pixel_focus: the pixels holding a light's image
                                                (render/pixel_focus.h; NULL: none) */
    const struct vbl_light_guide* light_guide; /* vrl.light_guide: built once per render
                                                  (transport/common/photon_trace.h; NULL: off) */
    const struct vbl_sun_grid* sun_grids; /* pt.shadow_control: per light (scene->lights order), the
                                             transmittance grid towards a distant light (its T NULL
                                             for other lights; volume/sun_grid.h); NULL: off */
} vbl_render_context;

/* 1 if the estimator must compute class c (vbl_render_context.skip_classes). */
static inline int vbl_ctx_wants(const vbl_render_context* ctx, vbl_transport_class c)
{
    return !(ctx->skip_classes & (1u << (unsigned)c));
}

/* 1 once the render must stop: *options.cancel is non-zero or the time limit has passed (a context
 * zeroed by memset never stops). The long phases of pass_begin (light tracing, the light-path
 * store, the VRL tree, blue-noise VSLs, the beam BVH) check it between fixed-size chunks and then
 * return VBL_ERROR_INTERRUPTED; the driver drops that pass, so where a phase stopped never reaches
 * the film and every pass still depends only on (scene, seed, options, pass index). camera_sample
 * loops over every virtual light check it every VBL_STOP_CHECK_EVERY lights and return early:
 * the driver drops that pass too. */
#define VBL_STOP_CHECK_EVERY 256
int vbl_render_stop_requested(const vbl_render_context* ctx);

typedef struct vbl_thread_state {
    vbl_extinction_cursor cursor;
    vbl_emission_cursor emission; /* initialised only when scene->has_emission */
    void* scratch; /* estimator-owned, NULL unless the estimator manages it */
} vbl_thread_state;

typedef struct vbl_camera_sample {
    int px, py;              /* pixel, row 0 at the top */
    uint64_t pixel_index;    /* py * width + px */
    double sx, sy;           /* continuous raster position inside the pixel */
    uint32_t sample_index;   /* pass * spp + sample: the global index in the pixel's sequence (pt.sampler) */
    vbl_vec3 origin, direction; /* unit direction */
    double t_max;            /* distance to the first surface along the ray (INFINITY if none):
                                media transport along the camera ray stops there */
} vbl_camera_sample;

/* Completes cs from its raster position (sx, sy): the camera ray and t_max, the first surface
 * along it (INFINITY if none). Returns 1 when a surface is hit. */
static inline int vbl_camera_sample_ray(const vbl_scene* scene, vbl_camera_sample* cs)
{
    vbl_camera_ray(&scene->camera, cs->sx, cs->sy, &cs->origin, &cs->direction);
    cs->t_max = INFINITY;
    vbl_surface_hit hit;
    if (!scene->surfaces || !vbl_surfaces_intersect(scene->surfaces, cs->origin, cs->direction, 0.0, INFINITY, &hit))
        return 0;
    cs->t_max = hit.t;
    return 1;
}

/* The camera sample's AOVs, where its estimator supplies them (vbl_estimator.camera_aovs): alpha
 * (1 on an opaque surface, else an estimate of 1 - T of the camera ray) and Z (the first collision
 * of a delta-tracking flight along the ray, else the surface; depth_hit 0: neither). */
typedef struct vbl_sample_aovs {
    double alpha, depth;
    int depth_hit;
} vbl_sample_aovs;

typedef struct vbl_sample_value {
    vbl_vec3 L[VBL_CLASS_COUNT];
    vbl_sample_aovs aovs; /* read only where camera_aovs says the estimator fills it */
} vbl_sample_value;

typedef struct vbl_estimator {
    const char* name;
    /* 1 if camera samples of one pass are correlated (they share a light store): the variance
     * AOV then uses per-pass means as its independent units instead of single samples. */
    int correlated_samples;
    vbl_result (*pass_begin)(const vbl_render_context* ctx, void** store); /* may be NULL */
    void (*camera_sample)(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                          const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out);
    void (*pass_end)(const vbl_render_context* ctx, void* store); /* may be NULL */
    /* 1 if camera_sample fills out->aovs in this render (its own walk along the camera ray gives
     * them at no cost), so the driver does not track the ray again for them; NULL: never */
    int (*camera_aovs)(const vbl_render_context* ctx, const void* store);
} vbl_estimator;

/* The estimator of a method, or NULL if it is not built yet (render/estimators.c). */
const vbl_estimator* vbl_estimator_for(vbl_render_method method);

/* ---- shared medium queries over the scene's extinction field -------------------------- */

/* 1 if a scene surface blocks origin + t direction for t in (0, t_max) (t_max may be INFINITY).
 * The far end is pulled back by the surfaces' ray epsilon so that a segment ending on a surface
 * (a light on a wall, a surface vertex) is not blocked by that surface; a segment starting on a
 * surface must start from an offset origin (vbl_surface_spawn). No surfaces: 0, no Embree call. */
static inline int vbl_ctx_occluded(const vbl_render_context* ctx, vbl_vec3 origin, vbl_vec3 direction, double t_max)
{
    const vbl_surfaces* s = ctx->scene->surfaces;
    if (!s) return 0;
    double t_end = t_max;
    if (isfinite(t_max)) t_end = t_max - vbl_surfaces_ray_epsilon(s, vbl_v3_madd(origin, direction, t_max));
    return t_end > 0.0 && vbl_surfaces_occluded(s, origin, direction, 0.0, t_end);
}

/* Origin for a ray leaving surface point p (geometric normal ng facing the arriving ray) in
 * direction w: offset by the ray epsilon to the side w points to. */
static inline vbl_vec3 vbl_surface_spawn(const vbl_surfaces* s, vbl_vec3 p, vbl_vec3 ng, vbl_vec3 w)
{
    double eps = vbl_surfaces_ray_epsilon(s, p);
    return vbl_v3_madd(p, ng, vbl_v3_dot(ng, w) >= 0.0 ? eps : -eps);
}

/* Class of a contribution by the camera-visible vertex (1: surface, 0: medium) and the vertex
 * before it in the light's flow: -1 the light itself (*_direct), 1 a surface, 0 a medium. */
static inline vbl_transport_class vbl_class_for_vertices(int visible_is_surface, int previous)
{
    if (previous < 0) return visible_is_surface ? VBL_CLASS_SURFACE_DIRECT : VBL_CLASS_VOLUME_DIRECT;
    if (visible_is_surface) return previous ? VBL_CLASS_SURFACE_FROM_SURFACE : VBL_CLASS_SURFACE_FROM_VOLUME;
    return previous ? VBL_CLASS_VOLUME_FROM_SURFACE : VBL_CLASS_VOLUME_FROM_VOLUME;
}

/* One estimate of the media's T along origin + t direction for t in [0, t_max] (t_max may be
 * INFINITY), clipped to the media's bounds, with `tracking`; surfaces are not tested (t_max may be
 * a surface's own distance). */
static inline double vbl_ctx_media_transmittance(const vbl_render_context* ctx, vbl_thread_state* ts,
                                                 vbl_vec3 origin, vbl_vec3 direction, double t_max,
                                                 const vbl_tracking_settings* tracking, vbl_rng* rng)
{
    double t0, t1;
    if (ctx->extinction->count == 0 ||
        !vbl_extinction_ray_bounds(ctx->extinction, origin, direction, 0.0, t_max, &t0, &t1) || !(t1 > t0))
        return 1.0;
    return vbl_transmittance_estimate(ctx->extinction, &ts->cursor, origin, direction, t0, t1, tracking, rng);
}

/* vbl_ctx_media_transmittance with ctx->tracking, and 0 when a surface blocks the segment
 * (vbl_ctx_occluded). */
static inline double vbl_ctx_transmittance(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                           vbl_vec3 direction, double t_max, vbl_rng* rng)
{
    if (vbl_ctx_occluded(ctx, origin, direction, t_max)) return 0.0;
    return vbl_ctx_media_transmittance(ctx, ts, origin, direction, t_max, &ctx->tracking, rng);
}

/* Delta-tracking free flight from t = 0 up to t_max (may be INFINITY). Returns 1 with the
 * collision distance, sigma_t and per-component sigma_t (VBL_MAX_MEDIA entries), 0 if the ray
 * leaves the media (probability T(0, t_max)). */
static inline int vbl_ctx_free_flight(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                      vbl_vec3 direction, double t_max, vbl_rng* rng, double* t_collision,
                                      double* sigma_t, double* component_sigma_t)
{
    double t0, t1;
    if (ctx->extinction->count == 0 ||
        !vbl_extinction_ray_bounds(ctx->extinction, origin, direction, 0.0, t_max, &t0, &t1) || !(t1 > t0))
        return 0;
    return vbl_free_flight_sample(ctx->extinction, &ts->cursor, origin, direction, t0, t1,
                                  ctx->tracking.use_global_majorant, rng, t_collision, sigma_t, component_sigma_t);
}

/* vbl_ctx_free_flight with a visitor at every tentative collision (vbl_free_flight_sample_visit):
 * the same random numbers and collisions; the emission estimators of emissive scenes use it. */
static inline int vbl_ctx_free_flight_visit(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                            vbl_vec3 direction, double t_max, vbl_rng* rng, double* t_collision,
                                            double* sigma_t, double* component_sigma_t, vbl_tracking_visit visit,
                                            void* user)
{
    double t0, t1;
    if (ctx->extinction->count == 0 ||
        !vbl_extinction_ray_bounds(ctx->extinction, origin, direction, 0.0, t_max, &t0, &t1) || !(t1 > t0))
        return 0;
    return vbl_free_flight_sample_visit(ctx->extinction, &ts->cursor, origin, direction, t0, t1,
                                        ctx->tracking.use_global_majorant, rng, t_collision, sigma_t,
                                        component_sigma_t, visit, user);
}

/* vbl_ctx_free_flight_visit (visit may be NULL) whose first u_count uniforms come from u
 * (vbl_free_flight_sample_pattern: pt's low-discrepancy free-flight pair); u_count 0: the same
 * random numbers and collisions as vbl_ctx_free_flight(_visit). */
static inline int vbl_ctx_free_flight_pattern(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                              vbl_vec3 direction, double t_max, vbl_rng* rng, const double* u,
                                              double* t_collision, double* sigma_t,
                                              double* component_sigma_t, vbl_tracking_visit visit, void* user)
{
    double t0, t1;
    if (ctx->extinction->count == 0 ||
        !vbl_extinction_ray_bounds(ctx->extinction, origin, direction, 0.0, t_max, &t0, &t1) || !(t1 > t0))
        return 0;
    return vbl_free_flight_sample_pattern(ctx->extinction, &ts->cursor, origin, direction, t0, t1,
                                          ctx->tracking.use_global_majorant, rng, u, t_collision, sigma_t,
                                          component_sigma_t, visit, user);
}

/* vbl_ctx_free_flight on a segment from `ray`'s origin along its direction up to ray->t1 (may be
 * INFINITY; ray->t0 is ignored: the flight starts at 0, clipped to the media's bounds): returns 1
 * with the collision distance *t and the medium there (media/medium.h), 0 if the ray leaves the
 * media. The same random numbers and collisions as vbl_ctx_free_flight. */
static inline int vbl_ctx_free_flight_medium(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_segment* ray,
                                             vbl_rng* rng, double* t, vbl_medium_point* mp)
{
    double t0, t1;
    if (ctx->extinction->count == 0 ||
        !vbl_extinction_ray_bounds(ctx->extinction, ray->origin, ray->direction, 0.0, ray->t1, &t0, &t1) || !(t1 > t0))
        return 0;
    const vbl_segment clipped = vbl_segment_make(ray->origin, ray->direction, t0, t1);
    return vbl_medium_free_flight(ctx->scene, ctx->extinction, &ts->cursor, &clipped,
                                  ctx->tracking.use_global_majorant, rng, t, mp);
}

#endif
