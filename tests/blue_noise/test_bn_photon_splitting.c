/* Photon splitting (Li et al. 2022, section 3.3): energy conservation (stored +
 * lost == split power), partition of unity with weights 1 - (d/r)^2 against brute force, the
 * same-side rule, lost hits, merge; emission conversion (Lambert exact, the octahedral
 * conversion of a Lambertian lobe against the single value, GGX never gains energy); export to
 * the renderer's surface VSL store reproduces the emission profile. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "transport/surface/blue_noise/photon_splitting.h"
#include "transport/surface/blue_noise/vsl_export.h"
#include "core/rng.h"
#include "vbl/vbl.h"

static const vbl_material materials[3] = {
    {VBL_MATERIAL_LAMBERT, {0.8, 0.5, 0.2}, {0, 0, 0}, 0.0, 0.0},
    {VBL_MATERIAL_PHONG, {0.3, 0.3, 0.3}, {0.5, 0.4, 0.3}, 30.0, 0.0},
    {VBL_MATERIAL_GGX, {0.2, 0.4, 0.6}, {0.9, 0.9, 0.9}, 0.0, 0.3},
};

/* A 10 x 10 grid of lights on z = 0 (spacing 0.1, radius 0.13, material i % 3) plus one light
 * facing down at the centre. */
static size_t make_lights(vbl_bn_light* l)
{
    size_t n = 0;
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i) {
            l[n].position = vbl_v3(0.05 + 0.1 * i, 0.05 + 0.1 * j, 0.0);
            l[n].normal = vbl_v3(0, 0, 1);
            l[n].radius = 0.13;
            l[n].material = (int)(n % 3);
            l[n].diffuse = vbl_material_is_diffuse(&materials[l[n].material]);
            ++n;
        }
    l[n].position = vbl_v3(0.5, 0.5, 0.0);
    l[n].normal = vbl_v3(0, 0, -1);
    l[n].radius = 0.2;
    l[n].material = 0;
    l[n].diffuse = 1;
    return n + 1;
}

static vbl_vec3 hemisphere(vbl_rng* r, vbl_vec3 n)
{
    double z = vbl_rng_uniform(r), phi = 2.0 * VBL_PI * vbl_rng_uniform(r), s = sqrt(fmax(0.0, 1.0 - z * z));
    z = fmax(z, 1e-3);
    vbl_vec3 t, b;
    vbl_v3_basis(n, &t, &b);
    return vbl_v3_normalize(vbl_v3_add(vbl_v3_add(vbl_v3_scale(t, s * cos(phi)), vbl_v3_scale(b, s * sin(phi))),
                                       vbl_v3_scale(n, z)));
}

/* Hits over [-0.3, 1.3]^2 (some far from any light), both sides of the plane. */
static vbl_bn_photon_hit* make_hits(size_t n, uint64_t seed)
{
    vbl_bn_photon_hit* h = malloc(n * sizeof *h);
    vbl_rng r = vbl_rng_make(seed, 0, 0);
    for (size_t i = 0; i < n; ++i) {
        h[i].position = vbl_v3(-0.3 + 1.6 * vbl_rng_uniform(&r), -0.3 + 1.6 * vbl_rng_uniform(&r), 0.0);
        h[i].normal = vbl_rng_uniform(&r) < 0.9 ? vbl_v3(0, 0, 1) : vbl_v3(0, 0, -1);
        h[i].incident = hemisphere(&r, h[i].normal);
        h[i].power = vbl_v3(vbl_rng_uniform(&r), 2.0 * vbl_rng_uniform(&r), 0.5 * vbl_rng_uniform(&r));
    }
    return h;
}

static void test_energy_conservation_and_partition(void** state)
{
    (void)state;
    vbl_bn_light lights[101];
    size_t nl = make_lights(lights);
    vbl_bn_incident_field f;
    assert_int_equal(vbl_bn_field_init(&f, lights, nl, 16), VBL_SUCCESS);
    const size_t n = 50000;
    vbl_bn_photon_hit* hits = make_hits(n, 3);
    /* partition of unity and the lost set against brute force */
    vbl_vec3 input = vbl_v3(0, 0, 0), lost = vbl_v3(0, 0, 0);
    size_t lost_hits = 0, idx[128];
    double w[128], worst_sum = 0.0, worst_w = 0.0;
    for (size_t i = 0; i < n; ++i) {
        input = vbl_v3_add(input, hits[i].power);
        double expect[101], sum = 0.0;
        for (size_t k = 0; k < nl; ++k) {
            vbl_vec3 d = vbl_v3_sub(hits[i].position, lights[k].position);
            double q = vbl_v3_dot(d, d) / (lights[k].radius * lights[k].radius);
            int same = vbl_v3_dot(lights[k].normal, hits[i].normal) > 0.0 &&
                       vbl_v3_dot(lights[k].normal, hits[i].incident) > 0.0;
            expect[k] = (q < 1.0 && same) ? 1.0 - q : 0.0;
            sum += expect[k];
        }
        size_t found = vbl_bn_split_weights(&f, &hits[i], idx, w, 128);
        if (sum == 0.0) {
            assert_int_equal(found, 0);
            lost = vbl_v3_add(lost, hits[i].power);
            ++lost_hits;
            continue;
        }
        double s = 0.0;
        size_t nonzero = 0;
        for (size_t k = 0; k < nl; ++k) nonzero += expect[k] > 0.0;
        assert_int_equal(found, nonzero);
        for (size_t k = 0; k < found; ++k) {
            s += w[k];
            worst_w = fmax(worst_w, fabs(w[k] - expect[idx[k]] / sum));
        }
        worst_sum = fmax(worst_sum, fabs(s - 1.0));
    }
    printf("partition of unity: max |sum w - 1| = %.3g, max |w - brute force| = %.3g, %zu of %zu hits lost\n",
           worst_sum, worst_w, lost_hits, n);
    assert_true(worst_sum < 1e-14 && worst_w < 1e-14);
    assert_true(lost_hits > n / 10 && lost_hits < 7 * n / 10);

    assert_int_equal(vbl_bn_split_photons(&f, hits, n), VBL_SUCCESS);
    vbl_vec3 stored = vbl_bn_field_stored_power(&f);
    assert_int_equal(f.hits, n);
    assert_int_equal(f.lost_hits, lost_hits);
    double e[3] = {stored.x + f.lost_power.x - input.x, stored.y + f.lost_power.y - input.y,
                   stored.z + f.lost_power.z - input.z};
    printf("energy: input (%.6f, %.6f, %.6f), stored + lost - input = (%.3g, %.3g, %.3g), lost (%.3f, %.3f, %.3f)\n",
           input.x, input.y, input.z, e[0], e[1], e[2], f.lost_power.x, f.lost_power.y, f.lost_power.z);
    for (int c = 0; c < 3; ++c) assert_true(fabs(e[c]) < 1e-10 * vbl_v3_get(input, c));
    assert_true(fabs(f.split_power.x - input.x) < 1e-10 * input.x);
    assert_true(fabs(f.lost_power.y - lost.y) < 1e-10 * lost.y);
    /* the downward light only receives hits from below */
    const vbl_vec3* down = f.values + f.offset[nl - 1];
    assert_true(down[0].x > 0.0);

    /* merge: two halves equal the whole */
    vbl_bn_incident_field a, b;
    assert_int_equal(vbl_bn_field_init(&a, lights, nl, 16), VBL_SUCCESS);
    assert_int_equal(vbl_bn_field_init(&b, lights, nl, 16), VBL_SUCCESS);
    assert_int_equal(vbl_bn_split_photons(&a, hits, n / 2), VBL_SUCCESS);
    assert_int_equal(vbl_bn_split_photons(&b, hits + n / 2, n - n / 2), VBL_SUCCESS);
    assert_int_equal(vbl_bn_field_merge(&a, &b), VBL_SUCCESS);
    for (size_t k = 0; k < f.offset[nl]; ++k)
        assert_true(fabs(a.values[k].y - f.values[k].y) <= 1e-12 * (1.0 + f.values[k].y));
    assert_int_equal(a.lost_hits, f.lost_hits);
    vbl_bn_field_free(&a);
    vbl_bn_field_free(&b);

    /* bad hit: named, nothing added */
    vbl_bn_photon_hit bad = hits[0];
    bad.power.y = NAN;
    assert_int_equal(vbl_bn_split_photons(&f, &bad, 1), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "hits[0].power"));
    assert_int_equal(f.hits, n);
    free(hits);
    vbl_bn_field_free(&f);

    lights[3].radius = 0.0;
    assert_int_equal(vbl_bn_field_init(&f, lights, nl, 16), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "lights[3].radius"));
}

static void test_emission_conversion(void** state)
{
    (void)state;
    /* the same Lambertian light twice: single value (diffuse = 1) and through the octahedral
     * conversion (diffuse = 0); plus a Phong and a GGX light */
    vbl_bn_light l[4];
    for (int i = 0; i < 4; ++i) {
        l[i].position = vbl_v3(2.0 * i, 0.0, 0.0);
        l[i].normal = vbl_v3_normalize(vbl_v3(0.2, -0.3, 1.0));
        l[i].radius = 0.5;
    }
    l[0].material = 0, l[0].diffuse = 1;
    l[1].material = 0, l[1].diffuse = 0;
    l[2].material = 1, l[2].diffuse = 0;
    l[3].material = 2, l[3].diffuse = 0;
    vbl_bn_incident_field f;
    assert_int_equal(vbl_bn_field_init(&f, l, 4, 16), VBL_SUCCESS);
    const size_t n = 4000;
    vbl_bn_photon_hit* h = malloc(4 * n * sizeof *h);
    vbl_rng r = vbl_rng_make(77, 0, 0);
    for (size_t k = 0; k < 4 * n; ++k) {
        h[k].position = l[k / n].position; /* exactly at the light: weight 1 */
        h[k].normal = l[k / n].normal;
        h[k].incident = hemisphere(&r, l[k / n].normal);
        h[k].power = vbl_v3(1.0, 1.0, 1.0);
    }
    assert_int_equal(vbl_bn_split_photons(&f, h, 4 * n), VBL_SUCCESS);
    assert_int_equal(f.lost_hits, 0);
    vbl_bn_emission e;
    assert_int_equal(vbl_bn_emission_from_field(&f, materials, 3, &e), VBL_SUCCESS);
    /* Lambert single value: P = E albedo exactly, I = E albedo / pi cos */
    assert_true(fabs(e.power[0].x - (double)n * 0.8) < 1e-9 * n);
    vbl_vec3 w = vbl_v3_normalize(vbl_v3(0.5, 0.1, 0.7));
    vbl_vec3 i0 = vbl_bn_emission_intensity(&e, 0, w), i1 = vbl_bn_emission_intensity(&e, 1, w);
    double expect = (double)n * 0.8 / VBL_PI * vbl_v3_dot(w, l[0].normal);
    assert_true(fabs(i0.x - expect) < 1e-9 * expect);
    printf("Lambert through the 16x16 map: P %.2f vs %.2f (single value), I(w) %.3f vs %.3f\n", e.power[1].x,
           e.power[0].x, i1.x, i0.x);
    assert_true(fabs(e.power[1].x / e.power[0].x - 1.0) < 0.02);
    assert_true(fabs(i1.x / i0.x - 1.0) < 1e-9); /* J is constant over cells: exact up to rounding */
    /* below the surface: nothing */
    vbl_vec3 below = vbl_v3_scale(l[2].normal, -1.0);
    assert_true(vbl_bn_emission_intensity(&e, 2, below).x == 0.0);
    /* Phong / GGX never emit more than arrives (albedo <= 1), allowing 3% quadrature error */
    for (int i = 2; i < 4; ++i) {
        printf("light %d (%s): P / E = (%.3f, %.3f, %.3f)\n", i, i == 2 ? "Phong" : "GGX", e.power[i].x / n,
               e.power[i].y / n, e.power[i].z / n);
        assert_true(e.power[i].x > 0.1 * n && e.power[i].x < 1.03 * n);
        assert_true(e.power[i].y < 1.03 * n && e.power[i].z < 1.03 * n);
    }
    /* no NaN anywhere */
    for (size_t k = 0; k < e.offset[4]; ++k) assert_true(isfinite(e.values[k].x + e.values[k].y + e.values[k].z));

    /* export to the renderer's store: per-cell entries whose emission sums to the profile */
    vbl_surface_vsl_store store;
    vbl_surface_vsl_store_init(&store, materials, 3);
    size_t added = 0;
    assert_int_equal(vbl_bn_export_vsls(&f, &store, &added), VBL_SUCCESS);
    assert_int_equal(added, store.count);
    vbl_vec3 sum = vbl_v3(0, 0, 0);
    for (size_t k = 0; k < store.count; ++k) sum = vbl_v3_add(sum, store.vsls[k].power);
    vbl_vec3 stored = vbl_bn_field_stored_power(&f);
    assert_true(fabs(sum.y - stored.y) < 1e-9 * stored.y);
    printf("export: %zu store entries for 4 lights\n", store.count);
    for (int li = 1; li < 4; ++li) {
        /* at a cell's representative outgoing direction the store entries reproduce I exactly */
        int cell = 5 * 16 + 9;
        vbl_vec3 wo = vbl_bn_to_world(l[li].normal, f.table.direction[cell]);
        vbl_vec3 I = vbl_bn_emission_intensity(&e, (size_t)li, wo), S = vbl_v3(0, 0, 0);
        for (size_t k = 0; k < store.count; ++k) {
            const vbl_surface_vsl* v = &store.vsls[k];
            if (vbl_v3_length(vbl_v3_sub(v->position, l[li].position)) > 0.0) continue;
            vbl_vec3 fr = vbl_material_eval(&materials[v->material], v->normal, wo, v->incident);
            S = vbl_v3_add(S, vbl_v3_scale(vbl_v3_mul(v->power, fr), vbl_v3_dot(v->normal, wo)));
        }
        assert_true(I.x > 0.0);
        assert_true(fabs(S.x / I.x - 1.0) < 1e-6);
    }
    vbl_surface_vsl_store_free(&store);
    assert_true(vbl_bn_median_radius(l, 4) == 0.5);
    vbl_bn_emission_free(&e);
    l[2].material = 7;
    assert_int_equal(vbl_bn_emission_from_field(&f, materials, 3, &e), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "lights[2].material"));
    vbl_bn_field_free(&f);
    free(h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_energy_conservation_and_partition),
        cmocka_unit_test(test_emission_conversion),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
