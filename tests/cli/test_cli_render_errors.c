/* `vbl render` bad input: one clear message naming the file/field on stderr, the documented exit
 * code (2 usage/colour space, 3 scene/VDB, 4 cannot write) and no output file; and the documented
 * limits: a warning line on stderr, the render still runs. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli_test_util.h"

static char* dir;

static int setup_each(void** state)
{
    (void)state;
    dir = ct_make_dir();
    return 0;
}

static int teardown_each(void** state)
{
    (void)state;
    chmod(dir, 0700);
    ct_remove_dir(dir);
    free(dir);
    return 0;
}

/* Runs `vbl render ARGS`, expects `code`, a message containing `needle`, and the folder to hold
 * exactly `files` entries afterwards (the inputs). */
static void expect_failure(const char* args, int code, const char* needle, int files)
{
    char* log = NULL;
    int got = ct_render(args, &log);
    if (got != code || !log || !strstr(log, needle))
        fail_msg("vbl render %s: exit %d (want %d), output:\n%s(want a message containing '%s')", args, got, code,
                 log ? log : "", needle);
    /* one message: a single line starting with "vbl" */
    assert_true(strncmp(log, "vbl", 3) == 0);
    assert_true(strchr(log, '\n') == log + strlen(log) - 1);
    free(log);
    char names[1024];
    int n = ct_count_entries(dir, names, sizeof names);
    if (n != files) fail_msg("folder holds %s (want %d entries)", names, files);
}

static void test_missing_scene(void** state)
{
    (void)state;
    char args[4096];
    snprintf(args, sizeof args, "'%s' -o '%s'", ct_path(dir, "nope.json"), ct_path(dir, "out.exr"));
    expect_failure(args, 3, "nope.json", 0);
}

static void test_malformed_scene(void** state)
{
    (void)state;
    const char* scene = ct_path(dir, "bad.json");
    ct_write_file(scene, "{\"camera\": {\"position\": [0, 0, 0],\n");
    char args[4096];
    snprintf(args, sizeof args, "'%s' -o '%s'", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 3, "bad.json", 1);
    /* valid JSON, invalid field */
    ct_write_scene(scene, 4, 3, NULL);
    FILE* f = fopen(scene, "r+");
    char text[4096];
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = 0;
    fclose(f);
    char* g = strstr(text, "\"g\": 0.3");
    memcpy(g, "\"g\": 1.5", 8);
    ct_write_file(scene, text);
    expect_failure(args, 3, "media[0].phase.g", 1);
}

static void test_missing_vdb(void** state)
{
    (void)state;
    const char* scene = ct_path(dir, "scene.json");
    ct_write_scene(scene, 4, 3, NULL);
    char args[4096];
    snprintf(args, sizeof args, "'%s' -o '%s' --vdb '%s'", scene, ct_path(dir, "out.exr"), ct_path(dir, "missing.vdb"));
    expect_failure(args, 3, "missing.vdb", 1);
}

static void test_unwritable_output(void** state)
{
    (void)state;
    const char* scene = ct_path(dir, "scene.json");
    ct_write_scene(scene, 4, 3, NULL);
    char args[4096];
    snprintf(args, sizeof args, "'%s' -o '%s'", scene, ct_path(dir, "no/such/dir/out.exr"));
    expect_failure(args, 4, "no/such/dir", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --preview '%s'", scene, ct_path(dir, "out.exr"),
             ct_path(dir, "nodir/p.png"));
    expect_failure(args, 4, "nodir", 1);
    if (geteuid() != 0) { /* root writes anywhere */
        char ro[2048];
        snprintf(ro, sizeof ro, "%s/ro", dir);
        assert_int_equal(mkdir(ro, 0500), 0);
        snprintf(args, sizeof args, "'%s' -o '%s/out.exr'", scene, ro);
        expect_failure(args, 4, "not writable", 2);
        rmdir(ro);
    }
}

static void test_bad_colour_space_and_flags(void** state)
{
    (void)state;
    const char* scene = ct_path(dir, "scene.json");
    ct_write_scene(scene, 4, 3, NULL);
    char args[4096];
#ifdef VBL_TEST_HAVE_COLOR
    snprintf(args, sizeof args, "'%s' -o '%s' --output-space NoSuchSpace", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "NoSuchSpace", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --output-space 'sRGB - Display'", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "not a scene-linear", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --preview '%s' --display NoSuchDisplay", scene,
             ct_path(dir, "out.exr"), ct_path(dir, "p.png"));
    expect_failure(args, 2, "NoSuchDisplay", 1);
#endif
    snprintf(args, sizeof args, "'%s' -o '%s' --compression lzma", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "--compression", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --aov depth", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "--aov", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --half-layers Z", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "--half-layers", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --vbl-single-scattering photons", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "--vbl-single-scattering", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --beams-alpha 0", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "--beams-alpha", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --beams-radius0 -1", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "--beams-radius0", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --vsl-placement camera", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "--vsl-placement", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --vsl-path-extension maybe", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "--vsl-path-extension", 1);
    snprintf(args, sizeof args, "'%s' -o '%s' --vsl-lights 0", scene, ct_path(dir, "out.exr"));
    expect_failure(args, 2, "--vsl-lights", 1);
}

/* A documented limit (vbl_render_limits, render.md "Limits at the extremes") is one warning line
 * on stderr and the render still runs: g 0.999 with vpl warns naming the field, pt does not. */
static void test_limit_warnings(void** state)
{
    (void)state;
    const char* scene = ct_path(dir, "scene.json");
    ct_write_scene(scene, 4, 3, NULL);
    FILE* f = fopen(scene, "r");
    char text[4096];
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = 0;
    fclose(f);
    char* g = strstr(text, "\"g\": 0.3}");
    assert_non_null(g);
    char edited[4200];
    snprintf(edited, sizeof edited, "%.*s\"g\": 0.999}%s", (int)(g - text), text, g + strlen("\"g\": 0.3}"));
    ct_write_file(scene, edited);
    static const char* const methods[2] = {"vpl", "pt"};
    for (int k = 0; k < 2; ++k) {
        char args[4096];
        snprintf(args, sizeof args, "'%s' -o '%s' -q --method %s --passes 1 --spp 1 --light-paths 64 --threads 1",
                 scene, ct_path(dir, "out.exr"), methods[k]);
        char* log = NULL;
        int got = ct_render(args, &log);
        if (got != 0) fail_msg("vbl render %s: exit %d, output:\n%s", args, got, log ? log : "");
        const char* w = log ? strstr(log, "vbl render: warning: ") : NULL;
        if (k == 0) {
            if (!w || !strstr(w, "media[0] phase g = 0.999") || !strstr(w, "method 'vpl'"))
                fail_msg("vbl render %s: no g warning, output:\n%s", args, log ? log : "");
            /* one line for the one limit */
            const char* end = strchr(w, '\n');
            assert_non_null(end);
            assert_null(strstr(end, "warning:"));
        } else if (w) {
            fail_msg("vbl render %s: unexpected warning, output:\n%s", args, log);
        }
        free(log);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_missing_scene, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_malformed_scene, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_missing_vdb, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_unwritable_output, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_bad_colour_space_and_flags, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_limit_warnings, setup_each, teardown_each),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
