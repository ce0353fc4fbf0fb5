/* Per-camera-ray VRL selection from the light tree (transport/virtual_lights/vrl_tree.h; vrl and vbl with
 * select = K > 0).
 *
 * 1. Selection pdf: on 300 synthetic VRLs (some excluded: too many bounces, zero power, zero
 *    length) split into pieces of at most 0.1 (the pieces tile each VRL) and four camera segments
 *    (one with a falling camera transmittance cache), the leaf pdfs (vbl_vrl_tree_pdf) sum to 1,
 *    pieces of excluded VRLs have pdf 0, every draw's returned pdf equals vbl_vrl_tree_pdf of the drawn index, and
 *    200000 draws fit the pdfs by chi-square (Sidak over the four segments, alpha 0.01).
 * 2. The tree's importance is not uniform: a VRL crossing the camera segment is drawn more often
 *    than one far away of the same mass (the traversal follows the distance bound).
 * 3. Same store, two estimators: for three camera rays through a lit heterogeneous sphere, the
 *    mean of volume_from_volume over 800 camera samples with select = 4 agrees with evaluating
 *    every VRL (select = 0) within 4 combined standard errors, for vrl and for vbl (fixed radius);
 *    both stores hold the same VRLs (the photon trace does not depend on select).
 * Mutations checked to fail: dropping the 1 / pdf weight in vrl (3: z = -27); taking the branch
 * probability of the wrong child in vbl_vrl_tree_pdf (1: draw pdf != recomputed pdf, 2 fails; the
 * pdfs still sum to 1, a permutation); a distorted branch probability in the traversal only
 * (1: draw pdf != recomputed pdf). */
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
#include "render_test_util.h"
#include "transport/common/photon_trace.h"
#include "transport/virtual_lights/virtual_beam_lights.h"
#include "transport/virtual_lights/vrl.h"
#include "transport/virtual_lights/vrl_tree.h"
#include "volume/transmittance_cache.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

#define N_VRLS 300
#define MAX_PIECES 1200

static void synthetic_vrls(vbl_vrl* v, int n)
{
    vbl_rng rng = vbl_rng_make(77, 0, 0);
    memset(v, 0, (size_t)n * sizeof *v);
    for (int i = 0; i < n; ++i) {
        v[i].origin = vbl_v3(2.0 * vbl_rng_uniform(&rng) - 1.0, 2.0 * vbl_rng_uniform(&rng) - 1.0,
                             2.0 * vbl_rng_uniform(&rng) - 1.0);
        v[i].direction = vbl_v3_normalize(vbl_v3(vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5,
                                                 vbl_rng_uniform(&rng) - 0.5));
        v[i].length = 0.02 + 0.3 * vbl_rng_uniform(&rng);
        double p = 0.1 + vbl_rng_uniform(&rng);
        v[i].power = vbl_v3(p, 0.8 * p, 0.5 * p);
        v[i].bounce = i % 4 == 3 ? 2 : 0; /* max_bounces 3 excludes bounce 2 */
    }
    v[5].power = vbl_v3(0, 0, 0);
    v[6].length = 0.0;
}

static int excluded(int i) { return i % 4 == 3 || i == 5 || i == 6; }

static void test_selection_pdf(void** state)
{
    (void)state;
    static vbl_vrl v[N_VRLS];
    synthetic_vrls(v, N_VRLS);
    vbl_vrl_tree tree;
    /* pieces of at most 0.1: VRLs of length 0.02 .. 0.32 give 1 .. 4 pieces */
    assert_int_equal(vbl_vrl_tree_build(&tree, v, N_VRLS, 3, 1e-3, 0.1, NULL, NULL), VBL_SUCCESS);
    int in_tree = 0;
    for (int i = 0; i < N_VRLS; ++i) in_tree += excluded(i) ? 0 : (int)ceil(v[i].length / 0.1);
    assert_int_equal(tree.light_count, in_tree);
    assert_true(tree.piece_count <= MAX_PIECES && tree.light_count > N_VRLS);
    /* the pieces of each VRL tile it */
    double covered[N_VRLS] = {0};
    for (int i = 0; i < tree.piece_count; ++i) {
        const vbl_vrl_tree_piece* pc = &tree.pieces[i];
        assert_true(pc->v0 >= 0.0 && pc->v1 > pc->v0 && pc->v1 <= v[pc->vrl].length);
        covered[pc->vrl] += pc->v1 - pc->v0;
    }
    for (int i = 0; i < N_VRLS; ++i)
        if (i != 6 && i % 4 != 3) assert_true(fabs(covered[i] - v[i].length) < 1e-12);
    /* a camera transmittance falling along the first segment (ratio-cache layout) */
    static vbl_transmittance_cache cache;
    memset(&cache, 0, sizeof cache);
    cache.kind = VBL_TRANSMITTANCE_CACHED_RATIO;
    cache.t0 = 1.0;
    cache.t1 = 7.0;
    cache.count = 40;
    for (int i = 0; i < cache.count; ++i) {
        cache.t[i] = 1.0 + 0.15 * i;
        cache.value[i] = exp(-0.3 * i);
    }
    const vbl_vrl_tree_query qs[4] = {
        {vbl_v3(-3, 0.1, 0.2), vbl_v3_normalize(vbl_v3(1, 0, 0)), 6.0, NULL, 0.0, 0.0},
        {vbl_v3(0.3, -0.4, -3), vbl_v3_normalize(vbl_v3(0.1, 0.1, 1)), 1.5, NULL, 0.0, 0.0}, /* ends inside */
        {vbl_v3(5, 5, 5), vbl_v3_normalize(vbl_v3(1, 1, 1)), 2.0, NULL, 0.0, 0.0},           /* far away */
        {vbl_v3(-3, 0.1, 0.2), vbl_v3_normalize(vbl_v3(1, 0, 0)), 6.0, &cache, 1.0, 1e-3},  /* with T_c */
    };
    static double expected[MAX_PIECES], observed[MAX_PIECES];
    const int np = tree.piece_count;
    const int draws = 200000;
    for (int k = 0; k < 4; ++k) {
        double sum = 0.0;
        for (int i = 0; i < np; ++i) {
            double p = vbl_vrl_tree_pdf(&tree, &qs[k], i);
            if (excluded(tree.pieces[i].vrl)) assert_true(p == 0.0);
            else assert_true(p > 0.0);
            sum += p;
            expected[i] = p * draws;
            observed[i] = 0.0;
        }
        printf("segment %d: sum of pdfs - 1 = %.3g\n", k, sum - 1.0);
        assert_true(fabs(sum - 1.0) < 1e-9);
        vbl_rng rng = vbl_rng_make(1234, (uint32_t)k, 0);
        for (int d = 0; d < draws; ++d) {
            double pdf;
            int j = vbl_vrl_tree_sample(&tree, &qs[k], vbl_rng_uniform(&rng), &pdf);
            assert_true(j >= 0 && j < np);
            if (d < 2000) assert_true(fabs(pdf - vbl_vrl_tree_pdf(&tree, &qs[k], j)) <= 1e-12 * pdf);
            observed[j] += 1.0;
        }
        char label[64];
        snprintf(label, sizeof label, "vrl tree selection, segment %d", k);
        assert_true(vbl_chi2_check(label, observed, expected, np, 0.01, 4));
    }
    vbl_vrl_tree_free(&tree);
}

/* Two VRLs of equal mass among far ones: the one crossing the segment gets the larger pdf. */
static void test_importance_follows_distance(void** state)
{
    (void)state;
    vbl_vrl v[64];
    memset(v, 0, sizeof v);
    for (int i = 0; i < 64; ++i) {
        v[i].origin = vbl_v3(0.1 * i, i % 2 ? 3.0 : 0.0, -0.5);
        v[i].direction = vbl_v3(0, 0, 1);
        v[i].length = 1.0;
        v[i].power = vbl_v3(1, 1, 1);
    }
    vbl_vrl_tree tree;
    assert_int_equal(vbl_vrl_tree_build(&tree, v, 64, -1, 1e-3, 0.0, NULL, NULL), VBL_SUCCESS); /* whole VRLs */
    assert_int_equal(tree.light_count, 64);
    vbl_vrl_tree_query q = {vbl_v3(-1, 0, 0), vbl_v3(1, 0, 0), 8.0, NULL, 0.0, 0.0}; /* crosses the even VRLs */
    double near = vbl_vrl_tree_pdf(&tree, &q, 10), far = vbl_vrl_tree_pdf(&tree, &q, 11);
    printf("pdf crossing %g, 3 away %g\n", near, far);
    assert_true(near > 2.0 * far);
    vbl_vrl_tree_free(&tree);
    /* empty tree */
    v[0].bounce = 5;
    assert_int_equal(vbl_vrl_tree_build(&tree, v, 1, 3, 1e-3, 0.0, NULL, NULL), VBL_SUCCESS);
    double pdf = 1.0;
    assert_int_equal(vbl_vrl_tree_sample(&tree, &q, 0.5, &pdf), -1);
    assert_true(pdf == 0.0);
    vbl_vrl_tree_free(&tree);
}

/* ---- same store: K selected lights vs every light --------------------------------------- */

typedef vbl_result (*begin_fn)(const vbl_render_context*, int select, void**);
typedef void (*sample_fn)(const vbl_render_context*, const void*, vbl_thread_state*, const vbl_camera_sample*,
                          vbl_rng*, vbl_sample_value*);

static vbl_result vrl_begin(const vbl_render_context* ctx, int select, void** store)
{
    vbl_vrl_settings s = VBL_VRL_SETTINGS_DEFAULT;
    s.select = select;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}

static vbl_result vbl_begin(const vbl_render_context* ctx, int select, void** store)
{
    vbl_beam_light_settings s = VBL_BEAM_LIGHT_SETTINGS_DEFAULT;
    s.select = select;
    s.radius0 = 0.05;
    s.alpha = 1.0;
    s.kernel_samples = 4;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_beam, &s, store);
}

static void same_store(const char* tag, begin_fn begin, sample_fn sample, void (*end)(const vbl_render_context*, void*),
                       const vbl_photon_store* (*photons)(const void*))
{
    vbl_camera cam = rt_camera(vbl_v3(0.2, -4, 0.3), vbl_v3(0, 0, 0), 40.0, 8, 8);
    vbl_scene* s = tt_scene(&cam);
    vbl_volume* vol = tt_make_sphere(16, 1.0);
    assert_int_equal(vbl_scene_add_medium(s, vol, 6.0, vbl_v3(0.9, 0.8, 0.7), 0.3, NULL), VBL_SUCCESS);
    tt_add_point(s, vbl_v3(0.3, 0.2, 1.6), 10.0);
    vbl_render_context ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.scene = s;
    ctx.extinction = &s->extinction;
    ctx.options = tt_options(1, 1, 150, 3);
    ctx.tracking.estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    ctx.threads = 1;
    void *all = NULL, *sel = NULL;
    assert_int_equal(begin(&ctx, 0, &all), VBL_SUCCESS);
    assert_int_equal(begin(&ctx, 4, &sel), VBL_SUCCESS);
    const vbl_photon_store *pa = photons(all), *ps = photons(sel);
    printf("%s: %zu VRLs\n", tag, pa->vrl_count);
    assert_true(pa->vrl_count == ps->vrl_count && pa->vrl_count > 50);
    assert_true(!memcmp(pa->vrls, ps->vrls, pa->vrl_count * sizeof *pa->vrls));
    vbl_thread_state ts;
    memset(&ts, 0, sizeof ts);
    vbl_extinction_cursor_init(&ts.cursor, ctx.extinction);
    const vbl_vec3 targets[3] = {vbl_v3(0, 0, 0), vbl_v3(0.3, 0, 0.5), vbl_v3(-0.5, 0.2, -0.3)};
    const int n = 800;
    for (int r = 0; r < 3; ++r) {
        vbl_camera_sample cs;
        memset(&cs, 0, sizeof cs);
        cs.origin = cam.position;
        cs.direction = vbl_v3_normalize(vbl_v3_sub(targets[r], cam.position));
        cs.t_max = INFINITY;
        vbl_mean_acc ma = {0}, mb = {0};
        for (int i = 0; i < n; ++i) {
            vbl_sample_value va, vb;
            memset(&va, 0, sizeof va);
            memset(&vb, 0, sizeof vb);
            vbl_rng ra = vbl_rng_make(11, (uint32_t)r, (uint64_t)i), rb = vbl_rng_make(12, (uint32_t)r, (uint64_t)i);
            sample(&ctx, all, &ts, &cs, &ra, &va);
            sample(&ctx, sel, &ts, &cs, &rb, &vb);
            vbl_vec3 a = va.L[VBL_CLASS_VOLUME_FROM_VOLUME], b = vb.L[VBL_CLASS_VOLUME_FROM_VOLUME];
            assert_true(isfinite(b.x + b.y + b.z));
            vbl_mean_add(&ma, a.x + a.y + a.z);
            vbl_mean_add(&mb, b.x + b.y + b.z);
        }
        double sa = vbl_mean_stderr(&ma), sb = vbl_mean_stderr(&mb);
        double z = (mb.mean - ma.mean) / sqrt(sa * sa + sb * sb);
        printf("%s ray %d: every VRL %.5g +- %.2g, select 4 %.5g +- %.2g, z = %.2f\n", tag, r, ma.mean, sa, mb.mean,
               sb, z);
        assert_true(ma.mean > 0.0);
        assert_true(fabs(z) < 4.0);
    }
    end(&ctx, all);
    end(&ctx, sel);
    vbl_scene_release(s);
    vt_free(vol);
}

static const vbl_photon_store* vbl_store_photons(const void* store); /* below */

static void test_same_store_vrl(void** state)
{
    (void)state;
    same_store("vrl", vrl_begin, vbl_vl_camera_sample, vbl_vl_pass_end, vbl_vl_photons);
}

static void test_same_store_vbl(void** state)
{
    (void)state;
    same_store("vbl", vbl_begin, vbl_vl_camera_sample, vbl_vl_pass_end, vbl_store_photons);
}

static const vbl_photon_store* vbl_store_photons(const void* store) { return vbl_vl_photons(store); }

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_selection_pdf),
        cmocka_unit_test(test_importance_follows_distance),
        cmocka_unit_test(test_same_store_vrl),
        cmocka_unit_test(test_same_store_vbl),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
