/* Quality presets: named bundles of render settings for users who trade accuracy for time.
 * The numbers come from the measured error-vs-time curves (bench/bench_curves.c,
 * docs/readme/performance.md): on both benchmark clouds (the sample cloud and a dense g = 0.8
 * one) the path tracer reaches every error level first, so all three presets use pt and differ
 * in camera samples; the vbl radius schedule (alpha 0.7, R0 0 = derived from the scene's scale,
 * render/radius_schedule) is still set so that `--preset X --method vbl` gets sensible values. */
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

/* Passes x spp from the pt curve on the sample cloud (medium rMAE = error of beauty - emission
 * against a long pt reference; docs/readme/performance.md has the measured error and time of
 * each): preview ~0.14, production ~0.05, final ~0.03. light_paths and the vbl schedule only
 * matter when the caller switches the method (pt ignores them); they are the per-pass counts the
 * benchmark found affordable (a vbl pass of 100 light paths costs ~100x a pt pass of 4 spp). */
static const vbl_preset vbl_presets[] = {
    {"preview", VBL_RENDER_PT, 16, 4, 30, 0.7, VBL_TRANSMITTANCE_RATIO_TRACKING},
    {"production", VBL_RENDER_PT, 64, 8, 100, 0.7, VBL_TRANSMITTANCE_RATIO_TRACKING},
    {"final", VBL_RENDER_PT, 256, 8, 300, 0.7, VBL_TRANSMITTANCE_RATIO_TRACKING},
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
        options->beam_lights.alpha = p->vbl_alpha;
        options->beam_lights.radius0 = 0.0;
        options->transmittance = p->transmittance;
        return VBL_SUCCESS;
    }
    return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "unknown preset '%s' (preview, production, final)", preset);
}
