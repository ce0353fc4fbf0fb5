/* pixel_focus (render/pixel_focus.h): the pixel holding a point light's image draws half its
 * positions with density ~ 1/r around the image.
 *   - the sampler: chi-square of positions against vbl_pixel_focus_pdf on a 12 x 12 grid of cells
 *     (the image at the centre, near an edge, near a corner), the weight 1 / p: at most 1 / alpha,
 *     mean 1 within 4.5 standard errors (the pixel's area), and finite at the image itself;
 *   - the foci: a point light inside the media's box in front of the camera has one, in its image's
 *     pixel; outside the box or behind the camera none;
 *   - renders: bit-identical at 1 and 2 threads and different from pixel_focus false; every layer's
 *     image mean agrees within Z_CRIT standard errors with the focus off, and the light's pixel's
 *     volume_direct standard error is lower (a point light inside a sphere of smoke, seen through
 *     it: under uniform positions that pixel's variance is infinite). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "chi2.h"
#include "core/rng.h"
#include "render/pixel_focus.h"
#include "render_test_util.h"
#include "surface_render_util.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

#define G 12
#define N 300000
#define K 24
#define Z_CRIT 4.5

/* The mixture's mass in cell (i, j) of the G x G grid of pixel (3, 5): the midpoint rule on
 * 16 x 16 sub-cells (the 1/r density is smooth there; the cell holding the image takes the rest
 * of the unit mass, check_focus). */
static double cell_mass(const vbl_pixel_focus* f, int i, int j)
{
    const int S = 16;
    double m = 0.0;
    for (int a = 0; a < S; ++a)
        for (int b = 0; b < S; ++b) {
            double x = f->px + (i + (a + 0.5) / S) / G, y = f->py + (j + (b + 0.5) / S) / G;
            m += vbl_pixel_focus_pdf(f, x, y);
        }
    return m / (S * S) / (G * G);
}

static int check_focus(double cx, double cy, uint64_t seed)
{
    vbl_pixel_focus f;
    assert_true(vbl_pixel_focus_make(3, 5, cx, cy, &f));
    static double obs[G * G], expct[G * G];
    memset(obs, 0, sizeof obs);
    vbl_rng rng = vbl_rng_make(seed, 0, 0);
    double sw = 0.0, sw2 = 0.0;
    int ok = 1;
    for (int n = 0; n < N; ++n) {
        double sx, sy;
        double w = vbl_pixel_focus_sample(&f, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &sx, &sy);
        ok &= sx >= 3.0 && sx < 4.0 && sy >= 5.0 && sy < 6.0;
        ok &= w > 0.0 && w <= 1.0 / VBL_PIXEL_FOCUS_ALPHA + 1e-12;
        sw += w;
        sw2 += w * w;
        int i = (int)((sx - 3.0) * G), j = (int)((sy - 5.0) * G);
        i = i < 0 ? 0 : (i >= G ? G - 1 : i);
        j = j < 0 ? 0 : (j >= G ? G - 1 : j);
        obs[i * G + j] += 1.0;
    }
    /* the cell with the image: its 1/r mass by the midpoint rule is poor; take it as the rest */
    const int ci = (int)((cx - 3.0) * G) < G ? (int)((cx - 3.0) * G) : G - 1, cj = (int)((cy - 5.0) * G) < G ? (int)((cy - 5.0) * G) : G - 1;
    double rest = 0.0;
    for (int i = 0; i < G; ++i)
        for (int j = 0; j < G; ++j) {
            expct[i * G + j] = (i == ci && j == cj) ? 0.0 : N * cell_mass(&f, i, j);
            rest += expct[i * G + j];
        }
    expct[ci * G + cj] = N - rest;
    const double mean = sw / N, se = sqrt((sw2 / N - mean * mean) / N);
    printf("focus (%.3f, %.3f): mean weight %.5f +- %.5f\n", cx, cy, mean, se);
    ok &= fabs(mean - 1.0) <= 4.5 * se;
    ok &= expct[ci * G + cj] > 0.0;
    char label[64];
    snprintf(label, sizeof label, "focus %.2f %.2f", cx - 3.0, cy - 5.0);
    return ok & vbl_chi2_check(label, obs, expct, G * G, 0.01, 3);
}

static void test_sampler(void** state)
{
    (void)state;
    int ok = check_focus(3.5, 5.5, 1);
    ok &= check_focus(3.93, 5.31, 2);  /* near an edge */
    ok &= check_focus(3.02, 5.985, 3); /* near a corner */
    assert_true(ok);
    /* the image itself: weight 0 (a null set), finite */
    vbl_pixel_focus f;
    assert_true(vbl_pixel_focus_make(0, 0, 0.5, 0.5, &f));
    assert_true(isinf(vbl_pixel_focus_pdf(&f, 0.5, 0.5)));
    /* an image outside the pixel makes no focus */
    assert_false(vbl_pixel_focus_make(0, 0, 1.5, 0.5, &f));
}

/* The sphere of smoke tt_make_sphere(16, 0.9) seen from 4 units away in an 8 x 8 film, a point light
 * at (0.05, -0.3, 0.02) inside it (its image near the film's centre). */
static vbl_scene* light_in_smoke(vbl_volume** volume)
{
    vbl_camera cam = rt_camera(vbl_v3(0.0, -4.0, 0.0), vbl_v3(0, 0, 0), 30.0, 8, 8);
    vbl_scene* scene = tt_scene(&cam);
    *volume = tt_make_sphere(16, 0.9);
    assert_int_equal(vbl_scene_add_medium(scene, *volume, 1.5, vbl_v3(0.8, 0.8, 0.8), 0.3, NULL), VBL_SUCCESS);
    tt_add_point(scene, vbl_v3(0.05, -0.3, 0.02), 2.0);
    return scene;
}

static void test_foci(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = light_in_smoke(&volume);
    vbl_pixel_foci foci;
    vbl_pixel_foci_build(scene, 1, vbl_v3(-1, -1, -1), vbl_v3(1, 1, 1), &foci);
    assert_int_equal(foci.count, 1);
    double sx, sy;
    assert_true(vbl_camera_raster(&scene->camera, vbl_v3(0.05, -0.3, 0.02), &sx, &sy));
    assert_int_equal(foci.focus[0].px, (int)sx);
    assert_int_equal(foci.focus[0].py, (int)sy);
    /* the raster position maps back to a ray through the light */
    vbl_vec3 o, d;
    vbl_camera_ray(&scene->camera, sx, sy, &o, &d);
    vbl_vec3 to = vbl_v3_normalize(vbl_v3_sub(vbl_v3(0.05, -0.3, 0.02), o));
    assert_true(vbl_v3_dot(to, d) > 1.0 - 1e-12);
    vbl_pixel_foci_build(scene, 1, vbl_v3(0.5, 0.5, 0.5), vbl_v3(1, 1, 1), &foci); /* the light outside the box */
    assert_int_equal(foci.count, 0);
    vbl_pixel_foci_build(scene, 0, vbl_v3(-1, -1, -1), vbl_v3(1, 1, 1), &foci); /* no media */
    assert_int_equal(foci.count, 0);
    assert_false(vbl_camera_raster(&scene->camera, vbl_v3(0.0, -5.0, 0.0), &sx, &sy)); /* behind */
    vbl_scene_release(scene);
    vt_free(volume);
}

typedef struct focus_config {
    int focus, threads;
} focus_config;

static vbl_film* render_cfg(const vbl_scene* scene, const void* cfg_ptr, uint64_t seed)
{
    const focus_config* cfg = cfg_ptr;
    vbl_render_options o = tt_options(1, 16, 0, seed);
    o.method = VBL_RENDER_PT;
    o.pixel_focus = cfg->focus;
    if (cfg->threads > 0) o.threads = cfg->threads;
    return render_or_fail(scene, &o);
}

static void test_renders(void** state)
{
    (void)state;
    vbl_volume* volume;
    vbl_scene* scene = light_in_smoke(&volume);
    const focus_config on1 = {1, 1}, on2 = {1, 2}, off = {0, 2};
    check_configs_deterministic(render_cfg, scene, &on1, &on2, &off);
    double m1[VBL_CLASS_COUNT], s1[VBL_CLASS_COUNT], m0[VBL_CLASS_COUNT], s0[VBL_CLASS_COUNT];
    layer_stats(render_cfg, scene, &on2, K, 11, m1, s1);
    layer_stats(render_cfg, scene, &off, K, 22, m0, s0);
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        if (!(m0[l] > 0.0)) continue;
        double z = (m1[l] - m0[l]) / sqrt(s1[l] * s1[l] + s0[l] * s0[l]);
        printf("%-22s focus %.6f (se %.6f)  uniform %.6f (se %.6f)  z = %+.2f\n", layer_names[l], m1[l], s1[l], m0[l],
               s0[l], z);
        assert_true(fabs(z) <= Z_CRIT);
    }
    /* the light's pixel: volume_direct's spread over the K renders */
    double sx, sy;
    assert_true(vbl_camera_raster(&scene->camera, vbl_v3(0.05, -0.3, 0.02), &sx, &sy));
    const int px = (int)sx, py = (int)sy;
    double sd[2];
    for (int c = 0; c < 2; ++c) {
        focus_config cfg = {1 - c, 0};
        double s = 0.0, s2 = 0.0;
        for (int k = 0; k < K; ++k) {
            vbl_film* f = render_cfg(scene, &cfg, 100 + 7919u * (uint64_t)k);
            const float* L = vbl_film_layer_rgb(f, "volume_direct");
            const double v = L[3 * (py * 8 + px)] + L[3 * (py * 8 + px) + 1] + L[3 * (py * 8 + px) + 2];
            s += v;
            s2 += v * v;
            vbl_film_release(f);
        }
        sd[c] = sqrt(fmax(0.0, (s2 - s * s / K) / (K - 1)));
    }
    printf("light's pixel (%d, %d): volume_direct sd focus %.4f, uniform %.4f\n", px, py, sd[0], sd[1]);
    assert_true(sd[0] < 0.8 * sd[1]);
    vbl_scene_release(scene);
    vt_free(volume);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sampler),
        cmocka_unit_test(test_foci),
        cmocka_unit_test(test_renders),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
