/* pt's split camera segment (option pt.camera_split; issue 14): the camera ray's first free
 * flight replaced by a forced scattering point and a transmittance-weighted surface/background
 * continuation, both traced.
 *
 * The camera segment's part of the RTE (pt.c),
 *   L = int_t0^t1 T(t0, t) [sigma_s(t) L_s(t) + sigma_a Le] dt + T(t0, t1) L_o(t1),
 * is estimated by delta tracking as one Bernoulli choice: a real collision (probability 1 - T)
 * continues in the medium, otherwise the path reaches the surface or the background. Where the
 * medium is semi-transparent that choice is most of a pixel's variance (each branch is seen only
 * part of the time). Here one ratio-tracking walk over the media along the camera ray (tentative
 * points p_i at the rate mu_i = VBL_PT_WALK_MAJORANT_SCALE x the majorant; Novak et al. 2014,
 * eq. 6) gives
 *  - every point the weight w_i = T^_{i-1} sigma_s(p_i) / mu_i, T^_{i-1} the product of
 *    (1 - sigma_t / mu) before p_i: sum_i w_i f(p_i) is the null-collision estimator of
 *    int T sigma_s f dt (Novak, Georgiev, Hanika and Jarosz 2018, "Monte Carlo methods for
 *    volumetric light transport simulation", sec. 5.2 and 6.2); one index k picked with
 *    probability w_k / W (W = sum w_i) turns it into W f(p_k) / sigma_s(p_k), a forced collision
 *    whose path continues in the medium with throughput W / sigma_s(p_k) times the kernel;
 *  - the end product T^ (the ratio-tracking estimate of T(t0, t1), Russian roulette below 0.1),
 *    which weights the surface or background continuation: the path also goes on to the surface
 *    with throughput T^ (splitting: both parts are traced, Vorba and Krivanek 2016 sec. 4 for
 *    splitting in general);
 *  - emissive media: at every tentative point beta T^_{i-1} sigma_a Le / mu (the null-collision
 *    emission estimator of pbrt-v4, sec. 14.2, with the ratio-tracking weight).
 * Past VBL_PT_SPLIT_POINTS points the rest of the segment is one delta-tracking free flight from
 * the last point (its collision, weighted T^ sigma_s / sigma_t, joins the candidates; reaching the
 * end keeps T^), so both parts stay unbiased. By Campbell's theorem over the walk's Poisson points
 * each part is unbiased for its term, whatever f is (the path's NEE, its MIS weights and its
 * continuation), so the split changes no mean, only the variance: a semi-transparent pixel sees
 * both its medium and what lies behind on every sample. */
#ifndef VBL_TRANSPORT_PT_CAMERA_SPLIT_H
#define VBL_TRANSPORT_PT_CAMERA_SPLIT_H

#include "transport/common/emission_estimate.h"
#include "transport/common/estimator.h"

#define VBL_PT_SPLIT_POINTS 256
/* The walk's rate over the majorant. At the majorant itself a factor 1 - sigma_t / mu is near 0
 * wherever the majorant is tight, so T^ and the weights jump like delta tracking's 0/1 and are
 * most of the forced point's variance; at 8x every factor is >= 7/8. Measured on the sun-lit
 * cloud (bench/pt_ab, docs/readme/performance.md): volume_direct rMAE at equal CPU against delta
 * tracking 0.91x at 1x, 0.73x at 2x, 0.63x at 4x, 0.58x at 8x with one path per walk (session
 * 9, when 4x was chosen); with pt.split_paths' two paths the walk's cost is shared, and 8x gives
 * volume_direct 0.79-0.83x of 4x at equal CPU on three race scenes, the other layers 1.01-1.06x
 * (session 11, bench/results/pt_walk_rate_split_s11.txt). */
#define VBL_PT_WALK_MAJORANT_SCALE 8.0

/* The walk along one camera segment: candidate points t[0..n) with the running sums of their
 * weights cum[i] = w_0 + ... + w_i, and the estimate T_end of the segment's transmittance. */
typedef struct vbl_pt_split_walk {
    double t_first; /* a delta-tracking collision's distance (the Z AOV; want_depth), or -1 */
    int n;
    double T_end;
    double t[VBL_PT_SPLIT_POINTS + 1], cum[VBL_PT_SPLIT_POINTS + 1];
    /* the running ratio-tracking product (vbl_pt_camera_split_transmittance): T_before[i] before
     * tentative point i, T_after past the last of them; capped: the walk stopped at
     * VBL_PT_SPLIT_POINTS points (the last at t[VBL_PT_SPLIT_POINTS - 1]) and went on by delta
     * tracking, whose collision may be entry n - 1 (not a tentative point) */
    int capped;
    double T_after;
    double T_before[VBL_PT_SPLIT_POINTS];
} vbl_pt_split_walk;

/* 1 if options.pt.camera_split is on and the scene has media. */
int vbl_pt_camera_split_active(const vbl_render_context* ctx);

/* The walk along origin + t direction (unit), t in [0, t_surface] (INFINITY: to the media's far
 * side). u_first in [0, 1) (or < 0: from rng) is the first tentative point's exponential depth.
 * With `emission` (emissive scenes) each tentative point adds beta T^ sigma_a Le / mu to
 * emission->L. With want_depth, walk->t_first is a delta-tracking collision along the segment
 * (drawn on the walk's own points) or -1; without it -1. No media on the segment: n = 0,
 * T_end = 1. */
void vbl_pt_camera_split_walk(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                              vbl_vec3 direction, double t_surface, double u_first, vbl_vec3 beta,
                              vbl_emission_visit_state* emission, int want_depth, vbl_rng* rng,
                              vbl_pt_split_walk* walk);

/* The walk's own estimate of the transmittance from its start to t (t inside the walked interval):
 * the running product of the factors 1 - sigma_t / mu of the tentative points before t, with the
 * walk's roulette (ratio tracking, Novak et al. 2014, eq. 6). For any t chosen independently of
 * the walk it is unbiased for T(t0, t); it costs no lookup. Where the walk was capped before t,
 * *t_rest = t_c < t, its last tentative point, and the result is the product up to t_c, which the
 * caller multiplies by an independent estimate of T(t_c, t) (unbiased: the running product times
 * the rest's transmittance is a martingale in the stopping point); else *t_rest = t. */
double vbl_pt_camera_split_transmittance(const vbl_pt_split_walk* walk, double t, double* t_rest);

/* The candidate picked by u in [0, 1): index i with cum[i - 1] <= u W < cum[i] (binary search);
 * -1 if the walk has no weight. */
int vbl_pt_camera_split_pick(const vbl_pt_split_walk* walk, double u);

/* Mean-RGB sigma_s of the media at p from their extinctions there (vbl_extinction_eval's sum and
 * components); 0 where nothing scatters. The walk's weights are T^ times it over mu. */
double vbl_pt_camera_split_sigma_s(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 p, double sigma_t,
                                   const double* comps);

#endif
