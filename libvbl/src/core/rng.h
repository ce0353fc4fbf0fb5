/* Deterministic random numbers: PCG32 streams keyed by (seed, pass, pixel/path index), so an
 * image depends only on the scene, seed and pass count, never on the thread count. */
#ifndef VBL_CORE_RNG_H
#define VBL_CORE_RNG_H

#include <stdint.h>

typedef struct vbl_rng { uint64_t state, inc; } vbl_rng;

/* SplitMix64 finalizer: decorrelates structured keys. */
static inline uint64_t vbl_hash64(uint64_t x)
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

static inline uint32_t vbl_rng_next_u32(vbl_rng* r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ull + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

/* Stream for a (seed, a, b) key: e.g. (scene seed, pass, pixel index). */
static inline vbl_rng vbl_rng_make(uint64_t seed, uint64_t a, uint64_t b)
{
    vbl_rng r;
    uint64_t key = vbl_hash64(seed ^ vbl_hash64(a ^ vbl_hash64(b + 0x632BE59BD9B4E019ull)));
    r.state = 0u;
    r.inc = (vbl_hash64(key ^ 0xD1B54A32D192ED03ull) << 1u) | 1u;
    vbl_rng_next_u32(&r);
    r.state += key;
    vbl_rng_next_u32(&r);
    return r;
}

/* Uniform double in [0, 1): 53 random bits from two draws. */
static inline double vbl_rng_uniform(vbl_rng* r)
{
    uint64_t hi = vbl_rng_next_u32(r), lo = vbl_rng_next_u32(r);
    uint64_t bits = ((hi << 32) | lo) >> 11;
    return (double)bits * (1.0 / 9007199254740992.0);
}

#endif
