/* Quality presets: named bundles of render settings for users who trade accuracy for time.
 * The numbers are chosen from the measured error-vs-time curves (bench/bench_methods,
 * docs/readme/beams.md); R0 stays 0 (derived from the scene's scale, render/radius_schedule). */
#include <string.h>

#include "core/error.h"
#include "vbl/vbl_render.h"

typedef struct vbl_preset {
    const char* name;
    vbl_render_method method;
    int passes, spp, light_paths;
    double vbl_alpha;
    vbl_transmittance_estimator transmittance;
} vbl_preset;

static const vbl_preset vbl_presets[] = {
    {"preview", VBL_RENDER_VBL, 4, 1, 200, 0.7, VBL_TRANSMITTANCE_RATIO_TRACKING},
    {"production", VBL_RENDER_VBL, 32, 1, 1000, 0.7, VBL_TRANSMITTANCE_RATIO_TRACKING},
    {"final", VBL_RENDER_VBL, 128, 1, 4000, 0.7, VBL_TRANSMITTANCE_RATIO_TRACKING},
};

vbl_result vbl_render_options_apply_preset(const char* preset, vbl_render_options* options)
{
    if (!preset || !options) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render_options_apply_preset: NULL argument");
    if (options->size < sizeof(vbl_render_options))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render_options_apply_preset: options.size is too small");
    for (size_t i = 0; i < sizeof vbl_presets / sizeof vbl_presets[0]; ++i) {
        const vbl_preset* p = &vbl_presets[i];
        if (strcmp(p->name, preset) != 0) continue;
        options->method = p->method;
        options->passes = p->passes;
        options->spp = p->spp;
        options->light_paths = p->light_paths;
        options->vbl_alpha = p->vbl_alpha;
        options->vbl_radius0 = 0.0;
        options->transmittance = p->transmittance;
        return VBL_SUCCESS;
    }
    return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "unknown preset '%s' (preview, production, final)", preset);
}
