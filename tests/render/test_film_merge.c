#define _POSIX_C_SOURCE 200809L
/* vbl_film_merge (vbl/vbl_film.h): films of disjoint pass ranges (options.first_pass) merge into
 * the film of one render of all their passes. Exact to float rounding, not bit-identical: each
 * part's layer is a float mean of its passes and the merge re-weights those floats in double, so
 * transport layers, beauty and A agree within a few float ulps (checked: |a - b| <= 4e-7 (|a| +
 * |b|)); samples agree exactly; the beauty R,G,B is exactly the float sum of the merged transport
 * layers. The parts are uneven (1 + 3 passes) so that an unweighted mean fails. Also the
 * transport-class names, films built from pixels, and the refusals (overlap, other seed, size). */
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

#include "render_test_util.h"
#include "temp_scene.h"
#include "vbl/vbl.h"

static char scene_path[1024];

static int setup(void** state)
{
    (void)state;
    return rt_merge_scene_write("vbl_film_merge", scene_path, sizeof scene_path);
}

static int teardown(void** state)
{
    (void)state;
    vbl_test_temp_scene_remove(scene_path);
    return 0;
}

static vbl_film* render_range(const vbl_scene* scene, vbl_render_method method, int first, int passes)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.method = method;
    o.first_pass = first;
    o.passes = passes;
    o.threads = 2;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    return film;
}

static void expect_merge_equals_single(vbl_render_method method)
{
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    vbl_film* all = render_range(scene, method, 0, 4);
    vbl_film* parts[2] = {render_range(scene, method, 1, 3), render_range(scene, method, 0, 1)}; /* any order */
    vbl_film* merged = NULL;
    assert_int_equal(vbl_film_merge((const vbl_film* const*)parts, 2, &merged), VBL_SUCCESS);

    vbl_film_stats s, t;
    memset(&s, 0, sizeof s);
    memset(&t, 0, sizeof t);
    s.size = t.size = sizeof s;
    assert_int_equal(vbl_film_get_stats(merged, &s), VBL_SUCCESS);
    assert_int_equal(vbl_film_get_stats(all, &t), VBL_SUCCESS);
    assert_int_equal(s.passes, 4);
    assert_int_equal(s.first_pass, 0);
    assert_int_equal(s.method, t.method);
    assert_int_equal(vbl_film_layer_count(merged), vbl_film_layer_count(all));
    const size_t n = (size_t)vbl_film_width(all) * (size_t)vbl_film_height(all);
    int transport_layers = 0;
    double worst = 0.0;
    for (int i = 0; i < vbl_film_layer_count(all); ++i) {
        const char* name = vbl_film_layer_name(all, i);
        int ca = 0, cb = 0;
        const float* a = vbl_film_layer(merged, name, &ca);
        const float* b = vbl_film_layer(all, name, &cb);
        assert_non_null(a);
        assert_int_equal(ca, cb);
        if (!strcmp(name, "variance") || !strcmp(name, "Z")) continue; /* estimates of their own (merge rules) */
        vbl_transport_class c;
        if (vbl_transport_class_parse(name, &c) == VBL_SUCCESS) ++transport_layers;
        vbl_clear_error();
        for (size_t v = 0; v < n * (size_t)ca; ++v) {
            if (!strcmp(name, "samples")) {
                assert_true(a[v] == b[v]);
                continue;
            }
            double d = fabs((double)a[v] - (double)b[v]), tol = 4e-7 * (fabs(a[v]) + fabs(b[v]));
            if (d > tol) fail_msg("%s layer '%s' value %zu: merged %.9g, single render %.9g", vbl_render_method_name(method), name, v, a[v], b[v]);
            if (b[v] != 0.0f) worst = fmax(worst, d / fabs(b[v]));
        }
    }
    assert_true(transport_layers >= 2);
    /* the layers still sum to the beauty exactly (float, class order) */
    const float* beauty = vbl_film_layer(merged, "", NULL);
    for (size_t p = 0; p < n; ++p)
        for (int k = 0; k < 3; ++k) {
            float sum = 0.0f;
            for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
                const float* layer = vbl_film_layer_rgb(merged, vbl_transport_class_name((vbl_transport_class)c));
                if (layer) sum += layer[3 * p + (size_t)k];
            }
            assert_true(sum == beauty[4 * p + (size_t)k]);
        }
    print_message("%s: merged 1 + 3 passes vs one render of 4: largest relative difference %.3g\n",
                  vbl_render_method_name(method), worst);
    vbl_film_release(merged);
    vbl_film_release(parts[0]);
    vbl_film_release(parts[1]);
    vbl_film_release(all);
    vbl_scene_release(scene);
}

static void test_merge_equals_single_render_pt(void** state)
{
    (void)state;
    expect_merge_equals_single(VBL_RENDER_PT);
}

static void test_merge_equals_single_render_vrl(void** state)
{
    (void)state;
    expect_merge_equals_single(VBL_RENDER_VRL);
}

/* vbl_render_resume: a 1-pass checkpoint continued to 4 passes = one 4-pass render. */
static void test_resume_equals_single_render(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    vbl_film* all = render_range(scene, VBL_RENDER_PT, 0, 4);
    vbl_film* checkpoint = render_range(scene, VBL_RENDER_PT, 0, 1);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.threads = 2;
    vbl_film* resumed = NULL;
    assert_int_equal(vbl_render_resume(scene, &o, checkpoint, &resumed), VBL_SUCCESS);
    vbl_film_stats s;
    memset(&s, 0, sizeof s);
    s.size = sizeof s;
    assert_int_equal(vbl_film_get_stats(resumed, &s), VBL_SUCCESS);
    assert_int_equal(s.passes, 4);
    const size_t n = 12 * 9 * 4;
    const float* a = vbl_film_layer(resumed, "", NULL);
    const float* b = vbl_film_layer(all, "", NULL);
    for (size_t v = 0; v < n; ++v) assert_true(fabs((double)a[v] - b[v]) <= 4e-7 * (fabs(a[v]) + fabs(b[v])));
    o.seed = 6; /* another render */
    vbl_film* bad = NULL;
    assert_int_equal(vbl_render_resume(scene, &o, checkpoint, &bad), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "seed"));
    assert_null(bad);
    vbl_clear_error();
    vbl_film_release(resumed);
    vbl_film_release(checkpoint);
    vbl_film_release(all);
    vbl_scene_release(scene);
}

static void test_merge_refusals(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    vbl_film* a = render_range(scene, VBL_RENDER_PT, 0, 2);
    vbl_film* b = render_range(scene, VBL_RENDER_PT, 1, 2);
    const vbl_film* overlap[2] = {a, b};
    vbl_film* out = NULL;
    assert_int_equal(vbl_film_merge(overlap, 2, &out), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "overlaps"));
    assert_null(out);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.first_pass = 2;
    o.passes = 1;
    o.seed = 99;
    vbl_film* other_seed = NULL;
    assert_int_equal(vbl_render(scene, &o, &other_seed), VBL_SUCCESS);
    const vbl_film* mixed[2] = {a, other_seed};
    assert_int_equal(vbl_film_merge(mixed, 2, &out), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "seed"));
    assert_int_equal(vbl_film_merge(NULL, 0, &out), VBL_ERROR_INVALID_ARGUMENT);
    /* one film merges into a copy of itself */
    const vbl_film* one[1] = {a};
    assert_int_equal(vbl_film_merge(one, 1, &out), VBL_SUCCESS);
    const float* x = vbl_film_layer(out, "volume_direct", NULL);
    const float* y = vbl_film_layer(a, "volume_direct", NULL);
    assert_memory_equal(x, y, sizeof(float) * 12 * 9 * 3);
    vbl_film_release(out);
    vbl_film_release(other_seed);
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_scene_release(scene);
    vbl_clear_error();
}

/* Films from pixels (an EXR read back): the merge rules on known numbers. */
static void test_film_from_pixels_rules(void** state)
{
    (void)state;
    vbl_film_stats s;
    memset(&s, 0, sizeof s);
    s.size = sizeof s;
    s.passes = 1;
    s.first_pass = 0;
    vbl_film* f1 = NULL;
    assert_int_equal(vbl_film_create(1, 1, &s, &f1), VBL_SUCCESS);
    const float beauty1[4] = {9, 9, 9, 0.5f}, vd1[3] = {1, 2, 3}, samples1[1] = {4}, var1[3] = {1, 1, 1},
                z1[1] = {2};
    assert_int_equal(vbl_film_add_layer(f1, "", 4, NULL, beauty1), VBL_SUCCESS);
    assert_int_equal(vbl_film_add_layer(f1, "volume_direct", 3, NULL, vd1), VBL_SUCCESS);
    assert_int_equal(vbl_film_add_layer(f1, "Z", 1, NULL, z1), VBL_SUCCESS);
    assert_int_equal(vbl_film_add_layer(f1, "samples", 1, NULL, samples1), VBL_SUCCESS);
    assert_int_equal(vbl_film_add_layer(f1, "variance", 3, NULL, var1), VBL_SUCCESS);
    assert_int_equal(vbl_film_add_layer(f1, "samples", 1, NULL, samples1), VBL_ERROR_INVALID_ARGUMENT);
    assert_string_equal(vbl_film_layer_channel_name(f1, "Z", 0), "Z");
    assert_string_equal(vbl_film_layer_channel_name(f1, "samples", 0), "Y");
    s.passes = 3;
    s.first_pass = 1;
    vbl_film* f2 = NULL;
    assert_int_equal(vbl_film_create(1, 1, &s, &f2), VBL_SUCCESS);
    const float beauty2[4] = {0, 0, 0, 1.0f}, vd2[3] = {5, 6, 7}, samples2[1] = {12}, var2[3] = {2, 2, 2},
                z2[1] = {0}; /* Z = 0: no collision, carries no depth */
    assert_int_equal(vbl_film_add_layer(f2, "", 4, NULL, beauty2), VBL_SUCCESS);
    assert_int_equal(vbl_film_add_layer(f2, "volume_direct", 3, NULL, vd2), VBL_SUCCESS);
    assert_int_equal(vbl_film_add_layer(f2, "Z", 1, NULL, z2), VBL_SUCCESS);
    assert_int_equal(vbl_film_add_layer(f2, "samples", 1, NULL, samples2), VBL_SUCCESS);
    assert_int_equal(vbl_film_add_layer(f2, "variance", 3, NULL, var2), VBL_SUCCESS);
    const vbl_film* films[2] = {f1, f2};
    vbl_film* m = NULL;
    assert_int_equal(vbl_film_merge(films, 2, &m), VBL_SUCCESS);
    const float* vd = vbl_film_layer(m, "volume_direct", NULL);
    assert_true(vd[0] == (1.0f + 3 * 5.0f) / 4 && vd[1] == (2.0f + 3 * 6.0f) / 4 && vd[2] == (3.0f + 3 * 7.0f) / 4);
    const float* b = vbl_film_layer(m, "", NULL);
    assert_true(b[0] == vd[0] && b[1] == vd[1] && b[2] == vd[2]); /* re-summed, not 9 * 1/4 */
    assert_true(b[3] == (0.5f + 3 * 1.0f) / 4);
    assert_true(vbl_film_layer(m, "samples", NULL)[0] == 16.0f);
    assert_true(fabsf(vbl_film_layer(m, "variance", NULL)[0] - (1.0f * 1 + 9.0f * 2) / 16) < 1e-7f);
    assert_true(vbl_film_layer(m, "Z", NULL)[0] == 2.0f);
    vbl_film_stats ms;
    memset(&ms, 0, sizeof ms);
    ms.size = sizeof ms;
    assert_int_equal(vbl_film_get_stats(m, &ms), VBL_SUCCESS);
    assert_int_equal(ms.passes, 4);
    vbl_film_retain(m); /* shared films take no layers */
    assert_int_equal(vbl_film_add_layer(m, "extra", 1, NULL, samples1), VBL_ERROR_INVALID_ARGUMENT);
    vbl_film_release(m);
    vbl_film_release(m);
    vbl_film_release(f1);
    vbl_film_release(f2);
    vbl_clear_error();
}

static void test_transport_class_names(void** state)
{
    (void)state;
    static const char* const expected[VBL_CLASS_COUNT] = {"background",        "surface_direct",
                                                          "volume_direct",     "surface_from_surface",
                                                          "surface_from_volume", "volume_from_surface",
                                                          "volume_from_volume",  "volume_emission"};
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        assert_string_equal(vbl_transport_class_name((vbl_transport_class)c), expected[c]);
        vbl_transport_class back;
        assert_int_equal(vbl_transport_class_parse(expected[c], &back), VBL_SUCCESS);
        assert_int_equal(back, c);
    }
    assert_null(vbl_transport_class_name(VBL_CLASS_COUNT));
    vbl_transport_class back;
    assert_int_equal(vbl_transport_class_parse("beauty", &back), VBL_ERROR_INVALID_ARGUMENT);
    vbl_clear_error();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_merge_equals_single_render_pt),
        cmocka_unit_test(test_merge_equals_single_render_vrl),
        cmocka_unit_test(test_resume_equals_single_render),
        cmocka_unit_test(test_merge_refusals),
        cmocka_unit_test(test_film_from_pixels_rules),
        cmocka_unit_test(test_transport_class_names),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
