/* Progressive photon beams along camera rays (photon_beams.h). */
#include "transport/photon_beams/photon_beams.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/work_count.h"
#include "transport/common/radius_schedule.h"
#include "media/medium.h"
#include "transport/photon_beams/beam_bvh.h"
#include "transport/common/emission_estimate.h"
#include "transport/common/light_emission.h"
#include "transport/photon_beams/photon_beam_kernel.h"
#include "volume/transmittance_cache.h"

struct vbl_photon_beam_gather {
    const vbl_photon_store* photons; /* borrowed */
    vbl_beam* beams;                 /* the used VRLs, query radius sqrt(2) R */
    uint32_t* vrl_index;             /* beams[i] is photons->vrls[vrl_index[i]] */
    size_t count;
    vbl_beam_bvh bvh;
    double radius;                   /* kernel half-width R */
};

typedef struct vbl_photon_beams_store {
    vbl_photon_beams_settings settings;
    vbl_photon_store photons;
    vbl_photon_beam_gather* gather;
    double radius;
} vbl_photon_beams_store;

void vbl_photon_beams_settings_from_options(const vbl_render_options* o, vbl_photon_beams_settings* out)
{
    vbl_photon_beams_settings d = VBL_PHOTON_BEAMS_SETTINGS_DEFAULT;
    *out = d;
    if (o->beams.radius0 > 0.0) out->radius0 = o->beams.radius0;
    if (o->beams.alpha > 0.0) out->alpha = o->beams.alpha;
}

vbl_result vbl_photon_beams_trace(const vbl_render_context* ctx, int long_vrls, vbl_photon_store* out)
{
    /* photon_trace stores VRL k when k + 2 <= M and walks while a VRL can still be stored; with
     * M + 1 that is k + 1 <= M: every beam that can end one scattering event later at the camera. */
    vbl_render_context c = *ctx;
    if (c.options.max_bounces >= 0) c.options.max_bounces += 1;
    vbl_photon_settings ps;
    memset(&ps, 0, sizeof ps); /* fields added later stay 0 */
    ps.store_vrls = 1;
    ps.long_vrls = long_vrls;
    ps.cache_kind = VBL_TRANSMITTANCE_CACHED_RATIO;
    ps.cache_entries = 16;
    if (ctx->options.transmittance == VBL_TRANSMITTANCE_CACHED_DELTA) ps.cache_kind = VBL_TRANSMITTANCE_CACHED_DELTA;
    return vbl_photon_trace_with_surfaces(&c, &ps, c.scene->surfaces != NULL, out);
}

/* The beam BVH's stop hook: the render's cancel flag and time limit. */
static int vbl_beams_stop(void* user) { return vbl_render_stop_requested((const vbl_render_context*)user); }

static int vbl_beam_used(int bounce, int M, int extra) { return M < 0 || bounce + extra <= M; }

double vbl_beams_default_radius(const vbl_scene* scene, const vbl_photon_store* photons, int max_bounces, int extra,
                                int bounce0_only)
{
    vbl_vec3 c;
    double r = 0.0;
    if (!vbl_media_bounding_sphere(scene, &c, &r) || !(r > 0.0)) return 0.0;
    double h = r / sqrt(3.0), L = 0.0;
    for (size_t j = 0; j < photons->vrl_count; ++j)
        if (vbl_beam_used(photons->vrls[j].bounce, max_bounces, extra) && (!bounce0_only || photons->vrls[j].bounce == 0))
            L += photons->vrls[j].length;
    return vbl_radius_default_r0(vbl_v3(c.x - h, c.y - h, c.z - h), vbl_v3(c.x + h, c.y + h, c.z + h), L, 0.0);
}

void vbl_photon_beam_gather_free(vbl_photon_beam_gather* g)
{
    if (!g) return;
    vbl_beam_bvh_free(&g->bvh);
    free(g->beams);
    free(g->vrl_index);
    free(g);
}

vbl_result vbl_photon_beam_gather_build(const vbl_render_context* ctx, const vbl_photon_store* photons,
                                        double radius, int single_scattering, int multiple_scattering,
                                        vbl_photon_beam_gather** out)
{
    *out = NULL;
    const int M = ctx->options.max_bounces;
    vbl_photon_beam_gather* g = calloc(1, sizeof *g);
    if (!g) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (photon beams)", ctx->scene->path);
    g->photons = photons;
    g->radius = radius;
    if (!(radius > 0.0) || !isfinite(radius) || photons->vrl_count == 0) {
        *out = g; /* nothing to gather */
        return VBL_SUCCESS;
    }
    g->beams = malloc(photons->vrl_count * sizeof *g->beams);
    g->vrl_index = malloc(photons->vrl_count * sizeof *g->vrl_index);
    if (!g->beams || !g->vrl_index) {
        vbl_photon_beam_gather_free(g);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu photon beams", ctx->scene->path,
                         photons->vrl_count);
    }
    const double query = sqrt(2.0) * radius; /* the kernel's reach: |y_n|, |y_m| <= R */
    for (size_t j = 0; j < photons->vrl_count && j < UINT32_MAX; ++j) {
        const vbl_vrl* l = &photons->vrls[j];
        if (!vbl_beam_used(l->bounce, M, 1) || !(l->length > 0.0)) continue;
        if (l->bounce == 0 ? !single_scattering : !multiple_scattering) continue;
        vbl_beam* b = &g->beams[g->count];
        b->origin = l->origin;
        b->direction = l->direction;
        b->length = l->length;
        b->radius = query;
        g->vrl_index[g->count++] = (uint32_t)j;
    }
    vbl_beam_bvh_options bo;
    memset(&bo, 0, sizeof bo); /* the defaults */
    bo.stop = vbl_beams_stop;
    bo.stop_user = (void*)ctx;
    vbl_result r = vbl_beam_bvh_build(&g->bvh, g->beams, g->count, &bo);
    if (r) {
        vbl_photon_beam_gather_free(g);
        return r;
    }
    *out = g;
    return VBL_SUCCESS;
}

typedef struct vbl_gather_visit {
    const vbl_render_context* ctx;
    const vbl_photon_beam_gather* g;
    vbl_thread_state* ts;
    const vbl_transmittance_cache* cache;
    vbl_vec3 c_o, c_d; /* camera segment start (at u0) and direction */
    double u0, len_c;
    vbl_vec3 direct, multiple;
} vbl_gather_visit;

/* One beam piece: eq (38) with the piece's part of the kernel's passage. */
static void vbl_gather_piece(void* user, uint32_t beam, double t0, double t1)
{
    vbl_gather_visit* v = user;
    const vbl_photon_beam_gather* g = v->g;
    vbl_work_add(VBL_WORK_LIGHT_EVAL, 1);
    const vbl_vrl* l = &g->photons->vrls[g->vrl_index[beam]];
    vbl_photon_beam_eval_result e;
    vbl_vec3 b_o = vbl_v3_madd(l->origin, l->direction, t0);
    if (!vbl_photon_beam_eval(v->c_o, v->c_d, v->len_c, b_o, l->direction, t1 - t0, g->radius, &e)) return;
    double Tc = vbl_transmittance_cache_eval(v->cache, v->u0 + e.t_c);
    if (!(Tc > 0.0)) return;
    double Tb = vbl_vrl_transmittance(g->photons, l, t0 + e.t_b);
    if (!(Tb > 0.0)) return;
    vbl_medium_point mp; /* what scatters at x_c (media/medium.h) */
    vbl_vec3 x = vbl_v3_madd(v->c_o, v->c_d, e.t_c);
    if (!(vbl_medium_query(v->ctx->scene, v->ctx->extinction, &v->ts->cursor, x, &mp) > 0.0)) return;
    vbl_vec3 f = vbl_medium_phase_kernel(&mp, e.cos_scatter); /* sigma_s f at x_c: the mixture of the lobes */
    f = vbl_v3_scale(vbl_v3_mul(f, l->power), Tc * Tb * e.weight);
    if (!(vbl_v3_max_component(f) > 0.0)) return;
    if (l->bounce == 0) v->direct = vbl_v3_add(v->direct, f);
    else v->multiple = vbl_v3_add(v->multiple, f);
}

void vbl_photon_beam_gather_eval(const vbl_render_context* ctx, const vbl_photon_beam_gather* g, vbl_thread_state* ts,
                                 vbl_vec3 o, vbl_vec3 d, double t_max, vbl_rng* rng, vbl_sample_value* out)
{
    if (!g || g->count == 0) return;
    double u0, u1;
    vbl_transmittance_cache cache;
    if (!vbl_camera_segment_cache_to(ctx, ts, o, d, t_max, rng, &cache, &u0, &u1)) return;
    vbl_photon_beam_gather_eval_cached(ctx, g, ts, &cache, o, d, u0, u1, out);
}

void vbl_photon_beam_gather_eval_cached(const vbl_render_context* ctx, const vbl_photon_beam_gather* g,
                                        vbl_thread_state* ts, const vbl_transmittance_cache* cache, vbl_vec3 o,
                                        vbl_vec3 d, double u0, double u1, vbl_sample_value* out)
{
    if (!g || g->count == 0 || !(u1 > u0)) return;
    vbl_gather_visit v;
    v.ctx = ctx;
    v.g = g;
    v.ts = ts;
    v.cache = cache;
    v.c_o = vbl_v3_madd(o, d, u0);
    v.c_d = d;
    v.u0 = u0;
    v.len_c = u1 - u0;
    v.direct = vbl_v3(0.0, 0.0, 0.0);
    v.multiple = vbl_v3(0.0, 0.0, 0.0);
    vbl_beam_bvh_visit(&g->bvh, v.c_o, d, v.len_c, vbl_gather_piece, &v);
    out->L[VBL_CLASS_VOLUME_DIRECT] = vbl_v3_add(out->L[VBL_CLASS_VOLUME_DIRECT], v.direct);
    out->L[VBL_CLASS_VOLUME_FROM_VOLUME] = vbl_v3_add(out->L[VBL_CLASS_VOLUME_FROM_VOLUME], v.multiple);
}

/* ---- the `beams` method ------------------------------------------------------------------ */

vbl_result vbl_photon_beams_pass_begin_with(const vbl_render_context* ctx, const vbl_photon_beams_settings* settings,
                                            void** store)
{
    *store = NULL;
    const vbl_scene* scene = ctx->scene;
    if (!(settings->alpha > 0.0 && settings->alpha <= 1.0))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: beams alpha = %g is outside (0, 1]", scene->path,
                         settings->alpha);
    if (!(settings->radius0 <= 0.0 || isfinite(settings->radius0)))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: beams radius0 = %g is not finite", scene->path,
                         settings->radius0);
    vbl_photon_beams_store* s = calloc(1, sizeof *s);
    if (!s) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (beams store)", scene->path);
    s->settings = *settings;
    vbl_result r = vbl_photon_beams_trace(ctx, 0, &s->photons);
    if (!r) {
        vbl_work_add(VBL_WORK_STORE_LIGHT, s->photons.vrl_count); /* the cost model (core/work_count.h) */
        double r0 = settings->radius0 > 0.0 ? settings->radius0
                                            : vbl_beams_default_radius(scene, &s->photons, ctx->options.max_bounces, 1, 0);
        s->radius = vbl_radius_at_pass(r0, settings->alpha, 1, ctx->pass);
        r = vbl_photon_beam_gather_build(ctx, &s->photons, s->radius, settings->single_scattering,
                                         settings->multiple_scattering, &s->gather);
    }
    if (r) {
        vbl_photon_store_free(&s->photons);
        free(s);
        return r;
    }
    *store = s;
    return VBL_SUCCESS;
}

static vbl_result vbl_photon_beams_pass_begin(const vbl_render_context* ctx, void** store)
{
    vbl_photon_beams_settings settings;
    vbl_photon_beams_settings_from_options(&ctx->options, &settings);
    return vbl_photon_beams_pass_begin_with(ctx, &settings, store);
}

void vbl_photon_beams_pass_end(const vbl_render_context* ctx, void* store)
{
    (void)ctx;
    vbl_photon_beams_store* s = store;
    if (!s) return;
    vbl_photon_beam_gather_free(s->gather);
    vbl_photon_store_free(&s->photons);
    free(s);
}

double vbl_photon_beams_store_radius(const void* store)
{
    return store ? ((const vbl_photon_beams_store*)store)->radius : 0.0;
}

void vbl_photon_beams_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                                    const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_photon_beams_store* s = store;
    vbl_add_visible_emission(ctx, ts, sample->origin, sample->direction, rng, out);
    vbl_camera_media_emission(ctx, ts, sample, 0, rng, out); /* the fire's bounce-0 beams: its volume_direct */
    if (!s || ctx->options.max_bounces == 0) return;
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_DIRECT) && !vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_VOLUME))
        return; /* render.hybrid: pt owns both beam classes */
    vbl_photon_beam_gather_eval(ctx, s->gather, ts, sample->origin, sample->direction, sample->t_max, rng, out);
}

const vbl_estimator vbl_estimator_beams = {"beams", 1, vbl_photon_beams_pass_begin, vbl_photon_beams_camera_sample,
                                           vbl_photon_beams_pass_end, NULL};
