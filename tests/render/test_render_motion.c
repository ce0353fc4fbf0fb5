/* Vector role grids and velocity motion blur (issue 15 items 1 and 3): albedo grids (a constant
 * Cd grid renders the mean of the constant albedo; pt against vrl on a varying Cd), velocity
 * grids (vec3s and Houdini's float triplet), bad-input messages, and motion blur: a moving
 * emissive box against its time-averaged closed form per column, the majorant dilation bound,
 * zero velocity and motion_blur = 0 bit-identical to no motion, determinism at 1 and 2 threads.
 * Fixtures: tests/fixtures/motion_fixtures.cc. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "render_test_util.h"
#include "vbl/vbl.h"
#include "volume/extinction.h"

/* ---- scene files ------------------------------------------------------------------------ */

/* Writes `json` (FIX/<name> -> the fixture folder) as scene.json and loads it. */
static vbl_result load_scene(const char* json, vbl_scene** scene)
{
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    char resolved[8192] = "", path[512];
    const char* s = json;
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

static vbl_scene* must_load(const char* json)
{
    vbl_scene* scene = NULL;
    vbl_result r = load_scene(json, &scene);
    if (r) printf("load failed: %s\n", vbl_last_error_message());
    assert_int_equal(r, VBL_SUCCESS);
    return scene;
}

static void expect_load_error(const char* json, vbl_result code, const char* const* parts)
{
    vbl_scene* scene = NULL;
    vbl_result r = load_scene(json, &scene);
    const char* msg = vbl_last_error_message();
    printf("-> %s: %s\n", vbl_result_name(r), msg);
    assert_int_equal(r, code);
    assert_null(scene);
    for (const char* const* p = parts; *p; ++p) {
        if (!strstr(msg, *p)) printf("missing '%s'\n", *p);
        assert_non_null(strstr(msg, *p));
    }
}

static vbl_film* render_with(const vbl_scene* scene, vbl_render_method method, int passes, int spp, uint64_t seed,
                             int threads, int shadow_control);
static vbl_film* render(const vbl_scene* scene, vbl_render_method method, int passes, int spp, uint64_t seed,
                        int threads)
{
    return render_with(scene, method, passes, spp, seed, threads, 1);
}

/* render() with pt.shadow_control on or off */
static vbl_film* render_with(const vbl_scene* scene, vbl_render_method method, int passes, int spp, uint64_t seed,
                             int threads, int shadow_control)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.pt.shadow_control = shadow_control;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.method = method;
    o.passes = passes;
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    o.max_bounces = -1;
    vbl_film* film = NULL;
    vbl_result r = vbl_render(scene, &o, &film);
    if (r) printf("render failed: %s\n", vbl_last_error_message());
    assert_int_equal(r, VBL_SUCCESS);
    return film;
}

/* Mean of a layer's channel ch over the image. */
static double layer_mean(const vbl_film* film, const char* layer, int ch)
{
    int w = vbl_film_width(film), h = vbl_film_height(film), c = 0;
    const float* p = vbl_film_layer(film, layer, &c);
    assert_non_null(p);
    double s = 0.0;
    for (int i = 0; i < w * h; ++i) {
        assert_true(isfinite(p[i * c + ch]));
        s += p[i * c + ch];
    }
    return s / (w * h);
}

/* Mean and standard error over `n` independent renders (seeds seed0 .. seed0 + n - 1) of a
 * layer's image mean, per channel: the error of a layer without a variance AOV. */
static void replica_mean(const vbl_scene* scene, vbl_render_method method, int passes, int spp, uint64_t seed0, int n,
                         const char* layer, double mean[3], double se[3])
{
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    for (int k = 0; k < n; ++k) {
        vbl_film* f = render(scene, method, passes, spp, seed0 + (uint64_t)k, 2);
        for (int ch = 0; ch < 3; ++ch) {
            double m = layer_mean(f, layer, ch);
            s[ch] += m;
            s2[ch] += m * m;
        }
        vbl_film_release(f);
    }
    for (int ch = 0; ch < 3; ++ch) {
        mean[ch] = s[ch] / n;
        se[ch] = sqrt(fmax(0.0, (s2[ch] - n * mean[ch] * mean[ch]) / (n - 1.0)) / n);
    }
}

/* Mean of the beauty's channel ch and its standard error (from the variance AOV). */
static void beauty_mean(const vbl_film* film, int ch, double* mean, double* se)
{
    int w = vbl_film_width(film), h = vbl_film_height(film), c = 0, cv = 0;
    const float* p = vbl_film_layer(film, "", &c);
    const float* var = vbl_film_layer(film, "variance", &cv);
    assert_non_null(p);
    assert_non_null(var);
    double s = 0.0, v = 0.0;
    for (int i = 0; i < w * h; ++i) {
        assert_true(isfinite(p[i * c + ch]));
        s += p[i * c + ch];
        v += var[i * cv + ch];
    }
    *mean = s / (w * h);
    *se = sqrt(v) / (w * h);
}

static int films_equal(const vbl_film* a, const vbl_film* b)
{
    int c = 0;
    const float* pa = vbl_film_layer(a, "", &c);
    const float* pb = vbl_film_layer(b, "", &c);
    size_t n = (size_t)vbl_film_width(a) * (size_t)vbl_film_height(a) * (size_t)c;
    return vbl_film_width(a) == vbl_film_width(b) && vbl_film_height(a) == vbl_film_height(b) &&
           !memcmp(pa, pb, n * sizeof(float));
}

/* ---- albedo grids --------------------------------------------------------------------------- */

#define LIT_BOX(albedo)                                                                                            \
    "{\"camera\": {\"position\": [0.75, -6, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 20, "         \
    "\"resolution\": [8, 8]}, \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, 0.2, -1], "             \
    "\"irradiance\": 2}], \"media\": [{\"vdb\": \"FIX/albedo_const.vdb\", \"density_scale\": 3, \"albedo\": " albedo \
    "}]}"

/* A constant Cd grid equal to a constant albedo renders the same mean (pt, independent seeds). */
static void test_albedo_constant_grid(void** state)
{
    (void)state;
    const char* grids[] = {LIT_BOX("{\"grid\": \"Cd\"}"), LIT_BOX("{\"grid\": \"Cd_grey\", \"scale\": [1, 1, 1]}")};
    const char* consts[] = {LIT_BOX("[0.5, 0.75, 0.625]"), LIT_BOX("0.75")};
    for (int k = 0; k < 2; ++k) {
        vbl_scene* with_grid = must_load(grids[k]);
        vbl_scene* constant = must_load(consts[k]);
        vbl_film* a = render(with_grid, VBL_RENDER_PT, 2, 32, 11, 2);
        vbl_film* b = render(constant, VBL_RENDER_PT, 2, 32, 12, 2);
        for (int ch = 0; ch < 3; ++ch) {
            double ma, sa, mb, sb;
            beauty_mean(a, ch, &ma, &sa);
            beauty_mean(b, ch, &mb, &sb);
            double z = (ma - mb) / sqrt(sa * sa + sb * sb);
            printf("%s Cd grid ch %d: %.5f +- %.5f, constant albedo %.5f +- %.5f (z %.2f)\n", k ? "float" : "vec3s", ch,
                   ma, sa, mb, sb, z);
            assert_true(mb > 20.0 * sb); /* the test has signal */
            assert_true(fabs(z) < 4.0);
        }
        vbl_film_release(a);
        vbl_film_release(b);
        if (k == 1) { /* the grey grid: pt only */
            vbl_scene_release(with_grid);
            vbl_scene_release(constant);
            continue;
        }
        /* vrl, same seed: the grid's constant equals the albedo, so every light path and VRL
         * kernel is the same (light paths scattering with the scale, 1, instead would differ).
         * pt.shadow_control off: its camera-walk control sums exactly for a constant albedo and at
         * stratified picks for an albedo grid, so the two scenes would take different (each
         * unbiased) single-scattering estimators */
        a = render_with(with_grid, VBL_RENDER_VRL, 2, 2, 13, 2, 0);
        b = render_with(constant, VBL_RENDER_VRL, 2, 2, 13, 2, 0);
        int c = 0;
        const float* pa = vbl_film_layer(a, "", &c);
        const float* pb = vbl_film_layer(b, "", &c);
        double worst = 0.0, sum = 0.0;
        for (int i = 0; i < vbl_film_width(a) * vbl_film_height(a) * c; ++i) {
            worst = fmax(worst, fabs(pa[i] - pb[i]) / (fabs(pb[i]) + 1e-6));
            sum += pb[i];
        }
        printf("vrl: constant Cd grid against constant albedo: largest relative difference %.3g\n", worst);
        assert_true(sum > 0.0);
        assert_true(worst < 1e-5);
        vbl_film_release(a);
        vbl_film_release(b);
        vbl_scene_release(with_grid);
        vbl_scene_release(constant);
    }
}

/* pt and vrl agree on a medium whose albedo varies across it (a dark Cd ramp along x, so that
 * light paths scattering with albedo 1 instead of Cd would show in volume_from_volume). Optical
 * depth ~1.5: in this
 * box at density_scale 2 (depth ~3) vrl is 3-5% below pt with a constant albedo too (z ~2 at
 * 16 / 96 passes), a difference of vrl's, not of the albedo grid. */
static void test_albedo_pt_vs_vrl(void** state)
{
    (void)state;
    const char* json =
        "{\"camera\": {\"position\": [0.75, -6, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 20, "
        "\"resolution\": [8, 8]}, \"lights\": [{\"type\": \"distant\", \"direction\": [-0.6, 0.3, -1], "
        "\"irradiance\": 2}], \"media\": [{\"vdb\": \"FIX/albedo_ramp.vdb\", \"density_scale\": 0.7, "
        "\"albedo\": {\"grid\": \"Cd\"}}]}";
    vbl_scene* scene = must_load(json);
    const char* layers[] = {""};
    for (int l = 0; l < 1; ++l) {
        double mp[3], sp[3], mv[3], sv[3];
        replica_mean(scene, VBL_RENDER_PT, 1, 16, 3, 4, layers[l], mp, sp);
        replica_mean(scene, VBL_RENDER_VRL, 6, 2, 40, 4, layers[l], mv, sv);
        for (int ch = 0; ch < 3; ++ch) {
            double z = (mp[ch] - mv[ch]) / sqrt(sp[ch] * sp[ch] + sv[ch] * sv[ch]);
            printf("Cd ramp %s ch %d: pt %.5f +- %.5f, vrl %.5f +- %.5f (z %.2f)\n", l ? layers[l] : "beauty", ch, mp[ch],
                   sp[ch], mv[ch], sv[ch], z);
            assert_true(mv[ch] > 10.0 * sv[ch]);
            assert_true(fabs(z) < 4.5);
        }
    }
    /* methods that do not read albedo grids refuse them */
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.method = VBL_RENDER_VPL;
    o.passes = 1;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_ERROR_UNSUPPORTED);
    assert_non_null(strstr(vbl_last_error_message(), "albedo grid"));
    vbl_scene_release(scene);
}

#define MEDIUM(m) "{\"camera\": {\"position\": [0, -3, 0], \"look_at\": [0, 0, 0], \"resolution\": [4, 4]}, \"media\": [" m "]}"

static void test_vector_grid_errors(void** state)
{
    (void)state;
    const char* nan_albedo[] = {"scene.json", "media[0].albedo", "Cd", "albedo_bad.vdb", "1 NaN", NULL};
    expect_load_error(MEDIUM("{\"vdb\": \"FIX/albedo_bad.vdb\", \"albedo\": {\"grid\": \"Cd\"}}"), VBL_ERROR_BAD_VOXELS,
                      nan_albedo);
    const char* high[] = {"media[0].albedo", "Cd_high", "above 1", NULL};
    expect_load_error(MEDIUM("{\"vdb\": \"FIX/albedo_bad.vdb\", \"albedo\": {\"grid\": \"Cd_high\"}}"), VBL_ERROR_SCENE,
                      high);
    const char* nan_vel[] = {"scene.json", "media[0].velocity", "vel_nan", "moving.vdb", "1 NaN", NULL};
    expect_load_error(MEDIUM("{\"vdb\": \"FIX/moving.vdb\", \"velocity\": {\"grid\": \"vel_nan\"}}"),
                      VBL_ERROR_BAD_VOXELS, nan_vel);
    const char* float_vel[] = {"media[0].velocity", "'emission'", "float grid", "vec3s", NULL};
    expect_load_error(MEDIUM("{\"vdb\": \"FIX/moving.vdb\", \"velocity\": {\"grid\": \"emission\"}}"), VBL_ERROR_GRID_TYPE,
                      float_vel);
    const char* missing[] = {"media[0].velocity", "albedo_const.vdb", "no velocity grid", "vel.x", NULL};
    expect_load_error(MEDIUM("{\"vdb\": \"FIX/albedo_const.vdb\", \"velocity\": {}}"), VBL_ERROR_GRID_NOT_FOUND, missing);
    const char* vec_density[] = {"media[0].emission", "'velocity'", "not a float grid", NULL};
    expect_load_error(MEDIUM("{\"vdb\": \"FIX/moving.vdb\", \"emission\": {\"grid\": \"velocity\"}}"), VBL_ERROR_GRID_TYPE,
                      vec_density);
    /* the vec3s grid and Houdini's float triplet load the same field */
    vbl_scene* a = must_load(MEDIUM("{\"vdb\": \"FIX/moving.vdb\", \"velocity\": {}}"));
    vbl_scene* b = must_load(MEDIUM("{\"vdb\": \"FIX/moving.vdb\", \"velocity\": {\"grid\": \"vel\"}}"));
    assert_string_equal(a->media[0].velocity.v[0]->info.grid_name, "velocity.x");
    assert_string_equal(b->media[0].velocity.v[1]->info.grid_name, "vel.y");
    assert_true(a->motion && b->motion);
    assert_true(a->media[0].velocity.max_speed == b->media[0].velocity.max_speed);
    assert_true(fabs(a->media[0].velocity.max_speed - 57.6) < 1e-4);
    vbl_scene_release(a);
    vbl_scene_release(b);
}

/* ---- motion blur ----------------------------------------------------------------------------- */

/* The emissive box of moving.vdb (density 1 on voxels [0,7]^3, voxel 0.1, emission 1, albedo 0)
 * moving along +x at 57.6 units/s, shutter [-0.5, 0.5] frames at 24 fps: displacement
 * +-1.2, i.e. 1.5 majorant blocks either way. Seen from -y by a far narrow camera. */
#define SIGMA 2.0
#define SPEED 57.6
#define HALF_T (0.5 / 24.0)
#define MOVING(velocity, render)                                                                                  \
    "{\"fps\": 24, \"camera\": {\"position\": [0.35, -60, 0.35], \"look_at\": [0.35, 0, 0.35], "                  \
    "\"fov_deg\": 0.2805, \"resolution\": [32, 2], \"shutter\": [-0.5, 0.5]}, \"media\": [{\"vdb\": "             \
    "\"FIX/moving.vdb\", \"density_scale\": 2, \"albedo\": 0, \"emission\": {\"grid\": \"emission\"}" velocity "}]" \
    render "}"

/* Optical depth of the box displaced by dx along the ray (midpoint rule, 200 steps over its y span). */
static double box_depth(vbl_vec3 o, vbl_vec3 d, double dx)
{
    const double y0 = -0.1, y1 = 0.8; /* the trilinear support in y */
    double ta = (y0 - o.y) / d.y, tb = (y1 - o.y) / d.y, tau = 0.0;
    const int n = 200;
    for (int i = 0; i < n; ++i) {
        double t = ta + (tb - ta) * (i + 0.5) / n;
        vbl_vec3 p = vbl_v3_madd(o, d, t);
        p.x -= dx;
        tau += rt_box_density(8, 0.1, vbl_v3(0, 0, 0), p);
    }
    return SIGMA * tau * (tb - ta) / n;
}

/* The pixel's expected value: mean over the pixel (4 x 4) and the shutter (64 strata) of
 * 1 - exp(-tau) (albedo 0, Le = 1: L = Le (1 - T)); with `blur` 0 at t = 0 only. */
static double expected_pixel(const vbl_camera* cam, int px, int py, int blur)
{
    double sum = 0.0;
    int n = 0;
    for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) {
            vbl_vec3 o, d;
            vbl_camera_ray(cam, px + (sx + 0.5) / 4.0, py + (sy + 0.5) / 4.0, &o, &d);
            for (int k = 0; k < (blur ? 64 : 1); ++k) {
                double t = blur ? -HALF_T + 2.0 * HALF_T * (k + 0.5) / 64.0 : 0.0;
                sum += -expm1(-box_depth(o, d, SPEED * t));
                ++n;
            }
        }
    return sum / n;
}

static void test_motion_closed_form(void** state)
{
    (void)state;
    vbl_scene* scene = must_load(MOVING(", \"velocity\": {}", ""));
    assert_true(scene->motion);
    assert_true(fabs(scene->shutter_open + HALF_T) < 1e-15 && fabs(scene->shutter_close - HALF_T) < 1e-15);
    vbl_film* film = render(scene, VBL_RENDER_PT, 1, 256, 21, 2);
    int c = 0, cv = 0;
    const float* p = vbl_film_layer(film, "", &c);
    const float* var = vbl_film_layer(film, "variance", &cv);
    const int w = scene->camera.width, h = scene->camera.height;
    double chi2 = 0.0, max_static_z = 0.0;
    for (int x = 0; x < w; ++x) {
        double m = 0.0, v = 0.0, e = 0.0, e_static = 0.0;
        for (int y = 0; y < h; ++y) {
            m += p[(y * w + x) * c];
            v += var[(y * w + x) * cv];
            e += expected_pixel(&scene->camera, x, y, 1);
            e_static += expected_pixel(&scene->camera, x, y, 0);
        }
        m /= h;
        e /= h;
        e_static /= h;
        double se = sqrt(v) / h + 1e-4; /* + the quadrature's error */
        double z = (m - e) / se;
        chi2 += z * z;
        if (fabs(m - e_static) / se > max_static_z) max_static_z = fabs(m - e_static) / se;
        printf("column %2d: %.4f +- %.4f, blurred %.4f (z %+.2f), frozen %.4f\n", x, m, se, e, z, e_static);
        assert_true(fabs(z) < 4.5);
    }
    printf("chi2 %.1f over %d columns; largest z against the frozen box %.1f\n", chi2, w, max_static_z);
    assert_true(chi2 < 2.0 * w + 20.0);
    assert_true(max_static_z > 10.0); /* the test tells blur from no blur */
    vbl_film_release(film);
    vbl_scene_release(scene);
}

/* The dilated majorant bounds the advected density: along random rays at random shutter times,
 * every sampled point's sigma_t is <= its segment's majorant, and 0 where no segment covers it. */
static void test_motion_majorant_bound(void** state)
{
    (void)state;
    vbl_scene* scene = must_load(MOVING(", \"velocity\": {}", ""));
    const vbl_extinction* ext = &scene->extinction;
    vbl_extinction_cursor cursor;
    vbl_extinction_cursor_init(&cursor, ext);
    vbl_rng rng = vbl_rng_make(7, 0, 0);
    int checked = 0, positive = 0;
    for (int r = 0; r < 400; ++r) {
        /* rays along x (the motion) and y through the swept region */
        vbl_vec3 o = vbl_v3(-3.0 + 6.0 * vbl_rng_uniform(&rng), -3.0, -0.2 + vbl_rng_uniform(&rng));
        vbl_vec3 target = vbl_v3(-3.0 + 6.0 * vbl_rng_uniform(&rng), 3.0, -0.2 + vbl_rng_uniform(&rng));
        if (r & 1) {
            o = vbl_v3(-3.0, -0.2 + vbl_rng_uniform(&rng), -0.2 + vbl_rng_uniform(&rng));
            target = vbl_v3(3.0, -0.2 + vbl_rng_uniform(&rng), -0.2 + vbl_rng_uniform(&rng));
        }
        vbl_vec3 d = vbl_v3_normalize(vbl_v3_sub(target, o));
        cursor.time = scene->shutter_open + (scene->shutter_close - scene->shutter_open) * vbl_rng_uniform(&rng);
        vbl_extinction_iter it;
        vbl_extinction_iter_init(&it, ext, o, d, 0.0, 10.0, 0);
        vbl_majorant_segment seg;
        double covered = 0.0;
        while (vbl_extinction_iter_next(&it, &seg)) {
            for (int k = 0; k < 16; ++k) {
                double t = seg.t0 + (seg.t1 - seg.t0) * vbl_rng_uniform(&rng);
                double s = vbl_extinction_eval(ext, &cursor, vbl_v3_madd(o, d, t), NULL);
                assert_true(s <= seg.majorant * (1.0 + 1e-6) + 1e-9);
                positive += s > 0.0;
                ++checked;
            }
            covered = seg.t1;
        }
        for (int k = 0; k < 16; ++k) { /* past the last segment nothing is there */
            double t = covered + (10.0 - covered) * vbl_rng_uniform(&rng);
            assert_true(vbl_extinction_eval(ext, &cursor, vbl_v3_madd(o, d, t), NULL) == 0.0);
        }
    }
    printf("majorant bound: %d points, %d inside the moving box\n", checked, positive);
    assert_true(positive > 100);
    vbl_scene_release(scene);
}

/* Zero velocity and motion_blur = 0 render bit for bit as the scene without velocity; blur is
 * deterministic at 1 and 2 threads; the virtual-light methods refuse moving media. */
static void test_motion_identity_and_determinism(void** state)
{
    (void)state;
    vbl_scene* still = must_load(MOVING("", ""));
    vbl_scene* zero = must_load(MOVING(", \"velocity\": {\"grid\": \"vel_zero\"}", ""));
    vbl_scene* off = must_load(MOVING(", \"velocity\": {}", ", \"render\": {\"motion_blur\": false}"));
    vbl_scene* moving = must_load(MOVING(", \"velocity\": {}", ""));
    assert_false(still->motion);
    assert_false(zero->motion);
    assert_true(off->motion && !off->render.motion_blur);
    vbl_film* a = render(still, VBL_RENDER_PT, 1, 8, 5, 2);
    vbl_film* b = render(zero, VBL_RENDER_PT, 1, 8, 5, 2);
    vbl_render_options o = off->render;
    o.passes = 1;
    o.spp = 8;
    o.seed = 5;
    o.threads = 2;
    o.max_bounces = -1;
    vbl_film* c = NULL;
    assert_int_equal(vbl_render(off, &o, &c), VBL_SUCCESS);
    assert_true(films_equal(a, b));
    assert_true(films_equal(a, c));
    vbl_film* m1 = render(moving, VBL_RENDER_PT, 1, 8, 5, 1);
    vbl_film* m2 = render(moving, VBL_RENDER_PT, 1, 8, 5, 2);
    assert_true(films_equal(m1, m2));
    assert_false(films_equal(a, m1));
    vbl_render_options ov = VBL_RENDER_OPTIONS_DEFAULT;
    ov.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    ov.method = VBL_RENDER_VRL;
    ov.passes = 1;
    vbl_film* f = NULL;
    assert_int_equal(vbl_render(moving, &ov, &f), VBL_ERROR_UNSUPPORTED);
    printf("%s\n", vbl_last_error_message());
    assert_non_null(strstr(vbl_last_error_message(), "motion_blur"));
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_film_release(c);
    vbl_film_release(m1);
    vbl_film_release(m2);
    vbl_scene_release(still);
    vbl_scene_release(zero);
    vbl_scene_release(off);
    vbl_scene_release(moving);
}

/* A frame sequence with motion blur end to end: moving.####.vdb (frames 1-3, links to the
 * fixture), the medium placed per frame by transform_frames 0.5 units further along +x each
 * frame, its velocity (scaled to 12 units/s = 0.5 units per frame at 24 fps) blurring each frame
 * over the shutter. Every frame renders finite, with motion, and the image's centroid moves by
 * 0.5 units per frame (the medium's frame placement; the blur is symmetric about it). */
static void test_motion_sequence(void** state)
{
    (void)state;
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    char target[512], link_path[600];
    snprintf(target, sizeof target, "%s/moving.vdb", fixtures ? fixtures : ".");
    for (int f = 1; f <= 3; ++f) {
        snprintf(link_path, sizeof link_path, "%s/moving.%04d.vdb", rt_temp_dir, f);
        FILE* in = fopen(target, "rb");
        FILE* out = fopen(link_path, "wb");
        assert_non_null(in);
        assert_non_null(out);
        char buf[65536];
        size_t n;
        while ((n = fread(buf, 1, sizeof buf, in)) > 0) assert_int_equal(fwrite(buf, 1, n, out), n);
        fclose(in);
        fclose(out);
    }
    const char* json =
        "{\"fps\": 24, \"camera\": {\"position\": [0.85, -60, 0.35], \"look_at\": [0.85, 0, 0.35], "
        "\"fov_deg\": 0.2805, \"resolution\": [32, 2]}, \"media\": [{\"vdb\": \"moving.####.vdb\", "
        "\"density_scale\": 2, \"albedo\": 0, \"emission\": {\"grid\": \"emission\"}, "
        "\"velocity\": {\"scale\": 0.208333333333333333}, \"transform_frames\": {"
        "\"1\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], \"3\": [[1,0,0,1],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}}]}";
    char path[512];
    rt_write_file(rt_temp_dir, "sequence.json", json, path);
    double centroid[3];
    for (int f = 1; f <= 3; ++f) {
        vbl_scene_load_options lo;
        memset(&lo, 0, sizeof lo);
        lo.size = sizeof lo;
        lo.use_frame = 1;
        lo.frame = f;
        vbl_scene* scene = NULL;
        vbl_result r = vbl_scene_load_ex(path, &lo, &scene);
        if (r) printf("frame %d: %s\n", f, vbl_last_error_message());
        assert_int_equal(r, VBL_SUCCESS);
        assert_true(scene->motion);
        assert_true(fabs(scene->media[0].velocity.max_speed - 12.0) < 1e-3);
        vbl_film* film = render(scene, VBL_RENDER_PT, 1, 64, 9, 2);
        int c = 0;
        const float* p = vbl_film_layer(film, "", &c);
        const int w = vbl_film_width(film), h = vbl_film_height(film);
        double sum = 0.0, moment = 0.0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                double v = p[(y * w + x) * c];
                assert_true(isfinite(v) && v >= 0.0);
                sum += v;
                moment += v * (x + 0.5);
            }
        assert_true(sum > 0.0);
        /* pixels -> world x: the image spans 4.7 units over 32 pixels, centred on x = 0.85 */
        centroid[f - 1] = 0.85 + (moment / sum - 16.0) * (4.7 / 32.0);
        printf("frame %d: centroid x %.4f\n", f, centroid[f - 1]);
        vbl_film_release(film);
        vbl_scene_release(scene);
    }
    /* the box's centre is at 0.35 + 0.5 (f - 1) */
    for (int f = 0; f < 3; ++f) assert_true(fabs(centroid[f] - (0.35 + 0.5 * f)) < 0.03);
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]); /* one test by name (timing, debugging) */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_albedo_constant_grid),
        cmocka_unit_test(test_albedo_pt_vs_vrl),
        cmocka_unit_test(test_vector_grid_errors),
        cmocka_unit_test(test_motion_closed_form),
        cmocka_unit_test(test_motion_majorant_bound),
        cmocka_unit_test(test_motion_identity_and_determinism),
        cmocka_unit_test(test_motion_sequence),
    };
    return cmocka_run_group_tests(tests, rt_temp_dir_setup, rt_temp_dir_teardown);
}
