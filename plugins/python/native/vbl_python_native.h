/* libvbl_python: the small C side of the Python package `vbl` (plugins/python/vbl), for what the
 * Python binding cannot do through libvbl's public API alone:
 *  - the cancel flag of a render (vbl_render_options.cancel is a pointer field of the opaque
 *    options, which the reflection API does not set);
 *  - colour-managed scene loading through the OCIO adapter (color/, vbl_color.h): a
 *    vbl_scene_load_options.convert_color callback;
 *  - writing a film as the multi-layer EXR `vbl render` writes, with the same header
 *    attributes, through the CLI's own writer (plugins/render_exr, vbl_render_exr.h).
 * Linked against the shared libvbl, with the EXR writer and the OCIO adapter inside. Every call
 * reports errors through libvbl's channel (vbl_last_error_message). */
#ifndef VBL_PYTHON_NATIVE_H
#define VBL_PYTHON_NATIVE_H

#include <stddef.h>

#include <vbl/vbl.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Points options->cancel at `flag` (NULL: no flag). Once *flag is non-zero the pass in progress
 * stops at its next pixel and is dropped (vbl/vbl_render_options.h, `cancel`). */
VBL_API void vbl_py_options_set_cancel(vbl_render_options* options, const volatile int* flag);

/* ---- colour ------------------------------------------------------------------------------ */

/* An OCIO config and its scene_linear space. `config`: NULL for $OCIO else the shipped config,
 * "" or "libvbl" for the shipped one, else a config file. */
typedef struct vbl_py_color vbl_py_color;
VBL_API vbl_result vbl_py_color_open(const char* config, vbl_py_color** out);
VBL_API void vbl_py_color_release(vbl_py_color* color);
/* The config's scene_linear colour space name (the film's space). */
VBL_API const char* vbl_py_color_scene_space(const vbl_py_color* color);
/* 1 and the CIE xy of the primaries and white of scene_linear (the EXR "chromaticities"), 0 if
 * the config does not know them (no attribute, as `vbl render`). */
VBL_API int vbl_py_color_chromaticities(const vbl_py_color* color, float out[8]);
/* A vbl_scene_load_options.convert_color callback; its `user` is a vbl_py_color*. Converts a scene
 * colour from the scene's color_space to scene_linear, as `vbl render` does. */
VBL_API vbl_result vbl_py_convert_scene_color(void* user, const char* color_space, const char* field, double rgb[3]);
/* 0 if the scene's color_space (NULL: none) is known to the config; else VBL_ERROR_SCENE naming it. */
VBL_API vbl_result vbl_py_color_check_scene(const vbl_py_color* color, const vbl_scene* scene);

/* ---- EXR --------------------------------------------------------------------------------- */

typedef struct vbl_py_exr_options {
    size_t size;                  /* sizeof(vbl_py_exr_options) */
    const vbl_scene* scene;       /* vbl:scene (its path), vbl:scene_hash, vbl:media */
    const char* scene_label;      /* vbl:scene as written; NULL: the scene's path */
    const vbl_render_options* render_options; /* the options rendered with (hash, max_bounces, ...) */
    const char* status;           /* vbl:status: "complete", "interrupted", "time_limit"; NULL: from the stats */
    int passes_requested;         /* vbl:passes_requested; 0: render_options->passes */
    const char* preset;           /* vbl:preset; NULL: "none" */
    int has_frame, frame;         /* vbl:frame */
    int compression;              /* vbl_exr_compression; -1: ZIP (the CLI's default) */
    int half_all;                 /* every colour layer as HALF */
    const char* half_layers;      /* comma-separated colour layers as HALF (beauty, background, ...,
                                     volume_indirect, lightgroup_<name>, variance); another name:
                                     VBL_ERROR_INVALID_ARGUMENT, as --half-layers */
    int aov_z, aov_samples, aov_variance; /* write these AOVs when the film has them */
    const vbl_py_color* color;    /* NULL: open the default config (as `vbl render` without --config) */
    const char* output_space;     /* NULL: scene_linear; else a linear colour space or role of the config
                                     (`vbl render --output-space`): colour layers converted, the beauty
                                     re-summed from the converted transport layers */
} vbl_py_exr_options;

/* Writes `film` to `path` (temporary name, then renamed) with the layers and header attributes of
 * `vbl render -o path` (docs/readme/output.md, "Metadata"), in scene_linear or `output_space`. */
VBL_API vbl_result vbl_py_film_write_exr(const vbl_film* film, const char* path, const vbl_py_exr_options* options);

/* An EXR file read whole (planar float channels, row 0 at the top) with its header attributes:
 * the vbl_exr_image of vbl_exr.h. Attribute values as text (numbers with %d / %.17g), `type` as
 * vbl_exr_attribute_type (-1: another EXR type, text ""). */
typedef struct vbl_py_exr vbl_py_exr;
VBL_API vbl_result vbl_py_exr_open(const char* path, vbl_py_exr** out);
VBL_API void vbl_py_exr_close(vbl_py_exr* file);
VBL_API int vbl_py_exr_width(const vbl_py_exr* file);
VBL_API int vbl_py_exr_height(const vbl_py_exr* file);
VBL_API int vbl_py_exr_channel_count(const vbl_py_exr* file);
VBL_API const char* vbl_py_exr_channel_name(const vbl_py_exr* file, int index);
VBL_API const float* vbl_py_exr_channel_pixels(const vbl_py_exr* file, int index);
VBL_API int vbl_py_exr_attribute_count(const vbl_py_exr* file);
VBL_API const char* vbl_py_exr_attribute_name(const vbl_py_exr* file, int index);
VBL_API const char* vbl_py_exr_attribute(const vbl_py_exr* file, const char* name, int* type);

#ifdef __cplusplus
}
#endif

#endif
