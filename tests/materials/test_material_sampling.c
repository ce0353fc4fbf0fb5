/* Material sampling: chi-square of sampled directions against vbl_material_pdf (cells in
 * (cos angle to the lobe axis, azimuth) plus one cell for rejected draws, so the acceptance rate
 * is tested too), pdf mass <= 1 == acceptance probability, sample/eval/pdf consistency, must-fail
 * checks, and finite results at extreme inputs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "material_test_util.h"

#define NU 20
#define NPHI 12
#define NCELLS (NU * NPHI + 1) /* + rejected draws */
#define NSAMPLES 200000
#define NPILOT 20000

typedef struct sample_case {
    vbl_material_type type;
    double kd, ks, exponent, roughness, theta_o;
} sample_case;

static const sample_case kCases[] = {
    {VBL_MATERIAL_LAMBERT, 0.8, 0.0, 0.0, 0.0, 30.0},
    {VBL_MATERIAL_LAMBERT, 0.8, 0.0, 0.0, 0.0, 88.0},
    {VBL_MATERIAL_PHONG, 0.3, 0.6, 0.0, 0.0, 40.0},
    {VBL_MATERIAL_PHONG, 0.3, 0.6, 1.0, 0.0, 0.0},
    {VBL_MATERIAL_PHONG, 0.3, 0.6, 1.0, 0.0, 60.0},
    {VBL_MATERIAL_PHONG, 0.3, 0.6, 60.0, 0.0, 45.0},
    {VBL_MATERIAL_PHONG, 0.3, 0.6, 60.0, 0.0, 87.0},
    {VBL_MATERIAL_PHONG, 0.0, 0.9, 100.0, 0.0, 20.0},
    {VBL_MATERIAL_PHONG, 0.0, 0.9, 100.0, 0.0, 89.0},
    {VBL_MATERIAL_PHONG, 0.1, 0.9, 1000.0, 0.0, 0.0},
    {VBL_MATERIAL_PHONG, 0.1, 0.9, 1000.0, 0.0, 85.0},
    {VBL_MATERIAL_GGX, 0.5, 0.04, 0.0, 0.05, 0.0},
    {VBL_MATERIAL_GGX, 0.5, 0.04, 0.0, 0.05, 45.0},
    {VBL_MATERIAL_GGX, 0.0, 1.0, 0.0, 0.05, 89.0},
    {VBL_MATERIAL_GGX, 0.4, 0.5, 0.0, 0.3, 30.0},
    {VBL_MATERIAL_GGX, 0.4, 0.5, 0.0, 0.3, 86.0},
    {VBL_MATERIAL_GGX, 0.0, 1.0, 0.0, 0.3, 60.0},
    {VBL_MATERIAL_GGX, 0.4, 0.5, 0.0, 1.0, 10.0},
    {VBL_MATERIAL_GGX, 0.0, 1.0, 0.0, 1.0, 88.0},
    {VBL_MATERIAL_GGX, 0.2, 0.9, 0.0, 0.001, 50.0},
};
#define NCASES ((int)(sizeof kCases / sizeof kCases[0]))

typedef struct setup {
    vbl_material m;
    vbl_vec3 n, wo;
    mt_frame frame;
    double edges[NU + 1];
} setup;

static int cmp_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static void rng3(vbl_rng* r, double* u)
{
    for (int k = 0; k < 3; ++k) u[k] = vbl_rng_uniform(r);
}

/* Cell edges in u = cos(angle to the lobe axis): quantiles of an independent pilot run, so every
 * cell holds ~1/NU of the samples however sharp the lobe. */
static setup make_setup(const sample_case* c, int index)
{
    setup s;
    s.m = mt_material(c->type, c->kd, c->ks, c->exponent, c->roughness);
    s.n = mt_normal();
    s.wo = mt_wo(s.n, c->theta_o, 0.3 + index);
    s.frame = mt_frame_make(mt_axis(&s.m, s.n, s.wo), s.n);
    static double us[NPILOT];
    int k = 0;
    vbl_rng rng = vbl_rng_make(99, 5, (uint64_t)index);
    for (int i = 0; i < NPILOT; ++i) {
        double u[3], pdf, phi;
        vbl_vec3 wi, f;
        rng3(&rng, u);
        if (vbl_material_sample(&s.m, s.n, s.wo, u[0], u[1], u[2], &wi, &pdf, &f)) mt_coords(&s.frame, wi, &us[k++], &phi);
    }
    qsort(us, (size_t)k, sizeof us[0], cmp_double);
    s.edges[0] = -1.0;
    s.edges[NU] = 1.0;
    for (int i = 1; i < NU; ++i) s.edges[i] = fmax(s.edges[i - 1], us[(size_t)i * (size_t)k / NU]);
    return s;
}

static int cell_of(const setup* s, vbl_vec3 w)
{
    double u, phi;
    mt_coords(&s->frame, w, &u, &phi);
    int lo = 0, hi = NU - 1; /* last edge <= u */
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (s->edges[mid] <= u) lo = mid;
        else hi = mid - 1;
    }
    int p = (int)((phi + VBL_PI) / (2.0 * VBL_PI) * NPHI);
    p = p < 0 ? 0 : (p >= NPHI ? NPHI - 1 : p);
    return lo * NPHI + p;
}

/* Expected counts: NSAMPLES * scale * integral of the pdf over each cell; the last cell gets
 * the rest (rejections), clamped at 0. Returns the pdf's total mass (times scale). */
static double expected_counts(const setup* s, double scale, double* expct)
{
    mt_ctx ctx = {&s->m, s->n, s->wo, scale};
    double mass = 0.0;
    for (int i = 0; i < NU; ++i) {
        for (int p = 0; p < NPHI; ++p) {
            double phi0 = -VBL_PI + 2.0 * VBL_PI * p / NPHI, phi1 = -VBL_PI + 2.0 * VBL_PI * (p + 1) / NPHI;
            double cm = mt_cell_integral(&s->frame, mt_pdf_fn, &ctx, s->edges[i], s->edges[i + 1], phi0, phi1, 2, 2).x;
            expct[i * NPHI + p] = NSAMPLES * cm;
            mass += cm;
        }
    }
    expct[NU * NPHI] = NSAMPLES * fmax(0.0, 1.0 - mass);
    return mass;
}

/* Draws NSAMPLES, fills the observed counts and checks each accepted sample against eval/pdf. */
static int draw(const setup* s, int index, double* obs, double* worst_f, double* worst_pdf)
{
    vbl_rng rng = vbl_rng_make(2026, 6, (uint64_t)index);
    int accepted = 0;
    for (int i = 0; i < NCELLS; ++i) obs[i] = 0.0;
    for (int i = 0; i < NSAMPLES; ++i) {
        double u[3], pdf = -1.0;
        vbl_vec3 wi, f;
        rng3(&rng, u);
        if (!vbl_material_sample(&s->m, s->n, s->wo, u[0], u[1], u[2], &wi, &pdf, &f)) {
            obs[NU * NPHI] += 1.0;
            continue;
        }
        ++accepted;
        assert_true(isfinite(pdf) && pdf > 0.0 && isfinite(f.x) && isfinite(f.y) && isfinite(f.z));
        assert_true(fabs(vbl_v3_length(wi) - 1.0) < 1e-12 && vbl_v3_dot(s->n, wi) > 0.0);
        vbl_vec3 fe = vbl_material_eval(&s->m, s->n, s->wo, wi);
        double pe = vbl_material_pdf(&s->m, s->n, s->wo, wi);
        double df = fmax(fabs(f.x - fe.x), fmax(fabs(f.y - fe.y), fabs(f.z - fe.z))) / fmax(1e-300, vbl_v3_max_component(fe));
        if (vbl_v3_max_component(fe) > 0.0) *worst_f = fmax(*worst_f, df);
        *worst_pdf = fmax(*worst_pdf, fabs(pdf - pe) / pe);
        obs[cell_of(s, wi)] += 1.0;
    }
    return accepted;
}

static void test_material_chi2(void** state)
{
    (void)state;
    int all_ok = 1;
    double worst_p = 1.0, worst_f = 0.0, worst_pdf = 0.0, worst_rate = 0.0;
    static double obs[NCELLS], expct[NCELLS];
    for (int c = 0; c < NCASES; ++c) {
        setup s = make_setup(&kCases[c], c);
        double mass = expected_counts(&s, 1.0, expct);
        int accepted = draw(&s, c, obs, &worst_f, &worst_pdf);
        char label[96];
        snprintf(label, sizeof label, "%s kd=%g ks=%g n=%g a=%g theta_o=%g", kCases[c].type == VBL_MATERIAL_LAMBERT ? "lambert"
                 : kCases[c].type == VBL_MATERIAL_PHONG ? "phong" : "ggx", kCases[c].kd, kCases[c].ks,
                 kCases[c].exponent, kCases[c].roughness, kCases[c].theta_o);
        all_ok &= vbl_chi2_check(label, obs, expct, NCELLS, 0.01, NCASES);
        vbl_chi2_result r = vbl_chi2_compute(obs, expct, NCELLS, 5.0);
        worst_p = fmin(worst_p, r.p_value);
        /* pdf mass <= 1 and equal to the acceptance probability (binomial, 4.5 sigma) */
        double rate = (double)accepted / NSAMPLES, sigma = sqrt(fmax(mass * (1.0 - mass), 1e-12) / NSAMPLES);
        double dev = fmax(0.0, fabs(rate - mass) - 2e-6) / sigma;
        printf("     pdf mass %.7f acceptance %.7f (%.2f sigma)\n", mass, rate, dev);
        worst_rate = fmax(worst_rate, dev);
        assert_true(mass <= 1.0 + 1e-6);
        assert_true(fabs(rate - mass) <= 4.5 * sigma + 2e-6); /* + quadrature error */
        /* nothing is rejected for Lambert, nor for Phong at normal incidence (cos alpha = cos theta_i) */
        if (kCases[c].type == VBL_MATERIAL_LAMBERT || (kCases[c].type == VBL_MATERIAL_PHONG && kCases[c].theta_o == 0.0))
            assert_true(fabs(mass - 1.0) < 1e-6);
    }
    printf("materials: worst chi-square p = %.4g, worst acceptance deviation %.2f sigma, worst |f - eval| %.3g, "
           "worst |pdf - pdf()| / pdf %.3g\n", worst_p, worst_rate, worst_f, worst_pdf);
    assert_true(worst_f < 1e-12);
    assert_true(worst_pdf < 1e-9);
    assert_true(all_ok);
}

/* The harness must reject: (a) the pdf times 1.1, (b) the pdf renormalised to ignore the
 * rejected draws, (c) GGX samples of roughness 0.3 against the roughness 0.33 pdf. */
static void test_material_chi2_detects_wrong_pdf(void** state)
{
    (void)state;
    static double obs[NCELLS], expct[NCELLS];
    double wf = 0.0, wp = 0.0;
    const sample_case phong = {VBL_MATERIAL_PHONG, 0.3, 0.6, 60.0, 0.0, 70.0};
    setup s = make_setup(&phong, 100);
    draw(&s, 100, obs, &wf, &wp);
    expected_counts(&s, 1.1, expct);
    assert_false(vbl_chi2_check("phong pdf x 1.1 (must fail)", obs, expct, NCELLS, 0.01, 1));
    double mass = expected_counts(&s, 1.0, expct);
    for (int i = 0; i < NCELLS - 1; ++i) expct[i] /= mass;
    expct[NCELLS - 1] = 0.0;
    assert_false(vbl_chi2_check("phong pdf ignoring rejection (must fail)", obs, expct, NCELLS, 0.01, 1));
    const sample_case ggx = {VBL_MATERIAL_GGX, 0.2, 0.5, 0.0, 0.3, 45.0};
    setup g = make_setup(&ggx, 101);
    draw(&g, 101, obs, &wf, &wp);
    g.m.roughness = 0.33;
    expected_counts(&g, 1.0, expct);
    assert_false(vbl_chi2_check("ggx a=0.3 vs pdf a=0.33 (must fail)", obs, expct, NCELLS, 0.01, 1));
}

/* Extreme inputs: grazing and below-surface wo, u at 0 and 1, tiny and unit roughness, exponent
 * 0 and 1e6: no NaN/Inf, a sample is either rejected or consistent with eval/pdf. */
static void test_material_extremes(void** state)
{
    (void)state;
    vbl_material ms[] = {mt_material(VBL_MATERIAL_LAMBERT, 1.0, 0.0, 0.0, 0.0),
                         mt_material(VBL_MATERIAL_PHONG, 0.0, 1.0, 0.0, 0.0),
                         mt_material(VBL_MATERIAL_PHONG, 0.5, 0.5, 1e6, 0.0),
                         mt_material(VBL_MATERIAL_GGX, 1.0, 0.0, 0.0, 1e-3),
                         mt_material(VBL_MATERIAL_GGX, 0.0, 1.0, 0.0, 1e-9), /* below the valid range */
                         mt_material(VBL_MATERIAL_GGX, 0.0, 0.0, 0.0, 1.0)};
    const double us[] = {0.0, 1e-300, 1e-12, 0.5, 1.0 - 1e-12, nextafter(1.0, 0.0), 1.0};
    const double thetas[] = {0.0, 1e-9, 45.0, 89.999999, 90.0 - 1e-12, 90.0, 120.0};
    vbl_vec3 n = mt_normal();
    for (size_t k = 0; k < sizeof ms / sizeof ms[0]; ++k) {
        for (size_t t = 0; t < sizeof thetas / sizeof thetas[0]; ++t) {
            vbl_vec3 wo = mt_wo(n, thetas[t], 1.0);
            vbl_vec3 md = vbl_material_max_direction(&ms[k], n, wo);
            assert_true(isfinite(md.x) && isfinite(md.y) && isfinite(md.z) && fabs(vbl_v3_length(md) - 1.0) < 1e-9);
            vbl_vec3 mc = vbl_material_max_in_cone(&ms[k], n, wo, md, cos(0.1));
            assert_true(isfinite(mc.x) && mc.x >= 0.0);
            for (size_t a = 0; a < sizeof us / sizeof us[0]; ++a)
                for (size_t b = 0; b < sizeof us / sizeof us[0]; ++b)
                    for (size_t c = 0; c < sizeof us / sizeof us[0]; ++c) {
                        vbl_vec3 wi, f;
                        double pdf;
                        if (!vbl_material_sample(&ms[k], n, wo, us[a], us[b], us[c], &wi, &pdf, &f)) continue;
                        assert_true(vbl_v3_dot(n, wo) > 0.0);
                        assert_true(isfinite(pdf) && pdf > 0.0 && isfinite(f.x) && isfinite(f.y) && isfinite(f.z));
                        assert_true(isfinite(wi.x) && isfinite(wi.y) && isfinite(wi.z) && vbl_v3_dot(n, wi) > 0.0);
                        double pe = vbl_material_pdf(&ms[k], n, wo, wi);
                        assert_true(fabs(pe - pdf) <= 1e-9 * pdf);
                        vbl_vec3 fe = vbl_material_eval(&ms[k], n, wo, wi);
                        if (!(isfinite(fe.x) && fabs(fe.x - f.x) <= 1e-9 * fmax(f.x, 1e-300)))
                            printf("k=%zu t=%zu u=%g %g %g f=%.17g eval=%.17g\n", k, t, us[a], us[b], us[c], f.x, fe.x);
                        assert_true(isfinite(fe.x) && fabs(fe.x - f.x) <= 1e-9 * fmax(f.x, 1e-300));
                    }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_material_chi2),
        cmocka_unit_test(test_material_chi2_detects_wrong_pdf),
        cmocka_unit_test(test_material_extremes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
