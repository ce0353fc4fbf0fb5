/* Helpers for the `vbl render` end-to-end tests: temporary folders, files, running the binary,
 * reading EXR attributes and PNG headers. */
#ifndef VBL_CLI_TEST_UTIL_H
#define VBL_CLI_TEST_UTIL_H

#include <stdint.h>

/* Path of the vbl binary ($VBL_BINARY_DIR/bin/vbl). */
const char* ct_vbl(void);
/* $VBL_FIXTURE_DIR/name. */
const char* ct_fixture(const char* name);
/* mkdtemp under $TMPDIR or /tmp; the returned string is malloc'd. */
char* ct_make_dir(void);
/* Removes every file in dir (not recursive), then dir. */
void ct_remove_dir(const char* dir);
/* dir/name in a rotating static buffer (8 slots). */
const char* ct_path(const char* dir, const char* name);
void ct_write_file(const char* path, const char* text);
/* Entries of dir except . and ..; `names` (if not NULL) receives them comma-separated. */
int ct_count_entries(const char* dir, char* names, int size);
/* Runs `vbl render ARGS` through the shell with stdout+stderr captured into *output (malloc'd,
 * may be NULL); returns the exit status (or -1). */
int ct_render(const char* args, char** output);
/* Runs `vbl ARGS` through the shell; *output (malloc'd, may be NULL) receives stdout, and stderr
 * too when with_stderr (else stderr is discarded); returns the exit status (or -1). */
int ct_vbl_run(const char* args, char** output, int with_stderr);
/* A small scene (box.vdb, a distant light and an environment light) of W x H pixels. */
void ct_write_scene(const char* path, int width, int height, const char* extra_top_level);
/* FNV-1a 64 of a file's bytes. */
uint64_t ct_fnv1a64_file(const char* path);
/* Reads a PNG header: 1 if readable, with width, height, bit depth and colour type. */
int ct_png_info(const char* path, int* width, int* height, int* bit_depth, int* color_type);

#endif
