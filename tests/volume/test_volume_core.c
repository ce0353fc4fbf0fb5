/* Volume core against closed forms on in-memory grids: DDA coverage, majorant bound, every
 * transmittance estimator and cache, parity with the global majorant, extremes. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/rng.h"
#include "volume/transmittance_cache.h"
#include "volume_test_grid.h"

#define N 16 /* box edge in voxels: voxels [0, N-1]^3 */

static double fn_const(int i, int j, int k, void* user)
{
    (void)i, (void)j, (void)k;
    return *(double*)user;
}
static double fn_ramp(int i, int j, int k, void* user)
{
    (void)j, (void)k, (void)user;
    return 1.0 + i; /* value 1 + x along x: exactly linear inside [0, N-1] */
}
static double fn_blob(int i, int j, int k, void* user)
{
    (void)user;
    double x = i - 7.5, y = j - 7.5, z = k - 7.5;
    double r2 = (x * x + y * y + z * z) / 64.0;
    double v = r2 < 1.0 ? (1.0 - r2) * (1.0 + 0.5 * sin(1.3 * i) * cos(0.7 * j + k)) : 0.0;
    return v > 0.0 ? v : 0.0;
}

static const int BMIN[3] = {0, 0, 0}, BMAX[3] = {N - 1, N - 1, N - 1};

/* Optical depth of the constant box along x at index y,z inside [0, N-1], from index x = a to b
 * (a <= b): trilinear support ramps 0 -> c over [-1, 0] and c -> 0 over [N-1, N]. */
static double box_profile_integral(double x) /* integral of the x-profile from -inf to x */
{
    if (x <= -1.0) return 0.0;
    if (x <= 0.0) return 0.5 * (x + 1.0) * (x + 1.0);
    if (x <= N - 1.0) return 0.5 + x;
    if (x <= N) return 0.5 + (N - 1.0) + 0.5 - 0.5 * (N - x) * (N - x);
    return (double)N;
}

static void assert_within(double estimate, double se, double truth, double k, const char* what)
{
    double tol = k * se + 1e-12;
    if (!(fabs(estimate - truth) <= tol)) {
        fprintf(stderr, "%s: estimate %.6g +- %.3g, truth %.6g\n", what, estimate, se, truth);
        fail();
    }
}

/* ---- DDA ---------------------------------------------------------------------------------- */

static void check_dda(const vbl_volume* v, vbl_vec3 o, vbl_vec3 d, double tmin, double tmax)
{
    vbl_majorant_iter it;
    vbl_majorant_segment s;
    vbl_majorant_iter_init(&it, v, o, d, tmin, tmax);
    /* Independent clip against the block grid box in index space. */
    const vbl_majorant_grid* g = &v->majorant;
    vbl_vec3 oi = vbl_affine_point(&v->world_to_index, o), di = vbl_affine_vector(&v->world_to_index, d);
    double a = tmin, b = tmax, oa[3] = {oi.x, oi.y, oi.z}, da[3] = {di.x, di.y, di.z};
    int empty = 0;
    for (int ax = 0; ax < 3; ++ax) {
        double lo = g->origin[ax], hi = g->origin[ax] + (double)g->dims[ax] * g->block;
        if (da[ax] == 0.0) {
            if (oa[ax] < lo || oa[ax] > hi) empty = 1;
            continue;
        }
        double t0 = (lo - oa[ax]) / da[ax], t1 = (hi - oa[ax]) / da[ax];
        if (t0 > t1) { double x = t0; t0 = t1; t1 = x; }
        a = fmax(a, t0);
        b = fmin(b, t1);
    }
    if (!(a < b)) empty = 1;
    int count = 0;
    double prev = NAN, first = NAN;
    while (vbl_majorant_iter_next(&it, &s)) {
        assert_true(s.t1 > s.t0);
        if (count == 0) first = s.t0;
        else assert_true(s.t0 == prev); /* contiguous: no gap, no overlap */
        prev = s.t1;
        /* The segment's midpoint lies in the block that gave the majorant: check the bound. */
        count++;
        assert_true(count <= g->dims[0] + g->dims[1] + g->dims[2] + 3);
    }
    if (empty) {
        /* Touching the box only within rounding is allowed to give a sliver. */
        if (count) assert_true(prev - first <= 1e-9 * (1.0 + fabs(first)) * (b > a ? 1.0 : 1.0) + fabs(b - a));
        return;
    }
    assert_true(count > 0);
    double scale = 1e-9 * (fabs(a) + fabs(b) + 1.0);
    assert_true(fabs(first - a) <= scale);
    assert_true(fabs(prev - b) <= scale);
}

static void test_dda_coverage(void** state)
{
    (void)state;
    double m[3][4], c = 1.0;
    vt_uniform_map(m, 0.5, -3.0, 1.0, 2.0);
    int bmax[3] = {40, 23, 17};
    vbl_volume* v = vt_make(BMIN, bmax, fn_const, &c, m);
    assert_non_null(v);
    assert_int_equal(v->majorant.origin[0], -1);
    vbl_rng rng = vbl_rng_make(1, 2, 3);
    for (int r = 0; r < 4000; ++r) {
        vbl_vec3 o = vbl_v3(-6.0 + 30.0 * vbl_rng_uniform(&rng), -2.0 + 16.0 * vbl_rng_uniform(&rng),
                            -1.0 + 14.0 * vbl_rng_uniform(&rng));
        vbl_vec3 d = vbl_v3(vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5);
        int kind = r % 4;
        if (kind == 1) { /* axis-parallel: two exact zeros */
            int ax = (int)(vbl_rng_uniform(&rng) * 3);
            double s = vbl_rng_uniform(&rng) < 0.5 ? -1.0 : 1.0;
            d = vbl_v3(ax == 0 ? s : 0.0, ax == 1 ? s : 0.0, ax == 2 ? s : 0.0);
        } else if (kind == 2) { /* one zero component, origin on a block face */
            d.y = 0.0;
            o.y = 1.0 + 0.5 * 8.0 * floor(vbl_rng_uniform(&rng) * 4.0);
        }
        double tmin = vbl_rng_uniform(&rng) < 0.5 ? -1e30 : 40.0 * (vbl_rng_uniform(&rng) - 0.5);
        double tmax = vbl_rng_uniform(&rng) < 0.5 ? 1e30 : tmin + 60.0 * vbl_rng_uniform(&rng);
        check_dda(v, o, d, tmin, tmax);
    }
    /* Zero-length and reversed intervals give nothing. */
    vbl_majorant_iter it;
    vbl_majorant_segment s;
    vbl_majorant_iter_init(&it, v, vbl_v3(1, 2, 3), vbl_v3(1, 0, 0), 2.0, 2.0);
    assert_int_equal(vbl_majorant_iter_next(&it, &s), 0);
    vbl_majorant_iter_init(&it, v, vbl_v3(1, 2, 3), vbl_v3(0, 0, 0), 0.0, 5.0); /* zero direction inside */
    assert_int_equal(vbl_majorant_iter_next(&it, &s), 1);
    assert_true(s.t0 == 0.0 && s.t1 == 5.0);
    vt_free(v);
}

/* ---- majorant bound ------------------------------------------------------------------------ */

static void test_majorant_bounds_trilinear(void** state)
{
    (void)state;
    double m[3][4] = {{0.3, 0.1, 0.0, 1.0}, {-0.1, 0.3, 0.05, 0.0}, {0.0, -0.02, 0.5, -2.0}};
    for (int block = 2; block <= 16; block *= 2) {
        size_t size;
        void* buf = vt_make_nanovdb(BMIN, BMAX, fn_blob, NULL, m, &size);
        vbl_volume* v = vt_wrap(buf, size, block);
        assert_non_null(v);
        vbl_grid_accessor acc;
        vbl_grid_accessor_init(&acc, v);
        vbl_rng rng = vbl_rng_make(7, (uint64_t)block, 0);
        long checked = 0;
        for (int r = 0; r < 1500; ++r) {
            vbl_vec3 o = vbl_v3(-2 + 10 * vbl_rng_uniform(&rng), -4 + 10 * vbl_rng_uniform(&rng),
                                -4 + 10 * vbl_rng_uniform(&rng));
            vbl_vec3 d = vbl_v3_normalize(vbl_v3(vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5,
                                                 vbl_rng_uniform(&rng) - 0.5));
            if (r % 5 == 0) d = vbl_v3(0, 0, r % 10 == 0 ? 1.0 : -1.0);
            vbl_majorant_iter it;
            vbl_majorant_segment s;
            vbl_majorant_iter_init(&it, v, o, d, -20.0, 20.0);
            while (vbl_majorant_iter_next(&it, &s)) {
                for (int k = 0; k < 6; ++k) {
                    double t = k == 0 ? s.t0 : (k == 1 ? s.t1 : s.t0 + (s.t1 - s.t0) * vbl_rng_uniform(&rng));
                    double x = vbl_grid_sample_world(&acc, vbl_v3_madd(o, d, t), VBL_FILTER_TRILINEAR);
                    assert_true(x <= s.majorant * (1.0 + 1e-12));
                    assert_true(x >= s.minorant * (1.0 - 1e-12) - 1e-300);
                    checked++;
                }
            }
        }
        assert_true(checked > 10000);
        vt_free(v);
    }
}

/* ---- transmittance: closed forms ------------------------------------------------------------ */

static vbl_volume* make_const_box(double c, double h)
{
    double m[3][4];
    vt_uniform_map(m, h, -0.25 * h, 0.5 * h, 2.0 * h);
    return vt_make(BMIN, BMAX, fn_const, &c, m);
}

/* Ray along +x at index (y, z) = (7.3, 5.6); world t = index x offset * h from index x = -5. */
static void const_box_ray(const vbl_volume* v, double h, double origin[3], double dir[3])
{
    vbl_vec3 o = vbl_affine_point(&v->index_to_world, vbl_v3(-5.0, 7.3, 5.6));
    origin[0] = o.x, origin[1] = o.y, origin[2] = o.z;
    dir[0] = h, dir[1] = 0.0, dir[2] = 0.0; /* t in index units */
}

static void test_estimators_constant_box(void** state)
{
    (void)state;
    const double c = 2.0, h = 0.1, scale = 1.5;
    vbl_volume* v = make_const_box(c, h);
    double o[3], d[3];
    const_box_ray(v, h, o, d);
    const double ts[4] = {3.0, 5.5, 12.25, 30.0}; /* index x = t - 5 */
    for (int e = 0; e <= VBL_TRANSMITTANCE_CACHED_RATIO; ++e) {
        if (e == VBL_TRANSMITTANCE_RAY_MARCHING) continue;
        for (int k = 0; k < 4; ++k) {
            double tau = scale * c * h * box_profile_integral(ts[k] - 5.0);
            vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
            opt.estimator = (vbl_transmittance_estimator)e;
            opt.density_scale = scale;
            opt.seed = 100 + (uint64_t)k;
            vbl_transmittance_result res;
            assert_int_equal(vbl_volume_transmittance(v, o, d, 0.0, ts[k], &opt, 5000, &res), VBL_SUCCESS);
            char what[64];
            snprintf(what, sizeof what, "%s t=%g", vbl_transmittance_estimator_name(opt.estimator), ts[k]);
            assert_within(res.mean, res.std_error, exp(-tau), 4.0, what);
            assert_true(res.std_error < 0.02);
        }
    }
    /* Residual ratio tracking in a constant region is exact (zero variance). */
    vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
    opt.estimator = VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING;
    opt.density_scale = scale;
    double o2[3];
    vbl_vec3 p = vbl_affine_point(&v->index_to_world, vbl_v3(1.0, 7.3, 5.6));
    o2[0] = p.x, o2[1] = p.y, o2[2] = p.z;
    vbl_transmittance_result res;
    assert_int_equal(vbl_volume_transmittance(v, o2, d, 0.0, 6.0, &opt, 100, &res), VBL_SUCCESS);
    /* interior blocks are constant only where the block and its shell are inside the box */
    assert_true(fabs(res.mean - exp(-scale * c * h * 6.0)) < 0.05);
    vt_free(v);
}

static void test_estimators_linear_ramp(void** state)
{
    (void)state;
    const double h = 0.05, scale = 0.7;
    double m[3][4];
    vt_uniform_map(m, h, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(BMIN, BMAX, fn_ramp, NULL, m);
    /* From index x = 0.5 to x = 0.5 + t along x, t <= 14.5: tau = scale h [(x + x^2/2)]. */
    double o[3] = {0.5 * h, 6.2 * h, 9.9 * h}, d[3] = {h, 0.0, 0.0};
    const double ts[3] = {1.0, 4.0, 14.0};
    for (int e = 0; e <= VBL_TRANSMITTANCE_CACHED_RATIO; ++e) {
        if (e == VBL_TRANSMITTANCE_RAY_MARCHING) continue;
        for (int k = 0; k < 3; ++k) {
            double x0 = 0.5, x1 = 0.5 + ts[k];
            double tau = scale * h * ((x1 + 0.5 * x1 * x1) - (x0 + 0.5 * x0 * x0));
            vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
            opt.estimator = (vbl_transmittance_estimator)e;
            opt.density_scale = scale;
            opt.seed = 7 + (uint64_t)k;
            vbl_transmittance_result res;
            assert_int_equal(vbl_volume_transmittance(v, o, d, 0.0, ts[k], &opt, 5000, &res), VBL_SUCCESS);
            char what[64];
            snprintf(what, sizeof what, "ramp %s t=%g", vbl_transmittance_estimator_name(opt.estimator), ts[k]);
            assert_within(res.mean, res.std_error, exp(-tau), 4.0, what);
        }
    }
    /* Ray marching: error falls as the step shrinks. */
    double prev = INFINITY;
    double x0 = 0.5, x1 = 14.5, truth = exp(-scale * h * ((x1 + 0.5 * x1 * x1) - (x0 + 0.5 * x0 * x0)));
    for (int s = 0; s < 4; ++s) {
        vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
        opt.estimator = VBL_TRANSMITTANCE_RAY_MARCHING;
        opt.density_scale = scale;
        opt.march_step = 8.0 * h / pow(4.0, s); /* world units: 8 .. 1/8 voxel */
        vbl_transmittance_result res;
        assert_int_equal(vbl_volume_transmittance(v, o, d, 0.0, 14.0, &opt, 4000, &res), VBL_SUCCESS);
        double err = fabs(res.mean - truth) + res.std_error;
        assert_true(err < prev);
        prev = err;
    }
    assert_true(prev < 1e-3);
    vt_free(v);
}

/* Same statistics from many independent caches evaluated at several t. */
static void test_caches_every_t(void** state)
{
    (void)state;
    double m[3][4];
    vt_uniform_map(m, 1.0, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(BMIN, BMAX, fn_ramp, NULL, m);
    vbl_extinction ext;
    vbl_extinction_init(&ext);
    assert_int_equal(vbl_extinction_add(&ext, v, 0.02, NULL), VBL_SUCCESS);
    vbl_extinction_cursor cur;
    vbl_extinction_cursor_init(&cur, &ext);
    vbl_vec3 o = vbl_v3(0.0, 7.5, 7.5), d = vbl_v3(1.0, 0.0, 0.0);
    const double ts[5] = {0.0, 2.0, 5.5, 9.0, 15.0};
    for (int kind = VBL_TRANSMITTANCE_CACHED_DELTA; kind <= VBL_TRANSMITTANCE_CACHED_RATIO; ++kind) {
        double sum[5] = {0}, sum2[5] = {0};
        const int caches = 3000;
        for (int i = 0; i < caches; ++i) {
            vbl_rng rng = vbl_rng_make(99, (uint64_t)kind, (uint64_t)i);
            vbl_transmittance_cache cache;
            vbl_transmittance_cache_build(&cache, (vbl_transmittance_estimator)kind, &ext, &cur, o, d, 0.0, 15.0, 16,
                                          0, &rng);
            double last = 1.0;
            for (int k = 0; k < 5; ++k) {
                double x = vbl_transmittance_cache_eval(&cache, ts[k]);
                assert_true(x <= last + 1e-15 || kind == VBL_TRANSMITTANCE_CACHED_RATIO); /* RR may raise */
                last = x;
                sum[k] += x;
                sum2[k] += x * x;
            }
        }
        for (int k = 0; k < 5; ++k) {
            double x1 = ts[k];
            double tau = 0.02 * (x1 + 0.5 * x1 * x1);
            double mean = sum[k] / caches, var = fmax(sum2[k] / caches - mean * mean, 0.0);
            char what[64];
            snprintf(what, sizeof what, "cache %d t=%g", kind, ts[k]);
            assert_within(mean, sqrt(var / caches), exp(-tau), 4.0, what);
        }
    }
    vt_free(v);
}

/* Ratio cache whose pass needs more points than it can store (tail by delta tracking): a loose
 * global majorant (one hot voxel far from the ray) makes ~600 tentative points. */
static double fn_spike(int i, int j, int k, void* user)
{
    (void)user;
    return (i == N - 1 && j == N - 1 && k == N - 1) ? 1000.0 : 1.0;
}

static void test_ratio_cache_overflow(void** state)
{
    (void)state;
    double m[3][4];
    vt_uniform_map(m, 1.0, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(BMIN, BMAX, fn_spike, NULL, m);
    vbl_extinction ext;
    vbl_extinction_init(&ext);
    assert_int_equal(vbl_extinction_add(&ext, v, 0.04, NULL), VBL_SUCCESS);
    vbl_extinction_cursor cur;
    vbl_extinction_cursor_init(&cur, &ext);
    vbl_vec3 o = vbl_v3(0.0, 7.5, 7.5), d = vbl_v3(2.0, 0.0, 0.0); /* t = index x / 2 */
    double sum[2] = {0}, sum2[2] = {0};
    const int caches = 4000;
    int overflowed = 0;
    for (int i = 0; i < caches; ++i) {
        vbl_rng rng = vbl_rng_make(5, 6, (uint64_t)i);
        vbl_transmittance_cache cache;
        vbl_transmittance_cache_build(&cache, VBL_TRANSMITTANCE_CACHED_RATIO, &ext, &cur, o, d, 0.0, 7.5, 0, 1, &rng);
        if (cache.count >= VBL_TRANSMITTANCE_CACHE_MAX - 1) overflowed++;
        for (int k = 0; k < 2; ++k) {
            double x = vbl_transmittance_cache_eval(&cache, k == 0 ? 1.0 : 6.0);
            sum[k] += x;
            sum2[k] += x * x;
        }
    }
    assert_true(overflowed > caches / 2);
    for (int k = 0; k < 2; ++k) {
        double mean = sum[k] / caches, se = sqrt(fmax(sum2[k] / caches - mean * mean, 0.0) / caches);
        assert_within(mean, se, exp(-0.04 * (k == 0 ? 2.0 : 12.0)), 4.0, "ratio cache overflow");
    }
    vt_free(v);
}

static void test_free_flight_distribution(void** state)
{
    (void)state;
    double m[3][4];
    vt_uniform_map(m, 1.0, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(BMIN, BMAX, fn_ramp, NULL, m);
    vbl_extinction ext;
    vbl_extinction_init(&ext);
    assert_int_equal(vbl_extinction_add(&ext, v, 0.01, NULL), VBL_SUCCESS);
    vbl_extinction_cursor cur;
    vbl_extinction_cursor_init(&cur, &ext);
    vbl_vec3 o = vbl_v3(0.0, 7.5, 7.5), d = vbl_v3(1.0, 0.0, 0.0);
    int hits[3] = {0}, n = 8000;
    const double ts[3] = {3.0, 8.0, 15.0};
    for (int i = 0; i < n; ++i) {
        vbl_rng rng = vbl_rng_make(3, 1, (uint64_t)i);
        double tc = 0, sig = 0, per[VBL_MAX_MEDIA];
        if (vbl_free_flight_sample(&ext, &cur, o, d, 0.0, 15.0, 0, &rng, &tc, &sig, per)) {
            assert_true(tc > 0.0 && tc < 15.0);
            assert_true(sig > 0.0 && fabs(per[0] - sig) < 1e-12);
            for (int k = 0; k < 3; ++k) hits[k] += tc <= ts[k];
        }
    }
    for (int k = 0; k < 3; ++k) {
        double p = 1.0 - exp(-0.01 * (ts[k] + 0.5 * ts[k] * ts[k]));
        double est = (double)hits[k] / n;
        assert_within(est, sqrt(p * (1 - p) / n), p, 4.0, "free flight");
    }
    vt_free(v);
}

static void test_parity_global_majorant(void** state)
{
    (void)state;
    double m[3][4];
    vt_uniform_map(m, 0.2, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(BMIN, BMAX, fn_blob, NULL, m);
    vbl_extinction ext;
    vbl_extinction_init(&ext);
    assert_int_equal(vbl_extinction_add(&ext, v, 4.0, NULL), VBL_SUCCESS);
    vbl_extinction_cursor cur;
    vbl_extinction_cursor_init(&cur, &ext);
    vbl_vec3 o = vbl_v3(-0.5, 1.3, 1.6), d = vbl_v3_normalize(vbl_v3(1.0, 0.2, 0.1));
    ext.components[0].density_scale = 0.4;
    for (int e = 0; e <= VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING; ++e) {
        double s[2] = {0}, s2[2] = {0};
        uint64_t lookups[2];
        const int n = 8000;
        for (int g = 0; g < 2; ++g) {
            uint64_t before = vbl_extinction_cursor_lookups(&cur);
            vbl_tracking_settings set = {(vbl_transmittance_estimator)e, 0.0, g, 1.0, 0.0, 0, 0, 0, {0.0, 0.0}};
            for (int i = 0; i < n; ++i) {
                vbl_rng rng = vbl_rng_make(11, (uint64_t)(e * 2 + g), (uint64_t)i);
                double x = vbl_transmittance_estimate(&ext, &cur, o, d, 0.0, 5.0, &set, &rng);
                assert_true(isfinite(x));
                s[g] += x;
                s2[g] += x * x;
            }
            lookups[g] = vbl_extinction_cursor_lookups(&cur) - before;
        }
        double m0 = s[0] / n, m1 = s[1] / n;
        double v0 = s2[0] / n - m0 * m0, v1 = s2[1] / n - m1 * m1;
        assert_within(m0, sqrt((v0 + v1) / n), m1, 4.0, "parity");
        assert_true(lookups[0] < lookups[1]); /* the DDA saves lookups */
        if (!(m0 > 0.05 && m0 < 0.95)) fprintf(stderr, "parity ray T = %g\n", m0);
        assert_true(m0 > 0.05 && m0 < 0.95); /* the test ray is neither empty nor opaque */
    }
    vt_free(v);
}

/* majorant_scale k: delta, ratio and residual tracking stay unbiased (same mean as k = 1 within
 * 4 sigma), ratio tracking's variance falls and its lookups grow about k-fold. */
static void test_majorant_scale(void** state)
{
    (void)state;
    double m[3][4];
    vt_uniform_map(m, 0.2, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(BMIN, BMAX, fn_blob, NULL, m);
    vbl_extinction ext;
    vbl_extinction_init(&ext);
    assert_int_equal(vbl_extinction_add(&ext, v, 0.4, NULL), VBL_SUCCESS);
    vbl_extinction_cursor cur;
    vbl_extinction_cursor_init(&cur, &ext);
    vbl_vec3 o = vbl_v3(-0.5, 1.3, 1.6), d = vbl_v3_normalize(vbl_v3(1.0, 0.2, 0.1));
    const double scales[2] = {1.0, 3.0};
    for (int e = 0; e <= VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING; ++e) {
        double mean[2], var[2];
        uint64_t lookups[2];
        const int n = 20000;
        for (int k = 0; k < 2; ++k) {
            uint64_t before = vbl_extinction_cursor_lookups(&cur);
            vbl_tracking_settings set = {(vbl_transmittance_estimator)e, 0.0, 0, scales[k], 0.0, 0, 0, 0, {0.0, 0.0}};
            double s = 0.0, s2 = 0.0;
            for (int i = 0; i < n; ++i) {
                vbl_rng rng = vbl_rng_make(23, (uint64_t)(e * 2 + k), (uint64_t)i);
                double x = vbl_transmittance_estimate(&ext, &cur, o, d, 0.0, 5.0, &set, &rng);
                assert_true(x >= 0.0 && x <= 1.0);
                s += x;
                s2 += x * x;
            }
            lookups[k] = vbl_extinction_cursor_lookups(&cur) - before;
            mean[k] = s / n;
            var[k] = s2 / n - mean[k] * mean[k];
        }
        printf("estimator %d: T %.5f / %.5f (k = 1 / 3), variance %.3g / %.3g, lookups %.2f / %.2f per query\n", e,
               mean[0], mean[1], var[0], var[1], (double)lookups[0] / n, (double)lookups[1] / n);
        assert_within(mean[1], sqrt((var[0] + var[1]) / n), mean[0], 4.0, "majorant scale");
        assert_true(mean[0] > 0.1 && mean[0] < 0.9);
        assert_true(lookups[1] > 2 * lookups[0]);
        if (e == VBL_TRANSMITTANCE_RATIO_TRACKING) assert_true(var[1] < 0.6 * var[0]);
    }
    vt_free(v);
}

/* Two overlapping components: merged segments and sum of optical depths. */
static void test_multi_component(void** state)
{
    (void)state;
    double m[3][4], c = 1.0;
    vt_uniform_map(m, 1.0, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(BMIN, BMAX, fn_const, &c, m);
    vbl_extinction ext;
    vbl_extinction_init(&ext);
    vbl_affine shift;
    memset(&shift, 0, sizeof shift);
    shift.m[0][0] = shift.m[1][1] = shift.m[2][2] = 1.0;
    shift.m[0][3] = -5.0; /* component 2 is the box moved by +5 in x */
    assert_int_equal(vbl_extinction_add(&ext, v, 0.05, NULL), VBL_SUCCESS);
    assert_int_equal(vbl_extinction_add(&ext, v, 0.03, &shift), VBL_SUCCESS);
    assert_true(fabs(ext.max_sigma_t - 0.08) < 1e-12);
    vbl_vec3 o = vbl_v3(-10.0, 7.5, 7.5), d = vbl_v3(1.0, 0.0, 0.0);
    vbl_extinction_iter it;
    vbl_majorant_segment s;
    vbl_extinction_iter_init(&it, &ext, o, d, 0.0, 40.0, 0);
    double prev = -1.0;
    int segs = 0;
    while (vbl_extinction_iter_next(&it, &s)) {
        assert_true(s.t1 > s.t0);
        if (prev >= 0.0) assert_true(s.t0 >= prev);
        prev = s.t1;
        double mid = 0.5 * (s.t0 + s.t1) - 10.0; /* index x */
        if (mid > 6.0 && mid < 14.0) assert_true(fabs(s.majorant - 0.08) < 1e-12);
        segs++;
    }
    assert_true(segs >= 3);
    vbl_extinction_cursor cur;
    vbl_extinction_cursor_init(&cur, &ext);
    double tau = 0.05 * box_profile_integral(40.0) + 0.03 * box_profile_integral(40.0);
    for (int e = 0; e <= VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING; ++e) {
        double sum = 0, sum2 = 0;
        const int n = 8000;
        vbl_tracking_settings set = {(vbl_transmittance_estimator)e, 0.0, 0, 1.0, 0.0, 0, 0, 0, {0.0, 0.0}};
        for (int i = 0; i < n; ++i) {
            vbl_rng rng = vbl_rng_make(12, (uint64_t)e, (uint64_t)i);
            double x = vbl_transmittance_estimate(&ext, &cur, o, d, 0.0, 40.0, &set, &rng);
            sum += x;
            sum2 += x * x;
        }
        double mean = sum / n;
        assert_within(mean, sqrt(fmax(sum2 / n - mean * mean, 0) / n), exp(-tau), 4.0, "two components");
    }
    double per[VBL_MAX_MEDIA];
    double sig = vbl_extinction_eval(&ext, &cur, vbl_v3(8.0, 7.5, 7.5), per);
    assert_true(fabs(sig - 0.08) < 1e-12 && fabs(per[0] - 0.05) < 1e-12 && fabs(per[1] - 0.03) < 1e-12);
    vt_free(v);
}

/* ---- extremes --------------------------------------------------------------------------------- */

static void test_extremes(void** state)
{
    (void)state;
    const double c = 1.0;
    /* Voxel sizes 1e-5 and 1e3: same index-space box, scale chosen so tau = 2 along x. */
    const double hs[3] = {1e-5, 1.0, 1e3};
    for (int hi = 0; hi < 3; ++hi) {
        double h = hs[hi];
        vbl_volume* v = make_const_box(c, h);
        double o[3], d[3];
        const_box_ray(v, h, o, d);
        for (int e = 0; e <= VBL_TRANSMITTANCE_CACHED_RATIO; ++e) {
            vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
            opt.estimator = (vbl_transmittance_estimator)e;
            opt.density_scale = 2.0 / (N * h);
            opt.seed = 3;
            vbl_transmittance_result res;
            assert_int_equal(vbl_volume_transmittance(v, o, d, 0.0, 30.0, &opt, 8000, &res), VBL_SUCCESS);
            double tol = e == VBL_TRANSMITTANCE_RAY_MARCHING ? 0.02 : 4.0 * res.std_error + 1e-12;
            assert_true(fabs(res.mean - exp(-2.0)) <= tol);
            /* Unit-length world direction: same answer with t in world units. */
            double du[3] = {1.0, 0.0, 0.0};
            vbl_transmittance_result r2;
            assert_int_equal(vbl_volume_transmittance(v, o, du, 0.0, 30.0 * h, &opt, 8000, &r2), VBL_SUCCESS);
            assert_true(fabs(r2.mean - exp(-2.0)) <= (e == VBL_TRANSMITTANCE_RAY_MARCHING ? 0.02 : 4.0 * r2.std_error + 1e-12));
        }
        vt_free(v);
    }
    /* Density scales 1e-8 .. 1e6 (tau up to 1.6e7: far past exp() underflow). */
    vbl_volume* v = make_const_box(c, 1.0);
    double o[3], d[3];
    const_box_ray(v, 1.0, o, d);
    const double scales[4] = {1e-8, 1.0, 1e3, 1e6};
    for (int si = 0; si < 4; ++si)
        for (int e = 0; e <= VBL_TRANSMITTANCE_CACHED_RATIO; ++e) {
            vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
            opt.estimator = (vbl_transmittance_estimator)e;
            opt.density_scale = scales[si];
            vbl_transmittance_result res;
            assert_int_equal(vbl_volume_transmittance(v, o, d, 0.0, 30.0, &opt, 200, &res), VBL_SUCCESS);
            assert_true(isfinite(res.mean) && isfinite(res.std_error));
            double truth = exp(-scales[si] * N);
            if (si == 0) assert_true(fabs(res.mean - truth) < 1e-5);
            if (si >= 2) assert_true(res.mean >= 0.0 && res.mean < 1e-30);
            /* bounded work: the tight majorant makes the count ~ optical depth of the first
             * voxel ramp until a collision (~sqrt(2 scale) steps), x16 for cached-delta */
            const uint64_t bound = 200u * 16u * 4000u;
            if (!(res.lookups < bound))
                fprintf(stderr, "scale %g %s: %llu lookups\n", scales[si], vbl_transmittance_estimator_name(opt.estimator),
                        (unsigned long long)res.lookups);
            assert_true(res.lookups < bound);
        }
    /* Grazing: along the support face y = -1 (value 0 there) and the first voxel plane y = 0. */
    {
        vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
        opt.density_scale = 0.1;
        vbl_transmittance_result res;
        double og[3] = {-0.25 - 5.0, 0.5 - 1.0, 2.0 + 4.0}, dx[3] = {1, 0, 0};
        assert_int_equal(vbl_volume_transmittance(v, og, dx, 0.0, 30.0, &opt, 1000, &res), VBL_SUCCESS);
        assert_true(res.mean == 1.0);
        double of[3] = {-0.25 - 5.0, 0.5 + 0.0, 2.0 + 4.0};
        assert_int_equal(vbl_volume_transmittance(v, of, dx, 0.0, 30.0, &opt, 4000, &res), VBL_SUCCESS);
        assert_within(res.mean, res.std_error, exp(-0.1 * N), 4.0, "grazing face");
        /* Starting inside, zero-length, reversed. */
        double oi[3] = {-0.25 + 3.0, 0.5 + 4.0, 2.0 + 4.0};
        assert_int_equal(vbl_volume_transmittance(v, oi, dx, 0.0, 5.0, &opt, 4000, &res), VBL_SUCCESS);
        assert_within(res.mean, res.std_error, exp(-0.5), 4.0, "inside");
        assert_int_equal(vbl_volume_transmittance(v, oi, dx, 2.0, 2.0, &opt, 10, &res), VBL_SUCCESS);
        assert_true(res.mean == 1.0 && res.lookups == 0);
        double dz[3] = {0, 0, 0};
        assert_int_equal(vbl_volume_transmittance(v, oi, dz, 0.0, 5.0, &opt, 4000, &res), VBL_SUCCESS);
        assert_true(res.mean == 1.0 && res.lookups == 0); /* no distance travelled */
        assert_int_equal(vbl_volume_transmittance(v, oi, dx, 0.0, NAN, &opt, 10, &res), VBL_ERROR_INVALID_ARGUMENT);
        assert_int_equal(vbl_volume_transmittance(v, oi, dx, 0.0, 1.0, &opt, 0, &res), VBL_ERROR_INVALID_ARGUMENT);
    }
    vt_free(v);
}

static void test_empty_grid(void** state)
{
    (void)state;
    double m[3][4], zero = 0.0;
    vt_uniform_map(m, 1.0, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(BMIN, BMAX, fn_const, &zero, m);
    assert_non_null(v);
    assert_int_equal(v->majorant.dims[0] * v->majorant.dims[1] * v->majorant.dims[2], 0);
    double o[3] = {-1, 3, 3}, d[3] = {1, 0, 0};
    for (int e = 0; e <= VBL_TRANSMITTANCE_CACHED_RATIO; ++e) {
        vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
        opt.estimator = (vbl_transmittance_estimator)e;
        vbl_transmittance_result res;
        assert_int_equal(vbl_volume_transmittance(v, o, d, 0.0, 30.0, &opt, 10, &res), VBL_SUCCESS);
        assert_true(res.mean == 1.0 && res.lookups == 0);
    }
    vt_free(v);
}

static void test_determinism_and_names(void** state)
{
    (void)state;
    vbl_volume* v = make_const_box(1.0, 1.0);
    double o[3], d[3];
    const_box_ray(v, 1.0, o, d);
    vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
    opt.density_scale = 0.1;
    opt.seed = 42;
    vbl_transmittance_result a, b;
    assert_int_equal(vbl_volume_transmittance(v, o, d, 0.0, 30.0, &opt, 5000, &a), VBL_SUCCESS);
    assert_int_equal(vbl_volume_transmittance(v, o, d, 0.0, 30.0, &opt, 5000, &b), VBL_SUCCESS);
    assert_true(a.mean == b.mean && a.std_error == b.std_error && a.lookups == b.lookups);
    for (int e = 0; e <= VBL_TRANSMITTANCE_CACHED_RATIO; ++e) {
        vbl_transmittance_estimator p;
        assert_int_equal(vbl_transmittance_estimator_parse(vbl_transmittance_estimator_name((vbl_transmittance_estimator)e), &p),
                         VBL_SUCCESS);
        assert_int_equal((int)p, e);
    }
    vbl_transmittance_estimator p;
    assert_int_equal(vbl_transmittance_estimator_parse("woodcock", &p), VBL_ERROR_INVALID_ARGUMENT);
    assert_true(strstr(vbl_last_error_message(), "woodcock") != NULL);
    vt_free(v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dda_coverage),
        cmocka_unit_test(test_majorant_bounds_trilinear),
        cmocka_unit_test(test_estimators_constant_box),
        cmocka_unit_test(test_estimators_linear_ramp),
        cmocka_unit_test(test_caches_every_t),
        cmocka_unit_test(test_ratio_cache_overflow),
        cmocka_unit_test(test_free_flight_distribution),
        cmocka_unit_test(test_parity_global_majorant),
        cmocka_unit_test(test_majorant_scale),
        cmocka_unit_test(test_multi_component),
        cmocka_unit_test(test_extremes),
        cmocka_unit_test(test_empty_grid),
        cmocka_unit_test(test_determinism_and_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
