/* Surface classes of the virtual-light methods (surface_gather.h). */
#include "transport/surface/surface_gather.h"

#include <math.h>
#include <stdlib.h>

#include "transport/surface/blue_noise/gather.h"
#include "transport/surface/blue_noise/prepare.h"
#include "core/error.h"
#include "core/work_count.h"
#include "sampling/vsl_cone.h"
#include "scene/lights.h"
#include "media/medium.h"
#include "transport/surface/surface_caustics.h"
#include "transport/surface/surface_cone_kernel.h"
#include "transport/surface/surface_from_volume.h"
#include "transport/path_tracing/pt.h"
#include "transport/surface/surface_vsl.h"

/* Callback state: the render context plus the albedo mix (sigma_s / sigma_t, RGB) at the last
 * medium point the kernel asked about (the kernels take a scalar M). */
typedef struct gather_cb {
    const vbl_render_context* ctx;
    vbl_thread_state* ts;
    vbl_rng* rng;
    const vbl_photon_store* photons;
    const vbl_vrl* vrl;
    const vbl_transmittance_cache* cache;
    vbl_vec3 albedo;
    vbl_medium_point mp; /* the medium at the last point the kernels asked about */
} gather_cb;

/* sigma_t at p, the medium there (c->mp) and its sigma_t-weighted albedo. */
static double vbl_medium_at(gather_cb* c, vbl_vec3 p, vbl_vec3* albedo)
{
    double sigma_t = vbl_medium_query(c->ctx->scene, c->ctx->extinction, &c->ts->cursor, p, &c->mp);
    *albedo = vbl_v3(0.0, 0.0, 0.0);
    if (!(sigma_t > 0.0)) return 0.0;
    for (int i = 0; i < c->mp.count; ++i) *albedo = vbl_v3_madd(*albedo, c->mp.lobe[i].albedo, c->mp.lobe[i].sigma_t / sigma_t);
    return sigma_t;
}

/* T V from a (in the media or offset off a surface) to b (on a surface or in the media). */
static double vbl_tv(const gather_cb* c, vbl_vec3 a, vbl_vec3 b)
{
    vbl_vec3 to = vbl_v3_sub(b, a);
    double w = vbl_v3_length(to);
    if (!(w > 0.0)) return 0.0;
    return vbl_ctx_transmittance(c->ctx, c->ts, a, vbl_v3_scale(to, 1.0 / w), w, c->rng);
}

/* Start of a segment leaving a surface VSL at y (shading normal n) towards b. */
static vbl_vec3 vbl_vsl_origin(const vbl_render_context* ctx, vbl_vec3 y, vbl_vec3 n, vbl_vec3 b)
{
    return vbl_surface_spawn(ctx->scene->surfaces, y, n, vbl_v3_sub(b, y));
}

/* M(v) of a VRL point p seen from the surface point x (surface_from_volume.h). */
static double vbl_vrl_medium(void* user, double v, vbl_vec3 p, vbl_vec3 x)
{
    gather_cb* c = user;
    double sigma_t = vbl_medium_at(c, p, &c->albedo);
    if (!(sigma_t > 0.0)) return 0.0;
    double tl = vbl_vrl_transmittance(c->photons, c->vrl, v);
    if (!(tl > 0.0)) return 0.0;
    return sigma_t * tl * vbl_tv(c, p, x);
}

/* vbl_vrl_medium and the medium at p (surface_from_volume.h's mixture form). */
static double vbl_vrl_medium_mixture(void* user, double v, vbl_vec3 p, vbl_vec3 x, vbl_medium_point* mp)
{
    gather_cb* c = user;
    double m = vbl_vrl_medium(user, v, p, x);
    *mp = c->mp;
    return m;
}

/* T V between a surface VSL at y and the surface point x (surface_vsl.h's visibility). */
static double vbl_vsl_visibility(void* user, vbl_vec3 y, vbl_vec3 x)
{
    return vbl_tv((gather_cb*)user, y, x);
}

/* M(u) of the camera point x_u seen from the VSL at y: the segment runs from x_u (in the media)
 * to y, whose end vbl_ctx_occluded pulls back by the ray epsilon (y's own surface does not
 * block it). */
static double vbl_camera_medium(void* user, double u, vbl_vec3 xu, vbl_vec3 y)
{
    gather_cb* c = user;
    double sigma_t = vbl_medium_at(c, xu, &c->albedo);
    if (!(sigma_t > 0.0)) return 0.0;
    double tc = vbl_transmittance_cache_eval(c->cache, u);
    if (!(tc > 0.0)) return 0.0;
    return sigma_t * tc * vbl_tv(c, xu, y);
}

/* vbl_volume_from_vsl (surface_vsl.c) with the VSL's BRDF peak precomputed per pass
 * (photon_trace.c: vbl_material_max_direction costs ~400 BRDF evaluations, too much per VSL and
 * camera sample): the same sampler (hints at the peak and the horizon, target HG x the VSL's
 * f cos, cone maxima for R > 0), the same estimate Phi M(u) K_R / pdf(u). */
typedef struct camera_target {
    vbl_vec3 c_d;
    double g_camera, radius;
    const vbl_surface_vsl* vsl;
    const vbl_material* vm;
} camera_target;

static double vbl_camera_target(void* user, vbl_vec3 p)
{
    const camera_target* t = user;
    vbl_surface_lobe a = vbl_surface_lobe_phase(t->g_camera, vbl_v3_scale(t->c_d, -1.0));
    vbl_surface_lobe b = vbl_surface_lobe_sender(t->vm, t->vsl->normal, t->vsl->incident);
    vbl_vsl_cone cone;
    if (!vbl_vsl_cone_init(&cone, vbl_v3_sub(p, t->vsl->position), t->radius, t->vsl->normal)) return 0.0;
    return vbl_surface_lobe_max_in_cone(&a, &cone) * vbl_surface_lobe_max_in_cone(&b, &cone);
}

static vbl_vec3 vbl_gather_volume_from_vsl(const vbl_segment* camera, double g_camera, const vbl_surface_vsl* vsl,
                                           vbl_vec3 peak, const vbl_material* vm, const vbl_surface_kernel* kernel,
                                           gather_cb* cb, double xi, double* u_out)
{
    const vbl_vec3 c_o = camera->origin, c_d = camera->direction;
    const double u0 = camera->t0, u1 = camera->t1, r = kernel->radius;
    const int n = kernel->n;
    const double* jitter = kernel->jitter;
    vbl_vec3 zero = vbl_v3(0, 0, 0);
    vbl_surface_line_sampler s;
    if (!vbl_surface_line_init(&s, c_o, c_d, u0, u1, vsl->position, r)) return zero;
    double hints[2];
    int nh = 0;
    if (vbl_surface_line_angle_toward(&s, peak, &hints[nh])) ++nh;
    if (vbl_surface_line_angle_horizon(&s, vsl->normal, &hints[nh])) ++nh;
    camera_target t = {c_d, g_camera, r, vsl, vm};
    vbl_surface_line_fit(&s, hints, nh, vbl_camera_target, &t);
    double pdf = 0.0;
    double u = vbl_surface_line_sample(&s, xi, &pdf);
    *u_out = u;
    if (!(pdf > 0.0)) return zero;
    vbl_vec3 x = vbl_surface_line_point(&s, u);
    double m = vbl_camera_medium(cb, u, x, vsl->position);
    if (!(m > 0.0)) return zero;
    vbl_vec3 k;
    if (cb->ctx->scene->media_count > 1) {
        /* overlapping media: the phase at x is the sigma_s-weighted mixture of their HG lobes, one
         * kernel per lobe (g_camera is only the sampler's hint); the weights replace the albedo */
        k = vbl_v3(0.0, 0.0, 0.0);
        for (int i = 0; i < cb->mp.count; ++i)
            k = vbl_v3_add(k, vbl_v3_mul(vbl_medium_lobe_weight(&cb->mp, i),
                                         vbl_surface_vsl_kernel_medium(x, c_d, cb->mp.lobe[i].g, vsl, vm, r, n, jitter)));
        cb->albedo = vbl_v3(1.0, 1.0, 1.0);
    } else {
        k = vbl_surface_vsl_kernel_medium(x, c_d, g_camera, vsl, vm, r, n, jitter);
    }
    return vbl_v3_scale(vbl_v3_mul(vsl->power, k), m / pdf);
}

static int vbl_any(vbl_vec3 v) { return vbl_v3_max_component(v) > 0.0; }

/* One estimate of T along the camera ray up to t (the surface hit). */
static double vbl_camera_transmittance(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 o, vbl_vec3 d,
                                       double t, vbl_rng* rng)
{
    double t0, t1;
    if (ctx->extinction->count == 0 || !vbl_extinction_ray_bounds(ctx->extinction, o, d, 0.0, t, &t0, &t1) ||
        !(t1 > t0))
        return 1.0;
    return vbl_transmittance_estimate(ctx->extinction, &ts->cursor, o, d, t0, t1, &ctx->tracking, rng);
}

/* surface_direct: NEE to every light (pt's surface NEE without light selection and MIS). */
static vbl_vec3 vbl_surface_nee(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_surface_hit* hit,
                                vbl_vec3 wo, vbl_rng* rng)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_material* m = &scene->materials[hit->material];
    vbl_vec3 sum = vbl_v3(0.0, 0.0, 0.0);
    for (int i = 0; i < scene->light_count; ++i) {
        double u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng);
        vbl_light_sample ls;
        if (!vbl_light_sample_incident(&scene->lights[i], hit->position, u1, u2, &ls) || !vbl_any(ls.li) ||
            !(ls.pdf > 0.0))
            continue;
        if (!(vbl_v3_dot(ls.wi, hit->geometric_normal) > 0.0)) continue;
        double cos_i = vbl_v3_dot(ls.wi, hit->shading_normal);
        if (!(cos_i > 0.0)) continue;
        vbl_vec3 f = vbl_material_eval(m, hit->shading_normal, wo, ls.wi);
        if (!vbl_any(f)) continue;
        vbl_vec3 origin = vbl_surface_spawn(scene->surfaces, hit->position, hit->geometric_normal, ls.wi);
        double T = vbl_ctx_transmittance(ctx, ts, origin, ls.wi, ls.distance, rng);
        if (!(T > 0.0)) continue;
        sum = vbl_v3_madd(sum, vbl_v3_mul(f, ls.li), T * cos_i / ls.pdf);
    }
    return sum;
}

/* Levels of eq 6 extensions shaded with the virtual lights before pt continues. */
#define VBL_BN_RECURSION_DEPTH 8

/* vbl_bn_trace_fn over the scene's surfaces. */
static int vbl_bn_trace_surfaces(void* user, vbl_vec3 origin, vbl_vec3 dir, vbl_vec3* position, vbl_vec3* normal)
{
    const vbl_surfaces* s = user;
    vbl_surface_hit hit;
    if (!vbl_surfaces_intersect(s, origin, dir, 0.0, INFINITY, &hit)) return 0;
    *position = hit.position;
    *normal = hit.shading_normal;
    return 1;
}

/* vbl_bn_shading.transmittance: one estimate of T on the unoccluded segment a -> b (gather_cb). */
static double vbl_bn_segment_transmittance(void* user, vbl_vec3 a, vbl_vec3 b)
{
    const gather_cb* c = user;
    vbl_vec3 to = vbl_v3_sub(b, a);
    double w = vbl_v3_length(to);
    if (!(w > 0.0)) return 1.0;
    return vbl_camera_transmittance(c->ctx, c->ts, a, vbl_v3_scale(to, 1.0 / w), w, c->rng);
}

/* Eq 6's L_p: the light reflected towards `origin` by the first vertex y along `dir` when y is a
 * surface, from a pt path (max_bounces one less): the sub-path's surface_direct, _from_surface
 * and _from_volume classes (pt's free flight to y carries T(x, y)); its emission class is direct
 * light, its volume classes (a medium vertex before y) belong to other classes at x. */
static vbl_vec3 vbl_bn_path_extension(const vbl_render_context* ctx, vbl_thread_state* ts,
                                      const vbl_camera_sample* sample, vbl_vec3 origin, vbl_vec3 dir, vbl_rng* rng)
{
    const int M = ctx->options.max_bounces;
    vbl_render_context sub = *ctx;
    if (M >= 0) sub.options.max_bounces = M - 1;
    vbl_camera_sample cs = *sample;
    cs.origin = origin;
    cs.direction = dir;
    cs.t_max = INFINITY;
    vbl_sample_value v;
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) v.L[c] = vbl_v3(0.0, 0.0, 0.0);
    vbl_pt_camera_sample(&sub, NULL, ts, &cs, rng, &v);
    return vbl_v3_add(vbl_v3_add(v.L[VBL_CLASS_SURFACE_DIRECT], v.L[VBL_CLASS_SURFACE_FROM_SURFACE]),
                      v.L[VBL_CLASS_SURFACE_FROM_VOLUME]);
}

static vbl_vec3 vbl_bn_shade_next(const vbl_render_context* ctx, vbl_thread_state* ts,
                                  const vbl_surface_gather_settings* gs, const vbl_camera_sample* sample,
                                  vbl_vec3 origin, vbl_vec3 dir, vbl_rng* rng, int depth);

/* One blue-noise shading of sp, a surface point or (material NULL) a medium point: vbl_bn_gather
 * (eqs 3-9; with media both strategies carry an estimate of T(x, y)) plus, unless
 * render.vsl_path_extension is false (then w_v = 1 wherever a light covers y), eq 6's extension
 * on the gather's BSDF (phase) sample, weighted by f cos / pdf (1 - w_v): recursive
 * (vbl_bn_shade_next) in surfaces-only scenes with unlimited bounces below
 * VBL_BN_RECURSION_DEPTH levels, a pt path (vbl_bn_path_extension) otherwise. The caller
 * checked gs->blue_noise and max_bounces >= 2 (or unlimited). */
static vbl_vec3 vbl_bn_shade(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_surface_gather_settings* gs,
                             const vbl_camera_sample* sample, const vbl_bn_shading* sp, vbl_rng* rng, int depth)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_bn_prepared* bn = gs->blue_noise;
    double u[6];
    for (int i = 0; i < 6; ++i) u[i] = vbl_rng_uniform(rng);
    const int extend = ctx->options.vsl.path_extension != VBL_VSL_PATH_EXTENSION_OFF;
    vbl_bn_gather_result res;
    vbl_bn_gather(&bn->set, &bn->emission, sp, vbl_bn_trace_surfaces, (void*)scene->surfaces, u,
                  extend ? VBL_BN_N_MIN_DEFAULT : 0.0, extend ? VBL_BN_N_MAX_DEFAULT : 0.0, &res);
    if (!extend || !res.bsdf_hit || !(res.w_v < 1.0) || !(res.bsdf_pdf > 0.0)) return res.L;
    const vbl_vec3 origin = sp->material ? vbl_surface_spawn(scene->surfaces, sp->position, sp->geometric_normal,
                                                             res.bsdf_dir)
                                         : sp->position;
    const vbl_vec3 L = (ctx->extinction->count == 0 && ctx->options.max_bounces < 0 && depth < VBL_BN_RECURSION_DEPTH)
                           ? vbl_bn_shade_next(ctx, ts, gs, sample, origin, res.bsdf_dir, rng, depth + 1)
                           : vbl_bn_path_extension(ctx, ts, sample, origin, res.bsdf_dir, rng);
    return vbl_v3_madd(res.L, vbl_v3_mul(res.bsdf_f, L), res.cos_x * (1.0 - res.w_v) / res.bsdf_pdf);
}

/* surface_from_surface at the surface hit from the blue-noise lights (vbl_bn_shade). */
static vbl_vec3 vbl_surface_from_blue_noise(const vbl_render_context* ctx, vbl_thread_state* ts,
                                            const vbl_surface_gather_settings* gs, const vbl_camera_sample* sample,
                                            const vbl_surface_hit* hit, vbl_vec3 wo, vbl_rng* rng, int depth)
{
    const vbl_scene* scene = ctx->scene;
    const int M = ctx->options.max_bounces;
    if (!gs->blue_noise || (M >= 0 && M < 2)) return vbl_v3(0.0, 0.0, 0.0);
    gather_cb cb = {.ctx = ctx, .ts = ts, .rng = rng, .photons = NULL, .cache = NULL};
    vbl_bn_shading sp = {hit->position, hit->shading_normal, hit->geometric_normal, wo,
                         &scene->materials[hit->material],
                         vbl_surfaces_ray_epsilon(scene->surfaces, hit->position),
                         ctx->extinction->count > 0 ? vbl_bn_segment_transmittance : NULL, &cb, NULL, NULL, 0.0};
    return vbl_bn_shade(ctx, ts, gs, sample, &sp, rng, depth);
}

/* Eq 6's L_p the paper's way ("shade y first", section 4): the light the first surface point y
 * along dir reflects towards origin, estimated like the camera's shading point: next-event
 * estimation at y plus the virtual lights at y (light + BSDF sample, w_v) and, where w_v < 1,
 * the next extension. Used in surfaces-only scenes with unlimited bounces (the lights' fields
 * hold every bounce; with media y's surface_from_volume would need the VRLs/VPLs, with a bounce
 * limit each level would need one bounce less in the field): there pt takes over. Below
 * VBL_BN_RECURSION_DEPTH levels; deeper, pt continues (unbiased either way). */
static vbl_vec3 vbl_bn_shade_next(const vbl_render_context* ctx, vbl_thread_state* ts,
                                  const vbl_surface_gather_settings* gs, const vbl_camera_sample* sample,
                                  vbl_vec3 origin, vbl_vec3 dir, vbl_rng* rng, int depth)
{
    vbl_surface_hit y;
    if (!vbl_surfaces_intersect(ctx->scene->surfaces, origin, dir, 0.0, INFINITY, &y)) return vbl_v3(0.0, 0.0, 0.0);
    const vbl_vec3 wo = vbl_v3_scale(dir, -1.0);
    vbl_vec3 L = vbl_surface_nee(ctx, ts, &y, wo, rng);
    return vbl_v3_add(L, vbl_surface_from_blue_noise(ctx, ts, gs, sample, &y, wo, rng, depth));
}

/* vbl_bn_shading.medium_f at a delta-tracking collision (user: its vbl_medium_point): sigma_s p(cos)
 * / sigma_t, RGB, with the mixture of the lobes there. */
static vbl_vec3 vbl_bn_medium_f(void* user, double cos_theta)
{
    const vbl_medium_point* mp = user;
    return vbl_v3_scale(vbl_medium_phase_kernel(mp, cos_theta), 1.0 / mp->sigma_t);
}

/* volume_from_surface over the camera segment [u0, u1] from the blue-noise lights (libvbl's
 * extension of the paper to media, docs/readme/blue_noise.md): one delta-tracking collision x
 * on the segment (density sigma_t T, so int T sigma_s L_s du is estimated by sigma_s / sigma_t
 * L_s(x) at x, 0 without a collision), shaded by vbl_bn_shade with the phase function for the
 * BSDF (the extension is a pt path there: the scene has media). */
static vbl_vec3 vbl_volume_from_blue_noise(const vbl_render_context* ctx, vbl_thread_state* ts,
                                           const vbl_surface_gather_settings* gs, const vbl_camera_sample* sample,
                                           double u0, double u1, vbl_rng* rng)
{
    const vbl_scene* scene = ctx->scene;
    const int M = ctx->options.max_bounces;
    vbl_vec3 zero = vbl_v3(0.0, 0.0, 0.0);
    if (!gs->blue_noise || (M >= 0 && M < 2) || !(u1 > u0)) return zero;
    const vbl_segment camera = vbl_segment_make(sample->origin, sample->direction, u0, u1);
    vbl_medium_point mp;
    double t = 0.0;
    if (!vbl_medium_free_flight(scene, ctx->extinction, &ts->cursor, &camera, ctx->tracking.use_global_majorant, rng,
                                &t, &mp) ||
        !(mp.sigma_t > 0.0))
        return zero;
    gather_cb cb = {.ctx = ctx, .ts = ts, .rng = rng, .photons = NULL, .cache = NULL};
    const vbl_vec3 x = vbl_segment_at(&camera, t);
    vbl_bn_shading sp = {x, vbl_v3(0, 0, 1), vbl_v3(0, 0, 1), vbl_v3_scale(sample->direction, -1.0), NULL, 0.0,
                         vbl_bn_segment_transmittance, &cb, vbl_bn_medium_f, &mp, gs->g_camera};
    return vbl_bn_shade(ctx, ts, gs, sample, &sp, rng, 0);
}

static int vbl_bn_render_stop(void* user) { return vbl_render_stop_requested((const vbl_render_context*)user); }

vbl_result vbl_surface_gather_blue_noise_begin(const vbl_render_context* ctx, vbl_surface_gather_settings* gs)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_render_options* o = &ctx->options;
    gs->blue_noise = NULL;
    gs->blue_noise_mode = 0;
    if (o->vsl.placement != VBL_VSL_PLACEMENT_BLUE_NOISE || !scene->surfaces) return VBL_SUCCESS;
    gs->blue_noise_mode = 1;
    gs->blue_noise_volume = scene->media_count > 0; /* volume_from_surface too (measured, blue_noise.md) */
    const int M = o->max_bounces;
    if (M >= 0 && M < 2) return VBL_SUCCESS; /* no surface_from_surface */
    const size_t N = (size_t)(o->vsl.lights > 0 ? o->vsl.lights : VBL_VSL_LIGHTS_DEFAULT);
    vbl_rng rng = vbl_rng_make(o->seed ^ VBL_RNG_DOMAIN_BLUE_NOISE, ctx->pass, 0);
    uint64_t seeds[2];
    for (int i = 0; i < 2; ++i) {
        uint64_t hi = vbl_rng_next_u32(&rng);
        seeds[i] = (hi << 32) | vbl_rng_next_u32(&rng);
    }
    vbl_bn_prepare_options po = VBL_BN_PREPARE_DEFAULT;
    po.lights = N;
    po.placement.seed = seeds[0];
    po.placement.candidates = 10 * po.lights;
    po.photons.seed = seeds[1];
    po.photons.paths = 10 * N;
    po.photons.max_bounce = M >= 0 ? M - 2 : -1;
    po.photons.extinction = ctx->extinction;
    po.photons.use_global_majorant = ctx->tracking.use_global_majorant;
    po.stop = vbl_bn_render_stop; /* cancel, time limit: the driver drops the pass (issue #18) */
    po.stop_user = (void*)ctx;
    vbl_bn_prepared* bn = calloc(1, sizeof *bn);
    if (!bn) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (blue-noise lights)", scene->path);
    vbl_result r = vbl_bn_prepare(scene, &po, bn);
    if (!r) r = vbl_bn_prepared_to_radiance(bn);
    if (r) {
        vbl_bn_prepared_free(bn);
        free(bn);
        return r;
    }
    gs->blue_noise = bn;
    return VBL_SUCCESS;
}

void vbl_surface_gather_blue_noise_end(vbl_surface_gather_settings* gs)
{
    if (gs->blue_noise) {
        vbl_bn_prepared_free(gs->blue_noise);
        free(gs->blue_noise);
    }
    gs->blue_noise = NULL;
}

void vbl_surface_gather_hit(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_photon_store* photons,
                            const vbl_surface_gather_settings* gs, const vbl_camera_sample* sample, vbl_rng* rng,
                            vbl_sample_value* out)
{
    const vbl_scene* scene = ctx->scene;
    const int M = ctx->options.max_bounces;
    if (!scene->surfaces || !isfinite(sample->t_max) || M == 0) return;
    /* render.hybrid: the surface classes another estimator owns are skipped */
    const int want_direct = vbl_ctx_wants(ctx, VBL_CLASS_SURFACE_DIRECT);
    const int want_volume = vbl_ctx_wants(ctx, VBL_CLASS_SURFACE_FROM_VOLUME);
    const int want_surface = vbl_ctx_wants(ctx, VBL_CLASS_SURFACE_FROM_SURFACE);
    if (!want_direct && !want_volume && !want_surface) return;
    const vbl_vec3 o = sample->origin, d = sample->direction;
    vbl_surface_hit hit;
    if (!vbl_surfaces_intersect(scene->surfaces, o, d, 0.0, INFINITY, &hit)) return;
    double tcam = vbl_camera_transmittance(ctx, ts, o, d, hit.t, rng);
    if (!(tcam > 0.0)) return;
    const vbl_vec3 wo = vbl_v3_scale(d, -1.0);
    const vbl_material* m = &scene->materials[hit.material];
    const vbl_vec3 x = hit.position, n = hit.shading_normal;

    if (want_direct) {
        vbl_vec3 direct = vbl_surface_nee(ctx, ts, &hit, wo, rng);
        out->L[VBL_CLASS_SURFACE_DIRECT] = vbl_v3_madd(out->L[VBL_CLASS_SURFACE_DIRECT], direct, tcam);
    }
    if (!photons) return;

    const double clamp2 = gs->clamp_distance * gs->clamp_distance;
    const int nk = gs->kernel_samples > 0 ? gs->kernel_samples : VBL_SURFACE_KERNEL_SAMPLES_DEFAULT;
    gather_cb cb = {.ctx = ctx, .ts = ts, .rng = rng, .photons = photons, .cache = NULL};
    const int need_sp = (gs->vrls && photons->vrl_count) || (photons->surface_vsl_count && gs->vsl_radius > 0.0);
    vbl_surface_point sp;
    if (need_sp) vbl_surface_point_init(&sp, x, n, wo, m);

    /* surface_from_volume */
    vbl_vec3 from_volume = vbl_v3(0.0, 0.0, 0.0);
    vbl_medium_point lobes; /* several media: every lobe, weighted by density scale (the sampler's hint) */
    lobes.count = 0;
    if (gs->vrls && scene->media_count > 1) vbl_medium_point_scene(scene, &lobes);
    if (gs->vrls && want_volume) {
        vbl_work_add(VBL_WORK_LIGHT_EVAL, photons->vrl_count);
        for (size_t j = 0; j < photons->vrl_count; ++j) {
            if (j % VBL_STOP_CHECK_EVERY == VBL_STOP_CHECK_EVERY - 1 && vbl_render_stop_requested(ctx)) break;
            const vbl_vrl* l = &photons->vrls[j];
            if (M >= 0 && l->bounce + 2 > M) continue;
            vbl_surface_vrl sv = {l->origin, l->direction, l->length, l->power, l->g};
            cb.vrl = l;
            cb.albedo = vbl_v3(0.0, 0.0, 0.0);
            double xi = vbl_rng_uniform(rng);
            vbl_surface_kernel kernel = {gs->vrl_radius, nk, {0.0, 0.0, 0.0}};
            if (gs->vrl_radius > 0.0)
                for (int k = 0; k < 3; ++k) kernel.jitter[k] = vbl_rng_uniform(rng);
            vbl_vec3 e;
            if (scene->media_count > 1) {
                /* overlapping media: the phase at the VRL point is the mixture of their lobes there,
                 * the sampler fitted to the scene's lobes; the weights replace the albedo */
                e = vbl_surface_from_vrl_mixture(&sp, &sv, &kernel, &lobes, vbl_vrl_medium_mixture, &cb, xi);
                cb.albedo = vbl_v3(1.0, 1.0, 1.0);
            } else if (gs->vrl_radius > 0.0) {
                e = vbl_surface_from_vbl(&sp, &sv, &kernel, vbl_vrl_medium, &cb, xi, NULL, NULL);
            } else {
                e = vbl_surface_from_vrl(&sp, &sv, vbl_vrl_medium, &cb, xi, NULL, NULL);
            }
            from_volume = vbl_v3_add(from_volume, vbl_v3_mul(e, cb.albedo));
        }
    }
    if (gs->vpls && want_volume) {
        vbl_work_add(VBL_WORK_LIGHT_EVAL, photons->vpl_count);
        for (size_t j = 0; j < photons->vpl_count; ++j) {
            if (j % VBL_STOP_CHECK_EVERY == VBL_STOP_CHECK_EVERY - 1 && vbl_render_stop_requested(ctx)) break;
            const vbl_vpl* p = &photons->vpls[j];
            if (M >= 0 && p->bounce + 1 > M) continue;
            vbl_vec3 to = vbl_v3_sub(x, p->position);
            double w2 = vbl_v3_dot(to, to);
            if (!(w2 > 0.0)) continue;
            double w = sqrt(w2);
            vbl_vec3 omega = vbl_v3_scale(to, 1.0 / w); /* light travels VPL -> x */
            vbl_vec3 wi = vbl_v3_scale(omega, -1.0);
            double cos_i = vbl_v3_dot(wi, n);
            if (!(cos_i > 0.0) || !(vbl_v3_dot(wi, hit.geometric_normal) > 0.0)) continue;
            vbl_vec3 f = vbl_v3_mul(vbl_material_eval(m, n, wo, wi), vbl_vpl_intensity(scene, p, vbl_v3_dot(p->incident, omega)));
            if (!vbl_any(f)) continue;
            double T = vbl_ctx_transmittance(ctx, ts, p->position, omega, w, rng);
            if (!(T > 0.0)) continue;
            from_volume = vbl_v3_madd(from_volume, f, T * cos_i / (clamp2 > w2 ? clamp2 : w2));
        }
    }
    out->L[VBL_CLASS_SURFACE_FROM_VOLUME] = vbl_v3_madd(out->L[VBL_CLASS_SURFACE_FROM_VOLUME], from_volume, tcam);
    if (!want_surface) return;

    /* surface_from_surface. The caustic split (surface_caustics.h): at a receiver that is not
     * highly specular, light from a highly specular VSL comes from the caustic photons instead. */
    vbl_vec3 from_surface = vbl_v3(0.0, 0.0, 0.0);
    if (gs->blue_noise_mode) {
        from_surface = vbl_surface_from_blue_noise(ctx, ts, gs, sample, &hit, wo, rng, 0);
        out->L[VBL_CLASS_SURFACE_FROM_SURFACE] =
            vbl_v3_madd(out->L[VBL_CLASS_SURFACE_FROM_SURFACE], from_surface, tcam);
        return;
    }
    const int split = photons->caustics_active && !vbl_material_is_highly_specular(m);
    if (split && gs->caustics != VBL_SURFACE_CAUSTICS_SKIP) {
        double R = gs->caustic_radius > 0.0 ? gs->caustic_radius : photons->caustic_radius;
        from_surface = vbl_caustic_gather(&photons->caustics, x, n, wo, m, R, M);
    }
    if (photons->surface_vsl_count == 0) {
        out->L[VBL_CLASS_SURFACE_FROM_SURFACE] =
            vbl_v3_madd(out->L[VBL_CLASS_SURFACE_FROM_SURFACE], from_surface, tcam);
        return;
    }
    vbl_work_add(VBL_WORK_LIGHT_EVAL, photons->surface_vsl_count);
    if (gs->vsl_radius > 0.0) {
        /* K_R is evaluated about x; visibility runs from the VSL (offset off its surface) to x */
        for (size_t j = 0; j < photons->surface_vsl_count; ++j) {
            const vbl_surface_vsl* v = &photons->surface_vsls[j];
            double jitter[3] = {vbl_rng_uniform(rng), vbl_rng_uniform(rng), vbl_rng_uniform(rng)};
            if (split && vbl_material_is_highly_specular(&scene->materials[v->material])) continue;
            if (M >= 0 && v->bounce + 2 > M) continue; /* stores traced one event deeper (vbl + beams) */
            vbl_vec3 k = vbl_surface_vsl_kernel_surface(&sp, v, &scene->materials[v->material], gs->vsl_radius, nk,
                                                        jitter);
            if (!vbl_any(k)) continue;
            double t = vbl_vsl_visibility(&cb, vbl_vsl_origin(ctx, v->position, v->normal, x), x);
            if (!(t > 0.0)) continue;
            from_surface = vbl_v3_madd(from_surface, vbl_v3_mul(v->power, k), t);
        }
    } else {
        for (size_t j = 0; j < photons->surface_vsl_count; ++j) {
            const vbl_surface_vsl* v = &photons->surface_vsls[j];
            if (split && vbl_material_is_highly_specular(&scene->materials[v->material])) continue;
            if (M >= 0 && v->bounce + 2 > M) continue;
            vbl_vec3 to = vbl_v3_sub(x, v->position);
            double w2 = vbl_v3_dot(to, to);
            if (!(w2 > 0.0)) continue;
            vbl_vec3 omega = vbl_v3_scale(to, 1.0 / sqrt(w2));
            vbl_vec3 wi = vbl_v3_scale(omega, -1.0);
            double cos_x = vbl_v3_dot(wi, n), cos_y = vbl_v3_dot(omega, v->normal);
            if (!(cos_x > 0.0) || !(cos_y > 0.0) || !(vbl_v3_dot(wi, hit.geometric_normal) > 0.0)) continue;
            const vbl_material* vm = &scene->materials[v->material];
            vbl_vec3 f = vbl_v3_mul(vbl_material_eval(m, n, wo, wi), vbl_material_eval(vm, v->normal, omega, v->incident));
            if (!vbl_any(f)) continue;
            double t = vbl_vsl_visibility(&cb, vbl_vsl_origin(ctx, v->position, v->normal, x), x);
            if (!(t > 0.0)) continue;
            from_surface = vbl_v3_madd(from_surface, vbl_v3_mul(v->power, f), t * cos_x * cos_y /
                                                                               (clamp2 > w2 ? clamp2 : w2));
        }
    }
    out->L[VBL_CLASS_SURFACE_FROM_SURFACE] = vbl_v3_madd(out->L[VBL_CLASS_SURFACE_FROM_SURFACE], from_surface, tcam);
}

void vbl_surface_gather_segment(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_photon_store* photons,
                                const vbl_surface_gather_settings* gs, const vbl_camera_sample* sample,
                                const vbl_transmittance_cache* cache, double u0, double u1, vbl_rng* rng,
                                vbl_sample_value* out)
{
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_SURFACE)) return; /* render.hybrid */
    if (gs->blue_noise_mode && gs->blue_noise_volume) {
        vbl_vec3 e = vbl_volume_from_blue_noise(ctx, ts, gs, sample, u0, u1, rng);
        out->L[VBL_CLASS_VOLUME_FROM_SURFACE] = vbl_v3_add(out->L[VBL_CLASS_VOLUME_FROM_SURFACE], e);
        return;
    }
    if (!photons || photons->surface_vsl_count == 0 || !(u1 > u0)) return;
    const vbl_scene* scene = ctx->scene;
    const vbl_vec3 o = sample->origin, d = sample->direction;
    const double clamp2 = gs->clamp_distance * gs->clamp_distance;
    const int nk = gs->kernel_samples > 0 ? gs->kernel_samples : VBL_SURFACE_KERNEL_SAMPLES_DEFAULT;
    const double R = gs->vsl_radius > 0.0 ? gs->vsl_radius : 0.0;
    const int M = ctx->options.max_bounces;
    gather_cb cb = {.ctx = ctx, .ts = ts, .rng = rng, .photons = photons, .cache = cache};
    const vbl_segment camera = {o, d, u0, u1};
    vbl_vec3 sum = vbl_v3(0.0, 0.0, 0.0);
    vbl_work_add(VBL_WORK_LIGHT_EVAL, photons->surface_vsl_count);
    for (size_t j = 0; j < photons->surface_vsl_count; ++j) {
        const vbl_surface_vsl v = photons->surface_vsls[j];
        double xi = vbl_rng_uniform(rng);
        vbl_surface_kernel kernel = {R, nk, {0.0, 0.0, 0.0}};
        for (int k = 0; k < 3; ++k) kernel.jitter[k] = vbl_rng_uniform(rng);
        if (M >= 0 && v.bounce + 2 > M) continue; /* stores traced one event deeper (vbl + beams) */
        cb.albedo = vbl_v3(0.0, 0.0, 0.0);
        double u = u0;
        vbl_vec3 e = vbl_gather_volume_from_vsl(&camera, gs->g_camera, &v, photons->surface_vsl_peaks[j],
                                                &scene->materials[v.material], &kernel, &cb, xi, &u);
        if (!vbl_any(e)) continue;
        if (R == 0.0 && clamp2 > 0.0) {
            vbl_vec3 to = vbl_v3_sub(vbl_v3_madd(o, d, u), v.position);
            double w2 = vbl_v3_dot(to, to);
            if (clamp2 > w2) e = vbl_v3_scale(e, w2 / clamp2);
        }
        sum = vbl_v3_add(sum, vbl_v3_mul(e, cb.albedo));
    }
    out->L[VBL_CLASS_VOLUME_FROM_SURFACE] = vbl_v3_add(out->L[VBL_CLASS_VOLUME_FROM_SURFACE], sum);
}

double vbl_surface_vsl_default_r0(const vbl_scene* scene, size_t vsl_count)
{
    vbl_vec3 lo, hi;
    if (!scene->surfaces || !vbl_surfaces_bounds(scene->surfaces, &lo, &hi)) return 0.0;
    vbl_vec3 e = vbl_v3_sub(hi, lo);
    double diag = vbl_v3_length(e);
    if (!(diag > 0.0) || !isfinite(diag)) return 0.0;
    double area = e.x * e.y + e.y * e.z + e.z * e.x; /* half the box's surface area */
    double r0 = vsl_count > 0 && area > 0.0 ? sqrt(area / (double)vsl_count) : 0.01 * diag;
    if (r0 < 1e-3 * diag) r0 = 1e-3 * diag;
    if (r0 > 0.1 * diag) r0 = 0.1 * diag;
    return r0;
}
