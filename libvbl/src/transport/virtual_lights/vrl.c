/* Virtual ray lights along camera rays: the ray kernel (vrl.h, virtual_lights_kernel.h). */
#include "transport/virtual_lights/vrl.h"

#include <string.h>

#include "core/error.h"
#include "transport/common/radius_schedule.h"
#include "sampling/vrl_camera_mis.h"
#include "sampling/vrl_pair.h"
#include "sampling/vrl_tc_pair.h"
#include "media/medium.h"
#include "transport/common/light_emission.h"
#include "transport/virtual_lights/virtual_lights_kernel.h"

static vbl_result vbl_vrl_begin(const vbl_render_context* ctx, const void* settings_, vbl_vl_store* s)
{
    const vbl_vrl_settings* settings = settings_;
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
    s->ray = *settings;
    s->samples = settings->samples;
    s->select = settings->select;
    s->camera_mis = settings->camera_mis;
    s->camera_rr = settings->transmittance_rr;
    s->rr_min_probability = settings->rr_min_probability;
    vbl_medium_point media;
    vbl_medium_point_scene(scene, &media);
    s->g_camera = vbl_medium_mean_g(&media); /* the camera samplers' hint */
    vbl_vec3 center;
    double radius = 0.0;
    if (settings->rr_radius > 0.0 && vbl_media_bounding_sphere(scene, &center, &radius))
        s->rr_distance = settings->rr_radius * radius;
    s->connect.rr_threshold = settings->transmittance_rr;
    if (settings->connect_marching) {
        s->connect.estimator = VBL_TRANSMITTANCE_RAY_MARCHING;
        s->connect.march_step = settings->march_step;
    }
    vbl_vl_trace_segments(ctx, s, settings->long_vrls);
    return VBL_SUCCESS;
}

static vbl_result vbl_vrl_after_trace(const vbl_render_context* ctx, vbl_vl_store* s)
{
    const vbl_scene* scene = ctx->scene;
    s->gather.vrls = 1;
    s->gather.kernel_samples = VBL_SURFACE_KERNEL_SAMPLES_DEFAULT;
    s->gather.g_camera = s->g_camera;
    if (scene->surfaces) {
        const double alpha = s->ray.surface_alpha > 0.0 ? s->ray.surface_alpha : VBL_RADIUS_ALPHA_DEFAULT;
        double r0 = s->ray.surface_radius0 > 0.0 ? s->ray.surface_radius0
                                                 : vbl_surface_vsl_default_r0(scene, s->photons.surface_vsl_count);
        s->gather.vsl_radius = vbl_radius_at_pass(r0, alpha, 2, ctx->pass);
    }
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
    out->camera_mis = (int)o->vrl.pair_sampler;
}

static vbl_result vbl_vrl_pass_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings settings;
    vbl_vrl_settings_from_options(&ctx->options, &settings);
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &settings, store);
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

/* One (u, v) draw of the pair by the store's sampler (vrl.pair_sampler): the product sampler
 * (2 uniforms, as before the option), or with a camera density one-sample MIS with the camera
 * technique (camera_mis 1, vrl_camera_mis.h) or the Tc x 1/distance technique (2, vrl_tc_pair.h;
 * 3: its free-flight form, sigma_t Tc x 1/distance from the cache's drops). */
static int vbl_vrl_draw(const vbl_vl_store* s, const vbl_vrl_pair* pair, const vbl_step_pdf* camera, vbl_rng* rng,
                        vbl_vrl_pair_sample* ps)
{
    double xi1 = vbl_rng_uniform(rng), xi2 = vbl_rng_uniform(rng);
    if (camera && s->camera_mis >= VBL_VRL_PAIR_TRANSMITTANCE) {
        vbl_vrl_tc_marginal m;
        vbl_vrl_tc_marginal_init(&m, pair, camera, s->camera_mis == VBL_VRL_PAIR_FREE_FLIGHT);
        return vbl_vrl_tc_pair_draw(pair, &m, vbl_rng_uniform(rng), xi1, xi2, ps);
    }
    if (camera) return vbl_vrl_camera_mis_draw(pair, camera, vbl_rng_uniform(rng), xi1, xi2, ps);
    return vbl_vrl_pair_draw(pair, xi1, xi2, ps) && ps->pdf > 0.0;
}

/* Adds one VRL's estimate of eq 7 over its part v in [v0, v1] (samples draws of the pair sampler) times `weight` to *g->acc. */
static void vbl_vrl_estimate(const vbl_vl_gather* g, const vbl_vrl* l, double v0, double v1, double weight)
{
    const vbl_render_context* ctx = g->ctx;
    const vbl_vl_store* s = g->s;
    vbl_thread_state* ts = g->ts;
    const vbl_step_pdf* camera = g->camera;
    const vbl_transmittance_cache* cache = &g->cam->cache;
    const vbl_vec3 o = g->cam->ray.origin, d = g->cam->ray.direction;
    vbl_rng* rng = g->rng;
    vbl_vec3* acc = g->acc;
    const vbl_scene* scene = ctx->scene;
    const int S = s->samples;
    vbl_medium_point mu, mv;
    vbl_vrl_pair pair;
    const vbl_segment light = vbl_segment_make(l->origin, l->direction, v0, v1);
    if (!vbl_vrl_pair_init(&pair, &g->cam->ray, &light, s->g_camera, l->g)) return;
    for (int k = 0; k < S; ++k) {
        vbl_vrl_pair_sample ps;
        if (!vbl_vrl_draw(s, &pair, camera, rng, &ps)) continue;
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

static void vbl_vrl_estimate_light(const vbl_vl_gather* g, size_t j, double v0, double v1, double weight)
{
    vbl_vrl_estimate(g, &g->s->photons.vrls[j], v0, v1, weight);
}

const vbl_vl_kernel vbl_vl_kernel_ray = {"vrl", 0, 2, 1, vbl_vrl_begin, vbl_vrl_after_trace, vbl_vrl_estimate_light};

int vbl_vrl_contributions(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                          const vbl_camera_sample* sample, vbl_rng* rng, double* contribution, double* visible,
                          double* pdf)
{
    const vbl_vl_store* s = store;
    const int M = ctx->options.max_bounces;
    for (size_t j = 0; s && j < s->photons.vrl_count; ++j) contribution[j] = 0.0;
    *visible = 0.0;
    vbl_vl_camera cam;
    if (!s || !vbl_vl_camera_cache(ctx, s, ts, sample->origin, sample->direction, sample->t_max, rng, &cam)) return 0;
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
        s->camera_mis && vbl_vrl_camera_step_pdf(cache, u0, u1, &camera_pdf) ? &camera_pdf : NULL;
    for (size_t j = 0; j < s->photons.vrl_count; ++j) {
        const vbl_vrl* l = &s->photons.vrls[j];
        if (M >= 0 && l->bounce + 2 > M) continue;
        vbl_vec3 acc = vbl_v3(0.0, 0.0, 0.0);
        const vbl_vl_gather g = {ctx, s, ts, &cam, camera, rng, &acc};
        vbl_vrl_estimate(&g, l, 0.0, l->length, 1.0);
        contribution[j] = acc.x + acc.y + acc.z;
    }
    return 1;
}

int vbl_vrl_sample_factors(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts, size_t vrl,
                           const vbl_vl_camera* cam, vbl_rng* rng, vbl_vrl_factors* out)
{
    const vbl_vl_store* s = store;
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
    vbl_vrl_pair_sample ps;
    vbl_step_pdf camera;
    const int has_camera = s->camera_mis && vbl_vrl_camera_step_pdf(cache, u0, u1, &camera);
    if (!vbl_vrl_draw(s, &pair, has_camera ? &camera : NULL, rng, &ps)) return 0;
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

const vbl_estimator vbl_estimator_vrl = {"vrl", 1, vbl_vrl_pass_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};
