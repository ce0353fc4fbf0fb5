/* Virtual point lights along camera rays: the point kernel (vpl.h, virtual_lights_kernel.h). */
#include "transport/virtual_lights/vpl.h"

#include <math.h>

#include "core/error.h"
#include "sampling/equiangular.h"
#include "media/medium.h"
#include "transport/virtual_lights/virtual_lights_kernel.h"

void vbl_vpl_settings_from_options(const vbl_render_options* o, vbl_vpl_settings* out)
{
    vbl_vpl_settings d = VBL_VPL_SETTINGS_DEFAULT;
    *out = d;
    out->clamp_distance = o->vpl.clamp_distance;
}

static vbl_result vbl_vpl_begin(const vbl_render_context* ctx, const void* settings_, vbl_vl_store* s)
{
    const vbl_vpl_settings* settings = settings_;
    if (!(settings->clamp_distance >= 0.0 && isfinite(settings->clamp_distance)))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vpl clamp_distance = %g must be finite and >= 0",
                         ctx->scene->path, settings->clamp_distance);
    s->point = *settings;
    s->trace.store_vpls = 1;
    s->trace.cache_kind = VBL_TRANSMITTANCE_CACHED_RATIO;
    s->trace.cache_entries = 16;
    return VBL_SUCCESS;
}

static vbl_result vbl_vpl_after_trace(const vbl_render_context* ctx, vbl_vl_store* s)
{
    vbl_medium_point media;
    vbl_medium_point_scene(ctx->scene, &media);
    s->g_camera = vbl_medium_mean_g(&media); /* the camera samplers' hint */
    s->gather.vpls = 1;
    s->gather.clamp_distance = s->point.clamp_distance; /* surface VSLs are VPLs: R = 0 */
    s->gather.g_camera = s->g_camera;
    return VBL_SUCCESS;
}

/* VPL j's volume_from_volume (vpl.h): u equiangular toward the VPL, one sample. */
static void vbl_vpl_estimate(const vbl_vl_gather* g, size_t j, double v0, double v1, double weight)
{
    (void)v0, (void)v1, (void)weight; /* points: the whole light, weight 1 */
    const vbl_render_context* ctx = g->ctx;
    const vbl_vl_store* s = g->s;
    const vbl_scene* scene = ctx->scene;
    const vbl_vec3 o = g->cam->ray.origin, d = g->cam->ray.direction;
    const double u0 = g->cam->ray.t0, u1 = g->cam->ray.t1;
    const double clamp2 = s->point.clamp_distance * s->point.clamp_distance;
    vbl_medium_point mu;
    const vbl_vpl* p = &s->photons.vpls[j];
    double pdf = 0.0;
    double u = vbl_equiangular_sample(o, d, u0, u1, p->position, vbl_rng_uniform(g->rng), &pdf);
    if (!(pdf > 0.0)) return;
    vbl_vec3 xu = vbl_v3_madd(o, d, u);
    vbl_vec3 to = vbl_v3_sub(xu, p->position);
    double w2 = vbl_v3_dot(to, to);
    if (!(w2 > 0.0)) return;
    double w = sqrt(w2);
    vbl_vec3 omega = vbl_v3_scale(to, 1.0 / w); /* light travels VPL -> x_u */
    double sigma_t = vbl_medium_query(scene, ctx->extinction, &g->ts->cursor, xu, &mu);
    if (!(sigma_t > 0.0)) return;
    double Tc = vbl_transmittance_cache_eval(&g->cam->cache, u);
    if (!(Tc > 0.0)) return;
    vbl_vec3 ku = vbl_medium_phase_kernel(&mu, -vbl_v3_dot(omega, d));
    vbl_vec3 iv = vbl_vpl_intensity(scene, p, vbl_v3_dot(p->incident, omega));
    vbl_vec3 f = vbl_v3_mul(ku, iv);
    if (!(vbl_v3_max_component(f) > 0.0)) return;
    double Tw = vbl_ctx_transmittance(ctx, g->ts, p->position, omega, w, g->rng);
    if (!(Tw > 0.0)) return;
    double geom = 1.0 / (clamp2 > w2 ? clamp2 : w2);
    *g->acc = vbl_v3_madd(*g->acc, f, Tc * Tw * geom / pdf);
}

const vbl_vl_kernel vbl_vl_kernel_point = {"vpl", 1, 1, 0, vbl_vpl_begin, vbl_vpl_after_trace, vbl_vpl_estimate};

static vbl_result vbl_vpl_pass_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vpl_settings settings;
    vbl_vpl_settings_from_options(&ctx->options, &settings);
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_point, &settings, store);
}

const vbl_estimator vbl_estimator_vpl = {"vpl", 1, vbl_vpl_pass_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};
