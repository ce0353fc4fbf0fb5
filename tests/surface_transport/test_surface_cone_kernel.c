/* The VSL gather kernel over the cone (surface_cone_kernel.h, VBL eq 9): its randomly jittered
 * quadrature is unbiased (mean within 4 standard errors of a brute-force 2D quadrature), R == 0 is
 * the singular integrand exactly, R -> 0 converges to it, and it stays finite and non-negative at
 * w = 0, w << R, grazing angles and g = +-0.999. */
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
#include "transport/surface/surface_cone_kernel.h"

typedef struct pair_case {
    const char* label;
    vbl_surface_lobe a, b;
} pair_case;

static vbl_material g_mat[3];

/* receiver at the origin (normal +z); sender lobes: a phase (VRL point) or a surface VSL. */
static pair_case make_case(int k)
{
    vbl_vec3 n = vbl_v3(0, 0, 1), wo = vbl_v3_normalize(vbl_v3(0.3, -0.2, 1.0));
    vbl_vec3 ny = vbl_v3_normalize(vbl_v3(0.3, 0.1, -1.0)), wiy = vbl_v3_normalize(vbl_v3(0.5, 0.0, -1.0));
    pair_case c;
    switch (k) {
    case 0:
        c.label = "receiver phong60 x phase g=0.7";
        c.a = vbl_surface_lobe_receiver(&g_mat[1], n, wo);
        c.b = vbl_surface_lobe_phase(0.7, vbl_v3_normalize(vbl_v3(0.2, 0.1, -1.0)));
        break;
    case 1:
        c.label = "receiver ggx0.3 x sender lambert";
        c.a = vbl_surface_lobe_receiver(&g_mat[2], n, wo);
        c.b = vbl_surface_lobe_sender(&g_mat[0], ny, wiy);
        break;
    case 2:
        c.label = "receiver lambert x sender phong60";
        c.a = vbl_surface_lobe_receiver(&g_mat[0], n, wo);
        c.b = vbl_surface_lobe_sender(&g_mat[1], ny, wiy);
        break;
    default:
        c.label = "camera phase g=-0.5 x sender ggx0.3";
        c.a = vbl_surface_lobe_phase(-0.5, vbl_v3_normalize(vbl_v3(1.0, 0.0, 0.3)));
        c.b = vbl_surface_lobe_sender(&g_mat[2], ny, wiy);
        break;
    }
    return c;
}

static void setup_materials(void)
{
    for (int i = 0; i < 3; ++i) g_mat[i] = st_material(i);
}

/* sender centres: a thin cone (w = 1, R = 0.3) and the hemisphere (w = 0.1 < R = 0.3) */
static const vbl_vec3 kCentre[2] = {{0.2, -0.1, 0.98}, {0.02, 0.01, 0.098}};

static void test_kernel_unbiased(void** state)
{
    (void)state;
    setup_materials();
    int ok = 1;
    for (int k = 0; k < 4; ++k)
        for (int gi = 0; gi < 2; ++gi) {
            pair_case c = make_case(k);
            vbl_vec3 x = vbl_v3(0, 0, 0), y = kCentre[gi];
            double radius = 0.3;
            double ref = st_cone_reference(&c.a, &c.b, x, y, radius);
            vbl_mean_acc acc = {0, 0, 0};
            vbl_rng rng = vbl_rng_make(77, (uint64_t)k, (uint64_t)gi);
            for (int i = 0; i < 4000; ++i) {
                double j[3] = {vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng)};
                vbl_mean_add(&acc, st_mean3(vbl_surface_cone_kernel(&c.a, &c.b, x, y, radius, 4, j)));
            }
            char label[128];
            snprintf(label, sizeof label, "%s %s", c.label, gi ? "hemisphere" : "thin cone");
            ok &= vbl_mean_check(label, &acc, ref, 4.0, 1e-6 * fabs(ref));
            assert_true(ref > 0.0);
        }
    assert_true(ok);
}

static void test_kernel_r0_and_limit(void** state)
{
    (void)state;
    setup_materials();
    for (int k = 0; k < 4; ++k) {
        pair_case c = make_case(k);
        vbl_vec3 x = vbl_v3(0, 0, 0), y = vbl_v3(0.4, -0.2, 1.5);
        const double j[3] = {0.25, 0.5, 0.75};
        vbl_vec3 omega = vbl_v3_normalize(vbl_v3_sub(x, y));
        double w2 = vbl_v3_dot(vbl_v3_sub(x, y), vbl_v3_sub(x, y));
        vbl_vec3 exact = vbl_v3_scale(vbl_v3_mul(vbl_surface_lobe_eval(&c.a, omega), vbl_surface_lobe_eval(&c.b, omega)),
                                      1.0 / w2);
        vbl_vec3 k0 = vbl_surface_cone_kernel(&c.a, &c.b, x, y, 0.0, 8, j);
        assert_true(fabs(k0.x - exact.x) <= 1e-12 * exact.x && fabs(k0.z - exact.z) <= 1e-12 * exact.z);
        double prev = INFINITY;
        printf("     %s: R -> 0 relative error:", c.label);
        for (int r = 0; r < 4; ++r) {
            double radius = 0.2 * pow(0.1, r);
            double kr = st_mean3(vbl_surface_cone_kernel(&c.a, &c.b, x, y, radius, 64, j));
            double err = fabs(kr / st_mean3(exact) - 1.0);
            printf(" R=%g %.2e", radius, err);
            if (r >= 2) assert_true(err < prev || err < 1e-4); /* falls as R -> 0 */
            prev = err;
        }
        printf("\n");
        assert_true(prev < 1e-3);
    }
}

static void test_kernel_extremes(void** state)
{
    (void)state;
    setup_materials();
    const double j[3] = {0.1, 0.2, 0.3};
    for (int k = 0; k < 4; ++k) {
        pair_case c = make_case(k);
        vbl_vec3 x = vbl_v3(0, 0, 0);
        const vbl_vec3 ys[4] = {{0, 0, 0}, {0, 0, 1e-12}, {1e-9, 0, 0}, {3, 0, 1e-9}};
        for (int i = 0; i < 4; ++i)
            for (int r = 0; r < 3; ++r) {
                double radius = r == 0 ? 0.0 : (r == 1 ? 1e-3 : 0.5);
                vbl_vec3 v = vbl_surface_cone_kernel(&c.a, &c.b, x, ys[i], radius, 16, j);
                assert_true(st_finite3(v) && st_nonneg3(v));
            }
    }
    /* extreme anisotropy */
    vbl_surface_lobe a = vbl_surface_lobe_receiver(&g_mat[1], vbl_v3(0, 0, 1), vbl_v3_normalize(vbl_v3(1, 0, 1e-6)));
    for (int s = -1; s <= 1; s += 2) {
        vbl_surface_lobe b = vbl_surface_lobe_phase(0.999 * s, vbl_v3(1, 0, 0));
        for (int r = 0; r < 3; ++r) {
            vbl_vec3 v = vbl_surface_cone_kernel(&a, &b, vbl_v3(0, 0, 0), vbl_v3(-1, 0, 1e-3), r * 0.05, 16, j);
            assert_true(st_finite3(v) && st_nonneg3(v));
        }
    }
}

/* ---- vbl_surface_lobe_sample: chi-square over the sphere against vbl_surface_lobe_pdf ---- */
#define NC 20
#define NPH 8
#define NLOBE_SAMPLES 200000

typedef struct sph_ctx {
    const vbl_surface_lobe* l;
    vbl_vec3 axis, t, b;
    double c;
} sph_ctx;
static vbl_vec3 sph_dir(const sph_ctx* k, double c, double phi)
{
    double s = sqrt(fmax(0.0, 1.0 - c * c));
    return vbl_v3_add(vbl_v3_scale(k->axis, c), vbl_v3_add(vbl_v3_scale(k->t, s * cos(phi)), vbl_v3_scale(k->b, s * sin(phi))));
}

/* cell edges in cos about the lobe's peak: dense near the peak */
static double c_edge(int i) { double q = (double)i / NC; return 1.0 - 2.0 * q * q; }

static int lobe_chi2(const char* label, const vbl_surface_lobe* l, vbl_vec3 axis, uint64_t seed, int tests)
{
    sph_ctx k = {l, axis, vbl_v3(0, 0, 0), vbl_v3(0, 0, 0), 0.0};
    vbl_v3_basis(axis, &k.t, &k.b);
    double obs[NC * NPH + 1] = {0}, expct[NC * NPH + 1];
    vbl_rng rng = vbl_rng_make(seed, 5, 0);
    long mismatch = 0;
    for (int i = 0; i < NLOBE_SAMPLES; ++i) {
        vbl_vec3 w;
        double p;
        double u0 = vbl_rng_uniform(&rng), u1 = vbl_rng_uniform(&rng), u2 = vbl_rng_uniform(&rng);
        if (!vbl_surface_lobe_sample(l, u0, u1, u2, &w, &p)) {
            obs[NC * NPH] += 1.0; /* no direction drawn: the cell of the missing mass */
            continue;
        }
        double q = vbl_surface_lobe_pdf(l, w);
        if (!(fabs(p - q) <= 1e-9 * fmax(p, q))) ++mismatch;
        double c = vbl_clamp(vbl_v3_dot(w, axis), -1.0, 1.0);
        int ci = 0;
        while (ci + 1 < NC && c < c_edge(ci + 1)) ++ci;
        double phi = atan2(vbl_v3_dot(w, k.b), vbl_v3_dot(w, k.t));
        if (phi < 0.0) phi += 2.0 * VBL_PI;
        int pi = (int)(phi / (2.0 * VBL_PI) * NPH);
        pi = pi < 0 ? 0 : (pi >= NPH ? NPH - 1 : pi);
        obs[ci * NPH + pi] += 1.0;
    }
    double total = 0.0;
    for (int ci = 0; ci < NC; ++ci)
        for (int pi = 0; pi < NPH; ++pi) {
            /* GL16 x GL16 over sub-cells (4 x 2): the pdfs are smooth within a cell up to the horizon kink */
            double m = 0.0;
            const double x16[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
                                   0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499};
            const double w16[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
                                   0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541};
            double c0 = c_edge(ci + 1), c1 = c_edge(ci);
            double p0 = 2.0 * VBL_PI * pi / NPH, p1 = 2.0 * VBL_PI * (pi + 1) / NPH;
            for (int sc = 0; sc < 4; ++sc)
                for (int sp = 0; sp < 2; ++sp) {
                    double a0 = c0 + (c1 - c0) * sc / 4, a1 = c0 + (c1 - c0) * (sc + 1) / 4;
                    double b0 = p0 + (p1 - p0) * sp / 2, b1 = p0 + (p1 - p0) * (sp + 1) / 2;
                    double ha = 0.5 * (a1 - a0), ma = 0.5 * (a1 + a0), hb = 0.5 * (b1 - b0), mb = 0.5 * (b1 + b0);
                    for (int i = 0; i < 16; ++i)
                        for (int j = 0; j < 16; ++j) {
                            double xa = i < 8 ? -x16[7 - i] : x16[i - 8], wa = i < 8 ? w16[7 - i] : w16[i - 8];
                            double xb = j < 8 ? -x16[7 - j] : x16[j - 8], wb = j < 8 ? w16[7 - j] : w16[j - 8];
                            m += wa * wb * ha * hb * vbl_surface_lobe_pdf(l, sph_dir(&k, ma + ha * xa, mb + hb * xb));
                        }
                }
            total += m;
            expct[ci * NPH + pi] = NLOBE_SAMPLES * m;
        }
    expct[NC * NPH] = NLOBE_SAMPLES * fmax(0.0, 1.0 - total);
    printf("     %s: pdf integral %.6f, pdf mismatches %ld, no-direction draws %.0f\n", label, total, mismatch,
           obs[NC * NPH]);
    return vbl_chi2_check(label, obs, expct, NC * NPH + 1, 0.01, tests) && mismatch == 0 && total <= 1.0 + 1e-3;
}

static vbl_vec3 reflect(vbl_vec3 n, vbl_vec3 w) { return vbl_v3_sub(vbl_v3_scale(n, 2.0 * vbl_v3_dot(n, w)), w); }

static void test_lobe_sampling_chi2(void** state)
{
    (void)state;
    setup_materials();
    vbl_vec3 n = vbl_v3_normalize(vbl_v3(0.1, -0.2, 1.0)), w = vbl_v3_normalize(vbl_v3(0.5, 0.2, 0.8));
    int ok = 1;
    for (int mi = 0; mi < 3; ++mi) {
        vbl_surface_lobe r = vbl_surface_lobe_receiver(&g_mat[mi], n, w);
        vbl_surface_lobe s = vbl_surface_lobe_sender(&g_mat[mi], n, w);
        char label[64];
        snprintf(label, sizeof label, "receiver lobe %s", st_material_name(mi));
        ok &= lobe_chi2(label, &r, vbl_v3_scale(reflect(n, w), -1.0), 40 + mi, 7);
        snprintf(label, sizeof label, "sender lobe %s", st_material_name(mi));
        ok &= lobe_chi2(label, &s, reflect(n, w), 50 + mi, 7);
    }
    vbl_surface_lobe ph = vbl_surface_lobe_phase(0.8, w);
    ok &= lobe_chi2("phase lobe g=0.8", &ph, w, 60, 7);
    assert_true(ok);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kernel_unbiased),
        cmocka_unit_test(test_kernel_r0_and_limit),
        cmocka_unit_test(test_kernel_extremes),
        cmocka_unit_test(test_lobe_sampling_chi2),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
