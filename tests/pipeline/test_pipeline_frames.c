/* `vbl render` in batch jobs (issue 7): --frames over VDB sequences (#### and %04d in the scene
 * and output paths), a missing frame stopping the batch or not (--keep-going), --preset,
 * --progress json lines and the documented exit codes. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli_test_util.h"
#include "vbl_exr.h"

#define W 8
#define H 6

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

static void copy_file(const char* from, const char* to)
{
    FILE* in = fopen(from, "rb");
    FILE* out = fopen(to, "wb");
    assert_true(in && out);
    char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, in)) > 0) assert_int_equal(fwrite(buf, 1, n, out), n);
    fclose(in);
    fclose(out);
}

/* A scene in dir whose media[0].vdb is `vdb` (relative to the scene). */
static const char* write_sequence_scene(const char* vdb)
{
    static char path[2048];
    snprintf(path, sizeof path, "%s/shot.json", dir);
    char text[4096];
    snprintf(text, sizeof text,
             "{\"camera\": {\"position\": [0.75, -3.0, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 40,\n"
             "             \"resolution\": [%d, %d]},\n"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.3, 0.5, -0.8], \"irradiance\": [2, 2, 2]}],\n"
             " \"media\": [{\"vdb\": \"%s\", \"density_scale\": 3.0}],\n"
             " \"render\": {\"method\": \"pt\", \"passes\": 2, \"spp\": 1, \"seed\": 3, \"max_bounces\": 2}}\n",
             W, H, vdb);
    ct_write_file(path, text);
    return path;
}

static int run(const char* args, char** log)
{
    return ct_vbl_run(args, log, 1);
}

static void expect(const char* args, int code, const char* needle)
{
    char* log = NULL;
    int got = run(args, &log);
    if (got != code || (needle && (!log || !strstr(log, needle))))
        fail_msg("vbl %s: exit %d (want %d), output:\n%s(want '%s')", args, got, code, log ? log : "",
                 needle ? needle : "");
    free(log);
}

static const char* exr_attr(const char* path, const char* name, char* out, size_t size)
{
    vbl_exr_image* img = NULL;
    if (vbl_exr_read(path, &img)) fail_msg("%s: %s", path, vbl_last_error_message());
    const char* v = vbl_exr_image_attribute(img, name, NULL);
    snprintf(out, size, "%s", v ? v : "(none)");
    vbl_exr_image_release(img);
    return out;
}

static void test_frames_over_a_vdb_sequence(void** state)
{
    (void)state;
    for (int f = 1; f <= 5; f += 2) {
        char name[64];
        snprintf(name, sizeof name, "box.%04d.vdb", f);
        copy_file(ct_fixture("box.vdb"), ct_path(dir, name));
    }
    const char* scene = write_sequence_scene("box.####.vdb");
    char args[8192], value[256];
    snprintf(args, sizeof args, "render '%s' -o '%s/out.%%04d.exr' -q --frames 1-5x2", scene, dir);
    expect(args, 0, NULL);
    for (int f = 1; f <= 5; f += 2) {
        char name[64];
        snprintf(name, sizeof name, "out.%04d.exr", f);
        assert_int_equal(atoi(exr_attr(ct_path(dir, name), "vbl:frame", value, sizeof value)), f);
        assert_non_null(strstr(exr_attr(ct_path(dir, name), "vbl:media", value, sizeof value), "box.000"));
    }
    /* a list, and printf-style patterns in the scene */
    write_sequence_scene("box.%04d.vdb");
    snprintf(args, sizeof args, "render '%s' -o '%s/list.####.exr' -q --frames 5,1", scene, dir);
    expect(args, 0, NULL);
    assert_true(access(ct_path(dir, "list.0005.exr"), F_OK) == 0 && access(ct_path(dir, "list.0001.exr"), F_OK) == 0);
    /* a pattern without --frames; several frames into one file; bad specs */
    snprintf(args, sizeof args, "render '%s' -o '%s/x.exr' -q", scene, dir);
    expect(args, 3, "no frame was given");
    snprintf(args, sizeof args, "render '%s' -o '%s/x.exr' -q --frames 1-3", scene, dir);
    expect(args, 2, "needs a frame pattern");
    snprintf(args, sizeof args, "render '%s' -o '%s/x.####.exr' -q", scene, dir);
    expect(args, 2, "no --frames");
    snprintf(args, sizeof args, "render '%s' -o '%s/x.####.exr' -q --frames 5-1", scene, dir);
    expect(args, 2, "--frames");
    snprintf(args, sizeof args, "render '%s' -o '%s/x.####.exr' -q --frames 1-3x0", scene, dir);
    expect(args, 2, "--frames");
    assert_true(access(ct_path(dir, "x.exr"), F_OK) != 0);
}

static void test_missing_frame_stops_or_keeps_going(void** state)
{
    (void)state;
    copy_file(ct_fixture("box.vdb"), ct_path(dir, "box.0001.vdb"));
    copy_file(ct_fixture("box.vdb"), ct_path(dir, "box.0003.vdb"));
    const char* scene = write_sequence_scene("box.####.vdb");
    char args[8192];
    /* default: stop at the missing frame 2 (exit 3, naming the frame and the file) */
    snprintf(args, sizeof args, "render '%s' -o '%s/s.####.exr' -q --frames 1-3", scene, dir);
    expect(args, 3, "frame 2: cannot open");
    assert_true(access(ct_path(dir, "s.0001.exr"), F_OK) == 0);
    assert_true(access(ct_path(dir, "s.0003.exr"), F_OK) != 0);
    /* --keep-going: frame 3 is rendered, the exit code still says a frame failed */
    snprintf(args, sizeof args, "render '%s' -o '%s/k.####.exr' -q --frames 1-3 --keep-going", scene, dir);
    expect(args, 3, "box.0002.vdb");
    assert_true(access(ct_path(dir, "k.0001.exr"), F_OK) == 0);
    assert_true(access(ct_path(dir, "k.0002.exr"), F_OK) != 0);
    assert_true(access(ct_path(dir, "k.0003.exr"), F_OK) == 0);
}

static void test_presets(void** state)
{
    (void)state;
    char scene[2048], args[8192], value[256];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    ct_write_scene(scene, W, H, NULL);
    const char* out = ct_path(dir, "p.exr");
    /* explicit flags win over the preset */
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --preset preview --method pt --passes 2 --spp 1", scene, out);
    expect(args, 0, NULL);
    assert_string_equal(exr_attr(out, "vbl:preset", value, sizeof value), "preview");
    assert_string_equal(exr_attr(out, "vbl:passes", value, sizeof value), "2");
    assert_string_equal(exr_attr(out, "vbl:method", value, sizeof value), "pt");
    remove(out);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --preset ultra", scene, out);
    expect(args, 2, "--preset 'ultra'");
    assert_true(access(out, F_OK) != 0);
}

static void test_progress_json_lines(void** state)
{
    (void)state;
    char scene[2048], args[8192];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    ct_write_scene(scene, W, H, NULL);
    snprintf(args, sizeof args, "render '%s' -o '%s' --passes 3 --progress json", scene, ct_path(dir, "j.exr"));
    char* out = NULL;
    assert_int_equal(ct_vbl_run(args, &out, 0), 0); /* stdout only */
    assert_non_null(out);
    int passes = 0, done = 0, end = 0, lines = 0;
    for (char* line = strtok(out, "\n"); line; line = strtok(NULL, "\n")) {
        ++lines;
        size_t n = strlen(line);
        if (line[0] != '{' || line[n - 1] != '}') fail_msg("not a JSON object line: %s", line);
        if (strstr(line, "\"event\":\"pass\"")) {
            ++passes;
            assert_non_null(strstr(line, "\"passes\":3"));
            assert_non_null(strstr(line, "\"eta\":"));
            assert_non_null(strstr(line, "\"elapsed\":"));
        }
        if (strstr(line, "\"event\":\"done\"")) {
            ++done;
            assert_non_null(strstr(line, "\"status\":\"complete\""));
        }
        if (strstr(line, "\"event\":\"end\"")) {
            ++end;
            assert_non_null(strstr(line, "\"exit_code\":0"));
        }
    }
    assert_int_equal(passes, 3);
    assert_int_equal(done, 1);
    assert_int_equal(end, 1);
    free(out);
    /* a failed frame: the last line says so */
    snprintf(args, sizeof args, "render '%s/none.json' -o '%s' --progress json", dir, ct_path(dir, "j.exr"));
    out = NULL;
    assert_int_equal(ct_vbl_run(args, &out, 0), 3);
    assert_non_null(strstr(out, "\"exit_code\":3"));
    free(out);
}

static void sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/* Exit codes: 2 usage, 3 bad input, 4 unwritable output, 5 interrupted. */
static void test_exit_codes(void** state)
{
    (void)state;
    char scene[2048], args[8192];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    ct_write_scene(scene, W, H, NULL);
    snprintf(args, sizeof args, "render '%s' -o '%s' --pass-range 3-1", scene, ct_path(dir, "a.exr"));
    expect(args, 2, "--pass-range");
    snprintf(args, sizeof args, "render '%s' -o '%s' --passes 4 --pass-range 2-5", scene, ct_path(dir, "a.exr"));
    expect(args, 2, "--pass-range 2-5");
    snprintf(args, sizeof args, "render '%s/missing.json' -o '%s'", dir, ct_path(dir, "a.exr"));
    expect(args, 3, "missing.json");
    snprintf(args, sizeof args, "render '%s' -o '%s/nodir/a.exr'", scene, dir);
    expect(args, 4, "nodir");
    /* interrupted: SIGTERM while rendering -> 5 */
    const char* out = ct_path(dir, "term.exr");
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        int devnull = open("/dev/null", O_WRONLY);
        if (devnull >= 0) dup2(devnull, 1), dup2(devnull, 2);
        execl(ct_vbl(), "vbl", "render", scene, "-o", out, "--progress", "json", "--checkpoint-passes", "1",
              "--passes", "100000", "--threads", "1", (char*)NULL);
        _exit(127);
    }
    for (int waited = 0; access(out, F_OK) != 0 && waited < 60000; ++waited) sleep_ms(1);
    kill(pid, SIGTERM);
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_frames_over_a_vdb_sequence, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_missing_frame_stops_or_keeps_going, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_presets, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_progress_json_lines, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_exit_codes, setup_each, teardown_each),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
