/* Piecewise-linear density (VRL section 4.2): chi-square for several vertex shapes including
 * zeros, exact mass, uniform fallback, zero-width segments, extreme xi. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "sampling/piecewise_linear.h"
#include "sampling_check1d.h"

static double pwl_sample_cb(void* c, double xi, double* pdf) { return vbl_pwl_sample((const vbl_pwl*)c, xi, pdf); }
static double pwl_pdf_cb(void* c, double x) { return vbl_pwl_pdf((const vbl_pwl*)c, x); }

typedef struct shape { const char* name; int n; double x[16], f[16]; } shape;

static const shape kShapes[] = {
    {"ramp up", 2, {0.0, 1.0}, {0.0, 3.0}},
    {"ramp down", 2, {-1.0, 2.0}, {5.0, 0.0}},
    {"peak", 10, {0, .1, .3, .6, 1, 1.1, 1.5, 2, 2.5, 3}, {1, 2, 4, 9, 30, 12, 5, 2, 1, .5}},
    {"zeros at ends", 5, {0, 1, 2, 3, 4}, {0, 1, 2, 1, 0}},
    {"two humps, zero gap", 7, {0, 1, 2, 3, 4, 5, 6}, {0, 2, 0, 0, 0, 3, 0}},
    {"single nonzero vertex", 4, {0, 1, 2, 3}, {0, 0, 7, 0}},
    {"zero-width segment", 5, {0, 1, 1, 2, 3}, {1, 2, 6, 1, 1}},
    {"16 vertices", 16, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15},
     {1, 3, 1, 4, 1, 5, 9, 2, 6, 5, 3, 5, 8, 9, 7, 9}},
    {"wide dynamic range", 4, {0, 1e-3, 1, 2}, {1e-12, 1e6, 1e-9, 1e-12}},
    {"all zero (uniform fallback)", 3, {0, 1, 3}, {0, 0, 0}},
    {"denormal (uniform fallback)", 3, {0, 1, 3}, {1e-310, 0, 1e-310}},
    {"negative/NaN read as 0", 4, {0, 1, 2, 3}, {-1, 2, NAN, 1}},
};
#define NSHAPES ((int)(sizeof kShapes / sizeof kShapes[0]))

static void test_pwl_chi2(void** state)
{
    (void)state;
    int ok = 1;
    for (int i = 0; i < NSHAPES; ++i) {
        vbl_pwl p;
        assert_true(vbl_pwl_init(&p, kShapes[i].x, kShapes[i].f, kShapes[i].n));
        double a = kShapes[i].x[0], b = kShapes[i].x[kShapes[i].n - 1];
        char label[80];
        snprintf(label, sizeof label, "pwl %s", kShapes[i].name);
        ok &= check1d(label, pwl_sample_cb, pwl_pdf_cb, &p, a, b, 24, 1, 100000, 700 + i, NSHAPES);
        /* Exact mass helper agrees with quadrature of the pdf. */
        check1d_pdf_ctx pc = {pwl_pdf_cb, &p};
        double m = vbl_pwl_mass(&p, a + 0.3 * (b - a), a + 0.7 * (b - a));
        double q = vbl_quad_adaptive(check1d_pdf_thunk, &pc, a + 0.3 * (b - a), a + 0.7 * (b - a), 1e-14, 1e-12);
        assert_true(fabs(m - q) < 1e-9);
    }
    assert_true(ok);
    /* Uniform fallbacks report the uniform density. */
    vbl_pwl p;
    vbl_pwl_init(&p, kShapes[9].x, kShapes[9].f, 3);
    assert_true(p.uniform && fabs(vbl_pwl_pdf(&p, 2.0) - 1.0 / 3.0) < 1e-15);
}

static void test_pwl_zero_regions_never_sampled(void** state)
{
    (void)state;
    vbl_pwl p;
    vbl_pwl_init(&p, kShapes[4].x, kShapes[4].f, kShapes[4].n); /* zero on [2, 4] */
    vbl_rng rng = vbl_rng_make(9, 9, 9);
    for (int i = 0; i < 100000; ++i) {
        double pdf, x = vbl_pwl_sample(&p, vbl_rng_uniform(&rng), &pdf);
        assert_true(pdf > 0.0);
        assert_false(x > 2.0 && x < 4.0);
    }
    const double xs[] = {0.0, 1e-300, nextafter(1.0, 0.0), 1.0};
    for (int i = 0; i < NSHAPES; ++i) {
        vbl_pwl q;
        vbl_pwl_init(&q, kShapes[i].x, kShapes[i].f, kShapes[i].n);
        for (size_t j = 0; j < sizeof xs / sizeof xs[0]; ++j) {
            double pdf, x = vbl_pwl_sample(&q, xs[j], &pdf);
            assert_true(isfinite(x) && x >= q.x[0] && x <= q.x[q.count - 1] && isfinite(pdf) && pdf >= 0.0);
        }
    }
}

static void test_pwl_invalid(void** state)
{
    (void)state;
    vbl_pwl p;
    double x[3] = {0, 2, 1}, f[3] = {1, 1, 1};
    assert_false(vbl_pwl_init(&p, x, f, 3));   /* decreasing */
    assert_false(vbl_pwl_init(&p, x, f, 1));   /* too few */
    assert_false(vbl_pwl_init(&p, x, f, 17));  /* too many */
    double y[2] = {1, 1};
    assert_false(vbl_pwl_init(&p, y, f, 2));   /* zero-width domain */
    double pdf = 1.0;
    vbl_pwl_sample(&p, 0.5, &pdf);
    assert_true(pdf == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pwl_chi2),
        cmocka_unit_test(test_pwl_zero_regions_never_sampled),
        cmocka_unit_test(test_pwl_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
