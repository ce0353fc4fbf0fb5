/* Files from vbl_exr_write opened by a real external reader (OpenImageIO's oiiotool/idiff):
 * layer names, metadata and pixel values as another program sees them. */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>

#include "output_test_util.h"
#include "vbl_exr.h"

#define W 5
#define H 3

static const char* tool(const char* var)
{
    const char* t = getenv(var);
    return t && t[0] ? t : (strcmp(var, "VBL_IDIFF") ? "oiiotool" : "idiff");
}

static float value(int layer, int c, int x, int y) { return 0.125f * (float)(layer + 1) + 0.25f * (float)c + 1.5f * (float)x + 10.0f * (float)y; }

static void write_test_file(const char* path, vbl_exr_compression comp, int tiled)
{
    static const char* const names[3] = {"", "emission", "volume_from_volume"};
    static float px[3][W * H * 4];
    vbl_exr_layer layers[3];
    for (int l = 0; l < 3; ++l) {
        int cc = l == 0 ? 4 : 3;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                for (int c = 0; c < cc; ++c) px[l][(y * W + x) * cc + c] = value(l, c, x, y);
        layers[l] = (vbl_exr_layer){names[l], cc, NULL, px[l], l == 2};
    }
    vbl_exr_attribute attrs[] = {
        {"software", "vbl test", VBL_EXR_ATTRIBUTE_STRING, 0, 0.0, NULL},
        {"vbl:seed", NULL, VBL_EXR_ATTRIBUTE_INT, 1234, 0.0, NULL},
        {"vbl:renderTime", NULL, VBL_EXR_ATTRIBUTE_DOUBLE, 0, 3.5, NULL},
    };
    const float chroma[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    vbl_exr_write_options opt = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    opt.compression = comp;
    opt.tiled = tiled;
    opt.tile_size = 2;
    opt.attributes = attrs;
    opt.attribute_count = 3;
    opt.chromaticities = chroma;
    opt.color_space = "Linear Rec.709 (sRGB)";
    if (vbl_exr_write(path, W, H, layers, 3, &opt) != VBL_SUCCESS) fail_msg("write: %s", vbl_last_error_message());
}

/* Parses "Pixel (x, y): a b c" lines of oiiotool --dumpdata into values[y][x][c]. */
static int parse_dump(const char* text, float* values, int channels)
{
    int count = 0;
    const char* p = text;
    while ((p = strstr(p, "Pixel ("))) {
        int x, y, n = 0;
        if (sscanf(p, "Pixel (%d, %d):%n", &x, &y, &n) != 2 || x < 0 || x >= W || y < 0 || y >= H) return -1;
        p += n;
        for (int c = 0; c < channels; ++c) {
            char* end;
            values[(y * W + x) * channels + c] = strtof(p, &end);
            if (end == p) return -1;
            p = end;
        }
        ++count;
    }
    return count;
}

/* One oiiotool run: header and every pixel; then (if `with_idiff`) idiff against OIIO's own copy. */
static void check_file(vbl_exr_compression comp, int tiled, const char* comp_name, int with_idiff)
{
    char* dir = out_make_temp_dir();
    const char* file = out_path(dir, "image.exr");
    write_test_file(file, comp, tiled);
    char cmd[2048], *out = NULL;
    snprintf(cmd, sizeof cmd, "%s --info -v --dumpdata '%s'", tool("VBL_OIIOTOOL"), file);
    if (out_run(cmd, &out) != 0) fail_msg("%s\n%s", cmd, out);
    const char* expect[] = {"5 x    3, 10 channel",
                            "channel list: R (float), G (float), B (float), A (float), emission.R (float), emission.G (float), emission.B (float), "
                            "volume_from_volume.R (half), volume_from_volume.G (half), volume_from_volume.B (half)",
                            "software: \"vbl test\"", "vbl:seed: 1234", "vbl:renderTime: 3.5",
                            "oiio:ColorSpace: \"Linear Rec.709 (sRGB)\"", comp_name,
                            "chromaticities: 0.64, 0.33, 0.3, 0.6, 0.15, 0.06, 0.3127, 0.329"};
    for (size_t i = 0; i < sizeof expect / sizeof expect[0]; ++i)
        if (!strstr(out, expect[i])) fail_msg("oiiotool --info lacks '%s':\n%s", expect[i], out);
    if (tiled && !strstr(out, "tile size: 2 x 2")) fail_msg("not tiled:\n%s", out);
    /* Pixel values in the channel order above: beauty R,G,B,A, emission R,G,B, volume_from_volume R,G,B. */
    float v[W * H * 10];
    if (parse_dump(out, v, 10) != W * H) fail_msg("cannot parse oiiotool output:\n%s", out);
    float lossy = comp == VBL_EXR_COMPRESSION_DWAA ? 0.02f : 0.0f;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int k = 0; k < 10; ++k) {
                int layer = k < 4 ? 0 : (k < 7 ? 1 : 2), c = k < 4 ? k : (k - 4) % 3;
                float expect_v = value(layer, c, x, y);
                float tol = (k == 3 ? 0.0f : lossy) + (layer == 2 ? 1.0f / 2048.0f : 0.0f);
                float got = v[(y * W + x) * 10 + k];
                if (fabsf(got - expect_v) > tol * fabsf(expect_v) + 1e-6f)
                    fail_msg("%s channel %d (%d,%d) = %g, expected %g", file, k, x, y, (double)got, (double)expect_v);
            }
    free(out);
    if (with_idiff) {
        /* idiff: identical to OIIO's own uncompressed copy, and able to fail on a changed file. */
        const char* copy = out_path(dir, "copy.exr");
        const char* changed = out_path(dir, "changed.exr");
        snprintf(cmd, sizeof cmd, "%s '%s' --compression none -o '%s' --addc 0.001 -o '%s'", tool("VBL_OIIOTOOL"), file,
                 copy, changed);
        assert_int_equal(out_run(cmd, NULL), 0);
        snprintf(cmd, sizeof cmd, "%s -fail 0 -warn 0 '%s' '%s'", tool("VBL_IDIFF"), file, copy);
        if (out_run(cmd, &out) != 0) fail_msg("%s\n%s", cmd, out);
        free(out);
        snprintf(cmd, sizeof cmd, "%s -fail 0.0001 '%s' '%s'", tool("VBL_IDIFF"), file, changed);
        assert_int_not_equal(out_run(cmd, NULL), 0);
    }
    out_remove_dir(dir);
}

static void test_scanline_zip(void** s) { (void)s; check_file(VBL_EXR_COMPRESSION_ZIP, 0, "compression: \"zip\"", 1); }
static void test_scanline_piz(void** s) { (void)s; check_file(VBL_EXR_COMPRESSION_PIZ, 0, "compression: \"piz\"", 0); }
static void test_tiled_none(void** s) { (void)s; check_file(VBL_EXR_COMPRESSION_NONE, 1, "compression: \"none\"", 0); }
static void test_scanline_dwaa(void** s) { (void)s; check_file(VBL_EXR_COMPRESSION_DWAA, 0, "compression: \"dwaa\"", 0); }

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scanline_zip),
        cmocka_unit_test(test_scanline_piz),
        cmocka_unit_test(test_tiled_none),
        cmocka_unit_test(test_scanline_dwaa),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
