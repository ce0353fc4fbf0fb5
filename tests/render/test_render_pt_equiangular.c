/* pt's equiangular NEE (transport/path_tracing/pt_equiangular.h): pt with and without it agree on every layer
 * (image means of K independent renders each, within Z_CRIT standard errors of the difference) in
 * a heterogeneous medium among Lambert surfaces lit by a point light inside the medium, a spot
 * light and a distant light; the mid-bound control optical depth is exact in homogeneous media and
 * lies between the minorant and majorant depths elsewhere; scenes without point/spot lights render
 * bit-identically with the option on and off; the scene file's render.pt block. Also pt with
 * transmittance_majorant_scale 4 against the same means. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render_test_util.h"
#include "scene/scene.h"
#include "surface_render_util.h"
#include "transport/path_tracing/pt.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume/control_depth.h"
#include "volume_test_grid.h"

#define W 12
#define H 10
#define K 16
#define Z_CRIT 4.5

typedef struct eq_case {
    vbl_scene* scene;
    vbl_volume* volume;
} eq_case;

/* lights: 1 point (+ spot + distant), 0 distant only */
static eq_case make_case(int local_lights)
{
    eq_case c;
    vbl_camera cam = rt_camera(vbl_v3(0.3, -4.0, 0.6), vbl_v3(0, 0, -0.3), 45.0, W, H);
    c.scene = tt_scene(&cam);
    c.volume = tt_make_sphere(16, 0.9);
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volume, 2.0, vbl_v3(0.9, 0.8, 0.7), 0.3, NULL), VBL_SUCCESS);
    if (local_lights) {
        tt_add_point(c.scene, vbl_v3(0.3, -0.2, 1.15), 3.0); /* just outside the medium: finite variance with and without */
        tt_add_spot(c.scene, vbl_v3(-0.6, -0.8, 1.5), vbl_v3(0.3, 0.4, -1.0), 6.0, 20.0, 35.0);
    }
    tt_add_distant(c.scene, vbl_v3(0.3, 0.5, -1.0), 1.0);
    vbl_material lam = {VBL_MATERIAL_LAMBERT, {0.7, 0.6, 0.5}, {0, 0, 0}, 0.0, 0.0};
    vbl_material wall = {VBL_MATERIAL_LAMBERT, {0.6, 0.7, 0.6}, {0, 0, 0}, 0.0, 0.0};
    add_quad(c.scene, vbl_v3(0, 0, -1), vbl_v3(2.5, 0, 0), vbl_v3(0, 2.5, 0), &lam);
    add_quad(c.scene, vbl_v3(0, 1.2, 0.5), vbl_v3(2.5, 0, 0), vbl_v3(0, 0, 1.5), &wall);
    return c;
}

/* The smoky Lambert box of test_surface_blue_noise (open front, a smoke ball of radius 0.7 and
 * peak sigma_t 3 about the centre, a point light above it inside the ball's grid bounds): the
 * configuration where equiangular NEE once biased volume_from_surface (+6%). */
static eq_case make_box_case(void)
{
    eq_case c;
    vbl_camera cam = rt_camera(vbl_v3(0.0, -3.2, 0.0), vbl_v3(0, 0, 0), 40.0, W, H);
    c.scene = tt_scene(&cam);
    tt_add_point(c.scene, vbl_v3(0.2, 0.1, 0.8), 3.0);
    vbl_material grey = {VBL_MATERIAL_LAMBERT, {0.6, 0.6, 0.6}, {0, 0, 0}, 0.0, 0.0};
    vbl_material red = {VBL_MATERIAL_LAMBERT, {0.7, 0.2, 0.2}, {0, 0, 0}, 0.0, 0.0};
    vbl_material green = {VBL_MATERIAL_LAMBERT, {0.2, 0.6, 0.3}, {0, 0, 0}, 0.0, 0.0};
    add_quad(c.scene, vbl_v3(0, 0, -1), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), &grey);  /* floor */
    add_quad(c.scene, vbl_v3(0, 0, 1), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), &grey);   /* ceiling */
    add_quad(c.scene, vbl_v3(0, 1, 0), vbl_v3(1, 0, 0), vbl_v3(0, 0, 1), &green);  /* back */
    add_quad(c.scene, vbl_v3(-1, 0, 0), vbl_v3(0, 1, 0), vbl_v3(0, 0, 1), &red);   /* left */
    add_quad(c.scene, vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), vbl_v3(0, 0, 1), &grey);   /* right */
    c.volume = tt_make_sphere(12, 0.7);
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volume, 3.0, vbl_v3(0.8, 0.8, 0.8), 0.3, NULL), VBL_SUCCESS);
    return c;
}

static double g_majorant_scale = 1.0; /* options.transmittance_majorant_scale of render_pt */

static vbl_film* render_pt(const vbl_scene* scene, int equiangular, int passes, int spp, uint64_t seed, int threads)
{
    vbl_render_options o = tt_options(passes, spp, 0, seed);
    o.threads = threads;
    o.transmittance_majorant_scale = g_majorant_scale;
    o.max_bounces = -1;
    o.pt.equiangular = equiangular;
    /* one forced point per camera walk: with pt.split_paths 2 (the default) the two points' own
     * NEE already covers the camera segment, and the on/off standard errors of volume_direct
     * (0.84x at 1 path, 1.16x at 2, 0.95x at 4 over these 16 renders) are within each other's
     * noise; what this file tests is equiangular NEE against a single collision's */
    o.pt.split_paths = 1;
    vbl_film* film = NULL;
    if (vbl_render_with_estimator(scene, &o, &vbl_estimator_pt, &film) != VBL_SUCCESS)
        fail_msg("render: %s", vbl_last_error_message());
    return film;
}

/* One render of layer_stats: 4 passes of 16 spp at 2 threads, equiangular NEE on or off. */
static vbl_film* render_stats(const vbl_scene* scene, const void* equiangular, uint64_t seed)
{
    return render_pt(scene, *(const int*)equiangular, 4, 16, seed, 2);
}

static const int eq_on = 1, eq_off = 0;

static void test_equiangular_agrees_per_layer(void** state)
{
    (void)state;
    eq_case c = make_case(1);
    double m_on[VBL_CLASS_COUNT], se_on[VBL_CLASS_COUNT], m_off[VBL_CLASS_COUNT], se_off[VBL_CLASS_COUNT];
    layer_stats(render_stats, c.scene, &eq_on, K, 101, m_on, se_on);
    layer_stats(render_stats, c.scene, &eq_off, K, 202, m_off, se_off);
    int checked = 0;
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        double se = sqrt(se_on[l] * se_on[l] + se_off[l] * se_off[l]);
        if (!(m_off[l] > 0.0)) continue;
        double z = (m_on[l] - m_off[l]) / se;
        printf("%-22s on %.6f (se %.6f)  off %.6f (se %.6f)  z = %+.2f  se ratio on/off %.2f\n", layer_names[l],
               m_on[l], se_on[l], m_off[l], se_off[l], z, se_on[l] / se_off[l]);
        assert_true(se > 0.0 && se < 0.2 * m_off[l]);
        assert_true(fabs(z) <= Z_CRIT);
        ++checked;
    }
    assert_true(checked >= 6); /* every class but emission (no visible lights) */
    /* what the option is for: volume_direct from the point light is less noisy */
    assert_true(se_on[VBL_CLASS_VOLUME_DIRECT] < se_off[VBL_CLASS_VOLUME_DIRECT]);

    /* transmittance_majorant_scale 4 (pt: shadow rays of the camera-visible vertex) keeps every
     * layer's mean; its surface_direct noise is the shadow rays' and falls */
    double m_k[VBL_CLASS_COUNT], se_k[VBL_CLASS_COUNT];
    g_majorant_scale = 4.0;
    layer_stats(render_stats, c.scene, &eq_on, K, 303, m_k, se_k);
    g_majorant_scale = 1.0;
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        if (!(m_off[l] > 0.0)) continue;
        double z = (m_k[l] - m_off[l]) / sqrt(se_k[l] * se_k[l] + se_off[l] * se_off[l]);
        printf("%-22s majorant x4 %.6f (se %.6f)  z = %+.2f vs off\n", layer_names[l], m_k[l], se_k[l], z);
        assert_true(fabs(z) <= Z_CRIT);
    }
    vbl_scene_release(c.scene);
    vt_free(c.volume);
}

/* The same in the smoky box (surfaces all round, point light only). */
static void test_equiangular_agrees_in_box(void** state)
{
    (void)state;
    eq_case c = make_box_case();
    double m_on[VBL_CLASS_COUNT], se_on[VBL_CLASS_COUNT], m_off[VBL_CLASS_COUNT], se_off[VBL_CLASS_COUNT];
    layer_stats(render_stats, c.scene, &eq_on, K, 404, m_on, se_on);
    layer_stats(render_stats, c.scene, &eq_off, K, 505, m_off, se_off);
    int checked = 0;
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        double se = sqrt(se_on[l] * se_on[l] + se_off[l] * se_off[l]);
        if (!(m_off[l] > 0.0)) continue;
        double z = (m_on[l] - m_off[l]) / se;
        printf("box %-22s on %.6f (se %.6f)  off %.6f (se %.6f)  z = %+.2f  rel %+.4f\n", layer_names[l], m_on[l],
               se_on[l], m_off[l], se_off[l], z, m_on[l] / m_off[l] - 1.0);
        assert_true(se > 0.0 && se < 0.2 * m_off[l]);
        assert_true(fabs(z) <= Z_CRIT);
        ++checked;
    }
    assert_true(checked >= 6);
    vbl_scene_release(c.scene);
    vt_free(c.volume);
}

/* Same image at 1 and 2 threads with equiangular NEE on. */
static void test_equiangular_deterministic(void** state)
{
    (void)state;
    eq_case c = make_case(1);
    vbl_film* a = render_pt(c.scene, 1, 1, 2, 5, 1);
    vbl_film* b = render_pt(c.scene, 1, 1, 2, 5, 2);
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        const float* pa = vbl_film_layer_rgb(a, layer_names[l]);
        const float* pb = vbl_film_layer_rgb(b, layer_names[l]);
        assert_true((pa == NULL) == (pb == NULL));
        if (pa) assert_memory_equal(pa, pb, sizeof(float) * 3 * W * H);
    }
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_scene_release(c.scene);
    vt_free(c.volume);
}

/* No point/spot light: the option changes nothing, bit for bit. */
static void test_no_local_lights_bit_identical(void** state)
{
    (void)state;
    eq_case c = make_case(0);
    vbl_film* a = render_pt(c.scene, 1, 1, 2, 9, 2);
    vbl_film* b = render_pt(c.scene, 0, 1, 2, 9, 2);
    int ch = 0;
    const float* pa = vbl_film_layer(a, "", &ch);
    const float* pb = vbl_film_layer(b, "", &ch);
    assert_memory_equal(pa, pb, sizeof(float) * (size_t)ch * W * H);
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_scene_release(c.scene);
    vt_free(c.volume);
}

/* Control optical depth: the homogeneous inside of a box exactly; elsewhere between the depths of
 * the minorants and of the majorants (checked against a fine quadrature of the true density,
 * which also lies between them). */
static void test_control_depth(void** state)
{
    (void)state;
    const int n = 65;
    const double h = 1.0 / 32.0;
    vbl_volume* box = rt_make_box(n, h, vbl_v3(-1, -1, -1)); /* density 1 on [-1, 1]^3 */
    vbl_extinction ext;
    vbl_extinction_init(&ext);
    assert_int_equal(vbl_extinction_add(&ext, box, 3.0, NULL), VBL_SUCCESS);
    vbl_vec3 o = vbl_v3(-0.5, -0.4, -0.3), d = vbl_v3_normalize(vbl_v3(1.0, 0.3, 0.2));
    double tau = vbl_control_optical_depth(&ext, o, d, 0.0, 0.5, 0);
    printf("control depth inside: %.12f (exact %.12f)\n", tau, 1.5);
    assert_true(fabs(tau - 1.5) < 1e-9);
    assert_true(vbl_control_optical_depth(&ext, o, d, 0.5, 0.5, 0) == 0.0);
    /* a ray leaving the box through its ramp */
    o = vbl_v3(0.2, 0.1, 0.0);
    d = vbl_v3_normalize(vbl_v3(1.0, 0.2, 0.1));
    double t1 = 1.5, exact = 0.0, lo = 0.0, hi = 0.0;
    const int steps = 20000;
    for (int i = 0; i < steps; ++i) {
        double t = (i + 0.5) * t1 / steps;
        exact += 3.0 * rt_box_density(n, h, vbl_v3(-1, -1, -1), vbl_v3_madd(o, d, t)) * t1 / steps;
    }
    vbl_extinction_iter it;
    vbl_majorant_segment seg;
    vbl_extinction_iter_init(&it, &ext, o, d, 0.0, t1, 0);
    while (vbl_extinction_iter_next(&it, &seg)) {
        lo += seg.minorant * (seg.t1 - seg.t0);
        hi += seg.majorant * (seg.t1 - seg.t0);
    }
    tau = vbl_control_optical_depth(&ext, o, d, 0.0, t1, 0);
    printf("control depth through the ramp: %.6f (min %.6f, exact %.6f, max %.6f)\n", tau, lo, exact, hi);
    assert_true(lo <= exact + 1e-6 && exact <= hi + 1e-6);
    assert_true(fabs(tau - 0.5 * (lo + hi)) < 1e-9);
    assert_true(lo < hi); /* the ramp is not homogeneous: a real test of the mid-bound */
    vt_free(box);
}

static void test_scene_file_option(void** state)
{
    (void)state;
    char dir[256], path[512];
    rt_make_temp_dir(dir);
#define CAMERA "\"camera\": {\"position\": [0, -4, 0], \"look_at\": [0, 0, 0], \"fov_deg\": 40, \"resolution\": [4, 4]}"
    const char* texts[3] = {"{" CAMERA ", \"render\": {\"pt\": {\"equiangular\": false}}}",
                            "{" CAMERA ", \"render\": {\"pt\": {\"equiangular\": true}}}", "{" CAMERA "}"};
    const int want[3] = {0, 1, 1}; /* absent: the default, on */
    for (int i = 0; i < 3; ++i) {
        rt_write_file(dir, "pt.json", texts[i], path);
        vbl_scene* scene = NULL;
        assert_int_equal(vbl_scene_load(path, &scene), VBL_SUCCESS);
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
        assert_int_equal(o.pt.equiangular, want[i]);
        vbl_scene_release(scene);
    }
    rt_write_file(dir, "bad.json", "{" CAMERA ", \"render\": {\"pt\": {\"equiangular\": 1}}}", path);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(path, &scene), VBL_ERROR_SCENE);
    assert_non_null(strstr(vbl_last_error_message(), "render.pt.equiangular"));
    /* render.pt.sampler: independent | sobol (default sobol since session 8: the file sets the
     * other one) */
    rt_write_file(dir, "s.json", "{" CAMERA ", \"render\": {\"pt\": {\"sampler\": \"independent\"}}}", path);
    assert_int_equal(vbl_scene_load(path, &scene), VBL_SUCCESS);
    vbl_render_options so = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(so.pt.sampler, VBL_PT_SAMPLER_SOBOL);
    assert_int_equal(vbl_scene_render_options(scene, &so), VBL_SUCCESS);
    assert_int_equal(so.pt.sampler, VBL_PT_SAMPLER_INDEPENDENT);
    vbl_scene_release(scene);
    scene = NULL;
    rt_write_file(dir, "s_bad.json", "{" CAMERA ", \"render\": {\"pt\": {\"sampler\": \"halton\"}}}", path);
    assert_int_equal(vbl_scene_load(path, &scene), VBL_ERROR_SCENE);
    assert_non_null(strstr(vbl_last_error_message(), "render.pt.sampler"));
    rt_write_file(dir, "bad2.json", "{" CAMERA ", \"render\": {\"pt\": {\"equiangle\": true}}}", path);
    assert_int_equal(vbl_scene_load(path, &scene), VBL_ERROR_SCENE);
    /* render.transmittance_majorant_scale: [1, 64] */
    rt_write_file(dir, "k.json", "{" CAMERA ", \"render\": {\"transmittance_majorant_scale\": 3}}", path);
    assert_int_equal(vbl_scene_load(path, &scene), VBL_SUCCESS);
    vbl_render_options ko = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &ko), VBL_SUCCESS);
    assert_true(ko.transmittance_majorant_scale == 3.0);
    vbl_scene_release(scene);
    scene = NULL;
    rt_write_file(dir, "k_bad.json", "{" CAMERA ", \"render\": {\"transmittance_majorant_scale\": 0.5}}", path);
    assert_int_equal(vbl_scene_load(path, &scene), VBL_ERROR_SCENE);
    assert_non_null(strstr(vbl_last_error_message(), "transmittance_majorant_scale"));
    rt_remove_dir(dir);
    /* the API refuses values outside the enum */
    eq_case c = make_case(1);
    vbl_render_options o = tt_options(1, 1, 0, 1);
    o.pt.equiangular = 3;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(c.scene, &o, &film), VBL_ERROR_INVALID_ARGUMENT);
    o.pt.equiangular = 1;
    o.transmittance_majorant_scale = 0.5;
    assert_int_equal(vbl_render(c.scene, &o, &film), VBL_ERROR_INVALID_ARGUMENT);
    vbl_scene_release(c.scene);
    vt_free(c.volume);
}

/* `test_render_pt_equiangular` runs the quick group; `... agreement` the statistical renders
 * (labelled slow: ~4 s in Release). */
int main(int argc, char** argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_control_depth),
        cmocka_unit_test(test_scene_file_option),
        cmocka_unit_test(test_no_local_lights_bit_identical),
        cmocka_unit_test(test_equiangular_deterministic),
    };
    const struct CMUnitTest agreement[] = {
        cmocka_unit_test(test_equiangular_agrees_per_layer),
        cmocka_unit_test(test_equiangular_agrees_in_box),
    };
    if (argc > 2) cmocka_set_test_filter(argv[2]);
    if (argc > 1 && !strcmp(argv[1], "agreement")) return cmocka_run_group_tests(agreement, NULL, NULL);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
