/* Test helper: wraps an in-memory NanoVDB buffer as a vbl_volume (no file loader involved). */
#include "volume_test_grid.h"

#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

vbl_volume* vt_wrap(void* buffer, size_t size, int block)
{
    vbl_volume* v = calloc(1, sizeof *v);
    v->refcount = 1;
    v->nanovdb_buffer = buffer;
    v->nanovdb_size = size;
    v->buf = pnanovdb_make_buf((uint32_t*)buffer, size / 4);
    v->grid.address.byte_offset = 0;
    v->root = pnanovdb_tree_get_root(v->buf, pnanovdb_grid_get_tree(v->buf, v->grid));
    pnanovdb_map_handle_t map = pnanovdb_grid_get_map(v->buf, v->grid);
    double inv[9], vec[3];
    for (int r = 0; r < 3; ++r) {
        vec[r] = pnanovdb_map_get_vecd(v->buf, map, (pnanovdb_uint32_t)r);
        for (int c = 0; c < 3; ++c) {
            v->index_to_world.m[r][c] = pnanovdb_map_get_matd(v->buf, map, (pnanovdb_uint32_t)(3 * r + c));
            inv[3 * r + c] = pnanovdb_map_get_invmatd(v->buf, map, (pnanovdb_uint32_t)(3 * r + c));
        }
        v->index_to_world.m[r][3] = vec[r];
    }
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) v->world_to_index.m[r][c] = inv[3 * r + c];
        v->world_to_index.m[r][3] = -(inv[3 * r] * vec[0] + inv[3 * r + 1] * vec[1] + inv[3 * r + 2] * vec[2]);
    }
    v->info.size = sizeof v->info;
    strcpy(v->info.file_path, "(test grid)");
    if (vbl_majorant_grid_build(&v->majorant, v, block) != VBL_SUCCESS) {
        vt_free(v);
        return NULL;
    }
    return v;
}

void vt_free(vbl_volume* v)
{
    if (!v) return;
    vbl_majorant_grid_free(&v->majorant);
    vbl_aligned_free(v->nanovdb_buffer);
    free(v);
}

vbl_volume* vt_make(const int bmin[3], const int bmax[3], vt_voxel_fn fn, void* user, const double m[3][4])
{
    size_t size = 0;
    void* buffer = vt_make_nanovdb(bmin, bmax, fn, user, m, &size);
    return vt_wrap(buffer, size, 0);
}

void vt_uniform_map(double m[3][4], double h, double tx, double ty, double tz)
{
    memset(m, 0, sizeof(double) * 12);
    m[0][0] = m[1][1] = m[2][2] = h;
    m[0][3] = tx;
    m[1][3] = ty;
    m[2][3] = tz;
}
