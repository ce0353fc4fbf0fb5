/* `vbl render` shot controls (issue #17 part 3) through the real binary: --resolution, --camera
 * (a named camera of the scene, a camera file), --flag=value (--passes=2), --animated-seed over
 * --frames, the warning for a scene without lights, and their usage errors. Tiny images, 1 pass. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_test_util.h"
#include "vbl_exr.h"

static char* dir;
static char scene[2048];

static int setup(void** state)
{
    (void)state;
    dir = ct_make_dir();
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    ct_write_scene(scene, 6, 4,
                   "  \"cameras\": {\"side\": {\"position\": [-3.0, 0.75, 0.75], \"look_at\": [0.75, 0.75, 0.75],"
                   " \"focal_length\": 50, \"resolution\": [5, 3]}},\n");
    return 0;
}

static int teardown(void** state)
{
    (void)state;
    ct_remove_dir(dir);
    free(dir);
    return 0;
}

/* Renders with `extra`, expects exit `code`; for 0 reads the EXR `name` back. */
static vbl_exr_image* run(const char* name, const char* extra, int code, char** log_out)
{
    char args[4096];
    snprintf(args, sizeof args, "'%s' -o '%s' %s", scene, ct_path(dir, name), extra);
    char* log = NULL;
    int got = ct_render(args, &log);
    if (got != code) fail_msg("vbl render %s -> %d, want %d:\n%s", args, got, code, log ? log : "");
    if (log_out) *log_out = log;
    else free(log);
    if (code || strchr(name, '#')) return NULL;
    vbl_exr_image* img = NULL;
    if (vbl_exr_read(ct_path(dir, name), &img) != VBL_SUCCESS) fail_msg("%s", vbl_last_error_message());
    return img;
}

static void test_resolution_camera_equals(void** state)
{
    (void)state;
    vbl_exr_image* img = run("res.exr", "-q --resolution=8x6 --passes=1 --spp=1", 0, NULL);
    assert_int_equal(vbl_exr_image_width(img), 8);
    assert_int_equal(vbl_exr_image_height(img), 6);
    assert_string_equal(vbl_exr_image_attribute(img, "vbl:passes", NULL), "1");
    assert_string_equal(vbl_exr_image_attribute(img, "vbl:spp", NULL), "1");
    vbl_exr_image_release(img);
    img = run("side.exr", "-q --camera side --passes 1 --spp 1", 0, NULL);
    assert_int_equal(vbl_exr_image_width(img), 5);
    assert_int_equal(vbl_exr_image_height(img), 3);
    vbl_exr_image_release(img);
    ct_write_file(ct_path(dir, "cam.json"),
                  "{\"position\": [0.75, -3.0, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 30, "
                  "\"resolution\": [7, 2]}");
    char extra[4096];
    snprintf(extra, sizeof extra, "-q --camera '%s' --resolution 3x9 --passes 1 --spp 1", ct_path(dir, "cam.json"));
    img = run("file.exr", extra, 0, NULL);
    assert_int_equal(vbl_exr_image_width(img), 3);
    assert_int_equal(vbl_exr_image_height(img), 9);
    vbl_exr_image_release(img);
    /* --flag=value in the other commands too (main.c splits it for them) */
    char* out = NULL;
    snprintf(extra, sizeof extra, "diff '%s' '%s' --layer=beauty", ct_path(dir, "res.exr"), ct_path(dir, "res.exr"));
    if (ct_vbl_run(extra, &out, 1) != 0) fail_msg("vbl %s:\n%s", extra, out ? out : "");
    assert_non_null(out);
    assert_non_null(strstr(out, "beauty"));
    free(out);
    run("bad.exr", "-q --camera nowhere --passes 1", 3, NULL);
    run("bad.exr", "-q --resolution 8 --passes 1", 2, NULL);
    run("bad.exr", "-q --resolution 0x4 --passes 1", 2, NULL);
    run("bad.exr", "-q --passes=0", 2, NULL);
}

static void test_animated_seed(void** state)
{
    (void)state;
    char* log = NULL;
    run("f.####.exr", "-q --frames 1-2 --animated-seed --passes 1 --spp 1 --resolution 4x3", 0, NULL);
    const char* seeds[2];
    vbl_exr_image* img[2];
    for (int f = 0; f < 2; ++f) {
        img[f] = NULL;
        assert_int_equal(vbl_exr_read(ct_path(dir, f ? "f.0002.exr" : "f.0001.exr"), &img[f]), VBL_SUCCESS);
        seeds[f] = vbl_exr_image_attribute(img[f], "vbl:seed", NULL);
        assert_non_null(seeds[f]);
    }
    /* seed 3 + f * 0x9E3779B97F4A7C15 (mod 2^64) */
    char want[2][32];
    for (int f = 0; f < 2; ++f)
        snprintf(want[f], sizeof want[f], "%llu", (unsigned long long)(3ull + (uint64_t)(f + 1) * 0x9E3779B97F4A7C15ull));
    assert_string_equal(seeds[0], want[0]);
    assert_string_equal(seeds[1], want[1]);
    vbl_exr_image_release(img[0]);
    vbl_exr_image_release(img[1]);
    run("g.exr", "-q --animated-seed --passes 1", 2, &log);
    assert_non_null(strstr(log, "--frames"));
    free(log);
}

static void test_no_lights_warning(void** state)
{
    (void)state;
    char path[2048];
    snprintf(path, sizeof path, "%s/dark.json", dir);
    char text[2048];
    snprintf(text, sizeof text,
             "{\"camera\": \"auto\", \"media\": [{\"vdb\": \"%s\"}], \"render\": {\"passes\": 1, \"spp\": 1}}",
             ct_fixture("box.vdb"));
    ct_write_file(path, text);
    char args[4096];
    snprintf(args, sizeof args, "'%s' -o '%s' -q --resolution 4x3", path, ct_path(dir, "dark.exr"));
    char* log = NULL;
    assert_int_equal(ct_render(args, &log), 0);
    if (!log || !strstr(log, "warning") || !strstr(log, "no lights")) fail_msg("no warning in:\n%s", log ? log : "");
    free(log);
    /* a lit scene: no warning */
    vbl_exr_image_release(run("lit.exr", "-q --passes 1 --spp 1", 0, &log));
    assert_true(!log || !strstr(log, "warning"));
    free(log);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_resolution_camera_equals),
        cmocka_unit_test(test_animated_seed),
        cmocka_unit_test(test_no_lights_warning),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
