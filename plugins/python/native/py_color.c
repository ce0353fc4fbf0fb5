/* Colour-managed scene loading for Python through the OCIO adapter (vbl_python_native.h): the same
 * conversion `vbl render` makes (vbl_color_convert_scene_color, color/src/color_scene.c). */
#include <stdio.h>
#include <stdlib.h>

#include "vbl_color.h"
#include "py_color_config.h"
#include "vbl_python_native.h"

struct vbl_py_color {
    vbl_color_config* config;
    const char* scene_space;
    vbl_color_scene_target target; /* {config, scene_space} for vbl_color_convert_scene_color */
};

vbl_result vbl_py_color_open(const char* config, vbl_py_color** out)
{
    *out = NULL;
    vbl_py_color* c = calloc(1, sizeof *c);
    if (!c) return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "vbl: out of memory opening the colour config");
    vbl_result r = vbl_color_config_open(config, &c->config);
    if (!r) r = vbl_color_resolve_space(c->config, "scene_linear", &c->scene_space);
    c->target = (vbl_color_scene_target){c->config, c->scene_space};
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
    return vbl_color_convert_scene_color(&((vbl_py_color*)user)->target, color_space, field, rgb);
}

vbl_result vbl_py_color_check_scene(const vbl_py_color* c, const vbl_scene* scene)
{
    return vbl_color_check_scene_space(c->config, vbl_scene_path(scene), vbl_scene_color_space(scene));
}

int vbl_py_color_chromaticities(const vbl_py_color* c, float out[8])
{
    int ok = c && vbl_color_space_chromaticities(c->config, c->scene_space, out) == VBL_SUCCESS;
    vbl_clear_error(); /* unknown primaries: no attribute (documented) */
    return ok;
}

const vbl_color_config* vbl_py_color_config(const vbl_py_color* c) { return c ? c->config : NULL; }
