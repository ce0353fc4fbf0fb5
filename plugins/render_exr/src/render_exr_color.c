/* The output colour space of `vbl render -o` through the OCIO adapter (vbl_render_exr.h): the
 * scene_linear -> output matrix and the chromaticities. */
#include <math.h>
#include <string.h>

#include "vbl_render_exr.h"

vbl_result vbl_render_exr_set_color(vbl_render_exr_settings* s, const vbl_color_config* config,
                                    const char* scene_space, const char* output_space)
{
    s->scene_space = scene_space;
    s->output_space = output_space;
    s->convert = strcmp(output_space, scene_space) != 0;
    if (s->convert) { /* read off the conversion of the unit vectors; the space must be linear */
        for (int c = 0; c < 3; ++c) {
            float e[3] = {0.0f, 0.0f, 0.0f};
            e[c] = 1.0f;
            vbl_result r = vbl_color_convert_rgb(config, scene_space, output_space, e);
            if (r) return r;
            for (int k = 0; k < 3; ++k) s->matrix[3 * k + c] = e[k];
        }
        static const float probes[2][3] = {{0.02f, 0.5f, 3.0f}, {40.0f, 0.25f, 0.125f}};
        for (int p = 0; p < 2; ++p) {
            float v[3] = {probes[p][0], probes[p][1], probes[p][2]};
            vbl_result r = vbl_color_convert_rgb(config, scene_space, output_space, v);
            if (r) return r;
            for (int k = 0; k < 3; ++k) {
                const double* m = s->matrix + 3 * k;
                double want = m[0] * probes[p][0] + m[1] * probes[p][1] + m[2] * probes[p][2];
                if (!(fabs(want - v[k]) <= 1e-4 * (1.0 + fabs(want))))
                    return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT,
                                            "'%s' is not a scene-linear colour space (the EXR holds linear "
                                            "radiance; use a display space only for a preview)",
                                            output_space);
            }
        }
    }
    s->have_chroma = vbl_color_space_chromaticities(config, output_space, s->chroma) == VBL_SUCCESS;
    vbl_clear_error(); /* unknown primaries: no chromaticities attribute (documented) */
    return VBL_SUCCESS;
}
