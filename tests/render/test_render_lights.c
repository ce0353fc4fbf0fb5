/* Light sampling: pdfs integrate to 1 and agree between sampling and evaluation; light-sampling
 * estimates of irradiance match closed forms (quad: Lambert's polygon formula; environment:
 * pi L); spot falloff. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>

#include "chi2.h"
#include "core/rng.h"
#include "sampling/sphere.h"
#include "scene/lights.h"

static vbl_light make_quad(void)
{
    vbl_light q = {0};
    q.type = VBL_LIGHT_QUAD;
    q.corner = vbl_v3(-0.5, -0.3, 2.0);
    q.edge1 = vbl_v3(1.0, 0.0, 0.2);
    q.edge2 = vbl_v3(0.1, 0.8, 0.0);
    vbl_vec3 n = vbl_v3_cross(q.edge1, q.edge2);
    q.area = vbl_v3_length(n);
    q.normal = vbl_v3_scale(n, 1.0 / q.area);
    /* emit downward, toward the origin */
    if (q.normal.z > 0) {
        vbl_vec3 t = q.edge1;
        q.edge1 = q.edge2;
        q.edge2 = t;
        q.normal = vbl_v3_scale(q.normal, -1.0);
    }
    q.color = vbl_v3(2.0, 2.0, 2.0);
    return q;
}

/* Irradiance on a plane with normal n at p from a uniformly emitting polygon (Lambert):
 * E = L/2 * sum_i theta_i (n . unit(v_i x v_{i+1})), v_i unit vectors to the vertices. */
static double polygon_irradiance(const vbl_vec3* verts, int count, vbl_vec3 p, vbl_vec3 n, double L)
{
    double sum = 0.0;
    for (int i = 0; i < count; ++i) {
        vbl_vec3 a = vbl_v3_normalize(vbl_v3_sub(verts[i], p));
        vbl_vec3 b = vbl_v3_normalize(vbl_v3_sub(verts[(i + 1) % count], p));
        double theta = acos(vbl_clamp(vbl_v3_dot(a, b), -1.0, 1.0));
        sum += theta * vbl_v3_dot(n, vbl_v3_normalize(vbl_v3_cross(a, b)));
    }
    return 0.5 * L * fabs(sum);
}

static void test_quad_pdf_consistency(void** state)
{
    (void)state;
    vbl_light q = make_quad();
    vbl_vec3 p = vbl_v3(0.1, 0.2, 0.0);
    vbl_rng rng = vbl_rng_make(1, 2, 3);
    /* sampled directions: the evaluated pdf equals the sampled one */
    for (int i = 0; i < 10000; ++i) {
        vbl_light_sample s;
        assert_true(vbl_light_sample_incident(&q, p, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &s));
        double pdf = vbl_light_pdf(&q, p, s.wi);
        assert_true(fabs(pdf - s.pdf) <= 1e-9 * s.pdf);
    }
    /* the solid-angle pdf integrates to 1 over the sphere (uniform-sphere estimate) */
    vbl_mean_acc acc = {0};
    for (int i = 0; i < 400000; ++i) {
        double pdf_u;
        vbl_vec3 w = vbl_sample_uniform_sphere(vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &pdf_u);
        vbl_mean_add(&acc, vbl_light_pdf(&q, p, w) / pdf_u);
    }
    assert_true(vbl_mean_check("quad pdf integral", &acc, 1.0, 4.0, 0.0));
    /* behind the emitter: no light */
    vbl_light_sample s;
    assert_false(vbl_light_sample_incident(&q, vbl_v3(0.0, 0.0, 5.0), 0.5, 0.5, &s));
}

static void test_quad_irradiance(void** state)
{
    (void)state;
    vbl_light q = make_quad();
    vbl_vec3 verts[4] = {q.corner, vbl_v3_add(q.corner, q.edge1), vbl_v3_add(vbl_v3_add(q.corner, q.edge1), q.edge2),
                         vbl_v3_add(q.corner, q.edge2)};
    vbl_vec3 points[3] = {vbl_v3(0.0, 0.0, 0.0), vbl_v3(1.5, -1.0, 0.5), vbl_v3(0.2, 0.1, 1.6)};
    vbl_vec3 n = vbl_v3(0.0, 0.0, 1.0);
    for (int k = 0; k < 3; ++k) {
        vbl_rng rng = vbl_rng_make(7, k, 0);
        vbl_mean_acc acc = {0};
        for (int i = 0; i < 200000; ++i) {
            vbl_light_sample s;
            double v = 0.0;
            if (vbl_light_sample_incident(&q, points[k], vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &s))
                v = s.li.x * fmax(0.0, vbl_v3_dot(s.wi, n)) / s.pdf;
            vbl_mean_add(&acc, v);
        }
        double ref = polygon_irradiance(verts, 4, points[k], n, q.color.x);
        char label[64];
        snprintf(label, sizeof label, "quad irradiance point %d (ref %.6f)", k, ref);
        assert_true(vbl_mean_check(label, &acc, ref, 4.0, 0.0));
    }
}

static void test_environment(void** state)
{
    (void)state;
    vbl_light env = {0};
    env.type = VBL_LIGHT_ENVIRONMENT;
    env.color = vbl_v3(0.5, 0.5, 0.5);
    vbl_rng rng = vbl_rng_make(3, 0, 0);
    vbl_mean_acc acc = {0};
    vbl_vec3 n = vbl_v3_normalize(vbl_v3(1.0, 2.0, -0.5));
    for (int i = 0; i < 200000; ++i) {
        vbl_light_sample s;
        assert_true(vbl_light_sample_incident(&env, vbl_v3(0, 0, 0), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &s));
        assert_true(fabs(vbl_light_pdf(&env, vbl_v3(0, 0, 0), s.wi) - s.pdf) < 1e-12);
        assert_true(isinf(s.distance));
        vbl_mean_add(&acc, s.li.x * fmax(0.0, vbl_v3_dot(s.wi, n)) / s.pdf);
    }
    assert_true(vbl_mean_check("environment irradiance = pi L", &acc, VBL_PI * 0.5, 4.0, 0.0));
}

static void test_delta_lights(void** state)
{
    (void)state;
    vbl_light spot = {0};
    spot.type = VBL_LIGHT_SPOT;
    spot.position = vbl_v3(0, 0, 2);
    spot.direction = vbl_v3(0, 0, -1);
    spot.color = vbl_v3(4, 4, 4);
    spot.cos_inner = cos(10.0 * VBL_PI / 180.0);
    spot.cos_outer = cos(20.0 * VBL_PI / 180.0);
    vbl_light_sample s;
    assert_true(vbl_light_sample_incident(&spot, vbl_v3(0, 0, 0), 0.3, 0.3, &s));
    assert_true(s.is_delta && fabs(s.li.x - 1.0) < 1e-12 && fabs(s.wi.z - 1.0) < 1e-12 && fabs(s.distance - 2.0) < 1e-12);
    /* outside the outer cone: nothing; halfway between the cones in cos: smoothstep(0.5) = 0.5 */
    assert_false(vbl_light_sample_incident(&spot, vbl_v3(2, 0, 0), 0.3, 0.3, &s));
    double c = 0.5 * (spot.cos_inner + spot.cos_outer);
    assert_true(fabs(vbl_spot_falloff(&spot, c) - 0.5) < 1e-12);
    assert_true(vbl_spot_falloff(&spot, 1.0) == 1.0 && vbl_spot_falloff(&spot, 0.0) == 0.0);
    vbl_light sun = {0};
    sun.type = VBL_LIGHT_DISTANT;
    sun.direction = vbl_v3(0, 0, -1);
    sun.color = vbl_v3(3, 3, 3);
    assert_true(vbl_light_sample_incident(&sun, vbl_v3(1, 2, 3), 0.1, 0.9, &s));
    assert_true(s.wi.z == 1.0 && s.li.x == 3.0 && isinf(s.distance) && vbl_light_pdf(&sun, vbl_v3(0, 0, 0), s.wi) == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quad_pdf_consistency),
        cmocka_unit_test(test_quad_irradiance),
        cmocka_unit_test(test_environment),
        cmocka_unit_test(test_delta_lights),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
