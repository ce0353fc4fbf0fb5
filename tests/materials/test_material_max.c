/* Maximum directions and cone bounds (VBL paper section 3.1 / 6): a brute-force search over a
 * dense grid finds no f cos above vbl_material_max_direction's value and comes within the grid
 * resolution of it; vbl_material_max_in_cone never falls below f cos inside its cone and is tight
 * for small cones; parameter validation names the field at fault. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "core/rng.h"
#include "material_test_util.h"
#include "sampling/sphere.h"

static int cmp_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static double fcos_mean(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    vbl_vec3 f = vbl_material_eval(m, n, wo, wi);
    return (f.x + f.y + f.z) / 3.0 * fmax(0.0, vbl_v3_dot(n, wi));
}

typedef struct max_case { vbl_material_type type; double kd, ks, exponent, roughness; } max_case;
static const max_case kCases[] = {
    {VBL_MATERIAL_LAMBERT, 0.7, 0.0, 0.0, 0.0},  {VBL_MATERIAL_PHONG, 0.3, 0.6, 1.0, 0.0},
    {VBL_MATERIAL_PHONG, 0.3, 0.6, 60.0, 0.0},   {VBL_MATERIAL_PHONG, 0.0, 1.0, 100.0, 0.0},
    {VBL_MATERIAL_PHONG, 0.8, 0.2, 10.0, 0.0},   {VBL_MATERIAL_PHONG, 0.1, 0.9, 1000.0, 0.0},
    {VBL_MATERIAL_GGX, 0.3, 0.5, 0.0, 0.05},     {VBL_MATERIAL_GGX, 0.0, 1.0, 0.0, 0.3},
    {VBL_MATERIAL_GGX, 0.9, 0.04, 0.0, 0.3},     {VBL_MATERIAL_GGX, 0.2, 0.5, 0.0, 1.0},
    {VBL_MATERIAL_GGX, 0.0, 0.9, 0.0, 0.001},
};
#define NCASES ((int)(sizeof kCases / sizeof kCases[0]))
static const double kTheta[] = {0.0, 30.0, 60.0, 85.0, 89.0};
#define NTHETA ((int)(sizeof kTheta / sizeof kTheta[0]))

static vbl_material case_material(int c)
{
    return mt_material(kCases[c].type, kCases[c].kd, kCases[c].ks, kCases[c].exponent, kCases[c].roughness);
}

/* Dense grid in the frame about the mirror direction: 1 - u graded from 2 down to 1e-10 (each
 * octave split in 24), 720 azimuths; plus 20000 random directions in a small cap about the
 * returned maximum. */
static void test_max_direction_brute_force(void** state)
{
    (void)state;
    vbl_vec3 n = mt_normal();
    double worst_excess = 0.0, worst_gap = 0.0;
    for (int c = 0; c < NCASES; ++c) {
        vbl_material m = case_material(c);
        for (int t = 0; t < NTHETA; ++t) {
            vbl_vec3 wo = mt_wo(n, kTheta[t], 0.4 + t);
            vbl_vec3 d = vbl_material_max_direction(&m, n, wo);
            assert_true(fabs(vbl_v3_length(d) - 1.0) < 1e-12 && vbl_v3_dot(n, d) > 0.0);
            double best = fcos_mean(&m, n, wo, d), grid = 0.0;
            mt_frame f = mt_frame_make(mt_axis(&m, n, wo), n);
            for (double k = 0.0; k <= 34.0 * 24.0; k += 1.0) {
                double u = 1.0 - 2.0 * pow(2.0, -k / 24.0);
                for (int p = 0; p < 720; ++p) grid = fmax(grid, fcos_mean(&m, n, wo, mt_dir(&f, u, -VBL_PI + p * VBL_PI / 360.0)));
            }
            vbl_rng rng = vbl_rng_make(5, 7, (uint64_t)(c * NTHETA + t));
            for (int i = 0; i < 20000; ++i) {
                vbl_vec3 w = vbl_sample_uniform_cone(d, cos(1e-3), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), NULL);
                grid = fmax(grid, fcos_mean(&m, n, wo, w));
            }
            double excess = (grid - best) / best, gap = (best - grid) / best;
            worst_excess = fmax(worst_excess, excess);
            worst_gap = fmax(worst_gap, gap);
            if (excess > 1e-9 || gap > 1e-3)
                printf("case %d theta_o %g: max_direction value %.12g, brute force %.12g\n", c, kTheta[t], best, grid);
            assert_true(excess <= 1e-9); /* nothing beats the returned direction */
            assert_true(gap <= 1e-3);    /* and the grid gets close to it: it is attained */
            if (m.type == VBL_MATERIAL_LAMBERT) assert_true(vbl_v3_length(vbl_v3_sub(d, n)) < 1e-12);
        }
    }
    printf("max_direction: brute force exceeds the returned value by at most %.3g (relative); grid within %.3g "
           "below it\n", worst_excess, worst_gap);
}

/* Bound check: random cones (axes anywhere, near n, near the maximum; half-angles 1e-4..1.5). */
static void test_max_in_cone_bounds(void** state)
{
    (void)state;
    vbl_vec3 n = mt_normal();
    static const double halves[] = {1e-4, 0.01, 0.1, 0.5, 1.5};
    double worst = -1.0; /* closest approach of a value to its bound, relative (must stay <= 0) */
    for (int c = 0; c < NCASES; ++c) {
        vbl_material m = case_material(c);
        double tight = 0.0, loose[64];
        int nloose = 0;
        for (int t = 0; t < NTHETA; ++t) {
            vbl_vec3 wo = mt_wo(n, kTheta[t], 1.1 + t);
            vbl_vec3 d = vbl_material_max_direction(&m, n, wo);
            vbl_rng rng = vbl_rng_make(6, 8, (uint64_t)(c * NTHETA + t));
            for (int k = 0; k < 60; ++k) {
                double half = halves[k % 5];
                vbl_vec3 axis = vbl_sample_uniform_sphere(vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), NULL);
                if (k % 3 == 1) axis = vbl_sample_uniform_cone(d, cos(0.3), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), NULL);
                if (k % 3 == 2) axis = vbl_sample_uniform_cone(n, cos(1.2), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), NULL);
                vbl_vec3 bound = vbl_material_max_in_cone(&m, n, wo, axis, cos(half));
                assert_true(isfinite(bound.x) && bound.x >= 0.0);
                double seen = 0.0;
                vbl_vec3 ta, tb;
                vbl_v3_basis(axis, &ta, &tb);
                for (int i = 0; i < 1120; ++i) {
                    /* the axis, 400 random points inside, 720 on the boundary circle (where the maximum
                     * over the cone lies unless the unconstrained maximum is inside) */
                    vbl_vec3 w = i == 0 ? axis
                                 : i < 400 ? vbl_sample_uniform_cone(axis, cos(half), vbl_rng_uniform(&rng),
                                                                     vbl_rng_uniform(&rng), NULL)
                                           : vbl_v3_normalize(vbl_v3_add(
                                                 vbl_v3_scale(axis, cos(half)),
                                                 vbl_v3_scale(vbl_v3_add(vbl_v3_scale(ta, cos(i * VBL_PI / 360.0)),
                                                                         vbl_v3_scale(tb, sin(i * VBL_PI / 360.0))),
                                                              sin(half))));
                    vbl_vec3 v = vbl_v3_scale(vbl_material_eval(&m, n, wo, w), fmax(0.0, vbl_v3_dot(n, w)));
                    seen = fmax(seen, v.x);
                    for (int ch = 0; ch < 3; ++ch) {
                        double b = vbl_v3_get(bound, ch), x = vbl_v3_get(v, ch);
                        if (x > 0.0) worst = fmax(worst, (x - b) / x);
                        assert_true(x <= b * (1.0 + 1e-9) + 1e-300);
                    }
                }
                if (half == 0.1 && seen > 1e-3 * bound.x && nloose < 64) loose[nloose++] = bound.x / seen;
            }
            /* tightness: a tiny cone about the maximum */
            double b = vbl_v3_get(vbl_material_max_in_cone(&m, n, wo, d, cos(1e-6)), 0);
            double v = vbl_v3_get(vbl_v3_scale(vbl_material_eval(&m, n, wo, d), vbl_v3_dot(n, d)), 0);
            tight = fmax(tight, b / v);
            assert_true(b / v < 1.0 + 1e-4);
            /* a cone entirely below the surface bounds nothing */
            vbl_vec3 below = vbl_material_max_in_cone(&m, n, wo, vbl_v3_scale(n, -1.0), cos(0.5));
            assert_true(below.x == 0.0 && below.y == 0.0 && below.z == 0.0);
        }
        qsort(loose, (size_t)nloose, sizeof loose[0], cmp_double);
        printf("max_in_cone case %d: bound / value for a 1e-6 rad cone about the maximum <= %.6f; bound / largest "
               "value seen in 0.1 rad cones: median %.3f, 90%% %.3f (%d cones)\n", c, tight,
               nloose ? loose[nloose / 2] : 0.0, nloose ? loose[(nloose * 9) / 10] : 0.0, nloose);
    }
    printf("max_in_cone: largest (value - bound) / value over all cones %.3g (must be <= 1e-9)\n", worst);
}

static void test_validate(void** state)
{
    (void)state;
    char why[256];
    vbl_material ok[] = {mt_material(VBL_MATERIAL_LAMBERT, 1.0, 5.0, -1.0, -1.0), /* unused fields ignored */
                         mt_material(VBL_MATERIAL_PHONG, 0.4, 0.6, 0.0, 0.0),
                         mt_material(VBL_MATERIAL_PHONG, 0.0, 1.0, 1e6, 0.0),
                         mt_material(VBL_MATERIAL_GGX, 1.0, 1.0, 0.0, 1.0),
                         mt_material(VBL_MATERIAL_GGX, 0.0, 0.0, 0.0, 1e-3)};
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; ++i) {
        assert_true(vbl_material_validate(&ok[i], why, sizeof why));
        assert_string_equal(why, "");
    }
    struct { vbl_material m; const char* field; } bad[] = {
        {mt_material(VBL_MATERIAL_LAMBERT, 1.5, 0.0, 0.0, 0.0), "albedo.r = 1.5"},
        {mt_material(VBL_MATERIAL_PHONG, 0.2, 0.2, -1.0, 0.0), "exponent = -1"},
        {mt_material(VBL_MATERIAL_PHONG, 0.2, 0.2, NAN, 0.0), "exponent = nan"},
        {mt_material(VBL_MATERIAL_PHONG, 0.2, 0.2, 2e6, 0.0), "exponent = 2e+06"},
        {mt_material(VBL_MATERIAL_PHONG, 0.6, 0.6, 60.0, 0.0), "albedo.r + specular.r = 1.2"},
        {mt_material(VBL_MATERIAL_PHONG, 0.2, -0.1, 60.0, 0.0), "specular.r = -0.1"},
        {mt_material(VBL_MATERIAL_GGX, 0.2, 0.2, 0.0, 0.0), "roughness = 0"},
        {mt_material(VBL_MATERIAL_GGX, 0.2, 0.2, 0.0, 1.5), "roughness = 1.5"},
        {mt_material(VBL_MATERIAL_GGX, 0.2, 0.2, 0.0, 1e-4), "roughness = 0.0001"},
        {mt_material((vbl_material_type)7, 0.2, 0.2, 0.0, 0.5), "type = 7"},
    };
    bad[0].m.albedo.y = 0.5;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_false(vbl_material_validate(&bad[i].m, why, sizeof why));
        printf("invalid: %s\n", why);
        assert_non_null(strstr(why, bad[i].field));
        assert_false(vbl_material_validate(&bad[i].m, NULL, 0));
    }
    /* a short buffer is truncated, never overrun */
    char tiny[8];
    assert_false(vbl_material_validate(&bad[1].m, tiny, sizeof tiny));
    assert_true(strlen(tiny) == sizeof tiny - 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_max_direction_brute_force),
        cmocka_unit_test(test_max_in_cone_bounds),
        cmocka_unit_test(test_validate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
