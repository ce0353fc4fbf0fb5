/* Surface VSLs (surface_vsl.h): the store's validation; surface_from_surface (VBL section 3.4)
 * and volume_from_surface (section 3.3) against brute-force quadrature (R == 0 exactly, R > 0
 * mean within 4 standard errors); the R -> 0 / eq 11 convergence; extremes finite. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "quad.h"
#include "transport/common/radius_schedule.h"
#include "surface_test_util.h"
#include "transport/surface/surface_vsl.h"

static vbl_material g_mat[3];

static void setup_store(vbl_surface_vsl_store* st)
{
    for (int i = 0; i < 3; ++i) g_mat[i] = st_material(i);
    vbl_surface_vsl_store_init(st, g_mat, 3);
    const vbl_surface_vsl v[4] = {
        {{0.3, 0.2, 1.2}, {0.0, 0.0, -1.0}, {0.0, 0.6, -0.8}, {1.0, 0.8, 0.6}, 0, 1},
        {{-0.8, 0.1, 0.9}, {0.6, 0.0, -0.8}, {-0.28, 0.0, -0.96}, {0.5, 0.5, 0.5}, 1, 2},
        {{0.5, -0.6, 0.4}, {-0.48, 0.64, -0.6}, {0.0, 0.0, -1.0}, {0.7, 0.7, 0.9}, 2, 1},
        {{0.2, 9.0, 1.0}, {0.0, -1.0, 0.0}, {0.0, -1.0, 0.0}, {1.0, 1.0, 1.0}, 0, 1}, /* blocked (y > 5) */
    };
    for (int i = 0; i < 4; ++i) assert_int_equal(vbl_surface_vsl_store_add(st, &v[i]), VBL_SUCCESS);
}

/* T V: homogeneous sigma_t = 0.4, a wall blocks everything beyond y = 5. */
static double visibility(void* ctx, vbl_vec3 a, vbl_vec3 b)
{
    (void)ctx;
    if (a.y > 5.0 || b.y > 5.0) return 0.0;
    return exp(-0.4 * vbl_v3_length(vbl_v3_sub(a, b)));
}

static vbl_vec3 kWo(void) { return vbl_v3_normalize(vbl_v3(0.3, -0.2, 1.0)); }

static void test_store_validation(void** state)
{
    (void)state;
    vbl_surface_vsl_store st;
    setup_store(&st);
    assert_int_equal(st.count, 4);
    vbl_surface_vsl bad = st.vsls[0];
    bad.material = 3;
    assert_int_equal(vbl_surface_vsl_store_add(&st, &bad), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "material = 3"));
    bad = st.vsls[0];
    bad.power.y = NAN;
    assert_int_equal(vbl_surface_vsl_store_add(&st, &bad), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "power"));
    bad = st.vsls[0];
    bad.normal = vbl_v3(0, 0, 2);
    assert_int_equal(vbl_surface_vsl_store_add(&st, &bad), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "normal"));
    assert_int_equal(st.count, 4);
    vbl_surface_vsl_store_free(&st);
    assert_int_equal(st.count, 0);
}

/* Exact R == 0 value and its brute-force R > 0 counterpart, summed over the store. */
static double sfs_reference(const vbl_surface_point* sp, const vbl_surface_vsl_store* st, double radius)
{
    double s = 0.0;
    for (size_t i = 0; i < st->count; ++i) {
        const vbl_surface_vsl* v = &st->vsls[i];
        double t = visibility(NULL, v->position, sp->position);
        if (!(t > 0.0)) continue;
        vbl_surface_lobe a = vbl_surface_lobe_receiver(sp->material, sp->normal, sp->wo);
        vbl_surface_lobe b = vbl_surface_lobe_sender(&st->materials[v->material], v->normal, v->incident);
        if (radius > 0.0) {
            /* the brute force integrates mean(A B): exact for grey powers (the caller sets them) */
            double k = st_cone_reference(&a, &b, sp->position, v->position, radius);
            s += t * k * st_mean3(v->power);
        } else {
            vbl_vec3 d = vbl_v3_sub(sp->position, v->position);
            double w2 = vbl_v3_dot(d, d);
            vbl_vec3 om = vbl_v3_scale(d, 1.0 / sqrt(w2));
            vbl_vec3 f = vbl_v3_mul(vbl_surface_lobe_eval(&a, om), vbl_surface_lobe_eval(&b, om));
            s += t * st_mean3(vbl_v3_mul(v->power, f)) / w2;
        }
    }
    return s;
}

static void test_surface_from_surface(void** state)
{
    (void)state;
    vbl_surface_vsl_store st;
    setup_store(&st);
    /* grey powers so that mean(P K) = mean(P) mean(K) in the R > 0 brute force */
    for (size_t i = 0; i < st.count; ++i) st.vsls[i].power = vbl_v3(0.8, 0.8, 0.8);
    int ok = 1;
    for (int mi = 0; mi < 3; ++mi) {
        vbl_surface_point sp;
        vbl_surface_point_init(&sp, vbl_v3(0, 0, 0), vbl_v3(0, 0, 1), kWo(), &g_mat[mi]);
        vbl_rng rng = vbl_rng_make(9, (uint64_t)mi, 0);
        /* R == 0: the VPL sum, exactly */
        double exact = sfs_reference(&sp, &st, 0.0);
        double got = st_mean3(vbl_surface_from_surface(&sp, &st, 0.0, visibility, NULL, 8, &rng));
        printf("     surface_from_surface %s R=0: %.10g (reference %.10g)\n", st_material_name(mi), got, exact);
        assert_true(fabs(got - exact) <= 1e-12 * exact);
        for (int r = 0; r < 2; ++r) {
            double radius = r ? 1.0 : 0.25; /* 1.0: the third VSL (w = 0.88) is gathered over the hemisphere */
            double ref = sfs_reference(&sp, &st, radius);
            vbl_mean_acc acc = {0, 0, 0};
            for (int i = 0; i < 3000; ++i) {
                vbl_vec3 e = vbl_surface_from_surface(&sp, &st, radius, visibility, NULL, 4, &rng);
                assert_true(st_finite3(e) && st_nonneg3(e));
                vbl_mean_add(&acc, st_mean3(e));
            }
            char label[96];
            snprintf(label, sizeof label, "surface_from_surface %s R=%g", st_material_name(mi), radius);
            ok &= vbl_mean_check(label, &acc, ref, 4.0, 1e-5 * ref);
        }
        /* eq 11: the bias of the R_p gather against the VPL sum falls with the passes */
        double prev = INFINITY;
        printf("     eq 11 (R0 = 0.5): ");
        const uint64_t passes[3] = {0, 100, 10000};
        for (int k = 0; k < 3; ++k) {
            double radius = vbl_radius_at_pass(0.5, VBL_RADIUS_ALPHA_DEFAULT, 2, passes[k]);
            double err = fabs(sfs_reference(&sp, &st, radius) / exact - 1.0);
            printf(" pass %d R=%.4f err %.2e", (int)passes[k], radius, err);
            assert_true(err < prev);
            prev = err;
        }
        printf("\n");
    }
    assert_true(ok);
    vbl_surface_vsl_store_free(&st);
}

/* volume_from_surface: camera segment through homogeneous media. */
typedef struct cam_ctx {
    vbl_vec3 c_o, c_d;
    double g, radius;
    const vbl_surface_vsl* vsl;
    const vbl_material* vm;
    st_medium medium;
    int n;
} cam_ctx;

static double cam_integrand(double u, void* c)
{
    const cam_ctx* k = (const cam_ctx*)c;
    vbl_vec3 x = vbl_v3_madd(k->c_o, k->c_d, u);
    double m = st_medium_fn((void*)&k->medium, u, x, k->vsl->position);
    const double j[3] = {0.5, 0.5, 0.5};
    vbl_vec3 kr = vbl_surface_vsl_kernel_medium(x, k->c_d, k->g, k->vsl, k->vm, k->radius, k->n, j);
    return m * st_mean3(vbl_v3_mul(k->vsl->power, kr));
}

static double cam_reference(const cam_ctx* k, double u0, double u1)
{
    double b[4] = {u0, 0, 0, u1};
    int nb = 1;
    double tp = vbl_v3_dot(vbl_v3_sub(k->vsl->position, k->c_o), k->c_d);
    if (tp > u0 && tp < u1) b[nb++] = tp;
    double dn = vbl_v3_dot(k->c_d, k->vsl->normal);
    if (dn != 0.0) {
        double tc = -vbl_v3_dot(vbl_v3_sub(k->c_o, k->vsl->position), k->vsl->normal) / dn;
        if (tc > u0 && tc < u1) b[nb++] = tc;
    }
    b[nb++] = u1;
    if (nb == 4 && b[1] > b[2]) {
        double t = b[1];
        b[1] = b[2];
        b[2] = t;
    }
    double s = 0.0;
    for (int i = 0; i + 1 < nb; ++i) {
        if (k->radius > 0.0) {
            for (int p = 0; p < 12; ++p)
                s += vbl_quad_gl16(cam_integrand, (void*)k, b[i] + (b[i + 1] - b[i]) * p / 12,
                                   b[i] + (b[i + 1] - b[i]) * (p + 1) / 12);
        } else {
            s += vbl_quad_adaptive(cam_integrand, (void*)k, b[i], b[i + 1], 1e-13, 1e-9);
        }
    }
    return s;
}

static void test_volume_from_surface(void** state)
{
    (void)state;
    vbl_surface_vsl_store st;
    setup_store(&st);
    int ok = 1;
    /* camera ray passing below the VSLs (they face -z), through their lobes */
    vbl_vec3 c_o = vbl_v3(-3.0, 0.1, 0.2), c_d = vbl_v3_normalize(vbl_v3(1.0, 0.0, 0.05));
    double u0 = 0.5, u1 = 5.5;
    const double gs[3] = {0.5, -0.3, 0.0};
    for (int vi = 0; vi < 3; ++vi)
        for (int r = 0; r < 2; ++r) {
            const vbl_surface_vsl* vsl = &st.vsls[vi];
            cam_ctx k = {c_o, c_d, gs[vi], r ? 0.2 : 0.0, vsl, &g_mat[vsl->material], {0.6, 0.9}, 256};
            double ref = cam_reference(&k, u0, u1);
            vbl_mean_acc acc = {0, 0, 0};
            vbl_rng rng = vbl_rng_make(31, (uint64_t)vi, (uint64_t)r);
            for (int i = 0; i < (r ? 6000 : 20000); ++i) {
                double xi = vbl_rng_uniform(&rng);
                double j[3] = {vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng)};
                const vbl_segment cam = {c_o, c_d, u0, u1};
                const vbl_surface_kernel kern = {k.radius, 4, {j[0], j[1], j[2]}};
                const vbl_surface_camera_medium med = {st_medium_fn, &k.medium};
                vbl_vec3 e = vbl_volume_from_vsl(&cam, gs[vi], vsl, &g_mat[vsl->material], &kern, med, xi, NULL, NULL);
                assert_true(st_finite3(e) && st_nonneg3(e));
                vbl_mean_add(&acc, st_mean3(e));
            }
            char label[96];
            snprintf(label, sizeof label, "volume_from_surface %s g=%g R=%g", st_material_name(vsl->material), gs[vi],
                     k.radius);
            ok &= vbl_mean_check(label, &acc, ref, 4.0, (r ? 2e-3 : 1e-7) * ref);
            assert_true(ref > 0.0);
        }
    /* the store-wide sum is the sum of the per-VSL estimates (same random numbers) */
    vbl_rng a = vbl_rng_make(1, 2, 3), b = vbl_rng_make(1, 2, 3);
    st_medium med = {0.6, 0.9};
    const vbl_segment cam = {c_o, c_d, u0, u1};
    const vbl_surface_camera_medium cm = {st_medium_fn, &med};
    vbl_vec3 total = vbl_volume_from_surface(&cam, 0.4, &st, 0.1, cm, 8, &a);
    vbl_vec3 sum = vbl_v3(0, 0, 0);
    for (size_t i = 0; i < st.count; ++i) {
        double xi = vbl_rng_uniform(&b);
        double j[3] = {vbl_rng_uniform(&b), vbl_rng_uniform(&b), vbl_rng_uniform(&b)};
        const vbl_surface_kernel kern = {0.1, 8, {j[0], j[1], j[2]}};
        sum = vbl_v3_add(sum, vbl_volume_from_vsl(&cam, 0.4, &st.vsls[i], &g_mat[st.vsls[i].material], &kern, cm, xi,
                                                  NULL, NULL));
    }
    assert_true(fabs(total.x - sum.x) <= 1e-12 * fabs(sum.x) && fabs(total.z - sum.z) <= 1e-12 * fabs(sum.z));
    assert_true(ok);
    vbl_surface_vsl_store_free(&st);
}

static void test_extremes_finite(void** state)
{
    (void)state;
    vbl_surface_vsl_store st;
    setup_store(&st);
    st_medium med = {0.6, 0.9};
    const double radii[3] = {0.0, 1e-4, 0.3};
    for (size_t vi = 0; vi < 3; ++vi) {
        const vbl_surface_vsl* v = &st.vsls[vi];
        const vbl_material* vm = &g_mat[v->material];
        for (int ri = 0; ri < 3; ++ri) {
            vbl_rng rng = vbl_rng_make(17, vi, (uint64_t)ri);
            /* receiver at the VSL (w = 0), 1e-12 away, grazing */
            vbl_surface_point sp;
            vbl_surface_point_init(&sp, v->position, vbl_v3_scale(v->normal, -1.0), vbl_v3_scale(v->normal, -1.0), vm);
            for (int k = 0; k < 3; ++k) {
                vbl_vec3 off = k == 0 ? vbl_v3(0, 0, 0) : (k == 1 ? vbl_v3(1e-12, 0, 0) : vbl_v3(2.0, 0, 0));
                sp.position = vbl_v3_add(v->position, off);
                double j[3] = {0.3, 0.6, 0.9};
                vbl_vec3 e = vbl_surface_vsl_kernel_surface(&sp, v, vm, radii[ri], 16, j);
                assert_true(st_finite3(e) && st_nonneg3(e));
                e = vbl_surface_from_surface(&sp, &st, radii[ri], visibility, NULL, 8, &rng);
                assert_true(st_finite3(e) && st_nonneg3(e));
            }
            /* camera segment through the VSL, along its plane, g = +-0.999 */
            for (int gi = 0; gi < 2; ++gi)
                for (int c = 0; c < 2; ++c) {
                    vbl_vec3 d = c == 0 ? v->normal : vbl_v3_normalize(vbl_v3_cross(v->normal, vbl_v3(0.3, 1, 0.2)));
                    vbl_vec3 o = vbl_v3_madd(v->position, d, -1.0);
                    for (int i = 0; i < 40; ++i) {
                        double xi = i == 0 ? 0.0 : (i == 1 ? 1.0 - 1e-16 : vbl_rng_uniform(&rng));
                        double j[3] = {vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), vbl_rng_uniform(&rng)};
                        double pdf = -1.0;
                        const vbl_segment cam = {o, d, 0.0, 2.0};
                        const vbl_surface_kernel kern = {radii[ri], 8, {j[0], j[1], j[2]}};
                        const vbl_surface_camera_medium cm = {st_medium_fn, &med};
                        vbl_vec3 e = vbl_volume_from_vsl(&cam, gi ? -0.999 : 0.999, v, vm, &kern, cm, xi, NULL, &pdf);
                        assert_true(st_finite3(e) && st_nonneg3(e) && isfinite(pdf) && pdf >= 0.0);
                    }
                }
        }
    }
    vbl_surface_vsl_store_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_store_validation),
        cmocka_unit_test(test_surface_from_surface),
        cmocka_unit_test(test_volume_from_surface),
        cmocka_unit_test(test_extremes_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
