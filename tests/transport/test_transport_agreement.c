/* vpl and vrl against the path tracer, per transport layer, on three small scenes (isotropic box +
 * point light, heterogeneous sphere g = 0.8 + spot light, two overlapping media + distant light),
 * and a dense medium. Each method renders K independent replicates (different seeds); block
 * means of volume_direct and volume_from_volume are compared by z = |a - b| / sqrt(se_a^2 +
 * se_b^2) against Z_CRIT (Sidak-corrected for the number of blocks, inflated for the Student-t
 * spread of K-replicate standard errors). Power check: scaling vrl's volume_from_volume by 1.1
 * must be rejected on the image means. Labelled `slow`. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render_test_util.h"
#include "transport/path_tracing/pt.h"
#include "transport/virtual_lights/vpl.h"
#include "transport/virtual_lights/vrl.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

/* 2 layers x up to 16 blocks: Sidak at family-wise 1e-3 gives |z| ~ 4.2 for a normal statistic;
 * with K = 10 replicates per method (Welch dof >= 9) 5.5 keeps the family-wise false-alarm rate
 * near 1e-3. */
#define Z_CRIT 5.5
#define K_REPS 10

/* long VRLs with ray-marched connections: another variant that must agree too */
static vbl_result long_vrl_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings s = VBL_VRL_SETTINGS_DEFAULT;
    s.long_vrls = 1;
    s.samples = 2;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}
static const vbl_estimator long_vrl = {"vrl-long", 1, long_vrl_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};

static vbl_result rr_vrl_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings s = VBL_VRL_SETTINGS_DEFAULT;
    s.rr_radius = 0.2;
    s.rr_min_probability = 0.2;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}
static const vbl_estimator rr_vrl = {"vrl-rr", 1, rr_vrl_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};

/* light-tree selection: 4 VRLs per camera sample (vrl_tree.h) */
static vbl_result sel_vrl_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings s = VBL_VRL_SETTINGS_DEFAULT;
    s.select = 4;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}
static const vbl_estimator sel_vrl = {"vrl-select", 1, sel_vrl_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};

/* transmittance-aware pair sampling (sampling/vrl_camera_mis.h) with the low roulette threshold */
static vbl_result mis_vrl_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings s = VBL_VRL_SETTINGS_DEFAULT;
    s.camera_mis = 1;
    s.transmittance_rr = 0.01;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}
static const vbl_estimator mis_vrl = {"vrl-camera-mis", 1, mis_vrl_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};

/* camera transmittance x 1/distance pair sampling (sampling/vrl_tc_pair.h, vrl.pair_sampler =
 * transmittance), alone and with light-tree selection, and its free-flight form (free_flight) */
static vbl_result tc_vrl_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings s = VBL_VRL_SETTINGS_DEFAULT;
    s.camera_mis = VBL_VRL_PAIR_TRANSMITTANCE;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}
static const vbl_estimator tc_vrl = {"vrl-tc", 1, tc_vrl_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};
static vbl_result tc_sel_vrl_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings s = VBL_VRL_SETTINGS_DEFAULT;
    s.camera_mis = VBL_VRL_PAIR_TRANSMITTANCE;
    s.select = 4;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}
static vbl_result ff_vrl_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings s = VBL_VRL_SETTINGS_DEFAULT;
    s.camera_mis = VBL_VRL_PAIR_FREE_FLIGHT;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}
static const vbl_estimator ff_vrl = {"vrl-free-flight", 1, ff_vrl_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};
static const vbl_estimator tc_sel_vrl = {"vrl-tc-select", 1, tc_sel_vrl_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};

typedef struct scene_case {
    vbl_scene* scene;
    vbl_volume* volumes[2];
    int volume_count;
} scene_case;

static void free_case(scene_case* c)
{
    vbl_scene_release(c->scene);
    for (int i = 0; i < c->volume_count; ++i) vt_free(c->volumes[i]);
}

static scene_case box_point(int res)
{
    scene_case c;
    memset(&c, 0, sizeof c);
    vbl_camera cam = rt_camera(vbl_v3(0.2, -4.0, 0.3), vbl_v3(0, 0, 0), 36.0, res, res);
    c.scene = tt_scene(&cam);
    c.volumes[0] = rt_make_box(9, 0.25, vbl_v3(-1, -1, -1));
    c.volume_count = 1;
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volumes[0], 1.2, vbl_v3(0.8, 0.7, 0.6), 0.0, NULL), VBL_SUCCESS);
    tt_add_point(c.scene, vbl_v3(0.4, 0.3, 1.6), 10.0);
    return c;
}

/* thinner box, wider view: the power check needs image means within ~1.5% */
static scene_case thin_box_point(int res)
{
    scene_case c;
    memset(&c, 0, sizeof c);
    vbl_camera cam = rt_camera(vbl_v3(0.3, -4.0, 0.5), vbl_v3(0.2, 0, 0), 40.0, res, res);
    c.scene = tt_scene(&cam);
    c.volumes[0] = rt_make_box(9, 0.25, vbl_v3(-1, -1, -1));
    c.volume_count = 1;
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volumes[0], 0.7, vbl_v3(0.9, 0.6, 0.5), 0.0, NULL), VBL_SUCCESS);
    /* far enough for emission into the cone of the media's bounding sphere */
    tt_add_point(c.scene, vbl_v3(1.5, 1.0, 4.5), 60.0);
    return c;
}

static scene_case sphere_spot(int res)
{
    scene_case c;
    memset(&c, 0, sizeof c);
    vbl_camera cam = rt_camera(vbl_v3(0.0, -3.5, 0.4), vbl_v3(0, 0, 0), 38.0, res, res);
    c.scene = tt_scene(&cam);
    c.volumes[0] = tt_make_sphere(20, 1.0);
    c.volume_count = 1;
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volumes[0], 3.0, vbl_v3(0.9, 0.9, 0.8), 0.8, NULL), VBL_SUCCESS);
    tt_add_spot(c.scene, vbl_v3(-2.0, -1.0, 1.5), vbl_v3(2.0, 1.0, -1.5), 20.0, 15.0, 25.0);
    return c;
}

static scene_case two_media_distant(int res)
{
    scene_case c;
    memset(&c, 0, sizeof c);
    vbl_camera cam = rt_camera(vbl_v3(0.3, -4.0, 0.5), vbl_v3(0.2, 0, 0), 40.0, res, res);
    c.scene = tt_scene(&cam);
    c.volumes[0] = rt_make_box(9, 0.25, vbl_v3(-1, -1, -1));
    c.volumes[1] = tt_make_sphere(16, 0.8);
    c.volume_count = 2;
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volumes[0], 0.7, vbl_v3(0.9, 0.6, 0.5), 0.5, NULL), VBL_SUCCESS);
    vbl_affine place = {{{1, 0, 0, 0.7}, {0, 1, 0, 0.2}, {0, 0, 1, 0.3}}};
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volumes[1], 2.5, vbl_v3(0.5, 0.8, 0.9), -0.3, &place),
                     VBL_SUCCESS);
    tt_add_distant(c.scene, vbl_v3(0.4, 0.6, -0.7), 2.0);
    return c;
}

static void agree(scene_case c, const vbl_estimator* est, int passes, int spp, int light_paths, int pt_passes,
                  int pt_spp, int check_power, const char* tag)
{
    tt_stats ref, got;
    vbl_render_options o = tt_options(pt_passes, pt_spp, 0, 101);
    tt_replicate(c.scene, &vbl_estimator_pt, &o, K_REPS, 4, &ref);
    o = tt_options(passes, spp, light_paths, 202);
    tt_replicate(c.scene, est, &o, K_REPS, 4, &got);
    assert_true(ref.finite && got.finite);
    double image_z = 0.0;
    double z = tt_compare(&ref, &got, 1.0, &image_z, tag);
    assert_true(ref.image_mean[1] > 0.0 && got.image_mean[1] > 0.0);
    assert_true(z < Z_CRIT);
    if (check_power) {
        double zs = tt_compare(&ref, &got, 1.1, &image_z, "  (x1.1)");
        (void)zs;
        assert_true(image_z > Z_CRIT); /* the comparison detects a 10% error in volume_from_volume */
    }
    free_case(&c);
}

/* vrl/vpl: 2 passes x 400 light paths x 1 spp per replicate; pt: 4 passes x 32 spp */
#define RES 12
static void test_box_point_vrl(void** state) { (void)state; agree(box_point(RES), &vbl_estimator_vrl, 2, 1, 400, 4, 32, 0, "box/point vrl"); }
/* 8 vrl passes: the x1.1 error is ~8 s.e. (at 2 passes it was 4-6 s.e., so the check passed or
 * failed with the random stream: it failed after the tracker's carried optical depth). */
static void test_power_vrl(void** state) { (void)state; agree(thin_box_point(8), &vbl_estimator_vrl, 8, 2, 1600, 4, 64, 1, "thin box/point vrl"); }
static void test_box_point_vpl(void** state) { (void)state; agree(box_point(RES), &vbl_estimator_vpl, 2, 1, 400, 4, 32, 0, "box/point vpl"); }
static void test_sphere_spot_vrl(void** state) { (void)state; agree(sphere_spot(RES), &vbl_estimator_vrl, 2, 1, 400, 4, 32, 0, "sphere/spot vrl"); }
static void test_sphere_spot_vpl(void** state) { (void)state; agree(sphere_spot(RES), &vbl_estimator_vpl, 2, 1, 400, 4, 32, 0, "sphere/spot vpl"); }
static void test_two_media_vrl(void** state) { (void)state; agree(two_media_distant(RES), &vbl_estimator_vrl, 2, 1, 400, 4, 32, 0, "two media/distant vrl"); }
static void test_two_media_vpl(void** state) { (void)state; agree(two_media_distant(RES), &vbl_estimator_vpl, 2, 1, 400, 4, 32, 0, "two media/distant vpl"); }
static void test_long_vrl(void** state) { (void)state; agree(sphere_spot(RES), &long_vrl, 2, 1, 200, 4, 32, 0, "sphere/spot long-vrl"); }
static void test_sel_vrl(void** state) { (void)state; agree(sphere_spot(RES), &sel_vrl, 2, 1, 1600, 4, 32, 0, "sphere/spot vrl-select"); }
static void test_mis_vrl(void** state) { (void)state; agree(sphere_spot(RES), &mis_vrl, 2, 1, 400, 4, 32, 0, "sphere/spot vrl-camera-mis"); }
static void test_tc_vrl(void** state) { (void)state; agree(sphere_spot(RES), &tc_vrl, 2, 1, 400, 4, 32, 0, "sphere/spot vrl-tc"); }
static void test_tc_ff_vrl(void** state) { (void)state; agree(box_point(RES), &ff_vrl, 2, 1, 400, 4, 32, 0, "box/point vrl-free-flight"); }
static void test_tc_sel_vrl(void** state) { (void)state; agree(two_media_distant(RES), &tc_sel_vrl, 2, 1, 1600, 4, 32, 0, "two media/distant vrl-tc-select"); }
static void test_rr_vrl(void** state) { (void)state; agree(box_point(RES), &rr_vrl, 2, 1, 400, 4, 32, 0, "box/point rr-vrl"); }

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_power_vrl), cmocka_unit_test(test_box_point_vrl),   cmocka_unit_test(test_box_point_vpl),
        cmocka_unit_test(test_sphere_spot_vrl), cmocka_unit_test(test_sphere_spot_vpl),
        cmocka_unit_test(test_two_media_vrl),   cmocka_unit_test(test_two_media_vpl),
        cmocka_unit_test(test_long_vrl),        cmocka_unit_test(test_rr_vrl), cmocka_unit_test(test_sel_vrl),
        cmocka_unit_test(test_mis_vrl),         cmocka_unit_test(test_tc_vrl), cmocka_unit_test(test_tc_sel_vrl),
        cmocka_unit_test(test_tc_ff_vrl),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
