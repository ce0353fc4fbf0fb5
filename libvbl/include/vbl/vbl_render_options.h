/* libvbl render options: ONE table (VBL_RENDER_OPTION_LIST below) from which come the struct
 * vbl_render_options, its defaults (VBL_RENDER_OPTIONS_DEFAULT, vbl_render_options_init), the
 * validator every front end uses (vbl_render_options_validate, vbl_render_option_set), the
 * scene file's `render` block, the `vbl render` flags and --help, the EXR options hash, the
 * documentation table (`vbl options --markdown`, docs/readme/options_table.md) and the Python
 * binding (through the reflection calls at the end of this header).
 *
 * Adding an option: docs/CONTRIBUTING.md, "Adding a render option". Included by vbl_render.h. */
#ifndef VBL_RENDER_OPTIONS_H
#define VBL_RENDER_OPTIONS_H

#include <math.h> /* INFINITY in the table */
#include <stddef.h>
#include <stdint.h>

#include "vbl/vbl_core.h"
#include "vbl/vbl_volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the modes (enum options) ---------------------------------------------------------- */

typedef enum vbl_render_method {
    VBL_RENDER_PT = 0,  /* volumetric path tracer (reference) */
    VBL_RENDER_VPL = 1, /* virtual point lights */
    VBL_RENDER_VRL = 2, /* virtual ray lights */
    VBL_RENDER_VBL = 3, /* virtual beam lights (media-to-media, progressive radius) */
    VBL_RENDER_BEAMS = 4 /* progressive photon beams (beam x beam 1D, progressive width) */
} vbl_render_method;

/* Multiple importance sampling heuristic of pt's light and phase samples (render.mis). */
typedef enum vbl_mis_heuristic {
    VBL_MIS_POWER = 0,   /* power heuristic, beta = 2 (default) */
    VBL_MIS_BALANCE = 1  /* balance heuristic */
} vbl_mis_heuristic;

/* vbl's volume_direct (render.vbl.single_scattering). */
typedef enum vbl_single_scattering {
    VBL_SINGLE_SCATTERING_DEFAULT = 0,     /* = equiangular */
    VBL_SINGLE_SCATTERING_EQUIANGULAR = 1,
    VBL_SINGLE_SCATTERING_BEAMS = 2        /* photon beams */
} vbl_single_scattering;

/* Surface VSLs for surface_from_surface of vpl/vrl/vbl (render.vsl_placement). */
typedef enum vbl_vsl_placement {
    VBL_VSL_PLACEMENT_LIGHT_PATHS = 0,
    VBL_VSL_PLACEMENT_BLUE_NOISE = 1
} vbl_vsl_placement;

/* blue_noise's adaptive camera path extension (render.vsl_path_extension). */
typedef enum vbl_vsl_path_extension {
    VBL_VSL_PATH_EXTENSION_DEFAULT = 0, /* = on */
    VBL_VSL_PATH_EXTENSION_ON = 1,
    VBL_VSL_PATH_EXTENSION_OFF = 2      /* virtual lights only (w_v = 1; biased near the lights, cheaper) */
} vbl_vsl_path_extension;

/* pt's random numbers for the pixel position, the light/direction sample dimensions and each
 * segment's free flight (render.pt.sampler, default sobol since session 8; method pt only: the pt
 * paths inside other methods use independent streams; docs/readme/render.md "Low-discrepancy
 * sampling"). */
typedef enum vbl_pt_sampler {
    VBL_PT_SAMPLER_INDEPENDENT = 0, /* independent PCG streams per (seed, pass, pixel) */
    VBL_PT_SAMPLER_SOBOL = 1        /* Owen-scrambled Sobol pairs per (seed, pixel), by global sample index */
} vbl_pt_sampler;

/* pt's NEE shadow-ray transmittance (render.pt.shadow_transmittance; docs/readme/sampling.md
 * "Shadow-ray transmittance"). */
typedef enum vbl_pt_shadow_transmittance {
    VBL_PT_SHADOW_DEFAULT = 0,      /* = unbiased-march-adaptive (session 6: docs/readme/sampling.md) */
    VBL_PT_SHADOW_RENDER = 1,       /* the render's `transmittance` estimator */
    VBL_PT_SHADOW_RESIDUAL_MID = 2, /* residual ratio tracking, control = the block mid-bound */
    VBL_PT_SHADOW_UNBIASED_MARCH = 3, /* unbiased ray marching (Kettunen et al. 2021) */
    /* the same, its cost following the need: a march's points stratified over the whole block, a
     * lower march density after the first scattering event (docs/readme/sampling.md) */
    VBL_PT_SHADOW_UNBIASED_MARCH_ADAPTIVE = 4
} vbl_pt_shadow_transmittance;

/* vrl's VRL-to-camera-ray transmittance (render.vrl.connect). */
typedef enum vbl_vrl_connect {
    VBL_VRL_CONNECT_RATIO = 0, /* ratio tracking (unbiased) */
    VBL_VRL_CONNECT_MARCH = 1  /* ray marching (biased) */
} vbl_vrl_connect;

/* vrl's (u, v) sampler of a VRL / camera-ray pair (render.vrl.pair_sampler). */
typedef enum vbl_vrl_pair_sampler {
    VBL_VRL_PAIR_PRODUCT = 0,      /* the product sampler (Novak et al. 2012 (VRL), section 4) */
    VBL_VRL_PAIR_CAMERA = 1,       /* MIS with u ~ Tc(u), v | u equiangular (sampling/vrl_camera_mis.h) */
    VBL_VRL_PAIR_TRANSMITTANCE = 2, /* MIS with u ~ Tc(u) / dist(u), v | u by the lobes (vrl_tc_pair.h) */
    VBL_VRL_PAIR_FREE_FLIGHT = 3    /* the same with u ~ sigma_t(u) Tc(u) / dist(u) (the cache's drops) */
} vbl_vrl_pair_sampler;

/* blue_noise: virtual lights per pass when render.vsl_lights is 0. */
#define VBL_VSL_LIGHTS_DEFAULT 1024
/* light_paths = 0: the method's default (vbl_render_options_light_paths). */
#define VBL_LIGHT_PATHS_DEFAULT 10000
/* vrl's default light paths per pass in scenes with surfaces (their gathers evaluate every virtual
 * light per surface hit, so a pass costs O(light paths) per pixel there). */
#define VBL_LIGHT_PATHS_DEFAULT_VRL 10
/* vbl's default light paths per pass in scenes with surfaces. */
#define VBL_LIGHT_PATHS_DEFAULT_VBL 10
/* vrl's and vbl's default light paths per pass in media-only scenes, where the light tree
 * (vrl.select) makes a camera sample O(K log N) (measured at equal CPU: docs/readme/vrl.md,
 * "Defaults"). */
#define VBL_LIGHT_PATHS_DEFAULT_VL_MEDIA_ONLY 1000
/* vrl.select's default: VRL pieces per camera sample from the light tree (docs/readme/vrl.md). */
#define VBL_VRL_SELECT_DEFAULT 8

/* Per-class combination of pt with a virtual-light method (render.hybrid; docs/readme/hybrid.md). */
typedef enum vbl_hybrid_mode {
    VBL_HYBRID_OFF = 0,     /* the method alone */
    VBL_HYBRID_CLASSES = 1, /* pt renders hybrid_pt_classes with hybrid_pt_spp samples, the method the rest */
    VBL_HYBRID_AUTO = 2     /* a deterministic pilot picks the classes and pt_spp (the default; with method pt,
                               or with light groups, it renders as off) */
} vbl_hybrid_mode;

/* Reported after every pass; return non-zero from the callback to stop after that pass. */
typedef struct vbl_render_progress {
    int pass;               /* passes completed so far (1 after the first) */
    int passes;             /* passes requested */
    double elapsed_seconds; /* since vbl_render started */
    double pass_seconds;    /* the pass just finished */
    uint64_t samples_per_pixel; /* camera samples per pixel so far */
    int first_pass;         /* options.first_pass: the absolute index of this render's first pass */
    const void* driver;     /* opaque: for vbl_render_snapshot inside the callback */
} vbl_render_progress;

/* The per-pass callback (options.callback, with options.callback_user_data): called by vbl_render
 * after every completed pass, between passes; non-zero stops the render after that pass. */
typedef int (*vbl_render_pass_callback)(const vbl_render_progress* progress, void* user_data);

/* ---- the table ------------------------------------------------------------------------- */

/* Column values of the table. */
typedef enum vbl_render_option_type {
    VBL_OPTION_INT = 0,
    VBL_OPTION_UINT64 = 1,
    VBL_OPTION_DOUBLE = 2, /* always finite */
    VBL_OPTION_BOOL = 3,   /* 0 / 1; text true|false (also on|off, 1|0) */
    VBL_OPTION_ENUM = 4    /* 0 .. n-1 named by `choices` ("pt|vpl|vrl|vbl|beams") */
} vbl_render_option_type;

/* What an option does to the pixels (and so how two renders' files may be merged). */
typedef enum vbl_render_option_effect {
    VBL_OPTION_EFFECT_NONE = 0,     /* never changes pixels (threads) */
    VBL_OPTION_EFFECT_PASSES = 1,   /* which passes run (passes, first_pass, time_limit): merged over */
    VBL_OPTION_EFFECT_IDENTITY = 2, /* changes pixels; an EXR attribute of its own (vbl:method, vbl:spp, ...) */
    VBL_OPTION_EFFECT_HASH = 3      /* changes pixels; part of vbl:options_hash */
} vbl_render_option_effect;

/* flags */
#define VBL_OPTION_MIN_OPEN 1u     /* range excludes min */
#define VBL_OPTION_MAX_OPEN 2u     /* range excludes max */
#define VBL_OPTION_ZERO_DEFAULT 4u /* the library also takes 0 = "the default named in help" (for callers
                                      older than the option's real default); scene files and the CLI do not */
#define VBL_OPTION_JSON_BOOL 8u    /* enum written as true / false in scene files (choices 1 / 2) */
#define VBL_OPTION_HASH_ALWAYS 16u /* in the options hash even at its default (options older than the
                                      table; newer ones enter the hash only when not at their default, so
                                      adding an option keeps old files mergeable) */

/* The table is one list per group: the common options, then one per method (or family), each
 * becoming a nested struct of vbl_render_options (options.vrl.samples, options.beams.radius0, ...).
 *
 * X(member prefix, name, member, c type, type, scene key under "render" (NULL: none), CLI flag (NULL:
 *   none), default, min, max, flags, choices (enum) or NULL, effect, help)
 *   - member prefix: empty for the common options, `group.` for a group's (`vrl.`): the field is
 *     options.<prefix><member> (options.passes, options.vrl.samples);
 *   - name: the option's stable name (reflection, vbl:options_hash, messages): "vrl_samples".
 * F(member prefix, member, c type, default): a struct field that is not an option (callbacks; `cancel`:
 *   may be NULL; once *cancel is non-zero the pass in progress stops (light tracing between blocks of
 *   64 paths, the beam BVH every 1024 nodes, the VRL light tree, the camera pass at its next pixel,
 *   every 16 samples and every 256 virtual lights) and is dropped, so the film holds only complete
 *   passes; vbl_render then returns VBL_ERROR_INTERRUPTED with the film of the passes done, NULL if
 *   none. time_limit stops a pass the same way, the first one included. While cancel or a time limit is set the driver keeps a copy
 *   of the accumulators of the last complete pass, 256 bytes per pixel).
 * The order in each list is its struct's (ABI): append new options at the end of their group's list. */
#define VBL_RENDER_OPTIONS_COMMON(X, F)                                                                      \
    X(, method, method, vbl_render_method, ENUM, "method", "--method", VBL_RENDER_PT, 0, 4, 0,               \
      "pt|vpl|vrl|vbl|beams", IDENTITY, "rendering method")                                                 \
    X(, passes, passes, int, INT, "passes", "--passes", 16, 1, 1e9, 0, NULL, PASSES,                         \
      "independent progressive passes")                                                                      \
    X(, spp, spp, int, INT, "spp", "--spp", 4, 1, 1e6, 0, NULL, IDENTITY, "camera samples per pixel per pass") \
    X(, light_paths, light_paths, int, INT, "light_paths", "--light-paths", 0, 0, 2e9, 0, NULL, IDENTITY,     \
      "light paths per pass (vpl, vrl, vbl, beams; 0: the method's default: vrl and vbl 1000 in media-only " \
      "scenes and 10 with surfaces, others 10000)")                                                         \
    X(, seed, seed, uint64_t, UINT64, "seed", "--seed", 0, 0, 18446744073709551615.0, 0, NULL, IDENTITY,    \
      "random seed (scene files: at most 2^53)")                                                             \
    X(, time_limit, time_limit, double, DOUBLE, "time_limit", "--time-limit", 0.0, 0, INFINITY, 0, NULL,     \
      PASSES,                                                                                                \
      "seconds: a pass running past it stops (in light tracing, builds or at a pixel) and is dropped; no pass done: no image (0: none)") \
    X(, threads, threads, int, INT, NULL, "--threads", 0, 0, 4096, 0, NULL, NONE, "worker threads (0: all cores)") \
    X(, max_bounces, max_bounces, int, INT, "max_bounces", "--max-bounces", -1, -1, 1e9, VBL_OPTION_HASH_ALWAYS, \
      NULL, HASH, "scattering events per path (-1: unlimited)")                                             \
    X(, transmittance, transmittance, vbl_transmittance_estimator, ENUM, "transmittance", "--transmittance", \
      VBL_TRANSMITTANCE_RATIO_TRACKING, 0, 5, VBL_OPTION_HASH_ALWAYS,                                        \
      "delta|ratio|residual|march|cached-delta|cached-ratio", HASH,                                          \
      "transmittance estimator of shadow rays and camera rays")                                              \
    X(, mis, mis, vbl_mis_heuristic, ENUM, "mis", "--mis", VBL_MIS_POWER, 0, 1, VBL_OPTION_HASH_ALWAYS,      \
      "power|balance", HASH, "multiple importance sampling heuristic")                                       \
    F(, callback, vbl_render_pass_callback, NULL)                                                            \
    F(, callback_user_data, void*, NULL)                                                                     \
    X(, first_pass, first_pass, int, INT, NULL, NULL, 0, 0, 2147483647.0, 0, NULL, PASSES,                   \
      "absolute index of the first pass (split rendering: vbl render --pass-range)")                        \
    X(, transmittance_majorant_scale, transmittance_majorant_scale, double, DOUBLE,                          \
      "transmittance_majorant_scale", "--transmittance-majorant-scale", 1.0, 1.0, 64.0, 0, NULL, HASH,       \
      "tracking of single transmittance estimates at k x the majorant (pt: camera-visible vertex only)")    \
    F(, cancel, const volatile int*, NULL)                                                                   \
    X(, transparent, transparent, int, BOOL, "transparent", "--transparent", 0, 0, 1, 0, NULL, HASH,        \
      "the beauty leaves out the background layer (environment and lights seen directly): a premultiplied " \
      "element over A; without it A = 1 wherever a background is rendered")                               \
    X(, light_groups, light_groups, int, BOOL, "light_groups", "--light-groups", 0, 0, 1, 0, NULL, HASH,    \
      "one beauty layer per light group (lights' \"group\"; untagged lights and emissive media: default); "   \
      "renders the groups one after another (time x groups)")                                               \
    X(, min_passes, min_passes, int, INT, "min_passes", "--min-passes", 0, 0, 1e9, 0, NULL, PASSES,         \
      "passes that complete even past time_limit (0: the limit holds for the first pass too)")          \
    X(, pixel_focus, pixel_focus, int, BOOL, "pixel_focus", "--pixel-focus", 1, 0, 1, 0, NULL, HASH,        \
      "the pixel holding the image of a point or spot light inside the media, and its neighbours within a "  \
      "pixel of the image, draw half their positions with density ~ 1/distance to the image, weighted by "   \
      "the mixture (single scattering there grows like 1/distance: infinite variance under uniform "         \
      "positions in the image's pixel, large in its neighbours; unbiased)")                                 \
    X(, motion_blur, motion_blur, int, BOOL, "motion_blur", "--motion-blur", 1, 0, 1, 0, NULL, HASH,        \
      "velocity motion blur over camera.shutter for media with a velocity grid (pt; 0: the frame's instant)") \
    X(, hybrid, hybrid, vbl_hybrid_mode, ENUM, "hybrid", "--hybrid", VBL_HYBRID_AUTO, 0, 2, 0, "off|classes|auto", \
      HASH, "vpl, vrl, vbl, beams: pt renders some transport classes, the method the others (classes: "      \
      "hybrid_pt_classes; auto, the default: a pilot picks them; pt and light groups ignore auto; "          \
      "docs/readme/hybrid.md)")                                                                              \
    X(, hybrid_pt_classes, hybrid_pt_classes, int, INT, "hybrid_pt_classes", "--hybrid-pt-classes", 0, 0, 255, 0, \
      NULL, HASH,                                                                                            \
      "hybrid = classes: the layers pt renders, comma-separated names (surface_direct,volume_from_volume) or " \
      "a bit mask (bit = vbl_transport_class)")                                                              \
    X(, hybrid_pt_spp, hybrid_pt_spp, int, INT, "hybrid_pt_spp", "--hybrid-pt-spp", 1, 1, 4096, 0, NULL, HASH, \
      "hybrid = classes: pt camera samples per virtual-light camera sample (auto sizes it by the pilot)")

/* pt: options.pt */
#define VBL_RENDER_OPTIONS_PT(X, F)                                                                          \
    X(pt., pt_equiangular, equiangular, int, BOOL, "pt.equiangular", "--pt-equiangular", 1, 0, 1, 0, NULL,   \
      HASH, "pt: equiangular NEE towards point/spot lights on every segment, MIS with the collision's NEE")   \
    X(pt., pt_sampler, sampler, vbl_pt_sampler, ENUM, "pt.sampler", "--pt-sampler", VBL_PT_SAMPLER_SOBOL,    \
      0, 1, 0, "independent|sobol", HASH,                                                                    \
      "pt: independent streams or Owen-scrambled Sobol pairs (pixel, light, direction, free flight)")       \
    X(pt., pt_shadow_transmittance, shadow_transmittance, vbl_pt_shadow_transmittance, ENUM,                 \
      "pt.shadow_transmittance", "--pt-shadow-transmittance", VBL_PT_SHADOW_DEFAULT, 0, 4, 0,                \
      "default|render|residual-mid|unbiased-march|unbiased-march-adaptive", HASH,                            \
      "pt: NEE shadow rays' transmittance: the `transmittance` estimator (render), residual ratio tracking "  \
      "with the majorant block's mid-bound as control (residual-mid), or unbiased ray marching "             \
      "(unbiased-march: stratified marched optical depths in a power series, may be negative; "              \
      "unbiased-march-adaptive: the same with block-wide strata and half the march density after the "    \
      "first scattering event; default = unbiased-march-adaptive)")                                         \
    X(pt., pt_equiangular_quads, equiangular_quads, int, BOOL, "pt.equiangular_quads",                      \
      "--pt-equiangular-quads", 1, 0, 1, 0, NULL, HASH,                                                      \
      "pt: quad lights join the equiangular NEE (a point on the quad, then equiangular towards it; MIS with " \
      "the collision's NEE and phase sampling)")                                                            \
    X(pt., pt_equiangular_camera_samples, equiangular_camera_samples, int, INT,                              \
      "pt.equiangular_camera_samples", "--pt-equiangular-camera-samples", 3, 1, 16, 0, NULL, HASH,           \
      "pt: equiangular NEE samples on the camera segment, stratified along it, each with the camera "       \
      "walk's transmittance (pt.camera_split); every other segment takes one")                             \
    X(pt., pt_guided_rr, guided_rr, int, BOOL, "pt.guided_rr", "--pt-guided-rr", 0, 0, 1, 0, NULL, HASH,      \
      "pt: adjoint-driven Russian roulette and splitting from a radiance cache of a deterministic pre-pass " \
      "(Vorba and Krivanek 2016; unbiased)")                                                                \
    X(pt., pt_guide_cells, guide_cells, int, INT, "pt.guide_cells", "--pt-guide-cells", 16, 1, 128, 0, NULL, \
      HASH, "pt.guided_rr: radiance cache cells per axis over the media's bounds")                          \
    X(pt., pt_guide_paths, guide_paths, int, INT, "pt.guide_paths", "--pt-guide-paths", 8, 1, 4096, 0, NULL, \
      HASH, "pt.guided_rr: pre-pass paths per radiance cache cell (and per 8x8 pixel block, twice as many)") \
    X(pt., pt_shadow_roulette, shadow_roulette, int, BOOL, "pt.shadow_roulette", "--pt-shadow-roulette", 1, 0, \
      1, 0, NULL, HASH,                                                                                      \
      "pt: Russian roulette on the NEE shadow rays of medium vertices after the first scattering event, "   \
      "survival 4 pi x phase value x throughput / the camera-visible vertex's throughput (at least 0.05; "  \
      "unbiased)")                                                                                            \
    X(pt., pt_shadow_control, shadow_control, int, BOOL, "pt.shadow_control", "--pt-shadow-control", 1, 0, 1, \
      0, NULL, HASH,                                                                                         \
      "pt: a transmittance grid towards each distant light, built once per render, as a control variate: "  \
      "the camera walk's single scattering sums it over the walk's points and the forced point's shadow "   \
      "ray estimates T - T_c; pt.shadow_roulette returns T_c where it stops a ray, survival 1/4 of its own, " \
      "at least 0.01 (unbiased)")                                                                            \
    X(pt., pt_shadow_control_flight, shadow_control_flight, int, BOOL, "pt.shadow_control_flight",            \
      "--pt-shadow-control-flight", 1, 0, 1, 0, NULL, HASH,                                                 \
      "pt.shadow_control at the vertices after the first scattering event: the control's single "          \
      "scattering summed over the free flight's tentative collisions (escaping flights too), the "         \
      "collision's shadow ray estimating T - T_c (media of constant albedo; unbiased)")                    \
    X(pt., pt_light_focus, light_focus, double, DOUBLE, "pt.light_focus", "--pt-light-focus", 0.25, 0, 0.5, \
      0, NULL, HASH,                                                                                         \
      "pt: share of scattered directions (at surfaces and at the first 4 medium events) drawn from cones "  \
      "about the point and spot lights inside the media (angle to the light uniform: density ~ 1/angle), " \
      "the rest by the BRDF or phase function, weighted by the mixture's density (rays passing near a "   \
      "light in smoke; 0: off; unbiased)")                                                                   \
    X(pt., pt_direct_strata, direct_strata, int, INT, "pt.direct_strata", "--pt-direct-strata", 1, 1, 64, 0,  \
      NULL, HASH,                                                                                            \
      "pt: camera rays' single scattering from distant (and, without pt.equiangular, point/spot) lights by " \
      "K distances stratified along the ray instead of the first collision's NEE (1: the collision)")     \
    X(pt., pt_surface_direct_rate, surface_direct_rate, double, DOUBLE, "pt.surface_direct_rate",           \
      "--pt-surface-direct-rate", 4.0, 1, 64, 0, NULL, HASH,                                                 \
      "pt: shadow rays from camera-visible surface points (surface_direct) estimate their transmittance "  \
      "at this many times the density (march points or tentative collisions; times "                      \
      "transmittance_majorant_scale)")    \
    X(pt., pt_camera_split, camera_split, int, BOOL, "pt.camera_split", "--pt-camera-split", 1, 0, 1, 0,     \
      NULL, HASH,                                                                                            \
      "pt: the camera segment's free flight split into a forced scattering point (resampled from a ratio-"   \
      "tracking walk at 8x the majorant) and the surface/background behind, weighted by the walk's "        \
      "transmittance; both traced (false: one delta-tracking free flight)")                                 \
    X(pt., pt_split_behind_march, split_behind_march, int, BOOL, "pt.split_behind_march",                     \
      "--pt-split-behind-march", 1, 0, 1, 0, NULL, HASH,                                                     \
      "pt.camera_split: weight the surface or background behind by its own transmittance estimate (pt's "   \
      "shadow-ray estimator at pt.surface_direct_rate x its density; false: the walk's ratio tracking)")     \
    X(pt., pt_split_paths, split_paths, int, INT, "pt.split_paths", "--pt-split-paths", 2, 1, 16, 0, NULL,    \
      HASH,                                                                                                  \
      "pt.camera_split: up to N forced scattering points per camera sample, stratified over the walk's "  \
      "weights, each continued by its own path (one camera walk serves them); the extra N - 1 in "          \
      "proportion to the medium's share W / (W + T behind) of what the camera sample sees")                \
    X(pt., pt_sobol_shadow_march, sobol_shadow_march, int, BOOL, "pt.sobol_shadow_march",                     \
      "--pt-sobol-shadow-march", 1, 0, 1, 0, NULL, HASH,                                                     \
      "pt.sampler = sobol: the shadow rays of camera-visible surfaces, and the camera split's estimate of "  \
      "the smoke in front of a surface, march their first two blocks' strata from Sobol numbers of the "   \
      "camera sample instead of jittering each (a pixel's nearly equal rays stratify each other; unbiased)")

/* vpl: options.vpl */
#define VBL_RENDER_OPTIONS_VPL(X, F)                                                                         \
    X(vpl., vpl_clamp_distance, clamp_distance, double, DOUBLE, "vpl.clamp_distance", "--vpl-clamp-distance", \
      0.0, 0, INFINITY, VBL_OPTION_HASH_ALWAYS, NULL, HASH,                                                  \
      "vpl: 1/w^2 -> 1/max(w^2, c^2) in world units (biased; 0: off)")

/* vrl (the VRL options also apply to vbl's VRLs): options.vrl */
#define VBL_RENDER_OPTIONS_VRL(X, F)                                                                         \
    X(vrl., vrl_samples, samples, int, INT, "vrl.samples", "--vrl-samples", 1, 1, 1e6,                       \
      VBL_OPTION_ZERO_DEFAULT | VBL_OPTION_HASH_ALWAYS, NULL, HASH,                                          \
      "vrl: (u, v) samples per VRL / camera-ray pair")                                                       \
    X(vrl., vrl_long, long_vrls, int, BOOL, "vrl.long", "--vrl-long", 0, 0, 1, VBL_OPTION_HASH_ALWAYS, NULL, \
      HASH, "vrl: long VRLs (to the media exit, cached transmittance)")                                      \
    X(vrl., vrl_connect_march, connect, vbl_vrl_connect, ENUM, "vrl.connect", "--vrl-connect",               \
      VBL_VRL_CONNECT_RATIO, 0, 1, VBL_OPTION_HASH_ALWAYS, "ratio|march", HASH,                              \
      "vrl: VRL-to-camera-ray transmittance by ratio tracking or ray marching (biased)")                     \
    X(vrl., vrl_march_step, march_step, double, DOUBLE, "vrl.march_step", "--vrl-march-step", 0.0, 0,        \
      INFINITY, VBL_OPTION_HASH_ALWAYS, NULL, HASH,                                                          \
      "vrl: march step in world units for connect = march (0: adaptive)")                                   \
    X(vrl., vrl_prune_radius, prune_radius, double, DOUBLE, "vrl.prune_radius", "--vrl-prune-radius", 0.0, 0, \
      INFINITY, VBL_OPTION_HASH_ALWAYS, NULL, HASH,                                                          \
      "vrl: Russian-roulette pruning radius, a fraction of the media's bounding radius (0: off)")           \
    X(vrl., vrl_prune_min_probability, prune_min_probability, double, DOUBLE, "vrl.prune_min_probability",   \
      "--vrl-prune-min-probability", 0.1, 0, 1,                                                              \
      VBL_OPTION_MIN_OPEN | VBL_OPTION_ZERO_DEFAULT | VBL_OPTION_HASH_ALWAYS, NULL, HASH,                    \
      "vrl: floor of the pruning survival probability")                                                      \
    X(vrl., vrl_select, select, int, INT, "vrl.select", "--vrl-select", VBL_VRL_SELECT_DEFAULT, 0, 1e6, 0,   \
      NULL, HASH,                                                                                            \
      "vrl, vbl: K VRL pieces per camera sample from a light tree, weighted 1 / (K pdf) (unbiased; 0: every " \
      "VRL)")                                                                                                \
    X(vrl., vrl_light_guide, light_guide, int, INT, "vrl.light_guide", "--vrl-light-guide", 0, 0, 2, 0, NULL,    \
      HASH, "vrl, vbl: light paths split / rouletted by camera importance: 0 off, 1 bounded, 2 window (unbiased)") \
    X(vrl., vrl_pair_sampler, pair_sampler, vbl_vrl_pair_sampler, ENUM, "vrl.pair_sampler", "--vrl-pair-sampler", \
      VBL_VRL_PAIR_PRODUCT, 0, 3, 0, "product|camera|transmittance|free_flight", HASH,                         \
      "vrl: (u, v) of a VRL / camera-ray pair by the product sampler, or MIS with u from the camera "          \
      "transmittance (camera), Tc x 1/distance (transmittance) or sigma_t Tc x 1/distance (free_flight) "      \
      "(unbiased)")

/* vbl (virtual beam lights): options.beam_lights */
#define VBL_RENDER_OPTIONS_BEAM_LIGHTS(X, F)                                                                 \
    X(beam_lights., vbl_radius0, radius0, double, DOUBLE, "vbl.radius0", "--vbl-radius0", 0.0, 0, INFINITY,  \
      VBL_OPTION_MIN_OPEN | VBL_OPTION_ZERO_DEFAULT | VBL_OPTION_HASH_ALWAYS, NULL, HASH,                    \
      "vbl: initial VSL radius in world units (default 0: from the scene's size and the VRL density)")      \
    X(beam_lights., vbl_alpha, alpha, double, DOUBLE, "vbl.alpha", "--vbl-alpha", 0.0, 0, 1,                 \
      VBL_OPTION_MIN_OPEN | VBL_OPTION_MAX_OPEN | VBL_OPTION_ZERO_DEFAULT | VBL_OPTION_HASH_ALWAYS, NULL,    \
      HASH, "vbl: radius reduction per pass (default 0: 0.7)")                                              \
    X(beam_lights., vbl_single_scattering, single_scattering, vbl_single_scattering, ENUM,                   \
      "vbl.single_scattering", "--vbl-single-scattering", VBL_SINGLE_SCATTERING_DEFAULT, 0, 2,               \
      VBL_OPTION_ZERO_DEFAULT | VBL_OPTION_HASH_ALWAYS, "default|equiangular|beams", HASH,                   \
      "vbl: volume_direct by equiangular sampling or photon beams (default: equiangular)")                 \
    X(beam_lights., vbl_radius_mfp, radius_mfp, double, DOUBLE, "vbl.radius_mfp", "--vbl-radius-mfp", 0.1, 0, \
      INFINITY, VBL_OPTION_MIN_OPEN, NULL, HASH,                                                         \
      "vbl: VSL radius cap in mean free paths at the VSL, R = min(R_world, f / sigma_t(x)), shrunk per pass " \
      "like R_world (1e30: world units only)")                                              \
    X(beam_lights., vbl_kernel_tolerance, kernel_tolerance, double, DOUBLE, "vbl.kernel_tolerance",          \
      "--vbl-kernel-tolerance", 0.01, 0, 1, 0, NULL, HASH,                                                   \
      "vbl: relative error bound of the thin-cone VSL kernel (the VRL kernel where R/w is small; 0: always " \
      "the cone quadrature)")

/* beams (progressive photon beams, also vbl's beam single scattering): options.beams */
#define VBL_RENDER_OPTIONS_BEAMS(X, F)                                                                       \
    X(beams., beams_radius0, radius0, double, DOUBLE, "beams.radius0", "--beams-radius0", 0.0, 0, INFINITY,  \
      VBL_OPTION_MIN_OPEN | VBL_OPTION_ZERO_DEFAULT | VBL_OPTION_HASH_ALWAYS, NULL, HASH,                    \
      "beams (and vbl with beam single scattering): initial beam half-width in world units "                 \
      "(default 0: from the scene and the beam density)")                                                    \
    X(beams., beams_alpha, alpha, double, DOUBLE, "beams.alpha", "--beams-alpha", 0.0, 0, 1,                 \
      VBL_OPTION_MIN_OPEN | VBL_OPTION_MAX_OPEN | VBL_OPTION_ZERO_DEFAULT | VBL_OPTION_HASH_ALWAYS, NULL,    \
      HASH, "beams: width reduction per pass (default 0: 0.7)")

/* Surface VSLs of vpl, vrl and vbl (surface_from_surface): options.vsl */
#define VBL_RENDER_OPTIONS_VSL(X, F)                                                                         \
    X(vsl., vsl_placement, placement, vbl_vsl_placement, ENUM, "vsl_placement", "--vsl-placement",           \
      VBL_VSL_PLACEMENT_LIGHT_PATHS, 0, 1, VBL_OPTION_HASH_ALWAYS, "light_paths|blue_noise", HASH,           \
      "vpl, vrl, vbl: surface VSLs for surface_from_surface from light paths or camera-driven blue noise")   \
    X(vsl., vsl_path_extension, path_extension, vbl_vsl_path_extension, ENUM, "vsl_path_extension",          \
      "--vsl-path-extension", VBL_VSL_PATH_EXTENSION_DEFAULT, 0, 2,                                           \
      VBL_OPTION_ZERO_DEFAULT | VBL_OPTION_JSON_BOOL | VBL_OPTION_HASH_ALWAYS, "default|on|off", HASH,       \
      "blue_noise: the adaptive camera path extension (default: on)")                                        \
    X(vsl., vsl_lights, lights, int, INT, "vsl_lights", "--vsl-lights", VBL_VSL_LIGHTS_DEFAULT, 1, 1e7,      \
      VBL_OPTION_ZERO_DEFAULT | VBL_OPTION_HASH_ALWAYS, NULL, HASH,                                          \
      "blue_noise: virtual lights per pass (from 10 N camera candidates, lit by 10 N light paths)")

/* Every option, in table order (descriptors, --help, the docs table): the groups in struct order. */
#define VBL_RENDER_OPTION_LIST(X, F)                                                                         \
    VBL_RENDER_OPTIONS_COMMON(X, F)                                                                          \
    VBL_RENDER_OPTIONS_PT(X, F)                                                                              \
    VBL_RENDER_OPTIONS_VPL(X, F)                                                                             \
    VBL_RENDER_OPTIONS_VRL(X, F)                                                                             \
    VBL_RENDER_OPTIONS_BEAM_LIGHTS(X, F)                                                                     \
    VBL_RENDER_OPTIONS_BEAMS(X, F)                                                                           \
    VBL_RENDER_OPTIONS_VSL(X, F)

/* ---- the structs, generated ------------------------------------------------------------ */

/* X-macro column picker (internal): one table row -> one struct field `ctype member;`. */
#define VBL_RENDER_OPTION_FIELD_(prefix, name, member, ctype, ...) ctype member;
/* X-macro column picker (internal): one plain (not reflected) row -> one struct field. */
#define VBL_RENDER_PLAIN_FIELD_(prefix, member, ctype, def) ctype member;
typedef struct vbl_pt_options {
    VBL_RENDER_OPTIONS_PT(VBL_RENDER_OPTION_FIELD_, VBL_RENDER_PLAIN_FIELD_)
} vbl_pt_options;
typedef struct vbl_vpl_options {
    VBL_RENDER_OPTIONS_VPL(VBL_RENDER_OPTION_FIELD_, VBL_RENDER_PLAIN_FIELD_)
} vbl_vpl_options;
typedef struct vbl_vrl_options {
    VBL_RENDER_OPTIONS_VRL(VBL_RENDER_OPTION_FIELD_, VBL_RENDER_PLAIN_FIELD_)
} vbl_vrl_options;
typedef struct vbl_beam_light_options {
    VBL_RENDER_OPTIONS_BEAM_LIGHTS(VBL_RENDER_OPTION_FIELD_, VBL_RENDER_PLAIN_FIELD_)
} vbl_beam_light_options;
typedef struct vbl_photon_beam_options {
    VBL_RENDER_OPTIONS_BEAMS(VBL_RENDER_OPTION_FIELD_, VBL_RENDER_PLAIN_FIELD_)
} vbl_photon_beam_options;
typedef struct vbl_vsl_options {
    VBL_RENDER_OPTIONS_VSL(VBL_RENDER_OPTION_FIELD_, VBL_RENDER_PLAIN_FIELD_)
} vbl_vsl_options;

/* Everything a render takes: the common options (one field per row of
 * VBL_RENDER_OPTIONS_COMMON) and one nested struct per method group, generated from the table
 * above. Start from VBL_RENDER_OPTIONS_DEFAULT or vbl_render_options_init. */
typedef struct vbl_render_options {
    size_t size; /* sizeof(vbl_render_options) */
    VBL_RENDER_OPTIONS_COMMON(VBL_RENDER_OPTION_FIELD_, VBL_RENDER_PLAIN_FIELD_)
    vbl_pt_options pt;                  /* method pt (VBL_RENDER_OPTIONS_PT) */
    vbl_vpl_options vpl;                /* method vpl (VBL_RENDER_OPTIONS_VPL) */
    vbl_vrl_options vrl;                /* method vrl, and vbl's VRLs (VBL_RENDER_OPTIONS_VRL) */
    vbl_beam_light_options beam_lights; /* method vbl */
    vbl_photon_beam_options beams;      /* method beams */
    vbl_vsl_options vsl;                /* surface VSLs of vpl/vrl/vbl (VBL_RENDER_OPTIONS_VSL) */
} vbl_render_options;

/* Designated initializer of the table's defaults:  vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT; */
#define VBL_RENDER_OPTION_INIT_(prefix, name, member, ctype, type, key, flag, def, ...) , .prefix member = (def)
/* X-macro column picker (internal): one plain row -> its designated initializer. */
#define VBL_RENDER_PLAIN_INIT_(prefix, member, ctype, def) , .prefix member = (def)
/* The defaults of every option (the table's default column), as an initializer. */
#define VBL_RENDER_OPTIONS_DEFAULT \
    {.size = sizeof(vbl_render_options) VBL_RENDER_OPTION_LIST(VBL_RENDER_OPTION_INIT_, VBL_RENDER_PLAIN_INIT_)}

/* The same defaults at run time (sets size). */
VBL_API void vbl_render_options_init(vbl_render_options* options);
/* The validator of vbl_render (every option in its range; size; first_pass + passes fits an int).
 * Failure: VBL_ERROR_INVALID_ARGUMENT, "vbl_render: vbl_alpha = 1 is outside (0, 1)". */
VBL_API vbl_result vbl_render_options_validate(const vbl_render_options* options);

/* ---- reflection (bindings, tools, docs) ------------------------------------------------ */

/* One row of the options table as data (vbl_render_option_desc): what bindings, the CLI and
 * the documentation generator read instead of mirroring the struct. */
typedef struct vbl_render_option_info {
    const char* name;      /* the option's name: "vbl_alpha" (the field options.beam_lights.alpha) */
    const char* key;       /* scene file key under "render": "vbl.alpha"; NULL: not in scene files */
    const char* flag;      /* `vbl render` flag: "--vbl-alpha"; NULL: none */
    vbl_render_option_type type; /* value type */
    const char* type_name; /* "int", "uint64", "double", "bool", "enum" */
    double default_value;  /* the default as a number (enum: its index) */
    double min, max;       /* range (enum: 0 .. choices - 1) */
    unsigned flags;        /* VBL_OPTION_* above */
    const char* choices;   /* enum: "pt|vpl|vrl|vbl|beams", else NULL */
    vbl_render_option_effect effect; /* what it does to the pixels (and to merging) */
    const char* help;      /* one-line help text (the CLI's --help and the docs table) */
} vbl_render_option_info;

/* Number of rows in the options table. */
VBL_API int vbl_render_option_count(void);
/* The index-th option (0 .. count - 1) in table order; NULL out of range. */
VBL_API const vbl_render_option_info* vbl_render_option_desc(int index);
/* Index of an option by field name ("vbl_alpha"), scene key ("vbl.alpha") or flag ("--vbl-alpha"); -1 if none. */
VBL_API int vbl_render_option_find(const char* name);
/* Sets an option from text: numbers as C literals, bools true|false|on|off|1|0, enums by name.
 * Accepts what the library accepts (the 0 of VBL_OPTION_ZERO_DEFAULT options too); failures
 * (VBL_ERROR_INVALID_ARGUMENT) name the option and the range and leave *options unchanged. */
VBL_API vbl_result vbl_render_option_set(vbl_render_options* options, const char* name, const char* value);
/* The same as scene files and `vbl render` flags take it: also refuses the 0 that stands for a default. */
VBL_API vbl_result vbl_render_option_set_strict(vbl_render_options* options, const char* name, const char* value);
/* Writes the option's value as text (what vbl_render_option_set takes back: doubles round-trip exactly)
 * into out[size]. VBL_ERROR_INVALID_ARGUMENT for unknown names or a too small buffer. */
VBL_API vbl_result vbl_render_option_get(const vbl_render_options* options, const char* name, char* out,
                                         size_t size);

/* "fnv1a64:<16 hex digits>" of the options whose effect is HASH (written as vbl:options_hash; two
 * renders' files merge only if their hashes agree). out[size >= 25]. */
VBL_API void vbl_render_options_hash(const vbl_render_options* options, char* out, size_t size);

/* The light paths per pass of these options without a scene: options->light_paths, or where that
 * is 0 the method's default for a scene with surfaces (VBL_LIGHT_PATHS_DEFAULT_VRL, _VBL for vrl and
 * vbl; VBL_LIGHT_PATHS_DEFAULT for the others). A render uses vbl_render_light_paths (vbl_render.h),
 * which also knows the media-only default. 0 for a NULL argument. */
VBL_API int vbl_render_options_light_paths(const vbl_render_options* options);

/* Heap options for bindings that do not mirror the struct: created with the defaults. */
VBL_API vbl_result vbl_render_options_create(vbl_render_options** out_options);
/* Frees options made by vbl_render_options_create (NULL is ignored). */
VBL_API void vbl_render_options_destroy(vbl_render_options* options);
/* Sets options->callback and its user_data (for bindings that cannot write function pointers). */
VBL_API void vbl_render_options_set_callback(vbl_render_options* options, vbl_render_pass_callback callback,
                                             void* user_data);

#ifdef __cplusplus
}
#endif

#endif /* VBL_RENDER_OPTIONS_H */
