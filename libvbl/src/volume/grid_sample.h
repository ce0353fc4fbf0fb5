/* Per-thread grid sampling through PNanoVDB read accessors (nearest and trilinear). */
#ifndef VBL_VOLUME_GRID_SAMPLE_H
#define VBL_VOLUME_GRID_SAMPLE_H

#include "volume/volume.h"

/* One per thread and volume: caches the last leaf/internal nodes visited. */
typedef struct vbl_grid_accessor {
    const vbl_volume* volume;
    pnanovdb_readaccessor_t accessor;
    uint64_t lookups;   /* grid value fetches (a trilinear sample counts 1 lookup) */
} vbl_grid_accessor;

void vbl_grid_accessor_init(vbl_grid_accessor* accessor, const vbl_volume* volume);

double vbl_grid_sample_index_nearest(vbl_grid_accessor* accessor, vbl_vec3 index_point);
double vbl_grid_sample_index_trilinear(vbl_grid_accessor* accessor, vbl_vec3 index_point);
double vbl_grid_sample_world(vbl_grid_accessor* accessor, vbl_vec3 world_point, vbl_filter filter);

#endif
