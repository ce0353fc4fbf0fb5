/* Colour-managed scene loading for Python through the OCIO adapter (vbl_python_native.h): the same
 * conversion `vbl render` makes (plugins/cli/render_output.c, vbl_render_convert_scene_color). */
#include <stdio.h>
#include <stdlib.h>

#include "vbl_color.h"
#include "py_color_config.h"
#include "vbl_python_native.h"

struct vbl_py_color {
    vbl_color_config* config;
    const char* scene_space;
};

vbl_result vbl_py_color_open(const char* config, vbl_py_color** out)
{
    *out = NULL;
    vbl_py_color* c = calloc(1, sizeof *c);
    if (!c) return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "vbl: out of memory opening the colour config");
    vbl_result r = vbl_color_config_open(config, &c->config);
    if (!r) r = vbl_color_resolve_space(c->config, "scene_linear", &c->scene_space);
    if (r) {
        vbl_py_color_release(c);
        return r;
    }
    *out = c;
    return VBL_SUCCESS;
}

void vbl_py_color_release(vbl_py_color* c)
{
    if (!c) return;
    vbl_color_config_release(c->config);
    free(c);
}

const char* vbl_py_color_scene_space(const vbl_py_color* c) { return c ? c->scene_space : NULL; }

vbl_result vbl_py_convert_scene_color(void* user, const char* color_space, const char* field, double rgb[3])
{
    (void)field; /* the loader prefixes the scene file, color_space and the field */
    const vbl_py_color* c = user;
    const char* space = NULL;
    vbl_result r = vbl_color_resolve_space(c->config, color_space, &space);
    float v[3] = {(float)rgb[0], (float)rgb[1], (float)rgb[2]};
    if (!r) r = vbl_color_convert_rgb(c->config, space, c->scene_space, v);
    if (r) {
        char msg[2048];
        snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
        return vbl_report_error(VBL_ERROR_SCENE, "%s", msg);
    }
    for (int i = 0; i < 3; ++i) rgb[i] = v[i];
    return VBL_SUCCESS;
}

vbl_result vbl_py_color_check_scene(const vbl_py_color* c, const vbl_scene* scene)
{
    const char* space = vbl_scene_color_space(scene);
    const char* resolved = NULL;
    if (space && vbl_color_resolve_space(c->config, space, &resolved)) {
        char msg[2048];
        snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
        return vbl_report_error(VBL_ERROR_SCENE, "%s: color_space = \"%s\": %s", vbl_scene_path(scene), space, msg);
    }
    return VBL_SUCCESS;
}

int vbl_py_color_chromaticities(const vbl_py_color* c, float out[8])
{
    int ok = c && vbl_color_space_chromaticities(c->config, c->scene_space, out) == VBL_SUCCESS;
    vbl_clear_error(); /* unknown primaries: no attribute (documented) */
    return ok;
}

const vbl_color_config* vbl_py_color_config(const vbl_py_color* c) { return c ? c->config : NULL; }
