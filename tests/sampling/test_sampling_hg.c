/* Henyey-Greenstein sampling: chi-square over (cos theta, phi), normalisation, sample/pdf
 * consistency, first moment = g (forward convention), extreme inputs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "quad.h"
#include "sampling/phase_hg.h"

static const double kG[] = {-0.999, -0.9, -0.5, 0.0, 0.3, 0.9, 0.999};
#define NG ((int)(sizeof(kG) / sizeof(kG[0])))
#define NCOS 16
#define NPHI 8
#define NSAMPLES 200000

static double hg_solid_angle(double c, void* ctx) { return 2.0 * VBL_PI * vbl_hg_pdf(*(const double*)ctx, c); }

/* cos-theta bin edges: a warped grid (equal-probability under the sampler's own inversion), with
 * exact endpoints; the expected counts come from integrating vbl_hg_pdf, independently. */
static void cos_edges(double g, double* e)
{
    for (int i = 0; i <= NCOS; ++i) e[i] = vbl_hg_sample_cos(g, (double)i / NCOS);
    e[0] = -1.0;
    e[NCOS] = 1.0;
    for (int i = 1; i <= NCOS; ++i)
        if (e[i] < e[i - 1]) e[i] = e[i - 1];
}

static double cell_mass(double g, double c0, double c1)
{
    return vbl_quad_adaptive(hg_solid_angle, &g, c0, c1, 1e-13, 1e-12);
}

static double azimuth(vbl_vec3 w, vbl_vec3 axis)
{
    vbl_vec3 t, b;
    vbl_v3_basis(axis, &t, &b);
    double phi = atan2(vbl_v3_dot(w, b), vbl_v3_dot(w, t));
    return phi < 0.0 ? phi + 2.0 * VBL_PI : phi;
}

static void test_hg_chi2(void** state)
{
    (void)state;
    vbl_vec3 axis = vbl_v3_normalize(vbl_v3(0.3, -0.5, 0.8));
    int all_ok = 1;
    for (int k = 0; k < NG; ++k) {
        double g = kG[k];
        double edges[NCOS + 1], obs[NCOS * NPHI] = {0}, expct[NCOS * NPHI];
        cos_edges(g, edges);
        vbl_rng rng = vbl_rng_make(42, 1, (uint64_t)k);
        for (int i = 0; i < NSAMPLES; ++i) {
            double u1 = vbl_rng_uniform(&rng), u2 = vbl_rng_uniform(&rng), pdf;
            vbl_vec3 w = vbl_hg_sample(g, axis, u1, u2, &pdf);
            double c = vbl_clamp(vbl_v3_dot(w, axis), -1.0, 1.0);
            int ci = 0;
            while (ci + 1 < NCOS && c >= edges[ci + 1]) ++ci;
            int pi = (int)(azimuth(w, axis) / (2.0 * VBL_PI) * NPHI);
            pi = pi < 0 ? 0 : (pi >= NPHI ? NPHI - 1 : pi);
            obs[ci * NPHI + pi] += 1.0;
        }
        double total = 0.0;
        for (int ci = 0; ci < NCOS; ++ci) {
            double m = cell_mass(g, edges[ci], edges[ci + 1]);
            total += m;
            for (int pi = 0; pi < NPHI; ++pi) expct[ci * NPHI + pi] = NSAMPLES * m / NPHI;
        }
        char label[64];
        snprintf(label, sizeof label, "hg g=%g", g);
        all_ok &= vbl_chi2_check(label, obs, expct, NCOS * NPHI, 0.01, NG);
        printf("     pdf integral over the sphere g=%g: %.12f\n", g, total);
        assert_true(fabs(total - 1.0) < 1e-8);
    }
    assert_true(all_ok);
}

/* The test must be able to fail: samples of g = 0.45 judged against the g = 0.5 pdf. */
static void test_hg_chi2_detects_wrong_pdf(void** state)
{
    (void)state;
    double edges[NCOS + 1], obs[NCOS] = {0}, expct[NCOS];
    cos_edges(0.5, edges);
    vbl_rng rng = vbl_rng_make(42, 2, 0);
    for (int i = 0; i < NSAMPLES; ++i) {
        double c = vbl_hg_sample_cos(0.45, vbl_rng_uniform(&rng));
        int ci = 0;
        while (ci + 1 < NCOS && c >= edges[ci + 1]) ++ci;
        obs[ci] += 1.0;
    }
    for (int ci = 0; ci < NCOS; ++ci) expct[ci] = NSAMPLES * cell_mass(0.5, edges[ci], edges[ci + 1]);
    assert_false(vbl_chi2_check("hg g=0.45 vs pdf g=0.5 (must fail)", obs, expct, NCOS, 0.01, 1));
}

static void test_hg_mean_cosine_is_g(void** state)
{
    (void)state;
    int ok = 1;
    for (int k = 0; k < NG; ++k) {
        vbl_rng rng = vbl_rng_make(7, 3, (uint64_t)k);
        vbl_mean_acc acc = {0, 0, 0};
        for (int i = 0; i < NSAMPLES; ++i) vbl_mean_add(&acc, vbl_hg_sample_cos(kG[k], vbl_rng_uniform(&rng)));
        char label[64];
        snprintf(label, sizeof label, "E[cos] g=%g", kG[k]);
        ok &= vbl_mean_check(label, &acc, kG[k], 4.5, 0.0);
    }
    assert_true(ok);
}

static void test_hg_sample_pdf_consistency_and_extremes(void** state)
{
    (void)state;
    vbl_vec3 axis = vbl_v3_normalize(vbl_v3(-0.2, 0.9, 0.1));
    const double us[] = {0.0, 1e-300, 1e-12, 0.25, 0.5, 0.75, 1.0 - 1e-12, nextafter(1.0, 0.0), 1.0};
    for (int k = 0; k < NG; ++k) {
        double g = kG[k];
        for (size_t i = 0; i < sizeof us / sizeof us[0]; ++i) {
            for (size_t j = 0; j < sizeof us / sizeof us[0]; ++j) {
                double pdf = -1.0;
                vbl_vec3 w = vbl_hg_sample(g, axis, us[i], us[j], &pdf);
                assert_true(isfinite(w.x) && isfinite(w.y) && isfinite(w.z));
                assert_true(fabs(vbl_v3_length(w) - 1.0) < 1e-12);
                assert_true(isfinite(pdf) && pdf > 0.0);
                double c = vbl_hg_sample_cos(g, us[i]);
                assert_true(c >= -1.0 && c <= 1.0);
                assert_true(fabs(pdf - vbl_hg_pdf(g, c)) <= 1e-12 * pdf);
                double pdf_dir = vbl_hg_pdf(g, vbl_v3_dot(w, axis)); /* via the returned direction */
                assert_true(fabs(pdf - pdf_dir) <= 1e-6 * pdf);
            }
        }
        /* Inversion monotone in u and hitting both poles. */
        assert_true(fabs(vbl_hg_sample_cos(g, 0.0) + 1.0) < 1e-12);
        assert_true(fabs(vbl_hg_sample_cos(g, 1.0) - 1.0) < 1e-12);
        double prev = -1.0;
        for (int i = 1; i <= 1000; ++i) {
            double c = vbl_hg_sample_cos(g, i / 1000.0);
            assert_true(c >= prev);
            prev = c;
        }
    }
    /* g = 0 is exactly the isotropic path. */
    for (int i = 0; i <= 16; ++i) assert_true(vbl_hg_sample_cos(0.0, i / 16.0) == 2.0 * (i / 16.0) - 1.0);
    assert_true(vbl_hg_eval(0.0, 0.3) == VBL_INV_4PI);
    /* Tiny g stays close to isotropic (no 1/g blow-up). */
    for (int i = 0; i <= 16; ++i) assert_true(fabs(vbl_hg_sample_cos(1e-12, i / 16.0) - (2.0 * i / 16.0 - 1.0)) < 1e-11);
    /* Forward convention: g > 0 peaks at cos = 1. */
    assert_true(vbl_hg_eval(0.9, 1.0) > vbl_hg_eval(0.9, -1.0));
    assert_true(vbl_hg_eval(-0.9, -1.0) > vbl_hg_eval(-0.9, 1.0));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hg_chi2),
        cmocka_unit_test(test_hg_chi2_detects_wrong_pdf),
        cmocka_unit_test(test_hg_mean_cosine_is_g),
        cmocka_unit_test(test_hg_sample_pdf_consistency_and_extremes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
