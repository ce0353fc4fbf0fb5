/* Issue-8 experiment: camera-driven blue-noise placement of the MEDIUM virtual lights that feed
 * volume_from_volume, against the classic light-path VPLs of the vpl method (transport/virtual_lights/vpl.h).
 *
 *   build/bench/bench_bn_media [--scenes cloud,smoky_room] [--res 96x72] [--threads 2]
 *       [--lights 100,300,1000] [--passes 16] [--budget 30] [--max-seconds 240]
 *       [--candidates 10] [--split-paths 10] [--alpha 2] [--neighbors 32] [--surface-paths 100]
 *       [--seed 1000003]
 *       [--reference-seconds 240] [--vdb build/samples/cloud.vdb] [--csv FILE]
 *       [--source-dir SRC] [--cache-dir BUILD/bench] (defaults compiled in)
 *
 * Both placements render through the SAME estimator (vbl_vl_camera_sample: equiangular gather
 * of point lights along the camera ray); only the set of medium VPLs of a pass differs:
 *   light_paths  the classic VPLs: vpl's own photon trace with L light paths per pass, L chosen
 *                so that a pass holds about N medium VPLs (L measured per scene, counts printed);
 *   camera       N camera-driven lights (Li et al. 2022, carried into media):
 *                3.1  M = candidates x N camera sub-paths: a camera ray through a random raster
 *                     position, a delta-tracking free flight to x1, an HG direction, a second
 *                     free flight to y = the candidate (the analogue of the secondary hit);
 *                3.2  weighted sample elimination to N (transport/surface/blue_noise/sample_elimination.h) with the
 *                     3D analogue of eq 2: d_i = distance to the m-th neighbour,
 *                     V_i = 4/3 pi d_i^3, r_i = cbrt(M V_i / (4 sqrt(2) N m)) (densest sphere
 *                     packing instead of the hexagonal disk packing); light radius R = alpha r;
 *                     elimination leaf boxes of 1024 (one parallel level at M = 10^4);
 *                3.3  photon splitting in 3D: K = split-paths x N light paths are traced (the
 *                     same photon trace, another seed) and each medium collision's power is split
 *                     among the lights whose sphere contains it with weights 1 - (d/R)^2
 *                     normalised to a partition of unity. A light's incident field is the list
 *                     of its split contributions (power, incident direction); it is handed to
 *                     the gather as ONE vbl_vpl per light, the contribution k picked with
 *                     probability p_k proportional to its luminance and power / p_k (an unbiased
 *                     one-sample estimate of the field's emission sum_k Phi_k HG(inc_k . w),
 *                     so the gather costs the same per light as for a classic VPL).
 * Scenes with surfaces: the surface VSLs come from the vpl store's own --surface-paths light
 * paths (100, the vpl setting of bench_curves) in both placements (same seeds), and the classic
 * VPLs from their own L paths, so N is the only variable; the surface layers differ only through
 * the medium VPLs (surface_from_volume gathers them too: "sfv" below).
 * The camera-driven emission is a density estimate: a light radiates the in-scattered power of
 * its sphere from its centre (blur by R) and collisions outside every sphere are lost (printed
 * as "lost"); this bias shows in the energy ratio and in the block rMAE below.
 *
 * Error: rMAE = sum |I - Iref| / sum |Iref| over the pixels and RGB of one layer against a long
 * pt reference cached in the format of bench_curves (BUILD/bench/bench_curves_ref_<scene>_<W>x<H>
 * .raw/.txt: a cached reference of the same scene and resolution is reused, whatever its VDB path
 * and length; else one is rendered with --reference-seconds). "blocks" = rMAE of 8 x 8 pixel
 * block means, which averages most of the noise away and leaves the systematic error (bias).
 * Each configuration is ONE progressive render with a snapshot per pass; it runs until it has
 * both --passes passes (equal-count table, read at that pass) and --budget seconds (equal-time
 * table, read at the last pass within the budget), capped at --max-seconds. Deterministic seeds:
 * both placements of one N use the same seed. Timings are printed, never asserted. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "transport/surface/blue_noise/kd_tree.h"
#include "transport/surface/blue_noise/sample_elimination.h"
#include "geometry/surfaces.h"
#include "render/render_internal.h"
#include "media/media.h"
#include "scene/scene.h"
#include "transport/common/estimator.h"
#include "transport/common/photon_trace.h"
#include "transport/virtual_lights/vpl.h"
#include "bench_reference.h"
#include "vbl/vbl.h"

/* random streams of the camera-driven lights: (seed ^ domain, pass, index) */
#define DOMAIN_CAMERA_PATHS 0x424E4D43414D5031ull
#define DOMAIN_SPLIT_PATHS 0x424E4D53504C5432ull
#define DOMAIN_RESERVOIR 0x424E4D5245535633ull
#define DOMAIN_CLASSIC_PATHS 0x424E4D434C535334ull

/* ======================================================================================== */
/* ---- the two placements of the medium VPLs --------------------------------------------- */

typedef enum placement_kind { PLACEMENT_LIGHT_PATHS = 0, PLACEMENT_CAMERA = 1 } placement_kind;

typedef struct placement_config {
    placement_kind kind;
    size_t lights;           /* N: camera-driven lights per pass */
    int light_paths;         /* L: light paths of the classic VPLs */
    int surface_light_paths; /* scenes with surfaces: light paths of the surface VSLs (both placements) */
    double candidate_factor; /* M = candidate_factor N camera sub-paths */
    double split_factor;     /* K = split_factor N light paths split per pass */
    double alpha;            /* light radius = alpha r_max */
    size_t neighbors;        /* m of the local density (3D eq 2) */
} placement_config;

typedef struct placement_stats {
    int passes;
    double vpls;          /* sums over passes */
    double candidates;
    double lost;          /* fraction of the split power outside every light */
    double radius;        /* mean light radius */
    double build_seconds; /* camera-driven placement + splitting */
    double phase_seconds[4]; /* of which: candidates, r_max + elimination, split trace, splitting */
} placement_stats;

/* The estimator has no user pointer: the bench sets these before each (single) render. */
static placement_config g_config;
static placement_stats g_stats;

static double first_surface(const vbl_scene* scene, vbl_vec3 o, vbl_vec3 d)
{
    vbl_surface_hit hit;
    if (scene->surfaces && vbl_surfaces_intersect(scene->surfaces, o, d, 0.0, INFINITY, &hit)) return hit.t;
    return INFINITY;
}

/* Section 3.1 in media: camera ray, free flight to x1, phase-sampled direction, free flight to
 * the candidate y. Returns 0 when either flight leaves the media (or hits a surface). */
static int camera_subpath(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_rng* rng, vbl_vec3* y)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_camera* cam = &scene->camera;
    vbl_vec3 o, d, wi;
    double t, sigma_t, pdf, comps[VBL_MAX_MEDIA];
    double sx = vbl_rng_uniform(rng) * cam->width, sy = vbl_rng_uniform(rng) * cam->height;
    vbl_camera_ray(cam, sx, sy, &o, &d);
    if (!vbl_ctx_free_flight(ctx, ts, o, d, first_surface(scene, o, d), rng, &t, &sigma_t, comps)) return 0;
    vbl_vec3 x1 = vbl_v3_madd(o, d, t);
    double u0 = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng);
    if (!vbl_media_sample_phase(scene, comps, d, u0, u1, u2, &wi, &pdf)) return 0;
    if (!vbl_ctx_free_flight(ctx, ts, x1, wi, first_surface(scene, x1, wi), rng, &t, &sigma_t, comps)) return 0;
    *y = vbl_v3_madd(x1, wi, t);
    return 1;
}

/* M candidates (slot i draws from its own stream and retries up to 32 sub-paths); returns how
 * many succeeded, compacted in slot order into out[]. */
static size_t place_candidates(const vbl_render_context* ctx, size_t M, vbl_vec3* out)
{
    unsigned char* ok = calloc(M ? M : 1, 1);
    if (!ok) return 0;
#pragma omp parallel num_threads(ctx->threads)
    {
        vbl_thread_state ts;
        memset(&ts, 0, sizeof ts);
        vbl_extinction_cursor_init(&ts.cursor, ctx->extinction);
#pragma omp for schedule(dynamic, 256)
        for (long i = 0; i < (long)M; ++i) {
            vbl_rng rng = vbl_rng_make(ctx->options.seed ^ DOMAIN_CAMERA_PATHS, ctx->pass, (uint64_t)i);
            for (int attempt = 0; attempt < 32 && !ok[i]; ++attempt)
                ok[i] = (unsigned char)camera_subpath(ctx, &ts, &rng, &out[i]);
        }
    }
    size_t n = 0;
    for (size_t i = 0; i < M; ++i)
        if (ok[i]) out[n++] = out[i];
    free(ok);
    return n;
}

/* 3D analogue of eq 2: r_i = cbrt(M V_i / (4 sqrt(2) N m)), V_i the ball through the m-th
 * nearest neighbour (densest sphere packing of the N kept lights in the local volume). */
static vbl_result rmax_3d(const vbl_vec3* p, size_t M, size_t N, size_t m, int threads, double* r)
{
    vbl_bn_kdtree tree;
    vbl_result res = vbl_bn_kdtree_build(&tree, p, NULL, M);
    if (res) return res;
    if (m > M - 1) m = M - 1;
    int failed = 0;
#pragma omp parallel num_threads(threads > 0 ? threads : omp_get_max_threads()) reduction(| : failed)
    {
        size_t* idx = malloc(sizeof(size_t) * (m + 1));
        double* d2 = malloc(sizeof(double) * (m + 1));
        if (!idx || !d2) failed = 1;
#pragma omp for schedule(static)
        for (long i = 0; i < (long)M; ++i) {
            if (!idx || !d2) continue;
            size_t found = vbl_bn_kdtree_nearest(&tree, p[i], m, (size_t)i, idx, d2);
            double d = found ? sqrt(d2[found - 1]) : 0.0;
            double v = 4.0 / 3.0 * VBL_PI * d * d * d;
            r[i] = found ? cbrt((double)M * v / (4.0 * sqrt(2.0) * (double)N * (double)found)) : 0.0;
        }
        free(idx);
        free(d2);
    }
    vbl_bn_kdtree_free(&tree);
    if (failed) return VBL_ERROR_OUT_OF_MEMORY;
    double smallest = INFINITY;
    for (size_t i = 0; i < M; ++i)
        if (r[i] > 0.0 && r[i] < smallest) smallest = r[i];
    for (size_t i = 0; i < M; ++i)
        if (!(r[i] > 0.0)) r[i] = isfinite(smallest) ? smallest : 0.0;
    return VBL_SUCCESS;
}

/* One camera-driven light while its incident field is gathered (section 3.3). */
typedef struct split_light {
    vbl_vec3 position;
    double radius;
    double lum_sum;        /* sum of the split contributions' luminance */
    vbl_vec3 power_sum;    /* sum of the split contributions (RGB) */
    vbl_vec3 pick_power;   /* the reservoir's contribution: w Phi, its incident direction, bounce */
    double pick_lum;
    vbl_vec3 pick_incident;
    int pick_bounce;
} split_light;

static double luminance(vbl_vec3 c) { return (c.x + c.y + c.z) / 3.0; }

typedef struct weight_sum_target {
    double* sums; /* per collision */
    double radius;
} weight_sum_target;

static void add_weight_to_collision(void* user, size_t index, double d2)
{
    weight_sum_target* t = user;
    double r2 = t->radius * t->radius;
    if (d2 < r2) t->sums[index] += 1.0 - d2 / r2;
}

typedef struct split_query {
    split_light* light;
    const vbl_vpl* collisions;
    const double* weight_sums;
    vbl_rng* rng;
} split_query;

/* The light's share of collision `index`: (1 - (d/R)^2) / sum over covering lights (partition of
 * unity); the reservoir keeps one contribution with probability proportional to its luminance. */
static void add_split_contribution(void* user, size_t index, double d2)
{
    split_query* q = user;
    split_light* l = q->light;
    double r2 = l->radius * l->radius;
    if (!(d2 < r2) || !(q->weight_sums[index] > 0.0)) return;
    const vbl_vpl* c = &q->collisions[index];
    vbl_vec3 part = vbl_v3_scale(c->power, (1.0 - d2 / r2) / q->weight_sums[index]);
    double lum = luminance(part);
    if (!(lum > 0.0)) return;
    l->power_sum = vbl_v3_add(l->power_sum, part);
    l->lum_sum += lum;
    if (vbl_rng_uniform(q->rng) * l->lum_sum < lum) {
        l->pick_power = part;
        l->pick_lum = lum;
        l->pick_incident = c->incident;
        l->pick_bounce = c->bounce;
    }
}

/* Splits the medium collisions of K light paths among the lights; returns the fraction of the
 * collisions' power (luminance) that no light covers. */
static vbl_result split_collisions(const vbl_render_context* ctx, split_light* lights, size_t n, double* lost)
{
    vbl_render_context split_ctx = *ctx;
    split_ctx.options.light_paths = (int)ceil(g_config.split_factor * (double)g_config.lights);
    split_ctx.options.seed = ctx->options.seed ^ DOMAIN_SPLIT_PATHS;
    vbl_photon_settings ps = {0, 1, 0, VBL_TRANSMITTANCE_CACHED_RATIO, 16};
    vbl_photon_store photons;
    memset(&photons, 0, sizeof photons);
    double t0 = omp_get_wtime();
    vbl_result res = vbl_photon_trace(&split_ctx, &ps, &photons);
    g_stats.phase_seconds[2] += omp_get_wtime() - t0;
    if (res) return res;
    t0 = omp_get_wtime();
    const int M = ctx->options.max_bounces;
    size_t count = 0; /* collisions that may feed volume_from_volume (bounce + 1 <= M) */
    for (size_t j = 0; j < photons.vpl_count; ++j)
        if (M < 0 || photons.vpls[j].bounce + 1 <= M) photons.vpls[count++] = photons.vpls[j];
    vbl_vec3* where = malloc(sizeof(vbl_vec3) * (count ? count : 1));
    double* weight_sums = calloc(count ? count : 1, sizeof(double));
    vbl_bn_kdtree collision_tree;
    memset(&collision_tree, 0, sizeof collision_tree);
    if (!where || !weight_sums) res = VBL_ERROR_OUT_OF_MEMORY;
    for (size_t j = 0; !res && j < count; ++j) where[j] = photons.vpls[j].position;
    *lost = 0.0;
    if (!res && count > 0) res = vbl_bn_kdtree_build(&collision_tree, where, NULL, count);
    if (!res && count > 0) {
        /* partition-of-unity denominators: each light adds its weights to the collisions it
         * covers (sequential: O(covered pairs), and the sums do not depend on threads) */
        for (size_t i = 0; i < n; ++i) {
            weight_sum_target t = {weight_sums, lights[i].radius};
            vbl_bn_kdtree_within(&collision_tree, lights[i].position, lights[i].radius, add_weight_to_collision, &t);
        }
        double lost_lum = 0.0, all_lum = 0.0;
        for (size_t j = 0; j < count; ++j) {
            double lum = luminance(photons.vpls[j].power);
            all_lum += lum;
            if (!(weight_sums[j] > 0.0)) lost_lum += lum;
        }
        *lost = all_lum > 0.0 ? lost_lum / all_lum : 0.0;
#pragma omp parallel for num_threads(ctx->threads) schedule(dynamic, 16)
        for (long i = 0; i < (long)n; ++i) {
            vbl_rng rng = vbl_rng_make(ctx->options.seed ^ DOMAIN_RESERVOIR, ctx->pass, (uint64_t)i);
            split_query q = {&lights[i], photons.vpls, weight_sums, &rng};
            vbl_bn_kdtree_within(&collision_tree, lights[i].position, lights[i].radius, add_split_contribution, &q);
        }
    }
    vbl_bn_kdtree_free(&collision_tree);
    free(where);
    free(weight_sums);
    vbl_photon_store_free(&photons);
    g_stats.phase_seconds[3] += omp_get_wtime() - t0;
    return res;
}

/* A light as the gather's point light: the reservoir's contribution scaled by 1 / p_k, the
 * medium fractions and mean g at the light's centre. Returns 0 for a light that received nothing. */
static int light_to_vpl(const vbl_render_context* ctx, vbl_extinction_cursor* cursor, const split_light* l,
                        vbl_vpl* out)
{
    double comps[VBL_MAX_MEDIA];
    if (!(l->lum_sum > 0.0) || !(l->pick_lum > 0.0)) return 0;
    double sigma_t = vbl_extinction_eval(ctx->extinction, cursor, l->position, comps);
    if (!(sigma_t > 0.0)) return 0;
    memset(out, 0, sizeof *out);
    out->position = l->position;
    out->incident = l->pick_incident;
    out->power = vbl_v3_scale(l->pick_power, l->lum_sum / l->pick_lum);
    for (int i = 0; i < ctx->scene->media_count && i < VBL_MAX_MEDIA; ++i) out->fraction[i] = comps[i] / sigma_t;
    out->g = vbl_media_mean_g(ctx->scene, comps);
    out->bounce = l->pick_bounce;
    return 1;
}

/* The N camera-driven lights of this pass as vbl_vpl entries (malloc'ed, *count of them). */
static vbl_result build_camera_lights(const vbl_render_context* ctx, vbl_vpl** out, size_t* count)
{
    *out = NULL;
    *count = 0;
    size_t N = g_config.lights, M = (size_t)ceil(g_config.candidate_factor * (double)N);
    vbl_vec3* candidates = malloc(sizeof(vbl_vec3) * (M ? M : 1));
    if (!candidates) return VBL_ERROR_OUT_OF_MEMORY;
    double t0 = omp_get_wtime();
    M = place_candidates(ctx, M, candidates);
    g_stats.candidates += (double)M;
    g_stats.phase_seconds[0] += omp_get_wtime() - t0;
    if (M < 2) {
        free(candidates);
        return VBL_SUCCESS;
    }
    if (N > M) N = M;
    double* r = malloc(sizeof(double) * M);
    size_t* kept = malloc(sizeof(size_t) * N);
    double* kept_r = malloc(sizeof(double) * N);
    split_light* lights = calloc(N, sizeof *lights);
    vbl_vpl* vpls = malloc(sizeof(vbl_vpl) * N);
    vbl_result res = (r && kept && kept_r && lights && vpls) ? VBL_SUCCESS : VBL_ERROR_OUT_OF_MEMORY;
    t0 = omp_get_wtime();
    if (!res) res = rmax_3d(candidates, M, N, g_config.neighbors, ctx->threads, r);
    vbl_bn_elimination_options eo = VBL_BN_ELIMINATION_DEFAULT;
    eo.leaf_size = 1024; /* N = 1000: one parallel level (the default 4096 suits 10^5 candidates) */
    if (!res) res = vbl_bn_eliminate_with_rmax(candidates, M, N, r, &eo, kept, kept_r, NULL);
    g_stats.phase_seconds[1] += omp_get_wtime() - t0;
    double radius_sum = 0.0, lost = 0.0;
    for (size_t i = 0; !res && i < N; ++i) {
        lights[i].position = candidates[kept[i]];
        lights[i].radius = g_config.alpha * kept_r[i];
        radius_sum += lights[i].radius;
    }
    if (!res) res = split_collisions(ctx, lights, N, &lost);
    if (!res) {
        vbl_extinction_cursor cursor;
        vbl_extinction_cursor_init(&cursor, ctx->extinction);
        for (size_t i = 0; i < N; ++i) *count += (size_t)light_to_vpl(ctx, &cursor, &lights[i], &vpls[*count]);
        *out = vpls;
        vpls = NULL;
        g_stats.radius += radius_sum / (double)N;
        g_stats.lost += lost;
    }
    free(candidates);
    free(r);
    free(kept);
    free(kept_r);
    free(lights);
    free(vpls);
    return res;
}

/* The classic VPLs of L light paths traced apart from the store's (scenes with surfaces, whose
 * surface VSLs come from the store's own surface_light_paths paths). */
static vbl_result trace_classic_vpls(const vbl_render_context* ctx, vbl_vpl** out, size_t* count)
{
    vbl_render_context classic = *ctx;
    classic.options.light_paths = g_config.light_paths;
    classic.options.seed = ctx->options.seed ^ DOMAIN_CLASSIC_PATHS;
    vbl_photon_settings ps = {0, 1, 0, VBL_TRANSMITTANCE_CACHED_RATIO, 16};
    vbl_photon_store photons;
    memset(&photons, 0, sizeof photons);
    vbl_result res = vbl_photon_trace(&classic, &ps, &photons);
    if (res) return res;
    *out = photons.vpls;
    *count = photons.vpl_count;
    photons.vpls = NULL;
    photons.vpl_count = 0;
    vbl_photon_store_free(&photons);
    return VBL_SUCCESS;
}

/* pass_begin: the vpl store, then the medium VPLs of the placement swapped in. With surfaces the
 * store traces surface_light_paths paths for its surface VSLs (the same in both placements) and
 * the classic VPLs come from their own L paths; without surfaces the classic placement keeps the
 * store's VPLs of L paths and the camera placement's store traces none. */
static vbl_result placement_pass_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vpl_settings settings;
    vbl_vpl_settings_from_options(&ctx->options, &settings);
    vbl_render_context inner = *ctx;
    const int surfaces = ctx->scene->surfaces != NULL;
    inner.options.light_paths = surfaces ? g_config.surface_light_paths
                                         : (g_config.kind == PLACEMENT_CAMERA ? 0 : g_config.light_paths);
    vbl_result res = vbl_vl_pass_begin(&inner, &vbl_vl_kernel_point, &settings, store);
    if (res) return res;
    vbl_photon_store* photons = vbl_vl_photons_mutable(*store);
    if (g_config.kind == PLACEMENT_CAMERA || surfaces) {
        double t0 = omp_get_wtime();
        vbl_vpl* lights = NULL;
        size_t count = 0;
        res = g_config.kind == PLACEMENT_CAMERA ? build_camera_lights(ctx, &lights, &count)
                                                : trace_classic_vpls(ctx, &lights, &count);
        if (res) {
            vbl_vl_pass_end(ctx, *store);
            *store = NULL;
            return res;
        }
        free(photons->vpls);
        photons->vpls = lights;
        photons->vpl_count = count;
        g_stats.build_seconds += omp_get_wtime() - t0;
    }
    g_stats.vpls += (double)photons->vpl_count;
    g_stats.passes += 1;
    return VBL_SUCCESS;
}

static const vbl_estimator placement_estimator = {"bn_media", 1, placement_pass_begin, vbl_vl_camera_sample,
                                                  vbl_vl_pass_end, vbl_vl_camera_aovs};

/* Calibration: medium VPLs per light path of the vpl store (one pass, no camera work). */
static double g_calibration_vpls;

static vbl_result calibration_pass_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vpl_settings settings = VBL_VPL_SETTINGS_DEFAULT;
    vbl_result res = vbl_vl_pass_begin(ctx, &vbl_vl_kernel_point, &settings, store);
    if (!res) g_calibration_vpls = (double)vbl_vl_photons_mutable(*store)->vpl_count;
    return res;
}

static void calibration_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                                      const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    (void)ctx, (void)store, (void)ts, (void)sample, (void)rng, (void)out;
}

static const vbl_estimator calibration_estimator = {"bn_media_calibration", 1, calibration_pass_begin,
                                                    calibration_camera_sample, vbl_vl_pass_end, NULL};

/* ======================================================================================== */
/* ---- scenes, reference, error ---------------------------------------------------------- */

typedef struct bench_scene {
    const char* name;
    const char* file;        /* relative to the source tree */
    double reference_factor; /* x --reference-seconds when the reference must be rendered */
} bench_scene;

static const bench_scene bench_scenes[] = {
    {"cloud", "samples/cloud.json", 1.0},           /* density 12, albedo 0.95, g = 0.5, sun + sky */
    {"smoky_room", "samples/smoky_room.json", 2.5}, /* the cloud as smoke in a room, spot light */
};

/* indices in bench_layer_names (bench_reference.h) */
#define LAYER_SFV 5
#define LAYER_VFV 7
#define LAYER_MEDIUM BENCH_LAYER_MEDIUM

/* rMAE of B x B block means: noise averages out, systematic error (bias) stays. */
static double block_rmae(const float* img, const float* ref, int width, int height, int B)
{
    double num = 0.0, den = 0.0;
    for (int by = 0; by + B <= height; by += B)
        for (int bx = 0; bx + B <= width; bx += B)
            for (int k = 0; k < 3; ++k) {
                double si = 0.0, sr = 0.0;
                for (int y = by; y < by + B; ++y)
                    for (int x = bx; x < bx + B; ++x) {
                        si += img[3 * (y * width + x) + k];
                        sr += ref[3 * (y * width + x) + k];
                    }
                num += fabs(si - sr);
                den += fabs(sr);
            }
    return den > 0.0 ? num / den : NAN;
}

typedef struct bench_args {
    const char* vdb;
    const char* source_dir; /* the scenes' tree (compiled-in default) */
    const char* cache_dir;  /* the references' folder (compiled-in default) */
    const char* csv;
    int width, height, threads, passes;
    double budget, max_seconds, reference_seconds;
    double candidate_factor, split_factor, alpha;
    size_t neighbors;
    int surface_light_paths;
    uint64_t seed;
    char scenes[256];
    size_t lights[8];
    int light_count;
} bench_args;

static vbl_scene* load_scene(const bench_args* a, const bench_scene* s)
{
    return bench_load_scene("bench_bn_media", a->source_dir, s->file, a->vdb, a->width, a->height);
}

/* A bench_curves reference of this scene and resolution, any VDB path and length (bench_reference.h). */
static void make_reference(const vbl_scene* scene, const bench_args* a, const bench_scene* s, bench_reference* r)
{
    bench_reference_request q = {"bench_bn_media", a->cache_dir, s->name, s->file, a->vdb, a->width, a->height,
                                 a->threads, a->reference_seconds * s->reference_factor, 1};
    bench_reference_make(scene, &q, r);
    const size_t per = (size_t)BENCH_LAYERS * 3 * r->n;
    const int shown[3] = {LAYER_VFV, LAYER_SFV, LAYER_MEDIUM};
    for (int k = 0; k < 3; ++k) {
        int l = shown[k];
        if (!r->present[l]) continue;
        const float* a0 = r->halves + (size_t)l * 3 * r->n;
        const float* b0 = r->halves + per + (size_t)l * 3 * r->n;
        printf("# reference %s %-20s own rMAE (floor) ~ %.4f, blocks %.4f\n", s->name, bench_layer_names[l],
               0.5 * bench_rmae(a0, b0, 3 * r->n), 0.5 * block_rmae(a0, b0, r->width, r->height, 8));
    }
}

/* ======================================================================================== */
/* ---- one progressive render ------------------------------------------------------------ */

#define TRACKED 3 /* volume_from_volume, surface_from_volume, medium */
static const int tracked_layers[TRACKED] = {LAYER_VFV, LAYER_SFV, LAYER_MEDIUM};

typedef struct curve_point {
    int pass;
    double seconds;
    double err[TRACKED], blocks[TRACKED], ratio[TRACKED]; /* ratio: sum I / sum Iref */
} curve_point;

typedef struct curve {
    const bench_reference* ref;
    int min_passes;
    double budget, max_seconds, overhead;
    float* img;
    curve_point* points;
    int count, capacity;
} curve;

static int on_pass(const vbl_render_progress* progress, void* user)
{
    curve* c = user;
    double t0 = omp_get_wtime();
    double seconds = progress->elapsed_seconds - c->overhead;
    vbl_film* film = NULL;
    if (vbl_render_snapshot(progress, &film)) {
        fprintf(stderr, "bench_bn_media: %s\n", vbl_last_error_message());
        exit(1);
    }
    if (c->count == c->capacity) {
        c->capacity = c->capacity ? 2 * c->capacity : 64;
        c->points = realloc(c->points, sizeof *c->points * (size_t)c->capacity);
        if (!c->points) exit(1);
    }
    curve_point* p = &c->points[c->count++];
    p->pass = progress->pass;
    p->seconds = seconds;
    for (int k = 0; k < TRACKED; ++k) {
        int l = tracked_layers[k];
        p->err[k] = p->blocks[k] = p->ratio[k] = NAN;
        if (!c->ref->present[l]) continue;
        bench_film_rgb(film, l, c->ref->n, c->img);
        const float* rl = c->ref->ref + (size_t)l * 3 * c->ref->n;
        p->err[k] = bench_rmae(c->img, rl, 3 * c->ref->n);
        p->blocks[k] = block_rmae(c->img, rl, c->ref->width, c->ref->height, 8);
        double si = 0.0, sr = 0.0;
        for (int i = 0; i < 3 * c->ref->n; ++i) {
            si += c->img[i];
            sr += rl[i];
        }
        p->ratio[k] = sr != 0.0 ? si / sr : NAN;
    }
    vbl_film_release(film);
    c->overhead += omp_get_wtime() - t0;
    return (progress->pass >= c->min_passes && seconds >= c->budget) || seconds >= c->max_seconds;
}

typedef struct run_result {
    size_t lights;
    placement_kind kind;
    int light_paths;
    placement_stats stats;
    int ok;
    curve_point at_count; /* at --passes */
    curve_point at_time;  /* last pass within --budget */
    curve_point last;
    curve_point at_fraction[4]; /* last pass within budget / 8, / 4, / 2 and budget: error vs time */
} run_result;

static const double budget_fractions[4] = {0.125, 0.25, 0.5, 1.0};

static const char* kind_name(placement_kind k) { return k == PLACEMENT_CAMERA ? "camera" : "light_paths"; }

static void run_one(const vbl_scene* scene, const bench_args* a, const bench_reference* ref, const char* scene_name,
                    const placement_config* config, uint64_t seed, FILE* csv, run_result* out)
{
    memset(out, 0, sizeof *out);
    out->lights = config->lights;
    out->kind = config->kind;
    out->light_paths = config->light_paths;
    curve c;
    memset(&c, 0, sizeof c);
    c.ref = ref;
    c.min_passes = a->passes;
    c.budget = a->budget;
    c.max_seconds = a->max_seconds;
    c.img = malloc(sizeof(float) * 3 * (size_t)ref->n);
    if (!c.img) exit(1);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_scene_render_options(scene, &o);
    o.method = VBL_RENDER_VPL;
    o.spp = 1;
    o.light_paths = config->light_paths;
    o.passes = 1 << 30;
    o.seed = seed;
    o.threads = a->threads;
    o.callback = on_pass;
    o.callback_user_data = &c;
    g_config = *config;
    memset(&g_stats, 0, sizeof g_stats);
    vbl_film* film = NULL;
    vbl_result r = vbl_render_with_estimator(scene, &o, &placement_estimator, &film);
    if (film) vbl_film_release(film);
    out->stats = g_stats;
    if ((r && r != VBL_ERROR_INTERRUPTED) || c.count == 0) {
        printf("# %s %s N=%zu: failed (%s)\n", scene_name, kind_name(config->kind), config->lights,
               r ? vbl_last_error_message() : "no pass");
        free(c.img);
        free(c.points);
        return;
    }
    out->ok = 1;
    out->last = c.points[c.count - 1];
    out->at_count = c.points[c.count - 1];
    out->at_time = c.points[0];
    for (int f = 0; f < 4; ++f) {
        out->at_fraction[f] = c.points[0];
        out->at_fraction[f].err[0] = NAN; /* no pass finished that early */
    }
    for (int i = 0; i < c.count; ++i) {
        if (c.points[i].pass == a->passes) out->at_count = c.points[i];
        if (c.points[i].seconds <= a->budget) out->at_time = c.points[i];
        for (int f = 0; f < 4; ++f)
            if (c.points[i].seconds <= budget_fractions[f] * a->budget) out->at_fraction[f] = c.points[i];
    }
    for (int i = 0; csv && i < c.count; ++i) {
        const curve_point* p = &c.points[i];
        fprintf(csv, "%s,%s,%zu,%d,%d,%.4f", scene_name, kind_name(config->kind), config->lights,
                config->light_paths, p->pass, p->seconds);
        for (int k = 0; k < TRACKED; ++k) fprintf(csv, ",%.6f,%.6f,%.5f", p->err[k], p->blocks[k], p->ratio[k]);
        fputc('\n', csv);
    }
    if (csv) fflush(csv);
    free(c.img);
    free(c.points);
}

/* Light paths per pass that give about N classic VPLs (rate measured on pass 0 of 2000 paths). */
static double measure_vpls_per_path(const vbl_scene* scene, const bench_args* a)
{
    const int paths = 2000;
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_scene_render_options(scene, &o);
    o.method = VBL_RENDER_VPL;
    o.spp = 1;
    o.passes = 1;
    o.light_paths = paths;
    o.seed = 77;
    o.threads = a->threads;
    vbl_film* film = NULL;
    g_calibration_vpls = 0.0;
    if (vbl_render_with_estimator(scene, &o, &calibration_estimator, &film)) {
        fprintf(stderr, "bench_bn_media: %s\n", vbl_last_error_message());
        exit(1);
    }
    vbl_film_release(film);
    return g_calibration_vpls / paths;
}

/* ======================================================================================== */
/* ---- tables ---------------------------------------------------------------------------- */

static void print_err(const curve_point* p, int k)
{
    if (isnan(p->err[k])) printf(" - | - | - |");
    else printf(" %.4f | %.4f | %.3f |", p->err[k], p->blocks[k], p->ratio[k]);
}

static void print_tables(const char* scene_name, const bench_reference* ref, const run_result* runs, int count,
                         const bench_args* a)
{
    int sfv = ref->present[LAYER_SFV];
    printf("\n### %s: equal virtual-light count (pass %d, spp 1)\n\n", scene_name, a->passes);
    printf("| N | placement | L | medium VPLs/pass | s/pass | build s/pass | vfv rMAE | vfv blocks | vfv sum/ref |%s"
           " medium rMAE | medium blocks | medium sum/ref |\n",
           sfv ? " sfv rMAE | sfv blocks | sfv sum/ref |" : "");
    printf("|---|---|---|---|---|---|---|---|---|%s---|---|---|\n", sfv ? "---|---|---|" : "");
    for (int i = 0; i < count; ++i) {
        const run_result* r = &runs[i];
        if (!r->ok) continue;
        const curve_point* p = &r->at_count;
        double per = r->stats.passes > 0 ? 1.0 / r->stats.passes : 0.0;
        printf("| %zu | %s | %d | %.0f | %.3f | %.3f |", r->lights, kind_name(r->kind), r->light_paths,
               r->stats.vpls * per, p->pass > 0 ? p->seconds / p->pass : NAN, r->stats.build_seconds * per);
        print_err(p, 0);
        if (sfv) print_err(p, 1);
        print_err(p, 2);
        printf("\n");
    }
    printf("\n### %s: equal time (last pass within %g s)\n\n", scene_name, a->budget);
    printf("| N | placement | passes | seconds | vfv rMAE | vfv blocks | vfv sum/ref |%s medium rMAE | medium blocks | "
           "medium sum/ref |\n",
           sfv ? " sfv rMAE | sfv blocks | sfv sum/ref |" : "");
    printf("|---|---|---|---|---|---|---|%s---|---|---|\n", sfv ? "---|---|---|" : "");
    for (int i = 0; i < count; ++i) {
        const run_result* r = &runs[i];
        if (!r->ok) continue;
        const curve_point* p = &r->at_time;
        printf("| %zu | %s | %d | %.2f |", r->lights, kind_name(r->kind), p->pass, p->seconds);
        print_err(p, 0);
        if (sfv) print_err(p, 1);
        print_err(p, 2);
        printf("\n");
    }
    printf("\n### %s: volume_from_volume rMAE vs time (last pass within t; passes in brackets)\n\n| N | placement |",
           scene_name);
    for (int f = 0; f < 4; ++f) printf(" t = %.2f s |", budget_fractions[f] * a->budget);
    printf("\n|---|---|---|---|---|---|\n");
    for (int i = 0; i < count; ++i) {
        const run_result* r = &runs[i];
        if (!r->ok) continue;
        printf("| %zu | %s |", r->lights, kind_name(r->kind));
        for (int f = 0; f < 4; ++f) {
            const curve_point* p = &r->at_fraction[f];
            if (isnan(p->err[0])) printf(" - |");
            else printf(" %.4f (%d) |", p->err[0], p->pass);
        }
        printf("\n");
    }
    printf("\n### %s: camera-driven lights (per pass means) and the longest run of each configuration\n\n",
           scene_name);
    printf("| N | placement | candidates | build ms/pass: candidates, elimination, split trace, splitting | mean radius | "
           "lost split power | passes at end | seconds | vfv rMAE | vfv blocks | vfv sum/ref |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < count; ++i) {
        const run_result* r = &runs[i];
        if (!r->ok) continue;
        double per = r->stats.passes > 0 ? 1.0 / r->stats.passes : 0.0;
        if (r->kind == PLACEMENT_CAMERA)
            printf("| %zu | %s | %.0f | %.1f, %.1f, %.1f, %.1f | %.4f | %.2f%% | %d | %.1f |", r->lights,
                   kind_name(r->kind), r->stats.candidates * per, 1e3 * r->stats.phase_seconds[0] * per,
                   1e3 * r->stats.phase_seconds[1] * per, 1e3 * r->stats.phase_seconds[2] * per,
                   1e3 * r->stats.phase_seconds[3] * per, r->stats.radius * per, 100.0 * r->stats.lost * per,
                   r->last.pass, r->last.seconds);
        else
            printf("| %zu | %s | - | - | - | - | %d | %.1f |", r->lights, kind_name(r->kind), r->last.pass,
                   r->last.seconds);
        print_err(&r->last, 0);
        printf("\n");
    }
    printf("\n");
    fflush(stdout);
}

/* ======================================================================================== */

static int parse_lights(const char* v, bench_args* a)
{
    a->light_count = 0;
    for (const char* s = v; *s && a->light_count < 8;) {
        long n = strtol(s, NULL, 10);
        if (n < 1) return 0;
        a->lights[a->light_count++] = (size_t)n;
        const char* e = strchr(s, ',');
        if (!e) break;
        s = e + 1;
    }
    return a->light_count > 0;
}

int main(int argc, char** argv)
{
    bench_args a;
    memset(&a, 0, sizeof a);
    a.vdb = VBL_BENCH_DEFAULT_VDB;
    a.source_dir = VBL_BENCH_SOURCE_DIR;
    a.cache_dir = VBL_BENCH_CACHE_DIR;
    a.width = 96;
    a.height = 72;
    a.threads = 2;
    a.passes = 16;
    a.budget = 30.0;
    a.max_seconds = 240.0;
    a.reference_seconds = 240.0;
    a.candidate_factor = 10.0;
    a.split_factor = 10.0;
    a.alpha = 2.0;
    a.neighbors = 32;
    a.surface_light_paths = 100;
    a.seed = 1000003u;
    snprintf(a.scenes, sizeof a.scenes, "cloud,smoky_room");
    parse_lights("100,300,1000", &a);
    for (int i = 1; i < argc; ++i) {
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) goto usage;
        if (!strcmp(argv[i], "--vdb")) a.vdb = v;
        else if (!strcmp(argv[i], "--source-dir")) a.source_dir = v;
        else if (!strcmp(argv[i], "--cache-dir")) a.cache_dir = v;
        else if (!strcmp(argv[i], "--csv")) a.csv = v;
        else if (!strcmp(argv[i], "--res")) {
            if (sscanf(v, "%dx%d", &a.width, &a.height) != 2 || a.width < 8 || a.height < 8) goto usage;
        } else if (!strcmp(argv[i], "--threads")) a.threads = atoi(v);
        else if (!strcmp(argv[i], "--passes")) a.passes = atoi(v);
        else if (!strcmp(argv[i], "--budget")) a.budget = atof(v);
        else if (!strcmp(argv[i], "--max-seconds")) a.max_seconds = atof(v);
        else if (!strcmp(argv[i], "--reference-seconds")) a.reference_seconds = atof(v);
        else if (!strcmp(argv[i], "--candidates")) a.candidate_factor = atof(v);
        else if (!strcmp(argv[i], "--split-paths")) a.split_factor = atof(v);
        else if (!strcmp(argv[i], "--alpha")) a.alpha = atof(v);
        else if (!strcmp(argv[i], "--neighbors")) a.neighbors = (size_t)atol(v);
        else if (!strcmp(argv[i], "--surface-paths")) a.surface_light_paths = atoi(v);
        else if (!strcmp(argv[i], "--seed")) a.seed = strtoull(v, NULL, 10);
        else if (!strcmp(argv[i], "--scenes")) snprintf(a.scenes, sizeof a.scenes, "%s", v);
        else if (!strcmp(argv[i], "--lights")) {
            if (!parse_lights(v, &a)) goto usage;
        } else goto usage;
        ++i;
    }
    if (a.threads < 0 || a.passes < 1 || !(a.budget > 0.0) || !(a.max_seconds > 0.0) || !(a.candidate_factor >= 1.0) ||
        !(a.split_factor > 0.0) || !(a.alpha > 0.0) || a.neighbors < 1 || !(a.reference_seconds > 0.0) ||
        a.surface_light_paths < 0)
        goto usage;
    FILE* csv = NULL;
    if (a.csv) {
        if (!(csv = fopen(a.csv, "w"))) {
            fprintf(stderr, "bench_bn_media: cannot write %s\n", a.csv);
            return 1;
        }
        fprintf(csv, "scene,placement,lights,light_paths,pass,seconds,vfv_rmae,vfv_blocks,vfv_ratio,sfv_rmae,"
                     "sfv_blocks,sfv_ratio,medium_rmae,medium_blocks,medium_ratio\n");
    }
    double load[3] = {0};
    FILE* lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = -1;
        fclose(lf);
    }
    printf("# bench_bn_media: %dx%d, threads %d, %d passes (equal count) and %g s (equal time) per configuration "
           "(cap %g s), candidates %g N, split paths %g N, alpha %g, m %zu, surface VSL paths %d, seed %llu; load "
           "average at start %.2f %.2f %.2f\n",
           a.width, a.height, a.threads, a.passes, a.budget, a.max_seconds, a.candidate_factor, a.split_factor,
           a.alpha, a.neighbors, a.surface_light_paths, (unsigned long long)a.seed, load[0], load[1], load[2]);
    fflush(stdout);
    for (size_t s = 0; s < sizeof bench_scenes / sizeof bench_scenes[0]; ++s) {
        const bench_scene* bs = &bench_scenes[s];
        if (!bench_in_list(a.scenes, bs->name)) continue;
        vbl_scene* scene = load_scene(&a, bs);
        bench_reference ref;
        memset(&ref, 0, sizeof ref);
        make_reference(scene, &a, bs, &ref);
        double rate = measure_vpls_per_path(scene, &a);
        printf("# %s: %.3f medium VPLs per light path (vpl store, 2000 paths)\n", bs->name, rate);
        fflush(stdout);
        run_result runs[16];
        int count = 0;
        for (int li = 0; li < a.light_count; ++li) {
            placement_config config = {PLACEMENT_LIGHT_PATHS, a.lights[li], 1, a.surface_light_paths,
                                       a.candidate_factor, a.split_factor, a.alpha, a.neighbors};
            config.light_paths = rate > 0.0 ? (int)fmax(1.0, round((double)a.lights[li] / rate)) : 1;
            uint64_t seed = a.seed + 7919u * (uint64_t)li;
            for (int k = 0; k < 2; ++k) {
                config.kind = k ? PLACEMENT_CAMERA : PLACEMENT_LIGHT_PATHS;
                run_one(scene, &a, &ref, bs->name, &config, seed, csv, &runs[count]);
                const run_result* r = &runs[count++];
                printf("# %s N=%zu %s: %d passes, %.1f s, vfv rMAE %.4f\n", bs->name, r->lights, kind_name(r->kind),
                       r->last.pass, r->last.seconds, r->last.err[0]);
                fflush(stdout);
            }
        }
        print_tables(bs->name, &ref, runs, count, &a);
        free(ref.halves);
        free(ref.ref);
        vbl_scene_release(scene);
    }
    if (csv) fclose(csv);
    return 0;
usage:
    fprintf(stderr, "usage: bench_bn_media [--scenes cloud,smoky_room] [--res WxH] [--threads N] "
                    "[--lights 100,300,1000] "
                    "[--passes P] [--budget S] [--max-seconds S] [--candidates F] [--split-paths F] [--alpha A] "
                    "[--neighbors m] [--surface-paths L] [--seed S] [--reference-seconds S] [--vdb FILE] "
                    "[--source-dir DIR] [--cache-dir DIR] [--csv FILE]\n");
    return 2;
}
