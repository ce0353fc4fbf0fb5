/* Virtual beam lights, media-to-media: the beam kernel (virtual_beam_lights.h,
 * virtual_lights_kernel.h). */
#include "transport/virtual_lights/virtual_beam_lights.h"

#include "core/error.h"
#include "media/medium.h"
#include "transport/common/radius_schedule.h"
#include "sampling/beam_light_pair.h"
#include "transport/common/light_emission.h"
#include "transport/photon_beams/photon_beams.h"
#include "transport/virtual_lights/virtual_lights_kernel.h"
#include "sampling/vrl_pair.h"
#include "sampling/vsl_cone.h"

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

static vbl_result vbl_beam_light_begin(const vbl_render_context* ctx, const void* settings_, vbl_vl_store* s)
{
    const vbl_beam_light_settings* settings = settings_;
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
    if (settings->beams_single_scattering && !(settings->beams_alpha > 0.0 && settings->beams_alpha <= 1.0))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: beams alpha = %g is outside (0, 1]", scene->path,
                         settings->beams_alpha);
    s->beam.settings = *settings;
    s->samples = settings->samples;
    s->select = settings->select;
    s->beams_direct = settings->beams_single_scattering;
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
    s->beam.thin_sin = vbl_vsl_thin_cone_sin(g_max, settings->kernel_tolerance);
    vbl_vl_trace_segments(ctx, s, settings->long_vrls);
    return VBL_SUCCESS;
}

static vbl_result vbl_beam_light_after_trace(const vbl_render_context* ctx, vbl_vl_store* s)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_beam_light_settings* settings = &s->beam.settings;
    const int M = ctx->options.max_bounces;
    /* R_0 when none is given: radius_schedule.h's k sqrt(V / L) over the cube inscribed in the
     * media's bounding sphere and this pass's total length of the VRLs the VBLs use */
    double r0 = settings->radius0 > 0.0 ? settings->radius0 : vbl_beam_light_default_radius(scene, &s->photons, M);
    s->beam.radius = vbl_radius_at_pass(r0, settings->alpha, 2, ctx->pass);
    /* optical units: the same eq-11 factor s_p = R_p / R_0 on f / sigma_t(x) */
    const double shrink = vbl_radius_at_pass(1.0, settings->alpha, 2, ctx->pass);
    s->beam.radius_mfp = settings->radius_mfp > 0.0 && isfinite(settings->radius_mfp) ? settings->radius_mfp * shrink : 0.0;
    s->beam.sampler_radius = s->beam.radius;
    if (s->beam.radius_mfp > 0.0 && ctx->extinction->max_sigma_t > 0.0)
        s->beam.sampler_radius = fmin(s->beam.radius, s->beam.radius_mfp / ctx->extinction->max_sigma_t);
    s->gather.vrls = 1;
    s->gather.vrl_radius = s->beam.radius; /* surface_from_volume: VBL eqs 8-9 with R_p */
    s->gather.kernel_samples = VBL_SURFACE_KERNEL_SAMPLES_DEFAULT;
    s->gather.g_camera = s->g_camera;
    if (scene->surfaces) /* surface VSLs: their own R_0 (surface density), the same eq 11 alpha */
        s->gather.vsl_radius = vbl_radius_at_pass(vbl_surface_vsl_default_r0(scene, s->photons.surface_vsl_count),
                                                  settings->alpha, 2, ctx->pass);
    if (settings->beams_single_scattering && M != 0) {
        double b0 = settings->beams_radius0 > 0.0 ? settings->beams_radius0
                                                  : vbl_beams_default_radius(scene, &s->photons, M, 1, 1);
        s->beam.beam_radius = vbl_radius_at_pass(b0, settings->beams_alpha, 1, ctx->pass);
        return vbl_photon_beam_gather_build(ctx, &s->photons, s->beam.beam_radius, 1, 0, &s->beams);
    }
    return VBL_SUCCESS;
}

static double vbl_beam_light_radius_at(const vbl_vl_store* s, double sigma_t)
{
    return s->beam.radius_mfp > 0.0 && sigma_t > 0.0 ? fmin(s->beam.radius, s->beam.radius_mfp / sigma_t) : s->beam.radius;
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
static vbl_vec3 vbl_beam_light_pair_kernel(const vbl_vl_store* s, const vbl_medium_point* mu,
                                           const vbl_medium_point* mv, vbl_vec3 xu, vbl_vec3 d, vbl_vec3 xv,
                                           vbl_vec3 ld, double j1, double j2)
{
    const double R = vbl_beam_light_radius_at(s, mv->sigma_t);
    vbl_vsl_cone cone;
    if (!vbl_vsl_cone_init(&cone, vbl_v3_sub(xu, xv), R, vbl_v3_scale(d, -1.0))) return vbl_v3(0.0, 0.0, 0.0);
    const double cl = vbl_v3_dot(ld, cone.axis), cc = -vbl_v3_dot(cone.axis, d);
    int thin = cone.radius <= s->beam.thin_sin * cone.w;
    if (!thin && s->beam.settings.kernel_tolerance > 0.0 && cone.w > cone.radius) {
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
        thin = vbl_vsl_midpoint_error_bound(cone.half_angle, b1, b2) <= s->beam.settings.kernel_tolerance;
    }
    if (thin) {
        vbl_vec3 kv = vbl_medium_phase_kernel(mv, cl);
        vbl_vec3 ku = vbl_medium_phase_kernel(mu, cc);
        return vbl_v3_scale(vbl_v3_mul(kv, ku), cone.geometry);
    }
    return vbl_beam_light_kernel_sum(mu, mv, xu, d, xv, ld, R, s->beam.settings.kernel_samples, j1, j2);
}

/* Adds one VRL's VBL estimate over its part v in [v0, v1] (samples draws of the pair sampler) times
 * `weight` to *acc. A pair whose every VSL is thin from every camera point (R_p <= thin_sin x the
 * segments' distance, or R_p == 0: the VRL limit) draws (u, v) with the VRL sampler
 * (sampling/vrl_pair.h), which costs what vrl's does; the others with the two-stage VBL sampler at
 * the sampler radius (<= every VSL's radius, so pdf >= c K_R: bounded weights). */
static void vbl_beam_light_estimate(const vbl_render_context* ctx, const vbl_vl_store* s, vbl_thread_state* ts,
                             const vbl_vrl* l, double v0, double v1, vbl_vec3 o, vbl_vec3 d, double u0, double u1,
                             const vbl_transmittance_cache* cache, double weight, vbl_rng* rng, vbl_vec3* acc)
{
    const vbl_scene* scene = ctx->scene;
    const int S = s->beam.settings.samples;
    vbl_medium_point mu, mv;
    vbl_beam_light_pair pair;
    vbl_vrl_pair vpair;
    int thin = !(s->beam.radius > 0.0);
    if (!thin && s->beam.thin_sin > 0.0) {
        double h = vbl_segment_distance(vbl_v3_madd(o, d, u0), d, u1 - u0, vbl_v3_madd(l->origin, l->direction, v0),
                                        l->direction, v1 - v0);
        thin = s->beam.radius <= s->beam.thin_sin * h;
    }
    if (thin) {
        const vbl_segment camera = vbl_segment_make(o, d, u0, u1), light = vbl_segment_make(l->origin, l->direction, v0, v1);
        if (!vbl_vrl_pair_init(&vpair, &camera, &light, s->g_camera, l->g)) return;
    } else if (!vbl_beam_light_pair_init(&pair, o, d, u0, u1, l->origin, l->direction, v0, v1, s->g_camera, l->g,
                                         s->beam.sampler_radius)) {
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

static void vbl_beam_light_estimate_light(const vbl_vl_gather* g, size_t j, double v0, double v1, double weight)
{
    const vbl_vl_camera* cam = g->cam;
    vbl_beam_light_estimate(g->ctx, g->s, g->ts, &g->s->photons.vrls[j], v0, v1, cam->ray.origin, cam->ray.direction,
                            cam->ray.t0, cam->ray.t1, &cam->cache, weight, g->rng, g->acc);
}

const vbl_vl_kernel vbl_vl_kernel_beam = {"vbl", 0, 2, 0, vbl_beam_light_begin, vbl_beam_light_after_trace,
                                          vbl_beam_light_estimate_light};

static vbl_result vbl_beam_light_pass_begin(const vbl_render_context* ctx, void** store)
{
    vbl_beam_light_settings settings;
    vbl_beam_light_settings_from_options(&ctx->options, &settings);
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_beam, &settings, store);
}

const vbl_estimator vbl_estimator_vbl = {"vbl", 1, vbl_beam_light_pass_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};
