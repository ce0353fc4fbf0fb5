/* The angular line sampler of the surface transports (surface_line_sampler.h) and the samplers
 * built on it (VRL/VBL to a surface point, VSL to a camera segment): chi-square against their own
 * pdf, normalisation, sample/pdf consistency, and a must-fail check (a wrong pdf is rejected). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "quad.h"
#include "surface_test_util.h"
#include "transport/surface/surface_from_volume.h"
#include "transport/surface/surface_line_sampler.h"
#include "transport/surface/surface_vsl.h"

#define NBINS 40
#define NSAMPLES 60000L

typedef double (*pdf_fn)(const vbl_surface_line_sampler* s, double t);

static double true_pdf(const vbl_surface_line_sampler* s, double t) { return vbl_surface_line_pdf(s, t); }
/* Deliberately wrong: the equiangular density (what the sampler draws without its fit). */
static double wrong_pdf(const vbl_surface_line_sampler* s, double t)
{
    double dt = t - s->tp;
    return (t >= s->t0 && t <= s->t1) ? s->h / ((s->phi1 - s->phi0) * (s->h * s->h + dt * dt)) : 0.0;
}

typedef struct qctx { const vbl_surface_line_sampler* s; pdf_fn pdf; } qctx;
static double q_pdf(double t, void* c) { const qctx* q = (const qctx*)c; return q->pdf(q->s, t); }

/* Bins uniform in the mapping angle; returns the chi-square verdict, and checks (counted in *bad)
 * normalisation, domain and consistency of the returned pdf with vbl_surface_line_pdf. */
static int chi2_line(const char* label, const vbl_surface_line_sampler* s, pdf_fn pdf, uint64_t seed, int tests,
                     int* bad)
{
    double edges[NBINS + 1], obs[NBINS] = {0}, expct[NBINS];
    for (int i = 0; i <= NBINS; ++i)
        edges[i] = vbl_clamp(s->tp + s->h * tan(s->phi0 + (s->phi1 - s->phi0) * i / NBINS), s->t0, s->t1);
    edges[0] = s->t0;
    edges[NBINS] = s->t1;
    vbl_rng rng = vbl_rng_make(seed, 3, 0);
    long outside = 0, mismatch = 0;
    for (long k = 0; k < NSAMPLES; ++k) {
        double p;
        double t = vbl_surface_line_sample(s, vbl_rng_uniform(&rng), &p);
        if (!(t >= s->t0 && t <= s->t1) || !(p > 0.0) || !isfinite(p)) {
            ++outside;
            continue;
        }
        double q = vbl_surface_line_pdf(s, t);
        if (!(fabs(p - q) <= 1e-9 * fmax(p, q))) ++mismatch;
        int b = 0;
        while (b + 1 < NBINS && t >= edges[b + 1]) ++b;
        obs[b] += 1.0;
    }
    qctx qc = {s, pdf};
    double total = 0.0;
    for (int i = 0; i < NBINS; ++i) {
        double m = edges[i + 1] > edges[i] ? vbl_quad_adaptive(q_pdf, &qc, edges[i], edges[i + 1], 1e-14, 1e-10) : 0.0;
        total += m;
        expct[i] = NSAMPLES * m;
    }
    printf("     %s: integral %.10f, outside %ld, pdf mismatches %ld\n", label, total, outside, mismatch);
    if (bad) *bad += (fabs(total - 1.0) > 1e-6) + (outside != 0) + (mismatch != 0);
    return vbl_chi2_check(label, obs, expct, NBINS, 0.01, tests);
}

/* Surface point at the origin, normal +z, wo tilted; the VRL configurations of the estimator tests. */
static vbl_surface_vrl vrl_config(int c, double g)
{
    vbl_surface_vrl v;
    v.power = vbl_v3(1, 1, 1);
    v.g = g;
    if (c == 0) { /* crossing near the point (and through the surface plane) */
        v.origin = vbl_v3(-1.5, 0.05, 0.6);
        v.direction = vbl_v3_normalize(vbl_v3(1.5, 0.0, -0.5));
        v.length = 3.0;
    } else if (c == 1) { /* parallel to the surface */
        v.origin = vbl_v3(-2.0, 0.2, 0.3);
        v.direction = vbl_v3(1, 0, 0);
        v.length = 4.0;
    } else { /* far */
        v.origin = vbl_v3(3.0, 4.0, 5.0);
        v.direction = vbl_v3_normalize(vbl_v3(-1.0, 0.2, -0.1));
        v.length = 2.0;
    }
    return v;
}

static void test_line_equiangular(void** state)
{
    (void)state;
    vbl_surface_line_sampler s;
    int bad = 0, ok = 1;
    assert_true(vbl_surface_line_init(&s, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), -1.0, 3.0, vbl_v3(0.5, 0.3, 0), 0.0));
    ok &= chi2_line("equiangular", &s, true_pdf, 1, 3, &bad);
    /* the point on the line: the floored scale keeps a finite density */
    assert_true(vbl_surface_line_init(&s, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), -1.0, 3.0, vbl_v3(0.5, 0, 0), 0.0));
    ok &= chi2_line("equiangular on-line R=0", &s, true_pdf, 2, 3, &bad);
    assert_true(vbl_surface_line_init(&s, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), -1.0, 3.0, vbl_v3(0.5, 0, 0), 0.2));
    ok &= chi2_line("equiangular on-line R=0.2", &s, true_pdf, 3, 3, &bad);
    assert_int_equal(bad, 0);
    assert_true(ok);
    /* no support */
    assert_false(vbl_surface_line_init(&s, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 1.0, 1.0, vbl_v3(0, 1, 0), 0.0));
    double p = 1.0;
    vbl_surface_line_sample(&s, 0.5, &p);
    assert_true(p == 0.0);
}

static void test_vrl_surface_sampler_chi2(void** state)
{
    (void)state;
    const double radii[2] = {0.0, 0.15};
    const double gs[3] = {0.6, -0.4, 0.95};
    int bad = 0, ok = 1, tests = 3 * 3 * 2;
    for (int mi = 0; mi < 3; ++mi) {
        vbl_material m = st_material(mi);
        vbl_surface_point sp;
        vbl_surface_point_init(&sp, vbl_v3(0, 0, 0), vbl_v3(0, 0, 1), vbl_v3_normalize(vbl_v3(0.3, -0.2, 1.0)), &m);
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 2; ++r) {
                vbl_surface_vrl vrl = vrl_config(c, gs[c]);
                vbl_surface_line_sampler s;
                assert_true(vbl_surface_vrl_sampler_init(&s, &sp, &vrl, radii[r]));
                assert_true(s.defensive < 1.0); /* fitted */
                char label[96];
                snprintf(label, sizeof label, "vrl->surface %s config %d R=%g", st_material_name(mi), c, radii[r]);
                ok &= chi2_line(label, &s, true_pdf, 100 + 10 * mi + 2 * c + r, tests, &bad);
            }
    }
    assert_int_equal(bad, 0);
    assert_true(ok);
}

static void test_vsl_camera_sampler_chi2(void** state)
{
    (void)state;
    int bad = 0, ok = 1;
    for (int mi = 0; mi < 3; ++mi) {
        vbl_material m = st_material(mi);
        vbl_surface_vsl vsl = {vbl_v3(0, 0, 0), vbl_v3(0, 0, 1), vbl_v3_normalize(vbl_v3(-0.5, 0.1, 1.0)),
                               vbl_v3(1, 1, 1), 0, 1};
        for (int r = 0; r < 2; ++r) {
            vbl_surface_line_sampler s;
            const vbl_segment cam = {vbl_v3(-3, 0.3, 1.0), vbl_v3_normalize(vbl_v3(1, 0, -0.2)), 0.5, 5.0};
            assert_true(vbl_surface_vsl_camera_sampler_init(&s, &cam, 0.7, &vsl, &m, r ? 0.2 : 0.0));
            char label[96];
            snprintf(label, sizeof label, "vsl->camera %s R=%g", st_material_name(mi), r ? 0.2 : 0.0);
            ok &= chi2_line(label, &s, true_pdf, 300 + 2 * mi + r, 6, &bad);
        }
    }
    assert_int_equal(bad, 0);
    assert_true(ok);
}

/* Must fail: sampling the fitted (Phong, glossy) density but testing against the equiangular pdf. */
static void test_wrong_pdf_must_fail(void** state)
{
    (void)state;
    vbl_material m = st_material(1);
    vbl_surface_point sp;
    vbl_surface_point_init(&sp, vbl_v3(0, 0, 0), vbl_v3(0, 0, 1), vbl_v3_normalize(vbl_v3(0.3, -0.2, 1.0)), &m);
    vbl_surface_vrl vrl = vrl_config(1, 0.6);
    vbl_surface_line_sampler s;
    assert_true(vbl_surface_vrl_sampler_init(&s, &sp, &vrl, 0.0));
    int bad = 0;
    printf("     (the next line must report a rejected fit)\n");
    assert_false(chi2_line("MUST-FAIL wrong pdf", &s, wrong_pdf, 7, 1, &bad));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_line_equiangular),
        cmocka_unit_test(test_vrl_surface_sampler_chi2),
        cmocka_unit_test(test_vsl_camera_sampler_chi2),
        cmocka_unit_test(test_wrong_pdf_must_fail),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
