/* The virtual-light estimator's common parts (virtual_lights.h); kernels in vpl.c, vrl.c,
 * virtual_beam_lights.c. */
#include "transport/virtual_lights/virtual_lights_kernel.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/work_count.h"
#include "media/medium.h"
#include "sampling/step_pdf.h"
#include "transport/common/emission_estimate.h"
#include "transport/common/light_emission.h"
#include "transport/path_tracing/pt_camera_classes.h"
#include "transport/photon_beams/photon_beams.h"

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

double vbl_vrl_connect_transmittance(const vbl_render_context* ctx, const vbl_tracking_settings* settings,
                                     vbl_thread_state* ts, vbl_vec3 a, vbl_vec3 dir, double len, vbl_rng* rng)
{
    if (vbl_ctx_occluded(ctx, a, dir, len)) return 0.0; /* surfaces block the connection */
    return vbl_ctx_media_transmittance(ctx, ts, a, dir, len, settings, rng);
}

void vbl_vl_pass_end(const vbl_render_context* ctx, void* store)
{
    (void)ctx;
    vbl_vl_store* s = store;
    if (!s) return;
    vbl_surface_gather_blue_noise_end(&s->gather);
    vbl_vrl_tree_free(&s->tree);
    vbl_photon_beam_gather_free(s->beams);
    vbl_photon_store_free(&s->photons);
    free(s);
}

vbl_result vbl_vl_pass_begin(const vbl_render_context* ctx, const vbl_vl_kernel* kernel, const void* settings,
                             void** store)
{
    *store = NULL;
    vbl_vl_store* s = calloc(1, sizeof *s);
    if (!s) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (%s store)", ctx->scene->path, kernel->name);
    s->kernel = kernel;
    s->samples = 1;
    s->connect = ctx->tracking;
    vbl_result r = kernel->begin(ctx, settings, s);
    if (r) {
        free(s);
        return r;
    }
    /* one trace for the beams and the VBLs: beams need k + 1 <= M, the VBLs skip k + 2 > M */
    r = s->beams_direct ? vbl_photon_beams_trace(ctx, s->trace.long_vrls, &s->photons)
                        : vbl_photon_trace_with_surfaces(ctx, &s->trace, ctx->scene->surfaces != NULL, &s->photons);
    if (r) {
        free(s);
        return r;
    }
    /* the cost model's count of the pass's store (core/work_count.h; the hybrid pilot reads it) */
    vbl_work_add(VBL_WORK_STORE_LIGHT, s->photons.vrl_count + s->photons.vpl_count + s->photons.surface_vsl_count);
    if (kernel->after_trace) r = kernel->after_trace(ctx, s);
    if (!r && s->select > 0) r = vbl_vrl_select_tree_build(ctx, &s->photons, &s->tree);
    if (r || (r = vbl_surface_gather_blue_noise_begin(ctx, &s->gather))) { /* render.vsl_placement */
        vbl_vl_pass_end(ctx, s);
        return r;
    }
    *store = s;
    return VBL_SUCCESS;
}

const vbl_photon_store* vbl_vl_photons(const void* store)
{
    return store ? &((const vbl_vl_store*)store)->photons : NULL;
}

vbl_photon_store* vbl_vl_photons_mutable(void* store)
{
    return store ? &((vbl_vl_store*)store)->photons : NULL;
}

vbl_surface_gather_settings* vbl_vl_gather_settings(void* store)
{
    return store ? &((vbl_vl_store*)store)->gather : NULL;
}

int vbl_vl_camera_cache(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts, vbl_vec3 origin,
                        vbl_vec3 direction, double t_max, vbl_rng* rng, vbl_vl_camera* out)
{
    const vbl_vl_store* s = store;
    double u0, u1;
    if (ctx->extinction->count == 0 || !(t_max > 0.0) ||
        !vbl_extinction_ray_bounds(ctx->extinction, origin, direction, 0.0, t_max, &u0, &u1) || !(u1 > u0))
        return 0;
    out->ray = vbl_segment_make(origin, direction, u0, u1);
    vbl_transmittance_estimator kind = ctx->options.transmittance == VBL_TRANSMITTANCE_CACHED_DELTA
                                           ? VBL_TRANSMITTANCE_CACHED_DELTA
                                           : VBL_TRANSMITTANCE_CACHED_RATIO;
    vbl_transmittance_cache_build_rr(&out->cache, kind, ctx->extinction, &ts->cursor, origin, direction, u0, u1, 16,
                                     ctx->tracking.use_global_majorant, s->camera_rr, rng);
    return 1;
}

/* One selected piece (vbl_vrl_tree_select) through the kernel (user: the vbl_vl_gather). */
static void vbl_vl_visit_piece(const vbl_vrl_tree_piece* pc, double weight, void* user)
{
    const vbl_vl_gather* g = user;
    vbl_work_add(VBL_WORK_LIGHT_EVAL, 1);
    g->s->kernel->estimate(g, (size_t)pc->vrl, pc->v0, pc->v1, weight);
}

/* volume_from_volume along the camera segment: K lights from the tree, or every light of the pass
 * (bounce k counts when k + scatter_offset <= max_bounces) with distance roulette for segments:
 * with h the distance between the camera and light segments, a light is kept with probability
 * q = clamp(rr_distance / h, rr_min_probability, 1) and divided by q (unbiased). */
static void vbl_vl_gather_lights(const vbl_vl_gather* g)
{
    const vbl_render_context* ctx = g->ctx;
    const vbl_vl_store* s = g->s;
    const vbl_vl_kernel* k = s->kernel;
    const vbl_vl_camera* cam = g->cam;
    const vbl_vec3 d = cam->ray.direction;
    const double u0 = cam->ray.t0, u1 = cam->ray.t1;
    const vbl_vec3 cam_start = vbl_v3_madd(cam->ray.origin, d, u0);
    const int M = ctx->options.max_bounces;
    if (s->select > 0) {
        /* K draws from the light tree (vrl_tree.h), each weighted 1 / (K pdf): unbiased */
        vbl_vrl_tree_query q = {cam_start, d,
                                vbl_vrl_tree_visible_length(&cam->cache, u0, u1, VBL_VRL_SELECT_VISIBLE_CUT), &cam->cache,
                                u0, VBL_VRL_SELECT_VISIBLE_CUT};
        vbl_vrl_tree_select(&s->tree, &q, s->select, k->weight_per_sample ? s->samples : 1.0, g->rng,
                            vbl_vl_visit_piece, (void*)g);
        return;
    }
    const size_t n = k->points ? s->photons.vpl_count : s->photons.vrl_count;
    vbl_work_add(VBL_WORK_LIGHT_EVAL, n);
    for (size_t j = 0; j < n; ++j) {
        if (j % VBL_STOP_CHECK_EVERY == VBL_STOP_CHECK_EVERY - 1 && vbl_render_stop_requested(ctx)) break;
        if (k->points) {
            if (M >= 0 && s->photons.vpls[j].bounce + k->scatter_offset > M) continue;
            k->estimate(g, j, 0.0, 0.0, 1.0);
            continue;
        }
        const vbl_vrl* l = &s->photons.vrls[j];
        if (M >= 0 && l->bounce + k->scatter_offset > M) continue;
        double weight = k->weight_per_sample ? 1.0 / s->samples : 1.0;
        if (s->rr_distance > 0.0) {
            double h = vbl_segment_distance(cam_start, d, u1 - u0, l->origin, l->direction, l->length);
            double q = h > s->rr_distance ? s->rr_distance / h : 1.0;
            if (q < s->rr_min_probability) q = s->rr_min_probability;
            if (q < 1.0) {
                if (vbl_rng_uniform(g->rng) >= q) continue;
                weight /= q;
            }
        }
        k->estimate(g, j, 0.0, l->length, weight);
    }
}

/* The classes a camera sample takes from pt (vbl_pt_camera_classes): the single-scattering ones,
 * less volume_direct where the bounce-0 photon beams give it. */
static unsigned vbl_vl_pt_classes(const vbl_vl_store* s)
{
    unsigned from_pt = VBL_PT_SINGLE_SCATTER_CLASSES;
    if (s && s->beams_direct) from_pt &= ~(1u << VBL_CLASS_VOLUME_DIRECT);
    return from_pt;
}

int vbl_vl_camera_aovs(const vbl_render_context* ctx, const void* store)
{
    return vbl_pt_camera_classes_aovs(ctx, vbl_vl_pt_classes(store));
}

void vbl_vl_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                          const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_vl_store* s = store;
    const vbl_scene* scene = ctx->scene;
    const vbl_vec3 o = sample->origin, d = sample->direction;
    const int beams_direct = s && s->beams_direct; /* then the bounce-0 beams are its volume_direct */
    /* emission, volume_emission and volume_direct: pt's estimator (pt_camera_classes.h) */
    vbl_pt_camera_classes(ctx, ts, sample, vbl_vl_pt_classes(s), rng, out);
    if (scene->has_emission && scene->surfaces && vbl_ctx_wants(ctx, VBL_CLASS_SURFACE_DIRECT)) {
        /* the emissive media's surface_direct (emission_estimate.h); its volume_emission is pt's */
        vbl_sample_value e;
        memset(&e, 0, sizeof e);
        vbl_camera_media_emission(ctx, ts, sample, VBL_EMISSION_DIRECT_SURFACE, rng, &e);
        out->L[VBL_CLASS_SURFACE_DIRECT] = vbl_v3_add(out->L[VBL_CLASS_SURFACE_DIRECT], e.L[VBL_CLASS_SURFACE_DIRECT]);
    }
    if (scene->surfaces && s) vbl_surface_gather_hit(ctx, ts, &s->photons, &s->gather, sample, rng, out);
    const size_t lights = s ? (s->kernel->points ? s->photons.vpl_count : s->photons.vrl_count) : 0;
    if (!s || (lights == 0 && s->photons.surface_vsl_count == 0 && !s->gather.blue_noise)) return;
    /* render.hybrid: with every media class of the camera segment owned by pt, no segment work */
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_VOLUME) && !vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_SURFACE) &&
        !(beams_direct && vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_DIRECT)))
        return;

    vbl_vl_camera cam; /* one camera-ray cache for the surface gathers, the beams and the lights */
    if (!vbl_vl_camera_cache(ctx, s, ts, o, d, sample->t_max, rng, &cam)) return;
    const double u0 = cam.ray.t0, u1 = cam.ray.t1;
    vbl_surface_gather_segment(ctx, ts, &s->photons, &s->gather, sample, &cam.cache, u0, u1, rng, out);
    if (beams_direct) vbl_photon_beam_gather_eval_cached(ctx, s->beams, ts, &cam.cache, o, d, u0, u1, out);
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_VOLUME)) return; /* render.hybrid: pt owns it */
    vbl_step_pdf camera_pdf;
    const vbl_step_pdf* camera =
        s->camera_mis && vbl_vrl_camera_step_pdf(&cam.cache, u0, u1, &camera_pdf) ? &camera_pdf : NULL;
    vbl_vec3 acc = vbl_v3(0.0, 0.0, 0.0);
    const vbl_vl_gather g = {ctx, s, ts, &cam, camera, rng, &acc};
    vbl_vl_gather_lights(&g);
    out->L[VBL_CLASS_VOLUME_FROM_VOLUME] = vbl_v3_add(out->L[VBL_CLASS_VOLUME_FROM_VOLUME], acc);
}
