/* Surface caustics by progressive photon mapping (transport/surface/surface_caustics.h).
 *
 * Scene: a Lambert floor (z = -1), a tilted Phong mirror (centre (1, 0, 0.5), normal
 * (-1, 0, -1)/sqrt 2) lit by a spot light aimed at it from (-1, 0, -0.5): the mirror throws a
 * caustic onto the floor, which the camera sees (the mirror itself is outside the view). A thin
 * sphere medium sits out of view (photon tracing needs media).
 *
 * Fast (no argument):
 *   - the highly specular predicate is transport/surface/blue_noise/camera_placement.c's rule;
 *   - the kernel integrates to 1 over the disc; the hash-grid gather equals a brute-force sum
 *     (cells smaller / larger than R, scan fallback); finite at tiny R; a uniform photon field
 *     gives the expected radiance;
 *   - photon stores: caustic photons only on non-specular surfaces straight after a highly
 *     specular vertex (traced back), bounce + 1 <= max_bounces; none (and the VRL/VPL/VSL stores
 *     bit-identical to caustics OFF) for media-only and Lambert-only scenes;
 *   - vrl/vpl renders of the caustic scene: bit-identical with 1 and 2 threads, layers sum to
 *     beauty, finite.
 * `slow`: vpl's surface_from_surface image mean against pt's (Phong 250 mirror), and the
 * block-RMS error of the caustic gather falling from 1 pass to 16 passes (R_0 = 0.4, eq 11). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "transport/surface/blue_noise/camera_placement.h"
#include "core/rng.h"
#include "material/material.h"
#include "transport/common/radius_schedule.h"
#include "render/render_internal.h"
#include "render_test_util.h"
#include "transport/common/photon_trace.h"
#include "transport/path_tracing/pt.h"
#include "transport/surface/surface_caustics.h"
#include "transport/surface/surface_gather.h"
#include "transport/virtual_lights/vpl.h"
#include "transport/virtual_lights/vrl.h"
#include "transport_test_util.h"
#include "surface_render_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

#define W 16
#define H 12
#define BLOCK 4
#define NB ((W / BLOCK) * (H / BLOCK))

/* ---- scene ---------------------------------------------------------------------------------- */

typedef struct caustic_case {
    vbl_scene* scene;
    vbl_volume* volume;
} caustic_case;

/* kind 0: media only; 1: floor + Lambert "mirror"; 2: floor + Phong mirror of `exponent`. */
static caustic_case make_case(int kind, double exponent)
{
    caustic_case c;
    vbl_camera cam = rt_camera(vbl_v3(-0.2, -1.0, 3.0), vbl_v3(-0.1, 0.0, -1.0), 30.0, W, H);
    c.scene = tt_scene(&cam);
    c.volume = tt_make_sphere(8, 0.3);
    vbl_affine tr;
    memset(&tr, 0, sizeof tr);
    tr.m[0][0] = tr.m[1][1] = tr.m[2][2] = 1.0;
    tr.m[0][3] = -2.0;
    tr.m[1][3] = 2.0;
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volume, 0.5, vbl_v3(0.8, 0.8, 0.8), 0.0, &tr), VBL_SUCCESS);
    const vbl_vec3 L = vbl_v3(-1.0, 0.0, -0.5), M = vbl_v3(1.0, 0.0, 0.5);
    tt_add_spot(c.scene, L, vbl_v3_sub(M, L), 20.0, 12.0, 16.0);
    if (kind >= 1) {
        vbl_material floor = {VBL_MATERIAL_LAMBERT, {0.7, 0.6, 0.5}, {0, 0, 0}, 0.0, 0.0};
        vbl_material lam = {VBL_MATERIAL_LAMBERT, {0.7, 0.7, 0.7}, {0, 0, 0}, 0.0, 0.0};
        vbl_material mir = {VBL_MATERIAL_PHONG, {0.0, 0.0, 0.0}, {0.9, 0.9, 0.9}, exponent, 0.0};
        add_quad(c.scene, vbl_v3(0, 0, -1), vbl_v3(2, 0, 0), vbl_v3(0, 2, 0), &floor);
        const double s = 0.35 / sqrt(2.0);
        add_quad(c.scene, M, vbl_v3(0, 0.35, 0), vbl_v3(s, 0, -s), kind == 2 ? &mir : &lam);
    }
    return c;
}

static void free_case(caustic_case* c)
{
    vbl_scene_release(c->scene);
    vt_free(c->volume);
}

/* ---- probe estimator: photon trace with chosen settings + the surface gather alone ---------- */

typedef struct probe_store {
    vbl_photon_store photons;
    vbl_surface_gather_settings gather;
} probe_store;

static double g_caustic_r0;      /* vbl_caustic_settings radius0 */
static int g_caustics_off;       /* vbl_caustic_settings mode OFF */
static int g_check;              /* pass_begin: compare against caustics OFF and trace photons back */
static size_t g_caustics, g_bad, g_active, g_store_mismatch;

static int same_stores(const vbl_photon_store* a, const vbl_photon_store* b)
{
    if (a->vrl_count != b->vrl_count || a->vpl_count != b->vpl_count || a->surface_vsl_count != b->surface_vsl_count)
        return 0;
    return (!a->vrl_count || memcmp(a->vrls, b->vrls, a->vrl_count * sizeof *a->vrls) == 0) &&
           (!a->vpl_count || memcmp(a->vpls, b->vpls, a->vpl_count * sizeof *a->vpls) == 0) &&
           (!a->surface_vsl_count ||
            memcmp(a->surface_vsls, b->surface_vsls, a->surface_vsl_count * sizeof *a->surface_vsls) == 0);
}

static vbl_result probe_begin(const vbl_render_context* ctx, void** store)
{
    probe_store* s = calloc(1, sizeof *s);
    assert_non_null(s);
    vbl_photon_settings ps;
    memset(&ps, 0, sizeof ps);
    ps.store_vrls = 1;
    ps.store_vpls = 1;
    ps.cache_kind = VBL_TRANSMITTANCE_CACHED_RATIO;
    ps.cache_entries = 16;
    vbl_caustic_settings cs = {g_caustics_off ? VBL_CAUSTICS_OFF : VBL_CAUSTICS_AUTO, g_caustic_r0, 0.0};
    vbl_result r = vbl_photon_trace_with_caustics(ctx, &ps, ctx->scene->surfaces != NULL, &cs, &s->photons);
    if (r) {
        free(s);
        return r;
    }
    if (g_check) { /* pass_begin is the driver's single-threaded entry */
        const vbl_scene* scene = ctx->scene;
        const int M = ctx->options.max_bounces;
        const vbl_photon_store* p = &s->photons;
        g_active += (size_t)p->caustics_active;
        g_caustics += p->caustics.count;
        for (size_t i = 0; i < p->caustics.count; ++i) {
            const vbl_caustic_photon* c = &p->caustics.photons[i];
            int ok = c->bounce >= 1 && (M < 0 || c->bounce + 1 <= M) && fabs(c->position.z + 1.0) < 1e-6;
            /* straight back along the incident direction: the first surface is highly specular */
            vbl_surface_hit hit;
            vbl_vec3 o = vbl_surface_spawn(scene->surfaces, c->position, c->normal, c->incident);
            ok = ok && vbl_surfaces_intersect(scene->surfaces, o, c->incident, 0.0, INFINITY, &hit) &&
                 vbl_material_is_highly_specular(&scene->materials[hit.material]);
            if (!ok) ++g_bad;
        }
        if (M < 0 || !p->caustics_active) { /* the walk is unchanged: the other stores too */
            vbl_caustic_settings off = cs;
            off.mode = VBL_CAUSTICS_OFF;
            vbl_photon_store q;
            assert_int_equal(vbl_photon_trace_with_caustics(ctx, &ps, scene->surfaces != NULL, &off, &q), VBL_SUCCESS);
            assert_int_equal(q.caustics_active, 0);
            assert_int_equal(q.caustics.count, 0);
            if (!same_stores(p, &q)) ++g_store_mismatch;
            vbl_photon_store_free(&q);
        }
    }
    s->gather.kernel_samples = VBL_SURFACE_KERNEL_SAMPLES_DEFAULT;
    *store = s;
    return VBL_SUCCESS;
}

static void probe_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                         const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    const probe_store* s = store;
    if (ctx->scene->surfaces && s) vbl_surface_gather_hit(ctx, ts, &s->photons, &s->gather, sample, rng, out);
}

static void probe_end(const vbl_render_context* ctx, void* store)
{
    (void)ctx;
    probe_store* s = store;
    if (!s) return;
    vbl_photon_store_free(&s->photons);
    free(s);
}

static const vbl_estimator probe = {"caustic-probe", 1, probe_begin, probe_sample, probe_end, NULL};

/* ---- fast ----------------------------------------------------------------------------------- */

static void test_predicate(void** state)
{
    (void)state;
    vbl_bn_placement_options o = VBL_BN_PLACEMENT_DEFAULT;
    const double exps[6] = {0.0, 60.0, 199.9, 200.0, 1e4, 1e6};
    const double ks[2] = {0.0, 0.3};
    const double rough[7] = {1e-3, 0.01, 0.05, 0.1, 0.1000001, 0.3, 1.0};
    int highly = 0;
    for (int e = 0; e < 6; ++e)
        for (int k = 0; k < 2; ++k) {
            vbl_material m = {VBL_MATERIAL_PHONG, {0.2, 0.2, 0.2}, {ks[k], ks[k], ks[k]}, exps[e], 0.0};
            int h = vbl_material_is_highly_specular(&m);
            assert_int_equal(h, vbl_bn_highly_specular(&m, &o));
            assert_int_equal(h, ks[k] > 0.0 && exps[e] >= 200.0);
            highly += h;
        }
    for (int r = 0; r < 7; ++r) {
        vbl_material m = {VBL_MATERIAL_GGX, {0.2, 0.2, 0.2}, {0.04, 0.04, 0.04}, 0.0, rough[r]};
        int h = vbl_material_is_highly_specular(&m);
        assert_int_equal(h, vbl_bn_highly_specular(&m, &o));
        assert_int_equal(h, rough[r] <= 0.1);
        highly += h;
    }
    vbl_material lam = {VBL_MATERIAL_LAMBERT, {0.8, 0.8, 0.8}, {0, 0, 0}, 0.0, 0.0};
    assert_int_equal(vbl_material_is_highly_specular(&lam), 0);
    assert_int_equal(highly, 3 + 4);
    vbl_material two[2] = {lam, lam};
    assert_int_equal(vbl_materials_any_highly_specular(two, 2), 0);
    two[1].type = VBL_MATERIAL_GGX;
    two[1].roughness = 0.05;
    assert_int_equal(vbl_materials_any_highly_specular(two, 2), 1);
}

static vbl_vec3 brute_gather(const vbl_caustic_photon* ph, size_t n, vbl_vec3 x, vbl_vec3 nrm, vbl_vec3 wo,
                             const vbl_material* m, double R, int M)
{
    vbl_vec3 s = vbl_v3(0, 0, 0);
    for (size_t i = 0; i < n; ++i) {
        vbl_vec3 to = vbl_v3_sub(ph[i].position, x);
        double k = vbl_caustic_kernel(vbl_v3_dot(to, to), R);
        if (!(k > 0.0) || vbl_v3_dot(ph[i].normal, nrm) <= 0.5 || vbl_v3_dot(ph[i].incident, nrm) <= 0.0) continue;
        if (M >= 0 && ph[i].bounce + 1 > M) continue;
        s = vbl_v3_add(s, vbl_v3_scale(vbl_v3_mul(vbl_material_eval(m, nrm, wo, ph[i].incident), ph[i].power), k));
    }
    return s;
}

static void test_kernel_and_map(void** state)
{
    (void)state;
    /* the kernel integrates to 1 over the disc */
    const double radii[3] = {1e-3, 0.5, 7.0};
    for (int r = 0; r < 3; ++r) {
        const double R = radii[r];
        const int n = 200000;
        double s = 0.0;
        for (int i = 0; i < n; ++i) {
            double rr = (i + 0.5) * R / n;
            s += vbl_caustic_kernel(rr * rr, R) * 2.0 * VBL_PI * rr * (R / n);
        }
        printf("kernel integral over the disc, R = %g: %.12f\n", R, s);
        assert_true(fabs(s - 1.0) < 1e-8);
        assert_true(vbl_caustic_kernel(R * R * 1.0000001, R) == 0.0);
    }
    /* Cartesian check (the disc as a plane region, R = 1) */
    {
        const int n = 2000;
        double s = 0.0, h = 2.0 / n;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double x = -1.0 + (i + 0.5) * h, y = -1.0 + (j + 0.5) * h;
                s += vbl_caustic_kernel(x * x + y * y, 1.0) * h * h;
            }
        assert_true(fabs(s - 1.0) < 1e-4);
    }

    /* grid gather == brute force: photons on two planes (z = 0 facing +z, z = 0.02 facing -z) */
    const size_t N = 3000;
    vbl_caustic_photon* ph = calloc(N, sizeof *ph);
    assert_non_null(ph);
    vbl_rng rng = vbl_rng_make(42, 0, 0);
    for (size_t i = 0; i < N; ++i) {
        int back = i % 7 == 0;
        ph[i].position = vbl_v3(vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), back ? 0.02 : 0.0);
        ph[i].normal = vbl_v3(0, 0, back ? -1.0 : 1.0);
        double u = vbl_rng_uniform(&rng), v = 2.0 * VBL_PI * vbl_rng_uniform(&rng);
        double st = sqrt(1.0 - u * u);
        ph[i].incident = vbl_v3(st * cos(v), st * sin(v), back ? -u : u);
        ph[i].power = vbl_v3(vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng));
        ph[i].bounce = 1 + (int)(i % 3);
    }
    vbl_material mats[2] = {{VBL_MATERIAL_LAMBERT, {0.7, 0.6, 0.5}, {0, 0, 0}, 0.0, 0.0},
                            {VBL_MATERIAL_PHONG, {0.3, 0.3, 0.3}, {0.5, 0.5, 0.5}, 40.0, 0.0}};
    const double cells[3] = {0.01, 0.05, 0.3};
    const double Rs[5] = {0.004, 0.02, 0.05, 0.2, 3.0};
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        vbl_caustic_map map;
        assert_int_equal(vbl_caustic_map_build(&map, ph, N, cells[c]), VBL_SUCCESS);
        assert_int_equal(map.count, N);
        for (int q = 0; q < 60; ++q) {
            vbl_vec3 x = vbl_v3(1.2 * vbl_rng_uniform(&rng) - 0.1, 1.2 * vbl_rng_uniform(&rng) - 0.1, 0.0);
            vbl_vec3 wo = vbl_v3_normalize(vbl_v3(0.3, -0.2, 1.0));
            for (int r = 0; r < 5; ++r)
                for (int M = -1; M <= 3; M += 4) {
                    const vbl_material* m = &mats[q % 2];
                    vbl_vec3 a = vbl_caustic_gather(&map, x, vbl_v3(0, 0, 1), wo, m, Rs[r], M);
                    vbl_vec3 b = brute_gather(ph, N, x, vbl_v3(0, 0, 1), wo, m, Rs[r], M);
                    double d = vbl_v3_max_component(vbl_v3(fabs(a.x - b.x), fabs(a.y - b.y), fabs(a.z - b.z)));
                    double rel = d / fmax(1e-300, vbl_v3_max_component(b));
                    if (d > 0.0) worst = fmax(worst, rel);
                    assert_true(d <= 1e-11 * fmax(1.0, vbl_v3_max_component(b)));
                }
        }
        vbl_caustic_map_free(&map);
    }
    printf("grid vs brute force: largest relative difference %.3g\n", worst);

    /* uniform photon field of total flux Phi on the unit square: L = (a / pi) Phi / A inside */
    {
        const size_t U = 40000;
        vbl_caustic_photon* up = calloc(U, sizeof *up);
        assert_non_null(up);
        for (size_t i = 0; i < U; ++i) {
            up[i].position = vbl_v3(vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), 0.0);
            up[i].normal = vbl_v3(0, 0, 1);
            up[i].incident = vbl_v3(0, 0, 1);
            up[i].power = vbl_v3(2.0 / U, 2.0 / U, 2.0 / U);
            up[i].bounce = 1;
        }
        vbl_caustic_map map;
        assert_int_equal(vbl_caustic_map_build(&map, up, U, 0.05), VBL_SUCCESS);
        double s = 0.0;
        const int Q = 200;
        for (int q = 0; q < Q; ++q) {
            vbl_vec3 x = vbl_v3(0.2 + 0.6 * vbl_rng_uniform(&rng), 0.2 + 0.6 * vbl_rng_uniform(&rng), 0.0);
            s += vbl_caustic_gather(&map, x, vbl_v3(0, 0, 1), vbl_v3(0, 0, 1), &mats[0], 0.05, -1).x;
        }
        double expect = 0.7 / VBL_PI * 2.0;
        printf("uniform field: mean L %.5f expected %.5f\n", s / Q, expect);
        assert_true(fabs(s / Q - expect) < 0.03 * expect);
        vbl_caustic_map_free(&map);
        free(up);
    }

    /* tiny R (a query exactly on a photon), a huge R against tiny cells, empty maps: finite */
    {
        vbl_caustic_map map;
        assert_int_equal(vbl_caustic_map_build(&map, ph, N, 0.05), VBL_SUCCESS);
        const double tiny[6] = {0.0, 1e-300, 1e-100, 1e-60, 1e-30, 1e-12};
        for (int r = 0; r < 6; ++r) {
            vbl_vec3 a = vbl_caustic_gather(&map, ph[5].position, ph[5].normal, ph[5].normal, &mats[1], tiny[r], -1);
            assert_true(isfinite(a.x) && isfinite(a.y) && isfinite(a.z) && a.x >= 0.0 && a.y >= 0.0 && a.z >= 0.0);
        }
        vbl_caustic_map_free(&map);
        assert_int_equal(vbl_caustic_map_build(&map, ph, N, 1e-9), VBL_SUCCESS);
        vbl_vec3 a = vbl_caustic_gather(&map, vbl_v3(0.5, 0.5, 0), vbl_v3(0, 0, 1), vbl_v3(0, 0, 1), &mats[0], 1.0, -1);
        vbl_vec3 b = brute_gather(ph, N, vbl_v3(0.5, 0.5, 0), vbl_v3(0, 0, 1), vbl_v3(0, 0, 1), &mats[0], 1.0, -1);
        assert_true(fabs(a.x - b.x) <= 1e-11 * b.x);
        vbl_caustic_map_free(&map);
        assert_int_equal(vbl_caustic_map_build(&map, NULL, 0, 0.1), VBL_SUCCESS);
        a = vbl_caustic_gather(&map, vbl_v3(0, 0, 0), vbl_v3(0, 0, 1), vbl_v3(0, 0, 1), &mats[0], 1.0, -1);
        assert_true(a.x == 0.0 && a.y == 0.0 && a.z == 0.0);
        assert_int_not_equal(vbl_caustic_map_build(&map, ph, N, 0.0), VBL_SUCCESS);
    }
    free(ph);
}

static void reset_probe(void)
{
    g_caustics = g_bad = g_active = g_store_mismatch = 0;
    g_check = 1;
    g_caustic_r0 = 0.0;
}

static void test_photon_stores(void** state)
{
    (void)state;
    /* media only and Lambert only: no caustics, stores as with caustics OFF */
    for (int kind = 0; kind <= 1; ++kind) {
        caustic_case c = make_case(kind, 0.0);
        for (int M = -1; M <= 3; M += 4) {
            reset_probe();
            vbl_film* f = render_with(c.scene, &probe, 2, 1, 256, 3, 2, M);
            printf("kind %d M %d: active %zu caustics %zu\n", kind, M, g_active, g_caustics);
            assert_int_equal(g_active, 0);
            assert_int_equal(g_caustics, 0);
            assert_int_equal(g_store_mismatch, 0);
            vbl_film_release(f);
        }
        free_case(&c);
    }
    /* the mirror: caustic photons, all straight after the mirror, within max_bounces */
    caustic_case c = make_case(2, 1e4);
    for (int M = -1; M <= 3; ++M) {
        if (M == 0 || M == 1) continue;
        reset_probe();
        vbl_film* f = render_with(c.scene, &probe, 2, 1, 256, 3, 2, M);
        printf("mirror M %d: active %zu caustics %zu bad %zu sfs %.4g\n", M, g_active, g_caustics, g_bad,
               layer_total(f, "surface_from_surface"));
        assert_int_equal(g_active, 2);
        assert_true(g_caustics > 50);
        assert_int_equal(g_bad, 0);
        assert_int_equal(g_store_mismatch, 0);
        assert_true(tt_film_finite(f));
        assert_true(layer_total(f, "surface_from_surface") > 0.0);
        vbl_film_release(f);
    }
    /* the mirror with caustics OFF in the trace: nothing active */
    free_case(&c);
}

/* The camera never sees the mirror (pixel centres). */
static void check_mirror_hidden(const vbl_scene* scene)
{
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            vbl_vec3 o, d;
            vbl_camera_ray(&scene->camera, x + 0.5, y + 0.5, &o, &d);
            vbl_surface_hit hit;
            assert_true(vbl_surfaces_intersect(scene->surfaces, o, d, 0.0, INFINITY, &hit));
            assert_int_equal(hit.material, 0);
        }
}

static void test_render_determinism(void** state)
{
    (void)state;
    caustic_case c = make_case(2, 1e4);
    check_mirror_hidden(c.scene);
    const vbl_estimator* ests[2] = {&vbl_estimator_vpl, &vbl_estimator_vrl};
    for (int e = 0; e < 2; ++e) {
        vbl_film* a = render_with(c.scene, ests[e], 2, 1, 128, 9, 1, -1);
        vbl_film* b = render_with(c.scene, ests[e], 2, 1, 128, 9, 2, -1);
        check_sum_to_beauty(a);
        printf("%s surface_from_surface total %.5g\n", ests[e]->name, layer_total(a, "surface_from_surface"));
        assert_true(layer_total(a, "surface_from_surface") > 0.0);
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

/* ---- slow ------------------------------------------------------------------------------------ */

typedef struct stats {
    double mean[NB + 1], se[NB + 1]; /* surface_from_surface blocks; NB: image mean */
} stats;

static void replicate(const vbl_scene* scene, const vbl_estimator* est, int K, int passes, int spp, int paths,
                      uint64_t seed, stats* out)
{
    double sum[NB + 1] = {0}, sq[NB + 1] = {0};
    for (int r = 0; r < K; ++r) {
        vbl_film* film = render_with(scene, est, passes, spp, paths, seed + 7919u * (uint64_t)r, 2, -1);
        assert_true(tt_film_finite(film));
        const float* p = vbl_film_layer_rgb(film, "surface_from_surface");
        assert_non_null(p);
        double b[NB + 1] = {0};
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                double v = (p[3 * (y * W + x)] + p[3 * (y * W + x) + 1] + p[3 * (y * W + x) + 2]) / 3.0;
                b[(y / BLOCK) * (W / BLOCK) + x / BLOCK] += v / (BLOCK * BLOCK);
                b[NB] += v / (W * H);
            }
        for (int k = 0; k <= NB; ++k) {
            sum[k] += b[k];
            sq[k] += b[k] * b[k];
        }
        vbl_film_release(film);
    }
    for (int k = 0; k <= NB; ++k) {
        double m = sum[k] / K;
        out->mean[k] = m;
        out->se[k] = K > 1 ? sqrt(fmax(0.0, (sq[k] - K * m * m) / (K - 1)) / K) : 0.0;
    }
}

static double zval(double a, double sa, double b, double sb)
{
    double s = sqrt(sa * sa + sb * sb), d = fabs(a - b);
    return s > 0.0 ? d / s : (d > 0.0 ? INFINITY : 0.0);
}

static double block_rms(const stats* a, const stats* ref)
{
    double e = 0.0, r = 0.0;
    for (int k = 0; k < NB; ++k) {
        e += (a->mean[k] - ref->mean[k]) * (a->mean[k] - ref->mean[k]);
        r += ref->mean[k] * ref->mean[k];
    }
    return sqrt(e / r);
}

static void test_slow_agreement(void** state)
{
    (void)state;
    caustic_case c = make_case(2, 250.0);
    check_mirror_hidden(c.scene);
    stats ref, vp, vr, off, a, b;
    replicate(c.scene, &vbl_estimator_pt, 12, 1, 2048, 0, 100, &ref);
    assert_true(ref.mean[NB] > 0.0);
    const vbl_estimator* ests[2] = {&vbl_estimator_vpl, &vbl_estimator_vrl};
    stats* outs[2] = {&vp, &vr};
    for (int e = 0; e < 2; ++e) {
        replicate(c.scene, ests[e], 8, 4, 1, 1000, 200 + 100 * (uint64_t)e, outs[e]);
        double z = zval(outs[e]->mean[NB], outs[e]->se[NB], ref.mean[NB], ref.se[NB]);
        double zp = zval(1.25 * outs[e]->mean[NB], 1.25 * outs[e]->se[NB], ref.mean[NB], ref.se[NB]);
        printf("surface_from_surface image mean: pt %.5g +- %.2g, %s (caustics, default R0) %.5g +- %.2g, z %.2f, "
               "block rms %.3f; x 1.25: z %.2f\n",
               ref.mean[NB], ref.se[NB], ests[e]->name, outs[e]->mean[NB], outs[e]->se[NB], z,
               block_rms(outs[e], &ref), zp);
        assert_true(z < 4.0);
        assert_true(zp > 4.0); /* power check: a 25% error is detected */
    }
    /* for the record: the same store with caustics OFF (highly specular VSLs as point lights) */
    reset_probe();
    g_check = 0;
    g_caustics_off = 1;
    replicate(c.scene, &probe, 4, 4, 1, 1000, 500, &off);
    g_caustics_off = 0;
    printf("caustics OFF (mirror VSLs, point form): %.5g +- %.2g, z %.2f, block rms %.3f\n", off.mean[NB], off.se[NB],
           zval(off.mean[NB], off.se[NB], ref.mean[NB], ref.se[NB]), block_rms(&off, &ref));
    /* falling error: R_0 = 0.4, 16 x 1 pass against 2 x 16 passes (equal cost) */
    reset_probe();
    g_check = 0;
    g_caustic_r0 = 0.4;
    replicate(c.scene, &probe, 16, 1, 1, 1000, 300, &a);
    replicate(c.scene, &probe, 4, 16, 1, 1000, 400, &b);
    double ea = block_rms(&a, &ref), eb = block_rms(&b, &ref);
    printf("R_0 0.4: 1 pass block rms %.3f (image %.5g) | 16 passes (R_15 %.3f) block rms %.3f (image %.5g)\n", ea,
           a.mean[NB], vbl_radius_at_pass(0.4, VBL_RADIUS_ALPHA_DEFAULT, 2, 15), eb, b.mean[NB]);
    assert_true(eb < ea);
    g_caustic_r0 = 0.0;
    free_case(&c);
}

int main(int argc, char** argv)
{
    if (argc > 1 && strcmp(argv[1], "slow") == 0) {
        const struct CMUnitTest slow[] = {cmocka_unit_test(test_slow_agreement)};
        return cmocka_run_group_tests(slow, NULL, NULL);
    }
    const struct CMUnitTest fast[] = {
        cmocka_unit_test(test_predicate),
        cmocka_unit_test(test_kernel_and_map),
        cmocka_unit_test(test_photon_stores),
        cmocka_unit_test(test_render_determinism),
    };
    return cmocka_run_group_tests(fast, NULL, NULL);
}
