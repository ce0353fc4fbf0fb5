/* Stratified single scattering along camera rays for pt (pt_direct_strata.h), on the medium
 * interface (media/medium.h). */
#include "transport/path_tracing/pt_direct_strata.h"

#include <math.h>

#include "media/medium.h"
#include "scene/lights.h"
#include "transport/path_tracing/pt_equiangular.h"
#include "volume/control_depth.h"
#include "volume/transmittance_cache.h"

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

/* Places the K stratified distances: u[k] ascending in [0, 1) -> t[k] and the proxy pdf p(t[k]).
 * Returns how many were placed (a u whose target depth rounds past tau_c(t0, t1) is dropped: a
 * set of measure zero). */
static int vbl_pt_ds_place(const vbl_extinction* ext, vbl_vec3 origin, vbl_vec3 direction, double t0, double t1,
                           int use_global, int count, const double* u, double* t, double* pdf)
{
    double tau_total = vbl_control_optical_depth(ext, origin, direction, t0, t1, use_global);
    if (!(tau_total > 0.0) || !isfinite(tau_total)) return 0;
    const double norm = -expm1(-tau_total); /* 1 - exp(-tau_c(t0, t1)), in (0, 1] */
    if (!(norm > 0.0)) return 0;
    vbl_extinction_iter iter;
    vbl_majorant_segment seg;
    vbl_extinction_iter_init(&iter, ext, origin, direction, t0, t1, use_global);
    double tau = 0.0;
    int k = 0;
    while (k < count && vbl_extinction_iter_next(&iter, &seg)) {
        double c = 0.5 * (seg.majorant + seg.minorant);
        if (!(c > 0.0)) continue;
        double seg_tau = c * (seg.t1 - seg.t0);
        while (k < count) {
            double survive = 1.0 - u[k] * norm; /* exp(-target depth) */
            double target = -log1p(-u[k] * norm);
            if (target > tau + seg_tau) break;
            double tk = seg.t0 + (target - tau) / c;
            t[k] = fmin(fmax(tk, seg.t0), seg.t1);
            pdf[k] = c * survive / norm;
            ++k;
        }
        tau += seg_tau;
    }
    return k;
}

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
    double t0, t1;
    if (!vbl_extinction_ray_bounds(ext, origin, direction, 0.0, t_surface, &t0, &t1) || !(t1 > t0)) return;
    double u[VBL_PT_DIRECT_STRATA_MAX], t[VBL_PT_DIRECT_STRATA_MAX], pdf[VBL_PT_DIRECT_STRATA_MAX];
    for (int k = 0; k < count; ++k) {
        u[k] = (k + vbl_rng_uniform(rng)) / count;
        if (!(u[k] < 1.0)) u[k] = nextafter(1.0, 0.0);
    }
    const int use_global = ctx->tracking.use_global_majorant;
    int placed = vbl_pt_ds_place(ext, origin, direction, t0, t1, use_global, count, u, t, pdf);
    if (placed == 0) return;
    /* one ratio-tracking pass from t0 to the farthest sample, read at every t_k */
    vbl_transmittance_cache cache;
    vbl_transmittance_cache_build_rr(&cache, VBL_TRANSMITTANCE_CACHED_RATIO, ext, &ts->cursor, origin, direction, t0,
                                     t[placed - 1], 0, use_global, ctx->tracking.rr_threshold, rng);
    for (int k = 0; k < placed; ++k) {
        double T_camera = vbl_transmittance_cache_eval(&cache, t[k]);
        /* the light pick and its sample are drawn whatever follows, so later samples keep their place */
        double u_pick = vbl_rng_uniform(rng), u1 = vbl_rng_uniform(rng), u2 = vbl_rng_uniform(rng);
        if (!(T_camera > 0.0) || !(pdf[k] > 0.0)) continue;
        const vbl_light* light = vbl_pt_ds_pick(ctx, n_lights, u_pick);
        if (!light) continue;
        vbl_vec3 x = vbl_v3_madd(origin, direction, t[k]);
        vbl_medium_point mp;
        if (!(vbl_medium_query(scene, ext, &ts->cursor, x, &mp) > 0.0)) continue;
        vbl_light_sample ls;
        if (!vbl_light_sample_incident(light, x, u1, u2, &ls) || !(vbl_v3_max_component(ls.li) > 0.0)) continue;
        vbl_vec3 kernel = vbl_medium_phase_kernel(&mp, vbl_v3_dot(direction, ls.wi));
        if (!(vbl_v3_max_component(kernel) > 0.0)) continue;
        double T_light = vbl_ctx_transmittance(ctx, ts, x, ls.wi, ls.distance, rng);
        if (!(T_light > 0.0)) continue;
        /* T^(t_k) K L T^_l / (K p(t_k) / N_s); ls.pdf is 1 for the delta lights fed here */
        double s = T_camera * T_light * n_lights / (count * pdf[k] * ls.pdf);
        if (!isfinite(s)) continue;
        L->x += beta.x * kernel.x * ls.li.x * s;
        L->y += beta.y * kernel.y * ls.li.y * s;
        L->z += beta.z * kernel.z * ls.li.z * s;
    }
}
