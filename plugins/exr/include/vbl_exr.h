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

typedef struct vbl_exr_attribute {
    const char* name;
    const char* value;                 /* string attributes */
} vbl_exr_attribute;

typedef struct vbl_exr_write_options {
    size_t size;                       /* sizeof(vbl_exr_write_options) */
    vbl_exr_compression compression;
    int tiled;                         /* 0: scanlines, 1: tiles of tile_size^2 */
    int tile_size;                     /* 0: 64 */
    const vbl_exr_attribute* attributes;
    int attribute_count;
    const float* chromaticities;       /* NULL or 8 floats: red xy, green xy, blue xy, white xy */
} vbl_exr_write_options;

#define VBL_EXR_WRITE_OPTIONS_DEFAULT {sizeof(vbl_exr_write_options), VBL_EXR_COMPRESSION_ZIP, 0, 0, NULL, 0, NULL}

vbl_result vbl_exr_write(const char* path, int width, int height, const vbl_exr_layer* layers,
                         int layer_count, const vbl_exr_write_options* options);

#ifdef __cplusplus
}
#endif

#endif
