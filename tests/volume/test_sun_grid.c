/* The transmittance grid towards a distant light (volume/sun_grid.h; pt.shadow_control, issue 14):
 * against a fine quadrature of the optical depth on a Gaussian blob, at 200 random points for
 * three light directions; bit-identical at 1 and 2 threads; points outside the box read the value
 * where their ray enters it, or 1 where it misses; nodes a surface blocks hold 0, the others the
 * open grid's values; finite in [0, 1] at density scales 1e-8 and 1e6; bad boxes and directions
 * are refused. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "core/rng.h"
#include "volume/sun_grid.h"
#include "volume_test_grid.h"

#define N 32
static const double H = 1.0 / 16.0; /* voxel edge: the volume spans [0, 2) */

/* A Gaussian blob of peak 1 around the box's centre (sigma 6 voxels). */
static double fn_blob(int i, int j, int k, void* user)
{
    (void)user;
    const double c = 0.5 * (N - 1), r2 = (i - c) * (i - c) + (j - c) * (j - c) + (k - c) * (k - c);
    const double v = exp(-r2 / (2.0 * 36.0));
    return v > 1e-4 ? v : 0.0;
}

typedef struct blob {
    vbl_volume* vol;
    vbl_extinction ext;
    vbl_vec3 lo, hi; /* the trilinear support: index (-1, N) */
} blob;

static void blob_make(blob* b, double scale)
{
    double m[3][4];
    vt_uniform_map(m, H, 0.0, 0.0, 0.0);
    const int bmin[3] = {0, 0, 0}, bmax[3] = {N - 1, N - 1, N - 1};
    b->vol = vt_make(bmin, bmax, fn_blob, NULL, m);
    assert_non_null(b->vol);
    vbl_extinction_init(&b->ext);
    assert_int_equal(vbl_extinction_add(&b->ext, b->vol, scale, NULL), VBL_SUCCESS);
    b->lo = vbl_v3(-H, -H, -H);
    b->hi = vbl_v3(N * H, N * H, N * H);
}

/* exp(-tau) from x along w to the box's far side, tau by the midpoint rule at 1/32 voxel */
static double reference_T(const blob* b, vbl_extinction_cursor* cur, vbl_vec3 x, vbl_vec3 w)
{
    double tau = 0.0;
    const double dt = H / 32.0;
    for (double t = 0.5 * dt;; t += dt) {
        vbl_vec3 p = vbl_v3_madd(x, w, t);
        if (p.x < b->lo.x || p.y < b->lo.y || p.z < b->lo.z || p.x > b->hi.x || p.y > b->hi.y || p.z > b->hi.z) break;
        tau += vbl_extinction_eval(&b->ext, cur, p, NULL) * dt;
    }
    return exp(-tau);
}

static void test_matches_quadrature(void** state)
{
    (void)state;
    blob b;
    blob_make(&b, 2.0); /* optical depth ~2.3 through the centre */
    vbl_extinction_cursor cur;
    vbl_extinction_cursor_init(&cur, &b.ext);
    const vbl_vec3 dirs[3] = {vbl_v3_normalize(vbl_v3(0.3, -0.4, 0.87)), vbl_v3_normalize(vbl_v3(-1.0, 0.2, 0.1)),
                              vbl_v3(0.0, 1.0, 0.0)};
    for (int d = 0; d < 3; ++d) {
        vbl_sun_grid g;
        assert_int_equal(vbl_sun_grid_build(&g, &b.ext, b.lo, b.hi, dirs[d], (size_t)1 << 17, 1, NULL, NULL), VBL_SUCCESS);
        vbl_rng rng = vbl_rng_make(7, (uint64_t)d, 1);
        double max_err = 0.0, sum_err = 0.0, min_T = 1.0;
        for (int i = 0; i < 200; ++i) {
            vbl_vec3 x = vbl_v3(vbl_rng_uniform(&rng) * N * H, vbl_rng_uniform(&rng) * N * H,
                                vbl_rng_uniform(&rng) * N * H);
            const double Tc = vbl_sun_grid_eval(&g, x), T = reference_T(&b, &cur, x, dirs[d]);
            assert_true(Tc >= 0.0 && Tc <= 1.0);
            const double e = fabs(Tc - T);
            if (e > max_err) max_err = e;
            if (T < min_T) min_T = T;
            sum_err += e;
        }
        printf("direction %d: nodes %d x %d x %d, |T_c - T| max %.4f mean %.5f (smallest T %.3f)\n", d, g.n[0], g.n[1],
               g.n[2], max_err, sum_err / 200, min_T);
        assert_true(min_T < 0.3);     /* the test reaches the blob's shadow */
        assert_true(max_err < 0.05); /* measured 0.031, 0.022, 0.004 */
        assert_true(sum_err / 200 < 0.006); /* measured 0.0037, 0.0031, 0.0004 */
        vbl_sun_grid_free(&g);
    }
    vt_free(b.vol);
}

static void test_threads_and_outside(void** state)
{
    (void)state;
    blob b;
    blob_make(&b, 2.0);
    const vbl_vec3 w = vbl_v3_normalize(vbl_v3(0.3, -0.4, 0.87));
    vbl_sun_grid g1, g2;
    assert_int_equal(vbl_sun_grid_build(&g1, &b.ext, b.lo, b.hi, w, (size_t)1 << 16, 1, NULL, NULL), VBL_SUCCESS);
    assert_int_equal(vbl_sun_grid_build(&g2, &b.ext, b.lo, b.hi, w, (size_t)1 << 16, 2, NULL, NULL), VBL_SUCCESS);
    assert_memory_equal(g1.n, g2.n, sizeof g1.n);
    assert_memory_equal(g1.T, g2.T, sizeof(float) * (size_t)g1.n[0] * g1.n[1] * g1.n[2]);
    assert_true((size_t)g1.n[0] * g1.n[1] * g1.n[2] <= (size_t)1 << 16);
    /* below the box, its ray enters the bottom face at the centre: the value there */
    const vbl_vec3 entry = vbl_v3(1.0, 1.0, b.lo.z);
    const vbl_vec3 below = vbl_v3_madd(entry, w, -0.5);
    assert_true(fabs(vbl_sun_grid_eval(&g1, below) - vbl_sun_grid_eval(&g1, entry)) < 1e-12);
    assert_true(vbl_sun_grid_eval(&g1, entry) < 0.5); /* under the blob's centre */
    /* beside the box, its ray leaves it alone: no media on the way */
    assert_true(vbl_sun_grid_eval(&g1, vbl_v3(5.0, 1.0, 1.0)) == 1.0);
    assert_true(vbl_sun_grid_eval(&g1, vbl_v3(NAN, 1.0, 1.0)) == 1.0);
    vbl_sun_grid_free(&g1);
    vbl_sun_grid_free(&g2);
    vt_free(b.vol);
}

/* blocks every node with x > 1 (a wall along the light's direction) */
static int block_right(void* user, vbl_vec3 x, vbl_vec3 w)
{
    (void)w;
    ++*(int*)user;
    return x.x > 1.0;
}

static void test_occluded_nodes(void** state)
{
    (void)state;
    blob b;
    blob_make(&b, 2.0);
    const vbl_vec3 w = vbl_v3(0.0, 0.0, 1.0);
    vbl_sun_grid g, open;
    int calls = 0;
    assert_int_equal(vbl_sun_grid_build(&g, &b.ext, b.lo, b.hi, w, (size_t)1 << 15, 1, block_right, &calls), VBL_SUCCESS);
    assert_int_equal(vbl_sun_grid_build(&open, &b.ext, b.lo, b.hi, w, (size_t)1 << 15, 1, NULL, NULL), VBL_SUCCESS);
    assert_int_equal(calls, g.n[0] * g.n[1] * g.n[2]); /* one test per node */
    int blocked = 0;
    for (int i = 0; i < g.n[0]; ++i)
        for (int j = 0; j < g.n[1]; ++j)
            for (int k = 0; k < g.n[2]; ++k) {
                const size_t at = ((size_t)i * g.n[1] + j) * g.n[2] + k;
                if (b.lo.x + i * g.h[0] > 1.0) {
                    assert_true(g.T[at] == 0.0f);
                    ++blocked;
                } else
                    assert_true(g.T[at] == open.T[at]); /* w along z: no node reads a blocked one */
            }
    assert_true(blocked > 0);
    vbl_sun_grid_free(&g);
    vbl_sun_grid_free(&open);
    vt_free(b.vol);
}

static void test_extremes_and_errors(void** state)
{
    (void)state;
    const double scales[2] = {1e-8, 1e6};
    const vbl_vec3 w = vbl_v3(0.0, 0.0, 1.0);
    for (int s = 0; s < 2; ++s) {
        blob b;
        blob_make(&b, scales[s]);
        vbl_sun_grid g;
        assert_int_equal(vbl_sun_grid_build(&g, &b.ext, b.lo, b.hi, w, (size_t)1 << 15, 1, NULL, NULL), VBL_SUCCESS);
        const double centre = vbl_sun_grid_eval(&g, vbl_v3(1.0, 1.0, 0.5));
        assert_true(centre >= 0.0 && centre <= 1.0);
        if (s == 0) assert_true(centre > 1.0 - 1e-6);
        else assert_true(centre < 1e-6);
        vbl_sun_grid_free(&g);
        vt_free(b.vol);
    }
    blob b;
    blob_make(&b, 1.0);
    vbl_sun_grid g;
    assert_int_equal(vbl_sun_grid_build(&g, &b.ext, b.hi, b.lo, w, 1000, 1, NULL, NULL), VBL_ERROR_INVALID_ARGUMENT);
    assert_null(g.T);
    assert_int_equal(vbl_sun_grid_build(&g, &b.ext, b.lo, b.hi, vbl_v3(0.0, 0.0, 2.0), 1000, 1, NULL, NULL),
                     VBL_ERROR_INVALID_ARGUMENT);
    assert_int_equal(vbl_sun_grid_eval(&g, vbl_v3(1.0, 1.0, 1.0)) == 1.0, 1); /* no grid: 1 */
    vt_free(b.vol);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_quadrature),
        cmocka_unit_test(test_threads_and_outside),
        cmocka_unit_test(test_occluded_nodes),
        cmocka_unit_test(test_extremes_and_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
