/* Path tracer (reference) for media and opaque surfaces. The estimator of the RTE with a
 * surface boundary (the rendering equation at surface points):
 *   L(x, w) = int_0^s T(x, x_t) sigma_s(x_t) int p(w', w) L_i(x_t, w') dw' dt + T(x, x_s) L_o(x_s, w)
 *   L_o(y, w) = int f(w, w') L_i(y, w') |cos theta'| dw'         (opaque, no emission)
 * with s the distance to the first surface (INFINITY: the environment, L_o = L_env). Free paths by
 * delta tracking clipped at the surface hit (collision density sigma_t T, so the throughput is
 * multiplied by the scattering kernel / sigma_t at a real collision; reaching the surface has
 * probability T(x, x_s)); one light chosen uniformly per vertex for NEE, with surface occlusion
 * and media transmittance on the shadow ray; quad/environment lights combine NEE and
 * phase/BRDF sampling by MIS (Veach 1997, eq. 9.13 balance / 9.14 power heuristic); point/spot
 * lights add an equiangular distance sample on every segment, MIS-combined with the collision's
 * NEE (Kulla and Fajardo 2012; transport/path_tracing/pt_equiangular.h, option pt_equiangular; quad
 * lights too with pt.equiangular_quads, three-strategy MIS with NEE and phase sampling). Lights do
 * not occlude; surfaces occlude everything. Contributions are classified by the camera-visible
 * vertex and the vertex before it (vbl_class_for_vertices).
 * Emissive media (docs/readme/emission.md) add the emission term int_0^s T sigma_a Le dt of the
 * RTE: at every tentative collision of the free flight (null or real) the walk adds
 * beta sigma_a Le / mu (vbl_free_flight_sample_visit; the null-scattering emission estimator of
 * Pharr, Jakob and Humphreys 2023, pbrt-v4, sec. 14.2; transport/common/emission_estimate.h,
 * with the light sampling of the emissive media);
 * seen directly it goes to volume_emission, after scattering to the class of that vertex. A
 * scene without emission takes the plain free flight (decided once per scene).
 * Russian roulette on throughput from the third event on; with pt.guided_rr, adjoint-driven
 * roulette and splitting from a pre-pass radiance cache (Vorba and Krivanek 2016, sec. 4-5;
 * transport/path_tracing/pt_guide.h) where the cache has data. */
#include "transport/path_tracing/pt.h"

#include <math.h>

#include "sampling/sobol.h"
#include "scene/lights.h"
#include "media/media.h"
#include "media/medium.h"
#include "media/medium_grids.h"
#include "transport/common/emission_estimate.h"
#include "transport/path_tracing/pt_camera_split.h"
#include "transport/path_tracing/pt_direct_strata.h"
#include "transport/path_tracing/pt_equiangular.h"
#include "transport/path_tracing/pt_guide.h"
#include "transport/path_tracing/pt_light_focus.h"
#include "transport/path_tracing/pt_shadow_control.h"

/* Where a path's 2D sample pairs come from (option pt.sampler): the render's rng stream
 * (independent), or the Owen-scrambled Sobol pair of (seed, pixel, pair, bounce) at the sample's
 * global index (sampling/sobol.h; pair 0, the pixel position, is drawn by the render driver).
 * With sobol, every segment's free flight takes its first optical depth and its real/null
 * decisions from a pair (vbl_free_flight_sample_pattern), the light pick is folded into the light
 * pair and the roulette shares a pair with the lobe/BRDF-component choice; the other numbers
 * (transmittance estimates, the free flight's later depths, the emission NEE) stay on the stream.
 * With independent, the stream is consumed exactly as before these pairs existed. */
typedef struct vbl_pt_dims {
    int sobol;
    uint64_t seed, pixel;
    uint32_t index;
} vbl_pt_dims;

enum {
    VBL_PT_PAIR_LIGHT = 1,       /* light pick (folded into u) and the point on the light */
    VBL_PT_PAIR_EQUIANGULAR = 2, /* the equiangular NEE's light pick and distance */
    VBL_PT_PAIR_DIRECTION = 3,   /* the phase/BRDF direction */
    VBL_PT_PAIR_FREE_FLIGHT = 4, /* the segment's first optical depth and first real/null decision */
    VBL_PT_PAIR_EVENT = 5,       /* the lobe/BRDF-component choice and the Russian roulette */
    VBL_PT_PAIR_SHADOW_MARCH = 6, /* pt.sobol_shadow_march: the camera-visible surface's shadow march */
    VBL_PT_PAIR_SHADOW_MARCH_BEHIND = 7 /* ... and the camera split's march of the smoke in front of it */
};

/* Two numbers of `pair` at scattering event `bounce` (0: the camera segment). */
static void vbl_pt_u2(const vbl_pt_dims* d, uint32_t pair, int bounce, vbl_rng* rng, double* u, double* v)
{
    if (!d->sobol) {
        *u = vbl_rng_uniform(rng);
        *v = vbl_rng_uniform(rng);
        return;
    }
    vbl_sobol_pair(vbl_sobol_key(d->seed, d->pixel, pair, (uint32_t)bounce), d->index, u, v);
}

static void vbl_add_scaled(vbl_vec3* acc, vbl_vec3 a, vbl_vec3 b, double s)
{
    acc->x += a.x * b.x * s;
    acc->y += a.y * b.y * s;
    acc->z += a.z * b.z * s;
}

/* Where a path stands: the kind of the camera-visible vertex and of the latest vertex. */
typedef struct vbl_pt_path {
    int events;            /* scattering events so far (surface or medium) */
    int first_is_surface;  /* kind of vertex 1 */
    int second;            /* kind of vertex 2: 1 surface, 0 medium, -1 none yet */
} vbl_pt_path;

/* Class of light arriving at the latest vertex from a light (events >= 1) or seen directly. */
static vbl_transport_class vbl_pt_class(const vbl_pt_path* p)
{
    if (p->events <= 0) return VBL_CLASS_EMISSION;
    return vbl_class_for_vertices(p->first_is_surface, p->events == 1 ? -1 : p->second);
}

static void vbl_pt_vertex(vbl_pt_path* p, int is_surface)
{
    ++p->events;
    if (p->events == 1) p->first_is_surface = is_surface;
    if (p->events == 2) p->second = is_surface;
}

/* 1 if every class the path can still add to is skipped (ctx->skip_classes, render.hybrid): from
 * vertex 2 on a path adds to one class only; at vertex 1 to *_direct and the two classes of its kind. */
static int vbl_pt_path_skipped(const vbl_render_context* ctx, const vbl_pt_path* p)
{
    if (!ctx->skip_classes || p->events <= 0) return 0;
    if (p->events >= 2) return !vbl_ctx_wants(ctx, vbl_pt_class(p));
    return !vbl_ctx_wants(ctx, vbl_class_for_vertices(p->first_is_surface, -1)) &&
           !vbl_ctx_wants(ctx, vbl_class_for_vertices(p->first_is_surface, 0)) &&
           !vbl_ctx_wants(ctx, vbl_class_for_vertices(p->first_is_surface, 1));
}

/* Light of quad/environment lights seen along (origin, direction) before t_limit (INFINITY:
 * nothing blocks the ray, so the environment is seen too). prev_pdf is the phase/BRDF pdf of
 * direction and `vertex` the scattering point it was sampled at (ignored for camera rays). */
static void vbl_pt_add_visible_lights(const vbl_render_context* ctx, vbl_vec3 origin, vbl_vec3 vertex,
                                      vbl_vec3 direction, double t_limit, const vbl_pt_path* path, double prev_pdf,
                                      const vbl_pt_eq_vertex* eq_vertex, vbl_vec3 beta, vbl_sample_value* out)
{
    const vbl_scene* scene = ctx->scene;
    if (!scene->has_visible_lights || !vbl_ctx_wants(ctx, vbl_pt_class(path))) return;
    double select_pdf = 1.0 / scene->light_count;
    vbl_vec3* L = &out->L[vbl_pt_class(path)];
    for (int i = 0; i < scene->light_count; ++i) {
        const vbl_light* light = &scene->lights[i];
        if (light->type == VBL_LIGHT_QUAD) {
            double t_hit;
            if (!vbl_quad_intersect(light, origin, direction, &t_hit) || !(t_hit < t_limit)) continue;
        } else if (light->type == VBL_LIGHT_ENVIRONMENT) {
            if (!isinf(t_limit)) continue;
        } else {
            continue;
        }
        double w = 1.0;
        if (path->events > 0 && eq_vertex && light->type == VBL_LIGHT_QUAD) { /* and the equiangular sample */
            double t_hit = 0.0;
            vbl_quad_intersect(light, vertex, direction, &t_hit);
            w = vbl_pt_equiangular_quad_weight(ctx, light, eq_vertex, direction, t_hit, prev_pdf, VBL_PT_EQ_PHASE);
        } else if (path->events > 0) {
            w = vbl_mis_weight(ctx->options.mis, prev_pdf, select_pdf * vbl_light_pdf(light, vertex, direction));
        }
        vbl_add_scaled(L, beta, light->color, w);
    }
}

/* Picks one light uniformly and samples it from x (the light pair of scattering event `bounce`);
 * 0 if the sample carries no light. */
static int vbl_pt_pick_light(const vbl_scene* scene, vbl_vec3 x, const vbl_pt_dims* dims, int bounce, vbl_rng* rng,
                             vbl_light_sample* ls, double* select_pdf, const vbl_light** picked)
{
    if (scene->light_count == 0) return 0;
    *select_pdf = 1.0 / scene->light_count;
    const int n = scene->light_count;
    double u1, u2;
    int pick;
    if (dims->sobol) { /* the pick is u1's leading part, the rest of u1 the light's own (uniform again) */
        vbl_pt_u2(dims, VBL_PT_PAIR_LIGHT, bounce, rng, &u1, &u2);
        pick = (int)(u1 * n);
        if (pick >= n) pick = n - 1;
        u1 = u1 * n - pick;
        if (!(u1 < 1.0)) u1 = nextafter(1.0, 0.0);
        if (!(u1 >= 0.0)) u1 = 0.0;
    } else {
        pick = (int)(vbl_rng_uniform(rng) * n);
        if (pick >= n) pick = n - 1;
        vbl_pt_u2(dims, VBL_PT_PAIR_LIGHT, bounce, rng, &u1, &u2);
    }
    if (picked) *picked = &scene->lights[pick];
    if (!vbl_light_sample_incident(&scene->lights[pick], x, u1, u2, ls)) return 0;
    return vbl_v3_max_component(ls->li) > 0.0;
}

/* A free-flight segment: origin + t travel, t up to t_surface (INFINITY: none). */
typedef struct vbl_pt_segment {
    vbl_vec3 origin, travel;
    double t_surface;
} vbl_pt_segment;

/* pt.shadow_roulette: the survival probability of a shadow ray at a vertex of throughput beta
 * whose phase function takes the value p towards the light, on a path whose throughput at its
 * camera-visible vertex was beta_1 (max component ref): q = clamp(4 pi p max(beta) / ref,
 * VBL_PT_SHADOW_RR_MIN, 1), the ray's unoccluded contribution relative to an isotropic
 * camera-visible vertex of the same path, whose light the pixel is mostly made of (albedo left
 * out: that vertex's contribution carries it too). A Russian roulette decided before the shadow
 * ray's random numbers, survivors weighted 1/q: unbiased for any q > 0. A forward-scattering
 * phase function (g = 0.8: 4 pi p from 0.06 to 45) leaves most deep vertices' shadow rays with
 * small weights, and those rays were 56 % of a dense cloud's CPU (docs/readme/performance.md,
 * session 12). */
#define VBL_PT_SHADOW_RR_MIN 0.05
static double vbl_pt_shadow_ratio(vbl_vec3 beta, double phase, double ref)
{
    return 4.0 * VBL_PI * phase * vbl_v3_max_component(beta) / ref;
}
/* q clamped to [q_min, 1] (NaN: q_min) */
static double vbl_pt_survival_clamp(double q, double q_min)
{
    return q >= 1.0 ? 1.0 : (q > q_min ? q : q_min);
}
static double vbl_pt_shadow_survival(vbl_vec3 beta, double phase, double ref)
{
    return vbl_pt_survival_clamp(vbl_pt_shadow_ratio(beta, phase, ref), VBL_PT_SHADOW_RR_MIN);
}

/* Next-event estimation at the medium vertex at distance t on segment `seg`; rr_ref > 0: the
 * shadow ray's roulette (pt.shadow_roulette) against the path's first-vertex throughput rr_ref,
 * 0: always traced. */
static void vbl_pt_next_event_medium(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_pt_segment* seg,
                                     double t, double sigma_t, const vbl_medium_point* mp, const vbl_pt_path* path,
                                     const vbl_pt_dims* dims, int last, double rr_ref,
                                     const vbl_pt_light_focus_vertex* fv, int control_first, int segment_control,
                                     vbl_vec3 beta, vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_scene* scene = ctx->scene;
    vbl_vec3 x = vbl_v3_madd(seg->origin, seg->travel, t), travel = seg->travel;
    vbl_light_sample ls;
    double select_pdf;
    const vbl_light* light = NULL;
    if (!vbl_ctx_wants(ctx, vbl_pt_class(path))) return; /* render.hybrid: another estimator's class */
    if (!vbl_pt_pick_light(scene, x, dims, path->events, rng, &ls, &select_pdf, &light)) return;
    if (path->events == 1 && vbl_pt_direct_strata_skips(ctx, light)) return; /* pt_direct_strata.h */
    double cos_theta = vbl_v3_dot(travel, ls.wi);
    vbl_vec3 kernel = vbl_medium_phase_kernel(mp, cos_theta);
    if (vbl_v3_max_component(kernel) <= 0.0) return;
    const double phase = vbl_medium_phase_pdf(mp, cos_theta);
    double T;
    const vbl_sun_grid* control = vbl_pt_shadow_control_of(ctx, light); /* pt.shadow_control */
    if (control && control_first && path->events == 1) /* vbl_pt_shadow_control_walk added T_c's part */
        T = vbl_ctx_transmittance(ctx, ts, x, ls.wi, ls.distance, rng) - vbl_sun_grid_eval(control, x);
    else if (control && (segment_control || rr_ref > 0.0)) {
        /* the roulette on T^ - T_c: E = T_c + (E[T^] - T_c), less the part `summed` that the free
         * flight to x already added (pt.shadow_control_flight: T_c); a blocked ray's T is 0
         * exactly, so it takes no roulette */
        const double Tc = vbl_sun_grid_eval(control, x), summed = segment_control ? Tc : 0.0;
        if (vbl_ctx_occluded(ctx, x, ls.wi, ls.distance)) {
            T = -summed;
        } else {
            const double q = rr_ref > 0.0 ? vbl_pt_survival_clamp(VBL_PT_SHADOW_CONTROL_RR_SCALE *
                                                                      vbl_pt_shadow_ratio(beta, phase, rr_ref),
                                                                  VBL_PT_SHADOW_CONTROL_RR_MIN)
                                          : 1.0;
            T = Tc - summed;
            if (!(q < 1.0 && vbl_rng_uniform(rng) >= q))
                T += (vbl_ctx_media_transmittance(ctx, ts, x, ls.wi, ls.distance, &ctx->tracking, rng) - Tc) / q;
        }
    } else {
        double q = 1.0;
        if (rr_ref > 0.0) {
            q = vbl_pt_shadow_survival(beta, phase, rr_ref);
            if (q < 1.0 && vbl_rng_uniform(rng) >= q) return;
        }
        T = vbl_ctx_transmittance(ctx, ts, x, ls.wi, ls.distance, rng) / q;
    }
    if (T == 0.0) return; /* an unbiased estimate may be negative (unbiased-march): kept, or the mean drops */
    double w = 1.0;
    /* at the path's last vertex no phase direction is traced: that strategy's density is 0; the
     * traced direction's density is pt.light_focus's mixture where it is on (pt_light_focus.h) */
    const double phase_pdf = last || ls.is_delta ? 0.0 /* delta lights: not used below */
                             : (fv && fv->c > 0.0 ? vbl_pt_light_focus_medium_pdf(fv, mp, x, travel, ls.wi) : phase);
    if (light->type == VBL_LIGHT_QUAD && vbl_pt_equiangular_quads_active(ctx)) { /* three strategies */
        const vbl_pt_eq_vertex v = {seg->origin, travel, seg->t_surface, t, sigma_t};
        w = vbl_pt_equiangular_quad_weight(ctx, light, &v, ls.wi, ls.distance, phase_pdf, VBL_PT_EQ_NEE);
    } else if (!ls.is_delta)
        w = vbl_mis_weight(ctx->options.mis, select_pdf * ls.pdf, phase_pdf);
    else /* against the segment's equiangular sample (pt_equiangular.h) */
        w = vbl_pt_equiangular_ff_weight(ctx, light, seg->origin, travel, seg->t_surface, t, sigma_t);
    /* beta * (kernel / sigma_t) * L_i * T * w / (select_pdf * pdf) */
    double s = T * w / (select_pdf * ls.pdf * sigma_t);
    vbl_vec3* L = &out->L[vbl_pt_class(path)];
    L->x += beta.x * kernel.x * ls.li.x * s;
    L->y += beta.y * kernel.y * ls.li.y * s;
    L->z += beta.z * kernel.z * ls.li.z * s;
}

/* Next-event estimation at a surface hit (wo towards the previous vertex). */
static void vbl_pt_next_event_surface(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_surface_hit* hit,
                                      vbl_vec3 wo, const vbl_pt_path* path, const vbl_pt_dims* dims, int last,
                                      const vbl_pt_light_focus* focus, vbl_vec3 beta, vbl_rng* rng,
                                      vbl_sample_value* out)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_material* m = &scene->materials[hit->material];
    vbl_light_sample ls;
    double select_pdf;
    if (!vbl_ctx_wants(ctx, vbl_pt_class(path))) return; /* render.hybrid: another estimator's class */
    if (!vbl_pt_pick_light(scene, hit->position, dims, path->events, rng, &ls, &select_pdf, NULL)) return;
    if (!(vbl_v3_dot(ls.wi, hit->geometric_normal) > 0.0)) return; /* below the surface: opaque */
    double cos_i = vbl_v3_dot(ls.wi, hit->shading_normal);
    if (!(cos_i > 0.0)) return;
    vbl_vec3 f = vbl_material_eval(m, hit->shading_normal, wo, ls.wi);
    if (!(vbl_v3_max_component(f) > 0.0)) return;
    vbl_vec3 origin = vbl_surface_spawn(scene->surfaces, hit->position, hit->geometric_normal, ls.wi);
    double T = vbl_ctx_transmittance(ctx, ts, origin, ls.wi, ls.distance, rng);
    if (T == 0.0) return; /* an unbiased estimate may be negative (unbiased-march): kept, or the mean drops */
    double w = 1.0;
    if (!ls.is_delta) /* at the path's last vertex no direction is traced: its density is 0 */
        w = vbl_mis_weight(ctx->options.mis, select_pdf * ls.pdf,
                           last ? 0.0 : vbl_pt_light_focus_surface_pdf(focus, m, hit, wo, ls.wi));
    double s = T * w * cos_i / (select_pdf * ls.pdf);
    vbl_vec3* L = &out->L[vbl_pt_class(path)];
    L->x += beta.x * f.x * ls.li.x * s;
    L->y += beta.y * f.y * ls.li.y * s;
    L->z += beta.z * f.z * ls.li.z * s;
}

/* pt.guided_rr's splitting (pt_guide.h) and pt.camera_split's surface part (pt_camera_split.h):
 * the copies of a path still to trace, each with its own stream (drawn from the splitting
 * path's), depth first; at most VBL_PT_SPLIT_STACK wait at once. */
#define VBL_PT_SPLIT_STACK 32
typedef struct vbl_pt_branch {
    vbl_vec3 origin, direction, vertex, beta;
    double prev_pdf;
    vbl_pt_path path;
    vbl_pt_eq_vertex eq_vertex;
    int has_eq_vertex;
    int sobol;          /* the copy's 2D pairs: Sobol (camera split) or its stream (guide copies) */
    int resume_surface; /* 1: the camera split's surface part (the segment's media already walked) */
    double resume_t;    /* >= 0: pt.split_paths' copy, scattering at this distance on the camera ray */
    double rr_scale;    /* the roulette's throughput scale (the split's path count: see rr_scale) */
    double beta_first;  /* max(beta) at the path's camera-visible vertex (pt.shadow_roulette) */
    vbl_rng rng;
} vbl_pt_branch;

/* The split camera segment's lights seen directly (pt_camera_split.h): a quad light before the
 * surface with its own transmittance estimate, the environment (the ray escapes) with the
 * segment's T_end; no MIS at the camera vertex. */
static void vbl_pt_split_visible_lights(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                        vbl_vec3 direction, double t_surface, double T_end, vbl_vec3 beta,
                                        vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_scene* scene = ctx->scene;
    if (!scene->has_visible_lights || !vbl_ctx_wants(ctx, VBL_CLASS_EMISSION)) return;
    vbl_vec3* L = &out->L[VBL_CLASS_EMISSION];
    for (int i = 0; i < scene->light_count; ++i) {
        const vbl_light* light = &scene->lights[i];
        double T;
        if (light->type == VBL_LIGHT_QUAD) {
            double t_hit;
            if (!vbl_quad_intersect(light, origin, direction, &t_hit) || !(t_hit < t_surface)) continue;
            T = vbl_ctx_transmittance(ctx, ts, origin, direction, t_hit, rng);
        } else if (light->type == VBL_LIGHT_ENVIRONMENT) {
            if (!isinf(t_surface)) continue;
            T = T_end;
        } else {
            continue;
        }
        vbl_add_scaled(L, beta, light->color, T);
    }
}

void vbl_pt_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                          const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    (void)store;
    const vbl_scene* scene = ctx->scene;
    /* motion blur: the emitter blocks do not move with the medium, so emission is collected by
     * tracking only (unbiased; docs/readme/emission.md "Motion blur") */
    const int emission_nee = scene->emission_nee && !(scene->motion && ctx->options.motion_blur);
    const int max_bounces = ctx->options.max_bounces;
    vbl_vec3 origin = sample->origin, direction = sample->direction, vertex = sample->origin;
    vbl_vec3 beta = vbl_v3(1.0, 1.0, 1.0);
    double prev_pdf = 0.0;
    double components[VBL_MAX_MEDIA] = {0};
    vbl_pt_path path = {0, 0, -1};
    const int equiangular = vbl_pt_equiangular_active(ctx);
    const int direct_strata = vbl_pt_direct_strata_active(ctx);
    const int camera_split = vbl_pt_camera_split_active(ctx);
    const int control_first = vbl_pt_shadow_control_first(ctx); /* pt.shadow_control at the walk */
    const int control_flight = vbl_pt_shadow_control_flight_active(ctx); /* ... and along deeper flights */
    /* pt.split_behind_march: the camera split's surface or background part weighted by its own
     * estimate of the segment's T, with surface_first_ctx's tracking (the camera-visible surface's
     * march density), instead of the walk's ratio-tracking product: the walk's noise was most of
     * surface_direct's behind thin smoke (docs/readme/performance.md, session 10). Any unbiased
     * estimate of T keeps that part unbiased; it is drawn whatever the walk gave, wherever T_end
     * is used: a surface behind, or an environment where the ray escapes. */
    const int split_march = ctx->options.pt.split_behind_march;
    int split_env = 0;
    for (int i = 0; split_march && scene->has_visible_lights && i < scene->light_count; ++i)
        split_env |= scene->lights[i].type == VBL_LIGHT_ENVIRONMENT;
    int resume_surface = 0; /* the next segment is a camera split's surface part */
    double resume_t = -1.0; /* >= 0: the next segment scatters there (a pt.split_paths copy) */
    const int split_paths = camera_split ? ctx->options.pt.split_paths : 1;
    /* the throughput roulette compares N beta, not beta, on the N paths of pt.split_paths: each
     * carries 1/N of the camera sample's weight, and q = beta would end all but ~1 of them by the
     * third event, undoing the split */
    double rr_scale = 1.0;
    const int shadow_roulette = ctx->options.pt.shadow_roulette;
    double beta_first = 1.0; /* max(beta) at the camera-visible vertex (vbl_pt_shadow_survival) */
    /* the medium vertex the current ray left from, for quad lights' three-strategy MIS */
    const int eq_quads = vbl_pt_equiangular_quads_active(ctx);
    vbl_pt_eq_vertex eq_vertex = {sample->origin, sample->direction, 0.0, 0.0, 0.0}; /* set before use */
    int has_eq_vertex = 0;
    vbl_pt_dims dims = {ctx->options.pt.sampler == VBL_PT_SAMPLER_SOBOL, ctx->options.seed, sample->pixel_index,
                        sample->sample_index};
    /* options.transmittance_majorant_scale buys low-noise shadow rays where they matter most, at
     * the camera-visible vertex (surface_direct, volume_direct); deeper vertices use the tight
     * majorant (their noise is dominated by the path, not by T) */
    /* options.pt.shadow_transmittance: pt's transmittance estimates (NEE shadow rays, the
     * equiangular sample's segment) by residual ratio tracking with the mid-bound control
     * (volume/transmittance.h) or unbiased ray marching (transmittance_unbiased_march.h); free
     * flights are unaffected */
    vbl_render_context shadow_ctx;
    if (ctx->options.pt.shadow_transmittance == VBL_PT_SHADOW_UNBIASED_MARCH) {
        shadow_ctx = *ctx;
        shadow_ctx.tracking.unbiased_march = 1;
        ctx = &shadow_ctx;
    } else if (ctx->options.pt.shadow_transmittance == VBL_PT_SHADOW_UNBIASED_MARCH_ADAPTIVE ||
               ctx->options.pt.shadow_transmittance == VBL_PT_SHADOW_DEFAULT) { /* the default (docs/readme/sampling.md) */
        shadow_ctx = *ctx;
        shadow_ctx.tracking.unbiased_march = 2;
        ctx = &shadow_ctx;
    } else if (ctx->options.pt.shadow_transmittance == VBL_PT_SHADOW_RESIDUAL_MID) {
        shadow_ctx = *ctx;
        shadow_ctx.tracking.estimator = VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING;
        shadow_ctx.tracking.residual_mid = 1;
        ctx = &shadow_ctx;
    }
    const vbl_render_context* first_ctx = ctx;
    /* pt.surface_direct_rate: the shadow rays of a camera-visible surface point (surface_direct)
     * at that many times the march density; their transmittance noise is most of that layer's
     * noise where a lit surface sees its light through thin smoke (measured in
     * docs/readme/sampling.md) */
    vbl_render_context surface_first_ctx = *ctx;
    surface_first_ctx.tracking.majorant_scale *= ctx->options.pt.surface_direct_rate;
    /* pt.sobol_shadow_march: those shadow rays, and the camera split's march of the smoke in front
     * of the surface (split_march, below), place the first factor march of each of their first two
     * blocks systematically at a Sobol number of the camera sample
     * (vbl_unbiased_march_params.offsets; one pair per ray: its two numbers are independent and
     * uniform, as the blocks' product needs). Each estimate stays unbiased; over a pixel's
     * samples, whose rays to a light nearly coincide, the numbers are stratified, so the samples'
     * marches interleave instead of falling independently: surface_direct's noise there is mostly
     * those marches' (docs/readme/sampling.md). */
    vbl_tracking_settings behind_tracking = surface_first_ctx.tracking; /* split_march's estimate */
    if (dims.sobol && ctx->options.pt.sobol_shadow_march && ctx->extinction->count > 0 &&
        (scene->has_surfaces || split_env)) {
        vbl_pt_u2(&dims, VBL_PT_PAIR_SHADOW_MARCH, 1, rng, &surface_first_ctx.tracking.march_offset[0],
                  &surface_first_ctx.tracking.march_offset[1]);
        vbl_pt_u2(&dims, VBL_PT_PAIR_SHADOW_MARCH_BEHIND, 1, rng, &behind_tracking.march_offset[0],
                  &behind_tracking.march_offset[1]);
        surface_first_ctx.tracking.march_offsets = behind_tracking.march_offsets = 2;
    }
    const vbl_pt_guide* guide = ctx->pt_guide;
    const vbl_pt_light_focus* focus = ctx->pt_light_focus; /* pt.light_focus (NULL: off) */
    vbl_pt_branch branches[VBL_PT_SPLIT_STACK];
    int branch_count = 0;
    vbl_rng branch_rng;
    vbl_render_context tight_ctx;
    /* the adaptive march's deep vertices march at VBL_UNBIASED_MARCH_DEEP_RATE (chosen by the
     * vertex, before the shadow ray's random numbers: unbiased) */
    if (ctx->tracking.majorant_scale > 1.0 || ctx->tracking.unbiased_march == 2) {
        tight_ctx = *ctx;
        tight_ctx.tracking.majorant_scale = 1.0;
        if (tight_ctx.tracking.unbiased_march == 2) tight_ctx.tracking.unbiased_march = 3;
        ctx = &tight_ctx;
    }
    vbl_pt_split_walk walk; /* the camera split's walk (pt_camera_split.h) */
    for (;;) { /* the camera path, then each waiting copy of a split */
    for (;;) {
        const vbl_render_context* nee_ctx = path.events == 0 ? first_ctx : ctx;
        vbl_surface_hit hit;
        int on_surface = vbl_surfaces_intersect(scene->surfaces, origin, direction, 0.0, INFINITY, &hit);
        double t_surface = on_surface ? hit.t : INFINITY;
        double t = INFINITY, sigma_t = 0.0;
        int collided;
        double u_ff[2]; /* pt.sampler = sobol: the flight's first depth and its real/null decisions */
        const double* ff = dims.sobol ? u_ff : NULL;
        if (ff) vbl_pt_u2(&dims, VBL_PT_PAIR_FREE_FLIGHT, path.events, rng, &u_ff[0], &u_ff[1]);
        const vbl_vec3 segment_beta = beta; /* the throughput into this segment (the split rescales beta) */
        int segment_estimators = 1; /* the segment's visible lights, direct strata, equiangular NEE */
        int split_end = 0;          /* the split has no part left to trace (after the segment's estimators) */
        const vbl_pt_split_walk* segment_walk = NULL; /* the camera split's walk along this segment */
        int segment_control = 0; /* pt.shadow_control_flight summed this flight's control part */
        if (resume_surface) { /* pt_camera_split.h: the surface part, weighted by T_end already */
            resume_surface = 0;
            collided = 0;
            segment_estimators = 0;
        } else if (resume_t >= 0.0) { /* a pt.split_paths copy: beta holds W / n; times sigma_t / sigma_s here */
            t = resume_t;
            resume_t = -1.0;
            const vbl_vec3 x = vbl_v3_madd(origin, direction, t);
            sigma_t = vbl_extinction_eval(ctx->extinction, &ts->cursor, x, components);
            const double ss = vbl_pt_camera_split_sigma_s(ctx, ts, x, sigma_t, components);
            collided = sigma_t > 0.0 && ss > 0.0 && isfinite(sigma_t / ss);
            if (collided) beta = vbl_v3_scale(beta, sigma_t / ss);
            split_end = !collided;
            segment_estimators = 0;
        } else if (camera_split && path.events == 0) { /* pt_camera_split.h */
            segment_walk = &walk;
            vbl_emission_visit_state e = {scene, &ts->emission, beta, &out->L[VBL_CLASS_VOLUME_EMISSION]};
            vbl_pt_camera_split_walk(ctx, ts, origin, direction, t_surface, ff ? u_ff[0] : -1.0, beta,
                                     scene->has_emission ? &e : NULL, 1, rng, &walk);
            const double u_pick = ff ? u_ff[1] : vbl_rng_uniform(rng);
            /* pt.split_paths: n paths from the points of n strata of the walk's weights, (j + u) / n,
             * each continued with W / n (unbiased: point i is picked n w_i / W times on average, so
             * the n paths' mean estimates the sum; Novak et al. 2018, sec. 5.2, with stratified
             * resampling); copy j > 0 waits on the stack with a stream of its own. n is drawn
             * given the walk, 1 + (N - 1) x the medium part's share W / (W + T^ behind) rounded
             * at random (a surface or an environment behind; else the share is 1): the extra paths
             * go where the medium is what the camera sample sees, and the surface part behind
             * (traced once) keeps its CPU share in thin smoke. Any n >= 1 keeps the mean. */
            int n_paths = split_paths;
            if (split_paths > 1) {
                const double W = walk.n > 0 ? walk.cum[walk.n - 1] : 0.0;
                const double behind = on_surface || split_env ? walk.T_end : 0.0; /* the walk's, in [0, 1] */
                const double share = W > 0.0 && isfinite(W) ? W / (W + behind) : 0.0;
                n_paths = 1 + (int)floor((split_paths - 1) * share + vbl_rng_uniform(rng));
                if (n_paths > split_paths) n_paths = split_paths;
            }
            const int k = vbl_pt_camera_split_pick(&walk, u_pick / n_paths);
            /* the AOVs (vbl_pt_camera_aovs): alpha 1 - the walk's T^ (in [0, 1], unlike the
             * march's estimate below), Z the walk's delta-tracking collision, else the surface */
            out->aovs.alpha = on_surface ? 1.0 : 1.0 - walk.T_end;
            out->aovs.depth_hit = walk.t_first >= 0.0 || on_surface;
            out->aovs.depth = walk.t_first >= 0.0 ? walk.t_first : t_surface;
            if (split_march && (on_surface || split_env)) /* the part behind: see split_march */
                walk.T_end = vbl_ctx_media_transmittance(ctx, ts, origin, direction, t_surface, &behind_tracking, rng);
            vbl_pt_split_visible_lights(ctx, ts, origin, direction, t_surface, walk.T_end, beta, rng, out);
            if (control_first)
                vbl_pt_shadow_control_walk(ctx, ts, &walk, origin, direction, u_pick, beta,
                                           &out->L[VBL_CLASS_VOLUME_DIRECT]);
            segment_estimators = 2;
            collided = 0;
            if (k >= 0 && n_paths > 1) { /* the other strata's points, traced after this path */
                uint64_t key = (uint64_t)vbl_rng_next_u32(rng) << 32;
                key |= vbl_rng_next_u32(rng);
                const vbl_vec3 copy_beta = vbl_v3_scale(beta, walk.cum[walk.n - 1] / n_paths);
                for (int j = 1; j < n_paths; ++j) { /* n <= 16: the stack (empty here) holds them */
                    const int kj = vbl_pt_camera_split_pick(&walk, (j + u_pick) / n_paths);
                    if (kj < 0) continue;
                    branches[branch_count++] = (vbl_pt_branch){
                        .origin = origin, .direction = direction, .vertex = vertex, .beta = copy_beta,
                        .prev_pdf = prev_pdf, .path = path, .eq_vertex = eq_vertex, .has_eq_vertex = has_eq_vertex,
                        .sobol = 0, .resume_t = walk.t[kj], .rr_scale = n_paths,
                        .rng = vbl_rng_make(key, (uint64_t)j, VBL_RNG_DOMAIN_GUIDE)};
                }
            }
            if (k >= 0) { /* the medium part: throughput W sigma_t / sigma_s(p_k) into the collision code */
                t = walk.t[k];
                vbl_vec3 x = vbl_v3_madd(origin, direction, t);
                sigma_t = vbl_extinction_eval(ctx->extinction, &ts->cursor, x, components);
                const double ss = vbl_pt_camera_split_sigma_s(ctx, ts, x, sigma_t, components);
                const double scale = walk.cum[walk.n - 1] / n_paths * sigma_t / ss;
                if (sigma_t > 0.0 && ss > 0.0 && isfinite(scale)) {
                    collided = 1;
                    if (on_surface && walk.T_end != 0.0) { /* the surface part waits on the stack */
                        uint64_t key = (uint64_t)vbl_rng_next_u32(rng) << 32;
                        key |= vbl_rng_next_u32(rng);
                        branches[branch_count++] = (vbl_pt_branch){
                            .origin = origin, .direction = direction, .vertex = vertex,
                            .beta = vbl_v3_scale(beta, walk.T_end), .prev_pdf = prev_pdf, .path = path,
                            .eq_vertex = eq_vertex, .has_eq_vertex = has_eq_vertex, .sobol = dims.sobol,
                            .resume_surface = 1, .resume_t = -1.0, .rr_scale = 1.0,
                            .rng = vbl_rng_make(key, 0u, VBL_RNG_DOMAIN_GUIDE)};
                    }
                    beta = vbl_v3_scale(beta, scale);
                    rr_scale = n_paths;
                }
            }
            if (!collided) {
                if (on_surface && walk.T_end == 0.0) split_end = 1; /* nothing reaches the surface */
                beta = vbl_v3_scale(beta, walk.T_end);
            }
        } else {
            vbl_tracking_visit visit = NULL;
            void* visit_user = NULL;
            vbl_emission_visit_state e;
            if (scene->has_emission) {
                /* after a scattering event with emission NEE on, this strategy's MIS weight */
                double w = 1.0;
                if (path.events > 0 && emission_nee)
                    w = vbl_mis_weight(ctx->options.mis, prev_pdf,
                                       vbl_emission_lights_pdf(&scene->emission_lights, vertex, direction));
                e = (vbl_emission_visit_state){
                    scene, &ts->emission, vbl_v3_scale(beta, w),
                    &out->L[path.events <= 0 ? VBL_CLASS_VOLUME_EMISSION : vbl_pt_class(&path)]};
                visit = vbl_emission_visit;
                visit_user = &e;
            }
            /* pt.shadow_control_flight: the control's part of the NEE at the vertex this flight
             * reaches, summed over its tentative collisions (pt_shadow_control.h); that vertex's
             * shadow ray then estimates T - T_c. Its class as the NEE's own (render.hybrid); no
             * bounce limit to check: a path stops at its last vertex, so a flight always reaches
             * a vertex it keeps. */
            vbl_pt_path reached = path;
            vbl_pt_control_flight cf;
            if (control_flight && path.events >= 1) {
                vbl_pt_vertex(&reached, 0);
                segment_control = vbl_ctx_wants(ctx, vbl_pt_class(&reached));
            }
            if (segment_control) {
                vbl_pt_control_flight_begin(&cf, ctx, direction, visit, visit_user);
                visit = vbl_pt_control_flight_visit;
                visit_user = &cf;
            }
            collided = vbl_ctx_free_flight_pattern(ctx, ts, origin, direction, t_surface, rng, ff, &t, &sigma_t,
                                                   components, visit, visit_user);
            if (segment_control) vbl_pt_control_flight_end(&cf, beta, &out->L[vbl_pt_class(&reached)]);
        }
        double t_limit = collided ? t : t_surface;
        if (segment_estimators == 1)
            vbl_pt_add_visible_lights(ctx, origin, vertex, direction, t_limit, &path, prev_pdf,
                                      has_eq_vertex ? &eq_vertex : NULL, beta, out);
        if (segment_estimators && direct_strata && path.events == 0 && vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_DIRECT)) /* the camera segment's single scattering, stratified */
            vbl_pt_direct_strata(nee_ctx, ts, origin, direction, t_surface, segment_beta, rng,
                                 &out->L[VBL_CLASS_VOLUME_DIRECT]);
        vbl_pt_path next = path; /* the segment's equiangular NEE: light scattered once more, at a medium vertex */
        vbl_pt_vertex(&next, 0);
        if (segment_estimators && equiangular && (max_bounces < 0 || path.events < max_bounces) &&
            vbl_ctx_wants(ctx, vbl_pt_class(&next))) {
            double u_pick, u_t;
            vbl_pt_u2(&dims, VBL_PT_PAIR_EQUIANGULAR, path.events, rng, &u_pick, &u_t);
            const int next_last = max_bounces >= 0 && path.events + 1 >= max_bounces; /* no phase sample there */
            const vbl_pt_light_focus_vertex next_fv = vbl_pt_light_focus_at_event(focus, next.events);
            /* pt.equiangular_camera_samples: n stratified samples on the camera segment, each
             * taking its T(t0, t) from the camera walk's running product (pt_equiangular.h) */
            const int n_eq = path.events == 0 ? ctx->options.pt.equiangular_camera_samples : 1;
            vbl_pt_equiangular_nee(nee_ctx, ts, origin, direction, t_surface, segment_beta, u_pick, u_t, n_eq,
                                   !next_last, vbl_pt_light_focus_medium_pdf_fn, &next_fv, segment_walk, rng,
                                   &out->L[vbl_pt_class(&next)]);
        }
        if (split_end) break;
        if (!collided && !on_surface) break; /* escaped */
        if (collided && !(sigma_t > 0.0)) break;

        vbl_pt_vertex(&path, !collided);
        if (path.events == 1) beta_first = vbl_v3_max_component(beta); /* pt.shadow_roulette's reference */
        if (max_bounces >= 0 && path.events > max_bounces) break;
        if (vbl_pt_path_skipped(ctx, &path)) break; /* render.hybrid */
        double u0, u1, u2, u_rr = -1.0; /* u_rr < 0: the roulette draws from the stream */
        vbl_vec3 wi;
        double pdf = 0.0;
        if (collided) {
            vbl_vec3 x = vbl_v3_madd(origin, direction, t);
            vbl_pt_segment seg = {origin, direction, t_surface};
            vbl_medium_point mp; /* what scatters at x (media/medium.h) */
            vbl_medium_point_from_components(scene, components, &mp);
            vbl_medium_point_apply_grids(scene, x, ts->cursor.time, &mp); /* albedo grids */
            int last = max_bounces >= 0 && path.events >= max_bounces;
            /* pt.shadow_roulette: after the first scattering event (the camera-visible vertex keeps
             * every shadow ray: volume_direct) */
            const double shadow_rr = shadow_roulette && path.events >= 2 ? beta_first : 0.0;
            /* pt.light_focus: this vertex's directions (and every MIS weight using their density) */
            const vbl_pt_light_focus_vertex fv = vbl_pt_light_focus_at_event(focus, path.events);
            vbl_pt_next_event_medium(nee_ctx, ts, &seg, t, sigma_t, &mp, &path, &dims, last, shadow_rr, &fv,
                                     control_first, segment_control, beta, rng, out);
            if (scene->has_emission && emission_nee)
                vbl_emission_nee_medium(ctx, ts, x, direction, sigma_t, &mp, last, vbl_pt_light_focus_medium_pdf_fn,
                                        &fv, beta, rng, &out->L[vbl_pt_class(&path)]);
            if (last) break;
            /* continue by sampling the sigma_s-weighted phase mixture (with pt.light_focus's cones) */
            if (dims.sobol) vbl_pt_u2(&dims, VBL_PT_PAIR_EVENT, path.events, rng, &u0, &u_rr);
            else u0 = vbl_rng_uniform(rng);
            vbl_pt_u2(&dims, VBL_PT_PAIR_DIRECTION, path.events, rng, &u1, &u2);
            if (!vbl_pt_light_focus_medium_sample(&fv, &mp, x, direction, u0, u1, u2, &wi, &pdf)) break;
            vbl_vec3 kernel = vbl_medium_phase_kernel(&mp, vbl_v3_dot(direction, wi));
            beta = vbl_v3_scale(vbl_v3_mul(beta, kernel), 1.0 / (pdf * sigma_t));
            if (eq_quads) {
                eq_vertex = (vbl_pt_eq_vertex){origin, direction, t_surface, t, sigma_t};
                has_eq_vertex = 1;
            }
            origin = vertex = x;
        } else {
            vbl_vec3 wo = vbl_v3_scale(direction, -1.0);
            int last = max_bounces >= 0 && path.events >= max_bounces;
            vbl_pt_next_event_surface(path.events == 1 ? &surface_first_ctx : nee_ctx, ts, &hit, wo, &path, &dims,
                                      last, focus, beta, rng, out);
            if (scene->has_emission && emission_nee)
                vbl_emission_nee_surface(ctx, ts, &hit, wo, last, vbl_pt_light_focus_surface_pdf_fn, focus, beta, rng,
                                         &out->L[vbl_pt_class(&path)]);
            if (last) break;
            /* continue by sampling the BRDF; reflection only (opaque surfaces) */
            const vbl_material* m = &scene->materials[hit.material];
            if (dims.sobol) vbl_pt_u2(&dims, VBL_PT_PAIR_EVENT, path.events, rng, &u0, &u_rr);
            else u0 = vbl_rng_uniform(rng);
            vbl_pt_u2(&dims, VBL_PT_PAIR_DIRECTION, path.events, rng, &u1, &u2);
            vbl_vec3 f;
            /* pt.light_focus: the BRDF's directions mixed with the lights' cones (pt_light_focus.h) */
            if (!vbl_pt_light_focus_surface_sample(focus, m, &hit, wo, u0, u1, u2, &wi, &pdf, &f) || !(pdf > 0.0)) break;
            double cos_i = vbl_v3_dot(wi, hit.shading_normal);
            if (!(cos_i > 0.0) || !(vbl_v3_dot(wi, hit.geometric_normal) > 0.0)) break;
            double s = cos_i / pdf;
            beta = vbl_v3(beta.x * f.x * s, beta.y * f.y * s, beta.z * f.z * s);
            vertex = hit.position;
            origin = vbl_surface_spawn(scene->surfaces, hit.position, hit.geometric_normal, wi);
            has_eq_vertex = 0;
        }
        if (!(vbl_v3_max_component(beta) > 0.0)) break;
        /* pt.guided_rr: the cache's roulette and splitting where it knows the radiance (pt_guide.h) */
        int copies = guide ? vbl_pt_guide_decide(guide, vertex, sample->px, sample->py,
                                                 1 + VBL_PT_SPLIT_STACK - branch_count, rng, &beta)
                           : -1;
        if (copies == 0) break;
        if (copies > 1) { /* the copies draw from streams of their own, not the shared Sobol pattern */
            dims.sobol = 0;
            uint64_t key = (uint64_t)vbl_rng_next_u32(rng) << 32;
            key |= vbl_rng_next_u32(rng);
            for (int k = 1; k < copies; ++k)
                branches[branch_count++] = (vbl_pt_branch){
                    .origin = origin, .direction = wi, .vertex = vertex, .beta = beta, .prev_pdf = pdf,
                    .path = path, .eq_vertex = eq_vertex, .has_eq_vertex = has_eq_vertex, .resume_t = -1.0,
                    .rr_scale = rr_scale, .beta_first = beta_first,
                    .rng = vbl_rng_make(key, (uint64_t)k, VBL_RNG_DOMAIN_GUIDE)}; /* sobol 0: own streams */
        }
        /* Russian roulette from the third scattering event on (unbiased: survivors / q) */
        if (copies < 0 && path.events >= 3) {
            double q = fmin(1.0, rr_scale * vbl_v3_max_component(beta));
            if ((dims.sobol && u_rr >= 0.0 ? u_rr : vbl_rng_uniform(rng)) >= q) break;
            beta = vbl_v3_scale(beta, 1.0 / q);
        }
        prev_pdf = pdf;
        direction = wi;
    }
        if (branch_count == 0) break;
        const vbl_pt_branch* b = &branches[--branch_count];
        origin = b->origin, direction = b->direction, vertex = b->vertex, beta = b->beta;
        prev_pdf = b->prev_pdf, path = b->path, eq_vertex = b->eq_vertex, has_eq_vertex = b->has_eq_vertex;
        dims.sobol = b->sobol;
        resume_surface = b->resume_surface;
        resume_t = b->resume_t;
        rr_scale = b->rr_scale;
        beta_first = b->beta_first;
        branch_rng = b->rng;
        rng = &branch_rng;
    }
}

/* With the camera split, the walk along every camera ray gives the alpha and Z AOVs (render.c
 * would otherwise track each camera ray twice more for them: 8-17 % of a pass in the race clouds). */
static int vbl_pt_camera_aovs(const vbl_render_context* ctx, const void* store)
{
    (void)store;
    return vbl_pt_camera_split_active(ctx);
}

const vbl_estimator vbl_estimator_pt = {"pt", 0, NULL, vbl_pt_camera_sample, NULL, vbl_pt_camera_aovs};
