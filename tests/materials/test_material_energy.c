/* Energy and symmetry of the materials: directional albedo int f cos dw (white furnace) by
 * quadrature with the horizon handled exactly, reciprocity, and the pdf's total mass. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "core/rng.h"
#include "material_test_util.h"

static vbl_vec3 albedo(const vbl_material* m, double theta_deg)
{
    vbl_vec3 n = mt_normal(), wo = mt_wo(n, theta_deg, 0.7);
    mt_ctx c = {m, n, wo, 1.0};
    mt_frame f = mt_frame_make(mt_axis(m, n, wo), n);
    return mt_hemisphere_integral(&f, mt_fcos_fn, &c);
}

static const double kTheta[] = {0.0, 30.0, 60.0, 80.0, 85.0, 89.0};
#define NTHETA ((int)(sizeof kTheta / sizeof kTheta[0]))

static void test_lambert_albedo_is_kd(void** state)
{
    (void)state;
    vbl_material m = mt_material(VBL_MATERIAL_LAMBERT, 0.0, 0.0, 0.0, 0.0);
    m.albedo = vbl_v3(0.2, 0.5, 1.0);
    for (int i = 0; i < NTHETA; ++i) {
        vbl_vec3 a = albedo(&m, kTheta[i]);
        assert_true(fabs(a.x - 0.2) < 1e-9 && fabs(a.y - 0.5) < 1e-9 && fabs(a.z - 1.0) < 1e-9);
    }
}

/* Normalized Phong: albedo = kd + ks exactly at normal incidence (any exponent), never above it. */
static void test_phong_albedo(void** state)
{
    (void)state;
    static const double exps[] = {0.0, 1.0, 10.0, 60.0, 100.0, 1000.0, 1e5};
    static const double kd[] = {0.0, 0.5, 0.2}, ks[] = {1.0, 0.5, 0.8};
    double worst = 0.0;
    for (size_t e = 0; e < sizeof exps / sizeof exps[0]; ++e) {
        for (int k = 0; k < 3; ++k) {
            vbl_material m = mt_material(VBL_MATERIAL_PHONG, kd[k], ks[k], exps[e], 0.0);
            printf("phong n=%-6g kd=%.1f ks=%.1f albedo:", exps[e], kd[k], ks[k]);
            for (int i = 0; i < NTHETA; ++i) {
                double a = albedo(&m, kTheta[i]).x;
                printf(" %g:%.6f", kTheta[i], a);
                if (i == 0) assert_true(fabs(a - (kd[k] + ks[k])) < 1e-7);
                assert_true(a <= kd[k] + ks[k] + 1e-7);
                worst = fmax(worst, a);
            }
            printf("\n");
        }
    }
    printf("phong: largest directional albedo %.9f (kd + ks = 1)\n", worst);
}

static double schlick1(double f0, double c) { return f0 + (1.0 - f0) * pow(1.0 - c, 5.0); }

/* GGX with F0 = 1, kd = 0 loses energy only through single-scattering shadowing/masking; with
 * kd = 1 the Fresnel-weighted diffuse lobe must keep the total <= 1: the design invariant is
 * (1 - A_s) / (1 - F(cos_o)) >= 20/21 (the diffuse albedo is (20/21) kd (1 - F(cos_o))). */
static void test_ggx_albedo(void** state)
{
    (void)state;
    static const double rough[] = {0.001, 0.05, 0.3, 1.0};
    for (size_t r = 0; r < sizeof rough / sizeof rough[0]; ++r) {
        vbl_material m = mt_material(VBL_MATERIAL_GGX, 0.0, 1.0, 0.0, rough[r]);
        printf("ggx F0=1 kd=0 a=%-5g albedo:", rough[r]);
        for (int i = 0; i < NTHETA; ++i) {
            double a = albedo(&m, kTheta[i]).x;
            printf(" %g:%.5f", kTheta[i], a);
            assert_true(a <= 1.0 + 1e-6);
            if (rough[r] <= 0.05 && kTheta[i] <= 60.0) assert_true(a > 0.99); /* near-mirror keeps energy */
        }
        printf("\n");
    }
    static const double f0[] = {0.0, 0.04, 0.5};
    double worst = 0.0, margin = 1e9;
    for (size_t r = 0; r < sizeof rough / sizeof rough[0]; ++r) {
        for (int k = 0; k < 3; ++k) {
            vbl_material m = mt_material(VBL_MATERIAL_GGX, 1.0, f0[k], 0.0, rough[r]);
            vbl_material ms = mt_material(VBL_MATERIAL_GGX, 0.0, f0[k], 0.0, rough[r]);
            assert_true(vbl_material_validate(&m, NULL, 0));
            printf("ggx F0=%-4g kd=1 a=%-5g albedo:", f0[k], rough[r]);
            for (int i = 0; i < NTHETA; ++i) {
                double a = albedo(&m, kTheta[i]).x, as = albedo(&ms, kTheta[i]).x;
                double fo = schlick1(f0[k], cos(kTheta[i] * VBL_PI / 180.0));
                printf(" %g:%.5f", kTheta[i], a);
                assert_true(a <= 1.0 + 1e-6);
                worst = fmax(worst, a);
                if (fo < 0.999) margin = fmin(margin, (1.0 - as) / (1.0 - fo));
                /* the diffuse part has albedo (20/21) (1 - F(cos_o)) exactly */
                assert_true(fabs((a - as) - 20.0 / 21.0 * (1.0 - fo)) < 1e-7);
            }
            printf("\n");
        }
    }
    printf("ggx: largest albedo with kd = 1: %.6f; min (1 - A_s) / (1 - F(cos_o)) = %.6f (must be >= 20/21)\n",
           worst, margin);
    assert_true(margin >= 20.0 / 21.0);
}

static void test_reciprocity(void** state)
{
    (void)state;
    vbl_material ms[] = {mt_material(VBL_MATERIAL_LAMBERT, 0.7, 0.0, 0.0, 0.0),
                         mt_material(VBL_MATERIAL_PHONG, 0.3, 0.6, 60.0, 0.0),
                         mt_material(VBL_MATERIAL_PHONG, 0.1, 0.9, 1000.0, 0.0),
                         mt_material(VBL_MATERIAL_GGX, 0.3, 0.5, 0.0, 0.05),
                         mt_material(VBL_MATERIAL_GGX, 0.3, 0.04, 0.0, 1.0)};
    vbl_vec3 n = mt_normal();
    double worst = 0.0;
    for (size_t k = 0; k < sizeof ms / sizeof ms[0]; ++k) {
        vbl_rng rng = vbl_rng_make(11, 1, k);
        for (int i = 0; i < 20000; ++i) {
            vbl_vec3 wo = mt_wo(n, 90.0 * vbl_rng_uniform(&rng), 2.0 * VBL_PI * vbl_rng_uniform(&rng));
            vbl_vec3 wi = mt_wo(n, 90.0 * vbl_rng_uniform(&rng), 2.0 * VBL_PI * vbl_rng_uniform(&rng));
            if (i % 4 == 0) /* near the mirror direction, where the lobes are large */
                wi = vbl_v3_normalize(vbl_v3_add(vbl_v3_sub(vbl_v3_scale(n, 2.0 * vbl_v3_dot(n, wo)), wo),
                                                 vbl_v3_scale(wi, 0.02)));
            vbl_vec3 a = vbl_material_eval(&ms[k], n, wo, wi), b = vbl_material_eval(&ms[k], n, wi, wo);
            double d = fabs(a.x - b.x) / fmax(1e-300, fmax(a.x, b.x));
            if (a.x > 0.0 || b.x > 0.0) worst = fmax(worst, d);
            assert_true(isfinite(a.x) && isfinite(b.x));
        }
    }
    printf("reciprocity: worst relative |f(wo,wi) - f(wi,wo)| = %.3g\n", worst);
    assert_true(worst < 1e-12);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lambert_albedo_is_kd),
        cmocka_unit_test(test_phong_albedo),
        cmocka_unit_test(test_ggx_albedo),
        cmocka_unit_test(test_reciprocity),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
