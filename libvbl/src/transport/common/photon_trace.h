/* Photon tracing for the virtual-light methods (vpl, vrl): random walks from the lights through
 * the media by delta tracking, recorded as virtual ray lights (path segments in the media) and
 * virtual point lights (scattering vertices).
 *
 * Path i of pass p draws from vbl_rng_make(seed ^ VBL_RNG_DOMAIN_LIGHT, p, i). A light is chosen
 * with probability proportional to vbl_light_power; its emission sample (light_emission.h) has
 * flux weight F, so the photon starts with power Phi_0 = F / (select_pdf * light_paths): summing
 * over the light_paths paths of a pass gives an unbiased estimate of the emitted flux.
 * Emissive media are one more source, selected by the bound on their power
 * (vbl_photon_source_add_media): the photon starts at an emitting point inside them, sampled by
 * sigma_a Le over the blocks of pt's emission light sampling, in a uniform direction
 * (light_emission.h); its walk is a light's walk from there, so its records carry fire light
 * that scattered k times exactly as a light's do (what scattered at most once at the camera
 * comes from vbl_camera_media_emission, emission_estimate.h). Scenes without emission draw the
 * same numbers as before.
 *
 * Walk: segment k (k = 0 straight from the light) runs from the light / vertex k into the media
 * (clipped to the media bounds along the ray). A delta-tracking free flight (density
 * sigma_t T) ends it at vertex k+1 or lets it escape. At a vertex the direction is resampled
 * from the sigma_s-weighted phase mixture and Phi_{k+1} = Phi_k * kernel / (sigma_t pdf)
 * (= Phi_k * albedo for a single medium). From vertex 2 on, Russian roulette with survival
 * q = min(1, max(Phi) / max(Phi_0)) (survivors divided by q, unbiased).
 *
 * Records (light carried by segment k has scattered k times; scattering once more on it and once
 * at the camera point makes k + 2 events, so the virtual lights only ever produce
 * volume_from_volume; single scattering is pt's estimator's job, pt_camera_classes.h):
 *   VRL k: origin = the segment's entry into the media, unit direction, power Phi_k and
 *          - short VRLs (default): length to the free-flight collision (or the media exit if the
 *            photon escaped). Transmittance along the VRL is then accounted for by the random
 *            length (P(collision beyond v) = T(v)), so estimators use T_vrl = 1;
 *          - long VRLs: length to the media exit along the ray, plus a cached transmittance
 *            (vbl_transmittance_cache over the segment, stored compactly) for T(v).
 *   VPL k (vertex k >= 1): position, incident travel direction, power Phi_{k-1} arriving, and
 *          the per-medium fractions sigma_t,i / sigma_t at the vertex, so that the VPL's
 *          intensity toward w is Phi * sum_i fraction_i albedo_i HG_i(cos) (= Phi kernel/sigma_t).
 * Surfaces (opaque, scene->surfaces): a segment ends at the first surface along it (VRLs end
 *          there, long VRLs too). The surface hit is a scattering vertex like a medium vertex:
 *          vertex k+1 of the walk, counted in max_bounces and in Russian roulette alike. There
 *          the photon (power Phi_k arriving from -d) is recorded as a surface VSL
 *          (surface_vsl.h: position, shading normal on the incident side, incident = -d,
 *          power Phi_k, material, bounce = k) when store_surface_vsls is set, and the
 *          walk continues by BRDF sampling: new direction w from vbl_material_sample, then
 *          Phi_{k+1} = Phi_k f(w, -d) cos(n, w) / pdf(w) (reflection only; w below the geometric
 *          normal ends the walk), from an origin offset off the surface (vbl_surface_spawn);
 *          Caustics (surface_caustics.h; vbl_caustic_settings mode AUTO, surface VSLs recorded and a
 *          highly specular material in the scene, else nothing changes, not even the random
 *          numbers): a hit that is not highly specular, reached straight from a highly specular
 *          surface vertex, also records a caustic photon (position, normal, incident, power Phi_k,
 *          bounce k) when k + 1 <= M; the walk then continues from highly specular vertices while
 *          vertex k + 1 <= M - 1 (one event more than elsewhere, so that max_bounces paths ending
 *          in a caustic are not lost); nothing else is stored from that extra segment.
 *          the next segment (and its VRL) starts there. A VSL of bounce k feeds light that
 *          scattered k + 2 times at the camera (VSL + camera vertex), so only VSLs with
 *          k + 2 <= M are stored. With surfaces the walk always continues through them (light
 *          reflected into the media belongs to volume_from_volume, as in pt) and photons are
 *          emitted towards the sphere bounding the media AND the surfaces (so surfaces outside
 *          the media receive photons); media-only scenes trace exactly as before (same random
 *          numbers, same records).
 * max_bounces M >= 0: only VRLs with k + 2 <= M, VPLs with k + 1 <= M and surface VSLs with
 * k + 2 <= M are stored, and walks
 * stop as soon as nothing more can be stored. */
#ifndef VBL_TRANSPORT_PHOTON_TRACE_H
#define VBL_TRANSPORT_PHOTON_TRACE_H

#include <stddef.h>

#include "transport/common/camera_importance.h"
#include "transport/common/estimator.h"
#include "transport/surface/surface_caustics.h"
#include "transport/surface/surface_vsl.h"

typedef struct vbl_vrl {
    vbl_vec3 origin, direction; /* direction unit */
    double length;
    vbl_vec3 power;             /* flux carried along the segment */
    double g;                   /* sigma_s-weighted HG g at its start (for the pair sampler) */
    int bounce;                 /* scattering events before this segment (0: from the light) */
    int cache_count;            /* long VRLs: entries in the store's cache pool */
    size_t cache_offset;
} vbl_vrl;

typedef struct vbl_vpl {
    vbl_vec3 position;
    vbl_vec3 incident;          /* unit travel direction of the arriving photon */
    vbl_vec3 power;             /* flux arriving at the vertex */
    double fraction[VBL_MAX_MEDIA]; /* sigma_t,i / sigma_t at the vertex */
    double g;                   /* sigma_s-weighted HG g at the vertex */
    int bounce;                 /* scattering events including this one (>= 1) */
} vbl_vpl;

typedef struct vbl_photon_settings {
    int store_vrls;
    int store_vpls;
    int long_vrls;              /* 1: VRLs run to the media exit with cached T (see above) */
    vbl_transmittance_estimator cache_kind; /* long VRLs: CACHED_DELTA or CACHED_RATIO */
    int cache_entries;          /* CACHED_DELTA distances per VRL */
} vbl_photon_settings;

/* Surface caustics (surface_caustics.h), with store_surface_vsls only. {0} (or NULL) = defaults. */
typedef struct vbl_caustic_settings {
    int mode;        /* VBL_CAUSTICS_AUTO (0): caustic photons when a material is highly specular;
                        VBL_CAUSTICS_OFF: never (the VSLs alone, exactly as before) */
    double radius0;  /* R_0 of the gather in world units; <= 0: vbl_caustic_default_r0 */
    double alpha;    /* eq 11 alpha in (0, 1]; <= 0: VBL_RADIUS_ALPHA_DEFAULT */
} vbl_caustic_settings;

#define VBL_CAUSTICS_AUTO 0
#define VBL_CAUSTICS_OFF 1

typedef struct vbl_photon_store {
    vbl_vrl* vrls;
    size_t vrl_count;
    vbl_vpl* vpls;
    size_t vpl_count;
    double* cache_pool;          /* long VRLs: (t, value) pairs */
    size_t cache_pool_count;     /* pairs */
    vbl_surface_vsl* surface_vsls; /* vbl_photon_trace_with_surfaces(.., 1, ..): photon hits on surfaces */
    vbl_vec3* surface_vsl_peaks; /* per VSL: vbl_material_max_direction(material, normal, incident) */
    size_t surface_vsl_count;
    /* Surface caustics: caustics_active = 1 when this trace applied the split of
     * surface_caustics.h (then highly specular VSLs are not gathered at non-specular receivers);
     * caustic_radius = R_p of this pass (eq 11); the map's cells are R_p wide. */
    int caustics_active;
    vbl_caustic_map caustics;
    double caustic_radius;
    size_t paths;                /* light paths traced */
} vbl_photon_store;

/* Traces ctx->options.light_paths paths for pass ctx->pass (OpenMP with ctx->threads; the result
 * does not depend on the thread count). */
vbl_result vbl_photon_trace(const vbl_render_context* ctx, const vbl_photon_settings* settings,
                            vbl_photon_store* out);
/* The same, also recording surface VSLs when store_surface_vsls is 1 (vbl_photon_trace: 0; the
 * walk through surfaces is the same either way, so the VRLs/VPLs do not depend on it). */
vbl_result vbl_photon_trace_with_surfaces(const vbl_render_context* ctx, const vbl_photon_settings* settings,
                                          int store_surface_vsls, vbl_photon_store* out);
/* The same with explicit caustic settings (vbl_photon_trace_with_surfaces: NULL = defaults, i.e.
 * caustics AUTO with the default R_0 and alpha). */
vbl_result vbl_photon_trace_with_caustics(const vbl_render_context* ctx, const vbl_photon_settings* settings,
                                          int store_surface_vsls, const vbl_caustic_settings* caustics,
                                          vbl_photon_store* out);
void vbl_photon_store_free(vbl_photon_store* store);

/* The store's surface VSLs as a read-only vbl_surface_vsl_store view over the scene's materials
 * (for the surface_vsl.h gathers; nothing is copied or owned). */
vbl_surface_vsl_store vbl_photon_store_surface_view(const vbl_photon_store* store, const vbl_scene* scene);

/* A VPL's radiant intensity towards the light-travel direction with cos = incident . omega:
 * Phi sum_i fraction_i albedo_i HG_i(cos). */
vbl_vec3 vbl_vpl_intensity(const vbl_scene* scene, const vbl_vpl* p, double cos_theta);

/* T(0, v) along a long VRL from its cache (1 for short VRLs): the cache's step function. */
double vbl_vrl_transmittance(const vbl_photon_store* store, const vbl_vrl* vrl, double v);

/* The camera ray's overlap [u0, u1] with the media and one cached transmittance estimate over
 * it (CACHED_DELTA when options.transmittance asks for it, else CACHED_RATIO), shared by all
 * virtual lights of the camera sample (unbiased: the cache is independent of their samples).
 * Returns 0 if the ray misses the media. */
struct vbl_transmittance_cache;
int vbl_camera_segment_cache(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin, vbl_vec3 direction,
                             vbl_rng* rng, struct vbl_transmittance_cache* cache, double* u0, double* u1);
/* The same over the ray's first t_max units (the first surface, vbl_camera_sample.t_max). */
int vbl_camera_segment_cache_to(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                vbl_vec3 direction, double t_max, vbl_rng* rng, struct vbl_transmittance_cache* cache,
                                double* u0, double* u1);

/* vrl.light_guide (methods vrl and vbl; camera_importance.h): light paths steered toward
 * camera-visible media by importance-driven Russian roulette and splitting (Vorba and Krivanek
 * 2016, sec. 4). At a medium vertex x (from vertex 1 on, in place of the roulette above) with
 * arriving power Phi, r = max(Phi) / Phi_0 (I(x) + floor) / ref:
 *   r < 1:  the walk survives with probability q, Phi / q, where
 *           vrl.light_guide = 1 (bounded): q = max(r, max(Phi) / Phi_0) (no walk ever carries more
 *           than Phi_0, the bound of the unguided roulette), no roulette when q >= 1;
 *           vrl.light_guide = 2 (window, Vorba and Krivanek's weight window): q = r;
 *   r >= 2: n = min(floor(r), VBL_LIGHT_GUIDE_SPLIT) copies (and at most VBL_LIGHT_GUIDE_COPIES
 *           made per root path), each of power Phi / n, each sampling its own direction; copy c
 *           of path i draws from vbl_rng_make(seed ^ VBL_RNG_DOMAIN_LIGHT_SPLIT, pass, i << 20 | c)
 *           (copies counted depth first), the last copy goes on with the path's own stream.
 * n and q are fixed before the copies' futures, so the estimate stays unbiased. Surface vertices
 * keep the roulette above. ref = the mean of I + floor over the vertices of
 * VBL_LIGHT_GUIDE_PILOT_PATHS unguided walks (fixed seed, once per render), so that the expected
 * number of vertices, and records, per pass is about unchanged; floor =
 * VBL_CAMERA_IMPORTANCE_FLOOR times the mean I. Everything is a function of the scene, the seed
 * and the pass: images are the same at any thread count and split/merge stays exact. */
#define VBL_LIGHT_GUIDE_SPLIT 8
#define VBL_LIGHT_GUIDE_COPIES 64
#define VBL_LIGHT_GUIDE_PILOT_PATHS 1024
#define VBL_RNG_DOMAIN_LIGHT_SPLIT 0x53504C4954434F50ull /* split copies of light paths */

typedef struct vbl_light_guide {
    vbl_camera_importance grid;
    double floor, ref; /* see above (ref > 0) */
} vbl_light_guide;

/* Builds the guide once per render (render.c, with vrl.light_guide and method vrl or vbl);
 * *out = NULL when the camera sees no medium the light reaches (the walks are then unguided). */
vbl_result vbl_light_guide_build(const vbl_render_context* ctx, vbl_light_guide** out);
void vbl_light_guide_free(vbl_light_guide* guide);

#endif
