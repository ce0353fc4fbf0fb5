/* pt.equiangular_camera_samples (issue 14): the camera segment's equiangular NEE towards point,
 * spot and quad lights with n distance strata, each taking T(t0, t) from the camera walk's running
 * ratio-tracking product (vbl_pt_camera_split_transmittance, pt_camera_split.h) instead of a march
 * of its own:
 *   - the walk's product at t, on hand-built walks: before, between and past its points, after a
 *     roulette that ended it, and past a cap (the rest left to the caller);
 *   - quick group: bit-identical at 1 and 2 threads and different from 1 sample; finite and summing
 *     to the beauty at density scales 1e-8 and 1e6; among Lambert surfaces (point, quad and distant
 *     lights) every layer's image mean with 3 samples agrees within Z_CRIT standard errors with the
 *     estimator before this option (one sample, pt.camera_split off: T by the march); in a thin
 *     sphere lit by a point light inside it, volume_direct's mean agrees with that estimator and
 *     its standard error with 3 samples falls below SE_MAX x one sample's (both with the walk);
 *     and a dense sphere around the light, where most walks end in their roulette before the far
 *     side (T^ = 0 past that point) and the walk's product is the only T (2 s, so in the quick
 *     group since session 17: it is the one case that exercises the product after a roulette). */
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
#include "transport/path_tracing/pt_camera_split.h"

#define K 16
#define Z_CRIT 4.5
#define SE_MAX 0.85

typedef struct eq_config {
    int samples, split, passes, spp, threads, max_bounces; /* max_bounces 0: the default (-1) */
} eq_config;

static vbl_film* render_cfg(const vbl_scene* scene, const void* cfg_ptr, uint64_t seed)
{
    const eq_config* cfg = cfg_ptr;
    vbl_render_options o = tt_options(cfg->passes, cfg->spp, 0, seed);
    o.method = VBL_RENDER_PT;
    o.pt.equiangular_camera_samples = cfg->samples;
    o.pt.camera_split = cfg->split;
    if (cfg->threads > 0) o.threads = cfg->threads;
    if (cfg->max_bounces > 0) o.max_bounces = cfg->max_bounces;
    return render_or_fail(scene, &o);
}

/* A walk with n tentative points at t = 1, 2, ..., n and the products before them 1, 1/2, 1/4, ... */
static vbl_pt_split_walk walk_points(int n, double T_after, int capped)
{
    vbl_pt_split_walk w;
    memset(&w, 0, sizeof w);
    w.n = n;
    for (int i = 0; i < n; ++i) {
        w.t[i] = 1.0 + i;
        w.T_before[i] = ldexp(1.0, -i);
    }
    w.T_after = T_after;
    w.capped = capped;
    return w;
}

static void test_walk_product(void** state)
{
    (void)state;
    double rest;
    vbl_pt_split_walk w = walk_points(3, 0.125, 0);
    assert_true(vbl_pt_camera_split_transmittance(&w, 0.5, &rest) == 1.0 && rest == 0.5); /* before the first */
    assert_true(vbl_pt_camera_split_transmittance(&w, 1.5, &rest) == 0.5 && rest == 1.5);
    assert_true(vbl_pt_camera_split_transmittance(&w, 2.0, &rest) == 0.5); /* a point's own factor comes after it */
    assert_true(vbl_pt_camera_split_transmittance(&w, 2.5, &rest) == 0.25);
    assert_true(vbl_pt_camera_split_transmittance(&w, 9.0, &rest) == 0.125 && rest == 9.0); /* past the last */
    w = walk_points(3, 0.0, 0); /* the roulette ended the walk at its last point */
    assert_true(vbl_pt_camera_split_transmittance(&w, 3.5, &rest) == 0.0);
    assert_true(vbl_pt_camera_split_transmittance(&w, 2.5, &rest) == 0.25);
    /* capped at its last tentative point, t = VBL_PT_SPLIT_POINTS: the rest (cap, t] is the caller's;
     * the delta-tracking collision stored after the points (entry n - 1) is not one of them */
    const int cap = VBL_PT_SPLIT_POINTS;
    w = walk_points(cap, 0.125, 1);
    w.n = cap + 1;
    w.t[cap] = cap + 50.0;
    assert_true(vbl_pt_camera_split_transmittance(&w, 2.5, &rest) == 0.25 && rest == 2.5);
    assert_true(vbl_pt_camera_split_transmittance(&w, cap + 10.0, &rest) == 0.125 && rest == cap);
    memset(&w, 0, sizeof w); /* no points: nothing in the way */
    w.T_after = 1.0;
    assert_true(vbl_pt_camera_split_transmittance(&w, 1.0, &rest) == 1.0 && rest == 1.0);
}

static void test_deterministic_and_active(void** state)
{
    (void)state;
    const eq_config on1 = {3, 1, 2, 2, 1, 0}, on2 = {3, 1, 2, 2, 2, 0}, off = {1, 1, 2, 2, 2, 0};
    pt_switch_check_deterministic(render_cfg, &on1, &on2, &off);
}

static void test_finite_at_extremes(void** state)
{
    (void)state;
    pt_switch_check_extremes();
}

/* Every layer with `on` against one sample with pt.camera_split off (the march's T(t0, t)). */
static void test_surfaces_agree(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = pt_switch_scene(4.0, 0, 8, 8, &volume);
    const eq_config on = {3, 1, 1, 8, 0, 0}, before = {1, 0, 1, 8, 0, 0};
    check_layers_agree(render_cfg, scene, &on, &before, K, Z_CRIT, 4, VBL_CLASS_VOLUME_DIRECT, "3 samples", "before");
    vbl_scene_release(scene);
    vt_free(volume);
}

/* The sphere tt_make_sphere(16, 0.9) (albedo 0.8, g 0.3) at density_scale with a point light
 * inside it, off its centre, seen whole through an 8 x 8 film. */
static vbl_scene* lamp_sphere(double density_scale, vbl_volume** volume)
{
    vbl_camera cam = rt_camera(vbl_v3(0.0, -4.0, 0.0), vbl_v3(0, 0, 0), 30.0, 8, 8);
    vbl_scene* scene = tt_scene(&cam);
    *volume = tt_make_sphere(16, 0.9);
    assert_int_equal(vbl_scene_add_medium(scene, *volume, density_scale, vbl_v3(0.8, 0.7, 0.6), 0.3, NULL),
                     VBL_SUCCESS);
    tt_add_point(scene, vbl_v3(0.25, 0.2, 0.1), 2.0);
    return scene;
}

/* Single scattering in thin smoke around a lamp: volume_direct's mean agrees with the estimator
 * before the option, and 3 strata cut its standard error against 1 (both with the walk's T). */
static void test_lamp_volume_direct(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = lamp_sphere(1.0, &volume);
    const eq_config three = {3, 1, 2, 4, 0, 1}, before = {1, 0, 2, 4, 0, 1}, one = {1, 1, 2, 4, 0, 1};
    check_layers_agree(render_cfg, scene, &three, &before, K, Z_CRIT, 1, VBL_CLASS_VOLUME_DIRECT, "3 samples",
                       "before");
    double m3[VBL_CLASS_COUNT], s3[VBL_CLASS_COUNT], m1[VBL_CLASS_COUNT], s1[VBL_CLASS_COUNT];
    layer_stats(render_cfg, scene, &three, K, 33, m3, s3);
    layer_stats(render_cfg, scene, &one, K, 44, m1, s1);
    const int l = VBL_CLASS_VOLUME_DIRECT;
    printf("volume_direct: 3 samples %.6f (se %.6f), 1 sample %.6f (se %.6f): se ratio %.2f (at most %.2f)\n", m3[l],
           s3[l], m1[l], s1[l], s3[l] / s1[l], SE_MAX);
    assert_true(s3[l] < SE_MAX * s1[l]);
    vbl_scene_release(scene);
    vt_free(volume);
}

/* Optical depth ~10 across: most camera walks end in their roulette, and every layer agrees. */
static void test_dense_lamp_agrees(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = lamp_sphere(6.0, &volume);
    const eq_config on = {3, 1, 1, 32, 0, 0}, before = {1, 0, 1, 32, 0, 0};
    check_layers_agree(render_cfg, scene, &on, &before, 2 * K, Z_CRIT, 2, VBL_CLASS_VOLUME_DIRECT, "3 samples",
                       "before");
    vbl_scene_release(scene);
    vt_free(volume);
}

int main(void)
{
    const struct CMUnitTest quick[] = {
        cmocka_unit_test(test_walk_product),
        cmocka_unit_test(test_deterministic_and_active),
        cmocka_unit_test(test_finite_at_extremes),
        cmocka_unit_test(test_surfaces_agree),
        cmocka_unit_test(test_lamp_volume_direct),
        cmocka_unit_test(test_dense_lamp_agrees),
    };
    return cmocka_run_group_tests(quick, NULL, NULL);
}
