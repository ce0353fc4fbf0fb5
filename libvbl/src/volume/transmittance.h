/* Transmittance estimators and free-flight sampling over an extinction field. All of them walk
 * the same merged majorant segments (extinction.h); each counts its density lookups in the
 * cursor. Rays are scene-space origin + t * direction, t in [t0, t1]. */
#ifndef VBL_VOLUME_TRANSMITTANCE_H
#define VBL_VOLUME_TRANSMITTANCE_H

#include <math.h>

#include "core/rng.h"
#include "volume/extinction.h"
#include "volume/transmittance_unbiased_march.h"

typedef struct vbl_tracking_settings {
    vbl_transmittance_estimator estimator;
    double march_step;        /* ray marching step (world units); <= 0: adaptive */
    int use_global_majorant;  /* 1: ignore the majorant grid (parity tests, benchmarks) */
    /* > 1: delta / ratio / residual tracking draw tentative collisions at majorant_scale times the
     * (residual) majorant: majorant_scale times the lookups, lower variance (ratio tracking of a
     * constant sigma over length L: relative variance exp(sigma^2 L / mu) - 1). <= 1 (0 in older
     * initializers): the tight majorant. Free-flight sampling and the caches ignore it. */
    double majorant_scale;
    double rr_threshold;      /* ratio estimators' Russian-roulette threshold, (0, 1]; 0: 0.1 */
    /* Residual ratio tracking's control (issue 14 item 4): 0 (older initializers) the segment
     * minorant, rate majorant - minorant; 1 the mid-bound c = (majorant + minorant) / 2, rate
     * (majorant - minorant) / 2 = max |sigma_t - c| (factors 1 - (sigma_t - c) / mu in [0, 2]). */
    int residual_mid;
    /* 1: every estimator above is replaced by unbiased ray marching (transmittance_unbiased_march.h,
     * issue 14 item 4; pt.shadow_transmittance = unbiased-march); majorant_scale > 1 multiplies its
     * march density. 2: the adaptive march (vbl_unbiased_march_adaptive, pt.shadow_transmittance =
     * unbiased-march-adaptive), 3: the same at a deep path vertex. 0 (older initializers): off. */
    int unbiased_march;
    /* march_offsets > 0: the unbiased march's first factor march in each of the ray's first
     * march_offsets blocks places its strata systematically from march_offset[b] in [0, 1)
     * (vbl_unbiased_march_params.offsets; pt.sobol_shadow_march). The other estimators ignore
     * them. 0 (older initializers): off. */
    int march_offsets;
    double march_offset[VBL_UNBIASED_MARCH_OFFSETS];
} vbl_tracking_settings;

/* The next tentative collision of a Poisson process of piecewise-constant rate (rate mu on the
 * current segment, up to t1), with ONE exponential optical depth carried across segments: *tau
 * (< 0: none drawn yet) is the depth left to the next collision, drawn ~ Exp(1) once and reduced
 * by mu x length over each segment it crosses; a collision costs one log, a crossed segment none.
 * By memorylessness the depth left after a crossing is again Exp(1) and independent of the past,
 * so the points are the same process as a fresh exponential per segment (the optical-depth
 * inversion of regular tracking over piecewise-constant cells, Novak et al. 2018, "Monte Carlo
 * methods for volumetric light transport simulation", applied to the majorant segments).
 * Returns 1 with *t moved to the collision if it lies in (*t, t1) (never stalls below an ulp),
 * else 0 with the depth to carry on (a collision that rounds onto t1 is dropped and the next
 * segment draws afresh: below an ulp). */
static inline int vbl_exp_carry_step(double* tau, double* t, double t1, double mu, vbl_rng* rng)
{
    if (!(*tau >= 0.0)) *tau = -log1p(-vbl_rng_uniform(rng));
    const double room = mu * (t1 - *t);
    if (*tau >= room) {
        *tau -= room;
        return 0;
    }
    double next = *t + *tau / mu;
    *tau = -1.0;
    if (!(next > *t)) next = nextafter(*t, INFINITY);
    if (next >= t1) return 0;
    *t = next;
    return 1;
}

/* One estimate of T(t0, t1) (unbiased for every estimator except ray marching). The cached
 * estimators are not valid here (use transmittance_cache.h). */
double vbl_transmittance_estimate(const vbl_extinction* ext, vbl_extinction_cursor* cursor,
                                  vbl_vec3 origin, vbl_vec3 direction, double t0, double t1,
                                  const vbl_tracking_settings* settings, vbl_rng* rng);

/* Delta-tracking free-flight sampling: draws a real collision at t in (t0, t1) with density
 * sigma_t(t) T(t0, t). Returns 1 and sets *t_collision and *sigma_t_at (and per-component
 * sigma_t when `per_component` is not NULL) on a collision, 0 if the ray passes t1 (probability
 * T(t0, t1)). */
int vbl_free_flight_sample(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                           vbl_vec3 direction, double t0, double t1, int use_global_majorant,
                           vbl_rng* rng, double* t_collision, double* sigma_t_at, double* per_component);

/* Called by vbl_free_flight_sample_visit at every tentative collision point p (null or real,
 * before the real/null decision) with the majorant mu it was drawn with, and the per-component
 * sigma_t there. Summing f(p) / mu over these points estimates int_0^d T(t) f(x_t) dt without
 * bias (the null-collision formulation: the points are a Poisson process of rate mu, and the
 * walk reaches each with probability T); in a homogeneous segment (known sigma) only the real
 * collision is drawn, with mu = sigma (the collision estimator). */
typedef void (*vbl_tracking_visit)(void* user, vbl_vec3 p, double mu, const double* per_component);

/* vbl_free_flight_sample with a visitor (the same random numbers, the same collisions); the
 * direction is made unit first, so `p` is a scene point and mu per world unit. per_component
 * must not be NULL. */
int vbl_free_flight_sample_visit(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                 vbl_vec3 direction, double t0, double t1, int use_global_majorant, vbl_rng* rng,
                                 double* t_collision, double* sigma_t_at, double* per_component,
                                 vbl_tracking_visit visit, void* visit_user);

/* vbl_free_flight_sample_visit (visit may be NULL) whose first u_first_count uniforms are taken
 * from u_first instead of rng, in the order the flight consumes them: the exponential optical
 * depth to the first tentative collision (carried across majorant segments, vbl_exp_carry_step),
 * then the first real/null decision (u < sigma_t / mu), then the next depth, ...; the rest come
 * from rng. With u_first uniform on [0, 1)^n the collision law is delta tracking's; a caller's
 * low-discrepancy pair there stratifies the first tentative collision and whether it is real (pt,
 * pt.sampler = sobol). u_first NULL or u_first_count 0: vbl_free_flight_sample_visit exactly. */
int vbl_free_flight_sample_pattern(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                   vbl_vec3 direction, double t0, double t1, int use_global_majorant, vbl_rng* rng,
                                   const double* u, double* t_collision, double* sigma_t_at,
                                   double* per_component, vbl_tracking_visit visit, void* visit_user);

#endif
