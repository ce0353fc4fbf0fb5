/* Per-frame values of scene fields for sequences (docs/readme/render.md, "Per-frame camera and
 * media"): an object {"<frame>": value, ...} keyed by integer frames. At frame f the value is the
 * key's at f, linearly interpolated between the nearest keys below and above f, and the first /
 * last key's outside them (held). */
#ifndef VBL_SCENE_SCENE_KEYFRAMES_H
#define VBL_SCENE_SCENE_KEYFRAMES_H

#include "scene/scene_json.h"

/* The two keys around `frame` among the members of `keys` that have `key` (NULL: the members
 * themselves are the values): *below / *above (may be equal), and the weight of *above. 0 if no
 * member qualifies; a member name that is not an integer fails (VBL_ERROR_SCENE, -1). */
int vbl_keyframes_find(const vbl_json_ctx* ctx, const cJSON* keys, const char* field, const char* key, int frame,
                       const cJSON** below, const cJSON** above, double* weight);

/* A number or [x,y,z] at `frame` from "frames": {"<f>": {"<key>": value}} into *out (kept when no
 * key has it). */
vbl_result vbl_keyframes_number(const vbl_json_ctx* ctx, const cJSON* keys, const char* field, const char* key,
                                int frame, double* out);
vbl_result vbl_keyframes_vec3(const vbl_json_ctx* ctx, const cJSON* keys, const char* field, const char* key,
                              int frame, vbl_vec3* out);

#endif
