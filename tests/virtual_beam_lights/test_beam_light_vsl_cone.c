/* VSL cone (Novak et al. 2012 (VBL), section 3.1, figure 5 right): geometry, least rotation,
 * exact single-lobe maximum and the product maximum against brute force, uniform cone sampling. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "sampling/phase_hg.h"
#include "sampling/vsl_cone.h"

static vbl_vec3 rand_dir(vbl_rng* r)
{
    double z = 1.0 - 2.0 * vbl_rng_uniform(r), ph = 2.0 * VBL_PI * vbl_rng_uniform(r);
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return vbl_v3(s * cos(ph), s * sin(ph), z);
}

static void test_cone_geometry(void** state)
{
    (void)state;
    vbl_vsl_cone c;
    assert_true(vbl_vsl_cone_init(&c, vbl_v3(0, 0, 2), 1.0, vbl_v3(1, 0, 0)));
    assert_true(fabs(c.half_angle - VBL_PI / 6) < 1e-14);
    assert_true(fabs(c.solid_angle - 2 * VBL_PI * (1 - cos(VBL_PI / 6))) < 1e-14);
    assert_true(fabs(c.geometry - c.solid_angle / VBL_PI) < 1e-14); /* Omega / (pi R^2), R = 1 */
    /* inside the sphere: hemisphere, geometry 2 / R^2 */
    assert_true(vbl_vsl_cone_init(&c, vbl_v3(0, 0.5, 0), 1.0, vbl_v3(1, 0, 0)));
    assert_true(fabs(c.half_angle - VBL_PI / 2) < 1e-15 && fabs(c.geometry - 2.0) < 1e-15);
    /* w == 0 takes the fallback axis; R == 0 && w == 0 has no direction */
    assert_true(vbl_vsl_cone_init(&c, vbl_v3(0, 0, 0), 0.1, vbl_v3(0, 2, 0)) && c.axis.y == 1.0);
    assert_false(vbl_vsl_cone_init(&c, vbl_v3(0, 0, 0), 0.0, vbl_v3(0, 1, 0)));
    /* thin cone: 1 - cos without cancellation */
    assert_true(vbl_vsl_cone_init(&c, vbl_v3(1e3, 0, 0), 1e-9, vbl_v3(0, 1, 0)));
    assert_true(fabs(c.one_minus_cos / (0.5e-24) - 1.0) < 1e-12);
    assert_true(fabs(c.geometry * 1e6 - 1.0) < 1e-12);
    /* R == 0: geometry 1 / w^2, no solid angle */
    assert_true(vbl_vsl_cone_init(&c, vbl_v3(0, 3, 0), 0.0, vbl_v3(0, 1, 0)));
    assert_true(c.solid_angle == 0.0 && fabs(c.geometry - 1.0 / 9.0) < 1e-15);
}

static void test_cone_closest(void** state)
{
    (void)state;
    vbl_rng rng = vbl_rng_make(7, 0, 0);
    for (int i = 0; i < 2000; ++i) {
        vbl_vsl_cone c;
        vbl_vec3 d = vbl_v3_scale(rand_dir(&rng), 0.1 + 3 * vbl_rng_uniform(&rng));
        vbl_vsl_cone_init(&c, d, vbl_rng_uniform(&rng), vbl_v3(0, 0, 1));
        vbl_vec3 t = rand_dir(&rng);
        vbl_vec3 w = vbl_vsl_cone_closest(&c, t);
        assert_true(fabs(vbl_v3_length(w) - 1.0) < 1e-12);
        double aw = atan2(vbl_v3_length(vbl_v3_cross(c.axis, w)), vbl_v3_dot(c.axis, w));
        assert_true(aw <= c.half_angle + 1e-12);
        double best = atan2(vbl_v3_length(vbl_v3_cross(t, w)), vbl_v3_dot(t, w));
        /* no random in-cone direction is closer to the target */
        for (int k = 0; k < 50; ++k) {
            vbl_vec3 x = vbl_vsl_cone_sample(&c, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), NULL);
            assert_true(atan2(vbl_v3_length(vbl_v3_cross(t, x)), vbl_v3_dot(t, x)) >= best - 1e-12);
        }
    }
}

static void test_cone_hg_max_brute_force(void** state)
{
    (void)state;
    vbl_rng rng = vbl_rng_make(8, 0, 0);
    const double gs[] = {0.0, 0.3, 0.9, -0.7, 0.999, -0.999};
    int product_close = 0, product_total = 0;
    double worst = 1.0;
    for (int i = 0; i < 300; ++i) {
        vbl_vsl_cone c;
        vbl_vec3 d = vbl_v3_scale(rand_dir(&rng), 0.2 + 2 * vbl_rng_uniform(&rng));
        vbl_vsl_cone_init(&c, d, 0.8 * vbl_rng_uniform(&rng), vbl_v3(0, 0, 1));
        double g1 = gs[i % 6], g2 = gs[(i / 6) % 6];
        vbl_vec3 m1 = rand_dir(&rng), m2 = rand_dir(&rng), arg;
        double f1 = vbl_vsl_cone_hg_max(&c, g1, m1, &arg);
        double fp = vbl_vsl_cone_hg_product_max(&c, g1, m1, g2, m2, NULL);
        double b1 = 0.0, bp = 0.0;
        for (int k = 0; k < 4000; ++k) {
            vbl_vec3 x = vbl_vsl_cone_sample(&c, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), NULL);
            double a = vbl_hg_eval(g1, vbl_v3_dot(m1, x));
            b1 = fmax(b1, a);
            bp = fmax(bp, a * vbl_hg_eval(g2, vbl_v3_dot(m2, x)));
        }
        assert_true(atan2(vbl_v3_length(vbl_v3_cross(c.axis, arg)), vbl_v3_dot(c.axis, arg)) <= c.half_angle + 1e-12);
        assert_true(f1 >= b1 * (1.0 - 1e-9)); /* exact maximum: never below a sampled value */
        assert_true(f1 <= vbl_hg_eval(g1, g1 >= 0 ? 1.0 : -1.0) * (1 + 1e-12));
        assert_true(fp > 0.0 && isfinite(fp));
        ++product_total;
        product_close += fp >= 0.9 * bp;
        worst = fmin(worst, fp / bp);
    }
    printf("product max >= 0.9 x brute force in %d / %d cones (worst ratio %.3f)\n", product_close, product_total, worst);
    assert_true(product_close >= 0.95 * product_total);
}

static void test_cone_sampling_chi2(void** state)
{
    (void)state;
    /* 1 - cos(theta) must be uniform on [0, 1 - cos alpha] and every sample in the cone */
    const double rs[] = {1e-6, 0.3, 0.99, 5.0};
    int ok = 1;
    for (int j = 0; j < 4; ++j) {
        vbl_vsl_cone c;
        vbl_vsl_cone_init(&c, vbl_v3(0.3, -1, 0.2), rs[j], vbl_v3(0, 0, 1));
        enum { NB = 10, NS = 20000 };
        double obs[NB] = {0}, ex[NB];
        vbl_rng rng = vbl_rng_make(9, (uint64_t)j, 0);
        for (int s = 0; s < NS; ++s) {
            double pdf;
            vbl_vec3 x = vbl_vsl_cone_sample(&c, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &pdf);
            assert_true(fabs(pdf * c.solid_angle - 1.0) < 1e-12);
            vbl_vec3 cr = vbl_v3_cross(c.axis, x);
            double s2 = vbl_v3_dot(cr, cr), ct = vbl_v3_dot(c.axis, x);
            double omc = ct > 0 ? s2 / (1 + ct) : 1 - ct;
            int b = (int)(omc / c.one_minus_cos * NB);
            obs[b < 0 ? 0 : (b >= NB ? NB - 1 : b)] += 1;
            ok &= vbl_vsl_cone_pdf(&c, x) > 0.0 || c.half_angle < 1e-5;
        }
        for (int b = 0; b < NB; ++b) ex[b] = NS / (double)NB;
        ok &= vbl_chi2_check("cone 1-cos uniform", obs, ex, NB, 0.01, 4);
    }
    assert_true(ok);
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cone_geometry),
        cmocka_unit_test(test_cone_closest),
        cmocka_unit_test(test_cone_hg_max_brute_force),
        cmocka_unit_test(test_cone_sampling_chi2),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
