/* pt.light_focus (issue 14): scattered directions at surfaces and at the first medium events from
 * the BRDF or phase function mixed with focus cones about the point/spot lights inside the media
 * (transport/path_tracing/pt_light_focus.h), against BRDF and phase sampling alone (0):
 *   - bit-identical at 1 and 2 threads, and different from 0 (the mixture is active);
 *   - finite and summing to the beauty at density scales 1e-8 and 1e6, and with the light on a
 *     surface (distance 0: that focus is skipped there);
 *   - every layer's image mean agrees within Z_CRIT standard errors over K renders each, in a
 *     smoky sphere with a point light inside, a quad light (lights hit by scattered rays: the
 *     MIS uses the mixture's density) and a Lambert floor and wall; in an emissive sphere (the
 *     emission NEEs' MIS uses the mixture's density too); with a large quad light next to the
 *     point light (the quads' equiangular three-strategy weights); with a spot light instead;
 *   - the variance it exists to cut: in the first scene with two scattering events, the spread
 *     over the K renders of surface_from_volume and volume_from_volume is below SPREAD_MAX x that
 *     of BRDF and phase sampling. Their fireflies come from rays that leave a surface or a medium
 *     vertex and pass the light closely (single scattering ~ 1/distance, infinite variance under
 *     a bounded density). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render_test_util.h"
#include "surface_render_util.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"
#include "pt_switch_scene.h"
#include "volume/blackbody.h"

#define K 24
#define Z_CRIT 4.5
#define SPREAD_MAX 0.8

typedef struct focus_config {
    double focus;
    int passes, spp, threads;
    int max_bounces; /* 0: unlimited */
} focus_config;

static vbl_film* render_cfg(const vbl_scene* scene, const void* cfg_ptr, uint64_t seed)
{
    const focus_config* cfg = cfg_ptr;
    vbl_render_options o = tt_options(cfg->passes, cfg->spp, 0, seed);
    o.method = VBL_RENDER_PT;
    o.pt.light_focus = cfg->focus;
    if (cfg->threads > 0) o.threads = cfg->threads;
    if (cfg->max_bounces > 0) o.max_bounces = cfg->max_bounces;
    return render_or_fail(scene, &o);
}

/* The sphere tt_make_sphere(16, 0.9) (albedo 0.9, g 0.3) with a point light (spot: a spot light
 * aimed down) of `intensity` inside it, a quad light above, a Lambert floor and wall; w x h film. */
static vbl_scene* focus_scene_lit(double density_scale, vbl_vec3 point, double intensity, int spot, int w, int h,
                                  vbl_volume** volume)
{
    vbl_camera cam = rt_camera(vbl_v3(0.3, -4.0, 0.6), vbl_v3(0, 0, -0.3), 45.0, w, h);
    vbl_scene* scene = tt_scene(&cam);
    *volume = tt_make_sphere(16, 0.9);
    assert_int_equal(vbl_scene_add_medium(scene, *volume, density_scale, vbl_v3(0.9, 0.9, 0.9), 0.3, NULL),
                     VBL_SUCCESS);
    if (spot) tt_add_spot(scene, point, vbl_v3_normalize(vbl_v3(0.2, 0.3, -1.0)), intensity, 20.0, 35.0);
    else tt_add_point(scene, point, intensity);
    vbl_light q = pt_switch_quad_light(vbl_v3(-1.0, -0.6, 1.6), vbl_v3(0, 1, 0), vbl_v3(1, 0, 0), vbl_v3(0, 0, -1), 1.0);
    assert_int_equal(vbl_scene_add_light(scene, &q), VBL_SUCCESS);
    pt_switch_surfaces(scene);
    return scene;
}

/* The scene with a point light. */
static vbl_scene* focus_scene(double density_scale, vbl_vec3 point, double intensity, int w, int h, vbl_volume** volume)
{
    return focus_scene_lit(density_scale, point, intensity, 0, w, h, volume);
}

static const vbl_vec3 light_inside = {0.15, -0.2, 0.25};

static void test_deterministic_and_active(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = focus_scene(2.0, light_inside, 3.0, 12, 10, &volume);
    const focus_config on1 = {0.25, 2, 2, 1, 0}, on2 = {0.25, 2, 2, 2, 0}, off = {0.0, 2, 2, 2, 0};
    check_configs_deterministic(render_cfg, scene, &on1, &on2, &off);
    vbl_scene_release(scene);
    vt_free(volume);
}

static void test_finite_at_extremes(void** state)
{
    (void)state;
    const double scales[3] = {1e-8, 1e6, 2.0};
    /* the last: the light on the floor (z = -1), at the distance-0 edge of its own focus */
    const vbl_vec3 lights[3] = {light_inside, light_inside, {0.1, 0.1, -1.0}};
    for (int i = 0; i < 3; ++i) {
        vbl_volume* volume;
        vbl_scene* scene = focus_scene(scales[i], lights[i], 3.0, 12, 10, &volume);
        vbl_render_options o = tt_options(1, 2, 0, 5);
        o.method = VBL_RENDER_PT;
        o.pt.light_focus = 0.5;
        o.max_bounces = 4; /* at 1e6 a shadow ray's tracking takes ~1e5 steps: bound the work */
        vbl_film* f = render_or_fail(scene, &o);
        double total = check_sum_to_beauty(f);
        printf("density scale %g: beauty total %g\n", scales[i], total);
        assert_true(total > 0.0);
        vbl_film_release(f);
        vbl_scene_release(scene);
        vt_free(volume);
    }
}

/* Layer means with and without the focus over `renders` renders each: |z| <= Z_CRIT on every
 * layer with signal, at least 4 of them with a standard error below 20 % of the mean; the spreads
 * (standard errors) go to se_on / se_off. */
static void check_agreement(const vbl_scene* scene, int passes, int spp, int max_bounces, int renders,
                            double se_on[VBL_CLASS_COUNT], double se_off[VBL_CLASS_COUNT])
{
    const focus_config on = {0.25, passes, spp, 0, max_bounces}, off = {0.0, passes, spp, 0, max_bounces};
    double m1[VBL_CLASS_COUNT], m0[VBL_CLASS_COUNT];
    layer_stats(render_cfg, scene, &on, renders, 11, m1, se_on);
    layer_stats(render_cfg, scene, &off, renders, 22, m0, se_off);
    int checked = 0;
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        if (!(m0[l] > 0.0)) continue;
        double se = sqrt(se_on[l] * se_on[l] + se_off[l] * se_off[l]);
        double z = (m1[l] - m0[l]) / se;
        printf("%-22s focus %.6f (se %.6f)  brdf %.6f (se %.6f)  z = %+.2f\n", layer_names[l], m1[l], se_on[l], m0[l],
               se_off[l], z);
        assert_true(se > 0.0);
        assert_true(fabs(z) <= Z_CRIT);
        checked += se < 0.2 * m0[l]; /* layers the check has power on (volume_from_volume's spread is
                                        heavy-tailed: its phase sampling has the same singularity) */
    }
    assert_true(checked >= 4);
}

static void test_smoke_agrees(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = focus_scene(2.0, light_inside, 3.0, 8, 8, &volume);
    double se_on[VBL_CLASS_COUNT], se_off[VBL_CLASS_COUNT];
    check_agreement(scene, 1, 16, 0, K, se_on, se_off);
    vbl_scene_release(scene);
    vt_free(volume);
}

/* Two scattering events: surface_from_volume (volume_from_volume) is the camera-visible surface's
 * (medium vertex's) scattered ray and the single scattering its segment picks up near the light,
 * whose variance BRDF (phase) sampling leaves infinite. */
static void test_less_spread(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = focus_scene(2.0, light_inside, 3.0, 8, 8, &volume);
    double se_on[VBL_CLASS_COUNT], se_off[VBL_CLASS_COUNT];
    /* 3K renders: without the focus volume_from_volume's variance is infinite, so its sample spread
     * over K renders depends on whether a firefly fell in them (the ratio read 0.43-1.18 over four
     * seed sets at K, 0.09-0.56 at 3K) */
    check_agreement(scene, 1, 16, 2, 3 * K, se_on, se_off);
    const int layers[2] = {VBL_CLASS_SURFACE_FROM_VOLUME, VBL_CLASS_VOLUME_FROM_VOLUME};
    for (int i = 0; i < 2; ++i) {
        const int l = layers[i];
        printf("%s: spread with the focus / without = %.3f (at most %.2f)\n", layer_names[l], se_on[l] / se_off[l],
               SPREAD_MAX);
        assert_true(se_on[l] < SPREAD_MAX * se_off[l]);
    }
    vbl_scene_release(scene);
    vt_free(volume);
}

/* The smoky scene's sphere emits, and its emission outshines the (dim) point light the focus
 * aims at: the surfaces' emission NEE weighs against the mixture's density, and against the
 * BRDF's density alone (the emission NEE's weight not updated) surface_direct reads z = +6.0
 * (measured), so the check can fail. */
static void test_emission_agrees(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = focus_scene(2.0, light_inside, 0.2, 8, 8, &volume);
    vbl_volume* emission = tt_make_sphere(16, 0.9);
    assert_int_equal(vbl_scene_set_medium_emission(scene, 0, emission, vbl_v3(1.0, 0.6, 0.3), 8.0, NULL, 1.0, 0.0, 0.0,
                                                   VBL_BLACKBODY_PEAK),
                     VBL_SUCCESS);
    assert_true(scene->has_emission && scene->emission_lights.count > 0);
    double se_on[VBL_CLASS_COUNT], se_off[VBL_CLASS_COUNT];
    check_agreement(scene, 1, 8, 0, K, se_on, se_off);
    vbl_scene_release(scene);
    vt_free(emission);
    vt_free(volume);
}

/* A 1.2 x 1.2 quad light facing down just above the (dim) point light, inside the smoke: the
 * focus cones' directions hit the quad often, and the MIS weights at medium and surface vertices
 * (NEE against the direction's density, the quad hit by the scattered ray, the equiangular
 * three-strategy weights) all use the mixture's density. Limits: the NEE weight at medium
 * vertices taken with the phase density instead moves the means by ~1 % here (measured), below
 * this check's resolution; it guards larger errors. */
static void test_quad_near_the_light_agrees(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = focus_scene(2.0, light_inside, 0.3, 8, 8, &volume);
    vbl_light q = pt_switch_quad_light(vbl_v3(-0.45, -0.8, 0.3), vbl_v3(0, 1.2, 0), vbl_v3(1.2, 0, 0), vbl_v3(0, 0, -1),
                                       3.0);
    q.area = 1.44;
    assert_int_equal(vbl_scene_add_light(scene, &q), VBL_SUCCESS);
    double se_on[VBL_CLASS_COUNT], se_off[VBL_CLASS_COUNT];
    check_agreement(scene, 1, 8, 0, K, se_on, se_off);
    vbl_scene_release(scene);
    vt_free(volume);
}

/* A spot light inside the smoke instead, aimed down at the floor (the focus aims at its position,
 * also outside its cone, where the light adds nothing: unbiased, only wasted samples). */
static void test_spot_light_agrees(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = focus_scene_lit(2.0, light_inside, 4.0, 1, 8, 8, &volume);
    double se_on[VBL_CLASS_COUNT], se_off[VBL_CLASS_COUNT];
    check_agreement(scene, 1, 32, 0, K, se_on, se_off);
    vbl_scene_release(scene);
    vt_free(volume);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_deterministic_and_active),
        cmocka_unit_test(test_finite_at_extremes),
        cmocka_unit_test(test_smoke_agrees),
        cmocka_unit_test(test_less_spread),
        cmocka_unit_test(test_emission_agrees),
        cmocka_unit_test(test_quad_near_the_light_agrees),
        cmocka_unit_test(test_spot_light_agrees),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
