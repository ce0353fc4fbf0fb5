/* Cancellation inside a pass (issue 18, #13 item 5): vbl_render_options.cancel stops the pass in
 * progress at its next pixel and drops it, so the film is exactly the film of the complete passes;
 * the time limit cuts passes the same way, the first one included (light tracing and builds:
 * test_render_stop_phases.c). Asserted on pass counts and pixels,
 * never on time. A custom estimator raises the flag at a fixed pixel of a fixed pass, so where the
 * pass stops is deterministic. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <pthread.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "render/render_internal.h"
#include "render_test_util.h"
#include "vbl/vbl.h"

#define W 40
#define H 24

static volatile int g_cancel;
static int g_cancel_pass = -1;
static uint64_t g_cancel_pixel;

static void flag_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                        const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    (void)store;
    (void)ts;
    double u = vbl_rng_uniform(rng);
    out->L[VBL_CLASS_VOLUME_FROM_VOLUME] = (vbl_vec3){u, 0.5 * u, 0.25 + 0.1 * (double)ctx->pass};
    out->L[VBL_CLASS_VOLUME_DIRECT] = (vbl_vec3){1.0 - u, u * u, 0.5};
    if ((int)ctx->pass == g_cancel_pass && sample->pixel_index == g_cancel_pixel) g_cancel = 1;
}

static const vbl_estimator flag_estimator = {"cancel_test", 0, NULL, flag_sample, NULL, NULL};


static int setup(void** state)
{
    (void)state;
    /* a medium and a light, so the film has the layers the test estimators write */
    return rt_lit_box_setup(W, H, 1);
}

static vbl_render_options options(int passes)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.passes = passes;
    o.spp = 2;
    o.threads = 2;
    o.seed = 7;
    return o;
}

static vbl_film* render_plain(int passes)
{
    vbl_render_options o = options(passes);
    vbl_film* film = NULL;
    g_cancel_pass = -1;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &flag_estimator, &film), VBL_SUCCESS);
    return film;
}

static void assert_same_pixels(const vbl_film* a, const vbl_film* b)
{
    static const char* const layers[] = {"", "volume_direct", "volume_from_volume"};
    for (int l = 0; l < 3; ++l) {
        int ca = 0, cb = 0;
        const float* pa = vbl_film_layer(a, layers[l], &ca);
        const float* pb = vbl_film_layer(b, layers[l], &cb);
        assert_non_null(pa);
        assert_non_null(pb);
        assert_int_equal(ca, cb);
        assert_memory_equal(pa, pb, sizeof(float) * (size_t)ca * W * H);
        double sum = 0.0;
        for (int i = 0; i < ca * W * H; ++i) sum += pa[i];
        assert_true(sum > 0.0); /* the layer holds the estimator's values */
    }
}

static vbl_film_stats stats_of(const vbl_film* film)
{
    vbl_film_stats s;
    memset(&s, 0, sizeof s);
    s.size = sizeof s;
    assert_int_equal(vbl_film_get_stats(film, &s), VBL_SUCCESS);
    return s;
}

/* Raised in the middle of the third pass: the film is the 2-pass film, bit for bit. */
static void test_cancel_mid_pass_drops_the_pass(void** state)
{
    (void)state;
    vbl_film* two = render_plain(2);
    vbl_render_options o = options(6);
    o.cancel = &g_cancel;
    g_cancel = 0;
    g_cancel_pass = 2;
    g_cancel_pixel = (uint64_t)(W * H / 2 + 3);
    vbl_film* film = NULL;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &flag_estimator, &film), VBL_ERROR_INTERRUPTED);
    assert_non_null(film);
    vbl_film_stats s = stats_of(film);
    assert_int_equal(s.passes, 2);
    assert_int_equal(s.cancelled, 1);
    assert_int_equal(s.discarded_pass, 1);
    assert_same_pixels(film, two);
    vbl_film_release(film);
    vbl_film_release(two);
}

/* Raised in the first pass (or before it): no complete pass, no film. */
static void test_cancel_in_first_pass(void** state)
{
    (void)state;
    vbl_render_options o = options(3);
    o.cancel = &g_cancel;
    g_cancel = 0;
    g_cancel_pass = 0;
    g_cancel_pixel = 17;
    vbl_film* film = (vbl_film*)&film;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &flag_estimator, &film), VBL_ERROR_INTERRUPTED);
    assert_null(film);
    g_cancel = 1;
    g_cancel_pass = -1;
    film = (vbl_film*)&film;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &flag_estimator, &film), VBL_ERROR_INTERRUPTED);
    assert_null(film);
    g_cancel = 0;
}

/* A flag that stays 0 changes nothing: bit-identical to a render without one. */
static void test_unset_flag_is_identical(void** state)
{
    (void)state;
    vbl_film* plain = render_plain(3);
    vbl_render_options o = options(3);
    o.cancel = &g_cancel;
    g_cancel = 0;
    g_cancel_pass = -1;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &flag_estimator, &film), VBL_SUCCESS);
    assert_int_equal(stats_of(film).discarded_pass, 0);
    assert_same_pixels(film, plain);
    vbl_film_release(film);
    vbl_film_release(plain);
}

/* A time limit already past stops the first pass: no film. With min_passes 1 the first pass
 * completes and the second stops at its first pixel and is dropped: the 1-pass film, marked
 * time_limited. */
static void test_time_limit_cuts_second_pass(void** state)
{
    (void)state;
    vbl_film* one = render_plain(1);
    vbl_render_options o = options(4);
    o.time_limit = 1e-12;
    vbl_film* film = (vbl_film*)&film;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &flag_estimator, &film), VBL_ERROR_INTERRUPTED);
    assert_null(film);
    o.min_passes = 1;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &flag_estimator, &film), VBL_SUCCESS);
    vbl_film_stats s = stats_of(film);
    assert_int_equal(s.passes, 1);
    assert_int_equal(s.time_limited, 1);
    assert_int_equal(s.cancelled, 0);
    assert_same_pixels(film, one);
    vbl_film_release(film);
    vbl_film_release(one);
}

static void* raise_later(void* arg)
{
    (void)arg;
    struct timespec t = {0, 200 * 1000 * 1000};
    nanosleep(&t, NULL);
    g_cancel = 1;
    return NULL;
}

/* A real method with a huge first pass (pt, 10^5 samples per pixel in a medium: minutes) returns once the
 * flag is raised from another thread, with no film (no pass completed). Were the flag ignored, the
 * test would run for the whole pass (minutes under the sanitizers) and near ctest's timeout. */
static void test_huge_pass_returns(void** state)
{
    (void)state;
    vbl_render_options o = options(2);
    o.method = VBL_RENDER_PT;
    o.spp = 100000;
    o.cancel = &g_cancel;
    g_cancel = 0;
    pthread_t thread;
    assert_int_equal(pthread_create(&thread, NULL, raise_later, NULL), 0);
    vbl_film* film = (vbl_film*)&film;
    assert_int_equal(vbl_render(rt_lit_box, &o, &film), VBL_ERROR_INTERRUPTED);
    assert_null(film);
    pthread_join(thread, NULL);
    g_cancel = 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cancel_mid_pass_drops_the_pass),
        cmocka_unit_test(test_cancel_in_first_pass),
        cmocka_unit_test(test_unset_flag_is_identical),
        cmocka_unit_test(test_time_limit_cuts_second_pass),
        cmocka_unit_test(test_huge_pass_returns),
    };
    return cmocka_run_group_tests(tests, setup, rt_lit_box_teardown);
}
