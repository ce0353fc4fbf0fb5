/* Per-thread grid sampling through PNanoVDB read accessors. Conventions follow OpenVDB's
 * PointSampler (nearest: voxel round(p) = floor(p + 0.5)) and BoxSampler (trilinear between the
 * 8 voxels around floor(p), voxel (i,j,k)'s value at index point (i,j,k)). Missing tiles read the
 * background, as OpenVDB's tree does. */
#include "volume/grid_sample.h"

#include <math.h>

void vbl_grid_accessor_init(vbl_grid_accessor* accessor, const vbl_volume* volume)
{
    accessor->volume = volume;
    pnanovdb_readaccessor_init(&accessor->accessor, volume->root);
    accessor->lookups = 0;
}

static inline float vbl_grid_fetch(vbl_grid_accessor* a, int i, int j, int k)
{
    pnanovdb_coord_t ijk;
    ijk.x = i;
    ijk.y = j;
    ijk.z = k;
    pnanovdb_address_t address =
        pnanovdb_readaccessor_get_value_address(PNANOVDB_GRID_TYPE_FLOAT, a->volume->buf, &a->accessor, &ijk);
    return pnanovdb_read_float(a->volume->buf, address);
}

/* The 8 voxels (i + dx, j + dy, k + dz), d[4 dx + 2 dy + dz], with one tree descent per 8^3
 * leaf region they touch (the region's key: coordinates with the low 3 bits cleared): inside a
 * leaf, a voxel's value is at the leaf table + 4 (64 (x & 7) + 8 (y & 7) + (z & 7)); at a tile or
 * the background (level > 0) the whole region holds one value. The same floats as 8 fetches. */
static void vbl_grid_fetch8(vbl_grid_accessor* a, int i, int j, int k, float d[8])
{
    const pnanovdb_buf_t buf = a->volume->buf;
    int have = 0, key[3] = {0, 0, 0};
    pnanovdb_uint32_t level = 0;
    pnanovdb_address_t table = {0};
    for (int c = 0; c < 8; ++c) {
        const int x = i + (c >> 2), y = j + ((c >> 1) & 1), z = k + (c & 1);
        const pnanovdb_uint32_t off = 4u * (pnanovdb_uint32_t)(((x & 7) << 6) | ((y & 7) << 3) | (z & 7));
        if (!have || (x & ~7) != key[0] || (y & ~7) != key[1] || (z & ~7) != key[2]) {
            pnanovdb_coord_t ijk = {x, y, z};
            pnanovdb_address_t addr = pnanovdb_readaccessor_get_value_address_and_level(PNANOVDB_GRID_TYPE_FLOAT, buf,
                                                                                       &a->accessor, &ijk, &level);
            table = level == 0 ? pnanovdb_address_offset_neg(addr, off) : addr;
            key[0] = x & ~7, key[1] = y & ~7, key[2] = z & ~7;
            have = 1;
        }
        d[c] = pnanovdb_read_float(buf, level == 0 ? pnanovdb_address_offset(table, off) : table);
    }
}

/* floor() into an int, saturating far outside the int range (such points read the background). */
static inline int vbl_floor_to_int(double x)
{
    double f = floor(x);
    if (!(f > -2147483000.0)) return -2147483000; /* also NaN */
    if (f > 2147483000.0) return 2147483000;
    return (int)f;
}

double vbl_grid_sample_index_nearest(vbl_grid_accessor* accessor, vbl_vec3 p)
{
    accessor->lookups++;
    return vbl_grid_fetch(accessor, vbl_floor_to_int(p.x + 0.5), vbl_floor_to_int(p.y + 0.5),
                          vbl_floor_to_int(p.z + 0.5));
}

/* OpenVDB BoxSampler's lerp, with its float rounding (so results match it to float precision even
 * where values cancel): a + float((b - a) * w). Stays within [min(a,b), max(a,b)] for w in [0,1]. */
static inline float vbl_lerp(float a, float b, double w) { return a + (float)((double)(b - a) * w); }

double vbl_grid_sample_index_trilinear(vbl_grid_accessor* accessor, vbl_vec3 p)
{
    accessor->lookups++;
    int i = vbl_floor_to_int(p.x), j = vbl_floor_to_int(p.y), k = vbl_floor_to_int(p.z);
    double u = p.x - (double)i, v = p.y - (double)j, w = p.z - (double)k;
    /* Saturated coordinates: weights stay in [0, 1] (values there are background anyway). */
    u = vbl_clamp(u, 0.0, 1.0);
    v = vbl_clamp(v, 0.0, 1.0);
    w = vbl_clamp(w, 0.0, 1.0);
    float d000, d001, d010, d011, d100, d101, d110, d111;
    if ((i & 7) != 7 && (j & 7) != 7 && (k & 7) != 7) {
        /* All 8 voxels lie in one 8^3 leaf-sized region: one tree descent. In a leaf, the value
         * of (x, y, z) is at table + 4 (64 (x & 7) + 8 (y & 7) + (z & 7)) (PNanoVDB's
         * pnanovdb_leaf_coord_to_offset, float stride 32 bits); at a tile or the background
         * (level > 0, which covers at least the whole region) all 8 are the same value. The same
         * floats as 8 separate fetches, so results are bit-identical. */
        pnanovdb_coord_t ijk = {i, j, k};
        pnanovdb_uint32_t level = 0;
        pnanovdb_address_t a = pnanovdb_readaccessor_get_value_address_and_level(
            PNANOVDB_GRID_TYPE_FLOAT, accessor->volume->buf, &accessor->accessor, &ijk, &level);
        const pnanovdb_buf_t buf = accessor->volume->buf;
        if (level == 0) {
            d000 = pnanovdb_read_float(buf, a);
            d001 = pnanovdb_read_float(buf, pnanovdb_address_offset(a, 4u));
            d010 = pnanovdb_read_float(buf, pnanovdb_address_offset(a, 32u));
            d011 = pnanovdb_read_float(buf, pnanovdb_address_offset(a, 36u));
            d100 = pnanovdb_read_float(buf, pnanovdb_address_offset(a, 256u));
            d101 = pnanovdb_read_float(buf, pnanovdb_address_offset(a, 260u));
            d110 = pnanovdb_read_float(buf, pnanovdb_address_offset(a, 288u));
            d111 = pnanovdb_read_float(buf, pnanovdb_address_offset(a, 292u));
        } else {
            d000 = d001 = d010 = d011 = d100 = d101 = d110 = d111 = pnanovdb_read_float(buf, a);
        }
    } else {
        /* The 8 voxels straddle 2, 4 or 8 leaf regions: one descent per region (vbl_grid_fetch8). */
        float d[8];
        vbl_grid_fetch8(accessor, i, j, k, d);
        d000 = d[0], d001 = d[1], d010 = d[2], d011 = d[3], d100 = d[4], d101 = d[5], d110 = d[6], d111 = d[7];
    }
    float a = vbl_lerp(vbl_lerp(d000, d001, w), vbl_lerp(d010, d011, w), v);
    float b = vbl_lerp(vbl_lerp(d100, d101, w), vbl_lerp(d110, d111, w), v);
    return vbl_lerp(a, b, u);
}

double vbl_grid_sample_world(vbl_grid_accessor* accessor, vbl_vec3 world_point, vbl_filter filter)
{
    vbl_vec3 p = vbl_affine_point(&accessor->volume->world_to_index, world_point);
    return filter == VBL_FILTER_NEAREST ? vbl_grid_sample_index_nearest(accessor, p)
                                        : vbl_grid_sample_index_trilinear(accessor, p);
}
