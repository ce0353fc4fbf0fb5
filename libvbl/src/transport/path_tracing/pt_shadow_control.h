/* pt.shadow_control (issue 14): a control variate for the shadow rays towards distant lights.
 *
 * Once per render, a deterministic transmittance grid towards each distant light over the media's
 * box (volume/sun_grid.h; surfaces that block the light zero its nodes). It serves two estimators,
 * both unbiased for any deterministic T_c, whose error only sets the variance left:
 *  - the camera-visible vertex (the camera walk's forced points, pt_camera_split.h): the walk's
 *    single scattering sum_i w_i f(p_i) (Novak et al. 2018, sec. 5.2) splits into
 *    sum_i w_i h(p_i) T_c(p_i), summed over the walk's candidates here (exactly for one medium of
 *    constant albedo, at stratified picks otherwise), and
 *    sum_i w_i h(p_i) (T - T_c)(p_i), estimated as before by the forced point, whose shadow ray now
 *    estimates T - T_c. Which point the pick lands on (lit skin or self-shadowed core) no longer
 *    moves the estimate by T's full range, only by T - T_c's;
 *  - deeper medium vertices (pt.shadow_roulette): where the roulette stops a shadow ray the
 *    estimate is T_c instead of 0, and a traced ray's T^ enters as T_c + (T^ - T_c) / q (Russian
 *    roulette on the difference to a control). The roulette's added variance falls from
 *    ~T^2 (1 - q) / q to ~E[(T^ - T_c)^2] (1 - q) / q, so it stops more rays: survival
 *    VBL_PT_SHADOW_CONTROL_RR_SCALE x pt.shadow_roulette's, at least VBL_PT_SHADOW_CONTROL_RR_MIN;
 *  - with pt.shadow_control_flight, the T_c part of those deeper vertices moves from the collision
 *    to the free flight that reached it: the control's single scattering along the segment,
 *    int_0^end T(t) sigma_s(t) f L T_c(t) dt, is summed over the flight's tentative collisions,
 *    each adding sigma_s(p_j) f L T_c(p_j) / mu_j (delta tracking's points are Poisson at rate mu
 *    and point t_j is reached with probability T(0, t_j): the track-length form of the collision
 *    estimator, cf. Novak et al. 2018, sec. 5.2), escaping flights included; the collision's shadow
 *    ray then estimates only T - T_c (roulette as above, 0 where stopped). A flight that leaves a
 *    cloud through its lit skin without colliding now adds the light it passed.
 * Measured in docs/readme/sampling.md ("A control variate for shadow rays towards distant lights"). */
#ifndef VBL_PT_SHADOW_CONTROL_H
#define VBL_PT_SHADOW_CONTROL_H

#include "transport/common/estimator.h"
#include "transport/path_tracing/pt_camera_split.h"
#include "volume/sun_grid.h"

/* Nodes per grid (1 MB of floats; the grid is no finer than the media's voxels). 1M nodes gave
 * the same variance at 3x the build time on the race clouds. */
#define VBL_PT_SHADOW_CONTROL_NODES ((size_t)1 << 18)
/* Distant lights that get a grid (the first ones in scene order); the others keep the plain
 * estimators. */
#define VBL_PT_SHADOW_CONTROL_LIGHTS 8
/* The deep vertices' roulette with the control: q = clamp(scale x pt.shadow_roulette's q before
 * its clamp, min, 1); 0.25 / 0.01 measured against 1 / 0.05 and 0.1 / 0.005 and 0.03 / 0.002 on
 * the race clouds (sampling.md). */
#define VBL_PT_SHADOW_CONTROL_RR_SCALE 0.25
#define VBL_PT_SHADOW_CONTROL_RR_MIN 0.01

/* The grids, one per light (scene->lights order; T NULL for lights without one), in *out; NULL
 * when the option is off or the scene has no media or no distant light. Fails with
 * VBL_ERROR_OUT_OF_MEMORY. */
vbl_result vbl_pt_shadow_control_build(const vbl_render_context* ctx, vbl_sun_grid** out);
void vbl_pt_shadow_control_free(vbl_sun_grid* grids, int count);

/* The grid of `light` (NULL: none). */
static inline const vbl_sun_grid* vbl_pt_shadow_control_of(const vbl_render_context* ctx, const vbl_light* light)
{
    if (!ctx->sun_grids || !light) return NULL;
    const vbl_sun_grid* g = &ctx->sun_grids[light - ctx->scene->lights];
    return g->T ? g : NULL;
}

/* 1 if the camera-visible vertex takes the control (vbl_pt_shadow_control_walk): grids built,
 * pt.camera_split on, volume_direct wanted and reached, pt.direct_strata off. */
int vbl_pt_shadow_control_first(const vbl_render_context* ctx);

/* Picks of the walk that estimate the control's sum where the NEE kernel over sigma_s differs
 * between candidates (several media, an albedo grid). */
#define VBL_PT_SHADOW_CONTROL_PICKS 8

/* Adds to *L the control's part of the camera-visible vertex's NEE from the distant lights with a
 * grid: beta sum_l Li_l sum_i w_i h(p_i) T_c,l(p_i) over the walk's candidates p_i = origin + t_i
 * direction (weights w_i), h = the NEE kernel over mean sigma_s at p_i. One medium of constant
 * albedo: h = albedo HG(g, cos_l) / mean albedo at every candidate, the sum exact. Otherwise the
 * sum is estimated at VBL_PT_SHADOW_CONTROL_PICKS stratified picks (j + u) / M of the weights
 * (u uniform in [0, 1); the medium's lookups through ts). */
void vbl_pt_shadow_control_walk(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_pt_split_walk* walk,
                                vbl_vec3 origin, vbl_vec3 direction, double u, vbl_vec3 beta, vbl_vec3* L);

/* pt.shadow_control_flight: 1 if the option, pt.shadow_control's grids and pt.shadow_roulette are
 * on and every medium has a constant albedo (the NEE kernel at a point is then sum_c sigma_c(p) x
 * a per-segment constant, from the flight's own lookups; with an albedo grid the collision keeps
 * the control as above). */
int vbl_pt_shadow_control_flight_active(const vbl_render_context* ctx);

/* The flight's state: per distant light l with a grid and medium c, the kernel albedo_c x colour_l
 * x HG(g_c, cos_l) (constant along the segment), and the sum over the tentative collisions of
 * sum_l sum_c kernel_lc sigma_c / mu x T_c,l (RGB); `next` (may be NULL) is another visitor the
 * flight also feeds (volume emission). */
typedef struct vbl_pt_control_flight {
    int media, count;
    const vbl_sun_grid* grid[VBL_PT_SHADOW_CONTROL_LIGHTS];
    vbl_vec3 kernel[VBL_PT_SHADOW_CONTROL_LIGHTS][VBL_MAX_MEDIA];
    vbl_vec3 sum;
    vbl_tracking_visit next;
    void* next_user;
} vbl_pt_control_flight;

/* Starts the segment travelling along unit `direction`. */
void vbl_pt_control_flight_begin(vbl_pt_control_flight* f, const vbl_render_context* ctx, vbl_vec3 direction,
                                 vbl_tracking_visit next, void* next_user);
/* The free flight's visitor (vbl_tracking_visit, user = the vbl_pt_control_flight): one tentative
 * collision at p, rate mu, per-component extinctions (media order). */
void vbl_pt_control_flight_visit(void* user, vbl_vec3 p, double mu, const double* per_component);
/* Adds beta x the sum to *L. */
void vbl_pt_control_flight_end(const vbl_pt_control_flight* f, vbl_vec3 beta, vbl_vec3* L);

#endif
