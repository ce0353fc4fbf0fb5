/* Public volume queries: point samples, transmittance estimates, estimator names. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/rng.h"
#include "volume/transmittance_cache.h"

#ifdef _OPENMP
#include <omp.h>
#endif

VBL_API double vbl_volume_sample(const vbl_volume* volume, const double world_point[3], vbl_filter filter)
{
    if (!volume || !world_point) return 0.0;
    vbl_grid_accessor acc;
    vbl_grid_accessor_init(&acc, volume);
    return vbl_grid_sample_world(&acc, vbl_v3(world_point[0], world_point[1], world_point[2]), filter);
}

static const char* const vbl_estimator_names[] = {"delta", "ratio", "residual", "march", "cached-delta", "cached-ratio"};
#define VBL_ESTIMATOR_COUNT ((int)(sizeof vbl_estimator_names / sizeof vbl_estimator_names[0]))

VBL_API const char* vbl_transmittance_estimator_name(vbl_transmittance_estimator estimator)
{
    int e = (int)estimator;
    return e >= 0 && e < VBL_ESTIMATOR_COUNT ? vbl_estimator_names[e] : "unknown";
}

VBL_API vbl_result vbl_transmittance_estimator_parse(const char* name, vbl_transmittance_estimator* out)
{
    if (!name || !out) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "estimator name is NULL");
    for (int e = 0; e < VBL_ESTIMATOR_COUNT; ++e)
        if (!strcmp(name, vbl_estimator_names[e])) {
            *out = (vbl_transmittance_estimator)e;
            return VBL_SUCCESS;
        }
    return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                     "unknown transmittance estimator '%s' (delta, ratio, residual, march, cached-delta, cached-ratio)",
                     name);
}

/* Samples are processed in fixed chunks whose partial statistics are merged in chunk order, so
 * the result does not depend on the thread count. */
#define VBL_TR_CHUNK 256

typedef struct vbl_tr_chunk {
    double n, mean, m2; /* Welford */
    uint64_t lookups;
} vbl_tr_chunk;

VBL_API vbl_result vbl_volume_transmittance(const vbl_volume* volume, const double origin[3],
                                            const double direction[3], double tmin, double tmax,
                                            const vbl_transmittance_options* options, unsigned samples,
                                            vbl_transmittance_result* out)
{
    if (!volume || !origin || !direction || !out)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_volume_transmittance: NULL argument");
    vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
    if (options) {
        if (options->size < sizeof(vbl_transmittance_options))
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_transmittance_options.size = %zu is too small",
                             options->size);
        opt = *options;
    }
    if ((int)opt.estimator < 0 || (int)opt.estimator >= VBL_ESTIMATOR_COUNT)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "transmittance estimator %d is unknown", (int)opt.estimator);
    if (!(opt.density_scale >= 0.0) || !isfinite(opt.density_scale))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "density_scale = %g must be finite and >= 0", opt.density_scale);
    if (samples == 0) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "samples = 0");
    if (isnan(tmin) || isnan(tmax) || !isfinite(tmin))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "ray interval [%g, %g] is not valid", tmin, tmax);
    for (int a = 0; a < 3; ++a)
        if (!isfinite(origin[a]) || !isfinite(direction[a]))
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "ray origin/direction must be finite");
    if (opt.cache_size < 0 || opt.cache_size > VBL_TRANSMITTANCE_CACHE_MAX)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "cache_size = %d is outside [0, %d]", opt.cache_size,
                         VBL_TRANSMITTANCE_CACHE_MAX);

    vbl_extinction ext;
    vbl_extinction_init(&ext);
    vbl_result r = vbl_extinction_add(&ext, volume, opt.density_scale, NULL);
    if (r != VBL_SUCCESS) return r;
    vbl_tracking_settings settings = {opt.estimator, opt.march_step, 0, 1.0, 0.0, 0, 0, 0, {0.0, 0.0}};
    const vbl_vec3 o = vbl_v3(origin[0], origin[1], origin[2]);
    const vbl_vec3 d = vbl_v3(direction[0], direction[1], direction[2]);

    const long chunks = (long)((samples + VBL_TR_CHUNK - 1) / VBL_TR_CHUNK);
    vbl_tr_chunk stack_parts[64];
    vbl_tr_chunk* parts = chunks <= 64 ? stack_parts : malloc((size_t)chunks * sizeof *parts);
    if (!parts) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vbl_volume_transmittance: %u samples", samples);
    const int parallel = chunks > 1
#ifdef _OPENMP
                         && !omp_in_parallel()
#endif
        ;
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
    for (long c = 0; c < chunks; ++c) {
        vbl_extinction_cursor cursor;
        vbl_extinction_cursor_init(&cursor, &ext);
        vbl_tr_chunk part = {0.0, 0.0, 0.0, 0};
        unsigned end = (unsigned)((c + 1) * VBL_TR_CHUNK) < samples ? (unsigned)((c + 1) * VBL_TR_CHUNK) : samples;
        for (unsigned s = (unsigned)(c * VBL_TR_CHUNK); s < end; ++s) {
            vbl_rng rng = vbl_rng_make(opt.seed, 0x7472616e736d6974ull, s);
            double x;
            if (opt.estimator == VBL_TRANSMITTANCE_CACHED_DELTA || opt.estimator == VBL_TRANSMITTANCE_CACHED_RATIO) {
                vbl_transmittance_cache cache;
                vbl_transmittance_cache_build(&cache, opt.estimator, &ext, &cursor, o, d, tmin, tmax, opt.cache_size,
                                              0, &rng);
                x = vbl_transmittance_cache_eval(&cache, tmax);
            } else {
                x = vbl_transmittance_estimate(&ext, &cursor, o, d, tmin, tmax, &settings, &rng);
            }
            part.n += 1.0;
            double delta = x - part.mean;
            part.mean += delta / part.n;
            part.m2 += delta * (x - part.mean);
        }
        part.lookups = vbl_extinction_cursor_lookups(&cursor);
        parts[c] = part;
    }
    /* Chan et al. merge, in chunk order. */
    double n = 0.0, mean = 0.0, m2 = 0.0;
    uint64_t lookups = 0;
    for (long c = 0; c < chunks; ++c) {
        double nb = parts[c].n, total = n + nb, delta = parts[c].mean - mean;
        mean += delta * nb / total;
        m2 += parts[c].m2 + delta * delta * n * nb / total;
        n = total;
        lookups += parts[c].lookups;
    }
    if (parts != stack_parts) free(parts);
    out->mean = mean;
    out->std_error = n > 1.0 ? sqrt(fmax(m2, 0.0) / (n - 1.0) / n) : 0.0;
    out->lookups = lookups;
    return VBL_SUCCESS;
}
