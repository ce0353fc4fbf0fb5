/* Piecewise-constant density (sampling/step_pdf.h): chi-square for several step shapes
 * (including empty pieces, zero-width pieces, a defensive share and a falling transmittance-like
 * staircase), pdf normalisation, empty pieces never sampled, uniform fallback, invalid input.
 * Mutation checked: the pdf reading the previous piece's value fails the chi-square (p = 0). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "sampling/step_pdf.h"
#include "sampling_check1d.h"

static double step_sample_cb(void* c, double xi, double* pdf)
{
    return vbl_step_pdf_sample((const vbl_step_pdf*)c, xi, pdf);
}
static double step_pdf_cb(void* c, double x) { return vbl_step_pdf_pdf((const vbl_step_pdf*)c, x); }

typedef struct shape {
    const char* name;
    int n;
    double x[12], y[11], defensive;
} shape;

static const shape kShapes[] = {
    {"single piece", 1, {0.5, 2.0}, {3.0}, 0.0},
    {"staircase down", 6, {0, .2, .5, .6, 1.3, 2, 3}, {1, .8, .5, .3, .05, .001}, 0.0},
    {"empty middle", 4, {0, 1, 2, 3, 4}, {1, 0, 0, 2}, 0.0},
    {"empty middle, defensive", 4, {0, 1, 2, 3, 4}, {1, 0, 0, 2}, 0.2},
    {"zero-width piece", 4, {0, 1, 1, 2, 3}, {1, 50, 2, 1}, 0.0},
    {"wide dynamic range", 4, {0, 0.3, 1, 2, 3}, {1e3, 1e-1, 1e-4, 1e-7}, 0.0},
    {"all zero (uniform fallback)", 2, {0, 1, 3}, {0, 0}, 0.0},
    {"negative/NaN read as 0", 3, {0, 1, 2, 3}, {-1, NAN, 1}, 0.0},
};
#define NSHAPES ((int)(sizeof kShapes / sizeof kShapes[0]))

static void test_step_chi2(void** state)
{
    (void)state;
    int ok = 1;
    for (int i = 0; i < NSHAPES; ++i) {
        vbl_step_pdf p;
        assert_true(vbl_step_pdf_init(&p, kShapes[i].x, kShapes[i].y, kShapes[i].n, kShapes[i].defensive));
        double a = kShapes[i].x[0], b = kShapes[i].x[kShapes[i].n];
        char label[80];
        snprintf(label, sizeof label, "step %s", kShapes[i].name);
        /* uniform bins: quantile bins would collapse onto the pieces' edges */
        ok &= check1d(label, step_sample_cb, step_pdf_cb, &p, a, b, 32, 1, 100000, 900 + i, NSHAPES);
        /* piecewise quadrature (the density jumps at the breakpoints) */
        check1d_pdf_ctx pc = {step_pdf_cb, &p};
        double m = 0.0;
        for (int k = 0; k < kShapes[i].n; ++k)
            if (p.x[k + 1] > p.x[k]) m += vbl_quad_gl16(check1d_pdf_thunk, &pc, p.x[k], p.x[k + 1]);
        assert_true(fabs(m - 1.0) < 1e-9);
    }
    assert_true(ok);
    vbl_step_pdf u;
    vbl_step_pdf_init(&u, kShapes[6].x, kShapes[6].y, 2, 0.0);
    assert_true(fabs(vbl_step_pdf_pdf(&u, 2.0) - 1.0 / 3.0) < 1e-15);
    assert_true(vbl_step_pdf_pdf(&u, 3.5) == 0.0 && vbl_step_pdf_pdf(&u, -0.1) == 0.0);
}

static void test_step_empty_pieces_never_sampled(void** state)
{
    (void)state;
    vbl_step_pdf p;
    vbl_step_pdf_init(&p, kShapes[2].x, kShapes[2].y, kShapes[2].n, 0.0); /* zero on (1, 3) */
    vbl_rng rng = vbl_rng_make(9, 9, 9);
    for (int i = 0; i < 100000; ++i) {
        double pdf, x = vbl_step_pdf_sample(&p, vbl_rng_uniform(&rng), &pdf);
        assert_true(pdf > 0.0);
        assert_false(x > 1.0 && x < 3.0);
        assert_true(fabs(pdf - vbl_step_pdf_pdf(&p, x)) <= 1e-15 * pdf);
    }
    const double xs[] = {0.0, 1e-300, nextafter(1.0, 0.0)};
    for (int i = 0; i < NSHAPES; ++i) {
        vbl_step_pdf q;
        vbl_step_pdf_init(&q, kShapes[i].x, kShapes[i].y, kShapes[i].n, kShapes[i].defensive);
        for (size_t j = 0; j < sizeof xs / sizeof xs[0]; ++j) {
            double pdf, x = vbl_step_pdf_sample(&q, xs[j], &pdf);
            assert_true(isfinite(x) && x >= q.x[0] && x <= q.x[q.count] && isfinite(pdf) && pdf > 0.0);
        }
    }
}

static void test_step_invalid(void** state)
{
    (void)state;
    vbl_step_pdf p;
    const double x[] = {0.0, 1.0, 0.5}, y[] = {1.0, 1.0};
    assert_false(vbl_step_pdf_init(&p, x, y, 2, 0.0));  /* decreasing breakpoints */
    assert_false(vbl_step_pdf_init(&p, x, y, 0, 0.0));  /* no pieces */
    assert_false(vbl_step_pdf_init(&p, x, y, 1, 1.0));  /* defensive outside [0, 1) */
    const double z[] = {1.0, 1.0};
    assert_false(vbl_step_pdf_init(&p, z, y, 1, 0.0)); /* zero width */
    double pdf;
    assert_true(vbl_step_pdf_sample(&p, 0.5, &pdf) == 0.0 && pdf == 0.0);
    assert_true(vbl_step_pdf_pdf(&p, 0.5) == 0.0);
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_step_chi2),
        cmocka_unit_test(test_step_empty_pieces_never_sampled),
        cmocka_unit_test(test_step_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
