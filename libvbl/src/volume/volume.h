/* The in-memory volume: a NanoVDB float grid (PNanoVDB access) and its block majorant grid. */
#ifndef VBL_VOLUME_VOLUME_H
#define VBL_VOLUME_VOLUME_H

#define PNANOVDB_C
#include <nanovdb/PNanoVDB.h>

#include "core/math.h"
#include "vbl/vbl_volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Block max/min of the trilinear support, in index space. Block (bx,by,bz) covers index cells
 * [origin + b*block, origin + (b+1)*block) and stores the max (and min) of every value that
 * trilinear interpolation inside it can touch (its voxels and the one-voxel neighbour shell). */
typedef struct vbl_majorant_grid {
    int block;          /* block edge in voxels */
    int origin[3];      /* index coordinate of block (0,0,0)'s lower corner */
    int dims[3];        /* blocks per axis */
    float* max_density; /* dims[0]*dims[1]*dims[2], x fastest */
    float* min_density;
    double global_max, global_min;
    /* Coarse level (hierarchical DDA, Museth 2014): cell (cx,cy,cz) covers the blocks
     * [c * VBL_MAJORANT_COARSE, (c + 1) * VBL_MAJORANT_COARSE) per axis (clipped to dims) and
     * stores the max / min of their max_density / min_density, so it bounds every trilinear
     * sample in them. NULL when not built (the iterator then walks blocks only). */
    int coarse_dims[3];
    float* coarse_max;
    float* coarse_min;
    float* coarse_spread; /* coarse max / the smallest block max in the cell (>= 1; inf if one is 0) */
} vbl_majorant_grid;

/* Blocks per coarse cell edge (a power of two: the iterator divides by shifting). */
#define VBL_MAJORANT_COARSE_LOG2 2
#define VBL_MAJORANT_COARSE (1 << VBL_MAJORANT_COARSE_LOG2)

struct vbl_volume {
    int refcount;
    void* nanovdb_buffer;          /* 32-byte aligned, owned */
    size_t nanovdb_size;
    pnanovdb_buf_t buf;
    pnanovdb_grid_handle_t grid;
    pnanovdb_root_handle_t root;
    vbl_affine index_to_world;
    vbl_affine world_to_index;
    vbl_volume_info info;
    vbl_majorant_grid majorant;
};

/* Wraps a NanoVDB float grid buffer (takes ownership of `buffer`, allocated with
 * vbl_aligned_alloc), validates it, computes statistics, applies the bad-voxel policy and builds
 * the majorant grid. `path`/`grid_index` are for messages and info. */
vbl_result vbl_volume_create_from_nanovdb(void* buffer, size_t size, const char* path,
                                          int grid_index, const vbl_volume_load_options* options,
                                          vbl_volume** out_volume);

/* As vbl_volume_create_from_nanovdb; allow_negative = 1 for signed grids (velocity components),
 * where only NaN and Inf are bad values. */
vbl_result vbl_volume_create_signed(void* buffer, size_t size, const char* path, int grid_index,
                                    const vbl_volume_load_options* options, int allow_negative, vbl_volume** out_volume);
/* Component `component` (0..2) of a vec3s/vec3d grid as a float volume named "<grid>.x|y|z"
 * (grid selection by options->grid_name/grid_index, as vbl_volume_load). */
vbl_result vbl_volume_load_vec3_component(const char* path, const vbl_volume_load_options* options, int component,
                                          int allow_negative, vbl_volume** out_volume);
/* vbl_volume_load of a signed float grid (e.g. Houdini's vel.x): negative values allowed. */
vbl_result vbl_volume_load_signed(const char* path, const vbl_volume_load_options* options, vbl_volume** out_volume);

/* Majorant grid lifecycle (majorant_grid.c). */
vbl_result vbl_majorant_grid_build(vbl_majorant_grid* grid, const vbl_volume* volume, int block);
void vbl_majorant_grid_free(vbl_majorant_grid* grid);
/* `out` = `src` dilated by k[a] blocks along each axis a (grown by as many blocks on each side):
 * every block the max (min) over the source blocks within k of it, empty space counting as 0. */
vbl_result vbl_majorant_grid_dilate(const vbl_majorant_grid* src, const int k[3], vbl_majorant_grid* out);
/* Builds (or rebuilds) the coarse level of a grid from its blocks; build and dilate call it. */
vbl_result vbl_majorant_grid_build_coarse(vbl_majorant_grid* grid);

#ifdef __cplusplus
}
#endif

#endif
