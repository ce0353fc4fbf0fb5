/* Colour management for libvbl's outputs: a C interface over OpenColorIO (C++ inside).
 *
 * Configs: vbl_color_config_open(NULL) uses $OCIO when set (an unreadable $OCIO is an error, not a
 * silent fallback), otherwise the config libvbl ships (color/config/libvbl.ocio, compiled into
 * the library and installed as share/libvbl/libvbl.ocio). Colour space arguments accept a colour
 * space name, an alias or a role ("scene_linear"). Errors go through vbl_last_error_message(). */
#ifndef VBL_COLOR_H
#define VBL_COLOR_H

#include <stddef.h>

#include <vbl/vbl_core.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vbl_color_config vbl_color_config;

/* `path` NULL: $OCIO, else the shipped config. "" or "libvbl": the shipped config. */
vbl_result vbl_color_config_open(const char* path, vbl_color_config** out_config);
void vbl_color_config_retain(vbl_color_config* config);
void vbl_color_config_release(vbl_color_config* config);

/* Where the config came from: a file path or "<libvbl built-in>". */
const char* vbl_color_config_source(const vbl_color_config* config);
/* Path of the shipped config file as installed (for `export OCIO=...`). */
const char* vbl_color_shipped_config_path(void);

/* Resolves a colour space name or role to the config's colour space name (stays valid while the
 * config lives). Unknown names give VBL_ERROR_INVALID_ARGUMENT with a message listing the spaces. */
vbl_result vbl_color_resolve_space(const vbl_color_config* config, const char* name_or_role, const char** out_name);
/* Colour space count/name by index (for listings). */
int vbl_color_space_count(const vbl_color_config* config);
const char* vbl_color_space_name(const vbl_color_config* config, int index);

const char* vbl_color_default_display(const vbl_color_config* config);
const char* vbl_color_default_view(const vbl_color_config* config, const char* display);

/* Converts `pixel_count` pixels in place from `src` to `dst`; `channels` 3 (RGB) or 4 (RGBA,
 * alpha untouched). Identical spaces are a no-op. */
vbl_result vbl_color_convert(const vbl_color_config* config, const char* src, const char* dst, float* pixels,
                             size_t pixel_count, int channels);
/* Converts one RGB triple (scene colours from a JSON scene). */
vbl_result vbl_color_convert_rgb(const vbl_color_config* config, const char* src, const char* dst, float rgb[3]);

/* Applies exposure (multiplies by 2^exposure_stops in `src`) then the display/view transform
 * (NULL display/view: the config's defaults). Output is display-encoded, not clamped. */
vbl_result vbl_color_display_view(const vbl_color_config* config, const char* src, const char* display,
                                  const char* view, float exposure_stops, float* pixels, size_t pixel_count,
                                  int channels);

/* CIE xy of the red, green, blue primaries and white of a scene-linear space (for the EXR
 * "chromaticities" attribute), found by matching the space's matrix to ACES2065-1 (role
 * aces_interchange) against known primaries: Rec.709, ACEScg (AP1), ACES2065-1 (AP0), Rec.2020,
 * P3-D65. VBL_ERROR_UNSUPPORTED if the space is not linear with one of those primaries. */
vbl_result vbl_color_space_chromaticities(const vbl_color_config* config, const char* space, float out[8]);

/* ---- Scene colours ---------------------------------------------------------------------- */

/* Where vbl_color_convert_scene_color converts to: a config and its scene_linear space. */
typedef struct vbl_color_scene_target {
    const vbl_color_config* config;
    const char* scene_space;
} vbl_color_scene_target;

/* vbl_scene_load_options.convert_color with `user` a vbl_color_scene_target: a scene colour from
 * the scene's "color_space" into target->scene_space. Failures are VBL_ERROR_SCENE with the
 * adapter's message (the loader prefixes the scene file, color_space and the field). */
vbl_result vbl_color_convert_scene_color(void* user, const char* color_space, const char* field, double rgb[3]);

/* A scene's "color_space" (NULL: none) must be known to `config` even when no colour needed
 * converting: VBL_ERROR_SCENE "<scene_path>: color_space = \"X\": <why>" otherwise. */
vbl_result vbl_color_check_scene_space(const vbl_color_config* config, const char* scene_path,
                                       const char* color_space);

/* ---- Previews ---------------------------------------------------------------------------- */

typedef struct vbl_preview_options {
    size_t size;                   /* sizeof(vbl_preview_options) */
    const vbl_color_config* config;/* NULL: vbl_color_config_open(NULL) */
    const char* input_space;       /* colour space of the pixels; NULL: role scene_linear */
    const char* display;           /* NULL: the config's default display */
    const char* view;              /* NULL: the display's default view */
    float exposure;                /* stops, applied in the input space */
} vbl_preview_options;

#define VBL_PREVIEW_OPTIONS_DEFAULT {sizeof(vbl_preview_options), NULL, NULL, NULL, NULL, 0.0f}

/* Writes an 8-bit RGB PNG of `pixels` (`channels` 3 or 4 floats per pixel, row 0 = top; alpha is
 * ignored: premultiplied colour over black) through the display/view transform, clamped to
 * [0, 1] and rounded. Written to a temporary file beside `path` and renamed. */
vbl_result vbl_preview_write_png(const char* path, const float* pixels, int width, int height, int channels,
                                 const vbl_preview_options* options);

#ifdef __cplusplus
}
#endif

#endif
