/* Single scattering along camera rays: equiangular sampling toward point/spot lights,
 * free-flight sampling + light sampling for distant/quad/environment lights, and for quad and
 * environment lights also a phase-sampled direction, MIS-combined (options.mis). */
#include "transport/common/single_scatter.h"

#include <math.h>

#include "sampling/equiangular.h"
#include "scene/lights.h"
#include "media/media.h"

static void vbl_ss_add(vbl_vec3* acc, vbl_vec3 kernel, vbl_vec3 li, double s)
{
    acc->x += kernel.x * li.x * s;
    acc->y += kernel.y * li.y * s;
    acc->z += kernel.z * li.z * s;
}

void vbl_single_scatter_estimate(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                 vbl_vec3 direction, vbl_rng* rng, vbl_vec3* radiance)
{
    vbl_single_scatter_estimate_to(ctx, ts, origin, direction, INFINITY, rng, radiance);
}

void vbl_single_scatter_estimate_to(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                    vbl_vec3 direction, double t_max, vbl_rng* rng, vbl_vec3* radiance)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_extinction* ext = ctx->extinction;
    if (ext->count == 0 || scene->light_count == 0 || !(t_max > 0.0)) return;
    double t0, t1;
    if (!vbl_extinction_ray_bounds(ext, origin, direction, 0.0, t_max, &t0, &t1) || !(t1 > t0)) return;
    double components[VBL_MAX_MEDIA] = {0};
    int has_non_delta = 0;

    /* point and spot lights: equiangular sampling of the distance */
    for (int i = 0; i < scene->light_count; ++i) {
        const vbl_light* light = &scene->lights[i];
        if (light->type != VBL_LIGHT_POINT && light->type != VBL_LIGHT_SPOT) {
            has_non_delta = 1;
            continue;
        }
        double pdf_t = 0.0;
        double t = vbl_equiangular_sample(origin, direction, t0, t1, light->position, vbl_rng_uniform(rng), &pdf_t);
        if (!(pdf_t > 0.0) || !(t >= t0 && t <= t1)) continue;
        vbl_vec3 x = vbl_v3_madd(origin, direction, t);
        double sigma_t = vbl_extinction_eval(ext, &ts->cursor, x, components);
        if (!(sigma_t > 0.0)) continue;
        vbl_light_sample ls;
        if (!vbl_light_sample_incident(light, x, 0.5, 0.5, &ls)) continue;
        vbl_vec3 kernel = vbl_media_scatter_kernel_at(scene, components, x, ts->cursor.time, vbl_v3_dot(direction, ls.wi));
        if (vbl_v3_max_component(kernel) <= 0.0 || vbl_v3_max_component(ls.li) <= 0.0) continue;
        double T_camera = vbl_transmittance_estimate(ext, &ts->cursor, origin, direction, t0, t, &ctx->tracking, rng);
        if (!(T_camera > 0.0)) continue;
        double T_light = vbl_ctx_transmittance(ctx, ts, x, ls.wi, ls.distance, rng);
        vbl_ss_add(radiance, kernel, ls.li, T_camera * T_light / pdf_t);
    }
    if (!has_non_delta) return;

    /* distant, quad and environment lights: one free flight, then each light sampled */
    double t = 0.0, sigma_t = 0.0;
    if (!vbl_free_flight_sample(ext, &ts->cursor, origin, direction, t0, t1, ctx->tracking.use_global_majorant, rng,
                                &t, &sigma_t, components) ||
        !(sigma_t > 0.0))
        return;
    vbl_vec3 x = vbl_v3_madd(origin, direction, t);
    for (int i = 0; i < scene->light_count; ++i) {
        const vbl_light* light = &scene->lights[i];
        if (light->type == VBL_LIGHT_POINT || light->type == VBL_LIGHT_SPOT) continue;
        double u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng);
        vbl_light_sample ls;
        if (!vbl_light_sample_incident(light, x, u1, u2, &ls)) continue;
        double cos_theta = vbl_v3_dot(direction, ls.wi);
        vbl_vec3 kernel = vbl_media_scatter_kernel_at(scene, components, x, ts->cursor.time, cos_theta);
        if (vbl_v3_max_component(kernel) <= 0.0 || vbl_v3_max_component(ls.li) <= 0.0) continue;
        double w = 1.0; /* quad, environment: MIS with the phase sample below */
        if (light->type != VBL_LIGHT_DISTANT)
            w = vbl_mis_weight(ctx->options.mis, ls.pdf, vbl_media_phase_pdf(scene, components, cos_theta));
        double T_light = vbl_ctx_transmittance(ctx, ts, x, ls.wi, ls.distance, rng);
        vbl_ss_add(radiance, kernel, ls.li, w * T_light / (ls.pdf * sigma_t));
    }
    if (!scene->has_visible_lights) return; /* distant lights only: light sampling is exact in direction */

    /* quad and environment lights: one phase-sampled direction, MIS-weighted against each light's
     * own sampling (Veach 1997, section 9.2, eq. 9.13/9.14). A near-delta lobe (|g| -> 1) is found
     * only this way; light sampling alone almost never lands in it. */
    vbl_vec3 wi;
    double pdf_phase = 0.0;
    double u0 = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng);
    if (!vbl_media_sample_phase(scene, components, direction, u0, u1, u2, &wi, &pdf_phase) || !(pdf_phase > 0.0))
        return;
    vbl_vec3 kernel = vbl_media_scatter_kernel_at(scene, components, x, ts->cursor.time, vbl_v3_dot(direction, wi));
    if (vbl_v3_max_component(kernel) <= 0.0) return;
    for (int i = 0; i < scene->light_count; ++i) {
        const vbl_light* light = &scene->lights[i];
        double t_hit = INFINITY;
        if (light->type == VBL_LIGHT_QUAD) {
            if (!vbl_quad_intersect(light, x, wi, &t_hit)) continue;
        } else if (light->type != VBL_LIGHT_ENVIRONMENT) {
            continue;
        }
        double pdf_light = vbl_light_pdf(light, x, wi);
        double w = vbl_mis_weight(ctx->options.mis, pdf_phase, pdf_light);
        if (!(w > 0.0) || vbl_v3_max_component(light->color) <= 0.0) continue;
        double T_light = vbl_ctx_transmittance(ctx, ts, x, wi, t_hit, rng);
        vbl_ss_add(radiance, kernel, light->color, w * T_light / (pdf_phase * sigma_t));
    }
}

static void vbl_single_scatter_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                                             const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    (void)store;
    vbl_single_scatter_estimate_to(ctx, ts, sample->origin, sample->direction, sample->t_max, rng,
                                   &out->L[VBL_CLASS_VOLUME_DIRECT]);
}

const vbl_estimator vbl_estimator_single_scatter = {"single-scatter", 0, NULL, vbl_single_scatter_camera_sample,
                                                    NULL};
