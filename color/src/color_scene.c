/* Scene colours through a config (vbl_color.h): the scene loader's convert_color hook and the
 * check of a scene's color_space, shared by `vbl render` and the Python module. */
#include <stdio.h>

#include "vbl_color.h"

vbl_result vbl_color_convert_scene_color(void* user, const char* color_space, const char* field, double rgb[3])
{
    (void)field; /* the loader prefixes the scene file, color_space and the field */
    const vbl_color_scene_target* t = user;
    const char* space = NULL;
    vbl_result r = vbl_color_resolve_space(t->config, color_space, &space);
    float v[3] = {(float)rgb[0], (float)rgb[1], (float)rgb[2]};
    if (!r) r = vbl_color_convert_rgb(t->config, space, t->scene_space, v);
    if (r) {
        char msg[2048];
        snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
        return vbl_report_error(VBL_ERROR_SCENE, "%s", msg);
    }
    for (int i = 0; i < 3; ++i) rgb[i] = v[i];
    return VBL_SUCCESS;
}

vbl_result vbl_color_check_scene_space(const vbl_color_config* config, const char* scene_path,
                                       const char* color_space)
{
    const char* resolved = NULL;
    if (color_space && vbl_color_resolve_space(config, color_space, &resolved)) {
        char msg[2048];
        snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
        return vbl_report_error(VBL_ERROR_SCENE, "%s: color_space = \"%s\": %s", scene_path, color_space, msg);
    }
    return VBL_SUCCESS;
}
