/* pt.shadow_control's grids and the camera walk's control sum (pt_shadow_control.h). */
#include "transport/path_tracing/pt_shadow_control.h"

#include <stdlib.h>

#include "media/medium.h"
#include "media/medium_grids.h"
#include "sampling/phase_hg.h"
#include "transport/path_tracing/pt_direct_strata.h"

/* The sweep's visibility test: a surface between the node and the light (Embree; thread-safe). */
static int vbl_pt_shadow_control_occluded(void* user, vbl_vec3 x, vbl_vec3 w)
{
    return vbl_ctx_occluded((const vbl_render_context*)user, x, w, INFINITY);
}

vbl_result vbl_pt_shadow_control_build(const vbl_render_context* ctx, vbl_sun_grid** out)
{
    *out = NULL;
    const vbl_scene* scene = ctx->scene;
    if (!ctx->options.pt.shadow_control || ctx->extinction->count == 0) return VBL_SUCCESS;
    int any = 0;
    for (int i = 0; i < scene->light_count; ++i) any |= scene->lights[i].type == VBL_LIGHT_DISTANT;
    vbl_vec3 lo, hi;
    if (!any || !vbl_scene_media_box(scene, &lo, &hi)) return VBL_SUCCESS;
    vbl_sun_grid* grids = calloc((size_t)scene->light_count, sizeof *grids);
    if (!grids) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "out of memory for pt.shadow_control's grids");
    int built = 0;
    for (int i = 0; i < scene->light_count && built < VBL_PT_SHADOW_CONTROL_LIGHTS; ++i) {
        if (scene->lights[i].type != VBL_LIGHT_DISTANT) continue;
        vbl_result r = vbl_sun_grid_build(&grids[i], ctx->extinction, lo, hi, vbl_v3_scale(scene->lights[i].direction, -1.0),
                                          VBL_PT_SHADOW_CONTROL_NODES, ctx->threads,
                                          scene->surfaces ? vbl_pt_shadow_control_occluded : NULL, (void*)ctx);
        if (r) {
            vbl_pt_shadow_control_free(grids, scene->light_count);
            return r;
        }
        ++built;
    }
    *out = grids;
    return VBL_SUCCESS;
}

void vbl_pt_shadow_control_free(vbl_sun_grid* grids, int count)
{
    if (!grids) return;
    for (int i = 0; i < count; ++i) vbl_sun_grid_free(&grids[i]);
    free(grids);
}

int vbl_pt_shadow_control_first(const vbl_render_context* ctx)
{
    return ctx->sun_grids && vbl_pt_camera_split_active(ctx) && vbl_ctx_wants(ctx, VBL_CLASS_VOLUME_DIRECT) &&
           ctx->options.max_bounces != 0 && !vbl_pt_direct_strata_active(ctx);
}

/* One medium of constant albedo: the NEE kernel over sigma_s is the same at every candidate. */
static int vbl_pt_shadow_control_uniform(const vbl_render_context* ctx)
{
    return ctx->extinction->count == 1 && ctx->scene->media[0].albedo_volume[0] == NULL;
}

/* The NEE kernel of medium m towards the distant light with grid g, for a ray travelling along
 * `direction`, over m's extinction: albedo HG(g, cos) (vbl_medium_phase_kernel's lobe) times L_i. */
static vbl_vec3 vbl_pt_shadow_control_kernel(const vbl_medium* m, const vbl_light* light, const vbl_sun_grid* g,
                                             vbl_vec3 direction)
{
    return vbl_v3_scale(vbl_v3_mul(m->albedo, light->color), vbl_hg_eval(m->g, vbl_v3_dot(direction, g->w)));
}

void vbl_pt_shadow_control_walk(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_pt_split_walk* walk,
                                vbl_vec3 origin, vbl_vec3 direction, double u, vbl_vec3 beta, vbl_vec3* L)
{
    const vbl_scene* scene = ctx->scene;
    if (walk->n <= 0) return;
    if (vbl_pt_shadow_control_uniform(ctx)) { /* h is one constant: the exact sum over the candidates */
        const vbl_medium* m = &scene->media[0];
        const double mean = (m->albedo.x + m->albedo.y + m->albedo.z) / 3.0;
        if (!(mean > 0.0)) return;
        for (int l = 0; l < scene->light_count; ++l) {
            const vbl_sun_grid* g = &ctx->sun_grids[l];
            if (!g->T) continue;
            double sum = 0.0, prev = 0.0;
            for (int i = 0; i < walk->n; ++i) {
                const double w = walk->cum[i] - prev; /* the candidate's weight */
                prev = walk->cum[i];
                if (w > 0.0) sum += w * vbl_sun_grid_eval(g, vbl_v3_madd(origin, direction, walk->t[i]));
            }
            /* the forced point's NEE kernel over sigma_s: the kernel over sigma_t / mean albedo
             * (pt.c's beta W sigma_t / sigma_s times kernel / sigma_t, with one medium) */
            const vbl_vec3 k = vbl_pt_shadow_control_kernel(m, &scene->lights[l], g, direction);
            const double s = sum / mean;
            L->x += beta.x * k.x * s;
            L->y += beta.y * k.y * s;
            L->z += beta.z * k.z * s;
        }
        return;
    }
    /* Several media or an albedo grid: h differs per candidate, so the sum is estimated at
     * VBL_PT_SHADOW_CONTROL_PICKS stratified picks (j + u) / M of the walk's weights, each
     * W / M h(p) T_c(p) with the medium point as the forced point's NEE sees it (unbiased for the
     * sum whatever u's relation to the forced point's own pick). */
    const double W = walk->cum[walk->n - 1];
    const int M = VBL_PT_SHADOW_CONTROL_PICKS;
    double comps[VBL_MAX_MEDIA];
    for (int j = 0; j < M; ++j) {
        const int k = vbl_pt_camera_split_pick(walk, (j + u) / M);
        if (k < 0) continue;
        const vbl_vec3 p = vbl_v3_madd(origin, direction, walk->t[k]);
        const double sigma_t = vbl_extinction_eval(ctx->extinction, &ts->cursor, p, comps);
        if (!(sigma_t > 0.0)) continue;
        vbl_medium_point mp;
        vbl_medium_point_from_components(scene, comps, &mp);
        vbl_medium_point_apply_grids(scene, p, ts->cursor.time, &mp);
        const double ss = (mp.sigma_s.x + mp.sigma_s.y + mp.sigma_s.z) / 3.0;
        if (!(ss > 0.0)) continue;
        for (int l = 0; l < scene->light_count; ++l) {
            const vbl_sun_grid* g = &ctx->sun_grids[l];
            if (!g->T) continue;
            const vbl_vec3 kernel = vbl_medium_phase_kernel(&mp, vbl_v3_dot(direction, g->w));
            const vbl_light* light = &scene->lights[l];
            const double s = W / M * vbl_sun_grid_eval(g, p) / ss;
            L->x += beta.x * kernel.x * light->color.x * s;
            L->y += beta.y * kernel.y * light->color.y * s;
            L->z += beta.z * kernel.z * light->color.z * s;
        }
    }
}

int vbl_pt_shadow_control_flight_active(const vbl_render_context* ctx)
{
    if (!ctx->sun_grids || !ctx->options.pt.shadow_control_flight || !ctx->options.pt.shadow_roulette) return 0;
    for (int c = 0; c < ctx->extinction->count; ++c)
        if (ctx->scene->media[c].albedo_volume[0]) return 0;
    return ctx->extinction->count > 0;
}

void vbl_pt_control_flight_begin(vbl_pt_control_flight* f, const vbl_render_context* ctx, vbl_vec3 direction,
                                 vbl_tracking_visit next, void* next_user)
{
    const vbl_scene* scene = ctx->scene;
    f->media = ctx->extinction->count;
    f->count = 0;
    f->sum = vbl_v3(0.0, 0.0, 0.0);
    f->next = next;
    f->next_user = next_user;
    for (int l = 0; l < scene->light_count; ++l) {
        const vbl_sun_grid* g = vbl_pt_shadow_control_of(ctx, &scene->lights[l]);
        if (!g) continue;
        for (int c = 0; c < f->media; ++c) /* the collision's NEE kernel over sigma_c */
            f->kernel[f->count][c] = vbl_pt_shadow_control_kernel(&scene->media[c], &scene->lights[l], g, direction);
        f->grid[f->count++] = g;
    }
}

void vbl_pt_control_flight_visit(void* user, vbl_vec3 p, double mu, const double* per_component)
{
    vbl_pt_control_flight* f = user;
    if (f->next) f->next(f->next_user, p, mu, per_component);
    if (!(mu > 0.0)) return;
    for (int l = 0; l < f->count; ++l) {
        const double Tc = vbl_sun_grid_eval(f->grid[l], p);
        if (!(Tc > 0.0)) continue;
        for (int c = 0; c < f->media; ++c) {
            const double r = per_component[c] / mu; /* sigma_c / mu, in [0, 1]: mu bounds the sum */
            if (r > 0.0) f->sum = vbl_v3_madd(f->sum, f->kernel[l][c], r * Tc);
        }
    }
}

void vbl_pt_control_flight_end(const vbl_pt_control_flight* f, vbl_vec3 beta, vbl_vec3* L)
{
    L->x += beta.x * f->sum.x;
    L->y += beta.y * f->sum.y;
    L->z += beta.z * f->sum.z;
}
