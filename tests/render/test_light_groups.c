/* Light groups (issue #17 part 2): lights tagged with a "group" in the scene; options.light_groups
 * adds one beauty layer per group. Checked: off (the default), nothing changes, bit for bit, against
 * the same scene without tags; on, each group's layer is bit for bit the beauty of the scene holding
 * only that group's lights rendered with the group's seed, for pt and for vrl (whose virtual lights
 * must then come from that group's lights only); the groups add up to the beauty to float rounding;
 * the layers merge. 12x9 pixels, 2 passes x 1 spp, 60 light paths. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_test_util.h"
#include "vbl/vbl.h"

#define W 12
#define H 9
#define SEED 11ull
#define STEP 0x9E3779B97F4A7C15ull

static const char* const key_light =
    "{\"type\": \"distant\", \"direction\": [-0.3, 0.5, -0.8], \"irradiance\": [2.0, 1.8, 1.5]%s}";
static const char* const sky_light = "{\"type\": \"environment\", \"radiance\": [0.10, 0.12, 0.20]%s}";
static const char* const fill_light = "{\"type\": \"point\", \"position\": [2.5, -1, 2], \"intensity\": [1, 1, 1.2]%s}";

/* lights: a mask of key (1), sky (2), fill (4, untagged); tags: 1 to write the groups. */
static vbl_scene* load(int lights, int tags)
{
    char list[2048] = "", one[512];
    const char* const fmt[3] = {key_light, sky_light, fill_light};
    const char* const tag[3] = {", \"group\": \"key\"", ", \"group\": \"sky\"", ""};
    for (int i = 0; i < 3; ++i) {
        if (!(lights & (1 << i))) continue;
        snprintf(one, sizeof one, fmt[i], tags ? tag[i] : "");
        if (list[0]) strcat(list, ", ");
        strcat(list, one);
    }
    char text[4096], path[512];
    snprintf(text, sizeof text,
             "{\"camera\": {\"position\": [0.75, -3.0, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 45,"
             " \"resolution\": [%d, %d]}, \"lights\": [%s],"
             " \"media\": [{\"vdb\": \"%s/box.vdb\", \"density_scale\": 3.0, \"albedo\": [0.9, 0.8, 0.7]}],"
             " \"render\": {\"passes\": 2, \"spp\": 1, \"light_paths\": 60}}",
             W, H, list, getenv("VBL_FIXTURE_DIR"));
    rt_write_file(rt_temp_dir, "scene.json", text, path);
    vbl_scene* scene = NULL;
    if (vbl_scene_load(path, &scene)) fail_msg("%s", vbl_last_error_message());
    return scene;
}

static vbl_film* render(const vbl_scene* scene, vbl_render_method method, int groups, uint64_t seed, int first,
                        int passes)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.method = method;
    o.light_groups = groups;
    o.seed = seed;
    o.first_pass = first;
    o.passes = passes;
    o.threads = 2;
    vbl_film* film = NULL;
    if (vbl_render(scene, &o, &film)) fail_msg("%s", vbl_last_error_message());
    return film;
}

static void assert_same_layers(const vbl_film* a, const vbl_film* b)
{
    assert_int_equal(vbl_film_layer_count(a), vbl_film_layer_count(b));
    for (int i = 0; i < vbl_film_layer_count(a); ++i) {
        const char* name = vbl_film_layer_name(a, i);
        int ca = 0, cb = 0;
        const float* pa = vbl_film_layer(a, name, &ca);
        const float* pb = vbl_film_layer(b, name, &cb);
        assert_non_null(pb);
        assert_int_equal(ca, cb);
        assert_memory_equal(pa, pb, sizeof(float) * (size_t)ca * W * H);
    }
}

static void test_off_by_default(void** state)
{
    (void)state;
    vbl_scene* tagged = load(7, 1);
    vbl_scene* plain = load(7, 0);
    vbl_film* a = render(tagged, VBL_RENDER_PT, 0, SEED, 0, 2);
    vbl_film* b = render(plain, VBL_RENDER_PT, 0, SEED, 0, 2);
    vbl_film* c = render(plain, VBL_RENDER_PT, 1, SEED, 0, 2); /* asked, but no group in the scene */
    assert_same_layers(a, b);
    assert_same_layers(c, b);
    assert_null(vbl_film_layer(a, "lightgroup_key", NULL));
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_film_release(c);
    vbl_scene_release(tagged);
    vbl_scene_release(plain);
}

static void check_groups(vbl_render_method method)
{
    vbl_scene* tagged = load(7, 1);
    vbl_film* film = render(tagged, method, 1, SEED, 0, 2);
    /* groups in order of first use: default (untagged fill), key, sky */
    static const char* const names[3] = {"lightgroup_default", "lightgroup_key", "lightgroup_sky"};
    static const int masks[3] = {4, 1, 2};
    const float* group[3];
    for (int g = 0; g < 3; ++g) {
        group[g] = vbl_film_layer_rgb(film, names[g]);
        if (!group[g]) fail_msg("no layer %s", names[g]);
        /* the group alone, with its seed: the same estimates bit for bit */
        vbl_scene* alone = load(masks[g], 0);
        vbl_film* ref = render(alone, method, 0, SEED + (uint64_t)g * STEP, 0, 2);
        const float* rb = vbl_film_layer(ref, "", NULL);
        for (int i = 0; i < W * H; ++i)
            for (int k = 0; k < 3; ++k)
                if (group[g][3 * i + k] != rb[4 * i + k])
                    fail_msg("%s pixel %d ch %d: %.9g, the group alone %.9g", names[g], i, k, group[g][3 * i + k],
                             rb[4 * i + k]);
        vbl_film_release(ref);
        vbl_scene_release(alone);
    }
    /* the groups add up to the beauty to float rounding; the classes still sum to it exactly */
    const float* beauty = vbl_film_layer(film, "", NULL);
    int lit = 0;
    for (int i = 0; i < W * H; ++i)
        for (int k = 0; k < 3; ++k) {
            float sum = group[0][3 * i + k] + group[1][3 * i + k] + group[2][3 * i + k];
            float b = beauty[4 * i + k];
            assert_true(fabsf(sum - b) <= 1e-6f * fabsf(b) + 1e-30f);
            float classes = 0.0f;
            for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
                const float* l = vbl_film_layer_rgb(film, vbl_transport_class_name((vbl_transport_class)c));
                if (l) classes += l[3 * i + k];
            }
            assert_true(classes == b);
            lit += group[0][3 * i + k] > 0.0f && group[1][3 * i + k] > 0.0f && group[2][3 * i + k] > 0.0f;
        }
    assert_true(lit > W * H / 4); /* every group lights the box */
    vbl_film_release(film);
    vbl_scene_release(tagged);
}

static void test_groups_pt(void** state)
{
    (void)state;
    check_groups(VBL_RENDER_PT);
}

static void test_groups_vrl(void** state)
{
    (void)state;
    check_groups(VBL_RENDER_VRL);
}

static void test_groups_merge(void** state)
{
    (void)state;
    vbl_scene* tagged = load(7, 1);
    vbl_film* a = render(tagged, VBL_RENDER_PT, 1, SEED, 0, 1);
    vbl_film* b = render(tagged, VBL_RENDER_PT, 1, SEED, 1, 1);
    vbl_film* whole = render(tagged, VBL_RENDER_PT, 1, SEED, 0, 2);
    const vbl_film* parts[2] = {a, b};
    vbl_film* merged = NULL;
    assert_int_equal(vbl_film_merge(parts, 2, &merged), VBL_SUCCESS);
    const float* m = vbl_film_layer_rgb(merged, "lightgroup_sky");
    const float* w = vbl_film_layer_rgb(whole, "lightgroup_sky");
    assert_non_null(m);
    for (int i = 0; i < 3 * W * H; ++i) assert_true(fabsf(m[i] - w[i]) <= 4e-7f * (fabsf(m[i]) + fabsf(w[i])) + 1e-30f);
    vbl_film_release(merged);
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_film_release(whole);
    /* every light tagged, no emissive media: the empty default group is neither rendered nor written */
    vbl_scene* all_tagged = load(3, 1);
    vbl_film* two = render(all_tagged, VBL_RENDER_PT, 1, SEED, 0, 1);
    assert_null(vbl_film_layer(two, "lightgroup_default", NULL));
    assert_non_null(vbl_film_layer_rgb(two, "lightgroup_key"));
    vbl_film_release(two);
    vbl_scene_release(all_tagged);
    /* a time limit would end the groups at different pass counts: refused */
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.light_groups = 1;
    o.time_limit = 5.0;
    vbl_film* none = NULL;
    assert_int_equal(vbl_render(tagged, &o, &none), VBL_ERROR_UNSUPPORTED);
    assert_null(none);
    vbl_scene_release(tagged);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_off_by_default),
        cmocka_unit_test(test_groups_pt),
        cmocka_unit_test(test_groups_vrl),
        cmocka_unit_test(test_groups_merge),
    };
    return cmocka_run_group_tests(tests, rt_temp_dir_setup, rt_temp_dir_teardown);
}
