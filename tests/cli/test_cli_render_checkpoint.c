/* `vbl render` checkpoints: with --checkpoint-passes 1 a render killed (SIGKILL) after its first
 * checkpoint leaves a complete, readable EXR of the passes so far and no temporary files;
 * checkpointing does not change the final image; SIGTERM writes the passes done and exits 5. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli_test_util.h"
#include "vbl_exr.h"

#define W 16
#define H 12

static char* dir;
static const char* scene;

static int setup(void** state)
{
    (void)state;
    dir = ct_make_dir();
    static char scene_path[2048];
    snprintf(scene_path, sizeof scene_path, "%s/scene.json", dir);
    ct_write_scene(scene_path, W, H, NULL);
    scene = scene_path;
    return 0;
}

static int teardown(void** state)
{
    (void)state;
    ct_remove_dir(dir);
    free(dir);
    return 0;
}

static void sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/* Starts `vbl render SCENE -o OUT -q --checkpoint-passes 1 --passes 100000 --spp 64` (a pass
 * takes tens of milliseconds, a checkpoint write well under one) and waits for OUT to appear. */
static pid_t start_long_render(const char* out)
{
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        execl(ct_vbl(), "vbl", "render", scene, "-o", out, "-q", "--checkpoint-passes", "1", "--passes", "100000",
              "--spp", "64", "--threads", "1", (char*)NULL);
        _exit(127);
    }
    for (int waited = 0; access(out, F_OK) != 0; ++waited) {
        int status = 0;
        if (waitpid(pid, &status, WNOHANG) == pid) fail_msg("vbl render exited early (status %d)", status);
        if (waited > 60000) {
            kill(pid, SIGKILL);
            waitpid(pid, NULL, 0);
            fail_msg("no checkpoint after 60 s");
        }
        sleep_ms(1);
    }
    return pid;
}

static void assert_readable_checkpoint(const char* out, const char* status_a, const char* status_b)
{
    vbl_exr_image* img = NULL;
    if (vbl_exr_read(out, &img) != VBL_SUCCESS) fail_msg("%s", vbl_last_error_message());
    const char* status = vbl_exr_image_attribute(img, "vbl:status", NULL);
    assert_non_null(status);
    if (strcmp(status, status_a) && strcmp(status, status_b)) fail_msg("vbl:status = %s", status);
    const char* passes = vbl_exr_image_attribute(img, "vbl:passes", NULL);
    assert_non_null(passes);
    assert_true(atoi(passes) >= 1);
    assert_string_equal(vbl_exr_image_attribute(img, "vbl:passes_requested", NULL), "100000");
    const float* r = vbl_exr_image_channel_pixels(img, vbl_exr_image_find_channel(img, "R"));
    const float* e = vbl_exr_image_channel_pixels(img, vbl_exr_image_find_channel(img, "background.R"));
    const float* d = vbl_exr_image_channel_pixels(img, vbl_exr_image_find_channel(img, "volume_direct.R"));
    const float* m = vbl_exr_image_channel_pixels(img, vbl_exr_image_find_channel(img, "volume_from_volume.R"));
    assert_true(r && e && d && m);
    for (int i = 0; i < W * H; ++i) assert_true(e[i] + d[i] + m[i] == r[i]);
    vbl_exr_image_release(img);
    /* only the scene and the EXR: no temporary file left behind */
    char names[1024];
    if (ct_count_entries(dir, names, sizeof names) != 2) fail_msg("folder holds %s", names);
}

static void test_killed_render_keeps_checkpoint(void** state)
{
    (void)state;
    const char* out = ct_path(dir, "killed.exr");
    pid_t pid = start_long_render(out);
    kill(pid, SIGKILL);
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFSIGNALED(status));
    assert_readable_checkpoint(out, "checkpoint", "checkpoint");
    remove(out);
}

static void test_sigterm_writes_passes_done(void** state)
{
    (void)state;
    const char* out = ct_path(dir, "term.exr");
    pid_t pid = start_long_render(out);
    kill(pid, SIGTERM);
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 5);
    assert_readable_checkpoint(out, "interrupted", "checkpoint");
    remove(out);
}

/* Checkpoints (by passes or seconds) leave the final image bit-identical to a plain render. */
static void test_checkpoints_do_not_change_the_image(void** state)
{
    (void)state;
    static const char* const runs[3][2] = {{"plain.exr", ""},
                                           {"by_passes.exr", "--checkpoint-passes 1"},
                                           {"by_seconds.exr", "--checkpoint-seconds 0.001"}};
    vbl_exr_image* img[3] = {NULL, NULL, NULL};
    for (int k = 0; k < 3; ++k) {
        char args[4096];
        snprintf(args, sizeof args, "'%s' -o '%s' -q --passes 3 %s", scene, ct_path(dir, runs[k][0]), runs[k][1]);
        char* log = NULL;
        int code = ct_render(args, &log);
        if (code) fail_msg("vbl render %s -> %d\n%s", args, code, log ? log : "");
        free(log);
        if (vbl_exr_read(ct_path(dir, runs[k][0]), &img[k])) fail_msg("%s", vbl_last_error_message());
        assert_string_equal(vbl_exr_image_attribute(img[k], "vbl:status", NULL), "complete");
        assert_string_equal(vbl_exr_image_attribute(img[k], "vbl:passes", NULL), "3");
    }
    for (int k = 1; k < 3; ++k)
        for (int c = 0; c < vbl_exr_image_channel_count(img[0]); ++c) {
            const char* name = vbl_exr_image_channel_name(img[0], c);
            int j = vbl_exr_image_find_channel(img[k], name);
            assert_true(j >= 0);
            assert_memory_equal(vbl_exr_image_channel_pixels(img[0], c), vbl_exr_image_channel_pixels(img[k], j),
                                sizeof(float) * W * H);
        }
    for (int k = 0; k < 3; ++k) {
        vbl_exr_image_release(img[k]);
        remove(ct_path(dir, runs[k][0]));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_killed_render_keeps_checkpoint),
        cmocka_unit_test(test_sigterm_writes_passes_done),
        cmocka_unit_test(test_checkpoints_do_not_change_the_image),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
