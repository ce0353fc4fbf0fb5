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
    float d000 = vbl_grid_fetch(accessor, i, j, k), d001 = vbl_grid_fetch(accessor, i, j, k + 1);
    float d010 = vbl_grid_fetch(accessor, i, j + 1, k), d011 = vbl_grid_fetch(accessor, i, j + 1, k + 1);
    float d100 = vbl_grid_fetch(accessor, i + 1, j, k), d101 = vbl_grid_fetch(accessor, i + 1, j, k + 1);
    float d110 = vbl_grid_fetch(accessor, i + 1, j + 1, k), d111 = vbl_grid_fetch(accessor, i + 1, j + 1, k + 1);
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
