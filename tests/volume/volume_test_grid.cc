// Test helper: builds NanoVDB float grids in memory with nanovdb::GridBuilder.
#include "volume_test_grid.h"

#include <cstring>

#include <nanovdb/util/GridBuilder.h>

#include "core/alloc.h"

extern "C" void* vt_make_nanovdb(const int bmin[3], const int bmax[3], vt_voxel_fn fn, void* user,
                                 const double m[3][4], size_t* out_size)
{
    nanovdb::GridBuilder<float> builder(0.0f);
    auto acc = builder.getAccessor();
    for (int k = bmin[2]; k <= bmax[2]; ++k)
        for (int j = bmin[1]; j <= bmax[1]; ++j)
            for (int i = bmin[0]; i <= bmax[0]; ++i) {
                double v = fn(i, j, k, user);
                if (v != 0.0) acc.setValue(nanovdb::Coord(i, j, k), float(v));
            }
    double mat[3][3], inv[3][3], tr[3];
    for (int r = 0; r < 3; ++r) {
        tr[r] = m[r][3];
        for (int c = 0; c < 3; ++c) mat[c][r] = m[r][c]; // NanoVDB stores the transpose
    }
    // inverse of the 3x3 part
    double a = m[0][0], b = m[0][1], c = m[0][2], d = m[1][0], e = m[1][1], f = m[1][2], g = m[2][0], h = m[2][1],
           i = m[2][2];
    double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    double minv[3][3] = {{(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det},
                         {(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det},
                         {(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det}};
    for (int r = 0; r < 3; ++r)
        for (int cc = 0; cc < 3; ++cc) inv[cc][r] = minv[r][cc];
    nanovdb::Map map;
    map.set(mat, inv, tr, 1.0);
    auto handle = builder.getHandle<nanovdb::AbsDiff>(map, "density");
    void* buffer = vbl_aligned_alloc(32, handle.size());
    std::memcpy(buffer, handle.data(), handle.size());
    *out_size = handle.size();
    return buffer;
}
