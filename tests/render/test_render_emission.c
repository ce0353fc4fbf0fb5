/* Emissive media (issue 15): blackbody chromaticities against the published Planckian locus,
 * the emission-only homogeneous box against L = Le (1 - exp(-sigma_t d)) with pt, the layer it
 * goes to, and the scene file's role grids with their error messages (missing role grid, wrong
 * grid type, bad voxel values). */
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
#include "render/render_internal.h"
#include "material/material.h"
#include "media/media_emission.h"
#include "vbl/vbl.h"
#include "volume/blackbody.h"

/* ---- blackbody ----------------------------------------------------------------------------- */

/* The published CIE 1931 (x, y) chromaticities of the Planckian locus, 4 decimals (Wyszecki
 * and Stiles 1982, Color Science, 2nd ed.; the same values as the Wikipedia "Planckian locus"
 * table). */
static const double k_locus[][3] = {
    {1000, 0.6528, 0.3444}, {1500, 0.5857, 0.3931}, {2000, 0.5267, 0.4133}, {2500, 0.4770, 0.4137},
    {3000, 0.4369, 0.4041}, {4000, 0.3805, 0.3768}, {5000, 0.3451, 0.3516}, {6000, 0.3221, 0.3318},
    {6500, 0.3135, 0.3237}, {7000, 0.3064, 0.3166}, {8000, 0.2952, 0.3048}, {10000, 0.2807, 0.2884}};

static void test_blackbody_chromaticity(void** state)
{
    (void)state;
    for (size_t i = 0; i < sizeof k_locus / sizeof k_locus[0]; ++i) {
        for (int norm = 0; norm < 2; ++norm) {
            double xyz[3];
            vbl_blackbody_xyz(k_locus[i][0], (vbl_blackbody_normalization)norm, xyz);
            double s = xyz[0] + xyz[1] + xyz[2];
            double x = xyz[0] / s, y = xyz[1] / s;
            if (norm == 0)
                printf("%5.0f K: x %.5f (%.4f) y %.5f (%.4f)\n", k_locus[i][0], x, k_locus[i][1], y, k_locus[i][2]);
            assert_true(fabs(x - k_locus[i][1]) < 1e-3);
            assert_true(fabs(y - k_locus[i][2]) < 1e-3);
            if (norm == VBL_BLACKBODY_LUMINANCE) assert_true(fabs(xyz[1] - 1.0) < 1e-12);
        }
    }
    /* peak normalisation: brighter with temperature over the visible range, dark when cold */
    double prev = 0.0;
    for (int t = 500; t <= 5000; t += 500) {
        double xyz[3];
        vbl_blackbody_xyz(t, VBL_BLACKBODY_PEAK, xyz);
        assert_true(xyz[1] > prev);
        prev = xyz[1];
    }
    double cold[3];
    vbl_blackbody_xyz(300.0, VBL_BLACKBODY_PEAK, cold);
    assert_true(cold[1] < 1e-20);
    /* 6504 K is near the D65 white of Rec.709 (D65 lies 0.005 off the locus), 2000 K orange */
    vbl_vec3 w = vbl_blackbody_rgb(6504.0, VBL_BLACKBODY_LUMINANCE);
    printf("6504 K rgb %.4f %.4f %.4f\n", w.x, w.y, w.z);
    assert_true(fabs(w.x - 1.0) < 0.1 && fabs(w.y - 1.0) < 0.1 && fabs(w.z - 1.0) < 0.1);
    vbl_vec3 o = vbl_blackbody_rgb(2000.0, VBL_BLACKBODY_LUMINANCE);
    assert_true(o.x > o.y && o.y > o.z);
    /* the table interpolates the direct computation */
    vbl_blackbody_table table;
    assert_true(vbl_blackbody_table_build(&table, VBL_BLACKBODY_PEAK));
    const double temps[] = {0.0, -5.0, 812.5, 1500.25, 3333.3, 9000.0, 16383.5, 20000.0};
    for (size_t i = 0; i < sizeof temps / sizeof temps[0]; ++i) {
        vbl_vec3 a = vbl_blackbody_table_rgb(&table, temps[i]), b = vbl_blackbody_rgb(temps[i], VBL_BLACKBODY_PEAK);
        double m = fmax(1e-30, vbl_v3_max_component(b));
        assert_true(fabs(a.x - b.x) <= 2e-3 * m + 1e-9 && fabs(a.y - b.y) <= 2e-3 * m + 1e-9 &&
                    fabs(a.z - b.z) <= 2e-3 * m + 1e-9);
        assert_true(a.x >= 0.0 && a.y >= 0.0 && a.z >= 0.0);
    }
    vbl_blackbody_table_free(&table);
}

/* ---- emission-only homogeneous box --------------------------------------------------------- */

static void image_mean(const vbl_film* film, const char* layer, int ch, double* mean, double* se)
{
    int w = vbl_film_width(film), h = vbl_film_height(film), c = 0, cv = 0;
    const float* p = vbl_film_layer(film, layer, &c);
    const float* var = vbl_film_layer(film, "variance", &cv);
    assert_non_null(p);
    assert_non_null(var);
    double s = 0.0, v = 0.0;
    for (int i = 0; i < w * h; ++i) {
        assert_true(isfinite(p[i * c + ch]));
        s += p[i * c + ch];
        v += var[i * 3 + ch];
    }
    *mean = s / (w * h);
    *se = sqrt(v) / (w * h);
}

/* Density box of n voxels on [-1, 1]^3 (trilinear: optical depth n h along an axis through its
 * plateau), albedo 0, emission grid a larger constant box so Le is constant wherever
 * sigma_a > 0. Far camera, 1 degree fov: every ray crosses the plateau along ~x. n = 9: every
 * majorant block touches the boundary ramp (tentative points, heterogeneous segments); n = 41:
 * inner blocks are homogeneous (analytic flights, the collision estimator). */
/* An estimator outside the list of those that render emissive media (render.c): adds nothing. */
static void no_emission_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                                      const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    (void)ctx, (void)store, (void)ts, (void)sample, (void)rng, (void)out;
}
static const vbl_estimator no_emission_estimator = {"test-no-emission", 0, NULL, no_emission_camera_sample, NULL, NULL};

static void emission_box(int n)
{
    const double half = 1.0, h = 2.0 * half / (n - 1), sigma = 0.7;
    const int m = n + 4;
    vbl_volume* density = rt_make_box(n, h, vbl_v3(-half, -half, -half));
    vbl_volume* emission = rt_make_box(m, h, vbl_v3(-half - 2 * h, -half - 2 * h, -half - 2 * h));
    assert_non_null(density);
    assert_non_null(emission);
    vbl_camera cam = rt_camera(vbl_v3(50.0, 0.0, 0.0), vbl_v3(0, 0, 0), 1.0, 8, 8);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("emission_box", &cam, &scene), VBL_SUCCESS);
    assert_int_equal(vbl_scene_add_medium(scene, density, sigma, vbl_v3(0, 0, 0), 0.0, NULL), VBL_SUCCESS);
    const vbl_vec3 color = vbl_v3(1.0, 0.5, 0.25);
    const double scale = 2.0;
    assert_int_equal(vbl_scene_set_medium_emission(scene, 0, emission, color, scale, NULL, 1.0, 0.0, 0.0,
                                                   VBL_BLACKBODY_PEAK),
                     VBL_SUCCESS);
    assert_true(scene->has_emission);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.passes = 2;
    o.spp = 128;
    o.max_bounces = -1;
    o.seed = 5;
    o.threads = 2;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    const double tau = sigma * n * h;
    const double expected[3] = {scale * color.x * -expm1(-tau), scale * color.y * -expm1(-tau),
                                scale * color.z * -expm1(-tau)};
    int channels = 0;
    assert_non_null(vbl_film_layer(film, "volume_emission", &channels));
    double scattered, scattered_se;
    image_mean(film, "volume_direct", 0, &scattered, &scattered_se); /* albedo 0: nothing scatters */
    assert_true(scattered == 0.0);
    for (int ch = 0; ch < 3; ++ch) {
        double mean, se, layer_mean, layer_se;
        image_mean(film, "", ch, &mean, &se);
        image_mean(film, "volume_emission", ch, &layer_mean, &layer_se);
        printf("emission box n=%d channel %d: mean %.5f se %.5f expected %.5f (%.2f se)\n", n, ch, mean, se, expected[ch],
               fabs(mean - expected[ch]) / se);
        assert_true(se > 0.0 && se < 0.01 * expected[ch]);
        assert_true(fabs(mean - expected[ch]) <= 4.0 * se);
        assert_true(fabs(layer_mean - mean) <= 1e-6 * mean); /* the only layer: it is the beauty */
    }
    vbl_film_release(film);
    /* an estimator that does not transport emission (here a test estimator that adds nothing)
     * refuses the scene: a clear error, not a dark image (the methods do:
     * test_render_emission_methods.c) */
    o.passes = 1;
    assert_int_equal(vbl_render_with_estimator(scene, &o, &no_emission_estimator, &film), VBL_ERROR_UNSUPPORTED);
    assert_non_null(strstr(vbl_last_error_message(), "emissive media"));
    /* albedo 1 absorbs nothing, so it emits nothing: no emission work at all */
    vbl_scene* white = NULL;
    assert_int_equal(vbl_scene_create_empty("white", &cam, &white), VBL_SUCCESS);
    assert_int_equal(vbl_scene_add_medium(white, density, sigma, vbl_v3(1, 1, 1), 0.0, NULL), VBL_SUCCESS);
    assert_int_equal(vbl_scene_set_medium_emission(white, 0, emission, color, scale, NULL, 1.0, 0.0, 0.0,
                                                   VBL_BLACKBODY_PEAK),
                     VBL_SUCCESS);
    assert_false(white->has_emission);
    assert_int_equal(vbl_scene_set_medium_emission(white, 0, emission, vbl_v3(-1, 0, 0), scale, NULL, 1.0, 0.0, 0.0,
                                                   VBL_BLACKBODY_PEAK),
                     VBL_ERROR_INVALID_ARGUMENT);
    vbl_scene_release(white);
    vbl_scene_release(scene);
    vbl_volume_release(density);
    vbl_volume_release(emission);
}

static void test_emission_box_closed_form(void** state)
{
    (void)state;
    emission_box(9);
    emission_box(41);
}

/* ---- emissive media as light sources -------------------------------------------------------- */

/* NEE towards emissive media (MIS with phase/BRDF sampling) against the pure collision
 * (tracking) estimator: a scattering emissive box (albedo 0.7) over a Lambertian floor, both
 * strategies unbiased, so every layer's image mean agrees within k sigma; NEE is less noisy on
 * the floor. */
static void test_emission_nee_vs_tracking(void** state)
{
    (void)state;
    const int n = 9;
    const double half = 0.5, h = 2.0 * half / (n - 1);
    vbl_volume* density = rt_make_box(n, h, vbl_v3(-half, -half, -half));
    vbl_volume* emission = rt_make_box(n, h, vbl_v3(-half, -half, -half)); /* Le ramps like density */
    vbl_camera cam = rt_camera(vbl_v3(3.0, -3.0, 1.5), vbl_v3(0, 0, -0.6), 45.0, 10, 10);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("emission_nee", &cam, &scene), VBL_SUCCESS);
    assert_int_equal(vbl_scene_add_medium(scene, density, 2.0, vbl_v3(0.7, 0.7, 0.7), 0.3, NULL), VBL_SUCCESS);
    assert_int_equal(vbl_scene_set_medium_emission(scene, 0, emission, vbl_v3(1.0, 0.6, 0.3), 3.0, NULL, 1.0, 0.0, 0.0,
                                                   VBL_BLACKBODY_PEAK),
                     VBL_SUCCESS);
    assert_true(scene->emission_lights.count > 0);
    double p[12] = {-3, -3, -0.8, 3, -3, -0.8, 3, 3, -0.8, -3, 3, -0.8};
    unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    vbl_material floor;
    memset(&floor, 0, sizeof floor);
    floor.type = VBL_MATERIAL_LAMBERT;
    floor.albedo = vbl_v3(0.6, 0.6, 0.6);
    assert_int_equal(vbl_scene_add_mesh(scene, p, 4, idx, 2, &floor, NULL), VBL_SUCCESS);
    const char* layers[] = {"", "volume_emission", "volume_direct", "volume_from_volume", "surface_direct",
                            "surface_from_volume"};
    /* the variance AOV is the beauty's: per-layer errors from R independent renders instead */
    enum { R = 8 };
    double mean[2][6], se[2][6];
    for (int nee = 1; nee >= 0; --nee) {
        scene->emission_nee = nee;
        double sum[6] = {0}, sq[6] = {0};
        for (int r = 0; r < R; ++r) {
            vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
            o.passes = 1;
            o.spp = 16;
            o.max_bounces = -1;
            o.seed = 100 + (uint64_t)r;
            o.threads = 2;
            vbl_film* film = NULL;
            assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
            for (int l = 0; l < 6; ++l) {
                double m3 = 0.0;
                for (int ch = 0; ch < 3; ++ch) {
                    double m, e;
                    image_mean(film, layers[l], ch, &m, &e);
                    m3 += m;
                }
                sum[l] += m3;
                sq[l] += m3 * m3;
            }
            vbl_film_release(film);
        }
        for (int l = 0; l < 6; ++l) {
            mean[nee][l] = sum[l] / R;
            se[nee][l] = sqrt(fmax(0.0, sq[l] / R - mean[nee][l] * mean[nee][l]) / (R - 1));
        }
    }
    for (int l = 0; l < 6; ++l) {
        double diff = mean[1][l] - mean[0][l], sigma = sqrt(se[0][l] * se[0][l] + se[1][l] * se[1][l]);
        printf("layer '%s': nee %.5f (se %.5f) tracking %.5f (se %.5f): %.2f sigma\n", layers[l], mean[1][l], se[1][l],
               mean[0][l], se[0][l], fabs(diff) / sigma);
        assert_true(mean[0][l] > 0.0);
        assert_true(fabs(diff) <= 4.0 * sigma);
    }
    assert_true(se[1][4] < se[0][4]); /* the floor lit by the box: NEE is less noisy */
    vbl_scene_release(scene);
    vbl_volume_release(density);
    vbl_volume_release(emission);
}

/* ---- role grids in scene files ------------------------------------------------------------- */

#define CAMERA "\"camera\": {\"position\": [0, -3, 0], \"look_at\": [0, 0, 0], \"resolution\": [4, 4]}"

static vbl_result load_medium(const char* medium_json, vbl_scene** scene)
{
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    char text[4096], path[512];
    snprintf(text, sizeof text, "{" CAMERA ", \"media\": [%s]}", medium_json);
    /* fixture paths are written as FIX/<name> and resolved here */
    char resolved[4096] = "";
    const char* s = text;
    for (const char* m; (m = strstr(s, "FIX/"));) {
        strncat(resolved, s, (size_t)(m - s));
        strncat(resolved, fixtures ? fixtures : ".", sizeof resolved - strlen(resolved) - 1);
        strncat(resolved, "/", sizeof resolved - strlen(resolved) - 1);
        s = m + 4;
    }
    strncat(resolved, s, sizeof resolved - strlen(resolved) - 1);
    rt_write_file(rt_temp_dir, "scene.json", resolved, path);
    *scene = NULL;
    return vbl_scene_load(path, scene);
}

static void expect_load_error(const char* medium_json, vbl_result code, const char* const* parts)
{
    vbl_scene* scene = NULL;
    vbl_result r = load_medium(medium_json, &scene);
    const char* msg = vbl_last_error_message();
    printf("%s -> %s: %s\n", medium_json, vbl_result_name(r), msg);
    assert_int_equal(r, code);
    assert_null(scene);
    for (const char* const* p = parts; *p; ++p) assert_non_null(strstr(msg, *p));
}

static void test_role_grids(void** state)
{
    (void)state;
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    char probe[512];
    snprintf(probe, sizeof probe, "%s/multi.vdb", fixtures ? fixtures : ".");
    FILE* f = fopen(probe, "rb");
    assert_non_null(f);
    fclose(f);
    /* one file, two roles: "temperature" found by name; blackbody on */
    vbl_scene* scene = NULL;
    vbl_result rl = load_medium("{\"vdb\": \"FIX/multi.vdb\", \"albedo\": 0.5, "
                                 "\"temperature\": {\"scale\": 4000, \"blackbody_intensity\": 2}}",
                                 &scene);
    if (rl) printf("load: %s\n", vbl_last_error_message());
    assert_int_equal(rl, VBL_SUCCESS);
    assert_true(scene->has_emission);
    assert_non_null(scene->media[0].temperature_volume);
    assert_null(scene->media[0].emission_volume);
    assert_true(scene->media[0].blackbody_intensity == 2.0 && scene->media[0].temperature_scale == 4000.0);
    vbl_scene_release(scene);
    /* a second file with its own transform: "heat" is the temperature of no_density.vdb */
    assert_int_equal(load_medium("{\"vdb\": \"FIX/box.vdb\", \"albedo\": 0.2, \"temperature\": {\"vdb\": "
                                 "\"FIX/no_density.vdb\", \"grid\": \"heat\", \"offset\": 1000}, "
                                 "\"emission\": {\"vdb\": \"FIX/no_density.vdb\", \"grid\": \"temperature\", "
                                 "\"color\": [1, 0.4, 0.1], \"scale\": 3}}",
                                 &scene),
                     VBL_SUCCESS);
    assert_true(scene->has_emission);
    assert_non_null(scene->media[0].emission_volume);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.passes = 1;
    o.spp = 2;
    o.threads = 2;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    double mean, se;
    image_mean(film, "volume_emission", 0, &mean, &se);
    vbl_film_release(film);
    vbl_scene_release(scene);

    const char* missing[] = {"media[0].emission", "box.vdb", "no emission grid", "'flame'", "'density' float", NULL};
    expect_load_error("{\"vdb\": \"FIX/box.vdb\", \"albedo\": 0, \"emission\": {}}", VBL_ERROR_GRID_NOT_FOUND,
                      missing);
    const char* named[] = {"media[0].temperature", "multi.vdb", "'nope'", NULL};
    expect_load_error("{\"vdb\": \"FIX/multi.vdb\", \"temperature\": {\"grid\": \"nope\"}}", VBL_ERROR_GRID_NOT_FOUND,
                      named);
    const char* type[] = {"media[0].emission", "multi.vdb", "'vel'", "vec3s", NULL};
    expect_load_error("{\"vdb\": \"FIX/multi.vdb\", \"emission\": {\"grid\": \"vel\"}}", VBL_ERROR_GRID_TYPE, type);
    const char* bad[] = {"media[0].temperature", "bad_values.vdb", "temperature grid 'density'", NULL};
    expect_load_error("{\"vdb\": \"FIX/box.vdb\", \"temperature\": {\"vdb\": \"FIX/bad_values.vdb\", "
                      "\"grid\": \"density\"}}",
                      VBL_ERROR_BAD_VOXELS, bad);
    const char* key[] = {"media[0].temperature", "normalization", NULL};
    expect_load_error("{\"vdb\": \"FIX/multi.vdb\", \"temperature\": {\"normalization\": \"max\"}}", VBL_ERROR_SCENE,
                      key);
    const char* neg[] = {"media[0].emission.scale", NULL};
    expect_load_error("{\"vdb\": \"FIX/multi.vdb\", \"emission\": {\"grid\": \"temperature\", \"scale\": -1}}",
                      VBL_ERROR_SCENE, neg);
    /* roles by name, as `vbl info` prints them */
    assert_string_equal(vbl_grid_role_for("flame"), "emission");
    assert_string_equal(vbl_grid_role_for("heat"), "temperature");
    assert_string_equal(vbl_grid_role_for("Cd"), "albedo");
    assert_string_equal(vbl_grid_role_for("vel.y"), "velocity");
    assert_null(vbl_grid_role_for("flags"));
}

/* A real fire cache end to end: openusd_densityAndHeat.vdb's "heat" is found as the temperature
 * role, the fire (the only light) lights a ground plane (surface_direct through the
 * unidirectional estimator),
 * layers sum to the beauty, nothing is NaN, and 1 and 2 threads give the same image. */
static void test_fire_cache_end_to_end(void** state)
{
    (void)state;
    const char* shared = getenv("VBL_SHARED_DATA");
    char vdb[512], obj[512], text[2048], path[512];
    snprintf(vdb, sizeof vdb, "%s/openusd_densityAndHeat.vdb", shared ? shared : ".");
    FILE* f = fopen(vdb, "rb");
    if (!f) {
        printf("SKIP: %s absent\n", vdb);
        return;
    }
    fclose(f);
    rt_write_file(rt_temp_dir, "ground.obj", "v -30 -30 -3\nv 30 -30 -3\nv 30 30 -3\nv -30 30 -3\nf 1 2 3\nf 1 3 4\n", obj);
    snprintf(text, sizeof text,
             "{\"camera\": {\"position\": [0, -45, 12], \"look_at\": [0, 0, 6], \"up\": [0, 0, 1], \"fov_deg\": 40, "
             "\"resolution\": [24, 18]}, "
             "\"media\": [{\"vdb\": \"%s\", \"density_scale\": 2, \"albedo\": 0.5, "
             "\"temperature\": {\"scale\": 3000, \"blackbody_intensity\": 4}}], "
             "\"surfaces\": [{\"mesh\": \"ground.obj\", \"material\": {\"type\": \"lambert\", \"albedo\": 0.5}}], "
             "\"render\": {\"passes\": 1, \"spp\": 4, \"seed\": 9, \"max_bounces\": -1}}",
             vdb);
    rt_write_file(rt_temp_dir, "fire.json", text, path);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(path, &scene), VBL_SUCCESS);
    assert_true(scene->has_emission);
    vbl_film* films[2] = {NULL, NULL};
    for (int k = 0; k < 2; ++k) {
        vbl_render_options o = scene->render;
        o.threads = k + 1;
        assert_int_equal(vbl_render(scene, &o, &films[k]), VBL_SUCCESS);
    }
    int w = vbl_film_width(films[0]), h = vbl_film_height(films[0]), c = 0;
    const float* beauty = vbl_film_layer(films[0], "", &c);
    assert_null(vbl_film_layer(films[0], "background", &c));
    const char* layers[] = {"emission", "volume_emission", "volume_direct", "volume_from_volume", "surface_direct",
                            "surface_from_surface", "surface_from_volume", "volume_from_surface"};
    double emitted = 0.0, ground = 0.0;
    for (int i = 0; i < w * h; ++i)
        for (int ch = 0; ch < 3; ++ch) {
            double sum = 0.0;
            for (size_t l = 0; l < sizeof layers / sizeof layers[0]; ++l) {
                int lc = 0;
                const float* p = vbl_film_layer(films[0], layers[l], &lc);
                if (l == 1 || l == 4) assert_non_null(p); /* no lights: only the fire lights anything */
                if (!p) continue;
                assert_true(isfinite(p[3 * i + ch]) && p[3 * i + ch] >= 0.0f);
                sum += p[3 * i + ch];
                if (l == 1) emitted += p[3 * i + ch];
                if (l == 4) ground += p[3 * i + ch];
            }
            assert_true(isfinite(beauty[4 * i + ch]));
            assert_true(fabs(beauty[4 * i + ch] - sum) <= 1e-5 * fabs(sum) + 1e-12);
        }
    printf("fire cache: volume_emission sum %.4g, surface_direct sum %.4g\n", emitted, ground);
    assert_true(emitted > 0.0 && ground > 0.0);
    const float* beauty2 = vbl_film_layer(films[1], "", &c);
    assert_memory_equal(beauty, beauty2, sizeof(float) * 4 * (size_t)(w * h));
    vbl_film_release(films[0]);
    vbl_film_release(films[1]);
    vbl_scene_release(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blackbody_chromaticity),
        cmocka_unit_test(test_emission_box_closed_form),
        cmocka_unit_test(test_emission_nee_vs_tracking),
        cmocka_unit_test(test_role_grids),
        cmocka_unit_test(test_fire_cache_end_to_end),
    };
    return cmocka_run_group_tests(tests, rt_temp_dir_setup, rt_temp_dir_teardown);
}
