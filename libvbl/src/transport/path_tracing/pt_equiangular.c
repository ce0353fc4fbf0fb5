/* Equiangular NEE for pt (pt_equiangular.h). */
#include "transport/path_tracing/pt_equiangular.h"

#include <math.h>

#include "sampling/equiangular.h"
#include "scene/lights.h"
#include "media/media.h"
#include "volume/control_depth.h"

static int vbl_pt_eq_light(const vbl_light* light)
{
    return light->type == VBL_LIGHT_POINT || light->type == VBL_LIGHT_SPOT;
}

static int vbl_pt_eq_light_count(const vbl_scene* scene)
{
    int n = 0;
    for (int i = 0; i < scene->light_count; ++i) n += vbl_pt_eq_light(&scene->lights[i]);
    return n;
}

int vbl_pt_equiangular_active(const vbl_render_context* ctx)
{
    return ctx->options.pt.equiangular && ctx->extinction->count > 0 &&
           vbl_pt_eq_light_count(ctx->scene) > 0;
}

/* Approximate free-flight density (per unit t) times the light-selection probability. */
static double vbl_pt_eq_q_ff(const vbl_render_context* ctx, vbl_vec3 origin, vbl_vec3 direction, double t0, double t,
                             double sigma_t)
{
    double tau = vbl_control_optical_depth(ctx->extinction, origin, direction, t0, t, ctx->tracking.use_global_majorant);
    return sigma_t * exp(-tau) / ctx->scene->light_count;
}

/* The weight h(a, b) of the strategy with density a; 1 where the other one cannot sample. */
static double vbl_pt_eq_weight(vbl_mis_heuristic heuristic, double a, double b)
{
    if (!(b > 0.0)) return 1.0;
    return vbl_mis_weight(heuristic, a, b);
}

double vbl_pt_equiangular_ff_weight(const vbl_render_context* ctx, const vbl_light* light, vbl_vec3 origin,
                                    vbl_vec3 direction, double t_surface, double t, double sigma_t)
{
    if (!vbl_pt_eq_light(light) || !vbl_pt_equiangular_active(ctx)) return 1.0;
    double t0, t1;
    if (!vbl_extinction_ray_bounds(ctx->extinction, origin, direction, 0.0, t_surface, &t0, &t1) || !(t1 > t0))
        return 1.0;
    double q_ea = vbl_equiangular_pdf(origin, direction, t0, t1, light->position, t) / vbl_pt_eq_light_count(ctx->scene);
    if (!(q_ea > 0.0)) return 1.0;
    return vbl_pt_eq_weight(ctx->options.mis, vbl_pt_eq_q_ff(ctx, origin, direction, t0, t, sigma_t), q_ea);
}

void vbl_pt_equiangular_nee(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                            vbl_vec3 direction, double t_surface, vbl_vec3 beta, double u_pick, double u_t,
                            vbl_rng* rng, vbl_vec3* L)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_extinction* ext = ctx->extinction;
    const int n_eq = vbl_pt_eq_light_count(scene);
    double t0, t1;
    if (!vbl_extinction_ray_bounds(ext, origin, direction, 0.0, t_surface, &t0, &t1) || !(t1 > t0)) return;
    int k = (int)(u_pick * n_eq);
    if (k >= n_eq) k = n_eq - 1;
    const vbl_light* light = NULL;
    for (int i = 0; i < scene->light_count; ++i)
        if (vbl_pt_eq_light(&scene->lights[i]) && k-- == 0) {
            light = &scene->lights[i];
            break;
        }
    if (!light) return;
    double pdf_t = 0.0;
    double t = vbl_equiangular_sample(origin, direction, t0, t1, light->position, u_t, &pdf_t);
    if (!(pdf_t > 0.0) || !(t >= t0 && t <= t1)) return;
    vbl_vec3 x = vbl_v3_madd(origin, direction, t);
    double components[VBL_MAX_MEDIA] = {0};
    double sigma_t = vbl_extinction_eval(ext, &ts->cursor, x, components);
    if (!(sigma_t > 0.0)) return;
    vbl_light_sample ls;
    if (!vbl_light_sample_incident(light, x, 0.5, 0.5, &ls) || !(vbl_v3_max_component(ls.li) > 0.0)) return;
    vbl_vec3 kernel = vbl_media_scatter_kernel_at(scene, components, x, ts->cursor.time, vbl_v3_dot(direction, ls.wi));
    if (!(vbl_v3_max_component(kernel) > 0.0)) return;
    double T_camera = vbl_transmittance_estimate(ext, &ts->cursor, origin, direction, t0, t, &ctx->tracking, rng);
    if (!(T_camera > 0.0)) return;
    double T_light = vbl_ctx_transmittance(ctx, ts, x, ls.wi, ls.distance, rng);
    if (!(T_light > 0.0)) return;
    double q_ea = pdf_t / n_eq;
    double w = vbl_pt_eq_weight(ctx->options.mis, q_ea, vbl_pt_eq_q_ff(ctx, origin, direction, t0, t, sigma_t));
    double s = T_camera * T_light * w / q_ea;
    if (!isfinite(s)) return;
    L->x += beta.x * kernel.x * ls.li.x * s;
    L->y += beta.y * kernel.y * ls.li.y * s;
    L->z += beta.z * kernel.z * ls.li.z * s;
}
