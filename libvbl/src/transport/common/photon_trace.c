/* Photon tracing into VRL/VPL stores (see photon_trace.h for the estimator and its weights). */
#include "transport/common/photon_trace.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "transport/common/radius_schedule.h"
#include "sampling/phase_hg.h"
#include "media/medium.h"
#include "media/medium_grids.h"
#include "transport/common/light_emission.h"
#include "volume/transmittance_cache.h"

/* Paths are traced in fixed blocks (independent of the thread count) whose records are
 * concatenated in block order, so the store is identical at any thread count. */
#define VBL_PHOTON_BLOCK 64

typedef struct vbl_photon_block {
    vbl_vrl* vrls;
    size_t vrl_count, vrl_cap;
    vbl_vpl* vpls;
    size_t vpl_count, vpl_cap;
    double* pool;
    size_t pool_count, pool_cap; /* pairs */
    vbl_surface_vsl* vsls;
    size_t vsl_count, vsl_cap;
    vbl_caustic_photon* caustics;
    size_t caustic_count, caustic_cap;
    int failed;
} vbl_photon_block;

static int vbl_grow(void** data, size_t* cap, size_t need, size_t elem)
{
    if (need <= *cap) return 1;
    size_t n = *cap ? *cap * 2 : 16;
    while (n < need) n *= 2;
    void* p = realloc(*data, n * elem);
    if (!p) return 0;
    *data = p;
    *cap = n;
    return 1;
}

vbl_surface_vsl_store vbl_photon_store_surface_view(const vbl_photon_store* store, const vbl_scene* scene)
{
    vbl_surface_vsl_store v;
    v.vsls = store->surface_vsls;
    v.count = v.capacity = store->surface_vsl_count;
    v.materials = scene->materials;
    v.material_count = scene->has_surfaces ? (size_t)vbl_surfaces_count(scene->surfaces) : 0;
    return v;
}

vbl_vec3 vbl_vpl_intensity(const vbl_scene* scene, const vbl_vpl* p, double cos_theta)
{
    vbl_vec3 k = vbl_v3(0.0, 0.0, 0.0);
    for (int i = 0; i < scene->media_count; ++i)
        if (p->fraction[i] > 0.0)
            k = vbl_v3_madd(k, scene->media[i].albedo, p->fraction[i] * vbl_hg_eval(scene->media[i].g, cos_theta));
    return vbl_v3_mul(k, p->power);
}

double vbl_vrl_transmittance(const vbl_photon_store* store, const vbl_vrl* vrl, double v)
{
    if (vrl->cache_count <= 0) return 1.0; /* short VRL, or no collision recorded */
    const double* p = store->cache_pool + 2 * vrl->cache_offset;
    int lo = 0, hi = vrl->cache_count; /* first index with t > v */
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (p[2 * mid] <= v) lo = mid + 1;
        else hi = mid;
    }
    return lo == 0 ? 1.0 : p[2 * (lo - 1) + 1];
}

typedef struct vbl_trace_shared {
    const vbl_render_context* ctx;
    const vbl_photon_settings* settings;
    int store_surface_vsls;
    int caustics; /* the split of surface_caustics.h is on for this trace */
    vbl_photon_source source;
    const vbl_light_guide* guide; /* vrl.light_guide: steer the walks (NULL: plain roulette) */
    int guide_mode;               /* its value: 1 bounded, 2 window (photon_trace.h) */
    uint64_t split_seed;          /* seed ^ VBL_RNG_DOMAIN_LIGHT_SPLIT */
    struct vbl_guide_pilot* pilot; /* vbl_light_guide_build's calibration (NULL otherwise) */
} vbl_trace_shared;

/* vbl_light_guide_build's calibration: the importance summed over the vertices of unguided walks. */
typedef struct vbl_guide_pilot {
    const vbl_light_guide* guide;
    double sum;
    size_t count;
} vbl_guide_pilot;


/* The photon (power *phi travelling along *d) reached surface `hit` at the end of segment k:
 * records the surface VSL (and a caustic photon when *prev_specular says the previous vertex was
 * a highly specular surface), then continues by BRDF sampling (photon_trace.h). Returns 0 when
 * the walk ends (absorbed, max_bounces, Russian roulette, out of memory: blk->failed). */
static int vbl_trace_surface_vertex(const vbl_trace_shared* sh, const vbl_surface_hit* hit, int k, vbl_rng* rng,
                                    vbl_vec3* phi, double phi0, vbl_vec3* x, vbl_vec3* d, vbl_photon_block* blk,
                                    int* prev_specular)
{
    const vbl_scene* scene = sh->ctx->scene;
    const int M = sh->ctx->options.max_bounces;
    const int vertex = k + 1;
    const vbl_vec3 wi = vbl_v3_scale(*d, -1.0); /* towards where the photon came from */
    const int specular = sh->caustics && vbl_material_is_highly_specular(&scene->materials[hit->material]);
    if (sh->caustics && *prev_specular && !specular && (M < 0 || k + 1 <= M)) {
        if (!vbl_grow((void**)&blk->caustics, &blk->caustic_cap, blk->caustic_count + 1, sizeof(vbl_caustic_photon))) {
            blk->failed = 1;
            return 0;
        }
        vbl_caustic_photon* c = &blk->caustics[blk->caustic_count++];
        c->position = hit->position;
        c->normal = hit->shading_normal;
        c->incident = wi;
        c->power = *phi;
        c->bounce = k;
    }
    *prev_specular = specular;
    if (sh->store_surface_vsls && (M < 0 || k + 2 <= M)) {
        if (!vbl_grow((void**)&blk->vsls, &blk->vsl_cap, blk->vsl_count + 1, sizeof(vbl_surface_vsl))) {
            blk->failed = 1;
            return 0;
        }
        vbl_surface_vsl* v = &blk->vsls[blk->vsl_count++];
        v->position = hit->position;
        v->normal = hit->shading_normal;
        v->incident = wi;
        v->power = *phi;
        v->material = hit->material;
        v->bounce = k;
    }
    /* a highly specular vertex can still feed a caustic photon one event later */
    if (M >= 0 && vertex > (specular ? M - 1 : M - 2)) return 0;
    const vbl_material* m = &scene->materials[hit->material];
    double u0 = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng);
    vbl_vec3 w, f;
    double pdf = 0.0;
    if (!vbl_material_sample(m, hit->shading_normal, wi, u0, u1, u2, &w, &pdf, &f) || !(pdf > 0.0)) return 0;
    double cos_o = vbl_v3_dot(w, hit->shading_normal);
    if (!(cos_o > 0.0) || !(vbl_v3_dot(w, hit->geometric_normal) > 0.0)) return 0;
    /* the sender convention of surface_vsl.h: f(outgoing, incident) (equal for reciprocal BRDFs) */
    f = vbl_material_eval(m, hit->shading_normal, w, wi);
    *phi = vbl_v3_scale(vbl_v3_mul(*phi, f), cos_o / pdf);
    if (!vbl_photon_continues(phi, phi0, vertex >= 2, rng)) return 0;
    *x = vbl_surface_spawn(scene->surfaces, hit->position, hit->geometric_normal, w);
    *d = w;
    return 1;
}

/* vrl.light_guide (photon_trace.h): per root light path, the split copies made so far; copy c of
 * path i draws from vbl_rng_make(seed ^ VBL_RNG_DOMAIN_LIGHT_SPLIT, pass, i << 20 | c). */
typedef struct vbl_split_state {
    uint64_t path;
    uint32_t copies;
} vbl_split_state;

static void vbl_walk(const vbl_trace_shared* sh, vbl_extinction_cursor* cursor, vbl_transmittance_cache* tmp,
                     vbl_rng* rng, vbl_photon_block* blk, vbl_vec3 x, vbl_vec3 d, vbl_vec3 phi, double phi0,
                     int k_start, vbl_split_state* split);

static void vbl_trace_one(const vbl_trace_shared* sh, vbl_extinction_cursor* cursor, vbl_emission_cursor* emission,
                          vbl_transmittance_cache* tmp, vbl_rng* rng, vbl_photon_block* blk, uint64_t path)
{
    const vbl_render_context* ctx = sh->ctx;
    /* light (or emissive media) selection proportional to power */
    vbl_emission_sample es;
    vbl_vec3 phi;
    if (!vbl_photon_emit_with_media(&sh->source, ctx->scene, ctx->extinction, cursor, emission,
                                    (size_t)ctx->options.light_paths, rng, &es, &phi))
        return;
    vbl_split_state split = {path, 0};
    vbl_walk(sh, cursor, tmp, rng, blk, es.origin, es.direction, phi, vbl_v3_max_component(phi), 0, &split);
}

/* The walk from segment k_start at x along d with power phi (photon_trace.h). */
static void vbl_walk(const vbl_trace_shared* sh, vbl_extinction_cursor* cursor, vbl_transmittance_cache* tmp,
                     vbl_rng* rng, vbl_photon_block* blk, vbl_vec3 x, vbl_vec3 d, vbl_vec3 phi, double phi0,
                     int k_start, vbl_split_state* split)
{
    const vbl_render_context* ctx = sh->ctx;
    const vbl_scene* scene = ctx->scene;
    const vbl_extinction* ext = ctx->extinction;
    const vbl_photon_settings* st = sh->settings;
    const int M = ctx->options.max_bounces;
    const int use_global = ctx->tracking.use_global_majorant;

    int prev_specular = 0; /* the previous vertex was a highly specular surface (caustics) */
    double comps[VBL_MAX_MEDIA] = {0};
    vbl_medium_point mp; /* what scatters at a vertex / at a VRL's middle (media/medium.h) */
    for (int k = k_start;; ++k) {
        double t0 = 0.0, t1 = 0.0, t_surface = INFINITY;
        vbl_surface_hit hit; /* the segment ends at the first surface (see photon_trace.h) */
        const int on_surface = scene->surfaces && vbl_surfaces_intersect(scene->surfaces, x, d, 0.0, INFINITY, &hit);
        if (on_surface) t_surface = hit.t;
        const int in_media = vbl_extinction_ray_bounds(ext, x, d, 0.0, t_surface, &t0, &t1) && t1 > t0;
        if (!in_media) {
            if (!on_surface) return; /* media-only scenes: exactly the former early exit */
            if (!vbl_trace_surface_vertex(sh, &hit, k, rng, &phi, phi0, &x, &d, blk, &prev_specular)) return;
            continue;
        }
        double t = 0.0, sigma_t = 0.0;
        int collided = vbl_free_flight_sample(ext, cursor, x, d, t0, t1, use_global, rng, &t, &sigma_t, comps);
        if (st->store_vrls && (M < 0 || k + 2 <= M)) {
            double end = (collided && !st->long_vrls) ? t : t1;
            if (end > t0) {
                if (!vbl_grow((void**)&blk->vrls, &blk->vrl_cap, blk->vrl_count + 1, sizeof(vbl_vrl))) {
                    blk->failed = 1;
                    return;
                }
                vbl_vrl* r = &blk->vrls[blk->vrl_count++];
                r->origin = vbl_v3_madd(x, d, t0);
                r->direction = d;
                r->length = end - t0;
                r->power = phi;
                if (scene->media_count == 1) {
                    r->g = scene->media[0].g;
                } else {
                    vbl_medium_query(scene, ext, cursor, vbl_v3_madd(x, d, 0.5 * (t0 + end)), &mp);
                    r->g = vbl_medium_mean_g(&mp);
                }
                r->bounce = k;
                r->cache_count = 0;
                r->cache_offset = 0;
                if (st->long_vrls) {
                    vbl_transmittance_cache_build(tmp, st->cache_kind, ext, cursor, r->origin, d, 0.0, r->length,
                                                  st->cache_entries, use_global, rng);
                    if (!vbl_grow((void**)&blk->pool, &blk->pool_cap, blk->pool_count + (size_t)tmp->count,
                                  2 * sizeof(double))) {
                        blk->failed = 1;
                        return;
                    }
                    r->cache_offset = blk->pool_count;
                    r->cache_count = tmp->count;
                    for (int i = 0; i < tmp->count; ++i) {
                        blk->pool[2 * (blk->pool_count + i)] = tmp->t[i];
                        blk->pool[2 * (blk->pool_count + i) + 1] = tmp->value[i];
                    }
                    blk->pool_count += (size_t)tmp->count;
                }
            }
        }
        if (!collided && on_surface) {
            if (!vbl_trace_surface_vertex(sh, &hit, k, rng, &phi, phi0, &x, &d, blk, &prev_specular)) return;
            continue;
        }
        if (!collided || !(sigma_t > 0.0)) return;
        prev_specular = 0;
        x = vbl_v3_madd(x, d, t);
        const int vertex = k + 1;
        vbl_medium_point_from_components(scene, comps, &mp);
        vbl_medium_point_apply_grids(scene, x, cursor->time, &mp); /* albedo grids */
        if (st->store_vpls && (M < 0 || vertex <= M - 1)) {
            if (!vbl_grow((void**)&blk->vpls, &blk->vpl_cap, blk->vpl_count + 1, sizeof(vbl_vpl))) {
                blk->failed = 1;
                return;
            }
            vbl_vpl* p = &blk->vpls[blk->vpl_count++];
            p->position = x;
            p->incident = d;
            p->power = phi;
            for (int i = 0; i < VBL_MAX_MEDIA; ++i) p->fraction[i] = i < scene->media_count ? comps[i] / sigma_t : 0.0;
            p->g = vbl_medium_mean_g(&mp);
            p->bounce = vertex;
        }
        if (sh->pilot) { /* vbl_light_guide_build's calibration walk: the mean importance at vertices */
            sh->pilot->sum += vbl_camera_importance_at(&sh->pilot->guide->grid, x);
            sh->pilot->count += 1;
        }
        if (M >= 0 && vertex > M - 2) return;
        int copies = 1;
        if (sh->guide) {
            /* weight window (Vorba and Krivanek 2016, sec. 4, eq. 5-6 with the camera importance as
             * the adjoint): r = Phi I(x) / (Phi_0 I_ref); roulette with q = r below 1, n = floor(r)
             * copies of weight Phi / n from 2 on (at most VBL_LIGHT_GUIDE_SPLIT here and
             * VBL_LIGHT_GUIDE_COPIES per root path); unbiased for any choice made before the copies. */
            const double r = vbl_v3_max_component(phi) / phi0 *
                             (vbl_camera_importance_at(&sh->guide->grid, x) + sh->guide->floor) / sh->guide->ref;
            /* mode 1 (bounded): q = max(r, Phi / Phi_0), so no weight ever exceeds Phi_0 (the
             * unguided bound); mode 2 (window): q = r (weights up to Phi_0 ref / floor) */
            const double q = sh->guide_mode == 2 ? r : fmax(r, vbl_v3_max_component(phi) / phi0);
            if (!(r >= 1.0) && q < 1.0) {
                if (!(q > 0.0) || vbl_rng_uniform(rng) >= q) return;
                phi = vbl_v3_scale(phi, 1.0 / q);
            } else if (r >= 2.0) {
                const uint32_t left = VBL_LIGHT_GUIDE_COPIES - split->copies;
                copies = r < VBL_LIGHT_GUIDE_SPLIT ? (int)r : VBL_LIGHT_GUIDE_SPLIT;
                if ((uint32_t)copies > left + 1) copies = (int)left + 1;
                phi = vbl_v3_scale(phi, 1.0 / copies);
            }
        }
        for (int c = 0; c < copies; ++c) {
            vbl_rng copy_rng;
            vbl_rng* cr = rng; /* copy 0 goes on with the path's own stream */
            if (c + 1 < copies) {
                split->copies += 1;
                copy_rng = vbl_rng_make(sh->split_seed, ctx->pass, split->path << 20 | split->copies);
                cr = &copy_rng;
            }
            double u0 = vbl_rng_uniform(cr), u1 = vbl_rng_uniform(cr), u2 = vbl_rng_uniform(cr);
            vbl_vec3 wi;
            double pdf = 0.0;
            if (!vbl_medium_phase_sample(&mp, d, u0, u1, u2, &wi, &pdf)) {
                if (c + 1 < copies) continue;
                return;
            }
            vbl_vec3 out = vbl_v3_scale(vbl_v3_mul(phi, vbl_medium_phase_kernel(&mp, vbl_v3_dot(d, wi))),
                                        1.0 / (pdf * sigma_t));
            if (c + 1 < copies) { /* the extra copies first (depth first: their streams in a fixed order) */
                if (vbl_v3_max_component(out) > 0.0)
                    vbl_walk(sh, cursor, tmp, cr, blk, x, wi, out, phi0, vertex, split);
                if (blk->failed) return;
                continue;
            }
            phi = out;
            if (sh->guide ? !(vbl_v3_max_component(phi) > 0.0) : !vbl_photon_continues(&phi, phi0, vertex >= 2, rng))
                return;
            d = wi;
        }
    }
}

/* The light paths' source: the scene's lights emitting towards the sphere around the media and
 * the surfaces, and the emissive media (photons from the fire too). 0 if nothing emits. */
static int vbl_trace_source_init(const vbl_scene* scene, vbl_photon_source* source)
{
    vbl_vec3 center = vbl_v3(0.0, 0.0, 0.0);
    double radius = 0.0;
    if (!vbl_photon_emission_sphere(scene, 1, &center, &radius)) return 0;
    double power = vbl_photon_source_init(source, scene, center, radius);
    if (scene->has_emission) power = vbl_photon_source_add_media(source, scene);
    return power > 0.0;
}

void vbl_light_guide_free(vbl_light_guide* guide)
{
    if (!guide) return;
    vbl_camera_importance_free(&guide->grid);
    free(guide);
}

vbl_result vbl_light_guide_build(const vbl_render_context* ctx, vbl_light_guide** out)
{
    *out = NULL;
    const vbl_scene* scene = ctx->scene;
    vbl_light_guide* g = calloc(1, sizeof *g);
    if (!g) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for the light guide", scene->path);
    vbl_trace_shared sh;
    memset(&sh, 0, sizeof sh);
    if ((scene->light_count == 0 && !scene->has_emission) || !vbl_camera_importance_build(ctx, &g->grid) ||
        !(g->grid.total > 0.0) || !vbl_trace_source_init(scene, &sh.source)) {
        vbl_light_guide_free(g);
        return VBL_SUCCESS;
    }
    /* the calibration: unguided walks that store nothing, from a stream of their own */
    vbl_render_context c = *ctx;
    c.options.light_paths = VBL_LIGHT_GUIDE_PILOT_PATHS;
    c.light_guide = NULL;
    vbl_photon_settings none;
    memset(&none, 0, sizeof none);
    vbl_guide_pilot pilot = {g, 0.0, 0};
    vbl_photon_block blk;
    memset(&blk, 0, sizeof blk);
    sh.ctx = &c;
    sh.settings = &none;
    sh.pilot = &pilot;
    vbl_extinction_cursor cursor;
    vbl_extinction_cursor_init(&cursor, ctx->extinction);
    vbl_emission_cursor emission;
    if (scene->has_emission) vbl_emission_cursor_init(&emission, scene);
    const uint64_t seed = ctx->options.seed ^ VBL_RNG_DOMAIN_LIGHT_SPLIT ^ VBL_RNG_DOMAIN_LIGHT;
    for (int i = 0; i < VBL_LIGHT_GUIDE_PILOT_PATHS; ++i) {
        vbl_rng rng = vbl_rng_make(seed, 0, (uint64_t)i);
        vbl_trace_one(&sh, &cursor, &emission, NULL, &rng, &blk, (uint64_t)i);
    }
    if (!(pilot.count > 0 && pilot.sum > 0.0)) {
        vbl_light_guide_free(g);
        return VBL_SUCCESS;
    }
    const double mean = pilot.sum / (double)pilot.count;
    g->floor = VBL_CAMERA_IMPORTANCE_FLOOR * mean;
    g->ref = mean + g->floor;
    *out = g;
    return VBL_SUCCESS;
}

void vbl_photon_store_free(vbl_photon_store* store)
{
    if (!store) return;
    free(store->vrls);
    free(store->vpls);
    free(store->cache_pool);
    free(store->surface_vsls);
    free(store->surface_vsl_peaks);
    vbl_caustic_map_free(&store->caustics);
    memset(store, 0, sizeof *store);
}

vbl_result vbl_photon_trace(const vbl_render_context* ctx, const vbl_photon_settings* settings,
                            vbl_photon_store* out)
{
    return vbl_photon_trace_with_surfaces(ctx, settings, 0, out);
}

vbl_result vbl_photon_trace_with_surfaces(const vbl_render_context* ctx, const vbl_photon_settings* settings,
                                          int store_surface_vsls, vbl_photon_store* out)
{
    return vbl_photon_trace_with_caustics(ctx, settings, store_surface_vsls, NULL, out);
}

vbl_result vbl_photon_trace_with_caustics(const vbl_render_context* ctx, const vbl_photon_settings* settings,
                                          int store_surface_vsls, const vbl_caustic_settings* caustics,
                                          vbl_photon_store* out)
{
    memset(out, 0, sizeof *out);
    const vbl_scene* scene = ctx->scene;
    vbl_caustic_settings cs;
    memset(&cs, 0, sizeof cs);
    if (caustics) cs = *caustics;
    if (!(cs.alpha <= 1.0) || !isfinite(cs.radius0))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "%s: caustic settings alpha = %g is above 1 or radius0 = %g is not finite", scene->path,
                         cs.alpha, cs.radius0);
    const int n = ctx->options.light_paths;
    const int M = ctx->options.max_bounces;
    /* surfaces-only scenes still need light paths for the surface VSLs and caustics */
    const int surface_paths = store_surface_vsls && scene->surfaces != NULL;
    if (n <= 0 || (scene->light_count == 0 && !scene->has_emission) || (ctx->extinction->count == 0 && !surface_paths) ||
        (M >= 0 && M < 2))
        return VBL_SUCCESS;

    vbl_trace_shared sh;
    memset(&sh, 0, sizeof sh);
    sh.ctx = ctx;
    sh.settings = settings;
    sh.store_surface_vsls = store_surface_vsls && scene->surfaces != NULL;
    sh.caustics = sh.store_surface_vsls && cs.mode != VBL_CAUSTICS_OFF &&
                  vbl_materials_any_highly_specular(scene->materials, vbl_surfaces_count(scene->surfaces));
    /* emit towards the media and the surfaces (without media only with surface paths: above) */
    if (!vbl_trace_source_init(scene, &sh.source)) return VBL_SUCCESS;

    sh.guide = ctx->light_guide;
    sh.guide_mode = ctx->options.vrl.light_guide;
    sh.split_seed = ctx->options.seed ^ VBL_RNG_DOMAIN_LIGHT_SPLIT;

    const int blocks = (n + VBL_PHOTON_BLOCK - 1) / VBL_PHOTON_BLOCK;
    vbl_photon_block* blk = calloc((size_t)blocks, sizeof *blk);
    if (!blk) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for %d light paths", scene->path, n);
    const uint64_t seed = ctx->options.seed ^ VBL_RNG_DOMAIN_LIGHT;
    volatile int stopped = 0; /* cancel / time limit between blocks of VBL_PHOTON_BLOCK paths */
#pragma omp parallel num_threads(ctx->threads)
    {
        vbl_extinction_cursor cursor;
        vbl_extinction_cursor_init(&cursor, ctx->extinction);
        vbl_emission_cursor emission;
        if (scene->has_emission) vbl_emission_cursor_init(&emission, scene);
        vbl_transmittance_cache* tmp = settings->long_vrls ? malloc(sizeof *tmp) : NULL;
#pragma omp for schedule(dynamic, 1)
        for (int b = 0; b < blocks; ++b) {
            if (stopped || vbl_render_stop_requested(ctx)) {
                stopped = 1;
                continue;
            }
            if (settings->long_vrls && !tmp) {
                blk[b].failed = 1;
                continue;
            }
            int end = (b + 1) * VBL_PHOTON_BLOCK < n ? (b + 1) * VBL_PHOTON_BLOCK : n;
            for (int i = b * VBL_PHOTON_BLOCK; i < end && !blk[b].failed; ++i) {
                vbl_rng rng = vbl_rng_make(seed, ctx->pass, (uint64_t)i);
                vbl_trace_one(&sh, &cursor, &emission, tmp, &rng, &blk[b], (uint64_t)i);
            }
        }
        free(tmp);
    }

    size_t nv = 0, np = 0, nc = 0, ns = 0, ncau = 0;
    int failed = 0;
    for (int b = 0; b < blocks; ++b) {
        nv += blk[b].vrl_count;
        np += blk[b].vpl_count;
        nc += blk[b].pool_count;
        ns += blk[b].vsl_count;
        ncau += blk[b].caustic_count;
        failed |= blk[b].failed;
    }
    if (stopped) failed = 1; /* the blocks are freed below; the driver drops the pass */
    if (!failed) {
        out->vrls = nv ? malloc(nv * sizeof(vbl_vrl)) : NULL;
        out->vpls = np ? malloc(np * sizeof(vbl_vpl)) : NULL;
        out->cache_pool = nc ? malloc(nc * 2 * sizeof(double)) : NULL;
        out->surface_vsls = ns ? malloc(ns * sizeof(vbl_surface_vsl)) : NULL;
        out->surface_vsl_peaks = ns ? malloc(ns * sizeof(vbl_vec3)) : NULL;
        failed = (nv && !out->vrls) || (np && !out->vpls) || (nc && !out->cache_pool) ||
                 (ns && (!out->surface_vsls || !out->surface_vsl_peaks));
    }
    if (!failed) {
        for (int b = 0; b < blocks; ++b) {
            for (size_t i = 0; i < blk[b].vrl_count; ++i) {
                vbl_vrl r = blk[b].vrls[i];
                r.cache_offset += out->cache_pool_count;
                out->vrls[out->vrl_count++] = r;
            }
            if (blk[b].vpl_count) memcpy(out->vpls + out->vpl_count, blk[b].vpls, blk[b].vpl_count * sizeof(vbl_vpl));
            out->vpl_count += blk[b].vpl_count;
            if (blk[b].pool_count)
                memcpy(out->cache_pool + 2 * out->cache_pool_count, blk[b].pool, blk[b].pool_count * 2 * sizeof(double));
            out->cache_pool_count += blk[b].pool_count;
            if (blk[b].vsl_count)
                memcpy(out->surface_vsls + out->surface_vsl_count, blk[b].vsls,
                       blk[b].vsl_count * sizeof(vbl_surface_vsl));
            out->surface_vsl_count += blk[b].vsl_count;
        }
        out->paths = (size_t)n;
        /* the VSLs' BRDF peaks, once per pass (surface_gather.c's camera-segment sampler) */
        const long nsl = (long)out->surface_vsl_count;
#pragma omp parallel for num_threads(ctx->threads) schedule(dynamic, 64)
        for (long i = 0; i < nsl; ++i) {
            const vbl_surface_vsl* v = &out->surface_vsls[i];
            out->surface_vsl_peaks[i] = vbl_material_max_direction(&scene->materials[v->material], v->normal, v->incident);
        }
    }
    if (!failed && sh.caustics) {
        /* the caustic photons in block order, then the pass's R_p and the grid (cells R_p wide) */
        vbl_caustic_photon* all = ncau ? malloc(ncau * sizeof *all) : NULL;
        if (ncau && !all) {
            failed = 1;
        } else {
            size_t at = 0;
            for (int b = 0; b < blocks; ++b) {
                if (blk[b].caustic_count) memcpy(all + at, blk[b].caustics, blk[b].caustic_count * sizeof *all);
                at += blk[b].caustic_count;
            }
            vbl_vec3 lo, hi;
            if (!vbl_surfaces_bounds(scene->surfaces, &lo, &hi)) lo = hi = vbl_v3(0.0, 0.0, 0.0);
            double r0 = cs.radius0 > 0.0 ? cs.radius0 : vbl_caustic_default_r0(all, ncau, lo, hi);
            double alpha = cs.alpha > 0.0 ? cs.alpha : VBL_RADIUS_ALPHA_DEFAULT;
            out->caustic_radius = r0 > 0.0 && isfinite(r0) ? vbl_radius_at_pass(r0, alpha, 2, ctx->pass) : 0.0;
            out->caustics_active = out->caustic_radius > 0.0; /* else the VSLs alone, as before */
            if (ncau && out->caustic_radius > 0.0 &&
                vbl_caustic_map_build(&out->caustics, all, ncau, out->caustic_radius) != VBL_SUCCESS)
                failed = 1;
            free(all);
        }
    }
    for (int b = 0; b < blocks; ++b) {
        free(blk[b].caustics);
        free(blk[b].vrls);
        free(blk[b].vpls);
        free(blk[b].pool);
        free(blk[b].vsls);
    }
    free(blk);
    if (failed) {
        vbl_photon_store_free(out);
        if (stopped)
            return vbl_error(VBL_ERROR_INTERRUPTED, "%s: light tracing stopped (cancel or time limit)", scene->path);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory storing virtual lights for %d light paths",
                         scene->path, n);
    }
    return VBL_SUCCESS;
}

int vbl_camera_segment_cache(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin, vbl_vec3 direction,
                             vbl_rng* rng, vbl_transmittance_cache* cache, double* u0, double* u1)
{
    return vbl_camera_segment_cache_to(ctx, ts, origin, direction, INFINITY, rng, cache, u0, u1);
}

int vbl_camera_segment_cache_to(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                vbl_vec3 direction, double t_max, vbl_rng* rng, vbl_transmittance_cache* cache,
                                double* u0, double* u1)
{
    if (ctx->extinction->count == 0 || !(t_max > 0.0) ||
        !vbl_extinction_ray_bounds(ctx->extinction, origin, direction, 0.0, t_max, u0, u1) || !(*u1 > *u0))
        return 0;
    vbl_transmittance_estimator kind =
        ctx->options.transmittance == VBL_TRANSMITTANCE_CACHED_DELTA ? VBL_TRANSMITTANCE_CACHED_DELTA
                                                                     : VBL_TRANSMITTANCE_CACHED_RATIO;
    vbl_transmittance_cache_build(cache, kind, ctx->extinction, &ts->cursor, origin, direction, *u0, *u1, 16,
                                  ctx->tracking.use_global_majorant, rng);
    return 1;
}
