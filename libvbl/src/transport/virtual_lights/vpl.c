/* Virtual point lights along camera rays (vpl.h). */
#include "transport/virtual_lights/vpl.h"

#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "sampling/equiangular.h"
#include "sampling/phase_hg.h"
#include "media/medium.h"
#include "transport/common/emission_estimate.h"
#include "transport/common/light_emission.h"
#include "transport/common/photon_trace.h"
#include "transport/common/single_scatter.h"
#include "transport/surface/surface_gather.h"
#include "volume/transmittance_cache.h"

typedef struct vbl_vpl_store {
    vbl_vpl_settings settings;
    vbl_photon_store photons;
    vbl_surface_gather_settings gather; /* surfaces: VPLs and surface VSLs as point lights */
} vbl_vpl_store;

vbl_result vbl_vpl_pass_begin_with(const vbl_render_context* ctx, const vbl_vpl_settings* settings, void** store)
{
    *store = NULL;
    if (!(settings->clamp_distance >= 0.0 && isfinite(settings->clamp_distance)))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vpl clamp_distance = %g must be finite and >= 0",
                         ctx->scene->path, settings->clamp_distance);
    vbl_vpl_store* s = calloc(1, sizeof *s);
    if (!s) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (vpl store)", ctx->scene->path);
    s->settings = *settings;
    vbl_photon_settings ps = {0, 1, 0, VBL_TRANSMITTANCE_CACHED_RATIO, 16};
    vbl_result r = vbl_photon_trace_with_surfaces(ctx, &ps, ctx->scene->surfaces != NULL, &s->photons);
    if (r) {
        free(s);
        return r;
    }
    vbl_medium_point media;
    vbl_medium_point_scene(ctx->scene, &media);
    s->gather.vpls = 1;
    s->gather.clamp_distance = settings->clamp_distance; /* surface VSLs are VPLs: R = 0 */
    s->gather.g_camera = vbl_medium_mean_g(&media); /* the camera samplers' hint */
    if ((r = vbl_surface_gather_blue_noise_begin(ctx, &s->gather))) { /* render.vsl_placement */
        vbl_photon_store_free(&s->photons);
        free(s);
        return r;
    }
    *store = s;
    return VBL_SUCCESS;
}

vbl_photon_store* vbl_vpl_store_photons(void* store)
{
    return store ? &((vbl_vpl_store*)store)->photons : NULL;
}

vbl_surface_gather_settings* vbl_vpl_store_gather(void* store)
{
    return store ? &((vbl_vpl_store*)store)->gather : NULL;
}

void vbl_vpl_settings_from_options(const vbl_render_options* o, vbl_vpl_settings* out)
{
    vbl_vpl_settings d = VBL_VPL_SETTINGS_DEFAULT;
    *out = d;
    out->clamp_distance = o->vpl.clamp_distance;
}

static vbl_result vbl_vpl_pass_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vpl_settings settings;
    vbl_vpl_settings_from_options(&ctx->options, &settings);
    return vbl_vpl_pass_begin_with(ctx, &settings, store);
}

void vbl_vpl_pass_end(const vbl_render_context* ctx, void* store)
{
    (void)ctx;
    vbl_vpl_store* s = store;
    if (!s) return;
    vbl_surface_gather_blue_noise_end(&s->gather);
    vbl_photon_store_free(&s->photons);
    free(s);
}

void vbl_vpl_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                           const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_vpl_store* s = store;
    const vbl_scene* scene = ctx->scene;
    const vbl_vec3 o = sample->origin, d = sample->direction;
    const int M = ctx->options.max_bounces;
    vbl_add_visible_emission(ctx, ts, o, d, rng, out);
    vbl_camera_media_emission(ctx, ts, sample, VBL_EMISSION_DIRECT_VOLUME | VBL_EMISSION_DIRECT_SURFACE, rng, out);
    if (M != 0 && vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_DIRECT))
        vbl_single_scatter_estimate_to(ctx, ts, o, d, sample->t_max, rng, &out->L[VBL_CLASS_VOLUME_DIRECT]);
    if (scene->surfaces && s) vbl_surface_gather_hit(ctx, ts, &s->photons, &s->gather, sample, rng, out);
    if (!s || (s->photons.vpl_count == 0 && s->photons.surface_vsl_count == 0 && !s->gather.blue_noise)) return;
    /* render.hybrid: with both media classes of the camera segment owned by pt, no segment work */
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_VOLUME) && !vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_SURFACE)) return;

    vbl_transmittance_cache cache;
    double u0, u1;
    if (!vbl_camera_segment_cache_to(ctx, ts, o, d, sample->t_max, rng, &cache, &u0, &u1)) return;
    vbl_surface_gather_segment(ctx, ts, &s->photons, &s->gather, sample, &cache, u0, u1, rng, out);
    const double clamp2 = s->settings.clamp_distance * s->settings.clamp_distance;
    vbl_medium_point mu;
    vbl_vec3 acc = vbl_v3(0.0, 0.0, 0.0);
    if (!vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_FROM_VOLUME)) return; /* render.hybrid: pt owns it */
    for (size_t j = 0; j < s->photons.vpl_count; ++j) {
        if (j % VBL_STOP_CHECK_EVERY == VBL_STOP_CHECK_EVERY - 1 && vbl_render_stop_requested(ctx)) break;
        const vbl_vpl* p = &s->photons.vpls[j];
        if (M >= 0 && p->bounce + 1 > M) continue;
        double pdf = 0.0;
        double u = vbl_equiangular_sample(o, d, u0, u1, p->position, vbl_rng_uniform(rng), &pdf);
        if (!(pdf > 0.0)) continue;
        vbl_vec3 xu = vbl_v3_madd(o, d, u);
        vbl_vec3 to = vbl_v3_sub(xu, p->position);
        double w2 = vbl_v3_dot(to, to);
        if (!(w2 > 0.0)) continue;
        double w = sqrt(w2);
        vbl_vec3 omega = vbl_v3_scale(to, 1.0 / w); /* light travels VPL -> x_u */
        double sigma_t = vbl_medium_query(scene, ctx->extinction, &ts->cursor, xu, &mu);
        if (!(sigma_t > 0.0)) continue;
        double Tc = vbl_transmittance_cache_eval(&cache, u);
        if (!(Tc > 0.0)) continue;
        vbl_vec3 ku = vbl_medium_phase_kernel(&mu, -vbl_v3_dot(omega, d));
        vbl_vec3 iv = vbl_vpl_intensity(scene, p, vbl_v3_dot(p->incident, omega));
        vbl_vec3 f = vbl_v3_mul(ku, iv);
        if (!(vbl_v3_max_component(f) > 0.0)) continue;
        double Tw = vbl_ctx_transmittance(ctx, ts, p->position, omega, w, rng);
        if (!(Tw > 0.0)) continue;
        double geom = 1.0 / (clamp2 > w2 ? clamp2 : w2);
        acc = vbl_v3_madd(acc, f, Tc * Tw * geom / pdf);
    }
    out->L[VBL_CLASS_VOLUME_FROM_VOLUME] = vbl_v3_add(out->L[VBL_CLASS_VOLUME_FROM_VOLUME], acc);
}

const vbl_estimator vbl_estimator_vpl = {"vpl", 1, vbl_vpl_pass_begin, vbl_vpl_camera_sample, vbl_vpl_pass_end};
