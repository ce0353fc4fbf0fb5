/* Owen-scrambled, index-shuffled 2D Sobol points (Burley 2020, "Practical Hash-based Owen
 * Scrambling", JCGT 9(4): sec. 2 the (0,2)-sequence of Sobol's first two dimensions, sec. 3 nested
 * uniform scrambling by a hash whose output bit k depends on input bits <= k only (applied to the
 * bit-reversed value), sec. 4 shuffling the index by the same scramble and padding independent 2D
 * pairs with independent seeds).
 *
 * Dimension 0 is the van der Corput sequence (generator matrix: the identity on digits, i.e. the
 * bit reversal of the index); dimension 1 is Sobol's dimension with primitive polynomial x + 1,
 * whose generator matrix is the upper-triangular Pascal matrix mod 2 (C[i][j] = binomial(j, i) mod
 * 2, by Lucas' theorem 1 iff i & j == i). Both are derived here, no table is stored. The pair is a
 * (0,2)-sequence in base 2: every aligned block of 2^m consecutive points is a (0,m,2)-net (each
 * elementary interval of area 2^-m holds exactly one point), and nested uniform scrambling plus the
 * index shuffle keep that property (a shuffled prefix of 2^m points is an aligned block). */
#ifndef VBL_SAMPLING_SOBOL_H
#define VBL_SAMPLING_SOBOL_H

#include <stdint.h>

#include "core/rng.h"

/* Unscrambled 32-bit digits of point `index` (dimension 0 or 1), as a fraction x / 2^32. */
uint32_t vbl_sobol_digits(uint32_t index, int dimension);

/* Nested uniform (Owen) scramble of the 32-bit fraction x keyed by seed (Burley 2020, sec. 3). */
uint32_t vbl_owen_scramble(uint32_t x, uint32_t seed);

/* Point `index` of the shuffled, scrambled pair keyed by `key` (one key per pixel, pair and
 * bounce): u, v in [0, 1). The 21 bits below the 32 digits are filled from a hash of (key, index)
 * so the values have double precision without leaving their elementary interval. */
void vbl_sobol_pair(uint64_t key, uint32_t index, double* u, double* v);

/* The key of one padded pair: (render seed, pixel index, pair id, bounce); pairs differ in every
 * component so each is an independent shuffle and scramble (Burley 2020, sec. 4, padding). */
static inline uint64_t vbl_sobol_key(uint64_t seed, uint64_t pixel, uint32_t pair, uint32_t bounce)
{
    return vbl_hash64(seed ^ vbl_hash64(pixel ^ vbl_hash64(((uint64_t)pair << 32 | bounce) + 0x5851F42D4C957F2Dull)));
}

#endif
