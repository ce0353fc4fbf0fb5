/* Per-thread grid sampling through PNanoVDB read accessors (nearest and trilinear), with a cache of
 * the 8^3 leaf-sized regions last read, so that the tracking loops' lookups (a few along a ray, in
 * the same or neighbouring leaves) read their 8 floats without a tree descent. The trilinear
 * sampler is inline here: the extinction field (extinction.c) calls it at every tentative
 * collision. */
#ifndef VBL_VOLUME_GRID_SAMPLE_H
#define VBL_VOLUME_GRID_SAMPLE_H

#include <limits.h>
#include <math.h>
#include <string.h>

#include "volume/volume.h"

/* One 8^3 leaf-sized region of index space (the voxels whose coordinates share the bits above
 * the low 3): in a leaf, the value of voxel (x, y, z) is word `table[off & mask]` with off =
 * 64 (x & 7) + 8 (y & 7) + (z & 7) (PNanoVDB's pnanovdb_leaf_coord_to_offset, float stride 32
 * bits) and mask = ~0; a region inside a tile or the background (which always covers whole
 * regions) holds one value, `table[0]`, and mask = 0. */
typedef struct vbl_grid_region {
    int key[3];             /* the region's voxel with the low 3 bits cleared; key[0] = INT_MIN: empty */
    uint32_t mask;
    const uint32_t* table;
} vbl_grid_region;

/* Regions cached per accessor: direct-mapped by bit 3 of each coordinate, so the 2 x 2 x 2
 * regions a trilinear footprint can straddle never evict each other. */
#define VBL_GRID_REGION_SLOTS 8

/* One per thread and volume: caches the regions and the last leaf/internal nodes visited. */
typedef struct vbl_grid_accessor {
    const vbl_volume* volume;
    pnanovdb_readaccessor_t accessor;
    uint64_t lookups;   /* grid value fetches (a trilinear sample counts 1 lookup) */
    vbl_grid_region regions[VBL_GRID_REGION_SLOTS];
} vbl_grid_accessor;

void vbl_grid_accessor_init(vbl_grid_accessor* accessor, const vbl_volume* volume);

double vbl_grid_sample_index_nearest(vbl_grid_accessor* accessor, vbl_vec3 index_point);
double vbl_grid_sample_index_trilinear(vbl_grid_accessor* accessor, vbl_vec3 index_point);
double vbl_grid_sample_world(vbl_grid_accessor* accessor, vbl_vec3 world_point, vbl_filter filter);

/* ---- internals: the inline trilinear sampler ------------------------------------------------ */

/* Descends the tree for the region of voxel (i, j, k) and caches it in its slot (grid_sample.c). */
const vbl_grid_region* vbl_grid_region_fill(vbl_grid_accessor* a, int i, int j, int k);

/* The cached region of voxel (i, j, k), filled on a miss. */
static inline const vbl_grid_region* vbl_grid_region_of(vbl_grid_accessor* a, int i, int j, int k)
{
    const vbl_grid_region* r = &a->regions[((i & 8) >> 3) | ((j & 8) >> 2) | ((k & 8) >> 1)];
    if (r->key[0] == (i & ~7) && r->key[1] == (j & ~7) && r->key[2] == (k & ~7)) return r;
    return vbl_grid_region_fill(a, i, j, k);
}

static inline float vbl_grid_region_value(const vbl_grid_region* r, int i, int j, int k)
{
    const uint32_t off = (uint32_t)(((i & 7) << 6) | ((j & 7) << 3) | (k & 7));
    float f;
    memcpy(&f, &r->table[off & r->mask], sizeof f);
    return f;
}

/* floor() into an int, saturating far outside the int range (such points read the background). */
static inline int vbl_grid_floor_to_int(double x)
{
    double f = floor(x);
    if (!(f > -2147483000.0)) return -2147483000; /* also NaN */
    if (f > 2147483000.0) return 2147483000;
    return (int)f;
}

/* OpenVDB BoxSampler's lerp, with its float rounding (so results match it to float precision even
 * where values cancel): a + float((b - a) * w). Stays within [min(a,b), max(a,b)] for w in [0,1]. */
static inline float vbl_grid_lerp(float a, float b, double w) { return a + (float)((double)(b - a) * w); }

/* The trilinear sample at a point whose coordinates may lie outside (-VBL_GRID_NEAR, VBL_GRID_NEAR)
 * or be NaN: floors saturated, weights clamped (grid_sample.c). */
double vbl_grid_sample_index_trilinear_far(vbl_grid_accessor* a, vbl_vec3 p);
#define VBL_GRID_NEAR 2147483000.0

/* The 8 voxels around (i, j, k) (d[4 dx + 2 dy + dz] = voxel (i + dx, j + dy, k + dz)) and the
 * trilinear blend with weights (u, v, w) in [0, 1]. Inside one region ((7/8)^3 of the footprints)
 * one cache probe serves all 8 voxels; a footprint across region faces probes once per region it
 * touches (every probe hits once the regions are cached). The same floats as 8 separate
 * accessor fetches and OpenVDB BoxSampler's order of lerps, so results are bit-identical to them. */
static inline double vbl_grid_trilinear_at(vbl_grid_accessor* a, int i, int j, int k, double u, double v, double w)
{
    float d000, d001, d010, d011, d100, d101, d110, d111;
    if ((i & 7) != 7 && (j & 7) != 7 && (k & 7) != 7) {
        const vbl_grid_region* r = vbl_grid_region_of(a, i, j, k);
        const uint32_t m = r->mask, o = (uint32_t)(((i & 7) << 6) | ((j & 7) << 3) | (k & 7));
        const uint32_t* t = r->table;
        memcpy(&d000, &t[o & m], 4);
        memcpy(&d001, &t[(o + 1u) & m], 4);
        memcpy(&d010, &t[(o + 8u) & m], 4);
        memcpy(&d011, &t[(o + 9u) & m], 4);
        memcpy(&d100, &t[(o + 64u) & m], 4);
        memcpy(&d101, &t[(o + 65u) & m], 4);
        memcpy(&d110, &t[(o + 72u) & m], 4);
        memcpy(&d111, &t[(o + 73u) & m], 4);
    } else {
        /* r[dx][dy][dz]: the region of voxel (i + dx, j + dy, k + dz); along an axis that crosses
         * no region face both voxels share one, so one face costs 2 probes, an edge 4, a corner 8 */
        const int sx = (i & 7) == 7, sy = (j & 7) == 7, sz = (k & 7) == 7;
        const vbl_grid_region* r000 = vbl_grid_region_of(a, i, j, k);
        const vbl_grid_region* r001 = sz ? vbl_grid_region_of(a, i, j, k + 1) : r000;
        const vbl_grid_region* r010 = sy ? vbl_grid_region_of(a, i, j + 1, k) : r000;
        const vbl_grid_region* r011 = sy ? (sz ? vbl_grid_region_of(a, i, j + 1, k + 1) : r010) : r001;
        const vbl_grid_region* r100 = sx ? vbl_grid_region_of(a, i + 1, j, k) : r000;
        const vbl_grid_region* r101 = sx ? (sz ? vbl_grid_region_of(a, i + 1, j, k + 1) : r100) : r001;
        const vbl_grid_region* r110 = sx ? (sy ? vbl_grid_region_of(a, i + 1, j + 1, k) : r100) : r010;
        const vbl_grid_region* r111 =
            sx ? (sy ? (sz ? vbl_grid_region_of(a, i + 1, j + 1, k + 1) : r110) : r101) : r011;
        d000 = vbl_grid_region_value(r000, i, j, k);
        d001 = vbl_grid_region_value(r001, i, j, k + 1);
        d010 = vbl_grid_region_value(r010, i, j + 1, k);
        d011 = vbl_grid_region_value(r011, i, j + 1, k + 1);
        d100 = vbl_grid_region_value(r100, i + 1, j, k);
        d101 = vbl_grid_region_value(r101, i + 1, j, k + 1);
        d110 = vbl_grid_region_value(r110, i + 1, j + 1, k);
        d111 = vbl_grid_region_value(r111, i + 1, j + 1, k + 1);
    }
    const float x0 = vbl_grid_lerp(vbl_grid_lerp(d000, d001, w), vbl_grid_lerp(d010, d011, w), v);
    const float x1 = vbl_grid_lerp(vbl_grid_lerp(d100, d101, w), vbl_grid_lerp(d110, d111, w), v);
    return vbl_grid_lerp(x0, x1, u);
}

/* floor(x) for |x| < VBL_GRID_NEAR: truncation, one less below a negative non-integer. */
static inline int vbl_grid_floor_near(double x)
{
    const int i = (int)x;
    return i - (x < (double)i);
}

/* Trilinear sample at an index-space point: OpenVDB's BoxSampler convention (the 8 voxels around
 * floor(p), voxel (i,j,k)'s value at index point (i,j,k)). For |coordinates| < VBL_GRID_NEAR,
 * p - floor(p) lies in [0, 1] in floating point (x >= floor(x) exactly and x - floor(x) < 1
 * rounds to at most 1), so the far path's clamps and saturation change nothing there. */
static inline double vbl_grid_sample_index_trilinear_inline(vbl_grid_accessor* a, vbl_vec3 p)
{
    if (!(fabs(p.x) < VBL_GRID_NEAR && fabs(p.y) < VBL_GRID_NEAR && fabs(p.z) < VBL_GRID_NEAR))
        return vbl_grid_sample_index_trilinear_far(a, p);
    a->lookups++;
    const int i = vbl_grid_floor_near(p.x), j = vbl_grid_floor_near(p.y), k = vbl_grid_floor_near(p.z);
    return vbl_grid_trilinear_at(a, i, j, k, p.x - (double)i, p.y - (double)j, p.z - (double)k);
}

/* vbl_grid_sample_world with the trilinear filter, inline. */
static inline double vbl_grid_sample_world_trilinear_inline(vbl_grid_accessor* a, vbl_vec3 world_point)
{
    return vbl_grid_sample_index_trilinear_inline(a, vbl_affine_point(&a->volume->world_to_index, world_point));
}

#endif
