/* The split camera segment of pt (pt_camera_split.h), on the medium interface (media/medium.h). */
#include "transport/path_tracing/pt_camera_split.h"

#include <math.h>

#include "media/medium.h"
#include "media/medium_grids.h"
#include "volume/transmittance.h"

#define VBL_PT_SPLIT_RR 0.1 /* the walk's Russian-roulette threshold on T^ (as the transmittance estimators') */

int vbl_pt_camera_split_active(const vbl_render_context* ctx)
{
    return ctx->options.pt.camera_split && ctx->extinction->count > 0;
}

double vbl_pt_camera_split_sigma_s(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 p, double sigma_t,
                                  const double* comps)
{
    if (!(sigma_t > 0.0)) return 0.0;
    vbl_medium_point mp;
    vbl_medium_point_from_components(ctx->scene, comps, &mp);
    vbl_medium_point_apply_grids(ctx->scene, p, ts->cursor.time, &mp); /* albedo grids */
    return (mp.sigma_s.x + mp.sigma_s.y + mp.sigma_s.z) / 3.0;
}

static void vbl_pt_split_emit(vbl_emission_visit_state* e, vbl_vec3 beta, double T, vbl_vec3 p, double mu,
                              const double* comps)
{
    e->beta = vbl_v3_scale(beta, T);
    vbl_emission_visit(e, p, mu, comps);
}

/* The Z AOV's search past a walk that stopped at t: a delta-tracking flight over (t, t1). */
static void vbl_pt_split_depth_rest(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                                    vbl_vec3 direction, double t, double t1, vbl_rng* rng, vbl_pt_split_walk* walk)
{
    double d, sigma_t, comps[VBL_MAX_MEDIA];
    if (vbl_free_flight_sample_pattern(ctx->extinction, &ts->cursor, origin, direction, t, t1,
                                       ctx->tracking.use_global_majorant, rng, NULL, &d, &sigma_t, comps, NULL, NULL))
        walk->t_first = d;
}

void vbl_pt_camera_split_walk(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                              vbl_vec3 direction, double t_surface, double u_first, vbl_vec3 beta,
                              vbl_emission_visit_state* emission, int want_depth, vbl_rng* rng,
                              vbl_pt_split_walk* walk)
{
    const vbl_extinction* ext = ctx->extinction;
    walk->n = walk->capped = 0;
    walk->T_end = walk->T_after = 1.0;
    walk->t_first = -1.0;
    double t0, t1;
    if (ext->count == 0 || !vbl_extinction_ray_bounds(ext, origin, direction, 0.0, t_surface, &t0, &t1) ||
        !(t1 > t0))
        return;
    /* the Z AOV: delta tracking on the walk's own tentative points (each a real collision with
     * probability sigma_t / mu: the points are Poisson at rate mu >= sigma_t); where the walk
     * stops before one is found, a free flight from its last point (memoryless) ends the search */
    int seek_depth = want_depth;
    const int use_global = ctx->tracking.use_global_majorant;
    double T = 1.0, W = 0.0, t_last = t0;
    double tau = u_first >= 0.0 && u_first < 1.0 ? -log1p(-u_first) : -1.0; /* carried depth (vbl_exp_carry_step) */
    int n = 0;
    vbl_extinction_iter iter;
    vbl_majorant_segment seg;
    vbl_extinction_iter_init(&iter, ext, origin, direction, t0, t1, use_global);
    while (vbl_extinction_iter_next(&iter, &seg)) {
        /* every factor 1 - sigma_t / mu >= 7/8 (pt_camera_split.h) */
        const double mu = VBL_PT_WALK_MAJORANT_SCALE * seg.majorant;
        if (!(mu > 0.0)) continue;
        double t = seg.t0;
        while (vbl_exp_carry_step(&tau, &t, seg.t1, mu, rng)) {
            double comps[VBL_MAX_MEDIA];
            if (n == VBL_PT_SPLIT_POINTS) { /* the rest: one delta-tracking flight from the last point */
                double d, sigma_t;
                if (emission) emission->beta = vbl_v3_scale(beta, T);
                int hit = vbl_free_flight_sample_pattern(ext, &ts->cursor, origin, direction, t_last, t1, use_global,
                                                         rng, NULL, &d, &sigma_t, comps,
                                                         emission ? vbl_emission_visit : NULL, emission);
                if (seek_depth && hit) walk->t_first = d;
                walk->n = n;
                walk->capped = 1;
                walk->T_after = T;
                walk->T_end = hit ? 0.0 : T;
                if (hit) { /* the collision estimator: T^ sigma_s / sigma_t (the store has one spare entry) */
                    double ss = vbl_pt_camera_split_sigma_s(ctx, ts, vbl_v3_madd(origin, direction, d), sigma_t, comps);
                    double w = sigma_t > 0.0 ? T * ss / sigma_t : 0.0;
                    if (w > 0.0 && isfinite(w)) {
                        walk->t[n] = d;
                        walk->cum[n] = W + w;
                        walk->n = n + 1;
                    }
                }
                return;
            }
            const vbl_vec3 p = vbl_v3_madd(origin, direction, t);
            const double sigma_t = vbl_extinction_eval(ext, &ts->cursor, p, comps);
            if (emission && sigma_t > 0.0) vbl_pt_split_emit(emission, beta, T, p, mu, comps);
            W += T * vbl_pt_camera_split_sigma_s(ctx, ts, p, sigma_t, comps) / mu;
            walk->t[n] = t;
            walk->cum[n] = W;
            walk->T_before[n] = T;
            walk->n = ++n;
            t_last = t;
            if (seek_depth && vbl_rng_uniform(rng) * mu < sigma_t) {
                walk->t_first = t;
                seek_depth = 0;
            }
            const double f = 1.0 - sigma_t / mu;
            T *= f > 0.0 ? f : 0.0;
            if (!(T > 0.0)) {
                walk->T_end = walk->T_after = 0.0;
                if (seek_depth) vbl_pt_split_depth_rest(ctx, ts, origin, direction, t, t1, rng, walk);
                return;
            }
            if (T < VBL_PT_SPLIT_RR) { /* roulette: survivors carry T^ = threshold (unbiased) */
                if (vbl_rng_uniform(rng) >= T / VBL_PT_SPLIT_RR) {
                    walk->T_end = walk->T_after = 0.0;
                    if (seek_depth) vbl_pt_split_depth_rest(ctx, ts, origin, direction, t, t1, rng, walk);
                    return;
                }
                T = VBL_PT_SPLIT_RR;
            }
        }
    }
    walk->T_end = walk->T_after = T;
}

double vbl_pt_camera_split_transmittance(const vbl_pt_split_walk* walk, double t, double* t_rest)
{
    *t_rest = t;
    const int n = walk->capped ? VBL_PT_SPLIT_POINTS : walk->n; /* the tentative points */
    if (n == 0 || walk->t[n - 1] < t) { /* past every tentative point */
        if (walk->capped) *t_rest = walk->t[n - 1];
        return walk->T_after;
    }
    int lo = 0, hi = n - 1; /* the first point at or past t */
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if (walk->t[mid] >= t) hi = mid;
        else lo = mid + 1;
    }
    return walk->T_before[lo];
}

int vbl_pt_camera_split_pick(const vbl_pt_split_walk* walk, double u)
{
    if (walk->n <= 0) return -1;
    const double W = walk->cum[walk->n - 1];
    if (!(W > 0.0) || !isfinite(W)) return -1;
    const double target = u * W;
    int lo = 0, hi = walk->n - 1; /* the first i with cum[i] > target (cum is non-decreasing) */
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (walk->cum[mid] > target) hi = mid;
        else lo = mid + 1;
    }
    return walk->cum[lo] > target ? lo : -1;
}
