/* Virtual ray lights along camera rays (vrl.h). */
#include "transport/virtual_lights/vrl.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "transport/common/radius_schedule.h"
#include "sampling/vrl_camera_mis.h"
#include "sampling/vrl_pair.h"
#include "media/medium.h"
#include "transport/common/emission_estimate.h"
#include "transport/common/light_emission.h"
#include "transport/common/photon_trace.h"
#include "transport/common/single_scatter.h"
#include "transport/surface/surface_gather.h"
#include "transport/virtual_lights/vrl_tree.h"
#include "volume/transmittance_cache.h"

typedef struct vbl_vrl_store {
    vbl_vrl_settings settings;
    vbl_photon_store photons;
    double g_camera;        /* HG g used by the sampler at camera points */
    double rr_distance;     /* world units; 0: no pruning */
    vbl_tracking_settings connect;
    vbl_surface_gather_settings gather; /* surfaces: eq 6 VRLs, surface VSLs of radius R_p */
    vbl_vrl_tree tree;      /* settings.select > 0: the pass's light tree (vrl_tree.h) */
} vbl_vrl_store;

double vbl_segment_distance(vbl_vec3 p0, vbl_vec3 a, double la, vbl_vec3 q0, vbl_vec3 b, double lb)
{
    /* closest points of two segments (clamped line-line solution, unit directions) */
    vbl_vec3 r = vbl_v3_sub(p0, q0);
    double ab = vbl_v3_dot(a, b), c = vbl_v3_dot(a, r), f = vbl_v3_dot(b, r);
    double denom = 1.0 - ab * ab;
    double s = denom > 1e-12 ? vbl_clamp((ab * f - c) / denom, 0.0, la) : 0.0;
    double t = ab * s + f;
    if (t < 0.0) {
        t = 0.0;
        s = vbl_clamp(-c, 0.0, la);
    } else if (t > lb) {
        t = lb;
        s = vbl_clamp(ab * lb - c, 0.0, la);
    }
    return vbl_v3_length(vbl_v3_sub(vbl_v3_madd(p0, a, s), vbl_v3_madd(q0, b, t)));
}

typedef struct vbl_piece_weight_ctx {
    const vbl_render_context* ctx;
    vbl_extinction_cursor cursor;
    double floor;
    unsigned calls;
} vbl_piece_weight_ctx;

/* Mean sigma_s (mean of R, G, B) at VBL_VRL_SELECT_DENSITY_POINTS midpoints of [v0, v1], floored
 * at 1e-3 of the global majorant so that no piece with power loses its probability. */
static double vbl_piece_weight(void* user, const vbl_vrl* l, double v0, double v1)
{
    vbl_piece_weight_ctx* w = user;
    const vbl_scene* scene = w->ctx->scene;
    vbl_medium_point mp; /* media/medium.h */
    double sum = 0.0;
    /* cancel / time limit: weight 0 leaves the remaining pieces out, so the build ends at once;
     * the stop is latched, so the driver drops this pass at its first pixel and the tree never
     * reaches the film */
    if ((w->calls++ & 255u) == 255u && vbl_render_stop_requested(w->ctx)) return 0.0;
    if (w->ctx->stop_latch && *w->ctx->stop_latch) return 0.0;
    for (int k = 0; k < VBL_VRL_SELECT_DENSITY_POINTS; ++k) {
        vbl_vec3 x = vbl_v3_madd(l->origin, l->direction, v0 + (v1 - v0) * (k + 0.5) / VBL_VRL_SELECT_DENSITY_POINTS);
        if (!(vbl_medium_query(scene, w->ctx->extinction, &w->cursor, x, &mp) > 0.0)) continue;
        for (int i = 0; i < mp.count; ++i) {
            vbl_vec3 a = mp.lobe[i].albedo;
            sum += mp.lobe[i].sigma_t * (a.x + a.y + a.z) / 3.0;
        }
    }
    return fmax(sum / VBL_VRL_SELECT_DENSITY_POINTS, w->floor);
}

/* The tree build's stop hook: the render's cancel flag and time limit. */
static int vbl_vrl_tree_stop(void* user) { return vbl_render_stop_requested((const vbl_render_context*)user); }

vbl_result vbl_vrl_select_tree_build(const vbl_render_context* ctx, const vbl_photon_store* photons, vbl_vrl_tree* tree)
{
    vbl_vec3 center;
    double radius = 0.0;
    if (!vbl_media_bounding_sphere(ctx->scene, &center, &radius) || !(radius > 0.0)) radius = 1.0;
    vbl_piece_weight_ctx w;
    w.ctx = ctx;
    w.calls = 0;
    vbl_extinction_cursor_init(&w.cursor, ctx->extinction);
    w.floor = ctx->extinction->max_sigma_t > 0.0 ? 1e-3 * ctx->extinction->max_sigma_t : 1.0;
    return vbl_vrl_tree_build_stoppable(tree, photons->vrls, photons->vrl_count, ctx->options.max_bounces,
                                        VBL_VRL_SELECT_FLOOR_REL * radius, VBL_VRL_SELECT_PIECE_REL * radius,
                                        vbl_piece_weight, &w, &(vbl_vrl_tree_stop_hook){vbl_vrl_tree_stop, (void*)ctx});
}

vbl_result vbl_vrl_pass_begin_with(const vbl_render_context* ctx, const vbl_vrl_settings* settings, void** store)
{
    *store = NULL;
    const vbl_scene* scene = ctx->scene;
    if (settings->samples < 1)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vrl samples = %d must be >= 1", scene->path,
                         settings->samples);
    if (settings->select < 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vrl select = %d must be >= 0", scene->path, settings->select);
    if (!(settings->transmittance_rr > 0.0 && settings->transmittance_rr <= 1.0))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vrl transmittance_rr = %g is outside (0, 1]", scene->path,
                         settings->transmittance_rr);
    if (settings->rr_radius > 0.0 && !(settings->rr_min_probability > 0.0 && settings->rr_min_probability <= 1.0))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vrl rr_min_probability = %g is outside (0, 1]",
                         scene->path, settings->rr_min_probability);
    const double alpha = settings->surface_alpha > 0.0 ? settings->surface_alpha : VBL_RADIUS_ALPHA_DEFAULT;
    if (!(alpha <= 1.0) || !isfinite(settings->surface_radius0))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vrl surface_alpha = %g is outside (0, 1] or surface_radius0 = %g is not finite",
                         scene->path, settings->surface_alpha, settings->surface_radius0);
    vbl_vrl_store* s = calloc(1, sizeof *s);
    if (!s) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (vrl store)", scene->path);
    s->settings = *settings;
    vbl_medium_point media;
    vbl_medium_point_scene(scene, &media);
    s->g_camera = vbl_medium_mean_g(&media); /* the camera samplers' hint */
    vbl_vec3 center;
    double radius = 0.0;
    if (settings->rr_radius > 0.0 && vbl_media_bounding_sphere(scene, &center, &radius))
        s->rr_distance = settings->rr_radius * radius;
    s->connect = ctx->tracking;
    s->connect.rr_threshold = settings->transmittance_rr;
    if (settings->connect_marching) {
        s->connect.estimator = VBL_TRANSMITTANCE_RAY_MARCHING;
        s->connect.march_step = settings->march_step;
    }
    vbl_photon_settings ps = {1, 0, settings->long_vrls, VBL_TRANSMITTANCE_CACHED_RATIO, 16};
    if (ctx->options.transmittance == VBL_TRANSMITTANCE_CACHED_DELTA) ps.cache_kind = VBL_TRANSMITTANCE_CACHED_DELTA;
    vbl_result r = vbl_photon_trace_with_surfaces(ctx, &ps, scene->surfaces != NULL, &s->photons);
    if (r) {
        free(s);
        return r;
    }
    if (settings->select > 0 && (r = vbl_vrl_select_tree_build(ctx, &s->photons, &s->tree))) {
        vbl_photon_store_free(&s->photons);
        free(s);
        return r;
    }
    s->gather.vrls = 1;
    s->gather.kernel_samples = VBL_SURFACE_KERNEL_SAMPLES_DEFAULT;
    s->gather.g_camera = s->g_camera;
    if (scene->surfaces) {
        double r0 = settings->surface_radius0 > 0.0 ? settings->surface_radius0
                                                    : vbl_surface_vsl_default_r0(scene, s->photons.surface_vsl_count);
        s->gather.vsl_radius = vbl_radius_at_pass(r0, alpha, 2, ctx->pass);
    }
    if ((r = vbl_surface_gather_blue_noise_begin(ctx, &s->gather))) { /* render.vsl_placement */
        vbl_vrl_tree_free(&s->tree);
        vbl_photon_store_free(&s->photons);
        free(s);
        return r;
    }
    *store = s;
    return VBL_SUCCESS;
}

void vbl_vrl_settings_from_options(const vbl_render_options* o, vbl_vrl_settings* out)
{
    vbl_vrl_settings d = VBL_VRL_SETTINGS_DEFAULT;
    *out = d;
    if (o->vrl.samples > 0) out->samples = o->vrl.samples;
    out->long_vrls = o->vrl.long_vrls != 0;
    out->connect_marching = o->vrl.connect != 0;
    out->march_step = o->vrl.march_step;
    out->rr_radius = o->vrl.prune_radius;
    if (o->vrl.prune_min_probability > 0.0) out->rr_min_probability = o->vrl.prune_min_probability;
    out->select = o->vrl.select;
}

static vbl_result vbl_vrl_pass_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings settings;
    vbl_vrl_settings_from_options(&ctx->options, &settings);
    return vbl_vrl_pass_begin_with(ctx, &settings, store);
}

double vbl_vrl_store_surface_radius(const void* store)
{
    return store ? ((const vbl_vrl_store*)store)->gather.vsl_radius : 0.0;
}

const vbl_photon_store* vbl_vrl_store_photons(const void* store)
{
    return store ? &((const vbl_vrl_store*)store)->photons : NULL;
}

void vbl_vrl_pass_end(const vbl_render_context* ctx, void* store)
{
    (void)ctx;
    vbl_vrl_store* s = store;
    if (!s) return;
    vbl_surface_gather_blue_noise_end(&s->gather);
    vbl_vrl_tree_free(&s->tree);
    vbl_photon_store_free(&s->photons);
    free(s);
}

double vbl_vrl_connect_transmittance(const vbl_render_context* ctx, const vbl_tracking_settings* settings,
                                        vbl_thread_state* ts, vbl_vec3 a, vbl_vec3 dir, double len, vbl_rng* rng)
{
    double t0, t1;
    if (vbl_ctx_occluded(ctx, a, dir, len)) return 0.0; /* surfaces block the connection */
    if (!vbl_extinction_ray_bounds(ctx->extinction, a, dir, 0.0, len, &t0, &t1) || !(t1 > t0)) return 1.0;
    return vbl_transmittance_estimate(ctx->extinction, &ts->cursor, a, dir, t0, t1, settings, rng);
}

int vbl_vrl_camera_cache(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts, vbl_vec3 origin,
                         vbl_vec3 direction, double t_max, vbl_rng* rng, vbl_vrl_camera* out)
{
    const vbl_vrl_store* s = store;
    double u0, u1;
    if (ctx->extinction->count == 0 || !(t_max > 0.0) ||
        !vbl_extinction_ray_bounds(ctx->extinction, origin, direction, 0.0, t_max, &u0, &u1) || !(u1 > u0))
        return 0;
    out->ray = vbl_segment_make(origin, direction, u0, u1);
    vbl_transmittance_estimator kind = ctx->options.transmittance == VBL_TRANSMITTANCE_CACHED_DELTA
                                           ? VBL_TRANSMITTANCE_CACHED_DELTA
                                           : VBL_TRANSMITTANCE_CACHED_RATIO;
    vbl_transmittance_cache_build_rr(&out->cache, kind, ctx->extinction, &ts->cursor, origin, direction, u0, u1, 16,
                                     ctx->tracking.use_global_majorant, s->settings.transmittance_rr, rng);
    return 1;
}

int vbl_vrl_camera_step_pdf(const vbl_transmittance_cache* cache, double u0, double u1, vbl_step_pdf* out)
{
    /* T(u) = 1 before the first cached point, value[i] from t[i] on (vbl_transmittance_cache_eval) */
    double x[VBL_STEP_PDF_MAX_PIECES + 1], y[VBL_STEP_PDF_MAX_PIECES];
    int n = 0;
    x[0] = u0;
    double cur = 1.0;
    for (int i = 0; i < cache->count && n < VBL_STEP_PDF_MAX_PIECES - 1; ++i) {
        double t = cache->t[i];
        if (t <= u0) {
            cur = cache->value[i];
            continue;
        }
        if (t >= u1) break;
        y[n] = cur;
        x[++n] = t;
        cur = cache->value[i];
    }
    y[n] = cur;
    x[++n] = u1;
    return vbl_step_pdf_init(out, x, y, n, 0.0);
}

/* One camera sample's gather over the VRLs: the store, the camera segment with its cache, and
 * the estimate's accumulator (also the light tree's visitor). */
typedef struct vbl_vrl_gather {
    const vbl_render_context* ctx;
    const vbl_vrl_store* s;
    vbl_thread_state* ts;
    const vbl_vrl_camera* cam;
    const vbl_step_pdf* camera; /* the camera technique's u density (camera_mis), or NULL */
    vbl_rng* rng;
    vbl_vec3* acc;
} vbl_vrl_gather;

/* Adds one VRL's estimate of eq 7 over its part v in [v0, v1] (samples draws of the pair sampler) times `weight` to *g->acc. */
static void vbl_vrl_estimate(const vbl_vrl_gather* g, const vbl_vrl* l, double v0, double v1, double weight)
{
    const vbl_render_context* ctx = g->ctx;
    const vbl_vrl_store* s = g->s;
    vbl_thread_state* ts = g->ts;
    const vbl_step_pdf* camera = g->camera;
    const vbl_transmittance_cache* cache = &g->cam->cache;
    const vbl_vec3 o = g->cam->ray.origin, d = g->cam->ray.direction;
    vbl_rng* rng = g->rng;
    vbl_vec3* acc = g->acc;
    const vbl_scene* scene = ctx->scene;
    const int S = s->settings.samples;
    vbl_medium_point mu, mv;
    vbl_vrl_pair pair;
    const vbl_segment light = vbl_segment_make(l->origin, l->direction, v0, v1);
    if (!vbl_vrl_pair_init(&pair, &g->cam->ray, &light, s->g_camera, l->g)) return;
    for (int k = 0; k < S; ++k) {
        double xi1 = vbl_rng_uniform(rng), xi2 = vbl_rng_uniform(rng);
        vbl_vrl_pair_sample ps;
        if (camera) {
            if (!vbl_vrl_camera_mis_draw(&pair, camera, vbl_rng_uniform(rng), xi1, xi2, &ps)) continue;
        } else if (!vbl_vrl_pair_draw(&pair, xi1, xi2, &ps) || !(ps.pdf > 0.0)) {
            continue;
        }
        vbl_vec3 xu = vbl_v3_madd(o, d, ps.u), xv = vbl_v3_madd(l->origin, l->direction, ps.v);
        vbl_vec3 to = vbl_v3_sub(xu, xv);
        double w2 = vbl_v3_dot(to, to);
        if (!(w2 > 0.0)) continue;
        double w = sqrt(w2);
        vbl_vec3 omega = vbl_v3_scale(to, 1.0 / w); /* light travels VRL point -> camera point */
        double Tc = vbl_transmittance_cache_eval(cache, ps.u);
        if (!(Tc > 0.0)) continue;
        double Tl = vbl_vrl_transmittance(&s->photons, l, ps.v);
        if (!(Tl > 0.0)) continue;
        if (!(vbl_medium_query(scene, ctx->extinction, &ts->cursor, xv, &mv) > 0.0)) continue;
        if (!(vbl_medium_query(scene, ctx->extinction, &ts->cursor, xu, &mu) > 0.0)) continue;
        vbl_vec3 kv = vbl_medium_phase_kernel(&mv, vbl_v3_dot(l->direction, omega));
        vbl_vec3 ku = vbl_medium_phase_kernel(&mu, -vbl_v3_dot(omega, d));
        vbl_vec3 f = vbl_v3_mul(vbl_v3_mul(kv, ku), l->power);
        if (!(vbl_v3_max_component(f) > 0.0)) continue;
        double Tw = vbl_vrl_connect_transmittance(ctx, &s->connect, ts, xv, omega, w, rng);
        if (!(Tw > 0.0)) continue;
        *acc = vbl_v3_madd(*acc, f, Tc * Tl * Tw * weight / (w2 * ps.pdf));
    }
}

/* One selected piece (vbl_vrl_tree_select) through vbl_vrl_estimate (user: the vbl_vrl_gather). */
static void vbl_vrl_visit_piece(const vbl_vrl_tree_piece* pc, double weight, void* user)
{
    const vbl_vrl_gather* g = user;
    vbl_vrl_estimate(g, &g->s->photons.vrls[pc->vrl], pc->v0, pc->v1, weight);
}

void vbl_vrl_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                           const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_vrl_store* s = store;
    const vbl_scene* scene = ctx->scene;
    const vbl_vec3 o = sample->origin, d = sample->direction;
    const int M = ctx->options.max_bounces;
    vbl_add_visible_emission(ctx, ts, o, d, rng, out);
    vbl_camera_media_emission(ctx, ts, sample, VBL_EMISSION_DIRECT_VOLUME | VBL_EMISSION_DIRECT_SURFACE, rng, out);
    if (M != 0 && vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_DIRECT))
        vbl_single_scatter_estimate_to(ctx, ts, o, d, sample->t_max, rng, &out->L[VBL_CLASS_VOLUME_DIRECT]);
    if (scene->surfaces && s) vbl_surface_gather_hit(ctx, ts, &s->photons, &s->gather, sample, rng, out);
    if (!s || (s->photons.vrl_count == 0 && s->photons.surface_vsl_count == 0 && !s->gather.blue_noise)) return;
    /* render.hybrid: with both media classes of the camera segment owned by pt, no segment work */
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_VOLUME) && !vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_SURFACE)) return;

    vbl_vrl_camera cam;
    if (!vbl_vrl_camera_cache(ctx, s, ts, o, d, sample->t_max, rng, &cam)) return;
    const vbl_transmittance_cache* cache = &cam.cache;
    const double u0 = cam.ray.t0, u1 = cam.ray.t1;
    vbl_surface_gather_segment(ctx, ts, &s->photons, &s->gather, sample, cache, u0, u1, rng, out);
    const int S = s->settings.samples;
    vbl_step_pdf camera_pdf;
    const vbl_step_pdf* camera =
        s->settings.camera_mis && vbl_vrl_camera_step_pdf(cache, u0, u1, &camera_pdf) ? &camera_pdf : NULL;
    vbl_vec3 acc = vbl_v3(0.0, 0.0, 0.0);
    const vbl_vrl_gather g = {ctx, s, ts, &cam, camera, rng, &acc};
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_VOLUME)) return; /* render.hybrid: pt owns it */
    if (s->settings.select > 0) {
        /* K draws from the light tree (vrl_tree.h), each weighted 1 / (K pdf): unbiased */
        const int K = s->settings.select;
        vbl_vrl_tree_query q = {vbl_v3_madd(o, d, u0), d,
                                vbl_vrl_tree_visible_length(cache, u0, u1, VBL_VRL_SELECT_VISIBLE_CUT), cache, u0,
                                VBL_VRL_SELECT_VISIBLE_CUT};
        vbl_vrl_tree_select(&s->tree, &q, K, S, rng, vbl_vrl_visit_piece, (void*)&g);
    } else {
        const vbl_vec3 cam_start = vbl_v3_madd(o, d, u0);
        for (size_t j = 0; j < s->photons.vrl_count; ++j) {
            if (j % VBL_STOP_CHECK_EVERY == VBL_STOP_CHECK_EVERY - 1 && vbl_render_stop_requested(ctx)) break;
            const vbl_vrl* l = &s->photons.vrls[j];
            if (M >= 0 && l->bounce + 2 > M) continue;
            double weight = 1.0 / S;
            if (s->rr_distance > 0.0) {
                double h = vbl_segment_distance(cam_start, d, u1 - u0, l->origin, l->direction, l->length);
                double q = h > s->rr_distance ? s->rr_distance / h : 1.0;
                if (q < s->settings.rr_min_probability) q = s->settings.rr_min_probability;
                if (q < 1.0) {
                    if (vbl_rng_uniform(rng) >= q) continue;
                    weight /= q;
                }
            }
            vbl_vrl_estimate(&g, l, 0.0, l->length, weight);
        }
    }
    out->L[VBL_CLASS_VOLUME_FROM_VOLUME] = vbl_v3_add(out->L[VBL_CLASS_VOLUME_FROM_VOLUME], acc);
}

int vbl_vrl_contributions(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                          const vbl_camera_sample* sample, vbl_rng* rng, double* contribution, double* visible,
                          double* pdf)
{
    const vbl_vrl_store* s = store;
    const int M = ctx->options.max_bounces;
    for (size_t j = 0; s && j < s->photons.vrl_count; ++j) contribution[j] = 0.0;
    *visible = 0.0;
    vbl_vrl_camera cam;
    if (!s || !vbl_vrl_camera_cache(ctx, s, ts, sample->origin, sample->direction, sample->t_max, rng, &cam)) return 0;
    const vbl_transmittance_cache* cache = &cam.cache;
    const double u0 = cam.ray.t0, u1 = cam.ray.t1;
    *visible = vbl_vrl_tree_visible_length(cache, u0, u1, VBL_VRL_SELECT_VISIBLE_CUT) / (u1 - u0);
    if (pdf) {
        vbl_vrl_tree_query q = {vbl_v3_madd(sample->origin, sample->direction, u0), sample->direction,
                                vbl_vrl_tree_visible_length(cache, u0, u1, VBL_VRL_SELECT_VISIBLE_CUT), cache, u0,
                                VBL_VRL_SELECT_VISIBLE_CUT};
        for (size_t j = 0; j < s->photons.vrl_count; ++j) pdf[j] = 0.0;
        for (int i = 0; i < s->tree.piece_count; ++i) pdf[s->tree.pieces[i].vrl] += vbl_vrl_tree_pdf(&s->tree, &q, i);
    }
    vbl_step_pdf camera_pdf;
    const vbl_step_pdf* camera =
        s->settings.camera_mis && vbl_vrl_camera_step_pdf(cache, u0, u1, &camera_pdf) ? &camera_pdf : NULL;
    for (size_t j = 0; j < s->photons.vrl_count; ++j) {
        const vbl_vrl* l = &s->photons.vrls[j];
        if (M >= 0 && l->bounce + 2 > M) continue;
        vbl_vec3 acc = vbl_v3(0.0, 0.0, 0.0);
        const vbl_vrl_gather g = {ctx, s, ts, &cam, camera, rng, &acc};
        vbl_vrl_estimate(&g, l, 0.0, l->length, 1.0);
        contribution[j] = acc.x + acc.y + acc.z;
    }
    return 1;
}

int vbl_vrl_sample_factors(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts, size_t vrl,
                           const vbl_vrl_camera* cam, vbl_rng* rng, vbl_vrl_factors* out)
{
    const vbl_vrl_store* s = store;
    const vbl_scene* scene = ctx->scene;
    const vbl_vrl* l = &s->photons.vrls[vrl];
    const vbl_transmittance_cache* cache = &cam->cache;
    const vbl_vec3 o = cam->ray.origin, d = cam->ray.direction;
    const double u0 = cam->ray.t0, u1 = cam->ray.t1;
    vbl_medium_point mu, mv;
    vbl_vrl_pair pair;
    memset(out, 0, sizeof *out);
    const vbl_segment light = vbl_segment_make(l->origin, l->direction, 0.0, l->length);
    if (!vbl_vrl_pair_init(&pair, &cam->ray, &light, s->g_camera, l->g)) return 0;
    double xi1 = vbl_rng_uniform(rng), xi2 = vbl_rng_uniform(rng);
    vbl_vrl_pair_sample ps;
    vbl_step_pdf camera;
    if (s->settings.camera_mis && vbl_vrl_camera_step_pdf(cache, u0, u1, &camera)) {
        if (!vbl_vrl_camera_mis_draw(&pair, &camera, vbl_rng_uniform(rng), xi1, xi2, &ps)) return 0;
    } else if (!vbl_vrl_pair_draw(&pair, xi1, xi2, &ps) || !(ps.pdf > 0.0)) {
        return 0;
    }
    vbl_vec3 xu = vbl_v3_madd(o, d, ps.u), xv = vbl_v3_madd(l->origin, l->direction, ps.v);
    vbl_vec3 to = vbl_v3_sub(xu, xv);
    double w2 = vbl_v3_dot(to, to);
    if (!(w2 > 0.0)) return 0;
    double w = sqrt(w2);
    vbl_vec3 omega = vbl_v3_scale(to, 1.0 / w);
    out->pdf = ps.pdf;
    out->w2 = w2;
    out->phase_geometry = vbl_vrl_pair_phase_geometry(&pair, ps.u, ps.v);
    out->tc = vbl_transmittance_cache_eval(cache, ps.u);
    out->tl = vbl_vrl_transmittance(&s->photons, l, ps.v);
    double su = vbl_medium_query(scene, ctx->extinction, &ts->cursor, xu, &mu);
    double sv = vbl_medium_query(scene, ctx->extinction, &ts->cursor, xv, &mv);
    out->sigma_u = su;
    out->sigma_v = sv;
    if (su > 0.0 && sv > 0.0) {
        vbl_vec3 kv = vbl_medium_phase_kernel(&mv, vbl_v3_dot(l->direction, omega));
        vbl_vec3 ku = vbl_medium_phase_kernel(&mu, -vbl_v3_dot(omega, d));
        vbl_vec3 f = vbl_v3_mul(vbl_v3_mul(kv, ku), l->power);
        out->f = f.x + f.y + f.z;
        out->power = l->power.x + l->power.y + l->power.z;
    }
    out->tw = vbl_vrl_connect_transmittance(ctx, &s->connect, ts, xv, omega, w, rng);
    vbl_tracking_settings march = s->connect;
    march.estimator = VBL_TRANSMITTANCE_RAY_MARCHING;
    march.march_step = 0.0;
    out->tw_march = vbl_vrl_connect_transmittance(ctx, &march, ts, xv, omega, w, rng);
    double t0, t1;
    out->tc_march = 1.0;
    if (vbl_extinction_ray_bounds(ctx->extinction, o, d, u0, ps.u, &t0, &t1) && t1 > t0)
        out->tc_march = vbl_transmittance_estimate(ctx->extinction, &ts->cursor, o, d, t0, t1, &march, rng);
    return 1;
}

const vbl_estimator vbl_estimator_vrl = {"vrl", 1, vbl_vrl_pass_begin, vbl_vrl_camera_sample, vbl_vrl_pass_end};
