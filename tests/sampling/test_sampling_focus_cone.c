/* Focus cone directions (sampling/focus_cone.h; pt.light_focus): angle to the axis uniform in
 * [0, psi_max], density 1 / (2 pi psi_max sin psi).
 *   - chi-square in the cone's own frame over equal-area (cos psi, phi) cells against the claimed
 *     law (sampling uniform in cos psi, the uniform cone's law, fails it);
 *   - chi-square in the world frame (the axis tilted, cells in (z, phi)) against the pdf function
 *     integrated over each cell (64 x 64 midpoints; the 1/psi singularity is integrable): the
 *     sampler and vbl_focus_cone_pdf describe the same density, and it integrates to 1;
 *   - the returned pdf equals vbl_focus_cone_pdf, 0 outside the cone, no sample where the density
 *     is not finite (psi = 0) or psi_max is out of range. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <math.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "sampling/focus_cone.h"

#define N 400000

static void test_cone_frame_chi2(void** state)
{
    (void)state;
    enum { NZ = 24, NPHI = 8 };
    const double psi_maxes[3] = {0.05, 0.7, 2.0};
    int ok = 1;
    for (int c = 0; c < 3; ++c) {
        const double psi_max = psi_maxes[c], zmin = cos(psi_max);
        const vbl_vec3 axis = vbl_v3_normalize(vbl_v3(0.3, -0.5, 0.8));
        vbl_vec3 t, b;
        vbl_v3_basis(axis, &t, &b);
        double obs[NZ * NPHI] = {0}, expct[NZ * NPHI];
        vbl_rng rng = vbl_rng_make(11 + c, 0, 0);
        for (int i = 0; i < N; ++i) {
            vbl_vec3 w;
            double pdf;
            if (!vbl_focus_cone_sample(axis, psi_max, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &w, &pdf)) continue;
            const double z = vbl_v3_dot(w, axis);
            int zi = (int)((z - zmin) / (1.0 - zmin) * NZ);
            zi = zi < 0 ? 0 : (zi >= NZ ? NZ - 1 : zi);
            const double phi = atan2(vbl_v3_dot(w, b), vbl_v3_dot(w, t));
            int pi = (int)((phi + VBL_PI) / (2.0 * VBL_PI) * NPHI);
            pi = pi < 0 ? 0 : (pi >= NPHI ? NPHI - 1 : pi);
            obs[zi * NPHI + pi] += 1.0;
        }
        for (int zi = 0; zi < NZ; ++zi) { /* P(z in cell) = (psi(z_lo) - psi(z_hi)) / psi_max, uniform in phi */
            const double z0 = zmin + (1.0 - zmin) * zi / NZ, z1 = zmin + (1.0 - zmin) * (zi + 1) / NZ;
            const double p = (acos(fmin(1.0, z0)) - acos(fmin(1.0, z1))) / psi_max / NPHI;
            for (int k = 0; k < NPHI; ++k) expct[zi * NPHI + k] = N * p;
        }
        char label[64];
        snprintf(label, sizeof label, "focus cone frame, psi_max %g", psi_max);
        ok &= vbl_chi2_check(label, obs, expct, NZ * NPHI, 0.01, 6);
    }
    assert_true(ok);
}

static void test_world_frame_against_pdf(void** state)
{
    (void)state;
    enum { NZ = 32, NPHI = 32, SUB = 64 };
    const vbl_vec3 axis = vbl_v3_normalize(vbl_v3(0.4, 0.1, 0.9));
    const double psi_max = 0.6;
    static double obs[NZ * NPHI], expct[NZ * NPHI];
    vbl_rng rng = vbl_rng_make(5, 0, 0);
    int bad_pdf = 0;
    for (int i = 0; i < N; ++i) {
        vbl_vec3 w;
        double pdf;
        if (!vbl_focus_cone_sample(axis, psi_max, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &w, &pdf)) continue;
        const double p2 = vbl_focus_cone_pdf(axis, psi_max, w);
        bad_pdf += !(fabs(pdf - p2) <= 1e-9 * p2) || fabs(vbl_v3_length(w) - 1.0) > 1e-12;
        int zi = (int)((w.z + 1.0) * 0.5 * NZ);
        zi = zi < 0 ? 0 : (zi >= NZ ? NZ - 1 : zi);
        int pi = (int)((atan2(w.y, w.x) + VBL_PI) / (2.0 * VBL_PI) * NPHI);
        pi = pi < 0 ? 0 : (pi >= NPHI ? NPHI - 1 : pi);
        obs[zi * NPHI + pi] += 1.0;
    }
    assert_int_equal(bad_pdf, 0);
    double total = 0.0;
    for (int zi = 0; zi < NZ; ++zi)
        for (int pi = 0; pi < NPHI; ++pi) {
            double s = 0.0; /* int over the cell of pdf dz dphi, midpoints */
            const double dz = 2.0 / NZ / SUB, dphi = 2.0 * VBL_PI / NPHI / SUB;
            for (int a = 0; a < SUB; ++a)
                for (int c = 0; c < SUB; ++c) {
                    const double z = -1.0 + (zi * SUB + a + 0.5) * dz;
                    const double phi = -VBL_PI + (pi * SUB + c + 0.5) * dphi;
                    const double r = sqrt(fmax(0.0, 1.0 - z * z));
                    s += vbl_focus_cone_pdf(axis, psi_max, vbl_v3(r * cos(phi), r * sin(phi), z));
                }
            expct[zi * NPHI + pi] = N * s * dz * dphi;
            total += s * dz * dphi;
        }
    printf("integral of the pdf over the sphere: %.5f\n", total);
    assert_true(fabs(total - 1.0) < 2e-3);
    assert_true(vbl_chi2_check("focus cone, world frame vs pdf", obs, expct, NZ * NPHI, 0.01, 2));
}

static void test_edges(void** state)
{
    (void)state;
    const vbl_vec3 axis = vbl_v3(0, 0, 1);
    vbl_vec3 w;
    double pdf = -1.0;
    assert_false(vbl_focus_cone_sample(axis, 0.5, 0.0, 0.3, &w, &pdf)); /* psi = 0: density not finite */
    assert_false(vbl_focus_cone_sample(axis, 0.0, 0.5, 0.3, &w, &pdf));
    assert_false(vbl_focus_cone_sample(axis, -1.0, 0.5, 0.3, &w, &pdf));
    assert_false(vbl_focus_cone_sample(axis, NAN, 0.5, 0.3, &w, &pdf));
    assert_false(vbl_focus_cone_sample(axis, 4.0, 0.5, 0.3, &w, &pdf));
    assert_true(vbl_focus_cone_pdf(axis, 0.5, axis) == 0.0);                 /* on the axis */
    assert_true(vbl_focus_cone_pdf(axis, 0.5, vbl_v3(1, 0, 0)) == 0.0);      /* outside */
    assert_true(vbl_focus_cone_pdf(axis, NAN, vbl_v3(0.1, 0, 0.99)) == 0.0);
    /* the smallest angles still give finite densities */
    const double us[3] = {1e-300, 1e-12, nextafter(1.0, 0.0)};
    for (int i = 0; i < 3; ++i) {
        if (!vbl_focus_cone_sample(axis, VBL_PI, us[i], 0.7, &w, &pdf)) continue;
        assert_true(isfinite(pdf) && pdf > 0.0 && isfinite(w.x + w.y + w.z));
        const double p2 = vbl_focus_cone_pdf(axis, VBL_PI, w);
        assert_true(isfinite(p2) && p2 >= 0.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cone_frame_chi2),
        cmocka_unit_test(test_world_frame_against_pdf),
        cmocka_unit_test(test_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
