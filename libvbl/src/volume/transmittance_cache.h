/* Cached transmittance along a ray (Novak et al. 2012 (VRL), section 6, after Jarosz et al. 2011b):
 * one traversal stores a few tracked distances; afterwards T(t0, t) for any t in [t0, t1] is
 * estimated unbiasedly in O(log n).
 *  - VBL_TRANSMITTANCE_CACHED_DELTA: n independent Woodcock collision distances;
 *    T(t) ~ #(d_i > t) / n.
 *  - VBL_TRANSMITTANCE_CACHED_RATIO: one ratio-tracking pass records the tentative collision
 *    points and running products; T(t) ~ product over points before t (lower variance). */
#ifndef VBL_VOLUME_TRANSMITTANCE_CACHE_H
#define VBL_VOLUME_TRANSMITTANCE_CACHE_H

#include "volume/transmittance.h"

#define VBL_TRANSMITTANCE_CACHE_MAX 256

typedef struct vbl_transmittance_cache {
    vbl_transmittance_estimator kind; /* CACHED_DELTA or CACHED_RATIO */
    double t0, t1;
    int count;
    double t[VBL_TRANSMITTANCE_CACHE_MAX];     /* sorted distances / tentative points */
    double value[VBL_TRANSMITTANCE_CACHE_MAX]; /* CACHED_RATIO: product up to and incl. t[i] */
} vbl_transmittance_cache;

/* `entries`: number of Woodcock distances (CACHED_DELTA, typically 16); ignored for ratio. */
void vbl_transmittance_cache_build(vbl_transmittance_cache* cache, vbl_transmittance_estimator kind,
                                   const vbl_extinction* ext, vbl_extinction_cursor* cursor,
                                   vbl_vec3 origin, vbl_vec3 direction, double t0, double t1,
                                   int entries, int use_global_majorant, vbl_rng* rng);

/* The same with the ratio-tracking Russian-roulette threshold (0: the default 0.1,
 * volume/transmittance.c); a lower one gives a less noisy cache deep in dense media, at the cost
 * of more lookups. */
void vbl_transmittance_cache_build_rr(vbl_transmittance_cache* cache, vbl_transmittance_estimator kind,
                                      const vbl_extinction* ext, vbl_extinction_cursor* cursor,
                                      vbl_vec3 origin, vbl_vec3 direction, double t0, double t1,
                                      int entries, int use_global_majorant, double rr_threshold, vbl_rng* rng);

/* Unbiased estimate of T(t0, t) for t in [t0, t1] (t is clamped into it). */
double vbl_transmittance_cache_eval(const vbl_transmittance_cache* cache, double t);

#endif
