/* Shared helpers of the surface render tests (test_surface_render_agreement.c,
 * test_surface_caustics.c, test_surface_blue_noise.c) and pt's per-layer agreement tests
 * (tests/render/test_render_pt_core.c, _sampler.c, _equiangular.c): layer names, a quad mesh,
 * layer sums and the layers-sum-to-beauty check, per-layer means over independent renders,
 * rendering with an estimator. Header-only (static); include after cmocka.h. */
#ifndef VBL_TEST_SURFACE_RENDER_UTIL_H
#define VBL_TEST_SURFACE_RENDER_UTIL_H

#include <math.h>

#include "core/math.h"
#include "material/material.h"
#include "render/render_internal.h"
#include "scene/scene.h"
#include "transport/common/estimator.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"

static const char* const layer_names[VBL_CLASS_COUNT] = {
    "background",          "surface_direct",      "volume_direct",     "surface_from_surface",
    "surface_from_volume", "volume_from_surface", "volume_from_volume", "volume_emission"};

/* The quad c +- u +- v (two triangles) with material m. */
static inline void add_quad(vbl_scene* scene, vbl_vec3 c, vbl_vec3 u, vbl_vec3 v, const vbl_material* m)
{
    double p[12];
    const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    for (int i = 0; i < 4; ++i) {
        vbl_vec3 q = vbl_v3_add(c, vbl_v3_add(vbl_v3_scale(u, su[i]), vbl_v3_scale(v, sv[i])));
        p[3 * i] = q.x;
        p[3 * i + 1] = q.y;
        p[3 * i + 2] = q.z;
    }
    unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    assert_int_equal(vbl_scene_add_mesh(scene, p, 4, idx, 2, m, NULL), VBL_SUCCESS);
}

/* Sum over pixels and channels of an RGB layer (0 if the film has no such layer). */
static inline double layer_total(const vbl_film* film, const char* name)
{
    const float* p = vbl_film_layer_rgb(film, name);
    const int n = vbl_film_width(film) * vbl_film_height(film);
    double s = 0.0;
    if (p)
        for (int i = 0; i < 3 * n; ++i) s += p[i];
    return s;
}

/* Every pixel's transport layers sum to its beauty (float rounding) and the film is finite;
 * returns the sum of |beauty| over pixels and channels. */
static inline double check_sum_to_beauty(const vbl_film* film)
{
    int ch = 0;
    const float* beauty = vbl_film_layer(film, "", &ch);
    assert_non_null(beauty);
    const int n = vbl_film_width(film) * vbl_film_height(film);
    double total = 0.0;
    for (int p = 0; p < n; ++p)
        for (int k = 0; k < 3; ++k) {
            double s = 0.0;
            for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
                const float* L = vbl_film_layer_rgb(film, layer_names[l]);
                if (L) s += L[3 * p + k];
            }
            double b = beauty[ch * p + k];
            assert_true(fabs(s - b) <= 1e-4 * fmax(1.0, fabs(b)));
            total += fabs(b);
        }
    assert_true(tt_film_finite(film));
    return total;
}

/* a and b (the same render at different thread counts) are bit-identical on every layer, and
 * d (another setting) differs from a somewhere: the setting takes effect deterministically. */
static inline void check_identical_and_differs(const vbl_film* a, const vbl_film* b, const vbl_film* d)
{
    const int n = 3 * vbl_film_width(a) * vbl_film_height(a);
    int differs = 0;
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        const float* pa = vbl_film_layer_rgb(a, layer_names[l]);
        const float* pb = vbl_film_layer_rgb(b, layer_names[l]);
        const float* pd = vbl_film_layer_rgb(d, layer_names[l]);
        assert_true((pa == NULL) == (pb == NULL));
        if (!pa) continue;
        assert_memory_equal(pa, pb, sizeof(float) * (size_t)n);
        for (int k = 0; pd && k < n; ++k) differs |= pa[k] != pd[k];
    }
    assert_true(differs);
}

/* One of layer_stats's renders: the film of `scene` under the caller's `config` with `seed`. */
typedef vbl_film* (*layer_stats_render)(const vbl_scene* scene, const void* config, uint64_t seed);

/* Image means (per pixel, R+G+B) of every layer over `renders` independent films
 * render(scene, config, seed0 + 7919 k), k = 0 .. renders - 1, each checked to sum to its beauty
 * (check_sum_to_beauty): the mean and its standard error per layer. */
static inline void layer_stats(layer_stats_render render, const vbl_scene* scene, const void* config, int renders,
                               uint64_t seed0, double mean[VBL_CLASS_COUNT], double se[VBL_CLASS_COUNT])
{
    double s[VBL_CLASS_COUNT] = {0}, s2[VBL_CLASS_COUNT] = {0};
    for (int k = 0; k < renders; ++k) {
        vbl_film* film = render(scene, config, seed0 + 7919u * (uint64_t)k);
        check_sum_to_beauty(film);
        const int pixels = vbl_film_width(film) * vbl_film_height(film);
        for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
            double m = layer_total(film, layer_names[l]) / pixels;
            s[l] += m;
            s2[l] += m * m;
        }
        vbl_film_release(film);
    }
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        mean[l] = s[l] / renders;
        double var = (s2[l] - renders * mean[l] * mean[l]) / (renders - 1);
        se[l] = sqrt(fmax(var, 0.0) / renders);
    }
}

/* vbl_render(scene, o), failing the test with the library's message on error. */
static inline vbl_film* render_or_fail(const vbl_scene* scene, const vbl_render_options* o)
{
    vbl_film* film = NULL;
    if (vbl_render(scene, o, &film) != VBL_SUCCESS) fail_msg("render: %s", vbl_last_error_message());
    return film;
}

/* The films of on1 and on2 (one configuration at 1 and at 2 threads) with seed 5 are bit-identical
 * and differ from off's (check_identical_and_differs): the option is deterministic and active. */
static inline void check_configs_deterministic(layer_stats_render render, const vbl_scene* scene, const void* on1,
                                               const void* on2, const void* off)
{
    vbl_film* a = render(scene, on1, 5);
    vbl_film* b = render(scene, on2, 5);
    vbl_film* d = render(scene, off, 5);
    check_identical_and_differs(a, b, d);
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_film_release(d);
}

/* Layer means of configurations `on` and `off` over `renders` renders each (layer_stats, seeds 11
 * and 22): on every layer where off's mean is positive, the pooled standard error is below 0.2x
 * that mean and |z| <= z_crit; at least min_checked such layers. Prints a line per layer, the
 * configurations named on_name and off_name. Returns on's standard error over off's on se_layer. */
static inline double check_layers_agree(layer_stats_render render, const vbl_scene* scene, const void* on,
                                        const void* off, int renders, double z_crit, int min_checked, int se_layer,
                                        const char* on_name, const char* off_name)
{
    double m1[VBL_CLASS_COUNT], s1[VBL_CLASS_COUNT], m0[VBL_CLASS_COUNT], s0[VBL_CLASS_COUNT];
    layer_stats(render, scene, on, renders, 11, m1, s1);
    layer_stats(render, scene, off, renders, 22, m0, s0);
    int checked = 0;
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        if (!(m0[l] > 0.0)) continue;
        const double se = sqrt(s1[l] * s1[l] + s0[l] * s0[l]), z = (m1[l] - m0[l]) / se;
        printf("%-22s %s %.6f (se %.6f)  %s %.6f (se %.6f)  z = %+.2f  se ratio %.2f\n", layer_names[l], on_name, m1[l],
               s1[l], off_name, m0[l], s0[l], z, s1[l] / s0[l]);
        assert_true(se > 0.0 && se < 0.2 * m0[l]);
        assert_true(fabs(z) <= z_crit);
        ++checked;
    }
    assert_true(checked >= min_checked);
    return s1[se_layer] / s0[se_layer];
}

/* Renders with estimator est (tt_options plus threads and max_bounces); fails the test on error. */
static inline vbl_film* render_with(const vbl_scene* scene, const vbl_estimator* est, int passes, int spp, int paths,
                                    uint64_t seed, int threads, int max_bounces)
{
    vbl_render_options o = tt_options(passes, spp, paths, seed);
    o.threads = threads;
    o.max_bounces = max_bounces;
    vbl_film* film = NULL;
    if (vbl_render_with_estimator(scene, &o, est, &film) != VBL_SUCCESS)
        fail_msg("render: %s", vbl_last_error_message());
    return film;
}

#endif
