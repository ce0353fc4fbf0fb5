/* Block majorant grid: for each block of `block`^3 index cells, the max and min of every voxel
 * value trilinear interpolation anywhere inside the block can read. A point p of block b (cells
 * [o, o+B)) reads voxels floor(p) .. floor(p)+1, i.e. [o, o+B] per axis; we also include the
 * voxel shell on both sides ([o-1, o+B+1]) so points that rounding puts a hair outside a DDA
 * segment, and points exactly on a shared face, stay bounded by both blocks. The result is a true
 * bound (trilinear weights are convex), not an estimate from samples. */
#include "volume/volume.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* Default block edge in voxels (measured: docs/readme/volume.md, "Majorant block size"). */
#define VBL_MAJORANT_DEFAULT_BLOCK 8
/* Refuse grids whose bounding box would need more blocks than this (sparse giants). */
#define VBL_MAJORANT_MAX_BLOCKS ((int64_t)1 << 28)

vbl_result vbl_majorant_grid_build(vbl_majorant_grid* grid, const vbl_volume* volume, int block)
{
    memset(grid, 0, sizeof *grid);
    if (block <= 0) block = VBL_MAJORANT_DEFAULT_BLOCK;
    if (block > 256) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "majorant_block_size = %d is outside [1, 256]", block);
    grid->block = block;

    pnanovdb_coord_t bmin = pnanovdb_root_get_bbox_min(volume->buf, volume->root);
    pnanovdb_coord_t bmax = pnanovdb_root_get_bbox_max(volume->buf, volume->root);
    if (bmin.x > bmax.x || bmin.y > bmax.y || bmin.z > bmax.z) return VBL_SUCCESS; /* empty: no blocks */

    /* Support of trilinear interpolation: index cells bmin-1 .. bmax. All extents and the block
     * count are int64 and checked axis by axis: a bbox of 2^31 voxels per axis would overflow
     * `hi - lo` in int and wrap the product of the block counts (to 0 for 2^31 x 2^31 x 2040). */
    const int64_t lo[3] = {(int64_t)bmin.x - 1, (int64_t)bmin.y - 1, (int64_t)bmin.z - 1};
    const int64_t hi[3] = {bmax.x, bmax.y, bmax.z};
    int64_t dims[3];
    int64_t total = 1;
    int too_many = 0;
    for (int a = 0; a < 3; ++a) {
        /* Blocks start exactly at the support (not at multiples of `block`): no empty margin
         * inside the first block, which matters in dense media (steps ~ majorant * length). */
        dims[a] = (hi[a] - lo[a]) / block + 1; /* hi >= lo here, so truncation is floor */
        /* The block loop visits index cells up to lo + dims * block + 1: they must be int32. */
        if (lo[a] - 1 < INT32_MIN || lo[a] + dims[a] * block + 1 > INT32_MAX) too_many = 1;
        if (!too_many && total > VBL_MAJORANT_MAX_BLOCKS / dims[a]) too_many = 1;
        if (!too_many) total *= dims[a];
    }
    if (too_many || total > VBL_MAJORANT_MAX_BLOCKS)
        return vbl_error(VBL_ERROR_UNSUPPORTED,
                         "%s: index bounding box [%d,%d,%d]..[%d,%d,%d] needs %lld x %lld x %lld majorant blocks of "
                         "%d^3 (limit %lld in all, index coordinates within +-2^31); use a larger "
                         "majorant_block_size or a grid without far-apart voxels",
                         volume->info.file_path, bmin.x, bmin.y, bmin.z, bmax.x, bmax.y, bmax.z, (long long)dims[0],
                         (long long)dims[1], (long long)dims[2], block, (long long)VBL_MAJORANT_MAX_BLOCKS);
    for (int a = 0; a < 3; ++a) {
        grid->origin[a] = (int)lo[a];
        grid->dims[a] = (int)dims[a];
    }
    grid->max_density = malloc((size_t)total * sizeof(float));
    grid->min_density = malloc((size_t)total * sizeof(float));
    if (!grid->max_density || !grid->min_density) {
        vbl_majorant_grid_free(grid);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: majorant grid of %lld blocks", volume->info.file_path,
                         (long long)total);
    }

    const int dx = grid->dims[0], dy = grid->dims[1];
    float* maxd = grid->max_density;
    float* mind = grid->min_density;
    const int* origin = grid->origin;
#pragma omp parallel
    {
        pnanovdb_readaccessor_t acc;
        pnanovdb_readaccessor_init(&acc, volume->root);
#pragma omp for schedule(dynamic, 16)
        for (int64_t index = 0; index < total; ++index) {
            int bx = (int)(index % dx), by = (int)((index / dx) % dy), bz = (int)(index / ((int64_t)dx * dy));
            int o[3] = {origin[0] + bx * block, origin[1] + by * block, origin[2] + bz * block};
            float mx = -3.402823466e38f, mn = 3.402823466e38f;
            for (int k = o[2] - 1; k <= o[2] + block + 1; ++k)
                for (int j = o[1] - 1; j <= o[1] + block + 1; ++j)
                    for (int i = o[0] - 1; i <= o[0] + block + 1; ++i) {
                        pnanovdb_coord_t ijk = {i, j, k};
                        float v = pnanovdb_read_float(
                            volume->buf,
                            pnanovdb_readaccessor_get_value_address(PNANOVDB_GRID_TYPE_FLOAT, volume->buf, &acc, &ijk));
                        if (v > mx) mx = v;
                        if (v < mn) mn = v;
                    }
            if (mx < mn) mx = mn = 0.0f; /* all NaN: the loader's policy rejects/sanitizes those */
            maxd[index] = mx;
            mind[index] = mn;
        }
    }
    grid->global_max = -1e300;
    grid->global_min = 1e300;
    for (int64_t index = 0; index < total; ++index) {
        if (maxd[index] > grid->global_max) grid->global_max = maxd[index];
        if (mind[index] < grid->global_min) grid->global_min = mind[index];
    }
    return VBL_SUCCESS;
}

void vbl_majorant_grid_free(vbl_majorant_grid* grid)
{
    free(grid->max_density);
    free(grid->min_density);
    grid->max_density = NULL;
    grid->min_density = NULL;
}
