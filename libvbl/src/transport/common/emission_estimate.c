/* Emission estimators shared by pt and the camera side of vpl/vrl/vbl/beams (emission_estimate.h). */
#include "transport/common/emission_estimate.h"

#include <math.h>

#include "material/material.h"
#include "media/media_emission.h"
#include "media/medium_grids.h"
#include "scene/lights.h"

static void vbl_add_scaled(vbl_vec3* acc, vbl_vec3 a, vbl_vec3 b, double s)
{
    acc->x += a.x * b.x * s;
    acc->y += a.y * b.y * s;
    acc->z += a.z * b.z * s;
}

void vbl_emission_visit(void* user, vbl_vec3 p, double mu, const double* per_component)
{
    vbl_emission_visit_state* e = user;
    vbl_vec3 em = vbl_media_emission(e->scene, e->cursor, p, per_component);
    vbl_add_scaled(e->L, e->beta, em, 1.0 / mu);
}

void vbl_emission_collect(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin, vbl_vec3 wi,
                          vbl_vec3 beta, vbl_rng* rng, vbl_vec3* L)
{
    const vbl_scene* scene = ctx->scene;
    vbl_surface_hit hit;
    double t_surface = vbl_surfaces_intersect(scene->surfaces, origin, wi, 0.0, INFINITY, &hit) ? hit.t : INFINITY;
    double components[VBL_MAX_MEDIA] = {0}, t = 0.0, sigma_t = 0.0;
    vbl_emission_visit_state e = {scene, &ts->emission, beta, L};
    vbl_ctx_free_flight_visit(ctx, ts, origin, wi, t_surface, rng, &t, &sigma_t, components, vbl_emission_visit, &e);
}

void vbl_emission_nee_medium(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 x, vbl_vec3 travel,
                             double sigma_t, const vbl_medium_point* mp, int last, vbl_medium_pdf_fn dir_pdf,
                             const void* dir_pdf_data, vbl_vec3 beta, vbl_rng* rng, vbl_vec3* L)
{
    const vbl_scene* scene = ctx->scene;
    double u0 = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng), pdf;
    vbl_vec3 wi;
    if (!vbl_emission_lights_sample(&scene->emission_lights, x, u0, u1, u2, &wi, &pdf)) return;
    double cos_theta = vbl_v3_dot(travel, wi);
    vbl_vec3 kernel = vbl_medium_phase_kernel(mp, cos_theta);
    if (!(vbl_v3_max_component(kernel) > 0.0)) return;
    const double p_dir = dir_pdf ? dir_pdf(dir_pdf_data, mp, x, travel, wi) : vbl_medium_phase_pdf(mp, cos_theta);
    double w = last ? 1.0 : vbl_mis_weight(ctx->options.mis, pdf, p_dir);
    double s = w / (pdf * sigma_t);
    vbl_vec3 b = vbl_v3(beta.x * kernel.x * s, beta.y * kernel.y * s, beta.z * kernel.z * s);
    vbl_emission_collect(ctx, ts, x, wi, b, rng, L);
}

void vbl_emission_nee_surface(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_surface_hit* hit,
                              vbl_vec3 wo, int last, vbl_surface_pdf_fn dir_pdf, const void* dir_pdf_data,
                              vbl_vec3 beta, vbl_rng* rng, vbl_vec3* L)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_material* m = &scene->materials[hit->material];
    double u0 = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng), pdf;
    vbl_vec3 wi;
    if (!vbl_emission_lights_sample(&scene->emission_lights, hit->position, u0, u1, u2, &wi, &pdf)) return;
    if (!(vbl_v3_dot(wi, hit->geometric_normal) > 0.0)) return;
    double cos_i = vbl_v3_dot(wi, hit->shading_normal);
    if (!(cos_i > 0.0)) return;
    vbl_vec3 f = vbl_material_eval(m, hit->shading_normal, wo, wi);
    if (!(vbl_v3_max_component(f) > 0.0)) return;
    const double p_dir = dir_pdf ? dir_pdf(dir_pdf_data, m, hit, wo, wi) : vbl_material_pdf(m, hit->shading_normal, wo, wi);
    double w = last ? 1.0 : vbl_mis_weight(ctx->options.mis, pdf, p_dir);
    double s = w * cos_i / pdf;
    vbl_vec3 b = vbl_v3(beta.x * f.x * s, beta.y * f.y * s, beta.z * f.z * s);
    vbl_vec3 origin = vbl_surface_spawn(scene->surfaces, hit->position, hit->geometric_normal, wi);
    vbl_emission_collect(ctx, ts, origin, wi, b, rng, L);
}

/* The phase-sampled (or BRDF-sampled) half of pt's MIS pair at a terminal first vertex: the
 * emission collected along the sampled direction, weighted against the light sampling pdf. */
static void vbl_emission_continuation(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 x, vbl_vec3 wi,
                                      double pdf, vbl_vec3 f, vbl_rng* rng, vbl_vec3* L)
{
    const vbl_scene* scene = ctx->scene;
    if (!(pdf > 0.0) || !(vbl_v3_max_component(f) > 0.0)) return;
    double w = vbl_mis_weight(ctx->options.mis, pdf, vbl_emission_lights_pdf(&scene->emission_lights, x, wi));
    vbl_emission_collect(ctx, ts, x, wi, vbl_v3_scale(f, w / pdf), rng, L);
}

void vbl_camera_media_emission(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_camera_sample* sample,
                               int direct, vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_scene* scene = ctx->scene;
    if (!scene->has_emission) return;
    if (ctx->options.max_bounces == 0) direct = 0;
    const vbl_vec3 o = sample->origin, d = sample->direction, one = vbl_v3(1.0, 1.0, 1.0);
    double components[VBL_MAX_MEDIA] = {0}, t = 0.0, sigma_t = 0.0;
    vbl_emission_visit_state e = {scene, &ts->emission, one, &out->L[VBL_CLASS_VOLUME_EMISSION]};
    int collided = vbl_ctx_free_flight_visit(ctx, ts, o, d, sample->t_max, rng, &t, &sigma_t, components,
                                             vbl_emission_visit, &e);
    if (collided) {
        if (!(direct & VBL_EMISSION_DIRECT_VOLUME) || !(sigma_t > 0.0)) return;
        vbl_medium_point mp;
        vbl_medium_point_from_components(scene, components, &mp);
        const vbl_vec3 x = vbl_v3_madd(o, d, t);
        vbl_medium_point_apply_grids(scene, x, ts->cursor.time, &mp); /* albedo grids */
        vbl_vec3* L = &out->L[VBL_CLASS_VOLUME_DIRECT];
        vbl_emission_nee_medium(ctx, ts, x, d, sigma_t, &mp, 0, NULL, NULL, one, rng, L);
        double u0 = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng), pdf = 0.0;
        vbl_vec3 wi;
        if (!vbl_medium_phase_sample(&mp, d, u0, u1, u2, &wi, &pdf)) return;
        vbl_vec3 k = vbl_v3_scale(vbl_medium_phase_kernel(&mp, vbl_v3_dot(d, wi)), 1.0 / sigma_t);
        vbl_emission_continuation(ctx, ts, x, wi, pdf, k, rng, L);
        return;
    }
    if (!(direct & VBL_EMISSION_DIRECT_SURFACE) || !scene->surfaces || !isfinite(sample->t_max)) return;
    vbl_surface_hit hit; /* the surface the ray reached (probability T(0, t_max)) */
    if (!vbl_surfaces_intersect(scene->surfaces, o, d, 0.0, INFINITY, &hit)) return;
    const vbl_vec3 wo = vbl_v3_scale(d, -1.0);
    vbl_vec3* L = &out->L[VBL_CLASS_SURFACE_DIRECT];
    vbl_emission_nee_surface(ctx, ts, &hit, wo, 0, NULL, NULL, one, rng, L);
    const vbl_material* m = &scene->materials[hit.material];
    double u0 = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng), pdf = 0.0;
    vbl_vec3 wi, f;
    if (!vbl_material_sample(m, hit.shading_normal, wo, u0, u1, u2, &wi, &pdf, &f) || !(pdf > 0.0)) return;
    double cos_i = vbl_v3_dot(wi, hit.shading_normal);
    if (!(cos_i > 0.0) || !(vbl_v3_dot(wi, hit.geometric_normal) > 0.0)) return;
    vbl_vec3 origin = vbl_surface_spawn(scene->surfaces, hit.position, hit.geometric_normal, wi);
    double w = vbl_mis_weight(ctx->options.mis, pdf, vbl_emission_lights_pdf(&scene->emission_lights, hit.position, wi));
    vbl_emission_collect(ctx, ts, origin, wi, vbl_v3_scale(f, cos_i * w / pdf), rng, L);
}
