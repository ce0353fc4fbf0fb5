/* Stopping outside the camera pass (issue 18 item 4, #13 item 5): the cancel flag and the time
 * limit end light tracing (between blocks of light paths), the beam BVH build (every 1024
 * nodes) and the VRL tree build (every node over 1024 pieces) with VBL_ERROR_INTERRUPTED, and the driver then drops the pass, so the film holds the
 * complete passes bit for bit. Asserted on what the film holds and on what pass_begin returned,
 * never on time: were light tracing not interruptible, the real pass_begin below would return
 * VBL_SUCCESS (after minutes of tracing) and the assertions on its result fail. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render_internal.h"
#include "render_test_util.h"
#include "transport/photon_beams/beam_bvh.h"
#include "transport/photon_beams/photon_beams.h"
#include "transport/virtual_lights/vrl.h"
#include "transport/virtual_lights/vrl_tree.h"
#include "vbl/vbl.h"

#define W 24
#define H 16

static volatile int g_cancel;

/* The wrapped estimator (vrl or beams) and what its pass_begin returned per pass. */
static const vbl_estimator* g_inner;
static int g_cancel_pass = -1;   /* pass whose pass_begin raises the flag first (-1: none) */
static int g_thread_pass = -1;   /* pass whose pass_begin lets another thread raise it */
static vbl_result g_begin_result[8];
static volatile int g_tracing;   /* 1 while the inner pass_begin runs (for the other thread) */

static void* raise_when_tracing(void* arg)
{
    (void)arg;
    while (!g_tracing) {
    }
    g_cancel = 1;
    return NULL;
}

static vbl_result wrapped_begin(const vbl_render_context* ctx, void** store)
{
    pthread_t thread;
    int spawned = 0;
    if ((int)ctx->pass == g_cancel_pass) g_cancel = 1;
    if ((int)ctx->pass == g_thread_pass) spawned = pthread_create(&thread, NULL, raise_when_tracing, NULL) == 0;
    g_tracing = 1;
    vbl_result r = g_inner->pass_begin(ctx, store);
    g_tracing = 0;
    if (spawned) pthread_join(thread, NULL);
    if (ctx->pass < 8) g_begin_result[ctx->pass] = r;
    return r;
}

static void wrapped_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                           const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    g_inner->camera_sample(ctx, store, ts, sample, rng, out);
}

static void wrapped_end(const vbl_render_context* ctx, void* store)
{
    if (g_inner->pass_end) g_inner->pass_end(ctx, store);
}

static const vbl_estimator wrapped = {"stop_phases_test", 1, wrapped_begin, wrapped_sample, wrapped_end, NULL};

static int setup(void** state)
{
    (void)state;
    /* a medium and a light, so the film has the layers the test estimators write */
    return rt_lit_box_setup(W, H, 4);
}

static vbl_render_options options(vbl_render_method method, int passes, int light_paths)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.method = method;
    o.passes = passes;
    o.spp = 1;
    o.threads = 2;
    o.seed = 11;
    o.light_paths = light_paths;
    return o;
}

static void reset(void)
{
    g_cancel = 0;
    g_cancel_pass = g_thread_pass = -1;
    for (int i = 0; i < 8; ++i) g_begin_result[i] = (vbl_result)-1;
}

static void assert_same_film(const vbl_film* a, const vbl_film* b)
{
    int ca = 0, cb = 0;
    const float* pa = vbl_film_layer(a, "", &ca);
    const float* pb = vbl_film_layer(b, "", &cb);
    assert_non_null(pa);
    assert_non_null(pb);
    assert_int_equal(ca, cb);
    assert_memory_equal(pa, pb, sizeof(float) * (size_t)ca * W * H);
    double sum = 0.0;
    for (int i = 0; i < ca * W * H; ++i) sum += pa[i];
    assert_true(sum > 0.0);
}

static vbl_film_stats stats_of(const vbl_film* film)
{
    vbl_film_stats s;
    memset(&s, 0, sizeof s);
    s.size = sizeof s;
    assert_int_equal(vbl_film_get_stats(film, &s), VBL_SUCCESS);
    return s;
}

/* The flag, raised as pass 1's light tracing starts, stops it (pass_begin returns
 * VBL_ERROR_INTERRUPTED) and pass 1 is dropped: the film is the 1-pass film, bit for bit. */
static void run_cancel_in_light_tracing(vbl_render_method method, const vbl_estimator* inner)
{
    reset();
    g_inner = inner;
    vbl_render_options o = options(method, 1, 400);
    vbl_film* one = NULL;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &wrapped, &one), VBL_SUCCESS);
    assert_int_equal(g_begin_result[0], VBL_SUCCESS);

    reset();
    o = options(method, 4, 400);
    o.cancel = &g_cancel;
    g_cancel_pass = 1;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &wrapped, &film), VBL_ERROR_INTERRUPTED);
    assert_int_equal(g_begin_result[0], VBL_SUCCESS);
    assert_int_equal(g_begin_result[1], VBL_ERROR_INTERRUPTED);
    assert_int_equal((int)g_begin_result[2], -1); /* never started */
    assert_non_null(film);
    vbl_film_stats s = stats_of(film);
    assert_int_equal(s.passes, 1);
    assert_int_equal(s.cancelled, 1);
    assert_int_equal(s.discarded_pass, 1);
    assert_same_film(film, one);
    vbl_film_release(film);
    vbl_film_release(one);
    g_cancel = 0;
}

static void test_vrl_light_tracing_stops(void** state)
{
    (void)state;
    run_cancel_in_light_tracing(VBL_RENDER_VRL, &vbl_estimator_vrl);
}

static void test_beams_light_tracing_stops(void** state)
{
    (void)state;
    run_cancel_in_light_tracing(VBL_RENDER_BEAMS, &vbl_estimator_beams);
}

/* Another thread raises the flag while the first pass traces 2*10^7 light paths (minutes): the
 * tracing returns VBL_ERROR_INTERRUPTED, no pass completed, no film. */
static void test_other_thread_stops_huge_light_tracing(void** state)
{
    (void)state;
    reset();
    g_inner = &vbl_estimator_vrl;
    vbl_render_options o = options(VBL_RENDER_VRL, 2, 20000000);
    o.cancel = &g_cancel;
    g_thread_pass = 0;
    vbl_film* film = (vbl_film*)&film;
    assert_int_equal(vbl_render_with_estimator(rt_lit_box, &o, &wrapped, &film), VBL_ERROR_INTERRUPTED);
    assert_int_equal(g_begin_result[0], VBL_ERROR_INTERRUPTED);
    assert_null(film);
    assert_non_null(strstr(vbl_last_error_message(), "light tracing"));
    g_cancel = 0;
}

/* A time limit already past stops the first pass too (it used to always complete): no film,
 * VBL_ERROR_INTERRUPTED, and the message says the time limit did it. */
static void test_time_limit_stops_first_pass(void** state)
{
    (void)state;
    reset();
    vbl_render_options o = options(VBL_RENDER_VRL, 3, 20000000);
    o.time_limit = 1e-9;
    vbl_film* film = (vbl_film*)&film;
    assert_int_equal(vbl_render(rt_lit_box, &o, &film), VBL_ERROR_INTERRUPTED);
    assert_null(film);
    assert_non_null(strstr(vbl_last_error_message(), "time limit"));
}

static int g_stop_calls;
static int stop_after_first(void* user)
{
    (void)user;
    return ++g_stop_calls >= 2;
}

/* The beam BVH build asks its stop hook every 1024 nodes and ends with VBL_ERROR_INTERRUPTED and
 * an empty BVH; without a hook the same beams build. */
static void test_beam_bvh_build_stops(void** state)
{
    (void)state;
    enum { N = 20000 };
    vbl_beam* beams = calloc(N, sizeof *beams);
    assert_non_null(beams);
    for (int i = 0; i < N; ++i) {
        beams[i].origin = vbl_v3(0.001 * i, 0.0007 * (i % 97), 0.0003 * (i % 31));
        beams[i].direction = vbl_v3(0.0, 0.0, 1.0);
        beams[i].length = 0.05;
        beams[i].radius = 0.01;
    }
    vbl_beam_bvh bvh;
    assert_int_equal(vbl_beam_bvh_build(&bvh, beams, N, NULL), VBL_SUCCESS);
    assert_true(bvh.piece_count > 2048);
    vbl_beam_bvh_free(&bvh);
    vbl_beam_bvh_options bo;
    memset(&bo, 0, sizeof bo);
    bo.stop = stop_after_first;
    g_stop_calls = 0;
    assert_int_equal(vbl_beam_bvh_build(&bvh, beams, N, &bo), VBL_ERROR_INTERRUPTED);
    assert_int_equal(g_stop_calls, 2);
    assert_null(bvh.nodes);
    assert_null(bvh.pieces);
    vbl_beam_bvh_free(&bvh);
    free(beams);
}

/* The VRL tree build asks its stop hook at every node over 1024 pieces and ends with
 * VBL_ERROR_INTERRUPTED and an empty tree; without a hook the same VRLs build. */
static void test_vrl_tree_build_stops(void** state)
{
    (void)state;
    enum { N = 5000 };
    vbl_vrl* vrls = calloc(N, sizeof *vrls);
    assert_non_null(vrls);
    for (int i = 0; i < N; ++i) {
        vrls[i].origin = vbl_v3(0.001 * i, 0.0007 * (i % 97), 0.0003 * (i % 31));
        vrls[i].direction = vbl_v3(0.0, 0.0, 1.0);
        vrls[i].length = 0.05;
        vrls[i].power = vbl_v3(1.0, 1.0, 1.0);
    }
    vbl_vrl_tree tree;
    assert_int_equal(vbl_vrl_tree_build(&tree, vrls, N, -1, 1e-3, 0.0, NULL, NULL), VBL_SUCCESS);
    assert_int_equal(tree.light_count, N);
    vbl_vrl_tree_free(&tree);
    g_stop_calls = 0;
    const vbl_vrl_tree_stop_hook hook = {stop_after_first, NULL};
    assert_int_equal(vbl_vrl_tree_build_stoppable(&tree, vrls, N, -1, 1e-3, 0.0, NULL, NULL, &hook), VBL_ERROR_INTERRUPTED);
    assert_int_equal(g_stop_calls, 2);
    assert_null(tree.nodes);
    assert_null(tree.pieces);
    vbl_vrl_tree_free(&tree);
    free(vrls);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vrl_light_tracing_stops),
        cmocka_unit_test(test_beams_light_tracing_stops),
        cmocka_unit_test(test_other_thread_stops_huge_light_tracing),
        cmocka_unit_test(test_time_limit_stops_first_pass),
        cmocka_unit_test(test_beam_bvh_build_stops),
        cmocka_unit_test(test_vrl_tree_build_stops),
    };
    return cmocka_run_group_tests(tests, setup, rt_lit_box_teardown);
}
