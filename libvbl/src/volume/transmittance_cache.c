/* Cached transmittance (Novak et al. 2012 (VRL), section 6, after Jarosz et al. 2011b). Both kinds
 * store a non-increasing step function: T(t0, t) ~ value[i] for the last t[i] <= t (1 before t[0]).
 *  - CACHED_DELTA: n independent Woodcock free-flight distances d_i (sorted; misses not stored);
 *    value[i] = (n - i - 1) / n, so T(t) ~ #(d_i > t) / n, unbiased since P(d > t) = T(t0, t).
 *  - CACHED_RATIO: one ratio-tracking pass (Novak et al. 2014) over [t0, t1]; t[i] are the
 *    tentative points, value[i] the running product with Russian roulette on small weights. The
 *    ratio estimator of T(t0, t) uses exactly the points before t, so one pass serves every t. If
 *    a pass would need more than VBL_TRANSMITTANCE_CACHE_MAX points, the tail after the last stored
 *    point is one fresh delta-tracking distance d (value 0 from d on): still unbiased. */
#include "volume/transmittance_cache.h"

#include <stdlib.h>

int vbl_ratio_track_record(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                           vbl_vec3 direction, double t0, double t1, int use_global, double rr_threshold, vbl_rng* rng,
                           void (*record)(void* user, double t, double weight), void* user, int max_records);

int vbl_unit_ray(vbl_vec3* direction, double* t0, double* t1, double* len);

static int vbl_cmp_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static void vbl_cache_record(void* user, double t, double weight)
{
    vbl_transmittance_cache* cache = user;
    if (cache->count >= VBL_TRANSMITTANCE_CACHE_MAX) return; /* cannot happen: capped by the caller */
    cache->t[cache->count] = t;
    cache->value[cache->count] = weight;
    cache->count++;
}

void vbl_transmittance_cache_build(vbl_transmittance_cache* cache, vbl_transmittance_estimator kind,
                                   const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                   vbl_vec3 direction, double t0, double t1, int entries, int use_global_majorant,
                                   vbl_rng* rng)
{
    vbl_transmittance_cache_build_rr(cache, kind, ext, cursor, origin, direction, t0, t1, entries, use_global_majorant,
                                     0.0, rng);
}

void vbl_transmittance_cache_build_rr(vbl_transmittance_cache* cache, vbl_transmittance_estimator kind,
                                      const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                      vbl_vec3 direction, double t0, double t1, int entries, int use_global_majorant,
                                      double rr_threshold, vbl_rng* rng)
{
    cache->kind = kind;
    cache->t0 = t0;
    cache->t1 = t1 > t0 ? t1 : t0;
    cache->count = 0;
    double len;
    if (!(t1 > t0) || !vbl_unit_ray(&direction, &t0, &t1, &len)) return;
    if (kind == VBL_TRANSMITTANCE_CACHED_DELTA) {
        int n = entries > 0 ? entries : 16;
        if (n > VBL_TRANSMITTANCE_CACHE_MAX) n = VBL_TRANSMITTANCE_CACHE_MAX;
        for (int i = 0; i < n; ++i) {
            double d;
            if (vbl_free_flight_sample(ext, cursor, origin, direction, t0, t1, use_global_majorant, rng, &d, NULL,
                                       NULL))
                cache->t[cache->count++] = d / len;
        }
        qsort(cache->t, (size_t)cache->count, sizeof(double), vbl_cmp_double);
        for (int i = 0; i < cache->count; ++i) cache->value[i] = (double)(n - i - 1) / (double)n;
        return;
    }
    /* CACHED_RATIO: the last slot is kept for the delta-tracking tail. */
    vbl_ratio_track_record(ext, cursor, origin, direction, t0, t1, use_global_majorant, rr_threshold, rng, vbl_cache_record, cache,
                           VBL_TRANSMITTANCE_CACHE_MAX - 1);
    for (int i = 0; i < cache->count; ++i) cache->t[i] /= len; /* back to the caller's t */
}

double vbl_transmittance_cache_eval(const vbl_transmittance_cache* cache, double t)
{
    if (t > cache->t1) t = cache->t1;
    /* Last index with t[i] <= t (binary search). */
    int lo = 0, hi = cache->count; /* answer in [lo-1, hi-1] */
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (cache->t[mid] <= t) lo = mid + 1;
        else hi = mid;
    }
    return lo == 0 ? 1.0 : cache->value[lo - 1];
}
