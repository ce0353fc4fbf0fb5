/* Progressive photon beams in rendering (transport/photon_beams/photon_beams.h): the `beams` method and the
 * `vbl` method's photon-beam single scattering.
 *
 * Default group (quick): registry and names; determinism at 1 vs 2 threads (beams, and vbl with
 * beam single scattering); vbl's beam single scattering equals `beams` bit for bit at
 * max_bounces 1; finite, non-negative films at the extremes (width 2e-4 x, just above the
 * refusal floor of test_transport_extremes, and 10 x the scene, g = +-0.999, beams parallel to the camera rays, camera inside the medium); camera rays
 * stop at t_max; option and scene-file validation (isotropic media: test_beam_light_isotropic.c).
 *
 * "converge" (label `slow`): single scattering (max_bounces 1) from a spot light in a constant-
 * density box. The reference is pt's volume_direct (many samples). Over K seeds, the RMSE of the
 * beams' volume_direct against it must fall with the passes P = 1..64 (width shrinking, eq 11 with
 * d = 1): radius_schedule.h gives RMSE ~ P^e, e = max(2 (alpha - 1), -alpha / 2) = -0.35 for
 * alpha = 0.7 (the bias alone falls like P^-0.6 and averaging alone cannot beat P^-0.5, so with the
 * bias dominating early the fitted slope lies between); accepted: slope in [-0.8, e + 0.15]. The
 * final RMSE must be below 0.3 x the one at P = 1 and 0.3 x the RMS of the pt image, below
 * 0.6 x that of the same renders at a (nearly) fixed width (alpha = 0.999: they stall at their
 * bias), and the image mean within 10 % of pt's (6 seeds: a sanity bound).
 *
 * "multiple" (label `slow`): the beams' volume_from_volume against pt's over P = 2..128 (8 seeds):
 * the fitted slope in [-0.8, -0.2], the RMSE at P = 128 below half the one at P = 2, and the image
 * means within 5 %. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "transport/common/radius_schedule.h"
#include "render_test_util.h"
#include "transport/photon_beams/photon_beams.h"
#include "transport/path_tracing/pt.h"
#include "transport/virtual_lights/virtual_beam_lights.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

#define BOX_DIAG (2.25 * 1.7320508075688772)

/* box [-1, 1.25]^3 of density `scale` (rt_make_box(9, 0.25)) */
static vbl_scene* box_scene(vbl_vec3 cam_pos, vbl_vec3 target, double scale, double albedo, double g,
                            vbl_volume** vol, int res)
{
    vbl_camera cam = rt_camera(cam_pos, target, 40.0, res, res);
    vbl_scene* s = tt_scene(&cam);
    *vol = rt_make_box(9, 0.25, vbl_v3(-1, -1, -1));
    assert_int_equal(vbl_scene_add_medium(s, *vol, scale, vbl_v3(albedo, albedo, albedo), g, NULL), VBL_SUCCESS);
    return s;
}

static vbl_film* render(const vbl_scene* s, vbl_render_options o)
{
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(s, &o, &film), VBL_SUCCESS);
    assert_true(tt_film_finite(film));
    return film;
}

static double layer_sum(const vbl_film* f, const char* name, int n)
{
    const float* p = vbl_film_layer_rgb(f, name);
    double sum = 0.0;
    for (int i = 0; p && i < 3 * n; ++i) sum += p[i];
    return sum;
}

static double layer_min(const vbl_film* f, const char* name, int n)
{
    const float* p = vbl_film_layer_rgb(f, name);
    double m = 0.0;
    for (int i = 0; p && i < 3 * n; ++i) m = fmin(m, p[i]);
    return m;
}

static void test_registry(void** state)
{
    (void)state;
    assert_string_equal(vbl_render_method_name(VBL_RENDER_BEAMS), "beams");
    vbl_render_method m = VBL_RENDER_PT;
    assert_int_equal(vbl_render_method_parse("beams", &m), VBL_SUCCESS);
    assert_int_equal(m, VBL_RENDER_BEAMS);
    assert_ptr_equal(vbl_estimator_for(VBL_RENDER_BEAMS), &vbl_estimator_beams);
}

static void test_determinism(void** state)
{
    (void)state;
    vbl_volume* vol;
    vbl_scene* s = box_scene(vbl_v3(0.2, -4, 0.3), vbl_v3(0, 0, 0), 1.0, 0.8, 0.5, &vol, 12);
    tt_add_point(s, vbl_v3(0.4, 0.3, 1.6), 10.0);
    const char* layers[2] = {"volume_direct", "volume_from_volume"};
    for (int method = 0; method < 2; ++method) {
        vbl_render_options o = tt_options(3, 1, 80, 5);
        o.method = method == 0 ? VBL_RENDER_BEAMS : VBL_RENDER_VBL;
        o.beam_lights.single_scattering = 2;
        o.threads = 1;
        vbl_film* a = render(s, o);
        o.threads = 2;
        vbl_film* b = render(s, o);
        for (int l = 0; l < 2; ++l) {
            const float* pa = vbl_film_layer_rgb(a, layers[l]);
            const float* pb = vbl_film_layer_rgb(b, layers[l]);
            assert_non_null(pa);
            assert_non_null(pb);
            assert_memory_equal(pa, pb, sizeof(float) * 3 * 12 * 12);
            assert_true(layer_sum(a, layers[l], 144) > 0.0);
        }
        vbl_film_stats st;
        memset(&st, 0, sizeof st);
        st.size = sizeof st;
        assert_int_equal(vbl_film_get_stats(a, &st), VBL_SUCCESS);
        assert_int_equal(st.method, o.method);
        vbl_film_release(a);
        vbl_film_release(b);
    }
    vbl_scene_release(s);
    vt_free(vol);
}

/* vbl with photon-beam single scattering at max_bounces 1 traces the same beams, builds the same
 * camera-ray caches and gathers with the same width as `beams`: volume_direct is bit-identical. */
static void test_vbl_single_scattering_is_beams(void** state)
{
    (void)state;
    vbl_volume* vol;
    vbl_scene* s = box_scene(vbl_v3(0.2, -4, 0.3), vbl_v3(0, 0, 0), 1.0, 0.8, 0.4, &vol, 8);
    tt_add_spot(s, vbl_v3(0.125, 0.125, 3.0), vbl_v3(0.1, 0.05, -1), 500.0, 5.0, 10.0);
    vbl_render_options o = tt_options(3, 2, 64, 21);
    o.max_bounces = 1;
    o.beams.radius0 = 0.3;
    o.method = VBL_RENDER_BEAMS;
    vbl_film* a = render(s, o);
    o.method = VBL_RENDER_VBL;
    o.vrl.select = 0; /* the light tree's draws would take the camera samples' random numbers */
    o.beam_lights.single_scattering = 2;
    vbl_film* b = render(s, o);
    o.beam_lights.single_scattering = 1; /* equiangular: a different estimate of the same layer */
    vbl_film* c = render(s, o);
    const float* pa = vbl_film_layer_rgb(a, "volume_direct");
    const float* pb = vbl_film_layer_rgb(b, "volume_direct");
    assert_non_null(pa);
    assert_non_null(pb);
    assert_memory_equal(pa, pb, sizeof(float) * 3 * 64);
    double sa = layer_sum(a, "volume_direct", 64), sc = layer_sum(c, "volume_direct", 64);
    printf("volume_direct sum: beams %g, vbl equiangular %g\n", sa, sc);
    assert_true(sa > 0.0 && sc > 0.0 && sa != sc);
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_film_release(c);
    vbl_scene_release(s);
    vt_free(vol);
}

static void extreme(double radius0, double g, vbl_vec3 cam, vbl_vec3 target, int light, int method)
{
    vbl_volume* vol;
    vbl_scene* s = box_scene(cam, target, 1.0, 0.9, g, &vol, 8);
    if (light == 0) tt_add_point(s, vbl_v3(0.4, 0.3, 1.6), 10.0);
    if (light == 1) tt_add_distant(s, vbl_v3_normalize(vbl_v3_sub(target, cam)), 1.0); /* beams parallel to rays */
    if (light == 2) tt_add_spot(s, cam, vbl_v3_sub(target, cam), 50.0, 1.0, 2.0); /* beams along the rays */
    vbl_render_options o = tt_options(2, 1, 24, 11);
    o.method = method;
    o.beam_lights.single_scattering = 2;
    o.beams.radius0 = radius0;
    vbl_film* f = render(s, o);
    double d = layer_sum(f, "volume_direct", 64), m = layer_sum(f, "volume_from_volume", 64);
    printf("extreme %s R0 %g g %g light %d: volume_direct %g volume_from_volume %g\n", vbl_render_method_name(method),
           radius0, g, light, d, m);
    assert_true(isfinite(d) && isfinite(m));
    assert_true(layer_min(f, "volume_direct", 64) >= 0.0 && layer_min(f, "volume_from_volume", 64) >= 0.0);
    vbl_film_release(f);
    vbl_scene_release(s);
    vt_free(vol);
}

static void test_extremes(void** state)
{
    (void)state;
    const double radii[3] = {0.0, 2e-4 * BOX_DIAG, 10.0 * BOX_DIAG}; /* below 1e-4 x: refused */
    const int methods[2] = {VBL_RENDER_BEAMS, VBL_RENDER_VBL};
    for (int k = 0; k < 2; ++k)
        for (int r = 0; r < 3; ++r) {
            extreme(radii[r], 0.999, vbl_v3(0.2, -4, 0.3), vbl_v3(0, 0, 0), 0, methods[k]);
            extreme(radii[r], -0.999, vbl_v3(0.2, -4, 0.3), vbl_v3(0, 0, 0), 0, methods[k]);
            extreme(radii[r], 0.0, vbl_v3(0.0, -4, 0.0), vbl_v3(0, 0, 0), 1, methods[k]);
            extreme(radii[r], 0.999, vbl_v3(0.0, -4, 0.0), vbl_v3(0, 0, 0), 1, methods[k]);
            extreme(radii[r], -0.999, vbl_v3(0.0, -4, 0.0), vbl_v3(0, 0, 0), 2, methods[k]);
            extreme(radii[r], 0.5, vbl_v3(0.1, -0.2, 0.1), vbl_v3(0.3, 1, 0), 0, methods[k]); /* camera inside */
        }
}

/* The gather stops at t_max: nothing beyond a wall in front of the medium, and half the ray's
 * length gives a smaller but non-zero estimate. */
static void test_t_max(void** state)
{
    (void)state;
    vbl_volume* vol;
    vbl_scene* s = box_scene(vbl_v3(0.2, -4, 0.3), vbl_v3(0, 0, 0), 1.0, 0.8, 0.0, &vol, 4);
    tt_add_point(s, vbl_v3(0.4, 0.3, 1.6), 10.0);
    vbl_render_context ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.scene = s;
    ctx.extinction = &s->extinction;
    ctx.options = tt_options(1, 1, 400, 3);
    ctx.tracking.estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    ctx.threads = 1;
    void* store = NULL;
    vbl_photon_beams_settings st = VBL_PHOTON_BEAMS_SETTINGS_DEFAULT;
    st.radius0 = 0.3;
    assert_int_equal(vbl_photon_beams_pass_begin_with(&ctx, &st, &store), VBL_SUCCESS);
    assert_true(vbl_photon_beams_store_radius(store) == 0.3);
    vbl_thread_state ts;
    memset(&ts, 0, sizeof ts);
    vbl_extinction_cursor_init(&ts.cursor, ctx.extinction);
    vbl_camera_sample cs;
    memset(&cs, 0, sizeof cs);
    cs.origin = vbl_v3(0.2, -4, 0.3);
    cs.direction = vbl_v3_normalize(vbl_v3(-0.2, 4, -0.3));
    double sums[3];
    const double tmax[3] = {INFINITY, 4.0, 2.5}; /* the box starts at ~3 */
    for (int k = 0; k < 3; ++k) {
        cs.t_max = tmax[k];
        double sum = 0.0;
        for (int i = 0; i < 64; ++i) {
            vbl_rng rng = vbl_rng_make(9, 0, (uint64_t)i);
            vbl_sample_value v;
            memset(&v, 0, sizeof v);
            vbl_photon_beams_camera_sample(&ctx, store, &ts, &cs, &rng, &v);
            sum += v.L[VBL_CLASS_VOLUME_DIRECT].x + v.L[VBL_CLASS_VOLUME_FROM_VOLUME].x;
        }
        sums[k] = sum;
    }
    printf("t_max: inf %g, 4 %g, 2.5 %g\n", sums[0], sums[1], sums[2]);
    assert_true(sums[0] > sums[1] && sums[1] > 0.0);
    assert_true(sums[2] == 0.0);
    vbl_photon_beams_pass_end(&ctx, store);
    vbl_scene_release(s);
    vt_free(vol);
}

static void test_bad_options(void** state)
{
    (void)state;
    vbl_volume* vol;
    vbl_scene* s = box_scene(vbl_v3(0.2, -4, 0.3), vbl_v3(0, 0, 0), 1.0, 0.8, 0.0, &vol, 4);
    tt_add_point(s, vbl_v3(0.4, 0.3, 1.6), 10.0);
    vbl_render_options o = tt_options(1, 1, 4, 1);
    o.method = VBL_RENDER_BEAMS;
    vbl_film* f = NULL;
    o.beams.alpha = 1.0;
    assert_int_equal(vbl_render(s, &o, &f), VBL_ERROR_INVALID_ARGUMENT);
    o.beams.alpha = 0.0;
    o.beams.radius0 = -1.0;
    assert_int_equal(vbl_render(s, &o, &f), VBL_ERROR_INVALID_ARGUMENT);
    o.beams.radius0 = NAN;
    assert_int_equal(vbl_render(s, &o, &f), VBL_ERROR_INVALID_ARGUMENT);
    o.beams.radius0 = 0.0;
    o.method = VBL_RENDER_VBL;
    o.beam_lights.single_scattering = 3;
    assert_int_equal(vbl_render(s, &o, &f), VBL_ERROR_INVALID_ARGUMENT);
    o.method = 5;
    o.beam_lights.single_scattering = 0;
    assert_int_equal(vbl_render(s, &o, &f), VBL_ERROR_INVALID_ARGUMENT);
    assert_null(f);
    vbl_scene_release(s);
    vt_free(vol);
}

#define CAMERA "\"camera\": {\"position\": [0, -5, 0], \"look_at\": [0, 0, 0], \"fov_deg\": 30, \"resolution\": [4, 3]}"

static void expect_scene_error(const char* dir, const char* render_block, const char* suffix)
{
    char text[1024], path[512], expected[1024];
    snprintf(text, sizeof text, "{" CAMERA ", \"render\": %s}", render_block);
    rt_write_file(dir, "scene.json", text, path);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(path, &scene), VBL_ERROR_SCENE);
    snprintf(expected, sizeof expected, "%s: %s", path, suffix);
    assert_string_equal(vbl_last_error_message(), expected);
    assert_null(scene);
}

static void test_scene_block(void** state)
{
    (void)state;
    char dir[256], path[512];
    rt_make_temp_dir(dir);
    rt_write_file(dir, "ok.json",
                  "{" CAMERA ", \"render\": {\"method\": \"beams\", \"beams\": {\"radius0\": 0.125, \"alpha\": 0.75}, "
                  "\"vbl\": {\"single_scattering\": \"beams\"}}}",
                  path);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(path, &scene), VBL_SUCCESS);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    assert_true(o.beams.radius0 == 0.0 && o.beams.alpha == 0.0 && o.beam_lights.single_scattering == 0);
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    assert_int_equal(o.method, VBL_RENDER_BEAMS);
    assert_true(o.beams.radius0 == 0.125 && o.beams.alpha == 0.75 && o.beam_lights.single_scattering == 2);
    vbl_scene_release(scene);
    rt_write_file(dir, "ok2.json", "{" CAMERA ", \"render\": {\"vbl\": {\"single_scattering\": \"equiangular\"}}}",
                  path);
    assert_int_equal(vbl_scene_load(path, &scene), VBL_SUCCESS);
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    assert_int_equal(o.beam_lights.single_scattering, 1);
    vbl_scene_release(scene);
    expect_scene_error(dir, "{\"beams\": {\"alpha\": 1}}", "render.beams.alpha = 1 is outside (0, 1)");
    expect_scene_error(dir, "{\"beams\": {\"radius0\": 0}}", "render.beams.radius0 = 0 is outside (0, inf)");
    expect_scene_error(dir, "{\"beams\": {\"width\": 2}}", "unknown key 'render.beams.width'");
    expect_scene_error(dir, "{\"vbl\": {\"single_scattering\": \"magic\"}}",
                       "render.vbl.single_scattering = \"magic\" is not one of equiangular, beams");
    expect_scene_error(dir, "{\"method\": \"magic\"}", "render.method = \"magic\" is not one of pt, vpl, vrl, vbl, beams");
    rt_remove_dir(dir);
}

/* ---- convergence to pt ------------------------------------------------------------------ */

enum { CV_RES = 8, CV_NP = CV_RES * CV_RES, CV_MAXP = 8 };

typedef struct cv_snap {
    const char* layer;
    int checkpoints[CV_MAXP], n;
    double* images; /* n x CV_NP */
} cv_snap;

static int cv_callback(const vbl_render_progress* p, void* user)
{
    cv_snap* c = user;
    for (int k = 0; k < c->n; ++k) {
        if (c->checkpoints[k] != p->pass) continue;
        vbl_film* f = NULL;
        assert_int_equal(vbl_render_snapshot(p, &f), VBL_SUCCESS);
        const float* px = vbl_film_layer_rgb(f, c->layer);
        assert_non_null(px);
        for (int i = 0; i < CV_NP; ++i) c->images[k * CV_NP + i] = (px[3 * i] + px[3 * i + 1] + px[3 * i + 2]) / 3.0;
        vbl_film_release(f);
    }
    return 0;
}

static void reference(const vbl_scene* s, const char* layer, int max_bounces, int passes, int spp, double* ref)
{
    vbl_render_options o = tt_options(passes, spp, 0, 77);
    o.max_bounces = max_bounces;
    vbl_film* f = NULL;
    assert_int_equal(vbl_render_with_estimator(s, &o, &vbl_estimator_pt, &f), VBL_SUCCESS);
    const float* p = vbl_film_layer_rgb(f, layer);
    assert_non_null(p);
    for (int i = 0; i < CV_NP; ++i) ref[i] = (p[3 * i] + p[3 * i + 1] + p[3 * i + 2]) / 3.0;
    vbl_film_release(f);
}

/* RMSE over K seeds (sqrt of the mean squared pixel error) at each checkpoint. */
static void cv_errors(const vbl_scene* s, const char* layer, int max_bounces, const double* ref, const int* checkpoints,
                      int n, int K, int light_paths, double r0, double alpha, double* rmse, double* mean_out)
{
    double images[CV_MAXP * CV_NP];
    cv_snap c = {layer, {0}, n, images};
    memcpy(c.checkpoints, checkpoints, sizeof(int) * (size_t)n);
    for (int k = 0; k < n; ++k) rmse[k] = 0.0;
    double mean = 0.0;
    for (int j = 0; j < K; ++j) {
        vbl_render_options o = tt_options(checkpoints[n - 1], 2, light_paths, 1000 + 7919u * (uint64_t)j);
        o.method = VBL_RENDER_BEAMS;
        o.max_bounces = max_bounces;
        o.callback = cv_callback;
        o.callback_user_data = &c;
        o.beams.radius0 = r0;
        o.beams.alpha = alpha;
        vbl_film_release(render(s, o));
        for (int k = 0; k < n; ++k)
            for (int i = 0; i < CV_NP; ++i) {
                double e = images[k * CV_NP + i] - ref[i];
                rmse[k] += e * e / (CV_NP * K);
                if (k == n - 1) mean += images[k * CV_NP + i] / (CV_NP * K);
            }
    }
    for (int k = 0; k < n; ++k) rmse[k] = sqrt(rmse[k]);
    if (mean_out) *mean_out = mean;
}

static double fit_slope(const int* x, const double* y, int n)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int k = 0; k < n; ++k) {
        double lx = log((double)x[k]), ly = log(y[k]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

static void test_converge_single(void** state)
{
    (void)state;
    vbl_volume* vol;
    vbl_scene* s = box_scene(vbl_v3(0.125, -4.5, 0.125), vbl_v3(0.125, 0.125, 0.125), 1.0, 0.8, 0.3, &vol, CV_RES);
    /* a narrow shaft (cone of 5 degrees, ~0.3 wide in the box) seen from the side: a wide beam
     * blurs it over several pixels (bias), a thin one is noisy (variance) */
    tt_add_spot(s, vbl_v3(0.125, 0.125, 3.0), vbl_v3(0.1, 0.05, -1), 1000.0, 3.0, 5.0);
    double ref[CV_NP], ref_mean = 0.0, ref_rms = 0.0;
    /* 32 passes: the mean of 16 (seed 77) has a ~2.7 % s.e. (8 seeds of 4 passes: s.d. 5 %); after
     * the tracker's carried optical depth its draw sat 2.4 s.e. low and the 10 % mean check failed
     * (old/new pt means over those 8 seeds: 0.01594 / 0.01631, z 0.9) */
    reference(s, "volume_direct", 1, 32, 512, ref);
    for (int i = 0; i < CV_NP; ++i) ref_mean += ref[i] / CV_NP;
    for (int i = 0; i < CV_NP; ++i) ref_rms += ref[i] * ref[i] / CV_NP;
    ref_rms = sqrt(ref_rms);
    const int cps[7] = {1, 2, 4, 8, 16, 32, 64};
    const double alpha = 0.7, r0 = 0.8;
    double rmse[7], fixed[7], mean;
    cv_errors(s, "volume_direct", 1, ref, cps, 7, 6, 256, r0, alpha, rmse, &mean);
    /* the same renders at a fixed width: schedule with alpha -> 1 is not allowed in options, so a
     * fixed width is approximated by the settings at alpha = 0.999 (R_64 / R_0 = 0.996) */
    cv_errors(s, "volume_direct", 1, ref, cps, 7, 6, 256, r0, 0.999, fixed, NULL);
    double slope = fit_slope(cps, rmse, 7);
    double e = vbl_radius_rmse_exponent(alpha, 1);
    for (int k = 0; k < 7; ++k)
        printf("single scattering P = %2d: RMSE %.4g (fixed width %.4g), ref mean %.4g\n", cps[k], rmse[k], fixed[k],
               ref_mean);
    printf("slope %.3f (expected about %.3f), final RMSE / RMS of pt %.3f, image mean %.4g vs pt %.4g\n", slope, e,
           rmse[6] / ref_rms, mean, ref_mean);
    assert_true(ref_mean > 0.0);
    assert_true(slope < e + 0.15 && slope > -0.8);
    assert_true(rmse[6] < 0.3 * rmse[0]);
    assert_true(rmse[6] < 0.3 * ref_rms);
    assert_true(rmse[6] < 0.6 * fixed[6]); /* the fixed width stalls at its bias */
    assert_true(fabs(mean - ref_mean) < 0.1 * ref_mean);
    vbl_scene_release(s);
    vt_free(vol);
}

static void test_converge_multiple(void** state)
{
    (void)state;
    vbl_volume* vol;
    vbl_scene* s = box_scene(vbl_v3(0.2, -4, 0.3), vbl_v3(0.125, 0.125, 0.125), 1.0, 0.9, 0.0, &vol, CV_RES);
    tt_add_point(s, vbl_v3(0.4, 0.3, 1.6), 10.0);
    double ref[CV_NP], ref_mean = 0.0;
    reference(s, "volume_from_volume", -1, 16, 1024, ref);
    for (int i = 0; i < CV_NP; ++i) ref_mean += ref[i] / CV_NP;
    const int cps[4] = {2, 8, 32, 128};
    double rmse[4], mean;
    cv_errors(s, "volume_from_volume", -1, ref, cps, 4, 8, 32, 0.6, 0.7, rmse, &mean);
    for (int k = 0; k < 4; ++k) printf("volume_from_volume P = %3d: RMSE %.4g (ref mean %.4g)\n", cps[k], rmse[k], ref_mean);
    double slope = fit_slope(cps, rmse, 4);
    printf("slope %.3f (expected about %.3f), image mean %.4g vs pt %.4g\n", slope, vbl_radius_rmse_exponent(0.7, 1),
           mean, ref_mean);
    assert_true(ref_mean > 0.0);
    assert_true(rmse[3] < 0.5 * rmse[0]);
    assert_true(slope < -0.2 && slope > -0.8);
    assert_true(fabs(mean - ref_mean) < 0.05 * ref_mean); /* 8 seeds x 128 passes: a sanity bound */
    vbl_scene_release(s);
    vt_free(vol);
}

int main(int argc, char** argv)
{
    if (argc > 1 && !strcmp(argv[1], "converge")) {
        const struct CMUnitTest slow[] = {cmocka_unit_test(test_converge_single)};
        return cmocka_run_group_tests(slow, NULL, NULL);
    }
    if (argc > 1 && !strcmp(argv[1], "multiple")) {
        const struct CMUnitTest slow[] = {cmocka_unit_test(test_converge_multiple)};
        return cmocka_run_group_tests(slow, NULL, NULL);
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_registry),    cmocka_unit_test(test_determinism), cmocka_unit_test(test_extremes),
        cmocka_unit_test(test_vbl_single_scattering_is_beams),
        cmocka_unit_test(test_t_max),       cmocka_unit_test(test_bad_options), cmocka_unit_test(test_scene_block),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
