/* Adaptive sample elimination (Li et al. 2022, section 3.2): exactly N kept,
 * blue-noise property (nearest-neighbour distance relative to r_max far above the input's),
 * density variation preserved (cell counts after / before within tolerance of N / M), eq 2 on a
 * uniform set, the parallel box scheme close to the sequential one, same result on 1 and 2
 * threads, bad input. Fixed seeds. */
#include <math.h>
#include <omp.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "transport/surface/blue_noise/kd_tree.h"
#include "transport/surface/blue_noise/sample_elimination.h"
#include "core/rng.h"
#include "vbl/vbl.h"

/* Uniform on the unit square (z = 0), or density (1 + 4x) / 3 in x (inverse CDF). */
static vbl_vec3* make_points(size_t M, int graded, uint64_t seed)
{
    vbl_vec3* p = malloc(M * sizeof *p);
    vbl_rng r = vbl_rng_make(seed, 0, 0);
    for (size_t i = 0; i < M; ++i) {
        double u = vbl_rng_uniform(&r), v = vbl_rng_uniform(&r);
        double x = graded ? (-1.0 + sqrt(1.0 + 24.0 * u)) / 4.0 : u; /* CDF (x + 2x^2) / 3 */
        p[i] = vbl_v3(x, v, 0.0);
    }
    return p;
}

/* Min and mean over the set's members of (distance to the nearest other member) / r_max. */
static void nn_ratio(const vbl_vec3* p, const size_t* members, size_t n, const double* r, double* min_ratio,
                     double* mean_ratio)
{
    vbl_bn_kdtree t;
    assert_int_equal(vbl_bn_kdtree_build(&t, p, members, n), VBL_SUCCESS);
    double lo = INFINITY, sum = 0.0;
    for (size_t k = 0; k < n; ++k) {
        size_t i = members ? members[k] : k, j;
        double d2;
        assert_int_equal(vbl_bn_kdtree_nearest(&t, p[i], 1, i, &j, &d2), 1);
        double ratio = sqrt(d2) / r[i];
        lo = fmin(lo, ratio);
        sum += ratio;
    }
    *min_ratio = lo;
    *mean_ratio = sum / (double)n;
    vbl_bn_kdtree_free(&t);
}

static void run_r(const vbl_vec3* p, size_t M, size_t N, const double* r, const vbl_bn_elimination_options* o,
                  size_t* kept, vbl_bn_elimination_stats* st)
{
    assert_int_equal(vbl_bn_eliminate_with_rmax(p, M, N, r, o, kept, NULL, st), VBL_SUCCESS);
    for (size_t k = 1; k < N; ++k) assert_true(kept[k] > kept[k - 1]);
    assert_true(kept[N - 1] < M);
}

static void run(const vbl_vec3* p, size_t M, size_t N, const vbl_bn_elimination_options* o, size_t* kept,
                vbl_bn_elimination_stats* st)
{
    run_r(p, M, N, NULL, o, kept, st);
}

static void test_blue_noise_property(void** state)
{
    (void)state;
    for (int graded = 0; graded < 2; ++graded) {
        const size_t M = 10000, N = 1000;
        vbl_vec3* p = make_points(M, graded, 21 + (uint64_t)graded);
        double* r = malloc(M * sizeof(double));
        size_t* kept = malloc(N * sizeof(size_t));
        vbl_bn_elimination_options o = VBL_BN_ELIMINATION_DEFAULT;
        o.leaf_size = 500; /* 8 leaf boxes, then the root */
        assert_int_equal(vbl_bn_compute_rmax(p, M, N, &o, r), VBL_SUCCESS);
        vbl_bn_elimination_stats st;
        run_r(p, M, N, r, &o, kept, &st);
        assert_int_equal(st.levels, 1);
        assert_true(st.eliminated_before_root > (M - N) / 2); /* 0.8 of each box's excess */
        double min_before, mean_before, min_after, mean_after;
        nn_ratio(p, NULL, M, r, &min_before, &mean_before);
        nn_ratio(p, kept, N, r, &min_after, &mean_after);
        printf("%s input: nearest-neighbour distance / r_max: min %.3f -> %.3f, mean %.3f -> %.3f "
               "(%zu leaf boxes, %zu eliminated before the root)\n",
               graded ? "graded" : "uniform", min_before, min_after, mean_before, mean_after, st.leaf_boxes,
               st.eliminated_before_root);
        assert_true(min_after > 0.5);
        assert_true(min_after > 20.0 * min_before);
        assert_true(mean_after > 1.3);
        free(r);
        free(kept);
        free(p);
    }
}

static void test_density_preserved(void** state)
{
    (void)state;
    const size_t M = 20000, N = 2000;
    vbl_vec3* p = make_points(M, 1, 33);
    size_t* kept = malloc(N * sizeof(size_t));
    vbl_bn_elimination_options o = VBL_BN_ELIMINATION_DEFAULT;
    o.leaf_size = 1000;
    run(p, M, N, &o, kept, NULL);
    /* 4 strips in x: the density (1 + 4x) / 3 varies 5x over the square */
    size_t before[4] = {0}, after[4] = {0};
    for (size_t i = 0; i < M; ++i) ++before[(int)fmin(3.0, 4.0 * p[i].x)];
    for (size_t k = 0; k < N; ++k) ++after[(int)fmin(3.0, 4.0 * p[kept[k]].x)];
    double worst = 0.0;
    for (int s = 0; s < 4; ++s) {
        double ratio = (double)after[s] / (double)before[s] / ((double)N / (double)M);
        printf("strip %d: %zu -> %zu candidates (ratio / (N/M) = %.3f)\n", s, before[s], after[s], ratio);
        worst = fmax(worst, fabs(ratio - 1.0));
    }
    assert_true(worst < 0.08);
    assert_true(after[3] > 2.5 * after[0]); /* the 3x variation between the outer strips survives */
    /* uniform elimination (eq 1 with the square's area) flattens it instead */
    o.uniform_area = 1.0;
    run(p, M, N, &o, kept, NULL);
    size_t flat[4] = {0};
    for (size_t k = 0; k < N; ++k) ++flat[(int)fmin(3.0, 4.0 * p[kept[k]].x)];
    printf("uniform elimination strips: %zu %zu %zu %zu\n", flat[0], flat[1], flat[2], flat[3]);
    assert_true((double)flat[3] < 1.5 * (double)flat[0]);
    free(kept);
    free(p);
}

static void test_rmax_eq2_on_uniform_set(void** state)
{
    (void)state;
    /* uniform density M on the unit square: the m-th neighbour distance d ~ sqrt(m / (pi M)), so eq 2
     * gives r ~ sqrt(1 / (2 sqrt 3 N)), eq 1 with A = 1 */
    const size_t M = 10000, N = 500;
    vbl_vec3* p = make_points(M, 0, 44);
    double* r = malloc(M * sizeof(double));
    assert_int_equal(vbl_bn_compute_rmax(p, M, N, NULL, r), VBL_SUCCESS);
    double sum = 0.0;
    size_t interior = 0;
    for (size_t i = 0; i < M; ++i) {
        if (p[i].x < 0.1 || p[i].x > 0.9 || p[i].y < 0.1 || p[i].y > 0.9) continue; /* no boundary effect */
        sum += r[i];
        ++interior;
    }
    double mean = sum / (double)interior, eq1 = sqrt(1.0 / (2.0 * sqrt(3.0) * (double)N));
    printf("eq 2 mean r_max (interior) %.5f vs eq 1 %.5f\n", mean, eq1);
    assert_true(fabs(mean / eq1 - 1.0) < 0.05);
    free(r);
    free(p);
}

static void test_exact_count_and_threads(void** state)
{
    (void)state;
    const size_t M = 10000;
    vbl_vec3* p = make_points(M, 1, 55);
    const size_t targets[3] = {1000, 3333, 10000}; /* cost grows as M^2 / N: keep M / N <= 50 */
    size_t* a = malloc(M * sizeof(size_t));
    size_t* b = malloc(M * sizeof(size_t));
    vbl_bn_elimination_options o = VBL_BN_ELIMINATION_DEFAULT;
    o.leaf_size = 128; /* 64 leaf boxes, 8 parents, the root */
    for (int t = 0; t < 3; ++t) {
        vbl_bn_elimination_stats st;
        omp_set_num_threads(1);
        run(p, M, targets[t], &o, a, &st);
        assert_int_equal(st.levels, 2);
        omp_set_num_threads(2);
        run(p, M, targets[t], &o, b, NULL);
        assert_memory_equal(a, b, targets[t] * sizeof(size_t));
    }
    free(a);
    free(b);
    free(p);
}

static void test_parallel_close_to_sequential(void** state)
{
    (void)state;
    const size_t M = 10000, N = 1000;
    vbl_vec3* p = make_points(M, 0, 66);
    double* r = malloc(M * sizeof(double));
    size_t* kept = malloc(N * sizeof(size_t));
    vbl_bn_elimination_options o = VBL_BN_ELIMINATION_DEFAULT;
    assert_int_equal(vbl_bn_compute_rmax(p, M, N, &o, r), VBL_SUCCESS);
    double min_seq, mean_seq, min_par, mean_par;
    o.leaf_size = 0;
    run_r(p, M, N, r, &o, kept, NULL);
    nn_ratio(p, kept, N, r, &min_seq, &mean_seq);
    o.leaf_size = 128;
    run(p, M, N, &o, kept, NULL); /* r_max computed inside: the same values */
    nn_ratio(p, kept, N, r, &min_par, &mean_par);
    printf("sequential: min %.3f mean %.3f; parallel (64 leaf boxes): min %.3f mean %.3f\n", min_seq, mean_seq,
           min_par, mean_par);
    assert_true(mean_par > 0.95 * mean_seq);
    assert_true(min_par > 0.7 * min_seq);
    free(r);
    free(kept);
    free(p);
}

static void test_bad_input(void** state)
{
    (void)state;
    vbl_vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {NAN, 0, 0}};
    size_t kept[4];
    assert_int_equal(vbl_bn_eliminate(p, 3, 4, NULL, kept, NULL, NULL), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "N = 4"));
    assert_int_equal(vbl_bn_eliminate(p, 4, 2, NULL, kept, NULL, NULL), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "points[3]"));
    vbl_bn_elimination_options o = VBL_BN_ELIMINATION_DEFAULT;
    o.partial = 1.5;
    assert_int_equal(vbl_bn_eliminate(p, 3, 2, &o, kept, NULL, NULL), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "partial"));
    /* coincident points: no NaN, exactly N */
    vbl_vec3 same[50];
    for (int i = 0; i < 50; ++i) same[i] = vbl_v3(0.5, 0.5, 0.5);
    double r[10];
    size_t kept10[10];
    assert_int_equal(vbl_bn_eliminate(same, 50, 10, NULL, kept10, r, NULL), VBL_SUCCESS);
    for (int i = 0; i < 10; ++i) assert_true(isfinite(r[i]) && r[i] >= 0.0);
    assert_int_equal(vbl_bn_eliminate(p, 1, 1, NULL, kept, r, NULL), VBL_SUCCESS);
    double bad_r[3] = {0.1, -1.0, 0.1};
    assert_int_equal(vbl_bn_eliminate_with_rmax(p, 3, 2, bad_r, NULL, kept, NULL, NULL), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "r_max[1]"));
    assert_int_equal(kept[0], 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blue_noise_property),  cmocka_unit_test(test_density_preserved),
        cmocka_unit_test(test_rmax_eq2_on_uniform_set), cmocka_unit_test(test_exact_count_and_threads),
        cmocka_unit_test(test_parallel_close_to_sequential), cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
