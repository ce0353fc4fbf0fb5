/* The VSL gather kernel over the cone (surface_cone_kernel.h, VBL eq 9): its randomly jittered
 * quadrature is unbiased (mean within 4 standard errors of a brute-force 2D quadrature), R == 0 is
 * the singular integrand exactly, R -> 0 converges to it, and it stays finite and non-negative at
 * w = 0, w << R, grazing angles and g = +-0.999. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "surface_test_util.h"
#include "transport/surface_cone_kernel.h"

typedef struct pair_case {
    const char* label;
    vbl_surface_lobe a, b;
} pair_case;

static vbl_material g_mat[3];

/* receiver at the origin (normal +z); sender lobes: a phase (VRL point) or a surface VSL. */
static pair_case make_case(int k)
{
    vbl_vec3 n = vbl_v3(0, 0, 1), wo = vbl_v3_normalize(vbl_v3(0.3, -0.2, 1.0));
    vbl_vec3 ny = vbl_v3_normalize(vbl_v3(0.3, 0.1, -1.0)), wiy = vbl_v3_normalize(vbl_v3(0.5, 0.0, -1.0));
    pair_case c;
    switch (k) {
    case 0:
        c.label = "receiver phong60 x phase g=0.7";
        c.a = vbl_surface_lobe_receiver(&g_mat[1], n, wo);
        c.b = vbl_surface_lobe_phase(0.7, vbl_v3_normalize(vbl_v3(0.2, 0.1, -1.0)));
        break;
    case 1:
        c.label = "receiver ggx0.3 x sender lambert";
        c.a = vbl_surface_lobe_receiver(&g_mat[2], n, wo);
        c.b = vbl_surface_lobe_sender(&g_mat[0], ny, wiy);
        break;
    case 2:
        c.label = "receiver lambert x sender phong60";
        c.a = vbl_surface_lobe_receiver(&g_mat[0], n, wo);
        c.b = vbl_surface_lobe_sender(&g_mat[1], ny, wiy);
        break;
    default:
        c.label = "camera phase g=-0.5 x sender ggx0.3";
        c.a = vbl_surface_lobe_phase(-0.5, vbl_v3_normalize(vbl_v3(1.0, 0.0, 0.3)));
        c.b = vbl_surface_lobe_sender(&g_mat[2], ny, wiy);
        break;
    }
    return c;
}

static void setup_materials(void)
{
    for (int i = 0; i < 3; ++i) g_mat[i] = st_material(i);
}

/* sender centres: a thin cone (w = 1, R = 0.3) and the hemisphere (w = 0.1 < R = 0.3) */
static const vbl_vec3 kCentre[2] = {{0.2, -0.1, 0.98}, {0.02, 0.01, 0.098}};

static void test_kernel_unbiased(void** state)
{
    (void)state;
    setup_materials();
    int ok = 1;
    for (int k = 0; k < 4; ++k)
        for (int gi = 0; gi < 2; ++gi) {
            pair_case c = make_case(k);
            vbl_vec3 x = vbl_v3(0, 0, 0), y = kCentre[gi];
            double radius = 0.3;
            double ref = st_cone_reference(&c.a, &c.b, x, y, radius);
            vbl_mean_acc acc = {0, 0, 0};
            vbl_rng rng = vbl_rng_make(77, (uint64_t)k, (uint64_t)gi);
            for (int i = 0; i < 4000; ++i) {
                double j[3] = {vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng)};
                vbl_mean_add(&acc, st_mean3(vbl_surface_cone_kernel(&c.a, &c.b, x, y, radius, 4, j)));
            }
            char label[128];
            snprintf(label, sizeof label, "%s %s", c.label, gi ? "hemisphere" : "thin cone");
            ok &= vbl_mean_check(label, &acc, ref, 4.0, 1e-6 * fabs(ref));
            assert_true(ref > 0.0);
        }
    assert_true(ok);
}

static void test_kernel_r0_and_limit(void** state)
{
    (void)state;
    setup_materials();
    for (int k = 0; k < 4; ++k) {
        pair_case c = make_case(k);
        vbl_vec3 x = vbl_v3(0, 0, 0), y = vbl_v3(0.4, -0.2, 1.5);
        const double j[3] = {0.25, 0.5, 0.75};
        vbl_vec3 omega = vbl_v3_normalize(vbl_v3_sub(x, y));
        double w2 = vbl_v3_dot(vbl_v3_sub(x, y), vbl_v3_sub(x, y));
        vbl_vec3 exact = vbl_v3_scale(vbl_v3_mul(vbl_surface_lobe_eval(&c.a, omega), vbl_surface_lobe_eval(&c.b, omega)),
                                      1.0 / w2);
        vbl_vec3 k0 = vbl_surface_cone_kernel(&c.a, &c.b, x, y, 0.0, 8, j);
        assert_true(fabs(k0.x - exact.x) <= 1e-12 * exact.x && fabs(k0.z - exact.z) <= 1e-12 * exact.z);
        double prev = INFINITY;
        printf("     %s: R -> 0 relative error:", c.label);
        for (int r = 0; r < 4; ++r) {
            double radius = 0.2 * pow(0.1, r);
            double kr = st_mean3(vbl_surface_cone_kernel(&c.a, &c.b, x, y, radius, 64, j));
            double err = fabs(kr / st_mean3(exact) - 1.0);
            printf(" R=%g %.2e", radius, err);
            if (r >= 2) assert_true(err < prev || err < 1e-4); /* falls as R -> 0 */
            prev = err;
        }
        printf("\n");
        assert_true(prev < 1e-3);
    }
}

static void test_kernel_extremes(void** state)
{
    (void)state;
    setup_materials();
    const double j[3] = {0.1, 0.2, 0.3};
    for (int k = 0; k < 4; ++k) {
        pair_case c = make_case(k);
        vbl_vec3 x = vbl_v3(0, 0, 0);
        const vbl_vec3 ys[4] = {{0, 0, 0}, {0, 0, 1e-12}, {1e-9, 0, 0}, {3, 0, 1e-9}};
        for (int i = 0; i < 4; ++i)
            for (int r = 0; r < 3; ++r) {
                double radius = r == 0 ? 0.0 : (r == 1 ? 1e-3 : 0.5);
                vbl_vec3 v = vbl_surface_cone_kernel(&c.a, &c.b, x, ys[i], radius, 16, j);
                assert_true(st_finite3(v) && st_nonneg3(v));
            }
    }
    /* extreme anisotropy */
    vbl_surface_lobe a = vbl_surface_lobe_receiver(&g_mat[1], vbl_v3(0, 0, 1), vbl_v3_normalize(vbl_v3(1, 0, 1e-6)));
    for (int s = -1; s <= 1; s += 2) {
        vbl_surface_lobe b = vbl_surface_lobe_phase(0.999 * s, vbl_v3(1, 0, 0));
        for (int r = 0; r < 3; ++r) {
            vbl_vec3 v = vbl_surface_cone_kernel(&a, &b, vbl_v3(0, 0, 0), vbl_v3(-1, 0, 1e-3), r * 0.05, 16, j);
            assert_true(st_finite3(v) && st_nonneg3(v));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kernel_unbiased),
        cmocka_unit_test(test_kernel_r0_and_limit),
        cmocka_unit_test(test_kernel_extremes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
