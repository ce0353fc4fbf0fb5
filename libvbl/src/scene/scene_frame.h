/* Frame numbers in scene paths (VDB sequences): "smoke.####.vdb" (a run of N '#': the frame
 * zero-padded to N digits) and printf-style "smoke.%04d.vdb" / "%d" (only d conversions with an
 * optional 0-flag and width). Used by the scene loader for media[i].vdb when
 * vbl_scene_load_options.use_frame is set; the `vbl` command uses the same public functions
 * for its output paths. */
#ifndef VBL_SCENE_SCENE_FRAME_H
#define VBL_SCENE_SCENE_FRAME_H

#include <stddef.h>

#include <cjson/cJSON.h>

#include "vbl/vbl_render.h"

/* vbl_frame_path_has_pattern / vbl_frame_path_format: public (vbl/vbl_render.h). */

/* The scene loader's hook for media[i] (`medium` is its JSON object, `dir` the scene file's
 * directory with a trailing '/', `*vdb_override` the caller's override or NULL). When the path
 * in use (the override, else medium.vdb) has a frame pattern: fails (VBL_ERROR_SCENE) if
 * options->use_frame is 0, else substitutes options->frame, resolves a scene-relative path
 * against `dir`, checks that the file exists (VBL_ERROR_FILE_NOT_FOUND naming the field, the
 * frame and the file) and points *vdb_override at the result in buf[size]. Paths without a
 * pattern are left alone. */
vbl_result vbl_scene_frame_vdb(const char* scene_path, const char* field, const cJSON* medium, const char* dir,
                               const vbl_scene_load_options* options, const char** vdb_override, char* buf,
                               size_t size);

#endif
