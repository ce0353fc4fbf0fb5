/* The trilinear sampler's leaf-grouped fetch (grid_sample.c: one tree descent per 8^3 leaf region
 * the 8 voxels touch) returns bit-identical values to 8 separate accessor fetches (the sampler
 * before issue 14 item 5), at points inside leaves, on leaf faces, edges and corners, at negative
 * coordinates and in the background. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include "core/rng.h"
#include "volume/grid_sample.h"
#include "volume_test_grid.h"

static double fn_wavy(int i, int j, int k, void* user)
{
    (void)user;
    double v = 1.0 + 0.5 * sin(0.9 * i + 0.1) * cos(0.7 * j - 0.3 * k) + 0.01 * (i - 2 * j + 3 * k);
    return v > 0.0 ? v : 0.0;
}

static float fetch(const vbl_volume* v, pnanovdb_readaccessor_t* acc, int i, int j, int k)
{
    pnanovdb_coord_t ijk = {i, j, k};
    return pnanovdb_read_float(v->buf, pnanovdb_readaccessor_get_value_address(PNANOVDB_GRID_TYPE_FLOAT, v->buf, acc, &ijk));
}

static float lerp(float a, float b, double w) { return a + (float)((double)(b - a) * w); }

/* The pre-issue-14 sampler: 8 independent fetches. */
static double reference_trilinear(const vbl_volume* v, pnanovdb_readaccessor_t* acc, vbl_vec3 p)
{
    int i = (int)floor(p.x), j = (int)floor(p.y), k = (int)floor(p.z);
    double u = p.x - i, w1 = p.y - j, w = p.z - k;
    float d000 = fetch(v, acc, i, j, k), d001 = fetch(v, acc, i, j, k + 1);
    float d010 = fetch(v, acc, i, j + 1, k), d011 = fetch(v, acc, i, j + 1, k + 1);
    float d100 = fetch(v, acc, i + 1, j, k), d101 = fetch(v, acc, i + 1, j, k + 1);
    float d110 = fetch(v, acc, i + 1, j + 1, k), d111 = fetch(v, acc, i + 1, j + 1, k + 1);
    float a = lerp(lerp(d000, d001, w), lerp(d010, d011, w), w1);
    float b = lerp(lerp(d100, d101, w), lerp(d110, d111, w), w1);
    return lerp(a, b, u);
}

static void test_bit_identical(void** state)
{
    (void)state;
    const int bmin[3] = {-13, -9, -17}, bmax[3] = {18, 22, 14}; /* several leaves, negative coords */
    double m[3][4];
    vt_uniform_map(m, 1.0, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(bmin, bmax, fn_wavy, NULL, m);
    assert_non_null(v);
    vbl_grid_accessor acc;
    vbl_grid_accessor_init(&acc, v);
    pnanovdb_readaccessor_t ref;
    pnanovdb_readaccessor_init(&ref, v->root);
    vbl_rng rng = vbl_rng_make(14, 5, 0);
    int fast = 0, straddle = 0, nonzero = 0;
    for (int n = 0; n < 200000; ++n) {
        double c[3];
        for (int a = 0; a < 3; ++a) {
            double x = -24.0 + 52.0 * vbl_rng_uniform(&rng);
            if (n % 3 == 0) x = 8.0 * floor(x / 8.0) + 7.0 + vbl_rng_uniform(&rng); /* cell 7 of a leaf */
            if (n % 7 == 0) x = floor(x);                                            /* on a voxel */
            c[a] = x;
        }
        vbl_vec3 p = vbl_v3(c[0], c[1], c[2]);
        int i = (int)floor(p.x), j = (int)floor(p.y), k = (int)floor(p.z);
        if ((i & 7) != 7 && (j & 7) != 7 && (k & 7) != 7) fast++;
        else straddle++;
        double got = vbl_grid_sample_index_trilinear(&acc, p), want = reference_trilinear(v, &ref, p);
        if (got != 0.0) nonzero++;
        if (got != want) {
            fprintf(stderr, "p = (%.17g, %.17g, %.17g): %.9g vs %.9g\n", p.x, p.y, p.z, got, want);
            fail();
        }
    }
    printf("fast path %d, straddling %d, non-zero %d of 200000\n", fast, straddle, nonzero);
    assert_true(fast > 20000 && straddle > 20000 && nonzero > 20000);
    assert_int_equal(acc.lookups, 200000);
    vt_free(v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_bit_identical)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
