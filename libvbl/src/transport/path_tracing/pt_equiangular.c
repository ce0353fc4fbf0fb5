/* Equiangular NEE for pt (pt_equiangular.h), on the medium interface (media/medium.h). */
#include "transport/path_tracing/pt_equiangular.h"

#include <math.h>

#include "media/medium.h"
#include "sampling/equiangular.h"
#include "scene/lights.h"
#include "volume/control_depth.h"

static int vbl_pt_eq_light(const vbl_render_context* ctx, const vbl_light* light)
{
    if (light->type == VBL_LIGHT_POINT || light->type == VBL_LIGHT_SPOT) return 1;
    return light->type == VBL_LIGHT_QUAD && ctx->options.pt.equiangular_quads;
}

static int vbl_pt_eq_light_count(const vbl_render_context* ctx)
{
    int n = 0;
    for (int i = 0; i < ctx->scene->light_count; ++i) n += vbl_pt_eq_light(ctx, &ctx->scene->lights[i]);
    return n;
}

int vbl_pt_equiangular_active(const vbl_render_context* ctx)
{
    return ctx->options.pt.equiangular && ctx->extinction->count > 0 && vbl_pt_eq_light_count(ctx) > 0;
}

int vbl_pt_equiangular_quads_active(const vbl_render_context* ctx)
{
    return ctx->options.pt.equiangular_quads && vbl_pt_equiangular_active(ctx);
}

/* The majorant segments' mid-bound optical depth tau_c(t0, t) (volume/control_depth.h). */
static double vbl_pt_eq_control_depth(const vbl_render_context* ctx, vbl_segment seg, double t)
{
    return vbl_control_optical_depth(ctx->extinction, seg.origin, seg.direction, seg.t0, t,
                                     ctx->tracking.use_global_majorant);
}

/* Approximate free-flight density (per unit t) at t on the segment, sigma_t exp(-tau_c(t0, t)). */
static double vbl_pt_eq_ff_density(const vbl_render_context* ctx, vbl_segment seg, double t, double sigma_t)
{
    return sigma_t * exp(-vbl_pt_eq_control_depth(ctx, seg, t));
}

/* The weight h(a, b) of the strategy with density a; 1 where the other one cannot sample. */
static double vbl_pt_eq_weight(vbl_mis_heuristic heuristic, double a, double b)
{
    if (!(b > 0.0)) return 1.0;
    return vbl_mis_weight(heuristic, a, b);
}

/* Three strategies (Veach 1997, eq. 9.13 / 9.14 over n = 3): the weight of density a. */
static double vbl_pt_eq_weight3(vbl_mis_heuristic heuristic, double a, double b, double c)
{
    if (heuristic == VBL_MIS_BALANCE) return a + b + c > 0.0 ? a / (a + b + c) : 0.0;
    double a2 = a * a, s = a2 + b * b + c * c;
    return s > 0.0 ? a2 / s : 0.0;
}

/* The segment's media interval [t0, t1] up to t_surface (0: none). */
static int vbl_pt_eq_bounds(const vbl_render_context* ctx, vbl_vec3 origin, vbl_vec3 direction, double t_surface,
                            vbl_segment* seg)
{
    double t0, t1;
    if (!vbl_extinction_ray_bounds(ctx->extinction, origin, direction, 0.0, t_surface, &t0, &t1) || !(t1 > t0))
        return 0;
    *seg = vbl_segment_make(origin, direction, t0, t1);
    return 1;
}

double vbl_pt_equiangular_ff_weight(const vbl_render_context* ctx, const vbl_light* light, vbl_vec3 origin,
                                    vbl_vec3 direction, double t_surface, double t, double sigma_t)
{
    if (light->type == VBL_LIGHT_QUAD || !vbl_pt_eq_light(ctx, light) || !vbl_pt_equiangular_active(ctx)) return 1.0;
    vbl_segment seg;
    if (!vbl_pt_eq_bounds(ctx, origin, direction, t_surface, &seg)) return 1.0;
    double q_ea = vbl_equiangular_pdf(origin, direction, seg.t0, seg.t1, light->position, t) / vbl_pt_eq_light_count(ctx);
    if (!(q_ea > 0.0)) return 1.0;
    double q_ff = vbl_pt_eq_ff_density(ctx, seg, t, sigma_t) / ctx->scene->light_count;
    return vbl_pt_eq_weight(ctx->options.mis, q_ff, q_ea);
}

/* Densities of the three strategies for the path (medium vertex x at t on the segment, light
 * point y on a quad, direction wi from x to y), per unit t and solid angle at x:
 *   nee: the free-flight collision (sigma_t exp(-tau_c)) times the light pick (1/N) and the
 *        quad's area sampling in solid angle (light_pdf);
 *   phase: the collision times the phase pdf of wi (the scattered ray hits y);
 *   eq: y by the same area sampling (light_pdf), the pick among the N_eq lights, and t
 *       equiangular towards y. */
static void vbl_pt_eq_quad_densities(const vbl_render_context* ctx, vbl_segment seg, double t, double ff,
                                     vbl_vec3 y, double light_pdf, double phase_pdf, double* nee, double* phase,
                                     double* eq)
{
    *nee = ff * light_pdf / ctx->scene->light_count;
    *phase = ff * phase_pdf;
    *eq = vbl_equiangular_pdf(seg.origin, seg.direction, seg.t0, seg.t1, y, t) / vbl_pt_eq_light_count(ctx) * light_pdf;
}

double vbl_pt_equiangular_quad_weight(const vbl_render_context* ctx, const vbl_light* light,
                                      const vbl_pt_eq_vertex* v, vbl_vec3 wi, double distance, double phase_pdf,
                                      int strategy)
{
    const vbl_mis_heuristic h = ctx->options.mis;
    vbl_vec3 x = vbl_v3_madd(v->origin, v->direction, v->t);
    double light_pdf = vbl_light_pdf(light, x, wi);
    double nee, phase, eq;
    vbl_segment seg;
    if (!vbl_pt_eq_bounds(ctx, v->origin, v->direction, v->t_surface, &seg)) { /* eq cannot sample here */
        nee = light_pdf / ctx->scene->light_count;
        phase = phase_pdf;
        eq = 0.0;
    } else {
        vbl_pt_eq_quad_densities(ctx, seg, v->t, vbl_pt_eq_ff_density(ctx, seg, v->t, v->sigma_t),
                                 vbl_v3_madd(x, wi, distance), light_pdf, phase_pdf,
                                 &nee, &phase, &eq);
    }
    if (strategy == VBL_PT_EQ_NEE) return vbl_pt_eq_weight3(h, nee, phase, eq);
    return vbl_pt_eq_weight3(h, phase, nee, eq);
}

/* One equiangular sample on the segment's media interval seg (vbl_pt_equiangular_nee). */
static void vbl_pt_eq_sample(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_segment seg, int n_eq,
                             vbl_vec3 beta, double u_pick, double u_t, int phase_traced, vbl_medium_pdf_fn dir_pdf,
                             const void* dir_pdf_data, const vbl_pt_split_walk* walk, vbl_rng* rng, vbl_vec3* L)
{
    const vbl_scene* scene = ctx->scene;
    const vbl_extinction* ext = ctx->extinction;
    const vbl_vec3 origin = seg.origin, direction = seg.direction;
    int k = (int)(u_pick * n_eq);
    if (k >= n_eq) k = n_eq - 1;
    const vbl_light* light = NULL;
    for (int i = 0; i < scene->light_count; ++i)
        if (vbl_pt_eq_light(ctx, &scene->lights[i]) && k-- == 0) {
            light = &scene->lights[i];
            break;
        }
    if (!light) return;
    /* The target point: the light's position, or a point drawn uniformly on the quad first
     * (the same (u1, u2) -> point map as vbl_light_sample_incident, so its area pdf is the NEE's). */
    const int quad = light->type == VBL_LIGHT_QUAD;
    double u1 = 0.5, u2 = 0.5;
    vbl_vec3 target = light->position;
    if (quad) {
        u1 = vbl_rng_uniform(rng);
        u2 = vbl_rng_uniform(rng);
        target = vbl_v3_add(light->corner, vbl_v3_add(vbl_v3_scale(light->edge1, u1), vbl_v3_scale(light->edge2, u2)));
    }
    double pdf_t = 0.0;
    double t = vbl_equiangular_sample(origin, direction, seg.t0, seg.t1, target, u_t, &pdf_t);
    if (!(pdf_t > 0.0) || !(t >= seg.t0 && t <= seg.t1)) return;
    vbl_vec3 x = vbl_segment_at(&seg, t);
    vbl_medium_point mp;
    double sigma_t = vbl_medium_query(scene, ext, &ts->cursor, x, &mp);
    if (!(sigma_t > 0.0)) return;
    vbl_light_sample ls;
    if (!vbl_light_sample_incident(light, x, u1, u2, &ls) || !(vbl_v3_max_component(ls.li) > 0.0)) return;
    double cos_theta = vbl_v3_dot(direction, ls.wi);
    vbl_vec3 kernel = vbl_medium_phase_kernel(&mp, cos_theta);
    if (!(vbl_v3_max_component(kernel) > 0.0)) return;
    double T_camera, t_rest = seg.t0; /* the walk's running product up to t_rest, then an estimate */
    /* the walk's product where the segment is thin (a deterministic choice of (segment, t): unbiased) */
    const double tau_c = vbl_pt_eq_control_depth(ctx, seg, t);
    if (!(tau_c < VBL_PT_EQ_WALK_DEPTH)) walk = NULL;
    T_camera = walk ? vbl_pt_camera_split_transmittance(walk, t, &t_rest) : 1.0;
    if (T_camera != 0.0 && t_rest < t)
        T_camera *= vbl_transmittance_estimate(ext, &ts->cursor, origin, direction, t_rest, t, &ctx->tracking, rng);
    if (T_camera == 0.0) return; /* negative estimates kept (unbiased) */
    double T_light = vbl_ctx_transmittance(ctx, ts, x, ls.wi, ls.distance, rng);
    if (T_light == 0.0) return;
    double q, w;
    if (quad) {
        double nee, phase, eq;
        vbl_pt_eq_quad_densities(ctx, seg, t, sigma_t * exp(-tau_c), target, ls.pdf,
                                 !phase_traced ? 0.0
                                 : dir_pdf   ? dir_pdf(dir_pdf_data, &mp, x, direction, ls.wi)
                                             : vbl_medium_phase_pdf(&mp, cos_theta),
                                 &nee,
                                 &phase, &eq);
        q = eq;
        w = vbl_pt_eq_weight3(ctx->options.mis, eq, nee, phase);
    } else {
        q = pdf_t / n_eq;
        w = vbl_pt_eq_weight(ctx->options.mis, q, sigma_t * exp(-tau_c) / scene->light_count);
    }
    double s = T_camera * T_light * w / q;
    if (!isfinite(s)) return;
    L->x += beta.x * kernel.x * ls.li.x * s;
    L->y += beta.y * kernel.y * ls.li.y * s;
    L->z += beta.z * kernel.z * ls.li.z * s;
}

void vbl_pt_equiangular_nee(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                            vbl_vec3 direction, double t_surface, vbl_vec3 beta, double u_pick, double u_t,
                            int samples, int phase_traced, vbl_medium_pdf_fn dir_pdf, const void* dir_pdf_data,
                            const vbl_pt_split_walk* walk, vbl_rng* rng, vbl_vec3* L)
{
    vbl_segment seg;
    if (!vbl_pt_eq_bounds(ctx, origin, direction, t_surface, &seg)) return;
    const int n_eq = vbl_pt_eq_light_count(ctx);
    /* sample r at the distance stratum (r + u_t) / n and the light pick rotated by r / n: each
     * uniform, so the mean of the n estimates is unbiased */
    const vbl_vec3 b = vbl_v3_scale(beta, 1.0 / samples);
    for (int r = 0; r < samples; ++r)
        vbl_pt_eq_sample(ctx, ts, seg, n_eq, b, fmod(u_pick + (double)r / samples, 1.0), (r + u_t) / samples,
                         phase_traced, dir_pdf, dir_pdf_data, walk, rng, L);
}
