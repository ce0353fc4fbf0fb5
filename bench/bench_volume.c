/* bench_volume [FILE.vdb] [--density-scale S] [--gap] [--exact R] [--coarse-depth K] [--coarse-ratio R]: density lookups/s (PNanoVDB trilinear vs OpenVDB
 * ValueAccessor + BoxSampler), majorant block sizes, and transmittance queries/s, variance and
 * efficiency (1 / (variance x time)) for every estimator and cache at 1 and 2 threads, and ratio /
 * residual tracking at k x the majorant (vbl_tracking_settings.majorant_scale); --gap adds unbiased
 * ray marching (transmittance_unbiased_march.h) at several march densities; --exact R compares the
 * trackers' mean T with the exact mean over the rays in R independent replicas (z-scores). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/rng.h"
#include "volume/transmittance_cache.h"
#include "volume/transmittance_unbiased_march.h"

double vbl_bench_openvdb_lookups(const char* path, const char* grid_name, const double* points, size_t n,
                                 double* checksum);

static double now(void) { return omp_get_wtime(); }
/* --gap times 1-thread runs in this thread's CPU time: on a shared, loaded machine wall time
 * counts the other jobs' slices too. */
static int g_cpu_clock = 0;
static double clock_now(void)
{
    if (!g_cpu_clock) return now();
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct bench_ray { vbl_vec3 o, d; double t1; } bench_ray;

static void make_points(const vbl_volume_info* info, double* pts, size_t n, int coherent)
{
    vbl_rng rng = vbl_rng_make(1, 2, (uint64_t)coherent);
    double lo[3], ext[3];
    for (int a = 0; a < 3; ++a) lo[a] = info->world_bbox_min[a], ext[a] = info->world_bbox_max[a] - lo[a];
    double step = 0.5 * fmin(info->voxel_size[0], fmin(info->voxel_size[1], info->voxel_size[2]));
    vbl_vec3 p = vbl_v3(0, 0, 0), d = vbl_v3(1, 0, 0);
    for (size_t i = 0; i < n; ++i) {
        if (!coherent || i % 256 == 0) {
            p = vbl_v3(lo[0] + ext[0] * vbl_rng_uniform(&rng), lo[1] + ext[1] * vbl_rng_uniform(&rng),
                       lo[2] + ext[2] * vbl_rng_uniform(&rng));
            d = vbl_v3_normalize(vbl_v3(vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5));
        } else {
            p = vbl_v3_madd(p, d, step); /* along a ray: half-voxel steps (tracking-like access) */
        }
        pts[3 * i] = p.x, pts[3 * i + 1] = p.y, pts[3 * i + 2] = p.z;
    }
}

/* Rays through the bbox: random origin on a sphere around it, aimed at a random interior point. */
static void make_rays(const vbl_volume_info* info, bench_ray* rays, int n)
{
    vbl_rng rng = vbl_rng_make(3, 4, 5);
    double c[3], r = 0.0;
    for (int a = 0; a < 3; ++a) {
        c[a] = 0.5 * (info->world_bbox_min[a] + info->world_bbox_max[a]);
        double e = info->world_bbox_max[a] - info->world_bbox_min[a];
        r += 0.25 * e * e;
    }
    r = sqrt(r);
    for (int i = 0; i < n; ++i) {
        double z = 2 * vbl_rng_uniform(&rng) - 1, phi = 2 * VBL_PI * vbl_rng_uniform(&rng), s = sqrt(1 - z * z);
        vbl_vec3 o = vbl_v3(c[0] + r * s * cos(phi), c[1] + r * s * sin(phi), c[2] + r * z);
        vbl_vec3 target = vbl_v3(c[0] + 0.3 * r * (vbl_rng_uniform(&rng) - 0.5), c[1] + 0.3 * r * (vbl_rng_uniform(&rng) - 0.5),
                                 c[2] + 0.3 * r * (vbl_rng_uniform(&rng) - 0.5));
        rays[i].o = o;
        rays[i].d = vbl_v3_normalize(vbl_v3_sub(target, o));
        rays[i].t1 = 2.0 * r;
    }
}

static double g_majorant_scale = 1.0; /* vbl_tracking_settings.majorant_scale of run_estimator */
static int g_residual_mid = 0;        /* vbl_tracking_settings.residual_mid of run_estimator */
static double g_coarse_depth = -9.0;  /* --coarse-depth: vbl_extinction.coarse_depth (-9: default) */
static double g_coarse_ratio = -1.0;  /* --coarse-ratio: vbl_extinction.coarse_ratio (< 0: default) */
static int g_unbiased = 0;            /* 1: run_estimator runs unbiased ray marching with g_um */
static vbl_unbiased_march_params g_um;
static uint64_t g_seed = 0;           /* added to run_estimator's seed (--exact replicas; 0 elsewhere) */

/* Runs `spr` estimates on each ray; returns seconds; fills mean per-ray variance and lookups. */
static double run_estimator(const vbl_extinction* ext, const bench_ray* rays, int nrays, int spr,
                            vbl_transmittance_estimator est, int use_global, int threads, double* mean_var,
                            double* mean_t, double* lookups_per_query)
{
    double var_sum = 0.0, t_sum = 0.0;
    unsigned long long lookups = 0;
    double t0 = clock_now();
#pragma omp parallel num_threads(threads) reduction(+ : var_sum, t_sum, lookups)
    {
        vbl_extinction_cursor cur;
        vbl_extinction_cursor_init(&cur, ext);
        vbl_tracking_settings set = {est, 0.0, use_global, g_majorant_scale, 0.0, g_residual_mid, 0, 0, {0.0, 0.0}};
#pragma omp for schedule(dynamic, 4)
        for (int r = 0; r < nrays; ++r) {
            double s = 0.0, s2 = 0.0;
            for (int k = 0; k < spr; ++k) {
                vbl_rng rng = vbl_rng_make(77 + g_seed, (uint64_t)r, (uint64_t)k);
                double x;
                if (g_unbiased) {
                    x = vbl_transmittance_unbiased_march(ext, &cur, rays[r].o, rays[r].d, 0.0, rays[r].t1, use_global,
                                                         &g_um, &rng);
                } else if (est == VBL_TRANSMITTANCE_CACHED_DELTA || est == VBL_TRANSMITTANCE_CACHED_RATIO) {
                    vbl_transmittance_cache cache;
                    vbl_transmittance_cache_build(&cache, est, ext, &cur, rays[r].o, rays[r].d, 0.0, rays[r].t1, 16,
                                                  use_global, &rng);
                    x = vbl_transmittance_cache_eval(&cache, rays[r].t1);
                } else {
                    x = vbl_transmittance_estimate(ext, &cur, rays[r].o, rays[r].d, 0.0, rays[r].t1, &set, &rng);
                }
                s += x;
                s2 += x * x;
            }
            double m = s / spr;
            var_sum += fmax(s2 / spr - m * m, 0.0) * spr / (spr - 1.0);
            t_sum += m;
        }
        lookups += vbl_extinction_cursor_lookups(&cur);
    }
    double secs = clock_now() - t0;
    *mean_var = var_sum / nrays;
    *mean_t = t_sum / nrays;
    *lookups_per_query = (double)lookups / ((double)nrays * spr);
    return secs;
}

/* --gap (issue 14 item 5): the tracking core against the lookup limit. The raw rate is trilinear
 * lookups at points along rays (half-voxel steps, 1 thread); a transmittance query of ratio
 * tracking (DDA majorants) costs lookups/query x the raw lookup time at best, so "x of the limit"
 * = (raw lookups/s / lookups per query) / queries/s. Thick: the default density scale (mean T
 * moderate); thin: a quarter of it (shadow rays through thin smoke). */
static int run_gap(vbl_volume* v, const vbl_volume_info* info, double scale)
{
    const size_t n = 2000000;
    double* pts = malloc(sizeof(double) * 3 * n);
    make_points(info, pts, n, 1);
    vbl_grid_accessor acc;
    vbl_grid_accessor_init(&acc, v);
    double sum = 0.0, best = 1e300;
    g_cpu_clock = 1;
    for (int rep = 0; rep < 3; ++rep) { /* best of 3: the machine is shared */
        double t0 = clock_now();
        for (size_t i = 0; i < n; ++i)
            sum += vbl_grid_sample_world(&acc, vbl_v3(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]), VBL_FILTER_TRILINEAR);
        double dt = clock_now() - t0;
        if (dt < best) best = dt;
    }
    free(pts);
    const double raw = (double)n / best;
    int nrays = 2000;
    bench_ray* rays = malloc(sizeof *rays * (size_t)nrays);
    make_rays(info, rays, nrays);
    if (scale <= 0.0) scale = 4.0 / (info->value_max * 64.0 * info->voxel_size[0]);
    double segs = 0.0, nonempty = 0.0, steps = 0.0, walk = 1e300;
    for (int rep = 0; rep < 3; ++rep) { /* the walk alone (thick medium's scale), best of 3 */
        vbl_extinction e1;
        vbl_extinction_init(&e1);
        if (g_coarse_depth > -2.0) e1.coarse_depth = g_coarse_depth;
        if (g_coarse_ratio >= 0.0) e1.coarse_ratio = g_coarse_ratio;
        vbl_extinction_add(&e1, v, scale, NULL);
        double s = 0.0, ne = 0.0, st = 0.0, chk = 0.0;
        double t0 = clock_now();
        for (int r = 0; r < 10 * nrays; ++r) { /* 10 walks per ray: a measurable time */
            vbl_extinction_iter it;
            vbl_majorant_segment seg;
            vbl_extinction_iter_init(&it, &e1, rays[r % nrays].o, rays[r % nrays].d, 0.0, rays[r % nrays].t1, 0);
            while (vbl_extinction_iter_next(&it, &seg)) {
                s += 1.0;
                ne += seg.majorant > 0.0;
                chk += seg.majorant * (seg.t1 - seg.t0);
            }
            st += (double)it.iters[0].steps;
        }
        double dt = clock_now() - t0;
        if (dt < walk) walk = dt;
        segs = s / (10.0 * nrays), nonempty = ne / (10.0 * nrays), steps = st / (10.0 * nrays);
        if (chk < 0.0) printf("#\n"); /* keeps the walk */
    }
    printf("# raw trilinear lookups/s along rays (1 thread, thread CPU time, best of 3): %.4g (checksum %.6g); majorant DDA segments per ray %.1f\n", raw, sum, segs);
    printf("# majorant walk (coarse_depth %g, coarse_ratio %g): %.1f segments per ray (%.1f non-empty), %.1f DDA steps per ray, %.0f ns per ray (walk only)\n",
           g_coarse_depth > -2.0 ? g_coarse_depth : VBL_COARSE_DEPTH_DEFAULT,
           g_coarse_ratio >= 0.0 ? g_coarse_ratio : VBL_COARSE_RATIO_DEFAULT, segs, nonempty, steps, 1e9 * walk / (10.0 * nrays));
    printf("| medium | estimator | mean T | variance | lookups/query | queries/s | limit queries/s | x of limit | efficiency 1/(var x s) |\n"
           "|---|---|---|---|---|---|---|---|---|\n");
    for (int thin = 0; thin < 2; ++thin) {
        vbl_extinction ext;
        vbl_extinction_init(&ext);
        if (g_coarse_depth > -2.0) ext.coarse_depth = g_coarse_depth;
        if (g_coarse_ratio >= 0.0) ext.coarse_ratio = g_coarse_ratio;
        vbl_extinction_add(&ext, v, thin ? 0.25 * scale : scale, NULL);
        const vbl_transmittance_estimator ests[] = {VBL_TRANSMITTANCE_RATIO_TRACKING,
                                                    VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING};
        /* rows: ratio, residual, residual with the mid-bound control at k = 1 and 2, then the
         * global majorant */
        for (int e = 0; e < 6; ++e) {
            double var = 0, mt = 0, lq = 0, s1 = 1e300;
            const int mid = e == 2 || e == 3, global = e >= 4;
            const vbl_transmittance_estimator est = ests[mid ? 1 : e % 2];
            g_residual_mid = mid;
            g_majorant_scale = e == 3 ? 2.0 : 1.0;
            for (int rep = 0; rep < 3; ++rep) {
                double s = run_estimator(&ext, rays, nrays, 16, est, global, 1, &var, &mt, &lq);
                if (s < s1) s1 = s;
            }
            double q = (double)nrays * 16 / s1, limit = raw / fmax(lq, 1e-9);
            printf("| %s (scale %.3g) | %s%s | %.4f | %.3g | %.2f | %.4g | %.4g | %.2f | %.3g |\n", thin ? "thin" : "thick",
                   thin ? 0.25 * scale : scale, vbl_transmittance_estimator_name(est),
                   global ? " (global)" : (e == 2 ? " mid-bound" : (e == 3 ? " mid-bound k=2" : "")), mt, var, lq, q, limit,
                   limit / q, var > 0 ? q / var : 0.0);
        }
        g_residual_mid = 0;
        g_majorant_scale = 1.0;
        /* issue 14 item 4: unbiased ray marching (Kettunen et al. 2021) at several march densities
         * (points per unit residual optical depth; the pilot at the same density or half) */
        /* session 6: {rate, pilot rate, theta, pilot_min_bound, block_strata}: the adaptive march */
        const double um_rates[][5] = {{1, 1, 1, 0, 0},   {2, 2, 1, 0, 0},   {4, 4, 1, 0, 0},     {8, 8, 1, 0, 0},
                                      {16, 16, 1, 0, 0}, {4, 2, 1, 0, 0},   {4, 4, 0.5, 0, 0},   {4, 4, 1, 0, 1},
                                      {4, 4, 1, 0.5, 1}, {4, 4, 1, 1.01, 1}, {2, 2, 1, 0.5, 1}, {1, 1, 1, 0.5, 1},
                                      {8, 8, 1, 0.5, 1}, {4, 4, 1, 0.25, 1}, {6, 6, 1, 0.5, 1}};
        for (size_t e = 0; e < sizeof um_rates / sizeof um_rates[0]; ++e) {
            double var = 0, mt = 0, lq = 0, s1 = 1e300;
            g_unbiased = 1;
            g_um = vbl_unbiased_march_defaults(1.0);
            g_um.rate = um_rates[e][0];
            g_um.pilot_rate = um_rates[e][1];
            g_um.theta = um_rates[e][2];
            g_um.pilot_min_bound = um_rates[e][3];
            g_um.block_strata = (int)um_rates[e][4];
            for (int rep = 0; rep < 3; ++rep) {
                double s = run_estimator(&ext, rays, nrays, 16, VBL_TRANSMITTANCE_RATIO_TRACKING, 0, 1, &var, &mt, &lq);
                if (s < s1) s1 = s;
            }
            g_unbiased = 0;
            double q = (double)nrays * 16 / s1, limit = raw / fmax(lq, 1e-9);
            printf("| %s (scale %.3g) | unbiased-march rate %g pilot %g theta %g pilot_min %g strata %d | %.4f | %.3g | %.2f | %.4g | %.4g | %.2f | %.3g |\n",
                   thin ? "thin" : "thick", thin ? 0.25 * scale : scale, g_um.rate, g_um.pilot_rate, g_um.theta,
                   g_um.pilot_min_bound, g_um.block_strata, mt, var,
                   lq, q, limit, limit / q, var > 0 ? q / var : 0.0);
        }
    }
    free(rays);
    return 0;
}

/* --exact R (issue 14 item 5, helper expcarry): is the tracking core's mean T in the thick cloud
 * off? Exact per-ray T = exp(-optical depth), the depth by the midpoint rule at 1/32 voxel (error
 * ~1e-4 relative); R replicas of run_estimator (16 queries per ray, seeds 77 + rep) per tracker;
 * z = (mean - exact) / s.e., s.e. = sqrt(mean per-ray variance / (16 rays)). Unbiased: z ~ N(0, 1)
 * per replica, and the pooled z over all replicas too. */
static int run_exact(vbl_volume* v, const vbl_volume_info* info, double scale, int reps)
{
    const int nrays = 2000;
    bench_ray* rays = malloc(sizeof *rays * (size_t)nrays);
    make_rays(info, rays, nrays);
    if (scale <= 0.0) scale = 4.0 / (info->value_max * 64.0 * info->voxel_size[0]);
    printf("| medium | estimator | exact mean T | replicas | pooled mean T | pooled s.e. | pooled z | z min / max | "
           "mean z^2 |\n|---|---|---|---|---|---|---|---|---|\n");
    for (int thin = 0; thin < 2; ++thin) {
        vbl_extinction ext;
        vbl_extinction_init(&ext);
        vbl_extinction_add(&ext, v, thin ? 0.25 * scale : scale, NULL);
        vbl_extinction_cursor cur;
        vbl_extinction_cursor_init(&cur, &ext);
        double exact = 0.0;
        const double h = info->voxel_size[0] / 32.0;
        for (int r = 0; r < nrays; ++r) {
            const int steps = (int)ceil(rays[r].t1 / h);
            const double dt = rays[r].t1 / steps;
            double tau = 0.0;
            for (int i = 0; i < steps; ++i)
                tau += vbl_extinction_eval(&ext, &cur, vbl_v3_madd(rays[r].o, rays[r].d, (i + 0.5) * dt), NULL);
            exact += exp(-tau * dt);
        }
        exact /= nrays;
        const vbl_transmittance_estimator ests[] = {VBL_TRANSMITTANCE_DELTA_TRACKING, VBL_TRANSMITTANCE_RATIO_TRACKING,
                                                    VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING,
                                                    VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING};
        for (int e = 0; e < 4; ++e) {
            double sm = 0.0, sv = 0.0, zmin = 1e300, zmax = -1e300, z2 = 0.0;
            g_residual_mid = e == 3;
            for (int rep = 0; rep < reps; ++rep) {
                double var, mt, lq;
                g_seed = (uint64_t)rep;
                run_estimator(&ext, rays, nrays, 16, ests[e], 0, 2, &var, &mt, &lq);
                const double se2 = var / (16.0 * nrays), z = (mt - exact) / sqrt(se2);
                sm += mt, sv += se2, z2 += z * z;
                zmin = fmin(zmin, z), zmax = fmax(zmax, z);
            }
            g_seed = 0;
            g_residual_mid = 0;
            const double pm = sm / reps, pse = sqrt(sv) / reps;
            printf("| %s (scale %.3g) | %s%s | %.6f | %d | %.6f | %.2g | %.2f | %.2f / %.2f | %.2f |\n", thin ? "thin" : "thick",
                   thin ? 0.25 * scale : scale, vbl_transmittance_estimator_name(ests[e]), e == 3 ? " mid-bound" : "", exact,
                   reps, pm, pse, (pm - exact) / pse, zmin, zmax, z2 / reps);
            fflush(stdout);
        }
    }
    free(rays);
    return 0;
}

int main(int argc, char** argv)
{
    const char* path = VBL_BENCH_DEFAULT_VDB;
    double scale = 0.0; /* 0: chosen so the mean transmittance is moderate */
    int gap_only = 0, exact_reps = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--density-scale") && i + 1 < argc) scale = atof(argv[++i]);
        else if (!strcmp(argv[i], "--gap")) gap_only = 1;
        else if (!strcmp(argv[i], "--exact") && i + 1 < argc) exact_reps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--coarse-depth") && i + 1 < argc) g_coarse_depth = atof(argv[++i]);
        else if (!strcmp(argv[i], "--coarse-ratio") && i + 1 < argc) g_coarse_ratio = atof(argv[++i]);
        else path = argv[i];
    }
    vbl_volume_load_options lopt = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    vbl_volume* v = NULL;
    if (vbl_volume_load(path, &lopt, &v) != VBL_SUCCESS) {
        fprintf(stderr, "bench_volume: %s\n", vbl_last_error_message());
        return 1;
    }
    vbl_volume_info info;
    info.size = sizeof info;
    vbl_volume_get_info(v, &info);
    printf("# %s: grid '%s', %llu active voxels, voxel size %g, values [%g, %g], OpenMP max threads %d\n", path,
           info.grid_name, (unsigned long long)info.active_voxels, info.voxel_size[0], info.value_min, info.value_max,
           omp_get_max_threads());

    if (exact_reps > 0) {
        int rc = run_exact(v, &info, scale, exact_reps);
        vbl_volume_release(v);
        return rc;
    }
    if (gap_only) {
        int rc = run_gap(v, &info, scale);
        vbl_volume_release(v);
        return rc;
    }

    /* 1. Lookups. */
    const size_t n = 4000000;
    double* pts = malloc(sizeof(double) * 3 * n);
    printf("\n## Density lookups (1 thread, trilinear)\n| access pattern | PNanoVDB lookups/s | OpenVDB BoxSampler lookups/s | ratio |\n|---|---|---|---|\n");
    for (int coherent = 0; coherent < 2; ++coherent) {
        make_points(&info, pts, n, coherent);
        vbl_grid_accessor acc;
        vbl_grid_accessor_init(&acc, v);
        double sum = 0.0, t0 = now();
        for (size_t i = 0; i < n; ++i)
            sum += vbl_grid_sample_world(&acc, vbl_v3(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]), VBL_FILTER_TRILINEAR);
        double tp = now() - t0, ref = 0.0;
        double to = vbl_bench_openvdb_lookups(path, info.grid_name, pts, n, &ref);
        if (fabs(sum - ref) > 1e-5 * fabs(ref) + 1e-9) fprintf(stderr, "checksum mismatch %.9g vs %.9g\n", sum, ref);
        printf("| %s | %.3g | %.3g | %.2fx |\n", coherent ? "along rays (half-voxel steps)" : "random points", n / tp,
               n / to, to / tp);
    }
    free(pts);

    int nrays = 2000;
    bench_ray* rays = malloc(sizeof *rays * (size_t)nrays);
    make_rays(&info, rays, nrays);
    if (scale <= 0.0) scale = 4.0 / (info.value_max * 64.0 * info.voxel_size[0]); /* ~ tau 4 across 64 voxels of max */

    /* 2. Majorant block size. */
    printf("\n## Majorant block size (ratio tracking, 1 thread, density scale %g)\n| block | build s | majorant KiB | queries/s | lookups/query |\n|---|---|---|---|---|\n", scale);
    for (int b = 4; b <= 32; b *= 2) {
        vbl_volume_load_options o2 = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
        o2.majorant_block_size = b;
        vbl_volume* vb = NULL;
        double t0 = now();
        if (vbl_volume_load(path, &o2, &vb) != VBL_SUCCESS) continue;
        double build = now() - t0;
        vbl_extinction ext;
        vbl_extinction_init(&ext);
        vbl_extinction_add(&ext, vb, scale, NULL);
        double var, mt, lq;
        double secs = run_estimator(&ext, rays, nrays, 16, VBL_TRANSMITTANCE_RATIO_TRACKING, 0, 1, &var, &mt, &lq);
        size_t bytes = (size_t)vb->majorant.dims[0] * vb->majorant.dims[1] * vb->majorant.dims[2] * 8u;
        printf("| %d | %.3f | %.1f | %.3g | %.1f |\n", b, build, bytes / 1024.0, nrays * 16.0 / secs, lq);
        vbl_volume_release(vb);
    }

    /* 3. Estimators. */
    vbl_extinction ext;
    vbl_extinction_init(&ext);
    vbl_extinction_add(&ext, v, scale, NULL);
    const int spr = 32;
    printf("\n## Transmittance estimators (%d rays x %d estimates, density scale %g)\n", nrays, spr, scale);
    printf("| estimator | majorant | mean T | variance | lookups/query | queries/s 1 thread | queries/s 2 threads | efficiency 1/(var x s) |\n|---|---|---|---|---|---|---|---|\n");
    for (int e = 0; e <= VBL_TRANSMITTANCE_CACHED_RATIO; ++e)
        for (int g = 0; g < 2; ++g) {
            if (g == 1 && e != VBL_TRANSMITTANCE_RATIO_TRACKING && e != VBL_TRANSMITTANCE_DELTA_TRACKING) continue;
            double var, mt, lq, var2, mt2, lq2;
            double s1 = run_estimator(&ext, rays, nrays, spr, (vbl_transmittance_estimator)e, g, 1, &var, &mt, &lq);
            double s2 = run_estimator(&ext, rays, nrays, spr, (vbl_transmittance_estimator)e, g, 2, &var2, &mt2, &lq2);
            double q = (double)nrays * spr, tq = s1 / q;
            char eff[32];
            if (var > 0.0) snprintf(eff, sizeof eff, "%.3g", 1.0 / (var * tq));
            else snprintf(eff, sizeof eff, "n/a (biased)");
            printf("| %s | %s | %.4f | %.3g | %.1f | %.3g | %.3g | %s |\n",
                   vbl_transmittance_estimator_name((vbl_transmittance_estimator)e), g ? "global" : "DDA", mt, var, lq,
                   q / s1, q / s2, e == VBL_TRANSMITTANCE_RAY_MARCHING ? "n/a (biased)" : eff);
        }

    /* 4. Majorant scale (issue 14, shadow rays through thin smoke): tentative collisions at k x the
     * majorant, at the density scale above and at a quarter of it (thin). */
    printf("\n## Majorant scale k (ratio / residual tracking, DDA, 1 thread, %d rays x %d estimates)\n", nrays, spr);
    printf("| density scale | estimator | k | mean T | variance | lookups/query | queries/s | efficiency 1/(var x s) |\n"
           "|---|---|---|---|---|---|---|---|\n");
    for (int thin = 0; thin < 2; ++thin) {
        vbl_extinction ext_k;
        vbl_extinction_init(&ext_k);
        vbl_extinction_add(&ext_k, v, thin ? 0.25 * scale : scale, NULL);
        for (int e = VBL_TRANSMITTANCE_RATIO_TRACKING; e <= VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING; ++e)
            for (double k = 1.0; k <= 8.0; k *= 2.0) {
                g_majorant_scale = k;
                double var, mt, lq;
                double s1 = run_estimator(&ext_k, rays, nrays, spr, (vbl_transmittance_estimator)e, 0, 1, &var, &mt, &lq);
                double q = (double)nrays * spr;
                printf("| %.3g | %s | %g | %.4f | %.3g | %.1f | %.3g | %.3g |\n", thin ? 0.25 * scale : scale,
                       vbl_transmittance_estimator_name((vbl_transmittance_estimator)e), k, mt, var, lq, q / s1,
                       var > 0.0 ? 1.0 / (var * s1 / q) : 0.0);
            }
    }
    g_majorant_scale = 1.0;
    free(rays);
    vbl_volume_release(v);
    return 0;
}
