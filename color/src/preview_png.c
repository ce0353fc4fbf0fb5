/* vbl_preview_write_png: display/view transform (OCIO) + 8-bit PNG (libpng), written atomically. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "vbl_color.h"

typedef struct vbl_png_error {
    jmp_buf jump;
    char message[256];
} vbl_png_error;

static void vbl_png_on_error(png_structp png, png_const_charp message)
{
    vbl_png_error* e = png_get_error_ptr(png);
    snprintf(e->message, sizeof e->message, "%s", message);
    longjmp(e->jump, 1);
}

static void vbl_png_on_warning(png_structp png, png_const_charp message)
{
    (void)png;
    (void)message;
}

/* Encodes `rgb8` (width*height*3 bytes) into the open stream. Returns 0 or -1 with `err` set. */
static int vbl_png_encode(FILE* f, const unsigned char* rgb8, int width, int height, int srgb_chunk, vbl_png_error* err)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, err, vbl_png_on_error, vbl_png_on_warning);
    if (!png) {
        snprintf(err->message, sizeof err->message, "out of memory");
        return -1;
    }
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(err->jump)) {
        if (!info) snprintf(err->message, sizeof err->message, "out of memory");
        png_destroy_write_struct(&png, info ? &info : NULL);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (srgb_chunk) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y) png_write_row(png, (png_const_bytep)(rgb8 + (size_t)y * (size_t)width * 3));
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return 0;
}

vbl_result vbl_preview_write_png(const char* path, const float* pixels, int width, int height, int channels,
                                 const vbl_preview_options* options)
{
    vbl_preview_options opt = VBL_PREVIEW_OPTIONS_DEFAULT;
    if (options) {
        if (options->size < sizeof(size_t) || options->size > sizeof opt)
            return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_preview_options.size = %zu is not a known size", options->size);
        memcpy(&opt, options, options->size);
    }
    if (!path || !path[0]) return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "preview output path is empty");
    if (!pixels || width <= 0 || height <= 0 || (channels != 3 && channels != 4) || (long long)width * height > (1LL << 31))
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: invalid preview image (%d x %d, %d channels)", path, width,
                                height, channels);
    vbl_color_config* owned = NULL;
    const vbl_color_config* config = opt.config;
    if (!config) {
        vbl_result r = vbl_color_config_open(NULL, &owned);
        if (r != VBL_SUCCESS) return r;
        config = owned;
    }
    size_t count = (size_t)width * (size_t)height;
    float* work = malloc(count * (size_t)channels * sizeof(float));
    unsigned char* rgb8 = malloc(count * 3);
    vbl_result result = VBL_SUCCESS;
    if (!work || !rgb8) result = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for the preview", path);
    if (result == VBL_SUCCESS) {
        memcpy(work, pixels, count * (size_t)channels * sizeof(float));
        result = vbl_color_display_view(config, opt.input_space ? opt.input_space : "scene_linear", opt.display,
                                        opt.view, opt.exposure, work, count, channels);
    }
    if (result == VBL_SUCCESS) {
        for (size_t i = 0; i < count; ++i)
            for (int c = 0; c < 3; ++c) {
                float v = work[i * (size_t)channels + (size_t)c];
                v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* also maps NaN to 0 */
                rgb8[i * 3 + (size_t)c] = (unsigned char)lrintf(v * 255.0f);
            }
        const char* display = opt.display ? opt.display : vbl_color_default_display(config);
        int srgb_chunk = display && strstr(display, "sRGB") != NULL;
        /* Temporary file beside the target, then rename. */
        size_t n = strlen(path) + 32;
        char* temp = malloc(n);
        const char* slash = strrchr(path, '/');
        int fd = -1;
        if (temp) {
            int dir_len = slash ? (int)(slash - path) + 1 : 0;
            snprintf(temp, n, "%.*s.%s.tmp-XXXXXX", dir_len, path, slash ? slash + 1 : path);
            fd = mkstemp(temp);
        }
        if (!temp) {
            result = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        } else if (fd < 0) {
            int e = errno;
            result = vbl_report_error(VBL_ERROR_FILE_IO, "%s: cannot create a file in its directory: %s", path, strerror(e));
        } else {
            (void)fchmod(fd, 0644);
            FILE* f = fdopen(fd, "wb");
            vbl_png_error err;
            memset(&err, 0, sizeof err);
            int failed = !f || vbl_png_encode(f, rgb8, width, height, srgb_chunk, &err) != 0;
            int e = errno;
            if (f) {
                if (fflush(f) != 0 && !failed) failed = 1, e = errno;
                if (!failed && fsync(fileno(f)) != 0) failed = 1, e = errno;
                if (fclose(f) != 0 && !failed) failed = 1, e = errno;
            } else {
                close(fd);
            }
            if (!failed && rename(temp, path) != 0) failed = 1, e = errno, err.message[0] = '\0';
            if (failed) {
                unlink(temp);
                result = vbl_report_error(VBL_ERROR_FILE_IO, "%s: cannot write the PNG preview: %s", path,
                                          err.message[0] ? err.message : strerror(e));
            }
        }
        free(temp);
    }
    free(work);
    free(rgb8);
    vbl_color_config_release(owned);
    return result;
}
