/* Blue noise foundations: k-d tree m-nearest / radius queries against brute force (with ties),
 * octahedral map round trips, exact cell solid angles (sum 4 pi, and each against the
 * fraction of uniformly drawn directions falling into the cell). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "transport/surface/blue_noise/kd_tree.h"
#include "transport/surface/blue_noise/octahedral.h"
#include "core/rng.h"
#include "vbl/vbl.h"

typedef struct pair { double d2; size_t i; } pair;

static int cmp_pair(const void* a, const void* b)
{
    const pair *x = a, *y = b;
    if (x->d2 != y->d2) return x->d2 < y->d2 ? -1 : 1;
    return (x->i > y->i) - (x->i < y->i);
}

static vbl_vec3 random_point(vbl_rng* r, int lattice)
{
    if (lattice) /* many exact distance ties */
        return vbl_v3(floor(8.0 * vbl_rng_uniform(r)), floor(8.0 * vbl_rng_uniform(r)), floor(3.0 * vbl_rng_uniform(r)));
    return vbl_v3(vbl_rng_uniform(r), vbl_rng_uniform(r), 0.3 * vbl_rng_uniform(r));
}

typedef struct collect { size_t* idx; size_t n; } collect;
static void collect_visit(void* ctx, size_t i, double d2)
{
    (void)d2;
    collect* c = ctx;
    c->idx[c->n++] = i;
}
static int cmp_size(const void* a, const void* b)
{
    size_t x = *(const size_t*)a, y = *(const size_t*)b;
    return (x > y) - (x < y);
}

static void test_kdtree_matches_brute_force(void** state)
{
    (void)state;
    for (int lattice = 0; lattice < 2; ++lattice) {
        const size_t n = 1500;
        vbl_vec3* p = malloc(n * sizeof *p);
        vbl_rng rng = vbl_rng_make(5, (uint64_t)lattice, 0);
        for (size_t i = 0; i < n; ++i) p[i] = random_point(&rng, lattice);
        vbl_bn_kdtree t;
        assert_int_equal(vbl_bn_kdtree_build(&t, p, NULL, n), VBL_SUCCESS);
        pair* all = malloc(n * sizeof *all);
        size_t idx[64], got[2000];
        double d2[64];
        for (int q = 0; q < 200; ++q) {
            vbl_vec3 qp = q % 2 ? p[(size_t)q * 7 % n] : random_point(&rng, lattice);
            size_t exclude = q % 2 ? (size_t)q * 7 % n : (size_t)-1;
            size_t m = 1 + (size_t)q % 64;
            size_t nb = 0;
            for (size_t i = 0; i < n; ++i) {
                if (i == exclude) continue;
                vbl_vec3 d = vbl_v3_sub(qp, p[i]);
                all[nb].d2 = vbl_v3_dot(d, d);
                all[nb++].i = i;
            }
            qsort(all, nb, sizeof *all, cmp_pair);
            size_t found = vbl_bn_kdtree_nearest(&t, qp, m, exclude, idx, d2);
            assert_int_equal(found, m);
            for (size_t k = 0; k < m; ++k) {
                assert_int_equal(idx[k], all[k].i);
                assert_true(d2[k] == all[k].d2);
            }
            /* radius query: exactly the points with d < r */
            double r = lattice ? 1.0 + (q % 3) : 0.02 + 0.1 * (q % 5);
            collect c = {got, 0};
            vbl_bn_kdtree_within(&t, qp, r, collect_visit, &c);
            size_t expect = 0;
            for (size_t k = 0; k < nb; ++k) expect += all[k].d2 < r * r;
            if (exclude != (size_t)-1) expect += 1; /* the query point itself (d = 0) */
            assert_int_equal(c.n, expect);
            qsort(got, c.n, sizeof(size_t), cmp_size);
            for (size_t k = 1; k < c.n; ++k) assert_true(got[k] > got[k - 1]);
        }
        /* subset build */
        size_t subset[100];
        for (size_t i = 0; i < 100; ++i) subset[i] = 3 * i;
        vbl_bn_kdtree ts;
        assert_int_equal(vbl_bn_kdtree_build(&ts, p, subset, 100), VBL_SUCCESS);
        size_t one;
        assert_int_equal(vbl_bn_kdtree_nearest(&ts, p[4], 1, (size_t)-1, &one, NULL), 1);
        assert_true(one % 3 == 0);
        vbl_bn_kdtree_free(&ts);
        vbl_bn_kdtree_free(&t);
        free(all);
        free(p);
    }
}

/* Sphere queries with per-point radii (vbl_bn_kdtree_set_radii): the points whose sphere
 * contains q, filtered by the caller as the light code does, equal brute force and come in the
 * same order as the plain max-radius query; radii spanning two decades (the pruning's case). */
typedef struct sphere_collect { const vbl_vec3* p; const double* r; vbl_vec3 q; size_t* idx; size_t n; size_t visits; } sphere_collect;
static void sphere_visit(void* ctx, size_t i, double d2)
{
    sphere_collect* c = ctx;
    ++c->visits;
    if (d2 <= c->r[i] * c->r[i]) c->idx[c->n++] = i;
}

static void test_kdtree_sphere_queries(void** state)
{
    (void)state;
    const size_t n = 4000;
    vbl_vec3* p = malloc(n * sizeof *p);
    double* r = malloc(n * sizeof *r);
    vbl_rng rng = vbl_rng_make(9, 0, 0);
    double rmax = 0.0;
    for (size_t i = 0; i < n; ++i) {
        p[i] = random_point(&rng, 0);
        r[i] = 0.002 * pow(100.0, vbl_rng_uniform(&rng)); /* 0.002 .. 0.2 */
        if (r[i] > rmax) rmax = r[i];
    }
    vbl_bn_kdtree plain, bounded;
    assert_int_equal(vbl_bn_kdtree_build(&plain, p, NULL, n), VBL_SUCCESS);
    assert_int_equal(vbl_bn_kdtree_build(&bounded, p, NULL, n), VBL_SUCCESS);
    assert_int_equal(vbl_bn_kdtree_set_radii(&bounded, r), VBL_SUCCESS);
    size_t* a = malloc(n * sizeof *a);
    size_t* b = malloc(n * sizeof *b);
    size_t visits_plain = 0, visits_bounded = 0, total = 0;
    for (int q = 0; q < 500; ++q) {
        vbl_vec3 qp = random_point(&rng, 0);
        sphere_collect ca = {p, r, qp, a, 0, 0}, cb = {p, r, qp, b, 0, 0};
        vbl_bn_kdtree_within(&plain, qp, rmax * (1.0 + 1e-12), sphere_visit, &ca);
        vbl_bn_kdtree_within(&bounded, qp, rmax * (1.0 + 1e-12), sphere_visit, &cb);
        size_t expect = 0;
        for (size_t i = 0; i < n; ++i) {
            vbl_vec3 d = vbl_v3_sub(qp, p[i]);
            expect += vbl_v3_dot(d, d) <= r[i] * r[i];
        }
        assert_int_equal(ca.n, expect);
        assert_int_equal(cb.n, expect);
        for (size_t k = 0; k < ca.n; ++k) assert_int_equal(a[k], b[k]); /* same points, same order */
        visits_plain += ca.visits;
        visits_bounded += cb.visits;
        total += expect;
    }
    printf("sphere queries: %zu hits, %zu visits with the max radius, %zu with subtree radii\n", total, visits_plain,
           visits_bounded);
    assert_true(visits_bounded < visits_plain);
    vbl_bn_kdtree_free(&plain);
    vbl_bn_kdtree_free(&bounded);
    free(a);
    free(b);
    free(r);
    free(p);
}

static vbl_vec3 uniform_direction(vbl_rng* r)
{
    double z = 1.0 - 2.0 * vbl_rng_uniform(r), phi = 2.0 * VBL_PI * vbl_rng_uniform(r);
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return vbl_v3(s * cos(phi), s * sin(phi), z);
}

static void test_octahedral_round_trip(void** state)
{
    (void)state;
    vbl_rng rng = vbl_rng_make(9, 0, 0);
    double worst = 0.0;
    for (int i = 0; i < 100000; ++i) {
        vbl_vec3 d = uniform_direction(&rng);
        double u, v;
        vbl_oct_encode(d, &u, &v);
        assert_true(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0);
        vbl_vec3 e = vbl_oct_decode(u, v);
        worst = fmax(worst, vbl_v3_length(vbl_v3_sub(d, e)));
    }
    printf("octahedral round trip: max |d - decode(encode(d))| = %.3g\n", worst);
    assert_true(worst < 1e-12);
    /* axes and the poles */
    vbl_vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int k = 0; k < 6; ++k) {
        double u, v;
        vbl_oct_encode(axes[k], &u, &v);
        assert_true(vbl_v3_length(vbl_v3_sub(vbl_oct_decode(u, v), axes[k])) < 1e-12);
    }
    for (int res = 2; res <= 32; res += 2)
        for (int c = 0; c < res * res; ++c) assert_int_equal(vbl_oct_cell(vbl_oct_cell_center(c, res), res), c);
}

static void test_octahedral_solid_angles(void** state)
{
    (void)state;
    const int resolutions[3] = {2, 16, 32};
    for (int r = 0; r < 3; ++r) {
        vbl_oct_table t;
        assert_int_equal(vbl_oct_table_init(&t, resolutions[r]), VBL_SUCCESS);
        double sum = 0.0, upper = 0.0, lo = INFINITY, hi = 0.0;
        int cells = t.resolution * t.resolution;
        for (int c = 0; c < cells; ++c) {
            assert_true(t.solid_angle[c] > 0.0);
            assert_true(t.upper[c] >= 0.0 && t.upper[c] <= t.solid_angle[c] * (1.0 + 1e-12));
            sum += t.solid_angle[c];
            upper += t.upper[c];
            lo = fmin(lo, t.solid_angle[c]);
            hi = fmax(hi, t.solid_angle[c]);
            /* representative direction: unit, inside the cell, above the horizon when the cell reaches it */
            assert_true(fabs(vbl_v3_length(t.direction[c]) - 1.0) < 1e-12);
            assert_int_equal(vbl_oct_cell(t.direction[c], t.resolution), c);
            if (t.upper[c] > 0.0) assert_true(t.direction[c].z > 0.0);
        }
        printf("octahedral %dx%d: sum of solid angles - 4 pi = %.3g, upper - 2 pi = %.3g, cell max/min = %.3f\n",
               t.resolution, t.resolution, sum - 4.0 * VBL_PI, upper - 2.0 * VBL_PI, hi / lo);
        assert_true(fabs(sum - 4.0 * VBL_PI) < 1e-10);
        assert_true(fabs(upper - 2.0 * VBL_PI) < 1e-10);
        vbl_oct_table_free(&t);
    }
    /* each 16x16 cell's solid angle against uniformly drawn directions (within 5 sigma) */
    vbl_oct_table t;
    assert_int_equal(vbl_oct_table_init(&t, 16), VBL_SUCCESS);
    const int n = 1000000;
    int* count = calloc(256, sizeof(int));
    vbl_rng rng = vbl_rng_make(10, 0, 0);
    for (int i = 0; i < n; ++i) ++count[vbl_oct_cell(uniform_direction(&rng), 16)];
    double worst = 0.0;
    for (int c = 0; c < 256; ++c) {
        double p = t.solid_angle[c] / (4.0 * VBL_PI), mean = n * p, sd = sqrt(n * p * (1.0 - p));
        worst = fmax(worst, fabs(count[c] - mean) / sd);
    }
    printf("octahedral 16x16: worst cell count deviation %.2f sigma (1e6 directions)\n", worst);
    assert_true(worst < 5.0);
    free(count);
    vbl_oct_table_free(&t);
    assert_int_equal(vbl_oct_table_init(&t, 15), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "res = 15"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kdtree_matches_brute_force),
        cmocka_unit_test(test_kdtree_sphere_queries),
        cmocka_unit_test(test_octahedral_round_trip),
        cmocka_unit_test(test_octahedral_solid_angles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
