/* Frame ranges and frame patterns for `vbl render --frames` (docs/readme/pipeline.md, "Frames").
 * Path patterns are libvbl's (vbl_frame_path_format): the same rules as the scene loader. */
#ifndef VBL_CLI_FRAMES_H
#define VBL_CLI_FRAMES_H

#include <stddef.h>

#define VBL_FRAMES_MAX 1000000

/* Parses "5", "1-10", "1-100x2", "1,3,7", "1-9x4,20" (frames >= 0, steps >= 1, ranges
 * ascending). *out (malloc'd) receives the frames in the order written; returns the count, or
 * 0 with a message in err[err_size] on a bad spec. */
int vbl_frames_parse(const char* spec, int** out, char* err, size_t err_size);

/* Frame patterns in output paths: vbl_frame_path_has_pattern / vbl_frame_path_format (vbl/vbl_render.h). */

#endif
