/* The estimator settings of vbl_render_options reach vrl and vpl through the render context:
 * with the same seed, changing vrl_samples / vrl_prune_radius / vrl_long / vrl_connect /
 * vrl.pair_sampler (each non-default sampler) changes the
 * volume_from_volume layer, vpl_clamp_distance darkens it pixel by pixel (it only lowers
 * 1/w^2 and draws the same random numbers), and pruned vrl (options.vrl.prune_radius > 0, the
 * scene-file route) still agrees with pt (block z-test as in test_transport_agreement; run with
 * the argument `agree`, labelled slow). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render_test_util.h"
#include "transport/path_tracing/pt.h"
#include "transport/virtual_lights/vpl.h"
#include "transport/virtual_lights/vrl.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

#define Z_CRIT 5.5

static vbl_volume* g_box;

static vbl_scene* box_point(int res)
{
    vbl_camera cam = rt_camera(vbl_v3(0.2, -4.0, 0.3), vbl_v3(0, 0, 0), 36.0, res, res);
    vbl_scene* s = tt_scene(&cam);
    g_box = rt_make_box(9, 0.25, vbl_v3(-1, -1, -1));
    assert_int_equal(vbl_scene_add_medium(s, g_box, 1.2, vbl_v3(0.8, 0.7, 0.6), 0.3, NULL), VBL_SUCCESS);
    tt_add_point(s, vbl_v3(0.4, 0.3, 1.6), 10.0);
    return s;
}

/* Mean of volume_from_volume (R, G, B) of one render; *max_gain receives max over pixels of
 * (this - other) when `other` is given. */
static double from_volume_mean(const vbl_scene* scene, const vbl_render_options* o, float* keep)
{
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, o, &film), VBL_SUCCESS);
    assert_true(tt_film_finite(film));
    const float* p = vbl_film_layer_rgb(film, "volume_from_volume");
    assert_non_null(p);
    int n = vbl_film_width(film) * vbl_film_height(film) * 3;
    double m = 0.0;
    for (int i = 0; i < n; ++i) m += p[i];
    if (keep) memcpy(keep, p, sizeof(float) * n);
    vbl_film_release(film);
    return m / n;
}

static void test_options_change_estimators(void** state)
{
    (void)state;
    vbl_scene* scene = box_point(8);
    vbl_render_options o = tt_options(1, 1, 200, 5);
    o.method = VBL_RENDER_VRL;
    o.vrl.select = 0; /* every VRL: the pruning roulette acts only there (no light tree) */
    double base = from_volume_mean(scene, &o, NULL);
    assert_true(base > 0.0);
    vbl_render_options v = o;
    v.vrl.select = VBL_VRL_SELECT_DEFAULT;
    assert_true(from_volume_mean(scene, &v, NULL) != base);
    v = o;
    v.vrl.samples = 3;
    assert_true(from_volume_mean(scene, &v, NULL) != base);
    v = o;
    v.vrl.prune_radius = 0.05;
    v.vrl.prune_min_probability = 0.3;
    assert_true(from_volume_mean(scene, &v, NULL) != base);
    v = o;
    v.vrl.long_vrls = 1;
    assert_true(from_volume_mean(scene, &v, NULL) != base);
    v = o;
    v.vrl.connect = 1;
    assert_true(from_volume_mean(scene, &v, NULL) != base);
    for (int ps = VBL_VRL_PAIR_CAMERA; ps <= VBL_VRL_PAIR_FREE_FLIGHT; ++ps) {
        v = o;
        v.vrl.pair_sampler = (vbl_vrl_pair_sampler)ps;
        assert_true(from_volume_mean(scene, &v, NULL) != base);
    }

    /* vpl clamping: every pixel darker or equal, the image clearly darker */
    static float a[8 * 8 * 3], b[8 * 8 * 3];
    o.method = VBL_RENDER_VPL;
    double unclamped = from_volume_mean(scene, &o, a);
    o.vpl.clamp_distance = 1.0;
    double clamped = from_volume_mean(scene, &o, b);
    printf("vpl from_volume mean: unclamped %.5g, clamp 1.0: %.5g\n", unclamped, clamped);
    for (int i = 0; i < 8 * 8 * 3; ++i) assert_true(b[i] <= a[i] * (1.0f + 1e-6f) + 1e-12f);
    assert_true(clamped < 0.95 * unclamped);
    vbl_scene_release(scene);
    vt_free(g_box);
}

static void test_pruned_vrl_agrees_with_pt(void** state)
{
    (void)state;
    vbl_scene* scene = box_point(12);
    tt_stats ref, got;
    vbl_render_options o = tt_options(4, 32, 0, 101);
    tt_replicate(scene, &vbl_estimator_pt, &o, 10, 4, &ref);
    o = tt_options(2, 1, 400, 202);
    o.vrl.prune_radius = 0.1;
    o.vrl.prune_min_probability = 0.05;
    o.vrl.samples = 2;
    tt_replicate(scene, &vbl_estimator_vrl, &o, 10, 4, &got);
    assert_true(ref.finite && got.finite);
    double image_z = 0.0;
    double z = tt_compare(&ref, &got, 1.0, &image_z, "box/point vrl pruned via options");
    assert_true(got.image_mean[1] > 0.0);
    assert_true(z < Z_CRIT);
    vbl_scene_release(scene);
    vt_free(g_box);
}

/* No argument: the quick deterministic checks; "agree": the pt agreement render (label slow). */
int main(int argc, char** argv)
{
    if (argc > 1 && !strcmp(argv[1], "agree")) {
        const struct CMUnitTest slow[] = {cmocka_unit_test(test_pruned_vrl_agrees_with_pt)};
        return cmocka_run_group_tests(slow, NULL, NULL);
    }
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_options_change_estimators)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
