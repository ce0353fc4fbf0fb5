/* Inverse-distance VRL marginal, VRL paper eqs (10)-(13): chi-square, normalisation,
 * agreement with eq (13) literally, parallel / crossing limits. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "sampling/sinh_marginal.h"
#include "sampling_check1d.h"

typedef struct sinh_case { double h, s, a, b; } sinh_case;
static double sinh_sample_cb(void* c, double xi, double* pdf)
{
    sinh_case* k = (sinh_case*)c;
    return vbl_sinh_marginal_sample(k->h, k->s, k->a, k->b, xi, pdf);
}
static double sinh_pdf_cb(void* c, double x)
{
    sinh_case* k = (sinh_case*)c;
    return vbl_sinh_marginal_pdf(k->h, k->s, k->a, k->b, x);
}

static const sinh_case kCases[] = {
    {0.5, 0.7, -2.0, 3.0},    /* skew, closest point inside */
    {0.3, 1.0, 1.0, 4.0},     /* perpendicular, closest point before */
    {0.2, 0.9, -9.0, -8.0},   /* far segment */
    {1e-5, 0.8, -1.0, 1.0},   /* nearly crossing */
    {0.0, 0.8, -1.0, 2.0},    /* crossing exactly: floored h */
    {0.5, 1e-4, -3.0, 2.0},   /* near parallel */
    {0.5, 1e-12, -3.0, 2.0},  /* numerically parallel */
    {0.5, 0.0, -3.0, 2.0},    /* exactly parallel: uniform */
    {1e-3, 0.05, -1.0, 1.0},  /* small angle, wide sinh range */
};
#define NCASES ((int)(sizeof kCases / sizeof kCases[0]))

static void test_sinh_chi2(void** state)
{
    (void)state;
    int ok = 1;
    for (int i = 0; i < NCASES; ++i) {
        sinh_case k = kCases[i];
        char label[80];
        snprintf(label, sizeof label, "sinh h=%g s=%g [%g,%g]", k.h, k.s, k.a, k.b);
        ok &= check1d(label, sinh_sample_cb, sinh_pdf_cb, &k, k.a, k.b, 32, 0, 100000, 500 + i, 2 * NCASES);
        if (k.h < 1e-4) continue; /* a floored spike fills one uniform bin */
        snprintf(label, sizeof label, "sinh h=%g s=%g [%g,%g] uniform bins", k.h, k.s, k.a, k.b);
        ok &= check1d(label, sinh_sample_cb, sinh_pdf_cb, &k, k.a, k.b, 20, 1, 100000, 600 + i, 2 * NCASES);
    }
    assert_true(ok);
}

/* Eqs (11)-(13) literally (valid for moderate sin theta and h). */
static void test_sinh_matches_paper(void** state)
{
    (void)state;
    const sinh_case k = kCases[0];
    double a0 = asinh(k.a * k.s / k.h), a1 = asinh(k.b * k.s / k.h);
    for (int i = 0; i <= 20; ++i) {
        double xi = i / 20.0, pdf;
        double ref = k.h * sinh(a0 + xi * (a1 - a0)) / k.s; /* eq 13 */
        double v = vbl_sinh_marginal_sample(k.h, k.s, k.a, k.b, xi, &pdf);
        assert_true(fabs(v - ref) < 1e-12 * (1.0 + fabs(ref)));
        double ref_pdf = k.s / ((a1 - a0) * sqrt(k.h * k.h + v * v * k.s * k.s)); /* eq 10 / eq 11 */
        assert_true(fabs(pdf - ref_pdf) < 1e-11 * ref_pdf);
        double cdf = (a0 - asinh(v * k.s / k.h)) / (a0 - a1); /* eq 12 */
        assert_true(fabs(cdf - xi) < 1e-12);
    }
}

static void test_sinh_limits(void** state)
{
    (void)state;
    /* Parallel: exactly uniform; near parallel: continuous limit. */
    for (int i = 0; i <= 10; ++i) {
        double xi = i / 10.0, pdf;
        double v = vbl_sinh_marginal_sample(0.5, 0.0, -3.0, 2.0, xi, &pdf);
        assert_true(fabs(v - (-3.0 + 5.0 * xi)) < 1e-14);
        assert_true(fabs(pdf - 0.2) < 1e-15);
        double v2 = vbl_sinh_marginal_sample(0.5, 1e-9, -3.0, 2.0, xi, &pdf);
        assert_true(fabs(v2 - v) < 1e-8 && fabs(pdf - 0.2) < 1e-8);
    }
    /* Extreme xi, degenerate geometry: finite and in the domain. */
    const double xs[] = {0.0, 1e-300, 0.5, nextafter(1.0, 0.0), 1.0};
    for (int i = 0; i < NCASES; ++i) {
        for (size_t j = 0; j < sizeof xs / sizeof xs[0]; ++j) {
            double pdf;
            double v = vbl_sinh_marginal_sample(kCases[i].h, kCases[i].s, kCases[i].a, kCases[i].b, xs[j], &pdf);
            assert_true(isfinite(v) && v >= kCases[i].a && v <= kCases[i].b);
            assert_true(isfinite(pdf) && pdf > 0.0);
        }
    }
    double pdf = 1.0;
    double v = vbl_sinh_marginal_sample(0.5, 0.5, 1.0, 1.0, 0.3, &pdf); /* zero length */
    assert_true(v == 1.0 && pdf == 0.0);
    v = vbl_sinh_marginal_sample(0.0, 0.5, 0.0, 0.0, 0.3, &pdf);
    assert_true(v == 0.0 && pdf == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sinh_chi2),
        cmocka_unit_test(test_sinh_matches_paper),
        cmocka_unit_test(test_sinh_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
