/* Per-thread grid sampling through PNanoVDB read accessors. Conventions follow OpenVDB's
 * PointSampler (nearest: voxel round(p) = floor(p + 0.5)) and BoxSampler (trilinear between the
 * 8 voxels around floor(p), voxel (i,j,k)'s value at index point (i,j,k)). Missing tiles read the
 * background, as OpenVDB's tree does. Values are read through the accessor's region cache
 * (grid_sample.h): one tree descent per 8^3 leaf-sized region while it stays cached. */
#include "volume/grid_sample.h"

void vbl_grid_accessor_init(vbl_grid_accessor* accessor, const vbl_volume* volume)
{
    accessor->volume = volume;
    pnanovdb_readaccessor_init(&accessor->accessor, volume->root);
    accessor->lookups = 0;
    for (int s = 0; s < VBL_GRID_REGION_SLOTS; ++s) {
        accessor->regions[s].key[0] = INT_MIN;
        accessor->regions[s].key[1] = accessor->regions[s].key[2] = 0;
        accessor->regions[s].mask = 0;
        accessor->regions[s].table = NULL;
    }
}

/* At a tile or the background (level > 0, which covers at least the whole region) the region holds
 * one value; in a leaf (level 0) the voxel's address minus its offset is the region's table. */
const vbl_grid_region* vbl_grid_region_fill(vbl_grid_accessor* a, int i, int j, int k)
{
    vbl_grid_region* r = &a->regions[((i & 8) >> 3) | ((j & 8) >> 2) | ((k & 8) >> 1)];
    const pnanovdb_buf_t buf = a->volume->buf;
    pnanovdb_coord_t ijk = {i, j, k};
    pnanovdb_uint32_t level = 0;
    pnanovdb_address_t addr =
        pnanovdb_readaccessor_get_value_address_and_level(PNANOVDB_GRID_TYPE_FLOAT, buf, &a->accessor, &ijk, &level);
    const pnanovdb_uint32_t off = 4u * (pnanovdb_uint32_t)(((i & 7) << 6) | ((j & 7) << 3) | (k & 7));
    if (level == 0) {
        addr = pnanovdb_address_offset_neg(addr, off);
        r->mask = ~0u;
    } else {
        r->mask = 0u;
    }
    r->table = buf.data + (addr.byte_offset >> 2);
    r->key[0] = i & ~7;
    r->key[1] = j & ~7;
    r->key[2] = k & ~7;
    return r;
}

double vbl_grid_sample_index_nearest(vbl_grid_accessor* accessor, vbl_vec3 p)
{
    accessor->lookups++;
    const int i = vbl_grid_floor_to_int(p.x + 0.5), j = vbl_grid_floor_to_int(p.y + 0.5),
              k = vbl_grid_floor_to_int(p.z + 0.5);
    return vbl_grid_region_value(vbl_grid_region_of(accessor, i, j, k), i, j, k);
}

double vbl_grid_sample_index_trilinear_far(vbl_grid_accessor* a, vbl_vec3 p)
{
    a->lookups++;
    const int i = vbl_grid_floor_to_int(p.x), j = vbl_grid_floor_to_int(p.y), k = vbl_grid_floor_to_int(p.z);
    /* Saturated coordinates: weights stay in [0, 1] (values there are background anyway). */
    const double u = vbl_clamp(p.x - (double)i, 0.0, 1.0), v = vbl_clamp(p.y - (double)j, 0.0, 1.0),
                 w = vbl_clamp(p.z - (double)k, 0.0, 1.0);
    return vbl_grid_trilinear_at(a, i, j, k, u, v, w);
}

double vbl_grid_sample_index_trilinear(vbl_grid_accessor* accessor, vbl_vec3 p)
{
    return vbl_grid_sample_index_trilinear_inline(accessor, p);
}

double vbl_grid_sample_world(vbl_grid_accessor* accessor, vbl_vec3 world_point, vbl_filter filter)
{
    vbl_vec3 p = vbl_affine_point(&accessor->volume->world_to_index, world_point);
    return filter == VBL_FILTER_NEAREST ? vbl_grid_sample_index_nearest(accessor, p)
                                        : vbl_grid_sample_index_trilinear_inline(accessor, p);
}
