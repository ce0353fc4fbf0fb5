#define _POSIX_C_SOURCE 200809L
/* Compositing-correct films (issue #17 part 1): the background layer (environment and visible
 * lights seen directly) and options.transparent, Z of misses, the totals volume_indirect /
 * surface_indirect, merging all of that, and the camera matrices of the EXR's worldToCamera /
 * worldToNDC against a hand-computed projection. A 12x9 box of smoke under a distant light and an
 * environment, pt, 2 passes x 2 spp (well under a second). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "temp_scene.h"
#include "vbl/vbl.h"

#define W 12
#define H 9
static const double env[3] = {0.10, 0.12, 0.20};
static char scene_path[1024];

static int setup(void** state)
{
    (void)state;
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    if (!fixtures) return -1;
    /* fov 50 so that the corners of the frame miss the box */
    return vbl_test_temp_scene_write("vbl_film_compositing", scene_path, sizeof scene_path,
            "{\"camera\": {\"position\": [0.75, -3.0, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 50,"
            " \"resolution\": [%d, %d]},\n"
            " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.3, 0.5, -0.8], \"irradiance\": [2.0, 1.8, 1.5]},"
            " {\"type\": \"environment\", \"radiance\": [%g, %g, %g]}],\n"
            " \"media\": [{\"vdb\": \"%s/box.vdb\", \"density_scale\": 3.0, \"albedo\": [0.9, 0.8, 0.7]}],\n"
            " \"render\": {\"passes\": 2, \"spp\": 2, \"seed\": 9}}\n",
            W, H, env[0], env[1], env[2], fixtures);
}

static int teardown(void** state)
{
    (void)state;
    vbl_test_temp_scene_remove(scene_path);
    return 0;
}

static vbl_film* render(const vbl_scene* scene, int transparent, int first, int passes)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.transparent = transparent;
    o.first_pass = first;
    o.passes = passes;
    o.threads = 2;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    return film;
}

static const float* layer(const vbl_film* film, const char* name, int want_channels)
{
    int channels = 0;
    const float* px = vbl_film_layer(film, name, &channels);
    if (!px) fail_msg("no layer '%s'", name);
    assert_int_equal(channels, want_channels);
    return px;
}

/* Beauty R,G,B == float sum of the class layers in class order (without the background when
 * transparent); totals == float sums of their classes. Bit for bit. */
static void check_sums(const vbl_film* film, int transparent)
{
    const float* beauty = layer(film, "", 4);
    const float* cls[VBL_CLASS_COUNT];
    for (int c = 0; c < VBL_CLASS_COUNT; ++c)
        cls[c] = vbl_film_layer_rgb(film, vbl_transport_class_name((vbl_transport_class)c));
    assert_non_null(cls[VBL_CLASS_BACKGROUND]);
    assert_non_null(cls[VBL_CLASS_VOLUME_FROM_VOLUME]);
    const float* vi = layer(film, VBL_FILM_TOTAL_VOLUME_INDIRECT, 3);
    assert_null(vbl_film_layer(film, VBL_FILM_TOTAL_SURFACE_INDIRECT, NULL)); /* no surfaces */
    for (int i = 0; i < W * H; ++i)
        for (int k = 0; k < 3; ++k) {
            float sum = 0.0f, indirect = 0.0f;
            for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
                if (!cls[c] || (transparent && c == VBL_CLASS_BACKGROUND)) continue;
                sum += cls[c][3 * i + k];
            }
            if (cls[VBL_CLASS_VOLUME_FROM_SURFACE]) indirect += cls[VBL_CLASS_VOLUME_FROM_SURFACE][3 * i + k];
            indirect += cls[VBL_CLASS_VOLUME_FROM_VOLUME][3 * i + k];
            if (beauty[4 * i + k] != sum) fail_msg("pixel %d ch %d: beauty %.9g, classes %.9g", i, k, beauty[4 * i + k], sum);
            if (vi[3 * i + k] != indirect) fail_msg("pixel %d ch %d: volume_indirect %.9g, sum %.9g", i, k, vi[3 * i + k], indirect);
        }
}

static void test_background_transparent_z(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    vbl_film* opaque = render(scene, 0, 0, 2);
    vbl_film* clear = render(scene, 1, 0, 2);
    assert_null(vbl_film_layer(opaque, "emission", NULL)); /* the old name is gone */
    check_sums(opaque, 0);
    check_sums(clear, 1);
    vbl_film_stats stats = {.size = sizeof stats};
    assert_int_equal(vbl_film_get_stats(clear, &stats), VBL_SUCCESS);
    assert_int_equal(stats.transparent, 1);
    /* the option changes only what the beauty sums (and A): the classes are the same estimates */
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        const char* name = vbl_transport_class_name((vbl_transport_class)c);
        const float* a = vbl_film_layer_rgb(opaque, name);
        const float* b = vbl_film_layer_rgb(clear, name);
        assert_true((a == NULL) == (b == NULL));
        if (a) assert_memory_equal(a, b, sizeof(float) * 3 * W * H);
    }
    const float* ob = layer(opaque, "", 4);
    const float* cb = layer(clear, "", 4);
    const float* bg = layer(clear, "background", 3);
    const float* z = layer(clear, "Z", 1);
    const float* oz = layer(opaque, "Z", 1);
    int misses = 0, hits = 0;
    for (int i = 0; i < W * H; ++i) {
        /* opaque: the sky is in the beauty, so A = 1 everywhere */
        assert_true(ob[4 * i + 3] == 1.0f);
        float a = cb[4 * i + 3];
        assert_true(a >= 0.0f && a <= 1.0f);
        assert_true(z[i] == oz[i]);
        if (z[i] != VBL_FILM_Z_MISS) {
            ++hits;
            assert_true(z[i] > 0.0f && z[i] < 10.0f);
        } else if (a == 0.0f) {
            ++misses;
        }
        /* the background is what the opaque beauty has on top of the transparent one */
        for (int k = 0; k < 3; ++k)
            assert_float_equal(cb[4 * i + k] + bg[3 * i + k], ob[4 * i + k], 1e-6 * (1.0 + ob[4 * i + k]));
    }
    /* the top-left corner sees the sky and nothing else: background = the sky, a clean element
     * (nothing where A = 0), and premultiplied `over` the sky gives the opaque render back */
    assert_true(cb[3] == 0.0f && z[0] == VBL_FILM_Z_MISS);
    for (int k = 0; k < 3; ++k) {
        assert_float_equal(bg[k], env[k], 1e-6 * env[k]);
        assert_true(cb[k] == 0.0f);
        assert_float_equal(cb[k] + (1.0f - cb[3]) * (float)env[k], ob[k], 1e-6);
    }
    assert_true(misses >= 4); /* the corners */
    assert_true(hits > W * H / 8); /* the box */
    vbl_film_release(opaque);
    vbl_film_release(clear);
    vbl_scene_release(scene);
}

/* Merging 1 + 1 passes of transparent films keeps the rules: background out of the beauty,
 * totals re-summed, Z of misses; an opaque film does not merge with a transparent one. */
static void test_merge_transparent(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    vbl_film* a = render(scene, 1, 0, 1);
    vbl_film* b = render(scene, 1, 1, 1);
    vbl_film* whole = render(scene, 1, 0, 2);
    vbl_film* opaque = render(scene, 0, 1, 1);
    const vbl_film* parts[2] = {a, b};
    vbl_film* merged = NULL;
    assert_int_equal(vbl_film_merge(parts, 2, &merged), VBL_SUCCESS);
    check_sums(merged, 1);
    const float* z = layer(merged, "Z", 1);
    const float* zw = layer(whole, "Z", 1);
    for (int i = 0; i < W * H; ++i)
        if (zw[i] == VBL_FILM_Z_MISS) assert_true(z[i] == VBL_FILM_Z_MISS);
    const float* mb = layer(merged, "", 4);
    const float* wb = layer(whole, "", 4);
    for (int i = 0; i < 4 * W * H; ++i)
        assert_true(fabsf(mb[i] - wb[i]) <= 4e-7f * (fabsf(mb[i]) + fabsf(wb[i])) + 1e-30f);
    const vbl_film* mixed[2] = {a, opaque};
    vbl_film* none = NULL;
    assert_int_equal(vbl_film_merge(mixed, 2, &none), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "transparent"));
    assert_null(none);
    vbl_film_release(merged);
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_film_release(whole);
    vbl_film_release(opaque);
    vbl_scene_release(scene);
}

/* p M (row vector) with the divide by w. */
static void project(const double m[16], const double p[3], double out[3], double* w)
{
    double v[4];
    for (int j = 0; j < 4; ++j) v[j] = p[0] * m[j] + p[1] * m[4 + j] + p[2] * m[8 + j] + m[12 + j];
    *w = v[3];
    for (int j = 0; j < 3; ++j) out[j] = v[j] / v[3];
}

/* worldToCamera / worldToNDC against the camera by hand: position (0.75, -3, 0.75) looking along
 * +y, up +z, so right = f x up = +x; vertical fov 50, aspect 12/9. */
static void test_camera_matrices(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    double w2c[16], w2n[16];
    assert_int_equal(vbl_scene_camera_matrices(scene, w2c, w2n), VBL_SUCCESS);
    assert_int_equal(vbl_scene_camera_matrices(NULL, w2c, w2n), VBL_ERROR_INVALID_ARGUMENT);
    const double t = tan(25.0 * 3.14159265358979323846 / 180.0), aspect = 12.0 / 9.0;
    /* a point 2 right, 1 up and 5 ahead of the camera: camera space (2, 1, 5) */
    const double p[3] = {0.75 + 2.0, -3.0 + 5.0, 0.75 + 1.0};
    double v[4];
    for (int j = 0; j < 4; ++j) v[j] = p[0] * w2c[j] + p[1] * w2c[4 + j] + p[2] * w2c[8 + j] + w2c[12 + j];
    assert_float_equal(v[0], 2.0, 1e-12);
    assert_float_equal(v[1], 1.0, 1e-12);
    assert_float_equal(v[2], 5.0, 1e-12);
    assert_float_equal(v[3], 1.0, 0.0);
    double ndc[3], w = 0.0;
    project(w2n, p, ndc, &w);
    assert_float_equal(w, 5.0, 1e-12);
    assert_float_equal(ndc[0], 0.5 + 0.5 * (2.0 / 5.0) / (t * aspect), 1e-12);
    assert_float_equal(ndc[1], 0.5 - 0.5 * (1.0 / 5.0) / t, 1e-12);
    /* the look-at point is the image centre; the top-left corner ray lands on (0, 0) */
    const double centre[3] = {0.75, 0.75, 0.75};
    project(w2n, centre, ndc, &w);
    assert_float_equal(ndc[0], 0.5, 1e-12);
    assert_float_equal(ndc[1], 0.5, 1e-12);
    const double corner[3] = {0.75 - 3.0 * t * aspect, 0.0, 0.75 + 3.0 * t};
    project(w2n, corner, ndc, &w);
    assert_float_equal(ndc[0], 0.0, 1e-12);
    assert_float_equal(ndc[1], 0.0, 1e-12);
    vbl_scene_release(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_background_transparent_z),
        cmocka_unit_test(test_merge_transparent),
        cmocka_unit_test(test_camera_matrices),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
