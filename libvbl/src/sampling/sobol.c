/* Owen-scrambled Sobol pairs (sobol.h). */
#include "sampling/sobol.h"

#include "core/rng.h"

static uint32_t vbl_reverse_bits32(uint32_t x)
{
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
}

/* Dimension 1's digits bit-reversed: digit i (weight 2^-(i+1)) at bit i. Digit i is
 * sum_j binomial(j, i) b_j mod 2 over the index bits b_j, and binomial(j, i) mod 2 = [i & j == i]
 * (Lucas): the xor of the b_j over the bit positions j that contain i as a subset, the
 * superset-xor transform of the index word over its 5-bit positions. Five shift-mask-xor steps
 * (one per position bit k: every position with bit k clear takes in the one with it set) compute
 * all 32 digits at once. The same numbers as Sobol's recurrence for x + 1 (see below). */
static uint32_t vbl_sobol1_reversed(uint32_t w)
{
    w ^= (w >> 1) & 0x55555555u;
    w ^= (w >> 2) & 0x33333333u;
    w ^= (w >> 4) & 0x0F0F0F0Fu;
    w ^= (w >> 8) & 0x00FF00FFu;
    w ^= (w >> 16) & 0x0000FFFFu;
    return w;
}

uint32_t vbl_sobol_digits(uint32_t index, int dimension)
{
    if (dimension == 0) return vbl_reverse_bits32(index);
    /* Column j of the Pascal matrix as a fraction: digit i (weight 2^-(i+1), bit 31 - i) is
     * binomial(j, i) mod 2. Row by row, binomial(j, i) = binomial(j-1, i) + binomial(j-1, i-1), so
     * column j = column j-1 xor (column j-1 shifted one digit down): v_j = v_{j-1} ^ (v_{j-1} >> 1),
     * v_0 = 1/2 (Sobol's recurrence for the polynomial x + 1 with m_1 = 1), summed over the index's
     * set bits: computed for all digits at once by vbl_sobol1_reversed. */
    return vbl_reverse_bits32(vbl_sobol1_reversed(index));
}

/* A permutation of 32-bit integers in which output bit k depends on input bits <= k only (additions
 * and multiplications carry upwards): Burley 2020, sec. 3, the improved Laine-Karras hash. */
static uint32_t vbl_lk_permute(uint32_t x, uint32_t seed)
{
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

uint32_t vbl_owen_scramble(uint32_t x, uint32_t seed)
{
    /* reversed, bit k of the fraction's digit string depends on the digits before it only */
    return vbl_reverse_bits32(vbl_lk_permute(vbl_reverse_bits32(x), seed));
}

void vbl_sobol_pair(uint64_t key, uint32_t index, double* u, double* v)
{
    uint64_t h = vbl_hash64(key);
    uint32_t shuffled = vbl_owen_scramble(index, (uint32_t)h);
    uint64_t h2 = vbl_hash64(h ^ 0xA0761D6478BD642Full);
    /* vbl_owen_scramble(vbl_sobol_digits(shuffled, d), seed) with the reversals that cancel left
     * out: owen(x) = reverse(permute(reverse(x))), and the digits are reverse(shuffled) (d = 0),
     * reverse(vbl_sobol1_reversed(shuffled)) (d = 1) */
    uint32_t x = vbl_reverse_bits32(vbl_lk_permute(shuffled, (uint32_t)h2));
    uint32_t y = vbl_reverse_bits32(vbl_lk_permute(vbl_sobol1_reversed(shuffled), (uint32_t)(h2 >> 32)));
    /* the low bits: below every elementary interval a 32-digit net resolves */
    uint64_t lo = vbl_hash64(h2 + index);
    const double scale = 1.0 / 4294967296.0, lo_scale = 1.0 / 2097152.0; /* 2^-32, 2^-21 */
    *u = ((double)x + (double)(lo & 0x1FFFFFu) * lo_scale) * scale;
    *v = ((double)y + (double)((lo >> 21) & 0x1FFFFFu) * lo_scale) * scale;
}
