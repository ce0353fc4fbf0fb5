/* Volumetric path tracer (reference). The estimator of the RTE without surfaces:
 *   L(x, w) = int_0^inf T(x, x_t) sigma_s(x_t) int p(w', w) L_i(x_t, w') dw' dt + T(x, x_inf) L_e
 * Free paths by delta tracking (collision density sigma_t T, so the throughput is multiplied by
 * the scattering kernel / sigma_t at a real collision); one light chosen uniformly per vertex
 * for NEE; quad/environment lights combine NEE and phase sampling by MIS (Veach 1997, eq. 9.13
 * balance / 9.14 power heuristic). Lights do not occlude and are occluded only by media. */
#include "transport/pt.h"

#include <math.h>

#include "scene/lights.h"
#include "scene/media.h"

static void vbl_add_scaled(vbl_vec3* acc, vbl_vec3 a, vbl_vec3 b, double s)
{
    acc->x += a.x * b.x * s;
    acc->y += a.y * b.y * s;
    acc->z += a.z * b.z * s;
}

/* Light of quad/environment lights seen along (origin, direction) before t_limit (INFINITY:
 * the ray escaped the media, so the environment is seen too). prev_pdf is the phase pdf of
 * direction (ignored for camera rays, scatter_events == 0). */
static void vbl_pt_add_visible_lights(const vbl_render_context* ctx, vbl_vec3 origin, vbl_vec3 direction,
                                      double t_limit, int scatter_events, double prev_pdf, vbl_vec3 beta,
                                      vbl_sample_value* out)
{
    const vbl_scene* scene = ctx->scene;
    if (!scene->has_visible_lights) return;
    double select_pdf = 1.0 / scene->light_count;
    vbl_vec3* L = &out->L[vbl_class_for_scatter_events(scatter_events)];
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
        if (scatter_events > 0)
            w = vbl_mis_weight(ctx->options.mis, prev_pdf, select_pdf * vbl_light_pdf(light, origin, direction));
        vbl_add_scaled(L, beta, light->color, w);
    }
}

/* Next-event estimation at a scattering vertex x reached travelling along `travel`. */
static void vbl_pt_next_event(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 x, vbl_vec3 travel,
                              double sigma_t, const double* component_sigma_t, int scatter_events, vbl_vec3 beta,
                              vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_scene* scene = ctx->scene;
    if (scene->light_count == 0) return;
    double select_pdf = 1.0 / scene->light_count;
    int pick = (int)(vbl_rng_uniform(rng) * scene->light_count);
    if (pick >= scene->light_count) pick = scene->light_count - 1;
    const vbl_light* light = &scene->lights[pick];
    double u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng);
    vbl_light_sample ls;
    if (!vbl_light_sample_incident(light, x, u1, u2, &ls)) return;
    if (vbl_v3_max_component(ls.li) <= 0.0) return;
    double cos_theta = vbl_v3_dot(travel, ls.wi);
    vbl_vec3 kernel = vbl_media_scatter_kernel(scene, component_sigma_t, cos_theta);
    if (vbl_v3_max_component(kernel) <= 0.0) return;
    double T = vbl_ctx_transmittance(ctx, ts, x, ls.wi, ls.distance, rng);
    if (!(T > 0.0)) return;
    double w = 1.0;
    if (!ls.is_delta)
        w = vbl_mis_weight(ctx->options.mis, select_pdf * ls.pdf,
                           vbl_media_phase_pdf(scene, component_sigma_t, cos_theta));
    /* beta * (kernel / sigma_t) * L_i * T * w / (select_pdf * pdf) */
    double s = T * w / (select_pdf * ls.pdf * sigma_t);
    vbl_vec3* L = &out->L[vbl_class_for_scatter_events(scatter_events)];
    L->x += beta.x * kernel.x * ls.li.x * s;
    L->y += beta.y * kernel.y * ls.li.y * s;
    L->z += beta.z * kernel.z * ls.li.z * s;
}

void vbl_pt_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                          const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    (void)store;
    const vbl_scene* scene = ctx->scene;
    const int max_bounces = ctx->options.max_bounces;
    vbl_vec3 origin = sample->origin, direction = sample->direction;
    vbl_vec3 beta = vbl_v3(1.0, 1.0, 1.0);
    double prev_pdf = 0.0;
    double components[VBL_MAX_MEDIA] = {0};
    for (int scatter_events = 0;; ) {
        double t = INFINITY, sigma_t = 0.0;
        int collided = vbl_ctx_free_flight(ctx, ts, origin, direction, INFINITY, rng, &t, &sigma_t, components);
        if (!collided) t = INFINITY;
        vbl_pt_add_visible_lights(ctx, origin, direction, t, scatter_events, prev_pdf, beta, out);
        if (!collided || !(sigma_t > 0.0)) break;
        ++scatter_events;
        if (max_bounces >= 0 && scatter_events > max_bounces) break;
        vbl_vec3 x = vbl_v3_madd(origin, direction, t);
        vbl_pt_next_event(ctx, ts, x, direction, sigma_t, components, scatter_events, beta, rng, out);
        if (max_bounces >= 0 && scatter_events >= max_bounces) break;
        /* continue by sampling the sigma_s-weighted phase mixture */
        double u0 = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng);
        vbl_vec3 wi;
        double pdf = 0.0;
        if (!vbl_media_sample_phase(scene, components, direction, u0, u1, u2, &wi, &pdf)) break;
        vbl_vec3 kernel = vbl_media_scatter_kernel(scene, components, vbl_v3_dot(direction, wi));
        double s = 1.0 / (pdf * sigma_t);
        beta = vbl_v3(beta.x * kernel.x * s, beta.y * kernel.y * s, beta.z * kernel.z * s);
        if (!(vbl_v3_max_component(beta) > 0.0)) break;
        /* Russian roulette from the third scattering event on (unbiased: survivors / q) */
        if (scatter_events >= 3) {
            double q = fmin(1.0, vbl_v3_max_component(beta));
            if (vbl_rng_uniform(rng) >= q) break;
            beta = vbl_v3_scale(beta, 1.0 / q);
        }
        prev_pdf = pdf;
        origin = x;
        direction = wi;
    }
}

const vbl_estimator vbl_estimator_pt = {"pt", 0, NULL, vbl_pt_camera_sample, NULL};
