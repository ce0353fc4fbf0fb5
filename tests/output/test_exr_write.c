/* vbl_exr_write / vbl_exr_read: channels, types, compression, tiling, metadata, values read back
 * through OpenEXRCore; atomic replacement and failure paths (no partial files). */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>
#include <math.h>

#include <Imath/half.h>
#include <omp.h>

#include "exr_internal.h"
#include "output_test_util.h"
#include "vbl_exr.h"
#include "vbl/vbl.h"

/* A deterministic test image: value of channel c at pixel (x, y) of layer l. */
static float pattern(int l, int c, int x, int y)
{
    return 0.01f * (float)((x * 7 + y * 13 + c * 29 + l * 3) % 97) + 0.5f * (float)l + 0.001f * (float)c;
}

static float* make_pixels(int l, int channels, int w, int h)
{
    float* p = malloc(sizeof(float) * (size_t)(channels * w * h));
    assert_non_null(p);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < channels; ++c) p[(y * w + x) * channels + c] = pattern(l, c, x, y);
    return p;
}

static float half_round(float v) { return imath_half_to_float(imath_float_to_half(v)); }

static void check_channel(const vbl_exr_image* img, const char* name, int half, const float* src, int stride, int c,
                          float tolerance)
{
    int idx = vbl_exr_image_find_channel(img, name);
    if (idx < 0) fail_msg("channel %s missing", name);
    assert_int_equal(vbl_exr_image_channel_is_half(img, idx), half);
    const float* px = vbl_exr_image_channel_pixels(img, idx);
    int n = vbl_exr_image_width(img) * vbl_exr_image_height(img);
    for (int i = 0; i < n; ++i) {
        float expect = half ? half_round(src[i * stride + c]) : src[i * stride + c];
        if (tolerance == 0.0f) {
            if (px[i] != expect) fail_msg("%s pixel %d: %.9g != %.9g", name, i, (double)px[i], (double)expect);
        } else if (fabsf(px[i] - expect) > tolerance * (1.0f + fabsf(expect))) {
            fail_msg("%s pixel %d: %.9g vs %.9g", name, i, (double)px[i], (double)expect);
        }
    }
}

/* Writes beauty RGBA (float) + 2 transport layers (half) + Z, reads back, checks everything. */
static void roundtrip(vbl_exr_compression comp, int tiled, int tile_size, int w, int h, float tolerance)
{
    char* dir = out_make_temp_dir();
    const char* path = out_path(dir, "out.exr");
    float* beauty = make_pixels(0, 4, w, h);
    float* emission = make_pixels(1, 3, w, h);
    float* vdirect = make_pixels(2, 3, w, h);
    float* depth = make_pixels(3, 1, w, h);
    static const char* const z_name[] = {"Z"};
    vbl_exr_layer layers[] = {
        {"", 4, NULL, beauty, 0},
        {NULL, 3, NULL, emission, 1},
        {NULL, 3, NULL, NULL, 1}, /* not produced: skipped */
        {NULL, 3, NULL, vdirect, 1},
        {"", 1, z_name, depth, 0},
    };
    layers[1].name = vbl_transport_class_name(VBL_CLASS_EMISSION);
    layers[2].name = vbl_transport_class_name(VBL_CLASS_SURFACE_DIRECT);
    layers[3].name = vbl_transport_class_name(VBL_CLASS_VOLUME_DIRECT);
    const float chroma[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
    vbl_exr_attribute attrs[] = {
        {"software", "vbl 0.1.0", VBL_EXR_ATTRIBUTE_STRING, 0, 0.0, NULL},
        {"vbl:passes", NULL, VBL_EXR_ATTRIBUTE_INT, 64, 0.0, NULL},
        {"vbl:renderTime", NULL, VBL_EXR_ATTRIBUTE_DOUBLE, 0, 12.625, NULL},
        {"vbl:scene", "/scenes/a very long scene path/cloud.json", VBL_EXR_ATTRIBUTE_STRING, 0, 0.0, NULL},
    };
    vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    opt.compression = comp;
    opt.tiled = tiled;
    opt.tile_size = tile_size;
    opt.attributes = attrs;
    opt.attribute_count = 4;
    opt.chromaticities = chroma;
    opt.color_space = "ACEScg";
    vbl_result r = vbl_exr_write(path, w, h, layers, 5, &opt);
    if (r != VBL_SUCCESS) fail_msg("write: %s", vbl_last_error_message());

    vbl_exr_image* img = NULL;
    r = vbl_exr_read(path, &img);
    if (r != VBL_SUCCESS) fail_msg("read: %s", vbl_last_error_message());
    assert_int_equal(vbl_exr_image_width(img), w);
    assert_int_equal(vbl_exr_image_height(img), h);
    assert_true(vbl_exr_image_windows_match(img));
    assert_int_equal(vbl_exr_image_compression(img), comp);
    assert_int_equal(vbl_exr_image_tiled(img), tiled);
    if (tiled) assert_int_equal(vbl_exr_image_tile_size(img), tile_size ? tile_size : 64);
    assert_int_equal(vbl_exr_image_channel_count(img), 4 + 3 + 3 + 1);
    assert_int_equal(vbl_exr_image_find_channel(img, "surface_direct.R"), -1);
    /* EXR keeps channels sorted by name. */
    assert_string_equal(vbl_exr_image_channel_name(img, 0), "A");
    assert_string_equal(vbl_exr_image_channel_name(img, 4), "Z");
    assert_string_equal(vbl_exr_image_channel_name(img, 5), "background.B");
    /* DWAA is lossy for R,G,B-named channels only; other channels and codecs are exact. */
    float t_rgb = tolerance;
    check_channel(img, "R", 0, beauty, 4, 0, t_rgb);
    check_channel(img, "G", 0, beauty, 4, 1, t_rgb);
    check_channel(img, "B", 0, beauty, 4, 2, t_rgb);
    check_channel(img, "A", 0, beauty, 4, 3, 0.0f);
    check_channel(img, "Z", 0, depth, 1, 0, 0.0f);
    check_channel(img, "background.R", 1, emission, 3, 0, t_rgb);
    check_channel(img, "background.G", 1, emission, 3, 1, t_rgb);
    check_channel(img, "volume_direct.B", 1, vdirect, 3, 2, t_rgb);

    int type = -2;
    assert_string_equal(vbl_exr_image_attribute(img, "software", &type), "vbl 0.1.0");
    assert_int_equal(type, VBL_EXR_ATTRIBUTE_STRING);
    assert_string_equal(vbl_exr_image_attribute(img, "vbl:passes", &type), "64");
    assert_int_equal(type, VBL_EXR_ATTRIBUTE_INT);
    assert_string_equal(vbl_exr_image_attribute(img, "vbl:renderTime", &type), "12.625");
    assert_int_equal(type, VBL_EXR_ATTRIBUTE_DOUBLE);
    assert_string_equal(vbl_exr_image_attribute(img, "vbl:scene", NULL), "/scenes/a very long scene path/cloud.json");
    assert_string_equal(vbl_exr_image_attribute(img, "oiio:ColorSpace", NULL), "ACEScg");
    assert_null(vbl_exr_image_attribute(img, "absent", NULL));
    float c[8];
    assert_true(vbl_exr_image_chromaticities(img, c));
    assert_memory_equal(c, chroma, sizeof c);
    vbl_exr_image_release(img);

    /* Only the target remains: the temporary file was renamed. */
    char first[256] = "";
    assert_int_equal(out_count_entries(dir, first, sizeof first), 1);
    assert_string_equal(first, "out.exr");
    out_remove_dir(dir);
    free(beauty);
    free(emission);
    free(vdirect);
    free(depth);
}

static void test_scanline_none(void** s) { (void)s; roundtrip(VBL_EXR_COMPRESSION_NONE, 0, 0, 37, 21, 0.0f); }
static void test_scanline_zip(void** s) { (void)s; roundtrip(VBL_EXR_COMPRESSION_ZIP, 0, 0, 37, 45, 0.0f); }
static void test_scanline_piz(void** s) { (void)s; roundtrip(VBL_EXR_COMPRESSION_PIZ, 0, 0, 70, 45, 0.0f); }
static void test_scanline_dwaa(void** s) { (void)s; roundtrip(VBL_EXR_COMPRESSION_DWAA, 0, 0, 70, 45, 0.05f); }
static void test_tiled_zip(void** s) { (void)s; roundtrip(VBL_EXR_COMPRESSION_ZIP, 1, 16, 67, 45, 0.0f); }
static void test_tiled_default_size_none(void** s) { (void)s; roundtrip(VBL_EXR_COMPRESSION_NONE, 1, 0, 130, 70, 0.0f); }
static void test_tiled_piz(void** s) { (void)s; roundtrip(VBL_EXR_COMPRESSION_PIZ, 1, 32, 67, 33, 0.0f); }
static void test_tiled_dwaa(void** s) { (void)s; roundtrip(VBL_EXR_COMPRESSION_DWAA, 1, 32, 67, 33, 0.05f); }

/* Float storage keeps the renderer's guarantee: the layers read back sum to the beauty exactly. */
static void test_layers_sum_to_beauty_in_float(void** s)
{
    (void)s;
    const int w = 19, h = 11, n = w * h;
    static const char* const names[7] = {"background", "surface_direct", "volume_direct", "surface_from_surface",
                                         "surface_from_volume", "volume_from_surface", "volume_from_volume"};
    float* layer_px[7];
    float* beauty = calloc((size_t)n * 4, sizeof(float));
    vbl_exr_layer layers[8];
    for (int l = 0; l < 7; ++l) {
        layer_px[l] = make_pixels(l + 1, 3, w, h);
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) beauty[i * 4 + c] += layer_px[l][i * 3 + c] * 0.37f;
        for (int i = 0; i < n * 3; ++i) layer_px[l][i] *= 0.37f;
        layers[l + 1] = (vbl_exr_layer){names[l], 3, NULL, layer_px[l], 0};
    }
    /* Recompute beauty as the exact float sum in layer order (what the renderer guarantees). */
    for (int i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            float sum = 0.0f;
            for (int l = 0; l < 7; ++l) sum += layer_px[l][i * 3 + c];
            beauty[i * 4 + c] = sum;
        }
        beauty[i * 4 + 3] = 0.5f;
    }
    layers[0] = (vbl_exr_layer){"", 4, NULL, beauty, 0};
    char* dir = out_make_temp_dir();
    const char* path = out_path(dir, "sum.exr");
    vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    opt.compression = VBL_EXR_COMPRESSION_PIZ;
    assert_int_equal(vbl_exr_write(path, w, h, layers, 8, &opt), VBL_SUCCESS);
    vbl_exr_image* img = NULL;
    assert_int_equal(vbl_exr_read(path, &img), VBL_SUCCESS);
    static const char* const rgb[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        const float* b = vbl_exr_image_channel_pixels(img, vbl_exr_image_find_channel(img, rgb[c]));
        for (int i = 0; i < n; ++i) {
            float sum = 0.0f;
            for (int l = 0; l < 7; ++l) {
                char name[64];
                snprintf(name, sizeof name, "%s.%s", names[l], rgb[c]);
                int idx = vbl_exr_image_find_channel(img, name);
                assert_true(idx >= 0);
                sum += vbl_exr_image_channel_pixels(img, idx)[i];
            }
            assert_true(sum == b[i]);
        }
    }
    vbl_exr_image_release(img);
    for (int l = 0; l < 7; ++l) free(layer_px[l]);
    free(beauty);
    out_remove_dir(dir);
}

/* A half layer with values beyond half's range is stored as float (never Inf). */
static void test_half_overflow_promotes_to_float(void** s)
{
    (void)s;
    float px[3 * 4] = {1.0f, 2.0f, 3.0f, 1e6f, 0.5f, 0.25f, 7.0f, 8.0f, 9.0f, 0.0f, 0.0f, 0.0f};
    vbl_exr_layer layer = {"emission", 3, NULL, px, 1};
    char* dir = out_make_temp_dir();
    const char* path = out_path(dir, "big.exr");
    assert_int_equal(vbl_exr_write(path, 2, 2, &layer, 1, NULL), VBL_SUCCESS);
    vbl_exr_image* img = NULL;
    assert_int_equal(vbl_exr_read(path, &img), VBL_SUCCESS);
    int idx = vbl_exr_image_find_channel(img, "emission.R");
    assert_int_equal(vbl_exr_image_channel_is_half(img, idx), 0);
    assert_true(vbl_exr_image_channel_pixels(img, idx)[1] == 1e6f);
    vbl_exr_image_release(img);
    out_remove_dir(dir);
}

/* Checkpoints: repeated writes to one target replace it atomically; no temporaries remain. */
static void test_repeated_writes_replace_atomically(void** s)
{
    (void)s;
    char* dir = out_make_temp_dir();
    const char* path = out_path(dir, "checkpoint.exr");
    float px[4 * 6];
    for (int pass = 1; pass <= 5; ++pass) {
        for (int i = 0; i < 24; ++i) px[i] = (float)(pass * 100 + i);
        vbl_exr_layer layer = {"", 4, NULL, px, 0};
        vbl_exr_attribute a = {"vbl:passes", NULL, VBL_EXR_ATTRIBUTE_INT, pass, 0.0, NULL};
        vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
        opt.attributes = &a;
        opt.attribute_count = 1;
        assert_int_equal(vbl_exr_write(path, 3, 2, &layer, 1, &opt), VBL_SUCCESS);
        vbl_exr_image* img = NULL;
        assert_int_equal(vbl_exr_read(path, &img), VBL_SUCCESS);
        assert_true(vbl_exr_image_channel_pixels(img, vbl_exr_image_find_channel(img, "R"))[0] == (float)(pass * 100));
        assert_int_equal(atoi(vbl_exr_image_attribute(img, "vbl:passes", NULL)), pass);
        vbl_exr_image_release(img);
        assert_int_equal(out_count_entries(dir, NULL, 0), 1);
    }
    out_remove_dir(dir);
}

/* An injected write failure (disk full) gives one clear error, leaves the previous file intact
 * and no temporary file behind. */
static void test_failing_write_leaves_previous_file(void** s)
{
    (void)s;
    char* dir = out_make_temp_dir();
    const char* path = out_path(dir, "full.exr");
    const int w = 64, h = 64;
    float* px = make_pixels(0, 4, w, h);
    vbl_exr_layer layer = {"", 4, NULL, px, 0};
    vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    opt.compression = VBL_EXR_COMPRESSION_NONE;
    assert_int_equal(vbl_exr_write(path, w, h, &layer, 1, &opt), VBL_SUCCESS);
    struct stat before;
    assert_int_equal(stat(path, &before), 0);
    for (int64_t limit = 0; limit <= 40000; limit += 10000) {
        px[0] = 99.0f;
        vbl_exr_test_set_write_limit(limit);
        vbl_result r = vbl_exr_write(path, w, h, &layer, 1, &opt);
        vbl_exr_test_set_write_limit(-1);
        assert_int_equal(r, VBL_ERROR_FILE_IO);
        const char* msg = vbl_last_error_message();
        if (!strstr(msg, path) || !strstr(msg, "No space left")) fail_msg("unclear message: %s", msg);
        char first[256] = "";
        assert_int_equal(out_count_entries(dir, first, sizeof first), 1);
        assert_string_equal(first, "full.exr");
    }
    /* The DWAA path (OpenEXR's C++ library) fails the same way. */
    opt.compression = VBL_EXR_COMPRESSION_DWAA;
    for (int64_t limit = 0; limit <= 2000; limit += 1000) {
        vbl_exr_test_set_write_limit(limit);
        vbl_result r = vbl_exr_write(path, w, h, &layer, 1, &opt);
        vbl_exr_test_set_write_limit(-1);
        assert_int_equal(r, VBL_ERROR_FILE_IO);
        const char* msg = vbl_last_error_message();
        if (!strstr(msg, path) || !strstr(msg, "No space left")) fail_msg("unclear message: %s", msg);
        assert_int_equal(out_count_entries(dir, NULL, 0), 1);
    }
    vbl_exr_image* img = NULL;
    assert_int_equal(vbl_exr_read(path, &img), VBL_SUCCESS);
    assert_int_equal(vbl_exr_image_compression(img), VBL_EXR_COMPRESSION_NONE);
    assert_true(vbl_exr_image_channel_pixels(img, vbl_exr_image_find_channel(img, "R"))[0] == pattern(0, 0, 0, 0));
    vbl_exr_image_release(img);
    free(px);
    out_remove_dir(dir);
}

static void test_unwritable_paths(void** s)
{
    (void)s;
    char* dir = out_make_temp_dir();
    float px[4] = {1, 2, 3, 4};
    vbl_exr_layer layer = {"", 4, NULL, px, 0};
    vbl_result r = vbl_exr_write(out_path(dir, "missing/sub/out.exr"), 1, 1, &layer, 1, NULL);
    assert_int_equal(r, VBL_ERROR_FILE_IO);
    assert_non_null(strstr(vbl_last_error_message(), "missing/sub/out.exr"));
    /* A path through a regular file (ENOTDIR: fails even for root, unlike permission bits). */
    FILE* f = fopen(out_path(dir, "plain"), "w");
    assert_non_null(f);
    fclose(f);
    r = vbl_exr_write(out_path(dir, "plain/out.exr"), 1, 1, &layer, 1, NULL);
    assert_int_not_equal(r, VBL_SUCCESS);
    assert_non_null(strstr(vbl_last_error_message(), "plain/out.exr"));
    /* The target is a directory: rename fails, the temporary is removed. */
    assert_int_equal(mkdir(out_path(dir, "isdir.exr"), 0755), 0);
    assert_int_equal(mkdir(out_path(out_path(dir, "isdir.exr"), "x"), 0755), 0);
    r = vbl_exr_write(out_path(dir, "isdir.exr"), 1, 1, &layer, 1, NULL);
    assert_int_equal(r, VBL_ERROR_FILE_IO);
    assert_int_equal(out_count_entries(dir, NULL, 0), 2);
    rmdir(out_path(out_path(dir, "isdir.exr"), "x"));
    rmdir(out_path(dir, "isdir.exr"));
    out_remove_dir(dir);
}

static void test_invalid_input(void** s)
{
    (void)s;
    char* dir = out_make_temp_dir();
    const char* path = out_path(dir, "bad.exr");
    float px[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    vbl_exr_layer dup[2] = {{"a", 4, NULL, px, 0}, {"a", 4, NULL, px, 1}};
    assert_int_equal(vbl_exr_write(path, 1, 1, dup, 2, NULL), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "a.R"));
    px[5] = NAN;
    vbl_exr_layer nan_layer = {"emission", 4, NULL, px, 0};
    assert_int_equal(vbl_exr_write(path, 2, 1, &nan_layer, 1, NULL), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "emission.G"));
    px[5] = 6;
    vbl_exr_layer five = {"x", 5, NULL, px, 0};
    assert_int_equal(vbl_exr_write(path, 1, 1, &five, 1, NULL), VBL_ERROR_INVALID_ARGUMENT);
    vbl_exr_layer ok = {"x", 4, NULL, px, 0};
    assert_int_equal(vbl_exr_write(path, 0, 1, &ok, 1, NULL), VBL_ERROR_INVALID_ARGUMENT);
    vbl_exr_attribute reserved = {"channels", "x", VBL_EXR_ATTRIBUTE_STRING, 0, 0.0, NULL};
    vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    opt.attributes = &reserved;
    opt.attribute_count = 1;
    assert_int_equal(vbl_exr_write(path, 1, 1, &ok, 1, &opt), VBL_ERROR_INVALID_ARGUMENT);
    assert_int_equal(out_count_entries(dir, NULL, 0), 0);
    /* Reading: missing and corrupt files. */
    vbl_exr_image* img = NULL;
    assert_int_equal(vbl_exr_read(path, &img), VBL_ERROR_FILE_NOT_FOUND);
    assert_null(img);
    FILE* f = fopen(path, "wb");
    fputs("not an exr file at all", f);
    fclose(f);
    assert_int_equal(vbl_exr_read(path, &img), VBL_ERROR_CORRUPT_FILE);
    assert_non_null(strstr(vbl_last_error_message(), path));
    out_remove_dir(dir);
}

/* Older callers built against the first header (options without color_space) still work. */
static void test_old_options_size(void** s)
{
    (void)s;
    char* dir = out_make_temp_dir();
    float px[4] = {1, 2, 3, 4};
    vbl_exr_layer layer = {"", 4, NULL, px, 0};
    vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    opt.size = offsetof(vbl_exr_write_options, color_space);
    assert_int_equal(vbl_exr_write(out_path(dir, "old.exr"), 1, 1, &layer, 1, &opt), VBL_SUCCESS);
    opt.size = 3;
    assert_int_equal(vbl_exr_write(out_path(dir, "old.exr"), 1, 1, &layer, 1, &opt), VBL_ERROR_INVALID_ARGUMENT);
    out_remove_dir(dir);
}

static unsigned char* read_all(const char* path, long* size)
{
    FILE* f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char* data = malloc((size_t)*size);
    assert_int_equal(fread(data, 1, (size_t)*size, f), (size_t)*size);
    fclose(f);
    return data;
}

/* Chunks are compressed in parallel: the file's bytes do not depend on the thread count. */
static void test_same_bytes_at_any_thread_count(void** s)
{
    (void)s;
    const int w = 150, h = 97;
    float* px = make_pixels(0, 4, w, h);
    vbl_exr_layer layer = {"", 4, NULL, px, 1};
    char* dir = out_make_temp_dir();
    for (int tiled = 0; tiled < 2; ++tiled)
        for (int comp = VBL_EXR_COMPRESSION_NONE; comp <= VBL_EXR_COMPRESSION_PIZ; ++comp) {
            vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
            opt.compression = (vbl_exr_compression)comp;
            opt.tiled = tiled;
            opt.tile_size = 16;
            int saved = omp_get_max_threads();
            omp_set_num_threads(1);
            assert_int_equal(vbl_exr_write(out_path(dir, "one.exr"), w, h, &layer, 1, &opt), VBL_SUCCESS);
            omp_set_num_threads(3);
            assert_int_equal(vbl_exr_write(out_path(dir, "three.exr"), w, h, &layer, 1, &opt), VBL_SUCCESS);
            omp_set_num_threads(saved);
            long n1, n3;
            unsigned char* a = read_all(out_path(dir, "one.exr"), &n1);
            unsigned char* b = read_all(out_path(dir, "three.exr"), &n3);
            assert_int_equal(n1, n3);
            assert_memory_equal(a, b, (size_t)n1);
            free(a);
            free(b);
        }
    out_remove_dir(dir);
    free(px);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scanline_none),
        cmocka_unit_test(test_scanline_zip),
        cmocka_unit_test(test_scanline_piz),
        cmocka_unit_test(test_scanline_dwaa),
        cmocka_unit_test(test_tiled_zip),
        cmocka_unit_test(test_tiled_default_size_none),
        cmocka_unit_test(test_tiled_piz),
        cmocka_unit_test(test_tiled_dwaa),
        cmocka_unit_test(test_layers_sum_to_beauty_in_float),
        cmocka_unit_test(test_half_overflow_promotes_to_float),
        cmocka_unit_test(test_repeated_writes_replace_atomically),
        cmocka_unit_test(test_failing_write_leaves_previous_file),
        cmocka_unit_test(test_unwritable_paths),
        cmocka_unit_test(test_invalid_input),
        cmocka_unit_test(test_old_options_size),
        cmocka_unit_test(test_same_bytes_at_any_thread_count),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
