/* The hierarchical majorant walk (majorant_iter.c, issue 14 item 5): its non-empty segments are
 * bit-identical to a block-by-block reference walk (empty coarse cells come as one segment),
 * segments cover the ray exactly once (random, axis-parallel, inside-start, face/edge/corner
 * touching, zero and huge lengths), merged coarse segments are true bounds (also on the dilated
 * grid of a moving medium), and transmittance means with merging agree with the block walk's
 * within k sigma. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/rng.h"
#include "volume/extinction.h"
#include "volume/transmittance.h"
#include "volume_test_grid.h"

#define N 64

/* Three blobs far apart in a 64^3 box: empty coarse cells between them (block 2: coarse cells
 * of 8 voxels). */
static double fn_blobs(int i, int j, int k, void* user)
{
    (void)user;
    static const double c[3][3] = {{10, 12, 9}, {50, 44, 20}, {30, 20, 52}};
    double v = 0.0;
    for (int b = 0; b < 3; ++b) {
        double x = i - c[b][0], y = j - c[b][1], z = k - c[b][2];
        double r2 = (x * x + y * y + z * z) / 49.0;
        if (r2 < 1.0) v += (1.0 - r2) * (1.0 + 0.4 * sin(1.3 * i) * cos(0.7 * j + k));
    }
    if (i >= 40 && i < 56 && j >= 4 && j < 20 && k >= 36 && k < 60) v += 0.5; /* a constant slab */
    return v;
}

/* Many small blobs: many transitions between empty and non-empty coarse cells. */
static double fn_sparse(int i, int j, int k, void* user)
{
    (void)user;
    double v = 0.0;
    for (int b = 0; b < 60; ++b) {
        uint64_t h = (uint64_t)b * 0x9E3779B97F4A7C15ull;
        double cx = (double)((h >> 8) % 60) + 2, cy = (double)((h >> 20) % 60) + 2, cz = (double)((h >> 32) % 60) + 2;
        double x = i - cx, y = j - cy, z = k - cz;
        double r2 = (x * x + y * y + z * z) / 6.0;
        if (r2 < 1.0) v += 1.0 - r2;
    }
    return v;
}

static const int BMIN[3] = {0, 0, 0}, BMAX[3] = {N - 1, N - 1, N - 1};

/* ---- reference: the block-by-block walk (the iterator before the coarse level) ------------- */
typedef struct ref_iter {
    const vbl_majorant_grid* g;
    double t, t_end, t_next[3], org[3], inv_dir[3];
    int cell[3], step[3], done;
} ref_iter;

static double ref_boundary(const ref_iter* it, int a)
{
    if (it->step[a] == 0) return INFINITY;
    return ((double)(it->cell[a] + (it->step[a] > 0 ? 1 : 0)) - it->org[a]) * it->inv_dir[a];
}

/* Initialized from the hierarchical iterator's entry state (same clip, same entry cell: the
 * init code is shared), then walked block by block. */
static void ref_init(ref_iter* r, const vbl_majorant_iter* it)
{
    r->g = it->grid;
    r->done = it->done;
    r->t = it->t;
    r->t_end = it->t_end;
    for (int a = 0; a < 3; ++a) {
        r->org[a] = it->org[a];
        r->inv_dir[a] = it->inv_dir[a];
        r->cell[a] = it->cell[a];
        r->step[a] = it->step[a];
    }
    if (!r->done)
        for (int a = 0; a < 3; ++a) r->t_next[a] = ref_boundary(r, a);
}

static int ref_next(ref_iter* it, vbl_majorant_segment* s)
{
    const vbl_majorant_grid* g = it->g;
    while (!it->done) {
        int axis = 0;
        if (it->t_next[1] < it->t_next[axis]) axis = 1;
        if (it->t_next[2] < it->t_next[axis]) axis = 2;
        double t_cross = it->t_next[axis];
        double t1 = t_cross < it->t_end ? t_cross : it->t_end;
        if (t1 < it->t) t1 = it->t;
        size_t index = (size_t)it->cell[0] + (size_t)g->dims[0] * ((size_t)it->cell[1] + (size_t)g->dims[1] * (size_t)it->cell[2]);
        double t0 = it->t;
        if (t_cross < it->t_end) {
            it->cell[axis] += it->step[axis];
            if (it->cell[axis] < 0 || it->cell[axis] >= g->dims[axis]) it->done = 1;
            else it->t_next[axis] = ref_boundary(it, axis);
            it->t = t1;
        } else {
            it->done = 1;
            it->t = it->t_end;
        }
        if (t1 > t0) {
            s->t0 = t0;
            s->t1 = t1;
            s->majorant = g->max_density[index];
            s->minorant = g->min_density[index];
            return 1;
        }
    }
    return 0;
}

#define MAXSEG 4096
typedef struct seglist { vbl_majorant_segment s[MAXSEG]; int n; } seglist;

/* Non-empty segments kept as they are; consecutive empty ones merged into one. */
static void push(seglist* l, const vbl_majorant_segment* s)
{
    const int empty = s->majorant == 0.0 && s->minorant == 0.0;
    if (empty && l->n > 0) {
        vbl_majorant_segment* p = &l->s[l->n - 1];
        if (p->majorant == 0.0 && p->minorant == 0.0 && p->t1 == s->t0) {
            p->t1 = s->t1;
            return;
        }
    }
    assert_true(l->n < MAXSEG);
    l->s[l->n++] = *s;
}

static seglist g_a, g_b;

/* A ray of several kinds (random, axis-parallel, inside, on a face / edge / corner, zero or huge
 * length) in index space of a grid with unit voxels. */
static void make_ray(vbl_rng* rng, int r, vbl_vec3* o, vbl_vec3* d, double* tmin, double* tmax)
{
    *o = vbl_v3(-10.0 + (N + 20.0) * vbl_rng_uniform(rng), -10.0 + (N + 20.0) * vbl_rng_uniform(rng),
                -10.0 + (N + 20.0) * vbl_rng_uniform(rng));
    *d = vbl_v3(vbl_rng_uniform(rng) - 0.5, vbl_rng_uniform(rng) - 0.5, vbl_rng_uniform(rng) - 0.5);
    *tmin = vbl_rng_uniform(rng) < 0.5 ? -1e30 : 100.0 * (vbl_rng_uniform(rng) - 0.5);
    *tmax = vbl_rng_uniform(rng) < 0.5 ? 1e30 : *tmin + 200.0 * vbl_rng_uniform(rng);
    switch (r % 8) {
    case 1: { /* axis-parallel */
        int ax = (int)(vbl_rng_uniform(rng) * 3);
        double s = vbl_rng_uniform(rng) < 0.5 ? -1.0 : 1.0;
        *d = vbl_v3(ax == 0 ? s : 0.0, ax == 1 ? s : 0.0, ax == 2 ? s : 0.0);
        break;
    }
    case 2: /* in a coarse-cell face plane (index -1 + 8 m: the grid starts one voxel below 0) */
        d->y = 0.0;
        o->y = -1.0 + 8.0 * floor(vbl_rng_uniform(rng) * 9.0);
        break;
    case 3: /* along a coarse-cell edge */
        d->y = d->z = 0.0;
        o->y = -1.0 + 8.0 * floor(vbl_rng_uniform(rng) * 9.0);
        o->z = -1.0 + 2.0 * floor(vbl_rng_uniform(rng) * 33.0);
        break;
    case 4: { /* through a coarse-cell corner, diagonal */
        double c = -1.0 + 8.0 * floor(1.0 + vbl_rng_uniform(rng) * 7.0);
        *o = vbl_v3(c, c + 8.0, c - 8.0);
        *d = vbl_v3(1.0, vbl_rng_uniform(rng) < 0.5 ? 1.0 : -1.0, 1.0);
        *tmin = -1e30;
        *tmax = 1e30;
        break;
    }
    case 5: /* starting inside */
        *tmin = 0.0;
        *o = vbl_v3(N * vbl_rng_uniform(rng), N * vbl_rng_uniform(rng), N * vbl_rng_uniform(rng));
        break;
    case 6: /* zero length */
        *tmax = *tmin;
        break;
    default:
        break;
    }
}

static double* g_voxel_map(double m[3][4])
{
    vt_uniform_map(m, 1.0, 0.0, 0.0, 0.0);
    return &m[0][0];
}

static void check_bit_identical(vt_voxel_fn fn)
{
    double m[3][4];
    g_voxel_map(m);
    size_t size;
    void* buf = vt_make_nanovdb(BMIN, BMAX, fn, NULL, m, &size);
    vbl_volume* v = vt_wrap(buf, size, 2);
    assert_non_null(v);
    assert_non_null(v->majorant.coarse_max);
    vbl_rng rng = vbl_rng_make(11, 12, 13);
    long merged_empty = 0, nonempty = 0;
    for (int r = 0; r < 3000; ++r) {
        vbl_vec3 o, d;
        double tmin, tmax;
        make_ray(&rng, r, &o, &d, &tmin, &tmax);
        vbl_majorant_iter it;
        vbl_majorant_segment s;
        vbl_majorant_iter_init(&it, v, o, d, tmin, tmax);
        const vbl_majorant_iter it0 = it;
        ref_iter ref;
        ref_init(&ref, &it);
        g_a.n = g_b.n = 0;
        int raw = 0;
        while (vbl_majorant_iter_next(&it, &s)) {
            assert_true(s.t1 > s.t0);
            push(&g_a, &s);
            raw++;
        }
        while (ref_next(&ref, &s)) push(&g_b, &s);
        assert_int_equal(g_a.n, g_b.n);
        for (int i = 0; i < g_a.n; ++i) {
            assert_true(g_a.s[i].t0 == g_b.s[i].t0);
            assert_true(g_a.s[i].t1 == g_b.s[i].t1);
            assert_true(g_a.s[i].majorant == g_b.s[i].majorant);
            assert_true(g_a.s[i].minorant == g_b.s[i].minorant);
            nonempty += g_a.s[i].majorant > 0.0;
        }
        long raw_ref = 0;
        ref_init(&ref, &it0);
        while (ref_next(&ref, &s)) raw_ref++;
        merged_empty += raw_ref - raw;
    }
    fprintf(stderr, "non-empty segments %ld, empty blocks merged %ld\n", nonempty, merged_empty);
    assert_true(nonempty > 2000);
    assert_true(merged_empty > 5000); /* empty coarse cells were crossed in one step */
    vt_free(v);
}

static void test_bit_identical_to_block_walk(void** state)
{
    (void)state;
    check_bit_identical(fn_blobs);
    check_bit_identical(fn_sparse);
}

/* Coverage and bounds with merging on (optical depth and spread criteria). */
static void check_merged(const vbl_volume* v, const vbl_majorant_grid* g, double tau, double ratio, int check_values)
{
    vbl_grid_accessor acc;
    vbl_grid_accessor_init(&acc, v);
    vbl_rng rng = vbl_rng_make(21, (uint64_t)(tau * 100), (uint64_t)(ratio * 100));
    long checked = 0, coarse = 0, fine_steps = 0, merged_steps = 0;
    for (int r = 0; r < 2000; ++r) {
        vbl_vec3 o, d;
        double tmin, tmax;
        make_ray(&rng, r, &o, &d, &tmin, &tmax);
        vbl_majorant_iter it, it0;
        vbl_majorant_segment s;
        vbl_majorant_iter_init_coarse(&it, g, &v->world_to_index, o, d, tmin, tmax, tau, ratio);
        vbl_majorant_iter_init_grid(&it0, g, &v->world_to_index, o, d, tmin, tmax);
        double first = NAN, prev = NAN, a = it.t, b = it.t_end;
        const int any = !it.done;
        int n = 0;
        while (vbl_majorant_iter_next(&it, &s)) {
            assert_true(s.t1 > s.t0);
            if (n == 0) first = s.t0;
            else assert_true(s.t0 == prev); /* no gap, no overlap */
            prev = s.t1;
            n++;
            if (!check_values) continue;
            for (int k = 0; k < 5; ++k) {
                double t = k == 0 ? s.t0 : (k == 1 ? s.t1 : s.t0 + (s.t1 - s.t0) * vbl_rng_uniform(&rng));
                double x = vbl_grid_sample_world(&acc, vbl_v3_madd(o, d, t), VBL_FILTER_TRILINEAR);
                assert_true(x <= s.majorant * (1.0 + 1e-12));
                assert_true(x >= s.minorant * (1.0 - 1e-12) - 1e-300);
                checked++;
            }
        }
        while (vbl_majorant_iter_next(&it0, &s)) {}
        fine_steps += (long)it0.steps;
        merged_steps += (long)it.steps;
        if (any && n) {
            assert_true(first == a); /* exactly the clipped interval */
            assert_true(prev == b);
        }
        coarse += n;
    }
    if (check_values) assert_true(checked > 10000);
    if (tau > 0.0 || ratio >= 1.0) assert_true(merged_steps < fine_steps); /* the merge does remove steps */
    else assert_true(merged_steps == fine_steps);
    (void)coarse;
}

static void test_merged_segments_bound_and_cover(void** state)
{
    (void)state;
    double m[3][4];
    g_voxel_map(m);
    size_t size;
    void* buf = vt_make_nanovdb(BMIN, BMAX, fn_blobs, NULL, m, &size);
    vbl_volume* v = vt_wrap(buf, size, 2);
    assert_non_null(v);
    check_merged(v, &v->majorant, 0.0, 0.0, 1);
    check_merged(v, &v->majorant, 2.0, 0.0, 1);
    check_merged(v, &v->majorant, 0.0, 2.0, 1);
    check_merged(v, &v->majorant, 1e30, 0.0, 1); /* every coarse cell merged */
    /* The coarse level bounds its blocks, on the volume's grid and on a dilated (moving) one. */
    int k[3] = {2, 1, 3};
    vbl_majorant_grid moving;
    assert_int_equal(vbl_majorant_grid_dilate(&v->majorant, k, &moving), VBL_SUCCESS);
    const vbl_majorant_grid* gs[2] = {&v->majorant, &moving};
    for (int gi = 0; gi < 2; ++gi) {
        const vbl_majorant_grid* g = gs[gi];
        assert_non_null(g->coarse_max);
        for (int z = 0; z < g->dims[2]; ++z)
            for (int y = 0; y < g->dims[1]; ++y)
                for (int x = 0; x < g->dims[0]; ++x) {
                    size_t f = (size_t)x + (size_t)g->dims[0] * ((size_t)y + (size_t)g->dims[1] * (size_t)z);
                    int L = VBL_MAJORANT_COARSE_LOG2;
                    size_t c = (size_t)(x >> L) + (size_t)g->coarse_dims[0] * ((size_t)(y >> L) + (size_t)g->coarse_dims[1] * (size_t)(z >> L));
                    assert_true(g->coarse_max[c] >= g->max_density[f]);
                    assert_true(g->coarse_min[c] <= g->min_density[f]);
                    assert_true(g->coarse_spread[c] >= 1.0f);
                }
    }
    /* the moving grid's merged segments cover the rays (its values bound the advected field by
     * the dilation, tested in test_render_motion) */
    check_merged(v, &moving, 2.0, 2.0, 0);
    vbl_majorant_grid_free(&moving);
    vt_free(v);
}

/* Ratio tracking through the blobs: the merged walk's mean agrees with the block walk's. */
static void test_transmittance_means_unchanged(void** state)
{
    (void)state;
    double m[3][4];
    g_voxel_map(m);
    size_t size;
    void* buf = vt_make_nanovdb(BMIN, BMAX, fn_blobs, NULL, m, &size);
    vbl_volume* v = vt_wrap(buf, size, 2);
    assert_non_null(v);
    vbl_extinction e[2];
    for (int i = 0; i < 2; ++i) {
        vbl_extinction_init(&e[i]);
        assert_int_equal(vbl_extinction_add(&e[i], v, 0.3, NULL), VBL_SUCCESS);
    }
    e[0].coarse_depth = -1.0; /* the plain block walk */
    e[0].coarse_ratio = 0.0;
    e[1].coarse_depth = 2.0;
    e[1].coarse_ratio = 3.0;
    vbl_tracking_settings set;
    memset(&set, 0, sizeof set);
    set.estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    set.majorant_scale = 1.0;
    const vbl_vec3 rays[3][2] = {{{-5, 12, 9}, {1, 0.01, 0.02}}, {{70, 50, 18}, {-1, -0.1, 0.05}}, {{30, 70, 0}, {0.1, -1, 1}}};
    for (int r = 0; r < 3; ++r) {
        double mean[2], var[2];
        const int n = 20000;
        for (int i = 0; i < 2; ++i) {
            vbl_extinction_cursor cur;
            vbl_extinction_cursor_init(&cur, &e[i]);
            double s = 0, s2 = 0;
            for (int k = 0; k < n; ++k) {
                vbl_rng rng = vbl_rng_make(5, (uint64_t)r, (uint64_t)(k + i * n));
                double x = vbl_transmittance_estimate(&e[i], &cur, rays[r][0], rays[r][1], 0.0, 120.0, &set, &rng);
                s += x;
                s2 += x * x;
            }
            mean[i] = s / n;
            var[i] = fmax(s2 / n - mean[i] * mean[i], 0.0) / n;
        }
        double se = sqrt(var[0] + var[1]);
        if (!(fabs(mean[0] - mean[1]) <= 4.0 * se + 1e-12)) {
            fprintf(stderr, "ray %d: block walk %.6g, merged %.6g (se %.3g)\n", r, mean[0], mean[1], se);
            fail();
        }
        assert_true(mean[0] > 0.01 && mean[0] < 0.99); /* the ray does cross the medium */
    }
    vt_free(v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bit_identical_to_block_walk),
        cmocka_unit_test(test_merged_segments_bound_and_cover),
        cmocka_unit_test(test_transmittance_means_unchanged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
