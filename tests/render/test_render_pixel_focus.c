/* pixel_focus (render/pixel_focus.h): the pixel holding a point light's image, and its neighbours
 * within a pixel of the image, draw half their positions with density ~ 1/r around the image.
 *   - the sampler: chi-square of positions against vbl_pixel_focus_pdf on a 12 x 12 grid of cells
 *     (the image at the centre, near an edge, near a corner; and outside the pixel: just past an
 *     edge, past a corner, 0.8 away), the weight 1 / p: at most 1 / alpha, mean 1 within 4.5
 *     standard errors (the pixel's area), and finite at the image itself; with the image outside,
 *     the density integrates to 1 over the pixel (the near edges' triangles subtracted: adding
 *     them instead fails this and the chi-square); beyond the reach, no focus;
 *   - the foci: a point light inside the media's box in front of the camera has one in its image's
 *     pixel and one in each neighbour within the reach; outside the box or behind the camera none;
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
#include <stdlib.h>
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
    const int S = 32;
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
        const double choice = vbl_rng_uniform(&rng), u = vbl_rng_uniform(&rng), v = vbl_rng_uniform(&rng);
        double w = vbl_pixel_focus_sample(&f, choice, u, v, &rng, &sx, &sy);
        ok &= sx >= 3.0 && sx < 4.0 && sy >= 5.0 && sy < 6.0;
        ok &= w > 0.0 && w <= 1.0 / VBL_PIXEL_FOCUS_ALPHA + 1e-12;
        sw += w;
        sw2 += w * w;
        int i = (int)((sx - 3.0) * G), j = (int)((sy - 5.0) * G);
        i = i < 0 ? 0 : (i >= G ? G - 1 : i);
        j = j < 0 ? 0 : (j >= G ? G - 1 : j);
        obs[i * G + j] += 1.0;
    }
    /* the cell with the image: its 1/r mass by the midpoint rule is poor; take it as the rest.
     * An image outside the pixel has no such cell: every cell by the midpoint rule, whose sum must
     * be the unit mass (the near edges' subtraction in vbl_pixel_focus_make) */
    const int inside = cx >= 3.0 && cx <= 4.0 && cy >= 5.0 && cy <= 6.0;
    const int ci = (int)((cx - 3.0) * G) < G ? (int)((cx - 3.0) * G) : G - 1, cj = (int)((cy - 5.0) * G) < G ? (int)((cy - 5.0) * G) : G - 1;
    double rest = 0.0;
    for (int i = 0; i < G; ++i)
        for (int j = 0; j < G; ++j) {
            expct[i * G + j] = (inside && i == ci && j == cj) ? 0.0 : N * cell_mass(&f, i, j);
            rest += expct[i * G + j];
        }
    if (inside) {
        expct[ci * G + cj] = N - rest;
        ok &= expct[ci * G + cj] > 0.0;
    } else {
        printf("focus (%.3f, %.3f) outside: the density's mass over the pixel %.5f\n", cx, cy, rest / N);
        ok &= fabs(rest / N - 1.0) < 2e-3;
    }
    const double mean = sw / N, se = sqrt((sw2 / N - mean * mean) / N);
    printf("focus (%.3f, %.3f): mean weight %.5f +- %.5f\n", cx, cy, mean, se);
    ok &= fabs(mean - 1.0) <= 4.5 * se;
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
    ok &= check_focus(2.97, 5.4, 4);   /* just past the left edge */
    ok &= check_focus(4.06, 4.93, 5);  /* past a corner */
    ok &= check_focus(3.6, 6.8, 6);    /* 0.8 past the top edge */
    assert_true(ok);
    /* beyond the reach (1 pixel from the square): no focus */
    vbl_pixel_focus g;
    assert_false(vbl_pixel_focus_make(3, 5, 3.5, 7.05, &g));
    assert_false(vbl_pixel_focus_make(3, 5, 2.2, 4.2, &g)); /* 0.8 and 0.8 diagonally: 1.13 */
    assert_true(vbl_pixel_focus_make(3, 5, 2.4, 4.4, &g));  /* 0.6 and 0.6: 0.85 */
    /* the image itself: weight 0 (a null set), finite */
    vbl_pixel_focus f;
    assert_true(vbl_pixel_focus_make(0, 0, 0.5, 0.5, &f));
    assert_true(isinf(vbl_pixel_focus_pdf(&f, 0.5, 0.5)));
    /* an image more than the reach outside the pixel makes no focus */
    assert_false(vbl_pixel_focus_make(0, 0, 2.5, 0.5, &f));
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
    double sx, sy;
    assert_true(vbl_camera_raster(&scene->camera, vbl_v3(0.05, -0.3, 0.02), &sx, &sy));
    /* the image's pixel, its 4 edge neighbours (within 1 of the image) and the corner neighbours
     * within the reach */
    assert_true(foci.count >= 5 && foci.count <= 9);
    assert_non_null(vbl_pixel_foci_find(&foci, (int)sx, (int)sy));
    for (int i = 0; i < foci.count; ++i) {
        assert_true(abs(foci.focus[i].px - (int)sx) <= 1 && abs(foci.focus[i].py - (int)sy) <= 1);
        assert_true(foci.focus[i].cx == sx && foci.focus[i].cy == sy);
    }
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
            if (dx == 0 || dy == 0) assert_non_null(vbl_pixel_foci_find(&foci, (int)sx + dx, (int)sy + dy));
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
