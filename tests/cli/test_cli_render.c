/* `vbl render` end to end: a 16x12, 2-pass render of a box of smoke through the real binary,
 * read back with vbl_exr_read: channels, types, layers summing to beauty bit-exactly, metadata,
 * colour space + chromaticities, AOVs on request, storage flags, the preview PNG. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli_test_util.h"
#include "vbl_exr.h"
#include "vbl/vbl.h"
#ifdef VBL_TEST_HAVE_COLOR
#include "vbl_color.h"
#endif

#define W 16
#define H 12

static char* dir;
static const char* scene;

static int setup(void** state)
{
    (void)state;
    dir = ct_make_dir();
    static char scene_path[2048];
    snprintf(scene_path, sizeof scene_path, "%s/scene.json", dir);
    ct_write_scene(scene_path, W, H, NULL);
    scene = scene_path;
    return 0;
}

static int teardown(void** state)
{
    (void)state;
    ct_remove_dir(dir);
    free(dir);
    return 0;
}

static vbl_exr_image* render_and_read(const char* name, const char* extra)
{
    char args[4096];
    const char* out = ct_path(dir, name);
    snprintf(args, sizeof args, "'%s' -o '%s' -q %s", scene, out, extra);
    char* log = NULL;
    int code = ct_render(args, &log);
    if (code != 0) fail_msg("vbl render %s -> %d:\n%s", args, code, log ? log : "");
    free(log);
    vbl_exr_image* img = NULL;
    if (vbl_exr_read(out, &img) != VBL_SUCCESS) fail_msg("%s", vbl_last_error_message());
    return img;
}

static const float* channel(const vbl_exr_image* img, const char* name)
{
    int i = vbl_exr_image_find_channel(img, name);
    if (i < 0) fail_msg("no channel %s", name);
    return vbl_exr_image_channel_pixels(img, i);
}

static const char* attr(const vbl_exr_image* img, const char* name)
{
    const char* v = vbl_exr_image_attribute(img, name, NULL);
    if (!v) fail_msg("no attribute %s", name);
    return v;
}

/* Beauty R,G,B == float sum background + volume_direct + volume_from_volume, in that order. */
static void assert_layers_sum(const vbl_exr_image* img)
{
    static const char* const layers[3] = {"background", "volume_direct", "volume_from_volume"};
    static const char* const rgb[3] = {"R", "G", "B"};
    int nonzero = 0;
    for (int c = 0; c < 3; ++c) {
        const float* beauty = channel(img, rgb[c]);
        const float* l[3];
        for (int k = 0; k < 3; ++k) {
            char name[64];
            snprintf(name, sizeof name, "%s.%s", layers[k], rgb[c]);
            l[k] = channel(img, name);
        }
        for (int i = 0; i < W * H; ++i) {
            float sum = 0.0f;
            for (int k = 0; k < 3; ++k) sum += l[k][i];
            if (sum != beauty[i]) fail_msg("pixel %d channel %s: layers sum %.9g, beauty %.9g", i, rgb[c], sum, beauty[i]);
            assert_true(isfinite(beauty[i]));
            nonzero += beauty[i] > 0.0f;
        }
    }
    assert_true(nonzero > W * H); /* the box is lit and visible */
}

static void test_layers_metadata_aovs_preview(void** state)
{
    (void)state;
    char extra[2048];
    snprintf(extra, sizeof extra, "--aov all --seed 7 --passes 2 --spp 2 --preview '%s'", ct_path(dir, "p.png"));
    vbl_exr_image* img = render_and_read("full.exr", extra);
    assert_int_equal(vbl_exr_image_width(img), W);
    assert_int_equal(vbl_exr_image_height(img), H);
    static const char* const expected[] = {"A", "B", "G", "R", "Z", "background.B", "background.G", "background.R",
                                           "samples.Y", "variance.B", "variance.G", "variance.R",
                                           "volume_direct.B", "volume_direct.G", "volume_direct.R",
                                           "volume_from_volume.B", "volume_from_volume.G", "volume_from_volume.R",
                                           "volume_indirect.B",    "volume_indirect.G",    "volume_indirect.R"};
    int n = (int)(sizeof expected / sizeof expected[0]);
    assert_int_equal(vbl_exr_image_channel_count(img), n);
    for (int i = 0; i < n; ++i) {
        int idx = vbl_exr_image_find_channel(img, expected[i]);
        if (idx < 0) fail_msg("missing channel %s", expected[i]);
        assert_int_equal(vbl_exr_image_channel_is_half(img, idx), 0);
    }
    assert_layers_sum(img);
    /* AOVs: alpha in [0, 1] and > 0 on the box; depth > 0 where the ray hit the medium (camera is
     * 3 units in front of the box face); samples = passes * spp; variance >= 0. */
    const float *a = channel(img, "A"), *z = channel(img, "Z"), *s = channel(img, "samples.Y"),
                *v = channel(img, "variance.R");
    int hits = 0;
    for (int i = 0; i < W * H; ++i) {
        assert_true(a[i] >= 0.0f && a[i] <= 1.0f);
        assert_true(s[i] == 4.0f);
        assert_true(v[i] >= 0.0f && isfinite(v[i]));
        if (z[i] == VBL_FILM_Z_MISS) continue; /* no collision: Cycles' large background depth */
        ++hits;
        assert_true(z[i] > 2.5f && z[i] < 6.0f);
    }
    assert_true(hits > W * H / 8);
    assert_true(a[(H / 2) * W + W / 2] > 0.5f);
    /* Metadata. */
    assert_string_equal(attr(img, "vbl:method"), "pt");
    assert_string_equal(attr(img, "vbl:passes"), "2");
    assert_string_equal(attr(img, "vbl:passes_requested"), "2");
    assert_string_equal(attr(img, "vbl:spp"), "2");
    assert_string_equal(attr(img, "vbl:seed"), "7");
    assert_string_equal(attr(img, "vbl:preset"), "none");
    assert_string_equal(attr(img, "vbl:status"), "complete");
    assert_string_equal(attr(img, "vbl:scene"), scene);
    assert_true(strncmp(attr(img, "software"), "vbl ", 4) == 0);
    assert_string_equal(attr(img, "vbl:version"), vbl_version_string());
    assert_true(atoi(attr(img, "vbl:threads")) >= 1);
    assert_true(atof(attr(img, "vbl:render_seconds")) >= 0.0);
    char hash[64];
    snprintf(hash, sizeof hash, "fnv1a64:%016llx", (unsigned long long)ct_fnv1a64_file(scene));
    assert_string_equal(attr(img, "vbl:scene_hash"), hash);
#ifdef VBL_TEST_HAVE_COLOR
    assert_string_equal(attr(img, "oiio:ColorSpace"), "Linear Rec.709 (sRGB)");
    float chroma[8];
    assert_int_equal(vbl_exr_image_chromaticities(img, chroma), 1);
    static const float rec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    for (int i = 0; i < 8; ++i) assert_true(fabsf(chroma[i] - rec709[i]) < 1e-3f);
    /* The preview: 8-bit RGB, 16 x 12. */
    int pw = 0, ph = 0, depth = 0, type = 0;
    assert_int_equal(ct_png_info(ct_path(dir, "p.png"), &pw, &ph, &depth, &type), 1);
    assert_int_equal(pw, W);
    assert_int_equal(ph, H);
    assert_int_equal(depth, 8);
    assert_int_equal(type, PNG_COLOR_TYPE_RGB);
#endif
    /* Same scene, seed, passes: the same pixels at another thread count; the hash is stable. */
    vbl_exr_image* again = render_and_read("again.exr", "--aov all --seed 7 --passes 2 --spp 2 --threads 1");
    assert_string_equal(attr(again, "vbl:scene_hash"), hash);
    assert_memory_equal(channel(img, "R"), channel(again, "R"), sizeof(float) * W * H);
    vbl_exr_image_release(again);
    vbl_exr_image_release(img);
    /* Nothing but the outputs in the folder: no temporary files left. */
    char names[1024];
    int count = ct_count_entries(dir, names, sizeof names);
#ifdef VBL_TEST_HAVE_COLOR
    if (count != 4) fail_msg("folder holds: %s", names);
#else
    (void)count;
#endif
    remove(ct_path(dir, "full.exr"));
    remove(ct_path(dir, "again.exr"));
    remove(ct_path(dir, "p.png"));
}

/* Without --aov: beauty + transport layers only. --half / --half-layers, compressions, tiles. */
static void test_storage_options(void** state)
{
    (void)state;
    vbl_exr_image* img = render_and_read("plain.exr", "");
    assert_int_equal(vbl_exr_image_channel_count(img), 16); /* beauty, 3 classes, volume_indirect */
    assert_true(vbl_exr_image_find_channel(img, "Z") < 0);
    assert_true(vbl_exr_image_find_channel(img, "samples.Y") < 0);
    assert_true(vbl_exr_image_find_channel(img, "variance.R") < 0);
    assert_int_equal(vbl_exr_image_compression(img), VBL_EXR_COMPRESSION_ZIP);
    assert_int_equal(vbl_exr_image_tiled(img), 0);
    assert_string_equal(attr(img, "vbl:seed"), "3"); /* the scene's render block */
    assert_layers_sum(img);
    vbl_exr_image_release(img);

    img = render_and_read("half.exr", "--half --aov z,samples --compression piz --tiled --tile-size 8");
    assert_int_equal(vbl_exr_image_compression(img), VBL_EXR_COMPRESSION_PIZ);
    assert_int_equal(vbl_exr_image_tiled(img), 1);
    assert_int_equal(vbl_exr_image_tile_size(img), 8);
    for (int i = 0; i < vbl_exr_image_channel_count(img); ++i) {
        const char* name = vbl_exr_image_channel_name(img, i);
        int want_half = strcmp(name, "Z") && strcmp(name, "samples.Y");
        if (vbl_exr_image_channel_is_half(img, i) != want_half) fail_msg("channel %s half = %d", name, !want_half);
    }
    vbl_exr_image_release(img);

    img = render_and_read("some.exr", "--half-layers background,beauty --compression none");
    assert_int_equal(vbl_exr_image_compression(img), VBL_EXR_COMPRESSION_NONE);
    for (int i = 0; i < vbl_exr_image_channel_count(img); ++i) {
        const char* name = vbl_exr_image_channel_name(img, i);
        int want_half = !strchr(name, '.') || !strncmp(name, "background.", 11);
        if (vbl_exr_image_channel_is_half(img, i) != want_half) fail_msg("channel %s half = %d", name, !want_half);
    }
    vbl_exr_image_release(img);

    img = render_and_read("dwaa.exr", "--compression dwaa");
    assert_int_equal(vbl_exr_image_compression(img), VBL_EXR_COMPRESSION_DWAA);
    vbl_exr_image_release(img);
}

#ifdef VBL_TEST_HAVE_COLOR
/* --output-space ACEScg: the pixels are the Rec.709 render converted, the layers still sum to
 * the beauty exactly, and the file names its space and AP1 chromaticities. */
static void test_output_space(void** state)
{
    (void)state;
    vbl_exr_image* ref = render_and_read("rec709.exr", "");
    vbl_exr_image* img = render_and_read("acescg.exr", "--output-space ACEScg");
    assert_string_equal(attr(img, "oiio:ColorSpace"), "ACEScg");
    float chroma[8];
    assert_int_equal(vbl_exr_image_chromaticities(img, chroma), 1);
    static const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
    for (int i = 0; i < 8; ++i) assert_true(fabsf(chroma[i] - ap1[i]) < 1e-3f);
    assert_layers_sum(img);
    vbl_color_config* config = NULL;
    assert_int_equal(vbl_color_config_open(NULL, &config), VBL_SUCCESS);
    static const char* const rgb[3] = {"R", "G", "B"};
    int differs = 0;
    for (int i = 0; i < W * H; ++i) {
        float v[3];
        for (int c = 0; c < 3; ++c) v[c] = channel(ref, rgb[c])[i];
        assert_int_equal(vbl_color_convert_rgb(config, "scene_linear", "ACEScg", v), VBL_SUCCESS);
        for (int c = 0; c < 3; ++c) {
            float got = channel(img, rgb[c])[i];
            if (fabsf(got - v[c]) > 1e-5f + 1e-4f * fabsf(v[c])) fail_msg("pixel %d %s: %g vs %g", i, rgb[c], got, v[c]);
            differs += got != channel(ref, rgb[c])[i];
        }
        assert_true(channel(img, "A")[i] == channel(ref, "A")[i]);
    }
    assert_true(differs > 0);
    vbl_color_config_release(config);
    vbl_exr_image_release(img);
    vbl_exr_image_release(ref);
}

/* A scene in ACEScg ("color_space") renders like the same scene with its colours converted to
 * Linear Rec.709 (the config's scene_linear) beforehand; an unknown space fails like other scene
 * errors (exit 3), naming the file and color_space. */
static void test_scene_color_space(void** state)
{
    (void)state;
    vbl_color_config* config = NULL;
    assert_int_equal(vbl_color_config_open(NULL, &config), VBL_SUCCESS);
    float irradiance[3] = {2.0f, 1.8f, 1.5f}, radiance[3] = {0.10f, 0.12f, 0.20f}, albedo[3] = {0.9f, 0.8f, 0.7f};
    float* colors[3] = {irradiance, radiance, albedo};
    for (int i = 0; i < 3; ++i)
        assert_int_equal(vbl_color_convert_rgb(config, "ACEScg", "scene_linear", colors[i]), VBL_SUCCESS);
    vbl_color_config_release(config);
    char text[4096];
    snprintf(text, sizeof text,
             "{\n"
             "  \"camera\": {\"position\": [0.75, -3.0, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 40,\n"
             "             \"resolution\": [%d, %d]},\n"
             "  \"lights\": [{\"type\": \"distant\", \"direction\": [-0.3, 0.5, -0.8], \"irradiance\": [%.9g, %.9g, %.9g]},\n"
             "             {\"type\": \"environment\", \"radiance\": [%.9g, %.9g, %.9g]}],\n"
             "  \"media\": [{\"vdb\": \"%s\", \"density_scale\": 3.0, \"albedo\": [%.9g, %.9g, %.9g],\n"
             "              \"phase\": {\"type\": \"hg\", \"g\": 0.3}}],\n"
             "  \"render\": {\"method\": \"pt\", \"passes\": 2, \"spp\": 2, \"seed\": 3, \"max_bounces\": 4}\n"
             "}\n",
             W, H, irradiance[0], irradiance[1], irradiance[2], radiance[0], radiance[1], radiance[2],
             ct_fixture("box.vdb"), albedo[0], albedo[1], albedo[2]);
    const char* rec709_scene = ct_path(dir, "rec709_scene.json");
    ct_write_file(rec709_scene, text);
    const char* aces_scene = ct_path(dir, "acescg_scene.json");
    ct_write_scene(aces_scene, W, H, "  \"color_space\": \"ACEScg\",\n");

    char args[4096];
    char* log = NULL;
    const char* names[2] = {"cs_rec709.exr", "cs_acescg.exr"};
    const char* scenes[2] = {rec709_scene, aces_scene};
    vbl_exr_image* img[2] = {NULL, NULL};
    for (int k = 0; k < 2; ++k) {
        const char* out = ct_path(dir, names[k]);
        snprintf(args, sizeof args, "'%s' -o '%s' -q", scenes[k], out);
        int code = ct_render(args, &log);
        if (code != 0) fail_msg("vbl render %s -> %d:\n%s", args, code, log ? log : "");
        free(log);
        log = NULL;
        if (vbl_exr_read(out, &img[k]) != VBL_SUCCESS) fail_msg("%s", vbl_last_error_message());
    }
    static const char* const rgb[3] = {"R", "G", "B"};
    double peak = 0.0;
    for (int i = 0; i < W * H; ++i)
        for (int c = 0; c < 3; ++c) {
            float want = channel(img[0], rgb[c])[i], got = channel(img[1], rgb[c])[i];
            if (fabsf(got - want) > 1e-4f * fabsf(want) + 1e-7f)
                fail_msg("pixel %d %s: %g vs %g", i, rgb[c], got, want);
            if (want > peak) peak = want;
        }
    assert_true(peak > 0.0); /* the comparison saw light */
    vbl_exr_image_release(img[0]);
    vbl_exr_image_release(img[1]);

    const char* bad_scene = ct_path(dir, "bad_space.json");
    ct_write_scene(bad_scene, W, H, "  \"color_space\": \"NoSuchSpace\",\n");
    snprintf(args, sizeof args, "'%s' -o '%s' -q", bad_scene, ct_path(dir, "bad_space.exr"));
    assert_int_equal(ct_render(args, &log), 3);
    char expected[2048];
    snprintf(expected, sizeof expected, "%s: color_space = \"NoSuchSpace\" (lights[0].irradiance): ", bad_scene);
    if (!log || !strstr(log, expected)) fail_msg("want '%s' in:\n%s", expected, log ? log : "");
    free(log);
}
#endif


/* Beauty R,G,B == float sum of the class layers but the background (--transparent), in class order. */
static void assert_transparent_sum(const vbl_exr_image* img)
{
    static const char* const layers[2] = {"volume_direct", "volume_from_volume"};
    static const char* const rgb[3] = {"R", "G", "B"};
    char name[64];
    for (int c = 0; c < 3; ++c) {
        const float* beauty = channel(img, rgb[c]);
        snprintf(name, sizeof name, "background.%s", rgb[c]);
        const float* bg = channel(img, name);
        const float* l[2];
        for (int k = 0; k < 2; ++k) {
            snprintf(name, sizeof name, "%s.%s", layers[k], rgb[c]);
            l[k] = channel(img, name);
        }
        int sky = 0;
        for (int i = 0; i < W * H; ++i) {
            float sum = l[0][i] + l[1][i];
            if (sum != beauty[i]) fail_msg("pixel %d channel %s: layers sum %.9g, beauty %.9g", i, rgb[c], sum, beauty[i]);
            sky += bg[i] > 0.0f;
        }
        assert_true(sky > W * H / 2); /* the background is rendered, only not in the beauty */
    }
}

/* --transparent, --opt=value, worldToCamera / worldToNDC, the output extension check and
 * vbl merge of transparent parts. */
static void test_transparent_camera_extension(void** state)
{
    (void)state;
    vbl_exr_image* img = render_and_read("clear.exr", "--transparent=on --passes=2 --spp 1 --seed 3 --aov=z");
    assert_transparent_sum(img);
    assert_string_equal(attr(img, "vbl:transparent"), "1");
    const float* a = channel(img, "A");
    assert_true(a[0] < 1.0f); /* the corner sees the sky through thin or no smoke */
    int type = -1;
    const char* m = vbl_exr_image_attribute(img, "worldToCamera", &type);
    assert_non_null(m);
    assert_int_equal(type, VBL_EXR_ATTRIBUTE_M44F);
    float e[16];
    const char* p = m;
    for (int k = 0; k < 16; ++k) {
        char* end = NULL;
        e[k] = strtof(p, &end);
        assert_true(end != p);
        p = end;
    }
    assert_true(e[15] == 1.0f && e[3] == 0.0f && e[7] == 0.0f && e[11] == 0.0f); /* affine, row vectors */
    assert_non_null(vbl_exr_image_attribute(img, "worldToNDC", &type));
    assert_int_equal(type, VBL_EXR_ATTRIBUTE_M44F);
    vbl_exr_image_release(img);

    /* vbl merge of two transparent pass ranges keeps the rules and the metadata */
    char args[4096];
    char* log = NULL;
    for (int part = 0; part < 2; ++part) {
        snprintf(args, sizeof args, "'%s' -o '%s' -q --transparent on --passes 2 --spp 1 --seed 3 --pass-range %d-%d",
                 scene, ct_path(dir, part ? "part1.exr" : "part0.exr"), part, part);
        assert_int_equal(ct_render(args, &log), 0);
        free(log);
    }
    snprintf(args, sizeof args, "merge '%s' '%s' '%s' -q", ct_path(dir, "merged.exr"), ct_path(dir, "part0.exr"),
             ct_path(dir, "part1.exr"));
    if (ct_vbl_run(args, &log, 1) != 0) fail_msg("vbl %s:\n%s", args, log ? log : "");
    free(log);
    img = NULL;
    assert_int_equal(vbl_exr_read(ct_path(dir, "merged.exr"), &img), VBL_SUCCESS);
    assert_transparent_sum(img);
    assert_string_equal(attr(img, "vbl:transparent"), "1");
    assert_non_null(vbl_exr_image_attribute(img, "worldToNDC", &type));
    assert_int_equal(type, VBL_EXR_ATTRIBUTE_M44F);
    vbl_exr_image_release(img);

    /* the format is the option's, not the name's: -o x.png / --preview x.jpg are refused (exit 2)
     * before anything is rendered or written */
    static const char* const bad[3] = {"-o '%s/out.png'", "-o '%s/out'", "-o '%s/ok.exr' --preview '%s/p.jpg'"};
    for (int k = 0; k < 3; ++k) {
        char o[2048];
        snprintf(o, sizeof o, bad[k], dir, dir);
        snprintf(args, sizeof args, "'%s' %s -q --passes 1", scene, o);
        assert_int_equal(ct_render(args, &log), 2);
        if (!log || !strstr(log, k == 2 ? "PNG" : "OpenEXR")) fail_msg("%s:\n%s", args, log ? log : "");
        free(log);
    }
    assert_int_equal(access(ct_path(dir, "out.png"), F_OK), -1);
    assert_int_equal(access(ct_path(dir, "ok.exr"), F_OK), -1);
    /* --opt=value for flags without a value is refused */
    snprintf(args, sizeof args, "'%s' -o '%s' -q --resume=yes", scene, ct_path(dir, "r.exr"));
    assert_int_equal(ct_render(args, &log), 2);
    free(log);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layers_metadata_aovs_preview),
        cmocka_unit_test(test_storage_options),
        cmocka_unit_test(test_transparent_camera_extension),
#ifdef VBL_TEST_HAVE_COLOR
        cmocka_unit_test(test_output_space),
        cmocka_unit_test(test_scene_color_space),
#endif
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
