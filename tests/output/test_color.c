/* vbl_color: shipped config, $OCIO handling, round trips between spaces, display/view
 * transforms, chromaticities, and PNG previews. */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>
#include <png.h>

#include "output_test_util.h"
#include "vbl_color.h"

static const char* const linear_spaces[] = {"Linear Rec.709 (sRGB)", "ACEScg", "ACES2065-1", "CIE-XYZ-D65"};

static vbl_color_config* open_builtin(void)
{
    vbl_color_config* cfg = NULL;
    if (vbl_color_config_open("libvbl", &cfg) != VBL_SUCCESS) fail_msg("%s", vbl_last_error_message());
    return cfg;
}

static double srgb_encode(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055; }

static void test_default_config_is_builtin(void** s)
{
    (void)s;
    unsetenv("OCIO");
    vbl_color_config* cfg = NULL;
    assert_int_equal(vbl_color_config_open(NULL, &cfg), VBL_SUCCESS);
    assert_string_equal(vbl_color_config_source(cfg), "<libvbl built-in>");
    const char* name = NULL;
    assert_int_equal(vbl_color_resolve_space(cfg, "scene_linear", &name), VBL_SUCCESS);
    assert_string_equal(name, "Linear Rec.709 (sRGB)");
    assert_int_equal(vbl_color_resolve_space(cfg, "aces_interchange", &name), VBL_SUCCESS);
    assert_string_equal(name, "ACES2065-1");
    assert_string_equal(vbl_color_default_display(cfg), "sRGB");
    assert_string_equal(vbl_color_default_view(cfg, "Rec.709"), "Standard");
    assert_true(vbl_color_space_count(cfg) >= 7);
    vbl_color_config_release(cfg);
}

static void round_trips(vbl_color_config* cfg)
{
    const float colours[6][3] = {{0.18f, 0.18f, 0.18f}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {12.5f, 0.3f, 0.001f}, {-0.05f, 0.5f, 2.0f}};
    for (size_t a = 0; a < 4; ++a)
        for (size_t b = 0; b < 4; ++b)
            for (int k = 0; k < 6; ++k) {
                float v[3] = {colours[k][0], colours[k][1], colours[k][2]};
                assert_int_equal(vbl_color_convert_rgb(cfg, linear_spaces[a], linear_spaces[b], v), VBL_SUCCESS);
                assert_int_equal(vbl_color_convert_rgb(cfg, linear_spaces[b], linear_spaces[a], v), VBL_SUCCESS);
                for (int c = 0; c < 3; ++c)
                    if (fabsf(v[c] - colours[k][c]) > 1e-5f * (1.0f + fabsf(colours[k][c])))
                        fail_msg("%s -> %s -> back: %g vs %g", linear_spaces[a], linear_spaces[b], (double)v[c],
                                 (double)colours[k][c]);
            }
    /* Display encodings round trip too (within [0, 1]). */
    float d[6] = {0.0f, 0.002f, 0.18f, 0.5f, 0.9f, 1.0f};
    float orig[6];
    memcpy(orig, d, sizeof d);
    assert_int_equal(vbl_color_convert(cfg, "scene_linear", "sRGB - Display", d, 2, 3), VBL_SUCCESS);
    assert_true(fabsf(d[2] - (float)srgb_encode(0.18)) < 1e-5f);
    assert_int_equal(vbl_color_convert(cfg, "sRGB - Display", "scene_linear", d, 2, 3), VBL_SUCCESS);
    for (int i = 0; i < 6; ++i) assert_true(fabsf(d[i] - orig[i]) < 1e-5f);
}

static void test_round_trips_builtin(void** s)
{
    (void)s;
    vbl_color_config* cfg = open_builtin();
    round_trips(cfg);
    /* Against the published ACEScg -> linear Rec.709 (Bradford) matrix's first column. */
    float v[3] = {1, 0, 0};
    assert_int_equal(vbl_color_convert_rgb(cfg, "ACEScg", "scene_linear", v), VBL_SUCCESS);
    assert_true(fabsf(v[0] - 1.70505f) < 1e-4f && fabsf(v[1] + 0.13026f) < 1e-4f && fabsf(v[2] + 0.02400f) < 1e-4f);
    /* RGBA: alpha untouched. */
    float px[4] = {0.2f, 0.3f, 0.4f, 0.75f};
    assert_int_equal(vbl_color_convert(cfg, "scene_linear", "ACEScg", px, 1, 4), VBL_SUCCESS);
    assert_true(px[3] == 0.75f);
    vbl_color_config_release(cfg);
}

/* $OCIO naming the shipped file gives the same config. */
static void test_ocio_env_file(void** s)
{
    (void)s;
    const char* src = getenv("VBL_SOURCE_DIR");
    assert_non_null(src);
    char path[1024];
    snprintf(path, sizeof path, "%s/color/config/libvbl.ocio", src);
    setenv("OCIO", path, 1);
    vbl_color_config* cfg = NULL;
    vbl_result r = vbl_color_config_open(NULL, &cfg);
    unsetenv("OCIO");
    if (r != VBL_SUCCESS) fail_msg("%s", vbl_last_error_message());
    assert_string_equal(vbl_color_config_source(cfg), path);
    round_trips(cfg);
    vbl_color_config_release(cfg);
}

static void test_bad_configs(void** s)
{
    (void)s;
    vbl_color_config* cfg = NULL;
    setenv("OCIO", "/nonexistent/vbl/config.ocio", 1);
    vbl_result r = vbl_color_config_open(NULL, &cfg);
    unsetenv("OCIO");
    assert_int_equal(r, VBL_ERROR_FILE_NOT_FOUND);
    assert_null(cfg);
    assert_non_null(strstr(vbl_last_error_message(), "$OCIO=/nonexistent/vbl/config.ocio"));

    char* dir = out_make_temp_dir();
    const char* bad = out_path(dir, "bad.ocio");
    FILE* f = fopen(bad, "w");
    fputs("ocio_profile_version: 2\ncolorspaces: [this is not: valid\n", f);
    fclose(f);
    r = vbl_color_config_open(bad, &cfg);
    assert_int_equal(r, VBL_ERROR_CORRUPT_FILE);
    assert_non_null(strstr(vbl_last_error_message(), bad));
    out_remove_dir(dir);
}

static void test_unknown_names(void** s)
{
    (void)s;
    vbl_color_config* cfg = open_builtin();
    float v[3] = {1, 1, 1};
    assert_int_equal(vbl_color_convert_rgb(cfg, "ACEScg", "No Such Space", v), VBL_ERROR_INVALID_ARGUMENT);
    const char* msg = vbl_last_error_message();
    assert_non_null(strstr(msg, "'No Such Space'"));
    assert_non_null(strstr(msg, "'ACEScg'"));
    assert_true(v[0] == 1.0f);
    assert_int_equal(vbl_color_display_view(cfg, "scene_linear", "Cinema", NULL, 0.0f, v, 1, 3), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "'Cinema'"));
    assert_int_equal(vbl_color_display_view(cfg, "scene_linear", "sRGB", "Filmic", 0.0f, v, 1, 3), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "'Standard'"));
    vbl_color_config_release(cfg);
}

static void test_display_views(void** s)
{
    (void)s;
    vbl_color_config* cfg = open_builtin();
    float v[6] = {0.18f, 0.18f, 0.18f, 0.09f, 0.5f, 0.0f};
    assert_int_equal(vbl_color_display_view(cfg, "scene_linear", NULL, NULL, 1.0f, v, 2, 3), VBL_SUCCESS);
    assert_true(fabsf(v[0] - (float)srgb_encode(0.36)) < 1e-5f);
    assert_true(fabsf(v[3] - (float)srgb_encode(0.18)) < 1e-5f);
    float w[3] = {0.18f, 0.18f, 0.18f};
    assert_int_equal(vbl_color_display_view(cfg, "scene_linear", "Rec.709", "Standard", 0.0f, w, 1, 3), VBL_SUCCESS);
    assert_true(fabsf(w[0] - (float)pow(0.18, 1.0 / 2.4)) < 1e-5f);
    /* ACEScg input: the display transform converts primaries first. */
    float a[3] = {0.18f, 0.18f, 0.18f};
    assert_int_equal(vbl_color_display_view(cfg, "ACEScg", "sRGB", "Standard", 0.0f, a, 1, 3), VBL_SUCCESS);
    assert_true(fabsf(a[1] - (float)srgb_encode(0.18)) < 1e-4f); /* grey stays grey */
    float raw[3] = {0.18f, 2.0f, -1.0f};
    assert_int_equal(vbl_color_display_view(cfg, "ACEScg", "sRGB", "Raw", 0.0f, raw, 1, 3), VBL_SUCCESS);
    assert_true(raw[0] == 0.18f && raw[1] == 2.0f);
    vbl_color_config_release(cfg);
}

static void test_chromaticities(void** s)
{
    (void)s;
    vbl_color_config* cfg = open_builtin();
    float c[8];
    assert_int_equal(vbl_color_space_chromaticities(cfg, "ACEScg", c), VBL_SUCCESS);
    assert_true(c[0] == 0.713f && c[3] == 0.830f && c[6] == 0.32168f);
    assert_int_equal(vbl_color_space_chromaticities(cfg, "scene_linear", c), VBL_SUCCESS);
    assert_true(c[0] == 0.64f && c[7] == 0.3290f);
    assert_int_equal(vbl_color_space_chromaticities(cfg, "ACES2065-1", c), VBL_SUCCESS);
    assert_true(c[0] == 0.7347f && c[5] == -0.0770f);
    assert_int_equal(vbl_color_space_chromaticities(cfg, "sRGB - Display", c), VBL_ERROR_UNSUPPORTED);
    assert_int_equal(vbl_color_space_chromaticities(cfg, "CIE-XYZ-D65", c), VBL_ERROR_UNSUPPORTED);
    vbl_color_config_release(cfg);
}

static unsigned char* read_png(const char* path, int* w, int* h)
{
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path)) fail_msg("%s: %s", path, image.message);
    image.format = PNG_FORMAT_RGB;
    unsigned char* buf = malloc(PNG_IMAGE_SIZE(image));
    assert_non_null(buf);
    if (!png_image_finish_read(&image, NULL, buf, 0, NULL)) fail_msg("%s: %s", path, image.message);
    *w = (int)image.width;
    *h = (int)image.height;
    return buf;
}

static void test_preview_png(void** s)
{
    (void)s;
    unsetenv("OCIO");
    char* dir = out_make_temp_dir();
    const char* path = out_path(dir, "preview.png");
    const int W = 4, H = 2;
    float px[4 * 2 * 4];
    for (int i = 0; i < W * H; ++i) {
        px[i * 4 + 0] = 0.02f * (float)i;
        px[i * 4 + 1] = 0.1f * (float)i;
        px[i * 4 + 2] = 3.0f; /* clips */
        px[i * 4 + 3] = 1.0f;
    }
    vbl_preview_options opt = VBL_PREVIEW_OPTIONS_DEFAULT;
    opt.exposure = -1.0f;
    if (vbl_preview_write_png(path, px, W, H, 4, &opt) != VBL_SUCCESS) fail_msg("%s", vbl_last_error_message());
    int w, h;
    unsigned char* rgb = read_png(path, &w, &h);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    for (int i = 0; i < W * H; ++i)
        for (int c = 0; c < 3; ++c) {
            double lin = px[i * 4 + c] * 0.5;
            double e = srgb_encode(lin > 1.0 ? 1.0 : lin);
            int expect = (int)lrint(e * 255.0);
            if (abs((int)rgb[i * 3 + c] - expect) > 0) fail_msg("pixel %d.%d: %d vs %d", i, c, rgb[i * 3 + c], expect);
        }
    free(rgb);
    assert_int_equal(out_count_entries(dir, NULL, 0), 1);

    /* Failures: unknown space or view, unwritable path: one error, no file. */
    opt.input_space = "Nope";
    assert_int_equal(vbl_preview_write_png(out_path(dir, "x.png"), px, W, H, 4, &opt), VBL_ERROR_INVALID_ARGUMENT);
    opt.input_space = NULL;
    opt.view = "Nope";
    assert_int_equal(vbl_preview_write_png(out_path(dir, "x.png"), px, W, H, 4, &opt), VBL_ERROR_INVALID_ARGUMENT);
    opt.view = NULL;
    assert_int_equal(vbl_preview_write_png(out_path(dir, "no/such/dir.png"), px, W, H, 4, &opt), VBL_ERROR_FILE_IO);
    assert_non_null(strstr(vbl_last_error_message(), "no/such/dir.png"));
    assert_int_equal(out_count_entries(dir, NULL, 0), 1);
    out_remove_dir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_config_is_builtin),
        cmocka_unit_test(test_round_trips_builtin),
        cmocka_unit_test(test_ocio_env_file),
        cmocka_unit_test(test_bad_configs),
        cmocka_unit_test(test_unknown_names),
        cmocka_unit_test(test_display_views),
        cmocka_unit_test(test_chromaticities),
        cmocka_unit_test(test_preview_png),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
