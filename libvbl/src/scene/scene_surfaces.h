/* The scene file's "surfaces" array (docs/readme/surfaces.md): meshes (OBJ/PLY through assimp,
 * optionally subdivided with OpenSubdiv), their placement and materials. */
#ifndef VBL_SCENE_SCENE_SURFACES_H
#define VBL_SCENE_SCENE_SURFACES_H

#include <cjson/cJSON.h>

#include "scene/scene.h"
#include "scene/scene_json.h"

/* The loader's colour reader: `key` of `obj` as RGB in [min, max] after conversion to
 * scene_linear (keeps *out when absent). `colors` is the loader's opaque colour context. */
typedef vbl_result (*vbl_surface_color_fn)(const vbl_json_ctx* ctx, const void* colors, const cJSON* obj,
                                            const char* parent_field, const char* key, double min, double max,
                                            vbl_vec3* out);

/* Parses root["surfaces"] (absent: nothing) and adds every mesh to the scene. `dir` is the scene
 * file's directory (with trailing '/', or ""), against which relative mesh paths resolve. */
vbl_result vbl_scene_parse_surfaces(vbl_scene* scene, const vbl_json_ctx* ctx, const cJSON* root, const char* dir,
                                    vbl_surface_color_fn color, const void* colors);

/* vbl_material_validate as a vbl_error: "<prefix>.<field> = <value> is outside ..." with
 * VBL_ERROR_SCENE. */
vbl_result vbl_scene_material_check(const vbl_material* m, const char* prefix);

#endif
