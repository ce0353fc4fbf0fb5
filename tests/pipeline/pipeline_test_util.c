#define _POSIX_C_SOURCE 200809L
#include "pipeline_test_util.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdint.h>

#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli_test_util.h"

char* pt_dir;
char pt_scene[2048];

int pt_setup(void** state)
{
    (void)state;
    pt_dir = ct_make_dir();
    snprintf(pt_scene, sizeof pt_scene, "%s/scene.json", pt_dir);
    ct_write_scene(pt_scene, PT_W, PT_H, NULL);
    return 0;
}

int pt_teardown(void** state)
{
    (void)state;
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", pt_dir);
    int rc = system(cmd);
    free(pt_dir);
    return rc == 0 ? 0 : -1;
}

void pt_run_expect(const char* args, int code, const char* needle)
{
    char* log = NULL;
    int got = ct_vbl_run(args, &log, 1);
    if (got != code || (needle && (!log || !strstr(log, needle))))
        fail_msg("vbl %s -> exit %d (want %d, '%s')\n%s", args, got, code, needle ? needle : "", log ? log : "");
    free(log);
}

vbl_exr_image* pt_read_exr(const char* path)
{
    vbl_exr_image* image = NULL;
    if (vbl_exr_read(path, &image)) fail_msg("cannot read %s: %s", path, vbl_last_error_message());
    return image;
}

const char* pt_attr(const vbl_exr_image* image, const char* name)
{
    const char* v = vbl_exr_image_attribute(image, name, NULL);
    if (!v) fail_msg("no attribute %s", name);
    return v;
}

void pt_sleep_ms(int ms)
{
    struct timespec t = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}
