/* A film as the multi-layer OpenEXR `vbl render -o` writes (docs/readme/output.md): which layers
 * (AOVs by request, Z unprefixed, one-channel layers as ".Y"), HALF rules, the colour conversion
 * to the output space (with the beauty and the totals re-summed from the converted classes) and
 * every header attribute ("Metadata"). The one implementation behind the `vbl` command
 * (plugins/cli/render_output.c) and libvbl_python's Film.write_exr (plugins/python/native), so the
 * two write the same file. Static library vbl_render_exr; errors through vbl_report_error. */
#ifndef VBL_RENDER_EXR_H
#define VBL_RENDER_EXR_H

#include <stddef.h>

#include <vbl/vbl.h>

#include "vbl_exr.h"

#define VBL_RENDER_EXR_MAX_LAYERS 32
#define VBL_RENDER_EXR_MAX_ATTRS 32

/* What the file holds besides the film: one render's settings (vbl_render_exr_settings_init, then
 * vbl_render_exr_hash_file, vbl_render_exr_set_scene and, with OCIO, vbl_render_exr_set_color). */
typedef struct vbl_render_exr_settings {
    const char* scene_label;      /* vbl:scene as written */
    char scene_hash[40];          /* vbl:scene_hash: "fnv1a64:<16 hex digits>" of the scene file */
    char media[4096];             /* vbl:media: the scene's VDB paths (realpath), ';'-separated */
    float world_to_camera[16], world_to_ndc[16]; /* worldToCamera, worldToNDC */
    int have_camera;
    int has_frame, frame;         /* vbl:frame */
    const char* preset;           /* vbl:preset; NULL: "none" */
    long pass_first, pass_last;   /* vbl:pass_range "A-B" when pass_first >= 0 */
    int aov_z, aov_samples, aov_variance; /* write these layers when the film has them */
    int half_all;                 /* every colour layer as HALF (--half) */
    const char* half_layers;      /* comma-separated layers as HALF (--half-layers; "beauty" = R,G,B,A) */
    int compression;              /* vbl_exr_compression; -1: the writer's default (ZIP) */
    int tiled, tile_size;
    const char* scene_space;      /* vbl:scene_color_space (the film's space); NULL: "scene_linear" */
    const char* output_space;     /* oiio:ColorSpace; NULL: not written (no OCIO) */
    int convert;                  /* output_space differs from scene_space: `matrix` applies */
    double matrix[9];             /* scene_space -> output_space, row-major, linear */
    int have_chroma;
    float chroma[8];              /* "chromaticities" of output_space when have_chroma */
} vbl_render_exr_settings;

/* Zero, pass_first = pass_last = -1, compression = -1. */
void vbl_render_exr_settings_init(vbl_render_exr_settings* s);
/* scene_hash of the file's bytes (FNV-1a 64); errors name the file. */
vbl_result vbl_render_exr_hash_file(vbl_render_exr_settings* s, const char* path);
/* media and the camera matrices (vbl_scene_camera_matrices) of a loaded scene. */
void vbl_render_exr_set_scene(vbl_render_exr_settings* s, const vbl_scene* scene);

/* 1 if the n bytes at p name a colour layer --half-layers takes: beauty, a transport class, a
 * total (volume_indirect, surface_indirect), lightgroup_<name>, variance. */
int vbl_render_exr_is_colour_layer(const char* p, size_t n);
/* VBL_ERROR_INVALID_ARGUMENT "'X' is not a colour layer (beauty, ...)" for the first entry of
 * `list` that is not one. */
vbl_result vbl_render_exr_check_half_layers(const char* list);

/* ---- layers ------------------------------------------------------------------------------ */

typedef enum {
    VBL_RENDER_EXR_BEAUTY,
    VBL_RENDER_EXR_TRANSPORT,
    VBL_RENDER_EXR_Z,
    VBL_RENDER_EXR_SAMPLES,
    VBL_RENDER_EXR_VARIANCE,
    VBL_RENDER_EXR_TOTAL, /* volume_indirect, surface_indirect: sums of transport layers */
    VBL_RENDER_EXR_GROUP  /* lightgroup_<name>: a light group's beauty (not re-summed) */
} vbl_render_exr_kind;

/* The kind of a film layer by its name ("" the beauty). */
vbl_render_exr_kind vbl_render_exr_layer_kind(const char* name);

/* The film's layers as written: AOVs filtered, RGB converted to the output space (converted
 * transport layers re-summed in film order, in float, into the beauty and the totals so that
 * they still add up exactly; variances through the element-wise squared matrix, channels taken as
 * uncorrelated). pixels[k] points into the film or into owned[k] (freed by _free). */
typedef struct vbl_render_exr_layers {
    const char* names[VBL_RENDER_EXR_MAX_LAYERS];
    const float* pixels[VBL_RENDER_EXR_MAX_LAYERS];
    int channels[VBL_RENDER_EXR_MAX_LAYERS];
    vbl_render_exr_kind kinds[VBL_RENDER_EXR_MAX_LAYERS];
    float* owned[VBL_RENDER_EXR_MAX_LAYERS];
    int count;
} vbl_render_exr_layers;

vbl_result vbl_render_exr_layers_make(const vbl_render_exr_settings* s, const vbl_film* film, vbl_render_exr_layers* L);
void vbl_render_exr_layers_free(vbl_render_exr_layers* L);
/* The EXR channel name of channel c of layer k ("R", "A", "Z", "samples.Y", "background.G"). */
void vbl_render_exr_channel_name(const vbl_render_exr_layers* L, int k, int c, char* out, size_t size);

/* ---- header ------------------------------------------------------------------------------ */

typedef struct vbl_render_exr_meta {
    char software[64], seed[32], options_hash[40], pass_range[64], hybrid[256];
    vbl_exr_attribute attrs[VBL_RENDER_EXR_MAX_ATTRS];
    int count;
} vbl_render_exr_meta;

/* The header attributes in the file's order, the last one oiio:ColorSpace when output_space is
 * set (the writer writes it from its options; listed for the identity checks of --resume).
 * `stats`: the film's (or, before rendering, the options'); passes = every pass in the file,
 * first_pass = the absolute index of its first one. The strings point into `s` and `m`. */
void vbl_render_exr_meta_make(const vbl_render_exr_settings* s, const vbl_film_stats* stats,
                              const vbl_render_options* options, int passes, int first_pass, int passes_requested,
                              const char* status, double render_seconds, vbl_render_exr_meta* m);

/* ---- writing ----------------------------------------------------------------------------- */

/* Writes L with the header m to `path` (temporary name, then renamed). */
vbl_result vbl_render_exr_write_layers(const char* path, int width, int height, const vbl_render_exr_settings* s,
                                       const vbl_render_exr_layers* L, const vbl_render_exr_meta* m);
/* The whole of it for a film: its layers, a header from its stats (passes, first_pass) and
 * `options`, written to `path`. status NULL: from the stats ("time_limit", "interrupted",
 * "complete"); render_seconds < 0: the film's. */
vbl_result vbl_render_exr_write_film(const char* path, const vbl_film* film, const vbl_render_exr_settings* s,
                                     const vbl_render_options* options, int passes_requested, const char* status,
                                     double render_seconds);

/* ---- colour (only where the OCIO adapter vbl_color is built: VBL_RENDER_EXR_HAVE_COLOR) ----- */

#ifdef VBL_RENDER_EXR_HAVE_COLOR
#include "vbl_color.h"
/* scene_space and output_space (resolved names of `config`, kept by pointer), the matrix between
 * them (read off the conversion of the unit vectors; VBL_ERROR_INVALID_ARGUMENT "'X' is not a
 * scene-linear colour space ..." if probes show it is not linear) and the output chromaticities
 * (none when the config does not know the primaries). */
vbl_result vbl_render_exr_set_color(vbl_render_exr_settings* s, const vbl_color_config* config,
                                    const char* scene_space, const char* output_space);
#endif

#endif
