/* Progressive radius reduction (Novak et al. 2012 (VBL), section 4.1, eq. 11): the product form,
 * the recurrence, monotone decrease, the asymptotic exponent alpha - 1 of R^d, and the default R_0. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "transport/common/radius_schedule.h"

static void test_radius_product_and_recurrence(void** state)
{
    (void)state;
    const double alphas[] = {0.1, 0.5, 0.7, 0.99};
    for (int a = 0; a < 4; ++a)
        for (int dim = 1; dim <= 2; ++dim) {
            double alpha = alphas[a], r0 = 0.37, prod = 1.0, r = r0;
            assert_true(vbl_radius_at_pass(r0, alpha, dim, 0) == r0);
            for (uint64_t p = 1; p <= 5000; ++p) {
                /* eq 11: R_p^d = R_0^d (prod_{k=1..p} (k + alpha) / k) / (p + 1) */
                prod *= (p + alpha) / (double)p;
                double expected = r0 * pow(prod / (p + 1.0), 1.0 / dim);
                double closed = vbl_radius_at_pass(r0, alpha, dim, p);
                double prev = r;
                r = vbl_radius_next(r, alpha, dim, p - 1);
                assert_true(fabs(closed - expected) <= 1e-10 * expected);
                assert_true(fabs(r - expected) <= 1e-10 * expected);
                assert_true(closed < prev); /* strictly decreasing */
            }
        }
}

static void test_radius_asymptotic_exponent(void** state)
{
    (void)state;
    /* log-log slope of R^d over passes -> alpha - 1; bias exponent 2 (alpha - 1) / d */
    for (int dim = 1; dim <= 2; ++dim)
        for (double alpha = 0.2; alpha < 1.0; alpha += 0.25) {
            double p1 = 1e5, p2 = 1e6;
            double slope = dim * (log(vbl_radius_at_pass(1.0, alpha, dim, (uint64_t)p2)) -
                                  log(vbl_radius_at_pass(1.0, alpha, dim, (uint64_t)p1))) /
                           log(p2 / p1);
            printf("dim %d alpha %.2f: slope of R^d %.5f (expected %.5f), bias exponent %.3f, rmse exponent %.3f\n", dim,
                   alpha, slope, alpha - 1.0, vbl_radius_bias_exponent(alpha, dim), vbl_radius_rmse_exponent(alpha, dim));
            assert_true(fabs(slope - (alpha - 1.0)) < 1e-4);
            assert_true(fabs(vbl_radius_bias_exponent(alpha, dim) - 2.0 * slope / dim) < 1e-3);
            assert_true(vbl_radius_rmse_exponent(alpha, dim) < 0.0);
        }
}

static void test_radius_invalid_and_default_r0(void** state)
{
    (void)state;
    assert_true(vbl_radius_at_pass(1.0, 0.0, 2, 3) == 0.0);
    assert_true(vbl_radius_at_pass(1.0, 0.7, 3, 3) == 0.0);
    assert_true(vbl_radius_at_pass(-1.0, 0.7, 2, 3) == 0.0);
    assert_true(vbl_radius_at_pass(1.0, 1.0, 2, 1000) == 1.0); /* alpha = 1: no reduction */
    vbl_vec3 lo = vbl_v3(0, 0, 0), hi = vbl_v3(2, 2, 2);
    /* V = 8, L = 800: spacing sqrt(0.01) = 0.1 */
    assert_true(fabs(vbl_radius_default_r0(lo, hi, 800.0, 0.0) - 0.1) < 1e-15);
    assert_true(fabs(vbl_radius_default_r0(lo, hi, 800.0, 2.0) - 0.2) < 1e-15);
    double diag = sqrt(12.0);
    assert_true(fabs(vbl_radius_default_r0(lo, hi, 0.0, 1.0) - 0.01 * diag) < 1e-15);    /* no VRLs */
    assert_true(fabs(vbl_radius_default_r0(lo, hi, 1e-9, 1.0) - 0.1 * diag) < 1e-15);    /* clamped up */
    assert_true(fabs(vbl_radius_default_r0(lo, hi, 1e30, 1.0) - 1e-4 * diag) < 1e-18);  /* clamped down */
    assert_true(vbl_radius_default_r0(lo, lo, 10.0, 1.0) == 0.0);
    assert_true(vbl_radius_default_r0(hi, lo, 10.0, 1.0) == 0.0);
    assert_true(vbl_radius_default_r0(lo, vbl_v3(2, 2, 0), 10.0, 1.0) > 0.0); /* flat box */
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_radius_product_and_recurrence),
        cmocka_unit_test(test_radius_asymptotic_exponent),
        cmocka_unit_test(test_radius_invalid_and_default_r0),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
