/* Test helpers: in-memory NanoVDB float grids (C++ GridBuilder) wrapped as vbl_volume without the
 * file loader, so the volume core is tested against closed forms independently of fixtures. */
#ifndef VBL_VOLUME_TEST_GRID_H
#define VBL_VOLUME_TEST_GRID_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef double (*vt_voxel_fn)(int i, int j, int k, void* user);

/* NanoVDB float grid buffer (vbl_aligned_alloc) with value fn(i,j,k) at every voxel of
 * [bmin, bmax] where it is non-zero (those voxels active), background 0, and the map
 * world = M * ijk + M[.][3] (row-major 3x4). */
void* vt_make_nanovdb(const int bmin[3], const int bmax[3], vt_voxel_fn fn, void* user, const double m[3][4],
                      size_t* out_size);

#ifdef __cplusplus
}
#endif

#ifndef __cplusplus
#include "volume/volume.h"
/* Wraps a buffer from vt_make_nanovdb as a vbl_volume (majorant block `block`, 0 = default). */
vbl_volume* vt_wrap(void* buffer, size_t size, int block);
void vt_free(vbl_volume* v);
/* Convenience: constant/ramp boxes with uniform voxel size h and index origin 0. */
vbl_volume* vt_make(const int bmin[3], const int bmax[3], vt_voxel_fn fn, void* user, const double m[3][4]);
void vt_uniform_map(double m[3][4], double h, double tx, double ty, double tz);
#endif

#endif
