/* Truncated Cauchy (VRL eq 14) and equiangular sampling: chi-square, normalisation,
 * consistency, degenerate inputs (point on the line, zero-length segments, extreme xi). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "sampling/cauchy.h"
#include "sampling/equiangular.h"
#include "sampling_check1d.h"

typedef struct cauchy_case { double h, a, b; } cauchy_case;
static double cauchy_sample_cb(void* c, double xi, double* pdf)
{
    cauchy_case* k = (cauchy_case*)c;
    return vbl_cauchy_sample(k->h, k->a, k->b, xi, pdf);
}
static double cauchy_pdf_cb(void* c, double x)
{
    cauchy_case* k = (cauchy_case*)c;
    return vbl_cauchy_pdf(k->h, k->a, k->b, x);
}

static const cauchy_case kCauchy[] = {
    {0.5, -2.0, 3.0},   /* closest point inside */
    {1.0, 2.0, 10.0},   /* closest point before the interval */
    {0.2, -9.0, -8.5},  /* far, short interval */
    {1e-4, -1.0, 1.0},  /* near-singular */
    {0.0, -1.0, 2.0},   /* point on the line: floored h */
    {0.0, 0.5, 2.0},    /* point on the line, outside the interval */
    {3.0, -0.1, 0.1},   /* nearly uniform */
};
#define NCAUCHY ((int)(sizeof kCauchy / sizeof kCauchy[0]))

static void test_cauchy_chi2(void** state)
{
    (void)state;
    int ok = 1;
    for (int i = 0; i < NCAUCHY; ++i) {
        cauchy_case k = kCauchy[i];
        char label[80];
        snprintf(label, sizeof label, "cauchy h=%g [%g,%g]", k.h, k.a, k.b);
        ok &= check1d(label, cauchy_sample_cb, cauchy_pdf_cb, &k, k.a, k.b, 32, 0, 100000, 100 + i, 2 * NCAUCHY);
        if (k.h < 1e-4) continue; /* the floored spike fills one uniform bin */
        snprintf(label, sizeof label, "cauchy h=%g [%g,%g] uniform bins", k.h, k.a, k.b);
        ok &= check1d(label, cauchy_sample_cb, cauchy_pdf_cb, &k, k.a, k.b, 20, 1, 100000, 200 + i, 2 * NCAUCHY);
    }
    assert_true(ok);
}

/* Eq (14) literally: uhat = h tan(lerp(atan(u0/h), atan(u1/h), xi)). */
static void test_cauchy_matches_eq14(void** state)
{
    (void)state;
    double h = 0.7, a = -1.3, b = 2.9;
    for (int i = 0; i <= 20; ++i) {
        double xi = i / 20.0;
        double b0 = atan(a / h), b1 = atan(b / h);
        double ref = h * tan(b0 + xi * (b1 - b0));
        double pdf;
        double x = vbl_cauchy_sample(h, a, b, xi, &pdf);
        assert_true(fabs(x - ref) < 1e-12);
        assert_true(fabs(pdf - h / ((b1 - b0) * (h * h + x * x))) < 1e-12 * pdf);
    }
}

typedef struct eq_case { vbl_vec3 o, d, p; double t0, t1; } eq_case;
static double eq_sample_cb(void* c, double xi, double* pdf)
{
    eq_case* k = (eq_case*)c;
    return vbl_equiangular_sample(k->o, k->d, k->t0, k->t1, k->p, xi, pdf);
}
static double eq_pdf_cb(void* c, double t)
{
    eq_case* k = (eq_case*)c;
    return vbl_equiangular_pdf(k->o, k->d, k->t0, k->t1, k->p, t);
}

static void test_equiangular_chi2_and_shape(void** state)
{
    (void)state;
    vbl_vec3 d = vbl_v3_normalize(vbl_v3(1.0, 2.0, -0.5));
    vbl_vec3 o = vbl_v3(0.3, -0.2, 1.0);
    eq_case cases[] = {
        {o, d, vbl_v3(1.0, 1.0, 1.0), 0.0, 4.0},
        {o, d, vbl_v3_madd(o, d, 2.0), 0.5, 3.0},      /* point exactly on the ray */
        {o, d, vbl_v3(-5.0, 3.0, 0.0), 0.1, 0.2},      /* far point, short segment */
        {o, d, vbl_v3(10.0, 10.0, 10.0), 0.0, 100.0},
    };
    int n = (int)(sizeof cases / sizeof cases[0]);
    int ok = 1;
    for (int i = 0; i < n; ++i) {
        char label[64];
        snprintf(label, sizeof label, "equiangular case %d", i);
        ok &= check1d(label, eq_sample_cb, eq_pdf_cb, &cases[i], cases[i].t0, cases[i].t1, 32, 0, 100000, 300 + i,
                      n);
        /* Shape: pdf proportional to 1/dist^2 (ratio constant along the ray). */
        double ref = -1.0;
        for (int j = 0; j <= 10; ++j) {
            double t = cases[i].t0 + (cases[i].t1 - cases[i].t0) * j / 10.0;
            vbl_vec3 x = vbl_v3_madd(cases[i].o, cases[i].d, t);
            vbl_vec3 r = vbl_v3_sub(x, cases[i].p);
            double dist2 = vbl_v3_dot(r, r);
            if (dist2 < 1e-12) continue; /* the floored peak on the ray */
            double ratio = eq_pdf_cb(&cases[i], t) * dist2;
            if (ref < 0.0) ref = ratio;
            assert_true(fabs(ratio - ref) < 1e-6 * ref);
        }
    }
    assert_true(ok);
}

static void test_degenerate_inputs(void** state)
{
    (void)state;
    const double xs[] = {0.0, 1e-300, 0.5, nextafter(1.0, 0.0), 1.0};
    for (size_t i = 0; i < sizeof xs / sizeof xs[0]; ++i) {
        for (int k = 0; k < NCAUCHY; ++k) {
            double pdf;
            double x = vbl_cauchy_sample(kCauchy[k].h, kCauchy[k].a, kCauchy[k].b, xs[i], &pdf);
            assert_true(isfinite(x) && x >= kCauchy[k].a && x <= kCauchy[k].b);
            assert_true(isfinite(pdf) && pdf > 0.0);
        }
        double pdf = 1.0;
        double x = vbl_cauchy_sample(0.5, 1.0, 1.0, xs[i], &pdf); /* zero length */
        assert_true(x == 1.0 && pdf == 0.0);
        x = vbl_cauchy_sample(0.0, 0.0, 0.0, xs[i], &pdf);
        assert_true(x == 0.0 && pdf == 0.0);
        x = vbl_equiangular_sample(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 2.0, 2.0, vbl_v3(0, 1, 0), xs[i], &pdf);
        assert_true(x == 2.0 && pdf == 0.0);
        /* Point at the segment start on the line: finite, in domain. */
        x = vbl_equiangular_sample(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 0.0, 1.0, vbl_v3(0, 0, 0), xs[i], &pdf);
        assert_true(isfinite(x) && x >= 0.0 && x <= 1.0 && isfinite(pdf) && pdf > 0.0);
    }
    assert_true(vbl_cauchy_pdf(0.5, -1.0, 1.0, 1.5) == 0.0);
    assert_true(vbl_equiangular_pdf(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 0.0, 1.0, vbl_v3(0, 1, 0), -0.1) == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cauchy_chi2),
        cmocka_unit_test(test_cauchy_matches_eq14),
        cmocka_unit_test(test_equiangular_chi2_and_shape),
        cmocka_unit_test(test_degenerate_inputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
