/* The trilinear sampler's region cache (grid_sample.h: the 8^3 leaf-sized regions last read, one
 * tree descent per region while it stays cached) returns bit-identical values to 8 separate
 * accessor fetches (the sampler before issue 14 item 5), at points inside leaves, on leaf faces,
 * edges and corners, at negative coordinates, in the background, in tiles of the lower and upper
 * nodes (the tiles.vdb fixture) and far outside the int range (saturated, NaN); nearest sampling
 * too. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "core/rng.h"
#include "volume/grid_sample.h"
#include "vbl/vbl_volume.h"
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

/* The sampler before issue 14 item 5 for any point: floors saturated at +-2147483000 (NaN low),
 * weights clamped to [0, 1], 8 separate fetches. */
static int sat_floor(double x)
{
    double f = floor(x);
    if (!(f > -2147483000.0)) return -2147483000;
    if (f > 2147483000.0) return 2147483000;
    return (int)f;
}

static double reference_any(const vbl_volume* v, pnanovdb_readaccessor_t* acc, vbl_vec3 p)
{
    int i = sat_floor(p.x), j = sat_floor(p.y), k = sat_floor(p.z);
    double u = vbl_clamp(p.x - i, 0.0, 1.0), w1 = vbl_clamp(p.y - j, 0.0, 1.0), w = vbl_clamp(p.z - k, 0.0, 1.0);
    float d000 = fetch(v, acc, i, j, k), d001 = fetch(v, acc, i, j, k + 1);
    float d010 = fetch(v, acc, i, j + 1, k), d011 = fetch(v, acc, i, j + 1, k + 1);
    float d100 = fetch(v, acc, i + 1, j, k), d101 = fetch(v, acc, i + 1, j, k + 1);
    float d110 = fetch(v, acc, i + 1, j + 1, k), d111 = fetch(v, acc, i + 1, j + 1, k + 1);
    float a = lerp(lerp(d000, d001, w), lerp(d010, d011, w), w1);
    float b = lerp(lerp(d100, d101, w), lerp(d110, d111, w), w1);
    return lerp(a, b, u);
}

static int same(double a, double b) { return a == b || (isnan(a) && isnan(b)); }

/* tiles.vdb: an upper-node tile 0.25 on [0,127]^3, a lower-node tile 0.5 on [128,135]x[0,7]^2 and
 * a voxel at (130,20,3): footprints in tiles, across tile / leaf / background faces, with the
 * cache's slots reused between far-apart points (random order) and along rays (in order). */
static void test_tiles_and_far_points(void** state)
{
    (void)state;
    const char* dir = getenv("VBL_FIXTURE_DIR");
    if (!dir || !dir[0]) {
        fprintf(stderr, "VBL_FIXTURE_DIR is not set (run through ctest)\n");
        fail();
    }
    char path[2048];
    snprintf(path, sizeof path, "%s/tiles.vdb", dir);
    vbl_volume_load_options opt = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    opt.grid_name = "density";
    vbl_volume* v = NULL;
    if (vbl_volume_load(path, &opt, &v) != VBL_SUCCESS) {
        fprintf(stderr, "cannot load %s: %s\n", path, vbl_last_error_message());
        fail();
    }
    vbl_grid_accessor acc;
    vbl_grid_accessor_init(&acc, v);
    pnanovdb_readaccessor_t ref;
    pnanovdb_readaccessor_init(&ref, v->root);
    vbl_rng rng = vbl_rng_make(14, 6, 0);
    int in_tile = 0, mixed = 0;
    vbl_vec3 p = vbl_v3(0, 0, 0), d = vbl_v3(1, 0, 0);
    for (int n = 0; n < 200000; ++n) {
        if (n % 64 == 0 || n % 2 == 1) { /* a random point, or the next step along a ray */
            const double lo[3] = {-12.0, -12.0, -12.0}, hi[3] = {150.0, 30.0, 140.0};
            double c[3];
            for (int a = 0; a < 3; ++a) {
                c[a] = lo[a] + (hi[a] - lo[a]) * vbl_rng_uniform(&rng);
                if (n % 5 == 0) c[a] = 8.0 * floor(c[a] / 8.0) + 7.0 + vbl_rng_uniform(&rng); /* across a region face */
                if (n % 11 == 0) c[a] = floor(c[a]);
            }
            if (n % 3 == 0) { /* around the lower-node tile and the voxel */
                c[0] = 126.0 + 12.0 * vbl_rng_uniform(&rng);
                c[1] = -2.0 + 24.0 * vbl_rng_uniform(&rng);
                c[2] = -2.0 + 8.0 * vbl_rng_uniform(&rng);
            }
            p = vbl_v3(c[0], c[1], c[2]);
            d = vbl_v3_normalize(vbl_v3(vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5));
        } else {
            p = vbl_v3_madd(p, d, 0.37);
        }
        double got = vbl_grid_sample_index_trilinear(&acc, p), want = reference_any(v, &ref, p);
        if (got == 0.25 || got == 0.5) in_tile++;
        else if (got != 0.0) mixed++;
        if (!same(got, want)) {
            fprintf(stderr, "p = (%.17g, %.17g, %.17g): %.9g vs %.9g\n", p.x, p.y, p.z, got, want);
            fail();
        }
        vbl_vec3 q = vbl_v3(floor(p.x + 0.5), floor(p.y + 0.5), floor(p.z + 0.5));
        double near = vbl_grid_sample_index_nearest(&acc, p);
        double near_want = fetch(v, &ref, (int)q.x, (int)q.y, (int)q.z);
        if (near != near_want) {
            fprintf(stderr, "nearest at (%.17g, %.17g, %.17g): %.9g vs %.9g\n", p.x, p.y, p.z, near, near_want);
            fail();
        }
    }
    printf("tiles: constant tile values %d, blended %d of 200000\n", in_tile, mixed);
    assert_true(in_tile > 20000 && mixed > 20000);
    /* far outside the int range, at its saturation bound and NaN: the far path (grid_sample.c) */
    const double far[] = {3e9, -3e9, 2147483000.0, -2147483000.0, 2147482999.5, -2147482999.5, 1e300, -1e300,
                          NAN, 0.5, 100.25, 130.0};
    const int nf = (int)(sizeof far / sizeof far[0]);
    for (int a = 0; a < nf; ++a)
        for (int b = 0; b < nf; ++b)
            for (int c = 0; c < nf; ++c) {
                vbl_vec3 q = vbl_v3(far[a], far[b], far[c]);
                double got = vbl_grid_sample_index_trilinear(&acc, q), want = reference_any(v, &ref, q);
                if (!same(got, want)) {
                    fprintf(stderr, "far p = (%.17g, %.17g, %.17g): %.9g vs %.9g\n", q.x, q.y, q.z, got, want);
                    fail();
                }
            }
    vbl_volume_release(v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_bit_identical), cmocka_unit_test(test_tiles_and_far_points)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
