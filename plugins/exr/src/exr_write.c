/* vbl_exr_write: one single-part multi-layer EXR through OpenEXRCore, written atomically. */
#define _POSIX_C_SOURCE 200809L

#include <Imath/half.h>
#include <OpenEXR/openexr.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "exr_internal.h"

#define VBL_EXR_MAX_NAME 255
#define VBL_EXR_HALF_MAX 65504.0f

typedef struct vbl_exr_out_channel {
    char name[VBL_EXR_MAX_NAME + 1];
    int half;
    void* plane;          /* width*height values of the stored type (uint16 half bits or float) */
} vbl_exr_out_channel;

typedef struct vbl_exr_write_state {
    vbl_exr_output_file file;
    const char* path;
    char message[512];
} vbl_exr_write_state;

static void vbl_exr_write_error_handler(exr_const_context_t ctxt, exr_result_t code, const char* msg)
{
    void* user = NULL;
    if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user) return;
    vbl_exr_write_state* state = user;
    if (!state->message[0]) snprintf(state->message, sizeof state->message, "%s (%s)", msg, exr_get_error_code_as_string(code));
}

static int64_t vbl_exr_write_fn(exr_const_context_t ctxt, void* user, const void* buffer, uint64_t size,
                                uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    vbl_exr_write_state* state = user;
    return vbl_exr_output_pwrite(&state->file, buffer, size, offset);
}

static exr_compression_t vbl_exr_core_compression(vbl_exr_compression c)
{
    switch (c) {
    case VBL_EXR_COMPRESSION_ZIP: return EXR_COMPRESSION_ZIP;
    case VBL_EXR_COMPRESSION_PIZ: return EXR_COMPRESSION_PIZ;
    case VBL_EXR_COMPRESSION_DWAA: return EXR_COMPRESSION_DWAA;
    default: return EXR_COMPRESSION_NONE;
    }
}

/* Fills `channels` (one per written channel) with planar copies in the stored type. */
static vbl_result vbl_exr_prepare_channels(const char* path, int width, int height, const vbl_exr_layer* layers,
                                           int layer_count, vbl_exr_out_channel** out, int* out_count)
{
    static const char* const rgba[4] = {"R", "G", "B", "A"};
    int total = 0;
    for (int l = 0; l < layer_count; ++l) {
        const vbl_exr_layer* layer = &layers[l];
        if (!layer->pixels) continue;
        if (layer->channel_count < 1 || layer->channel_count > 4)
            return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: layer '%s' has %d channels (1..4 allowed)", path,
                                    layer->name ? layer->name : "", layer->channel_count);
        total += layer->channel_count;
    }
    if (total == 0) return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: no layer has pixels to write", path);
    vbl_exr_out_channel* channels = calloc((size_t)total, sizeof *channels);
    if (!channels) return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    size_t pixel_count = (size_t)width * (size_t)height;
    int n = 0;
    vbl_result result = VBL_SUCCESS;
    for (int l = 0; l < layer_count && result == VBL_SUCCESS; ++l) {
        const vbl_exr_layer* layer = &layers[l];
        if (!layer->pixels) continue;
        const char* lname = layer->name ? layer->name : "";
        const int cc = layer->channel_count;
        /* A layer stored as half whose values exceed half's range is stored as float instead:
         * half would turn them into Inf. */
        int half = layer->store_half != 0;
        for (size_t i = 0; half && i < pixel_count * (size_t)cc; ++i)
            if (fabsf(layer->pixels[i]) > VBL_EXR_HALF_MAX) half = 0;
        for (int c = 0; c < cc && result == VBL_SUCCESS; ++c) {
            const char* cname = layer->channel_names ? layer->channel_names[c] : rgba[c];
            vbl_exr_out_channel* ch = &channels[n];
            if (!cname || !cname[0] || strchr(cname, '.')) {
                result = vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: layer '%s' channel %d has an invalid name '%s'",
                                          path, lname, c, cname ? cname : "(null)");
                break;
            }
            int len = lname[0] ? snprintf(ch->name, sizeof ch->name, "%s.%s", lname, cname)
                               : snprintf(ch->name, sizeof ch->name, "%s", cname);
            if (len < 0 || len > VBL_EXR_MAX_NAME) {
                result = vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: channel name '%s.%s' is longer than %d bytes",
                                          path, lname, cname, VBL_EXR_MAX_NAME);
                break;
            }
            for (int k = 0; k < n; ++k)
                if (!strcmp(channels[k].name, ch->name)) {
                    result = vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: channel '%s' is given twice", path, ch->name);
                    break;
                }
            if (result != VBL_SUCCESS) break;
            ch->half = half;
            ch->plane = malloc(pixel_count * (half ? 2u : 4u));
            if (!ch->plane) {
                result = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for channel '%s'", path, ch->name);
                break;
            }
            ++n;
            const float* src = layer->pixels + c;
            for (size_t i = 0; i < pixel_count; ++i) {
                float v = src[i * (size_t)cc];
                if (!isfinite(v)) {
                    result = vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: channel '%s' pixel (%zu, %zu) is %g",
                                              path, ch->name, i % (size_t)width, i / (size_t)width, (double)v);
                    break;
                }
                if (half) ((uint16_t*)ch->plane)[i] = imath_float_to_half(v);
                else ((float*)ch->plane)[i] = v;
            }
        }
    }
    *out = channels;
    *out_count = n;
    return result;
}

static void vbl_exr_free_channels(vbl_exr_out_channel* channels, int count)
{
    for (int i = 0; i < count; ++i) free(channels[i].plane);
    free(channels);
}

/* One chunk (scanline block or tile): where its pixels start and, once encoded, its bytes. */
typedef struct vbl_exr_chunk {
    exr_chunk_info_t info;
    int x0, y0;            /* first pixel (OpenEXRCore 3.1 gives tile indices in info.start_x/y) */
    int tx, ty;            /* tile indices (tiled parts) */
    void* data;
    uint64_t size;
    exr_result_t rv;
} vbl_exr_chunk;

/* Pipeline write step replaced by a copy: chunks are compressed in parallel, written in order. */
static exr_result_t vbl_exr_capture_chunk(exr_encode_pipeline_t* encoder)
{
    vbl_exr_chunk* chunk = encoder->encoding_user_data;
    const void* src = encoder->compressed_buffer ? encoder->compressed_buffer : encoder->packed_buffer;
    uint64_t size = encoder->compressed_buffer ? encoder->compressed_bytes : encoder->packed_bytes;
    chunk->data = malloc(size ? (size_t)size : 1);
    if (!chunk->data) return EXR_ERR_OUT_OF_MEMORY;
    if (size) memcpy(chunk->data, src, (size_t)size);
    chunk->size = size;
    return EXR_ERR_SUCCESS;
}

/* The default "yield" refuses to encode a chunk before its predecessor is written; here chunks
 * are only captured, and vbl_exr_write_chunks writes them in order. */
static exr_result_t vbl_exr_chunks_in_order(exr_encode_pipeline_t* encoder)
{
    (void)encoder;
    return EXR_ERR_SUCCESS;
}

/* Encodes one chunk with `encoder` (initialised on first use) into chunk->data. */
static exr_result_t vbl_exr_encode_chunk(exr_const_context_t ctxt, int width, vbl_exr_chunk* chunk,
                                         exr_encode_pipeline_t* encoder, int* initialized,
                                         const vbl_exr_out_channel* channels, int channel_count)
{
    exr_result_t rv = *initialized ? exr_encoding_update(ctxt, 0, &chunk->info, encoder)
                                   : exr_encoding_initialize(ctxt, 0, &chunk->info, encoder);
    if (rv != EXR_ERR_SUCCESS) return rv;
    for (int c = 0; c < encoder->channel_count; ++c) {
        exr_coding_channel_info_t* info = &encoder->channels[c];
        const vbl_exr_out_channel* ch = NULL;
        for (int k = 0; k < channel_count && !ch; ++k)
            if (!strcmp(channels[k].name, info->channel_name)) ch = &channels[k];
        if (!ch) return EXR_ERR_INVALID_ARGUMENT;
        int bpe = ch->half ? 2 : 4;
        info->user_bytes_per_element = (int16_t)bpe;
        info->user_data_type = (uint16_t)(ch->half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT);
        info->user_pixel_stride = bpe;
        info->user_line_stride = width * bpe;
        info->encode_from_ptr =
            (const uint8_t*)ch->plane + ((size_t)chunk->y0 * (size_t)width + (size_t)chunk->x0) * (size_t)bpe;
    }
    if (!*initialized) {
        rv = exr_encoding_choose_default_routines(ctxt, 0, encoder);
        if (rv != EXR_ERR_SUCCESS) return rv;
        encoder->write_fn = vbl_exr_capture_chunk;
        encoder->yield_until_ready_fn = vbl_exr_chunks_in_order;
        *initialized = 1;
    }
    encoder->encoding_user_data = chunk;
    return exr_encoding_run(ctxt, 0, encoder);
}

/* Compresses all chunks in batches, in parallel (OpenMP), and writes each batch in file order. */
static exr_result_t vbl_exr_write_chunks(exr_context_t ctxt, int width, int height, int tiled, int tile,
                                         exr_compression_t compression, const vbl_exr_out_channel* channels,
                                         int channel_count)
{
    uint64_t bytes_per_pixel = 0;
    for (int c = 0; c < channel_count; ++c) bytes_per_pixel += channels[c].half ? 2u : 4u;
    int32_t lines = 1;
    exr_result_t rv = tiled ? EXR_ERR_SUCCESS : exr_get_scanlines_per_chunk(ctxt, 0, &lines);
    if (rv != EXR_ERR_SUCCESS) return rv;
    const int tiles_x = (width + tile - 1) / tile;
    const int count = tiled ? tiles_x * ((height + tile - 1) / tile) : (height + lines - 1) / lines;
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
    if (threads < 1) threads = 1;
#endif
    const int batch = threads * 4;
    vbl_exr_chunk* chunks = calloc((size_t)batch, sizeof *chunks);
    exr_encode_pipeline_t* encoders = calloc((size_t)threads, sizeof *encoders);
    int* ready = calloc((size_t)threads, sizeof *ready);
    if (!chunks || !encoders || !ready) rv = EXR_ERR_OUT_OF_MEMORY;
    for (int first = 0; first < count && rv == EXR_ERR_SUCCESS; first += batch) {
        const int n = count - first < batch ? count - first : batch;
        /* Chunk descriptions are built here: exr_write_*_chunk_info insists on being called in
         * file order, each after the previous chunk was written (checked against it below). */
        for (int i = 0; i < n; ++i) {
            vbl_exr_chunk* c = &chunks[i];
            memset(c, 0, sizeof *c);
            int index = first + i;
            if (tiled) {
                c->tx = index % tiles_x;
                c->ty = index / tiles_x;
                c->x0 = c->tx * tile;
                c->y0 = c->ty * tile;
                c->info.start_x = c->tx; /* tile indices, as OpenEXRCore 3.1 fills them */
                c->info.start_y = c->ty;
                c->info.width = width - c->x0 < tile ? width - c->x0 : tile;
                c->info.height = height - c->y0 < tile ? height - c->y0 : tile;
                c->info.type = EXR_STORAGE_TILED;
            } else {
                c->y0 = index * lines;
                c->info.start_y = c->y0;
                c->info.width = width;
                c->info.height = height - c->y0 < lines ? height - c->y0 : lines;
                c->info.type = EXR_STORAGE_SCANLINE;
            }
            c->info.idx = index;
            c->info.compression = (uint8_t)compression;
            c->info.unpacked_size = (uint64_t)c->info.width * (uint64_t)c->info.height * bytes_per_pixel;
        }
        if (rv != EXR_ERR_SUCCESS) break;
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
#endif
        for (int i = 0; i < n; ++i) {
            int t = 0;
#ifdef _OPENMP
            t = omp_get_thread_num();
#endif
            chunks[i].rv = vbl_exr_encode_chunk(ctxt, width, &chunks[i], &encoders[t], &ready[t], channels, channel_count);
        }
        for (int i = 0; i < n; ++i) {
            vbl_exr_chunk* c = &chunks[i];
            exr_chunk_info_t check;
            if (rv == EXR_ERR_SUCCESS) rv = c->rv;
            /* Core tracks the output order in *_chunk_info; it must precede each chunk's write. */
            if (rv == EXR_ERR_SUCCESS)
                rv = tiled ? exr_write_tile_chunk_info(ctxt, 0, c->tx, c->ty, 0, 0, &check)
                           : exr_write_scanline_chunk_info(ctxt, 0, c->y0, &check);
            if (rv == EXR_ERR_SUCCESS && (check.width != c->info.width || check.height != c->info.height ||
                                          check.unpacked_size != c->info.unpacked_size))
                rv = EXR_ERR_INVALID_ARGUMENT;
            if (rv == EXR_ERR_SUCCESS)
                rv = tiled ? exr_write_tile_chunk(ctxt, 0, c->tx, c->ty, 0, 0, c->data, c->size)
                           : exr_write_scanline_chunk(ctxt, 0, c->y0, c->data, c->size);
            free(c->data);
            c->data = NULL;
        }
    }
    for (int t = 0; encoders && ready && t < threads; ++t)
        if (ready[t] || encoders[t].channels) exr_encoding_destroy(ctxt, &encoders[t]);
    free(chunks);
    free(encoders);
    free(ready);
    return rv;
}

static exr_result_t vbl_exr_set_attribute(exr_context_t ctxt, const vbl_exr_attribute* a)
{
    switch (a->type) {
    case VBL_EXR_ATTRIBUTE_INT: return exr_attr_set_int(ctxt, 0, a->name, a->int_value);
    case VBL_EXR_ATTRIBUTE_DOUBLE: return exr_attr_set_double(ctxt, 0, a->name, a->double_value);
    case VBL_EXR_ATTRIBUTE_FLOAT: return exr_attr_set_float(ctxt, 0, a->name, (float)a->double_value);
    case VBL_EXR_ATTRIBUTE_M44F: {
        exr_attr_m44f_t m;
        memcpy(m.m, a->m44, sizeof m.m);
        return exr_attr_set_m44f(ctxt, 0, a->name, &m);
    }
    default: return exr_attr_set_string(ctxt, 0, a->name, a->value ? a->value : "");
    }
}

static int vbl_exr_is_required_attribute(const char* name)
{
    static const char* const required[] = {"channels", "compression", "dataWindow", "displayWindow", "lineOrder",
                                           "pixelAspectRatio", "screenWindowCenter", "screenWindowWidth", "tiles",
                                           "chromaticities", "name", "type", "version", "chunkCount"};
    for (size_t i = 0; i < sizeof required / sizeof required[0]; ++i)
        if (!strcmp(name, required[i])) return 1;
    return 0;
}

vbl_result vbl_exr_write(const char* path, int width, int height, const vbl_exr_layer* layers, int layer_count,
                         const vbl_exr_write_options* options)
{
    vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    if (options) {
        if (options->size < offsetof(vbl_exr_write_options, color_space) || options->size > sizeof opt)
            return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vbl_exr_write_options.size = %zu is not a known size",
                                    path ? path : "(null)", options->size);
        memcpy(&opt, options, options->size);
        opt.size = sizeof opt;
    }
    if (!path || !path[0]) return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "EXR output path is empty");
    if (width <= 0 || height <= 0 || (int64_t)width * height > (int64_t)1 << 31)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: image size %d x %d is invalid", path, width, height);
    if (!layers || layer_count <= 0) return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: no layers to write", path);
    if ((int)opt.compression < VBL_EXR_COMPRESSION_NONE || opt.compression > VBL_EXR_COMPRESSION_DWAA)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: unknown compression %d", path, (int)opt.compression);
    int tile = opt.tile_size > 0 ? opt.tile_size : 64;
    if (opt.tiled && tile > 4096)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: tile size %d is too large", path, tile);
    if (opt.attribute_count < 0 || (opt.attribute_count > 0 && !opt.attributes))
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: attribute_count %d without attributes", path, opt.attribute_count);
    int long_names = 0;
    for (int i = 0; i < opt.attribute_count; ++i) {
        const vbl_exr_attribute* a = &opt.attributes[i];
        if (!a->name || !a->name[0] || strlen(a->name) > VBL_EXR_MAX_NAME || vbl_exr_is_required_attribute(a->name))
            return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: attribute %d has an invalid or reserved name '%s'",
                                    path, i, a->name ? a->name : "(null)");
        if (a->type == VBL_EXR_ATTRIBUTE_M44F && !a->m44)
            return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: m44f attribute '%s' without values", path, a->name);
        if ((unsigned)a->type > VBL_EXR_ATTRIBUTE_M44F)
            return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: attribute '%s' has unknown type %d", path, a->name, (int)a->type);
        if (strlen(a->name) > 31) long_names = 1;
    }

    vbl_exr_out_channel* channels = NULL;
    int channel_count = 0;
    vbl_result result = vbl_exr_prepare_channels(path, width, height, layers, layer_count, &channels, &channel_count);
    if (result != VBL_SUCCESS) {
        vbl_exr_free_channels(channels, channel_count);
        return result;
    }
    for (int i = 0; i < channel_count; ++i)
        if (strlen(channels[i].name) > 31) long_names = 1;

    vbl_exr_write_state* state = calloc(1, sizeof *state);
    if (!state) {
        vbl_exr_free_channels(channels, channel_count);
        return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    state->path = path;
    result = vbl_exr_output_open(&state->file, path);
    if (result != VBL_SUCCESS) {
        free(state);
        vbl_exr_free_channels(channels, channel_count);
        return result;
    }

    if (opt.compression == VBL_EXR_COMPRESSION_DWAA) {
        vbl_exr_plane* planes = calloc((size_t)channel_count, sizeof *planes);
        if (!planes) result = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        for (int i = 0; planes && i < channel_count; ++i)
            planes[i] = (vbl_exr_plane){channels[i].name, channels[i].half, channels[i].plane};
        if (planes) result = vbl_exr_write_imf(&state->file, path, width, height, planes, channel_count, &opt, tile);
        free(planes);
        if (result == VBL_SUCCESS) result = vbl_exr_output_commit(&state->file);
        else vbl_exr_output_abort(&state->file);
        free(state);
        vbl_exr_free_channels(channels, channel_count);
        return result;
    }

    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = vbl_exr_write_error_handler;
    init.user_data = state;
    init.write_fn = vbl_exr_write_fn;
    if (opt.dwa_quality > 0.0f) init.dwa_quality = opt.dwa_quality;
    exr_context_t ctxt = NULL;
    const char* step = "creating the file";
    int part = 0;
    exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS) step = "defining the header", rv = exr_add_part(ctxt, NULL, opt.tiled ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS) rv = exr_initialize_required_attr_simple(ctxt, 0, width, height, vbl_exr_core_compression(opt.compression));
    if (rv == EXR_ERR_SUCCESS && opt.tiled)
        rv = exr_set_tile_descriptor(ctxt, 0, (uint32_t)tile, (uint32_t)tile, EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN);
    if (rv == EXR_ERR_SUCCESS && long_names) rv = exr_set_longname_support(ctxt, 1);
    for (int i = 0; i < channel_count && rv == EXR_ERR_SUCCESS; ++i) {
        int r = exr_add_channel(ctxt, 0, channels[i].name, channels[i].half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                                EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
        if (r != EXR_ERR_SUCCESS) rv = r;
    }
    if (rv == EXR_ERR_SUCCESS && opt.chromaticities) {
        const float* c = opt.chromaticities;
        exr_attr_chromaticities_t chroma = {c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]};
        rv = exr_attr_set_chromaticities(ctxt, 0, "chromaticities", &chroma);
    }
    if (rv == EXR_ERR_SUCCESS && opt.color_space && opt.color_space[0])
        rv = exr_attr_set_string(ctxt, 0, "oiio:ColorSpace", opt.color_space);
    for (int i = 0; i < opt.attribute_count && rv == EXR_ERR_SUCCESS; ++i) rv = vbl_exr_set_attribute(ctxt, &opt.attributes[i]);
    if (rv == EXR_ERR_SUCCESS) step = "writing the header", rv = exr_write_header(ctxt);
    if (rv == EXR_ERR_SUCCESS) step = "writing pixels";
    if (rv == EXR_ERR_SUCCESS) rv = vbl_exr_write_chunks(ctxt, width, height, opt.tiled, tile, vbl_exr_core_compression(opt.compression),
                                  channels, channel_count);
    if (ctxt) {
        if (rv == EXR_ERR_SUCCESS) step = "finishing the file";
        exr_result_t frv = exr_finish(&ctxt);
        if (rv == EXR_ERR_SUCCESS) rv = frv;
    }
    if (rv == EXR_ERR_SUCCESS && state->file.failed_errno) rv = EXR_ERR_WRITE_IO;
    if (rv != EXR_ERR_SUCCESS) {
        if (state->file.failed_errno)
            result = vbl_report_error(VBL_ERROR_FILE_IO, "%s: write failed while %s: %s", path, step, strerror(state->file.failed_errno));
        else
            result = vbl_report_error(rv == EXR_ERR_OUT_OF_MEMORY ? VBL_ERROR_OUT_OF_MEMORY : VBL_ERROR_FILE_IO,
                                      "%s: OpenEXR failed while %s: %s", path, step,
                                      state->message[0] ? state->message : exr_get_default_error_message(rv));
        vbl_exr_output_abort(&state->file);
    } else {
        result = vbl_exr_output_commit(&state->file);
    }
    free(state);
    vbl_exr_free_channels(channels, channel_count);
    return result;
}
