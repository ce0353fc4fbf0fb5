/* libvbl_python (plugins/python/native), the C side of the Python package, from C so that it also
 * runs under ASan/UBSan (the Python tests do not): the cancel flag, colour-managed scene loading
 * through the OCIO adapter, Film.write_exr's writer (attributes, channels) and the EXR reader. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "vbl_python_native.h"

static char g_dir[256];

static const char* path_in(const char* name)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", g_dir, name);
    return path;
}

/* A 6x4 pt scene of box.vdb; `extra`: more top-level JSON members (", \"color_space\": ..."). */
static const char* write_scene(const char* name, const char* extra)
{
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    const char* path = path_in(name);
    FILE* f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f,
            "{\"camera\": {\"position\": [0.75, -3, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"resolution\": [6, 4]},\n"
            " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.3, 0.5, -0.8], \"irradiance\": [2, 1.8, 1.5]}],\n"
            " \"media\": [{\"vdb\": \"%s/box.vdb\", \"density_scale\": 3, \"albedo\": [0.9, 0.8, 0.7]}],\n"
            " \"render\": {\"method\": \"pt\", \"passes\": 2, \"spp\": 1, \"seed\": 3}%s}\n",
            fixtures ? fixtures : ".", extra);
    fclose(f);
    return path;
}

static vbl_scene* load(const char* path, vbl_py_color* color, vbl_result want)
{
    vbl_scene_load_options load = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    load.convert_color = vbl_py_convert_scene_color;
    load.convert_color_user = color;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load_ex(path, &load, &scene), want);
    return scene;
}

static void test_cancel_flag(void** state)
{
    (void)state;
    vbl_py_color* color = NULL;
    assert_int_equal(vbl_py_color_open(NULL, &color), VBL_SUCCESS);
    vbl_scene* scene = load(write_scene("cancel.json", ""), color, VBL_SUCCESS);
    vbl_render_options* options = NULL;
    assert_int_equal(vbl_render_options_create(&options), VBL_SUCCESS);
    assert_int_equal(vbl_scene_render_options(scene, options), VBL_SUCCESS);
    volatile int flag = 1; /* set before the first pass: nothing completes */
    vbl_py_options_set_cancel(options, &flag);
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, options, &film), VBL_ERROR_INTERRUPTED);
    assert_null(film);
    flag = 0;
    assert_int_equal(vbl_render(scene, options, &film), VBL_SUCCESS);
    assert_non_null(film);
    vbl_film_release(film);
    vbl_py_options_set_cancel(options, NULL);
    vbl_render_options_destroy(options);
    vbl_scene_release(scene);
    vbl_py_color_release(color);
}

static void test_color_managed_loading(void** state)
{
    (void)state;
    vbl_py_color* color = NULL;
    assert_int_equal(vbl_py_color_open(NULL, &color), VBL_SUCCESS);
    assert_non_null(vbl_py_color_scene_space(color));
    vbl_scene* scene = load(write_scene("acescg.json", ", \"color_space\": \"ACEScg\""), color, VBL_SUCCESS);
    assert_int_equal(vbl_py_color_check_scene(color, scene), VBL_SUCCESS);
    vbl_scene_release(scene);
    assert_null(load(write_scene("unknown.json", ", \"color_space\": \"no such space\""), color, VBL_ERROR_SCENE));
    assert_non_null(strstr(vbl_last_error_message(), "no such space"));
    float chroma[8];
    assert_int_equal(vbl_py_color_chromaticities(color, chroma), 1);
    assert_true(chroma[6] > 0.3f && chroma[6] < 0.32f); /* D65 white x = 0.3127 */
    vbl_py_color_release(color);
}

static void test_write_and_read_exr(void** state)
{
    (void)state;
    vbl_scene* scene = load(write_scene("exr.json", ""), NULL, VBL_SUCCESS);
    vbl_render_options* options = NULL;
    assert_int_equal(vbl_render_options_create(&options), VBL_SUCCESS);
    assert_int_equal(vbl_scene_render_options(scene, options), VBL_SUCCESS);
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, options, &film), VBL_SUCCESS);
    vbl_py_exr_options o;
    memset(&o, 0, sizeof o);
    o.size = sizeof o;
    o.compression = -1;
    /* refused: no scene */
    assert_int_equal(vbl_py_film_write_exr(film, path_in("out.exr"), &o), VBL_ERROR_INVALID_ARGUMENT);
    o.scene = scene;
    o.render_options = options;
    o.aov_z = o.aov_samples = o.aov_variance = 1;
    o.half_layers = "variance";
    assert_int_equal(vbl_py_film_write_exr(film, path_in("missing/out.exr"), &o), VBL_ERROR_FILE_IO);
    assert_int_equal(vbl_py_film_write_exr(film, path_in("out.exr"), &o), VBL_SUCCESS);
    vbl_py_exr* file = NULL;
    assert_int_equal(vbl_py_exr_open(path_in("out.exr"), &file), VBL_SUCCESS);
    assert_int_equal(vbl_py_exr_width(file), 6);
    assert_int_equal(vbl_py_exr_height(file), 4);
    int type = -2;
    assert_string_equal(vbl_py_exr_attribute(file, "vbl:status", &type), "complete");
    assert_int_equal(type, 0);
    assert_string_equal(vbl_py_exr_attribute(file, "vbl:passes", &type), "2");
    assert_int_equal(type, 1);
    char hash[64];
    vbl_render_options_hash(options, hash, sizeof hash);
    assert_string_equal(vbl_py_exr_attribute(file, "vbl:options_hash", NULL), hash);
    assert_non_null(vbl_py_exr_attribute(file, "vbl:scene_hash", NULL));
    assert_null(vbl_py_exr_attribute(file, "vbl:frame", NULL));
    int named = 0;
    for (int i = 0; i < vbl_py_exr_attribute_count(file); ++i) named += vbl_py_exr_attribute_name(file, i) != NULL;
    assert_int_equal(named, vbl_py_exr_attribute_count(file));
    assert_true(named >= 20); /* software, vbl:*, chromaticities, oiio:ColorSpace */
    assert_null(vbl_py_exr_attribute_name(file, named));
    /* R of the beauty, Z and samples.Y are there, the beauty equal to the film's */
    int r = -1, z = -1, samples = -1;
    for (int i = 0; i < vbl_py_exr_channel_count(file); ++i) {
        const char* name = vbl_py_exr_channel_name(file, i);
        if (!strcmp(name, "R")) r = i;
        if (!strcmp(name, "Z")) z = i;
        if (!strcmp(name, "samples.Y")) samples = i;
    }
    assert_true(r >= 0 && z >= 0 && samples >= 0);
    int channels = 0;
    const float* beauty = vbl_film_layer(film, "", &channels);
    const float* red = vbl_py_exr_channel_pixels(file, r);
    for (int p = 0; p < 24; ++p) assert_true(red[p] == beauty[p * channels]);
    vbl_py_exr_close(file);
    assert_int_equal(vbl_py_exr_open(path_in("nope.exr"), &file), VBL_ERROR_FILE_NOT_FOUND);
    /* another output space: converted colour layers, the beauty re-summed from them */
    o.output_space = "no such space";
    assert_int_equal(vbl_py_film_write_exr(film, path_in("acescg.exr"), &o), VBL_ERROR_INVALID_ARGUMENT);
    o.output_space = "ACEScg";
    assert_int_equal(vbl_py_film_write_exr(film, path_in("acescg.exr"), &o), VBL_SUCCESS);
    assert_int_equal(vbl_py_exr_open(path_in("acescg.exr"), &file), VBL_SUCCESS);
    const char* written = vbl_py_exr_attribute(file, "oiio:ColorSpace", NULL);
    assert_non_null(written);
    assert_non_null(strstr(written, "ACEScg"));
    vbl_py_exr_close(file);
    vbl_film_release(film);
    vbl_render_options_destroy(options);
    vbl_scene_release(scene);
}

int main(void)
{
    snprintf(g_dir, sizeof g_dir, "/tmp/vbl_python_native_XXXXXX");
    if (!mkdtemp(g_dir)) return 1;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cancel_flag),
        cmocka_unit_test(test_color_managed_loading),
        cmocka_unit_test(test_write_and_read_exr),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    const char* names[] = {"cancel.json", "acescg.json", "unknown.json", "exr.json", "out.exr", "acescg.exr"};
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i) unlink(path_in(names[i]));
    rmdir(g_dir);
    return failed;
}
