/* Multi-layer OpenEXR writer/reader (OpenEXRCore, C). Files are written to a temporary name in
 * the target directory and renamed, so a crash never leaves a torn EXR. Errors go through
 * libvbl's channel (vbl_last_error_message). */
#ifndef VBL_EXR_H
#define VBL_EXR_H

#include <vbl/vbl_core.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vbl_exr_compression {
    VBL_EXR_COMPRESSION_NONE = 0,
    VBL_EXR_COMPRESSION_ZIP = 1,
    VBL_EXR_COMPRESSION_PIZ = 2,
    VBL_EXR_COMPRESSION_DWAA = 3
} vbl_exr_compression;

/* One layer: `name` "" is the beauty (channels R,G,B[,A] unprefixed); any other name gives
 * channels "<name>.R", "<name>.G", ... so Nuke/OpenImageIO split them into layers. */
typedef struct vbl_exr_layer {
    const char* name;
    int channel_count;                 /* 1..4 */
    const char* const* channel_names;  /* NULL: "R","G","B","A" by count; else explicit ("Z") */
    const float* pixels;               /* channel_count floats per pixel, interleaved, row 0 = top */
    int store_half;                    /* 1: HALF channels, 0: FLOAT */
} vbl_exr_layer;
/* Layers whose `pixels` is NULL are skipped (a transport class the scene cannot produce). Sums
 * of layers equal the beauty exactly only in FLOAT storage; HALF rounds each channel separately
 * (relative error <= 2^-11 per value). */

/* Layer names: the beauty is ""; the light-transport classes are vbl_transport_class_name()'s
 * (vbl/vbl_film.h: "background", "volume_direct", ...), the one list of them. */

typedef enum vbl_exr_attribute_type {
    VBL_EXR_ATTRIBUTE_STRING = 0,      /* `value` */
    VBL_EXR_ATTRIBUTE_INT = 1,         /* `int_value` (EXR "int") */
    VBL_EXR_ATTRIBUTE_DOUBLE = 2,      /* `double_value` (EXR "double") */
    VBL_EXR_ATTRIBUTE_FLOAT = 3,       /* `double_value` stored as EXR "float" */
    VBL_EXR_ATTRIBUTE_M44F = 4         /* `m44`: 16 floats, row-major (EXR "m44f": worldToCamera, worldToNDC) */
} vbl_exr_attribute_type;

typedef struct vbl_exr_attribute {
    const char* name;
    const char* value;                 /* string attributes */
    vbl_exr_attribute_type type;       /* 0 (zero-initialised): string */
    int int_value;
    double double_value;
    const float* m44;                  /* M44F: 16 floats, row-major */
} vbl_exr_attribute;

typedef struct vbl_exr_write_options {
    size_t size;                       /* sizeof(vbl_exr_write_options) */
    vbl_exr_compression compression;
    int tiled;                         /* 0: scanlines, 1: tiles of tile_size^2 */
    int tile_size;                     /* 0: 64 */
    const vbl_exr_attribute* attributes;
    int attribute_count;
    const float* chromaticities;       /* NULL or 8 floats: red xy, green xy, blue xy, white xy */
    const char* color_space;           /* NULL or the OCIO colour space name of the pixels: written
                                          as string attribute "oiio:ColorSpace" */
    float dwa_quality;                 /* DWAA quality; 0: 45 (OpenEXR's default) */
} vbl_exr_write_options;

#define VBL_EXR_WRITE_OPTIONS_DEFAULT {sizeof(vbl_exr_write_options), VBL_EXR_COMPRESSION_ZIP, 0, 0, NULL, 0, NULL, NULL, 0.0f}

/* Writes one single-part EXR (data window = display window = [0,w-1]x[0,h-1], line order
 * increasing Y) to "<dir>/.<name>.tmp-XXXXXX", flushes it and renames it over `path`: readers
 * see either the previous complete file or the new one, so checkpoints may rewrite the same
 * path repeatedly. On failure the temporary file is removed and `path` is untouched. Channels
 * "<layer>.<c>" are written in EXR's (alphabetical) channel order. */
vbl_result vbl_exr_write(const char* path, int width, int height, const vbl_exr_layer* layers,
                         int layer_count, const vbl_exr_write_options* options);

/* ---- Reader (tests, merging, diffing, previews) ---------------------------------------- */

/* A decoded EXR image: every channel of the first part as planar floats (HALF/UINT converted),
 * row 0 = top of the data window. Reference counted. */
typedef struct vbl_exr_image vbl_exr_image;

vbl_result vbl_exr_read(const char* path, vbl_exr_image** out_image);
void vbl_exr_image_retain(vbl_exr_image* image);
void vbl_exr_image_release(vbl_exr_image* image);

int vbl_exr_image_width(const vbl_exr_image* image);
int vbl_exr_image_height(const vbl_exr_image* image);
/* 1 if the data window equals the display window (always for files this library writes). */
int vbl_exr_image_windows_match(const vbl_exr_image* image);
vbl_exr_compression vbl_exr_image_compression(const vbl_exr_image* image); /* -1 if another codec */
int vbl_exr_image_tiled(const vbl_exr_image* image);
int vbl_exr_image_tile_size(const vbl_exr_image* image);                   /* 0 for scanlines */

int vbl_exr_image_channel_count(const vbl_exr_image* image);
const char* vbl_exr_image_channel_name(const vbl_exr_image* image, int index);
int vbl_exr_image_channel_is_half(const vbl_exr_image* image, int index);
/* Index of a channel by full name ("R", "background.G"), or -1. */
int vbl_exr_image_find_channel(const vbl_exr_image* image, const char* name);
/* width*height floats, or NULL for a bad index. */
const float* vbl_exr_image_channel_pixels(const vbl_exr_image* image, int index);

/* Header attributes other than the required ones. Returns NULL if absent; otherwise the value
 * as text (strings as is, numbers with %d / %.17g, m44f as 16 numbers %.9g separated by spaces,
 * row-major) and, if `type` is not NULL, its type (-1 for other EXR attribute types, whose text
 * is ""). */
const char* vbl_exr_image_attribute(const vbl_exr_image* image, const char* name, int* type);
/* The header attributes other than the required ones, in file order, by index (NULL past the end). */
int vbl_exr_image_attribute_count(const vbl_exr_image* image);
const char* vbl_exr_image_attribute_name(const vbl_exr_image* image, int index);
/* 1 and 8 floats (red, green, blue, white xy) if the file has a chromaticities attribute. */
int vbl_exr_image_chromaticities(const vbl_exr_image* image, float out[8]);

#ifdef __cplusplus
}
#endif

#endif
