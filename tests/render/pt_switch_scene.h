/* The scene of pt's switch tests (issue 14: test_render_pt_core.c, test_render_pt_camera_split.c):
 * a heterogeneous sphere between a Lambert floor and wall, lit by a point, a distant and a quad
 * light. Header-only (static); include after cmocka.h, render_test_util.h and
 * surface_render_util.h. */
#ifndef VBL_TEST_PT_SWITCH_SCENE_H
#define VBL_TEST_PT_SWITCH_SCENE_H

#include <string.h>

/* A quad light of area 1 (edges e1, e2, unit normal) with radiance L. */
static inline vbl_light pt_switch_quad_light(vbl_vec3 corner, vbl_vec3 e1, vbl_vec3 e2, vbl_vec3 normal, double L)
{
    vbl_light q;
    memset(&q, 0, sizeof q);
    q.type = VBL_LIGHT_QUAD;
    q.corner = corner;
    q.edge1 = e1;
    q.edge2 = e2;
    q.area = 1.0;
    q.normal = normal;
    q.color = vbl_v3(L, L, L);
    return q;
}

/* The scene's Lambert floor (z = -1) and wall (y = 1.2) around the unit sphere's medium. */
static inline void pt_switch_surfaces(vbl_scene* scene)
{
    vbl_material lam = {VBL_MATERIAL_LAMBERT, {0.7, 0.6, 0.5}, {0, 0, 0}, 0.0, 0.0};
    vbl_material wall = {VBL_MATERIAL_LAMBERT, {0.6, 0.7, 0.6}, {0, 0, 0}, 0.0, 0.0};
    add_quad(scene, vbl_v3(0, 0, -1), vbl_v3(2.5, 0, 0), vbl_v3(0, 2.5, 0), &lam);
    add_quad(scene, vbl_v3(0, 1.2, 0.5), vbl_v3(2.5, 0, 0), vbl_v3(0, 0, 1.5), &wall);
}

/* The sphere tt_make_sphere(16, 0.9) (albedo (0.9, 0.8, 0.7), g 0.3, density_scale) seen through
 * a w x h film; quad_only: one 1 x 1 quad light inside the top of the medium and no other light
 * (the paths the three quad strategies share then carry most of volume_direct). The volume goes
 * to *volume (vt_free it after the scene). */
static inline vbl_scene* pt_switch_scene(double density_scale, int quad_only, int w, int h, vbl_volume** volume)
{
    vbl_camera cam = rt_camera(vbl_v3(0.3, -4.0, 0.6), vbl_v3(0, 0, -0.3), 45.0, w, h);
    vbl_scene* scene = tt_scene(&cam);
    *volume = tt_make_sphere(16, 0.9);
    assert_int_equal(vbl_scene_add_medium(scene, *volume, density_scale, vbl_v3(0.9, 0.8, 0.7), 0.3, NULL),
                     VBL_SUCCESS);
    if (!quad_only) {
        tt_add_point(scene, vbl_v3(0.3, -0.2, 1.15), 3.0);
        tt_add_distant(scene, vbl_v3(0.3, 0.5, -1.0), 1.0);
    }
    /* normal -z: emits downward */
    vbl_light q = pt_switch_quad_light(quad_only ? vbl_v3(-0.5, -0.5, 0.35) : vbl_v3(-1.0, -0.6, 1.6),
                                       vbl_v3(0, 1, 0), vbl_v3(1, 0, 0), vbl_v3(0, 0, -1), 2.0);
    assert_int_equal(vbl_scene_add_light(scene, &q), VBL_SUCCESS);
    pt_switch_surfaces(scene);
    return scene;
}

/* check_configs_deterministic on pt_switch_scene(2.0, 0, 12, 10): on1 (one thread) and on2 (two
 * threads) bit-identical, off different from them. */
static inline void pt_switch_check_deterministic(layer_stats_render render, const void* on1, const void* on2,
                                                 const void* off)
{
    vbl_volume* volume;
    vbl_scene* scene = pt_switch_scene(2.0, 0, 12, 10, &volume);
    check_configs_deterministic(render, scene, on1, on2, off);
    vbl_scene_release(scene);
    vt_free(volume);
}

/* A second tt_make_sphere(16, 0.9) overlapping the unit sphere at the origin (half a radius to the
 * right, 0.3 lower) at density_scale, albedo and g: two media of different albedo and phase
 * function. Returns its volume (vt_free it after the scene). */
static inline vbl_volume* pt_switch_add_overlapping_sphere(vbl_scene* scene, double density_scale, vbl_vec3 albedo,
                                                           double g)
{
    vbl_volume* second = tt_make_sphere(16, 0.9);
    vbl_affine shift;
    memset(&shift, 0, sizeof shift);
    shift.m[0][0] = shift.m[1][1] = shift.m[2][2] = 1.0;
    shift.m[0][3] = 0.5;
    shift.m[2][3] = -0.3;
    assert_int_equal(vbl_scene_add_medium(scene, second, density_scale, albedo, g, &shift), VBL_SUCCESS);
    return second;
}

/* pt with its defaults on pt_switch_scene at density scales 1e-8 (nothing scatters) and 1e6 (every
 * walk ends within a voxel): finite films summing to their beauty, with signal. */
static inline void pt_switch_check_extremes(void)
{
    const double scales[2] = {1e-8, 1e6};
    for (int i = 0; i < 2; ++i) {
        vbl_volume* volume;
        vbl_scene* scene = pt_switch_scene(scales[i], 0, 12, 10, &volume);
        vbl_render_options o = tt_options(1, 1, 0, 5);
        o.method = VBL_RENDER_PT;
        o.max_bounces = 3; /* at 1e6 a shadow ray's tracking takes ~1e5 steps: bound the work */
        vbl_film* f = NULL;
        assert_int_equal(vbl_render(scene, &o, &f), VBL_SUCCESS);
        const double total = check_sum_to_beauty(f);
        printf("density scale %g: beauty total %g\n", scales[i], total);
        assert_true(total > 0.0);
        vbl_film_release(f);
        vbl_scene_release(scene);
        vt_free(volume);
    }
}

/* A Lambert floor (z = -1, edges 2 floor_half, albedo floor_albedo) under the sphere
 * tt_make_sphere(16, 0.9) (density_scale, albedo, HG g), lit by one point light of intensity 3 at
 * `light`, seen through `cam`: the floor's shadow rays cross the smoke (test_render_pt_core's
 * pt.surface_direct_rate, test_render_pt_camera_split's pt.sobol_shadow_march). The volume goes to
 * *volume (vt_free it after the scene). */
static inline vbl_scene* pt_floor_under_smoke(vbl_camera cam, double density_scale, vbl_vec3 albedo, double g,
                                              vbl_vec3 light, vbl_vec3 floor_albedo, double floor_half,
                                              vbl_volume** volume)
{
    vbl_scene* scene = tt_scene(&cam);
    *volume = tt_make_sphere(16, 0.9);
    assert_int_equal(vbl_scene_add_medium(scene, *volume, density_scale, albedo, g, NULL), VBL_SUCCESS);
    tt_add_point(scene, light, 3.0);
    vbl_material lam = {VBL_MATERIAL_LAMBERT, {floor_albedo.x, floor_albedo.y, floor_albedo.z}, {0, 0, 0}, 0.0, 0.0};
    add_quad(scene, vbl_v3(0, 0, -1), vbl_v3(floor_half, 0, 0), vbl_v3(0, floor_half, 0), &lam);
    return scene;
}

#endif
