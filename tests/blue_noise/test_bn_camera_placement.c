/* Camera-driven virtual-light placement (Li et al. 2022, section 3.1) in a
 * programmatic open box (floor, back and left Lambert walls, right wall a Phong mirror):
 * candidates lie on the surfaces, face and are unoccluded from the camera sub-path vertex x they
 * were shot from, x is camera-visible (or, after a specular extension, seen in the mirror); no
 * NaN; same candidates on 1 and 2 threads; candidates -> lights. */
#include <math.h>
#include <omp.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "transport/surface/blue_noise/blue_noise_lights.h"
#include "transport/surface/blue_noise/camera_placement.h"
#include "geometry/surfaces.h"
#include "scene/scene.h"
#include "vbl/vbl.h"

typedef struct quad { vbl_vec3 c, u, v; double h; } quad;

static const quad quads[4] = {
    {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 2.0},   /* floor */
    {{0, 2, 2}, {1, 0, 0}, {0, 0, 1}, 2.0},   /* back wall */
    {{-2, 0, 2}, {0, 1, 0}, {0, 0, 1}, 2.0},  /* left wall */
    {{2, 0, 2}, {0, 1, 0}, {0, 0, 1}, 2.0},   /* right wall: mirror */
};

static void add_quad(vbl_scene* scene, const quad* q, const vbl_material* m)
{
    double p[12];
    const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    for (int i = 0; i < 4; ++i) {
        vbl_vec3 x = vbl_v3_add(q->c, vbl_v3_add(vbl_v3_scale(q->u, su[i] * q->h), vbl_v3_scale(q->v, sv[i] * q->h)));
        p[3 * i] = x.x, p[3 * i + 1] = x.y, p[3 * i + 2] = x.z;
    }
    unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    assert_int_equal(vbl_scene_add_mesh(scene, p, 4, idx, 2, m, NULL), VBL_SUCCESS);
}

static vbl_scene* make_scene(void)
{
    vbl_camera cam;
    assert_int_equal(vbl_camera_make(vbl_v3(-0.5, -5.0, 1.6), vbl_v3(0.3, 0.0, 1.0), vbl_v3(0, 0, 1), 55.0, 32, 24, &cam),
                     VBL_SUCCESS);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("bn box", &cam, &scene), VBL_SUCCESS);
    vbl_material white = {VBL_MATERIAL_LAMBERT, {0.7, 0.7, 0.7}, {0, 0, 0}, 0.0, 0.0};
    vbl_material mirror = {VBL_MATERIAL_PHONG, {0.02, 0.02, 0.02}, {0.95, 0.95, 0.95}, 5000.0, 0.0};
    for (int i = 0; i < 3; ++i) add_quad(scene, &quads[i], &white);
    add_quad(scene, &quads[3], &mirror);
    return scene;
}

static int on_quad(vbl_vec3 p, const quad* q)
{
    vbl_vec3 d = vbl_v3_sub(p, q->c), n = vbl_v3_cross(q->u, q->v);
    return fabs(vbl_v3_dot(d, n)) < 1e-5 && fabs(vbl_v3_dot(d, q->u)) <= q->h + 1e-5 &&
           fabs(vbl_v3_dot(d, q->v)) <= q->h + 1e-5;
}

static int which_quad(vbl_vec3 p)
{
    for (int i = 0; i < 4; ++i)
        if (on_quad(p, &quads[i])) return i;
    return -1;
}

static int visible(const vbl_surfaces* s, vbl_vec3 a, vbl_vec3 b)
{
    vbl_vec3 d = vbl_v3_sub(b, a);
    double len = vbl_v3_length(d);
    return !vbl_surfaces_occluded(s, a, vbl_v3_scale(d, 1.0 / len), 1e-5 * len, len * (1.0 - 1e-5));
}

static void test_candidates_on_visible_surfaces(void** state)
{
    (void)state;
    vbl_scene* scene = make_scene();
    vbl_bn_placement_options o = VBL_BN_PLACEMENT_DEFAULT;
    o.candidates = 20000;
    o.seed = 12;
    vbl_bn_candidate* c = NULL;
    size_t n = 0;
    vbl_bn_placement_stats st;
    assert_int_equal(vbl_bn_place_candidates(scene, &o, &c, &n, &st), VBL_SUCCESS);
    printf("placement: %zu traced -> %zu candidates (%zu primary misses, %zu secondary misses, %zu absorbed, "
           "%zu after a specular extension)\n",
           st.traced, n, st.primary_misses, st.secondary_misses, st.absorbed, st.extended);
    assert_int_equal(n + st.primary_misses + st.secondary_misses + st.absorbed, o.candidates);
    assert_true(n > o.candidates / 3); /* the box is open: many rays leave it */
    assert_true(st.extended > 100);
    size_t per_quad[4] = {0}, mirror_checked = 0;
    for (size_t k = 0; k < n; ++k) {
        const vbl_bn_candidate* a = &c[k];
        assert_true(isfinite(a->position.x + a->position.y + a->position.z));
        assert_true(fabs(vbl_v3_length(a->normal) - 1.0) < 1e-9);
        int qy = which_quad(a->position), qx = which_quad(a->from);
        assert_true(qy >= 0 && qx >= 0);
        ++per_quad[qy];
        assert_int_equal(a->surface, qy);
        assert_true(a->pixel < 32u * 24u);
        /* y faces x and nothing lies between them */
        assert_true(vbl_v3_dot(a->normal, vbl_v3_sub(a->from, a->position)) > 0.0);
        /* (segments shorter than 0.05 run along a corner: Embree's float precision decides) */
        if (vbl_v3_length(vbl_v3_sub(a->from, a->position)) > 0.05)
            assert_true(visible(scene->surfaces, a->from, a->position));
        if (a->depth == 0) {
            assert_true(visible(scene->surfaces, scene->camera.position, a->from));
        } else {
            /* extended once through the mirror x = 2: the camera sees x's mirror image through it */
            assert_int_equal(a->depth, 1);
            vbl_vec3 image = vbl_v3(4.0 - a->from.x, a->from.y, a->from.z), cam = scene->camera.position;
            double t = (2.0 - cam.x) / (image.x - cam.x);
            vbl_vec3 m = vbl_v3_add(cam, vbl_v3_scale(vbl_v3_sub(image, cam), t));
            /* (within 0.1 of its edges: the Phong lobe of exponent 5000 is ~0.02 rad wide) */
            assert_true(t > 0.0 && t < 1.0 && fabs(m.y) < 2.1 && fabs(m.z - 2.0) < 2.1);
            ++mirror_checked;
        }
    }
    printf("candidates per surface: floor %zu, back %zu, left %zu, mirror %zu; %zu checked through the mirror\n",
           per_quad[0], per_quad[1], per_quad[2], per_quad[3], mirror_checked);
    for (int i = 0; i < 4; ++i) assert_true(per_quad[i] > 100);

    /* no extension without the specular rule */
    o.max_specular_depth = 0;
    vbl_bn_candidate* c0 = NULL;
    size_t n0 = 0;
    assert_int_equal(vbl_bn_place_candidates(scene, &o, &c0, &n0, &st), VBL_SUCCESS);
    assert_int_equal(st.extended, 0);
    for (size_t k = 0; k < n0; ++k) assert_int_equal(c0[k].depth, 0);
    free(c0);

    /* candidates -> blue-noise lights */
    vbl_bn_light* lights = NULL;
    size_t nl = 0;
    assert_int_equal(vbl_bn_lights_from_candidates(c, n, n / 10, VBL_BN_VSL_ALPHA_DEFAULT, scene->materials,
                                                   (size_t)scene->surface_count, NULL, &lights, &nl),
                     VBL_SUCCESS);
    assert_int_equal(nl, n / 10);
    double rmin = INFINITY, rmax = 0.0;
    for (size_t k = 0; k < nl; ++k) {
        assert_true(isfinite(lights[k].radius) && lights[k].radius > 0.0);
        assert_true(which_quad(lights[k].position) >= 0);
        assert_int_equal(lights[k].diffuse, lights[k].material != 3);
        rmin = fmin(rmin, lights[k].radius);
        rmax = fmax(rmax, lights[k].radius);
    }
    printf("%zu lights, radius (alpha r_max) in [%.4f, %.4f]\n", nl, rmin, rmax);
    free(lights);
    free(c);
    vbl_scene_release(scene);
}

static void test_threads_and_errors(void** state)
{
    (void)state;
    vbl_scene* scene = make_scene();
    vbl_bn_placement_options o = VBL_BN_PLACEMENT_DEFAULT;
    o.candidates = 5000;
    vbl_bn_candidate *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    omp_set_num_threads(1);
    assert_int_equal(vbl_bn_place_candidates(scene, &o, &a, &na, NULL), VBL_SUCCESS);
    omp_set_num_threads(2);
    assert_int_equal(vbl_bn_place_candidates(scene, &o, &b, &nb, NULL), VBL_SUCCESS);
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, na * sizeof *a);
    free(a);
    free(b);
    vbl_scene_release(scene);

    vbl_camera cam;
    assert_int_equal(vbl_camera_make(vbl_v3(0, -3, 1), vbl_v3(0, 0, 0), vbl_v3(0, 0, 1), 40.0, 4, 4, &cam),
                     VBL_SUCCESS);
    vbl_scene* empty = NULL;
    assert_int_equal(vbl_scene_create_empty("no surfaces", &cam, &empty), VBL_SUCCESS);
    assert_int_equal(vbl_bn_place_candidates(empty, &o, &a, &na, NULL), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "no surfaces"));
    vbl_scene_release(empty);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_candidates_on_visible_surfaces),
        cmocka_unit_test(test_threads_and_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
