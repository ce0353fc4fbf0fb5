/* The blue-noise light preparation end to end in a closed Lambertian box lit by a point light:
 * camera placement -> adaptive elimination -> light paths (photon_paths.h) split among the lights. Checks: energy (stored + lost == traced), and each floor
 * light's irradiance estimate Phi_j / A_j (A_j = the area its partition-of-unity weight covers,
 * integrated by Monte Carlo) against the analytic direct irradiance I cos / d^2: unbiased up to
 * the smoothing over the light's radius, with the error falling as the photon count grows. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "transport/surface/blue_noise/blue_noise_lights.h"
#include "transport/surface/blue_noise/vsl_export.h"
#include "core/rng.h"
#include "scene/scene.h"
#include "transport/surface/blue_noise/photon_paths.h"
#include "transport/surface/blue_noise/prepare.h"
#include <omp.h>
#include "vbl/vbl.h"

static const vbl_vec3 light_pos = {0.3, 0.2, 1.6};
static const double intensity = 5.0;

static void add_quad(vbl_scene* scene, vbl_vec3 c, vbl_vec3 u, vbl_vec3 v, const vbl_material* m)
{
    double p[12];
    const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    for (int i = 0; i < 4; ++i) {
        vbl_vec3 x = vbl_v3_add(c, vbl_v3_add(vbl_v3_scale(u, su[i]), vbl_v3_scale(v, sv[i])));
        p[3 * i] = x.x, p[3 * i + 1] = x.y, p[3 * i + 2] = x.z;
    }
    unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    assert_int_equal(vbl_scene_add_mesh(scene, p, 4, idx, 2, m, NULL), VBL_SUCCESS);
}

static vbl_scene* box_scene(void)
{
    vbl_camera cam;
    assert_int_equal(vbl_camera_make(vbl_v3(0, -0.9, 1.0), vbl_v3(0.3, 1.0, 0.3), vbl_v3(0, 0, 1), 70.0, 32, 24, &cam),
                     VBL_SUCCESS);
    vbl_scene* s = NULL;
    assert_int_equal(vbl_scene_create_empty("bn closed box", &cam, &s), VBL_SUCCESS);
    vbl_material m = {VBL_MATERIAL_LAMBERT, {0.6, 0.6, 0.6}, {0, 0, 0}, 0.0, 0.0};
    vbl_vec3 X = {1, 0, 0}, Y = {0, 1, 0}, Z = {0, 0, 1};
    add_quad(s, vbl_v3(0, 0, 0), X, Y, &m);  /* floor */
    add_quad(s, vbl_v3(0, 0, 2), X, Y, &m);  /* ceiling */
    add_quad(s, vbl_v3(0, 1, 1), X, Z, &m);  /* walls */
    add_quad(s, vbl_v3(0, -1, 1), X, Z, &m);
    add_quad(s, vbl_v3(1, 0, 1), Y, Z, &m);
    add_quad(s, vbl_v3(-1, 0, 1), Y, Z, &m);
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_POINT;
    l.position = light_pos;
    l.color = vbl_v3(intensity, intensity, intensity);
    assert_int_equal(vbl_scene_add_light(s, &l), VBL_SUCCESS);
    return s;
}

static void test_pipeline_box(void** state)
{
    (void)state;
    vbl_scene* s = box_scene();
    vbl_bn_placement_options po = VBL_BN_PLACEMENT_DEFAULT;
    po.candidates = 12000;
    vbl_bn_candidate* c = NULL;
    size_t nc = 0;
    vbl_bn_placement_stats ps;
    assert_int_equal(vbl_bn_place_candidates(s, &po, &c, &nc, &ps), VBL_SUCCESS);
    assert_int_equal(nc, po.candidates); /* closed box: every sub-path ends on a wall */
    vbl_bn_light* lights = NULL;
    size_t nl = 0;
    assert_int_equal(vbl_bn_lights_from_candidates(c, nc, 1200, VBL_BN_VSL_ALPHA_DEFAULT, s->materials,
                                                   (size_t)s->surface_count, NULL, &lights, &nl),
                     VBL_SUCCESS);
    assert_int_equal(nl, 1200);

    /* area covered by each floor light's partition-of-unity weight (Monte Carlo on the floor) */
    vbl_bn_incident_field f;
    assert_int_equal(vbl_bn_field_init(&f, lights, nl, 16), VBL_SUCCESS);
    double* area = calloc(nl, sizeof(double));
    const int samples = 120000;
    vbl_rng rng = vbl_rng_make(3, 0, 0);
    size_t idx[256];
    double w[256];
    for (int i = 0; i < samples; ++i) {
        vbl_bn_photon_hit h = {{2.0 * vbl_rng_uniform(&rng) - 1.0, 2.0 * vbl_rng_uniform(&rng) - 1.0, 0.0},
                               {0, 0, 1}, {0, 0, 1}, {1, 1, 1}};
        size_t found = vbl_bn_split_weights(&f, &h, idx, w, 256);
        assert_true(found <= 256);
        for (size_t k = 0; k < found; ++k) area[idx[k]] += w[k] * 4.0 / samples;
    }
    vbl_bn_field_free(&f);

    double rms[2] = {0, 0};
    const int paths[2] = {10000, 40000};
    for (int run = 0; run < 2; ++run) {
        vbl_bn_photon_options po2 = VBL_BN_PHOTON_DEFAULT;
        po2.paths = (size_t)paths[run];
        po2.seed = 17 + (uint64_t)run;
        po2.max_bounce = 0; /* the direct hits: analytic irradiance */
        vbl_bn_photon_stats st;
        assert_int_equal(vbl_bn_field_init(&f, lights, nl, 16), VBL_SUCCESS);
        assert_int_equal(vbl_bn_trace_photons(s, &po2, &f, &st), VBL_SUCCESS);
        assert_int_equal(st.hits, po2.paths); /* closed box: one direct hit per path */
        vbl_vec3 stored = vbl_bn_field_stored_power(&f);
        double err = stored.x + f.lost_power.x - f.split_power.x;
        assert_true(fabs(err) < 1e-10 * f.split_power.x);
        assert_true(fabs(f.split_power.x - st.emitted.x) < 1e-10 * st.emitted.x);
        double flux = 4.0 * VBL_PI * intensity; /* point light inside the box: all of it */
        assert_true(fabs(st.emitted.x / flux - 1.0) < 1e-10);
        double sum2 = 0.0, sum_ratio = 0.0;
        size_t floor_lights = 0;
        for (size_t j = 0; j < nl; ++j) {
            if (fabs(lights[j].position.z) > 1e-9 || area[j] < 1e-4) continue;
            vbl_vec3 d = vbl_v3_sub(light_pos, lights[j].position);
            double r2 = vbl_v3_dot(d, d), e_true = intensity * d.z / (r2 * sqrt(r2));
            double e_est = f.values[f.offset[j]].x / area[j];
            double rel = e_est / e_true - 1.0;
            sum2 += rel * rel;
            sum_ratio += e_est / e_true;
            ++floor_lights;
        }
        rms[run] = sqrt(sum2 / (double)floor_lights);
        printf("%d light paths: lost %.1f%% of the flux (%zu of %zu hits: surfaces no camera sub-path reaches); "
               "%zu floor lights: mean E_est / E = %.4f, rms relative error %.3f\n",
               paths[run], 100.0 * f.lost_power.x / f.split_power.x, f.lost_hits, st.hits, floor_lights,
               sum_ratio / (double)floor_lights, rms[run]);
        assert_true(floor_lights > 120);
        assert_true(fabs(sum_ratio / (double)floor_lights - 1.0) < 0.05);
        vbl_bn_field_free(&f);
    }
    assert_true(rms[1] < 0.7 * rms[0]);
    free(area);
    free(lights);
    free(c);
    vbl_scene_release(s);
}

/* Same field on 1 and 2 threads (all bounces, Russian roulette); the surface-VSL adapter gives the
 * same split as the hits themselves. */
static void test_photons_threads_and_adapter(void** state)
{
    (void)state;
    vbl_scene* s = box_scene();
    vbl_bn_placement_options po = VBL_BN_PLACEMENT_DEFAULT;
    po.candidates = 5000;
    vbl_bn_candidate* c = NULL;
    size_t nc = 0;
    assert_int_equal(vbl_bn_place_candidates(s, &po, &c, &nc, NULL), VBL_SUCCESS);
    vbl_bn_light* lights = NULL;
    size_t nl = 0;
    assert_int_equal(vbl_bn_lights_from_candidates(c, nc, 500, 2.0, s->materials, (size_t)s->surface_count, NULL,
                                                   &lights, &nl),
                     VBL_SUCCESS);
    vbl_bn_incident_field a, b;
    assert_int_equal(vbl_bn_field_init(&a, lights, nl, 16), VBL_SUCCESS);
    assert_int_equal(vbl_bn_field_init(&b, lights, nl, 16), VBL_SUCCESS);
    vbl_bn_photon_options o = VBL_BN_PHOTON_DEFAULT;
    o.paths = 10000;
    o.chunk = 3000;
    vbl_bn_photon_stats sa, sb;
    omp_set_num_threads(1);
    assert_int_equal(vbl_bn_trace_photons(s, &o, &a, &sa), VBL_SUCCESS);
    omp_set_num_threads(2);
    assert_int_equal(vbl_bn_trace_photons(s, &o, &b, &sb), VBL_SUCCESS);
    assert_int_equal(sa.hits, sb.hits);
    assert_true(sa.hits > 2 * o.paths); /* multiple bounces (albedo 0.6, roulette) */
    assert_memory_equal(a.values, b.values, a.offset[nl] * sizeof(vbl_vec3));
    /* all bounces: the hits carry more than the emitted flux (reflected light is counted again) */
    printf("all bounces: %zu hits from %zu paths, split power / emitted = %.3f (1 / (1 - 0.6) = 2.5 expected)\n",
           sa.hits, o.paths, a.split_power.x / sa.emitted.x);
    assert_true(fabs(a.split_power.x / sa.emitted.x - 2.5) < 0.15);
    vbl_bn_field_free(&b);

    /* adapter: hits as surface VSL records */
    vbl_surface_vsl v[3];
    vbl_bn_photon_hit h[3];
    for (int i = 0; i < 3; ++i) {
        v[i].position = h[i].position = lights[7 * i].position;
        v[i].normal = h[i].normal = lights[7 * i].normal;
        v[i].incident = h[i].incident = lights[7 * i].normal;
        v[i].power = h[i].power = vbl_v3(1.0 + i, 2.0, 3.0);
        v[i].material = 0;
        v[i].bounce = 0;
    }
    vbl_bn_incident_field x, y;
    assert_int_equal(vbl_bn_field_init(&x, lights, nl, 16), VBL_SUCCESS);
    assert_int_equal(vbl_bn_field_init(&y, lights, nl, 16), VBL_SUCCESS);
    assert_int_equal(vbl_bn_split_surface_vsls(&x, v, 3), VBL_SUCCESS);
    assert_int_equal(vbl_bn_split_photons(&y, h, 3), VBL_SUCCESS);
    assert_memory_equal(x.values, y.values, x.offset[nl] * sizeof(vbl_vec3));
    v[1].power.x = -1.0;
    assert_int_equal(vbl_bn_split_surface_vsls(&x, v, 3), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "hits[1].power"));
    vbl_bn_field_free(&x);
    vbl_bn_field_free(&y);
    vbl_bn_field_free(&a);
    free(lights);
    free(c);
    vbl_scene_release(s);
}

/* vbl_bn_prepare: the chain in one call, Lambert emission = albedo x stored, same on 1 and 2
 * threads, export to the renderer's store. */
static void test_prepare(void** state)
{
    (void)state;
    vbl_scene* s = box_scene();
    vbl_bn_prepare_options o = VBL_BN_PREPARE_DEFAULT;
    o.placement.candidates = 8000;
    o.lights = 800;
    o.photons.paths = 10000;
    vbl_bn_prepared a, b;
    omp_set_num_threads(1);
    assert_int_equal(vbl_bn_prepare(s, &o, &a), VBL_SUCCESS);
    omp_set_num_threads(2);
    assert_int_equal(vbl_bn_prepare(s, &o, &b), VBL_SUCCESS);
    assert_int_equal(a.light_count, 800);
    assert_int_equal(a.light_count, b.light_count);
    assert_memory_equal(a.emission.values, b.emission.values, a.emission.offset[a.light_count] * sizeof(vbl_vec3));
    vbl_vec3 stored = vbl_bn_field_stored_power(&a.field);
    double emitted = 0.0;
    for (size_t j = 0; j < a.light_count; ++j) emitted += a.emission.power[j].x;
    printf("prepare: %zu lights, %zu hits (%zu lost), emitted / stored = %.6f (albedo 0.6)\n", a.light_count,
           a.photons.hits, a.photons.lost_hits, emitted / stored.x);
    assert_true(fabs(emitted / stored.x - 0.6) < 1e-9);
    double p = 0.0;
    size_t j = vbl_bn_pick_light(&a.set, 0.5, &p);
    assert_true(j < a.light_count && p > 0.0);
    assert_true(fabs(p - a.emission.power[j].x / emitted) < 1e-9);
    vbl_surface_vsl_store store;
    vbl_surface_vsl_store_init(&store, s->materials, (size_t)s->surface_count);
    assert_int_equal(vbl_bn_export_vsls(&a.field, &store, NULL), VBL_SUCCESS);
    assert_true(store.count > 0 && store.count <= a.light_count); /* Lambert: one entry per lit light */
    vbl_surface_vsl_store_free(&store);
    vbl_bn_prepared_free(&a);
    vbl_bn_prepared_free(&b);
    vbl_scene_release(s);
}

/* vbl_bn_prepare's stop hook (issue #18: a signal ends the render within a second): a hook that
 * never says stop changes nothing (bit for bit) and is asked in every step; one that says stop at
 * its k-th call, for k in the placement, the elimination and the photon tracing, ends the call
 * with VBL_ERROR_INTERRUPTED and *out empty (ASan: nothing leaks). */
static int g_calls, g_stop_at;
static int count_or_stop(void* user)
{
    (void)user;
    int k;
#pragma omp atomic capture
    k = ++g_calls;
    return g_stop_at > 0 && k >= g_stop_at;
}

static void test_prepare_stops(void** state)
{
    (void)state;
    vbl_scene* s = box_scene();
    vbl_bn_prepare_options o = VBL_BN_PREPARE_DEFAULT;
    o.placement.candidates = 8000;
    o.lights = 800;
    o.photons.paths = 10000;
    o.elimination.leaf_size = 1000; /* a level of parallel boxes below the root */
    omp_set_num_threads(1);
    vbl_bn_prepared a, b;
    assert_int_equal(vbl_bn_prepare(s, &o, &a), VBL_SUCCESS);
    o.stop = count_or_stop;
    g_calls = 0;
    g_stop_at = -1;
    assert_int_equal(vbl_bn_prepare(s, &o, &b), VBL_SUCCESS);
    const int total = g_calls;
    /* placement: 8000 / 256 calls; rmax: 8000 / 256; boxes and root: gathers and steps / 1024; photons: 10000 / 256 */
    printf("prepare: the stop hook was asked %d times\n", total);
    assert_true(total >= 32 + 32 + 40);
    assert_int_equal(a.light_count, b.light_count);
    assert_memory_equal(a.lights, b.lights, a.light_count * sizeof *a.lights);
    assert_memory_equal(a.emission.values, b.emission.values, a.emission.offset[a.light_count] * sizeof(vbl_vec3));
    assert_memory_equal(a.emission.power, b.emission.power, a.light_count * sizeof(vbl_vec3));
    vbl_bn_prepared_free(&b);
    const int stops[] = {1, 20, 40, 64, total};
    const char* where[] = {"placement", "placement", "elimination", "elimination", "photons"};
    for (size_t i = 0; i < sizeof stops / sizeof stops[0]; ++i) {
        g_calls = 0;
        g_stop_at = stops[i];
        omp_set_num_threads(1 + (int)(i & 1));
        assert_int_equal(vbl_bn_prepare(s, &o, &b), VBL_ERROR_INTERRUPTED);
        if (!strstr(vbl_last_error_message(), where[i]))
            fail_msg("stop at call %d of %d: '%s' does not name %s", stops[i], total, vbl_last_error_message(), where[i]);
        assert_null(b.lights);
        assert_int_equal(b.light_count, 0);
        assert_null(b.emission.values);
        vbl_bn_prepared_free(&b);
    }
    vbl_bn_prepared_free(&a);
    vbl_scene_release(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pipeline_box),
        cmocka_unit_test(test_photons_threads_and_adapter),
        cmocka_unit_test(test_prepare),
        cmocka_unit_test(test_prepare_stops),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
