/* The surface classes of the virtual-light methods (vrl, vpl) rendered end to end against pt.
 *
 * Scene: a heterogeneous sphere medium (radius 0.8, g = 0.3) above a ground plane (z = -1) with
 * a back wall (y = 1.2), lit by a point light; "lambert" uses Lambert surfaces, "phong" a Phong
 * 40 ground.
 *
 * Fast (no argument):
 *   - layers sum to beauty and stay finite (vrl, vpl, both scenes);
 *   - determinism: vrl and vpl images bit-identical with 1 and 2 threads;
 *   - photon stores: no surface VSLs without surfaces (media-only scenes trace as before), VSLs
 *     with surfaces, and every VSL has bounce + 2 <= max_bounces.
 * `lambert`, `phong`, `radius` (slow, one ctest each): K replicates per method, block means (4x4 pixel blocks, mean RGB) per class;
 *   - unbiased classes, z = |a - b| / sqrt(se_a^2 + se_b^2) <= Z_CRIT on every block and the
 *     image mean: vrl and vpl surface_direct, volume_direct, volume_from_volume, vrl
 *     surface_from_volume (VRL eq 6); power check: vrl's surface_from_volume x 1.3 rejected
 *     (VRL contributions are heavy-tailed, so each replicate averages 16 passes);
 *   - radius classes (vrl surface VSLs, R_0 = 0.5, eq 11): the block-RMS error against pt of
 *     surface_from_surface and of volume_from_surface falls from 1 pass to 24 passes; the same
 *     for surface_from_volume by VBL eqs 8-9 (what virtual_beam_lights.c gets), R_0 = 0.5. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "material/material.h"
#include "transport/common/radius_schedule.h"
#include "render/render_internal.h"
#include "render_test_util.h"
#include "transport/common/photon_trace.h"
#include "transport/path_tracing/pt.h"
#include "transport/surface/surface_gather.h"
#include "transport/virtual_lights/vpl.h"
#include "transport/virtual_lights/virtual_beam_lights.h"
#include "transport/virtual_lights/vrl.h"
#include "transport_test_util.h"
#include "surface_render_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

#define W 16
#define H 12
#define BLOCK 4
#define NB ((W / BLOCK) * (H / BLOCK))
#define Z_CRIT 5.0

typedef struct scene_case {
    vbl_scene* scene;
    vbl_volume* volume;
} scene_case;

/* phong: 0 Lambert ground, 1 Phong ground; surfaces: 0 media only */
static scene_case make_case(int phong, int surfaces)
{
    scene_case c;
    vbl_camera cam = rt_camera(vbl_v3(0.3, -4.0, 0.6), vbl_v3(0, 0, -0.4), 45.0, W, H);
    c.scene = tt_scene(&cam);
    c.volume = tt_make_sphere(16, 0.8);
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volume, 3.0, vbl_v3(0.9, 0.8, 0.7), 0.3, NULL), VBL_SUCCESS);
    tt_add_point(c.scene, vbl_v3(0.6, -0.6, 1.4), 6.0);
    if (surfaces) {
        vbl_material lam = {VBL_MATERIAL_LAMBERT, {0.7, 0.6, 0.5}, {0, 0, 0}, 0.0, 0.0};
        vbl_material pho = {VBL_MATERIAL_PHONG, {0.4, 0.4, 0.4}, {0.4, 0.4, 0.4}, 40.0, 0.0};
        vbl_material wall = {VBL_MATERIAL_LAMBERT, {0.6, 0.7, 0.6}, {0, 0, 0}, 0.0, 0.0};
        add_quad(c.scene, vbl_v3(0, 0, -1), vbl_v3(2.5, 0, 0), vbl_v3(0, 2.5, 0), phong ? &pho : &lam);
        add_quad(c.scene, vbl_v3(0, 1.2, 0.5), vbl_v3(2.5, 0, 0), vbl_v3(0, 0, 1.5), &wall);
    }
    return c;
}

static void free_case(scene_case* c)
{
    vbl_scene_release(c->scene);
    vt_free(c->volume);
}

/* ---- estimator variants ------------------------------------------------------------------ */

static size_t g_vsl_count, g_vsl_bad_bounce;
static int g_max_bounces;

static vbl_result vrl_probe_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings s;
    vbl_vrl_settings_from_options(&ctx->options, &s);
    vbl_result r = vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
    if (r) return r;
    const vbl_photon_store* p = vbl_vl_photons(*store);
    g_vsl_count += p->surface_vsl_count; /* pass_begin is the driver's single-threaded entry */
    for (size_t i = 0; i < p->surface_vsl_count; ++i)
        if (g_max_bounces >= 0 && p->surface_vsls[i].bounce + 2 > g_max_bounces) ++g_vsl_bad_bounce;
    return VBL_SUCCESS;
}
static const vbl_estimator vrl_probe = {"vrl-probe", 1, vrl_probe_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};

static vbl_result vrl_r05_begin(const vbl_render_context* ctx, void** store)
{
    vbl_vrl_settings s = VBL_VRL_SETTINGS_DEFAULT;
    s.surface_radius0 = 0.5;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}
static const vbl_estimator vrl_r05 = {"vrl-r05", 1, vrl_r05_begin, vbl_vl_camera_sample, vbl_vl_pass_end,
                                        vbl_vl_camera_aovs};

/* What virtual_beam_lights.c gets (the lines handed to the lead): surface_from_volume by VBL eqs 8-9 with
 * R_p from R_0 = 0.5 (eq 11) on the VRL store, and in the volume_direct slot the unbiased eq 6
 * estimate from the SAME store (the photon noise, which dominates, then cancels in the
 * difference, so the radius bias shows). */
static void vbl_surface_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                               const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    vbl_surface_gather_settings gs;
    memset(&gs, 0, sizeof gs);
    gs.vrls = 1;
    gs.vrl_radius = vbl_radius_at_pass(0.5, VBL_RADIUS_ALPHA_DEFAULT, 2, ctx->pass);
    gs.kernel_samples = VBL_SURFACE_KERNEL_SAMPLES_DEFAULT;
    vbl_sample_value tmp;
    memset(&tmp, 0, sizeof tmp);
    vbl_surface_gather_hit(ctx, ts, vbl_vl_photons(store), &gs, sample, rng, &tmp);
    out->L[VBL_CLASS_SURFACE_FROM_VOLUME] = tmp.L[VBL_CLASS_SURFACE_FROM_VOLUME];
    gs.vrl_radius = 0.0;
    memset(&tmp, 0, sizeof tmp);
    vbl_surface_gather_hit(ctx, ts, vbl_vl_photons(store), &gs, sample, rng, &tmp);
    out->L[VBL_CLASS_VOLUME_DIRECT] = tmp.L[VBL_CLASS_SURFACE_FROM_VOLUME];
}
static const vbl_estimator vbl_surface = {"vbl-surface", 1, vrl_r05_begin, vbl_surface_sample, vbl_vl_pass_end, NULL};

/* ---- fast ---------------------------------------------------------------------------------- */

static void test_sum_finite_and_deterministic(void** state)
{
    (void)state;
    const vbl_estimator* ests[3] = {&vbl_estimator_vrl, &vbl_estimator_vpl, &vbl_estimator_vbl};
    for (int phong = 0; phong < 2; ++phong) {
        scene_case c = make_case(phong, 1);
        for (int e = 0; e < 3; ++e) {
            vbl_film* a = render_with(c.scene, ests[e], 2, 1, 48, 11, 1, -1);
            vbl_film* b = render_with(c.scene, ests[e], 2, 1, 48, 11, 2, -1);
            assert_true(check_sum_to_beauty(a) > 0.0);
            /* every surface class is produced */
            for (int l = 1; l < VBL_CLASS_COUNT; ++l) {
                printf("%s %s %-20s total %.5g\n", phong ? "phong" : "lambert", ests[e]->name, layer_names[l],
                       layer_total(a, layer_names[l]));
                if (l != VBL_CLASS_EMISSION && l != VBL_CLASS_VOLUME_EMISSION) /* no emissive media here */
                    assert_true(layer_total(a, layer_names[l]) > 0.0);
            }
            for (int l = 0; l < vbl_film_layer_count(a); ++l) {
                const char* name = vbl_film_layer_name(a, l);
                int ca = 0, cb = 0;
                const float* pa = vbl_film_layer(a, name, &ca);
                const float* pb = vbl_film_layer(b, name, &cb);
                assert_int_equal(ca, cb);
                assert_true(memcmp(pa, pb, sizeof(float) * (size_t)ca * W * H) == 0);
            }
            vbl_film_release(a);
            vbl_film_release(b);
        }
        free_case(&c);
    }
}

static void test_photon_store_surfaces(void** state)
{
    (void)state;
    /* media only: no surface VSL, nothing in the surface layers */
    scene_case m = make_case(0, 0);
    g_vsl_count = g_vsl_bad_bounce = 0;
    g_max_bounces = -1;
    vbl_film* f = render_with(m.scene, &vrl_probe, 2, 1, 64, 5, 2, -1);
    assert_int_equal(g_vsl_count, 0);
    for (int l = 0; l < VBL_CLASS_COUNT; ++l)
        if (l == VBL_CLASS_SURFACE_DIRECT || l == VBL_CLASS_SURFACE_FROM_SURFACE || l == VBL_CLASS_SURFACE_FROM_VOLUME ||
            l == VBL_CLASS_VOLUME_FROM_SURFACE)
            assert_true(layer_total(f, layer_names[l]) == 0.0);
    vbl_film_release(f);
    free_case(&m);
    /* with surfaces: VSLs recorded, within max_bounces */
    scene_case c = make_case(0, 1);
    for (int M = 2; M <= 4; M += 2) {
        g_vsl_count = g_vsl_bad_bounce = 0;
        g_max_bounces = M;
        f = render_with(c.scene, &vrl_probe, 2, 1, 64, 5, 2, M);
        printf("max_bounces %d: %zu surface VSLs in 2 passes\n", M, g_vsl_count);
        assert_true(g_vsl_count > 0);
        assert_int_equal(g_vsl_bad_bounce, 0);
        vbl_film_release(f);
    }
    /* max_bounces 1: only direct light; no surface VSL */
    g_vsl_count = 0;
    g_max_bounces = 1;
    f = render_with(c.scene, &vrl_probe, 1, 1, 64, 5, 2, 1);
    assert_int_equal(g_vsl_count, 0);
    assert_true(layer_total(f, "surface_from_surface") == 0.0);
    assert_true(layer_total(f, "surface_from_volume") == 0.0);
    assert_true(layer_total(f, "volume_from_surface") == 0.0);
    assert_true(layer_total(f, "surface_direct") > 0.0);
    vbl_film_release(f);
    free_case(&c);
}

/* ---- slow: agreement with pt ---------------------------------------------------------------- */

typedef struct stats {
    double mean[VBL_CLASS_COUNT][NB + 1], se[VBL_CLASS_COUNT][NB + 1]; /* index NB: image mean */
} stats;

static void replicate(const vbl_scene* scene, const vbl_estimator* est, int K, int passes, int spp, int paths,
                      uint64_t seed, stats* out)
{
    static double sum[VBL_CLASS_COUNT][NB + 1], sq[VBL_CLASS_COUNT][NB + 1];
    memset(sum, 0, sizeof sum);
    memset(sq, 0, sizeof sq);
    for (int r = 0; r < K; ++r) {
        vbl_film* film = render_with(scene, est, passes, spp, paths, seed + 7919u * (uint64_t)r, 2, -1);
        assert_true(tt_film_finite(film));
        for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
            const float* p = vbl_film_layer_rgb(film, layer_names[l]);
            double b[NB + 1] = {0};
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    double v = p ? (p[3 * (y * W + x)] + p[3 * (y * W + x) + 1] + p[3 * (y * W + x) + 2]) / 3.0 : 0.0;
                    b[(y / BLOCK) * (W / BLOCK) + x / BLOCK] += v / (BLOCK * BLOCK);
                    b[NB] += v / (W * H);
                }
            for (int k = 0; k <= NB; ++k) {
                sum[l][k] += b[k];
                sq[l][k] += b[k] * b[k];
            }
        }
        vbl_film_release(film);
    }
    for (int l = 0; l < VBL_CLASS_COUNT; ++l)
        for (int k = 0; k <= NB; ++k) {
            double m = sum[l][k] / K;
            out->mean[l][k] = m;
            out->se[l][k] = sqrt(fmax(0.0, (sq[l][k] - K * m * m) / (K - 1)) / K);
        }
}

static double zval(double a, double sa, double b, double sb)
{
    double s = sqrt(sa * sa + sb * sb), d = fabs(a - b);
    if (s > 0.0) return d / s;
    return d > 1e-12 * (fabs(a) + fabs(b)) ? INFINITY : 0.0;
}

/* Largest block/image z of layer l between a and scale * b. */
static double compare(const stats* a, const stats* b, int l, double scale, const char* tag, double* image_z)
{
    double zmax = 0.0;
    for (int k = 0; k < NB; ++k) zmax = fmax(zmax, zval(a->mean[l][k], a->se[l][k], scale * b->mean[l][k], scale * b->se[l][k]));
    *image_z = zval(a->mean[l][NB], a->se[l][NB], scale * b->mean[l][NB], scale * b->se[l][NB]);
    printf("%-10s %-20s image %.5g +- %.2g vs %.5g +- %.2g  image z %.2f  max block z %.2f\n", tag, layer_names[l],
           a->mean[l][NB], a->se[l][NB], scale * b->mean[l][NB], scale * b->se[l][NB], *image_z, zmax);
    return fmax(zmax, *image_z);
}

static void agree_scene(int phong)
{
    scene_case c = make_case(phong, 1);
    const int K = 12;
    stats* ref = calloc(1, sizeof *ref);
    stats* vr = calloc(1, sizeof *vr);
    stats* vp = calloc(1, sizeof *vp);
    replicate(c.scene, &vbl_estimator_pt, 8, 1, 256, 0, 100, ref);
    replicate(c.scene, &vbl_estimator_vrl, K, 16, 1, 64, 200, vr);
    replicate(c.scene, &vbl_estimator_vpl, K, 16, 1, 64, 300, vp);
    const char* tag = phong ? "phong" : "lambert";
    double iz;
    const int unbiased[3] = {VBL_CLASS_SURFACE_DIRECT, VBL_CLASS_VOLUME_DIRECT, VBL_CLASS_VOLUME_FROM_VOLUME};
    for (int i = 0; i < 3; ++i) {
        char t[32];
        snprintf(t, sizeof t, "%s-vrl", tag);
        assert_true(compare(ref, vr, unbiased[i], 1.0, t, &iz) < Z_CRIT);
        snprintf(t, sizeof t, "%s-vpl", tag);
        assert_true(compare(ref, vp, unbiased[i], 1.0, t, &iz) < Z_CRIT);
    }
    char t[32];
    snprintf(t, sizeof t, "%s-vrl", tag);
    assert_true(compare(ref, vr, VBL_CLASS_SURFACE_FROM_VOLUME, 1.0, t, &iz) < Z_CRIT);
    /* power: a 30% error in surface_from_volume is detected */
    compare(ref, vr, VBL_CLASS_SURFACE_FROM_VOLUME, 1.3, "power", &iz);
    assert_true(iz > Z_CRIT);
    /* vpl surface_from_volume / the radius-free point forms: reported (heavy-tailed, unclamped) */
    snprintf(t, sizeof t, "%s-vpl", tag);
    compare(ref, vp, VBL_CLASS_SURFACE_FROM_VOLUME, 1.0, t, &iz);
    compare(ref, vp, VBL_CLASS_SURFACE_FROM_SURFACE, 1.0, t, &iz);
    compare(ref, vp, VBL_CLASS_VOLUME_FROM_SURFACE, 1.0, t, &iz);
    snprintf(t, sizeof t, "%s-vrl", tag);
    compare(ref, vr, VBL_CLASS_SURFACE_FROM_SURFACE, 1.0, t, &iz);
    compare(ref, vr, VBL_CLASS_VOLUME_FROM_SURFACE, 1.0, t, &iz);
    free(ref);
    free(vr);
    free(vp);
    free_case(&c);
}

static void test_agree_lambert(void** state)
{
    (void)state;
    agree_scene(0);
}

static void test_agree_phong(void** state)
{
    (void)state;
    agree_scene(1);
}

/* Radius classes: |image mean - pt| of surface_from_surface + volume_from_surface, 1 vs 24 passes
 * from R_0 = 0.5 (eq 11 shrinks R_p; bias ~ R^2 and the pass-average's variance both fall). */
static void test_radius_error_falls(void** state)
{
    (void)state;
    scene_case c = make_case(0, 1);
    stats* ref = calloc(1, sizeof *ref);
    stats* a = calloc(1, sizeof *a);
    stats* b = calloc(1, sizeof *b);
    replicate(c.scene, &vbl_estimator_pt, 8, 1, 256, 0, 400, ref);
    replicate(c.scene, &vrl_r05, 24, 1, 1, 64, 500, a);
    replicate(c.scene, &vrl_r05, 4, 24, 1, 64, 600, b);
    stats* va = calloc(1, sizeof *va);
    stats* vb = calloc(1, sizeof *vb);
    replicate(c.scene, &vbl_surface, 8, 1, 1, 64, 700, va);
    replicate(c.scene, &vbl_surface, 2, 24, 1, 64, 800, vb);
    const int ls[3] = {VBL_CLASS_SURFACE_FROM_SURFACE, VBL_CLASS_VOLUME_FROM_SURFACE, VBL_CLASS_SURFACE_FROM_VOLUME};
    for (int i = 0; i < 3; ++i) {
        int l = ls[i];
        const double* ma = a->mean[l];
        const double* mb = b->mean[l];
        const double* mra = ref->mean[l];
        const double* mrb = ref->mean[l];
        if (i == 2) { /* VBL against eq 6 on the same photons */
            ma = va->mean[l];
            mb = vb->mean[l];
            mra = va->mean[VBL_CLASS_VOLUME_DIRECT];
            mrb = vb->mean[VBL_CLASS_VOLUME_DIRECT];
        }
        double r = mra[NB];
        double ea = fabs(ma[NB] - mra[NB]) / mra[NB], eb = fabs(mb[NB] - mrb[NB]) / mrb[NB];
        /* block RMS relative error */
        double ra = 0.0, rb = 0.0, rr = 0.0, rr2 = 0.0;
        for (int k = 0; k < NB; ++k) {
            ra += (ma[k] - mra[k]) * (ma[k] - mra[k]);
            rb += (mb[k] - mrb[k]) * (mb[k] - mrb[k]);
            rr += mra[k] * mra[k];
            rr2 += mrb[k] * mrb[k];
        }
        ra = sqrt(ra / rr);
        rb = sqrt(rb / rr2);
        printf("%-20s %s %.5g | 1 pass (R 0.5): %.5g (image err %.3f, block rms %.3f) | 24 passes (R_23 %.3f): "
               "%.5g (image err %.3f, block rms %.3f)\n",
               layer_names[l], i == 2 ? "eq 6" : "pt", r, ma[NB], ea, ra,
               vbl_radius_at_pass(0.5, VBL_RADIUS_ALPHA_DEFAULT, 2, 23), mb[NB], eb, rb);
        assert_true(rb < ra);
    }
    /* the vbl method itself (default radii: VSLs, VBLs eqs 8-9, caustics off here) against pt:
     * block RMS error of every surface class falls from 1 to 24 passes */
    stats* ma1 = calloc(1, sizeof *ma1);
    stats* ma24 = calloc(1, sizeof *ma24);
    replicate(c.scene, &vbl_estimator_vbl, 8, 1, 1, 64, 900, ma1);
    replicate(c.scene, &vbl_estimator_vbl, 2, 24, 1, 64, 1000, ma24);
    const int vs[4] = {VBL_CLASS_SURFACE_DIRECT, VBL_CLASS_SURFACE_FROM_SURFACE, VBL_CLASS_SURFACE_FROM_VOLUME,
                       VBL_CLASS_VOLUME_FROM_SURFACE};
    for (int i = 0; i < 4; ++i) {
        int l = vs[i];
        double ra = 0.0, rb = 0.0, rr = 0.0;
        for (int k = 0; k < NB; ++k) {
            ra += (ma1->mean[l][k] - ref->mean[l][k]) * (ma1->mean[l][k] - ref->mean[l][k]);
            rb += (ma24->mean[l][k] - ref->mean[l][k]) * (ma24->mean[l][k] - ref->mean[l][k]);
            rr += ref->mean[l][k] * ref->mean[l][k];
        }
        ra = sqrt(ra / rr);
        rb = sqrt(rb / rr);
        printf("vbl %-20s pt %.5g | 1 pass %.5g (block rms %.3f) | 24 passes %.5g (block rms %.3f)\n", layer_names[l],
               ref->mean[l][NB], ma1->mean[l][NB], ra, ma24->mean[l][NB], rb);
        assert_true(rb < ra);
        assert_true(rb < 0.25);
    }
    free(ma1);
    free(ma24);
    free(ref);
    free(a);
    free(b);
    free(va);
    free(vb);
    free_case(&c);
}

int main(int argc, char** argv)
{
    if (argc > 1 && strcmp(argv[1], "lambert") == 0) {
        const struct CMUnitTest slow[] = {cmocka_unit_test(test_agree_lambert)};
        return cmocka_run_group_tests(slow, NULL, NULL);
    }
    if (argc > 1 && strcmp(argv[1], "phong") == 0) {
        const struct CMUnitTest slow[] = {cmocka_unit_test(test_agree_phong)};
        return cmocka_run_group_tests(slow, NULL, NULL);
    }
    if (argc > 1 && strcmp(argv[1], "radius") == 0) {
        const struct CMUnitTest slow[] = {cmocka_unit_test(test_radius_error_falls)};
        return cmocka_run_group_tests(slow, NULL, NULL);
    }
    const struct CMUnitTest fast[] = {
        cmocka_unit_test(test_photon_store_surfaces),
        cmocka_unit_test(test_sum_finite_and_deterministic),
    };
    return cmocka_run_group_tests(fast, NULL, NULL);
}
