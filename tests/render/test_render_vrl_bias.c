/* Issue 13: vrl's volume_from_volume against pt in the regime where a 19% deficit was reported
 * (the albedo_ramp.vdb box at density_scale 1, optical depth 1.6 across, a constant albedo, a
 * slanted distant light, the default 10 light paths per pass). Many independent replicas per
 * method, so that the standard error is estimated honestly: with 4 replicas of a skewed estimate
 * the sample SE is often far below the true one and a low mean looks significant.
 *   quick: albedo 0.8, 8x8, vrl 24 replicas x 32 passes x 1 spp, pt 32 x 32 spp; |z| < 4, and a
 *          power check: vrl's mean x 0.85 must be rejected (|z| > 4).
 *   slow (argument "slow"): density_scale 1, 2, 4 x albedo 0.3, 0.99, and 3 / 100 light paths,
 *          16 replicas each. */
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

static vbl_scene* load_box(double density_scale, double albedo)
{
    vbl_scene* scene = rt_ramp_box_load(density_scale, albedo, 8, "");
    assert_non_null(scene);
    return scene;
}

/* Mean over pixels and RGB of volume_from_volume for n replicas (seeds seed0 + k), and its
 * standard error across replicas (rt_layer_replicas). */
static void replicas(const vbl_scene* scene, vbl_render_method method, int passes, int spp, int light_paths, int n,
                     uint64_t seed0, double* mean, double* se)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.method = method;
    o.passes = passes;
    o.spp = spp;
    o.light_paths = light_paths;
    o.vrl.select = 0; /* every VRL, as before the tree became the default: on 8x8 images at 1 spp a
                       * pass is mostly the tree build (the tree's own agreement tests: test_vrl_tree) */
    o.threads = 1;
    assert_int_equal(rt_layer_replicas(scene, &o, "volume_from_volume", n, seed0, mean, se), 0);
}

/* Returns z of vrl against pt; prints both. */
static double compare(double density_scale, double albedo, int light_paths, int vrl_reps, int vrl_passes,
                      int pt_reps, double* vrl_mean, double* se_total)
{
    vbl_scene* scene = load_box(density_scale, albedo);
    double mp, sp, mv, sv;
    replicas(scene, VBL_RENDER_PT, 1, 32, 0, pt_reps, 1, &mp, &sp);
    replicas(scene, VBL_RENDER_VRL, vrl_passes, 1, light_paths, vrl_reps, 1000, &mv, &sv);
    vbl_scene_release(scene);
    double se = sqrt(sp * sp + sv * sv), z = (mv - mp) / se;
    printf("density %g albedo %g light paths %d: pt %.6f +- %.6f, vrl %.6f +- %.6f (ratio %.3f, z %.2f)\n",
           density_scale, albedo, light_paths, mp, sp, mv, sv, mv / mp, z);
    assert_true(mp > 20.0 * sp); /* the test has signal */
    assert_true(mv > 10.0 * sv);
    *vrl_mean = mv;
    *se_total = se;
    return z;
}

static void test_vrl_box_density1(void** state)
{
    (void)state;
    double mv, se;
    double z = compare(1.0, 0.8, 0, 24, 32, 32, &mv, &se);
    assert_true(fabs(z) < 4.0);
    /* power: a 15% deficit (the reported one was 19%) is rejected */
    double z_low = z - 0.15 * mv / se;
    printf("power check: vrl x 0.85 would give z %.2f\n", z_low);
    assert_true(fabs(z_low) > 4.0);
}

/* 16 replicas per method: at 64 (until session 10, 775 s, most of the suite's time) the standard
 * errors were 0.3-0.6 % of the means; at 16 they are about 0.6-1.2 % (2.4 % for 3 light paths),
 * so |z| < 4.5 still rejects a deficit of 6-11 % (the reported one was 19 %). */
static void test_vrl_box_slow(void** state)
{
    (void)state;
    const double densities[] = {1.0, 2.0, 4.0}, albedos[] = {0.3, 0.99};
    double mv, se;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 2; ++j) assert_true(fabs(compare(densities[i], albedos[j], 0, 16, 32, 16, &mv, &se)) < 4.5);
    const int light_paths[] = {3, 100};
    for (int k = 0; k < 2; ++k) assert_true(fabs(compare(1.0, 0.99, light_paths[k], 16, 32, 16, &mv, &se)) < 4.5);
}

int main(int argc, char** argv)
{
    const int slow = argc > 1 && !strcmp(argv[1], "slow");
    const struct CMUnitTest quick[] = {cmocka_unit_test(test_vrl_box_density1)};
    const struct CMUnitTest longer[] = {cmocka_unit_test(test_vrl_box_slow)};
    return slow ? cmocka_run_group_tests(longer, rt_temp_dir_setup, rt_temp_dir_teardown)
                : cmocka_run_group_tests(quick, rt_temp_dir_setup, rt_temp_dir_teardown);
}
