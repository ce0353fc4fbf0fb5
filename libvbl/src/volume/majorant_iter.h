/* 3D DDA over the majorant grid along a ray: piecewise-constant majorant segments that skip
 * empty blocks (pbrt-v4 style `next(&iter, &segment)` loop shared by every tracking estimator). */
#ifndef VBL_VOLUME_MAJORANT_ITER_H
#define VBL_VOLUME_MAJORANT_ITER_H

#include <stddef.h>

#include "volume/volume.h"

/* A ray-parameter interval with constant bounds on the (unscaled) grid value. */
typedef struct vbl_majorant_segment {
    double t0, t1;
    double majorant;   /* >= every trilinear sample in the interval */
    double minorant;   /* <= every trilinear sample in the interval (residual tracking control) */
} vbl_majorant_segment;

typedef struct vbl_majorant_iter {
    const vbl_majorant_grid* grid;
    double t, t_end;
    int cell[3], step[3], done;
    double t_next[3], t_delta[3];
    double org[3], inv_dir[3]; /* ray in block units: (index - grid origin) / block */
    /* Hierarchical DDA state (majorant_iter.c): */
    size_t index;          /* linear block index of `cell` */
    ptrdiff_t stride[3];   /* change of `index` for one step along each axis */
    int coarse_check;      /* 1: `cell` has just entered a coarse cell not examined yet */
    double coarse_tau;     /* a coarse cell with majorant x length <= coarse_tau is one segment */
    double coarse_ratio;   /* ... and one whose max is <= coarse_ratio x its smallest block max */
    int coarse_merge;      /* coarse_tau > 0 or coarse_ratio >= 1 */
    unsigned long steps;   /* DDA steps taken (block and coarse-cell crossings), for benchmarks */
} vbl_majorant_iter;

/* Ray in *world* space of the volume: origin + t * direction, t in [tmin, tmax]. Segments come
 * in increasing t, are contiguous where the ray is inside the grid's support and cover exactly
 * the overlap of [tmin, tmax] with it; empty blocks (majorant 0) are returned too, so callers
 * see continuous coverage of non-empty space only when they skip majorant == 0 themselves.
 * A run of empty blocks inside one empty coarse cell (VBL_MAJORANT_COARSE^3 blocks) comes as
 * one segment; non-empty blocks come one segment each, exactly as a block-by-block walk. */
void vbl_majorant_iter_init(vbl_majorant_iter* iter, const vbl_volume* volume, vbl_vec3 origin,
                            vbl_vec3 direction, double tmin, double tmax);
/* The same on any majorant grid (e.g. a dilated copy) placed by `world_to_index`. */
void vbl_majorant_iter_init_grid(vbl_majorant_iter* iter, const vbl_majorant_grid* grid, const vbl_affine* world_to_index,
                                 vbl_vec3 origin, vbl_vec3 direction, double tmin, double tmax);
/* As vbl_majorant_iter_init_grid, and a coarse cell comes as one segment with the coarse cell's
 * bounds (fewer, looser segments; still true bounds) when its (unscaled) majorant times the
 * ray's length in it is <= coarse_tau, or its max is <= coarse_ratio times the smallest max of
 * its blocks, or its blocks all hold the same constant value. coarse_tau <= 0 and coarse_ratio
 * < 1: only empty coarse cells are merged (the segments of vbl_majorant_iter_init_grid). */
void vbl_majorant_iter_init_coarse(vbl_majorant_iter* iter, const vbl_majorant_grid* grid,
                                   const vbl_affine* world_to_index, vbl_vec3 origin, vbl_vec3 direction, double tmin,
                                   double tmax, double coarse_tau, double coarse_ratio);
/* Returns 1 and fills `segment`, or 0 when the ray has left the grid or passed tmax. */
int vbl_majorant_iter_next(vbl_majorant_iter* iter, vbl_majorant_segment* segment);

#endif
