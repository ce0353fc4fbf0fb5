/* Stratified single scattering along camera rays for pt (pt_direct_strata.h), on the medium
 * interface (media/medium.h). */
#include "transport/path_tracing/pt_direct_strata.h"

#include <math.h>

#include "media/medium.h"
#include "media/medium_grids.h"
#include "scene/lights.h"
#include "transport/path_tracing/pt_camera_split.h"
#include "transport/path_tracing/pt_equiangular.h"
#include "volume/transmittance.h"

static int vbl_pt_ds_light(const vbl_render_context* ctx, const vbl_light* light)
{
    if (light->type == VBL_LIGHT_DISTANT) return 1;
    if (light->type == VBL_LIGHT_POINT || light->type == VBL_LIGHT_SPOT) return !vbl_pt_equiangular_active(ctx);
    return 0;
}

static int vbl_pt_ds_light_count(const vbl_render_context* ctx)
{
    int n = 0;
    for (int i = 0; i < ctx->scene->light_count; ++i) n += vbl_pt_ds_light(ctx, &ctx->scene->lights[i]);
    return n;
}

int vbl_pt_direct_strata_active(const vbl_render_context* ctx)
{
    if (ctx->options.pt.direct_strata <= 1 || ctx->extinction->count == 0) return 0;
    if (ctx->options.max_bounces == 0) return 0;
    return vbl_pt_ds_light_count(ctx) > 0;
}

int vbl_pt_direct_strata_skips(const vbl_render_context* ctx, const vbl_light* light)
{
    return vbl_pt_ds_light(ctx, light) && vbl_pt_direct_strata_active(ctx);
}

static double vbl_pt_ds_mean(vbl_vec3 v) { return (v.x + v.y + v.z) / 3.0; }

/* One of the N_s lights the estimator feeds, picked by u in [0, 1). */
static const vbl_light* vbl_pt_ds_pick(const vbl_render_context* ctx, int n, double u)
{
    int k = (int)(u * n);
    if (k >= n) k = n - 1;
    for (int i = 0; i < ctx->scene->light_count; ++i)
        if (vbl_pt_ds_light(ctx, &ctx->scene->lights[i]) && k-- == 0) return &ctx->scene->lights[i];
    return NULL;
}

void vbl_pt_direct_strata(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                          vbl_vec3 direction, double t_surface, vbl_vec3 beta, vbl_rng* rng, vbl_vec3* L)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_extinction* ext = ctx->extinction;
    const int n_lights = vbl_pt_ds_light_count(ctx);
    if (n_lights == 0) return;
    int count = ctx->options.pt.direct_strata;
    if (count > VBL_PT_DIRECT_STRATA_MAX) count = VBL_PT_DIRECT_STRATA_MAX;
    vbl_pt_split_walk walk; /* the camera split's walk: its points, weights and roulette (pt_camera_split.h) */
    vbl_pt_camera_split_walk(ctx, ts, origin, direction, t_surface, -1.0, beta, NULL, 0, rng, &walk);
    const int n = walk.n;
    const double *t = walk.t, *cum = walk.cum;
    if (n == 0) return;
    const double W = cum[n - 1];
    if (!(W > 0.0) || !isfinite(W)) return;
    int i = 0;
    for (int k = 0; k < count; ++k) {
        /* stratum k of the weights' CDF: u in [k, k + 1) / K, then the first point past it */
        double target = (k + vbl_rng_uniform(rng)) / count * W;
        double u_pick = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng);
        while (i < n - 1 && !(cum[i] > target)) ++i;
        const vbl_light* light = vbl_pt_ds_pick(ctx, n_lights, u_pick);
        if (!light) continue;
        vbl_vec3 x = vbl_v3_madd(origin, direction, t[i]);
        vbl_medium_point mp;
        if (!(vbl_medium_query(scene, ext, &ts->cursor, x, &mp) > 0.0)) continue;
        double ss = vbl_pt_ds_mean(mp.sigma_s);
        if (!(ss > 0.0)) continue;
        vbl_light_sample ls;
        if (!vbl_light_sample_incident(light, x, u1, u2, &ls) || !(vbl_v3_max_component(ls.li) > 0.0)) continue;
        vbl_vec3 kernel = vbl_medium_phase_kernel(&mp, vbl_v3_dot(direction, ls.wi));
        if (!(vbl_v3_max_component(kernel) > 0.0)) continue;
        double T_light = vbl_ctx_transmittance(ctx, ts, x, ls.wi, ls.distance, rng);
        if (T_light == 0.0) continue; /* unbiased-march estimates may be negative: kept (unbiased) */
        /* (W / K) (kernel / sigma_s) L T_l / (pdf / N_s); ls.pdf is 1 for the delta lights fed here */
        double s = W * T_light * n_lights / (count * ss * ls.pdf);
        if (!isfinite(s)) continue;
        L->x += beta.x * kernel.x * ls.li.x * s;
        L->y += beta.y * kernel.y * ls.li.y * s;
        L->z += beta.z * kernel.z * ls.li.z * s;
    }
}
