/* The carried exponential optical depth of the tracking core (vbl_exp_carry_step, issue 14
 * item 5): one Exp(1) draw carried across majorant segments is the same Poisson process as a
 * fresh draw per segment. Checked (1) on the helper over hundreds of piecewise-constant rate
 * segments (every gap in optical depth ~ Exp(1): chi-square; counts ~ Poisson), (2) end to end
 * against the exact transmittance and free-flight CDF (optical depth by fine quadrature) in a
 * thick heterogeneous medium crossing many majorant segments and in a piecewise-constant medium
 * (homogeneous closed-form segments, sampled analytically with the carried depth). Fixed seeds. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/rng.h"
#include "volume/transmittance.h"
#include "volume_test_grid.h"

#define NX 127 /* grid voxels [0, NX] x [0, NY]^2: 16 majorant blocks along x */
#define NY 31 /* 4 blocks across: the inner ones are homogeneous in the slabs */

static void assert_within(double estimate, double se, double truth, double k, const char* what)
{
    double z = (estimate - truth) / (se + 1e-300);
    fprintf(stderr, "%s: estimate %.6g +- %.3g, truth %.6g, z %.2f\n", what, estimate, se, truth, z);
    if (!(fabs(estimate - truth) <= k * se + 1e-12)) fail();
}

/* Chi-square statistic of `bins` equiprobable bins of u in [0, 1). */
static double chi_square(const int* counts, int bins, int n)
{
    double e = (double)n / bins, x2 = 0.0;
    for (int b = 0; b < bins; ++b) x2 += (counts[b] - e) * (counts[b] - e) / e;
    return x2;
}

/* ---- (1) the helper on a piecewise-constant rate ------------------------------------------ */

#define SEGS 400
static void test_carry_poisson_process(void** state)
{
    (void)state;
    double t_edge[SEGS + 1], rate[SEGS];
    vbl_rng g = vbl_rng_make(5, 6, 7);
    t_edge[0] = 0.0;
    for (int s = 0; s < SEGS; ++s) {
        t_edge[s + 1] = t_edge[s] + 0.005 + 0.05 * vbl_rng_uniform(&g);
        rate[s] = s % 7 == 3 ? 0.0 : 40.0 * vbl_rng_uniform(&g) * vbl_rng_uniform(&g); /* some empty */
    }
    double lambda = 0.0; /* total optical depth */
    for (int s = 0; s < SEGS; ++s) lambda += rate[s] * (t_edge[s + 1] - t_edge[s]);
    enum { BINS = 20 };
    int gaps[BINS] = {0}, n_gaps = 0;
    double cnt = 0.0, cnt2 = 0.0;
    const int trials = 4000;
    for (int i = 0; i < trials; ++i) {
        vbl_rng rng = vbl_rng_make(41, 1, (uint64_t)i);
        /* depth: optical depth at the segment start; last: of the last point, or 0. Every gap
         * from a point (or 0) of depth <= lambda - 25 is counted: it ends inside the ray except
         * with probability e^-25, and by the strong Markov property it is Exp(1) whatever came
         * before (counting only the gaps that end inside would favour short ones). */
        double tau = -1.0, last = 0.0, depth = 0.0;
        int k = 0;
        for (int s = 0; s < SEGS; ++s) {
            if (!(rate[s] > 0.0)) continue; /* as the trackers: empty segments draw nothing */
            double t = t_edge[s];
            while (vbl_exp_carry_step(&tau, &t, t_edge[s + 1], rate[s], &rng)) {
                assert_true(t > t_edge[s] && t < t_edge[s + 1]);
                double at = depth + rate[s] * (t - t_edge[s]); /* optical depth of the point */
                double u = 1.0 - exp(-(at - last));             /* the gap is Exp(1): u ~ U[0, 1) */
                int b = (int)(u * BINS);
                if (last <= lambda - 25.0) {
                    gaps[b < BINS ? b : BINS - 1]++;
                    n_gaps++;
                }
                last = at;
                k++;
            }
            depth += rate[s] * (t_edge[s + 1] - t_edge[s]);
        }
        cnt += k;
        cnt2 += (double)k * k;
    }
    /* 19 degrees of freedom: P(chi2 > 43.8) = 0.001 */
    double x2 = chi_square(gaps, BINS, n_gaps);
    fprintf(stderr, "gaps %d over %d segments, chi2 %.2f (19 dof)\n", n_gaps, SEGS, x2);
    assert_true(x2 < 43.8);
    double mean = cnt / trials, var = cnt2 / trials - mean * mean;
    assert_within(mean, sqrt(lambda / trials), lambda, 4.0, "points per ray (Poisson mean)");
    /* Poisson: variance = mean (the variance's own s.e. ~ mean sqrt(2 / trials)) */
    assert_within(var, lambda * sqrt(2.0 / trials), lambda, 4.0, "points per ray (Poisson variance)");
}

/* ---- (2) end to end ------------------------------------------------------------------------ */

static double fn_thick(int i, int j, int k, void* user)
{
    (void)user;
    double y = (j - 15.5) / 16.0, z = (k - 15.5) / 16.0;
    double r2 = y * y + z * z;
    if (r2 >= 1.0) return 0.0;
    return (1.0 - r2) * (1.0 + 0.8 * sin(0.37 * i) * cos(0.5 * j + 0.3 * k)) * (0.6 + 0.4 * cos(0.05 * i));
}
static double fn_steps(int i, int j, int k, void* user)
{
    (void)j, (void)k, (void)user;
    return i < 40 ? 1.0 : (i < 80 ? 0.25 : 2.0); /* constant slabs: homogeneous blocks inside each */
}

/* Optical depth along o + t d, t in [0, t1], by the midpoint rule with `steps` points. */
static double quad_tau(const vbl_extinction* ext, vbl_extinction_cursor* cur, vbl_vec3 o, vbl_vec3 d, double t1,
                       int steps)
{
    double h = t1 / steps, tau = 0.0;
    for (int i = 0; i < steps; ++i) tau += vbl_extinction_eval(ext, cur, vbl_v3_madd(o, d, (i + 0.5) * h), NULL);
    return tau * h;
}

typedef struct medium_case {
    const char* name;
    vt_voxel_fn fn;
    double scale;
} medium_case;

static void check_medium(const medium_case* mc, int want_homogeneous)
{
    const int bmin[3] = {0, 0, 0}, bmax[3] = {NX, NY, NY};
    double m[3][4];
    vt_uniform_map(m, 1.0, 0.0, 0.0, 0.0);
    vbl_volume* v = vt_make(bmin, bmax, mc->fn, NULL, m);
    vbl_extinction ext;
    vbl_extinction_init(&ext);
    assert_int_equal(vbl_extinction_add(&ext, v, mc->scale, NULL), VBL_SUCCESS);
    vbl_extinction_cursor cur;
    vbl_extinction_cursor_init(&cur, &ext);
    vbl_vec3 o = vbl_v3(-2.0, 13.7, 14.2), d = vbl_v3(1.0, 0.0, 0.0);
    const double t1 = NX + 4.0;
    /* the ray crosses many non-empty majorant segments (homogeneous ones for the slabs) */
    vbl_extinction_iter it;
    vbl_majorant_segment seg;
    int nonempty = 0, homogeneous = 0;
    vbl_extinction_iter_init(&it, &ext, o, d, 0.0, t1, 0);
    while (vbl_extinction_iter_next(&it, &seg)) {
        nonempty += seg.majorant > 0.0;
        homogeneous += seg.majorant > 0.0 && seg.majorant == seg.minorant;
    }
    fprintf(stderr, "%s: %d non-empty segments, %d homogeneous\n", mc->name, nonempty, homogeneous);
    assert_true(nonempty >= 14);
    if (want_homogeneous) assert_true(homogeneous >= 6);
    const double tau = quad_tau(&ext, &cur, o, d, t1, 400000);
    assert_true(tau > 3.0 && tau < 6.0); /* thick: T ~ 0.002 .. 0.05 */
    /* transmittance: every tracker against exp(-tau) */
    for (int e = 0; e < 4; ++e) {
        const vbl_transmittance_estimator est = e == 0   ? VBL_TRANSMITTANCE_DELTA_TRACKING
                                                : e == 1 ? VBL_TRANSMITTANCE_RATIO_TRACKING
                                                         : VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING;
        vbl_tracking_settings set = {est, 0.0, 0, 1.0, 0.0, e == 3, 0, 0, {0.0, 0.0}};
        const int n = e == 0 ? 400000 : 100000;
        double s = 0.0, s2 = 0.0;
        for (int i = 0; i < n; ++i) {
            vbl_rng rng = vbl_rng_make(2024, (uint64_t)e, (uint64_t)i);
            double x = vbl_transmittance_estimate(&ext, &cur, o, d, 0.0, t1, &set, &rng);
            s += x;
            s2 += x * x;
        }
        double mean = s / n, var = fmax(s2 / n - mean * mean, 0.0);
        char what[96];
        snprintf(what, sizeof what, "%s T %s%s", mc->name, vbl_transmittance_estimator_name(est), e == 3 ? " mid" : "");
        assert_within(mean, sqrt(var / n), exp(-tau), 4.0, what);
        assert_true(sqrt(var / n) < 0.03 * exp(-tau)); /* resolves a 12 % bias at 4 sigma */
    }
    /* free flight: P(collision before t) = 1 - exp(-tau(t)) at several t, and the sigma_t reported */
    const double ts[4] = {20.0, 45.0, 70.0, t1};
    double tau_t[4];
    for (int k = 0; k < 4; ++k) tau_t[k] = quad_tau(&ext, &cur, o, d, ts[k], 100000);
    int hits[4] = {0};
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        vbl_rng rng = vbl_rng_make(2025, 9, (uint64_t)i);
        double tc = 0.0, sig = 0.0;
        if (vbl_free_flight_sample(&ext, &cur, o, d, 0.0, t1, 0, &rng, &tc, &sig, NULL)) {
            assert_true(tc > 0.0 && tc < t1 && sig > 0.0);
            for (int k = 0; k < 4; ++k) hits[k] += tc <= ts[k];
        }
    }
    for (int k = 0; k < 4; ++k) {
        double p = 1.0 - exp(-tau_t[k]);
        char what[96];
        snprintf(what, sizeof what, "%s free flight t=%g", mc->name, ts[k]);
        assert_within((double)hits[k] / n, sqrt(p * (1.0 - p) / n), p, 4.0, what);
    }
    vt_free(v);
}

static void test_thick_heterogeneous(void** state)
{
    (void)state;
    const medium_case mc = {"thick heterogeneous", fn_thick, 0.06};
    check_medium(&mc, 0);
}

static void test_piecewise_constant(void** state)
{
    (void)state;
    const medium_case mc = {"piecewise constant", fn_steps, 0.035};
    check_medium(&mc, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_carry_poisson_process),
        cmocka_unit_test(test_thick_heterogeneous),
        cmocka_unit_test(test_piecewise_constant),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
