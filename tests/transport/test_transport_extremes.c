/* The extremes every method must survive (issue 18 item 5; docs/readme/render.md "Limits at the
 * extremes"). Each case either agrees with pt within its confidence interval or runs into a
 * documented limit that the test asserts (vbl_render_limits' warning, or vbl_render's refusal):
 *  - limits: vbl_render_limits names the scene and field for |g| > 0.95 with vpl/vrl/vbl/beams
 *    and for radius0 above 0.1 x the media's size, and stays silent for pt and ordinary scenes;
 *  - beams.radius0 below 1e-4 x the media's size is refused (before, 1e-200 and 1e-6 rendered an
 *    exactly black image), at the floor itself the scattered light is not 0;
 *  - g = 0.999, lit from behind: every method's volume_direct agrees with pt (all sample or
 *    evaluate the lobe exactly for single scattering), and the methods whose multiple
 *    scattering misses the lobe are the ones that warn. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/render_internal.h"
#include "render/render_limits.h"
#include "render_test_util.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

static const vbl_render_method methods[5] = {VBL_RENDER_PT, VBL_RENDER_VPL, VBL_RENDER_VRL, VBL_RENDER_VBL,
                                             VBL_RENDER_BEAMS};

/* The box [-1, 1]^3 of density `scale` (falling to 0 over one more voxel of 0.25: the media's
 * bounding sphere has diameter 2 sqrt(3) 1.25 = 4.33), albedo 0.8, seen from -y. */
static vbl_scene* box_scene(double scale, double g, int res, vbl_volume** vol)
{
    vbl_camera cam = rt_camera(vbl_v3(0.2, -4, 0.3), vbl_v3(0.125, 0.125, 0.125), 40.0, res, res);
    vbl_scene* s = tt_scene(&cam);
    *vol = rt_make_box(9, 0.25, vbl_v3(-1, -1, -1));
    assert_int_equal(vbl_scene_add_medium(s, *vol, scale, vbl_v3(0.8, 0.8, 0.8), g, NULL), VBL_SUCCESS);
    return s;
}

static void test_limit_messages(void** state)
{
    (void)state;
    vbl_volume *vol, *vol2;
    vbl_scene* s = box_scene(1.0, 0.999, 8, &vol);
    vbl_scene* plain = box_scene(1.0, 0.95, 8, &vol2);
    tt_add_distant(s, vbl_v3(0, 0, -1), 1.0);
    tt_add_distant(plain, vbl_v3(0, 0, -1), 1.0);
    const double d = vbl_limits_media_diameter(s);
    assert_true(fabs(d / (2.0 * sqrt(3.0) * 1.25) - 1.0) < 0.01);
    char msg[2048];
    vbl_render_options o = tt_options(1, 1, 10, 1);
    for (int m = 0; m < 5; ++m) {
        o.method = methods[m];
        int n = vbl_render_limits(s, &o, msg, sizeof msg);
        printf("%s: %d %s", vbl_render_method_name(o.method), n, msg);
        assert_int_equal(n, m == 0 ? 0 : 1);
        if (m > 0) assert_non_null(strstr(msg, "media[0] phase g = 0.999"));
        assert_int_equal(vbl_render_limits(plain, &o, msg, sizeof msg), 0); /* |g| = 0.95 is inside */
        assert_string_equal(msg, "");
    }
    /* radius0: beams' above 0.1 d for beams (and vbl with beam single scattering), vbl's for vbl */
    o.beams.radius0 = 0.11 * d;
    o.method = VBL_RENDER_BEAMS;
    assert_int_equal(vbl_render_limits(plain, &o, msg, sizeof msg), 1);
    assert_non_null(strstr(msg, "beams.radius0"));
    o.method = VBL_RENDER_VBL;
    assert_int_equal(vbl_render_limits(plain, &o, msg, sizeof msg), 0); /* equiangular single scattering */
    o.beam_lights.single_scattering = VBL_SINGLE_SCATTERING_BEAMS;
    assert_int_equal(vbl_render_limits(plain, &o, msg, sizeof msg), 1);
    o.beam_lights.radius0 = 0.11 * d;
    assert_int_equal(vbl_render_limits(plain, &o, msg, sizeof msg), 2);
    assert_non_null(strstr(msg, "vbl.radius0"));
    o.beams.radius0 = o.beam_lights.radius0 = 0.09 * d;
    assert_int_equal(vbl_render_limits(plain, &o, msg, sizeof msg), 0);
    /* optically thick (density 1e6: the default kernel's floor 4.3e-4 spans 430 mean free paths):
     * beams and vbl warn, vpl too (4.3e6 mean free paths across), pt and vrl do not */
    vbl_volume* vol3;
    vbl_scene* thick = box_scene(1e6, 0.3, 8, &vol3);
    tt_add_distant(thick, vbl_v3(0, 0, -1), 1.0);
    vbl_render_options t = tt_options(1, 1, 10, 1);
    for (int m = 0; m < 5; ++m) {
        t.method = methods[m];
        int n = vbl_render_limits(thick, &t, msg, sizeof msg);
        assert_int_equal(n, methods[m] == VBL_RENDER_PT || methods[m] == VBL_RENDER_VRL ? 0 : 1);
        if (n) assert_non_null(strstr(msg, "optically thick"));
    }
    vbl_scene_release(thick);
    vt_free(vol3);
    /* density 1e4: the floor spans 4.3 mean free paths (no warning), an explicit 2e-3 spans 20 */
    thick = box_scene(1e4, 0.3, 8, &vol3);
    tt_add_distant(thick, vbl_v3(0, 0, -1), 1.0);
    t.method = VBL_RENDER_BEAMS;
    assert_int_equal(vbl_render_limits(thick, &t, msg, sizeof msg), 0);
    t.method = VBL_RENDER_VPL; /* 4.3e4 mean free paths across */
    assert_int_equal(vbl_render_limits(thick, &t, msg, sizeof msg), 1);
    t.method = VBL_RENDER_BEAMS;
    t.beams.radius0 = 2e-3;
    assert_int_equal(vbl_render_limits(thick, &t, msg, sizeof msg), 1);
    assert_non_null(strstr(msg, "optically thick"));
    vbl_scene_release(thick);
    vt_free(vol3);
    /* a short buffer is truncated, NUL-terminated, and the count stays */
    o.beam_lights.radius0 = 0.11 * d;
    char tiny[8];
    assert_int_equal(vbl_render_limits(s, &o, tiny, sizeof tiny), 2);
    assert_true(strlen(tiny) < sizeof tiny);
    assert_int_equal(vbl_render_limits(s, &o, NULL, 0), 2);
    vbl_scene_release(s);
    vbl_scene_release(plain);
    vt_free(vol);
    vt_free(vol2);
}

static double layer_mean(const vbl_film* f, const char* name)
{
    const float* p = vbl_film_layer_rgb(f, name);
    int n = vbl_film_width(f) * vbl_film_height(f);
    double sum = 0.0;
    for (int i = 0; p && i < 3 * n; ++i) sum += p[i];
    return sum / (3.0 * n);
}

/* beams.radius0 below 1e-4 x the media's size is refused; at the floor the image is not black. */
static void test_beams_radius_floor(void** state)
{
    (void)state;
    vbl_volume* vol;
    vbl_scene* s = box_scene(1.0, 0.3, 8, &vol);
    tt_add_distant(s, vbl_v3(0, 0, -1), 1.0);
    const double d = vbl_limits_media_diameter(s);
    const double tiny[3] = {1e-200, 1e-6, 0.99e-4 * d};
    vbl_film* f = NULL;
    for (int i = 0; i < 3; ++i) {
        vbl_render_options o = tt_options(1, 1, 200, 3);
        o.method = VBL_RENDER_BEAMS;
        o.beams.radius0 = tiny[i];
        assert_int_equal(vbl_render(s, &o, &f), VBL_ERROR_INVALID_ARGUMENT);
        assert_null(f);
        assert_non_null(strstr(vbl_last_error_message(), "beams.radius0"));
        o.method = VBL_RENDER_VBL; /* vbl uses beams.radius0 only with beam single scattering */
        o.beam_lights.single_scattering = VBL_SINGLE_SCATTERING_BEAMS;
        assert_int_equal(vbl_render(s, &o, &f), VBL_ERROR_INVALID_ARGUMENT);
    }
    printf("refused: %s\n", vbl_last_error_message());
    /* at the floor: beams of 4e-4 units still meet camera rays (8x8 pixels, 2000 paths) */
    vbl_render_options o = tt_options(1, 1, 2000, 3);
    o.method = VBL_RENDER_BEAMS;
    o.beams.radius0 = 1e-4 * d;
    assert_int_equal(vbl_render(s, &o, &f), VBL_SUCCESS);
    assert_true(tt_film_finite(f));
    double direct = layer_mean(f, "volume_direct");
    printf("beams at R0 = %g: volume_direct %g\n", o.beams.radius0, direct);
    assert_true(direct > 0.0);
    vbl_film_release(f);
    vbl_scene_release(s);
    vt_free(vol);
}

static void add_environment(vbl_scene* s, double L)
{
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_ENVIRONMENT;
    l.color = vbl_v3(L, L, L);
    assert_int_equal(vbl_scene_add_light(s, &l), VBL_SUCCESS);
}

/* g = 0.999 under a uniform environment (the sample cloud's sky): the in-scattered light is
 * smooth (int p L dw = L for any g), so volume_direct must agree. Before the single-scattering
 * estimator of vpl/vrl/vbl sampled the phase lobe it found 0.0005 of pt's 0.041 (8x8, K = 3).
 * Multiple scattering through a lobe of width ~ (1 - g) rad stays out of reach of the connection
 * methods: that is the documented limit they warn about. */
static void test_g_near_one(void** state)
{
    (void)state;
    const double gs[2] = {0.999, -0.999};
    for (int k = 0; k < 2; ++k) {
        vbl_volume* vol;
        vbl_scene* s = box_scene(1.0, gs[k], 8, &vol);
        add_environment(s, 0.2);
        tt_stats ref, got;
        vbl_render_options o = tt_options(2, 4, 0, 41 + k);
        tt_replicate(s, vbl_estimator_for(VBL_RENDER_PT), &o, 3, 1, &ref);
        o = tt_options(2, 1, 100, 51 + k);
        o.method = VBL_RENDER_VPL;
        tt_replicate(s, vbl_estimator_for(o.method), &o, 3, 1, &got);
        assert_true(ref.finite && got.finite);
        double z = fabs(ref.image_mean[0] - got.image_mean[0]) /
                   sqrt(ref.image_se[0] * ref.image_se[0] + got.image_se[0] * got.image_se[0]);
        printf("g = %g volume_direct: pt %.5g +- %.2g, vpl %.5g +- %.2g (z %.2f); volume_from_volume pt %.5g, "
               "vpl %.5g\n",
               gs[k], ref.image_mean[0], ref.image_se[0], got.image_mean[0], got.image_se[0], z, ref.image_mean[1],
               got.image_mean[1]);
        assert_true(ref.image_mean[0] > 0.02 && z < 4.0);
        for (int m = 0; m < 5; ++m) {
            o.method = methods[m];
            assert_int_equal(vbl_render_limits(s, &o, NULL, 0), m == 0 ? 0 : 1);
        }
        vbl_scene_release(s);
        vt_free(vol);
    }
}

/* A point light inside a dense heterogeneous sphere (optical depth ~4.3 from the light to the
 * edge, albedo 0.8). Issue 18 reported pt = 0 against 0.0015-0.0083 for the other methods. pt is
 * right in expectation but heavy-tailed here: its camera paths rarely come near the light, so a
 * short render is too dark. Measured (explore runs, 8x8, 8 renders, volume_from_volume): pt 0.132
 * +- 0.0075 at 32 spp, 0.183 +- 0.014 at 256 spp; vpl 0.174 +- 0.015 (200 paths), 0.174 +- 0.011
 * (2000 paths); pt without equiangular NEE 0.164 +- 0.011 at 256 spp. Here, cheaply and framed off
 * the light: pt at 32 spp against vpl and vrl, image means within 4 standard errors. pt takes 16
 * renders: with 4, a draw of its heavy tail decides the test (pt.camera_split on and off agree at
 * 64 renders: volume_from_volume 0.477 +- 0.022 and 0.511 +- 0.026, 2026-12-06). */
static void test_point_light_inside(void** state)
{
    (void)state;
    /* framed off the light: its image (where every method is heavy-tailed) stays out of view.
     * (Until 2026-12-07 the target (0.55, 0, 0.45) left the image in pixel (1, 6); with
     * pixel_focus pt resolved that pixel at 32 spp and vrl's 4 spp read 4.7 sigma low there.) */
    vbl_camera cam = rt_camera(vbl_v3(0.2, -4, 0.3), vbl_v3(0.85, 0, 0.6), 20.0, 8, 8);
    vbl_scene* s = tt_scene(&cam);
    vbl_volume* vol = tt_make_sphere(16, 1.0);
    assert_int_equal(vbl_scene_add_medium(s, vol, 8.0, vbl_v3(0.8, 0.8, 0.8), 0.3, NULL), VBL_SUCCESS);
    tt_add_point(s, vbl_v3(0.05, 0.03, 0.02), 10.0);
    tt_stats pt, vl[2];
    vbl_render_options o = tt_options(2, 32, 0, 73);
    tt_replicate(s, vbl_estimator_for(VBL_RENDER_PT), &o, 16, 2, &pt);
    assert_true(pt.finite && pt.image_mean[1] > 0.0);
    const vbl_render_method m[2] = {VBL_RENDER_VPL, VBL_RENDER_VRL};
    for (int k = 0; k < 2; ++k) {
        /* 4 spp: volume_direct is pt's estimator (pt_camera_classes.h), heavy-tailed with the light
         * inside the medium: 8 samples a pixel (4 renders x 2 passes x 1 spp) gave 0.066 +- 0.004
         * against pt's 0.086 (a typical low draw of a heavy tail; pt at 128 spp: 0.094). 8 renders:
         * since pt.equiangular_camera_samples (2026-12-07) pt's own standard error is 0.00026, and vrl's
         * 4 renders read 0.0180 +- 0.00044 (z 4.3; 8 renders 0.0184 +- 0.0011, 16 0.0194 +- 0.0009) */
        o = tt_options(2, 4, k == 0 ? 200 : 20, 71 + k);
        o.method = m[k];
        tt_replicate(s, vbl_estimator_for(o.method), &o, 8, 2, &vl[k]);
        double image_z;
        tt_compare(&pt, &vl[k], 1.0, &image_z, vbl_render_method_name(o.method));
        /* image means only: single blocks near the light are heavy-tailed for every method */
        assert_true(vl[k].finite && image_z < 4.0);
    }
    vbl_scene_release(s);
    vt_free(vol);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_limit_messages),
        cmocka_unit_test(test_beams_radius_floor),
        cmocka_unit_test(test_g_near_one),
        cmocka_unit_test(test_point_light_inside),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
