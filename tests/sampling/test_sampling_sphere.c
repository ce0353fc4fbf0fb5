/* Uniform sphere and cone sampling: chi-square over (z, phi), support, pdf consistency. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "sampling/sphere.h"

#define NZ 16
#define NPHI 8
#define N 200000

static int chi2_cone(const char* label, vbl_vec3 axis, double cos_max, int sphere, uint64_t seed, int tests)
{
    double obs[NZ * NPHI] = {0}, expct[NZ * NPHI];
    vbl_vec3 t, b;
    vbl_v3_basis(axis, &t, &b);
    vbl_rng rng = vbl_rng_make(seed, 0, 0);
    int ok = 1;
    for (int i = 0; i < N; ++i) {
        double u1 = vbl_rng_uniform(&rng), u2 = vbl_rng_uniform(&rng), pdf;
        vbl_vec3 w = sphere ? vbl_sample_uniform_sphere(u1, u2, &pdf) : vbl_sample_uniform_cone(axis, cos_max, u1, u2, &pdf);
        ok &= fabs(vbl_v3_length(w) - 1.0) < 1e-12;
        double c = vbl_v3_dot(w, axis);
        ok &= c >= cos_max - 1e-12;
        ok &= sphere ? pdf == VBL_INV_4PI : fabs(pdf - vbl_uniform_cone_pdf(axis, cos_max, w)) < 1e-12 * pdf || c < cos_max;
        /* Cells: equal area in z = cos in [cos_max, 1] (uniform in z is the claim under test). */
        int zi = (int)((c - cos_max) / (1.0 - cos_max) * NZ);
        zi = zi < 0 ? 0 : (zi >= NZ ? NZ - 1 : zi);
        double phi = atan2(vbl_v3_dot(w, b), vbl_v3_dot(w, t));
        int pi = (int)((phi + VBL_PI) / (2.0 * VBL_PI) * NPHI);
        pi = pi < 0 ? 0 : (pi >= NPHI ? NPHI - 1 : pi);
        obs[zi * NPHI + pi] += 1.0;
    }
    /* Expected from the pdf: cell solid angle (dz dphi) times the density. */
    double density = sphere ? VBL_INV_4PI : 1.0 / (2.0 * VBL_PI * (1.0 - cos_max));
    for (int k = 0; k < NZ * NPHI; ++k) expct[k] = N * density * ((1.0 - cos_max) / NZ) * (2.0 * VBL_PI / NPHI);
    return ok & vbl_chi2_check(label, obs, expct, NZ * NPHI, 0.01, tests);
}

static void test_sphere_and_cone(void** state)
{
    (void)state;
    vbl_vec3 axis = vbl_v3_normalize(vbl_v3(0.2, -0.7, 0.4));
    int ok = chi2_cone("uniform sphere", vbl_v3(0, 0, 1), -1.0, 1, 1, 5);
    ok &= chi2_cone("cone cos_max=0.3", axis, 0.3, 0, 2, 5);
    ok &= chi2_cone("cone cos_max=0.99", axis, 0.99, 0, 3, 5);
    ok &= chi2_cone("cone cos_max=-0.5", axis, -0.5, 0, 4, 5);
    ok &= chi2_cone("cone cos_max=1-1e-9", vbl_v3(0, 0, -1), 1.0 - 1e-9, 0, 5, 5);
    assert_true(ok);
}

static void test_cone_degenerate(void** state)
{
    (void)state;
    double pdf = 1.0;
    vbl_vec3 axis = vbl_v3(0, 1, 0);
    vbl_vec3 w = vbl_sample_uniform_cone(axis, 1.0, 0.5, 0.5, &pdf);
    assert_true(pdf == 0.0 && w.y == 1.0);
    const double xs[] = {0.0, nextafter(1.0, 0.0), 1.0};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            w = vbl_sample_uniform_sphere(xs[i], xs[j], &pdf);
            assert_true(isfinite(w.x + w.y + w.z) && fabs(vbl_v3_length(w) - 1.0) < 1e-12);
            w = vbl_sample_uniform_cone(axis, 0.5, xs[i], xs[j], &pdf);
            assert_true(isfinite(w.x + w.y + w.z) && fabs(vbl_v3_length(w) - 1.0) < 1e-12 && w.y >= 0.5 - 1e-12);
        }
    assert_true(vbl_uniform_cone_pdf(axis, 0.5, vbl_v3(1, 0, 0)) == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_and_cone),
        cmocka_unit_test(test_cone_degenerate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
