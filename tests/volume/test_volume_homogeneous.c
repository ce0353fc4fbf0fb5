/* Closed-form transmittance in homogeneous majorant blocks (volume/transmittance.c): where a
 * block's majorant equals its minorant the density is known exactly, so transmittance estimators
 * multiply by exp(-sigma len) and free-flight sampling draws the exponential analytically, with no
 * density lookups. Checked against closed forms on a constant box of 32^3 voxels (majorant blocks
 * of 8: the blocks whose voxels and one-voxel shell lie inside the box are homogeneous, index
 * x in [7, 23) along the test rays, the rest ramps to 0 at the faces). */
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
#include "volume/transmittance.h"
#include "volume/transmittance_cache.h"
#include "volume_test_grid.h"

#define N 32
static const int BMIN[3] = {0, 0, 0}, BMAX[3] = {N - 1, N - 1, N - 1};

static double fn_const(int i, int j, int k, void* user)
{
    (void)i, (void)j, (void)k;
    return *(double*)user;
}
/* the same box with a 1e-6 relative checkerboard (above float precision): no block is homogeneous */
static double fn_almost(int i, int j, int k, void* user)
{
    return *(double*)user * (1.0 + 1e-6 * ((i + j + k) & 1));
}

/* integral of the trilinear x-profile of a box of N voxels (ramps over [-1, 0] and [N-1, N]) */
static double profile_integral(double x)
{
    if (x <= -1.0) return 0.0;
    if (x <= 0.0) return 0.5 * (x + 1.0) * (x + 1.0);
    if (x <= N - 1.0) return 0.5 + x;
    if (x <= N) return (double)N - 0.5 * (N - x) * (N - x);
    return (double)N;
}

typedef struct fixture {
    vbl_volume* vol;
    vbl_extinction ext;
    vbl_extinction_cursor cur;
} fixture;

static void make(fixture* f, vt_voxel_fn fn, double c, double scale)
{
    double m[3][4];
    vt_uniform_map(m, 1.0, 0.0, 0.0, 0.0); /* world = index */
    f->vol = vt_make(BMIN, BMAX, fn, &c, m);
    assert_non_null(f->vol);
    vbl_extinction_init(&f->ext);
    assert_int_equal(vbl_extinction_add(&f->ext, f->vol, scale, NULL), VBL_SUCCESS);
    vbl_extinction_cursor_init(&f->cur, &f->ext);
}

static const vbl_vec3 RAY_O = {-3.0, 11.3, 12.6}, RAY_D = {1.0, 0.0, 0.0}; /* x = t - 3 */

static void test_interior_exact(void** state)
{
    (void)state;
    const double c = 0.5, scale = 0.2, sigma = c * scale;
    fixture f;
    make(&f, fn_const, c, scale);
    vbl_majorant_iter it;
    vbl_majorant_segment seg;
    vbl_majorant_iter_init(&it, f.vol, RAY_O, RAY_D, 12.0, 24.0); /* index x 9 .. 21 */
    int homogeneous = 0;
    while (vbl_majorant_iter_next(&it, &seg)) homogeneous += seg.majorant == seg.minorant && seg.majorant > 0.0;
    assert_true(homogeneous >= 2);
    const vbl_transmittance_estimator kinds[4] = {VBL_TRANSMITTANCE_DELTA_TRACKING, VBL_TRANSMITTANCE_RATIO_TRACKING,
                                                  VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING,
                                                  VBL_TRANSMITTANCE_RAY_MARCHING};
    for (int k = 0; k < 4; ++k) {
        vbl_tracking_settings st = {kinds[k], 0.0, 0, 1.0, 0.0, 0, 0, 0, {0.0, 0.0}};
        for (int i = 0; i < 50; ++i) {
            vbl_rng rng = vbl_rng_make(7, 0, (uint64_t)i);
            uint64_t before = vbl_extinction_cursor_lookups(&f.cur);
            double T = vbl_transmittance_estimate(&f.ext, &f.cur, RAY_O, RAY_D, 12.0, 24.0, &st, &rng);
            assert_true(fabs(T - exp(-sigma * 12.0)) < 1e-12);
            assert_true(vbl_extinction_cursor_lookups(&f.cur) == before);
        }
    }
    /* free flight inside: exponential law, no lookups, sigma and the component exact */
    const int n = 20000;
    const double ts[3] = {14.0, 17.0, 22.0};
    int hits[3] = {0}, collided = 0;
    uint64_t before = vbl_extinction_cursor_lookups(&f.cur);
    for (int i = 0; i < n; ++i) {
        vbl_rng rng = vbl_rng_make(8, 0, (uint64_t)i);
        double t = 0.0, sig = 0.0, per[VBL_MAX_MEDIA];
        if (!vbl_free_flight_sample(&f.ext, &f.cur, RAY_O, RAY_D, 12.0, 24.0, 0, &rng, &t, &sig, per)) continue;
        collided++;
        assert_true(t > 12.0 && t < 24.0);
        assert_true(sig == sigma && per[0] == sigma);
        for (int k = 0; k < 3; ++k) hits[k] += t <= ts[k];
    }
    assert_true(vbl_extinction_cursor_lookups(&f.cur) == before);
    double pc = 1.0 - exp(-sigma * 12.0);
    assert_true(fabs((double)collided / n - pc) < 4.0 * sqrt(pc * (1 - pc) / n));
    for (int k = 0; k < 3; ++k) {
        double p = 1.0 - exp(-sigma * (ts[k] - 12.0));
        assert_true(fabs((double)hits[k] / n - p) < 4.0 * sqrt(p * (1 - p) / n));
    }
    /* caches: the ratio cache steps to 0 at an exponential distance (no lookups); mean of T(t) */
    double sum[3] = {0};
    before = vbl_extinction_cursor_lookups(&f.cur);
    for (int i = 0; i < n; ++i) {
        vbl_rng rng = vbl_rng_make(9, 0, (uint64_t)i);
        vbl_transmittance_cache cache;
        vbl_transmittance_cache_build(&cache, VBL_TRANSMITTANCE_CACHED_RATIO, &f.ext, &f.cur, RAY_O, RAY_D, 12.0, 24.0,
                                      0, 0, &rng);
        for (int k = 0; k < 3; ++k) sum[k] += vbl_transmittance_cache_eval(&cache, ts[k]);
    }
    assert_true(vbl_extinction_cursor_lookups(&f.cur) == before);
    for (int k = 0; k < 3; ++k) {
        double p = exp(-sigma * (ts[k] - 12.0));
        assert_true(fabs(sum[k] / n - p) < 4.0 * sqrt(p * (1 - p) / n));
    }
    vt_free(f.vol);
}

/* Whole rays through the box (ramps at the faces tracked as before, closed form inside):
 * unbiased against the exact optical depth, and far fewer lookups than on the same box made
 * non-homogeneous by a 1e-6 checkerboard. */
static void test_whole_box(void** state)
{
    (void)state;
    const double c = 1.0, scale = 0.25;
    fixture a, b;
    make(&a, fn_const, c, scale);
    make(&b, fn_almost, c, scale);
    const double t1s[3] = {6.0, 20.0, 40.0};
    const vbl_transmittance_estimator kinds[3] = {VBL_TRANSMITTANCE_DELTA_TRACKING, VBL_TRANSMITTANCE_RATIO_TRACKING,
                                                  VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING};
    const int n = 20000;
    for (int e = 0; e < 3; ++e)
        for (int k = 0; k < 3; ++k) {
            double truth = exp(-scale * c * (profile_integral(t1s[k] - 3.0) - profile_integral(-3.0)));
            vbl_tracking_settings st = {kinds[e], 0.0, 0, 1.0, 0.0, 0, 0, 0, {0.0, 0.0}};
            double s = 0.0, s2 = 0.0, sb = 0.0, sb2 = 0.0;
            uint64_t la = vbl_extinction_cursor_lookups(&a.cur), lb = vbl_extinction_cursor_lookups(&b.cur);
            for (int i = 0; i < n; ++i) {
                vbl_rng rng = vbl_rng_make(11 + (uint64_t)e, (uint64_t)k, (uint64_t)i);
                double T = vbl_transmittance_estimate(&a.ext, &a.cur, RAY_O, RAY_D, 0.0, t1s[k], &st, &rng);
                assert_true(T >= 0.0 && T <= 1.0);
                s += T;
                s2 += T * T;
                rng = vbl_rng_make(11 + (uint64_t)e, (uint64_t)k, (uint64_t)i);
                double Tb = vbl_transmittance_estimate(&b.ext, &b.cur, RAY_O, RAY_D, 0.0, t1s[k], &st, &rng);
                sb += Tb;
                sb2 += Tb * Tb;
            }
            la = vbl_extinction_cursor_lookups(&a.cur) - la;
            lb = vbl_extinction_cursor_lookups(&b.cur) - lb;
            double mean = s / n, se = sqrt(fmax(s2 / n - mean * mean, 0.0) / n);
            double mb = sb / n, seb = sqrt(fmax(sb2 / n - mb * mb, 0.0) / n);
            printf("%s t1 %g: T %.5f +- %.5f (exact %.5f; non-homogeneous box %.5f +- %.5f), lookups per ray %.3f vs "
                   "%.3f\n",
                   vbl_transmittance_estimator_name(kinds[e]), t1s[k], mean, se, truth, mb, seb, (double)la / n,
                   (double)lb / n);
            assert_true(fabs(mean - truth) <= 4.0 * se + 1e-9);
            assert_true(fabs(mb - truth) <= 4.0 * seb + 1e-6);
            if (t1s[k] >= 20.0 && kinds[e] != VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING) {
                /* lookups drop on rays that end inside (no lookup there); rays that go on to the
                 * far ramp now reach it with weight exp(-sigma len) instead of stopping */
                if (t1s[k] == 20.0) assert_true(la < lb);
                assert_true(se < 0.8 * seb); /* and the closed form removes variance */
            }
        }
    /* free flight across the whole box: P(collision before t) = 1 - T(0, t) */
    const int m = 20000;
    int hits[3] = {0};
    for (int i = 0; i < m; ++i) {
        vbl_rng rng = vbl_rng_make(21, 0, (uint64_t)i);
        double t = 0.0, sig = 0.0;
        if (!vbl_free_flight_sample(&a.ext, &a.cur, RAY_O, RAY_D, 0.0, 40.0, 0, &rng, &t, &sig, NULL)) continue;
        assert_true(sig > 0.0 && sig <= scale * c * (1 + 1e-12));
        for (int k = 0; k < 3; ++k) hits[k] += t <= t1s[k];
    }
    for (int k = 0; k < 3; ++k) {
        double p = 1.0 - exp(-scale * c * (profile_integral(t1s[k] - 3.0) - profile_integral(-3.0)));
        assert_true(fabs((double)hits[k] / m - p) < 4.0 * sqrt(p * (1 - p) / m) + 1e-9);
    }
    vt_free(a.vol);
    vt_free(b.vol);
}

/* Two overlapping constant boxes: the merged segments are homogeneous with the summed sigma;
 * per-component values at an analytic collision come from one lookup and sum to sigma. */
static void test_two_media_and_determinism(void** state)
{
    (void)state;
    fixture f;
    make(&f, fn_const, 1.0, 0.1);
    assert_int_equal(vbl_extinction_add(&f.ext, f.vol, 0.3, NULL), VBL_SUCCESS);
    vbl_extinction_cursor_init(&f.cur, &f.ext);
    vbl_tracking_settings st = {VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, 0, 1.0, 0.0, 0, 0, 0, {0.0, 0.0}};
    vbl_rng rng = vbl_rng_make(1, 2, 3);
    double T = vbl_transmittance_estimate(&f.ext, &f.cur, RAY_O, RAY_D, 12.0, 16.0, &st, &rng);
    assert_true(fabs(T - exp(-0.4 * 4.0)) < 1e-12); /* above the Russian-roulette threshold 0.1 */
    for (int i = 0; i < 200; ++i) {
        vbl_rng r1 = vbl_rng_make(5, 0, (uint64_t)i), r2 = vbl_rng_make(5, 0, (uint64_t)i);
        double t1 = 0, s1 = 0, p1[VBL_MAX_MEDIA], t2 = 0, s2 = 0, p2[VBL_MAX_MEDIA];
        int c1 = vbl_free_flight_sample(&f.ext, &f.cur, RAY_O, RAY_D, 12.0, 24.0, 0, &r1, &t1, &s1, p1);
        int c2 = vbl_free_flight_sample(&f.ext, &f.cur, RAY_O, RAY_D, 12.0, 24.0, 0, &r2, &t2, &s2, p2);
        assert_int_equal(c1, c2); /* bit-deterministic */
        if (!c1) continue;
        assert_true(t1 == t2 && s1 == s2);
        assert_true(fabs(s1 - 0.4) < 1e-12 && fabs(p1[0] + p1[1] - s1) < 1e-12 && fabs(p1[0] - 0.1) < 1e-12);
    }
    vt_free(f.vol);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_interior_exact),
        cmocka_unit_test(test_whole_box),
        cmocka_unit_test(test_two_media_and_determinism),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
