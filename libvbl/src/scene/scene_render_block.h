/* The scene file's `render` block, parsed from the render options table
 * (vbl/vbl_render_options.h): every option with a scene key, in table order. */
#ifndef VBL_SCENE_RENDER_BLOCK_H
#define VBL_SCENE_RENDER_BLOCK_H

#include "scene/scene_json.h"
#include "vbl/vbl_render.h"

/* Reads root.render (optional) into *o, keeping the fields it leaves out. Failures name the
 * field: "render.vbl.alpha = 1 is outside (0, 1)", "unknown key 'render.vrl.sample'". */
vbl_result vbl_scene_parse_render_block(const vbl_json_ctx* ctx, const cJSON* root, vbl_render_options* o);

#endif
