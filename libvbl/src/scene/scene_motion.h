/* Vector role grids and motion of the scene file (docs/readme/emission.md "Grids by role",
 * "Motion blur"): a medium's albedo grid ("albedo": {"grid", "vdb", "scale"}), its velocity
 * ("velocity": {"grid", "vdb", "scale"}), the scene's "fps" and camera.shutter. */
#ifndef VBL_SCENE_SCENE_MOTION_H
#define VBL_SCENE_SCENE_MOTION_H

#include "scene/scene.h"
#include "scene/scene_json.h"

/* Loads the albedo grid named by the object `albedo` (field e.g. "media[0].albedo"; its "scale"
 * is already in medium->albedo) from its "vdb" or medium->vdb_path (`dir`: the scene's folder).
 * Fails if albedo * A(x) can exceed 1 in a channel. */
vbl_result vbl_scene_parse_albedo_grid(const vbl_json_ctx* ctx, const cJSON* albedo, const char* field, const char* dir,
                                       vbl_medium* medium);
/* A role object's file: its own "vdb" (absolute, or relative to the scene's folder `dir`), else the
 * medium's file `medium_path`. */
vbl_result vbl_scene_role_file(const vbl_json_ctx* ctx, const cJSON* obj, const char* field, const char* dir,
                               const char* medium_path, char* out, size_t size);
/* "velocity" of medium object `obj` (absent: nothing). */
vbl_result vbl_scene_parse_velocity(const vbl_json_ctx* ctx, const cJSON* obj, const char* field, const char* dir,
                                    vbl_medium* medium);
/* After the media and the extinction field: "fps" and camera.shutter; decides scene->motion and
 * gives the extinction components their velocity (dilated majorants). */
vbl_result vbl_scene_parse_motion(const vbl_json_ctx* ctx, const cJSON* root, vbl_scene* scene);

#endif
