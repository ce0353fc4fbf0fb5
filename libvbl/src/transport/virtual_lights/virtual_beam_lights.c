/* Virtual beam lights, media-to-media (virtual_beam_lights.h). */
#include "transport/virtual_lights/virtual_beam_lights.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "media/medium.h"
#include "transport/common/radius_schedule.h"
#include "sampling/beam_light_pair.h"
#include "transport/common/emission_estimate.h"
#include "transport/common/light_emission.h"
#include "transport/photon_beams/photon_beams.h"
#include "transport/common/photon_trace.h"
#include "transport/common/single_scatter.h"
#include "transport/surface/surface_gather.h"
#include "transport/virtual_lights/vrl.h"
#include "transport/virtual_lights/vrl_tree.h"
#include "sampling/vrl_pair.h"
#include "sampling/vsl_cone.h"
#include "volume/transmittance_cache.h"

typedef struct vbl_beam_light_store {
    vbl_beam_light_settings settings;
    vbl_photon_store photons;
    double g_camera; /* HG g the sampler uses at camera points (any value is unbiased) */
    double radius;   /* R_p of this pass (world units): the cap of every VSL's radius */
    double radius_mfp; /* s_p x settings.radius_mfp (0: off): R_p(x) = min(radius, radius_mfp / sigma_t(x)) */
    double sampler_radius; /* the pair sampler's R: min(radius, radius_mfp / majorant) <= every R_p(x) */
    double thin_sin;  /* VSLs with R <= thin_sin w take the midpoint kernel (vbl_vsl_thin_cone_sin) */
    vbl_photon_beam_gather* beams; /* beams_single_scattering: bounce-0 photon beams */
    double beam_radius;
    vbl_surface_gather_settings gather; /* surfaces: VBL eqs 8-9 (R_p), surface VSLs (surface_gather.h) */
    vbl_vrl_tree tree;  /* settings.select > 0: the pass's light tree (vrl_tree.h) */
} vbl_beam_light_store;

void vbl_beam_light_settings_from_options(const vbl_render_options* o, vbl_beam_light_settings* out)
{
    vbl_beam_light_settings d = VBL_BEAM_LIGHT_SETTINGS_DEFAULT;
    *out = d;
    if (o->beam_lights.radius0 > 0.0) out->radius0 = o->beam_lights.radius0;
    if (o->beam_lights.alpha > 0.0) out->alpha = o->beam_lights.alpha;
    if (o->vrl.samples > 0) out->samples = o->vrl.samples;
    out->long_vrls = o->vrl.long_vrls != 0;
    out->beams_single_scattering =
        o->beam_lights.single_scattering == 0 ? VBL_BEAM_LIGHT_BEAMS_SINGLE_SCATTERING_DEFAULT : o->beam_lights.single_scattering == 2;
    if (o->beams.radius0 > 0.0) out->beams_radius0 = o->beams.radius0;
    if (o->beams.alpha > 0.0) out->beams_alpha = o->beams.alpha;
    out->select = o->vrl.select;
    if (o->beam_lights.radius_mfp > 0.0) out->radius_mfp = o->beam_lights.radius_mfp;
    out->kernel_tolerance = o->beam_lights.kernel_tolerance;
}

/* Default VSL radius R_0 of the vbl method. A VSL bounds the 1/w^2 falloff inside its radius (eq 9),
 * which removes part of the near-field energy, so unlike the photon-beam width R_0 must stay small
 * against the medium's features: the beam-density default (vbl_beams_default_radius), capped at
 * VBL_BEAM_LIGHT_RADIUS_CAP x the diameter of the media's bounding sphere. Measured on the sample cloud
 * (docs/readme/beams.md, 8 passes x 200 light paths): R_0 = 0.3 (0.1 x the diameter, the old
 * default) kept 30% of vrl's volume_from_volume; R_0 = 0.03 (0.01 x) kept 92-101% per channel. */
#define VBL_BEAM_LIGHT_RADIUS_CAP 0.01
static double vbl_beam_light_default_radius(const vbl_scene* scene, const vbl_photon_store* photons, int max_bounces)
{
    double r0 = vbl_beams_default_radius(scene, photons, max_bounces, 2, 0);
    vbl_vec3 c;
    double radius = 0.0;
    if (vbl_media_bounding_sphere(scene, &c, &radius) && radius > 0.0)
        r0 = fmin(r0, VBL_BEAM_LIGHT_RADIUS_CAP * 2.0 * radius);
    return r0;
}

vbl_result vbl_beam_light_pass_begin_with(const vbl_render_context* ctx, const vbl_beam_light_settings* settings, void** store)
{
    *store = NULL;
    const vbl_scene* scene = ctx->scene;
    if (settings->samples < 1 || settings->kernel_samples < 1)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vbl samples = %d and kernel samples = %d must be >= 1",
                         scene->path, settings->samples, settings->kernel_samples);
    if (!(settings->alpha > 0.0 && settings->alpha <= 1.0))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vbl alpha = %g is outside (0, 1]", scene->path,
                         settings->alpha);
    if (!(settings->radius0 <= 0.0 || isfinite(settings->radius0)))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vbl radius0 = %g is not finite", scene->path,
                         settings->radius0);
    if (settings->select < 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vbl select = %d must be >= 0", scene->path, settings->select);
    if (isnan(settings->radius_mfp))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vbl radius_mfp is not a number", scene->path);
    if (!(settings->kernel_tolerance >= 0.0 && settings->kernel_tolerance <= 1.0))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vbl kernel_tolerance = %g is outside [0, 1]", scene->path,
                         settings->kernel_tolerance);
    vbl_beam_light_store* s = calloc(1, sizeof *s);
    if (!s) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (vbl store)", scene->path);
    s->settings = *settings;
    double w = 0.0, g = 0.0;
    for (int i = 0; i < scene->media_count; ++i) {
        const vbl_medium* m = &scene->media[i];
        double wi = m->density_scale * (m->albedo.x + m->albedo.y + m->albedo.z);
        w += wi;
        g += wi * m->g;
    }
    s->g_camera = w > 0.0 ? g / w : 0.0;
    double g_max = 0.0;
    for (int i = 0; i < scene->media_count; ++i) g_max = fmax(g_max, fabs(scene->media[i].g));
    s->thin_sin = vbl_vsl_thin_cone_sin(g_max, settings->kernel_tolerance);
    if (settings->beams_single_scattering && !(settings->beams_alpha > 0.0 && settings->beams_alpha <= 1.0)) {
        free(s);
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: beams alpha = %g is outside (0, 1]", scene->path,
                         settings->beams_alpha);
    }
    const int M = ctx->options.max_bounces;
    vbl_result r;
    if (settings->beams_single_scattering) {
        /* one trace for both: beams need k + 1 <= M, the VBLs skip k + 2 > M below */
        r = vbl_photon_beams_trace(ctx, settings->long_vrls, &s->photons);
    } else {
        vbl_photon_settings ps;
        memset(&ps, 0, sizeof ps); /* fields added later stay 0 */
        ps.store_vrls = 1;
        ps.long_vrls = settings->long_vrls;
        ps.cache_kind = VBL_TRANSMITTANCE_CACHED_RATIO;
        ps.cache_entries = 16;
        if (ctx->options.transmittance == VBL_TRANSMITTANCE_CACHED_DELTA) ps.cache_kind = VBL_TRANSMITTANCE_CACHED_DELTA;
        r = vbl_photon_trace_with_surfaces(ctx, &ps, scene->surfaces != NULL, &s->photons);
    }
    if (r) {
        free(s);
        return r;
    }
    /* R_0 when none is given: radius_schedule.h's k sqrt(V / L) over the cube inscribed in the
     * media's bounding sphere and this pass's total length of the VRLs the VBLs use */
    double r0 = settings->radius0 > 0.0 ? settings->radius0 : vbl_beam_light_default_radius(scene, &s->photons, M);
    s->radius = vbl_radius_at_pass(r0, settings->alpha, 2, ctx->pass);
    /* optical units: the same eq-11 factor s_p = R_p / R_0 on f / sigma_t(x) */
    const double shrink = vbl_radius_at_pass(1.0, settings->alpha, 2, ctx->pass);
    s->radius_mfp = settings->radius_mfp > 0.0 && isfinite(settings->radius_mfp) ? settings->radius_mfp * shrink : 0.0;
    s->sampler_radius = s->radius;
    if (s->radius_mfp > 0.0 && ctx->extinction->max_sigma_t > 0.0)
        s->sampler_radius = fmin(s->radius, s->radius_mfp / ctx->extinction->max_sigma_t);
    s->gather.vrls = 1;
    s->gather.vrl_radius = s->radius; /* surface_from_volume: VBL eqs 8-9 with R_p */
    s->gather.kernel_samples = VBL_SURFACE_KERNEL_SAMPLES_DEFAULT;
    s->gather.g_camera = s->g_camera;
    if (scene->surfaces) /* surface VSLs: their own R_0 (surface density), the same eq 11 alpha */
        s->gather.vsl_radius = vbl_radius_at_pass(vbl_surface_vsl_default_r0(scene, s->photons.surface_vsl_count),
                                                  settings->alpha, 2, ctx->pass);
    if (settings->beams_single_scattering && M != 0) {
        double b0 = settings->beams_radius0 > 0.0 ? settings->beams_radius0
                                                  : vbl_beams_default_radius(scene, &s->photons, M, 1, 1);
        s->beam_radius = vbl_radius_at_pass(b0, settings->beams_alpha, 1, ctx->pass);
        r = vbl_photon_beam_gather_build(ctx, &s->photons, s->beam_radius, 1, 0, &s->beams);
        if (r) {
            vbl_photon_store_free(&s->photons);
            free(s);
            return r;
        }
    }
    if (settings->select > 0 && !r) r = vbl_vrl_select_tree_build(ctx, &s->photons, &s->tree);
    if (r || (r = vbl_surface_gather_blue_noise_begin(ctx, &s->gather))) { /* render.vsl_placement */
        vbl_vrl_tree_free(&s->tree);
        vbl_photon_beam_gather_free(s->beams);
        vbl_photon_store_free(&s->photons);
        free(s);
        return r;
    }
    *store = s;
    return VBL_SUCCESS;
}

static vbl_result vbl_beam_light_pass_begin(const vbl_render_context* ctx, void** store)
{
    vbl_beam_light_settings settings;
    vbl_beam_light_settings_from_options(&ctx->options, &settings);
    return vbl_beam_light_pass_begin_with(ctx, &settings, store);
}

void vbl_beam_light_pass_end(const vbl_render_context* ctx, void* store)
{
    (void)ctx;
    vbl_beam_light_store* s = store;
    if (!s) return;
    vbl_surface_gather_blue_noise_end(&s->gather);
    vbl_vrl_tree_free(&s->tree);
    vbl_photon_beam_gather_free(s->beams);
    vbl_photon_store_free(&s->photons);
    free(s);
}

const vbl_photon_store* vbl_beam_light_store_photons(const void* store)
{
    return store ? &((const vbl_beam_light_store*)store)->photons : NULL;
}

double vbl_beam_light_store_radius(const void* store)
{
    return store ? ((const vbl_beam_light_store*)store)->radius : 0.0;
}

static double vbl_beam_light_radius_at(const vbl_beam_light_store* s, double sigma_t)
{
    return s->radius_mfp > 0.0 && sigma_t > 0.0 ? fmin(s->radius, s->radius_mfp / sigma_t) : s->radius;
}

double vbl_beam_light_store_radius_at(const void* store, double sigma_t)
{
    return store ? vbl_beam_light_radius_at(store, sigma_t) : 0.0;
}

/* eq (10)'s sum_ij sigma_s,i(u) sigma_s,j(v) K_R(g_i, g_j) over the lobes of the two medium points
 * (RGB), by the cone quadrature. One lattice jitter for all pairs. */
static vbl_vec3 vbl_beam_light_kernel_sum(const vbl_medium_point* mu, const vbl_medium_point* mv, vbl_vec3 xu,
                                          vbl_vec3 d, vbl_vec3 xv, vbl_vec3 ld, double radius, int n, double j1,
                                          double j2)
{
    vbl_vec3 acc = vbl_v3(0.0, 0.0, 0.0);
    for (int i = 0; i < mu->count; ++i) {
        vbl_vec3 su = vbl_v3_scale(mu->lobe[i].albedo, mu->lobe[i].sigma_t);
        for (int j = 0; j < mv->count; ++j) {
            vbl_vec3 sv = vbl_v3_scale(mv->lobe[j].albedo, mv->lobe[j].sigma_t);
            double k = vbl_vsl_kernel(xu, d, mu->lobe[i].g, xv, ld, mv->lobe[j].g, radius, n, j1, j2);
            if (k > 0.0) acc = vbl_v3_madd(acc, vbl_v3_mul(su, sv), k);
        }
    }
    return acc;
}

/* The eq (10) factor sum_ij sigma_s,i sigma_s,j K_R at one pair of points, R = R_p(x_v) (optical):
 * the thin-cone midpoint (the VRL kernel times the cone's geometry) where its error bound
 * (beam_light_pair.h) is below settings.kernel_tolerance: at once where R <= thin_sin w (the global
 * bound), else by the bound local to this cone and these lobes; otherwise the cone quadrature. */
static vbl_vec3 vbl_beam_light_pair_kernel(const vbl_beam_light_store* s, const vbl_medium_point* mu,
                                           const vbl_medium_point* mv, vbl_vec3 xu, vbl_vec3 d, vbl_vec3 xv,
                                           vbl_vec3 ld, double j1, double j2)
{
    const double R = vbl_beam_light_radius_at(s, mv->sigma_t);
    vbl_vsl_cone cone;
    if (!vbl_vsl_cone_init(&cone, vbl_v3_sub(xu, xv), R, vbl_v3_scale(d, -1.0))) return vbl_v3(0.0, 0.0, 0.0);
    const double cl = vbl_v3_dot(ld, cone.axis), cc = -vbl_v3_dot(cone.axis, d);
    int thin = cone.radius <= s->thin_sin * cone.w;
    if (!thin && s->settings.kernel_tolerance > 0.0 && cone.w > cone.radius) {
        /* the local bound over this cone: each end's largest lobe bound (beam_light_pair.h) */
        double b1 = 0.0, b2 = 0.0, b1u = 0.0, b2u = 0.0, b1v = 0.0, b2v = 0.0, x1, x2;
        for (int i = 0; i < mu->count; ++i) {
            vbl_vsl_lobe_local_bounds(mu->lobe[i].g, cc, cone.sin_half, cone.cos_half, &x1, &x2);
            b1u = fmax(b1u, x1);
            b2u = fmax(b2u, x2);
        }
        for (int j = 0; j < mv->count; ++j) {
            vbl_vsl_lobe_local_bounds(mv->lobe[j].g, cl, cone.sin_half, cone.cos_half, &x1, &x2);
            b1v = fmax(b1v, x1);
            b2v = fmax(b2v, x2);
        }
        b1 = b1u + b1v;
        b2 = b2u + b2v;
        thin = vbl_vsl_midpoint_error_bound(cone.half_angle, b1, b2) <= s->settings.kernel_tolerance;
    }
    if (thin) {
        vbl_vec3 kv = vbl_medium_phase_kernel(mv, cl);
        vbl_vec3 ku = vbl_medium_phase_kernel(mu, cc);
        return vbl_v3_scale(vbl_v3_mul(kv, ku), cone.geometry);
    }
    return vbl_beam_light_kernel_sum(mu, mv, xu, d, xv, ld, R, s->settings.kernel_samples, j1, j2);
}

/* Adds one VRL's VBL estimate over its part v in [v0, v1] (samples draws of the pair sampler) times
 * `weight` to *acc. A pair whose every VSL is thin from every camera point (R_p <= thin_sin x the
 * segments' distance, or R_p == 0: the VRL limit) draws (u, v) with the VRL sampler
 * (sampling/vrl_pair.h), which costs what vrl's does; the others with the two-stage VBL sampler at
 * the sampler radius (<= every VSL's radius, so pdf >= c K_R: bounded weights). */
static void vbl_beam_light_estimate(const vbl_render_context* ctx, const vbl_beam_light_store* s, vbl_thread_state* ts,
                             const vbl_vrl* l, double v0, double v1, vbl_vec3 o, vbl_vec3 d, double u0, double u1,
                             const vbl_transmittance_cache* cache, double weight, vbl_rng* rng, vbl_vec3* acc)
{
    const vbl_scene* scene = ctx->scene;
    const int S = s->settings.samples;
    vbl_medium_point mu, mv;
    vbl_beam_light_pair pair;
    vbl_vrl_pair vpair;
    int thin = !(s->radius > 0.0);
    if (!thin && s->thin_sin > 0.0) {
        double h = vbl_segment_distance(vbl_v3_madd(o, d, u0), d, u1 - u0, vbl_v3_madd(l->origin, l->direction, v0),
                                        l->direction, v1 - v0);
        thin = s->radius <= s->thin_sin * h;
    }
    if (thin) {
        const vbl_segment camera = vbl_segment_make(o, d, u0, u1), light = vbl_segment_make(l->origin, l->direction, v0, v1);
        if (!vbl_vrl_pair_init(&vpair, &camera, &light, s->g_camera, l->g)) return;
    } else if (!vbl_beam_light_pair_init(&pair, o, d, u0, u1, l->origin, l->direction, v0, v1, s->g_camera, l->g,
                                         s->sampler_radius)) {
        return;
    }
    for (int k = 0; k < S; ++k) {
        double xi1 = vbl_rng_uniform(rng), xi2 = vbl_rng_uniform(rng);
        double j1 = vbl_rng_uniform(rng), j2 = vbl_rng_uniform(rng); /* the kernel's lattice jitter */
        double su, sv, pdf;
        if (thin) {
            vbl_vrl_pair_sample ps;
            if (!vbl_vrl_pair_draw(&vpair, xi1, xi2, &ps)) continue;
            su = ps.u, sv = ps.v, pdf = ps.pdf;
        } else {
            vbl_beam_light_pair_sample ps;
            if (!vbl_beam_light_pair_draw(&pair, xi1, xi2, &ps)) continue;
            su = ps.u, sv = ps.v, pdf = ps.pdf;
        }
        if (!(pdf > 0.0)) continue;
        vbl_vec3 xu = vbl_v3_madd(o, d, su), xv = vbl_v3_madd(l->origin, l->direction, sv);
        double Tc = vbl_transmittance_cache_eval(cache, su);
        if (!(Tc > 0.0)) continue;
        double Tl = vbl_vrl_transmittance(&s->photons, l, sv);
        if (!(Tl > 0.0)) continue;
        if (!(vbl_medium_query(scene, ctx->extinction, &ts->cursor, xv, &mv) > 0.0)) continue;
        if (!(vbl_medium_query(scene, ctx->extinction, &ts->cursor, xu, &mu) > 0.0)) continue;
        vbl_vec3 f = vbl_v3_mul(vbl_beam_light_pair_kernel(s, &mu, &mv, xu, d, xv, l->direction, j1, j2), l->power);
        if (!(vbl_v3_max_component(f) > 0.0)) continue;
        /* T along the connecting segment VSL centre -> camera point (w = 0: nothing to cross) */
        vbl_vec3 to = vbl_v3_sub(xu, xv);
        double w = vbl_v3_length(to);
        double Tw = w > 0.0 ? vbl_vrl_connect_transmittance(ctx, &ctx->tracking, ts, xv, vbl_v3_scale(to, 1.0 / w), w,
                                                            rng)
                            : 1.0;
        if (!(Tw > 0.0)) continue;
        *acc = vbl_v3_madd(*acc, f, Tc * Tl * Tw * weight / (S * pdf));
    }
}

/* One selected piece (vbl_vrl_tree_select) through vbl_beam_light_estimate. */
typedef struct vbl_beam_light_piece_visit {
    const vbl_render_context* ctx;
    const vbl_beam_light_store* s;
    vbl_thread_state* ts;
    vbl_vec3 o, d;
    double u0, u1;
    const vbl_transmittance_cache* cache;
    vbl_rng* rng;
    vbl_vec3* acc;
} vbl_beam_light_piece_visit;

static void vbl_beam_light_visit_piece(const vbl_vrl_tree_piece* pc, double weight, void* user)
{
    const vbl_beam_light_piece_visit* v = user;
    vbl_beam_light_estimate(v->ctx, v->s, v->ts, &v->s->photons.vrls[pc->vrl], pc->v0, pc->v1, v->o, v->d, v->u0, v->u1,
                            v->cache, weight, v->rng, v->acc);
}

void vbl_beam_light_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                           const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_beam_light_store* s = store;
    const vbl_scene* scene = ctx->scene;
    const vbl_vec3 o = sample->origin, d = sample->direction;
    const int M = ctx->options.max_bounces;
    vbl_add_visible_emission(ctx, ts, o, d, rng, out);
    const int beams_direct = s && s->settings.beams_single_scattering;
    vbl_camera_media_emission(ctx, ts, sample, (beams_direct ? 0 : VBL_EMISSION_DIRECT_VOLUME) | VBL_EMISSION_DIRECT_SURFACE,
                              rng, out); /* with beams_direct the fire's bounce-0 beams are its volume_direct */
    if (!beams_direct && M != 0 && vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_DIRECT))
        vbl_single_scatter_estimate_to(ctx, ts, o, d, sample->t_max, rng, &out->L[VBL_CLASS_VOLUME_DIRECT]);
    if (scene->surfaces && s) vbl_surface_gather_hit(ctx, ts, &s->photons, &s->gather, sample, rng, out);
    if (!s || (s->photons.vrl_count == 0 && s->photons.surface_vsl_count == 0 && !s->gather.blue_noise)) return;
    /* render.hybrid: with every media class of the camera segment owned by pt, no segment work */
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_VOLUME) && !vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_SURFACE) &&
        !(beams_direct && vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_DIRECT)))
        return;

    vbl_transmittance_cache cache; /* one camera-ray cache for the beams and the VBLs */
    double u0, u1;
    if (!vbl_camera_segment_cache_to(ctx, ts, o, d, sample->t_max, rng, &cache, &u0, &u1)) return;
    vbl_surface_gather_segment(ctx, ts, &s->photons, &s->gather, sample, &cache, u0, u1, rng, out);
    if (beams_direct) vbl_photon_beam_gather_eval_cached(ctx, s->beams, ts, &cache, o, d, u0, u1, out);
    vbl_vec3 acc = vbl_v3(0.0, 0.0, 0.0);
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_VOLUME)) return; /* render.hybrid: pt owns it */
    if (s->settings.select > 0) {
        /* K draws from the light tree (vrl_tree.h), each weighted 1 / (K pdf): unbiased */
        const int K = s->settings.select;
        vbl_vrl_tree_query q = {vbl_v3_madd(o, d, u0), d,
                                vbl_vrl_tree_visible_length(&cache, u0, u1, VBL_VRL_SELECT_VISIBLE_CUT), &cache, u0,
                                VBL_VRL_SELECT_VISIBLE_CUT};
        vbl_beam_light_piece_visit v = {ctx, s, ts, o, d, u0, u1, &cache, rng, &acc};
        vbl_vrl_tree_select(&s->tree, &q, K, 1.0, rng, vbl_beam_light_visit_piece, &v);
    } else {
        for (size_t j = 0; j < s->photons.vrl_count; ++j) {
            if (j % VBL_STOP_CHECK_EVERY == VBL_STOP_CHECK_EVERY - 1 && vbl_render_stop_requested(ctx)) break;
            const vbl_vrl* l = &s->photons.vrls[j];
            if (M >= 0 && l->bounce + 2 > M) continue;
            vbl_beam_light_estimate(ctx, s, ts, l, 0.0, l->length, o, d, u0, u1, &cache, 1.0, rng, &acc);
        }
    }
    out->L[VBL_CLASS_VOLUME_FROM_VOLUME] = vbl_v3_add(out->L[VBL_CLASS_VOLUME_FROM_VOLUME], acc);
}

const vbl_estimator vbl_estimator_vbl = {"vbl", 1, vbl_beam_light_pass_begin, vbl_beam_light_camera_sample, vbl_beam_light_pass_end};
