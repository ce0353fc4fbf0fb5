/* Beam BVH (Jarosz et al. 2011a, section 8.3): queries return exactly the
 * brute-force set, long beams are split, the build is deterministic, bad beams are rejected. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "core/rng.h"
#include "transport/photon_beams/beam_bvh.h"

static vbl_vec3 rand_dir(vbl_rng* r)
{
    double z = 1.0 - 2.0 * vbl_rng_uniform(r), ph = 2.0 * VBL_PI * vbl_rng_uniform(r);
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return vbl_v3(s * cos(ph), s * sin(ph), z);
}

static void make_beams(vbl_beam* b, int n, vbl_rng* rng)
{
    for (int i = 0; i < n; ++i) {
        int kind = i % 4;
        if (kind == 0) { /* point light: shared vertex */
            b[i].origin = vbl_v3(0.1, 0.2, 0.3);
        } else {
            b[i].origin = vbl_v3(4 * vbl_rng_uniform(rng) - 2, 4 * vbl_rng_uniform(rng) - 2, 4 * vbl_rng_uniform(rng) - 2);
        }
        b[i].direction = kind == 3 ? vbl_v3(1, 0, 0) : rand_dir(rng); /* some axis-parallel */
        b[i].length = kind == 1 ? 6.0 * vbl_rng_uniform(rng) : 1.5 * vbl_rng_uniform(rng);
        b[i].radius = i % 17 == 0 ? 0.0 : 0.002 + 0.08 * vbl_rng_uniform(rng);
        if (i % 53 == 0) b[i].length = 0.0;
    }
}

static void test_bvh_matches_brute_force(void** state)
{
    (void)state;
    enum { NB = 3000, NQ = 400 };
    vbl_beam* beams = (vbl_beam*)malloc(NB * sizeof *beams);
    vbl_rng rng = vbl_rng_make(12, 0, 0);
    make_beams(beams, NB, &rng);
    vbl_beam_bvh bvh;
    assert_int_equal(vbl_beam_bvh_build(&bvh, beams, NB, NULL), VBL_SUCCESS);
    printf("%d beams -> %zu pieces, %zu nodes\n", NB, bvh.piece_count, bvh.node_count);
    assert_true(bvh.piece_count > NB); /* long beams were split */
    vbl_beam_hits hits = {0};
    uint32_t* ref = (uint32_t*)malloc(NB * sizeof *ref);
    size_t total = 0;
    for (int q = 0; q < NQ; ++q) {
        vbl_vec3 o = vbl_v3(6 * vbl_rng_uniform(&rng) - 3, 6 * vbl_rng_uniform(&rng) - 3, 6 * vbl_rng_uniform(&rng) - 3);
        vbl_vec3 d = q % 5 == 0 ? vbl_v3(0, 0, 1) : (q % 7 == 0 ? vbl_v3(1, 0, 0) : rand_dir(&rng));
        if (q % 11 == 0) o = vbl_v3(0.1, 0.2, 0.3); /* through the shared vertex */
        double len = q % 13 == 0 ? 0.0 : 8.0 * vbl_rng_uniform(&rng);
        assert_int_equal(vbl_beam_bvh_query(&bvh, o, d, len, &hits), VBL_SUCCESS);
        size_t n = 0;
        for (int i = 0; i < NB; ++i)
            if (vbl_segment_distance2(o, d, len, beams[i].origin, beams[i].direction, beams[i].length) <=
                beams[i].radius * beams[i].radius)
                ref[n++] = (uint32_t)i;
        if (n != hits.count) printf("query %d: bvh %zu vs brute force %zu\n", q, hits.count, n);
        assert_int_equal(n, hits.count);
        assert_true(n == 0 || memcmp(ref, hits.ids, n * sizeof *ref) == 0);
        total += n;
    }
    printf("%zu hits over %d queries\n", total, NQ);
    assert_true(total > NQ); /* the test exercises real hits */
    vbl_beam_hits_free(&hits);
    free(ref);
    vbl_beam_bvh_free(&bvh);
    free(beams);
}

static void test_segment_distance(void** state)
{
    (void)state;
    /* crossing, parallel overlapping, parallel disjoint, endpoint cases */
    assert_true(fabs(vbl_segment_distance2(vbl_v3(-1, 0, 0), vbl_v3(1, 0, 0), 2, vbl_v3(0, -1, 0.5), vbl_v3(0, 1, 0), 2) - 0.25) < 1e-15);
    assert_true(fabs(vbl_segment_distance2(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 2, vbl_v3(1, 0.3, 0), vbl_v3(1, 0, 0), 5) - 0.09) < 1e-15);
    assert_true(fabs(vbl_segment_distance2(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 1, vbl_v3(3, 0, 0), vbl_v3(-1, 0, 0), 1) - 1.0) < 1e-15);
    assert_true(fabs(vbl_segment_distance2(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 1, vbl_v3(2, 1, 0), vbl_v3(0, 1, 0), 1) - 2.0) < 1e-15);
    /* brute force over a fine grid of parameters never beats it */
    vbl_rng rng = vbl_rng_make(5, 0, 0);
    for (int i = 0; i < 200; ++i) {
        vbl_vec3 p0 = rand_dir(&rng), d0 = rand_dir(&rng), p1 = rand_dir(&rng), d1 = rand_dir(&rng);
        double l0 = 2 * vbl_rng_uniform(&rng), l1 = 2 * vbl_rng_uniform(&rng);
        double dist = vbl_segment_distance2(p0, d0, l0, p1, d1, l1), bf = INFINITY;
        for (int a = 0; a <= 100; ++a)
            for (int b = 0; b <= 100; ++b) {
                vbl_vec3 x = vbl_v3_sub(vbl_v3_madd(p0, d0, l0 * a / 100), vbl_v3_madd(p1, d1, l1 * b / 100));
                bf = fmin(bf, vbl_v3_dot(x, x));
            }
        assert_true(dist <= bf + 1e-12 && dist >= bf - 1e-3);
    }
}

static void test_bvh_deterministic_and_invalid(void** state)
{
    (void)state;
    enum { NB = 500 };
    vbl_beam beams[NB];
    vbl_rng rng = vbl_rng_make(13, 0, 0);
    make_beams(beams, NB, &rng);
    vbl_beam_bvh a, b;
    vbl_beam_bvh_options opt = {0.5, 2, 16, NULL, NULL};
    assert_int_equal(vbl_beam_bvh_build(&a, beams, NB, &opt), VBL_SUCCESS);
    assert_int_equal(vbl_beam_bvh_build(&b, beams, NB, &opt), VBL_SUCCESS);
    assert_true(a.node_count == b.node_count && a.piece_count == b.piece_count);
    assert_true(memcmp(a.nodes, b.nodes, a.node_count * sizeof *a.nodes) == 0);
    for (size_t i = 0; i < a.piece_count; ++i) /* fieldwise: the struct has padding */
        assert_true(a.pieces[i].beam == b.pieces[i].beam && a.pieces[i].t0 == b.pieces[i].t0 && a.pieces[i].t1 == b.pieces[i].t1);
    for (size_t i = 0; i < a.piece_count; ++i) /* at most 16 pieces per beam (options.max_pieces) */
        assert_true(a.pieces[i].t1 - a.pieces[i].t0 >= beams[a.pieces[i].beam].length / 16.0 * (1 - 1e-12));
    vbl_beam_bvh_free(&a);
    vbl_beam_bvh_free(&b);
    /* empty set and bad beams */
    vbl_beam_hits hits = {0};
    assert_int_equal(vbl_beam_bvh_build(&a, beams, 0, NULL), VBL_SUCCESS);
    assert_int_equal(vbl_beam_bvh_query(&a, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 1.0, &hits), VBL_SUCCESS);
    assert_int_equal(hits.count, 0);
    vbl_beam_bvh_free(&a);
    beams[7].radius = NAN;
    assert_int_equal(vbl_beam_bvh_build(&a, beams, NB, NULL), VBL_ERROR_INVALID_ARGUMENT);
    assert_true(a.nodes == NULL && a.pieces == NULL);
    beams[7].radius = 0.1;
    beams[9].length = -1.0;
    assert_int_equal(vbl_beam_bvh_build(&a, beams, NB, NULL), VBL_ERROR_INVALID_ARGUMENT);
    vbl_beam_hits_free(&hits);
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_segment_distance),
        cmocka_unit_test(test_bvh_matches_brute_force),
        cmocka_unit_test(test_bvh_deterministic_and_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
