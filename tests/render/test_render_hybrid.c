#define _POSIX_C_SOURCE 200809L
/* render.hybrid (render/hybrid.h, docs/readme/hybrid.md): pt renders some transport classes, a
 * virtual-light method the others. Tests: the combination takes every class from exactly one
 * estimator (all 256 masks); hybrid_pt_classes parses layer names; a hybrid vrl render agrees
 * with pt per layer within k sigma over independent seeds (classes mode with pt_spp 2, and auto);
 * 1 vs 2 threads bit-identical; split + merge equals one render; the auto plan does not depend
 * on threads or the pass range; method pt refuses it. Small images, few passes, fixed seeds. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/hybrid.h"
#include "render_test_util.h"
#include "temp_scene.h"
#include "vbl/vbl.h"

static char scene_path[1024];

static int setup(void** state)
{
    (void)state;
    return rt_merge_scene_write("vbl_hybrid", scene_path, sizeof scene_path);
}

static int teardown(void** state)
{
    (void)state;
    vbl_test_temp_scene_remove(scene_path);
    return 0;
}

static void test_combine_partitions_classes(void** state)
{
    (void)state;
    vbl_sample_value method, pt, out;
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        method.L[c] = vbl_v3(c + 1.0, 0.0, 0.0);
        pt.L[c] = vbl_v3(0.0, 3.0 * (100.0 + c), 0.0); /* a sum of 3 pt samples of 100 + c */
    }
    for (unsigned mask = 0; mask <= VBL_HYBRID_ALL_CLASSES; ++mask) {
        vbl_hybrid_combine(&method, &pt, 3, mask, &out);
        for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
            if (mask & (1u << c)) { /* from pt only, as its mean */
                assert_true(out.L[c].x == 0.0);
                assert_true(fabs(out.L[c].y - (100.0 + c)) < 1e-12);
            } else { /* from the method only */
                assert_true(out.L[c].x == c + 1.0);
                assert_true(out.L[c].y == 0.0);
            }
        }
    }
}

/* vbl_hybrid_assign on made-up pilot numbers: class 6 (volume_from_volume) only, P = 4 pilot
 * passes, 64 pt samples; pt per sample costs 1, the method per pass 10. */
static unsigned assign_one(double vl_var, double pt_var, double vl_total, double pt_total, double* pt_var_out)
{
    vbl_hybrid_pilot_stats st;
    memset(&st, 0, sizeof st);
    double vt[VBL_CLASS_COUNT] = {0}, pt[VBL_CLASS_COUNT] = {0}, ve[VBL_CLASS_COUNT] = {0}, pe[VBL_CLASS_COUNT] = {0};
    const int c = VBL_CLASS_VOLUME_FROM_VOLUME;
    st.vl_variance[c] = vl_var;
    st.pt_variance[c] = pt_var;
    st.vl_cost = 10.0;
    st.pt_cost = 1.0;
    vt[c] = vl_total;
    pt[c] = pt_total;
    ve[c] = fabs(vl_total);
    pe[c] = fabs(pt_total);
    unsigned mask = vbl_hybrid_assign(&st, vt, pt, ve, pe, 4, 64.0);
    if (pt_var_out) *pt_var_out = st.pt_variance[c];
    /* the classes without energy follow pt: to pt when it owns volume_from_volume, else nowhere */
    assert_int_equal(mask, (mask & (1u << c)) ? VBL_HYBRID_ALL_CLASSES : 0u);
    return mask & (1u << c);
}

static void test_assign_rules(void** state)
{
    (void)state;
    const unsigned vfv = 1u << VBL_CLASS_VOLUME_FROM_VOLUME;
    /* variance x cost: pt 5 x 1 against the method's 1 x 10 -> pt; 20 x 1 -> the method */
    assert_int_equal(assign_one(1.0, 5.0, 1.0, 1.0, NULL), vfv);
    assert_int_equal(assign_one(1.0, 20.0, 1.0, 1.0, NULL), 0u);
    /* the method found no light where pt did: pt owns it, whatever the (unseen) variances */
    assert_int_equal(assign_one(0.0, 100.0, 0.0, 1.0, NULL), vfv);
    /* and the other way round: pt found none, the method some */
    assert_int_equal(assign_one(100.0, 0.0, 1.0, 0.0, NULL), 0u);
    /* a heavy-tailed pt: its pilot variance (1 per sample; pt 1 x 1 against the method's 0.2 x 10)
     * says it wins. Its total 0.3 below the method's is 1.2 standard errors (sqrt(0.2 / 4 + 1 / 64)
     * = 0.256): noise, the decision stands */
    double raised;
    assert_int_equal(assign_one(0.2, 1.0, 1.0, 0.7, &raised), vfv);
    assert_true(raised == 1.0);
    /* 0.9 below (3.5 se): pt missed light; its variance is raised to (d^2 - var(vl total)) x 64
     * = (0.81 - 0.05) x 64 = 48.6, and the method wins */
    assert_int_equal(assign_one(0.2, 1.0, 1.0, 0.1, &raised), 0u);
    assert_true(fabs(raised - (0.81 - 0.2 / 4.0) * 64.0) < 1e-9);
    /* the method 1.15 below pt (3.2 se): its variance is raised to (1.3225 - 5 / 64) x 4 = 4.98, and
     * pt (5 x 1 against 49.8) keeps the class that the method's pilot variance (0.2 x 10) would win */
    assert_int_equal(assign_one(0.2, 5.0, 0.05, 1.2, NULL), vfv);
    assert_int_equal(assign_one(0.2, 5.0, 1.2, 1.2, NULL), 0u);
}

static void test_pt_classes_option(void** state)
{
    (void)state;
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(o.hybrid, VBL_HYBRID_AUTO);
    assert_int_equal(vbl_render_option_set_strict(&o, "hybrid_pt_classes", "surface_direct,volume_from_volume"),
                     VBL_SUCCESS);
    assert_int_equal(o.hybrid_pt_classes, (1 << VBL_CLASS_SURFACE_DIRECT) | (1 << VBL_CLASS_VOLUME_FROM_VOLUME));
    assert_int_equal(vbl_render_option_set(&o, "--hybrid-pt-classes", "6"), VBL_SUCCESS);
    assert_int_equal(o.hybrid_pt_classes, 6);
    assert_int_not_equal(vbl_render_option_set(&o, "hybrid_pt_classes", "volume_direct,nonsense"), VBL_SUCCESS);
    assert_non_null(strstr(vbl_last_error_message(), "nonsense"));
    assert_int_equal(o.hybrid_pt_classes, 6); /* unchanged */
    assert_int_not_equal(vbl_render_option_set(&o, "hybrid_pt_classes", "volume_direct,"), VBL_SUCCESS);
    assert_int_not_equal(vbl_render_option_set(&o, "hybrid_pt_spp", "0"), VBL_SUCCESS);
    assert_int_equal(vbl_render_option_set(&o, "hybrid", "auto"), VBL_SUCCESS);
    assert_int_equal(o.hybrid, VBL_HYBRID_AUTO);
    vbl_clear_error();
    /* scene files: layer names as a string */
    char path[1024];
    assert_int_equal(vbl_test_temp_scene_write("vbl_hybrid_opt", path, sizeof path,
                     "{\"camera\": {\"position\": [0, -3, 0], \"look_at\": [0, 0, 0], \"fov_deg\": 40, \"resolution\": [4, 4]},"
                     " \"lights\": [{\"type\": \"environment\", \"radiance\": [1, 1, 1]}],"
                     " \"render\": {\"method\": \"vrl\", \"hybrid\": \"classes\", \"hybrid_pt_classes\": \"volume_direct,background\"}}\n"),
                     0);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(path, &scene), VBL_SUCCESS);
    vbl_render_options from_file = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &from_file), VBL_SUCCESS);
    assert_int_equal(from_file.hybrid, VBL_HYBRID_CLASSES);
    assert_int_equal(from_file.hybrid_pt_classes, (1 << VBL_CLASS_VOLUME_DIRECT) | (1 << VBL_CLASS_BACKGROUND));
    vbl_scene_release(scene);
    vbl_test_temp_scene_remove(path);
}

static vbl_film* render(const vbl_scene* scene, vbl_render_method method, vbl_hybrid_mode mode, int pt_classes,
                        int pt_spp, uint64_t seed, int first, int passes, int threads)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_scene_render_options(scene, &o), VBL_SUCCESS);
    o.method = method;
    o.hybrid = mode;
    o.hybrid_pt_classes = pt_classes;
    o.hybrid_pt_spp = pt_spp;
    o.seed = seed;
    o.first_pass = first;
    o.passes = passes;
    o.threads = threads;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    return film;
}

static vbl_film_stats stats_of(const vbl_film* film)
{
    vbl_film_stats s;
    memset(&s, 0, sizeof s);
    s.size = sizeof s;
    assert_int_equal(vbl_film_get_stats(film, &s), VBL_SUCCESS);
    return s;
}

/* The image mean of a class layer (R + G + B), 0 if the film has no such layer. */
static double layer_mean(const vbl_film* film, int c)
{
    const float* p = vbl_film_layer_rgb(film, vbl_transport_class_name((vbl_transport_class)c));
    if (!p) return 0.0;
    const size_t n = (size_t)vbl_film_width(film) * (size_t)vbl_film_height(film);
    double s = 0.0;
    for (size_t i = 0; i < 3 * n; ++i) s += p[i];
    return s / (double)n;
}

#define SEEDS 6

/* Per class, the image mean of the hybrid vs pt over SEEDS independent renders each: within
 * 4.5 sigma of the difference of the two means. */
static void expect_agrees_with_pt(vbl_hybrid_mode mode, int pt_classes, int pt_spp)
{
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    double h[VBL_CLASS_COUNT][SEEDS], p[VBL_CLASS_COUNT][SEEDS];
    unsigned plan = 0;
    for (int k = 0; k < SEEDS; ++k) {
        vbl_film* a = render(scene, VBL_RENDER_VRL, mode, pt_classes, pt_spp, 100 + k, 0, 2, 2);
        vbl_film* b = render(scene, VBL_RENDER_PT, VBL_HYBRID_OFF, 0, 1, 200 + k, 0, 2, 2);
        vbl_film_stats s = stats_of(a);
        assert_int_equal(s.hybrid, mode);
        plan |= (unsigned)s.hybrid_pt_classes;
        for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
            h[c][k] = layer_mean(a, c);
            p[c][k] = layer_mean(b, c);
        }
        vbl_film_release(a);
        vbl_film_release(b);
    }
    int compared = 0;
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        double mh = 0, mp = 0, vh = 0, vp = 0;
        for (int k = 0; k < SEEDS; ++k) mh += h[c][k] / SEEDS, mp += p[c][k] / SEEDS;
        for (int k = 0; k < SEEDS; ++k)
            vh += (h[c][k] - mh) * (h[c][k] - mh) / (SEEDS - 1), vp += (p[c][k] - mp) * (p[c][k] - mp) / (SEEDS - 1);
        double sigma = sqrt((vh + vp) / SEEDS);
        if (mh == 0.0 && mp == 0.0) continue;
        ++compared;
        double z = fabs(mh - mp) / (sigma > 0.0 ? sigma : 1e-300);
        print_message("%s class %-20s hybrid %.5f pt %.5f  z %.2f%s\n", mode == VBL_HYBRID_AUTO ? "auto" : "classes",
                      vbl_transport_class_name((vbl_transport_class)c), mh, mp, z, (plan >> c) & 1u ? " (pt)" : "");
        if (z > 4.5) fail_msg("class %s: hybrid %.6f vs pt %.6f, z = %.2f", vbl_transport_class_name((vbl_transport_class)c), mh, mp, z);
    }
    assert_true(compared >= 3);
    vbl_scene_release(scene);
}

static void test_classes_agree_with_pt(void** state)
{
    (void)state;
    expect_agrees_with_pt(VBL_HYBRID_CLASSES, 1 << VBL_CLASS_VOLUME_DIRECT, 2); /* vrl: volume_from_volume */
}

static void test_auto_agrees_with_pt(void** state)
{
    (void)state;
    expect_agrees_with_pt(VBL_HYBRID_AUTO, 0, 1);
}

static void expect_films_identical(const vbl_film* a, const vbl_film* b)
{
    assert_int_equal(vbl_film_layer_count(a), vbl_film_layer_count(b));
    const size_t n = (size_t)vbl_film_width(a) * (size_t)vbl_film_height(a);
    for (int i = 0; i < vbl_film_layer_count(a); ++i) {
        const char* name = vbl_film_layer_name(a, i);
        int ca = 0, cb = 0;
        const float* pa = vbl_film_layer(a, name, &ca);
        const float* pb = vbl_film_layer(b, name, &cb);
        assert_non_null(pb);
        assert_int_equal(ca, cb);
        assert_memory_equal(pa, pb, n * (size_t)ca * sizeof(float));
    }
}

static void test_threads_and_plan_deterministic(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    vbl_film* one = render(scene, VBL_RENDER_VRL, VBL_HYBRID_AUTO, 0, 1, 5, 0, 2, 1);
    vbl_film* two = render(scene, VBL_RENDER_VRL, VBL_HYBRID_AUTO, 0, 1, 5, 0, 2, 2);
    vbl_film* later = render(scene, VBL_RENDER_VRL, VBL_HYBRID_AUTO, 0, 1, 5, 7, 1, 2);
    expect_films_identical(one, two);
    vbl_film_stats a = stats_of(one), b = stats_of(two), c = stats_of(later);
    assert_int_equal(a.hybrid_pt_classes, b.hybrid_pt_classes);
    assert_int_equal(a.hybrid_pt_spp, b.hybrid_pt_spp);
    assert_int_equal(a.hybrid_pt_classes, c.hybrid_pt_classes); /* a split's pass range does not move the plan */
    assert_int_equal(a.hybrid_pt_spp, c.hybrid_pt_spp);
    print_message("auto plan: pt classes 0x%x, pt_spp %d\n", (unsigned)a.hybrid_pt_classes, a.hybrid_pt_spp);
    /* classes mode at 1 vs 2 threads too */
    vbl_film* c1 = render(scene, VBL_RENDER_VPL, VBL_HYBRID_CLASSES, 1 << VBL_CLASS_VOLUME_DIRECT, 3, 9, 0, 1, 1);
    vbl_film* c2 = render(scene, VBL_RENDER_VPL, VBL_HYBRID_CLASSES, 1 << VBL_CLASS_VOLUME_DIRECT, 3, 9, 0, 1, 2);
    expect_films_identical(c1, c2);
    vbl_film_release(c1);
    vbl_film_release(c2);
    vbl_film_release(later);
    vbl_film_release(one);
    vbl_film_release(two);
    vbl_scene_release(scene);
}

static void test_split_merge_equals_single(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    vbl_film* all = render(scene, VBL_RENDER_VRL, VBL_HYBRID_AUTO, 0, 1, 5, 0, 4, 2);
    vbl_film* parts[2] = {render(scene, VBL_RENDER_VRL, VBL_HYBRID_AUTO, 0, 1, 5, 1, 3, 2),
                          render(scene, VBL_RENDER_VRL, VBL_HYBRID_AUTO, 0, 1, 5, 0, 1, 2)};
    vbl_film* merged = NULL;
    assert_int_equal(vbl_film_merge((const vbl_film* const*)parts, 2, &merged), VBL_SUCCESS);
    const size_t n = (size_t)vbl_film_width(all) * (size_t)vbl_film_height(all);
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        const char* name = vbl_transport_class_name((vbl_transport_class)c);
        const float* a = vbl_film_layer_rgb(merged, name);
        const float* b = vbl_film_layer_rgb(all, name);
        assert_true((a == NULL) == (b == NULL));
        for (size_t v = 0; a && v < 3 * n; ++v)
            if (fabs((double)a[v] - (double)b[v]) > 4e-7 * (fabs(a[v]) + fabs(b[v])))
                fail_msg("layer %s value %zu: merged %.9g, single %.9g", name, v, a[v], b[v]);
    }
    /* another plan does not merge */
    vbl_film* other = render(scene, VBL_RENDER_VRL, VBL_HYBRID_CLASSES, 1 << VBL_CLASS_VOLUME_DIRECT, 1, 5, 4, 1, 2);
    const vbl_film* mix[2] = {all, other};
    vbl_film* bad = NULL;
    if (stats_of(other).hybrid_pt_classes != stats_of(all).hybrid_pt_classes ||
        stats_of(other).hybrid != stats_of(all).hybrid)
        assert_int_not_equal(vbl_film_merge(mix, 2, &bad), VBL_SUCCESS);
    vbl_clear_error();
    vbl_film_release(bad);
    vbl_film_release(other);
    vbl_film_release(merged);
    vbl_film_release(parts[0]);
    vbl_film_release(parts[1]);
    vbl_film_release(all);
    vbl_scene_release(scene);
}

/* A cancel (SIGINT in the CLI) set before the render stops it in the pilot (its light tracing or its
 * pixels): an interrupted error, no film. (How soon it stops is not timed here: measured with the
 * CLI, hybrid.md.) */
static void test_cancel_in_pilot(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    static volatile int cancel = 1;
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.method = VBL_RENDER_VRL;
    o.hybrid = VBL_HYBRID_AUTO;
    o.passes = 4;
    o.cancel = &cancel;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_ERROR_INTERRUPTED);
    assert_null(film);
    vbl_clear_error();
    vbl_scene_release(scene);
}

/* auto is the default: a virtual-light render runs the pilot and records its plan; pt renders it as
 * off (the same image and options hash as with off); classes with pt is still an error. */
static void test_auto_default_and_pt(void** state)
{
    (void)state;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load(scene_path, &scene), VBL_SUCCESS);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(o.hybrid, VBL_HYBRID_AUTO);
    o.passes = 1;
    o.threads = 1;
    vbl_film* film = NULL;
    o.method = VBL_RENDER_VRL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    assert_int_equal(stats_of(film).hybrid, VBL_HYBRID_AUTO);
    vbl_film_release(film);
    /* pt: auto renders as off */
    char h_auto[64], h_off[64];
    o.method = VBL_RENDER_PT;
    vbl_render_options_hash(&o, h_auto, sizeof h_auto);
    vbl_film* pt_auto = NULL;
    assert_int_equal(vbl_render(scene, &o, &pt_auto), VBL_SUCCESS);
    assert_int_equal(stats_of(pt_auto).hybrid, VBL_HYBRID_OFF);
    o.hybrid = VBL_HYBRID_OFF;
    vbl_render_options_hash(&o, h_off, sizeof h_off);
    assert_string_equal(h_auto, h_off);
    vbl_film* pt_off = NULL;
    assert_int_equal(vbl_render(scene, &o, &pt_off), VBL_SUCCESS);
    expect_films_identical(pt_auto, pt_off);
    vbl_film_release(pt_auto);
    vbl_film_release(pt_off);
    /* a virtual-light method: auto and off hash differently (films of the two do not merge) */
    o.method = VBL_RENDER_VRL;
    vbl_render_options_hash(&o, h_off, sizeof h_off);
    o.hybrid = VBL_HYBRID_AUTO;
    vbl_render_options_hash(&o, h_auto, sizeof h_auto);
    assert_string_not_equal(h_auto, h_off);
    /* classes with pt: refused */
    o.method = VBL_RENDER_PT;
    o.hybrid = VBL_HYBRID_CLASSES;
    film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_ERROR_INVALID_ARGUMENT);
    assert_null(film);
    assert_non_null(strstr(vbl_last_error_message(), "hybrid"));
    vbl_clear_error();
    vbl_scene_release(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_combine_partitions_classes),
        cmocka_unit_test(test_assign_rules),
        cmocka_unit_test(test_pt_classes_option),
        cmocka_unit_test(test_classes_agree_with_pt),
        cmocka_unit_test(test_auto_agrees_with_pt),
        cmocka_unit_test(test_threads_and_plan_deterministic),
        cmocka_unit_test(test_split_merge_equals_single),
        cmocka_unit_test(test_auto_default_and_pt),
        cmocka_unit_test(test_cancel_in_pilot),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
