/* Section 4 helpers: power-based light selection (frequencies within 4 standard errors), the
 * uniform cone of eq 4 (inside the cone, its pdf integrates to 1 over the sphere, cos
 * distribution), lights containing a point against brute force, eq 8's density against the
 * light count per unit area of a blue-noise set (eq 1), eq 9's blend weight and eq 5. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "transport/surface/blue_noise/light_sampling.h"
#include "transport/surface/blue_noise/sample_elimination.h"
#include "core/rng.h"
#include "vbl/vbl.h"

static void test_pick_by_power(void** state)
{
    (void)state;
    vbl_bn_light l[5];
    vbl_vec3 power[5] = {{1, 1, 1}, {0, 0, 0}, {3, 3, 3}, {0.5, 1.0, 1.5}, {5, 0, 1}};
    for (int i = 0; i < 5; ++i) {
        memset(&l[i], 0, sizeof l[i]);
        l[i].position = vbl_v3(i, 0, 0);
        l[i].normal = vbl_v3(0, 0, 1);
        l[i].radius = 0.3;
    }
    vbl_bn_light_set s;
    assert_int_equal(vbl_bn_light_set_init(&s, l, 5, power, 2.0), VBL_SUCCESS);
    const int n = 200000;
    int count[5] = {0};
    vbl_rng r = vbl_rng_make(4, 0, 0);
    for (int i = 0; i < n; ++i) {
        double p;
        size_t j = vbl_bn_pick_light(&s, vbl_rng_uniform(&r), &p);
        assert_true(j < 5);
        assert_true(fabs(p - vbl_bn_light_prob(&s, j)) < 1e-15);
        ++count[j];
    }
    assert_int_equal(count[1], 0);
    for (int j = 0; j < 5; ++j) {
        double p = vbl_bn_light_prob(&s, (size_t)j), se = sqrt(n * p * (1.0 - p)) + 1e-9;
        assert_true(fabs(count[j] - n * p) < 4.0 * se + 1e-9);
    }
    size_t last = vbl_bn_pick_light(&s, 0.999999999999, NULL);
    assert_true(last == 4);
    vbl_bn_light_set_free(&s);
    power[2].y = NAN;
    assert_int_equal(vbl_bn_light_set_init(&s, l, 5, power, 2.0), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "power[2]"));
}

static vbl_vec3 uniform_direction(vbl_rng* r)
{
    double z = 1.0 - 2.0 * vbl_rng_uniform(r), phi = 2.0 * VBL_PI * vbl_rng_uniform(r);
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return vbl_v3(s * cos(phi), s * sin(phi), z);
}

static void test_cone(void** state)
{
    (void)state;
    const vbl_vec3 x = {0.1, -0.2, 0.3};
    const vbl_vec3 centres[3] = {{2, 1, 0.5}, {0.2, -0.1, 0.35}, {0, 0, 5}};
    const double radii[3] = {0.5, 0.3, 0.05}; /* outside, inside (whole sphere), tiny */
    for (int k = 0; k < 3; ++k) {
        vbl_vec3 c = centres[k];
        double r = radii[k];
        vbl_vec3 axis = vbl_v3_normalize(vbl_v3_sub(c, x));
        double d = vbl_v3_length(vbl_v3_sub(c, x));
        double cmax = d > r ? sqrt(1.0 - r * r / (d * d)) : -1.0;
        vbl_rng rng = vbl_rng_make(6, (uint64_t)k, 0);
        const int n = 100000;
        double cmid = 0.5 * (1.0 + cmax);
        int above = 0;
        for (int i = 0; i < n; ++i) {
            vbl_vec3 w;
            double pdf;
            assert_true(vbl_bn_sample_cone(x, c, r, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &w, &pdf));
            double ct = vbl_v3_dot(w, axis);
            assert_true(ct >= cmax - 1e-12);
            assert_true(fabs(pdf - vbl_bn_cone_pdf(x, c, r, w)) < 1e-12 * pdf);
            above += ct >= cmid;
        }
        /* uniform in solid angle: P(cos >= cmid) = 1/2 */
        assert_true(fabs(above - 0.5 * n) < 4.0 * sqrt(0.25 * n));
        /* the pdf integrates to 1: 4 pi E_uniform[pdf] over uniform directions (too rare a hit
         * for the tiny cone: there the pdf is checked against 1 / (2 pi (1 - cos theta))) */
        if (k == 2) {
            assert_true(fabs(vbl_bn_cone_pdf(x, c, r, axis) * 2.0 * VBL_PI * (1.0 - cmax) - 1.0) < 1e-9);
            continue;
        }
        int m = 400000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < m; ++i) {
            double v = 4.0 * VBL_PI * vbl_bn_cone_pdf(x, c, r, uniform_direction(&rng));
            sum += v;
            sum2 += v * v;
        }
        double mean = sum / m, se = sqrt(fmax(0.0, sum2 / m - mean * mean) / m);
        printf("cone %d: integral of the pdf %.4f +- %.4f\n", k, mean, se);
        assert_true(fabs(mean - 1.0) < 4.0 * se + 1e-12);
    }
}

static void test_density_and_containment(void** state)
{
    (void)state;
    /* a blue-noise set of N lights on the unit square: eq 8 gives N per unit area (eq 1) */
    const size_t M = 10000, N = 1000;
    vbl_vec3* p = malloc(M * sizeof *p);
    vbl_rng r = vbl_rng_make(8, 0, 0);
    for (size_t i = 0; i < M; ++i) p[i] = vbl_v3(vbl_rng_uniform(&r), vbl_rng_uniform(&r), 0.0);
    size_t kept[1000];
    double rmax[1000];
    assert_int_equal(vbl_bn_eliminate(p, M, N, NULL, kept, rmax, NULL), VBL_SUCCESS);
    vbl_bn_light* l = calloc(N, sizeof *l);
    for (size_t k = 0; k < N; ++k) {
        l[k].position = p[kept[k]];
        l[k].normal = vbl_v3(0, 0, 1);
        l[k].radius = VBL_BN_VSL_ALPHA_DEFAULT * rmax[k];
        l[k].diffuse = 1;
    }
    vbl_bn_light_set s;
    assert_int_equal(vbl_bn_light_set_init(&s, l, N, NULL, VBL_BN_VSL_ALPHA_DEFAULT), VBL_SUCCESS);
    double sum = 0.0, covered = 0.0;
    int samples = 0;
    for (int i = 0; i < 4000; ++i) {
        vbl_vec3 y = vbl_v3(0.15 + 0.7 * vbl_rng_uniform(&r), 0.15 + 0.7 * vbl_rng_uniform(&r), 0.0);
        size_t n = 0;
        double rho = vbl_bn_density_at(&s, y, &n);
        size_t brute = 0;
        for (size_t k = 0; k < N; ++k) {
            vbl_vec3 d = vbl_v3_sub(y, l[k].position);
            brute += vbl_v3_dot(d, d) <= l[k].radius * l[k].radius;
        }
        assert_int_equal(n, brute);
        assert_true(n > 0);
        sum += rho;
        covered += (double)n;
        ++samples;
    }
    printf("eq 8 mean density %.1f lights per unit area (N = %zu on the unit square); %.1f lights cover a point\n",
           sum / samples, N, covered / samples);
    assert_true(fabs(sum / samples / (double)N - 1.0) < 0.1);
    vbl_bn_light_set_free(&s);
    free(l);
    free(p);
}

static void test_blend_weight(void** state)
{
    (void)state;
    /* a rho = dist2 rho / (pdf cos) */
    assert_true(vbl_bn_virtual_light_weight(1.0, 1.0, 1.0, 40.0, 40, 80) == 0.0);
    assert_true(vbl_bn_virtual_light_weight(1.0, 1.0, 1.0, 80.0, 40, 80) == 1.0);
    assert_true(fabs(vbl_bn_virtual_light_weight(1.0, 1.0, 1.0, 60.0, 40, 80) - 0.5) < 1e-15);
    assert_true(fabs(vbl_bn_virtual_light_weight(4.0, 2.0, -0.5, 15.0, 40, 80) - 0.5) < 1e-15); /* |cos| */
    assert_true(vbl_bn_virtual_light_weight(1.0, 1.0, 1.0, 0.0, 40, 80) == 0.0); /* no light covers y */
    assert_true(vbl_bn_virtual_light_weight(1.0, 0.0, 1.0, 1.0, 40, 80) == 1.0); /* pdf 0: infinite footprint */
    assert_true(vbl_bn_virtual_light_weight(1.0, 1.0, 0.0, 1.0, 40, 80) == 1.0);
    assert_true(vbl_bn_virtual_light_weight(0.0, 0.0, 0.0, 1.0, 40, 80) == 1.0);
    assert_true(vbl_bn_virtual_light_weight(1.0, 1.0, 1.0, 50.0, 60, 60) == 0.0);
    assert_true(vbl_bn_virtual_light_weight(1.0, 1.0, 1.0, 70.0, 60, 60) == 1.0);
    /* monotone in the distance, never NaN */
    double prev = 0.0;
    for (int i = 0; i <= 100; ++i) {
        double w = vbl_bn_virtual_light_weight(0.02 * i, 3.0, 0.7, 1000.0, 40, 80);
        assert_true(w >= prev && w >= 0.0 && w <= 1.0);
        prev = w;
    }
    assert_true(fabs(vbl_bn_power_heuristic(1.0, 1.0) - 0.5) < 1e-15);
    assert_true(vbl_bn_power_heuristic(0.0, 0.0) == 0.0);
    assert_true(fabs(vbl_bn_power_heuristic(3.0, 4.0) + vbl_bn_power_heuristic(4.0, 3.0) - 1.0) < 1e-15);
    assert_true(vbl_bn_light_density(0.0, 2.0) == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pick_by_power),
        cmocka_unit_test(test_cone),
        cmocka_unit_test(test_density_and_containment),
        cmocka_unit_test(test_blend_weight),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
