/* A film as the EXR `vbl render` writes (vbl_python_native.h): a thin wrapper over
 * plugins/render_exr (vbl_render_exr.h), the implementation the `vbl` command writes with, so the
 * layers, HALF rules, colour conversion and header attributes are the CLI's by construction
 * (tests/pipeline/test_python_idioms.py compares the two files attribute by attribute). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "py_color_config.h"
#include "vbl_render_exr.h"
#include "vbl_python_native.h"

vbl_result vbl_py_film_write_exr(const vbl_film* film, const char* path, const vbl_py_exr_options* o)
{
    if (!film || !path || !o || o->size < sizeof *o || !o->scene || !o->render_options)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT,
                                "vbl_py_film_write_exr: film, path, options, options->scene and "
                                "options->render_options are required");
    vbl_render_exr_settings* s = calloc(1, sizeof *s);
    if (!s) return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    vbl_render_exr_settings_init(s);
    const char* scene_path = vbl_scene_path(o->scene);
    s->scene_label = o->scene_label ? o->scene_label : scene_path;
    s->has_frame = o->has_frame;
    s->frame = o->frame;
    s->preset = o->preset;
    s->aov_z = o->aov_z;
    s->aov_samples = o->aov_samples;
    s->aov_variance = o->aov_variance;
    s->half_all = o->half_all;
    s->half_layers = o->half_layers;
    s->compression = o->compression;
    vbl_result r = vbl_render_exr_check_half_layers(o->half_layers);
    if (r) {
        char msg[2048];
        snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
        r = vbl_report_error(r, "%s: half_layers: %s", path, msg);
    }
    if (!r) r = vbl_render_exr_hash_file(s, scene_path);
    vbl_render_exr_set_scene(s, o->scene);
    vbl_py_color* own = NULL;
    const vbl_py_color* color = o->color;
    if (!r && !color) r = vbl_py_color_open(NULL, &own), color = own;
    if (!r) {
        const char* space = vbl_py_color_scene_space(color);
        const char* output = space; /* the EXR's colour space */
        if (o->output_space) r = vbl_color_resolve_space(vbl_py_color_config(color), o->output_space, &output);
        if (!r) r = vbl_render_exr_set_color(s, vbl_py_color_config(color), space, output);
        if (r) {
            char msg[2048];
            snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
            r = vbl_report_error(r, "%s: output_space: %s", path, msg);
        }
    }
    if (!r)
        r = vbl_render_exr_write_film(path, film, s, o->render_options,
                                      o->passes_requested > 0 ? o->passes_requested : o->render_options->passes,
                                      o->status, -1.0);
    vbl_py_color_release(own);
    free(s);
    return r;
}
