/* Isotropic media take the analytic path in the VBL sampler and kernel (sampling/beam_light_pair.h):
 * with g_light = g_camera = 0 stage 2 is uniform in the angle (no cone maxima) and the VSL
 * kernel is geometry / (4 pi)^2 (no quadrature). The general path at g = 1e-12 (HG then differs
 * from 1 / (4 pi) by ~1e-12 relative) must give the same samples, densities and kernel values to
 * 1e-8, and a `vbl` render of an isotropic box the same image statistics. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/rng.h"
#include "render_test_util.h"
#include "sampling/beam_light_pair.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

static vbl_vec3 rand_dir(vbl_rng* r)
{
    double z = 2.0 * vbl_rng_uniform(r) - 1.0, phi = 2.0 * VBL_PI * vbl_rng_uniform(r);
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return vbl_v3(s * cos(phi), s * sin(phi), z);
}

static int close_rel(double a, double b, double tol) { return fabs(a - b) <= tol * fmax(fabs(a), fabs(b)) + 1e-300; }

static void test_pair_and_kernel_match_general_path(void** state)
{
    (void)state;
    vbl_rng rng = vbl_rng_make(42, 0, 0);
    int compared = 0;
    for (int trial = 0; trial < 200; ++trial) {
        vbl_vec3 co = vbl_v3(vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng));
        vbl_vec3 lo = vbl_v3(2 * vbl_rng_uniform(&rng), 2 * vbl_rng_uniform(&rng) - 1, vbl_rng_uniform(&rng));
        vbl_vec3 cd = rand_dir(&rng), ld = rand_dir(&rng);
        double R = trial % 4 == 0 ? 0.0 : 0.5 * vbl_rng_uniform(&rng);
        double len_c = 0.5 + 3 * vbl_rng_uniform(&rng), len_l = 0.2 + 2 * vbl_rng_uniform(&rng);
        vbl_beam_light_pair iso, gen;
        int a = vbl_beam_light_pair_init(&iso, co, cd, 0.0, len_c, lo, ld, 0.0, len_l, 0.0, 0.0, R);
        int b = vbl_beam_light_pair_init(&gen, co, cd, 0.0, len_c, lo, ld, 0.0, len_l, 1e-12, 1e-12, R);
        assert_int_equal(a, b);
        assert_true(iso.isotropic && !gen.isotropic);
        if (!a) continue;
        for (int k = 0; k < 8; ++k) {
            double x1 = vbl_rng_uniform(&rng), x2 = vbl_rng_uniform(&rng);
            vbl_beam_light_pair_sample si, sg;
            int di = vbl_beam_light_pair_draw(&iso, x1, x2, &si), dg = vbl_beam_light_pair_draw(&gen, x1, x2, &sg);
            assert_int_equal(di, dg);
            if (!di) continue;
            if (!(close_rel(si.u, sg.u, 1e-8) && close_rel(si.v, sg.v, 1e-8) && close_rel(si.pdf, sg.pdf, 1e-8)))
                printf("trial %d: u %.12g/%.12g v %.12g/%.12g pdf %.12g/%.12g\n", trial, si.u, sg.u, si.v, sg.v, si.pdf,
                       sg.pdf);
            assert_true(close_rel(si.u, sg.u, 1e-8) && close_rel(si.v, sg.v, 1e-8));
            assert_true(close_rel(si.pdf, sg.pdf, 1e-8));
            assert_true(close_rel(vbl_beam_light_pair_density(&iso, si.u, si.v), si.pdf, 1e-9));
            double uq = len_c * vbl_rng_uniform(&rng);
            assert_true(close_rel(vbl_beam_light_pair_conditional_pdf(&iso, si.v, uq), vbl_beam_light_pair_conditional_pdf(&gen, si.v, uq),
                                  1e-8));
            vbl_vec3 xc = vbl_v3_madd(co, cd, si.u), xl = vbl_v3_madd(lo, ld, si.v);
            double ki = vbl_vsl_kernel(xc, cd, 0.0, xl, ld, 0.0, R, 16, 0.3, 0.7);
            double kg = vbl_vsl_kernel(xc, cd, 1e-12, xl, ld, 1e-12, R, 16, 0.3, 0.7);
            assert_true(isfinite(ki) && ki >= 0.0);
            assert_true(close_rel(ki, kg, 1e-8));
            compared++;
        }
    }
    printf("isotropic vs general path: %d samples compared\n", compared);
    assert_true(compared > 1000);
}

/* vbl renders of an isotropic box: g = 0 (analytic path) and g = 1e-12 (general path) draw the
 * same random numbers and so give the same image up to rounding. */
static void test_render_unchanged(void** state)
{
    (void)state;
    double sums[2];
    for (int k = 0; k < 2; ++k) {
        vbl_camera cam = rt_camera(vbl_v3(0.2, -4, 0.3), vbl_v3(0.125, 0.125, 0.125), 40.0, 8, 8);
        vbl_scene* s = tt_scene(&cam);
        vbl_volume* vol = rt_make_box(9, 0.25, vbl_v3(-1, -1, -1));
        assert_int_equal(vbl_scene_add_medium(s, vol, 1.0, vbl_v3(0.9, 0.9, 0.9), k == 0 ? 0.0 : 1e-12, NULL),
                         VBL_SUCCESS);
        tt_add_point(s, vbl_v3(0.4, 0.3, 1.6), 10.0);
        vbl_render_options o = tt_options(2, 1, 40, 900);
        o.method = VBL_RENDER_VBL;
        o.beam_lights.single_scattering = 1;
        vbl_film* f = NULL;
        assert_int_equal(vbl_render(s, &o, &f), VBL_SUCCESS);
        const float* p = vbl_film_layer_rgb(f, "volume_from_volume");
        assert_non_null(p);
        double sum = 0.0;
        for (int i = 0; i < 3 * 64; ++i) sum += p[i];
        sums[k] = sum;
        vbl_film_release(f);
        vbl_scene_release(s);
        vt_free(vol);
    }
    printf("vbl isotropic render: analytic %.9g, general %.9g\n", sums[0], sums[1]);
    assert_true(sums[0] > 0.0);
    assert_true(close_rel(sums[0], sums[1], 1e-4));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pair_and_kernel_match_general_path),
        cmocka_unit_test(test_render_unchanged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
