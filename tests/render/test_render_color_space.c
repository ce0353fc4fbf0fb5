/* Scene colour spaces (top-level "color_space"): light colours and media albedo go through the
 * loader's convert_color callback before their range checks; no callback, a failing callback
 * and an out-of-range converted albedo fail the load naming the file and field. */
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

#define CAMERA "\"camera\": {\"position\": [0, -5, 0], \"look_at\": [0, 0, 0], \"fov_deg\": 30, \"resolution\": [8, 6]}"

typedef struct convert_log {
    double factor;
    int calls;
    char fields[8][64];
    char space[64];
    int fail;
} convert_log;

static vbl_result scale_color(void* user, const char* color_space, const char* field, double rgb[3])
{
    convert_log* log = user;
    if (log->fail) return vbl_report_error(VBL_ERROR_UNSUPPORTED, "no colour space called '%s'", color_space);
    if (log->calls < 8) snprintf(log->fields[log->calls], sizeof log->fields[0], "%s", field);
    log->calls++;
    snprintf(log->space, sizeof log->space, "%s", color_space);
    for (int i = 0; i < 3; ++i) rgb[i] *= log->factor;
    return VBL_SUCCESS;
}

static vbl_result load(const char* text, convert_log* log, vbl_scene** scene, char* path)
{
    rt_write_file(rt_temp_dir, "scene.json", text, path);
    vbl_scene_load_options o = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    if (log) {
        o.convert_color = scale_color;
        o.convert_color_user = log;
    }
    return vbl_scene_load_ex(path, &o, scene);
}

static void expect(vbl_result got, vbl_result code, const char* path, const char* suffix)
{
    char expected[1024];
    snprintf(expected, sizeof expected, "%s: %s", path, suffix);
    if (got != code || strcmp(vbl_last_error_message(), expected))
        fprintf(stderr, "got %s '%s'\nwant %s '%s'\n", vbl_result_name(got), vbl_last_error_message(),
                vbl_result_name(code), expected);
    assert_int_equal(got, code);
    assert_string_equal(vbl_last_error_message(), expected);
}

static void assert_rgb(vbl_vec3 v, double r, double g, double b)
{
    assert_true(fabs(v.x - r) < 1e-12 && fabs(v.y - g) < 1e-12 && fabs(v.z - b) < 1e-12);
}

static void test_callback_converts_lights_and_albedo(void** state)
{
    (void)state;
    char path[512], text[2048];
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    char vdb[512];
    snprintf(vdb, sizeof vdb, "%s/box.vdb", fixtures ? fixtures : ".");
    FILE* f = fopen(vdb, "rb");
    int have_vdb = f != NULL;
    if (f) fclose(f);
    else fprintf(stderr, "note: %s absent; testing lights only\n", vdb);
    /* albedo 1.6 is outside [0, 1] as written but 0.8 once converted: the range applies after */
    snprintf(text, sizeof text,
             "{" CAMERA ", \"color_space\": \"ACEScg\", \"lights\": ["
             "{\"type\": \"point\", \"position\": [0, 0, 1], \"intensity\": [2, 4, 6]},"
             "{\"type\": \"distant\", \"direction\": [0, 0, -1], \"irradiance\": 3},"
             "{\"type\": \"quad\", \"corner\": [0, 0, 2], \"edge1\": [1, 0, 0], \"edge2\": [0, 1, 0], "
             "\"radiance\": [1, 0, 0.5]},"
             "{\"type\": \"environment\", \"radiance\": [0.2, 0.4, 0.8]}]%s%s%s}",
             have_vdb ? ", \"media\": [{\"vdb\": \"" : "", have_vdb ? vdb : "",
             have_vdb ? "\", \"albedo\": [1.6, 0.4, 1.0]}]" : "");
    convert_log log = {0.5, 0, {{0}}, {0}, 0};
    vbl_scene* scene = NULL;
    assert_int_equal(load(text, &log, &scene, path), VBL_SUCCESS);
    assert_string_equal(vbl_scene_color_space(scene), "ACEScg");
    assert_string_equal(log.space, "ACEScg");
    assert_int_equal(log.calls, have_vdb ? 5 : 4);
    assert_string_equal(log.fields[0], "lights[0].intensity");
    assert_string_equal(log.fields[1], "lights[1].irradiance");
    assert_string_equal(log.fields[2], "lights[2].radiance");
    assert_string_equal(log.fields[3], "lights[3].radiance");
    assert_rgb(scene->lights[0].color, 1.0, 2.0, 3.0);
    assert_rgb(scene->lights[1].color, 1.5, 1.5, 1.5);
    assert_rgb(scene->lights[2].color, 0.5, 0.0, 0.25);
    assert_rgb(scene->lights[3].color, 0.1, 0.2, 0.4);
    if (have_vdb) {
        assert_string_equal(log.fields[4], "media[0].albedo");
        assert_rgb(scene->media[0].albedo, 0.8, 0.2, 0.5);
    }
    vbl_scene_release(scene);

    /* no color_space: the callback is not called and colours stay as written */
    convert_log idle = {0.5, 0, {{0}}, {0}, 0};
    assert_int_equal(load("{" CAMERA ", \"lights\": [{\"type\": \"environment\", \"radiance\": 0.3}]}", &idle,
                          &scene, path),
                     VBL_SUCCESS);
    assert_null(vbl_scene_color_space(scene));
    assert_int_equal(idle.calls, 0);
    assert_rgb(scene->lights[0].color, 0.3, 0.3, 0.3);
    vbl_scene_release(scene);
}

static void test_errors(void** state)
{
    (void)state;
    char path[512];
    vbl_scene* scene = NULL;
    const char* env = "{" CAMERA ", \"color_space\": \"ACEScg\", "
                      "\"lights\": [{\"type\": \"environment\", \"radiance\": 0.3}]}";
    /* no callback */
    expect(load(env, NULL, &scene, path), VBL_ERROR_SCENE, path,
           "color_space = \"ACEScg\" needs a colour-managed loader (vbl render, or vbl_scene_load_ex with "
           "convert_color)");
    assert_null(scene);
    assert_int_equal(vbl_scene_load(path, &scene), VBL_ERROR_SCENE);
    assert_null(scene);
    /* the callback's failure propagates, its message prefixed with file, color_space and field */
    convert_log failing = {0.5, 0, {{0}}, {0}, 1};
    expect(load(env, &failing, &scene, path), VBL_ERROR_UNSUPPORTED, path,
           "color_space = \"ACEScg\" (lights[0].radiance): no colour space called 'ACEScg'");
    assert_null(scene);
    /* a converted albedo outside [0, 1] fails (before the VDB is opened), never clamped */
    convert_log doubling = {2.0, 0, {{0}}, {0}, 0};
    expect(load("{" CAMERA ", \"color_space\": \"ACEScg\", \"media\": [{\"vdb\": \"x.vdb\", \"albedo\": [0.6, 0.25, "
                "0.5]}]}",
                &doubling, &scene, path),
           VBL_ERROR_SCENE, path, "media[0].albedo converts to [1.2, 0.5, 1] in scene_linear: outside [0, 1]");
    /* a negative converted light colour fails too */
    convert_log negating = {-1.0, 0, {{0}}, {0}, 0};
    expect(load(env, &negating, &scene, path), VBL_ERROR_SCENE, path,
           "lights[0].radiance converts to [-0.3, -0.3, -0.3] in scene_linear: outside [0, 1e+30]");
    /* type checks */
    expect(load("{" CAMERA ", \"color_space\": 3}", &doubling, &scene, path), VBL_ERROR_SCENE, path,
           "color_space must be a string");
    expect(load("{" CAMERA ", \"color_space\": \"\"}", &doubling, &scene, path), VBL_ERROR_SCENE, path,
           "color_space is empty");
}

/* Callers built against the struct before convert_color (a smaller size) still load. */
static void test_old_options_size(void** state)
{
    (void)state;
    char path[512];
    rt_write_file(rt_temp_dir, "old.json", "{" CAMERA "}", path);
    vbl_scene_load_options o = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    o.size = offsetof(vbl_scene_load_options, convert_color);
    o.convert_color = scale_color; /* beyond the declared size: ignored */
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load_ex(path, &o, &scene), VBL_SUCCESS);
    vbl_scene_release(scene);
    o.size = offsetof(vbl_scene_load_options, vdb_override_count);
    assert_int_equal(vbl_scene_load_ex(path, &o, &scene), VBL_ERROR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_callback_converts_lights_and_albedo),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_old_options_size),
    };
    return cmocka_run_group_tests(tests, rt_temp_dir_setup, rt_temp_dir_teardown);
}
