/* `vbl preview`: EXR layer -> OCIO display/view -> PNG, through the real command line. */
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
#include "vbl_exr.h"

#define W 3
#define H 2

static char vbl_bin[1024];
static char* dir;
static const char* exr;

static double srgb_encode(double v)
{
    v = v < 0 ? 0 : (v > 1 ? 1 : v);
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

static float beauty_value(int c, int i) { return 0.05f * (float)(i + 1) + 0.1f * (float)c; }
static float emission_value(int c, int i) { return 0.5f * beauty_value(2 - c, i); }

static void write_exr(const char* path, const char* colour_space)
{
    static float beauty[W * H * 4], emission[W * H * 3], depth[W * H];
    for (int i = 0; i < W * H; ++i) {
        for (int c = 0; c < 3; ++c) {
            beauty[i * 4 + c] = beauty_value(c, i);
            emission[i * 3 + c] = emission_value(c, i);
        }
        beauty[i * 4 + 3] = 1.0f;
        depth[i] = 0.1f * (float)i;
    }
    static const char* const z[1] = {"Z"};
    vbl_exr_layer layers[3] = {{"", 4, NULL, beauty, 0}, {"emission", 3, NULL, emission, 0}, {"", 1, z, depth, 0}};
    vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    opt.color_space = colour_space;
    if (vbl_exr_write(path, W, H, layers, 3, &opt) != VBL_SUCCESS) fail_msg("%s", vbl_last_error_message());
}

static int setup(void** s)
{
    (void)s;
    const char* bin = getenv("VBL_BINARY_DIR");
    snprintf(vbl_bin, sizeof vbl_bin, "%s/bin/vbl", bin ? bin : ".");
    dir = out_make_temp_dir();
    exr = out_path(dir, "in.exr");
    static char exr_copy[1024];
    snprintf(exr_copy, sizeof exr_copy, "%s", exr);
    exr = exr_copy;
    write_exr(exr, NULL);
    unsetenv("OCIO");
    return 0;
}

static int teardown(void** s)
{
    (void)s;
    out_remove_dir(dir);
    return 0;
}

static unsigned char* read_png(const char* path)
{
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path)) fail_msg("%s: %s", path, image.message);
    assert_int_equal(image.width, W);
    assert_int_equal(image.height, H);
    image.format = PNG_FORMAT_RGB;
    unsigned char* buf = malloc(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, NULL, buf, 0, NULL)) fail_msg("%s: %s", path, image.message);
    return buf;
}

static int run(const char* args, char** out)
{
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "'%s' preview %s", vbl_bin, args);
    return out_run(cmd, out);
}

static void test_beauty_and_layers(void** s)
{
    (void)s;
    const char* png = out_path(dir, "beauty.png");
    char args[4096], *out = NULL;
    snprintf(args, sizeof args, "'%s' -o '%s' --exposure 1", exr, png);
    if (run(args, &out) != 0) fail_msg("%s", out);
    free(out);
    unsigned char* px = read_png(png);
    for (int i = 0; i < W * H; ++i)
        for (int c = 0; c < 3; ++c)
            assert_int_equal(px[i * 3 + c], (int)lrint(255.0 * srgb_encode(2.0 * beauty_value(c, i))));
    free(px);

    snprintf(args, sizeof args, "'%s' -o '%s' --layer emission --display Rec.709 --view Standard", exr, png);
    if (run(args, &out) != 0) fail_msg("%s", out);
    free(out);
    px = read_png(png);
    for (int i = 0; i < W * H; ++i)
        for (int c = 0; c < 3; ++c)
            assert_int_equal(px[i * 3 + c], (int)lrint(255.0 * pow(emission_value(c, i), 1.0 / 2.4)));
    free(px);

    snprintf(args, sizeof args, "'%s' -o '%s' --layer Z --view Raw", exr, png);
    if (run(args, &out) != 0) fail_msg("%s", out);
    free(out);
    px = read_png(png);
    for (int i = 0; i < W * H; ++i) assert_int_equal(px[i * 3 + 1], (int)lrintf(0.1f * (float)i * 255.0f));
    free(px);
}

/* A file tagged ACEScg is converted from ACEScg: grey stays grey, colours change. */
static void test_tagged_colour_space(void** s)
{
    (void)s;
    const char* tagged = out_path(dir, "acescg.exr");
    char tagged_copy[1024];
    snprintf(tagged_copy, sizeof tagged_copy, "%s", tagged);
    write_exr(tagged_copy, "ACEScg");
    const char* a = out_path(dir, "a.png");
    char a_copy[1024];
    snprintf(a_copy, sizeof a_copy, "%s", a);
    const char* b = out_path(dir, "b.png");
    char args[4096];
    snprintf(args, sizeof args, "'%s' -o '%s'", tagged_copy, a_copy);
    assert_int_equal(run(args, NULL), 0);
    snprintf(args, sizeof args, "'%s' -o '%s' --input-space scene_linear", tagged_copy, b);
    assert_int_equal(run(args, NULL), 0);
    unsigned char* pa = read_png(a_copy);
    unsigned char* pb = read_png(b);
    assert_memory_not_equal(pa, pb, W * H * 3);
    free(pa);
    free(pb);
}

static void test_errors(void** s)
{
    (void)s;
    const char* png = out_path(dir, "never.png");
    char png_copy[1024];
    snprintf(png_copy, sizeof png_copy, "%s", png);
    char args[4096], *out = NULL;
    struct {
        const char* extra;
        int code;
        const char* text;
    } cases[] = {
        {"--layer nothing", 2, "no layer 'nothing'"},
        {"--display Nope", 2, "unknown display 'Nope'"},
        {"--view Nope", 2, "unknown view 'Nope'"},
        {"--input-space Nope", 2, "unknown colour space 'Nope'"},
        {"--exposure x", 2, "--exposure"},
        {"--config /nonexistent.ocio", 3, "/nonexistent.ocio"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        snprintf(args, sizeof args, "'%s' -o '%s' %s", exr, png_copy, cases[k].extra);
        int code = run(args, &out);
        if (code != cases[k].code || !strstr(out, cases[k].text) || strchr(out, '\n') != out + strlen(out) - 1)
            fail_msg("'%s': exit %d, output: %s", cases[k].extra, code, out);
        free(out);
    }
    setenv("OCIO", "/nonexistent/dir/config.ocio", 1);
    snprintf(args, sizeof args, "'%s' -o '%s'", exr, png_copy);
    int code = run(args, &out);
    unsetenv("OCIO");
    if (code != 3 || !strstr(out, "$OCIO=/nonexistent/dir/config.ocio")) fail_msg("exit %d: %s", code, out);
    free(out);
    snprintf(args, sizeof args, "'%s' -o '%s/missing/x.png'", exr, dir);
    assert_int_equal(run(args, NULL), 4);
    snprintf(args, sizeof args, "'%s/none.exr' -o '%s'", dir, png_copy);
    assert_int_equal(run(args, NULL), 3);
    /* Only the input (and earlier tests' outputs) remain: no never.png, no temporaries. */
    FILE* f = fopen(png_copy, "rb");
    assert_null(f);
    int n = out_count_entries(dir, NULL, 0);
    char listing[256];
    snprintf(listing, sizeof listing, "ls -a '%s' | grep -c tmp", dir);
    char* tmp_count = NULL;
    out_run(listing, &tmp_count);
    assert_int_equal(atoi(tmp_count), 0);
    free(tmp_count);
    assert_true(n >= 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_beauty_and_layers),
        cmocka_unit_test(test_tagged_colour_space),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
