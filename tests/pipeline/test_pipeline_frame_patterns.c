/* Frame specs and frame patterns: `--frames` parsing (plugins/cli/frames.c) and the path
 * substitution of the scene loader (libvbl/src/scene/scene_frame.c), which must agree. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <stdlib.h>
#include <string.h>

#include "frames.h"
#include "scene/scene_frame.h"

static void test_frame_specs(void** state)
{
    (void)state;
    char err[256];
    int* f = NULL;
    assert_int_equal(vbl_frames_parse("5", &f, err, sizeof err), 1);
    assert_int_equal(f[0], 5);
    free(f);
    assert_int_equal(vbl_frames_parse("1-10", &f, err, sizeof err), 10);
    assert_int_equal(f[9], 10);
    free(f);
    assert_int_equal(vbl_frames_parse("1-100x2", &f, err, sizeof err), 50);
    assert_int_equal(f[0], 1);
    assert_int_equal(f[49], 99);
    free(f);
    assert_int_equal(vbl_frames_parse("1,3,7", &f, err, sizeof err), 3);
    assert_int_equal(f[2], 7);
    free(f);
    assert_int_equal(vbl_frames_parse("0-9x4,20", &f, err, sizeof err), 4); /* 0 4 8 20 */
    assert_int_equal(f[2], 8);
    assert_int_equal(f[3], 20);
    free(f);
    static const char* const bad[] = {"", "x", "5-1", "1-3x0", "1,", "-3", "1-", "1-3y2", "1.5", "1,,2", NULL};
    for (int i = 0; bad[i]; ++i) {
        f = NULL;
        if (vbl_frames_parse(bad[i], &f, err, sizeof err) != 0) fail_msg("'%s' accepted", bad[i]);
        assert_null(f);
        assert_non_null(strstr(err, "--frames"));
    }
}

static void test_patterns(void** state)
{
    (void)state;
    static const char* const cases[][3] = {
        {"smoke.####.vdb", "7", "smoke.0007.vdb"}, {"smoke.%04d.vdb", "7", "smoke.0007.vdb"},
        {"s.%d.vdb", "12345", "s.12345.vdb"},      {"s.#.vdb", "42", "s.42.vdb"},
        {"a/%%/b.%03d", "5", "a/%/b.005"},         {"s.%5d", "3", "s.    3"},
        {"plain.vdb", "3", "plain.vdb"},           {"f##_g###", "9", "f09_g009"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char b[256];
        int frame = atoi(cases[i][1]);
        assert_int_equal(vbl_frame_path_format(cases[i][0], frame, b, sizeof b), 0);
        assert_string_equal(b, cases[i][2]);
        int has = strcmp(cases[i][0], "plain.vdb") != 0;
        assert_int_equal(vbl_frame_path_has_pattern(cases[i][0]), has);
    }
    char out[8];
    assert_int_equal(vbl_frame_path_format("s.%s", 1, out, sizeof out), -1);      /* only d conversions */
    assert_int_equal(vbl_frame_path_format("long.####.vdb", 1, out, sizeof out), -1); /* does not fit */
    assert_int_equal(vbl_frame_path_has_pattern("100%%.vdb"), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frame_specs),
        cmocka_unit_test(test_patterns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
