/* vbl_exr_read: decodes every channel of an EXR's first part to planar floats (OpenEXRCore). */
#define _POSIX_C_SOURCE 200809L

#include <OpenEXR/openexr.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exr_internal.h"

typedef struct vbl_exr_image_channel {
    char* name;
    int half;
    float* pixels;
} vbl_exr_image_channel;

typedef struct vbl_exr_attr_entry {
    char* name;
    char* text;
    int type;
} vbl_exr_attr_entry;

struct vbl_exr_image {
    int refcount;
    int width, height;
    int windows_match;
    vbl_exr_compression compression;
    int tiled, tile_size;
    int channel_count;
    vbl_exr_image_channel* channels;
    int attribute_count;
    vbl_exr_attr_entry* attributes;
    int has_chromaticities;
    float chromaticities[8];
};

typedef struct vbl_exr_read_state {
    char message[512];
} vbl_exr_read_state;

static void vbl_exr_read_error_handler(exr_const_context_t ctxt, exr_result_t code, const char* msg)
{
    void* user = NULL;
    if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user) return;
    vbl_exr_read_state* state = user;
    if (!state->message[0]) snprintf(state->message, sizeof state->message, "%s (%s)", msg, exr_get_error_code_as_string(code));
}

/* Decoded planes larger than this many times the file's size are refused before allocating (zlib
 * cannot exceed 1032:1, RLE 64:1; the other codecs store at least a bit per value per run), unless
 * they fit in the floor below. A 2 KB file asked for 23 GB through its data window (issue 18). */
#define VBL_EXR_MAX_EXPANSION 4096
#define VBL_EXR_EXPANSION_FLOOR ((uint64_t)256 << 20) /* 256 MiB */

/* `in` for a message: bytes outside printable ASCII as \xNN, at most `out_size` - 1 characters. */
static const char* vbl_exr_printable(const char* in, char* out, size_t out_size)
{
    static const char hex[] = "0123456789abcdef";
    size_t n = 0;
    for (; in && *in && n + 5 < out_size; ++in) {
        unsigned char c = (unsigned char)*in;
        if (c >= 0x20 && c < 0x7f && c != '\\') {
            out[n++] = (char)c;
        } else {
            out[n++] = '\\';
            out[n++] = 'x';
            out[n++] = hex[c >> 4];
            out[n++] = hex[c & 15];
        }
    }
    out[n] = '\0';
    return out;
}

static long long vbl_exr_file_size(const char* path)
{
    FILE* f = fopen(path, "rb");
    if (!f) return -1;
    long long size = fseek(f, 0, SEEK_END) == 0 ? (long long)ftell(f) : -1;
    fclose(f);
    return size;
}

static char* vbl_exr_dup(const char* s, size_t n)
{
    char* copy = malloc(n + 1);
    if (!copy) return NULL;
    memcpy(copy, s, n);
    copy[n] = '\0';
    return copy;
}

void vbl_exr_image_retain(vbl_exr_image* image)
{
    if (image) ++image->refcount;
}

void vbl_exr_image_release(vbl_exr_image* image)
{
    if (!image || --image->refcount > 0) return;
    for (int i = 0; i < image->channel_count; ++i) {
        free(image->channels[i].name);
        free(image->channels[i].pixels);
    }
    for (int i = 0; i < image->attribute_count; ++i) {
        free(image->attributes[i].name);
        free(image->attributes[i].text);
    }
    free(image->channels);
    free(image->attributes);
    free(image);
}

static int vbl_exr_is_structural(const char* name)
{
    static const char* const names[] = {"channels", "compression", "dataWindow", "displayWindow", "lineOrder",
                                        "pixelAspectRatio", "screenWindowCenter", "screenWindowWidth", "tiles",
                                        "chromaticities", "type", "version", "chunkCount", "name"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (!strcmp(name, names[i])) return 1;
    return 0;
}

static vbl_result vbl_exr_read_attributes(exr_context_t ctxt, vbl_exr_image* image, const char* path)
{
    int32_t count = 0;
    if (exr_get_attribute_count(ctxt, 0, &count) != EXR_ERR_SUCCESS) count = 0;
    image->attributes = calloc((size_t)(count > 0 ? count : 1), sizeof *image->attributes);
    if (!image->attributes) return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    for (int32_t i = 0; i < count; ++i) {
        const exr_attribute_t* a = NULL;
        if (exr_get_attribute_by_index(ctxt, 0, EXR_ATTR_LIST_FILE_ORDER, i, &a) != EXR_ERR_SUCCESS || !a) continue;
        if (a->type == EXR_ATTR_CHROMATICITIES && !strcmp(a->name, "chromaticities")) {
            const exr_attr_chromaticities_t* c = a->chromaticities;
            const float v[8] = {c->red_x, c->red_y, c->green_x, c->green_y, c->blue_x, c->blue_y, c->white_x, c->white_y};
            memcpy(image->chromaticities, v, sizeof v);
            image->has_chromaticities = 1;
        }
        if (vbl_exr_is_structural(a->name)) continue;
        char buffer[320] = "";
        const char* text = buffer;
        size_t text_len;
        int type = -1;
        switch (a->type) {
        case EXR_ATTR_STRING: text = a->string->str ? a->string->str : ""; type = VBL_EXR_ATTRIBUTE_STRING; break;
        case EXR_ATTR_INT: snprintf(buffer, sizeof buffer, "%d", a->i); type = VBL_EXR_ATTRIBUTE_INT; break;
        case EXR_ATTR_DOUBLE: snprintf(buffer, sizeof buffer, "%.17g", a->d); type = VBL_EXR_ATTRIBUTE_DOUBLE; break;
        case EXR_ATTR_FLOAT: snprintf(buffer, sizeof buffer, "%.9g", (double)a->f); type = VBL_EXR_ATTRIBUTE_FLOAT; break;
        case EXR_ATTR_M44F: {
            size_t used = 0;
            for (int e = 0; e < 16 && used < sizeof buffer; ++e)
                used += (size_t)snprintf(buffer + used, sizeof buffer - used, e ? " %.9g" : "%.9g", (double)a->m44f->m[e]);
            type = VBL_EXR_ATTRIBUTE_M44F;
            break;
        }
        default: break;
        }
        text_len = a->type == EXR_ATTR_STRING ? (size_t)(a->string->length > 0 ? a->string->length : 0) : strlen(text);
        vbl_exr_attr_entry* dst = &image->attributes[image->attribute_count];
        dst->name = vbl_exr_dup(a->name, strlen(a->name));
        dst->text = vbl_exr_dup(text, text_len);
        dst->type = type;
        if (!dst->name || !dst->text) {
            free(dst->name);
            free(dst->text);
            return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        }
        ++image->attribute_count;
    }
    return VBL_SUCCESS;
}

/* Decodes one chunk into the planar float buffers. */
static exr_result_t vbl_exr_read_chunk(exr_context_t ctxt, size_t x, size_t y, const exr_chunk_info_t* cinfo, exr_decode_pipeline_t* decoder,
                                       int* initialized, vbl_exr_image* image)
{
    exr_result_t rv = *initialized ? exr_decoding_update(ctxt, 0, cinfo, decoder)
                                   : exr_decoding_initialize(ctxt, 0, cinfo, decoder);
    if (rv != EXR_ERR_SUCCESS) return rv;
    for (int c = 0; c < decoder->channel_count; ++c) {
        exr_coding_channel_info_t* info = &decoder->channels[c];
        vbl_exr_image_channel* ch = NULL;
        for (int k = 0; k < image->channel_count && !ch; ++k)
            if (!strcmp(image->channels[k].name, info->channel_name)) ch = &image->channels[k];
        if (!ch) return EXR_ERR_INVALID_ARGUMENT;
        info->user_bytes_per_element = 4;
        info->user_data_type = EXR_PIXEL_FLOAT;
        info->user_pixel_stride = 4;
        info->user_line_stride = 4 * image->width;
        info->decode_to_ptr = (uint8_t*)(ch->pixels + y * (size_t)image->width + x);
    }
    if (!*initialized) {
        rv = exr_decoding_choose_default_routines(ctxt, 0, decoder);
        if (rv != EXR_ERR_SUCCESS) return rv;
        *initialized = 1;
    }
    return exr_decoding_run(ctxt, 0, decoder);
}

vbl_result vbl_exr_read(const char* path, vbl_exr_image** out_image)
{
    if (out_image) *out_image = NULL;
    if (!path || !out_image) return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_exr_read: NULL argument");
    const long long file_size = vbl_exr_file_size(path);
    if (file_size < 0) return vbl_report_error(VBL_ERROR_FILE_NOT_FOUND, "%s: cannot open for reading", path);
    char quoted[256];

    vbl_exr_read_state state = {{0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = vbl_exr_read_error_handler;
    init.user_data = &state;
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_start_read(&ctxt, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        exr_finish(&ctxt);
        return vbl_report_error(VBL_ERROR_CORRUPT_FILE, "%s: not a readable OpenEXR file: %s", path,
                                vbl_exr_printable(state.message[0] ? state.message : exr_get_default_error_message(rv),
                                                  quoted, sizeof quoted));
    }
    vbl_result result = VBL_SUCCESS;
    vbl_exr_image* image = calloc(1, sizeof *image);
    exr_storage_t storage = EXR_STORAGE_SCANLINE;
    exr_attr_box2i_t dw, disp;
    exr_compression_t comp = EXR_COMPRESSION_NONE;
    const exr_attr_chlist_t* chlist = NULL;
    if (!image) {
        exr_finish(&ctxt);
        return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    image->refcount = 1;
    if (exr_get_storage(ctxt, 0, &storage) != EXR_ERR_SUCCESS || exr_get_data_window(ctxt, 0, &dw) != EXR_ERR_SUCCESS ||
        exr_get_display_window(ctxt, 0, &disp) != EXR_ERR_SUCCESS || exr_get_compression(ctxt, 0, &comp) != EXR_ERR_SUCCESS ||
        exr_get_channels(ctxt, 0, &chlist) != EXR_ERR_SUCCESS || !chlist) {
        result = vbl_report_error(VBL_ERROR_CORRUPT_FILE, "%s: incomplete EXR header", path);
        goto done;
    }
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED) {
        result = vbl_report_error(VBL_ERROR_UNSUPPORTED, "%s: deep EXR images are not supported", path);
        goto done;
    }
    /* In 64 bits: max - min of two int32 overflows int for windows of 2^31 pixels. */
    const int64_t width = (int64_t)dw.max.x - dw.min.x + 1, height = (int64_t)dw.max.y - dw.min.y + 1;
    if (width <= 0 || height <= 0) {
        result = vbl_report_error(VBL_ERROR_CORRUPT_FILE, "%s: empty data window", path);
        goto done;
    }
    {
        const uint64_t channels = (uint64_t)(chlist->num_channels > 0 ? chlist->num_channels : 1);
        const uint64_t limit = (uint64_t)file_size * VBL_EXR_MAX_EXPANSION > VBL_EXR_EXPANSION_FLOOR
                                   ? (uint64_t)file_size * VBL_EXR_MAX_EXPANSION
                                   : VBL_EXR_EXPANSION_FLOOR;
        /* width, height < 2^32 and channels < 2^31: the product in long double cannot wrap. */
        const long double bytes = (long double)width * (long double)height * (long double)channels * 4.0L;
        if (width > INT32_MAX || height > INT32_MAX || bytes > (long double)limit) {
            result = vbl_report_error(VBL_ERROR_CORRUPT_FILE,
                                      "%s: dataWindow %lld x %lld with %llu channels needs %.3g GB of pixels, more than "
                                      "%d x the file's %lld bytes (at least %llu MiB allowed): corrupt header",
                                      path, (long long)width, (long long)height, (unsigned long long)channels,
                                      (double)(bytes / 1e9L), VBL_EXR_MAX_EXPANSION, file_size,
                                      (unsigned long long)(VBL_EXR_EXPANSION_FLOOR >> 20));
            goto done;
        }
        /* The limit before the per-channel calloc (vbl_memory_limit: --memory-limit / VBL_MEMORY_LIMIT). */
        if (bytes > (long double)vbl_memory_limit()) {
            result = vbl_report_error(VBL_ERROR_UNSUPPORTED,
                                      "%s: dataWindow %lld x %lld with %llu channels needs %.1f MiB, more than the memory limit "
                                      "of %.1f MiB (--memory-limit / VBL_MEMORY_LIMIT)",
                                      path, (long long)width, (long long)height, (unsigned long long)channels,
                                      (double)(bytes / 1048576.0L), (double)vbl_memory_limit() / 1048576.0);
            goto done;
        }
    }
    image->width = (int)width;
    image->height = (int)height;
    image->windows_match = !memcmp(&dw, &disp, sizeof dw);
    image->tiled = storage == EXR_STORAGE_TILED;
    switch (comp) {
    case EXR_COMPRESSION_NONE: image->compression = VBL_EXR_COMPRESSION_NONE; break;
    case EXR_COMPRESSION_ZIP: image->compression = VBL_EXR_COMPRESSION_ZIP; break;
    case EXR_COMPRESSION_PIZ: image->compression = VBL_EXR_COMPRESSION_PIZ; break;
    case EXR_COMPRESSION_DWAA: image->compression = VBL_EXR_COMPRESSION_DWAA; break;
    default: image->compression = (vbl_exr_compression)-1; break;
    }
    image->channels = calloc((size_t)(chlist->num_channels > 0 ? chlist->num_channels : 1), sizeof *image->channels);
    if (!image->channels) {
        result = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        goto done;
    }
    for (int c = 0; c < chlist->num_channels; ++c) {
        const exr_attr_chlist_entry_t* e = &chlist->entries[c];
        vbl_exr_image_channel* ch = &image->channels[c];
        if (e->x_sampling != 1 || e->y_sampling != 1) {
            result = vbl_report_error(VBL_ERROR_UNSUPPORTED, "%s: channel '%s' is subsampled", path,
                                      vbl_exr_printable(e->name.str, quoted, sizeof quoted));
            goto done;
        }
        ch->name = vbl_exr_dup(e->name.str, (size_t)e->name.length);
        ch->half = e->pixel_type == EXR_PIXEL_HALF;
        ch->pixels = calloc((size_t)image->width * (size_t)image->height, sizeof(float));
        image->channel_count = c + 1;
        if (!ch->name || !ch->pixels) {
            result = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
            goto done;
        }
    }
    result = vbl_exr_read_attributes(ctxt, image, path);
    if (result != VBL_SUCCESS) goto done;

    exr_decode_pipeline_t decoder = EXR_DECODE_PIPELINE_INITIALIZER;
    int ready = 0;
    if (!image->tiled) {
        int32_t lines = 1;
        rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines);
        for (int y = dw.min.y; y <= dw.max.y && rv == EXR_ERR_SUCCESS; y += lines) {
            exr_chunk_info_t cinfo;
            rv = exr_read_scanline_chunk_info(ctxt, 0, y, &cinfo);
            if (rv == EXR_ERR_SUCCESS) rv = vbl_exr_read_chunk(ctxt, 0, (size_t)(y - dw.min.y), &cinfo, &decoder, &ready, image);
        }
    } else {
        uint32_t tx_size = 0, ty_size = 0;
        exr_tile_level_mode_t level;
        exr_tile_round_mode_t round;
        rv = exr_get_tile_descriptor(ctxt, 0, &tx_size, &ty_size, &level, &round);
        image->tile_size = (int)tx_size;
        if (rv == EXR_ERR_SUCCESS && (tx_size == 0 || ty_size == 0)) rv = EXR_ERR_BAD_CHUNK_LEADER;
        int tiles_x = rv == EXR_ERR_SUCCESS ? (image->width + (int)tx_size - 1) / (int)tx_size : 0;
        int tiles_y = rv == EXR_ERR_SUCCESS ? (image->height + (int)ty_size - 1) / (int)ty_size : 0;
        for (int ty = 0; ty < tiles_y && rv == EXR_ERR_SUCCESS; ++ty)
            for (int tx = 0; tx < tiles_x && rv == EXR_ERR_SUCCESS; ++tx) {
                exr_chunk_info_t cinfo;
                rv = exr_read_tile_chunk_info(ctxt, 0, tx, ty, 0, 0, &cinfo);
                /* OpenEXRCore 3.1 gives tile indices, not pixels, in cinfo.start_x/y. */
                if (rv == EXR_ERR_SUCCESS)
                    rv = vbl_exr_read_chunk(ctxt, (size_t)tx * tx_size, (size_t)ty * ty_size, &cinfo, &decoder, &ready, image);
            }
    }
    if (ready || decoder.channels) exr_decoding_destroy(ctxt, &decoder);
    if (rv == EXR_ERR_FEATURE_NOT_IMPLEMENTED) {
        /* DWAA/DWAB: OpenEXRCore 3.1 cannot decode them; the C++ library can. */
        const char** names = calloc((size_t)image->channel_count + 1, sizeof *names);
        float** planes = calloc((size_t)image->channel_count + 1, sizeof *planes);
        for (int c = 0; names && planes && c < image->channel_count; ++c) {
            names[c] = image->channels[c].name;
            planes[c] = image->channels[c].pixels;
        }
        state.message[0] = '\0';
        if (names && planes &&
            vbl_exr_read_imf(path, image->channel_count, names, planes, image->width, state.message, sizeof state.message) == 0)
            rv = EXR_ERR_SUCCESS;
        free(names);
        free(planes);
    }
    if (rv != EXR_ERR_SUCCESS)
        result = vbl_report_error(VBL_ERROR_CORRUPT_FILE, "%s: cannot decode pixels: %s", path,
                                  vbl_exr_printable(state.message[0] ? state.message : exr_get_default_error_message(rv),
                                                    quoted, sizeof quoted));
done:
    exr_finish(&ctxt);
    if (result != VBL_SUCCESS) {
        vbl_exr_image_release(image);
        return result;
    }
    *out_image = image;
    return VBL_SUCCESS;
}

int vbl_exr_image_width(const vbl_exr_image* image) { return image ? image->width : 0; }
int vbl_exr_image_height(const vbl_exr_image* image) { return image ? image->height : 0; }
int vbl_exr_image_windows_match(const vbl_exr_image* image) { return image ? image->windows_match : 0; }
vbl_exr_compression vbl_exr_image_compression(const vbl_exr_image* image)
{
    return image ? image->compression : (vbl_exr_compression)-1;
}
int vbl_exr_image_tiled(const vbl_exr_image* image) { return image ? image->tiled : 0; }
int vbl_exr_image_tile_size(const vbl_exr_image* image) { return image ? image->tile_size : 0; }
int vbl_exr_image_channel_count(const vbl_exr_image* image) { return image ? image->channel_count : 0; }

const char* vbl_exr_image_channel_name(const vbl_exr_image* image, int index)
{
    return image && index >= 0 && index < image->channel_count ? image->channels[index].name : NULL;
}

int vbl_exr_image_channel_is_half(const vbl_exr_image* image, int index)
{
    return image && index >= 0 && index < image->channel_count ? image->channels[index].half : 0;
}

int vbl_exr_image_find_channel(const vbl_exr_image* image, const char* name)
{
    if (!image || !name) return -1;
    for (int i = 0; i < image->channel_count; ++i)
        if (!strcmp(image->channels[i].name, name)) return i;
    return -1;
}

const float* vbl_exr_image_channel_pixels(const vbl_exr_image* image, int index)
{
    return image && index >= 0 && index < image->channel_count ? image->channels[index].pixels : NULL;
}

const char* vbl_exr_image_attribute(const vbl_exr_image* image, const char* name, int* type)
{
    if (!image || !name) return NULL;
    for (int i = 0; i < image->attribute_count; ++i)
        if (!strcmp(image->attributes[i].name, name)) {
            if (type) *type = image->attributes[i].type;
            return image->attributes[i].text;
        }
    return NULL;
}

int vbl_exr_image_chromaticities(const vbl_exr_image* image, float out[8])
{
    if (!image || !image->has_chromaticities) return 0;
    if (out) memcpy(out, image->chromaticities, sizeof image->chromaticities);
    return 1;
}

int vbl_exr_image_attribute_count(const vbl_exr_image* image) { return image ? image->attribute_count : 0; }

const char* vbl_exr_image_attribute_name(const vbl_exr_image* image, int index)
{
    return image && index >= 0 && index < image->attribute_count ? image->attributes[index].name : NULL;
}
