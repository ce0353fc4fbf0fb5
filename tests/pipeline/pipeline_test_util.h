/* What the `vbl render` / `vbl merge` pipeline tests share (test_pipeline_split.c,
 * test_pipeline_robust.c), on top of cli_test_util: the scene folder, running the binary against
 * an expected exit, reading EXR files and attributes (failing the test on an error). */
#ifndef VBL_PIPELINE_TEST_UTIL_H
#define VBL_PIPELINE_TEST_UTIL_H

#include <stddef.h>

#include "vbl_exr.h"

/* The cmocka group fixture: pt_setup makes a temporary folder pt_dir (ct_make_dir, malloc'd)
 * with the small scene (ct_write_scene) of PT_W x PT_H pixels at pt_scene; pt_teardown removes
 * the folder and all below it (rm -rf) and frees pt_dir. */
#define PT_W 16
#define PT_H 12
extern char* pt_dir;
extern char pt_scene[2048];
int pt_setup(void** state);
int pt_teardown(void** state);
/* Runs `vbl ARGS` (stdout+stderr captured); fails unless it exits `code` with `needle` in its
 * output (any output where needle is NULL). */
void pt_run_expect(const char* args, int code, const char* needle);
/* Reads an EXR file; fails the test if it cannot. */
vbl_exr_image* pt_read_exr(const char* path);
/* An attribute's value; fails the test if the image lacks it. */
const char* pt_attr(const vbl_exr_image* image, const char* name);
void pt_sleep_ms(int ms);

#endif
