/* The vrl/vpl estimator settings in the scene's render block (render.vrl, render.vpl): parsing,
 * defaults, errors naming file and field, and validation of the public options by vbl_render. */
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

#define CAMERA "\"camera\": {\"position\": [0, -5, 0], \"look_at\": [0, 0, 0], \"fov_deg\": 30, \"resolution\": [4, 3]}"

static vbl_result load_text(const char* name, const char* text, vbl_scene** scene)
{
    char path[512];
    rt_write_file(rt_temp_dir, name, text, path);
    return vbl_scene_load(path, scene);
}

static void expect_error(const char* render_block, const char* suffix)
{
    char text[2048];
    snprintf(text, sizeof text, "{" CAMERA ", \"render\": %s}", render_block);
    vbl_scene* scene = NULL;
    vbl_result r = load_text("scene.json", text, &scene);
    char expected[1024];
    snprintf(expected, sizeof expected, "%s/scene.json: %s", rt_temp_dir, suffix);
    if (r != VBL_ERROR_SCENE || strcmp(vbl_last_error_message(), expected))
        fprintf(stderr, "got %s '%s'\nwant VBL_ERROR_SCENE '%s'\n", vbl_result_name(r), vbl_last_error_message(),
                expected);
    assert_int_equal(r, VBL_ERROR_SCENE);
    assert_string_equal(vbl_last_error_message(), expected);
    assert_null(scene);
}

static void test_defaults(void** state)
{
    (void)state;
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    assert_int_equal(o.vrl.samples, 1);
    assert_int_equal(o.vrl.long_vrls, 0);
    assert_int_equal(o.vrl.connect, 0);
    assert_true(o.vrl.prune_radius == 0.0);
    assert_true(o.vrl.prune_min_probability == 0.1);
    assert_true(o.vpl.clamp_distance == 0.0);
    vbl_scene* scene = NULL;
    assert_int_equal(load_text("d.json", "{" CAMERA ", \"render\": {\"method\": \"vrl\"}}", &scene), VBL_SUCCESS);
    memset(&o, 0, sizeof o);
    o.size = sizeof o;
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    assert_int_equal(o.vrl.samples, 1);
    assert_true(o.vrl.prune_min_probability == 0.1);
    vbl_scene_release(scene);
}

static void test_parse_fields(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(load_text("ok.json",
                               "{" CAMERA ", \"render\": {\"method\": \"vrl\", \"light_paths\": 50,"
                               " \"vrl\": {\"samples\": 3, \"long\": true, \"connect\": \"march\", \"march_step\": 0.05,"
                               " \"prune_radius\": 0.25, \"prune_min_probability\": 0.05, \"select\": 3, \"_note\": \"x\"},"
                               " \"vpl\": {\"clamp_distance\": 0.1}}}",
                               &scene),
                     VBL_SUCCESS);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    assert_int_equal(o.method, VBL_RENDER_VRL);
    assert_int_equal(o.light_paths, 50);
    assert_int_equal(o.vrl.samples, 3);
    assert_int_equal(o.vrl.long_vrls, 1);
    assert_int_equal(o.vrl.connect, 1);
    assert_true(o.vrl.march_step == 0.05);
    assert_true(o.vrl.prune_radius == 0.25);
    assert_true(o.vrl.prune_min_probability == 0.05);
    assert_true(o.vpl.clamp_distance == 0.1);
    assert_int_equal(o.vrl.select, 3); /* not the default (VBL_VRL_SELECT_DEFAULT) */
    vbl_scene_release(scene);

    assert_int_equal(load_text("ok2.json",
                               "{" CAMERA ", \"render\": {\"vrl\": {\"long\": false, \"connect\": \"ratio\"}}}", &scene),
                     VBL_SUCCESS);
    o = (vbl_render_options)VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    assert_int_equal(o.vrl.long_vrls, 0);
    assert_int_equal(o.vrl.connect, 0);
    assert_int_equal(o.vrl.samples, 1);
    assert_int_equal(o.vrl.select, VBL_VRL_SELECT_DEFAULT);
    vbl_scene_release(scene);
}

static void test_parse_errors(void** state)
{
    (void)state;
    expect_error("{\"vrl\": {\"samples\": 0}}", "render.vrl.samples = 0 is outside [1, 1000000]");
    expect_error("{\"vrl\": {\"samples\": 1.5}}", "render.vrl.samples must be an integer");
    expect_error("{\"vrl\": {\"long\": 1}}", "render.vrl.long must be true or false");
    expect_error("{\"vrl\": {\"connect\": \"teleport\"}}", "render.vrl.connect = \"teleport\" is not one of ratio, march");
    expect_error("{\"vrl\": {\"connect\": 2}}", "render.vrl.connect must be a string");
    expect_error("{\"vrl\": {\"prune_radius\": -0.5}}", "render.vrl.prune_radius = -0.5 is outside [0, inf)");
    expect_error("{\"vrl\": {\"prune_min_probability\": 0}}", "render.vrl.prune_min_probability = 0 is outside (0, 1]");
    expect_error("{\"vrl\": {\"prune_min_probability\": 1.5}}",
                 "render.vrl.prune_min_probability = 1.5 is outside (0, 1]");
    expect_error("{\"vrl\": {\"march_step\": -1}}", "render.vrl.march_step = -1 is outside [0, inf)");
    expect_error("{\"vrl\": {\"select\": -1}}", "render.vrl.select = -1 is outside [0, 1000000]");
    expect_error("{\"vrl\": {\"sample\": 2}}", "unknown key 'render.vrl.sample'");
    expect_error("{\"vrl\": 3}", "render.vrl must be an object");
    expect_error("{\"vpl\": {\"clamp_distance\": -0.1}}", "render.vpl.clamp_distance = -0.1 is outside [0, inf)");
    expect_error("{\"vpl\": {\"clamp_distance\": \"far\"}}", "render.vpl.clamp_distance must be a number");
    expect_error("{\"vpl\": {\"clamp\": 1}}", "unknown key 'render.vpl.clamp'");
}

static void test_render_validates(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(load_text("v.json", "{" CAMERA "}", &scene), VBL_SUCCESS);
    vbl_render_options base = VBL_RENDER_OPTIONS_DEFAULT;
    base.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    base.passes = 1;
    base.spp = 1;
    base.threads = 1;
    vbl_film* film = NULL;
    vbl_render_options o = base;
    o.vrl.samples = -1;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "vrl_samples"));
    o = base;
    o.vrl.prune_min_probability = 2.0;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "vrl_prune_min_probability"));
    o = base;
    o.vpl.clamp_distance = -1.0;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "vpl_clamp_distance"));
    o = base;
    o.vrl.long_vrls = 2;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_ERROR_INVALID_ARGUMENT);
    o = base;
    o.vrl.select = -3;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "vrl_select"));
    assert_null(film);
    /* zeros in the new fields (initializers older than them) are the defaults */
    o = base;
    o.method = VBL_RENDER_VRL;
    o.vrl.samples = 0;
    o.vrl.prune_min_probability = 0.0;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    vbl_film_release(film);
    vbl_scene_release(scene);
}

/* light_paths 0 (the default) is the method's count, which films record (vbl:light_paths). */
static void test_light_paths_method_default(void** state)
{
    (void)state;
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    assert_int_equal(o.light_paths, 0);
    const struct {
        vbl_render_method method;
        int media_only, with_surfaces; /* the default count in a media-only scene and with surfaces */
    } want[] = {{VBL_RENDER_PT, VBL_LIGHT_PATHS_DEFAULT, VBL_LIGHT_PATHS_DEFAULT},
                {VBL_RENDER_VPL, VBL_LIGHT_PATHS_DEFAULT, VBL_LIGHT_PATHS_DEFAULT},
                {VBL_RENDER_VRL, VBL_LIGHT_PATHS_DEFAULT_VL_MEDIA_ONLY, VBL_LIGHT_PATHS_DEFAULT_VRL},
                {VBL_RENDER_VBL, VBL_LIGHT_PATHS_DEFAULT_VL_MEDIA_ONLY, VBL_LIGHT_PATHS_DEFAULT_VBL},
                {VBL_RENDER_BEAMS, VBL_LIGHT_PATHS_DEFAULT, VBL_LIGHT_PATHS_DEFAULT}};
    assert_int_equal(VBL_LIGHT_PATHS_DEFAULT, 10000);
    assert_true(VBL_LIGHT_PATHS_DEFAULT_VRL >= 1 && VBL_LIGHT_PATHS_DEFAULT_VRL <= 100);
    assert_true(VBL_LIGHT_PATHS_DEFAULT_VBL >= 1 && VBL_LIGHT_PATHS_DEFAULT_VBL <= 100);
    assert_true(VBL_LIGHT_PATHS_DEFAULT_VL_MEDIA_ONLY > VBL_LIGHT_PATHS_DEFAULT_VRL);
    assert_int_equal(o.vrl.select, VBL_VRL_SELECT_DEFAULT); /* the light tree is on by default */
    assert_true(VBL_VRL_SELECT_DEFAULT > 0);
    assert_int_equal(vbl_render_options_light_paths(NULL), 0);
    assert_int_equal(vbl_render_light_paths(NULL, NULL), 0);
    vbl_scene* scenes[2] = {NULL, NULL}; /* media only (no surfaces), with one quad */
    assert_int_equal(load_text("lp.json", "{" CAMERA "}", &scenes[0]), VBL_SUCCESS);
    assert_int_equal(load_text("lp_surface.json", "{" CAMERA "}", &scenes[1]), VBL_SUCCESS);
    const double quad[12] = {-3, -3, -1, 3, -3, -1, 3, 3, -1, -3, 3, -1};
    const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    vbl_material lambert;
    memset(&lambert, 0, sizeof lambert);
    lambert.type = VBL_MATERIAL_LAMBERT;
    lambert.albedo = vbl_v3(0.5, 0.5, 0.5);
    assert_int_equal(vbl_scene_add_mesh(scenes[1], quad, 4, idx, 2, &lambert, NULL), VBL_SUCCESS);
    for (size_t i = 0; i < sizeof want / sizeof want[0]; ++i) {
        for (int s = 0; s < 2; ++s) {
            const int count = s ? want[i].with_surfaces : want[i].media_only;
            o = (vbl_render_options)VBL_RENDER_OPTIONS_DEFAULT;
            o.method = want[i].method;
            assert_int_equal(vbl_render_options_light_paths(&o), want[i].with_surfaces); /* no scene */
            assert_int_equal(vbl_render_light_paths(NULL, &o), want[i].with_surfaces);
            assert_int_equal(vbl_render_light_paths(scenes[s], &o), count);
            o.light_paths = 7;
            assert_int_equal(vbl_render_options_light_paths(&o), 7);
            assert_int_equal(vbl_render_light_paths(scenes[s], &o), 7);
            /* the film records the count the render used */
            o.light_paths = 0;
            o.passes = 1;
            o.spp = 1;
            o.threads = 1;
            vbl_film* film = NULL;
            assert_int_equal(vbl_render(scenes[s], &o, &film), VBL_SUCCESS);
            vbl_film_stats st;
            memset(&st, 0, sizeof st);
            st.size = sizeof st;
            assert_int_equal(vbl_film_get_stats(film, &st), VBL_SUCCESS);
            assert_int_equal(st.light_paths, count);
            vbl_film_release(film);
        }
    }
    vbl_scene_release(scenes[0]);
    vbl_scene_release(scenes[1]);
}

/* vrl.select is hashed against 0 (its default before VBL_VRL_SELECT_DEFAULT) for vrl and vbl: a film
 * of the former default merges with --vrl-select 0 only, and files written before keep their hash
 * (the method is not hashed, so theirs is the hash of the default pt options). */
static void test_vrl_select_hash(void** state)
{
    (void)state;
    char pt_default[64], h[64], h0[64], h4[64];
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_render_options_hash(&o, pt_default, sizeof pt_default);
    o.vrl.select = 0; /* pt ignores it: same hash at 0 and at the default */
    vbl_render_options_hash(&o, h, sizeof h);
    assert_string_equal(h, pt_default);
    const vbl_render_method methods[] = {VBL_RENDER_VRL, VBL_RENDER_VBL};
    for (int m = 0; m < 2; ++m) {
        o = (vbl_render_options)VBL_RENDER_OPTIONS_DEFAULT; /* hybrid auto: hashed as its default */
        o.method = methods[m];
        vbl_render_options_hash(&o, h, sizeof h);
        o.vrl.select = 0;
        vbl_render_options_hash(&o, h0, sizeof h0);
        o.vrl.select = 4;
        vbl_render_options_hash(&o, h4, sizeof h4);
        assert_string_equal(h0, pt_default); /* every VRL: the hash of the files before */
        assert_string_not_equal(h, h0);      /* the default (light tree) is another estimator */
        assert_string_not_equal(h4, h0);
        assert_string_not_equal(h4, h);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_parse_fields),
        cmocka_unit_test(test_parse_errors),
        cmocka_unit_test(test_render_validates),
        cmocka_unit_test(test_light_paths_method_default),
        cmocka_unit_test(test_vrl_select_hash),
    };
    return cmocka_run_group_tests(tests, rt_temp_dir_setup, rt_temp_dir_teardown);
}
