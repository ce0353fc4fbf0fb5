/* Frame ranges and frame patterns for `vbl render --frames` (docs/readme/pipeline.md, "Frames").
 * The path rules mirror libvbl's scene loader (libvbl/src/scene/scene_frame.c): a run of N '#'
 * is the frame zero-padded to N digits, "%04d" / "%d" are printf-style. */
#ifndef VBL_CLI_FRAMES_H
#define VBL_CLI_FRAMES_H

#include <stddef.h>

#define VBL_FRAMES_MAX 1000000

/* Parses "5", "1-10", "1-100x2", "1,3,7", "1-9x4,20" (frames >= 0, steps >= 1, ranges
 * ascending). *out (malloc'd) receives the frames in the order written; returns the count, or
 * 0 with a message in err[err_size] on a bad spec. */
int vbl_frames_parse(const char* spec, int** out, char* err, size_t err_size);

/* 1 if `path` holds a frame pattern. */
int vbl_frames_has_pattern(const char* path);

/* `pattern` with every frame pattern replaced by `frame` (0 on success, -1 if it does not fit or
 * holds a '%' conversion other than d and %%). */
int vbl_frames_format(const char* pattern, int frame, char* out, size_t size);

#endif
