/* Photon-light shading (gather.h): the MIS pair of power-based light sampling and BSDF sampling
 * with the eq 9 weight agrees with an independent estimate of the same integral
 * int f cos w_v L_v dw by uniform hemisphere sampling (means within 4 combined standard errors),
 * both strategies contribute, no NaN. Two analytic planes (floor, wall) and lights on both.
 * The same for a medium point (material NULL): int f_medium w_v T L_v dw over the sphere, with an
 * HG value lobe (g 0.4), a different HG sampling lobe (g 0.2) and a transmittance callback. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "transport/surface/blue_noise/gather.h"
#include "core/rng.h"
#include "sampling/phase_hg.h"
#include "vbl/vbl.h"

/* floor z = 0 (|x|, |y| <= 2, normal +z) and wall y = 1 (|x| <= 2, 0 <= z <= 2, normal -y) */
static int trace_planes(void* ctx, vbl_vec3 o, vbl_vec3 d, vbl_vec3* p, vbl_vec3* n)
{
    (void)ctx;
    double best = INFINITY;
    if (d.z < 0.0) {
        double t = -o.z / d.z;
        vbl_vec3 q = vbl_v3_madd(o, d, t);
        if (t > 1e-9 && fabs(q.x) <= 2.0 && fabs(q.y) <= 2.0 && t < best) {
            best = t;
            *p = q;
            *n = vbl_v3(0, 0, 1);
        }
    }
    if (d.y > 0.0) {
        double t = (1.0 - o.y) / d.y;
        vbl_vec3 q = vbl_v3_madd(o, d, t);
        if (t > 1e-9 && fabs(q.x) <= 2.0 && q.z >= 0.0 && q.z <= 2.0 && t < best) {
            best = t;
            *p = q;
            *n = vbl_v3(0, -1, 0);
        }
    }
    return isfinite(best);
}

static const vbl_material mats[2] = {
    {VBL_MATERIAL_LAMBERT, {0.7, 0.6, 0.5}, {0, 0, 0}, 0.0, 0.0},
    {VBL_MATERIAL_PHONG, {0.3, 0.3, 0.3}, {0.5, 0.5, 0.5}, 40.0, 0.0},
};

static vbl_vec3 hemisphere(vbl_rng* r, vbl_vec3 n, double* pdf)
{
    double z = vbl_rng_uniform(r), phi = 2.0 * VBL_PI * vbl_rng_uniform(r), s = sqrt(fmax(0.0, 1.0 - z * z));
    vbl_vec3 t, b;
    vbl_v3_basis(n, &t, &b);
    if (pdf) *pdf = 1.0 / (2.0 * VBL_PI);
    return vbl_v3_normalize(
        vbl_v3_add(vbl_v3_add(vbl_v3_scale(t, s * cos(phi)), vbl_v3_scale(b, s * sin(phi))), vbl_v3_scale(n, z)));
}

typedef struct ref_ctx { const vbl_bn_light_set* s; const vbl_bn_emission* e; vbl_vec3 w; vbl_vec3 sum; } ref_ctx;
static void ref_visit(void* ctx, size_t i, double d2)
{
    (void)d2;
    ref_ctx* c = ctx;
    c->sum = vbl_v3_add(c->sum, vbl_bn_emission_intensity(c->e, i, vbl_v3_scale(c->w, -1.0)));
}

static vbl_vec3 sphere_direction(vbl_rng* r, double* pdf)
{
    double z = 1.0 - 2.0 * vbl_rng_uniform(r), phi = 2.0 * VBL_PI * vbl_rng_uniform(r), s = sqrt(fmax(0.0, 1.0 - z * z));
    *pdf = 1.0 / (4.0 * VBL_PI);
    return vbl_v3(s * cos(phi), s * sin(phi), z);
}

/* the medium point's value lobe and transmittance (exp(-0.5 d)) */
static vbl_vec3 medium_f(void* ctx, double cos_theta)
{
    (void)ctx;
    return vbl_v3_scale(vbl_v3(0.8, 0.7, 0.6), vbl_hg_eval(0.4, cos_theta));
}
static double medium_transmittance(void* ctx, vbl_vec3 a, vbl_vec3 b)
{
    (void)ctx;
    return exp(-0.5 * vbl_v3_length(vbl_v3_sub(b, a)));
}

/* f (times cos at surfaces), its sampling pdf, the transmittance and the sampling domain of sp */
static vbl_vec3 scatter_value(const vbl_bn_shading* sp, vbl_vec3 w)
{
    if (!sp->material)
        return sp->medium_f(sp->medium_ctx, -vbl_v3_dot(w, sp->wo));
    return vbl_v3_scale(vbl_material_eval(sp->material, sp->normal, sp->wo, w), vbl_v3_dot(sp->normal, w));
}
static double scatter_pdf(const vbl_bn_shading* sp, vbl_vec3 w)
{
    return sp->material ? vbl_material_pdf(sp->material, sp->normal, sp->wo, w) : vbl_hg_pdf(sp->phase_g, -vbl_v3_dot(w, sp->wo));
}

static void check_gather(const vbl_bn_light_set* s, const vbl_bn_emission* e, const vbl_bn_shading* sp,
                         const char* label)
{
    const double n_min = VBL_BN_N_MIN_DEFAULT, n_max = VBL_BN_N_MAX_DEFAULT;
    /* the estimator */
    const int K = 200000;
    double sum = 0.0, sum2 = 0.0, light = 0.0, bsdf = 0.0, partial = 0.0;
    for (int k = 0; k < K; ++k) {
        vbl_rng g = vbl_rng_make(41, 0, (uint64_t)k);
        double u[6];
        for (int i = 0; i < 6; ++i) u[i] = vbl_rng_uniform(&g);
        vbl_bn_gather_result res;
        vbl_bn_gather(s, e, sp, trace_planes, NULL, u, n_min, n_max, &res);
        assert_true(isfinite(res.L.x + res.L.y + res.L.z));
        assert_true(res.w_v >= 0.0 && res.w_v <= 1.0);
        if (res.bsdf_hit && res.lights_at_hit == 0) assert_true(res.w_v == 0.0);
        sum += res.L.x;
        sum2 += res.L.x * res.L.x;
        light += res.L_light.x;
        bsdf += res.L_bsdf.x;
        partial += res.w_v > 0.0 && res.w_v < 1.0;
    }
    double mean = sum / K, se = sqrt(fmax(0.0, sum2 / K - mean * mean) / K);

    /* reference: uniform hemisphere (surface) or sphere (medium) directions, the same integrand */
    const int R = 1000000;
    double rs = 0.0, rs2 = 0.0;
    vbl_rng g = vbl_rng_make(43, 0, 0);
    for (int k = 0; k < R; ++k) {
        double pdf;
        vbl_vec3 w = sp->material ? hemisphere(&g, sp->normal, &pdf) : sphere_direction(&g, &pdf);
        vbl_vec3 y = {0, 0, 0}, ny = {0, 0, 1};
        double v = 0.0;
        if (trace_planes(NULL, sp->position, w, &y, &ny)) {
            ref_ctx c = {s, e, w, {0, 0, 0}};
            vbl_bn_lights_containing(s, y, ref_visit, &c);
            if (c.sum.x > 0.0) {
                vbl_vec3 xy = vbl_v3_sub(y, sp->position);
                double w_v = vbl_bn_virtual_light_weight(vbl_v3_dot(xy, xy), scatter_pdf(sp, w), vbl_v3_dot(ny, w),
                                                         vbl_bn_density_at(s, y, NULL), n_min, n_max);
                double T = sp->transmittance ? sp->transmittance(sp->transmittance_ctx, sp->position, y) : 1.0;
                v = scatter_value(sp, w).x * c.sum.x * T * w_v / pdf;
            }
        }
        rs += v;
        rs2 += v * v;
    }
    double rmean = rs / R, rse = sqrt(fmax(0.0, rs2 / R - rmean * rmean) / R);
    double z = (mean - rmean) / sqrt(se * se + rse * rse);
    printf("gather (%s): MIS %.5f +- %.5f (light %.5f, BSDF %.5f; w_v in (0,1) for %.1f%% of BSDF samples), "
           "reference %.5f +- %.5f, z = %.2f\n",
           label, mean, se, light / K, bsdf / K, 100.0 * partial / K, rmean, rse, z);
    assert_true(fabs(z) < 4.0);
    assert_true(light > 0.05 * sum && bsdf > 0.05 * sum);
    assert_true(partial > 0.0);
}

static void test_gather_matches_reference(void** state)
{
    (void)state;
    vbl_bn_light l[64];
    size_t nl = 0;
    for (int i = 0; i < 7; ++i)
        for (int k = 0; k < 4; ++k) { /* wall */
            l[nl].position = vbl_v3(-0.9 + 0.3 * i, 1.0, 0.15 + 0.3 * k);
            l[nl].normal = vbl_v3(0, -1, 0);
            l[nl].radius = 0.25;
            l[nl].material = (int)(nl % 2);
            l[nl].diffuse = l[nl].material == 0;
            ++nl;
        }
    for (int i = 0; i < 5; ++i)
        for (int k = 0; k < 2; ++k) { /* floor, in front of the wall */
            l[nl].position = vbl_v3(-0.8 + 0.4 * i, 0.55 + 0.3 * k, 0.0);
            l[nl].normal = vbl_v3(0, 0, 1);
            l[nl].radius = 0.3;
            l[nl].material = (int)(nl % 2);
            l[nl].diffuse = l[nl].material == 0;
            ++nl;
        }
    /* incident fields from synthetic photons: unit power per light, random directions */
    vbl_bn_incident_field f;
    assert_int_equal(vbl_bn_field_init(&f, l, nl, 16), VBL_SUCCESS);
    vbl_rng r = vbl_rng_make(31, 0, 0);
    for (size_t i = 0; i < nl; ++i)
        for (int k = 0; k < 50; ++k) {
            vbl_bn_photon_hit h = {l[i].position, l[i].normal, hemisphere(&r, l[i].normal, NULL), {0.02, 0.02, 0.02}};
            assert_int_equal(vbl_bn_split_photons(&f, &h, 1), VBL_SUCCESS);
        }
    vbl_bn_emission e;
    assert_int_equal(vbl_bn_emission_from_field(&f, mats, 2, &e), VBL_SUCCESS);
    vbl_bn_light_set s;
    assert_int_equal(vbl_bn_light_set_init(&s, l, nl, e.power, 2.0), VBL_SUCCESS);

    vbl_bn_shading sp = {{0.1, 0.2, 0.0}, {0, 0, 1}, {0, 0, 1}, {0, 0, 0}, &mats[1], 1e-9, NULL, NULL, NULL, NULL, 0.0};
    sp.wo = vbl_v3_normalize(vbl_v3(0.2, -1.0, 0.7));
    check_gather(&s, &e, &sp, "surface point");
    vbl_bn_shading mp = {{0.1, 0.3, 0.6}, {0, 0, 1}, {0, 0, 1}, {0, 0, 0}, NULL, 0.0,
                         medium_transmittance, NULL, medium_f, NULL, 0.2};
    mp.wo = vbl_v3_normalize(vbl_v3(0.3, -1.0, 0.2));
    check_gather(&s, &e, &mp, "medium point");
    vbl_bn_light_set_free(&s);
    vbl_bn_emission_free(&e);
    vbl_bn_field_free(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gather_matches_reference),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
