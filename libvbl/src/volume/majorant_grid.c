/* Block majorant grid: for each block of `block`^3 index cells, the max and min of every voxel
 * value trilinear interpolation anywhere inside the block can read. A point p of block b (cells
 * [o, o+B)) reads voxels floor(p) .. floor(p)+1, i.e. [o, o+B] per axis; we also include the
 * voxel shell on both sides ([o-1, o+B+1]) so points that rounding puts a hair outside a DDA
 * segment, and points exactly on a shared face, stay bounded by both blocks. The result is a true
 * bound (trilinear weights are convex), not an estimate from samples. */
#include "volume/volume.h"

#include <math.h>
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
    return vbl_majorant_grid_build_coarse(grid);
}

vbl_result vbl_majorant_grid_build_coarse(vbl_majorant_grid* grid)
{
    free(grid->coarse_max);
    free(grid->coarse_min);
    free(grid->coarse_spread);
    grid->coarse_max = grid->coarse_min = grid->coarse_spread = NULL;
    if (!grid->max_density) return VBL_SUCCESS;
    const int C = VBL_MAJORANT_COARSE;
    int64_t total = 1;
    int cd[3];
    for (int a = 0; a < 3; ++a) {
        cd[a] = (grid->dims[a] + C - 1) / C;
        grid->coarse_dims[a] = cd[a];
        total *= cd[a];
    }
    float* cmax = malloc((size_t)total * sizeof(float));
    float* cmin = malloc((size_t)total * sizeof(float));
    float* cspread = malloc((size_t)total * sizeof(float));
    if (!cmax || !cmin || !cspread) {
        free(cmax);
        free(cmin);
        free(cspread);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "coarse majorant grid of %lld cells", (long long)total);
    }
    for (int64_t i = 0; i < total; ++i) {
        cmax[i] = -3.402823466e38f;
        cmin[i] = 3.402823466e38f;
        cspread[i] = 3.402823466e38f; /* smallest block max, then the ratio */
    }
    const int64_t dx = grid->dims[0], dy = grid->dims[1], dz = grid->dims[2];
    for (int64_t z = 0; z < dz; ++z)
        for (int64_t y = 0; y < dy; ++y)
            for (int64_t x = 0; x < dx; ++x) {
                int64_t f = x + dx * (y + dy * z);
                int64_t c = x / C + (int64_t)cd[0] * (y / C + (int64_t)cd[1] * (z / C));
                if (grid->max_density[f] > cmax[c]) cmax[c] = grid->max_density[f];
                if (grid->min_density[f] < cmin[c]) cmin[c] = grid->min_density[f];
                if (grid->max_density[f] < cspread[c]) cspread[c] = grid->max_density[f];
            }
    for (int64_t i = 0; i < total; ++i)
        cspread[i] = cspread[i] > 0.0f ? cmax[i] / cspread[i] : (cmax[i] > 0.0f ? INFINITY : 1.0f);
    grid->coarse_max = cmax;
    grid->coarse_min = cmin;
    grid->coarse_spread = cspread;
    return VBL_SUCCESS;
}

void vbl_majorant_grid_free(vbl_majorant_grid* grid)
{
    free(grid->max_density);
    free(grid->min_density);
    free(grid->coarse_max);
    free(grid->coarse_min);
    free(grid->coarse_spread);
    grid->coarse_spread = NULL;
    grid->max_density = NULL;
    grid->min_density = NULL;
    grid->coarse_max = NULL;
    grid->coarse_min = NULL;
}

/* One axis of the dilation: dst (dims_out) from src (dims_in, offset k along `axis`): each cell the
 * max (min) over the 2k+1 source cells around it along that axis, cells outside the source being
 * empty space (0). */
static void vbl_dilate_axis(const float* src_max, const float* src_min, const int in[3], float* dst_max,
                            float* dst_min, const int out[3], int axis, int k)
{
    const int64_t nx = out[0], ny = out[1], nz = out[2];
    for (int64_t z = 0; z < nz; ++z)
        for (int64_t y = 0; y < ny; ++y)
            for (int64_t x = 0; x < nx; ++x) {
                int64_t c[3] = {x, y, z};
                float mx = 0.0f, mn = 0.0f;
                int first = 1;
                for (int d = -k; d <= k; ++d) {
                    int64_t s[3] = {c[0], c[1], c[2]};
                    s[axis] += d - k; /* source index along axis; other axes already aligned */
                    float vmax = 0.0f, vmin = 0.0f;
                    if (s[axis] >= 0 && s[axis] < in[axis]) {
                        int64_t i = s[0] + (int64_t)in[0] * (s[1] + (int64_t)in[1] * s[2]);
                        vmax = src_max[i];
                        vmin = src_min[i];
                    }
                    if (first || vmax > mx) mx = vmax;
                    if (first || vmin < mn) mn = vmin;
                    first = 0;
                }
                int64_t o = x + nx * (y + ny * z);
                dst_max[o] = mx;
                dst_min[o] = mn;
            }
}

vbl_result vbl_majorant_grid_dilate(const vbl_majorant_grid* src, const int k[3], vbl_majorant_grid* out)
{
    memset(out, 0, sizeof *out);
    out->block = src->block;
    if (!src->max_density) return VBL_SUCCESS;
    int64_t total = 1;
    int dims[3];
    for (int a = 0; a < 3; ++a) {
        int64_t d = (int64_t)src->dims[a] + 2 * (int64_t)k[a];
        int64_t o = (int64_t)src->origin[a] - (int64_t)k[a] * src->block;
        if (k[a] < 0 || d > INT32_MAX || o < INT32_MIN || total > VBL_MAJORANT_MAX_BLOCKS / d)
            return vbl_error(VBL_ERROR_UNSUPPORTED, "motion blur: the moving majorant grid would be too large");
        total *= d;
        dims[a] = (int)d;
        out->origin[a] = (int)o;
    }
    /* separable: x, then y, then z, each pass growing one axis */
    int cur[3] = {src->dims[0], src->dims[1], src->dims[2]};
    const float* in_max = src->max_density;
    const float* in_min = src->min_density;
    float *buf_max[2] = {NULL, NULL}, *buf_min[2] = {NULL, NULL};
    for (int i = 0; i < 2; ++i) {
        buf_max[i] = malloc((size_t)total * sizeof(float));
        buf_min[i] = malloc((size_t)total * sizeof(float));
    }
    if (!buf_max[0] || !buf_max[1] || !buf_min[0] || !buf_min[1]) {
        for (int i = 0; i < 2; ++i) {
            free(buf_max[i]);
            free(buf_min[i]);
        }
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "motion blur: moving majorant grid of %lld blocks", (long long)total);
    }
    int which = 0;
    for (int axis = 0; axis < 3; ++axis) {
        int next[3] = {cur[0], cur[1], cur[2]};
        next[axis] = dims[axis];
        vbl_dilate_axis(in_max, in_min, cur, buf_max[which], buf_min[which], next, axis, k[axis]);
        in_max = buf_max[which];
        in_min = buf_min[which];
        cur[axis] = next[axis];
        which ^= 1;
    }
    /* the result is in buffer which^1 */
    out->max_density = buf_max[which ^ 1];
    out->min_density = buf_min[which ^ 1];
    free(buf_max[which]);
    free(buf_min[which]);
    for (int a = 0; a < 3; ++a) out->dims[a] = dims[a];
    out->global_max = src->global_max;
    out->global_min = src->global_min < 0.0 ? src->global_min : 0.0;
    vbl_result res = vbl_majorant_grid_build_coarse(out);
    if (res != VBL_SUCCESS) vbl_majorant_grid_free(out);
    return res;
}
