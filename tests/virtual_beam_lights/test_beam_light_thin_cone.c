/* The thin-cone shortcut of the VSL kernel (sampling/beam_light_pair.h, issue 13 item 4): the
 * midpoint geometry x f_l(a) f_c(a) against the exact cone average K_R (a fine deterministic
 * quadrature), for random directions and HG lobes:
 *   - the stated relative-error bound holds at every half-angle tried (1e-3 .. 0.5 rad), with the
 *     global lobe bounds and with the bounds local to the cone (vbl_vsl_lobe_local_bounds, never
 *     above the global ones); mutation checked: the local curvature term 3|g| / q0 left out fails it;
 *   - at the threshold vbl_vsl_thin_cone_sin(g_max, tol) the error is below tol, and the threshold
 *     is tight enough to matter: at 10x the threshold some configuration exceeds tol (so a test
 *     with a threshold 10x too loose fails);
 *   - vbl_vsl_kernel_adaptive takes the midpoint exactly below the threshold and the quadrature
 *     above it; R == 0 is the VRL integrand f_l f_c / w^2. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "core/rng.h"
#include "sampling/beam_light_pair.h"
#include "sampling/phase_hg.h"
#include "sampling/vsl_cone.h"

static vbl_vec3 rand_dir(vbl_rng* r)
{
    double z = 1.0 - 2.0 * vbl_rng_uniform(r), ph = 2.0 * VBL_PI * vbl_rng_uniform(r);
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return vbl_v3(s * cos(ph), s * sin(ph), z);
}

/* Exact cone mean of f_l f_c times the geometry: a 2D midpoint grid in (1 - cos theta, phi), fine
 * enough that its own error is far below the shortcut's (the integrand is smooth on a thin cap). */
static double exact_kernel(vbl_vec3 xc, vbl_vec3 cd, double gc, vbl_vec3 xl, vbl_vec3 ld, double gl, double R)
{
    vbl_vsl_cone cone;
    vbl_vsl_cone_init(&cone, vbl_v3_sub(xc, xl), R, vbl_v3_scale(cd, -1.0));
    const int nt = 48, np = 96;
    double sum = 0.0;
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < np; ++j) {
            vbl_vec3 w = vbl_vsl_cone_sample(&cone, (i + 0.5) / nt, (j + 0.5) / np, NULL);
            sum += vbl_hg_eval(gl, vbl_v3_dot(ld, w)) * vbl_hg_eval(gc, -vbl_v3_dot(cd, w));
        }
    return cone.geometry * sum / (nt * np);
}

typedef struct config {
    vbl_vec3 xc, cd, xl, ld;
    double gc, gl;
} config;

static config make_config(vbl_rng* r, double g_max)
{
    config c;
    c.xl = vbl_v3(0, 0, 0);
    c.xc = vbl_v3_scale(rand_dir(r), 1.0);
    /* directions drawn so that the lobes' steep flanks often face the cone */
    c.cd = rand_dir(r);
    c.ld = rand_dir(r);
    c.gc = g_max * (vbl_rng_uniform(r) < 0.5 ? 1.0 : -1.0) * (0.5 + 0.5 * vbl_rng_uniform(r));
    c.gl = g_max * (vbl_rng_uniform(r) < 0.5 ? 1.0 : -1.0) * (0.5 + 0.5 * vbl_rng_uniform(r));
    return c;
}

/* A unit direction at angle t from unit a (random azimuth). */
static vbl_vec3 tilt(vbl_rng* r, vbl_vec3 a, double t)
{
    vbl_vec3 u, v;
    vbl_v3_basis(a, &u, &v);
    double ph = 2.0 * VBL_PI * vbl_rng_uniform(r);
    vbl_vec3 p = vbl_v3_add(vbl_v3_scale(u, cos(ph)), vbl_v3_scale(v, sin(ph)));
    return vbl_v3_add(vbl_v3_scale(a, cos(t)), vbl_v3_scale(p, sin(t)));
}

static double midpoint(const config* c, double R)
{
    return vbl_vsl_kernel_adaptive(c->xc, c->cd, c->gc, c->xl, c->ld, c->gl, R, 16, 0.3, 0.7, 1.0);
}

static void test_bound_holds(void** state)
{
    (void)state;
    vbl_rng r = vbl_rng_make(11, 0, 0);
    const double g_max[3] = {0.3, 0.5, 0.8};
    const double alpha[5] = {1e-3, 0.01, 0.05, 0.2, 0.5};
    double worst_ratio = 0.0, worst_local = 0.0;
    for (int gi = 0; gi < 3; ++gi)
        for (int k = 0; k < 40; ++k) {
            config c = make_config(&r, g_max[gi]);
            double b1 = vbl_vsl_lobe_slope_bound(c.gc) + vbl_vsl_lobe_slope_bound(c.gl);
            double b2 = vbl_vsl_lobe_curvature_bound(c.gc) + vbl_vsl_lobe_curvature_bound(c.gl);
            for (int a = 0; a < 5; ++a) {
                double R = sin(alpha[a]); /* w = 1 */
                double ex = exact_kernel(c.xc, c.cd, c.gc, c.xl, c.ld, c.gl, R);
                double err = fabs(midpoint(&c, R) / ex - 1.0);
                double bound = vbl_vsl_midpoint_error_bound(alpha[a], b1, b2);
                assert_true(err <= bound);
                if (err / bound > worst_ratio) worst_ratio = err / bound;
                /* the bound local to this cone (what the estimator uses) */
                vbl_vec3 ax = vbl_v3_normalize(c.xc);
                double l1, l2, m1, m2;
                vbl_vsl_lobe_local_bounds(c.gl, vbl_v3_dot(c.ld, ax), R, cos(alpha[a]), &l1, &l2);
                vbl_vsl_lobe_local_bounds(c.gc, -vbl_v3_dot(c.cd, ax), R, cos(alpha[a]), &m1, &m2);
                assert_true(l1 + m1 <= b1 * (1.0 + 1e-9) && l2 + m2 <= b2 * (1.0 + 1e-9));
                double local = vbl_vsl_midpoint_error_bound(alpha[a], l1 + m1, l2 + m2);
                assert_true(err <= local);
                if (err / local > worst_local) worst_local = err / local;
            }
        }
    /* lobe peaks at 0..3 half-angles from the axis, where the local bound is tightest */
    for (int a = 0; a < 5; ++a)
        for (int k = 0; k < 60; ++k) {
            config c = make_config(&r, g_max[k % 3]);
            double R = sin(alpha[a]);
            vbl_vec3 ax = vbl_v3_normalize(c.xc);
            c.ld = vbl_v3_scale(tilt(&r, ax, 3.0 * alpha[a] * vbl_rng_uniform(&r)), c.gl > 0.0 ? 1.0 : -1.0);
            c.cd = vbl_v3_scale(tilt(&r, ax, 3.0 * alpha[a] * vbl_rng_uniform(&r)), c.gc > 0.0 ? -1.0 : 1.0);
            double ex = exact_kernel(c.xc, c.cd, c.gc, c.xl, c.ld, c.gl, R);
            double err = fabs(midpoint(&c, R) / ex - 1.0);
            double l1, l2, m1, m2;
            vbl_vsl_lobe_local_bounds(c.gl, vbl_v3_dot(c.ld, ax), R, cos(alpha[a]), &l1, &l2);
            vbl_vsl_lobe_local_bounds(c.gc, -vbl_v3_dot(c.cd, ax), R, cos(alpha[a]), &m1, &m2);
            double local = vbl_vsl_midpoint_error_bound(alpha[a], l1 + m1, l2 + m2);
            assert_true(err <= local);
            if (err / local > worst_local) worst_local = err / local;
        }
    printf("thin cone: largest observed error / bound = %.3f (global), %.3f (local)\n", worst_ratio, worst_local);
    /* the bound is not vacuous: somewhere it is within 30x of the observed error */
    assert_true(worst_ratio > 1.0 / 30.0 && worst_local > 1.0 / 30.0);
}

static void test_threshold(void** state)
{
    (void)state;
    const double tol = 0.01;
    const double g_max[3] = {0.3, 0.5, 0.8};
    for (int gi = 0; gi < 3; ++gi) {
        double s = vbl_vsl_thin_cone_sin(g_max[gi], tol);
        double b1 = 2.0 * vbl_vsl_lobe_slope_bound(g_max[gi]), b2 = 2.0 * vbl_vsl_lobe_curvature_bound(g_max[gi]);
        assert_true(s > 0.0 && s < 1.0);
        assert_true(vbl_vsl_midpoint_error_bound(asin(s), b1, b2) <= tol * (1.0 + 1e-12));
        assert_true(vbl_vsl_midpoint_error_bound(asin(s) * 1.01, b1, b2) > tol);
        vbl_rng r = vbl_rng_make(12, (uint64_t)gi, 0);
        double worst_at = 0.0, worst_10x = 0.0;
        for (int k = 0; k < 100; ++k) {
            config c = make_config(&r, g_max[gi]);
            double e1 = exact_kernel(c.xc, c.cd, c.gc, c.xl, c.ld, c.gl, s);
            worst_at = fmax(worst_at, fabs(midpoint(&c, s) / e1 - 1.0));
            double s10 = fmin(10.0 * s, 0.99);
            double e10 = exact_kernel(c.xc, c.cd, c.gc, c.xl, c.ld, c.gl, s10);
            worst_10x = fmax(worst_10x, fabs(midpoint(&c, s10) / e10 - 1.0));
        }
        printf("g_max %.1f: thin_sin %.4g, worst error at it %.2e, at 10x %.2e (tol %g)\n", g_max[gi], s, worst_at,
               worst_10x, tol);
        assert_true(worst_at <= tol);
        assert_true(worst_10x > tol);
    }
    assert_true(vbl_vsl_thin_cone_sin(0.5, 0.0) == 0.0);
    assert_true(vbl_vsl_thin_cone_sin(1.0, 0.01) == 0.0);
    assert_true(vbl_vsl_thin_cone_sin(0.0, 0.01) == 1.0); /* isotropic: the midpoint is exact */
}

static void test_adaptive_switch(void** state)
{
    (void)state;
    vbl_vec3 xc = vbl_v3(0.3, 0.2, 1.0), cd = vbl_v3_normalize(vbl_v3(1, 0.5, 0.2)), ld = vbl_v3(0, 0, 1);
    vbl_vec3 xl = vbl_v3(0, 0, 0);
    double w = vbl_v3_length(xc), gc = 0.6, gl = 0.7;
    vbl_vec3 a = vbl_v3_scale(xc, 1.0 / w);
    double f = vbl_hg_eval(gl, vbl_v3_dot(ld, a)) * vbl_hg_eval(gc, -vbl_v3_dot(cd, a));
    /* R == 0: exactly the VRL integrand */
    assert_true(fabs(vbl_vsl_kernel_adaptive(xc, cd, gc, xl, ld, gl, 0.0, 16, 0.1, 0.2, 0.0) - f / (w * w)) <=
                1e-15 * f / (w * w));
    const double thin = 0.01;
    double R_in = 0.9 * thin * w, R_out = 1.1 * thin * w;
    vbl_vsl_cone c_in;
    vbl_vsl_cone_init(&c_in, xc, R_in, ld);
    assert_true(vbl_vsl_kernel_adaptive(xc, cd, gc, xl, ld, gl, R_in, 16, 0.1, 0.2, thin) == f * c_in.geometry);
    assert_true(vbl_vsl_kernel_adaptive(xc, cd, gc, xl, ld, gl, R_out, 16, 0.1, 0.2, thin) ==
                vbl_vsl_kernel(xc, cd, gc, xl, ld, gl, R_out, 16, 0.1, 0.2));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bound_holds),
        cmocka_unit_test(test_threshold),
        cmocka_unit_test(test_adaptive_switch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
