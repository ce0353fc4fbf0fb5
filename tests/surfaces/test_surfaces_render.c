/* Rendering with surfaces. Fast (no argument): occlusion of shadow rays and camera-ray clipping
 * in every estimator, the layer layout, alpha/Z, and a surface + medium scene whose layers sum
 * to beauty and stay finite. `slow` (statistical, fixed seeds):
 *   - a point light over a Lambert plane: pt's surface_direct against the closed form
 *     L = (albedo / pi) I cos(theta) / d^2 integrated over each pixel (8x8 quadrature);
 *   - a point light at the centre of a closed Lambert sphere of radius R and albedo a: the
 *     irradiance is uniform, E = I / R^2 + a E (a closed sphere sees only itself, view factor 1),
 *     so every pixel sees L = a I / (pi R^2 (1 - a)), split into surface_direct = a I / (pi R^2)
 *     and surface_from_surface = the rest (a = 0.5 and 0.9; 1 / (1 - a) is the furnace identity). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render/render_internal.h"
#include "render_test_util.h"
#include "scene/scene.h"
#include "material/material.h"
#include "transport/path_tracing/pt.h"
#include "vbl/vbl.h"

static vbl_material lambert(double a)
{
    vbl_material m = {VBL_MATERIAL_LAMBERT, {a, a, a}, {0, 0, 0}, 0.0, 0.0};
    return m;
}

/* A square in the plane through `center` spanned by unit u, v (half size h). */
static void add_square(vbl_scene* scene, vbl_vec3 center, vbl_vec3 u, vbl_vec3 v, double h, const vbl_material* m)
{
    double p[12];
    const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    for (int i = 0; i < 4; ++i) {
        vbl_vec3 q = vbl_v3_add(center, vbl_v3_add(vbl_v3_scale(u, su[i] * h), vbl_v3_scale(v, sv[i] * h)));
        p[3 * i] = q.x;
        p[3 * i + 1] = q.y;
        p[3 * i + 2] = q.z;
    }
    unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    assert_int_equal(vbl_scene_add_mesh(scene, p, 4, idx, 2, m, NULL), VBL_SUCCESS);
}

static vbl_light point_light(vbl_vec3 p, double intensity)
{
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_POINT;
    l.position = p;
    l.color = vbl_v3(intensity, intensity, intensity);
    return l;
}

static vbl_light quad_light(vbl_vec3 corner, vbl_vec3 e1, vbl_vec3 e2, double radiance)
{
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_QUAD;
    l.corner = corner;
    l.edge1 = e1;
    l.edge2 = e2;
    l.color = vbl_v3(radiance, radiance, radiance);
    vbl_vec3 n = vbl_v3_cross(e1, e2);
    l.area = vbl_v3_length(n);
    l.normal = vbl_v3_scale(n, 1.0 / l.area);
    return l;
}

static vbl_film* render(const vbl_scene* scene, vbl_render_method method, int passes, int spp, int light_paths,
                        uint64_t seed)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.method = method;
    o.passes = passes;
    o.spp = spp;
    o.light_paths = light_paths;
    o.seed = seed;
    o.threads = 2;
    vbl_film* film = NULL;
    vbl_result r = vbl_render(scene, &o, &film);
    if (r) fail_msg("render: %s", vbl_last_error_message());
    return film;
}

static double layer_max_abs(const vbl_film* film, const char* name)
{
    const float* p = vbl_film_layer_rgb(film, name);
    if (!p) return 0.0;
    double m = 0.0;
    size_t n = (size_t)vbl_film_width(film) * vbl_film_height(film) * 3;
    for (size_t i = 0; i < n; ++i) m = fmax(m, fabs(p[i]));
    return m;
}

static double layer_sum(const vbl_film* film, const char* name)
{
    const float* p = vbl_film_layer_rgb(film, name);
    assert_non_null(p);
    double s = 0.0;
    size_t n = (size_t)vbl_film_width(film) * vbl_film_height(film) * 3;
    for (size_t i = 0; i < n; ++i) s += p[i];
    return s;
}

/* ---- fast -------------------------------------------------------------------------------- */

static vbl_scene* medium_scene(vbl_vec3 cam_pos, vbl_vec3 target, vbl_volume** box)
{
    vbl_camera cam = rt_camera(cam_pos, target, 40.0, 12, 10);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("occlusion", &cam, &scene), VBL_SUCCESS);
    *box = rt_make_box(8, 0.25, vbl_v3(-0.875, -0.875, 0.5)); /* [-0.875, 0.875]^2 x [0.5, 2.25] */
    assert_int_equal(vbl_scene_add_medium(scene, *box, 4.0, vbl_v3(0.8, 0.8, 0.8), 0.0, NULL), VBL_SUCCESS);
    return scene;
}

static void test_shadow_rays_blocked(void** state)
{
    (void)state;
    vbl_volume* box = NULL;
    vbl_scene* scene = medium_scene(vbl_v3(0, -6, 1.4), vbl_v3(0, 0, 1.4), &box);
    vbl_light l = point_light(vbl_v3(0, 0, 6), 50.0);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.passes = 1;
    o.spp = 4;
    o.threads = 2;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render_with_estimator(scene, &o, &vbl_estimator_pt, &film), VBL_SUCCESS);
    double lit = layer_sum(film, "volume_direct");
    assert_true(lit > 0.0);
    vbl_film_release(film);
    /* an opaque roof between the light and the medium: single scattering is exactly zero */
    vbl_material m = lambert(0.5);
    add_square(scene, vbl_v3(0, 0, 4), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), 10.0, &m);
    assert_int_equal(vbl_render_with_estimator(scene, &o, &vbl_estimator_pt, &film), VBL_SUCCESS);
    assert_true(layer_max_abs(film, "volume_direct") == 0.0);
    vbl_film_release(film);
    /* pt, vpl, vrl: no light reaches the medium, nothing scatters in it */
    const vbl_render_method methods[3] = {VBL_RENDER_PT, VBL_RENDER_VPL, VBL_RENDER_VRL};
    for (int i = 0; i < 3; ++i) {
        film = render(scene, methods[i], 1, 2, 200, 3);
        assert_true(layer_max_abs(film, "volume_direct") == 0.0);
        assert_true(layer_max_abs(film, "volume_from_volume") == 0.0);
        vbl_film_release(film);
    }
    vbl_scene_release(scene);
    vbl_volume_release(box);
}

static void test_camera_ray_clipped(void** state)
{
    (void)state;
    vbl_volume* box = NULL;
    vbl_scene* scene = medium_scene(vbl_v3(0, -6, 1.4), vbl_v3(0, 0, 1.4), &box);
    vbl_light l = point_light(vbl_v3(0, -4, 1.4), 50.0); /* on the camera's side of the wall */
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    vbl_material m = lambert(0.5);
    add_square(scene, vbl_v3(0, -2, 1.4), vbl_v3(1, 0, 0), vbl_v3(0, 0, 1), 20.0, &m); /* a wall y = -2 */
    const vbl_render_method methods[3] = {VBL_RENDER_PT, VBL_RENDER_VPL, VBL_RENDER_VRL};
    for (int i = 0; i < 3; ++i) {
        vbl_film* film = render(scene, methods[i], 1, 2, 300, 5);
        /* the camera sees the wall only: no volume class, surface light present */
        assert_true(layer_max_abs(film, "volume_direct") == 0.0);
        assert_true(layer_max_abs(film, "volume_from_volume") == 0.0);
        assert_true(layer_max_abs(film, "volume_from_surface") == 0.0);
        if (methods[i] == VBL_RENDER_PT) assert_true(layer_sum(film, "surface_direct") > 0.0);
        /* alpha 1 and Z = distance to the wall (4 / cos) everywhere */
        int ch = 0;
        const float* beauty = vbl_film_layer(film, "", &ch);
        const float* z = vbl_film_layer(film, "Z", NULL);
        assert_non_null(z);
        for (int p = 0; p < 12 * 10; ++p) {
            assert_true(fabs(beauty[4 * p + 3] - 1.0) < 1e-6);
            assert_true(z[p] >= 4.0 - 1e-4 && z[p] < 4.8);
        }
        vbl_film_release(film);
    }
    vbl_scene_release(scene);
    vbl_volume_release(box);
}

static void test_layers_sum_and_finite(void** state)
{
    (void)state;
    vbl_volume* box = NULL;
    vbl_scene* scene = medium_scene(vbl_v3(0.5, -6, 1.5), vbl_v3(0, 0, 1.0), &box);
    vbl_material floor_m = {VBL_MATERIAL_PHONG, {0.4, 0.4, 0.4}, {0.3, 0.3, 0.3}, 40.0, 0.0};
    vbl_material wall_m = {VBL_MATERIAL_GGX, {0.5, 0.3, 0.2}, {0.04, 0.04, 0.04}, 0.0, 0.3};
    add_square(scene, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), 5.0, &floor_m);
    add_square(scene, vbl_v3(0, 2, 2), vbl_v3(1, 0, 0), vbl_v3(0, 0, 1), 5.0, &wall_m);
    vbl_light l = point_light(vbl_v3(-1, -1, 3), 30.0);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    vbl_light q = quad_light(vbl_v3(1.0, -1.0, 3.5), vbl_v3(0.5, 0, 0), vbl_v3(0, -0.5, 0), 20.0); /* faces down */
    assert_int_equal(vbl_scene_add_light(scene, &q), VBL_SUCCESS);
    static const char* const names[7] = {"background", "surface_direct", "volume_direct", "surface_from_surface",
                                         "surface_from_volume", "volume_from_surface", "volume_from_volume"};
    const vbl_render_method methods[3] = {VBL_RENDER_PT, VBL_RENDER_VRL, VBL_RENDER_VPL};
    for (int mi = 0; mi < 3; ++mi) {
        vbl_film* film = render(scene, methods[mi], 2, 4, 300, 9);
        const float* layers[7];
        for (int c = 0; c < 7; ++c) {
            layers[c] = vbl_film_layer_rgb(film, names[c]);
            if (!layers[c]) fail_msg("missing layer %s", names[c]);
        }
        int ch = 0;
        const float* beauty = vbl_film_layer(film, "", &ch);
        assert_int_equal(ch, 4);
        for (int p = 0; p < 12 * 10; ++p)
            for (int k = 0; k < 3; ++k) {
                float s = 0.0f;
                for (int c = 0; c < 7; ++c) {
                    assert_true(isfinite(layers[c][3 * p + k]) && layers[c][3 * p + k] >= 0.0f);
                    s += layers[c][3 * p + k];
                }
                assert_true(s == beauty[4 * p + k]);
            }
        if (methods[mi] == VBL_RENDER_PT) {
            for (int c = 1; c < 7; ++c)
                if (!(layer_sum(film, names[c]) > 0.0)) fail_msg("pt: layer %s is empty", names[c]);
        }
        vbl_film_release(film);
    }
    vbl_scene_release(scene);
    vbl_volume_release(box);
}

static void test_layout(void** state)
{
    (void)state;
    vbl_camera cam = rt_camera(vbl_v3(0, -3, 1), vbl_v3(0, 0, 0), 40.0, 4, 4);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("layout", &cam, &scene), VBL_SUCCESS);
    vbl_material m = lambert(0.5);
    add_square(scene, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), 2.0, &m);
    vbl_light l = point_light(vbl_v3(0, 0, 2), 1.0);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    vbl_film* film = render(scene, VBL_RENDER_PT, 1, 1, 0, 1);
    assert_non_null(vbl_film_layer_rgb(film, "surface_direct"));
    assert_non_null(vbl_film_layer_rgb(film, "surface_from_surface"));
    assert_null(vbl_film_layer_rgb(film, "volume_from_surface")); /* no media */
    assert_null(vbl_film_layer_rgb(film, "volume_direct"));
    assert_null(vbl_film_layer_rgb(film, "background"));
    assert_true(layer_max_abs(film, "surface_from_surface") == 0.0); /* one plane: no interreflection */
    vbl_film_release(film);
    vbl_scene_release(scene);
}

/* Same seed, different thread counts: identical images (Embree queries are deterministic). */
static void test_thread_count_determinism(void** state)
{
    (void)state;
    vbl_volume* box = NULL;
    vbl_scene* scene = medium_scene(vbl_v3(0.5, -6, 1.5), vbl_v3(0, 0, 1.0), &box);
    vbl_material m = {VBL_MATERIAL_GGX, {0.5, 0.5, 0.5}, {0.04, 0.04, 0.04}, 0.0, 0.2};
    add_square(scene, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), 5.0, &m);
    vbl_light l = point_light(vbl_v3(-1, -1, 3), 30.0);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    const vbl_render_method methods[2] = {VBL_RENDER_PT, VBL_RENDER_VRL};
    for (int mi = 0; mi < 2; ++mi) {
        vbl_film* f[2];
        for (int t = 0; t < 2; ++t) {
            vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
            o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
            o.method = methods[mi];
            o.passes = 1;
            o.spp = 2;
            o.light_paths = 200;
            o.seed = 17;
            o.threads = t + 1;
            assert_int_equal(vbl_render(scene, &o, &f[t]), VBL_SUCCESS);
        }
        const float* a = vbl_film_layer(f[0], "", NULL);
        const float* b = vbl_film_layer(f[1], "", NULL);
        assert_memory_equal(a, b, 12 * 10 * 4 * sizeof(float));
        vbl_film_release(f[0]);
        vbl_film_release(f[1]);
    }
    vbl_scene_release(scene);
    vbl_volume_release(box);
}

/* The sample scenes load and render (tiny, pt) to finite images with the surface layers. */
static void test_samples_render(void** state)
{
    (void)state;
    const char* src = getenv("VBL_SOURCE_DIR");
    const char* bin = getenv("VBL_BINARY_DIR");
    if (!src || !bin) skip();
    char vdb[1024];
    snprintf(vdb, sizeof vdb, "%s/samples/cloud.vdb", bin);
    FILE* f = fopen(vdb, "rb");
    if (!f) skip(); /* target vbl_sample_cloud not built */
    fclose(f);
    const char* names[2] = {"smoky_room.json", "cloud_ground.json"};
    for (int i = 0; i < 2; ++i) {
        char path[1024];
        snprintf(path, sizeof path, "%s/samples/%s", src, names[i]);
        const char* overrides[1] = {vdb};
        vbl_scene_load_options o = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
        o.vdb_overrides = overrides;
        o.vdb_override_count = 1;
        vbl_scene* scene = NULL;
        if (vbl_scene_load_ex(path, &o, &scene)) fail_msg("%s", vbl_last_error_message());
        assert_true(scene->has_surfaces);
        scene->camera.width = 16; /* keep it tiny: the same view at 16 x 12 */
        scene->camera.height = 12;
        vbl_film* film = render(scene, VBL_RENDER_PT, 1, 2, 0, 1);
        assert_non_null(vbl_film_layer_rgb(film, "surface_direct"));
        assert_non_null(vbl_film_layer_rgb(film, "volume_from_surface"));
        assert_true(layer_sum(film, "surface_direct") > 0.0);
        const float* beauty = vbl_film_layer(film, "", NULL);
        for (int p = 0; p < 16 * 12 * 4; ++p) assert_true(isfinite(beauty[p]) && beauty[p] >= 0.0f);
        vbl_film_release(film);
        vbl_scene_release(scene);
    }
}

/* ---- slow ------------------------------------------------------------------------------ */

static void test_point_light_over_plane(void** state)
{
    (void)state;
    const int W = 16, H = 12;
    const double albedo = 0.6, I = 10.0;
    const vbl_vec3 light = vbl_v3(0.3, 0.2, 2.0);
    vbl_camera cam = rt_camera(vbl_v3(0, -1, 4), vbl_v3(0, 0, 0), 60.0, W, H);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("plane", &cam, &scene), VBL_SUCCESS);
    vbl_material m = lambert(albedo);
    add_square(scene, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), 20.0, &m);
    vbl_light l = point_light(light, I);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    vbl_film* film = render(scene, VBL_RENDER_PT, 4, 64, 0, 21);
    const float* sd = vbl_film_layer_rgb(film, "surface_direct");
    const float* var = vbl_film_layer_rgb(film, "variance");
    assert_non_null(sd);
    assert_non_null(var);
    assert_true(layer_max_abs(film, "surface_from_surface") == 0.0);
    double worst = 0.0, sum = 0.0, sum_ref = 0.0, var_sum = 0.0;
    for (int py = 0; py < H; ++py)
        for (int px = 0; px < W; ++px) {
            double ref = 0.0;
            const int Q = 16;
            for (int j = 0; j < Q; ++j)
                for (int i = 0; i < Q; ++i) {
                    vbl_vec3 o, d;
                    vbl_camera_ray(&cam, px + (i + 0.5) / Q, py + (j + 0.5) / Q, &o, &d);
                    double t = -o.z / d.z;
                    vbl_vec3 x = vbl_v3_madd(o, d, t);
                    vbl_vec3 to = vbl_v3_sub(light, x);
                    double d2 = vbl_v3_dot(to, to);
                    ref += albedo / VBL_PI * I * (to.z / sqrt(d2)) / d2;
                }
            ref /= Q * Q;
            int p = py * W + px;
            double got = sd[3 * p];
            double se = sqrt(var[3 * p]);
            double z = fabs(got - ref) / (se + 2e-3 * ref);
            worst = fmax(worst, z);
            sum += got;
            sum_ref += ref;
            var_sum += var[3 * p];
        }
    printf("plane: worst pixel |err|/(se + 0.2%%) = %.2f, image mean %.6f vs %.6f (se %.2g)\n", worst, sum / (W * H),
           sum_ref / (W * H), sqrt(var_sum) / (W * H));
    assert_true(worst < 5.0);
    assert_true(fabs(sum - sum_ref) < 4.0 * sqrt(var_sum) + 1e-3 * sum_ref);
    vbl_film_release(film);
    vbl_scene_release(scene);
}

/* A closed UV sphere of radius R (poles give degenerate triangles, dropped on load). */
static void add_sphere(vbl_scene* scene, double R, int nlat, int nlon, const vbl_material* m)
{
    int nv = (nlat + 1) * nlon;
    double* p = malloc(3 * (size_t)nv * sizeof(double));
    unsigned* idx = malloc(6 * (size_t)nlat * nlon * sizeof(unsigned));
    assert_non_null(p);
    assert_non_null(idx);
    for (int i = 0; i <= nlat; ++i)
        for (int j = 0; j < nlon; ++j) {
            double th = VBL_PI * i / nlat, ph = 2.0 * VBL_PI * j / nlon;
            int k = i * nlon + j;
            p[3 * k] = R * sin(th) * cos(ph);
            p[3 * k + 1] = R * sin(th) * sin(ph);
            p[3 * k + 2] = R * cos(th);
        }
    size_t t = 0;
    for (int i = 0; i < nlat; ++i)
        for (int j = 0; j < nlon; ++j) {
            unsigned a = i * nlon + j, b = i * nlon + (j + 1) % nlon, c = (i + 1) * nlon + j,
                     d = (i + 1) * nlon + (j + 1) % nlon;
            idx[3 * t] = a, idx[3 * t + 1] = c, idx[3 * t + 2] = b, ++t;
            idx[3 * t] = b, idx[3 * t + 1] = c, idx[3 * t + 2] = d, ++t;
        }
    assert_int_equal(vbl_scene_add_mesh(scene, p, (size_t)nv, idx, t, m, NULL), VBL_SUCCESS);
    assert_true(scene->dropped_triangles > 0); /* the pole triangles */
    free(p);
    free(idx);
}

static void sphere_furnace(double a)
{
    const int W = 12, H = 12;
    const double R = 1.0, I = 2.0;
    vbl_camera cam = rt_camera(vbl_v3(0.2, -0.1, 0.1), vbl_v3(0.3, 1.0, 0.3), 70.0, W, H);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("sphere", &cam, &scene), VBL_SUCCESS);
    vbl_material m = lambert(a);
    add_sphere(scene, R, 64, 128, &m);
    vbl_light l = point_light(vbl_v3(0, 0, 0), I);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    vbl_film* film = render(scene, VBL_RENDER_PT, 4, 128, 0, 77);
    const float* beauty = vbl_film_layer(film, "", NULL);
    const float* var = vbl_film_layer_rgb(film, "variance");
    double sum = 0.0, var_sum = 0.0;
    for (int p = 0; p < W * H; ++p) {
        sum += beauty[4 * p];
        var_sum += var[3 * p];
    }
    double mean = sum / (W * H), se = sqrt(var_sum) / (W * H);
    double direct = a * I / (VBL_PI * R * R), expect = direct / (1.0 - a);
    double sd = layer_sum(film, "surface_direct") / (3.0 * W * H);
    double sfs = layer_sum(film, "surface_from_surface") / (3.0 * W * H);
    printf("sphere a = %.2f: L = %.5f (se %.2g) vs %.5f; direct %.5f vs %.5f; from_surface %.5f vs %.5f\n", a, mean,
           se, expect, sd, direct, sfs, expect - direct);
    /* tessellation (64 x 128 facets) moves the closed form by about 0.1%: 0.5% allowance */
    assert_true(fabs(mean - expect) < 4.0 * se + 5e-3 * expect);
    assert_true(fabs(sd - direct) < 5e-3 * direct);
    assert_true(fabs(sfs - (expect - direct)) < 4.0 * se + 5e-3 * expect);
    vbl_film_release(film);
    vbl_scene_release(scene);
}

static void test_sphere_furnace(void** state)
{
    (void)state;
    sphere_furnace(0.5);
    sphere_furnace(0.9);
}

/* A scene with surfaces and no medium: the virtual-light methods still trace light paths for the
 * surface VSLs (they used to return early without media, leaving surface_from_surface black).
 * vpl's surface_from_surface (R = 0, unbiased) matches pt's image mean on a floor + wall lit by
 * a point light. */
static void test_surfaces_only_indirect(void** state)
{
    (void)state;
    const int W = 8, H = 6;
    vbl_camera cam = rt_camera(vbl_v3(0.5, -3.0, 1.5), vbl_v3(0, 0.5, 0.5), 45.0, W, H);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("surfaces-only", &cam, &scene), VBL_SUCCESS);
    vbl_material m = lambert(0.8);
    add_square(scene, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), 2.0, &m);   /* floor */
    add_square(scene, vbl_v3(0, 1.0, 1.0), vbl_v3(1, 0, 0), vbl_v3(0, 0, 1), 2.0, &m); /* wall */
    vbl_light l = point_light(vbl_v3(0.3, 0.2, 1.2), 5.0);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    double mean[2], se[2];
    const vbl_render_method methods[2] = {VBL_RENDER_PT, VBL_RENDER_VPL};
    for (int k = 0; k < 2; ++k) {
        vbl_film* film = k == 0 ? render(scene, VBL_RENDER_PT, 8, 32, 0, 31) : render(scene, methods[k], 16, 1, 400, 37);
        const float* sfs = vbl_film_layer_rgb(film, "surface_from_surface");
        assert_non_null(sfs);
        double sum = 0.0;
        for (int p = 0; p < W * H; ++p) sum += sfs[3 * p + 1];
        mean[k] = sum / (W * H);
        vbl_film_release(film);
    }
    /* spread over seeds for the standard errors: 4 more seeds each, one film each */
    double sq[2] = {0.0, 0.0}, m2[2] = {0.0, 0.0};
    for (int k = 0; k < 2; ++k)
        for (int r = 0; r < 4; ++r) {
            vbl_film* film = k == 0 ? render(scene, VBL_RENDER_PT, 8, 32, 0, 100 + r)
                                    : render(scene, VBL_RENDER_VPL, 16, 1, 400, 200 + r);
            const float* sfs = vbl_film_layer_rgb(film, "surface_from_surface");
            double sum = 0.0;
            for (int p = 0; p < W * H; ++p) sum += sfs[3 * p + 1];
            double v = sum / (W * H);
            m2[k] += v / 5.0;
            sq[k] += v * v;
            vbl_film_release(film);
        }
    for (int k = 0; k < 2; ++k) {
        m2[k] += mean[k] / 5.0;
        sq[k] += mean[k] * mean[k];
        double var = (sq[k] - 5.0 * m2[k] * m2[k]) / 4.0;
        se[k] = sqrt(fmax(var, 0.0) / 5.0);
    }
    double z = fabs(m2[0] - m2[1]) / sqrt(se[0] * se[0] + se[1] * se[1] + 1e-30);
    printf("surfaces only: surface_from_surface pt %.5f +- %.2g, vpl %.5f +- %.2g, z %.2f\n", m2[0], se[0], m2[1],
           se[1], z);
    assert_true(m2[1] > 0.0);
    assert_true(z < 4.0);
    vbl_scene_release(scene);
}

/* White furnace: albedo-1 Lambert surfaces under a uniform environment of radiance 1. A closed
 * cube standing on a floor, next to a wall (concave corners, so light bounces several times
 * between surfaces before it escapes): L = 1 solves the rendering equation at every visible
 * point, so every pixel of the beauty must be 1 within noise, whatever the geometry; the cube's
 * faces and the corners exercise surface_direct + surface_from_surface (energy conservation of
 * pt with surfaces, BRDF sampling, NEE to the environment and MIS). */
static void test_white_furnace(void** state)
{
    (void)state;
    const int W = 8, H = 6;
    vbl_camera cam = rt_camera(vbl_v3(2.5, -3.0, 2.0), vbl_v3(0, 0, 0.4), 45.0, W, H);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("furnace", &cam, &scene), VBL_SUCCESS);
    vbl_material white = lambert(1.0);
    const vbl_vec3 X = vbl_v3(1, 0, 0), Y = vbl_v3(0, 1, 0), Z = vbl_v3(0, 0, 1);
    add_square(scene, vbl_v3(0, 0, 0), X, Y, 3.0, &white);            /* floor */
    add_square(scene, vbl_v3(0, 1.0, 1.5), X, Z, 3.0, &white);        /* wall behind the cube */
    const double h = 0.4;                                             /* cube [-h, h]^2 x [0, 2h] */
    add_square(scene, vbl_v3(0, 0, 0.001), X, Y, h, &white);
    add_square(scene, vbl_v3(0, 0, 2 * h), X, Y, h, &white);
    add_square(scene, vbl_v3(-h, 0, h), Y, Z, h, &white);
    add_square(scene, vbl_v3(h, 0, h), Y, Z, h, &white);
    add_square(scene, vbl_v3(0, -h, h), X, Z, h, &white);
    add_square(scene, vbl_v3(0, h, h), X, Z, h, &white);
    vbl_light env;
    memset(&env, 0, sizeof env);
    env.type = VBL_LIGHT_ENVIRONMENT;
    env.color = vbl_v3(1.0, 1.0, 1.0);
    assert_int_equal(vbl_scene_add_light(scene, &env), VBL_SUCCESS);
    vbl_film* film = render(scene, VBL_RENDER_PT, 8, 64, 0, 17);
    int ch = 0;
    const float* beauty = vbl_film_layer(film, "", &ch);
    const float* var = vbl_film_layer_rgb(film, "variance");
    const float* sfs = vbl_film_layer_rgb(film, "surface_from_surface");
    assert_non_null(beauty);
    assert_non_null(var);
    assert_non_null(sfs);
    double sum = 0.0, vs = 0.0, worst = 0.0, bounced = 0.0;
    for (int p = 0; p < W * H; ++p) {
        double v = beauty[ch * p], se = sqrt(fmax(var[3 * p], 1e-12));
        sum += v;
        vs += var[3 * p];
        worst = fmax(worst, fabs(v - 1.0) / se);
        bounced += sfs[3 * p];
    }
    double mean = sum / (W * H), se = sqrt(vs) / (W * H);
    printf("white furnace: image mean %.5f (se %.2g), worst pixel %.2f se, surface_from_surface mean %.3f\n", mean,
           se, worst, bounced / (W * H));
    assert_true(fabs(mean - 1.0) < 4.0 * se + 1e-4);
    assert_true(worst < 5.0);
    assert_true(bounced / (W * H) > 0.05); /* the corners really bounce light */
    vbl_film_release(film);
    vbl_scene_release(scene);
}

/* A Lambert plane under a uniform environment sees L = albedo L_env exactly (irradiance
 * pi L_env); a Phong plane's surface_direct under a quad light against a quadrature of
 * f L cos cos' / d^2 over the light (pixel-averaged): both exercise NEE + BRDF sampling + MIS. */
static void test_environment_and_quad_mis(void** state)
{
    (void)state;
    const int W = 8, H = 6;
    vbl_camera cam = rt_camera(vbl_v3(0, -2, 3), vbl_v3(0, 0, 0), 40.0, W, H);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("env", &cam, &scene), VBL_SUCCESS);
    vbl_material m = lambert(0.7);
    add_square(scene, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), 100.0, &m);
    vbl_light env;
    memset(&env, 0, sizeof env);
    env.type = VBL_LIGHT_ENVIRONMENT;
    env.color = vbl_v3(0.5, 0.5, 0.5);
    assert_int_equal(vbl_scene_add_light(scene, &env), VBL_SUCCESS);
    vbl_film* film = render(scene, VBL_RENDER_PT, 4, 64, 0, 5);
    const float* sd = vbl_film_layer_rgb(film, "surface_direct");
    const float* var = vbl_film_layer_rgb(film, "variance");
    double sum = 0.0, vs = 0.0;
    for (int p = 0; p < W * H; ++p) {
        sum += sd[3 * p];
        vs += var[3 * p];
    }
    double mean = sum / (W * H), se = sqrt(vs) / (W * H);
    printf("environment: %.5f (se %.2g) vs %.5f\n", mean, se, 0.35);
    assert_true(fabs(mean - 0.35) < 4.0 * se + 1e-4);
    vbl_film_release(film);
    vbl_scene_release(scene);

    /* glossy plane, quad light facing down at height 1.5 */
    assert_int_equal(vbl_scene_create_empty("quad", &cam, &scene), VBL_SUCCESS);
    vbl_material ph = {VBL_MATERIAL_PHONG, {0.3, 0.3, 0.3}, {0.5, 0.5, 0.5}, 20.0, 0.0};
    add_square(scene, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), 100.0, &ph);
    vbl_light q = quad_light(vbl_v3(-0.5, 0.5, 1.5), vbl_v3(1.0, 0, 0), vbl_v3(0, -1.0, 0), 2.0);
    assert_true(q.normal.z < 0.0);
    assert_int_equal(vbl_scene_add_light(scene, &q), VBL_SUCCESS);
    film = render(scene, VBL_RENDER_PT, 4, 64, 0, 6);
    sd = vbl_film_layer_rgb(film, "surface_direct");
    var = vbl_film_layer_rgb(film, "variance");
    double got = 0.0, ref = 0.0;
    vs = 0.0;
    for (int py = 0; py < H; ++py)
        for (int px = 0; px < W; ++px) {
            const int S = 4, G = 120;
            double r = 0.0;
            for (int j = 0; j < S; ++j)
                for (int i = 0; i < S; ++i) {
                    vbl_vec3 o, d;
                    vbl_camera_ray(&cam, px + (i + 0.5) / S, py + (j + 0.5) / S, &o, &d);
                    vbl_vec3 x = vbl_v3_madd(o, d, -o.z / d.z);
                    vbl_vec3 wo = vbl_v3_scale(d, -1.0), n = vbl_v3(0, 0, 1);
                    for (int b = 0; b < G; ++b)
                        for (int a = 0; a < G; ++a) {
                            vbl_vec3 y = vbl_v3_add(q.corner, vbl_v3_add(vbl_v3_scale(q.edge1, (a + 0.5) / G),
                                                                          vbl_v3_scale(q.edge2, (b + 0.5) / G)));
                            vbl_vec3 to = vbl_v3_sub(y, x);
                            double d2 = vbl_v3_dot(to, to);
                            vbl_vec3 wi = vbl_v3_scale(to, 1.0 / sqrt(d2));
                            vbl_vec3 f = vbl_material_eval(&ph, n, wo, wi);
                            r += f.x * q.color.x * wi.z * (-vbl_v3_dot(wi, q.normal)) / d2 * q.area / (G * G);
                        }
                }
            r /= S * S;
            ref += r;
            got += sd[3 * (py * W + px)];
            vs += var[3 * (py * W + px)];
        }
    se = sqrt(vs) / (W * H);
    printf("quad over phong: %.5f (se %.2g) vs quadrature %.5f\n", got / (W * H), se, ref / (W * H));
    assert_true(fabs(got - ref) / (W * H) < 4.0 * se + 2e-3 * ref / (W * H));
    vbl_film_release(film);
    vbl_scene_release(scene);
}

/* Black (albedo 0) surfaces only occlude: a roof shading half of the medium and a wall cutting
 * it in two. pt and vrl must then agree on the volume layers (photon paths, VRL segments, VRL
 * connections and shadow rays all stop at surfaces). */
static double sum_se(const vbl_film* film, double* se)
{
    const float* var = vbl_film_layer_rgb(film, "variance");
    const float* beauty = vbl_film_layer(film, "", NULL);
    int n = vbl_film_width(film) * vbl_film_height(film);
    double s = 0.0, v = 0.0;
    for (int p = 0; p < n; ++p) {
        s += beauty[4 * p];
        v += var[3 * p];
    }
    *se = sqrt(v) / n;
    return s / n;
}

static void test_occluded_media_agreement(void** state)
{
    (void)state;
    vbl_volume* box = NULL;
    vbl_scene* scene = medium_scene(vbl_v3(0.3, -6, 1.4), vbl_v3(0, 0, 1.4), &box);
    scene->camera = rt_camera(vbl_v3(0.3, -6, 1.4), vbl_v3(0, 0, 1.4), 30.0, 16, 12);
    vbl_light l = point_light(vbl_v3(0.2, -0.3, 5), 40.0);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    vbl_material black = lambert(0.0);
    add_square(scene, vbl_v3(1.5, 0, 2.6), vbl_v3(1, 0, 0), vbl_v3(0, 1, 0), 1.5, &black);   /* roof over x > 0 */
    add_square(scene, vbl_v3(0, 0.1, 1.5), vbl_v3(0, 1, 0), vbl_v3(0, 0, 1), 1.5, &black);   /* wall x = 0 */
    vbl_film* pt = render(scene, VBL_RENDER_PT, 8, 16, 0, 101);
    vbl_film* vrl = render(scene, VBL_RENDER_VRL, 12, 4, 2000, 202);
    double se_pt, se_vrl;
    double a = sum_se(pt, &se_pt), b = sum_se(vrl, &se_vrl);
    int n = 16 * 12;
    printf("occluded media: pt %.5f (se %.2g) vrl %.5f (se %.2g); volume_direct %.5f / %.5f, "
           "volume_from_volume %.5f / %.5f\n",
           a, se_pt, b, se_vrl, layer_sum(pt, "volume_direct") / (3 * n), layer_sum(vrl, "volume_direct") / (3 * n),
           layer_sum(pt, "volume_from_volume") / (3 * n), layer_sum(vrl, "volume_from_volume") / (3 * n));
    assert_true(a > 0.0);
    assert_true(fabs(a - b) < 4.0 * sqrt(se_pt * se_pt + se_vrl * se_vrl) + 5e-3 * a);
    assert_true(layer_max_abs(pt, "surface_direct") == 0.0); /* black surfaces reflect nothing */
    vbl_film_release(pt);
    vbl_film_release(vrl);
    vbl_scene_release(scene);
    vbl_volume_release(box);
}

int main(int argc, char** argv)
{
    const struct CMUnitTest fast[] = {
        cmocka_unit_test(test_layout),
        cmocka_unit_test(test_shadow_rays_blocked),
        cmocka_unit_test(test_camera_ray_clipped),
        cmocka_unit_test(test_layers_sum_and_finite),
        cmocka_unit_test(test_thread_count_determinism),
        cmocka_unit_test(test_samples_render),
    };
    const struct CMUnitTest slow[] = {
        cmocka_unit_test(test_point_light_over_plane),
        cmocka_unit_test(test_sphere_furnace),
        cmocka_unit_test(test_white_furnace),
        cmocka_unit_test(test_surfaces_only_indirect),
        cmocka_unit_test(test_environment_and_quad_mis),
        cmocka_unit_test(test_occluded_media_agreement),
    };
    if (argc > 1 && !strcmp(argv[1], "slow")) return cmocka_run_group_tests(slow, NULL, NULL);
    return cmocka_run_group_tests(fast, NULL, NULL);
}
