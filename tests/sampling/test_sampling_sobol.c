/* Owen-scrambled Sobol pairs (sampling/sobol.h, Burley 2020): the generator matrices (dimension 0
 * the bit reversal, dimension 1 the Pascal matrix mod 2, against binomial coefficients computed
 * here), stratification (every elementary interval of area 2^-m holds exactly one of the first 2^m
 * points, and of every aligned block of 2^m, unscrambled, scrambled and shuffled), the scramble's
 * bijectivity on digit prefixes, uniformity of a point over keys and independence of padded pairs
 * (chi-square), and the mean of a smooth integrand over the first 2^m points. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "chi2.h"
#include "sampling/sobol.h"

#define VBL_E_MINUS_2 0.71828182845904523536

/* binomial(j, i) mod 2 by Pascal's rule (not Lucas' theorem, which the code's recurrence rests on) */
static int binom_mod2(int j, int i)
{
    static unsigned char row[33][33];
    static int done = 0;
    if (!done) {
        for (int a = 0; a <= 32; ++a) {
            row[a][0] = 1;
            for (int b = 1; b <= a; ++b) row[a][b] = (unsigned char)((row[a - 1][b - 1] + (b < a ? row[a - 1][b] : 0)) & 1);
        }
        done = 1;
    }
    return i <= j ? row[j][i] : 0;
}

static void test_generator_matrices(void** state)
{
    (void)state;
    for (int j = 0; j < 32; ++j) {
        uint32_t col0 = vbl_sobol_digits(1u << j, 0), col1 = vbl_sobol_digits(1u << j, 1);
        assert_int_equal(col0, 1u << (31 - j)); /* digit j of the index -> digit j of the fraction */
        for (int i = 0; i < 32; ++i) assert_int_equal((col1 >> (31 - i)) & 1u, (uint32_t)binom_mod2(j, i));
    }
    /* linear over GF(2) in the index */
    for (uint32_t a = 1; a < 5000; a += 37)
        for (uint32_t b = 3; b < 300000; b += 4099)
            for (int d = 0; d < 2; ++d)
                assert_int_equal(vbl_sobol_digits(a ^ b, d), vbl_sobol_digits(a, d) ^ vbl_sobol_digits(b, d));
}

/* 1 if the n = 2^m points are a (0,m,2)-net in base 2: for every split m = a + b each of the 2^m
 * intervals [i 2^-a, (i+1) 2^-a) x [j 2^-b, (j+1) 2^-b) holds exactly one point. */
static int is_net(const uint32_t* x, const uint32_t* y, int m)
{
    const int n = 1 << m;
    static unsigned char seen[1 << 12];
    for (int a = 0; a <= m; ++a) {
        int b = m - a;
        memset(seen, 0, (size_t)n);
        for (int k = 0; k < n; ++k) {
            uint32_t i = a ? x[k] >> (32 - a) : 0u, j = b ? y[k] >> (32 - b) : 0u;
            uint32_t cell = (i << b) | j;
            if (seen[cell]) return 0;
            seen[cell] = 1;
        }
    }
    return 1;
}

/* The digits of a shuffled, scrambled point (vbl_sobol_pair's integer part) */
static void pair_digits(uint64_t key, uint32_t index, uint32_t* x, uint32_t* y)
{
    double u, v;
    vbl_sobol_pair(key, index, &u, &v);
    assert_true(u >= 0.0 && u < 1.0 && v >= 0.0 && v < 1.0);
    *x = (uint32_t)(u * 4294967296.0);
    *y = (uint32_t)(v * 4294967296.0);
}

static void test_stratification(void** state)
{
    (void)state;
    static uint32_t x[1 << 12], y[1 << 12];
    int nets = 0;
    for (int m = 0; m <= 12; ++m) {
        const uint32_t n = 1u << m;
        /* unscrambled, the first block and a far block */
        for (uint32_t start = 0; start <= 5u * n; start += 5u * n) {
            for (uint32_t k = 0; k < n; ++k) {
                x[k] = vbl_sobol_digits(start + k, 0);
                y[k] = vbl_sobol_digits(start + k, 1);
            }
            assert_true(is_net(x, y, m));
            ++nets;
        }
        /* scrambled only, with independent seeds per dimension */
        for (uint32_t k = 0; k < n; ++k) {
            x[k] = vbl_owen_scramble(vbl_sobol_digits(k, 0), 0x9e3779b9u);
            y[k] = vbl_owen_scramble(vbl_sobol_digits(k, 1), 0x7f4a7c15u);
        }
        assert_true(is_net(x, y, m));
        /* shuffled + scrambled (what pt uses): the prefix of 2^m and an aligned later block, for
         * several keys */
        for (uint64_t key = 1; key <= 4; ++key)
            for (uint32_t start = 0; start <= 3u * n; start += 3u * n) {
                for (uint32_t k = 0; k < n; ++k) pair_digits(key * 0x2545F4914F6CDD1Dull, start + k, &x[k], &y[k]);
                assert_true(is_net(x, y, m));
                ++nets;
            }
    }
    printf("%d nets checked\n", nets);
    /* an unaligned block is not a net in general (the check can fail) */
    for (uint32_t k = 0; k < 16; ++k) {
        x[k] = vbl_sobol_digits(k + 3, 0);
        y[k] = vbl_sobol_digits(k + 3, 1);
    }
    assert_false(is_net(x, y, 4));
}

/* Nested uniform scrambling permutes every digit prefix: the top m digits of 2^m distinct prefixes
 * stay distinct, and digit k of the output depends on digits <= k of the input only. */
static void test_scramble_nested(void** state)
{
    (void)state;
    for (uint32_t seed = 1; seed < 40; seed += 7) {
        for (int m = 1; m <= 10; ++m) {
            static unsigned char seen[1 << 10];
            memset(seen, 0, sizeof seen);
            for (uint32_t p = 0; p < (1u << m); ++p) {
                uint32_t out = vbl_owen_scramble(p << (32 - m), seed * 0x85EBCA6Bu) >> (32 - m);
                assert_false(seen[out]);
                seen[out] = 1;
                /* changing digits below the prefix keeps the prefix's image */
                uint32_t low = (0xA5A5A5A5u * (p + 1)) >> m;
                assert_int_equal(vbl_owen_scramble((p << (32 - m)) | low, seed * 0x85EBCA6Bu) >> (32 - m), out);
            }
        }
    }
}

/* One point (fixed index) over many keys is uniform on the square (Owen scrambling makes every
 * point uniform), and two padded pairs of the same pixel are independent: chi-square on 16 x 16
 * cells of (u, v) of one pair and of (u of pair 1, u of pair 2). */
static void test_uniform_and_independent(void** state)
{
    (void)state;
    enum { N = 51200, C = 16 };
    static double obs_uv[C * C], obs_pairs[C * C], expct[C * C];
    int ok = 1;
    const uint32_t indices[3] = {0u, 5u, 1000u};
    for (int t = 0; t < 3; ++t) {
        memset(obs_uv, 0, sizeof obs_uv);
        memset(obs_pairs, 0, sizeof obs_pairs);
        for (int c = 0; c < C * C; ++c) expct[c] = (double)N / (C * C);
        for (uint64_t pixel = 0; pixel < N; ++pixel) {
            double u, v, u2, v2;
            vbl_sobol_pair(vbl_sobol_key(7, pixel, 1, 0), indices[t], &u, &v);
            vbl_sobol_pair(vbl_sobol_key(7, pixel, 2, 0), indices[t], &u2, &v2);
            obs_uv[(int)(u * C) * C + (int)(v * C)] += 1.0;
            obs_pairs[(int)(u * C) * C + (int)(u2 * C)] += 1.0;
        }
        char label[64];
        snprintf(label, sizeof label, "point %u over keys", indices[t]);
        ok &= vbl_chi2_check(label, obs_uv, expct, C * C, 0.01, 6);
        snprintf(label, sizeof label, "pairs 1 x 2 at point %u", indices[t]);
        ok &= vbl_chi2_check(label, obs_pairs, expct, C * C, 0.01, 6);
    }
    assert_true(ok);
}

/* The mean of a smooth integrand over the first 2^m points of a pixel's pair converges far faster
 * than the 1/sqrt(n) of independent points; it is unbiased over keys (mean within 4 sigma). */
static void test_mean(void** state)
{
    (void)state;
    vbl_mean_acc acc = {0};
    double worst = 0.0;
    for (uint64_t pixel = 0; pixel < 200; ++pixel) {
        double s = 0.0;
        for (uint32_t k = 0; k < 1024; ++k) {
            double u, v;
            vbl_sobol_pair(vbl_sobol_key(3, pixel, 0, 0), k, &u, &v);
            s += u * exp(u * v); /* integral over the unit square: e - 2 */
        }
        s /= 1024.0;
        vbl_mean_add(&acc, s);
        worst = fmax(worst, fabs(s - (VBL_E_MINUS_2)));
    }
    printf("worst |error| over 200 keys at n = 1024: %.2e (independent points: ~%.1e)\n", worst,
           3.0 * 0.45 / sqrt(1024.0));
    assert_true(vbl_mean_check("mean over keys", &acc, VBL_E_MINUS_2, 4.0, 0.0));
    assert_true(worst < 2e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_generator_matrices), cmocka_unit_test(test_stratification),
        cmocka_unit_test(test_scramble_nested), cmocka_unit_test(test_uniform_and_independent),
        cmocka_unit_test(test_mean),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
