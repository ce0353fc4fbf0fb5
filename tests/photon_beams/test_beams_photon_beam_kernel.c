/* Photon beams, beam x beam 1D estimate (Jarosz et al. 2011a, section 7.3, eq. 38, biweight):
 * kernel normalisation, eq 38 exactly for interior crossings, the line-line identity over
 * offsets, an analytic collimated bundle (converging as r shrinks), parallel lines finite. */
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
#include "transport/photon_beams/photon_beam_kernel.h"

static double bw(double x, void* c)
{
    (void)c;
    return vbl_biweight_1d(x);
}

static void test_biweight(void** state)
{
    (void)state;
    assert_true(fabs(vbl_quad_adaptive(bw, NULL, -1.0, 1.0, 1e-15, 1e-13) - 1.0) < 1e-12);
    assert_true(vbl_biweight_1d(1.0) == 0.0 && vbl_biweight_1d(-1.5) == 0.0 && vbl_biweight_1d(NAN) == 0.0);
    assert_true(fabs(vbl_biweight_1d(0.0) - 15.0 / 16.0) < 1e-16);
}

/* Interior crossing: weight = K_r(d) / sin(theta) and the closest points (eq 38). */
static void test_eq38_interior(void** state)
{
    (void)state;
    vbl_rng rng = vbl_rng_make(3, 0, 0);
    for (int i = 0; i < 500; ++i) {
        vbl_vec3 cd = vbl_v3_normalize(vbl_v3(1, 0.3 * vbl_rng_uniform(&rng), 0));
        double th = 0.2 + 2.7 * vbl_rng_uniform(&rng); /* beam direction in the plane y-z-ish */
        vbl_vec3 bd = vbl_v3_normalize(vbl_v3(cos(th), 0.2, sin(th)));
        double r = 0.05, d = (2 * vbl_rng_uniform(&rng) - 1) * r;
        vbl_vec3 n = vbl_v3_normalize(vbl_v3_cross(bd, cd));
        vbl_vec3 xc = vbl_v3_madd(vbl_v3(0, 0, 0), cd, 5.0), xb = vbl_v3_madd(xc, n, d);
        vbl_vec3 bo = vbl_v3_madd(xb, bd, -4.0);
        vbl_photon_beam_eval_result e;
        assert_true(vbl_photon_beam_eval(vbl_v3(0, 0, 0), cd, 10.0, bo, bd, 8.0, r, &e));
        double s = vbl_v3_length(vbl_v3_cross(bd, cd));
        double expect = vbl_biweight_1d(d / r) / r / s;
        assert_true(fabs(e.weight - expect) <= 1e-9 * expect);
        assert_true(fabs(e.t_c - 5.0) < 1e-9 && fabs(e.t_b - 4.0) < 1e-9 && fabs(e.distance - fabs(d)) < 1e-12);
    }
}

/* Line-line identity: integrating the weight over the offset along n gives 1 / sin(theta), the
 * exact transport of an infinitely thin beam averaged over its position. */
typedef struct octx { vbl_vec3 cd, bd, n; double r; } octx;
static double weight_at(double y, void* c)
{
    octx* o = (octx*)c;
    vbl_vec3 xc = vbl_v3_scale(o->cd, 5.0);
    vbl_vec3 bo = vbl_v3_madd(vbl_v3_madd(xc, o->n, y), o->bd, -4.0);
    vbl_photon_beam_eval_result e;
    vbl_photon_beam_eval(vbl_v3(0, 0, 0), o->cd, 10.0, bo, o->bd, 8.0, o->r, &e);
    return e.weight;
}
static void test_line_line_identity(void** state)
{
    (void)state;
    const double angles[] = {1.5, 0.7, 0.2, 0.05};
    for (int i = 0; i < 4; ++i) {
        octx o = {vbl_v3(1, 0, 0), vbl_v3(cos(angles[i]), sin(angles[i]), 0), vbl_v3(0, 0, 0), 0.03};
        o.n = vbl_v3_normalize(vbl_v3_cross(o.bd, o.cd));
        double integral = vbl_quad_adaptive(weight_at, &o, -o.r, o.r, 1e-14, 1e-12);
        assert_true(fabs(integral * sin(angles[i]) - 1.0) < 1e-9);
    }
}

/* Collimated bundle: N beams along +z, origins uniform on a disc of radius a at z = 0, total
 * power Phi; camera ray along +x at height z0 and offset y0 through a homogeneous medium. Exact
 * single scattering: sigma_s f(90 deg) Phi / (pi a^2) e^{-sigma_t z0} int_chord e^{-sigma_t u} du. */
typedef struct med { double sigma_t; } med;
static double tr(void* ctx, vbl_vec3 o, vbl_vec3 d, double t)
{
    (void)o;
    (void)d;
    return exp(-((med*)ctx)->sigma_t * t);
}
static void test_collimated_bundle(void** state)
{
    (void)state;
    const double a = 0.5, z0 = 0.7, y0 = 0.2, sig_t = 0.8, sig_s = 0.5, g = 0.3, phi = 2.0, xs = -1.0;
    med m = {sig_t};
    double half = sqrt(a * a - y0 * y0);
    double chord = (exp(-sig_t * (-half - xs)) - exp(-sig_t * (half - xs))) / sig_t; /* camera starts at x = xs */
    double exact = sig_s * vbl_hg_eval(g, 0.0) * phi / (VBL_PI * a * a) * exp(-sig_t * z0) * chord;
    const double rs[] = {0.2, 0.1, 0.05, 0.025};
    double prev = INFINITY;
    for (int k = 0; k < 4; ++k) {
        vbl_rng rng = vbl_rng_make(11, (uint64_t)k, 0);
        vbl_mean_acc acc = {0, 0, 0};
        const int n = 2000;
        for (int rep = 0; rep < 100; ++rep) {
            double est = 0.0;
            for (int b = 0; b < n; ++b) {
                double rr = a * sqrt(vbl_rng_uniform(&rng)), ph = 2 * VBL_PI * vbl_rng_uniform(&rng);
                const vbl_segment cam = vbl_segment_make(vbl_v3(xs, y0, z0), vbl_v3(1, 0, 0), 0.0, 3.0);
                const vbl_segment beam = vbl_segment_make(vbl_v3(rr * cos(ph), rr * sin(ph), 0), vbl_v3(0, 0, 1), 0.0, 2.0);
                est += vbl_photon_beam_estimate(&cam, &beam, rs[k], phi / n, sig_s, g, tr, &m);
            }
            vbl_mean_add(&acc, est);
        }
        double err = fabs(acc.mean - exact) / exact;
        printf("bundle r=%.3f: estimate %.6g +- %.2g, exact %.6g, rel err %.3g\n", rs[k], acc.mean, vbl_mean_stderr(&acc), exact,
               err);
        if (k == 3) assert_true(vbl_mean_check("bundle r=0.025", &acc, exact, 4.0, 0.01 * exact));
        if (k < 2) assert_true(err < prev);
        prev = err;
    }
}

/* Parallel and near-parallel lines: finite, bounded by K(0) len_c / (2 r^2). */
static void test_parallel_finite(void** state)
{
    (void)state;
    const double eps[] = {0.0, 1e-300, 1e-200, 1e-17, 1e-9, 1e-4};
    const double offs[] = {0.0, 1e-3, 0.009, 0.5};
    const double r = 0.01, len_c = 4.0;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 4; ++j)
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                vbl_vec3 bd = vbl_v3_normalize(vbl_v3(sgn, eps[i], 0.5 * eps[i]));
                vbl_photon_beam_eval_result e;
                vbl_photon_beam_eval(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), len_c, vbl_v3(-1, offs[j], 0.3 * offs[j]), bd, 3.0, r, &e);
                assert_true(isfinite(e.weight) && e.weight >= 0.0 && isfinite(e.t_c) && isfinite(e.t_b));
                assert_true(e.weight <= (15.0 / 16.0) * len_c / (2 * r * r) * (1 + 1e-12));
                assert_true(e.t_c >= 0.0 && e.t_c <= len_c && e.t_b >= 0.0 && e.t_b <= 3.0);
                const vbl_segment cam = vbl_segment_make(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 0.0, len_c);
                const vbl_segment beam = vbl_segment_make(vbl_v3(-1, offs[j], 0), bd, 0.0, 3.0);
                double est = vbl_photon_beam_estimate(&cam, &beam, r, 1.0, 1.0, 0.999 * sgn, NULL, NULL);
                assert_true(isfinite(est) && est >= 0.0);
            }
    /* no support: zero lengths, zero width */
    vbl_photon_beam_eval_result e;
    assert_false(vbl_photon_beam_eval(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 0.0, vbl_v3(0, 0, 0), vbl_v3(0, 1, 0), 1.0, 0.1, &e));
    assert_false(vbl_photon_beam_eval(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 1.0, vbl_v3(0, 0, 0), vbl_v3(0, 1, 0), 1.0, 0.0, &e));
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_biweight),
        cmocka_unit_test(test_eq38_interior),
        cmocka_unit_test(test_line_line_identity),
        cmocka_unit_test(test_collimated_bundle),
        cmocka_unit_test(test_parallel_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
