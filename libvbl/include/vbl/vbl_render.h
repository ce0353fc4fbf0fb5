/* libvbl rendering: scenes (JSON), render options, the progressive driver and its film.
 *
 *   vbl_scene* scene;  vbl_scene_load("scene.json", &scene);
 *   vbl_render_options options = VBL_RENDER_OPTIONS_DEFAULT;
 *   vbl_scene_render_options(scene, &options);      // the scene's `render` block
 *   options.passes = 8;                              // caller overrides
 *   vbl_film* film;  vbl_render(scene, &options, &film);
 *   const float* rgb = vbl_film_layer(film, "volume_direct", &channels);
 *
 * Every film layer is radiance (linear, scene-referred); the transport layers (background,
 * volume_direct, volume_from_volume, ...) sum to the beauty layer exactly in float, in that order. */
#ifndef VBL_RENDER_H
#define VBL_RENDER_H

#include "vbl/vbl_core.h"
#include "vbl/vbl_volume.h"
#include "vbl/vbl_render_options.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- scenes ---------------------------------------------------------------------------- */

/* A parsed scene: camera, lights, media (VDB volumes loaded), render settings. Immutable after
 * loading, reference counted; share it between threads and renders. */
typedef struct vbl_scene vbl_scene;

/* Options of vbl_scene_load_ex: VDB path overrides, the colour hook, the frame of a VDB
 * sequence and shot overrides (camera, image size). Start from VBL_SCENE_LOAD_OPTIONS_DEFAULT. */
typedef struct vbl_scene_load_options {
    size_t size;                    /* sizeof(vbl_scene_load_options) */
    /* Replaces media[i].vdb for i < vdb_override_count (NULL entries keep the scene's path).
     * Override paths are used as given (relative to the working directory). */
    const char* const* vdb_overrides;
    int vdb_override_count;         /* entries in vdb_overrides */
    /* Scene colours in a named input space. When the scene has a top-level "color_space", this
     * is called at load for every light colour (intensity / irradiance / radiance) and every
     * medium albedo, before their range checks, with the scene's colour space name, the field
     * ("lights[0].intensity", "media[1].albedo", "surfaces[0].material.albedo" / ".specular") and the RGB as written; it converts `rgb` in
     * place into the caller's scene_linear space (libvbl itself has no colour management; the
     * `vbl` command converts through OpenColorIO). A non-success result fails the load with that
     * result and the message "<file>: color_space = \"X\" (<field>): <callback's message>".
     * A scene naming a color_space loaded without a callback fails with VBL_ERROR_SCENE.
     * A converted albedo outside [0, 1] fails the load (VBL_ERROR_SCENE), naming the field and
     * the converted value; it is never clamped. */
    vbl_result (*convert_color)(void* user, const char* color_space, const char* field, double rgb[3]);
    void* convert_color_user;       /* passed to convert_color as `user` */
    /* VDB sequences: with use_frame = 1, frame patterns in media[i].vdb (and in the overrides)
     * are replaced by `frame`: a run of N '#' -> the frame zero-padded to N digits
     * ("smoke.####.vdb" -> "smoke.0007.vdb"), "%04d" / "%d" printf-style. A pattern with
     * use_frame = 0 fails the load (VBL_ERROR_SCENE); a missing frame file fails with
     * VBL_ERROR_FILE_NOT_FOUND naming the field, the frame and the file. */
    int frame;
    int use_frame;                  /* 1: substitute `frame` into frame patterns */
    /* Shot overrides (docs/readme/render.md, "Camera"). camera: NULL, or the name of an entry of
     * the scene's "cameras", else a JSON file holding a camera object (or {"camera": {...}});
     * neither: VBL_ERROR_FILE_NOT_FOUND. width, height > 0: the image size instead of the
     * camera's resolution (the lens keeps its vertical fov, or its focal length, sensor and fit). */
    const char* camera;
    int width;                      /* > 0: image width instead of the camera's */
    int height;                     /* > 0: image height instead of the camera's */
    /* Non-NULL: *cancel != 0 stops the load before the next medium or at the next step of a
     * volume load (vbl_volume_load_options.cancel): VBL_ERROR_INTERRUPTED. */
    const volatile int* cancel;
} vbl_scene_load_options;

/* The initializer of vbl_scene_load_options: size set, no overrides, no colour hook, no frame,
 * no cancel flag. */
#define VBL_SCENE_LOAD_OPTIONS_DEFAULT {sizeof(vbl_scene_load_options), NULL, 0, NULL, NULL, 0, 0, NULL, 0, 0, NULL}

/* Loads a JSON scene file (schema: docs/readme/render.md). Relative paths in it resolve
 * against the scene file's directory. Failures name the file and field, e.g.
 * "scene.json: media[0].phase.g = 1.2 is outside (-1, 1)" (VBL_ERROR_SCENE), or pass on the
 * volume loader's result (VBL_ERROR_FILE_NOT_FOUND, ...) prefixed with the field. */
VBL_API vbl_result vbl_scene_load(const char* path, vbl_scene** out_scene);
/* vbl_scene_load with options (NULL: the defaults). options->size may be that of an older,
 * shorter struct (the fields after it take their defaults). */
VBL_API vbl_result vbl_scene_load_ex(const char* path, const vbl_scene_load_options* options,
                                     vbl_scene** out_scene);
/* Frame patterns of VDB sequences and output paths: a run of N '#' is the frame zero-padded to N
 * digits; "%04d" / "%d" are printf-style (only d conversions, optional 0-flag and width; "%%"
 * is a literal '%'). The scene loader applies them to media[i].vdb (options.use_frame); the
 * `vbl` command to its output paths. has_pattern: 1 if `path` holds a pattern. format: 0 on
 * success, -1 when the result does not fit in out[size] or another '%' conversion is used. */
VBL_API int vbl_frame_path_has_pattern(const char* path);
/* Writes `pattern` with `frame` substituted into out[size] (see vbl_frame_path_has_pattern). */
VBL_API int vbl_frame_path_format(const char* pattern, int frame, char* out, size_t size);

/* Adds a reference (thread-safe; NULL is ignored). */
VBL_API void vbl_scene_retain(vbl_scene* scene);
/* Drops a reference; the last one frees the scene and its volumes (NULL is ignored). */
VBL_API void vbl_scene_release(vbl_scene* scene);

/* The scene file's path as given to vbl_scene_load. */
VBL_API const char* vbl_scene_path(const vbl_scene* scene);
/* The image size the scene renders at (the camera's resolution, or the load options' width and
 * height); 0 x 0 for NULL. Either pointer may be NULL. */
VBL_API void vbl_scene_resolution(const vbl_scene* scene, int* width, int* height);
/* Number of lights in the scene file (0 for NULL). */
VBL_API int vbl_scene_light_count(const vbl_scene* scene);
/* Number of media (0 for NULL). */
VBL_API int vbl_scene_medium_count(const vbl_scene* scene);
/* 1 if some medium emits light (fire): the scene is lit even without lights. */
VBL_API int vbl_scene_has_emission(const vbl_scene* scene);
/* The resolved VDB path of media[index] (NULL if out of range). */
VBL_API const char* vbl_scene_medium_path(const vbl_scene* scene, int index);
/* The scene's top-level "color_space" as written (its colours were converted from it at load),
 * or NULL when the scene names none (colours are already scene_linear). */
VBL_API const char* vbl_scene_color_space(const vbl_scene* scene);
/* The camera as OpenEXR's standard attributes want it (ImfStandardAttributes.h; row vectors,
 * p' = p M, matrices row-major, translation in the last row): world_to_camera maps into the
 * left-handed camera space of RenderMan (x right, y up, z the viewing direction);
 * world_to_ndc maps onto the image plane, (0, 0) the top-left and (1, 1) the bottom-right corner
 * of the display window, after dividing by w (z' = the camera-space depth, before the divide).
 * VBL_ERROR_INVALID_ARGUMENT for NULL arguments. */
VBL_API vbl_result vbl_scene_camera_matrices(const vbl_scene* scene, double world_to_camera[16],
                                             double world_to_ndc[16]);

/* ---- render options (the table, the struct and its reflection: vbl/vbl_render_options.h) ----- */

/* "pt", "vpl", "vrl", "vbl", "beams"; parse returns VBL_ERROR_INVALID_ARGUMENT for unknown names. */
VBL_API const char* vbl_render_method_name(vbl_render_method method);
/* The method named `name` into *out (see vbl_render_method_name). */
VBL_API vbl_result vbl_render_method_parse(const char* name, vbl_render_method* out);

/* Fills `options` (size set by the caller) with the scene's `render` block (defaults for
 * fields it leaves out); callback, threads and size are kept as they are. */
VBL_API vbl_result vbl_scene_render_options(const vbl_scene* scene, vbl_render_options* options);

/* The light paths per pass a render of `scene` with `options` traces: options->light_paths, or where
 * that is 0 the method's default for the scene: vrl and vbl trace VBL_LIGHT_PATHS_DEFAULT_VL_MEDIA_ONLY
 * in a scene without surfaces and VBL_LIGHT_PATHS_DEFAULT_VRL / _VBL with surfaces (chosen by
 * measured error at equal CPU time, docs/readme/vrl.md "Defaults"), the others
 * VBL_LIGHT_PATHS_DEFAULT. This is the count written to films and EXRs (vbl:light_paths). A NULL
 * scene gives vbl_render_options_light_paths; 0 for NULL options. */
VBL_API int vbl_render_light_paths(const vbl_scene* scene, const vbl_render_options* options);

/* ---- film ------------------------------------------------------------------------------ */

/* The result of a render: float layers, row 0 at the top, channels interleaved. Reference
 * counted, immutable. Layer names: "" (beauty R,G,B,A), the transport classes ("background",
 * "volume_direct", "volume_from_volume", ...: vbl/vbl_film.h) and their totals (R,G,B), "Z"
 * (1 channel), "samples" (1 channel), "variance" (R,G,B); only the layers the scene can produce
 * are present. */
typedef struct vbl_film vbl_film;

/* Adds a reference (thread-safe; NULL is ignored). */
VBL_API void vbl_film_retain(vbl_film* film);
/* Drops a reference; the last one frees the film (NULL is ignored). */
VBL_API void vbl_film_release(vbl_film* film);
/* Image width in pixels (0 for NULL). */
VBL_API int vbl_film_width(const vbl_film* film);
/* Image height in pixels (0 for NULL). */
VBL_API int vbl_film_height(const vbl_film* film);
/* Number of layers (0 for NULL). */
VBL_API int vbl_film_layer_count(const vbl_film* film);
/* Name of layer `index` in [0, vbl_film_layer_count) ("" is the beauty), NULL out of range. */
VBL_API const char* vbl_film_layer_name(const vbl_film* film, int index);
/* Channel names of a layer: "R","G","B"[,"A"] or "Z" / "Y". */
VBL_API int vbl_film_layer_channel_count(const vbl_film* film, const char* name);
/* Name of channel `channel` of layer `name`, NULL if there is no such layer or channel. */
VBL_API const char* vbl_film_layer_channel_name(const vbl_film* film, const char* name, int channel);
/* Pixels of a layer (NULL if the film has no such layer); *channels receives the count. */
VBL_API const float* vbl_film_layer(const vbl_film* film, const char* name, int* channels);
/* Convenience: the layer if it has 3 channels (R,G,B), else NULL. */
VBL_API const float* vbl_film_layer_rgb(const vbl_film* film, const char* name);

/* How a film was rendered (vbl_film_get_stats). */
typedef struct vbl_film_stats {
    size_t size;                  /* sizeof(vbl_film_stats) */
    vbl_render_method method;     /* the rendering method */
    int passes;                   /* passes completed */
    int spp;                      /* camera samples per pixel per pass */
    int light_paths;              /* light paths per pass as rendered (0 in options: the method's default) */
    uint64_t seed;                /* the render's seed */
    int threads;                  /* threads used */
    double render_seconds;        /* wall-clock time of the render (summed over light groups) */
    int cancelled;                /* 1: stopped by the callback */
    int time_limited;             /* 1: stopped by time_limit */
    int first_pass;               /* absolute index of the first pass in this film */
    int discarded_pass;           /* 1: a pass was stopped part way (cancel / time limit) and dropped */
    int transparent;              /* 1: options.transparent (the beauty leaves out `background`) */
    int hybrid;                   /* options.hybrid (vbl_hybrid_mode); 0: off */
    int hybrid_pt_classes;        /* hybrid: the classes pt rendered (bit = vbl_transport_class), as chosen */
    int hybrid_pt_spp;            /* hybrid: pt samples per method camera sample, as chosen */
} vbl_film_stats;

/* out->size: sizeof(vbl_film_stats), or the size of an older struct (without the fields added
 * since), which then receives only its own fields. */
VBL_API vbl_result vbl_film_get_stats(const vbl_film* film, vbl_film_stats* out);

/* ---- rendering ------------------------------------------------------------------------- */

/* Renders `scene` progressively. Same scene, options.seed and completed passes give a
 * bit-identical film at any thread count. If the callback (after a pass) or options.cancel
 * (within a pass) stops the render after at least one complete pass, *out_film receives the
 * film of the complete passes and VBL_ERROR_INTERRUPTED is returned (no film if none). Methods
 * not built yet return VBL_ERROR_UNSUPPORTED. */
VBL_API vbl_result vbl_render(const vbl_scene* scene, const vbl_render_options* options,
                              vbl_film** out_film);

/* The documented limits of the methods at the extremes (docs/readme/render.md "Limits at the
 * extremes") that `scene` rendered with `options` runs into: a near-delta phase function
 * (|g| > 0.95) with vpl, vrl, vbl or beams, an explicit beams.radius0 or vbl.radius0 above 0.1 x the
 * media's size, optically thick media with beams or vbl (kernel radius over 10 mean free paths) or
 * vpl (media over 1e4 mean free paths across). Writes one line per limit (naming the scene file and the field, '\n'-terminated)
 * into `message` (NULL or size 0: none written; truncated to size) and returns how many (0: none).
 * These renders still run (the CLI prints each line as a warning); vbl_render refuses only
 * beams.radius0 below 1e-4 x the media's size (VBL_ERROR_INVALID_ARGUMENT). */
VBL_API int vbl_render_limits(const vbl_scene* scene, const vbl_render_options* options, char* message,
                              size_t size);

/* Inside the pass callback only: a film of the passes completed so far (what vbl_render would
 * return if it stopped now), e.g. to write a checkpoint without stopping. Release it. */
VBL_API vbl_result vbl_render_snapshot(const vbl_render_progress* progress, vbl_film** out_film);

/* Quality presets: "preview", "production", "final" set method, passes, light paths, spp,
 * the vbl radius schedule (R0 factor, alpha) and estimators (docs/readme/performance.md lists the
 * values and their measured error and time). Unknown names: VBL_ERROR_INVALID_ARGUMENT.
 * Fields a preset does not mention are left as they are. */
VBL_API vbl_result vbl_render_options_apply_preset(const char* preset, vbl_render_options* options);

#ifdef __cplusplus
}
#endif

#endif /* VBL_RENDER_H */
