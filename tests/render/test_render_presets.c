/* Quality presets (vbl_render_options_apply_preset): unknown names and bad arguments fail with
 * a message naming the preset, each preset sets method / passes / light paths / radius schedule
 * to valid values that grow in cost from preview to final, fields a preset does not mention are
 * kept, explicit overrides after the preset win, and the preset options render. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_test_util.h"
#include "vbl/vbl.h"

static const char* const presets[] = {"preview", "production", "final"};
enum { PRESET_COUNT = 3 };

static void test_unknown_and_bad_arguments(void** state)
{
    (void)state;
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    vbl_render_options before = o;
    assert_int_equal(vbl_render_options_apply_preset("ultra", &o), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "'ultra'"));
    assert_non_null(strstr(vbl_last_error_message(), "preview"));
    assert_memory_equal(&o, &before, sizeof o); /* untouched on failure */
    assert_int_equal(vbl_render_options_apply_preset("Preview", &o), VBL_ERROR_INVALID_ARGUMENT);
    assert_int_equal(vbl_render_options_apply_preset("", &o), VBL_ERROR_INVALID_ARGUMENT);
    assert_int_equal(vbl_render_options_apply_preset(NULL, &o), VBL_ERROR_INVALID_ARGUMENT);
    assert_int_equal(vbl_render_options_apply_preset("preview", NULL), VBL_ERROR_INVALID_ARGUMENT);
    o.size = sizeof o - 8;
    assert_int_equal(vbl_render_options_apply_preset("preview", &o), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "size"));
}

static void test_each_preset_sets_settings(void** state)
{
    (void)state;
    double cost[PRESET_COUNT];
    for (int i = 0; i < PRESET_COUNT; ++i) {
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
        /* values no preset uses, to see that the preset overwrote them */
        o.method = (vbl_render_method)99;
        o.passes = -5;
        o.spp = -5;
        o.light_paths = -5;
        o.beam_lights.alpha = -1.0;
        o.beam_lights.radius0 = -1.0;
        /* fields presets leave alone */
        o.seed = 1234;
        o.threads = 3;
        o.time_limit = 7.5;
        o.max_bounces = 9;
        o.first_pass = 4;
        assert_int_equal(vbl_render_options_apply_preset(presets[i], &o), VBL_SUCCESS);
        vbl_render_method round_trip = (vbl_render_method)99;
        assert_int_equal(vbl_render_method_parse(vbl_render_method_name(o.method), &round_trip), VBL_SUCCESS);
        assert_int_equal(round_trip, o.method); /* a method this build knows */
        assert_true(o.passes >= 1);
        assert_true(o.spp >= 1);
        assert_true(o.light_paths >= 0);
        assert_true(o.beam_lights.alpha > 0.0 && o.beam_lights.alpha < 1.0);
        assert_true(o.beam_lights.radius0 >= 0.0);
        if (o.method != VBL_RENDER_PT) assert_true(o.light_paths >= 1);
        assert_int_equal(o.seed, 1234);
        assert_int_equal(o.threads, 3);
        assert_true(o.time_limit == 7.5);
        assert_int_equal(o.max_bounces, 9);
        assert_int_equal(o.first_pass, 4);
        cost[i] = (double)o.passes * o.spp * (o.method == VBL_RENDER_PT ? 1.0 : (double)o.light_paths);
    }
    /* more work from preview to production to final */
    assert_true(cost[0] < cost[1]);
    assert_true(cost[1] < cost[2]);
}

static void test_overrides_after_preset_win(void** state)
{
    (void)state;
    for (int i = 0; i < PRESET_COUNT; ++i) {
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
        assert_int_equal(vbl_render_options_apply_preset(presets[i], &o), VBL_SUCCESS);
        vbl_render_options preset = o;
        o.passes = preset.passes + 3;
        o.light_paths = preset.light_paths + 7;
        o.method = preset.method == VBL_RENDER_VRL ? VBL_RENDER_VPL : VBL_RENDER_VRL;
        o.beam_lights.alpha = 0.55;
        assert_int_equal(o.passes, preset.passes + 3);
        assert_int_equal(o.light_paths, preset.light_paths + 7);
        assert_true(o.beam_lights.alpha == 0.55);
        /* the same preset applied again restores its values (it is a function of the name only) */
        assert_int_equal(vbl_render_options_apply_preset(presets[i], &o), VBL_SUCCESS);
        assert_memory_equal(&o, &preset, sizeof o);
    }
}

static void test_preset_options_render(void** state)
{
    (void)state;
    char dir[256], path[512];
    rt_make_temp_dir(dir);
    rt_write_file(dir, "scene.json",
                  "{\"camera\": {\"position\": [0, -5, 0], \"look_at\": [0, 0, 0], \"fov_deg\": 30, "
                  "\"resolution\": [4, 3]}}",
                  path);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(path, &scene), VBL_SUCCESS);
    for (int i = 0; i < PRESET_COUNT; ++i) {
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
        assert_int_equal(vbl_render_options_apply_preset(presets[i], &o), VBL_SUCCESS);
        o.passes = 2; /* an override after the preset: the render does 2 passes */
        o.threads = 1;
        vbl_film* film = NULL;
        assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
        vbl_film_stats st;
        memset(&st, 0, sizeof st);
        st.size = sizeof st;
        assert_int_equal(vbl_film_get_stats(film, &st), VBL_SUCCESS);
        assert_int_equal(st.passes, 2);
        assert_int_equal(st.method, o.method);
        vbl_film_release(film);
    }
    vbl_scene_release(scene);
    rt_remove_dir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unknown_and_bad_arguments),
        cmocka_unit_test(test_each_preset_sets_settings),
        cmocka_unit_test(test_overrides_after_preset_win),
        cmocka_unit_test(test_preset_options_render),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
